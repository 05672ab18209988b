"""Delta-operator realisations: δx(k) = (x(k+1) − x(k))/h.

A delta-form system (A_δ, B_δ, C) and its shift form x(k+1) = A x + B u are related by
A = I + h A_δ, B = h B_δ (C unchanged).  Papers in the delta domain sometimes print matrices
whose form is ambiguous; :func:`filter_reading` reads printed filter matrices either way and
returns delta-form matrices.
"""
from __future__ import annotations

import numpy as np

from lmidsl import InputError

READINGS = ("delta", "shift")


def shift_to_delta(A, B, C, h: float):
    """(A_δ, B_δ, C) = ((A − I)/h, B/h, C) for a shift-form (A, B, C)."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    return (A - np.eye(A.shape[0])) / h, np.asarray(B, dtype=float) / h, np.asarray(C, dtype=float)


def delta_to_shift(A, B, C, h: float):
    """(A, B, C) = (I + h A_δ, h B_δ, C) for a delta-form (A_δ, B_δ, C)."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    return np.eye(A.shape[0]) + h * A, h * np.asarray(B, dtype=float), np.asarray(C, dtype=float)


def filter_reading(matrices: dict, reading: str, h: float, names=("Af", "Bf", "Cf")) -> dict:
    """Delta-form filter matrices from printed ones read as ``reading`` ('delta' or 'shift')."""
    if reading not in READINGS:
        raise InputError(f"reading must be one of {', '.join(READINGS)}, got {reading!r}")
    A, B, C = (np.atleast_2d(np.asarray(matrices[k], dtype=float)) for k in names)
    if reading == "shift":
        A, B, C = shift_to_delta(A, B, C, h)
    return dict(zip(names, (A, B, C)))


def balanced_realisation(A, B, C, h: float):
    """A balanced realisation of a stable delta-form system (same transfer function).

    The gramians are those of the shift form (I + hA, hB, C); the similarity x → T x that
    makes them equal and diagonal changes (A, B, C) to (T A T⁻¹, T B, C T⁻¹).  Analysis LMIs
    are invariant under it (their Lyapunov matrix is transformed by congruence), but their
    conditioning is not: a balanced filter is the well-conditioned one to certify.
    Returns (A, B, C, T); raises ValueError when the shift form is not Schur stable.
    """
    import scipy.linalg as sl

    Ash, Bsh, C = delta_to_shift(A, B, C, h)
    if max(abs(np.linalg.eigvals(Ash))) >= 1:
        raise ValueError("the filter is not stable in the delta sense (I + hA_f not Schur)")
    Wc = sl.solve_discrete_lyapunov(Ash, Bsh @ Bsh.T)
    Wo = sl.solve_discrete_lyapunov(Ash.T, C.T @ C)
    Lc = np.linalg.cholesky((Wc + Wc.T) / 2 + 1e-300 * np.eye(len(Wc)))
    U, s, _ = np.linalg.svd(Lc.T @ Wo @ Lc)
    T_inv = Lc @ U @ np.diag(s ** -0.25)           # x = T⁻¹ x_bal
    T = np.linalg.inv(T_inv)
    A = np.atleast_2d(np.asarray(A, dtype=float))
    return T @ A @ T_inv, T @ np.asarray(B, dtype=float), C @ T_inv, T
