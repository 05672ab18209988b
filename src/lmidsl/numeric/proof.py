"""Proved LMIs: each LMI checked in rigorous ball arithmetic at the returned point.

A solver returns a point in floating point, and numpy's eigenvalues of N at that point are
themselves rounded.  Here the claim ``N ≺ 0`` is *proved* instead, in the manner of VSDP
(verified semidefinite programming, Jansson et al.), with python-flint's ball arithmetic (arb):

* the point's values are binary floats, taken exactly; the data and the parameters are the
  decimals the user wrote (``repr`` of the float, e.g. the paper's 0.3 is 3/10, enclosed in a
  ball); derived scalars are evaluated from their definitions (√(r̄(1 − r̄)) is a ball);
* N is assembled block by block by the same walk as every other evaluator, in balls at
  :data:`PRECISION` bits, so every entry of the computed matrix encloses the exact entry;
* N ≺ 0 ⇔ −S ≻ 0 for S = (N + Nᵀ)/2 (the quadratic form xᵀNx is that of S), and a symmetric
  matrix is positive definite iff its LDLᵀ factorisation has only positive pivots (Sylvester).
  The factorisation is run in ball arithmetic: if every pivot ball lies in (0, ∞) the claim is
  **proved**; if a pivot ball lies in (−∞, 0) after positive ones, −S has a negative eigenvalue
  and the LMI is **violated** (also a proof); if a pivot ball contains 0, nothing is proved
  (**numerical only**, with the pivot named).

A non-strict LMI ``N ⪯ 0`` is proved only when it holds strictly (a ball cannot show that a
singular matrix is semidefinite); otherwise it is numerical only.

**At floating-point speed first.**  Before any ball is formed, the LMI is assembled as a
midpoint–radius enclosure in floating point (:mod:`lmidsl.numeric.enclosure`; scalars and
inverses in balls) and −S ≻ 0 is proved by Rump's verified positive definiteness
(:func:`verified_positive_definite`: one LAPACK Cholesky of a shifted matrix).  Only when that
fails (a margin below about n²u‖S‖, or a violated LMI) does the ball LDLᵀ above decide.
"""
from __future__ import annotations

import math
import threading
from contextlib import contextmanager
from functools import reduce

import mpmath
import numpy as np
import sympy as sp
from flint import arb, arb_mat, ctx

from ..symbolic.symbols import DerivedParam
from ..symbolic.walker import ExpressionWalker
from .enclosure import REALMIN, U, Enclosure, assemble, gamma, symmetric_part, up
from .evaluate import assemble_blocks, evaluate_block_matrix

PRECISION = 212          # bits of the balls' midpoints (about 64 decimal digits)

#: python-flint's working precision is one process-wide setting; the proved lower bound runs on a
#: worker thread (:mod:`lmidsl.certify.dual_bound`) while the main thread proves LMIs, so every
#: ball computation holds this lock for as long as it sets the precision.
_BALL_LOCK = threading.RLock()


@contextmanager
def ball_precision(bits: int):
    """Ball arithmetic at ``bits`` bits of midpoint precision, with no other thread changing it
    meanwhile (the previous precision is restored on exit)."""
    with _BALL_LOCK:
        saved = ctx.prec
        ctx.prec = bits
        try:
            yield
        finally:
            ctx.prec = saved


def round_down(x: float, steps: int = 2) -> float:
    """x moved ``steps`` floats towards −∞ (a float result made a safe lower bound)."""
    for _ in range(steps):
        x = math.nextafter(x, -math.inf)
    return x


def round_up(x: float, steps: int = 2) -> float:
    """x moved ``steps`` floats towards +∞ (a float result made a safe upper bound)."""
    for _ in range(steps):
        x = math.nextafter(x, math.inf)
    return x


PROVED = "proved"
NUMERICAL = "numerical only"
VIOLATED = "violated"


def decimal_ball(x) -> arb:
    """The decimal a float was written as (its shortest repr), as a ball containing it."""
    return arb(repr(float(x)))


def object_array(values, convert) -> np.ndarray:
    """A float matrix as an object array of ``convert(entry)`` (balls, for the proofs)."""
    a = np.atleast_2d(np.asarray(values, dtype=float))
    out = np.empty(a.shape, dtype=object)
    for idx, v in np.ndenumerate(a):
        out[idx] = convert(v)
    return out


