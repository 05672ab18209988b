"""Homogeneous polynomials in α over the unit simplex, with matrix coefficients, and Pólya's
relaxation: the algebra of robust LMIs over a polytope.

The unit simplex Λ_N = {α ∈ ℝᴺ : αᵢ ≥ 0, Σ αᵢ = 1}; a product of simplices Λ_{N₁} × … × Λ_{N_q}
(multi-simplex, e.g. one simplex Λ₂ per interval parameter).  A matrix polynomial is
*homogeneous* of degree g (one degree per simplex) when

    M(α) = Σ_{|k| = g} α^k M_k,      α^k = α₁^{k₁} ⋯ α_N^{k_N},

the sum over the C(N + g − 1, g) exponents k ∈ ℕᴺ with k₁ + … + k_N = g.  Data given at the
vertices, A(α) = Σ αᵢ Aᵢ, are homogeneous of degree 1 (on a multi-simplex, multi-affine:
A(α) = Σ_{i,j} α¹ᵢ α²ⱼ A_ij, degree (1, 1)); a constant C is degree 0.

Operations (:class:`HomogeneousPolynomial`), on the simplex where Σ αᵢ = 1:

* a sum of terms of degrees g < h is made homogeneous first: the lower one is multiplied by
  (Σ αᵢ)^{h−g} = 1, i.e. for each simplex
  (Σ αᵢ)^r Σ_k α^k M_k = Σ_m α^m Σ_{j ≤ m, |j| = r} r!/(j₁!⋯j_N!) M_{m−j};
* a product (in the order written: matrix products do not commute) adds the exponents:
  (Σ_k α^k M_k)(Σ_l α^l N_l) = Σ_m α^m Σ_{k+l=m} M_k N_l;
* a transpose acts on each coefficient.

**Pólya's relaxation of degree d.**  A homogeneous M(α) with M(α) ≺ 0 for all α ∈ Λ_N is
certified by asking every coefficient of (Σ αᵢ)^d M(α) (degree g + d) to be ≺ 0: each α^m ≥ 0
on the simplex and Σ_m α^m > 0, so M(α) = (Σ αᵢ)^d M(α) is a nonnegative, nonzero
combination of negative definite matrices.  The converse holds for d large enough
(Pólya's theorem; for matrices, Scherer 2005 and Oliveira & Peres, IEEE TAC 52(7), 2007):
the relaxation converges as d grows.  The multinomial coefficients are exact integers.

Coefficients are sympy expressions kept as sums of (integer, term) pairs and assembled into a
``MatAdd`` only at the end; :class:`PolynomialForm` walks a block of an LMI (the same walk as
every other concern, :mod:`lmidsl.symbolic.walker`) with the polynomial form of each symbol
that depends on α and treats every other sub-expression as a constant (degree 0).
"""
from __future__ import annotations

import itertools
from functools import lru_cache
from math import factorial

import sympy as sp

from ..errors import TheoremDefinitionError
from .walker import Walker

__all__ = ["exponents", "multi_exponents", "multinomial", "HomogeneousPolynomial", "PolynomialForm",
           "coefficient_blocks", "exponent_text", "exponent_latex", "vertex_exponents", "rate_vertices",
           "time_derivative", "statement_degree"]


@lru_cache(maxsize=None)
def exponents(N: int, g: int) -> tuple:
    """Every k ∈ ℕᴺ with |k| = g, in descending lexicographic order ((g,0,…,0) first, as ROLMIP
    lists monomials); C(N + g − 1, g) of them."""
    if N == 1:
        return ((g,),)
    out = []
    for first in range(g, -1, -1):
        out.extend((first, *rest) for rest in exponents(N - 1, g - first))
    return tuple(out)


@lru_cache(maxsize=None)
def multi_exponents(sizes: tuple, degrees: tuple) -> tuple:
    """The exponents of a multi-simplex: one exponent per simplex, first simplex slowest."""
    return tuple(itertools.product(*(exponents(N, g) for N, g in zip(sizes, degrees))))


