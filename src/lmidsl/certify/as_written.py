"""The compiled SDP against the SDP as written: a rigorous bound on every compiled coefficient's error.

The direct backend compiles each LMI N(x) = N⁰ + Σ_c x_c N^c (and the objective) in double
precision: the data are the doubles nearest to the decimals the user wrote, constant
sub-expressions are folded in floating point, and every product and sum of the compiling walk is
rounded.  The proofs of lmidsl (:mod:`lmidsl.certify.dual_bound`, :mod:`lmidsl.certify.infeasibility`)
are about the problem *as written*: the data and parameters are the decimals the user wrote, taken
as the rationals they denote (:func:`lmidsl.numeric.proof.decimal_ball`), like the proofs of the
LMIs at a point.  Where a data expression cancels (``K·(a + b − c)`` with a, b, c = 0.1, 0.2, 0.3
and K = 10²⁰ is 0 as written and about 2776 as compiled) the two problems differ by far more than
a rounding.

This module walks every LMI again, in the same order and with the same constant folding as the
compile (:meth:`~lmidsl.solver.backends.base.CompiledModel.walk_lmis`), in a *magnitude* algebra:
every value is a triple (B, ε, e) with, entrywise,

    |ĉ − c| ≤ ε·B   and   |c| ≤ B,

ĉ the compiled double, c the exact value, B ≥ 0 a matrix (or affine form, whose coefficients are
magnitudes) and ε a scalar:

* a folded constant K (data, parameters and numbers, no decision variable): its compiled double
  K̂ and a ball enclosure of the exact value (python-flint, data as written) give
  δ ≥ |K̂ − K| entrywise, ε = ε₀ = 4u and B = max(|K̂| + δ, δ/ε₀) — an entry that cancels (as
  written or as compiled) gets a large B, not a large ε for every entry;
* a rounded product, sum or matrix product with n terms per entry, m terms still pending per
  coefficient (the affine algebra adds duplicate triplets later): ε ← (1 + ε₁)(1 + ε₂)(1 + γ) − 1
  with γ ≥ γ_{nm+1} (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.1, doubled),
  B ← B₁·B₂ or B₁ + B₂ — minus signs become plus signs, so B has no cancellation;
* the coefficients of one LMI as the proofs read them (both triangles of the symmetric pairing
  summed, :class:`~lmidsl.certify.dual_point.DualData`) pay one more sum.

The radius of a coefficient is ε·B (slightly inflated for the rounding of B itself); ε of one
cell of a block matrix does not spread to the other cells.

The rational routes (a rational dual point on a support, exact dependencies between equations)
need the coefficients as written *exactly*: :class:`ExactCoefficients` evaluates the LMIs in
rational arithmetic (python-flint ``fmpq_mat``, decimals as the rationals they denote) at x = 0
and at the unit vectors of the variables asked for — the compiled N(x) is affine, so
N^c = N(e_c) − N(0) — with the conditioning's congruence and variable scaling applied exactly.
A parameter with an irrational value (√ of a parameter) has no such coefficients.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from functools import reduce

import numpy as np
import sympy as sp
from flint import arb, fmpq, fmpq_mat

from ..numeric.evaluate import NumericEvaluator
from ..numeric.exact import ExactEvaluator, NotRational, to_matrix
from ..numeric.proof import PRECISION, BallEvaluator, ball_precision, round_up
from ..symbolic.symbols import DECISION_TYPES, DerivedParam, StructuredVariable
from ..solver.backends.affine import Affine, block as affine_block
from ..solver.backends.base import BackendCompiler, CompiledModel, classify

U = 2.0 ** -53
TINY = 2.0 ** -900
#: ε of a folded constant that differs from its value as written (B absorbs the rest)
LEAF_EPS = 4 * U
#: relative slack for the rounding of B itself (a sum of ≤ 10⁷ non-negative terms loses less)
B_SLACK = 1e-6


class EnclosureUnavailable(ValueError):
    """A constant has no ball enclosure (a function python-flint does not evaluate, a singular
    inverse): the compiled coefficients cannot be related to the data as written."""


def gamma(k: int) -> float:
    """2·γ_k, γ_k = k u/(1 − k u): twice Higham's bound for k rounded operations."""
    return 2.0 * k * U / (1.0 - k * U)


