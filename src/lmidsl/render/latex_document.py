"""The LaTeX document of a theorem: the statement and, with an example, the solved numbers.

``theorem_latex(theorem, solution=None)`` writes a complete article (amsmath,
amssymb, graphicx, geometry; all in Debian's ``texlive-latex-base``): title and source, the
dimensions, data, scalar parameters and decision variables with their sets, every LMI with the
paper's equation label and its "where" definitions, the objective, the recovery formulas and
the analysis theorem that certifies them; with an example, the data, γ (computed, printed,
certified) as a table, the recovered filter and the decision variables.  Every page is
portrait: an LMI too wide for the line is printed with named blocks and a "where" list
(:mod:`lmidsl.render.latex_layout`), as papers print them.
"""
from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import sympy as sp

from .latex import (equation_tag, grouped_display, latex_of,
                    printer_for, lmi_where, name_to_latex, tag_text, with_vertex_index)
from .latex_safe import guarded, safe_math
from .latex_layout import choose_letter, definition, lmi_layout
from .latex_text import latex_matrix, latex_number, tex_text
from .robust_latex import as_stated, domain_latex, robust_conditions_latex, robust_where, scheduled_name
from ..symbolic.symbols import DiagonalVariable, StructuredVariable, SymmetricDataMatrix, SymmetricVariable
from ..errors import InputError, LmidslError, did_you_mean
from ..theorem.registry import get_theorem, linked_analysis
from ..theorem.theorem import Theorem
from ..theorem.values import FactorStep
from ..certify.verdict import LEVEL_NAMES

PREAMBLE = r"""\documentclass[10pt]{article}
\usepackage{amsmath,amssymb,graphicx}
\usepackage[a4paper,margin=2cm]{geometry}
\setcounter{MaxMatrixCols}{%(maxcols)d}
\allowdisplaybreaks
\sloppy
\newsavebox{\lmibox}
%% \fitlmi{math}: display-style math, shrunk to the line width (less room for a tag) if wider
\newcommand{\fitlmi}[1]{\sbox{\lmibox}{$\displaystyle #1$}%%
  \ifdim\wd\lmibox>\dimexpr\linewidth-5em\relax
    \typeout{lmidsl-shrink: \the\wd\lmibox\space to \the\dimexpr\linewidth-5em\relax}%%
    \resizebox{\dimexpr\linewidth-5em\relax}{!}{\usebox{\lmibox}}%%
  \else\usebox{\lmibox}\fi}
%% \lmidisplay{math}{tag}: a displayed LMI (a large one arrives with its blocks named, so that
%% it fits; \fitlmi is the last resort)
\newcommand{\lmitag}[1]{\if\relax\detokenize{#1}\relax\else\tag*{#1}\fi}
\newcommand{\lmidisplay}[2]{\begin{equation*}\fitlmi{#1}\lmitag{#2}\end{equation*}}
%% \lmiitem{math}: one display-style item of a list, shrunk to the line only if wider;
%% lmiitems: a centred paragraph of items, broken between items
\newcommand{\lmiitem}[1]{\sbox{\lmibox}{$\displaystyle #1$}%%
  \ifdim\wd\lmibox>\linewidth
    \typeout{lmidsl-shrink: \the\wd\lmibox\space to \the\linewidth}%%
    \resizebox{\linewidth}{!}{\usebox{\lmibox}}%%
  \else\usebox{\lmibox}\fi}
\newenvironment{lmiitems}{\par\medskip\centering\setlength{\lineskip}{8pt}}{\par\medskip}
\setlength{\parindent}{0pt}
\setlength{\parskip}{4pt}
"""


def _shape_latex(printer, symbol) -> str:
    """The set of a symbol: R, R^{n x k}, S^{n} (symmetric), D^{n} (diagonal)."""
    if isinstance(symbol, sp.Symbol):
        return r"\mathbb{R}"
    rows, cols = (printer.doprint(d) for d in symbol.shape)
    if isinstance(symbol, DiagonalVariable):
        return rf"\mathbb{{D}}^{{{rows}}}"
    if isinstance(symbol, (SymmetricVariable, SymmetricDataMatrix)) or (
            isinstance(symbol, StructuredVariable) and symbol.symmetric):
        return rf"\mathbb{{S}}^{{{rows}}}"
    rows, cols = ((f"({t})" if isinstance(d, sp.Add) else t)
                  for d, t in zip(symbol.shape, (rows, cols)))
    return rf"\mathbb{{R}}^{{{rows} \times {cols}}}"