def vertex_exponents(sizes: tuple) -> tuple:
    """The exponent of each vertex of Λ_{N₁} × … (α at the vertex: unit vectors), in the order
    the vertex data are listed (first simplex slowest)."""
    units = [[tuple(int(i == j) for j in range(N)) for i in range(N)] for N in sizes]
    return tuple(itertools.product(*units))


@lru_cache(maxsize=None)
def multinomial(k: tuple) -> int:
    """|k|! / (k₁! ⋯ k_N!), exact."""
    out = factorial(sum(k))
    for ki in k:
        out //= factorial(ki)
    return out


def _add_exp(a: tuple, b: tuple) -> tuple:
    return tuple(tuple(x + y for x, y in zip(p, q)) for p, q in zip(a, b))


def _sub_exp(a: tuple, b: tuple):
    out = tuple(tuple(x - y for x, y in zip(p, q)) for p, q in zip(a, b))
    return None if any(x < 0 for p in out for x in p) else out


def exponent_text(exponent: tuple) -> str:
    """'201' for ((2, 0, 1),), '10_01' for a multi-simplex exponent ('2-10-1' past 9)."""
    sep = "" if all(x < 10 for p in exponent for x in p) else "-"
    return "_".join(sep.join(str(x) for x in p) for p in exponent)


def exponent_latex(exponent: tuple) -> str:
    """'201' / '10,01' (a multi-simplex exponent): the subscript of a coefficient."""
    sep = "" if all(x < 10 for p in exponent for x in p) else ","
    return ",".join(sep.join(str(x) for x in p) for p in exponent)


def _term(coefficient, expr):
    if coefficient == 1:
        return expr
    if coefficient == -1:
        return -expr
    return sp.Integer(coefficient) * expr if isinstance(coefficient, int) else coefficient * expr


def _is_matrix(expr) -> bool:
    return isinstance(expr, sp.MatrixExpr)


