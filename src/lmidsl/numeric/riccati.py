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

**Stiff realisations.**  On closed loops with a pole at −5e7 and output entries ~1e8 (an H∞
controller of large gain) the Riccati solution in the coordinates as written is wrong in its
sign (λ_min(P) ≈ −1e-2, also after ``matrix_balance``): the LMI's entries reach 1e16 and the
margin it needs is ~1e-7.  :func:`storage_candidates` therefore also solves the equation for
the *balanced* realisation (Ab, Bb, Cb) = (T⁻¹AT, T⁻¹B, CT) (square-root balancing, Laub,
Heath, Paige and Ward, IEEE TAC 1987; the Gramians' Cholesky factors by SLICOT SB03OD
(Hammarling), each Gramian of (A, [B  ρI]) and (Aᵀ, [Cᵀ  ρI]) so that T exists for a
non-minimal system) and maps the storage back, P = T⁻ᵀ Pb T⁻¹: the LMI at P is the congruence
diag(T⁻ᵀ, I, I) · LMI_b(Pb) · diag(T⁻¹, I, I), so P is feasible iff Pb is.  In the balanced
coordinates the equation is solved with CᵀC + ε W, W = diag(w) weighting state i by the size of
row and column i of Ab (relative to the smallest): the rounding of AᵀP + PA in row i is
~u‖Ab_i‖‖Pb‖, so the margin is put where the rounding is (the augmented norm then rises by at
most ε ‖W^½(sI − A)⁻¹B‖∞²).  P is a float matrix; whether the LMI holds at it for the data as
written is for the ball-arithmetic proof to say (:func:`lmidsl.numeric.proof.prove_block_matrix`
at 212 bits, which a rounded eigenvalue of an LMI with entries ~1e16 cannot decide).
Measured on the stress set's stiff closed loops (``benchmarks/stress/designs.py``): proved at
γ = ‖G‖∞ (1 + 1e-5 … 9e-5) where the SDP certified 14.716 against the norm 2.631 (light-1),
nothing (huge_gain-2) and 2.8 % above the norm (spread-3).
"""
from __future__ import annotations

import numpy as np
from flint import acb_mat, arb, arb_mat

from .exact import midpoint
from .proof import PreciseMatrix, ball_precision, decimal_ball, object_array
from .systems import hinf_norm as systems_hinf_norm, is_stable

FRACTIONS = (0.5, 0.05)
"""ε as a fraction of the room (g − ‖G‖∞²) / ‖(sI − A)⁻¹B‖∞²: the CᵀC + εI of the Riccati
equation raises the squared norm by at most ε ‖(sI − A)⁻¹B‖∞², so these ε keep the augmented
norm below γ (a stabilising solution exists) while making the LMI as strict as possible."""


def bounded_real_storage(A, B, C, D, g: float, time: str, eps: float,
                         weights: np.ndarray | None = None) -> np.ndarray | None:
    """The stabilising solution P of the bounded-real Riccati equation with CᵀC + ε diag(w)
    (w = ``weights``, default all ones) at the level g = γ² (module docstring), or None when there
    is none (γ ≤ the norm, or A unstable)."""
    from scipy.linalg import solve_continuous_are, solve_discrete_are

    A, B, C, D = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B, C, D))
    n = A.shape[0]
    Q = C.T @ C + eps * (np.eye(n) if weights is None else np.diag(weights))
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


def realisation_norm(A, B, C, D, time: str) -> tuple[float | None, str]:
    """(‖G‖∞, how) by SLICOT AB13DD on the square-root balanced realisation when it exists (else
    on the data as written; None when A is not stable).  On stiff closed loops AB13DD on the data
    as written is wrong both ways (stress closed loops of hinfsyn controllers, eigenvalues to 3e10:
    7.832 where σ_max(G(jω)) on a grid peaks at 5.0287 and the balanced realisation gives 5.02870;
    1.8747 where the grid shows 2.00251); the balanced realisation's value agreed with the grid to
    4 digits on all of them.  Not a proof either way: the level only seeds the Riccati route, whose
    point is proved."""
    A, B, C = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B, C))
    balanced = balancing_transform(A, B, C, time)
    if balanced is not None:
        T, Ti = balanced
        value = hinf_norm(Ti @ A @ T, Ti @ B, C @ T, D, time)
        if value is not None and np.isfinite(value):
            return value, "SLICOT's norm of the balanced realisation"
    return hinf_norm(A, B, C, D, time), "SLICOT's norm"


def storage_candidates(A, B, C, D, g: float, time: str, norm: float, written=None):
    """(how, P) for the storages P of the bounded-real Riccati equation at the level g = γ² > ‖G‖∞²
    (``norm``): in the coordinates as written with ε = each of :data:`FRACTIONS` of the room
    (g − ‖G‖∞²) / ‖(sI − A)⁻¹B‖∞², then for the balanced realisation with ε I and ε W
    (module docstring), mapped back; only those for which a stabilising solution exists.  ``how``
    says which (for the notes); the candidates are not proved here.  ``written``: the realisation
    the proof reads, for :func:`precise_storage`."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    B = np.atleast_2d(np.asarray(B, dtype=float))
    C = np.atleast_2d(np.asarray(C, dtype=float))
    n = A.shape[0]
    if not g > norm ** 2:
        return
    realisations = [("as written", np.eye(n), np.eye(n))]
    balanced = balancing_transform(A, B, C, time)
    for how, T, Ti in realisations + ([("balanced", *balanced)] if balanced is not None else []):
        Ab, Bb, Cb = Ti @ A @ T, Ti @ B, C @ T
        size = np.linalg.norm(Ab, axis=0) + np.linalg.norm(Ab, axis=1)
        weightings = [("I", np.ones(n))]
        if how == "balanced" and size.min() > 0:
            weightings.append(("W", size / size.min()))
        gains = {}
        for name, w in weightings:
            gains[name] = gain = hinf_norm(Ab, Bb, np.diag(np.sqrt(w)), np.zeros((n, B.shape[1])), time)
            if gain is None:
                return
            for fraction in FRACTIONS:
                eps = fraction * (g - norm ** 2) / max(gain ** 2, 1e-300)
                Pb = bounded_real_storage(Ab, Bb, Cb, D, g, time, eps, None if name == "I" else w)
                if Pb is not None:
                    P = Ti.T @ Pb @ Ti
                    yield f"{how}, CᵀC + ε{name} with ε = {eps:.3g}", (P + P.T) / 2
        if how == "balanced" and time == "continuous" and n <= PRECISE_MAX_STATES:   # the last resort
            name, w = weightings[-1]
            eps = FRACTIONS[0] * (g - norm ** 2) / max(gains[name] ** 2, 1e-300)
            for digits in PRECISE_LADDER:
                P = precise_storage(A, B, C, D, g, eps, w, Ti, written, digits)
                if P is not None:
                    yield f"{how}, {digits}-digit Hamiltonian, CᵀC + ε{name} with ε = {eps:.3g}", P