def _domain_latex(extra: dict) -> str:
    """A parameter's domain as the code checks it (lmidsl.numeric.instance): (a, b) when open,
    [a, b] when closed, an infinite end always open; a one-point domain as ``= a``."""
    dom = extra.get("domain")
    if dom is None:
        return ""
    lo, hi = (float(v) for v in dom)
    if lo == hi:
        return f"$= {latex_number(lo)}$"
    is_open = extra.get("open", False)
    left = "(" if is_open or not np.isfinite(lo) else "["
    right = ")" if is_open or not np.isfinite(hi) else "]"
    return rf"$\in {left}{latex_number(lo)}, {latex_number(hi)}{right}$"


def _kind_text(symbol) -> str:
    return {"full": "full", "symmetric": "symmetric", "diagonal": "diagonal",
            "scalar": "scalar", "structured": "structured"}.get(getattr(symbol, "kind", ""), "")


def _table(header: list[str], rows: list[list[str]], spec: str) -> str:
    lines = [f"\\begin{{tabular}}{{{spec}}}", "\\hline", " & ".join(header) + r" \\", "\\hline"]
    lines += [" & ".join(r) + r" \\" for r in rows]
    lines += ["\\hline", "\\end{tabular}"]
    return "\n".join(lines)


def _recovery_name(theorem: Theorem, name: str) -> str:
    """LaTeX of a recovered matrix: its name in the analysis theorem, else a guess."""
    if theorem.analysis is not None:
        try:
            analysis = linked_analysis(theorem)
        except LmidslError:  # the analysis theorem is optional for printing
            analysis = None
        decl = analysis.data_decl.get(name) if analysis is not None else None
        if decl is not None:
            return latex_of(decl.symbol)
    return name_to_latex(name)


def _theorem_latex_names(theorem: Theorem, settings: dict) -> str:
    """Every LaTeX name the theorem's symbols print as (to pick block names none of them uses)."""
    printer = printer_for(theorem, None, **{k: v for k, v in settings.items() if k != "notation"})
    decls = [*theorem.data_decl.values(), *theorem.var_decl.values(), *theorem.param_decl.values(),
             *theorem.derived_decl.values()]
    return " ".join([printer.doprint(d.symbol) for d in decls] + [safe_math(d.latex) for d in theorem.notation.values()])


def lmi_parts(theorem: Theorem, lmi, settings: dict, taken: set | None = None):
    """(body, where pairs) of one LMI as the document prints it: in full when it fits the line,
    else with named blocks (:mod:`lmidsl.render.latex_layout`) defined first in its "where"."""
    taken = set() if taken is None else taken
    printer = printer_for(theorem, lmi, **settings)
    letter = choose_letter(_theorem_latex_names(theorem, settings), taken)
    body, named, is_named = lmi_layout(printer, lmi, letter)
    if is_named:
        taken.add(letter)
    return body, named + list(lmi_where(theorem, lmi, **settings))


def _display(lmi, body: str, where: list[tuple[str, str]]) -> str:
    """The LMI displayed with its tag, then "where" and its definitions (each broken between
    the terms of its sum when longer than the line)."""
    text = f"\\lmidisplay{{{body}}}{{{tag_text(lmi.label)}}}"
    vertex = r"for every vertex $i = 1, \dots, N$"
    if where:
        items = [definition(name, value) for name, value in where]
        text += "\n" + (vertex + ", " if lmi.per_vertex else "") + "where\n" + grouped_display(items, end=".")
    elif lmi.per_vertex:
        text += "\n" + vertex + "."
    return text