class HomogeneousPolynomial:
    """M(α) = Σ_k α^k M_k on Λ_{N₁} × …: ``sizes`` (N per simplex), ``degree`` (per simplex),
    ``terms[k]`` = {term: integer multiplier} (the coefficient M_k is Σ multiplier·term)."""

    __slots__ = ("sizes", "degree", "terms")

    def __init__(self, sizes: tuple, degree: tuple, terms: dict):
        self.sizes, self.degree, self.terms = tuple(sizes), tuple(degree), terms

    # -- constructors --------------------------------------------------------------------
    @classmethod
    def constant(cls, expr, sizes: tuple) -> "HomogeneousPolynomial":
        zero = tuple((0,) * N for N in sizes)
        return cls(sizes, (0,) * len(sizes), {zero: {expr: 1}})

    @classmethod
    def from_coefficients(cls, coefficients: dict, sizes: tuple, degree: tuple) -> "HomogeneousPolynomial":
        """Σ_k α^k C_k from {exponent: expression}."""
        return cls(sizes, degree, {k: {c: 1} for k, c in coefficients.items()})

    # -- algebra -------------------------------------------------------------------------
    def raised(self, degree: tuple) -> "HomogeneousPolynomial":
        """The same polynomial on the simplex, written with degree ``degree`` ≥ self.degree:
        multiplied by Π_s (Σ_i α^s_i)^{r_s}, with the multinomial coefficients."""
        shift = tuple(d - g for d, g in zip(degree, self.degree))
        if any(r < 0 for r in shift):
            raise ValueError(f"cannot lower the degree {self.degree} to {degree}")
        if not any(shift):
            return self
        return self._times_sum_power(shift)

    def polya(self, d) -> "HomogeneousPolynomial":
        """(Σ αᵢ)^d M(α) (``d`` an integer, or one per simplex): Pólya's multiplier."""
        d = (d,) * len(self.sizes) if isinstance(d, int) else tuple(d)
        return self._times_sum_power(d) if any(d) else self

    def _times_sum_power(self, shift: tuple) -> "HomogeneousPolynomial":
        extra = multi_exponents(self.sizes, shift)
        weight = {j: _product(multinomial(p) for p in j) for j in extra}
        out: dict = {}
        for k, terms in self.terms.items():
            for j in extra:
                m = _add_exp(k, j)
                bucket = out.setdefault(m, {})
                w = weight[j]
                for t, c in terms.items():
                    bucket[t] = bucket.get(t, 0) + w * c
        degree = tuple(g + r for g, r in zip(self.degree, shift))
        return HomogeneousPolynomial(self.sizes, degree, _drop_zeros(out))

    def __add__(self, other: "HomogeneousPolynomial") -> "HomogeneousPolynomial":
        degree = tuple(max(a, b) for a, b in zip(self.degree, other.degree))
        a, b = self.raised(degree), other.raised(degree)
        out = {k: dict(v) for k, v in a.terms.items()}
        for k, terms in b.terms.items():
            bucket = out.setdefault(k, {})
            for t, c in terms.items():
                bucket[t] = bucket.get(t, 0) + c
        return HomogeneousPolynomial(self.sizes, degree, _drop_zeros(out))

    def scaled(self, c) -> "HomogeneousPolynomial":
        """c·M(α) for an integer c."""
        return HomogeneousPolynomial(self.sizes, self.degree,
                                     {k: {t: c * v for t, v in terms.items()} for k, terms in self.terms.items()})

    def __neg__(self):
        return self.scaled(-1)

    def product(self, other: "HomogeneousPolynomial", multiply) -> "HomogeneousPolynomial":
        """M(α)·N(α) in this order; ``multiply(s, t)`` forms the product of two terms."""
        out: dict = {}
        for k, terms_k in self.terms.items():
            for l, terms_l in other.terms.items():
                bucket = out.setdefault(_add_exp(k, l), {})
                for s, a in terms_k.items():
                    for t, b in terms_l.items():
                        st = multiply(s, t)
                        bucket[st] = bucket.get(st, 0) + a * b
        degree = tuple(a + b for a, b in zip(self.degree, other.degree))
        return HomogeneousPolynomial(self.sizes, degree, _drop_zeros(out))

    def map(self, f) -> "HomogeneousPolynomial":
        """f applied to every term (f linear: a transpose, a trace)."""
        out: dict = {}
        for k, terms in self.terms.items():
            bucket = out.setdefault(k, {})
            for t, c in terms.items():
                ft = f(t)
                bucket[ft] = bucket.get(ft, 0) + c
        return HomogeneousPolynomial(self.sizes, self.degree, _drop_zeros(out))

    # -- coefficients --------------------------------------------------------------------
    def coefficient(self, exponent):
        """M_k as one sympy expression (a sum of integer multiples of terms); None when zero."""
        terms = self.terms.get(exponent)
        if not terms:
            return None
        parts = [_term(c, t) for t, c in terms.items()]
        if len(parts) == 1:
            return parts[0]
        return sp.MatAdd(*parts) if _is_matrix(parts[0]) else sp.Add(*parts)

    def value(self, alpha, evaluate) -> object:
        """M(α) at a point: Σ_k α^k evaluate(M_k) (``alpha``: one sequence per simplex)."""
        total = None
        for k in self.terms:
            weight = _product(a ** e for p, a_s in zip(k, alpha) for e, a in zip(p, a_s))
            v = weight * evaluate(self.coefficient(k))
            total = v if total is None else total + v
        return total

    def __repr__(self) -> str:
        return f"HomogeneousPolynomial(sizes={self.sizes}, degree={self.degree}, {len(self.terms)} monomials)"


def _product(values):
    out = 1
    for v in values:
        out = out * v
    return out


