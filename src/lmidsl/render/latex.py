r"""LaTeX of the LMIs, as the paper prints them.

:class:`LMILatexPrinter` is a sympy :class:`~sympy.printing.latex.LatexPrinter` with a few more
``_print_<Class>`` methods and settings.  It prints

* every declared symbol by its theorem's LaTeX name (``\hat{A}_f``, ``\bar{r}``, ``P_1``);
  per-vertex symbols of a polytopic LMI get the vertex index (``P_{1i}``, ``A_i``);
* a symmetric variable's transpose as the variable itself (``P^{T}`` never appears: the
  transpose of a :class:`~lmidsl.symbolic.symbols.SymmetricVariable` is the variable);
* ``I`` and ``0`` for identity and zero blocks (``I_{n}``, ``0_{n \times k}`` on request);
* a trace as ``\operatorname{tr}(W Z)`` (sympy's ``Trace``, e.g. in an objective);
* a :class:`~lmidsl.symbolic.blocks.BlockMatrixSpec` as a ``bmatrix`` with ``\star`` in the triangle the
  theorem left implicit, and an :class:`~lmidsl.theorem.values.LMI` as ``M < 0`` (or ``M \prec 0``);
* the terms of a sum in the paper's habitual order (positive terms first, then by number of
  factors; ``X`` before ``X^{T}``), because sympy sorts the terms of a ``MatAdd`` when it
  builds it and the order the theorem file wrote is lost;
* ``\mathrm{He}(X)`` for ``X + X^{T}`` when ``he="collapse"``.  ``He(X)`` is expanded to
  ``X + X^{T}`` when the theorem is stated (the compiler wants the sum), so the printer
  *recognises* the pairs: two terms ``c M`` and ``c M^{T}`` with the same scalar ``c`` and
  ``M^{T} \ne M`` print as ``c \mathrm{He}(M)``, ``M`` being the one with fewer transposes.
  Recognising rather than recording keeps the symbolic layer free of printing marks and also
  catches sums the theorem wrote out by hand; ``he="expand"`` (the default, the papers'
  usual form) prints the sum.
* named sub-expressions (:meth:`Theorem.define`, e.g. ``A_{cl0}``) by their name, with the
  definition stated below the LMI, like derived scalars (``a = (1 - \bar{r}) \bar{r}``) and
  structured variables (``\Lambda``).

:func:`lmi_latex` returns the LaTeX of one LMI; :mod:`lmidsl.render.latex_document` builds a
complete document from these pieces; text and numbers are in :mod:`lmidsl.render.latex_text`.
"""
from __future__ import annotations

import re

import sympy as sp
from sympy.matrices.expressions.matexpr import MatrixExpr
from sympy.printing.latex import LatexPrinter

from ..symbolic.blocks import BlockMatrixSpec
from ..symbolic.indexed import INDEXED_TYPES
from ..errors import InputError
from .latex_safe import math_name, plain_text, safe_math
from .latex_text import _GREEK, latex_matrix, latex_number, tex_text
from ..symbolic.symbols import (DerivedParam, StructuredVariable, SymmetricDataMatrix, SymmetricVariable,
                      _Described)
from ..theorem.theorem import Theorem
from ..theorem.values import LMI

__all__ = ["LMILatexPrinter", "lmi_latex", "lmi_where", "name_to_latex", "bisection_latex",
           "with_vertex_index", "tex_text", "latex_number", "latex_matrix"]

_RELATIONS = {
    ("<", False): "<", ("<=", False): r"\le", (">", False): ">", (">=", False): r"\ge",
    ("<", True): r"\prec", ("<=", True): r"\preceq", (">", True): r"\succ",
    (">=", True): r"\succeq",
}

_MODIFIERS = {"hat": r"\hat", "bar": r"\bar", "tilde": r"\tilde", "check": r"\check",
              "dot": r"\dot", "vec": r"\vec"}


#: the names :func:`name_to_latex` reads as the paper's notation (ASCII letters, digits, ``_``)
_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)*")


