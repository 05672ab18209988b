"""Full-order H∞ output feedback from Riccati equations, and its linearising variables.

**The controller.**  For the plant P = (A, B1, B2, C1, C2, D11, D12, D21) (D22 = 0) and a level γ
the central controller of the two-Riccati solution (Glover and Doyle, Systems & Control Letters
11, 1988; Zhou, Doyle, Glover, *Robust and Optimal Control*, 1996, Ch. 17) is computed by SLICOT
(SB10FD in continuous time, SB10DD in discrete time, through slycot).  Those routines need the
*regular* problem: D12 of full column rank, D21 of full row rank, and no zeros of P12, P21 on the
stability boundary.  Most published plants are singular (COMPleib: D21 = 0 on most).  They are
made regular by :func:`regularised_plant`, which adds the outputs ε x, ε u to z and the
disturbances ε w_x (on the state), ε w_y (on the measurement):

    B1ε = [B1, εI, 0],  C1ε = [C1; εI; 0],  D11ε = [[D11, 0, 0], [0, 0, 0], [0, 0, 0]],
    D12ε = [D12; 0; εI],  D21ε = [D21, 0, εI].

D12ε has full column rank and D21ε full row rank, and P12ε, P21ε have no finite zeros at all
(their realisations' system matrices have full rank at every s through the ε columns and rows).
The closed loop of the plant with any controller is the (1, 1) block of the regularised closed
loop, so its norm is at most the regularised one: a controller at level γ for Pε is one at level γ
for P, and γ_opt(Pε) ↓ γ_opt(P) as ε → 0 (the singular optimum is an infimum).  Nothing here is
a proof: the controller's closed-loop norm is measured, and the point built from it
(:func:`linearising_variables`) is proved against the theorem's own LMIs by the caller.  SLICOT
is given the plant in state coordinates balanced by its TB01ID (:func:`balanced_plant`): the
controller does not depend on them, and on badly scaled data it found none at any level.

**The linearising variables.**  For a full-order controller K = (AK, BK, CK, DK) whose closed loop
(Acl, Bcl, Ccl, Dcl) (state [x; xK]) satisfies the bounded real lemma with −γI on both diagonal
blocks at the storage 𝒫 ≻ 0, write (Scherer, Gahinet, Chilali, IEEE TAC 42(7), 1997, Sec. IV)

    𝒫 = [[Y, N], [Nᵀ, ·]],  𝒫⁻¹ = [[X, M], [Mᵀ, ·]],   so  X Y + M Nᵀ = I,

    Â = N AK Mᵀ + N BK C2 X + Y B2 CK Mᵀ + Y (A + B2 DK C2) X,
    B̂ = N BK + Y B2 DK,   Ĉ = CK Mᵀ + DK C2 X,   D̂ = DK.

With Π = [[X, I], [Mᵀ, 0]] (Π is invertible when M is), Πᵀ 𝒫 Acl Π and the other blocks are the
affine blocks of :func:`lmidsl.output_feedback_blocks` (A11 = A X + B2 Ĉ, A22 = Y A + B̂ C2, …) and
Πᵀ 𝒫 Π = [[X, I], [I, Y]]: the SGC LMI at (X, Y, Â, B̂, Ĉ, D̂, γ) is the congruence of the closed
loop's, in both time domains.
"""
from __future__ import annotations

import numpy as np
from flint import fmpq, fmpq_mat

from .exact import entries, rational_matrix
from .interconnection import lower_lft
from .proof import PreciseMatrix
from .riccati import hinf_norm


def regularised_plant(plant: tuple, eps: float) -> tuple:
    """The plant (A, B1, B2, C1, C2, D11, D12, D21) with the outputs ε x, ε u and the inputs
    ε w_x, ε w_y added (module docstring): a regular problem whose closed loops bound the plant's."""
    A, B1, B2, C1, C2, D11, D12, D21 = plant
    n, m1, m2, p1, p2 = A.shape[0], B1.shape[1], B2.shape[1], C1.shape[0], C2.shape[0]
    B1e = np.hstack([B1, eps * np.eye(n), np.zeros((n, p2))])
    C1e = np.vstack([C1, eps * np.eye(n), np.zeros((m2, n))])
    D11e = np.zeros((p1 + n + m2, m1 + n + p2))
    D11e[:p1, :m1] = D11
    D12e = np.vstack([D12, np.zeros((n, m2)), eps * np.eye(m2)])
    D21e = np.hstack([D21, np.zeros((p2, n)), eps * np.eye(p2)])
    return A, B1e, B2, C1e, C2, D11e, D12e, D21e