def _drop_zeros(terms: dict) -> dict:
    out = {}
    for k, bucket in terms.items():
        kept = {t: c for t, c in bucket.items() if c != 0}
        if kept:
            out[k] = kept
    return out


def _matmul(a, b):
    return a * b


class PolynomialForm(Walker):
    """The homogeneous polynomial in α of a matrix or scalar expression, given ``forms`` — the
    polynomial of each symbol that depends on α (vertex data, HPPD variables).  A sub-expression
    without such a symbol is a constant (degree 0); an inverse or a function of one is refused
    (it is not polynomial)."""

    action = "expand in the simplex variables"

    def __init__(self, forms: dict, sizes: tuple, where: str = ""):
        super().__init__(where)
        self.forms = forms
        self.sizes = tuple(sizes)
        self._symbols = frozenset(forms)

    def _dispatch(self, expr):
        if expr in self.forms:
            return self.forms[expr]
        if not expr.free_symbols & self._symbols:
            return HomogeneousPolynomial.constant(expr, self.sizes)
        return super()._dispatch(expr)

    def _not_polynomial(self, expr):
        raise self.error(TheoremDefinitionError,
                         f"{expr} is not polynomial in the simplex variables (only sums, products "
                         f"and transposes of parameter-dependent matrices are)")

    def _visit_MatAdd(self, expr):
        out = None
        for a in expr.args:
            p = self.visit(a)
            out = p if out is None else out + p
        return out

    _visit_Add = _visit_MatAdd

    def _visit_MatMul(self, expr):
        out = None
        for a in expr.args:
            p = self.visit(a)
            out = p if out is None else out.product(p, _matmul)
        return out

    _visit_Mul = _visit_MatMul

    def _visit_Transpose(self, expr):
        return self.visit(expr.arg).map(lambda t: t.T)

    def _visit_Trace(self, expr):
        return self.visit(expr.arg).map(sp.Trace)

    def _visit_MatPow(self, expr):
        base, exp = expr.args
        if exp.is_Integer and exp > 0:
            p = self.visit(base)
            out = p
            for _ in range(int(exp) - 1):
                out = out.product(p, _matmul)
            return out
        return self._not_polynomial(expr)

    _visit_Pow = _visit_MatPow

    def _visit_Basic(self, expr):
        return self._not_polynomial(expr)


def coefficient_blocks(spec, forms: dict, sizes: tuple, polya, where: str = "") -> tuple:
    """The coefficient LMIs of a block LMI stated in α: every block's polynomial
    (:class:`PolynomialForm`), all made homogeneous of the largest degree D, times
    (Σ αᵢ)^polya; returns (D + polya per simplex, [(exponent m, lower triangle of the
    coefficient blocks at α^m)]).  A block with no term at α^m is a zero block of its size."""
    walker = PolynomialForm(forms, sizes, where=where)
    polys = [[walker.visit(b) for b in row] for row in spec.lower]
    degree = tuple(max(p.degree[s] for row in polys for p in row) for s in range(len(sizes)))
    polya = (polya,) * len(sizes) if isinstance(polya, int) else tuple(polya)
    polys = [[p.raised(degree).polya(polya) for p in row] for row in polys]
    total = tuple(g + d for g, d in zip(degree, polya))
    out = []
    for m in multi_exponents(tuple(sizes), total):
        lower = []
        for i, row in enumerate(polys):
            cells = []
            for j, p in enumerate(row):
                c = p.coefficient(m)
                cells.append(sp.ZeroMatrix(spec.sizes[i], spec.sizes[j]) if c is None else c)
            lower.append(cells)
        out.append((m, lower))
    return total, out


