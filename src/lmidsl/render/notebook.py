"""Notebook display (Jupyter, VS Code, Colab): LaTeX of theorems and LMIs, HTML of results.

* :func:`theorem_display_latex`, :func:`lmi_display_latex`: display maths that both LaTeX and
  MathJax/KaTeX typeset (``$$\\begin{gathered} … \\end{gathered}$$``; text only in ``\\text{}``
  with no macro inside, ids in ``\\mathtt``).  ``Theorem._repr_latex_`` and ``LMI._repr_latex_``
  reach them through :data:`lmidsl.theorem.theorem.LATEX_RENDERER` (the theorem layer cannot
  import this one), registered by :mod:`lmidsl.render.latex`.
* :func:`solution_html`, :func:`verification_html`, :func:`sweep_html`: the verdict record
  (:class:`lmidsl.certify.verdict.Verdict`: its line and its levels — optimum, back-off, analysis,
  exact, claimed), the design and each LMI's largest eigenvalue, as a small HTML table.  The result classes live in lower layers, so they carry no
  ``_repr_html_``: :func:`register_ipython` registers these renderers with IPython's HTML
  formatter *by class name* (``for_type_by_name``), which imports none of them; ``import lmidsl``
  calls it when it runs inside IPython.  :func:`html` renders any of the three.

Importing this module registers the LaTeX renderers (``lmidsl`` imports it with the names that
hand theorems to the user, and in IPython).
"""
from __future__ import annotations

import html as _html
import importlib
import re

import numpy as np

from ..theorem.values import HTML_RENDERER, LATEX_RENDERER
from .latex import LMILatexPrinter, lmi_latex
from .latex_text import tex_text
from .report import performance_label

#: result classes and their renderer, by (module, class name)
HTML_RENDERERS = {
    ("lmidsl.solver.solution", "Solution"): "solution_html",
    ("lmidsl.studies.verify", "Verification"): "verification_html",
    ("lmidsl.studies.sweep", "SweepResult"): "sweep_html",
}


# -- LaTeX ----------------------------------------------------------------------------------
_TEXT_MACROS = {r"\_": " ", r"\&": "and", r"\%": " percent", r"\#": "no. ", r"\$": "",
                r"\dots{}": "...", r"\S{}": "Sec. ", "---": "-", "--": "-", "~": " ",
                r"\textbackslash{}": "/", r"\{": "(", r"\}": ")"}


def _text(segment: str) -> str:
    """A prose segment as ``\\text{…}`` with no macro inside (MathJax's ``\\text`` runs none)."""
    for macro, plain in _TEXT_MACROS.items():
        segment = segment.replace(macro, plain)
    segment = re.sub(r"\\[A-Za-z]+\{([^{}]*)\}", r"\1", segment)      # \'{e} and the like
    segment = re.sub(r"[\\{}^_]", "", segment)
    return rf"\text{{{segment}}}" if segment else ""


def math_text(text: str) -> str:
    """Plain text with Unicode maths (γ², Âf) as maths-mode LaTeX valid for LaTeX and MathJax:
    its maths as maths, its prose in ``\\text{}``."""
    pieces = tex_text(text).split("$")
    return "".join(_text(p) if k % 2 == 0 else p for k, p in enumerate(pieces))


def _id(name: str) -> str:
    return r"\mathtt{" + name.replace("_", r"\_") + "}"


def _gathered(lines: list[str]) -> str:
    return "$$\\begin{gathered}\n" + " \\\\\n".join(lines) + "\n\\end{gathered}$$"


def theorem_display_latex(theorem) -> str:
    """The id, the title and every LMI of ``theorem``, each with its label."""
    lines = [_id(theorem.id) + r"\text{: }" + math_text(theorem.title)]
    for lmi in theorem.lmis:
        lines.append(f"{lmi_latex(theorem, lmi)} \\qquad {math_text(lmi.label)}")
    return _gathered(lines)


def lmi_display_latex(lmi) -> str:
    """One LMI (its symbols by their LaTeX names) and its label."""
    settings = {"vertex_index": "i"} if getattr(lmi, "per_vertex", False) else {}
    return _gathered([f"{LMILatexPrinter(settings).doprint(lmi)} \\qquad {math_text(lmi.label)}"])


# -- HTML -----------------------------------------------------------------------------------
def _number(x, spec=".6g") -> str:
    return "—" if x is None else format(x, spec)


def _matrix_html(M) -> str:
    M = np.atleast_2d(np.asarray(M, dtype=float))
    rows = "".join("<tr>" + "".join(f"<td style='text-align:right'>{x:.5g}</td>" for x in row) + "</tr>"
                   for row in M)
    return f"<table style='display:inline-table;border-left:1px solid;border-right:1px solid'>{rows}</table>"


def _table(rows: list[tuple[str, str]]) -> str:
    body = "".join(f"<tr><th style='text-align:left'>{_html.escape(k)}</th><td style='text-align:left'>{v}</td></tr>"
                   for k, v in rows)
    return f"<table>{body}</table>"


