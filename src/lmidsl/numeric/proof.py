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
"""
from __future__ import annotations

import math
import threading
from contextlib import contextmanager
from functools import reduce

import numpy as np
import sympy as sp
from flint import arb, arb_mat, ctx

from ..symbolic.symbols import DerivedParam
from ..symbolic.walker import ExpressionWalker
from .evaluate import assemble_blocks, evaluate_block_matrix

PRECISION = 212          # bits of the balls' midpoints (about 64 decimal digits)

#: python-flint's working precision is one process-wide setting; the proved lower bound runs on a
#: worker thread (:mod:`lmidsl.solver.dual_bound`) while the main thread proves LMIs, so every
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


def _object_array(values, convert) -> np.ndarray:
    a = np.atleast_2d(np.asarray(values, dtype=float))
    out = np.empty(a.shape, dtype=object)
    for idx, v in np.ndenumerate(a):
        out[idx] = convert(v)
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
        return _object_array(self._lookup(symbol), decimal_ball)

    def variable(self, symbol):
        return _object_array(self._lookup(symbol), arb)

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
    return PROVED, f"LDLᵀ of −N in {PRECISION}-bit ball arithmetic: {n} positive pivots"


def prove_block_matrix(evaluator_args: tuple, spec, strict: bool = True) -> tuple[str, str]:
    """Assemble ``spec`` (the form N ≺ 0) in balls and prove or refute N ≺ 0."""
    with ball_precision(PRECISION):
        try:
            return negative_definite(evaluate_block_matrix(BallEvaluator(*evaluator_args), spec), strict)
        except (ZeroDivisionError, ValueError, TypeError, KeyError) as exc:
            return NUMERICAL, f"no ball evaluation ({type(exc).__name__}: {exc})"


__all__ = ["PROVED", "NUMERICAL", "VIOLATED", "BallEvaluator", "negative_definite",
           "prove_block_matrix", "decimal_ball", "PRECISION", "ball_precision", "round_down", "round_up"]
