"""A proved lower bound on an H∞ state-feedback optimum where stabilisation sets it: a dual point of
the state-feedback LMI built from the Hamiltonian's stable eigenvectors (continuous time) or from
interpolation points (discrete time).

The LMI (:meth:`~lmidsl.theorem.theorem.Theorem.state_feedback_form`, level γ on both diagonal
blocks, with Y ⪰ 0 among the theorem's LMIs) is N(Y, W, γ) ⪯ 0 with

    N = [[He(AY + B2W), B1, (C1Y + D12W)ᵀ], [B1ᵀ, −γI, D11ᵀ], [C1Y + D12W, D11, −γI]].

With B = [B1 B2], D = [D11 D12] and R = DᵀD − diag(γ₀²I, 0) invertible (the full-information
problem's; Zhou, Doyle, Glover 1996, ch. 16), Â = A − BR⁻¹DᵀC1 and Q̂ = C1ᵀC1 − C1ᵀDR⁻¹DᵀC1, take
vectors [x1ᵢ; x2ᵢ] and numbers λᵢ with Re λᵢ < 0 that satisfy, exactly, the second block row of
the Hamiltonian [[Â, −BR⁻¹Bᵀ], [−Q̂, −Âᵀ]]:

    −Q̂ x1ᵢ − Âᵀ x2ᵢ = λᵢ x2ᵢ,

and set pᵢ = x2ᵢ, rᵢ = C1x1ᵢ + D[wᵢ; uᵢ] with [wᵢ; uᵢ] = −R⁻¹(Bᵀx2ᵢ + DᵀC1x1ᵢ), and
hᵢ = B1ᵀpᵢ + D11ᵀrᵢ.  Then

* B2ᵀpᵢ + D12ᵀrᵢ = 0: R's second block row is [D12ᵀD11, D12ᵀD12] (no γ₀ in it), so
  D12ᵀD[wᵢ; uᵢ] = −(B2ᵀx2ᵢ + D12ᵀC1x1ᵢ); the W terms vanish;
* Aᵀpᵢ + C1ᵀrᵢ = Âᵀx2ᵢ + Q̂x1ᵢ = −λᵢpᵢ: with P = [pᵢ], Λ = diag(λᵢ) and any Hermitian G ⪰ 0, the
  Y terms of Re tr(G V*NV) are −tr(P*YP (ΛG + GΛ*)), which is ≥ 0 for Y ⪰ 0 when
  ΛG + GΛ* ⪯ 0.  G = [−cᵢc̄ⱼ/(λᵢ + λ̄ⱼ)] = ∫ e^{Λt}cc*e^{Λ*t}dt is such a G, for any vector c;
* with V = [P; κH; R] (H = [hᵢ], R = [rᵢ]) the dual point Z = Re(VGV*) ⪰ 0 gives, for every
  feasible (Y, W, γ), 0 ≥ Re tr(G V*NV) ≥ 2κa − γ(κ²a + b), a = tr(G H*H), b = tr(G R*R);
  κ = √(b/a) makes it 2√(ab) − 2γb, so

      γ ≥ √(a / b).

Nothing else is assumed: neither the Riccati equation's solution nor a theorem about it.  The
λᵢ and vectors are python-flint's rigorous enclosures (``acb_mat.eig``: every eigenvalue simple
and isolated) of the exact eigenpairs of that Hamiltonian built from the data as written, at a
level γ₀ (a double, exact); only the stable ones (Re λ < 0 proved) are used.  a and b are
evaluated in balls from those enclosures, so the ball of a/b holds the value of an exact dual
point.  γ₀ and c only make the bound tight: γ₀ a little below the least level at which the stabilising Riccati solution X = X₂X₁⁻¹ is ⪰ 0 (bisection in floating point),
where S = X₁*X₂ (Hermitian: the stable subspace is Lagrangian) has a negative eigenvalue; c its
eigenvector (with D11 = 0 the Hamiltonian's identities give a − γ₀²b = −γ₀² c*Sc > 0: the bound
exceeds γ₀).

**The interpolation certificate** (discrete time; :func:`interpolation_bound`).  The same dual
needs no eigenpairs: for any points sᵢ with |sᵢ| > 1 and any rᵢ in the kernel of P12(sᵢ)ᵀ, set
p2ᵢ = (sᵢI − Aᵀ)⁻¹C1ᵀrᵢ and p1ᵢ = sᵢp2ᵢ, so that Aᵀp2ᵢ + C1ᵀrᵢ = sᵢp2ᵢ and
B2ᵀp2ᵢ + D12ᵀrᵢ = P12(sᵢ)ᵀrᵢ = 0.  With S = diag(sᵢ) and F = P2*YP2 ⪰ 0 the Y terms of the
discrete LMI are tr(F(SGS* − G)), and the Pick matrix G = [1/(sᵢs̄ⱼ − 1)] is ⪰ 0 and makes
SGS* − G the all-ones matrix ⪰ 0; then γ ≥ √(tr(G H*H)/tr(G R*R)) with hᵢ = P11(sᵢ)ᵀrᵢ.  The
points are doubles taken exactly and rᵢ the exact ball projection of a floating-point vector onto
the kernel, so every identity holds exactly.  Points that make it tight: the mirror images 1/μ of
the eigenvalues of the full-information closed loop A + BF just above its Riccati threshold, with
the rᵢ of the best generalised eigenvector of the two Pick forms: it then proves the
full-information level, which in discrete time can be below a static state feedback's optimum.
In continuous time the points −μ, Re sᵢ > 0 and G = [1/(sᵢ + s̄ⱼ)] give the same certificate as
the eigenvectors above (to 1e-11 in floating point on bench_scale's plants) and need no R_γ⁻¹:
:mod:`lmidsl.certify.coupling_bound` uses them for singular output-feedback problems.
"""
from __future__ import annotations