def name_to_latex(name: str) -> str:
    r"""A LaTeX guess for an identifier: ``Af_hat`` -> ``\hat{A}_f``, ``P1`` -> ``P_1``,
    ``rbar`` -> ``\bar{r}``, ``xi1bar`` -> ``\bar{\xi}_1``, ``Gamma0`` -> ``\Gamma_0``; a name
    that is no identifier prints escaped (:func:`~lmidsl.render.latex_safe.math_name`)."""
    if not _IDENTIFIER.fullmatch(name):
        return math_name(name)
    parts = name.split("_")
    mods = []
    while len(parts) > 1 and parts[-1] in _MODIFIERS:
        mods.append(parts.pop())
    core, extra_subs = parts[0], parts[1:]
    for mod in sorted(_MODIFIERS, key=len, reverse=True):
        if core.endswith(mod) and len(core) > len(mod):
            mods.append(mod)
            core = core[: -len(mod)]
            break
    m = re.match(r"^([A-Za-z]+?)(\d+)$", core)
    if m and (m.group(1) in _GREEK or len(m.group(1)) == 1):
        base, sub = m.group(1), m.group(2)
    elif core in _GREEK or len(core) <= 1:
        base, sub = core, ""
    else:
        greek = next((g for g in sorted(_GREEK, key=len, reverse=True) if core.startswith(g)), None)
        if greek is not None:
            base, sub = greek, core[len(greek):]
        elif core[0].isupper() and core[1:].isalnum():
            base, sub = core[0], core[1:]
        else:
            base, sub = core, ""
    base = "\\" + base if base in _GREEK else (base if len(base) == 1 else rf"\mathrm{{{base}}}")
    for mod in mods:
        base = f"{_MODIFIERS[mod]}{{{base}}}"
    subs = [s for s in [sub, *extra_subs] if s]
    if subs:
        sub = ",".join(subs)
        base += f"_{sub}" if len(sub) == 1 else f"_{{{sub}}}"
    return base


def latex_of(symbol) -> str:
    """The declared LaTeX name of a symbol (when written in the harmless subset of LaTeX,
    :func:`~lmidsl.render.latex_safe.safe_math`; escaped otherwise), or a guess from its identifier."""
    latex = getattr(symbol, "latex_name", None) if isinstance(symbol, _Described) else None
    if latex and latex != symbol.name:
        return safe_math(latex)
    return name_to_latex(symbol.name)


def with_vertex_index(latex: str, index: str) -> str:
    r"""Append a vertex index to the subscript: ``P_1`` -> ``P_{1i}``, ``A`` -> ``A_{i}``."""
    m = re.match(r"^(.*)_\{([^{}]*)\}$", latex) or re.match(r"^(.*)_([A-Za-z0-9])$", latex)
    if m and "^" not in m.group(1)[-1:]:
        return f"{m.group(1)}_{{{m.group(2)}{index}}}"
    sub = index if len(index) == 1 else f"{{{index}}}"
    if "^" in latex:
        return f"{{{latex}}}_{sub}"
    return f"{latex}_{sub}"


def _is_symmetric(expr) -> bool:
    if isinstance(expr, (SymmetricVariable, SymmetricDataMatrix)):
        return True
    if isinstance(expr, StructuredVariable):
        return bool(expr.symmetric)
    return isinstance(expr, (sp.Identity, sp.ZeroMatrix)) and expr.is_square


def _split_coeff(term):
    """(scalar coefficient, matrix part) of a matrix term."""
    if isinstance(term, sp.MatMul):
        scalars = [a for a in term.args if not isinstance(a, MatrixExpr)]
        mats = [a for a in term.args if isinstance(a, MatrixExpr)]
        matrix = mats[0] if len(mats) == 1 else sp.MatMul(*mats)
        return sp.Mul(*scalars), matrix
    return sp.S.One, term


def _negative(c) -> bool:
    """A scalar coefficient with a leading minus sign (-2, -a; not 1 - r, which prints as is)."""
    return bool(c.as_coeff_Mul()[0].is_negative)


