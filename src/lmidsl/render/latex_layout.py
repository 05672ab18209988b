r"""How a large LMI is laid out on a portrait page, as papers do: when the matrix written out in
full would not fit the line, its long blocks are *named* (:math:`\Phi_{11}, \Phi_{21}, \dots`)
and defined in a "where" list below it; a definition longer than the line is broken between
the terms of its sum (``aligned``).  Short blocks (``0``, ``I``, ``P_1``, ``-\gamma^2 I``) stay
in the matrix.  Nothing is turned sideways, nothing shrunk.

Widths are estimated from the LaTeX source (:func:`latex_width`, in points of a 10 pt
display): a linear model of the characters, scripts, operators and brackets, fitted on the
measured widths of every block of every LMI of the registry (pdflatex ``\wd`` of a
``\displaystyle`` box; median error 10 %, 95th percentile 23 %), used with a margin.
"""
from __future__ import annotations

import re

LINE = 483.7
"""``\\linewidth`` of the document (A4, 2 cm margins), in points."""

TAG_ROOM = 50.0
"""Room kept for an equation tag (5 em)."""

#: the letters that name blocks, one per named LMI of a theorem (one its symbols do not use)
LETTERS = (r"\Phi", r"\Psi", r"\Xi", r"\Theta", r"\Pi", r"\Omega", r"\Upsilon", r"\Sigma", r"\Gamma")

#: fitted coefficients (points): characters, script characters, binary operators/relations,
#: brackets, and a constant
_COEF = (3.93, 4.56, 17.36, 4.11, 3.13)
MARGIN = 1.25
"""Estimated widths are multiplied by this before they are compared with the line."""

SHORT = 40.0
"""A block at most this wide (estimated, points) stays in the matrix; a wider one is named."""


def _features(tex: str) -> tuple[int, int, int, int]:
    s = re.sub(r"\\(left|right|displaystyle)\b", "", tex)
    scripts = 0

    def script(m):
        nonlocal scripts
        body = m.group(2) if m.group(2) is not None else m.group(3)
        scripts += len(re.sub(r"[{} ]", "", re.sub(r"\\[A-Za-z]+", "x", body)))
        return ""
    previous = None
    while previous != s:
        previous = s
        s = re.sub(r"([_^])(?:\{([^{}]*)\}|(\\?[A-Za-z0-9]))", script, s)
    ops = (len(re.findall(r"(?<![{(,&]) ?[+\-=<>] ", s))
           + len(re.findall(r"\\(?:le|ge|prec|succ|preceq|succeq|cdot)\b", s)))
    s = re.sub(r"\\(?:hat|bar|tilde|check|dot|vec|mathrm|operatorname|mathbf|mathcal)\b", "", s)
    s = re.sub(r"\\[A-Za-z]+", "x", s)
    s = re.sub(r"[{} &\\]", "", s)
    brackets = len(re.findall(r"[()\[\]]", s))
    return len(s) - brackets - ops, scripts, ops, brackets


def latex_width(tex: str) -> float:
    """The estimated width (points) of ``tex`` typeset in a 10 pt display (no matrices inside)."""
    return sum(c * f for c, f in zip(_COEF, (*_features(tex), 1)))


def matrix_width(rows: list[list[str]]) -> float:
    """Estimated width of a bmatrix of these entries: the widest entry of each column, the
    column separation (2 em) and the brackets."""
    columns = list(zip(*rows))
    return sum(max(latex_width(e) for e in col) for col in columns) + 20.0 * len(columns) + 12.0


def top_level_terms(tex: str) -> list[str]:
    """``tex`` split before each ``+``/``-`` outside every bracket and group (the terms of a sum;
    the first keeps its sign)."""
    terms, depth, start, i = [], 0, 0, 0
    while i < len(tex):
        ch = tex[i]
        if ch in "({[":
            depth += 1
        elif ch in ")}]":
            depth -= 1
        elif tex.startswith(r"\left", i) or tex.startswith(r"\right", i):
            i += 5 if tex.startswith(r"\left", i) else 6
            continue
        elif depth == 0 and ch in "+-" and i > 0 and tex[i - 1] == " " and tex[i + 1:i + 2] == " ":
            terms.append(tex[start:i].strip())
            start = i
        i += 1
    terms.append(tex[start:].strip())
    return [t for t in terms if t]


def definition(name: str, tex: str, limit: float = LINE / MARGIN) -> str:
    """``name = tex``, broken between the terms of the sum into lines that fit ``limit``
    (estimated) as an ``aligned`` block; on one line when it fits."""
    if latex_width(f"{name} = {tex}") <= limit:
        return f"{name} = {tex}"
    lines, current = [], []
    room = limit - latex_width(f"{name} = ")
    for term in top_level_terms(tex):
        if current and latex_width(" ".join(current + [term])) > room:
            lines.append(" ".join(current))
            current = []
        current.append(term)
    lines.append(" ".join(current))
    if len(lines) == 1:
        return f"{name} = {tex}"
    body = " \\\\\n  & \\quad ".join(lines)
    return f"\\begin{{aligned}}[t] {name} = {{}} & {body} \\end{{aligned}}"


def block_name(letter: str, i: int, j: int, q: int) -> str:
    return f"{letter}_{{{i + 1}{',' if q > 9 else ''}{j + 1}}}"


def choose_letter(used_latex: str, taken: set) -> str:
    """The first of :data:`LETTERS` that neither the theorem's LaTeX nor another LMI uses."""
    for letter in LETTERS:
        if letter not in taken and not re.search(re.escape(letter) + r"(?![A-Za-z])", used_latex):
            return letter
    return r"\mathcal{M}"


def block_rows(printer, spec) -> list[list[str | None]]:
    """The entries of a block LMI as ``printer`` prints them; None where the implicit triangle
    is (printed as the star)."""
    q = spec.nblocks
    upper = printer._settings["triangle"] == "upper" or (
        printer._settings["triangle"] == "given" and spec.given_as == "upper")
    return [[printer.doprint(spec.block(i, j)) if (j >= i if upper else j <= i) else None
             for j in range(q)] for i in range(q)]


def lmi_layout(printer, lmi, letter: str) -> tuple[str, list[tuple[str, str]], bool]:
    """(the LMI's LaTeX, the named blocks' (name, definition) pairs, named?): the LMI written
    out in full when it fits the line beside its tag, else with its long blocks named by
    ``letter``."""
    spec = lmi.spec
    full = printer.doprint(lmi)
    if spec.nblocks == 1:
        return full, [], False
    rows = block_rows(printer, spec)
    star = printer._settings["star"]
    shown = [[star if e is None else e for e in row] for row in rows]
    if MARGIN * matrix_width(shown) <= LINE - TAG_ROOM:
        return full, [], False
    q, named, out = spec.nblocks, [], []
    for i, row in enumerate(rows):
        line = []
        for j, entry in enumerate(row):
            if entry is None:
                line.append(star)
            elif latex_width(entry) <= SHORT:
                line.append(entry)
            else:
                name = block_name(letter, i, j, q)
                named.append((name, entry))
                line.append(name)
        out.append(line)
    return f"{printer._matrix_rows(out)} {printer.relation(lmi.sense)} 0", named, True