def balanced_plant(plant: tuple) -> tuple[tuple, np.ndarray]:
    """(the plant in balanced state coordinates, t): T⁻¹AT, T⁻¹B, CT with T = diag(t), t the
    powers of 2 nearest SLICOT TB01ID's balancing of the system matrix [[A, [B1 B2]], [[C1; C2], 0]]
    (powers of 2, so that the scaling is exact in doubles and :func:`linearising_variables` maps
    the point back exactly).  A controller acts on y and u, not on the plant's state: it is the
    same controller for both realisations, and its closed loops are similar (the same norm).  On
    a theorem's state-scaled data (COMPleib's TF1: ‖B1‖ = 1.9e-7, ‖C1‖ = 2.6e5) SLICOT found no
    controller at any level, and no closed-loop storage was a point; balanced, both."""
    from slycot import tb01id

    A, B1, B2, C1, C2, D11, D12, D21 = plant
    n = A.shape[0]
    B, C = np.hstack([B1, B2]), np.vstack([C1, C2])
    try:
        scale = tb01id(n, B.shape[1], C.shape[0], 0.0, A.copy(), B.copy(), C.copy(), job="A")[4]
        t = 2.0 ** np.round(np.log2(np.asarray(scale, dtype=float)))
    except Exception:        # noqa: BLE001 — slycot's errors: the plant as it is
        t = np.ones(n)
    if not np.all(np.isfinite(t)) or np.any(t == 0):
        t = np.ones(n)
    return (A * t / t[:, None], B1 / t[:, None], B2 / t[:, None], C1 * t, C2 * t, D11, D12, D21), t


def central_controller(plant: tuple, gamma: float, time: str):
    """(AK, BK, CK, DK): SLICOT's central H∞ controller of the regular ``plant`` at the level γ
    (SB10FD continuous, SB10DD discrete), or None where SLICOT finds none."""
    from slycot import sb10dd, sb10fd

    A, B1, B2, C1, C2, D11, D12, D21 = plant
    n, m2, p2 = A.shape[0], B2.shape[1], C2.shape[0]
    B, C = np.hstack([B1, B2]), np.vstack([C1, C2])
    D = np.block([[D11, D12], [D21, np.zeros((p2, m2))]])
    try:
        with np.errstate(all="ignore"):
            if time == "continuous":
                AK, BK, CK, DK, _ = sb10fd(n, B.shape[1], C.shape[0], m2, p2, gamma, A, B, C, D)
            else:
                _, AK, BK, CK, DK, *_ = sb10dd(n, B.shape[1], C.shape[0], m2, p2, gamma, A, B, C, D)
    except Exception:        # noqa: BLE001 — slycot raises on "no controller at this level"
        return None
    K = tuple(np.atleast_2d(np.asarray(M, dtype=float)) for M in (AK, BK, CK, DK))
    return K if all(np.all(np.isfinite(M)) for M in K) else None


def closed_loop(plant: tuple, controller: tuple) -> tuple:
    """(Acl, Bcl, Ccl, Dcl) of the plant (D22 = 0) with u = K y, state [x; xK]
    (:func:`lmidsl.numeric.interconnection.lower_lft`)."""
    B2, C2 = plant[2], plant[4]
    loop = lower_lft((*plant, np.zeros((C2.shape[0], B2.shape[1]))), controller, None)
    return loop.A, loop.B, loop.C, loop.D


def closed_loop_norm(plant: tuple, controller: tuple, time: str) -> float | None:
    """‖F_l(P, K)‖∞ by SLICOT (None when the loop is unstable)."""
    value = hinf_norm(*closed_loop(plant, controller), time)
    return value if value is not None and np.isfinite(value) else None