def _count_transposes(expr) -> int:
    return sum(1 for node in sp.preorder_traversal(expr) if isinstance(node, sp.Transpose))


def _nfactors(matrix) -> int:
    return len(matrix.args) if isinstance(matrix, sp.MatMul) else 1


class LMILatexPrinter(LatexPrinter):
    r"""sympy's LaTeX printer, taught the theorem's symbols, block LMIs and the paper's habits.

    Settings (besides sympy's): ``star`` (``\star`` or ``*``), ``he`` (``"expand"`` or
    ``"collapse"``), ``relation`` (``"<"`` for ``< 0``, ``"prec"`` for ``\prec 0``),
    ``identity_size`` / ``zero_size`` (print ``I_{n}``, ``0_{n \times k}``), ``term_order``
    (``"paper"`` or ``"sympy"``), ``triangle`` (``"given"``, ``"lower"`` or ``"upper"``: which
    triangle to print explicitly), ``vertex_index`` (subscript for per-vertex symbols in a
    polytopic LMI; None prints them bare), ``notation`` (expression -> LaTeX name),
    ``matrix_env`` (``bmatrix``), ``dim_order`` (dimensions in declaration order, so that a
    size prints as ``n + k`` rather than sympy's sorted ``k + n``).
    """

    printmethod = "_lmidsl_latex"
    _default_settings = {
        **LatexPrinter._default_settings,
        "star": r"\star",
        "he": "expand",
        "relation": "<",
        "identity_size": False,
        "zero_size": False,
        "term_order": "paper",
        "triangle": "given",
        "vertex_index": None,
        "notation": {},
        "matrix_env": "bmatrix",
        "dim_order": (),
        "index_sets": {},
    }

    def __init__(self, settings=None):
        super().__init__(settings)
        for key, allowed in (("he", ("expand", "collapse")), ("relation", ("<", "prec")),
                             ("term_order", ("paper", "sympy")),
                             ("triangle", ("given", "lower", "upper"))):
            if self._settings[key] not in allowed:
                raise InputError(f"latex setting {key}={self._settings[key]!r}: expected one of "
                                 f"{', '.join(allowed)}")

    # -- dispatch: named sub-expressions first ---------------------------------------------
    def _print(self, expr, **kwargs):
        notation = self._settings["notation"]
        if notation and isinstance(expr, sp.Basic) and expr in notation:
            return notation[expr]
        return super()._print(expr, **kwargs)

    def _paren(self, s: str) -> str:
        if any(t in s for t in (r"\begin", r"\frac", r"\sqrt", r"\sum")):
            return rf"\left({s}\right)"
        return f"({s})"

    def _add_parens(self, s) -> str:
        return self._paren(s)

    # -- symbols ---------------------------------------------------------------------
    def _symbol_latex(self, expr) -> str:
        latex = latex_of(expr)
        if self._settings["vertex_index"] and getattr(expr, "per_vertex", False):
            latex = with_vertex_index(latex, self._settings["vertex_index"])
        return latex

    def _print_Symbol(self, expr, style="plain"):
        if isinstance(expr, _Described):
            return self._symbol_latex(expr)
        if not _IDENTIFIER.fullmatch(expr.name):     # a dimension or an index named by the user
            return math_name(expr.name)
        return super()._print_Symbol(expr, style=style)

    def _print_MatrixSymbol(self, expr):
        if isinstance(expr, INDEXED_TYPES):          # A[i] -> A_{i}, Q[i, j] -> Q_{ij}
            return with_vertex_index(latex_of(expr), self._indices(expr.indices))
        if isinstance(expr, _Described):
            return self._symbol_latex(expr)
        if not _IDENTIFIER.fullmatch(expr.name):
            return math_name(expr.name)
        return super()._print_MatrixSymbol(expr)

    # -- index sets ---------------------------------------------------------------------
    def _indices(self, indices) -> str:
        parts = [self._print(k) for k in indices]
        return ("," if any(len(p) > 1 for p in parts) else "").join(parts)

    def _print_Coefficient(self, expr):          # π_ij
        return with_vertex_index(latex_of(expr), self._indices(expr.indices))

    def _range(self, op) -> str:
        r"""The range under Σ, col, diag: j \in \mathcal{N}, j \neq i."""
        sets = self._settings["index_sets"]
        text = rf"{self._print(op.index)} \in {sets.get(op.index.set_name, op.index.set_name)}"
        if op.condition is not None:
            text += f", {self._print(op.condition)}"
        return text

    def _print_IndexSum(self, expr):
        return rf"\sum_{{{self._range(expr)}}} {self._matrix_factor(expr.body)}"

    def _print_IndexStack(self, expr):
        return rf"\operatorname{{col}}_{{{self._range(expr)}}}\left({self._print(expr.body)}\right)"

    def _print_IndexDiag(self, expr):
        return rf"\operatorname{{diag}}_{{{self._range(expr)}}}\left({self._print(expr.body)}\right)"

    def quantifier(self, lmi) -> str:
        """', ∀ i ∈ 𝓘' (', ∀ i, j ∈ 𝓡, i < j') of a quantified LMI; '' otherwise."""
        q = getattr(lmi, "quantifier", None)
        if q is None:
            return ""
        sets = self._settings["index_sets"]
        groups: dict = {}
        for k in q.indices:
            groups.setdefault(k.set_name, []).append(self._print(k))
        text = ", ".join(rf"{', '.join(names)} \in {sets.get(name, name)}" for name, names in groups.items())
        if q.where is not None:
            text += rf",\ {self._print(q.where)}"
        return rf",\quad \forall\, {text}"

    def _print_Add(self, expr, order=None):
        dims = list(self._settings["dim_order"])
        if not dims or not expr.free_symbols or not expr.free_symbols <= set(dims):
            return super()._print_Add(expr, order=order)
        rank = {d: i for i, d in enumerate(dims)}
        terms = sorted(expr.args, key=lambda t: (bool(t.is_Number),
                                                 min((rank[x] for x in t.free_symbols), default=0)))
        out = ""
        for t in terms:
            negative = _negative(t)
            body = self._print(-t if negative else t)
            out += ("-" if negative else "") + body if not out else (" - " if negative else " + ") + body
        return out

    def _print_Mul(self, expr):
        """A product of symbols and sums as the papers write it: sums first, in plain
        parentheses, ``(1 - \\bar{r}) \\bar{r}``; anything with a fraction goes to sympy."""
        factors = list(expr.args)
        if any(f.is_Pow and f.exp.is_negative or f.is_Rational and not f.is_Integer
               or not f.is_commutative for f in factors):
            return super()._print_Mul(expr)
        sign = ""
        if _negative(expr):
            sign, expr = "-", -expr
            factors = list(expr.args) if isinstance(expr, sp.Mul) else [expr]
        numbers = [f for f in factors if f.is_Number]
        sums = [f for f in factors if isinstance(f, sp.Add)]
        rest = [f for f in factors if not f.is_Number and not isinstance(f, sp.Add)]
        parts = [self._print(f) for f in numbers]
        parts += [self._paren(self._print(f)) for f in sums]
        parts += [self.parenthesize(f, 50) for f in rest]  # 50: Mul precedence
        return sign + " ".join(parts)

    def _print_Identity(self, expr):
        if self._settings["identity_size"]:
            return rf"I_{{{self._print(expr.rows)}}}"
        return "I"

    def _print_ZeroMatrix(self, expr):
        if self._settings["zero_size"]:
            return rf"0_{{{self._print(expr.rows)} \times {self._print(expr.cols)}}}"
        return "0"

    # -- matrix operations --------------------------------------------------------------
    def _superscript(self, base_expr, sup: str) -> str:
        base = self._print(base_expr)
        if isinstance(base_expr, (sp.MatrixSymbol, sp.Identity)) or (
                isinstance(base_expr, MatrixExpr) and base_expr in self._settings["notation"]):
            return f"{{{base}}}^{{{sup}}}" if "^" in base else f"{base}^{{{sup}}}"
        return f"{self._paren(base)}^{{{sup}}}"

    def _print_Transpose(self, expr):
        arg = expr.arg
        if _is_symmetric(arg):
            return self._print(arg)
        if isinstance(arg, sp.Inverse) or (isinstance(arg, sp.MatPow) and arg.exp == -1):
            return self._superscript(arg.args[0], "-T")
        return self._superscript(arg, "T")

    def _print_Inverse(self, expr):
        arg = expr.arg
        if isinstance(arg, sp.Transpose) and not _is_symmetric(arg.arg):
            return self._superscript(arg.arg, "-T")
        return self._superscript(arg, "-1")

    def _print_MatPow(self, expr):
        base, exp = expr.args
        if exp == -1:
            return self._print_Inverse(sp.Inverse(base, evaluate=False)) if not isinstance(
                base, sp.Transpose) else self._superscript(base.arg, "-T")
        return self._superscript(base, self._print(exp))

    def _scalar_factor(self, c) -> str:
        s = self._print(c)
        if isinstance(c, sp.Add):
            return self._paren(s)
        return s

    def _matrix_factor(self, m) -> str:
        s = self._print(m)
        if isinstance(m, sp.MatAdd) and m not in self._settings["notation"] and not (
                self._settings["he"] == "collapse" and len(self._ordered_terms(m.args)) == 1):
            return self._paren(s)
        return s

    def _term(self, c, m) -> str:
        """c M for a coefficient c > 0 (not printed when 1) and a matrix M."""
        mats = m.args if isinstance(m, sp.MatMul) else (m,)
        parts = [] if c == 1 else [self._scalar_factor(c)]
        return " ".join(parts + [self._matrix_factor(f) for f in mats])

    def _print_MatMul(self, expr):
        coeff, matrix = _split_coeff(expr)
        sign = ""
        if _negative(coeff):
            sign, coeff = "-", -coeff
        return sign + self._term(coeff, matrix)

    def _ordered_terms(self, terms) -> list:
        """The terms in the paper's habitual order (stable): positive before negative, fewer
        factors first, a scalar-weighted term after an unweighted one; X right before X^T."""
        terms = list(terms)
        if self._settings["term_order"] == "paper":
            def key(t):
                c, m = _split_coeff(t)
                return (_negative(c), _nfactors(m),
                        bool(c not in (1, -1)))
            terms.sort(key=key)
        out, used = [], set()
        for i, t in enumerate(terms):
            if i in used:
                continue
            c, m = _split_coeff(t)
            partner = next((j for j in range(i + 1, len(terms)) if j not in used
                            and _split_coeff(terms[j]) == (c, m.T) and m != m.T), None)
            used.add(i)
            if partner is None:
                out.append((c, m, False))
                continue
            used.add(partner)
            other = _split_coeff(terms[partner])[1]
            if _count_transposes(other) < _count_transposes(m):
                m = other
            out.append((c, m, True))
        return out

    def _print_MatAdd(self, expr):
        pieces = []
        for c, m, pair in self._ordered_terms(expr.args):
            negative = _negative(c)
            if negative:
                c = -c
            if pair and self._settings["he"] == "collapse":
                body = rf"\mathrm{{He}}({self._print(m)})"
                items = [body if c == 1 else f"{self._scalar_factor(c)} {body}"]
            else:
                items = [self._term(c, m)] + ([self._term(c, m.T)] if pair else [])
            for item in items:
                if not pieces:
                    pieces.append(("-" if negative else "") + item)
                else:
                    pieces.append((" - " if negative else " + ") + item)
        return "".join(pieces)

    def _matrix_rows(self, rows) -> str:
        env = self._settings["matrix_env"]
        body = " \\\\\n".join(" & ".join(row) for row in rows)
        return f"\\begin{{{env}}}\n{body}\n\\end{{{env}}}"

    def _print_BlockMatrix(self, expr):
        b = expr.blocks
        rows = [[self._print(b[i, j]) for j in range(b.cols)] for i in range(b.rows)]
        return self._matrix_rows(rows).replace("\n", " ")

    def _print_BlockDiagMatrix(self, expr):
        return r"\mathrm{diag}(" + ", ".join(self._print(a) for a in expr.args) + ")"

    def _print_Trace(self, expr):
        return r"\operatorname{tr}" + self._paren(self._print(expr.arg))

    def _print_MatrixBase(self, expr):
        rows = [[self._print(expr[i, j]) for j in range(expr.cols)] for i in range(expr.rows)]
        return self._matrix_rows(rows).replace("\n", " ")

    # -- block LMIs -----------------------------------------------------------------------
    def _print_BlockMatrixSpec(self, spec: BlockMatrixSpec):
        q = spec.nblocks
        if q == 1:
            return self._print(spec.lower[0][0])
        upper = self._settings["triangle"] == "upper" or (
            self._settings["triangle"] == "given" and spec.given_as == "upper")
        star = self._settings["star"]
        rows = []
        for i in range(q):
            row = []
            for j in range(q):
                explicit = j >= i if upper else j <= i
                row.append(self._print(spec.block(i, j)) if explicit else star)
            rows.append(row)
        return self._matrix_rows(rows)

    def relation(self, sense: str) -> str:
        return _RELATIONS[(sense, self._settings["relation"] == "prec")]

    def _print_LMI(self, lmi: LMI):
        return f"{self._print(lmi.spec)} {self.relation(lmi.sense)} 0{self.quantifier(lmi)}"