class PreciseMatrix(np.ndarray):
    """A point's value whose exact value is a rational matrix (``exact``: an object array of
    python-flint ``fmpq``) that doubles cannot hold: numpy sees the rounded floats, the proofs
    (:class:`BallEvaluator`, :class:`EnclosureEvaluator`) the exact value.  Any array derived from
    it (a view, a product, a copy) is a plain float matrix again: ``exact`` is ``None`` there.

    Made for the storage of a stiff bounded-real lemma (:mod:`lmidsl.numeric.riccati`): with
    entries of the LMI ~1e16 around a margin ~1e-18, rounding P to doubles alone violates it."""

    exact = None

    @classmethod
    def of(cls, exact) -> "PreciseMatrix":
        exact = np.asarray(exact, dtype=object)
        out = np.array([[float(x) for x in row] for row in exact], dtype=float).view(cls)
        out.exact = exact
        return out

    def __array_finalize__(self, obj):
        self.exact = None

    def __reduce__(self):                      # a pickled copy is the float matrix
        return np.asarray(self).__reduce__()


def _exact_balls(value) -> np.ndarray | None:
    """The balls of a :class:`PreciseMatrix`'s exact value (at the current precision), or None."""
    exact = getattr(value, "exact", None)
    if exact is None:
        return None
    out = np.empty(exact.shape, dtype=object)
    for idx, x in np.ndenumerate(exact):
        out[idx] = arb(x)
    return out


class BallEvaluator(ExpressionWalker):
    """Evaluate a theorem's expressions in ball arithmetic (numpy object arrays of arb)."""

    def __init__(self, dims: dict, values: dict, params: dict, vertex: int | None = None):
        super().__init__(dims, vertex)
        self.values = values
        self.params = params

    def _lookup(self, symbol):
        value = self.values[symbol.name]
        if getattr(symbol, "per_vertex", False) and isinstance(value, list):
            value = value[self.vertex or 0]
        return value

    def data(self, symbol):
        return object_array(self._lookup(symbol), decimal_ball)

    def variable(self, symbol):
        value = self._lookup(symbol)
        exact = _exact_balls(value)
        return object_array(value, arb) if exact is None else exact

    def scalar_variable(self, symbol):
        return arb(float(np.asarray(self._lookup(symbol)).reshape(())))

    def parameter(self, symbol):
        if isinstance(symbol, DerivedParam):
            return self.visit(symbol.definition)
        return decimal_ball(self.params[symbol.name])

    def identity(self, n: int):
        out = np.empty((n, n), dtype=object)
        out[...] = arb(0)
        for i in range(n):
            out[i, i] = arb(1)
        return out

    def zeros(self, r: int, c: int):
        out = np.empty((r, c), dtype=object)
        out[...] = arb(0)
        return out

    def block(self, rows):
        return assemble_blocks(rows)

    def inverse(self, a, expr):
        a = np.atleast_2d(a)
        inv = arb_mat(a.tolist()).inv()          # raises ZeroDivisionError if not provably invertible
        return np.array([[inv[i, j] for j in range(inv.ncols())] for i in range(inv.nrows())],
                        dtype=object)

    def scale(self, c, a):
        return c * np.asarray(a, dtype=object)

    def trace(self, a):
        a = np.atleast_2d(np.asarray(a, dtype=object))
        return sum((a[i, i] for i in range(1, a.shape[0])), a[0, 0])     # a ball, not a float

    def _visit_Number(self, expr):
        if isinstance(expr, sp.Rational):
            return arb(int(expr.p)) / arb(int(expr.q))
        return arb(str(expr))

    def _visit_NumberSymbol(self, expr):
        if expr == sp.pi:
            return arb.pi()
        if expr == sp.E:
            return arb(1).exp()
        raise ZeroDivisionError(f"no ball for the constant {expr}")  # reported as not proved

    def _visit_Pow(self, expr):
        base, exp = expr.args
        value = self.visit(base)
        if exp.is_Integer:
            return value ** int(exp)
        if exp.is_Rational:
            return value ** (arb(int(exp.p)) / arb(int(exp.q)))
        return value ** self.visit(exp)

    def _visit_Abs(self, expr):
        return abs(self.visit(expr.args[0]))

    def _visit_exp(self, expr):
        return self.visit(expr.args[0]).exp()

    def _visit_log(self, expr):
        return self.visit(expr.args[0]).log()

    def _visit_sin(self, expr):
        return self.visit(expr.args[0]).sin()

    def _visit_cos(self, expr):
        return self.visit(expr.args[0]).cos()

    def _visit_Max(self, expr):
        return reduce(arb.max, (self.visit(a) for a in expr.args))

    def _visit_Min(self, expr):
        return reduce(arb.min, (self.visit(a) for a in expr.args))

    def _visit_MatrixBase(self, expr):
        rows = [[self.visit(sp.sympify(e)) for e in row] for row in expr.tolist()]
        return np.array(rows, dtype=object).reshape(expr.shape)


