"""Exact rational evaluation of a theorem's expressions (python-flint ``fmpq_mat``).

Used by the derivation checks (:mod:`lmidsl.studies.derivation`): two block matrices that are
equal as polynomial (or rational) functions of the symbols are equal at every point, and a
nonzero rational function vanishes at a random point with probability at most its degree over
the size of the sample set (Schwartz–Zippel).  Evaluating both sides at random *rational*
points in exact arithmetic therefore decides an identity with no rounding to explain away.

Matrices are ``fmpq_mat``, scalars ``fmpq``.  A leaf's value comes from ``lookup(symbol)``, a
callable given by the caller (random draws, definitions by substitution).  A value that is not
rational (a square root of a parameter, π) raises :class:`NotRational`.
"""
from __future__ import annotations

import random

import numpy as np
import sympy as sp
from flint import fmpq, fmpq_mat

from ..symbolic.symbols import DerivedParam
from ..symbolic.walker import ExpressionWalker


class NotRational(ValueError):
    """The expression has no exact rational value (e.g. √ of a parameter)."""


def as_fmpq(value) -> fmpq:
    r = sp.Rational(value)
    return fmpq(int(r.p), int(r.q))


def random_rational(rng: random.Random, size: int = 30) -> fmpq:
    """p/q with |p| ≤ size, 1 ≤ q ≤ size (never 0)."""
    while True:
        p = rng.randint(-size, size)
        if p:
            return fmpq(p, rng.randint(1, size))


def random_matrix(rng: random.Random, rows: int, cols: int, kind: str = "full") -> fmpq_mat:
    """A random rational matrix; ``kind`` symmetric or diagonal gives that structure."""
    M = fmpq_mat(rows, cols)
    for i in range(rows):
        for j in range(cols):
            if kind == "diagonal" and i != j:
                continue
            if kind == "symmetric" and j < i:
                M[i, j] = M[j, i]
                continue
            M[i, j] = random_rational(rng)
    return M


def rational_matrix(M) -> fmpq_mat:
    """The exact value of a matrix of doubles (each double is a rational), or of a
    :class:`~lmidsl.numeric.proof.PreciseMatrix`'s exact value, as an ``fmpq_mat``."""
    exact = getattr(M, "exact", None)
    M = np.atleast_2d(np.asarray(M if exact is None else exact, dtype=object))
    return fmpq_mat(M.shape[0], M.shape[1],
                    [x if isinstance(x, fmpq) else fmpq(*float(x).as_integer_ratio()) for x in M.ravel()])


def midpoint(x) -> fmpq:
    """The midpoint of a python-flint ``arb`` (or an mpmath ``mpf``) as an exact rational
    (ValueError / OverflowError when it is not finite)."""
    if hasattr(x, "mid"):
        man, exp = x.mid().man_exp()
    else:                                  # mpmath: man is the unsigned mantissa
        man, exp = (-x.man if x < 0 else x.man), x.exp
    man, exp = int(man), int(exp)
    return fmpq(man * 2 ** exp) if exp >= 0 else fmpq(man, 2 ** -exp)


def entries(M: fmpq_mat) -> np.ndarray:
    """An ``fmpq_mat`` as an object array of its ``fmpq`` entries."""
    return np.array([[M[i, j] for j in range(M.ncols())] for i in range(M.nrows())], dtype=object)


def to_matrix(value) -> fmpq_mat:
    return value if isinstance(value, fmpq_mat) else fmpq_mat(1, 1, [value])


class ExactEvaluator(ExpressionWalker):
    """Evaluate expressions exactly over the rationals; leaves come from ``lookup(symbol)``."""

    def __init__(self, dims: dict, lookup, free_irrational: bool = False):
        super().__init__(dims)
        self.lookup = lookup
        self.free_irrational = free_irrational
        self.freed: set = set()     # derived scalars with an irrational definition, taken as free

    def data(self, symbol):
        return self.lookup(symbol)

    variable = data
    scalar_variable = data

    def parameter(self, symbol):
        """A derived scalar from its definition; with ``free_irrational``, one whose definition is
        not rational (σ = √(ξ(1 − ξ))) is looked up as a free symbol instead: an identity that
        holds for every value of it holds for the defined one."""
        if isinstance(symbol, DerivedParam):
            try:
                return self.visit(symbol.definition)
            except NotRational:
                if not self.free_irrational:
                    raise
                self.freed.add(symbol.name)
        return self.lookup(symbol)

    def matmul(self, a, b):
        if isinstance(a, fmpq_mat) and isinstance(b, fmpq_mat) and a.ncols() != b.nrows():
            raise ValueError(f"product of {a.nrows()}x{a.ncols()} and {b.nrows()}x{b.ncols()}")
        return a * b

    def transpose(self, a):
        return a.transpose() if isinstance(a, fmpq_mat) else a

    def identity(self, n):
        M = fmpq_mat(n, n)
        for i in range(n):
            M[i, i] = 1
        return M

    def zeros(self, r, c):
        return fmpq_mat(r, c)

    def block(self, rows):
        rows = [[to_matrix(b) for b in row] for row in rows]
        heights = [row[0].nrows() for row in rows]
        widths = [b.ncols() for b in rows[0]]
        M = fmpq_mat(sum(heights), sum(widths))
        r0 = 0
        for row, h in zip(rows, heights):
            c0 = 0
            for b, w in zip(row, widths):
                if b.nrows() != h or b.ncols() != w:
                    raise ValueError("blocks do not conform")
                for i in range(h):
                    for j in range(w):
                        M[r0 + i, c0 + j] = b[i, j]
                c0 += w
            r0 += h
        return M

    def inverse(self, a, expr):
        if not isinstance(a, fmpq_mat):
            return 1 / a
        return a.inv()            # ZeroDivisionError when singular at this point

    def trace(self, a):
        a = to_matrix(a)
        return sum((a[i, i] for i in range(a.nrows())), fmpq(0))

    def scale(self, c, a):
        return a * c

    def _visit_Number(self, expr):
        if isinstance(expr, (sp.Rational, sp.Float)):
            return as_fmpq(expr)
        raise NotRational(f"{expr} is not rational")

    def _visit_NumberSymbol(self, expr):
        raise NotRational(f"{expr} is not rational")

    def _visit_Dim(self, expr):
        return fmpq(self.size(expr))

    def _visit_Mul(self, expr):
        out = fmpq(1)
        for a in expr.args:
            out = out * self.visit(a)
        return out

    def _visit_Pow(self, expr):
        base, exp = expr.args
        if not exp.is_Integer:
            raise NotRational(f"{expr}: a non-integer power")
        value = self.visit(base)
        return value ** int(exp) if int(exp) >= 0 else fmpq(1) / value ** (-int(exp))

    def _visit_MatrixBase(self, expr):
        rows, cols = expr.shape
        return fmpq_mat(rows, cols, [self.visit(sp.sympify(e)) for e in expr])


def block_values(evaluator: ExactEvaluator, spec) -> list[list[fmpq_mat]]:
    """The lower triangle of a block matrix spec, each block evaluated exactly."""
    return [[to_matrix(evaluator.visit(spec.lower[i][j])) for j in range(i + 1)]
            for i in range(spec.nblocks)]


__all__ = ["ExactEvaluator", "NotRational", "random_matrix", "random_rational", "block_values",
           "to_matrix", "as_fmpq"]