PRECISE_DIGITS = 60
"""Decimal digits of the Hamiltonian route (:func:`precise_storage`)."""
PRECISE_LADDER = (PRECISE_DIGITS, 2 * PRECISE_DIGITS)
"""The digits of the Hamiltonian route's tries, the second only when the first storage fails its
proof: the loop of a 60-digit state-feedback gain with entries 1e10 (24 states) has C_clᵀC_cl ~ 1e20
beside a margin ε ~ 1e-9: its 60-digit storage violated the LMI, its 120-digit one was proved."""
PRECISE_MAX_STATES = 32
"""The largest state dimension given the Hamiltonian route: its 2n eigenpairs at 60 digits cost
~0.3 s at n = 16 and 8–10 s at n = 48, where no such storage was ever proved (H∞ state feedback
at 48 states: three tries, 27 s, none certified; the floating-point storage at the next level was)."""


def precise_storage(A, B, C, D, g: float, eps: float, weights, Ti, written=None, digits: int = PRECISE_DIGITS):
    """The stabilising storage of the continuous bounded-real Riccati equation (CᵀC + ε diag(w))
    computed at ``digits`` digits and kept exactly (a
    :class:`~lmidsl.numeric.proof.PreciseMatrix`), or None.

    The realisation is (Ti A Ti⁻¹, Ti B, C Ti⁻¹) with the data the decimals as written (what the
    proof reads: a float's binary value differs by ~1e-17, more than the margin) and Ti's floats
    taken exactly (Ti⁻¹ at that precision); with Ā = A + BR⁻¹Sᵀ, Q̄ = Q + SR⁻¹Sᵀ, R = gI − DᵀD, S = CᵀD, the stable invariant
    subspace [X₁; X₂] of the Hamiltonian [[Ā, BR⁻¹Bᵀ], [−Q̄, −Āᵀ]] (python-flint's ``acb_mat.eig``,
    arb's QR iteration in C: 0.3 s for n = 16 where mpmath took 35 s) gives
    Pb = X₂X₁⁻¹ (Zhou, Doyle, Glover 1996, ch. 13), mapped back P = Tiᵀ Pb Ti and its midpoints
    taken as exact rationals.  ``written(balls)``, when given, returns the realisation (A, B, C, D)
    as the proof reads it, from ``balls(M, written)`` (a matrix's decimals as written, or with
    ``written=False`` its binary value): a closed loop A + B₂K whose storage is proved through
    W = K Y must be A + B₂K in exact arithmetic, not the rounded sum (on the H∞ state-feedback
    plants of 24 states the difference, ~1e-16 ‖B₂‖‖K‖, exceeded the margin: every such
    storage failed its proof).  For a stiff closed loop (eigenvalues 1e9 next to 1) the LMI's margin
    at the exact storage is ~1e-18 of entries ~1e9: double precision cannot hold P, its exact value
    can; the proof decides (:class:`~lmidsl.numeric.proof.PreciseMatrix` is what it reads).  Nothing
    here is rigorous: the enclosures are only used for their midpoints."""
    n, m = A.shape[0], B.shape[1]
    with ball_precision(int(digits * 3.33) + 8):
        Am, Bm, Cm, Dm = (_balls(A), _balls(B), _balls(C), _balls(D)) if written is None else written(_balls)
        Tm = _balls(Ti, written=False)
        try:
            Tinv = Tm.inv()
            Ab, Bb, Cb = Tm * Am * Tinv, Tm * Bm, Cm * Tinv
            Ri = (arb(g) * _identity(m) - Dm.transpose() * Dm).inv()
            W = arb_mat(n, n, [arb(eps) * arb(float(weights[i])) if i == j else 0 for i in range(n) for j in range(n)])
            Pb = _stabilising_solution(Ab, Bb, Cb.transpose() * Cb + W, Cb.transpose() * Dm, Ri)
            if Pb is None:
                return None
            Tc = acb_mat(Tm)
            exact = _exact_midpoints(Tc.transpose() * Pb * Tc)
        except (ZeroDivisionError, ValueError, ArithmeticError):
            return None
    if exact is None:
        return None
    exact = (exact + exact.T) / 2                  # symmetric exactly
    return PreciseMatrix.of(exact)