import numpy as np
from flint import acb, acb_mat, arb

from ..numeric.proof import ball_precision, round_down
from ..numeric.riccati import full_information_feedback, full_information_weights

#: working precision (bits) of the eigen-enclosures (the stable subspace is ill-conditioned close
#: to the optimum, where X grows without bound)
PRECISION = 192
#: the largest state dimension tried (the enclosure of the 2n eigenpairs costs O(n³) ball operations
#: at PRECISION bits: about 1 s at n = 24, 8 s at n = 48, on the bound's worker thread)
MAX_STATES = 64
#: the first level tried, relative distance below the floating-point threshold
JUST_BELOW = 1e-6


def proved_root(ball) -> float | None:
    """A double ≤ √x for every x in ``ball`` (a real ball of γ²), or None unless the ball is
    finite with a positive lower end."""
    if ball is None or not ball.is_finite() or not ball.lower() > 0:
        return None
    return max(round_down(float(arb(ball.lower()).sqrt().lower())), 0.0)


def _hamiltonian(floats, gamma: float) -> np.ndarray:
    """The Hamiltonian at γ in floating point (module docstring; np.linalg.LinAlgError when R_γ
    is singular)."""
    A, B1, B2, C1, D11, D12 = floats
    B, D, R = full_information_weights(B1, B2, D11, D12, gamma)
    Ah = A - B @ np.linalg.solve(R, D.T @ C1)
    Qh = C1.T @ C1 - C1.T @ D @ np.linalg.solve(R, D.T @ C1)
    return np.block([[Ah, -B @ np.linalg.solve(R, B.T)], [-Qh, -Ah.T]])


def _r_columns(floats, gamma: float, X1, X2) -> np.ndarray:
    """R = C1X₁ − D R_γ⁻¹(BᵀX₂ + DᵀC1X₁) in floating point."""
    A, B1, B2, C1, D11, D12 = floats
    B, D, R = full_information_weights(B1, B2, D11, D12, gamma)
    return C1 @ X1 - D @ np.linalg.solve(R, B.T @ X2 + D.T @ C1 @ X1)


