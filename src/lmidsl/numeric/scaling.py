"""Exact rescaling of signals, applied before compiling and undone after the recovery.

A theorem declares (``Theorem.scale_signal``) which data produce a signal u (``rows``: their
rows are u's components) and which consume it (``cols``), and which recovered matrices
consume or produce it.  Writing u = S u' with S = diag(s) > 0 is a change of coordinates:
producers become S⁻¹M, consumers M S, and the recovered matrices are mapped back
(consumers M = M' S⁻¹, producers M = S M').  The theorem author asserts that the theorem's
conditions are invariant under it (for an internal signal such as a measurement, γ is unchanged).

Why: interior-point solvers see the LMI data, not the system.  An output matrix of size ~30
next to data of size ~0.1 makes the Lyapunov-type variables span many orders of magnitude and
Clarabel / CVXOPT stop with numerical errors (seed 001, docs/reproductions/001.md).

Choice of S (``mode="auto"``): s_i is the power of two nearest the 2-norm of row i of the
producers stacked side by side (so they get unit-size rows); a power of two makes the
rescaling exact in floating point.  Without producers, consumers' column norms are used.
``mode="none"`` switches it off; a dict {signal: factor or [factors]} sets S by hand.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.linalg import matrix_balance

from ..errors import InputError
from .instance import Instance


@dataclass
class ScalingRecord:
    """One applied signal scaling: u = diag(factors) u'."""

    signal: str
    factors: list
    rows: tuple
    cols: tuple
    recovered_rows: tuple
    recovered_cols: tuple
    how: str

    def as_dict(self) -> dict:
        return {"signal": self.signal, "factors": self.factors, "how": self.how,
                "data_divided_rows": list(self.rows), "data_multiplied_cols": list(self.cols),
                "recovered_rows_multiplied": list(self.recovered_rows),
                "recovered_cols_divided": list(self.recovered_cols)}


@dataclass
class AppliedScaling:
    """The original instance, the scaled one the solver sees, and how to map results back."""

    original: Instance
    scaled: Instance
    records: list = field(default_factory=list)

    @property
    def active(self) -> bool:
        return any(any(f != 1.0 for f in r.factors) for r in self.records)

    def undo(self, recovered: dict) -> dict:
        """Recovered matrices of the scaled problem → matrices of the original problem."""
        out = dict(recovered)
        for rec in self.records:
            s = np.asarray(rec.factors, dtype=float)
            for name in rec.recovered_cols:
                if name in out:
                    out[name] = np.asarray(out[name]) / s[None, :]
            for name in rec.recovered_rows:
                if name in out:
                    out[name] = np.asarray(out[name]) * s[:, None]
        return out

    def as_dict(self) -> dict:
        return {"active": self.active, "signals": [r.as_dict() for r in self.records],
                "note": "values, LMI eigenvalues and condition numbers refer to the scaled instance; "
                        "recovered matrices are mapped back to the original data"}


def _matrices(data: dict, names) -> list:
    """The matrices of the named data, every vertex of a per-vertex datum included."""
    return [np.atleast_2d(v) for n in names for v in (data[n] if isinstance(data[n], list) else [data[n]])]


def _stack(data: dict, names, axis):
    return np.concatenate(_matrices(data, names), axis=axis)


def _power_of_two(x: np.ndarray) -> np.ndarray:
    out = np.ones_like(x)
    pos = x > 0
    out[pos] = 2.0 ** np.round(np.log2(x[pos]))
    return out


def auto_factors(instance: Instance, decl) -> tuple[np.ndarray, str]:
    """S for one declared scaling: unit-size producer rows, powers of two; for a state (a square
    datum that both produces and consumes the signal, x(k+1) = A x or ẋ = A x), the similarity
    that balances A (LAPACK's gebal through ``scipy.linalg.matrix_balance``, powers of two)."""
    data = instance.data
    square = [n for n in decl.rows if n in decl.cols and _first(data[n]).shape[0] == _first(data[n]).shape[1]]
    if square:
        A = sum(np.abs(_first(data[n])) for n in square)
        _, (scale, _) = matrix_balance(A, permute=False, separate=True)
        scale = np.asarray(scale, dtype=float)
        return scale * _equalising_factor(data, decl, square, scale), \
            f"matrix_balance({' + '.join(square)}) × 2^k equalising the input and output matrices"
    if decl.rows:
        norms = np.linalg.norm(_stack(data, decl.rows, axis=1), axis=1)
        return _power_of_two(norms), f"2^round(log2 ‖row of [{' '.join(decl.rows)}]‖)"
    if decl.cols:
        norms = np.linalg.norm(_stack(data, decl.cols, axis=0), axis=0)
        return 1.0 / _power_of_two(norms), f"2^-round(log2 ‖column of [{' '.join(decl.cols)}]‖)"
    raise InputError(f"{instance.theorem.id}: scaling of {decl.signal} names no data")


def _equalising_factor(data: dict, decl, square: list, scale: np.ndarray) -> float:
    """The uniform factor c (a power of two) of x = c·S x' that leaves the balanced A alone and
    gives the other producers (B: divided by c) and consumers (C: multiplied by c) the same
    norm: c = √(‖S⁻¹B‖ / ‖C S‖).  Without it, B ~ 100 and C ~ 0.01 after balancing make the
    Lyapunov matrix ~1e-3 and the strictness margin, not the problem, set the last digits."""
    b = max((np.linalg.norm(v / scale[:, None])
             for v in _matrices(data, [n for n in decl.rows if n not in square])), default=0.0)
    c = max((np.linalg.norm(v * scale[None, :])
             for v in _matrices(data, [n for n in decl.cols if n not in square])), default=0.0)
    if b == 0.0 or c == 0.0:
        return 1.0
    return float(2.0 ** np.round(0.5 * np.log2(b / c)))


def _first(value) -> np.ndarray:
    return np.atleast_2d(value[0] if isinstance(value, list) else value)


def _apply(value, fn):
    return [fn(v) for v in value] if isinstance(value, list) else fn(value)


def apply_scaling(instance: Instance, mode="auto") -> AppliedScaling:
    """Scale ``instance`` by its theorem's declared signal scalings (see the module docstring)."""
    theorem = instance.theorem
    if mode in (None, "none") or not theorem.scalings:
        return AppliedScaling(instance, instance, [])
    data = dict(instance.data)
    records = []
    for decl in theorem.scalings:
        if isinstance(mode, dict):
            if decl.signal not in mode:
                continue
            given = np.atleast_1d(np.asarray(mode[decl.signal], dtype=float))
            size = (_first(data[decl.rows[0]]).shape[0] if decl.rows
                    else _first(data[decl.cols[0]]).shape[1])
            s = np.broadcast_to(given, (size,)).astype(float)
            if np.any(s <= 0):
                raise InputError(f"{theorem.id}: scaling of {decl.signal} must be positive")
            how = "given"
        elif mode == "auto":
            s, how = auto_factors(instance, decl)
        else:
            raise InputError(f"scaling must be 'auto', 'none' or {{signal: factor}}, got {mode!r}")
        for name in decl.rows:
            data[name] = _apply(data[name], lambda v: np.asarray(v) / s[:, None])
        for name in decl.cols:
            data[name] = _apply(data[name], lambda v: np.asarray(v) * s[None, :])
        records.append(ScalingRecord(decl.signal, [float(x) for x in s], decl.rows, decl.cols,
                                     decl.recovered_rows, decl.recovered_cols, how))
    return AppliedScaling(instance, replace(instance, data=data), records)
