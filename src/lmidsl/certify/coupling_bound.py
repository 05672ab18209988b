"""A proved lower bound on an H∞ output-feedback optimum where the coupling of the two Riccati
equations sets it (ρ(X∞Y∞) = γ², Doyle, Glover, Khargonekar, Francis 1989).

The full-order LMI in the linearising variables (:mod:`lmidsl.certify.frequency_bound`, "Output
feedback") contains the full-information rows (X, w, z) and the full-control rows (Y, z, w), and
[[X, I], [I, Y]] ⪰ 0 is among the theorem's LMIs.  Take the Hamiltonian certificate of each
(:mod:`lmidsl.certify.hamiltonian_bound`): for the full-information problem of (A, B1, B2, C1,
D11, D12) at a level γ₀, the stable eigenvalues λᵢ with eigenvectors [x1ᵢ; x2ᵢ], P = [x2ᵢ], the
columns R and H, and for any vector c the Gramian G = [−cᵢc̄ⱼ/(λᵢ + λ̄ⱼ)] ⪰ 0; the dual point
Z₁ = Re(V G V*), V = [P; κH; R] in the rows (X, w, z), gives

    Re tr(Z₁ N) = x*Xx + 2κa₁ − γ(κ²a₁ + b₁),   x = Pc,  a₁ = tr(G H*H),  b₁ = tr(G R*R),

because ΛG + GΛ* = −cc* (the X terms are −tr(P*XP(ΛG + GΛ*))).  The same for the full-control
problem of the dual plant (Aᵀ, C1ᵀ, C2ᵀ, B1ᵀ, D11ᵀ, D21ᵀ), its vector d and Gramian in the rows
(Y, z, w): y*Yy + 2μa₂ − γ(μ²a₂ + b₂), y = P̃d.  Z₁ has a zero Y row and Z₂ a zero X row, so
Z = Z₁ + Z₂ ⪰ 0 pairs Â (the (Y, X) block) with zero, and Ĉ, B̂ and D̂ vanish by the identities of
each part.  On [[X, I], [I, Y]] ⪰ 0 the dual point Re(ww*), w = [x; −e^{iφ}y] with e^{iφ}x*y ≥ 0,
gives x*Xx + y*Yy ≥ 2|x*y|.  Every feasible (X, Y, Â, B̂, Ĉ, D̂, γ) therefore has, with κ = μ = 1/γ
and c, d scaled by t₁, t₂ ≥ 0,

    0 ≥ 2t₁t₂ξ + t₁²(a₁/γ − γb₁) + t₂²(a₂/γ − γb₂),   ξ = |x*y|,

so both brackets are ≤ 0 and (γb₁ − a₁/γ)(γb₂ − a₂/γ) ≥ ξ²: with g = γ², (gb₁ − a₁)(gb₂ − a₂) ≥ gξ²
on g ≥ max(a₁/b₁, a₂/b₂), i.e. g at least the larger root of b₁b₂g² − (a₁b₂ + a₂b₁ + ξ²)g + a₁a₂:

    γ ≥ √g₊.

With ξ = 0 this is the larger of the two Hamiltonian bounds; the coupling term is what lifts it to
the output-feedback optimum.  Nothing else is assumed: no Riccati solution, no theorem about the
optimum.  The eigenpairs are python-flint's rigorous enclosures (``acb_mat.eig``, at γ₀ a double),
c and d doubles taken exactly, and a₁, b₁, a₂, b₂, ξ and g₊ are evaluated in balls, so the bound
holds for an exact dual point.

**Discrete time.**  The form's rows (X, Y) are −[[X, I], [I, Y]] itself, so the dual point
Re(ww*) sits on those rows of the same LMI, and the two parts are the interpolation certificates
of :mod:`lmidsl.certify.hamiltonian_bound` (points sᵢ outside the unit circle, kernel vectors,
the Pick kernel G): the full-information one in the rows (X, w, X', z) has X terms x*Xx with
x = Σᵢ p2ᵢ, p2ᵢ = (sᵢI − Aᵀ)⁻¹C1ᵀrᵢ (tr(F(SGS* − G)) with SGS* − G the all-ones matrix), the
full-control one in the rows (Y, w, Y', z) (:mod:`lmidsl.certify.frequency_bound`, "Output
feedback") has Y terms y*Yy with y = Σᵢ aᵢ; the blocks that pair the two parts (Â, A + B2D̂C2 and
the −I between X' and Y') meet zero, and the argument above goes through unchanged.  The points
are the mirror images 1/μ of the eigenvalues of each full-information closed loop at γ₀, and
the kernel coefficients the forms' singular vectors.

**Singular problems** (D12 or D21 without full rank: no measurement noise, a free control
direction — most of COMPleib's plants).  The Hamiltonian certificate needs R_γ invertible; the
interpolation certificate does not: in continuous time, points sᵢ with Re sᵢ > 0 and the kernel
G = [1/(sᵢ + s̄ⱼ)] = ∫ e^{−sᵢt}e^{−s̄ⱼt}dt ⪰ 0 make the X terms Σ Gᵢⱼ(sᵢ + s̄ⱼ)p2ⱼ*Xp2ᵢ = x*Xx
(:mod:`lmidsl.certify.hamiltonian_bound`), and the argument is the same.  Its points are −μ for
the eigenvalues μ of the full-information closed loop of the plant with D12 regularised to
[D12; εI]; they only place the certificate, which is the plant's own.  On regular plants the
two constructions give the same bound to 16 digits (25 random plants), on singular ones it is
within 1e-4 of SLICOT's level for the ε-regularised plant (an upper bound on the optimum) on
COMPleib's AC3, AC6, AC11, AC15, HE2, DIS2, NN1, NN4.

**Making it tight.**  a, b and x are a Hermitian form, a Hermitian form and a linear map of c:
a₁ = c*M₁c, b₁ = c*N₁c, x = Pc (M₁ᵢⱼ = −(H*H)ᵢⱼ/(λⱼ + λ̄ᵢ), N₁ likewise with R), and the same for d.
A level γ is excluded when Q₁ = γ²N₁ − M₁ or Q₂ = γ²N₂ − M₂ has a negative eigenvalue, or when
γ σ_max(Q₁^{-1/2} P*P̃ Q₂^{-1/2}) > 1 (the dual of ρ(XY) > γ²); c and d are the top singular
vectors there, at the largest such γ found by bisection in floating point from the enclosures'
midpoints.  γ₀ matters little when it is near or above the optimum (on a random 3-state plant
γ₀ = 12.3 and 15 give 12.379858848 and 12.37985 for an optimum at 12.3798589–12.3798847); it
is refined by a few fixed-point steps γ₀ ← the bound at γ₀, started above the optimum: from far
below they can stall (a random 4-state plant: 6.80 from γ₀ = 5, 19.4736 from 30 or 1000, for
an optimum at 19.4736–19.4738).
"""
from __future__ import annotations

