"""The design stress set: plants built to be hard, each with its judge (python-control/slycot).

Every case is a dict ``{"name", "category", "theorem", "data", "params", "truth"}`` where
``truth`` says what a right answer is:

* ``{"kind": "norm", "value": ‖G‖∞}``: an analysis (bounded real lemma); right = certified
  within 1e-4 relative of the norm (linfnorm, SLICOT AB13DD);
* ``{"kind": "design", "optimum": γ*, "judge": ...}``: a synthesis; right = a certified design
  whose closed loop the judge measures at ≤ γ (1 + 1e-6); γ* is the best level an independent
  route achieves (SB10FD / SB10DD bisection on the level, each controller's closed loop measured;
  the LQR Riccati equation; the H∞ full-information Riccati bisection) — the "over the optimum"
  column is γ / γ* − 1;
* ``{"kind": "infeasible"}``: the plant is unstabilisable *as written* (exact integer data: a
  real unstable mode λ with an exact left eigenvector w, wᵀB = 0 in rational arithmetic, the
  structure hidden by a unimodular change of basis); right = proved infeasible;
* ``{"kind": "near_unstabilisable", "pbh": |wᴴB|/‖w‖‖B‖}``: the same plant with B perturbed by
  1e-9 … 1e-6 — stabilisable in exact arithmetic, but only with gains ≳ 1/pbh; a proof of
  infeasibility would be false; right = a judge-confirmed design, or "not solved" (never
  "proved infeasible"); the judge is the closed loop when a design is delivered.

Families: lightly damped (ζ = 1e-3), large-gain closed loops (a plant with its hinfsyn / sb10dd
controller, closed), weak actuators (B2 = (1e-6, 1)), badly scaled (state spread 1e±3), both
time domains.  Small n (≤ 6) so that the set runs in minutes.
"""
from __future__ import annotations

import numpy as np

CT, DT = "continuous", "discrete"


# -- building blocks ---------------------------------------------------------------------------
def _rng(seed):
    return np.random.default_rng(seed)


def light_block(wn: float, zeta: float, time: str) -> np.ndarray:
    """A lightly damped mode (ct: s² + 2ζω s + ω²; dt: its exact discretisation at h = 0.1)."""
    Am = np.array([[0.0, 1.0], [-wn ** 2, -2 * zeta * wn]])
    if time == DT:
        from scipy.linalg import expm
        Am = expm(0.1 * Am)
    return Am


def random_stable(rng, n, time, margin=(0.1, 1.0)):
    A = rng.standard_normal((n, n))
    eig = np.linalg.eigvals(A)
    if time == CT:
        return A - (max(eig.real) + rng.uniform(*margin)) * np.eye(n)
    return A * (rng.uniform(0.3, 0.9) / max(abs(eig)))


def random_unstable(rng, n, time, radius=1.3):
    A = rng.standard_normal((n, n))
    if time == DT:
        A = A * (radius / max(abs(np.linalg.eigvals(A))))
    return A


def spread(A, B, C, decades=3.0, B_cols=()):
    """x → S x, S = diag(logspace(−d, d)): the same transfer function, entries 1e−2d … 1e2d."""
    n = A.shape[0]
    S = np.diag(np.logspace(-decades, decades, n))
    Si = np.diag(1 / np.diag(S))
    return S @ A @ Si, S @ B, C @ Si


def plant(A, B1, B2, C1, C2, D11, D12, D21, D22=None):
    D22 = np.zeros((C2.shape[0], B2.shape[1])) if D22 is None else D22
    return dict(A=A, B1=B1, B2=B2, C1=C1, C2=C2, D11=D11, D12=D12, D21=D21, D22=D22)


def regular_plant(rng, A, m1=1, m2=1, p2=1, weak=1.0):
    """A regular generalized plant around A: C1 = [c; 0], D12 = [0; I], D21 = [0 I] (noise)."""
    n = A.shape[0]
    B1 = np.hstack([rng.standard_normal((n, m1)), np.zeros((n, p2))])
    B2 = rng.standard_normal((n, m2)) * weak
    C1 = np.vstack([rng.standard_normal((1, n)), np.zeros((m2, n))])
    D12 = np.vstack([np.zeros((1, m2)), np.eye(m2)])
    C2 = rng.standard_normal((p2, n))
    D21 = np.hstack([np.zeros((p2, m1)), np.eye(p2)])
    D11 = np.zeros((1 + m2, m1 + p2))
    return plant(A, B1, B2, C1, C2, D11, D12, D21)