def _balls(M, written: bool = True) -> arb_mat:
    """A float matrix as balls at the current precision: the decimals as written (what the proofs
    read: a float's binary value differs by ~1e-17, more than a stiff margin), or with
    ``written=False`` its binary value exactly (a balancing transform, a gain)."""
    return arb_mat(object_array(M, decimal_ball if written else (lambda x: arb(float(x)))).tolist())


def _identity(m: int) -> arb_mat:
    return arb_mat(m, m, [1 if i == j else 0 for i in range(m) for j in range(m)])


def _stabilising_solution(A: arb_mat, B: arb_mat, Q: arb_mat, S: arb_mat, Ri: arb_mat):
    """The stabilising solution X (an ``acb_mat``) of AᵀX + XA + Q + (XB + S) Ri (BᵀX + Sᵀ) = 0
    at the current precision, or None: with Ā = A + B Ri Sᵀ, the stable invariant subspace
    [X₁; X₂] of the Hamiltonian [[Ā, B Ri Bᵀ], [−(Q + S Ri Sᵀ), −Āᵀ]] (python-flint's
    ``acb_mat.eig``, arb's QR iteration in C), X = X₂X₁⁻¹ (Zhou, Doyle, Glover 1996, ch. 13).
    Ri = (γ²I − DᵀD)⁻¹ is the bounded-real equation; Ri = −R⁻¹ with the full-information
    R = DᵀD − diag(γ²I, 0) the H∞ full-information one.  Midpoints only: nothing is claimed."""
    n = A.nrows()
    Abar = A + B * Ri * S.transpose()
    Qbar = Q + S * Ri * S.transpose()
    G = B * Ri * B.transpose()
    H = acb_mat(2 * n, 2 * n)
    for i in range(n):
        for j in range(n):
            H[i, j], H[i, n + j], H[n + i, j], H[n + i, n + j] = Abar[i, j], G[i, j], -Qbar[i, j], -Abar[j, i]
    E, V = H.eig(right=True, nonstop=True)
    stable = [k for k in range(2 * n) if E[k].real.mid() < 0]
    if len(stable) != n:
        return None
    X1, X2 = acb_mat(n, n), acb_mat(n, n)
    for c, k in enumerate(stable):
        for i in range(n):
            X1[i, c], X2[i, c] = V[i, k], V[n + i, k]
    return X2 * X1.inv()