# -- helpers for one theorem ----------------------------------------------------------
def printer_for(theorem: Theorem, lmi: LMI | None = None, **settings) -> LMILatexPrinter:
    """The printer for ``theorem`` (its notation, its dimension order; the vertex index for a
    polytopic LMI)."""
    settings.setdefault("dim_order", tuple(theorem.dims.values()))
    settings.setdefault("index_sets", {n: safe_math(s.latex) for n, s in getattr(theorem, "index_sets", {}).items()})
    notation = {d.symbol: safe_math(d.latex) for d in theorem.notation.values()}
    # a named matrix keeps its name under a transpose: sympy distributes Gᵀ over G's definition
    # (a block matrix, a sum), so the distributed form is recognised and printed as G^{T}
    for d in theorem.notation.values():
        if isinstance(d.symbol, sp.MatrixExpr):
            transposed = d.symbol.T
            if transposed != d.symbol and transposed not in notation:
                latex = notation[d.symbol]
                notation[transposed] = f"{{{latex}}}^{{T}}" if "^" in latex else f"{latex}^{{T}}"
    notation.update(settings.pop("notation", {}))
    if lmi is not None and lmi.per_vertex:
        settings.setdefault("vertex_index", "i")
    return LMILatexPrinter({"notation": notation, **settings})