def negative_definite(N: np.ndarray, strict: bool = True) -> tuple[str, str]:
    """(verdict, why) for ``N ≺ 0`` from the ball LDLᵀ of −(N + Nᵀ)/2 (see the module docstring)."""
    n = N.shape[0]
    N = np.asarray(N, dtype=object)
    A = -(N + N.T) / 2
    L = np.empty((n, n), dtype=object)      # column j below the diagonal: L[j+1:, j]
    d = np.empty(n, dtype=object)
    for j in range(n):
        # pivot d_j = A_jj − Σ_k L_jk² d_k; column L_ij = (A_ij − Σ_k L_ik L_jk d_k) / d_j, i > j
        # (dot products of object arrays: every product and sum is a ball operation)
        w = L[j, :j] * d[:j]
        pivot = A[j, j] - np.dot(L[j, :j], w) if j else A[j, j]
        if not pivot > 0:
            if pivot < 0:
                return VIOLATED, f"pivot {j + 1} of the LDLᵀ of −N is negative ({pivot.mid()})"
            why = f"pivot {j + 1} of the LDLᵀ of −N contains 0 ({pivot})"
            return NUMERICAL, why + ("" if strict else "; a non-strict LMI is proved only if strict")
        d[j] = pivot
        if j + 1 < n:
            column = A[j + 1:, j] - L[j + 1:, :j].dot(w) if j else A[j + 1:, j]
            L[j + 1:, j] = column / pivot
    return PROVED, f"LDLᵀ of −N in {ctx.prec}-bit ball arithmetic: {n} positive pivots"


# -- Rump's verified positive definiteness ----------------------------------------------------
ETA = 2.0 ** -1074           # smallest positive (subnormal) double


def _collatz_bound(R: np.ndarray, steps: int = 4) -> float:
    """A float upper bound of ‖R‖₂ = ρ(R) for a symmetric non-negative R: for any x > 0,
    ρ(R) ≤ ‖D⁻¹RD‖_∞ = max_i (Rx)_i / x_i with D = diag(x) (Collatz; a few power steps choose x)."""
    n = R.shape[0]
    if n == 0 or not R.any():
        return 0.0
    x = np.ones(n)
    for _ in range(steps):
        y = R @ x
        top = float(y.max())
        if not top > 0 or not math.isfinite(top):
            break
        x = np.maximum(y / top, 1e-3)          # stays positive: every choice is a valid bound
    y = up(R @ x, n + 1)                        # upper bounds of the exact (Rx)_i
    return round_up(float(np.max(y / x)) * (1.0 + 4 * U))


def rump_shift(diag: np.ndarray) -> float:
    """Rump's shift c for a symmetric float A with positive diagonal (BIT 46, 2006, Cor. 2.4;
    INTLAB ``isspd``): if the floating-point Cholesky (round to nearest, any order of summation)
    of a float matrix Ã ≤ A − cI (Ã = A off the diagonal) runs to completion, then A ≻ 0, for

        c = Σ_j α_j a_jj + 6 n (n + max_j a_jj) η,   α_j = γ_{j+1}/(1 − γ_{j+1}),

    (j = number of entries left of the diagonal in row j, dense here; η = 2⁻¹⁰⁷⁴).  We take
    α_j from γ_{j+3} (two more roundings than Rump's, covering a triangular solve that multiplies
    by a reciprocal) and round the sum up."""
    n = len(diag)
    j = np.arange(n, dtype=float) + 3.0
    g = j * U / (1.0 - j * U)
    alpha = g / (1.0 - g) * (1.0 + 4 * U)
    total = float(up(np.dot(alpha, diag), n + 2))
    return round_up(total + 6.0 * n * (n + float(diag.max())) * ETA * 2 + REALMIN)