def grow(*eps: float, k: int = 1) -> float:
    """(Π (1 + ε_i))·(1 + 2γ_k) − 1, rounded up: the relative error after one more rounded step."""
    out = 1.0 + gamma(k)
    for e in eps:
        out *= 1.0 + e
    return round_up(out - 1.0, 4) * (1 + 8 * U)


@dataclass
class Mag:
    """A value of the magnitude walk: B (≥ 0, an ndarray, float or :class:`Affine` with
    non-negative coefficients) and ε."""

    B: object
    eps: float = 0.0

    @property
    def shape(self):
        return getattr(self.B, "shape", ())


def _pending(value) -> int:
    """Terms an affine coefficient still sums (duplicate triplets), 1 for a constant."""
    if not isinstance(value, Affine) or len(value.rows) < 2:
        return 1
    key = value.rows.astype(np.int64) * (int(value.cols.max()) + 1) + value.cols
    return int(np.unique(key, return_counts=True)[1].max())


class _Snapshot:
    """What the walk reads of a model, fixed when the solve ended (the model may be compiled
    again meanwhile, on another thread): its instance, conditioning and variables."""

    walk_lmis = CompiledModel.walk_lmis
    variable_for = CompiledModel.variable_for
    _parameter_value = CompiledModel._parameter_value

    def __init__(self, model):
        self.instance = model.instance
        self.equilibration = model.equilibration
        self._variables = dict(model._variables)
        self.space = getattr(model, "space", None)
        self.current_lmi = None
        self.decimals: dict = {}          # (name, vertex) -> the datum as written, exactly


class MagnitudeWalker(BackendCompiler):
    """The compiling walk in the magnitude algebra (module docstring): the same folding of
    constant sub-expressions as :class:`~lmidsl.solver.backends.base.BackendCompiler`."""

    def __init__(self, model, vertex):
        super().__init__(model, vertex)
        self.balls = BallEvaluator(model.instance.dims, model.instance.data, model.instance.params, vertex)

    def _dispatch(self, expr):
        decision, parameter = classify(expr)
        if not decision:
            scalar = not isinstance(expr, sp.MatrixExpr) and not expr.has(sp.MatrixSymbol)
            if not parameter or scalar or isinstance(expr, (sp.Inverse, sp.MatPow)):
                return self.constant(expr, parameter, scalar)
        return super(BackendCompiler, self)._dispatch(expr)

    def constant(self, expr, parameter: bool, scalar: bool) -> Mag:
        """A folded constant: its compiled double (as the compile computes it) against its ball."""
        model = self.model
        if not parameter:
            value = self.constants.visit(expr)
        elif scalar:
            value = model._parameter_value(expr)
        else:
            value = NumericEvaluator(self.dims, model.instance.data, model.instance.params, self.vertex).visit(expr)
        try:
            ball = self.balls.visit(expr)
        except (ZeroDivisionError, ValueError, TypeError, KeyError, NotImplementedError) as exc:
            raise EnclosureUnavailable(f"{self.context()}: no ball for {expr} ({type(exc).__name__}: {exc})") from None
        compiled = np.asarray(value, dtype=float)
        exact = np.asarray(ball, dtype=object)
        if exact.shape != compiled.shape:
            exact = np.broadcast_to(exact, compiled.shape)
        delta = np.empty(compiled.shape)
        for idx, c in np.ndenumerate(compiled):
            e = exact[idx]
            bound = (arb(float(c)) - (e if isinstance(e, arb) else arb(float(e)))).abs_upper()  # exact
            delta[idx] = 0.0 if bound == 0 else round_up(float(bound), 2)
        # B ≥ |K̂| + δ and B ≥ δ/ε₀: |K̂ − K| ≤ ε₀·B with one small ε₀ — an entry that cancels as
        # written (K̂ = 0, K = 0 ± 1e-64) or as compiled gets a larger B, not a larger ε for all
        B = np.maximum(np.abs(compiled) + delta, delta / LEAF_EPS) * (1 + 4 * U)
        eps = LEAF_EPS if delta.any() else 0.0
        return Mag(float(B) if compiled.ndim == 0 else B, eps)

    # -- leaves that are not constants ------------------------------------------------
    def variable(self, symbol):
        value = self.model.variable_for(symbol, self.vertex)
        factor = self.model.equilibration.variable(symbol.name)
        return Mag(value if factor == 1.0 else factor * value)          # 1·s_X: exact

    scalar_variable = variable

    def identity(self, n):
        return Mag(np.eye(n))

    def zeros(self, r, c):
        return Mag(np.zeros((r, c)))

    # -- operations: minus signs become plus signs ------------------------------------
    def add(self, a, b):
        return Mag(a.B + b.B, grow(max(a.eps, b.eps), k=1))

    subtract = add

    def negate(self, a):
        return a

    def scale(self, c, a):
        return Mag(c.B * a.B, grow(c.eps, a.eps, k=1))

    def matmul(self, a, b):
        inner = a.shape[-1] if len(a.shape) == 2 else 1
        k = inner * max(_pending(a.B), _pending(b.B)) + 1
        return Mag(a.B @ b.B, grow(a.eps, b.eps, k=k))

    def transpose(self, a):
        return Mag(a.B.T if len(a.shape) == 2 else a.B, a.eps)

    def trace(self, a):
        r = a.shape[0]
        value = a.B.trace() if isinstance(a.B, Affine) else float(np.trace(a.B))
        return Mag(value, grow(a.eps, k=r * _pending(a.B)))

    def block(self, rows):
        B = affine_block([[c.B for c in row] for row in rows])
        return Mag(B, max(c.eps for row in rows for c in row))

    def congruence(self, value, factor: float):
        if factor == 1.0:
            return value
        return Mag(value.B * factor, grow(value.eps, k=1))

    def inverse(self, a, expr):
        raise EnclosureUnavailable(f"{self.context()}: the inverse of {expr} depends on a decision variable")

    def _visit_Mul(self, expr):
        return reduce(self.scale, (self.visit(a) for a in expr.args))

    def _visit_Add(self, expr):
        return reduce(self.add, (self.visit(a) for a in expr.args))

    def _visit_Pow(self, expr):
        base, exp = expr.args
        if exp != 1:
            raise EnclosureUnavailable(f"{self.context()}: {expr} is not affine")
        return self.visit(base)