import numpy as np
from flint import acb_mat, arb

from ..numeric.proof import ball_precision, round_down
from ..numeric.riccati import full_information_feedback
from .hamiltonian_bound import (MAX_STATES, PRECISION, REGULARISATION, exact_column, full_column_rank, gramian, inner,
                                interpolation_forms, interpolation_parts, loop_points, midpoints, regularised,
                                split_directions, stable_eigendata, weighted_square)

#: fixed-point steps γ₀ ← bound(γ₀) in floating point before the enclosure
LEVEL_STEPS = 4
#: the certificate's directions are taken this far (relative) below the floating-point bound
BELOW = 1e-9
#: eigenvalues of the forms below this fraction of the largest are left out of the search
CONDITION = 1e-12
#: working precisions (bits) of a Hamiltonian's eigen-enclosure, tried in turn until it is accurate
ENCLOSURE_LADDER = (PRECISION, 512, 1024)


def _forms(lam, P, R, H) -> tuple:
    """(M, N, P) in floating point from the enclosures' midpoints: a = c*Mc, b = c*Nc, x = Pc."""
    lam = np.array([complex(float(z.real.mid()), float(z.imag.mid())) for z in lam])
    kernel = -1.0 / (lam[None, :] + lam.conj()[:, None])
    Hf, Rf, Pf = midpoints(H), midpoints(R), midpoints(P)
    return (Hf.conj().T @ Hf) * kernel, (Rf.conj().T @ Rf) * kernel, Pf