# -- references ---------------------------------------------------------------------------------
def dt_flag(time):
    return 0 if time == CT else True


def linf(A, B, C, D, time) -> float:
    import control
    if not stable(A, time):
        return float("inf")
    return float(control.linfnorm(control.ss(A, B, C, D, dt_flag(time)), tol=1e-10)[0])


def h2(A, B, C, D, time) -> float:
    import control
    if not stable(A, time):
        return float("inf")
    if time == CT and np.any(D):
        return float("inf")
    return float(control.norm(control.ss(A, B, C, D, dt_flag(time)), 2))


def stable(A, time) -> bool:
    e = np.linalg.eigvals(A)
    return bool(max(e.real) < 0) if time == CT else bool(max(abs(e)) < 1)


def hinfsyn_ct(P: dict):
    """(γ*, controller (AK, BK, CK, DK)) by SLICOT SB10AD (python-control's hinfsyn) in its
    bisection mode (job 1; hinfsyn's default bisection-then-scan takes 30 s on a 4-state plant)."""
    from slycot import sb10ad
    n, m2, p2 = P["A"].shape[0], P["B2"].shape[1], P["C2"].shape[0]
    B = np.hstack([P["B1"], P["B2"]])
    C = np.vstack([P["C1"], P["C2"]])
    D = np.block([[P["D11"], P["D12"]], [P["D21"], P["D22"]]])
    gam, AK, BK, CK, DK, *_ = sb10ad(n, B.shape[1], C.shape[0], m2, p2, 1e8, P["A"], B, C, D,
                                     job=1, gtol=1e-9)
    return float(gam), (AK, BK, CK, DK)


def sb10fd_level(P: dict, gamma: float):
    """A continuous-time H∞ controller at level γ by SLICOT SB10FD."""
    from slycot import sb10fd
    n, m2, p2 = P["A"].shape[0], P["B2"].shape[1], P["C2"].shape[0]
    B = np.hstack([P["B1"], P["B2"]])
    C = np.vstack([P["C1"], P["C2"]])
    D = np.block([[P["D11"], P["D12"]], [P["D21"], P["D22"]]])
    AK, BK, CK, DK, _ = sb10fd(n, B.shape[1], C.shape[0], m2, p2, gamma, P["A"], B, C, D)
    return AK, BK, CK, DK


def sb10dd_level(P: dict, gamma: float):
    """A discrete-time H∞ controller at level γ by SLICOT SB10DD, or None where it fails."""
    from slycot import sb10dd
    n, m2, p2 = P["A"].shape[0], P["B2"].shape[1], P["C2"].shape[0]
    m, p = P["B1"].shape[1] + m2, P["C1"].shape[0] + p2
    B = np.hstack([P["B1"], P["B2"]])
    C = np.vstack([P["C1"], P["C2"]])
    D = np.block([[P["D11"], P["D12"]], [P["D21"], P["D22"]]])
    try:
        _, AK, BK, CK, DK, *_ = sb10dd(n, m, p, m2, p2, gamma, P["A"], B, C, D)
    except Exception:        # noqa: BLE001 — SLICOT's "no controller at this level"
        return None
    K = (AK, BK, CK, DK)
    closed = of_closed_loop(P, K)
    norm = linf(*closed, DT)
    return (K, norm) if norm < gamma * (1 + 1e-6) else None


def sb10fd_met(P: dict, gamma: float):
    """(controller, closed-loop norm) by SB10FD at level γ when its closed loop meets γ, else None."""
    try:
        K = sb10fd_level(P, gamma)
    except Exception:        # noqa: BLE001 — SLICOT's "no controller at this level"
        return None
    norm = linf(*of_closed_loop(P, K), CT)
    return (K, norm) if norm < gamma * (1 + 1e-6) else None