def bounded_real_residual(loop: tuple, storage, g: float, time: str) -> float:
    """λ_max of the closed loop's bounded-real matrix at the storage P (γ²-form, g = γ²; the
    module docstring of :mod:`lmidsl.numeric.riccati`) in doubles, relative to its largest
    eigenvalue modulus: ≤ ~1e-9 where the LMI may hold up to rounding."""
    A, B, C, D = loop
    P = np.asarray(storage, dtype=float)
    m, p = B.shape[1], C.shape[0]
    if time == "continuous":
        L = np.block([[A.T @ P + P @ A, P @ B, C.T], [B.T @ P, -g * np.eye(m), D.T], [C, D, -np.eye(p)]])
    else:
        L = np.block([[A.T @ P @ A - P + C.T @ C, A.T @ P @ B + C.T @ D],
                      [B.T @ P @ A + D.T @ C, B.T @ P @ B + D.T @ D - g * np.eye(m)]])
    eig = np.linalg.eigvalsh((L + L.T) / 2)
    return float(eig[-1] / max(abs(eig).max(), 1e-300))


def linearising_variables(storage, gamma: float, plant: tuple, controller: tuple,
                          state_scale: np.ndarray | None = None) -> dict | None:
    """{X, Y, Ah, Bh, Ch, Dh} of the closed loop's storage 𝒫 = ``storage`` / γ (``storage``: of the
    γ²-form, doubles or a :class:`~lmidsl.numeric.proof.PreciseMatrix`; module docstring), computed
    exactly in rationals from the exact values of the storage, the plant's and the controller's
    doubles: the point's LMI is then exactly the congruence of the closed loop's by Π, which no
    rounding of the conversion can break (on singular plants 𝒫 has condition numbers ~1e13, and
    the conversion in doubles violated LMIs that held for the closed loop).  With ``state_scale``
    t, ``plant`` is the balanced one of :func:`balanced_plant` and the variables are mapped back
    to the plant's own coordinates x = T x_b, T = diag(t), exactly: X = T X_b T, Y = T⁻¹ Y_b T⁻¹,
    Â = T⁻¹ Â_b T, B̂ = T⁻¹ B̂_b, Ĉ = Ĉ_b T (the SGC LMI of the plant is the congruence of the
    balanced one by diag(T⁻¹, T, I, I)).  None when 𝒫 or its off-diagonal block is singular, or
    the controller is not of full order."""
    A, B1, B2, C1, C2 = (rational_matrix(M) for M in plant[:5])
    AK, BK, CK, DK = (rational_matrix(M) for M in controller)
    n = A.nrows()
    if AK.nrows() != n:
        return None
    P = rational_matrix(storage) / fmpq(*float(gamma).as_integer_ratio())
    try:
        Q = P.inv()
    except ZeroDivisionError:
        return None
    top, bottom = range(n), range(n, 2 * n)
    Y, N, X, M = _block(P, top, top), _block(P, top, bottom), _block(Q, top, top), _block(Q, top, bottom)
    if N.rank() < n or M.rank() < n:
        return None
    Mt = M.transpose()
    Ah = N * AK * Mt + N * BK * C2 * X + Y * B2 * CK * Mt + Y * (A + B2 * DK * C2) * X
    values = {"X": X, "Y": Y, "Ah": Ah, "Bh": N * BK + Y * B2 * DK, "Ch": CK * Mt + DK * C2 * X}
    if state_scale is not None:
        T = rational_matrix(np.diag(state_scale))
        Ti = rational_matrix(np.diag(1.0 / np.asarray(state_scale, dtype=float)))   # powers of 2: exact
        values = {"X": T * values["X"] * T, "Y": Ti * values["Y"] * Ti, "Ah": Ti * values["Ah"] * T,
                  "Bh": Ti * values["Bh"], "Ch": values["Ch"] * T}
    out = {k: PreciseMatrix.of(entries(v)) for k, v in values.items()}
    out["Dh"] = np.atleast_2d(np.asarray(controller[3], dtype=float))
    return out


def _block(M: fmpq_mat, rows: range, cols: range) -> fmpq_mat:
    """The block of an ``fmpq_mat`` on the given rows and columns."""
    return fmpq_mat(len(rows), len(cols), [M[i, j] for i in rows for j in cols])