def _lagrangian(floats, gamma: float):
    """S = X₁ᵀX₂ of the Hamiltonian's stable invariant subspace [X₁; X₂] at γ (ordered real Schur
    form, orthonormal basis) in floating point, or None when fewer than n eigenvalues are in the
    open left half-plane.  X = X₂X₁⁻¹ ⪰ 0 exactly when S ⪰ 0 and X₁ is invertible; S needs no
    inverse, so it stays finite where X grows without bound (close to the optimum)."""
    from scipy.linalg import schur
    n = floats[0].shape[0]
    try:
        _, U, k = schur(_hamiltonian(floats, gamma), output="real", sort="lhp")
    except (np.linalg.LinAlgError, ValueError):
        return None
    if k != n:
        return None
    S = U[:n, :n].T @ U[n:, :n]
    return (S + S.T) / 2


def _feasible(floats, gamma: float) -> bool:
    """Whether the stabilising solution at γ is ⪰ 0, as far as floating point tells (S ⪰ 0)."""
    S = _lagrangian(floats, gamma)
    if S is None or not np.all(np.isfinite(S)):
        return False
    eig = np.linalg.eigvalsh(S)
    return eig[0] >= -1e-12 * max(abs(eig[-1]), 1e-300)


def float_bound(floats, gamma0: float) -> float:
    """The bound √(a/b) of the certificate at γ₀ in floating point (0 where there is none): the
    real Schur form's stable block T₁₁ in place of Λ and G from T₁₁G + GT₁₁ᵀ = −ccᵀ (the same
    certificate in another basis), c the most negative direction of S.  Only to choose γ₀."""
    from scipy.linalg import schur, solve_continuous_lyapunov
    B1, D11 = floats[1], floats[4]
    n = floats[0].shape[0]
    try:
        with np.errstate(all="ignore"):
            T, U, k = schur(_hamiltonian(floats, gamma0), output="real", sort="lhp")
            if k != n:
                return 0.0
            X1, X2, T11 = U[:n, :n], U[n:, :n], T[:n, :n]
            S = X1.T @ X2
            c = np.linalg.eigh((S + S.T) / 2)[1][:, :1]
            G = solve_continuous_lyapunov(T11, -c @ c.T)
            R = _r_columns(floats, gamma0, X1, X2)
            Hh = B1.T @ X2 + D11.T @ R
            a, b = np.trace(Hh @ G @ Hh.T), np.trace(R @ G @ R.T)
    except (np.linalg.LinAlgError, ValueError):
        return 0.0
    return float(np.sqrt(a / b)) if b > 0 and a >= 0 and np.isfinite(a / b) else 0.0