def achieved_optimum(level, hi: float = 1e4):
    """The least level γ at which ``level(γ)`` returns a controller whose closed loop meets γ
    (bisection to 1e-5): an achieved level, so an upper bound on the optimum that SLICOT reaches
    (SB10AD's own γ estimate is not always achieved: 0.356 on the filter plant 41, whose best
    achieved level is 0.6618).  Returns (γ, controller), (None, None) when even ``hi`` fails."""
    best = level(hi)
    if best is None:
        return None, None
    lo = 0.0
    while hi - lo > 1e-5 * hi:
        mid = (lo + hi) / 2 if lo > 0 else hi / 2
        got = level(mid)
        if got is None:
            lo = mid
        else:
            hi, best = mid, got
    return hi, best[0]


def sb10dd_optimum(P: dict, hi: float = 1e4):
    """The least level at which SB10DD returns a controller meeting it (:func:`achieved_optimum`)."""
    return achieved_optimum(lambda g: sb10dd_level(P, g), hi)


def sb10fd_optimum(P: dict, hi: float = 1e5):
    """The least level at which SB10FD returns a controller meeting it (:func:`achieved_optimum`)."""
    return achieved_optimum(lambda g: sb10fd_met(P, g), hi)


def of_closed_loop(P: dict, K):
    """(A, B, C, D) of the plant with u = controller(y) (D22 = 0)."""
    AK, BK, CK, DK = (np.atleast_2d(k) for k in K)
    A, B1, B2, C1, C2 = P["A"], P["B1"], P["B2"], P["C1"], P["C2"]
    D11, D12, D21 = P["D11"], P["D12"], P["D21"]
    Acl = np.block([[A + B2 @ DK @ C2, B2 @ CK], [BK @ C2, AK]])
    Bcl = np.vstack([B1 + B2 @ DK @ D21, BK @ D21])
    Ccl = np.hstack([C1 + D12 @ DK @ C2, D12 @ CK])
    Dcl = D11 + D12 @ DK @ D21
    return Acl, Bcl, Ccl, Dcl


def sf_hinf_optimum(P: dict, time: str) -> float:
    """The H∞ state-feedback optimum: the least γ at which the full-information Riccati equation
    (scipy) has a stabilising solution X ⪰ 0 whose gain meets γ (closed loop by linfnorm);
    bisection to 1e-7.  Independent of lmidsl's code (same mathematics)."""
    from scipy.linalg import solve_continuous_are, solve_discrete_are
    A, B1, B2, C1, D11, D12 = (P[k] for k in ("A", "B1", "B2", "C1", "D11", "D12"))
    m1 = B1.shape[1]
    B, D = np.hstack([B1, B2]), np.hstack([D11, D12])

    def ok(g):
        R = D.T @ D
        R[:m1, :m1] -= g ** 2 * np.eye(m1)
        try:
            with np.errstate(all="ignore"):
                if time == CT:
                    X = solve_continuous_are(A, B, C1.T @ C1, R, s=C1.T @ D)
                    F = -np.linalg.solve(R, B.T @ X + D.T @ C1)
                else:
                    X = solve_discrete_are(A, B, C1.T @ C1, R, s=C1.T @ D)
                    F = -np.linalg.solve(R + B.T @ X @ B, B.T @ X @ A + D.T @ C1)
        except (np.linalg.LinAlgError, ValueError):
            return False
        if not np.all(np.isfinite(X)) or np.linalg.eigvalsh((X + X.T) / 2)[0] < -1e-9 * max(1, abs(X).max()):
            return False
        K = F[m1:]
        return linf(A + B2 @ K, B1, C1 + D12 @ K, D11, time) < g * (1 + 1e-9)

    hi = 1.0
    while not ok(hi):
        hi *= 2
        if hi > 1e12:
            return float("nan")
    lo = hi / 2
    while ok(lo) and lo > 1e-9:
        hi, lo = lo, lo / 2
    while hi / lo - 1 > 1e-7:
        mid = np.sqrt(lo * hi)
        hi, lo = (mid, lo) if ok(mid) else (hi, mid)
    return hi