def verified_positive_definite(mid: np.ndarray, rad: np.ndarray | None = None) -> tuple[bool, str]:
    """(True, why) when every symmetric A with |A − mid| ≤ rad is proved positive definite.

    Rump's method: (1) the diagonal is replaced by its lower ends a_jj = mid_jj − rad_jj (rounded
    down; A ⪰ the matrix with that diagonal), (2) van der Sluis scaling by powers of two
    (a congruence, exact when nothing underflows — checked), (3) M ≥ ‖rad_off‖₂ by a Collatz
    bound (every A in the enclosure is A′ + E with ‖E‖₂ ≤ M), (4) the floating-point Cholesky of
    Ã = A′ − (c + M) I, its diagonal rounded down (``nextafter``) so that Ã ≤ A′ − (c + M) I holds
    exactly, with c from :func:`rump_shift`.  Success proves λ_min(A′) > M, hence A ≻ 0."""
    A = np.array(mid, dtype=float)
    n = A.shape[0]
    if n == 0:
        return True, "empty"
    R = np.zeros_like(A) if rad is None else np.array(rad, dtype=float)
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(R))):
        return False, "not finite"
    if np.any(A != A.T) or np.any(R != R.T):
        return False, "not symmetric"
    d = np.diag(A) - np.diag(R)
    d = np.nextafter(np.nextafter(d, -np.inf), -np.inf)
    if not np.all(d > 0):
        j = int(np.argmin(d))
        return False, f"diagonal entry {j + 1} is not provably positive ({d[j]:.3g})"
    np.fill_diagonal(A, d)
    np.fill_diagonal(R, 0.0)
    top, low = float(d.max()), float(d.min())
    if top / low > math.sqrt(n) and 1e-100 < low and top < 1e100:
        s = 2.0 ** -np.ceil(0.5 * np.log2(d))
        S = np.outer(s, s)
        As, Rs = A * S, R * S
        # powers of two scale exactly unless a product under- or overflows: check it; a radius
        # that is not relative to its entries can grow in the scaled matrix: then unscaled too
        if np.array_equal(As / S, A) and np.array_equal(Rs / S, R) \
                and np.all(np.isfinite(As)) and np.all(np.isfinite(Rs)):
            ok, why = _shifted_cholesky(As, Rs, np.diag(As).copy())
            if ok:
                return ok, why
    return _shifted_cholesky(A, R, d)


def _shifted_cholesky(A: np.ndarray, R: np.ndarray, d: np.ndarray) -> tuple[bool, str]:
    """Step (4) of :func:`verified_positive_definite` on A′ = A (diagonal d), off-diagonal radius R."""
    M = _collatz_bound(R)
    c = round_up(rump_shift(d) + M)
    shifted = A.copy()
    np.fill_diagonal(shifted, np.nextafter(np.nextafter(d - c, -np.inf), -np.inf))
    try:
        L = np.linalg.cholesky(shifted)
    except np.linalg.LinAlgError:
        return False, f"the Cholesky of A − cI fails (c = {c:.3g}, relative {c / float(d.max()):.2g})"
    if not np.all(np.isfinite(L)):
        return False, "the Cholesky of A − cI overflows"
    return True, f"Rump's verified Cholesky (shift {c / float(d.max()):.2g} relative)"


def lower_eigenvalue_bound(mid: np.ndarray, rad: np.ndarray | None = None, estimate: float | None = None,
                           tries: int = 4) -> float | None:
    """A proved s ≤ λ_min(A) for every symmetric A with |A − mid| ≤ rad: the enclosure of A − sI
    (the float s exact, the diagonal's rounding in the radius) proved positive definite by
    :func:`verified_positive_definite`; s is tried a little below the eigenvalue estimate, then
    further below.  None when no try succeeds."""
    A = np.asarray(mid, dtype=float)
    n = A.shape[0]
    if n == 0:
        return math.inf
    R = np.zeros_like(A) if rad is None else np.asarray(rad, dtype=float)
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(R))):
        return None
    lam = float(np.linalg.eigvalsh(A)[0]) if estimate is None else float(estimate)
    scale = float(np.abs(np.diag(A)).max()) + float(np.abs(A).max())
    off = R.copy()
    np.fill_diagonal(off, 0.0)
    # what the proof below loses: the diagonal radius, ‖off-diagonal radius‖₂, Rump's shift
    margin = (float(np.diag(R).max()) + _collatz_bound(off)) * 1.01 \
        + 2.0 * rump_shift(np.full(n, scale)) + 8 * n * U * abs(lam)
    for _ in range(tries):
        s = round_down(lam - margin)
        shifted = A.copy()
        diag = np.diag(A) - s
        np.fill_diagonal(shifted, diag)
        Rs = R.copy()
        np.fill_diagonal(Rs, np.diag(R) + up(U * np.abs(diag), 1))
        if verified_positive_definite(shifted, Rs)[0]:
            return s
        margin *= 16.0
    return None


