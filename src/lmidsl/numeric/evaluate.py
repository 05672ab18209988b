"""Numerical evaluation of symbolic expressions with numpy.

Used after a solve (each LMI re-evaluated at the returned point, independently of the
backend), for recovery formulas, and for symmetry checks at bind time.  Every matrix that
gets inverted is recorded with its 2-norm condition number.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..symbolic.walker import ExpressionWalker


class NumericEvaluator(ExpressionWalker):
    """Evaluate expressions given numbers for data, variables and parameters.

    ``values`` maps symbol names to arrays (scalar variables to floats); a per-vertex symbol
    maps to a list indexed by vertex.  ``params`` maps parameter names (derived ones too) to
    floats.
    """

    def __init__(self, dims: dict, values: dict, params: dict, vertex: int | None = None):
        super().__init__(dims, vertex)
        self.values = values
        self.params = params
        self.inverted: list[dict] = []

    def _lookup(self, symbol):
        try:
            value = self.values[symbol.name]
        except KeyError:
            raise KeyError(f"no value for {symbol.name}") from None
        if getattr(symbol, "per_vertex", False) and isinstance(value, list):
            value = value[self.vertex or 0]
        return value

    def data(self, symbol):
        return np.asarray(self._lookup(symbol), dtype=float)

    variable = data

    def scalar_variable(self, symbol):
        return float(np.asarray(self._lookup(symbol)).reshape(()))

    def parameter(self, symbol):
        return float(self.params[symbol.name])

    def block(self, rows):
        return assemble_blocks(rows)

    def inverse(self, a, expr):
        a = np.atleast_2d(a)
        name = str(expr)
        if all(entry["matrix"] != name for entry in self.inverted):
            self.inverted.append({"matrix": name, "cond": float(np.linalg.cond(a))})
        try:
            inv = np.linalg.inv(a)
        except np.linalg.LinAlgError:
            raise InputError(f"the inverse of {name} is taken but {name} is singular here") from None
        if not np.all(np.isfinite(inv)):
            raise InputError(f"the inverse of {name} is taken but {name} is not invertible here")
        return inv

    def scale(self, c, a):
        return c * np.asarray(a)


def assemble_blocks(rows) -> np.ndarray:
    """[[M_ij]] from a list of rows of blocks (numbers or arrays, each taken as 2-D): ``np.block``
    for the 2-level case, filled into one preallocated array (``np.block``'s general nesting
    checks cost more than the copy for the many small blocks of an LMI).  Block (i, j) must be
    height_i × width_j, with the heights read from the first column and the widths from the
    first row."""
    rows = [[np.atleast_2d(b) for b in row] for row in rows]
    heights = [row[0].shape[0] for row in rows]
    widths = [b.shape[1] for b in rows[0]]
    dtype = np.result_type(*[b for row in rows for b in row])
    out = np.empty((sum(heights), sum(widths)), dtype=dtype)
    r0 = 0
    for row, h in zip(rows, heights):
        if len(row) != len(widths):
            raise ValueError(f"block rows of {len(widths)} and {len(row)} blocks")
        c0 = 0
        for b, w in zip(row, widths):
            if b.shape != (h, w):
                raise ValueError(f"a {b.shape[0]}x{b.shape[1]} block where {h}x{w} is expected")
            out[r0:r0 + h, c0:c0 + w] = b
            c0 += w
        r0 += h
    return out


def eigenvalues(M: np.ndarray) -> np.ndarray:
    """Eigenvalues (ascending) of the symmetric part of ``M`` (M is symmetric by construction)."""
    M = np.atleast_2d(np.asarray(M, dtype=float))
    return np.linalg.eigvalsh((M + M.T) / 2)


def max_eigenvalue(M: np.ndarray) -> float:
    """Largest eigenvalue of the symmetric part of ``M``."""
    return float(eigenvalues(M)[-1])


def asymmetry(M: np.ndarray) -> float:
    """‖M − Mᵀ‖_F / max(1, ‖M‖_F)."""
    M = np.atleast_2d(np.asarray(M, dtype=float))
    return float(np.linalg.norm(M - M.T) / max(1.0, np.linalg.norm(M)))


def evaluate_block_matrix(evaluator: ExpressionWalker, spec) -> np.ndarray:
    """The full symmetric matrix of a :class:`~lmidsl.symbolic.blocks.BlockMatrixSpec`, block by
    block: the lower triangle evaluated by ``evaluator`` (floats, or balls for the proofs), the
    upper triangle its transpose."""
    q = spec.nblocks
    lower = [[np.atleast_2d(evaluator.visit(spec.lower[i][j])) for j in range(i + 1)] for i in range(q)]
    return assemble_blocks([[lower[i][j] if j <= i else lower[j][i].T for j in range(q)] for i in range(q)])