def h2_sf_optimum(P: dict, time: str) -> float:
    """The H2 state-feedback optimum by python-control's lqr / dlqr (SLICOT SB02MD/OD): the
    closed loop of the LQR gain for Q = C1ᵀC1, R = D12ᵀD12, N = C1ᵀD12, its H2 norm."""
    import control
    A, B1, B2, C1, D12 = (P[k] for k in ("A", "B1", "B2", "C1", "D12"))
    Q, R, N = C1.T @ C1, D12.T @ D12, C1.T @ D12
    if time == CT:
        K, *_ = control.lqr(A, B2, Q, R, N)
    else:
        K, *_ = control.dlqr(A, B2, Q, R, N)
    K = -np.asarray(K)
    D11 = P.get("D11", np.zeros((C1.shape[0], B1.shape[1])))
    return h2(A + B2 @ K, B1, C1 + D12 @ K, D11, time)


# -- the unstabilisable plants ------------------------------------------------------------------
def hidden_unstabilisable(seed: int, time: str, n: int = 4):
    """Integer data, exactly unstabilisable: Ã = [[A11, a12], [0, λ]] with λ = 2 (ct) / −2 (dt)
    an unstable mode no input reaches, B̃ = [B̃1; 0], then A = T Ã T⁻¹, B = T B̃ for a unimodular
    integer T (T⁻¹ integer): every entry an exact small integer, the structure invisible.  The
    left eigenvector wᵀ = e_nᵀ T⁻¹ has wᵀB = 0 exactly."""
    rng = _rng(seed)
    lam = 2 if time == CT else -2
    At = np.zeros((n, n))
    At[:n - 1, :n - 1] = rng.integers(-2, 3, (n - 1, n - 1))
    At[:n - 1, n - 1] = rng.integers(-2, 3, n - 1)
    At[n - 1, n - 1] = lam
    Bt = np.zeros((n, 1))
    Bt[:n - 1, 0] = rng.integers(1, 3, n - 1)
    L = np.tril(rng.integers(-1, 2, (n, n)), -1) + np.eye(n)
    U = np.triu(rng.integers(-1, 2, (n, n)), 1) + np.eye(n)
    T = L @ U                                    # det 1, integer; T⁻¹ integer
    Ti = np.round(np.linalg.inv(T))
    assert np.array_equal(T @ Ti, np.eye(n))
    A = T @ At @ Ti
    B = T @ Bt
    return A, B


def pbh_gap(A, B, time) -> float:
    """min over unstable eigenvalues of |wᴴB| / (‖w‖ ‖B‖), w the left eigenvector (numpy)."""
    e, W = np.linalg.eig(A.T)
    worst = np.inf
    for lam, w in zip(e, W.T):
        if (time == CT and lam.real >= 0) or (time == DT and abs(lam) >= 1):
            worst = min(worst, np.linalg.norm(w.conj() @ B) / (np.linalg.norm(w) * np.linalg.norm(B)))
    return float(worst)