def lmi_snippet(theorem, label: str, **settings) -> str:
    r"""One LMI's LaTeX, ready to paste into a paper (amsmath only, no preamble, none of the
    document's macros): an ``equation`` with a ``\label`` and, below it, "where" and the
    definitions it uses (a large LMI's named blocks first, :mod:`lmidsl.render.latex_layout`)."""
    if isinstance(theorem, str):
        theorem = get_theorem(theorem)
    lmi = _find_lmi(theorem, label)
    robust = bool(getattr(theorem, "simplices", None))      # stated once in α: render/robust_latex.py
    if robust:
        lmi = as_stated(lmi)
    body, where = lmi_parts(theorem, lmi, settings)
    key = re.sub(r"[^A-Za-z0-9]+", "-", f"{theorem.id}-{lmi.label}").strip("-")
    comment = " ".join(f"{theorem.id} {lmi.label} (lmidsl latex {theorem.id} --lmi \"{lmi.label}\"; "
                       "needs amsmath)".split())           # one line: a newline would end the comment
    out = [f"% {comment}", "\\begin{equation}", body, f"\\label{{{key}}}", "\\end{equation}"]
    vertex = r"for every vertex $i = 1, \dots, N$" if lmi.per_vertex else ""
    extra = []
    if robust:
        vertex, extra = robust_where(theorem)
    if where or extra:
        out.append((vertex + ", " if vertex else "") + "where")
        items = [definition(name, value) for name, value in where] + extra
        out += ["\\begin{gather*}", ",\\\\\n".join(items) + ".", "\\end{gather*}"]
    elif vertex:
        out.append(vertex + ".")
    return guarded("\n".join(out) + "\n")


def _find_lmi(theorem: Theorem, label: str):
    for lmi in theorem.lmis:
        if lmi.label == label or equation_tag(lmi.label) == f"({label.strip('()')})":
            return lmi
    labels = [l.label for l in theorem.lmis]
    raise InputError(f"{theorem.id}: no LMI labelled {label!r}{did_you_mean(label, labels)}; "
                     f"LMIs: {', '.join(labels)}")


def _condition_latex(theorem: Theorem, settings: dict, defined: set) -> list[str]:
    out = []
    positives = []
    taken: set = set()
    for lmi in theorem.lmis:
        if lmi.spec.nblocks == 1 and equation_tag(lmi.label) is None:
            positives.append(lmi)
            continue
        body, where = lmi_parts(theorem, lmi, settings, taken)
        where = [(n, d) for n, d in where if n not in defined]
        defined |= {n for n, _ in where}
        if lmi.description:        # kept on the page of its LMI (no heading and line left alone)
            out.append(tex_text(lmi.description) + "\\par\\nopagebreak")
        out.append(_display(lmi, body, where))
    if positives:
        parts = []
        for lmi in positives:
            parts.append(printer_for(theorem, lmi, **settings).doprint(lmi)
                         + (r"\ (i = 1, \dots, N)" if lmi.per_vertex else ""))
        out.append("and\n" + grouped_display(parts, end="."))
    return out


def _maxcols(theorem: Theorem) -> int:
    widest = max((l.spec.nblocks for l in theorem.lmis), default=1)
    for decl in theorem.notation.values():
        if isinstance(decl.symbol, sp.BlockMatrix):
            widest = max(widest, decl.symbol.blocks.cols)
    return max(20, widest + 2)