def _inverse_root(Q: np.ndarray) -> np.ndarray | None:
    """S with S*QS = I on the eigenvectors of a Hermitian Q ⪰ 0 whose eigenvalues exceed
    ``CONDITION``·λ_max (Q^{-1/2} on the well-conditioned part: a direction of Q's near-kernel
    would get a length of 1e60 and a ball 1e11 wide — COMPleib's HE1), or None when Q has no such
    eigenvalue in floating point."""
    w, V = np.linalg.eigh((Q + Q.conj().T) / 2)
    if not np.all(np.isfinite(w)) or not w[-1] > 0:
        return None
    keep = w > CONDITION * w[-1]
    return V[:, keep] / np.sqrt(w[keep])


def _excluding(first, second, gamma: float):
    """(c, d) that exclude ``gamma`` (module docstring, "Making it tight"), or None when these
    forms do not."""
    (M1, N1, P1), (M2, N2, P2) = first, second
    Q1, Q2 = gamma ** 2 * N1 - M1, gamma ** 2 * N2 - M2
    for Q, k in ((Q1, 0), (Q2, 1)):
        w, V = np.linalg.eigh((Q + Q.conj().T) / 2)
        if np.isfinite(w[0]) and w[0] < -CONDITION * abs(w[-1]):
            zero = np.zeros(P2.shape[1] if k == 0 else P1.shape[1], dtype=complex)
            return (V[:, 0], zero) if k == 0 else (zero, V[:, 0])
    S1, S2 = _inverse_root(Q1), _inverse_root(Q2)
    if S1 is None or S2 is None:
        return None
    u, sv, vh = np.linalg.svd(S1.conj().T @ P1.conj().T @ P2 @ S2)
    if not gamma * sv[0] > 1:
        return None
    return S1 @ u[:, 0], S2 @ vh[0].conj()


def _float_level(first, second, start: float) -> float:
    """The largest γ the forms exclude (bisection, relative 1e-13), or ``start``·1e-3 if none."""
    lo, hi = start * 1e-3, start * 10
    if _excluding(first, second, lo) is None:
        return lo
    while _excluding(first, second, hi) is not None and hi < 1e15:
        lo, hi = hi, hi * 10
    while hi - lo > 1e-13 * hi:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if _excluding(first, second, mid) is not None else (lo, mid)
    return lo


def _g_plus(first: tuple, second: tuple):
    """A ball containing g₊ (module docstring) from the balls (a₁, b₁, x) and (a₂, b₂, y), or None
    when b₁ or b₂ is not provably positive."""
    (a1, b1, x), (a2, b2, y) = first, second
    if not (b1 > 0 and b2 > 0):
        return None
    xi = abs(inner(x, y))
    s = a1 * b2 + a2 * b1 + xi * xi
    disc = s * s - 4 * a1 * a2 * b1 * b2
    root = arb(0) if not disc > 0 else disc.sqrt()
    return (s + root) / (2 * b1 * b2)


def _hamiltonian_parts(floats: list, balls: list, gamma0: float):
    """(forms, evaluate) of a Hamiltonian certificate at γ₀ (continuous time): the floating-point
    forms (M, N, P) and c ↦ balls of (a, b, x); None when the enclosure fails."""
    for bits in ENCLOSURE_LADDER:
        with ball_precision(bits):
            found = stable_eigendata(balls, gamma0)
        if found is None or _accurate(found[2]):
            break
    if found is None or not _accurate(found[2]):
        return None
    lam, _, P, R, H = found

    def evaluate(c):
        G = gramian(lam, c)
        return weighted_square(H, G), weighted_square(R, G), P * exact_column(c)

    return _forms(lam, P, R, H), evaluate


def _accurate(M: acb_mat) -> bool:
    """Whether every entry's radius is below 1e-30 of the largest midpoint (the enclosure of an
    ill-conditioned stable subspace can come out 1e11 wide at 192 bits: COMPleib's HE1)."""
    scale = max(abs(complex(float(z.real.mid()), float(z.imag.mid()))) for z in M.entries())
    return all(float(z.rad()) <= 1e-30 * scale for z in M.entries())


