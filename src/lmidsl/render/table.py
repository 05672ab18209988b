"""THE table printer of the command line (rich): tables that fit the output width of
:mod:`lmidsl.render.terminal`, or every cell in full with ``--wide``.  Cell widths are terminal
cells (rich's ``cell_len``), so combining characters (P̂, S̄) and wide characters keep the
columns aligned."""
from __future__ import annotations

import io

from rich import box
from rich.console import Console
from rich.table import Table
from rich.text import Text

from .terminal import Settings, color_enabled, output_width

UNLIMITED = 100_000
"""The width a ``--wide`` table is laid out in (its natural width is used)."""

#: the header rule off a terminal: ASCII, so that a file or a pipe holds plain text
ASCII_HEAD = box.Box("    \n    \n -- \n    \n    \n    \n    \n    \n", ascii=True)


def _console(width: int | None, color: bool, buffer) -> Console:
    return Console(file=buffer, width=width or UNLIMITED, force_terminal=color,
                   color_system="standard" if color else None, no_color=not color,
                   highlight=False, emoji=False, markup=False, legacy_windows=False,
                   soft_wrap=False)


#: a cell whose text starts with one of these is coloured (on a terminal only)
STYLES = (("NOT", "bold red"), ("FAILED", "bold red"), ("VIOLATED", "bold red"), ("error", "red"),
          ("WORSE", "bold red"), ("certified", "green"), ("reproduced", "green"),
          ("bound holds", "green"), ("printed bound holds", "green"), ("yes", "green"), ("no", "yellow"))


def _cell(value, color: bool) -> Text:
    text = "" if value is None else (f"{value:.6g}" if isinstance(value, float) else str(value))
    style = ""
    if color:
        style = next((s for prefix, s in STYLES if text.startswith(prefix)), "")
        if " NOT " in text or ", NOT" in text or "WORSE" in text:
            style = "bold red"
    return Text(text, style=style)


def format_table(headers: list[str], rows: list[list], *, width: int | None = None,
                 color: bool | None = None, nowrap: tuple[int, ...] = ()) -> str:
    """A table as text that fits ``width`` cells (default :func:`output_width`): columns wrap
    (a long word is folded, never cut); ``nowrap`` columns (indices) keep their cells on one
    line as long as the others can give way.  Colour (``color``; default: on a terminal) marks
    the verdict words."""
    width = output_width() if width is None and not Settings.wide else width
    color = color_enabled() if color is None else color
    cells = [[_cell(c, color) for c in row] for row in rows]
    if width is not None and nowrap:
        # the columns kept whole must leave the others room (4 cells each), or nothing is kept whole
        # (a folded cell is still all there; a column rich cannot fit would be dropped)
        whole = sum(max([Text(h).cell_len for h in headers[i].split("\n")]
                        + [max((c.cell_len for c in r[i].split()), default=0) for r in cells])
                    for i in nowrap if i < len(headers))
        if whole + 4 * (len(headers) - len(nowrap)) + 2 * (len(headers) - 1) > width:
            nowrap = ()
    table = Table(box=box.SIMPLE_HEAD if color else ASCII_HEAD, show_edge=False, pad_edge=False,
                  padding=(0, 1, 0, 0), header_style="bold" if color else "", expand=False)
    for i, header in enumerate(headers):
        table.add_column(header, overflow="fold", no_wrap=i in nowrap)
    for row in cells:
        table.add_row(*row)
    buffer = io.StringIO()
    _console(width, color, buffer).print(table)
    return "\n".join(line.rstrip() for line in buffer.getvalue().rstrip("\n").splitlines())
