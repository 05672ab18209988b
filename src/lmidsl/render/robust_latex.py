r"""LaTeX of a robust theorem as a paper writes it, and of the coefficient LMIs it generates.

The statement (:class:`lmidsl.theorem.robust.RobustTheorem`)::

    \forall \alpha \in \Lambda_N:\quad A(\alpha)^T P(\alpha) + P(\alpha) A(\alpha) \prec 0, ...
    where A(\alpha) = \sum_{i=1}^{N} \alpha_i A_i,\ P(\alpha) = \sum_{|k| = g} \alpha^k P_k,
    \Lambda_N = \{\alpha \in \mathbb{R}^N : \alpha_i \ge 0, \sum_i \alpha_i = 1\}

and the relaxation used (the degree g of each HPPD variable, the degree D each LMI is made
homogeneous of, Pólya's d, the number of coefficient LMIs).  With a member (the theorem bound
to N, g, d), :func:`coefficient_lmis_latex` prints every generated LMI, labelled by its monomial.
Plain LaTeX (MathJax, KaTeX and the document preamble alike).
"""
from __future__ import annotations

from dataclasses import replace

from ..symbolic.simplex import exponent_latex
from .latex import display_lmi, grouped_display, lmi_latex, printer_for, tex_text

__all__ = ["robust_statement_latex", "robust_conditions_latex", "coefficient_lmis_latex", "domain_latex",
           "robust_where", "as_stated", "scheduled_name"]


def _simplex_set(s, size: str) -> str:
    return (rf"\Lambda_{{{size}}} = \{{{s.latex} \in \mathbb{{R}}^{{{size}}} : {s.latex}_i \ge 0,\ "
            rf"\textstyle\sum_{{i=1}}^{{{size}}} {s.latex}_i = 1\}}")


def _sizes(theorem, member=None) -> list:
    if member is not None:
        return [str(n) for n in member.robust.sizes]
    return [s.size or "N" if len(theorem.simplices) == 1 else f"N_{{{k + 1}}}" for k, s in enumerate(theorem.simplices)]


def domain_latex(theorem, member=None, rates: bool = True) -> str:
    r"""'\alpha \in \Lambda_N' or '(\alpha, \beta) \in \Lambda_{N_1} \times \Lambda_{N_2}'."""
    sizes = _sizes(theorem, member)
    names = [s.latex for s in theorem.simplices]
    point = names[0] if len(names) == 1 else "(" + ", ".join(names) + ")"
    out = point + r" \in " + r" \times ".join(rf"\Lambda_{{{n}}}" for n in sizes)
    for rate in getattr(theorem, "rates", ()) if rates else ():    # rate-bounded: α̇ ∈ b·H_N
        n = sizes[rate.simplex.index]
        out += rf",\ \dot{{{rate.simplex.latex}}} \in {rate.latex}\,\mathcal{{H}}_{{{n}}}"
    return out


def _definitions(theorem, member=None) -> list[str]:
    """A(α) = Σ αᵢ Aᵢ and P(α) = Σ_{|k|=g} α^k P_k for every α-dependent declaration."""
    sizes = _sizes(theorem, member)
    g = str(member.robust.degree) if member is not None else "g"
    out = []
    for name, decl in theorem.polynomial.items():
        lhs = decl.symbol.latex_name
        base = name if decl.kind != "vertex" else theorem.data_decl[name].symbol.name
        if decl.kind == "vertex":
            if len(theorem.simplices) == 1:
                s = theorem.simplices[0].latex
                out.append(rf"{lhs} = \sum_{{i=1}}^{{{sizes[0]}}} {s}_i {base}_i")
            else:
                idx = ",".join(f"i_{k + 1}" for k in range(len(sizes)))
                weights = " ".join(f"{s.latex}_{{i_{k + 1}}}" for k, s in enumerate(theorem.simplices))
                out.append(rf"{lhs} = \sum_{{{idx}}} {weights}\, {base}_{{{idx}}}")
        elif decl.kind == "derivative":
            a = decl.rate.simplex.latex
            n = sizes[decl.rate.simplex.index]
            of = theorem.polynomial[decl.of].symbol.latex_name
            out.append(rf"{lhs} = \sum_{{i=1}}^{{{n}}} \frac{{\partial {of}}}{{\partial {a}_i}}\, \dot{{{a}}}_i")
        else:
            degree = g if decl.degree == "degree" else str(decl.degree)
            s = ",".join(x.latex for x in decl.simplices)
            out.append(rf"{lhs} = \sum_{{|k| = {degree}}} {s}^{{k}} {base}_{{k}}")
    for rate in getattr(theorem, "rates", ()):
        n = sizes[rate.simplex.index]
        out.append(rf"\mathcal{{H}}_{{{n}}} = \{{h \in \mathbb{{R}}^{{{n}}} : \textstyle\sum_i h_i = 0,\ "
                   rf"|h_i| \le 1\}}\ (|\dot{{{rate.simplex.latex}}}_i| \le {rate.latex})")
    return out