def _get_lmi(theorem: Theorem, label: str) -> LMI:
    for lmi in theorem.lmis:
        if lmi.label == label:
            return lmi
    known = ", ".join(l.label for l in theorem.lmis)
    raise InputError(f"{theorem.id}: no LMI labelled {label!r}; LMIs: {known}")


def equation_tag(label: str) -> str | None:
    """The tag printed beside an LMI: a label that starts with the paper's '(n)' ('(30)', '(10)-exact')."""
    label = label.strip()
    return label if re.match(r"\(.+?\)", label) else None


def lmi_where(theorem: Theorem, lmi: LMI, **settings) -> list[tuple[str, str]]:
    """(name, definition) pairs of the named expressions, structured variables and derived
    scalars that the LMI uses, in the order: notation, structured variables, derived scalars
    (a derived scalar's own derived scalars follow it)."""
    blocks = [b for row in lmi.spec.lower for b in row]
    printer = printer_for(theorem, lmi, **settings)
    out = []
    for name, decl in theorem.notation.items():
        if any(b == decl.symbol or b.has(decl.symbol) for b in blocks):
            inner = printer_for(theorem, lmi, **settings)
            inner._settings["notation"] = {k: v for k, v in inner._settings["notation"].items()
                                           if k != decl.symbol}
            out.append((decl.latex, inner.doprint(decl.symbol)))
    atoms = set().union(*(b.atoms(sp.Symbol, sp.MatrixSymbol) for b in blocks)) if blocks else set()
    for decl in theorem.var_decl.values():
        s = decl.symbol
        if isinstance(s, StructuredVariable) and s in atoms:
            out.append((printer.doprint(s), printer.doprint(s.expansion)))
    for decl in theorem.notation.values():
        if any(b.has(decl.symbol) for b in blocks):
            atoms |= decl.symbol.atoms(sp.Symbol)
    seen = set()
    queue = [d.symbol for d in theorem.derived_decl.values() if d.symbol in atoms]
    while queue:
        s = queue.pop(0)
        if s in seen:
            continue
        seen.add(s)
        out.append((printer.doprint(s), printer.doprint(s.definition)))
        queue += [d for d in s.definition.free_symbols if isinstance(d, DerivedParam)]
    return out