def theorem_latex(theorem, solution=None, **settings) -> str:
    """A complete LaTeX document stating ``theorem`` (a Theorem or its id); with a ``solution``
    of it (:func:`lmidsl.solve`), the solved values too.  Printing never solves."""
    if isinstance(theorem, str):
        theorem = get_theorem(theorem)
    printer = printer_for(theorem, None, **{k: v for k, v in settings.items() if k != "notation"})
    out = [PREAMBLE % {"maxcols": _maxcols(theorem)}, "\\begin{document}"]
    out.append(f"\\section*{{{tex_text(theorem.title)}}}")
    src = theorem.source
    source = ", ".join(tex_text(x) for x in (src.citation or src.paper, src.equations) if x)
    out.append(f"\\textbf{{Source.}} {source}.\\\\\n\\textbf{{Theorem id.}} "
               f"\\texttt{{{tex_text(theorem.id)}}} ({tex_text(theorem.time)} time).")
    if theorem.description:
        out.append(tex_text(theorem.description))

    if theorem.dims:
        dims = ", ".join(printer.doprint(d) for d in theorem.dims.values())
        out.append(f"\\subsection*{{Dimensions}}\n${dims}$: positive integers, read off the data.")
    if theorem.data_decl:
        rows = []
        for decl in theorem.data_decl.values():
            s = decl.symbol
            note = tex_text(decl.description)
            if s.per_vertex and not getattr(theorem, "simplices", None):
                note += (", " if note else "") + f"per vertex (${with_vertex_index(latex_of(s), 'i')}$)"
            rows.append([f"${printer.doprint(s)}$", f"${_shape_latex(printer, s)}$", note])
        out.append("\\subsection*{Data}\n" + _table(["symbol", "in", "description"], rows,
                                                     "lll"))
    if theorem.param_decl or theorem.derived_decl:
        rows = []
        for decl in theorem.param_decl.values():
            dom_txt = _domain_latex(decl.extra)
            rows.append([f"${printer.doprint(decl.symbol)}$", dom_txt, tex_text(decl.description)])
        for decl in theorem.derived_decl.values():
            s = decl.symbol
            rows.append([f"${printer.doprint(s)}$", f"$= {printer.doprint(s.definition)}$",
                         tex_text(decl.description)])
        out.append("\\subsection*{Scalar parameters}\n"
                   + _table(["symbol", "domain / definition", "description"], rows, "lll"))
    if theorem.var_decl:
        rows = []
        for decl in theorem.var_decl.values():
            s = decl.symbol
            note = tex_text(decl.description)
            if isinstance(s, StructuredVariable):
                note = (note + "; " if note else "") + f"${printer.doprint(s)} = " \
                    f"{printer.doprint(s.expansion)}$"
            if getattr(s, "per_vertex", False):
                note += (", " if note else "") + f"per vertex (${with_vertex_index(latex_of(s), 'i')}$)"
            if decl.extra.get("nonneg"):
                note += (", " if note else "") + r"$\ge 0$"
            rows.append([f"${printer.doprint(s)}$", f"${_shape_latex(printer, s)}$",
                         _kind_text(s), note])
        out.append("\\subsection*{Decision variables}\n"
                   + _table(["symbol", "in", "kind", "description"], rows, "llll"))

    out.append("\\subsection*{Conditions}")
    defined: set = set()
    if getattr(theorem, "simplices", None):      # stated once in α: render/robust_latex.py
        out.append(robust_conditions_latex(theorem))
    else:
        if any(l.per_vertex for l in theorem.lmis):
            out.append(r"The subscript $i$ runs over the $N$ vertices of the polytope of data.")
        out += _condition_latex(theorem, settings, defined)

    if theorem.objective is not None:
        obj = printer.doprint(theorem.objective)
        text = f"\\subsection*{{Objective}}\nMinimise ${obj}$ subject to the conditions above."
        if theorem.performance is not None:
            name, expr = theorem.performance
            level, value = name_to_latex(name), printer.doprint(expr)
            if value == level or value == obj:     # no "γ = γ": say which quantity it is
                text += f" The performance level ${level}$ is the optimal value."
            elif value == rf"\sqrt{{{obj}}}" and obj.replace(" ", "") in (f"{level}^{{2}}", f"{level}^2"):
                text += f" The performance level ${level}$ is the square root of the optimal value."
            else:
                text += f" The performance level is ${level} = {value}$."
        out.append(text)
    kind = _design_word(theorem)
    if theorem.recovery or getattr(theorem, "scheduled", None):
        out.append(f"\\subsection*{{{kind.capitalize()} recovery}}\n" + _recovery_latex(theorem, printer))
    if theorem.analysis is not None:
        out.append(f"The recovered {kind} is certified by the analysis theorem "
                   f"\\texttt{{{tex_text(theorem.analysis.theorem)}}}.")
    if solution is not None:
        out.append(_solution_latex(theorem, solution, printer, settings))
    out.append("\\end{document}\n")
    return out[0] + "\n\n" + guarded("\n\n".join(out[1:]))     # the preamble is lmidsl's own


def _design_word(theorem: Theorem) -> str:
    """What the recovery produces, in words: 'controller', 'filter', 'gain', ... ('design')."""
    return {"gain": "state-feedback gain"}.get(theorem.designs, theorem.designs or "design")