def _final_eps(mag: Mag) -> float:
    """ε after the last sum the proofs make (the duplicates of a coefficient, both triangles),
    with the slack for the rounding of B."""
    return grow(mag.eps, k=2 * _pending(mag.B) + 1) * (1 + B_SLACK)


def radii(R):
    """(radii of the coefficient triplets, radii of the constant term) of a radius form R (an
    :class:`Affine` or a constant matrix), rounded up."""
    vals = np.asarray(R.vals, dtype=float) if isinstance(R, Affine) else np.zeros(0)
    const = np.asarray(R.const if isinstance(R, Affine) else R, dtype=float)
    return (np.where(vals > 0, vals * (1 + 4 * U) + TINY, 0.0),
            np.where(const > 0, const * (1 + 4 * U) + TINY, 0.0))


def _radius_of_cells(rows):
    """The radius form of a block matrix, cell by cell (ε of one cell does not spread)."""
    return affine_block([[c.B * _final_eps(c) for c in row] for row in rows])


@dataclass
class CoefficientBounds:
    """The radii of every compiled LMI (in the compile's order) and of the objective."""

    lmis: list = field(default_factory=list)        # radius form per LMI instance
    objective: object = None


def coefficient_bounds(snapshot) -> CoefficientBounds:
    """The magnitude walk of every LMI and of the objective of a model (its :class:`_Snapshot`):
    the radii of the compiled coefficients against the data as written (module docstring)."""
    out = CoefficientBounds()
    with ball_precision(PRECISION):
        for _, _, _, _, rows, _ in snapshot.walk_lmis(lambda v: MagnitudeWalker(snapshot, v)):
            out.lmis.append(_radius_of_cells(rows))
        objective = snapshot.instance.theorem.objective
        if objective is not None:
            mag = MagnitudeWalker(snapshot, None).visit(objective)
            out.objective = mag.B * _final_eps(mag)
    return out


def decimal(x) -> fmpq:
    """The decimal a double was written as (its shortest repr), exactly."""
    n, d = sp.Rational(repr(float(x))).as_numer_denom()
    return fmpq(int(n), int(d))