# -- the cases ---------------------------------------------------------------------------------
def _brl_cases():
    out = []
    # closed loops of plants with their hinfsyn controllers (large gains, near-singular recovery)
    for seed, kind in ((1, "light"), (2, "huge_gain"), (3, "spread")):
        rng = _rng(seed)
        if kind == "light":
            A = np.block([[random_stable(rng, 2, CT), np.zeros((2, 2))],
                          [np.zeros((2, 2)), light_block(1.3, 1e-3, CT)]])
            P = regular_plant(rng, A)
        elif kind == "huge_gain":
            P = regular_plant(rng, random_unstable(rng, 3, CT), weak=1e-2)
        else:
            A = random_unstable(rng, 3, CT)
            P = regular_plant(rng, A)
            P["A"], P["B1"], P["C1"] = spread(A, P["B1"], P["C1"])
            P["B2"] = np.diag(np.logspace(-3, 3, 3)) @ P["B2"]
            P["C2"] = P["C2"] @ np.diag(np.logspace(3, -3, 3))
        gam, K = hinfsyn_ct(P)
        Acl, Bcl, Ccl, Dcl = of_closed_loop(P, K)
        if not stable(Acl, CT):          # SB10AD's controller at its γ estimate can be unusable
            K = sb10fd_level(P, gam * (1 + 1e-4))
            Acl, Bcl, Ccl, Dcl = of_closed_loop(P, K)
        out.append(dict(name=f"brl_ct/{kind}-{seed}", category="BRL ct (closed loops)",
                        theorem="textbook.brl_ct", data=dict(A=Acl, B=Bcl, C=Ccl, D=Dcl),
                        truth={"kind": "norm", "value": linf(Acl, Bcl, Ccl, Dcl, CT),
                               "gain": float(np.linalg.norm(K[3]) + np.linalg.norm(K[2]))}))
    for seed, kind in ((4, "light"), (5, "huge_gain")):
        rng = _rng(seed)
        if kind == "light":
            A = np.block([[random_stable(rng, 2, DT), np.zeros((2, 2))],
                          [np.zeros((2, 2)), light_block(1.3, 1e-3, DT)]])
            P = regular_plant(rng, A)
        else:
            P = regular_plant(rng, random_unstable(rng, 3, DT), weak=1e-2)
        level, K = sb10dd_optimum(P)
        Acl, Bcl, Ccl, Dcl = of_closed_loop(P, K)
        out.append(dict(name=f"brl_dt/{kind}-{seed}", category="BRL dt (closed loops)",
                        theorem="textbook.brl_dt", data=dict(A=Acl, B=Bcl, C=Ccl, D=Dcl),
                        truth={"kind": "norm", "value": linf(Acl, Bcl, Ccl, Dcl, DT)}))
    # an open-loop lightly damped plant, badly scaled
    rng = _rng(6)
    A = np.block([[random_stable(rng, 2, CT), np.zeros((2, 2))], [np.zeros((2, 2)), light_block(0.7, 1e-3, CT)]])
    B, C = rng.standard_normal((4, 1)), rng.standard_normal((1, 4))
    A, B, C = spread(A, B, C, 2.0)
    out.append(dict(name="brl_ct/light-spread-6", category="BRL ct (closed loops)", theorem="textbook.brl_ct",
                    data=dict(A=A, B=B, C=C, D=np.zeros((1, 1))),
                    truth={"kind": "norm", "value": linf(A, B, C, np.zeros((1, 1)), CT)}))
    return out


def stiff_hinf_loop(seed: int):
    """(A, B, C, D) of the closed loop of a random plant (kind by seed mod 4: unstable, weak
    actuator, spread scales, lightly damped; 3 to 6 states) with SB10AD's controller at its γ
    estimate, or None when that loop is unstable: eigenvalues up to 3e10 next to 1 (seeds 100–123:
    15 stable loops), where SLICOT's norm of the data as written is off by up to 50 %."""
    rng = _rng(seed)
    kind, n = ("unstable", "weak", "spread", "light")[seed % 4], 3 + seed % 4
    if kind == "unstable":
        P = regular_plant(rng, random_unstable(rng, n, CT))
    elif kind == "weak":
        P = regular_plant(rng, random_unstable(rng, n, CT), weak=1e-2)
    elif kind == "spread":
        A = random_unstable(rng, n, CT)
        P = regular_plant(rng, A)
        P["A"], P["B1"], P["C1"] = spread(A, P["B1"], P["C1"])
    else:
        A = np.block([[random_stable(rng, n - 2, CT), np.zeros((n - 2, 2))],
                      [np.zeros((2, n - 2)), light_block(1.3, 1e-3, CT)]])
        P = regular_plant(rng, A)
    _, K = hinfsyn_ct(P)
    loop = of_closed_loop(P, K)
    return loop if stable(loop[0], CT) else None


def _sf_data(P, keys=("A", "B1", "B2", "C1", "D11", "D12")):
    return {k: P[k] for k in keys}