def lmi_latex(theorem: Theorem, label: str, *, display: bool = False, **settings) -> str:
    r"""The LaTeX of the LMI ``label`` of ``theorem``.

    By default the bare relation (``\begin{bmatrix}...\end{bmatrix} < 0``, math mode).  With
    ``display=True``: the display (``\lmidisplay``: tagged with the paper's label, shrunk to
    the line width, or on a landscape page when much too wide) followed by the "where"
    definitions; that form needs the preamble of :func:`lmidsl.render.latex_document.theorem_latex`.
    """
    lmi = _get_lmi(theorem, label) if isinstance(label, str) else label
    body = printer_for(theorem, lmi, **settings).doprint(lmi)
    if not display:
        return body
    return display_lmi(theorem, lmi, body, lmi_where(theorem, lmi, **settings))


def tag_text(label: str) -> str:
    """An LMI's tag as the document prints it: its '(n)' label, escaped (text); '' without one."""
    tag = equation_tag(label)
    return "" if tag is None else plain_text(tag)


def display_lmi(theorem, lmi, body, where) -> str:
    text = f"\\lmidisplay{{{body}}}{{{tag_text(lmi.label)}}}"
    if where or lmi.per_vertex:
        text += "\n" + _where_block(where, lmi.per_vertex)
    return text