def verified_spd_solve(G: np.ndarray, G_rad: np.ndarray, b: np.ndarray, b_rad: np.ndarray):
    """(w_mid, w_rad) enclosing G⁻¹b for every symmetric G with |G − G_mid| ≤ G_rad and every b
    with |b − b_mid| ≤ b_rad, or None: w̃ from a floating-point Cholesky (one refinement step),
    s ≤ λ_min over the enclosure proved by :func:`lower_eigenvalue_bound` (s > 0 proves every G
    positive definite, hence invertible), and for the exact w = G⁻¹b

        ‖w − w̃‖₂ ≤ ‖b − G w̃‖₂ / s ≤ ‖ |fl(b − G w̃)| + γ_{n+2}(|b| + |G||w̃|) + b_rad + G_rad|w̃| ‖₂ / s,

    the same bound β on every component, then sharpened componentwise with R ≈ G⁻¹ (from the
    factor): for every G′ in the enclosure, G′e = ρ′ with |ρ′| ≤ ρ̄ (the bracket above) gives
    e = Rρ′ + (I − RG′)e, so

        |e| ≤ |R| ρ̄ + C |e|,   C = |fl(I − fl(RG))| + γ_{n+2}|R||G| (rounding) + |R| G_rad  ≥ |I − RG′|,

    applied twice from |e| ≤ β (each product of non-negative floats rounded up by
    :func:`~lmidsl.numeric.enclosure.up`); the least of the bounds is kept per component.  The
    dual bound's correction reads these radii (on a 16-state bounded real lemma the norm-wise
    radius alone left λ_min ≥ −4.9e-8, the componentwise one −3e-10).  LAPACK speed (about five
    n³ products): the ball solve's O(n³) ball operations are what this replaces."""
    n = G.shape[0]
    try:
        L = np.linalg.cholesky(G)
    except np.linalg.LinAlgError:
        return None
    from scipy.linalg import cho_solve
    w = cho_solve((L, True), b)
    w = w + cho_solve((L, True), b - G @ w)                  # one step of refinement
    if not np.all(np.isfinite(w)):
        return None
    # λ_min(G) estimated by inverse iteration on the factor (O(n²) a step), then proved
    x = np.ones(n) / math.sqrt(n)
    for _ in range(4):
        y = cho_solve((L, True), x)
        norm = float(np.linalg.norm(y))
        if not norm > 0 or not math.isfinite(norm):
            return None
        x = y / norm
    estimate = 0.5 / norm if norm > 0 else 0.0
    s = lower_eigenvalue_bound(G, G_rad, estimate=estimate, tries=3)
    if s is None or not s > 0:
        return None
    absw = np.abs(w)
    res = b - G @ w
    err = np.abs(res) + gamma(n + 2) * (np.abs(b) + np.abs(G) @ absw) + b_rad + G_rad @ absw
    err = up(err, 2 * n + 8)
    bound = float(up(np.sqrt(float(up(np.dot(err, err), n + 2))), 2)) / s
    bound = round_up(bound * (1 + 4 * U))
    if not math.isfinite(bound):
        return None
    return w, _componentwise(G, G_rad, L, err, bound)