def _verdict_html(record) -> str:
    """The verdict record's line (:class:`lmidsl.certify.verdict.Verdict`), green when certified."""
    color = "green" if record.certified else "#b00"
    return f"<b style='color:{color}'>{_html.escape(record.line())}</b>"


def _levels_html(record) -> str:
    """The bracket: every level the record names (optimum, back-off, analysis, exact, claimed)."""
    levels = [(k, v) for k, v in (getattr(record, "levels", None) or {}).items() if v is not None]
    return ", ".join(f"{_html.escape(k)} {_number(v, '.8g')}" for k, v in levels)


def _design_html(design) -> str:
    if not design:
        return ""
    items = getattr(design, "items", None)
    pairs = items() if callable(items) else []
    return "".join(f"<div>{_html.escape(str(name))} = {_matrix_html(value)}</div>" for name, value in pairs)


def _result_html(title: str, record, rows: list, design) -> str:
    head = [("verdict", _verdict_html(record))]
    if _levels_html(record):
        head.append((f"levels ({getattr(record, 'quantity', '') or 'level'})", _levels_html(record)))
    body = _design_html(design)
    return (f"<div><b>{_html.escape(title)}</b>"
            + _table(head + rows + ([("design", body)] if body else [])) + "</div>")


def solution_html(sol) -> str:
    """The verdict record, the levels (optimum, back-off, analysis), the status, each LMI's
    largest eigenvalue and proof, the design."""
    where = f" [{sol.example}]" if getattr(sol, "example", None) else ""
    rows = [("status", _html.escape(f"{sol.status} ({sol.backend}/{sol.solver})"))]
    lmis = "".join(f"<tr><td>{_html.escape(str(r.label))}"
                   + (f" @ vertex {r.vertex}" if getattr(r, "vertex", None) is not None else "")
                   + f"</td><td style='text-align:right'>{r.max_eig:.3e}</td>"
                   f"<td>{_html.escape(str(getattr(r, 'proof', '') or ''))}</td></tr>" for r in getattr(sol, "lmis", []))
    if lmis:
        rows.append(("LMIs (λmax, proof)", f"<table>{lmis}</table>"))
    return _result_html(sol.theorem + where, sol.verdict, rows, sol.design)


def verification_html(v) -> str:
    """The verdict record, the levels (claimed, synthesis, analysis, exact), the checks, the design."""
    where = f" [{v.example}]" if getattr(v, "example", None) else ""
    checks = getattr(v, "checks", {}) or {}
    rows = []
    if checks:
        rows.append(("checks", _html.escape(", ".join(f"{k}: {'yes' if ok else 'no' if ok is False else '—'}"
                                                      for k, ok in checks.items()))))
    return _result_html(v.theorem + where, v.verdict, rows, getattr(v, "design", None))


def sweep_html(result) -> str:
    """One row per grid point: the parameters, status, γ, largest eigenvalue, its verdict word."""
    names = list(result.grid)
    head = "".join(f"<th>{_html.escape(h)}</th>"
                   for h in [*names, "status", performance_label(result.theorem), "max eig", "verdict"])
    body = "".join("<tr>" + "".join(f"<td>{_number(p.params[n], 'g')}</td>" for n in names)
                   + f"<td>{_html.escape(p.status)}</td><td>{_number(p.gamma)}</td>"
                   f"<td>{_number(p.worst_eig, '.2e')}</td><td>{_html.escape(p.verdict.word)}</td></tr>"
                   for p in result.points)
    proved = sum(bool(p.proved) for p in result.points)
    return (f"<div><b>{_html.escape(result.theorem)}</b>: {len(result.points)} points, {proved} proved"
            f"<table><tr>{head}</tr>{body}</table></div>")


def html(obj) -> str:
    """The HTML of a Solution, a Verification or a SweepResult."""
    for (module, name), renderer in HTML_RENDERERS.items():
        if any(c.__module__ == module and c.__name__ == name for c in type(obj).__mro__):
            return globals()[renderer](obj)
    raise TypeError(f"no notebook renderer for {type(obj).__name__}")


HTML_RENDERER["html"] = html        # Solution._repr_html_, in any front end (not only IPython)


def register_ipython(shell=None) -> list[str]:
    """Register the HTML renderers with IPython's display formatter by class name (nothing is
    imported); the names registered.  ``shell``: the IPython shell (default: the running one)."""
    if shell is None:
        try:
            shell = importlib.import_module("IPython").get_ipython()
        except ImportError:
            return []
    if shell is None:
        return []
    formatter = shell.display_formatter.formatters["text/html"]
    for (module, name), renderer in HTML_RENDERERS.items():
        formatter.for_type_by_name(module, name, lambda obj, *_, _r=renderer: globals()[_r](obj))
    return [name for _, name in HTML_RENDERERS]


LATEX_RENDERER["theorem"] = theorem_display_latex
LATEX_RENDERER["lmi"] = lmi_display_latex