def _exact_midpoints(M) -> np.ndarray | None:
    """The midpoints of the real parts of an ``acb_mat`` as exact rationals (an object array of
    ``fmpq``), or None when one is not finite (eig did not converge)."""
    try:
        out = np.array([[midpoint(M[i, j].real) for j in range(M.ncols())] for i in range(M.nrows())], dtype=object)
    except (ValueError, OverflowError):
        return None
    return out if np.all(np.isfinite([[float(x) for x in row] for row in out])) else None


def precise_full_information_gain(A, B1, B2, C1, D11, D12, gamma: float, eps: float, written=None):
    """(K, X): the state-feedback gain K of :func:`full_information_feedback` (continuous time,
    Q = C₁ᵀC₁ + εI) and the Riccati solution X ⪰ 0, computed at :data:`PRECISE_DIGITS` digits and
    kept exactly (object arrays of ``fmpq``, the balls' midpoints); None when there is no
    stabilising solution X ⪰ 0.  ``written(balls)``: the plant (A, B₁, B₂, C₁, D₁₁, D₁₂) as the
    proof reads it.

    X is the bounded-real storage of the loop closed by K at γ²: with u = Kx fixed, the
    Hamiltonian 2xᵀX(Ax + B₁w + B₂u) + |z|² − γ²|w|² is concave in w (γ²I ≻ D₁₁ᵀD₁₁) and its
    saddle point in (w, u) is (F_w x, Kx), so it is at most its value there, −ε|x|², less a
    negative-definite quadratic in w − F_w x: the closed loop's dissipation inequality holds
    strictly.  Near the optimal level the equation is ill-conditioned: SciPy's X has a relative
    error ~1e-5 and its gain's closed loop, summed in doubles, scatters ~1 % above the level (H∞
    state feedback, 24 states, one actuator: 75,593 … 80,196 for levels 75,383 … 75,700, the
    optimum ≥ 75,374.5 proved); at 60 digits, summed exactly, the loop's norm is below the level
    (75,389.998 at 75,390)."""
    m1 = np.atleast_2d(B1).shape[1]
    n = np.atleast_2d(A).shape[0]
    with ball_precision(int(PRECISE_DIGITS * 3.33) + 8):
        Am, B1m, B2m, C1m, D11m, D12m = (tuple(_balls(M) for M in (A, B1, B2, C1, D11, D12))
                                         if written is None else written(_balls))
        try:
            B = _side_by_side(B1m, B2m)
            D = _side_by_side(D11m, D12m)
            m = B.ncols()
            R = D.transpose() * D - arb(gamma) ** 2 * arb_mat(m, m, [1 if i == j < m1 else 0
                                                                  for i in range(m) for j in range(m)])
            Rinv = R.inv()
            X = _stabilising_solution(Am, B, C1m.transpose() * C1m + arb(eps) * _identity(n),
                                      C1m.transpose() * D, -Rinv)
            if X is None:
                return None
            F = -(acb_mat(Rinv) * (acb_mat(B).transpose() * X + acb_mat(D.transpose() * C1m)))
            Xq, Fq = _exact_midpoints(X), _exact_midpoints(F)
        except (ZeroDivisionError, ValueError, ArithmeticError):
            return None
    if Xq is None or Fq is None:
        return None
    Xq = (Xq + Xq.T) / 2
    eig = np.linalg.eigvalsh(np.array([[float(x) for x in row] for row in Xq]))
    if eig[0] < -1e-9 * max(abs(eig[-1]), 1.0):
        return None
    return Fq[m1:], Xq


def _side_by_side(L: arb_mat, R: arb_mat) -> arb_mat:
    return arb_mat([[L[i, j] for j in range(L.ncols())] + [R[i, j] for j in range(R.ncols())]
                    for i in range(L.nrows())])


BALANCING_REGULARISATION = 1e-12
"""ρ² relative to ‖B‖², ‖C‖²: the Gramians of (A, [B ρI]) and (Aᵀ, [Cᵀ ρI]) are positive
definite also for a non-minimal system, and differ from the plain ones by ~1e-12 relative."""