def robust_statement_latex(theorem, member=None) -> str:
    """The statement in α (display maths), its domain, the polynomial forms and the degrees
    (symbolic g, d; or the member's numbers)."""
    lines = [rf"\text{{{theorem.id}: {tex_text(theorem.title)}}}",
             rf"\text{{for all }} {domain_latex(theorem, member)}:"]
    for lmi in theorem.lmis:
        body = printer_for(theorem, lmi, vertex_index=None).doprint(lmi)
        lines.append(rf"{body} \qquad \text{{{tex_text(lmi.label)}}}")
    where = _definitions(theorem, member)
    sizes = _sizes(theorem, member)
    where += [_simplex_set(s, n) for s, n in zip(theorem.simplices, sizes)]
    lines.append(r"\text{where } " + r",\quad ".join(where))
    lines.append(_degrees_text(theorem, member))
    return "$$\\begin{gathered}\n" + " \\\\\n".join(lines) + "\n\\end{gathered}$$"


def _degrees_text(theorem, member=None) -> str:
    if member is None:
        g = theorem.param_decl["degree"].extra["default"]
        d = theorem.param_decl["polya"].extra["default"]
        return (rf"\text{{imposed: every coefficient of }} (\textstyle\sum_i \alpha_i)^{{d}} \times "
                rf"\text{{each LMI made homogeneous; defaults }} g = {g},\ d = {d}")
    info = member.robust
    parts = [f"g = {info.degree}", f"d = {info.polya}"]
    for label, degree in info.lmi_degree.items():
        count = len(info.coefficients[label])
        total = ",".join(str(x + info.polya) for x in degree)
        parts.append(rf"\text{{{tex_text(label)}: homogeneous of degree {','.join(map(str, degree))}, "
                     rf"times }} (\textstyle\sum_i \alpha_i)^{{{info.polya}}}\text{{: degree {total}, "
                     rf"{count} coefficient LMIs}}")
    return r"\text{imposed: }" + r",\quad ".join(parts)


def coefficient_lmis_latex(member) -> str:
    """Every coefficient LMI of a member, labelled by its monomial α^m."""
    info = member.robust
    alpha = ",".join(s.latex for s in info.statement.simplices)
    by_label = {lmi.label: lmi for lmi in member.lmis}
    lines = []
    for label, items in info.coefficients.items():
        for exponent, member_label in items:
            body = lmi_latex(member, by_label[member_label])
            lines.append(rf"{body} \qquad \text{{{tex_text(label)}, }} {alpha}^{{({exponent_latex(exponent)})}}")
    return "$$\\begin{gathered}\n" + " \\\\\n".join(lines) + "\n\\end{gathered}$$"


def robust_conditions_latex(theorem, member=None) -> str:
    r"""The 'Conditions' of a LaTeX document (:func:`lmidsl.render.latex_document.theorem_latex`)
    for a statement over the simplex: each LMI once, in α, "for all α ∈ Λ_N", the polynomial
    forms and the degrees (uses the document's ``\lmidisplay``)."""
    out = [rf"For all ${domain_latex(theorem, member)}$:"]
    for lmi in theorem.lmis:
        body = printer_for(theorem, lmi, vertex_index=None).doprint(lmi)
        out.append(display_lmi(theorem, _untagged_vertex(lmi), body, []))
    sizes = _sizes(theorem, member)
    where = _definitions(theorem, member) + [_simplex_set(s, n) for s, n in zip(theorem.simplices, sizes)]
    out.append("where\n" + grouped_display(where, end="."))
    out.append(f"${_degrees_text(theorem, member)}$.")
    return "\n\n".join(out)


def robust_where(theorem) -> tuple[str, list[str]]:
    r"""The quantifier ('for all $\alpha \in \Lambda_N$', with the rate set when there is one) and
    the definitions (A(α), P(α), Ṗ, the sets) of one LMI printed alone (``latex --lmi``)."""
    sizes = _sizes(theorem)
    where = _definitions(theorem) + [_simplex_set(s, n) for s, n in zip(theorem.simplices, sizes)]
    return rf"for all ${domain_latex(theorem)}$", where


def scheduled_name(theorem, name: str) -> str:
    """A scheduled recovery's name with its arguments: K(α)."""
    return f"{name}({','.join(s.latex for s in theorem.simplices)})"


def as_stated(lmi):
    """The LMI of a robust statement as printed: once, in α (not per vertex)."""
    return _untagged_vertex(lmi)


def _untagged_vertex(lmi):
    """The LMI as printed: stated once in α, not per vertex."""
    return replace(lmi, per_vertex=False)