def _sf_plants(time):
    """(name, plant) for state feedback: random 5-state, lightly damped, weak actuator
    (B2 = (1e-6, 1)), badly scaled, weak actuator unstable."""
    out = []
    rng = _rng(11)
    out.append(("random-5", regular_plant(rng, random_unstable(rng, 5, time))))
    rng = _rng(12)
    A = np.block([[random_unstable(rng, 2, time), np.zeros((2, 2))],
                  [np.zeros((2, 2)), light_block(1.1, 1e-3, time)]])
    out.append(("light-4", regular_plant(rng, A)))
    rng = _rng(13)
    A = np.array([[0.0, 1.0], [-1.0, -0.2]]) if time == CT else np.array([[1.0, 0.1], [-0.1, 0.98]])
    P = regular_plant(rng, A)
    P["B2"] = np.array([[1e-6], [1.0]])
    out.append(("weak-B2", P))
    if time == CT:
        rng = _rng(14)
        A = random_unstable(rng, 4, time)
        P = regular_plant(rng, A)
        P["A"], P["B1"], P["C1"] = spread(A, P["B1"], P["C1"], 2.0)
        P["B2"] = np.diag(np.logspace(-2, 2, 4)) @ P["B2"]
        out.append(("spread-4", P))
    return out


def _synthesis_cases():
    out = []
    sfx = {CT: "ct", DT: "dt"}
    for time in (CT, DT):
        for name, P in _sf_plants(time):
            out.append(dict(name=f"hinf_sf_{sfx[time]}/{name}", category=f"H∞ SF {sfx[time]}",
                            theorem=f"textbook.hinf_sf_{sfx[time]}", data=_sf_data(P),
                            truth={"kind": "design", "optimum": sf_hinf_optimum(P, time), "judge": "hinf_sf"}))
            if name == "spread-4":
                continue
            keys = ("A", "B1", "B2", "C1", "D12") if time == CT else ("A", "B1", "B2", "C1", "D11", "D12")
            P2 = dict(P)
            if time == CT:
                P2["D11"] = np.zeros_like(P["D11"])
            out.append(dict(name=f"h2_{sfx[time]}_sf/{name}", category=f"H2 SF {sfx[time]}",
                            theorem=f"textbook.h2_{sfx[time]}_sf", data=_sf_data(P2, keys),
                            truth={"kind": "design", "optimum": h2_sf_optimum(P2, time), "judge": "h2_sf"}))
    # output feedback: the best level SB10FD (ct) / SB10DD (dt) achieves is the reference
    for time, seeds in ((CT, (21, 22, 23)), (DT, (31, 32, 33))):
        for seed, kind in zip(seeds, ("random", "light", "weak")):
            rng = _rng(seed)
            if kind == "light":
                A = np.block([[random_unstable(rng, 1, time), np.zeros((1, 2))],
                              [np.zeros((2, 1)), light_block(1.2, 1e-3, time)]])
                P = regular_plant(rng, A)
            else:
                P = regular_plant(rng, random_unstable(rng, 3, time), weak=1e-2 if kind == "weak" else 1.0)
            gam, _ = sb10fd_optimum(P) if time == CT else sb10dd_optimum(P)
            out.append(dict(name=f"hinf_of_{sfx[time]}/{kind}-{seed}", category=f"H∞ OF {sfx[time]}",
                            theorem=f"textbook.hinf_of_{sfx[time]}", data=P,
                            truth={"kind": "design", "optimum": gam, "judge": "hinf_of"}))
    # filters: the filtering plant as a generalized plant with B2 = 0, D12 = −I, D22 = 0
    for time, seed in ((CT, 41), (CT, 42), (DT, 43)):
        rng = _rng(seed)
        if seed == 42:
            A = np.block([[random_stable(rng, 2, time), np.zeros((2, 2))],
                          [np.zeros((2, 2)), light_block(0.9, 1e-3, time)]])
        else:
            A = random_stable(rng, 3, time)
        n = A.shape[0]
        B1 = np.hstack([rng.standard_normal((n, 1)), np.zeros((n, 1))])
        C1, C2 = rng.standard_normal((1, n)), rng.standard_normal((1, n))
        D11, D21 = np.zeros((1, 2)), np.array([[0.0, 1.0]])
        GP = plant(A, B1, np.zeros((n, 1)), C1, C2, D11, -np.eye(1), D21)
        gam = sb10fd_optimum(GP)[0] if time == CT else sb10dd_optimum(GP)[0]
        out.append(dict(name=f"hinf_filter_{sfx[time]}/{'light' if seed == 42 else 'random'}-{seed}",
                        category=f"H∞ filter {sfx[time]}", theorem=f"textbook.hinf_filter_{sfx[time]}",
                        data=dict(A=A, B1=B1, C1=C1, C2=C2, D11=D11, D21=D21),
                        truth={"kind": "design", "optimum": gam, "judge": "filter"}))
    # pole region (α = 0.5, disk r = 10, sector 45°) on a lightly damped unstable plant
    rng = _rng(51)
    A = np.block([[random_unstable(rng, 2, CT), np.zeros((2, 2))], [np.zeros((2, 2)), light_block(1.0, 1e-3, CT)]])
    out.append(dict(name="pole_region_sf_ct/light-51", category="pole region ct",
                    theorem="textbook.pole_region_sf_ct", data=dict(A=A, B2=rng.standard_normal((4, 2))),
                    truth={"kind": "region"}))
    return out


