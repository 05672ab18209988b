"""A bounded-real-lemma point from a Riccati equation instead of an SDP solver.

For G = (A, B, C, D) and a level g = γ², the bounded-real LMI with storage P ≻ 0

    continuous:  [[AᵀP + PA, PB, Cᵀ], [BᵀP, −gI, Dᵀ], [C, D, −I]] ≺ 0,
    discrete:    [A B; C D]ᵀ diag(P, I) [A B; C D] − diag(P, gI) ≺ 0

holds (Schur complement on the last block) iff, with R = gI − DᵀD ≻ 0 and S = CᵀD,

    continuous:  AᵀP + PA + CᵀC + (PB + S) R⁻¹ (BᵀP + Sᵀ) ≺ 0,
    discrete:    AᵀPA − P + CᵀC + (AᵀPB + S)(R − BᵀPB)⁻¹(BᵀPA + Sᵀ) ≺ 0  (R − BᵀPB ≻ 0).

When A is stable and ‖G‖∞ < γ, the Riccati *equation* with CᵀC replaced by CᵀC + εI has a
stabilising solution P ≻ 0 for every ε > 0 small enough that the output-augmented system
(A, B, [C; √ε I], [D; 0]) still has norm < γ (Zhou, Doyle, Glover, *Robust and Optimal Control*,
1996, Cor. 13.24 and its discrete counterpart); at that P the left-hand side equals −εI: the LMI
holds strictly.  :func:`bounded_real_storage` solves it with SciPy's
``solve_continuous_are`` / ``solve_discrete_are`` (generalised Schur method; R = DᵀD − gI is
indefinite, which they allow) and returns P, or None when there is no stabilising solution.

Nothing here is a proof: the point is handed to the certificate
(:func:`lmidsl.solver.solution.lmi_certificate`, ball arithmetic), exactly as a solver's point
would be.  What it avoids is the SDP: on closed loops whose controller is nearly singular
(recovery condition numbers ~1e11), SDP solvers certify only a γ well above the closed loop's
norm while the Riccati route lands within ε of it.
"""
from __future__ import annotations

import numpy as np

from .systems import hinf_norm as systems_hinf_norm, is_stable

FRACTIONS = (0.5, 0.05)
"""ε as a fraction of the room (g − ‖G‖∞²) / ‖(sI − A)⁻¹B‖∞²: the CᵀC + εI of the Riccati
equation raises the squared norm by at most ε ‖(sI − A)⁻¹B‖∞², so these ε keep the augmented
norm below γ (a stabilising solution exists) while making the LMI as strict as possible."""


def bounded_real_storage(A, B, C, D, g: float, time: str, eps: float) -> np.ndarray | None:
    """The stabilising solution P of the bounded-real Riccati equation with CᵀC + εI at the level
    g = γ² (module docstring), or None when there is none (γ ≤ the norm, or A unstable)."""
    from scipy.linalg import solve_continuous_are, solve_discrete_are

    A, B, C, D = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B, C, D))
    n = A.shape[0]
    Q = C.T @ C + eps * np.eye(n)
    R = D.T @ D - g * np.eye(B.shape[1])
    S = C.T @ D
    try:
        with np.errstate(all="ignore"):
            if time == "continuous":
                P = solve_continuous_are(A, B, Q, R, s=S)
            else:
                P = solve_discrete_are(A, B, Q, R, s=S)
    except (np.linalg.LinAlgError, ValueError):
        return None
    if not np.all(np.isfinite(P)):
        return None
    P = (P + P.T) / 2
    if np.linalg.eigvalsh(P)[0] <= 0:
        return None
    return P


def hinf_norm(A, B, C, D, time: str) -> float | None:
    """‖(A, B, C, D)‖∞ by SLICOT AB13DD (:func:`lmidsl.numeric.systems.hinf_norm`), None when A is
    not stable."""
    value = systems_hinf_norm(A, B, C, D, time)
    return None if value == float("inf") else value


def storage_candidates(A, B, C, D, g: float, time: str, norm: float):
    """(ε, P) for each ε of :data:`FRACTIONS` of the room below the level g = γ² (``norm``:
    ‖G‖∞ < γ), those for which a stabilising solution exists."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    B = np.atleast_2d(np.asarray(B, dtype=float))
    n = A.shape[0]
    gain = hinf_norm(A, B, np.eye(n), np.zeros((n, B.shape[1])), time)
    if gain is None or not g > norm ** 2:
        return
    for fraction in FRACTIONS:
        eps = fraction * (g - norm ** 2) / max(gain ** 2, 1e-300)
        P = bounded_real_storage(A, B, C, D, g, time, eps)
        if P is not None:
            yield eps, P


def full_information_gain(A, B1, B2, C1, D11, D12, gamma: float, time: str, eps: float = 0.0):
    """The state-feedback gain K of the H∞ full-information Riccati equation at level γ, or None.

    With B = [B1 B2], D = [D11 D12] and R = DᵀD − diag(γ²I, 0), the stabilising solution X ⪰ 0 of

        continuous:  AᵀX + XA + Q − (XB + C1ᵀD) R⁻¹ (BᵀX + DᵀC1) = 0,
        discrete:    AᵀXA − X + Q − (AᵀXB + C1ᵀD)(R + BᵀXB)⁻¹(BᵀXA + DᵀC1) = 0,

    Q = C1ᵀC1 + εI, exists when γ exceeds the optimal state-feedback level (D12 of full column
    rank; Zhou, Doyle, Glover 1996, ch. 16 and 21), and F = −R⁻¹(BᵀX + DᵀC1) (discrete:
    −(R + BᵀXB)⁻¹(BᵀXA + DᵀC1)) gives the worst disturbance (first rows) and the gain K (last
    rows).  Nothing is claimed for K here: its closed loop is certified like any design."""
    from scipy.linalg import solve_continuous_are, solve_discrete_are

    A, B1, B2, C1, D11, D12 = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B1, B2, C1, D11, D12))
    n, m1 = A.shape[0], B1.shape[1]
    B, D = np.hstack([B1, B2]), np.hstack([D11, D12])
    R = D.T @ D
    R[:m1, :m1] -= gamma ** 2 * np.eye(m1)
    Q = C1.T @ C1 + eps * np.eye(n)
    try:
        with np.errstate(all="ignore"):
            if time == "continuous":
                X = solve_continuous_are(A, B, Q, R, s=C1.T @ D)
                F = -np.linalg.solve(R, B.T @ X + D.T @ C1)
            else:
                X = solve_discrete_are(A, B, Q, R, s=C1.T @ D)
                F = -np.linalg.solve(R + B.T @ X @ B, B.T @ X @ A + D.T @ C1)
    except (np.linalg.LinAlgError, ValueError):
        return None
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(F))):
        return None
    X = (X + X.T) / 2
    eig = np.linalg.eigvalsh(X)
    if eig[0] < -1e-9 * max(abs(eig[-1]), 1.0):
        return None
    return F[m1:, :]


__all__ = ["FRACTIONS", "bounded_real_storage", "full_information_gain", "hinf_norm", "storage_candidates"]