def _componentwise(G: np.ndarray, G_rad: np.ndarray, L: np.ndarray, err: np.ndarray, bound: float) -> np.ndarray:
    """Componentwise bounds on |e| from |e| ≤ bound (every component), |G′e| ≤ err for every G′
    within G_rad of G, and R = fl(G⁻¹) from the Cholesky factor L (:func:`verified_spd_solve`)."""
    from scipy.linalg import cho_solve
    n = G.shape[0]
    R = cho_solve((L, True), np.eye(n))
    if not np.all(np.isfinite(R)):
        return np.full(n, bound)
    Rabs = np.abs(R)
    E = np.eye(n) - R @ G
    # |I − RG′| ≤ |fl(I − fl(RG))|(1 + u) + γ_{n+2}|R||G| + |R| G_rad, every product rounded up
    C = up(np.abs(E), 2) + up(Rabs @ up(gamma(n + 2) * np.abs(G) + G_rad, 2), 2 * n + 8)
    first = up(Rabs @ err, 2 * n + 8)
    e = np.full(n, bound)
    for _ in range(2):
        e = np.minimum(e, up(first + up(C @ e, 2 * n + 8), 2))
    e = np.array([round_up(float(x)) for x in e])
    return e if np.all(np.isfinite(e)) else np.full(n, bound)


def prove_negative_definite(N: Enclosure, strict: bool = True) -> tuple[str, str] | None:
    """(PROVED, why) when every N in the enclosure has −(N + Nᵀ)/2 ≻ 0 (Rump), (VIOLATED, why)
    when a vector x has xᵀNx > 0 proved in interval arithmetic, else None (the balls decide)."""
    if not N.finite:
        return None
    S = symmetric_part(N, -1.0)
    ok, why = verified_positive_definite(S.mid, S.rad)
    if ok:
        return PROVED, why
    w, V = np.linalg.eigh(S.mid)
    if w[0] < 0:
        x = Enclosure.point(V[:, :1])
        q = x.T @ (S @ x)                      # an enclosure of xᵀSx for every S in the enclosure
        if float(q.rad[0, 0]) < -float(q.mid[0, 0]):     # exact comparison: mid + rad < 0
            return VIOLATED, f"xᵀ(−N)x < 0 proved for the eigenvector of λ_min(−N) ≈ {w[0]:.3g}"
    return None


class EnclosureEvaluator(ExpressionWalker):
    """A theorem's matrix expressions as floating-point enclosures (:mod:`lmidsl.numeric.enclosure`);
    every scalar subexpression and every inverse is evaluated in balls (:class:`BallEvaluator`)."""

    def __init__(self, dims: dict, values: dict, params: dict, vertex: int | None = None):
        super().__init__(dims, vertex)
        self.balls = BallEvaluator(dims, values, params, vertex)

    def visit(self, expr):
        if getattr(expr, "is_Matrix", False):
            return super().visit(expr)
        with ball_precision(PRECISION):        # a scalar: numbers, parameters, derived scalars
            value = self.balls.visit(expr)
            if isinstance(value, arb):
                return Enclosure.of_ball(value)
            if isinstance(value, (int, float)) and float(value) == value:
                return Enclosure.point(float(value))
            return Enclosure.of_balls(value)

    def data(self, symbol):
        return Enclosure.decimal(np.atleast_2d(np.asarray(self.balls._lookup(symbol), dtype=float)))

    def variable(self, symbol):
        value = self.balls._lookup(symbol)
        if getattr(value, "exact", None) is not None:
            with ball_precision(PRECISION):
                return Enclosure.of_balls(_exact_balls(value))
        return Enclosure.point(np.atleast_2d(np.asarray(value, dtype=float)))

    def identity(self, n: int):
        return Enclosure.point(np.eye(n))

    def zeros(self, r: int, c: int):
        return Enclosure.point(np.zeros((r, c)))

    def block(self, rows):
        return assemble(rows)

    def inverse(self, a, expr):
        with ball_precision(PRECISION):
            return Enclosure.of_balls(self.balls.inverse(a.balls(), expr))

    def scale(self, c, a):
        return c * a

    def element(self, a, i: int, j: int, expr):
        return a.atleast_2d()[i, j]

    def _visit_MatrixBase(self, expr):
        with ball_precision(PRECISION):
            return Enclosure.of_balls(self.balls.visit(expr))


def enclosure_of_block_matrix(evaluator: EnclosureEvaluator, spec) -> Enclosure:
    """The full symmetric matrix of a block spec as an enclosure (lower triangle evaluated, upper
    triangle its transpose; see :func:`lmidsl.numeric.evaluate.evaluate_block_matrix`)."""
    q = spec.nblocks
    lower = [[evaluator.visit(spec.lower[i][j]).atleast_2d() for j in range(i + 1)] for i in range(q)]
    return assemble([[lower[i][j] if j <= i else lower[j][i].T for j in range(q)] for i in range(q)])