# -- the time derivative of an HPPD matrix over a rate polytope (rate-bounded parameters) -------
@lru_cache(maxsize=None)
def rate_vertices(N: int) -> tuple:
    """The vertices of H_N = {h ∈ ℝᴺ : Σ hᵢ = 0, |hᵢ| ≤ 1}, the rates α̇ of a point moving on
    Λ_N with |α̇ᵢ| ≤ 1 (the set for the bound b is b·H_N).  A vertex has N − 1 coordinates at
    ±1 and the last fixed by Σ hᵢ = 0: integer vectors with entries in {−1, 0, 1} (N = 2:
    (1, −1) and (−1, 1); N = 3: the 6 permutations of (1, −1, 0))."""
    if N < 2:
        return ()
    found = set()
    for free in range(N):
        for signs in itertools.product((1, -1), repeat=N - 1):
            h = list(signs[:free]) + [0] + list(signs[free:])
            h[free] = -sum(h)
            if abs(h[free]) <= 1:
                found.add(tuple(h))
    # a vertex of the polytope is not a midpoint of two others (those with a free 0 may be)
    points = sorted(found, reverse=True)
    return tuple(p for p in points
                 if not any(tuple((a + b) for a, b in zip(q, r)) == tuple(2 * x for x in p)
                            for q in points for r in points if q < r and q != p and r != p))


def time_derivative(form: HomogeneousPolynomial, simplex: int, rate: int, scale=1) -> HomogeneousPolynomial:
    """Ṗ(α, β) = Σᵢ ∂P/∂αᵢ · α̇ᵢ with α̇ = scale·Σⱼ βⱼ hⱼ (hⱼ the vertices of
    :func:`rate_vertices`, β ∈ Λ_M a simplex of its own at position ``rate`` of ``form.sizes``).

    For P(α) = Σ_k α^k P_k homogeneous of degree g in the simplex at position ``simplex``,
    ∂P/∂αᵢ = Σ_k kᵢ α^{k−eᵢ} P_k, so Ṗ = Σ_k Σᵢ Σⱼ kᵢ hⱼᵢ α^{k−eᵢ} βⱼ (scale·P_k): homogeneous of
    degree g − 1 in α and 1 in β, multi-affine with the data (this is how ROLMIP writes the
    derivative of a polynomial variable over a rate polytope).  ``scale`` (the bound b, a symbol
    or number) multiplies every term; degree 0 in α gives the zero polynomial (a constant P)."""
    N = form.sizes[simplex]
    rates = rate_vertices(N)
    if len(rates) != form.sizes[rate]:
        raise ValueError(f"the rate simplex has {form.sizes[rate]} vertices, H_{N} has {len(rates)}")
    degree = list(form.degree)
    out: dict = {}
    for k, terms in form.terms.items():
        for i in range(N):
            ki = k[simplex][i]
            if not ki:
                continue
            lowered = list(k)
            lowered[simplex] = tuple(x - (a == i) for a, x in enumerate(k[simplex]))
            for j, h in enumerate(rates):
                if not h[i]:
                    continue
                m = list(lowered)
                m[rate] = tuple(x + (b == j) for b, x in enumerate(k[rate]))
                bucket = out.setdefault(tuple(m), {})
                for t, c in terms.items():
                    term = t if scale == 1 else scale * t
                    bucket[term] = bucket.get(term, 0) + c * ki * h[i]
    if out:
        degree[simplex] -= 1
        degree[rate] += 1
    return HomogeneousPolynomial(form.sizes, tuple(degree), _drop_zeros(out))


def statement_degree(spec, degrees: dict, nsimplex: int, where: str = "") -> tuple:
    """The degree per simplex of a block LMI stated in α (its largest block degree), before
    Pólya: its polynomial on the one-vertex domain Λ₁ × …, where each α-dependent symbol has
    one coefficient (``degrees``: symbol -> its degree per simplex), so nothing is expanded."""
    sizes = (1,) * nsimplex
    forms = {symbol: HomogeneousPolynomial.from_coefficients({tuple((g,) for g in degree): symbol}, sizes, degree)
             for symbol, degree in degrees.items()}
    total, _ = coefficient_blocks(spec, forms, sizes, 0, where=where)
    return total

