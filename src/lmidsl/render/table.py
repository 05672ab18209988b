"""THE table printer of the command line (rich): tables that fit the output width of
:mod:`lmidsl.render.terminal`, or every cell in full with ``--wide``.

Layout: each column gets its natural width when the table fits; otherwise the columns that can
wrap give way down to their longest word, so that a cell wraps between words and a number or an
id is never split.  When even the longest words do not fit side by side, the table is *stacked*:
one block per row, ``header: value`` on a line each (:func:`format_stacked`).  Cell widths are
terminal cells (rich's ``cell_len``), so combining characters (P̂, S̄) and wide characters keep
the columns aligned."""
from __future__ import annotations

import io

import numpy as np
from rich import box
from rich.cells import cell_len
from rich.console import Console
from rich.table import Table
from rich.text import Text

from .terminal import Settings, color_enabled, output_width, wrap

UNLIMITED = 100_000
"""The width a ``--wide`` table is laid out in (its natural width is used)."""

GAP = 2
"""Cells between two columns."""

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


def cell_text(value) -> str:
    """The text of one cell: floats in 6 significant digits, None empty."""
    return "" if value is None else (f"{value:.6g}" if isinstance(value, float) else str(value))


def _cell(text: str, color: bool) -> Text:
    style = ""
    if color:
        style = next((s for prefix, s in STYLES if text.startswith(prefix)), "")
        if " NOT " in text or ", NOT" in text or "WORSE" in text:
            style = "bold red"
    return Text(text, style=style)


def _longest_word(text: str) -> int:
    return max((cell_len(w) for w in text.split()), default=0)


def _longest_line(text: str) -> int:
    return max((cell_len(line) for line in text.split("\n")), default=0)


def column_widths(headers: list[str], cells: list[list[str]], width: int,
                  nowrap: tuple[int, ...] = ()) -> list[int] | None:
    """Widths of the columns in a table of ``width`` cells, or None when the table cannot fit
    without splitting a word (then it is stacked).  A column's least width is its longest word
    (its longest line for a ``nowrap`` column); the room left over goes to the columns in
    proportion to what they lack of their natural width."""
    columns = list(zip(headers, *cells)) if cells else [(h,) for h in headers]
    natural = [max(_longest_line(t) for t in col) for col in columns]
    least = [natural[i] if i in nowrap else max(_longest_word(t) for t in col)
             for i, col in enumerate(columns)]
    room = width - GAP * (len(columns) - 1)
    if sum(natural) <= room:
        return natural
    if sum(least) > room:
        return None
    spare, lack = room - sum(least), [n - m for n, m in zip(natural, least)]
    total = sum(lack)
    widths = [m + (spare * d) // total for m, d in zip(least, lack)]
    for i in sorted(range(len(widths)), key=lambda i: -lack[i]):     # the rounding remainder
        if sum(widths) < room and widths[i] < natural[i]:
            widths[i] += 1
    return widths


def format_stacked(headers: list[str], rows: list[list[str]], width: int) -> str:
    """The narrow form of a table: each row a block headed by its first cell, then
    ``header  value`` lines (values wrapped at their own indentation, words never split)."""
    names = [" ".join(h.split()) for h in headers]
    pad = min(max((cell_len(n) for n in names[1:]), default=0), width // 3)
    out = []
    for row in rows:
        out.append(wrap(" ".join(row[0].split()) if row else "", width))
        for name, value in zip(names[1:], row[1:]):
            if not value:
                continue
            head = f"  {name}{' ' * max(1, pad - cell_len(name) + 1)} "
            text = " ".join(value.split("\n"))
            out.append(wrap(head + text, width, indent=" " * min(cell_len(head), width // 2)))
        out.append("")
    return "\n".join(out).rstrip("\n")


def format_table(headers: list[str], rows: list[list], *, width: int | None = None,
                 color: bool | None = None, nowrap: tuple[int, ...] = ()) -> str:
    """A table as text that fits ``width`` cells (default :func:`output_width`): cells wrap
    between words inside their column, ``nowrap`` columns (indices) keep their lines whole, and
    a table whose words cannot sit side by side is stacked (:func:`format_stacked`).  Colour
    (``color``; default: on a terminal) marks the verdict words."""
    width = output_width() if width is None and not Settings.wide else width
    color = color_enabled() if color is None else color
    texts = [[cell_text(c) for c in row] for row in rows]
    widths = None
    if width is not None:
        widths = column_widths(headers, texts, width, nowrap)
        if widths is None:
            return format_stacked(headers, texts, width)
    table = Table(box=box.SIMPLE_HEAD if color else ASCII_HEAD, show_edge=False, pad_edge=False,
                  padding=(0, GAP - 1, 0, 0), header_style="bold" if color else "", expand=False,
                  collapse_padding=False)
    for i, header in enumerate(headers):
        table.add_column(header, overflow="fold", no_wrap=False,
                         width=None if widths is None else widths[i])
    for row in texts:
        table.add_row(*[_cell(t, color) for t in row])
    buffer = io.StringIO()
    _console(width, color, buffer).print(table)
    return "\n".join(line.rstrip() for line in buffer.getvalue().rstrip("\n").splitlines())


def format_matrix(name: str, M, indent: str = "  ", width: int | None = None, digits: int = 5) -> str:
    """THE text form of a matrix: ``name = [`` rows of right-aligned entries (``digits``
    significant digits) ``]``; a matrix wider than ``width`` (default :func:`output_width`) is
    printed in blocks of whole columns, each headed ``columns i–j`` (as MATLAB does)."""
    M = np.atleast_2d(np.asarray(M, dtype=float))
    cells = [[f"{x:.{digits}g}" for x in row] for row in M]
    size = max((len(c) for row in cells for c in row), default=1)
    head = f"{indent}{name} = ["
    width = output_width() if width is None else width
    per = M.shape[1] if width is None else max(1, (width - len(head) - 1) // (size + 1))
    blocks = [range(j, min(j + per, M.shape[1])) for j in range(0, max(M.shape[1], 1), per)]
    out = []
    for b, cols in enumerate(blocks):
        if len(blocks) > 1:
            out.append(f"{indent}{name}, columns {cols.start + 1}–{cols.stop}:" if cols.stop - cols.start > 1
                       else f"{indent}{name}, column {cols.start + 1}:")
        for i, row in enumerate(cells):
            lead = head if i == 0 else " " * len(head)
            tail = "]" if i == len(cells) - 1 else ""
            out.append(lead + " ".join(row[j].rjust(size) for j in cols) + tail)
    return "\n".join(out)
