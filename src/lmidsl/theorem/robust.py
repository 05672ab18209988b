"""Robust LMIs over the simplex: a theorem stated once in α, expanded into coefficient LMIs.

A robust theorem declares the uncertainty domain, the data given at its vertices and the
variables that are homogeneous polynomials in α, and writes its LMIs once, in α::

    thm = RobustTheorem("textbook.hpd_stability_ct", "...", Source(...), time="continuous")
    n = thm.dim("n")
    alpha = thm.simplex("alpha")                        # α ∈ Λ_N, N = number of vertices
    A = thm.data("A", n, n, over=alpha)                 # A(α) = Σ αᵢ Aᵢ
    P = thm.var("P", n, kind="symmetric", over=alpha)   # P(α) = Σ_{|k|=g} α^k P_k, g = `degree`
    thm.lmi("(HPPD)", [[He(P * A)]])                    # ∀ α ∈ Λ_N
    thm.positive(P)

``degree`` (g) and ``polya`` (d) are parameters of the theorem (``--set degree=2 --set
polya=1``; defaults at construction).  Binding an instance (``specialise``) builds, once per
(N, g, d), the *member*: an ordinary :class:`~lmidsl.theorem.theorem.Theorem` whose decision
variables are the coefficients P_k, whose data are the vertex matrices Aᵢ (aliases of the
per-vertex datum ``A``, filled in at bind time), and whose LMIs are the coefficient LMIs of
each stated LMI: every block made homogeneous of the LMI's largest degree, multiplied by
(Σ αᵢ)^d, one LMI per monomial α^m (:func:`lmidsl.symbolic.simplex.coefficient_blocks`).  The
member is compiled, solved, certified and proved like any theorem, so the proved LMIs at a
returned point are exactly the coefficient LMIs.  Each coefficient LMI ≺ 0 implies the stated
LMI for every α in the domain (Pólya; see :mod:`lmidsl.symbolic.simplex`).

A product of simplices (``thm.simplex("alpha", size="Na")``, ``thm.simplex("beta",
size="Nb")``) takes its sizes from parameters; the vertex data are then listed at the
Na·Nb product vertices (first simplex slowest) and are multi-affine in (α, β).

**Rate-bounded parameters** (continuous-time LPV systems, α = α(t)): ``rate =
thm.rate(alpha, bound="b")`` declares |α̇ᵢ(t)| ≤ b (b a parameter), i.e. α̇ ∈ b·H_N with
H_N = {h : Σ hᵢ = 0, |hᵢ| ≤ 1}, a polytope written as the convex combinations Σⱼ βⱼ hⱼ of its
vertices, β ∈ Λ_M a simplex of its own; ``dP = thm.derivative(P, rate)`` is
Ṗ(α, α̇) = Σᵢ ∂P/∂αᵢ α̇ᵢ (:func:`lmidsl.symbolic.simplex.time_derivative`), to be written in an
LMI as any matrix (``He(P * A) + dP``).  The member then expands over Λ_N × Λ_M, but data and
variables stay functions of α alone (degree 0 in β: no product-vertex duplication), and only
the LMIs that contain a derivative get one coefficient LMI per β-monomial.  A gain that
depends on α, K(α) = W(α)Y(α)⁻¹, is declared with :meth:`RobustTheorem.recover_scheduled` and
evaluated at a given α after the solve (:func:`lmidsl.certify.rate_bounded.scheduled`).

Theorem files and the member never mention α at compile time; the member's ``robust``
attribute (:class:`RobustMember`) says where it came from (the statement, sizes, degrees, the
polynomial forms), for printing and for the grid evidence (:mod:`lmidsl.certify.simplex_grid`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import InputError, TheoremDefinitionError
from ..symbolic.blocks import BlockMatrixSpec
from ..symbolic.simplex import (HomogeneousPolynomial, coefficient_blocks, exponent_latex, exponent_text,
                                multi_exponents, rate_vertices, statement_degree, time_derivative,
                                vertex_exponents)
from ..symbolic.symbols import DataMatrix
from .budget import check, robust_estimate
from .members import MemberRule, built_member
from .theorem import Theorem
from .values import LMI

MAX_DEGREE = 8
MAX_POLYA = 8


@dataclass(frozen=True)
class Simplex:
    """One simplex Λ_N of the uncertainty domain; ``size`` names the parameter giving N (None:
    N is the number of vertices, for a single simplex)."""

    name: str
    latex: str
    size: str | None
    index: int


@dataclass(frozen=True)
class Rate:
    """A bound |α̇ᵢ| ≤ b on the rate of the simplex ``simplex``: α̇ ∈ b·H_N (``bound`` names the
    parameter b)."""

    simplex: Simplex
    bound: str
    latex: str
    index: int


@dataclass
class PolynomialDecl:
    """A declaration that depends on α: vertex data (degree 1 in every simplex) or an HPPD
    variable of degree ``degree`` (an int, or the name of the degree parameter)."""

    symbol: object
    kind: str                 # "vertex", "variable" or "derivative" (of ``of`` over ``rate``)
    simplices: tuple
    degree: object = 1
    var_kind: str = "full"
    shape: tuple = ()
    of: str | None = None     # a derivative: the HPPD variable differentiated
    rate: Rate | None = None  # a derivative: the rate bound of its simplex


@dataclass
class RobustMember:
    """What a member theorem was expanded from."""

    statement: "RobustTheorem"
    sizes: tuple
    degree: int
    polya: int
    forms: dict                                  # statement symbol -> HomogeneousPolynomial
    vertex_data: dict                            # alias name -> (datum, vertex index)
    coefficients: dict = field(default_factory=dict)   # statement LMI label -> [(exponent, member label)]
    lmi_degree: dict = field(default_factory=dict)     # statement LMI label -> degree per simplex (before Pólya)
    coefficient_vars: dict = field(default_factory=dict)  # HPPD variable -> {exponent: coefficient symbol}
    rate_sizes: tuple = ()                       # vertices of each rate simplex (after the simplices)


class RobustTheorem(Theorem):
    """A theorem over the simplex (or a product of simplices), see the module docstring."""

    def __init__(self, id: str, title: str, source, *, degree: int = 1, polya: int = 0, **options):
        super().__init__(id, title, source, **options)
        self.options = options
        self.simplices: list[Simplex] = []
        self.rates: list[Rate] = []
        self.scheduled: dict = {}
        self.polynomial: dict[str, PolynomialDecl] = {}
        self._members: dict = {}
        self.param("degree", latex="g", domain=(0, MAX_DEGREE), default=degree,
                   description="degree of the homogeneous polynomial Lyapunov (HPPD) variables in α")
        self.param("polya", latex="d", domain=(0, MAX_POLYA), default=polya,
                   description="degree of Pólya's relaxation: the LMIs times (Σ αᵢ)^d")

    def __getstate__(self) -> dict:
        state = super().__getstate__()
        state["_members"] = {}          # rebuilt on demand
        return state

    # -- declarations ----------------------------------------------------------------------
    def simplex(self, name: str = "alpha", *, latex: str | None = None, size: str | None = None) -> Simplex:
        """Declare a simplex of the domain; ``size`` names an integer parameter giving its
        number of vertices (declared here), needed when the domain has several simplices."""
        if any(s.name == name for s in self.simplices):
            raise TheoremDefinitionError(f"{self.id}: the simplex {name} is declared twice")
        if size is not None:
            self.param(size, domain=(1, 64), default=2, description=f"number of vertices of the simplex {name}")
        s = Simplex(name, latex or ("\\" + name if name in ("alpha", "beta", "theta", "lambda") else name),
                    size, len(self.simplices))
        self.simplices.append(s)
        return s

    def _over(self, over, name: str) -> tuple:
        over = tuple(over) if isinstance(over, (list, tuple)) else (over,)
        if not over or not all(isinstance(s, Simplex) for s in over):
            raise TheoremDefinitionError(f"{self.id}: {name}: over= takes the simplices of thm.simplex()")
        if len(self.simplices) > 1 and any(s.size is None for s in self.simplices):
            raise TheoremDefinitionError(f"{self.id}: with several simplices, each needs size= (a parameter name)")
        return over

    def _arguments(self, over) -> str:
        return ",".join(s.latex for s in over)

    def data(self, name: str, rows, cols, *, over=None, latex: str | None = None, **kwargs):
        """Declare a datum; with ``over=alpha`` (or a tuple of every simplex), it is given at the
        vertices (under ``"vertices"``) and is affine (multi-affine) in α: A(α) = Σ αᵢ Aᵢ."""
        if over is None:
            return super().data(name, rows, cols, latex=latex, **kwargs)
        over = self._over(over, name)
        if len(over) != len(self.simplices):
            raise TheoremDefinitionError(f"{self.id}: vertex data {name} must be over every simplex "
                                         f"of the domain ({', '.join(s.name for s in self.simplices)})")
        latex = latex or f"{name}({self._arguments(over)})"
        symbol = super().data(name, rows, cols, latex=latex, per_vertex=True, **kwargs)
        self.polynomial[name] = PolynomialDecl(symbol, "vertex", over, 1, shape=(rows, cols))
        return symbol

    def var(self, name: str, rows, cols=None, *, over=None, degree="degree", kind: str = "full",
            latex: str | None = None, **kwargs):
        """Declare a decision matrix; with ``over=alpha`` it is a homogeneous polynomial of
        degree ``degree`` in α (the ``degree`` parameter by default, or a fixed integer):
        P(α) = Σ_{|k|=g} α^k P_k, one decision matrix P_k per monomial."""
        if over is None:
            return super().var(name, rows, cols, kind=kind, latex=latex, **kwargs)
        over = self._over(over, name)
        if not (degree == "degree" or isinstance(degree, int) and 0 <= degree <= MAX_DEGREE):
            raise TheoremDefinitionError(f"{self.id}: {name}: degree is 'degree' (the parameter) or an "
                                         f"integer in [0, {MAX_DEGREE}]")
        latex = latex or f"{name}({self._arguments(over)})"
        symbol = super().var(name, rows, cols, kind=kind, latex=latex, **kwargs)
        self.polynomial[name] = PolynomialDecl(symbol, "variable", over, degree, kind,
                                               (rows, rows if cols is None else cols))
        return symbol

    def rate(self, simplex: Simplex, *, bound: str = "b", latex: str | None = None,
             default: float | None = None) -> Rate:
        """Declare the rate bound |α̇ᵢ(t)| ≤ b of a time-varying α (b: a parameter named ``bound``,
        declared here).  For one scheduling parameter θ ∈ [θ₁, θ₂] with vertices A₁ = A(θ₁),
        A₂ = A(θ₂): α₂ = (θ − θ₁)/(θ₂ − θ₁), and |θ̇| ≤ ν is b = ν/(θ₂ − θ₁)."""
        if not isinstance(simplex, Simplex) or simplex not in self.simplices:
            raise TheoremDefinitionError(f"{self.id}: rate: the first argument is a simplex of thm.simplex()")
        if any(r.simplex == simplex for r in self.rates):
            raise TheoremDefinitionError(f"{self.id}: the rate of {simplex.name} is declared twice")
        self.param(bound, latex=latex or "b", domain=(0, 1e6), default=default,
                   description=f"bound on the rates |d{simplex.name}_i/dt|")
        rate = Rate(simplex, bound, latex or "b", len(self.rates))
        self.rates.append(rate)
        return rate

    def derivative(self, variable, rate: Rate, *, name: str | None = None, latex: str | None = None):
        """Ṗ(α, α̇) = Σᵢ ∂P/∂αᵢ α̇ᵢ of an HPPD variable P over the rate polytope of ``rate``: a
        matrix to write in an LMI (``He(P * A) + dP``), expanded by
        :func:`lmidsl.symbolic.simplex.time_derivative`."""
        decl = self.polynomial.get(getattr(variable, "name", None))
        if decl is None or decl.kind != "variable" or not isinstance(rate, Rate) or rate not in self.rates:
            raise TheoremDefinitionError(f"{self.id}: derivative: takes an HPPD variable (var(..., over=alpha)) "
                                         f"and a rate of thm.rate()")
        if rate.simplex not in decl.simplices:
            raise TheoremDefinitionError(f"{self.id}: derivative: {variable.name} does not depend on "
                                         f"{rate.simplex.name}")
        name = name or f"d{variable.name}"
        s = rate.simplex.latex
        latex = latex or rf"\dot{{{variable.name}}}({s},\dot{{{s}}})"
        symbol = super().var(name, *decl.shape, kind=decl.var_kind, latex=latex,
                             description=f"time derivative of {variable.name} along the rates |d{rate.simplex.name}/dt| ≤ {rate.bound}")
        self.polynomial[name] = PolynomialDecl(symbol, "derivative", decl.simplices, decl.degree, decl.var_kind,
                                               decl.shape, of=variable.name, rate=rate)
        return symbol

    def recover_scheduled(self, **formulas):
        """Recoveries that depend on α (K(α) = W(α)Y(α)⁻¹ with W, Y HPPD): checked for shapes like
        any recovery, kept in α, and evaluated at a given α after the solve
        (:func:`lmidsl.certify.rate_bounded.scheduled`)."""
        for key, expr in formulas.items():
            self._check_new(key)
            self.scheduled[key] = expr
        return tuple(formulas.values()) if len(formulas) > 1 else next(iter(formulas.values()))

    # -- members -----------------------------------------------------------------------------
    def sizes_for(self, inputs: dict) -> tuple:
        """The number of vertices of each simplex for these inputs."""
        vertices = inputs.get("vertices")
        count = len(vertices) if isinstance(vertices, list) and vertices else 1
        if not self.simplices:
            return ()
        if len(self.simplices) == 1 and self.simplices[0].size is None:
            return (count,)
        sizes = tuple(_integer(self.id, s.size, inputs.get(s.size, self.param_decl[s.size].extra["default"]),
                               1, 64) for s in self.simplices)
        if int(np.prod(sizes)) != count:
            raise InputError(f"{self.id}: the domain {' × '.join(f'Λ_{n}' for n in sizes)} has "
                             f"{int(np.prod(sizes))} vertices, but {count} are given under 'vertices'")
        return sizes

    def member_rule(self):
        return SimplexRule()

    def estimate(self, sizes: tuple, degree: int, polya: int, inputs: dict | None = None):
        """The size of the member for these sizes and degrees, before it is built
        (:func:`lmidsl.theorem.budget.robust_estimate`; dimensions from ``inputs``' data)."""
        degrees = {}
        for decl in self.polynomial.values():
            g = 1 if decl.kind == "vertex" else (degree if decl.degree == "degree" else decl.degree)
            degrees[decl.symbol] = tuple(g if s in decl.simplices else 0 for s in self.simplices)
        lmi_degrees = {lmi.label: statement_degree(lmi.spec, degrees, len(self.simplices))
                       for lmi in self.lmis if lmi.symbols() & set(degrees)}
        return robust_estimate(self, tuple(sizes), degree, polya, inputs or {}, lmi_degrees)

    def member(self, sizes: tuple, degree: int, polya: int) -> Theorem:
        """The coefficient theorem for these sizes and degrees (built once per declaration,
        :func:`lmidsl.theorem.members.built_member`; no limit check: ``specialise`` makes it)."""
        return built_member(self, SimplexRule(), (tuple(sizes), int(degree), int(polya)))

    def _expand(self, sizes: tuple, degree: int, polya: int) -> Theorem:
        m = Theorem.__new__(Theorem)
        m.__dict__.update({k: v for k, v in self.__dict__.items()
                           if k not in ("_members", "options", "simplices", "polynomial", "rates")})
        m.family = self
        m.var_decl, m.lmis = {}, []
        m.param_decl = dict(self.param_decl)
        for name, value in (("degree", degree), ("polya", polya)) + tuple(
                (s.size, n) for s, n in zip(self.simplices, sizes) if s.size):
            decl = self.param_decl[name]
            extra = {**decl.extra, "domain": (value, value), "default": value,
                     "note": f"the member for {name} = {value}; another value selects another member"}
            m.param_decl[name] = type(decl)(decl.symbol, decl.latex, decl.description, extra)
        taken = set(self.data_decl) | set(self.var_decl) | set(self.param_decl) | set(self.dims)
        forms, aliases, coefficient_vars = {}, {}, {}
        vertex_exps = vertex_exponents(sizes)
        nsimplex = len(sizes)
        rate_sizes = tuple(len(rate_vertices(sizes[r.simplex.index])) for r in self.rates)
        all_sizes = tuple(sizes) + rate_sizes
        still = tuple((0,) * M for M in rate_sizes)       # degree 0 in every rate simplex
        for name, decl in self.polynomial.items():
            symbol = decl.symbol
            if decl.kind == "derivative":
                continue
            if decl.kind == "vertex":
                members = {}
                for v, e in enumerate(vertex_exps):
                    alias = f"{name}_" + "_".join(str(p.index(1) + 1) for p in e)
                    _check_free(self.id, alias, taken)
                    tex = f"{self.data_decl[name].symbol.name}_{{{','.join(str(p.index(1) + 1) for p in e)}}}"
                    a = DataMatrix(alias, *symbol.shape, self.id)
                    a.latex_name = tex
                    a.description = f"vertex {v + 1} of {name}"
                    aliases[alias] = (name, v)
                    members[tuple(e) + still] = a
                forms[symbol] = HomogeneousPolynomial.from_coefficients(members, all_sizes,
                                                                        (1,) * nsimplex + (0,) * len(rate_sizes))
            else:
                g = degree if decl.degree == "degree" else decl.degree
                degrees = tuple(g if s in decl.simplices else 0 for s in self.simplices)
                coefficients = {}
                for k in multi_exponents(sizes, degrees):
                    cname = f"{name}_{exponent_text(k)}"
                    _check_free(self.id, cname, taken)
                    base = self.var_decl[name]
                    c = Theorem.var(m, cname, *decl.shape, kind=decl.var_kind,
                                    latex=f"{symbol.name}_{{{exponent_latex(k)}}}",
                                    description=f"coefficient of α^{exponent_text(k)} in {name}(α)"
                                                + (f": {base.description}" if base.description else ""))
                    coefficients[k] = c
                coefficient_vars[name] = coefficients
                forms[symbol] = HomogeneousPolynomial.from_coefficients(
                    {tuple(k) + still: c for k, c in coefficients.items()}, all_sizes,
                    degrees + (0,) * len(rate_sizes))
        for name, decl in self.polynomial.items():
            if decl.kind == "derivative":
                bound = self.param_decl[decl.rate.bound].symbol
                forms[decl.symbol] = time_derivative(forms[self.polynomial[decl.of].symbol],
                                                     decl.rate.simplex.index, nsimplex + decl.rate.index, bound)
        for name, decl in self.var_decl.items():
            if name not in self.polynomial:
                m.var_decl[name] = decl
        info = RobustMember(self, tuple(sizes), degree, polya, forms, aliases, rate_sizes=rate_sizes)
        symbols = set(forms)
        for lmi in self.lmis:
            if not (lmi.symbols() & symbols):
                m.lmis.append(lmi)
                continue
            where = f"{self.id}: LMI {lmi.label}"
            multiplier = (polya,) * nsimplex + (0,) * len(rate_sizes)   # affine in β: no Pólya there
            total, coefficients = coefficient_blocks(lmi.spec, forms, all_sizes, multiplier, where=where)
            info.lmi_degree[lmi.label] = tuple(t - d for t, d in zip(total, multiplier))
            labels = []
            for exponent, lower in coefficients:
                label = f"{lmi.label} α^{exponent_text(exponent[:nsimplex])}"
                if any(total[nsimplex:]):
                    label += f" β^{exponent_text(exponent[nsimplex:])}"
                coefficient = LMI(label, BlockMatrixSpec(lower, lmi.spec.sizes, "lower"), lmi.sense,
                                  lmi.strict, f"coefficient of α^{exponent_text(exponent)} of {lmi.label}")
                coefficient.per_vertex = False
                m.lmis.append(coefficient)
                labels.append((exponent, label))
            info.coefficients[lmi.label] = labels
        used = [("the objective", self.objective),
                *((f"the recovery of {k}", v) for k, v in self.recovery.items()),
                *((f"the report of {k}", v) for k, v in self.reported.items())]
        if self.performance is not None:
            used.append((f"the performance {self.performance[0]}", self.performance[1]))
        for what, expr in used:
            if expr is not None and sp.sympify(expr).free_symbols & symbols:
                raise TheoremDefinitionError(f"{self.id}: {what} uses a parameter-dependent symbol "
                                             f"({', '.join(sorted(str(s) for s in sp.sympify(expr).free_symbols & symbols))}); "
                                             f"only α-independent symbols can be used after the solve")
        m.vertex_data = aliases
        m.robust = info
        info.coefficient_vars = coefficient_vars
        return m

    def lmi(self, label: str, rows, **kwargs):
        """Declare an LMI (stated in α when it mentions α-dependent symbols); besides the checks
        of :meth:`Theorem.lmi`, every block must be polynomial in α (no inverse or function of
        an α-dependent matrix), checked now on a one-vertex domain."""
        lmi = super().lmi(label, rows, **kwargs)
        count = len(self.simplices) + len(self.rates)
        forms = {d.symbol: HomogeneousPolynomial.from_coefficients(
                     {tuple((1,) for _ in range(count)): d.symbol}, (1,) * count,
                     (1,) * count) for d in self.polynomial.values()}
        if forms and lmi.symbols() & set(forms):
            try:
                coefficient_blocks(lmi.spec, forms, (1,) * count, 0, where=f"{self.id}: LMI {label}")
            except TheoremDefinitionError:
                self.lmis.remove(lmi)
                raise
        return lmi

    def summary(self) -> dict:
        out = super().summary()
        out["robust"] = {"simplices": [s.name for s in self.simplices],
                         "degree": self.param_decl["degree"].extra["default"],
                         "polya": self.param_decl["polya"].extra["default"]}
        return out


class SimplexRule(MemberRule):
    """A :class:`RobustTheorem` (:mod:`lmidsl.theorem.members`): the key is the simplices' vertex
    counts, ``degree`` and ``polya``; the member's size is estimated from the statement and refused
    past the limits before it is expanded."""

    def key(self, theorem, inputs: dict) -> tuple:
        sizes = theorem.sizes_for(inputs)
        degree = _integer(theorem.id, "degree", inputs.get("degree", theorem.param_decl["degree"].extra["default"]),
                          0, MAX_DEGREE)
        polya = _integer(theorem.id, "polya", inputs.get("polya", theorem.param_decl["polya"].extra["default"]),
                         0, MAX_POLYA)
        check(theorem.id, theorem.estimate(sizes, degree, polya, inputs))
        return (tuple(sizes), degree, polya)

    def build(self, theorem, key: tuple) -> Theorem:
        return theorem._expand(*key)


def _integer(theorem_id: str, name: str, value, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
        raise InputError(f"{theorem_id}: {name} must be an integer, got {value!r}")
    value = int(value)
    if not low <= value <= high:
        raise InputError(f"{theorem_id}: {name} = {value} is outside [{low}, {high}]")
    return value


def _check_free(theorem_id: str, name: str, taken: set) -> None:
    if name in taken:
        raise TheoremDefinitionError(f"{theorem_id}: the expansion needs the name {name}, which the "
                                     f"theorem declares itself; rename that declaration")
    taken.add(name)


def vertex_matrices(instance, name: str) -> list:
    """The vertex values of a per-vertex datum of a bound instance (a list, vertex order)."""
    value = instance.data[name]
    return list(value) if isinstance(value, list) else [value]


__all__ = ["RobustTheorem", "RobustMember", "Simplex", "Rate", "SimplexRule", "vertex_matrices"]