def _recovery_latex(theorem: Theorem, printer) -> str:
    """The recovery steps in order: each factorisation with the relation its matrices satisfy
    (e.g. "M, N nonsingular with M N^T = I − X Y", so M and N are defined where they are used),
    then the formulas (a formula may use a matrix recovered before it)."""
    out, formulas = [], []

    def flush():
        if formulas:
            out.append(grouped_display(list(formulas), end="."))
            formulas.clear()

    for step in theorem.recovery_steps or [("formula", n) for n in theorem.recovery]:
        if isinstance(step, FactorStep):
            flush()
            names = [printer.doprint(theorem.intermediate_decl[n].symbol) for n in step.names]
            args = {f"a{i}": printer.doprint(a) for i, a in enumerate(step.args)}
            relation = step.factorization.relation.format(*names, **args)
            out.append(f"Let ${'$, $'.join(names)}$ be nonsingular with ${relation}$ "
                       f"({tex_text(step.factorization.name)}).")
        else:
            name = step[1]
            indexed = getattr(theorem, "indexed_recovery", {}).get(name)
            if indexed is not None:        # K_i = W_i Y_i^{-1}, ∀ i ∈ 𝓝
                expr, family, q = indexed
                formulas.append(f"{printer.doprint(family[q.indices])} = {printer.doprint(expr)}"
                                f"{printer.quantifier(SimpleNamespace(quantifier=q))}")
            else:
                formulas.append(f"{_recovery_name(theorem, name)} = {printer.doprint(theorem.recovery[name])}")
    for name, expr in getattr(theorem, "scheduled", {}).items():     # K(α) = W(α) Y(α)^{-1}, ∀ α
        formulas.append(f"{scheduled_name(theorem, name_to_latex(name))} = {printer.doprint(expr)}"
                        f",\\quad \\forall\\, {domain_latex(theorem, rates=False)}")
    flush()
    return "\n\n".join(out)


def _data_name(theorem: Theorem, name: str, printer) -> str:
    decl = theorem.data_decl.get(name)
    return f"${printer.doprint(decl.symbol)}$" if decl is not None else tex_text(name)


def _scaling_latex(theorem: Theorem, scaling, printer) -> str:
    """What the solver was given instead of the data: the exact signal scalings, stated apart."""
    items = []
    for rec in scaling.records:
        if all(f == 1.0 for f in rec.factors):
            continue
        factors = ", ".join(latex_number(f, 6) for f in rec.factors)
        parts = []
        if rec.rows:
            parts.append("the rows of " + ", ".join(_data_name(theorem, n, printer) for n in rec.rows)
                         + " divided by $S$")
        if rec.cols:
            parts.append("the columns of " + ", ".join(_data_name(theorem, n, printer) for n in rec.cols)
                         + " multiplied by $S$")
        sig = name_to_latex(rec.signal)
        items.append(f"signal ${sig} = S\\,{sig}'$ with "
                     f"$S = \\mathrm{{diag}}({factors})$: " + " and ".join(parts))
    return ("\\textbf{Scaling.} The solver was given the data above after an exact change of "
            "signal coordinates, which leaves the theorem's conditions and its performance level "
            "unchanged: " + "; ".join(items) + ". The recovered matrices below are mapped back "
            "to the data as given; the decision variables and the LMI eigenvalues are those of the "
            "scaled data.")


def _label_latex(theorem: Theorem, label: str, settings: dict) -> str:
    """An LMI's label for running text: '(30)', or the one-block LMI itself ('$P_1 > 0$')."""
    lmi = next((l for l in theorem.lmis if l.label == label), None)
    if lmi is None or equation_tag(label) is not None or lmi.spec.nblocks != 1:
        return tex_text(label)
    return f"${printer_for(theorem, None, **settings).doprint(lmi)}$"


def _inverted_latex(theorem: Theorem, name: str, printer) -> str:
    """A matrix the recovery inverted, named by sympy's string form (``S.T``, ``I - X*Z**(-1)``),
    as mathematics: a declared symbol by its LaTeX, an expression through :func:`tex_text`."""
    decl = theorem.var_decl.get(name) or getattr(theorem, "intermediate_decl", {}).get(name)
    if decl is not None:
        return f"${printer.doprint(decl.symbol)}$"
    text = re.sub(r"\*\*\(?-1\)?", "⁻¹", name).replace(".T", "ᵀ").replace("*", " ")
    return tex_text(text)