#: above this dimension the ball LDLᵀ fallback (Python loops, O(n³) ball operations) is skipped
BALL_FALLBACK_LIMIT = 160


def prove_block_matrix(evaluator_args: tuple, spec, strict: bool = True) -> tuple[str, str]:
    """Prove or refute N ≺ 0 for the form ``spec`` at a point: first Rump's floating-point proof on
    an enclosure of N, then (when it decides nothing) the ball LDLᵀ of N assembled in balls."""
    try:
        fast = prove_negative_definite(enclosure_of_block_matrix(EnclosureEvaluator(*evaluator_args), spec), strict)
    except (ZeroDivisionError, ValueError, TypeError, KeyError, np.linalg.LinAlgError):
        fast = None
    if fast is not None:
        return fast
    n = spec_dimension(evaluator_args, spec)
    if n is not None and n > BALL_FALLBACK_LIMIT:
        return NUMERICAL, (f"Rump's floating-point proof fails and the ball LDLᵀ is skipped "
                           f"(dimension {n} > {BALL_FALLBACK_LIMIT})")
    exact_point = any(getattr(v, "exact", None) is not None for v in evaluator_args[1].values())
    for bits in (PRECISION, EXACT_POINT_PRECISION) if exact_point else (PRECISION,):
        with ball_precision(bits):
            try:
                verdict = negative_definite(evaluate_block_matrix(BallEvaluator(*evaluator_args), spec), strict)
            except (ZeroDivisionError, ValueError, TypeError, KeyError) as exc:
                return NUMERICAL, f"no ball evaluation ({type(exc).__name__}: {exc})"
        if verdict[0] != NUMERICAL:
            break
    return verdict


EXACT_POINT_PRECISION = 4 * PRECISION
"""Bits of the ball LDLᵀ's second try at a point holding exact values (:class:`PreciseMatrix`), when
the first leaves a pivot containing 0: an exact point has no rounding to hide, only the balls' own
growth (H∞ state feedback at 32 states: cond(Y) ~ 1e18, a pivot ±7e-15 at 212 bits)."""


def accurate_max_eigenvalue(evaluator_args: tuple, spec) -> float | None:
    """λ_max((N + Nᵀ)/2) for N of the form ``spec`` at a point, N assembled in :data:`PRECISION`-bit
    balls and the eigenvalues of their midpoints computed by mpmath at that precision (None when no
    ball evaluation exists).  An estimate, not a proof: what numpy's rounded eigenvalue cannot
    resolve on a badly scaled N (entries ~1e16 around a margin ~1e-7, whose sign the proof decides)."""
    with ball_precision(PRECISION):
        try:
            N = evaluate_block_matrix(BallEvaluator(*evaluator_args), spec)
        except (ZeroDivisionError, ValueError, TypeError, KeyError):
            return None
        N = np.asarray(N, dtype=object)
        if not all(x.is_finite() for x in N.flat):
            return None
        mid = [[x.mid().man_exp() for x in row] for row in N]
    with mpmath.workprec(PRECISION):
        M = mpmath.matrix([[mpmath.ldexp(int(m), int(e)) for m, e in row] for row in mid])
        S = (M + M.T) / 2
        return float(max(mpmath.eigsy(S, eigvals_only=True)))


def spec_dimension(evaluator_args: tuple, spec) -> int | None:
    """The dimension of the block matrix ``spec`` under the bound dimensions, or None."""
    try:
        walker = ExpressionWalker(evaluator_args[0])
        return sum(walker.size(spec.lower[i][i].rows) for i in range(spec.nblocks))
    except (TypeError, ValueError, AttributeError):
        return None


__all__ = ["PROVED", "NUMERICAL", "VIOLATED", "BallEvaluator", "negative_definite", "EnclosureEvaluator",
           "verified_positive_definite", "lower_eigenvalue_bound", "verified_spd_solve", "prove_negative_definite", "rump_shift",
           "prove_block_matrix", "accurate_max_eigenvalue", "PreciseMatrix", "decimal_ball", "object_array", "PRECISION", "ball_precision", "round_down", "round_up"]