def _where_block(where, per_vertex: bool = False) -> str:
    """'where a = ..., A_{cl0} = ...' (and 'for every vertex i' of a polytopic LMI)."""
    vertex = r"for every vertex $i = 1, \dots, N$"
    if not where:
        return vertex + "."
    items = [f"{name} = {definition}" for name, definition in where]
    return (vertex + ", " if per_vertex else "") + "where\n" + grouped_display(items, end=".")


def grouped_display(items: list[str], end: str = "") -> str:
    """Display math items separated by commas, as many a line as fit: each item is a box of its
    own (\\lmiitem, shrunk only if it alone is wider than the line) and LaTeX breaks the lines
    between items, so no line is shrunk to hold a fixed number of them."""
    body = "\\hskip 2em plus 1em minus 0.5em\n".join(
        f"\\lmiitem{{{item}{',' if k < len(items) - 1 else end}}}" for k, item in enumerate(items))
    return "\\begin{lmiitems}\n" + body + "\n\\end{lmiitems}"


def bisection_latex(theorem: Theorem) -> str | None:
    """The goal of a theorem solved by bisection, in words and maths: 'maximise h ∈ [0, 10] such
    that the conditions are feasible (bisection to 10⁻⁴)'; None without a bisection."""
    b = getattr(theorem, "bisection", None)
    if b is None:
        return None
    decl = theorem.param_decl.get(b.parameter)
    name = LMILatexPrinter().doprint(decl.symbol) if decl is not None else b.parameter
    goal = "Maximise" if b.goal == "max" else "Minimise"
    text = (f"{goal} ${name} \\in [{latex_number(b.lower)}, {latex_number(b.upper)}]$ such that the "
            f"conditions are feasible (bisection on ${name}$ to ${latex_number(b.tol)}$)")
    return text + (f": {tex_text(b.performance)}." if b.performance else ".")