def _solution_latex(theorem: Theorem, sol, printer, settings: dict) -> str:
    ex = theorem.examples.get(sol.example) if sol.example else None
    title = f"Example \\texttt{{{tex_text(sol.example)}}}" if sol.example else "Solution"
    out = [f"\\subsection*{{{title}}}"]
    if ex is not None and ex.description:
        out.append(tex_text(ex.description) + ".")
    scaling = sol.scaling
    scaled = scaling is not None and scaling.active
    inst = scaling.original if scaling is not None else sol.instance   # the data the user gave
    if inst is not None:
        data = []
        for name, decl in theorem.data_decl.items():
            value = inst.data.get(name)
            if value is None:
                continue
            if isinstance(value, list):
                data += [f"{with_vertex_index(latex_of(decl.symbol), str(v + 1))} = "
                         f"{latex_matrix(m, 6)}" for v, m in enumerate(value)]
            else:
                data.append(f"{printer.doprint(decl.symbol)} = {latex_matrix(value, 6)}")
        for name, decl in theorem.param_decl.items():
            data.append(f"{printer.doprint(decl.symbol)} = {latex_number(inst.params[name], 6)}")
        for name, decl in theorem.derived_decl.items():
            data.append(f"{printer.doprint(decl.symbol)} = {latex_number(inst.params[name], 6)}")
        if data:
            out.append("Data (as given):\n" + grouped_display(data))
    if scaled:
        out.append(_scaling_latex(theorem, scaling, printer))
    rows = [["status", tex_text(f"{sol.status} ({sol.backend}, {sol.solver})")]]
    perf = theorem.performance[0] if theorem.performance else "gamma"
    perf_tex = name_to_latex(perf)
    verdict = sol.verdict
    if verdict.gamma is not None:
        rows.append([f"${perf_tex}$ ({tex_text(verdict.word)})", f"${latex_number(verdict.gamma, 6)}$"])
    for name, level in verdict.levels.items():
        if level is not None and level != verdict.gamma:
            rows.append([f"${perf_tex}$ at the {tex_text(LEVEL_NAMES.get(name, name))}",
                         f"${latex_number(level, 6)}$"])
    printed = ex.printed if ex is not None else {}
    if "gamma" in printed:
        rows.append([f"${perf_tex}$ printed in the paper", f"${latex_number(printed['gamma'], 6)}$"])
    if "gamma_bound" in printed:
        rows.append([f"${perf_tex}$ claimed by the paper (bound)",
                     f"${latex_number(printed['gamma_bound'], 6)}$"])
    analysis = sol.analysis
    if analysis is not None:
        g = "infeasible" if analysis.gamma is None else f"${latex_number(analysis.gamma, 6)}$"
        passed = "certified" if analysis.passed else "not certified"
        rows.append([f"${perf_tex}$ by analysis \\texttt{{{tex_text(analysis.theorem)}}}",
                     f"{g} ({passed})"])
    for r in sol.lmis:
        where = f" (vertex {r.vertex})" if r.vertex is not None else ""
        rows.append([f"$\\lambda_{{\\max}}$ of {_label_latex(theorem, r.label, settings)}{where}",
                     f"${latex_number(r.max_eig, 3)}$"])
    out.append("\\begin{center}\n" + _table(["quantity", "value"], rows, "ll") + "\n\\end{center}")
    if sol.recovered:
        items = [f"{_recovery_name(theorem, n)} = {latex_matrix(v, 5)}" for n, v in sol.recovered.items()]
        out.append(f"Recovered {_design_word(theorem)} (in the coordinates of the data as given):\n"
                   + grouped_display(items))
        if sol.inverted:
            out.append("Matrices inverted by the recovery (condition number): "
                       + ", ".join(f"{_inverted_latex(theorem, str(inv['matrix']), printer)} "
                                   f"(${latex_number(inv['cond'], 3)}$)" for inv in sol.inverted) + ".")
    variables = []
    for name, value in sol.values.items():
        decl = theorem.var_decl.get(name)
        if decl is None:
            continue
        s = decl.symbol
        if isinstance(value, list):
            variables += [f"{with_vertex_index(latex_of(s), str(v + 1))} = {latex_matrix(m, 5)}"
                          for v, m in enumerate(value) if np.size(m) <= 64]
        elif np.size(value) <= 64:
            variables.append(f"{printer.doprint(s)} = {latex_matrix(value, 5)}")
    if variables:
        out.append("Decision variables at the solution (matrices up to $8 \\times 8$"
                   + ("; they solve the LMIs of the scaled data" if scaled else "") + "):\n"
                   + grouped_display(variables))
    return "\n\n".join(out)