def balancing_transform(A, B, C, time: str):
    """(T, T⁻¹) of square-root balancing (module docstring), or None (A not stable, SLICOT
    unavailable or failing): Lc Lcᵀ, Lo Loᵀ the Gramians of (A, [B ρI]) and (Aᵀ, [Cᵀ ρI]) (SB03OD),
    Loᵀ Lc = U Σ Vᵀ, T = Lc V Σ^-½, T⁻¹ = Σ^-½ Uᵀ Loᵀ (then T⁻¹ A T has equal, diagonal Gramians)."""
    if not is_stable(A, time):
        return None
    n = A.shape[0]
    try:
        rho = np.sqrt(BALANCING_REGULARISATION)
        Lc = gramian_factor(A, np.hstack([B, rho * max(np.linalg.norm(B, 2), 1e-300) * np.eye(n)]), time)
        Lo = gramian_factor(A.T, np.hstack([C.T, rho * max(np.linalg.norm(C, 2), 1e-300) * np.eye(n)]), time)
        U, sigma, Vt = np.linalg.svd(Lo.T @ Lc)
    except (ImportError, ValueError, np.linalg.LinAlgError):
        return None
    if not (np.all(np.isfinite(sigma)) and sigma[-1] > 0):
        return None
    root = sigma ** -0.5
    return Lc @ Vt.T * root, (U * root).T @ Lo.T


def gramian_factor(A, B, time: str) -> np.ndarray:
    """L with L Lᵀ = X, the Gramian A X + X Aᵀ + B Bᵀ = 0 (discrete: A X Aᵀ − X + B Bᵀ = 0), A
    stable, by SLICOT SB03OD (Hammarling's method: the Cholesky factor directly, never X)."""
    from slycot import sb03od

    n = A.shape[0]
    R = np.linalg.qr(B.T, mode="r")              # BBᵀ = RᵀR, R with n columns
    R = np.vstack([R, np.zeros((n - R.shape[0], n))]) if R.shape[0] < n else R
    U, scale, _ = sb03od(n, n, A.T.copy(), np.zeros((n, n)), R, "C" if time == "continuous" else "D")
    return U.T / scale


def full_information_gain(A, B1, B2, C1, D11, D12, gamma: float, time: str, eps: float = 0.0):
    """The state-feedback gain K (the last rows of :func:`full_information_feedback`'s F), or
    None.  Nothing is claimed for K here: its closed loop is certified like any design."""
    F = full_information_feedback(A, B1, B2, C1, D11, D12, gamma, time, eps)
    return None if F is None else F[np.atleast_2d(np.asarray(B1)).shape[1]:, :]


def full_information_weights(B1, B2, D11, D12, gamma: float):
    """(B, D, R) = ([B1 B2], [D11 D12], DᵀD − diag(γ²I, 0)) of the full-information problem at γ."""
    m1 = B1.shape[1]
    B, D = np.hstack([B1, B2]), np.hstack([D11, D12])
    R = D.T @ D
    R[:m1, :m1] -= gamma ** 2 * np.eye(m1)
    return B, D, R


def full_information_feedback(A, B1, B2, C1, D11, D12, gamma: float, time: str, eps: float = 0.0):
    """F = [F_w; F_u] of the H∞ full-information Riccati equation at level γ, or None.

    With B = [B1 B2], D = [D11 D12] and R = DᵀD − diag(γ²I, 0), the stabilising solution X ⪰ 0 of

        continuous:  AᵀX + XA + Q − (XB + C1ᵀD) R⁻¹ (BᵀX + DᵀC1) = 0,
        discrete:    AᵀXA − X + Q − (AᵀXB + C1ᵀD)(R + BᵀXB)⁻¹(BᵀXA + DᵀC1) = 0,

    Q = C1ᵀC1 + εI, exists when γ exceeds the optimal state-feedback level (D12 of full column
    rank; Zhou, Doyle, Glover 1996, ch. 16 and 21), and F = −R⁻¹(BᵀX + DᵀC1) (discrete:
    −(R + BᵀXB)⁻¹(BᵀXA + DᵀC1)) gives the worst disturbance (first rows) and the gain K (last
    rows); None unless the stabilising solution exists and is ⪰ 0."""
    from scipy.linalg import solve_continuous_are, solve_discrete_are

    A, B1, B2, C1, D11, D12 = (np.atleast_2d(np.asarray(m, dtype=float)) for m in (A, B1, B2, C1, D11, D12))
    n = A.shape[0]
    B, D, R = full_information_weights(B1, B2, D11, D12, gamma)
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
    return F


__all__ = ["BALANCING_REGULARISATION", "FRACTIONS", "PRECISE_DIGITS", "PRECISE_LADDER", "precise_full_information_gain", "precise_storage", "realisation_norm", "balancing_transform", "bounded_real_storage",
           "full_information_feedback", "full_information_gain", "full_information_weights", "gramian_factor", "hinf_norm", "storage_candidates"]