def _exact_factor(x: float) -> fmpq:
    n, d = float(x).as_integer_ratio()        # a conditioning factor: the double itself
    return fmpq(n, d)


class _ExactWalk(ExactEvaluator):
    """One LMI walk in rational arithmetic: data and parameters as written, the decision vector
    x = Σ_c w_c e_c for ``point`` = {c: w_c} (entries of x; None: x = 0), each entry times its
    variable's conditioning factor, as compiled.  ``free``: values given to the derived
    parameters whose definitions are irrational (evaluated as free symbols)."""

    def __init__(self, snap, vertex, point: dict | None, free: dict | None = None, memo: dict | None = None,
                 active: frozenset | None = None):
        super().__init__(snap.instance.dims, self._value, free_irrational=free is not None)
        self.snap, self.vertex, self.point, self.free = snap, vertex, point or {}, free or {}
        self.memo = {} if memo is None else memo    # (id, vertex) -> value at x = 0, every sub-tree
        self.active = active                        # the variables of ``point`` (None: x = 0)

    def visit(self, expr):
        """A block with no rational value is :data:`IRRATIONAL` (its LMI has no exact
        coefficients; the others still do)."""
        if self._root is not None:
            return super().visit(expr)
        try:
            return super().visit(expr)
        except NotRational:
            return IRRATIONAL

    def transpose(self, a):
        return a if a is IRRATIONAL else super().transpose(a)

    def _dispatch(self, expr):
        """At x = 0 every sub-tree is kept; at a unit vector a sub-tree without its variable has
        its value at x = 0."""
        key = (id(expr), self.vertex)
        hit = self.memo.get(key)
        if hit is not None and hit[0] is expr and (self.active is None or
                                                   not any(_involves(expr, name) for name in self.active)):
            return hit[1]
        value = super()._dispatch(expr)
        if self.active is None:
            self.memo[key] = (expr, value)
        return value

    def context(self) -> str:
        lmi = self.snap.current_lmi
        return f"{self.snap.instance.theorem.id}: LMI {lmi[0]}" if lmi else self.snap.instance.theorem.id

    def _value(self, symbol):
        if symbol.name in self.free:
            return self.free[symbol.name]
        key = (symbol.name, self.vertex if getattr(symbol, "per_vertex", False) else None)
        cache = self.snap.decimals
        if key not in cache:
            cache[key] = self._decimal_value(symbol)
        return cache[key]

    def _decimal_value(self, symbol):
        source = self.snap.instance.params if symbol.name in self.snap.instance.params else self.snap.instance.data
        value = source[symbol.name]
        if getattr(symbol, "per_vertex", False) and isinstance(value, list):
            value = value[self.vertex or 0]
        a = np.asarray(value, dtype=float)
        if a.ndim == 0:
            return decimal(a)
        a = np.atleast_2d(a)
        return fmpq_mat(a.shape[0], a.shape[1], [decimal(x) for x in a.reshape(-1)])

    def variable(self, symbol):
        v = self.snap.variable_for(symbol, self.vertex).variable
        shape = v.shape
        hits = [(c - v.offset, w) for c, w in self.point.items() if v.offset <= c < v.offset + v.size]
        factor = _exact_factor(self.snap.equilibration.variable(symbol.name))
        if not shape:
            return sum((w for _, w in hits), fmpq(0)) * factor
        X = fmpq_mat(*shape)
        for c, w in hits:
            for r in v.basis_rows[v.basis_cols == c]:
                X[int(r) // shape[1], int(r) % shape[1]] += factor * w
        return X

    scalar_variable = variable

    def element(self, a, i, j, expr):
        return a[i, j]

    def unknown(self, expr):
        """A node with no exact rule (sin θ of a sector) has no rational value."""
        raise NotRational(f"no exact rule for {type(expr).__name__} ({expr})")

    def congruence(self, value, factor: float):
        return value if factor == 1.0 or value is IRRATIONAL else to_matrix(value) * _exact_factor(factor)


IRRATIONAL = object()
"""A block of an LMI whose value as written is not rational (sin θ, √ξ): that LMI has no exact
coefficients (None in :class:`ExactCoefficients`); a certificate that is zero on it needs none."""


_INVOLVES: dict = {}


def _involves(expr, name: str) -> bool:
    """Whether ``expr`` may depend on the decision variable ``name`` (a structured variable may
    hide any), cached by identity."""
    key = (id(expr), name)
    hit = _INVOLVES.get(key)
    if hit is not None and hit[0] is expr:
        return hit[1]
    found = any(getattr(s, "name", None) == name or isinstance(s, StructuredVariable)
                for s in expr.atoms(*DECISION_TYPES)) if classify(expr)[0] else False
    if len(_INVOLVES) > 200_000:
        _INVOLVES.clear()
    _INVOLVES[key] = (expr, found)
    return found


class ExactCoefficients:
    """The compiled LMIs and objective as written, in rational arithmetic (module docstring):
    N(0) and, for each combination Σ_c w_c e_c of entries of x asked for, its coefficient
    Σ_c w_c N^c = N(Σ_c w_c e_c) − N(0) (N is affine in x), per LMI instance in the compile's order
    (None for an LMI with an irrational block).  ``why`` says why there are none at all (an
    irrational objective, too many walks)."""

    #: at most this many combinations (each costs one walk of every LMI)
    MAX_COLUMNS = 600

    def __init__(self, snap, free: dict | None = None):
        self.snap, self.free = snap, free
        self.why = ""
        self._columns: dict = {}
        self._memo: dict = {}           # every sub-tree's value at x = 0
        self._zero = self._walk(None)

    def _variables_of(self, point: dict) -> frozenset:
        names = set()
        for (name, _), affine in self.snap._variables.items():
            v = affine.variable
            if v is not None and any(v.offset <= c < v.offset + v.size for c in point):
                names.add(name)
        return frozenset(names)

    def _walk(self, point: dict | None):
        """(per LMI instance its cells [(row offset, column offset, value)], the objective) at
        x = Σ_c point[c] e_c (None: x = 0)."""
        if self.why:
            return None
        snap, free, memo = self.snap, self.free, self._memo
        active = None if point is None else self._variables_of(point)
        try:
            lmis = []
            for _, _, _, _, rows, _ in snap.walk_lmis(lambda v: _ExactWalk(snap, v, point, free, memo, active)):
                if any(value is IRRATIONAL for row in rows for value in row):
                    lmis.append(None)
                    continue
                cells, r0 = [], 0
                for row in rows:
                    c0 = 0
                    for value in row:
                        cells.append((r0, c0, value))
                        c0 += to_matrix(value).ncols()
                    r0 += to_matrix(row[0]).nrows()
                lmis.append(cells)
            objective = snap.instance.theorem.objective
            q = None if objective is None else _ExactWalk(snap, None, point, free, memo, active).visit(objective)
            if q is IRRATIONAL:
                raise NotRational("the objective")
        except (NotRational, ZeroDivisionError, ValueError, TypeError, KeyError) as exc:
            self.why = f"no rational coefficients as written ({type(exc).__name__}: {exc})"
            return None
        return lmis, q

    def irrational(self) -> set:
        """Indices (compile order) of the LMI instances with no rational coefficients."""
        return set() if self._zero is None else {k for k, cells in enumerate(self._zero[0]) if cells is None}

    def constant(self):
        """(N(0) per LMI instance as cells [(row offset, column offset, fmpq_mat)], the objective's
        constant term), or None."""
        return self._zero

    def combination(self, weights: dict):
        """(Σ_c w_c N^c per LMI instance as its non-zero cells, Σ_c w_c q_c) for ``weights`` =
        {entry c of x: w_c (fmpq)}, or None.  A cell without the entries' variables is the same
        object as at x = 0 (and left out)."""
        key = tuple(sorted((int(c), str(w)) for c, w in weights.items() if w != 0))
        if key not in self._columns:
            if self._zero is None or len(self._columns) >= self.MAX_COLUMNS:
                self.why = self.why or f"more than {self.MAX_COLUMNS} variables need rational coefficients"
                return None
            at = self._walk({c: w for c, w in weights.items() if w != 0})
            if at is None:
                return None
            zero_lmis, zero_q = self._zero
            lmis = [None if cells is None or zeros is None else
                    [(r0, c0, to_matrix(v) - to_matrix(z)) for (r0, c0, v), (_, _, z) in zip(cells, zeros) if v is not z]
                    for cells, zeros in zip(at[0], zero_lmis)]
            self._columns[key] = (lmis, None if at[1] is None else at[1] - zero_q)
        return self._columns[key]


def _degree(expr, symbols) -> int | None:
    """An upper bound on the total degree of ``expr`` (a scalar or matrix expression) as a
    polynomial in ``symbols`` (a set); None when it is not a polynomial in them (an inverse or a
    function of one)."""
    if expr in symbols:
        return 1
    if not any(expr.has(s) for s in symbols):
        return 0
    args = [_degree(a, symbols) for a in expr.args]
    if any(a is None for a in args):
        return None
    if isinstance(expr, (sp.Mul, sp.MatMul)):
        return sum(args)
    if isinstance(expr, (sp.Add, sp.MatAdd, sp.BlockMatrix, sp.BlockDiagMatrix, sp.Transpose, sp.Trace)):
        return max(args)
    if isinstance(expr, (sp.Pow, sp.MatPow)) and expr.args[1].is_Integer and int(expr.args[1]) >= 0:
        return int(expr.args[1]) * args[0]
    return None


def _principal_lattice(k: int, total: int) -> list[tuple]:
    """{a ∈ ℕᵏ : a₁ + … + a_k ≤ total}, shifted by 1 in every coordinate."""
    return [tuple(x + 1 for x in a) for a in itertools.product(range(total + 1), repeat=k) if sum(a) <= total]


def irrational_grid(snap, limit: int = 64) -> list[dict] | None:
    """Points at which the derived parameters with irrational definitions (σ = √(ξ(1 − ξ))), taken
    as free symbols σ₁ … σ_k, decide a polynomial identity, whichever set is smaller:

    * the tensor grid of d_i + 1 distinct integers for each σ_i, d_i the degree of the LMIs and the
      objective in σ_i: a polynomial of degree ≤ d_i in each σ_i that vanishes on it is zero
      (induction on the symbols);
    * the principal lattice {a ∈ ℕᵏ : Σ a_i ≤ D} (shifted by 1), D the total degree in σ: a
      polynomial p of total degree ≤ D that vanishes on it is zero (induction on k and D: on
      a₁ = 0 it is the lattice of k − 1 symbols, so p = σ₁ q with deg q ≤ D − 1, and q(σ₁ + 1, …)
      vanishes on the lattice of total degree D − 1).  Four σ's of degree 1 in each and in all:
      5 points instead of 16.

    An identity between the coefficients checked at every point holds at the parameters' true
    values.  [] when no parameter is irrational; None when one is not polynomial or both sets
    exceed ``limit``."""
    theorem = snap.instance.theorem
    exprs = [b for lmi in theorem.lmis for row in lmi.negative_form().lower for b in row]
    if theorem.objective is not None:
        exprs.append(theorem.objective)
    derived = {s for e in exprs for s in e.free_symbols if isinstance(s, DerivedParam)}
    irrational = []
    for d in sorted(derived, key=lambda s: s.name):
        try:
            if _ExactWalk(snap, None, None).visit(d.definition) is IRRATIONAL:
                irrational.append(d)
        except NotRational:
            irrational.append(d)
        except (KeyError, ValueError, TypeError, ZeroDivisionError):
            return None
    if not irrational:
        return []
    degrees = []
    for d in irrational:
        found = [_degree(e, {d}) for e in exprs]
        if any(x is None for x in found):
            return None
        degrees.append(max(found))
    total = max(_degree(e, set(irrational)) for e in exprs)     # polynomial in each: in all
    tensor, lattice = math.prod(k + 1 for k in degrees), math.comb(total + len(irrational), total)
    if min(tensor, lattice) > limit:
        return None
    points = (list(itertools.product(*(range(1, k + 2) for k in degrees))) if tensor <= lattice
              else _principal_lattice(len(irrational), total))
    return [{d.name: fmpq(v) for d, v in zip(irrational, point)} for point in points]


def snapshot(model) -> _Snapshot:
    """What :func:`coefficient_bounds` needs of ``model``, taken now."""
    return _Snapshot(model)


__all__ = ["CoefficientBounds", "EnclosureUnavailable", "ExactCoefficients", "Mag", "MagnitudeWalker",
           "coefficient_bounds", "radii", "snapshot"]
