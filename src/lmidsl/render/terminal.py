"""Text for a terminal or a pipe: the output width, wrapped paragraphs, colour only on a
terminal (tables: :mod:`lmidsl.render.table`; progress: :mod:`lmidsl.render.progress`).  Light:
the command line's entry imports it (``lmidsl --help`` does not load rich's console).

The width is the terminal's on a terminal; off a terminal ``COLUMNS`` if set, else
:data:`DEFAULT_WIDTH`.  ``--wide`` (:func:`configure`) prints every cell in full, however wide
the lines.  Cell widths are terminal cells (rich's ``cell_len``), so combining characters
(P̂, S̄) and wide characters keep the columns aligned.
"""
from __future__ import annotations

import os
import sys
import textwrap

from rich.cells import cell_len

DEFAULT_WIDTH = 100
"""The width of text written off a terminal when ``COLUMNS`` is not set."""


class Settings:
    """What the command line asked for (set once by :func:`configure`)."""

    wide = False


def configure(wide: bool = False) -> None:
    """``--wide``: lay tables out at their natural width, wrap nothing."""
    Settings.wide = bool(wide)


def is_terminal(stream=None) -> bool:
    stream = sys.stdout if stream is None else stream
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def color_enabled(stream=None) -> bool:
    """Colour only on a terminal, and never with ``NO_COLOR`` set (https://no-color.org)."""
    return is_terminal(stream) and not os.environ.get("NO_COLOR") and os.environ.get("TERM") != "dumb"


def output_width(stream=None) -> int | None:
    """The width lines must fit: None with ``--wide``; the terminal's width on a terminal;
    otherwise ``COLUMNS`` when it is a positive integer, else :data:`DEFAULT_WIDTH`."""
    if Settings.wide:
        return None
    if is_terminal(stream):
        try:
            return os.get_terminal_size((sys.stdout if stream is None else stream).fileno()).columns
        except (OSError, ValueError, AttributeError):
            pass
    columns = os.environ.get("COLUMNS", "")
    return int(columns) if columns.isdigit() and int(columns) > 0 else DEFAULT_WIDTH


def wrap(text: str, width: int | None = None, indent: str | None = None) -> str:
    """Each line of ``text`` wrapped to ``width`` (default :func:`output_width`) between words
    (a word longer than the width stays whole: numbers and ids are never split), continued at
    ``indent`` (default: the line's own indentation plus two spaces); unchanged with ``--wide``."""
    width = output_width() if width is None else width
    if width is None:
        return text
    out = []
    for line in text.split("\n"):
        if cell_len(line) <= width:
            out.append(line)
            continue
        own = line[:len(line) - len(line.lstrip())]
        out += textwrap.wrap(line.strip(), width=width, initial_indent=own,
                             subsequent_indent=own + "  " if indent is None else indent,
                             break_long_words=False, break_on_hyphens=False) or [""]
    return "\n".join(out)


def echo(text: str = "") -> None:
    """Print ``text`` on stdout, wrapped to the output width."""
    print(wrap(text))