def best_level(floats, top: float) -> list:
    """Levels γ₀ to certify at, best first: the largest floating-point bounds (:func:`float_bound`)
    on a grid of ±10 % around ``top``, the best refined by golden-section search."""
    from scipy.optimize import minimize_scalar
    grid = top * np.exp(np.linspace(-0.1, 0.1, 41))
    values = [float_bound(floats, g) for g in grid]
    k = int(np.argmax(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    found = minimize_scalar(lambda g: -float_bound(floats, g), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-12 * hi, "maxiter": 60})
    candidates = [(-found.fun, float(found.x))] + sorted(zip(values, grid), reverse=True)[:2]
    return [g for _, g in sorted(candidates, reverse=True)]


def _levels(floats, top: float):
    """γ₀ to try: just below the threshold first (where the stabilising solution is not ⪰ 0,
    a − γ₀²b = −γ₀² c*Sc > 0 makes the bound exceed γ₀: within 1e-6 of the threshold in one
    eigen-enclosure when stabilisation sets the optimum), then :func:`best_level`'s."""
    yield top * (1 - JUST_BELOW)
    yield from best_level(floats, top)


def threshold(floats, start: float) -> float | None:
    """The least γ at which the stabilising solution is ⪰ 0 (:func:`_feasible`), from ``start``
    (a level below it, e.g. the frequency bound), or None."""
    return least_level(lambda g: _feasible(floats, g), start)


def least_level(feasible, start: float) -> float | None:
    """The least γ with ``feasible(γ)`` (a property that holds above some level) by doubling from
    ``start`` and bisection in floating point, or None when none is found below 1e12."""
    lo, hi = max(start, 1e-12), max(2 * start, 1.0)
    while not feasible(hi):
        lo, hi = hi, 2 * hi
        if hi > 1e12:
            return None
    if feasible(lo):
        return lo
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
        if hi - lo <= 1e-15 * hi:
            break
    return hi


def stable_eigendata(balls, gamma0: float):
    """(λ, X₁, X₂, R, H) in balls for the stable eigenpairs of the Hamiltonian at γ₀ built from
    ``balls`` (the data as written): λ the stable eigenvalues (Re λ < 0 proved), X₁ and X₂ the
    upper and lower halves of their eigenvectors, R = C1X₁ − D R_γ⁻¹(BᵀX₂ + DᵀC1X₁) and H = B1ᵀX₂ + D11ᵀR (module
    docstring); None when an eigenpair is not isolated, R_γ not provably invertible or no stable
    eigenvalue is proved."""
    A, B1, B2, C1, D11, D12 = (acb_mat([[acb(z) for z in row] for row in M.tolist()]) for M in balls)
    n, m1 = A.nrows(), B1.ncols()
    B = acb_mat([[B1[i, j] for j in range(m1)] + [B2[i, j] for j in range(B2.ncols())] for i in range(n)])
    D = acb_mat([[D11[i, j] for j in range(m1)] + [D12[i, j] for j in range(D12.ncols())]
                 for i in range(C1.nrows())])
    Rg = D.transpose() * D
    g2 = arb(gamma0) * arb(gamma0)
    for i in range(m1):
        Rg[i, i] -= g2
    try:
        Ri = Rg.inv()
    except ZeroDivisionError:
        return None
    Ah = A - B * Ri * D.transpose() * C1
    Qh = C1.transpose() * C1 - C1.transpose() * D * Ri * D.transpose() * C1
    G12 = -(B * Ri * B.transpose())
    Aht = Ah.transpose()
    H = acb_mat(2 * n, 2 * n)
    for i in range(n):
        for j in range(n):
            H[i, j], H[i, n + j], H[n + i, j], H[n + i, n + j] = Ah[i, j], G12[i, j], -Qh[i, j], -Aht[i, j]
    try:
        E, V = H.eig(right=True)         # rigorous: raises unless every eigenpair is isolated
    except (ValueError, ZeroDivisionError, ArithmeticError):
        return None
    stable = [k for k in range(2 * n) if E[k].real < 0]
    if not stable:
        return None
    X1 = acb_mat([[V[i, k] for k in stable] for i in range(n)])
    X2 = acb_mat([[V[n + i, k] for k in stable] for i in range(n)])
    R = C1 * X1 - D * (Ri * (B.transpose() * X2 + D.transpose() * C1 * X1))
    return [E[k] for k in stable], X1, X2, R, B1.transpose() * X2 + D11.transpose() * R


def midpoints(M: acb_mat) -> np.ndarray:
    """The midpoints of a complex ball matrix, as a numpy array."""
    return np.array([[complex(float(M[i, k].real.mid()), float(M[i, k].imag.mid())) for k in range(M.ncols())]
                     for i in range(M.nrows())])


def exact_entries(v) -> list:
    """The complex balls of a vector's doubles, taken exactly (zero radius)."""
    return [acb(float(z.real), float(z.imag)) for z in v]


def exact_column(v) -> acb_mat:
    """A vector of doubles as an exact ball column."""
    return acb_mat([[z] for z in exact_entries(v)])


def gramian(lam: list, c: np.ndarray) -> acb_mat:
    """G = [−cᵢc̄ⱼ/(λᵢ + λ̄ⱼ)] = ∫ e^{Λt}cc*e^{Λ*t}dt ⪰ 0 in balls, c's doubles taken exactly: then
    ΛG + GΛ* = −cc*."""
    cb = exact_entries(c)
    return acb_mat([[-cb[i] * cb[j].conjugate() / (lam[i] + lam[j].conjugate()) for j in range(len(lam))]
                    for i in range(len(lam))])


def _ball_bound(balls, gamma0: float):
    """A ball containing a/b (module docstring) for the stable eigenpairs of the Hamiltonian at
    γ₀ built from ``balls`` (the data as written), or None (an eigenpair not isolated, D12ᵀD12
    not provably invertible, no stable eigenvalue proved, b not provably positive)."""
    found = stable_eigendata(balls, gamma0)
    if found is None:
        return None
    lam, X1, X2, R, Hh = found
    # c: the most negative direction of S = X₁*X₂ from the midpoints (any c gives a valid bound;
    # a − γ₀²b = −γ₀² c*Sc, so this one makes the bound exceed γ₀ wherever S is not ⪰ 0)
    S = midpoints(X1).conj().T @ midpoints(X2)
    if not np.all(np.isfinite(S)):
        return None
    _, vecs = np.linalg.eigh((S + S.conj().T) / 2)
    Gm = gramian(lam, vecs[:, 0])
    a = weighted_square(Hh, Gm)
    b = weighted_square(R, Gm)
    if not b > 0:
        return None
    return a / b


def weighted_square(M: acb_mat, G: acb_mat):
    """Re tr(G M*M) = Re Σ (M G)ᵣᵢ conj(Mᵣᵢ), a real ball."""
    MG = M * G
    total = acb(0)
    for r in range(M.nrows()):
        for i in range(M.ncols()):
            total += MG[r, i] * M[r, i].conjugate()
    return total.real


def stabilisation_bound(floats: list, balls: list, start: float) -> tuple[float | None, str]:
    """(proved lower bound on γ, how) of the continuous-time state-feedback LMI (module
    docstring), trying levels γ₀ just below the floating-point threshold (:func:`threshold`, from
    ``start``); (None, why) when none gave a ball bound."""
    n = floats[0].shape[0]
    if n > MAX_STATES:
        return None, f"more than {MAX_STATES} states (the eigen-enclosures cost O(n³) ball operations)"
    D12 = floats[5]
    if D12.shape[1] == 0 or np.linalg.matrix_rank(D12) < D12.shape[1]:
        return None, "D12 has no full column rank"
    with np.errstate(all="ignore"):
        top = threshold(floats, start)
    if top is None:
        return None, "no level with a stabilising Riccati solution ⪰ 0 was found"
    best = None
    with ball_precision(PRECISION):
        for gamma0 in _levels(floats, top):       # done once one reaches its γ₀
            lower = proved_root(_ball_bound(balls, gamma0))
            if lower is None:
                continue
            if best is None or lower > best[0]:
                best = (lower, f"the Hamiltonian's stable eigenvectors at γ₀ = {gamma0:.10g} (a dual point: "
                               f"γ ≥ √(tr(G H*H)/tr(G R*R)))")
            if lower >= gamma0:
                break
    return best or (None, "no level near the Riccati threshold gave a ball bound")


def ball_transfer(balls: list, s):
    """(P11(s), P12(s)) in complex balls at the exact point ``s`` (an acb; None: s = ∞, the
    feedthroughs), or None when sI − A is not provably invertible."""
    Ab, B1b, B2b, C1b, D11b, D12b = balls
    n, m1, m2, p1 = Ab.shape[0], B1b.shape[1], B2b.shape[1], C1b.shape[0]

    def mat(rows):
        return acb_mat([[acb(z) for z in row] for row in rows])

    if s is None or n == 0:
        return mat(D11b.tolist()), mat(D12b.tolist())
    M = acb_mat([[(s if i == j else acb(0)) - Ab[i, j] for j in range(n)] for i in range(n)])
    try:
        X = M.solve(mat(np.hstack([B1b, B2b]).tolist()))
    except ZeroDivisionError:
        return None
    P = mat(C1b.tolist()) * X
    return (acb_mat([[P[i, j] + D11b[i, j] for j in range(m1)] for i in range(p1)]),
            acb_mat([[P[i, m1 + j] + D12b[i, j] for j in range(m2)] for i in range(p1)]))


def kernel_projection(P12: acb_mat, u: np.ndarray):
    """r = u − P̄12 (P12ᵀP̄12)⁻¹ P12ᵀ u in balls: the exact projection of the floating-point
    vector ``u`` (its doubles taken exactly) onto the kernel of P12ᵀ (P12ᵀ r = 0 exactly for the
    exact P12), or None when P12ᵀP̄12 is not provably invertible."""
    p1, m2 = P12.nrows(), P12.ncols()
    P12t = P12.transpose()
    P12c = acb_mat([[P12[i, j].conjugate() for j in range(m2)] for i in range(p1)])
    ub = exact_column(u)
    try:
        return ub - P12c * (P12t * P12c).solve(P12t * ub)
    except ZeroDivisionError:
        return None


def projected_response(balls: list, s, u: np.ndarray):
    """(r, P11(s)ᵀr) in balls: r the exact projection of ``u`` onto the kernel of P12(s)ᵀ
    (:func:`ball_transfer`, :func:`kernel_projection`), or None."""
    found = ball_transfer(balls, s)
    if found is None:
        return None
    P11, P12 = found
    r = kernel_projection(P12, u)
    return None if r is None else (r, P11.transpose() * r)


def transfer(floats, s: complex):
    """(P11(s), P12(s)) in floating point."""
    A, B1, B2, C1, D11, D12 = floats
    X = np.linalg.solve(s * np.eye(A.shape[0]) - A, np.hstack([B1, B2]))
    P = C1 @ X
    return P[:, :B1.shape[1]] + D11, P[:, B1.shape[1]:] + D12


def _pick(s_i, s_j, time: str = "discrete"):
    """The Pick kernel: 1/(sᵢs̄ⱼ − 1) for |s| > 1 (discrete time), 1/(sᵢ + s̄ⱼ) for Re s > 0
    (continuous time: ∫ e^{−sᵢt} e^{−s̄ⱼt} dt); either makes [kᵢⱼ] ⪰ 0."""
    return 1 / (s_i * s_j.conjugate() - 1) if time == "discrete" else 1 / (s_i + s_j.conjugate())


def _outside(s, time: str) -> bool:
    """Whether the point (a ball) is provably outside the unit disc (discrete) or in the open
    right half-plane (continuous): the domain of :func:`_pick`."""
    return bool(abs(s) > 1) if time == "discrete" else bool(s.real > 0)


def interpolation_forms(floats, points: list, time: str = "discrete"):
    """(T, B, P, bases) in floating point for the interpolation certificate at the given points
    (module docstring): with uᵢ = Nᵢzᵢ in the kernel of P12(sᵢ)ᵀ (Nᵢ = ``bases[i]``, z stacked),
    tr(G H*H) = z*Tz, tr(G R*R) = z*Bz and Σᵢ p2ᵢ = Pz, p2ᵢ = (sᵢI − Aᵀ)⁻¹C1ᵀuᵢ; None when a kernel
    is {0} or sᵢI − A is singular."""
    from scipy.linalg import null_space
    A, C1 = floats[0], floats[3]
    bases, images, storage = [], [], []
    try:
        for s in points:
            P11, P12 = transfer(floats, s)
            N = null_space(P12.T)
            if N.size == 0:
                return None
            bases.append(N)
            images.append(P11.T @ N)
            storage.append(np.linalg.solve(s * np.eye(A.shape[0]) - A.T, C1.T @ N))
    except np.linalg.LinAlgError:
        return None
    offsets = np.cumsum([0] + [N.shape[1] for N in bases])
    top = np.zeros((offsets[-1], offsets[-1]), dtype=complex)
    bottom = np.zeros_like(top)
    for i, si in enumerate(points):
        for j, sj in enumerate(points):
            k = _pick(si, sj, time)
            rows, cols = slice(offsets[j], offsets[j + 1]), slice(offsets[i], offsets[i + 1])
            top[rows, cols] = k * (images[j].conj().T @ images[i])
            bottom[rows, cols] = k * (bases[j].conj().T @ bases[i])
    return top, bottom, np.hstack(storage), bases


def split_directions(bases: list, z: np.ndarray) -> list:
    """The kernel vectors uᵢ = Nᵢzᵢ of a stacked coefficient vector z."""
    offsets = np.cumsum([0] + [N.shape[1] for N in bases])
    return [N @ z[offsets[i]:offsets[i + 1]] for i, N in enumerate(bases)]


def _interpolation_directions(floats, points: list, time: str = "discrete"):
    """The vectors uᵢ ∈ ker P12(sᵢ)ᵀ that maximise the certificate's ratio at the given points, in
    floating point: the top generalised eigenvector of the Hermitian forms tr(G H*H) and
    tr(G R*R) over the kernels (G the Pick kernel, H = [P11(sᵢ)ᵀuᵢ]); None when there is none."""
    from scipy.linalg import eigh
    found = interpolation_forms(floats, points, time)
    if found is None:
        return None
    top, bottom, _, bases = found
    try:
        _, vectors = eigh(top, bottom)
    except (np.linalg.LinAlgError, ValueError):
        return None
    return split_directions(bases, vectors[:, -1])


def interpolation_parts(balls, points: list, directions: list, storage: bool = False, time: str = "discrete"):
    """Balls of (a, b, x) = (tr(G H*H), tr(G R*R), Σᵢ p2ᵢ) of the interpolation certificate (module
    docstring) at the exact points (their doubles) with the exact kernel projections rᵢ of
    ``directions`` and p2ᵢ = (sᵢI − Aᵀ)⁻¹C1ᵀrᵢ (x only with ``storage``; else None), or None (a
    point not outside the unit circle, a matrix not provably invertible)."""
    n = balls[0].shape[0]
    if storage:
        At = acb_mat([[acb(z) for z in row] for row in balls[0].T.tolist()])
        C1t = acb_mat([[acb(z) for z in row] for row in balls[3].T.tolist()])
    exact, rs, hs = [], [], []
    x = acb_mat(n, 1)
    for s, u in zip(points, directions):
        sb = acb(float(s.real), float(s.imag))
        if not _outside(sb, time):
            return None
        found = projected_response(balls, sb, u)
        if found is None:
            return None
        exact.append(sb)
        rs.append(found[0])
        hs.append(found[1])
        if storage:
            M = acb_mat([[(sb if i == j else acb(0)) - At[i, j] for j in range(n)] for i in range(n)])
            try:
                x += M.solve(C1t * found[0])
            except ZeroDivisionError:
                return None
    a, b = acb(0), acb(0)
    for i, si in enumerate(exact):
        for j, sj in enumerate(exact):
            k = _pick(si, sj, time)
            a += k * inner(hs[j], hs[i])
            b += k * inner(rs[j], rs[i])
    return a.real, b.real, (x if storage else None)


def _ball_interpolation(balls, points: list, directions: list, time: str = "discrete"):
    """A ball containing a/b of the interpolation certificate (module docstring) at the exact
    points (their doubles) with the exact kernel projections of ``directions``, or None."""
    found = interpolation_parts(balls, points, directions, time=time)
    if found is None or not found[1] > 0:
        return None
    return found[0] / found[1]


def inner(x: acb_mat, y: acb_mat):
    """x*y of two ball column vectors."""
    return sum((x[i, 0].conjugate() * y[i, 0] for i in range(x.nrows())), acb(0))


#: how far above the floating-point Riccati threshold the closed loop that gives the points is taken
LOOP_STEPS = (1e-4, 1e-2, 1e-6)


def full_column_rank(M: np.ndarray) -> bool:
    """Whether M (floating point) has full column rank (and at least one column)."""
    return M.shape[1] > 0 and np.linalg.matrix_rank(M) == M.shape[1]


#: ε of the regularised D12 = [D12; εI] (relative to ‖[C1 D12]‖) that places the points of a
#: singular problem's interpolation certificate, tried in turn
REGULARISATION = (1e-3, 1e-5, 1e-1)


def regularised(floats: list, eps: float) -> list:
    """(A, B1, B2, [C1; 0], [D11; 0], [D12; εI]) (unchanged for ε = 0): a regular problem whose
    Riccati equation places the points of a singular problem's certificate, which stays the
    plant's own."""
    if eps == 0.0:
        return floats
    A, B1, B2, C1, D11, D12 = floats
    m2 = B2.shape[1]
    scale = eps * max(1.0, float(np.linalg.norm(np.hstack([C1, D12]), 2)))
    return [A, B1, B2, np.vstack([C1, np.zeros((m2, A.shape[0]))]), np.vstack([D11, np.zeros((m2, B1.shape[1]))]),
            np.vstack([D12, scale * np.eye(m2)])]


def loop_points(floats: list, F: np.ndarray, time: str) -> list:
    """The points of an interpolation certificate from the full-information closed loop A + BF:
    the mirror images 1/μ of its eigenvalues μ (discrete time) or −μ (continuous time)."""
    mu = np.linalg.eigvals(floats[0] + np.hstack([floats[1], floats[2]]) @ F)
    return [1 / m for m in mu if abs(m) > 1e-12] if time == "discrete" else [-m for m in mu if m.real < 0]


def interpolation_bound(floats: list, balls: list, start: float, time: str = "discrete") -> tuple[float | None, str]:
    """(proved lower bound on γ, how) of the state-feedback LMI from points sᵢ (module docstring,
    the interpolation certificate): the mirror images of the eigenvalues of the full-information
    closed loop A + BF just above the Riccati threshold (of the plant with D12 regularised,
    :func:`regularised`, where D12 has no full column rank), with the best kernel directions;
    (None, why) when none gave a ball bound."""
    n = floats[0].shape[0]
    if n > MAX_STATES:
        return None, f"more than {MAX_STATES} states"
    best = None
    for eps in (0.0,) if full_column_rank(floats[5]) else REGULARISATION:
        problem = regularised(floats, eps)

        def feedback(g):
            with np.errstate(all="ignore"):
                return full_information_feedback(*problem, g, time)

        hi = least_level(lambda g: feedback(g) is not None, start)
        if hi is None:
            continue
        with ball_precision(PRECISION):
            for step in LOOP_STEPS:
                F = feedback(hi * (1 + step))
                if F is None:
                    continue
                points = loop_points(floats, F, time)
                directions = _interpolation_directions(floats, points, time) if points else None
                if directions is None:
                    continue
                lower = proved_root(_ball_interpolation(balls, points, directions, time))
                if lower is None:
                    continue
                if best is None or lower > best[0]:
                    best = (lower, f"an interpolation certificate at the mirror images of the closed loop's "
                                   f"eigenvalues at γ = {hi * (1 + step):.10g}"
                                   f"{f' (D12 regularised by ε = {eps:g})' if eps else ''} "
                                   f"(γ ≥ √(tr(G H*H)/tr(G R*R)), G the Pick kernel)")
        if best is not None:
            break
    return best or (None, "no closed loop near the Riccati threshold gave a ball bound")


__all__ = ["ball_transfer", "exact_column", "exact_entries", "full_column_rank", "gramian", "inner", "interpolation_bound", "interpolation_forms",
           "interpolation_parts", "kernel_projection", "loop_points", "midpoints", "projected_response", "proved_root",
           "regularised", "split_directions", "stable_eigendata", "weighted_square",
           "stabilisation_bound", "transfer",
           "threshold"]