def _interpolation_parts(floats: list, balls: list, gamma0: float, time: str):
    """(forms, evaluate) of an interpolation certificate at the mirror images (discrete time:
    1/μ; continuous time: −μ) of the eigenvalues μ of the full-information closed loop A + BF at
    γ₀ — of the plant with D12 regularised to [D12; εI] where D12 has no full column rank (a
    singular problem: only the points come from it; the certificate is the plant's own); None
    when there is none."""
    F = None
    for eps in ((0.0,) if full_column_rank(floats[5]) else ()) + REGULARISATION:
        with np.errstate(all="ignore"):
            F = full_information_feedback(*regularised(floats, eps), gamma0, time)
        if F is not None:
            break
    if F is None:
        return None
    points = loop_points(floats, F, time)
    found = interpolation_forms(floats, points, time) if points else None
    if found is None:
        return None
    top, bottom, storage, bases = found

    def evaluate(z):
        return interpolation_parts(balls, points, split_directions(bases, z), storage=True, time=time)

    return (top, bottom, storage), evaluate


def _from_level(families, fi, fi_balls, fc, fc_balls, gamma0: float) -> tuple[float, float] | None:
    """(the best proved bound, its γ₀) of the fixed-point steps γ₀ ← the floating-point bound at γ₀, with
    ``families`` the constructions (:func:`_hamiltonian_parts` or :func:`_interpolation_parts`)
    of the full-information and the full-control part."""
    best = None
    for _ in range(LEVEL_STEPS):
        parts = [families[0](fi, fi_balls, gamma0), families[1](fc, fc_balls, gamma0)]
        if None in parts:
            break
        forms = [f for f, _ in parts]
        level = _float_level(*forms, gamma0)
        directions = _excluding(*forms, level * (1 - BELOW))
        if directions is None:
            break
        used = [k for k, v in enumerate(directions) if v.any()]
        values = [parts[k][1](directions[k]) for k in used]
        if None in values:
            ball = None
        elif len(used) == 1:                    # one certificate alone (t₂ = 0 or t₁ = 0): g ≥ a/b
            a, b, _ = values[0]
            ball = a / b if b > 0 else None
        else:
            ball = _g_plus(*values)
        if ball is not None and ball.is_finite() and ball.lower() > 0:
            lower = round_down(float(arb(ball.lower()).sqrt().lower()))
            if best is None or lower > best[0]:
                best = (lower, gamma0)
        if abs(level - gamma0) <= 1e-9 * level:
            break
        gamma0 = level
    return best


def coupling_bound(fi: list, fi_balls: list, fc: list, fc_balls: list, start: float, time: str,
                   level: float | None = None) -> tuple[float | None, str]:
    """(proved lower bound on γ, how) of the output-feedback LMI with [[X, I], [I, Y]] ⪰ 0 among its
    LMIs (continuous time) or as its leading principal block (discrete time) (module docstring):
    ``fi`` the full-information data (A, B1, B2, C1, D11, D12), ``fc`` the dual plant's, in
    floating point and in balls; ``start`` a level below the optimum (the larger of the two
    state-feedback bounds), ``level`` one above it if known (the SDP's).  The fixed-point steps
    on γ₀ start above the optimum — at ``level``, else at 10·``start`` — where they reach it
    (from below they can stall: 6.8 for an optimum of 19.47), then, if that gave nothing, just
    above ``start``.  (None, why) when none was proved."""
    n = fi[0].shape[0]
    if n > MAX_STATES:
        return None, f"more than {MAX_STATES} states (the eigen-enclosures cost O(n³) ball operations)"
    families, names = [], []
    for floats in (fi, fc):                        # a Hamiltonian where R_γ is invertible (continuous)
        if time == "continuous" and full_column_rank(floats[5]):
            families.append(_hamiltonian_parts)
            names.append("a Hamiltonian's stable eigenvectors")
        else:
            families.append(lambda f, b, g: _interpolation_parts(f, b, g, time))
            names.append("an interpolation certificate")
    what = f"full information: {names[0]}, full control: {names[1]},"
    best = None
    with ball_precision(PRECISION):
        for gamma0 in ([level * (1 + 1e-6)] if level else []) + [10 * start, start * (1 + 1e-3)]:
            best = _from_level(families, fi, fi_balls, fc, fc_balls, gamma0)
            if best is not None:
                break
    if best is None:
        return None, "no level gave a ball bound for the coupled certificate"
    return best[0], f"{what} at γ₀ = {best[1]:.10g} coupled through [[X, I], [I, Y]] ⪰ 0 (a dual point: γ ≥ √g₊)"


__all__ = ["coupling_bound"]