def _unstabilisable_cases():
    out = []
    for time, seed in ((CT, 61), (DT, 62)):
        sfx = "ct" if time == CT else "dt"
        A, B2 = hidden_unstabilisable(seed, time)
        n = A.shape[0]
        rng = _rng(seed)
        B1 = rng.integers(-1, 2, (n, 1)).astype(float)
        C1 = np.vstack([np.ones((1, n)), np.zeros((1, n))])
        D12 = np.array([[0.0], [1.0]])
        P = dict(A=A, B1=B1, B2=B2, C1=C1, D11=np.zeros((2, 1)), D12=D12)
        out.append(dict(name=f"hinf_sf_{sfx}/unstabilisable-{seed}", category="unstabilisable (exact)",
                        theorem=f"textbook.hinf_sf_{sfx}", data=P, truth={"kind": "infeasible"}))
        keys = ("A", "B1", "B2", "C1", "D12") if time == CT else ("A", "B1", "B2", "C1", "D11", "D12")
        out.append(dict(name=f"h2_{sfx}_sf/unstabilisable-{seed}", category="unstabilisable (exact)",
                        theorem=f"textbook.h2_{sfx}_sf", data={k: P[k] for k in keys},
                        truth={"kind": "infeasible"}))
        if time == CT:
            out.append(dict(name=f"pole_region_sf_ct/unstabilisable-{seed}", category="unstabilisable (exact)",
                            theorem="textbook.pole_region_sf_ct", data=dict(A=A, B2=B2),
                            truth={"kind": "infeasible"}))
            GP = dict(A=A, B1=np.hstack([B1, np.zeros((n, 1))]), B2=B2, C1=C1,
                      C2=np.ones((1, n)), D11=np.zeros((2, 2)), D12=D12, D21=np.array([[0.0, 1.0]]),
                      D22=np.zeros((1, 1)))
            out.append(dict(name=f"hinf_of_ct/unstabilisable-{seed}", category="unstabilisable (exact)",
                            theorem="textbook.hinf_of_ct", data=GP, truth={"kind": "infeasible"}))
        # near: the same with B2 perturbed along w (1e-9 · ‖B2‖, 1e-6 · ‖B2‖)
        for size in ((1e-9,) if time == CT else (1e-6,)):
            Bp = B2 + size * np.linalg.norm(B2) * np.ones_like(B2)
            Pn = dict(P, B2=Bp)
            out.append(dict(name=f"hinf_sf_{sfx}/near-unstabilisable-{size:g}", category="near-unstabilisable",
                            theorem=f"textbook.hinf_sf_{sfx}", data=Pn,
                            truth={"kind": "near_unstabilisable", "pbh": pbh_gap(A, Bp, time), "judge": "hinf_sf"}))
    return out


def cases() -> list[dict]:
    return _brl_cases() + _synthesis_cases() + _unstabilisable_cases()
