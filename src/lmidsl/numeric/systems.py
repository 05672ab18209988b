"""Numeric linear systems in either time domain: stability and frequency-response peaks.

A theorem says whether it is ``time="continuous"`` (ẋ = Ax, frequency variable s = jω,
stable iff every Re λ(A) < 0) or ``time="discrete"`` (x⁺ = Ax, z = e^{jωh}, stable iff every
|λ(A)| < 1).  Everything here takes the time domain as an argument, so a certificate written
once works for both.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError


def frequency_variable(omega: float, time: str, sampling: float = 1.0) -> complex:
    """s = jω (continuous) or z = e^{jωh} (discrete, h = ``sampling``)."""
    if time == "continuous":
        return 1j * omega
    if time == "discrete":
        return np.exp(1j * omega * sampling)
    raise InputError(f"unknown time domain {time!r}")


def is_stable(A: np.ndarray, time: str) -> bool:
    """Hurwitz (continuous) or Schur (discrete) stability of a state matrix."""
    eig = np.linalg.eigvals(np.atleast_2d(A))
    if time == "continuous":
        return bool(np.all(eig.real < 0))
    if time == "discrete":
        return bool(np.all(np.abs(eig) < 1))
    raise InputError(f"unknown time domain {time!r}")


def hinf_norm(A, B, C, D, time: str, tol: float = 1e-10) -> float:
    """‖(A, B, C, D)‖∞ of a stable system (+∞ when A is not stable): SLICOT's AB13DD (Bruinsma–
    Steinbuch, via slycot) — the routine behind python-control's ``norm(sys, "inf")`` and
    ``linfnorm``, called directly so that the evidence does not import python-control (scipy.signal
    and matplotlib: 2–3 s of CPU) to compute one norm."""
    return hinf_peak(A, B, C, D, time, tol)[0]


def hinf_peak(A, B, C, D, time: str, tol: float = 1e-10) -> tuple[float, float]:
    """(‖G‖∞, the frequency of the peak) of a stable system by AB13DD (see :func:`hinf_norm`):
    ω in rad/s (continuous) or θ in rad/sample (discrete, z = e^{jθ}); +∞ for a peak at infinity;
    (+∞, nan) when A is not stable."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    B, C = np.atleast_2d(np.asarray(B, dtype=float)), np.atleast_2d(np.asarray(C, dtype=float))
    D = np.atleast_2d(np.asarray(D, dtype=float)) if D is not None else np.zeros((C.shape[0], B.shape[1]))
    if A.size == 0:
        return (float(np.linalg.svd(D, compute_uv=False)[0]) if D.size else 0.0), 0.0
    if not is_stable(A, time):
        return float("inf"), float("nan")
    from slycot import ab13dd     # 0.5 s to import: only when a norm is computed
    n, m, p = A.shape[0], B.shape[1], C.shape[0]
    gpeak, fpeak = ab13dd("C" if time == "continuous" else "D", "I", "S", "Z" if not D.any() else "D",
                          n, m, p, A, np.eye(n), B, C, D, tol)
    return float(gpeak), float(fpeak)


def default_grid(time: str, sampling: float = 1.0, points: int = 1200, top: float = 1e4) -> np.ndarray:
    """ω = 0 and a logarithmic grid: 1e-3..``top`` rad/s (continuous) or up to π/h (discrete)."""
    if time == "continuous":
        return np.concatenate([[0.0], np.logspace(-3, np.log10(top), points)])
    return np.concatenate([[0.0], np.logspace(-4, np.log10(np.pi / sampling), points)])


def peak_gain(response, omegas: np.ndarray) -> tuple[float, float]:
    """(sup_ω σ̄(G(ω)), ω at the peak): grid search, then a local refinement.

    ``response(omegas)`` returns the stacked responses G(ω_k), shape (len(omegas), p, m).
    """
    from scipy.optimize import minimize_scalar   # 0.6 s to import: only when a peak is refined
    omegas = np.asarray(omegas, dtype=float)
    gains = np.linalg.svd(response(omegas), compute_uv=False)[:, 0]
    k = int(np.argmax(gains))
    best, where = float(gains[k]), float(omegas[k])
    lo = omegas[max(k - 1, 0)]
    hi = omegas[min(k + 1, len(omegas) - 1)]
    if hi > lo:
        res = minimize_scalar(
            lambda w: -np.linalg.svd(response(np.array([w])), compute_uv=False)[0, 0],
            bounds=(lo, hi), method="bounded", options={"xatol": 1e-9 * max(hi, 1.0)})
        if -res.fun > best:
            best, where = float(-res.fun), float(res.x)
    return best, where
