"""The indexed gallery against independent computations, on generated cases.

* Markov jump state feedback: every certified design passes the second-moment test assembled
  here (Hurwitz diag(Aᵢ ⊕ Aᵢ) + Πᵀ ⊗ I, Schur (Pᵀ ⊗ I) diag(Aᵢ ⊗ Aᵢ)), on random modes with
  uncontrolled modes (Bᵢ = 0), unstable modes, fast and slow switching;
* T–S fuzzy PDC: every certified design passes the Lyapunov decrease on a finer membership grid
  and a simulation of the fuzzy closed loop with state-dependent memberships;
* switched systems: a simulation under random switching stays below √κ(P) e^{−αt}‖x₀‖;
* delays: the published 4.472 (Jensen) and 6.059 (Wirtinger), and on random cases never above
  the analytic delay margin (imaginary-axis crossings of det(sI − A − A_d e^{−sh}));
* H2 output feedback within 1e-4 of python-control's ``h2syn``; mixed H2/H∞ designs meet both
  bounds by python-control; energy-to-peak below √g by the Gramian.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import solve_continuous_lyapunov
from scipy.optimize import brentq

import lmidsl
from lmidsl.pipeline import make_instance
from lmidsl.studies.bisection import bisect
from lmidsl.theorems.textbook import delay, fuzzy, h2_of, markov, mixed, switched
from lmidsl.theorems.textbook.plants import random_plant

control = pytest.importorskip("control")


# -- independent computations ---------------------------------------------------------------
def second_moment_value(closed, Pi, time):
    n = closed[0].shape[0]
    q = n * n
    N = len(closed)
    D = np.zeros((N * q, N * q))
    for k, a in enumerate(closed):
        blk = np.kron(a, np.eye(n)) + np.kron(np.eye(n), a) if time == "continuous" else np.kron(a, a)
        D[k * q:(k + 1) * q, k * q:(k + 1) * q] = blk
    C = np.kron(np.asarray(Pi).T, np.eye(q))
    if time == "continuous":
        return np.linalg.eigvals(D + C).real.max()
    return np.abs(np.linalg.eigvals(C @ D)).max()


def delay_margin(A, Ad, wmax=50.0, points=20000):
    """The smallest h > 0 at which a root of det(sI − A − A_d e^{−sh}) crosses the imaginary
    axis (A + A_d Hurwitz): s = jω with 1/e^{−jωh} an eigenvalue μ of (jωI − A)⁻¹A_d, |μ| = 1."""
    n = A.shape[0]

    def mu(w):
        return np.linalg.eigvals(np.linalg.solve(1j * w * np.eye(n) - A, Ad))

    best = np.inf
    ws = np.linspace(1e-6, wmax, points)
    mods = np.array([np.sort(np.abs(mu(w))) for w in ws])
    for k in range(n):
        f = mods[:, k] - 1.0
        for a in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:])):
            w = brentq(lambda x: np.sort(np.abs(mu(x)))[k] - 1.0, ws[a], ws[a + 1], xtol=1e-14)
            m = mu(w)
            z = m[np.argmin(np.abs(np.abs(m) - 1.0))]
            theta = np.angle(z) % (2 * np.pi)        # e^{−jωh} = 1/μ  ⇒  ωh = arg μ (mod 2π)
            best = min(best, (theta if theta > 0 else 2 * np.pi) / w)
    return best


def random_generator(rng, N, scale):
    Pi = rng.random((N, N)) * scale
    np.fill_diagonal(Pi, 0.0)
    np.fill_diagonal(Pi, -Pi.sum(axis=1))
    return Pi


def random_stochastic(rng, N, stay):
    P = rng.random((N, N))
    P = P / P.sum(axis=1, keepdims=True) * (1 - stay)
    P[np.diag_indices(N)] += stay
    return P / P.sum(axis=1, keepdims=True)


def mjls_cases(time, count, seed):
    rng = np.random.default_rng(seed)
    for c in range(count):
        N = int(rng.integers(2, 5))
        n = int(rng.integers(2, 4))
        modes = []
        for k in range(N):
            A = rng.standard_normal((n, n)) * (1.0 if time == "continuous" else 0.7)
            B = rng.standard_normal((n, 1))
            if k == N - 1 and c % 3 == 0:
                B = np.zeros((n, 1))                       # an uncontrolled mode
                A = A - (2.0 if time == "continuous" else 0.0) * np.eye(n)
            modes.append({"A": A.tolist(), "B": B.tolist()})
        fast = c % 2 == 0
        Pi = (random_generator(rng, N, 10.0 if fast else 0.1) if time == "continuous"
              else random_stochastic(rng, N, 0.2 if fast else 0.95))
        yield {"modes": modes, "Pi": Pi.tolist()}


# -- Markov jump systems ---------------------------------------------------------------------
MJLS = [("continuous", markov.mjls_sf_ct), ("discrete", markov.mjls_sf_dt)]


@pytest.mark.parametrize("time, thm", MJLS)
def test_every_certified_mjls_design_is_mean_square_stable(time, thm, count=10, seed=0):
    certified = 0
    cases = list(mjls_cases(time, count, seed + (7 if time == "continuous" else 8)))
    for data in cases:
        sol = lmidsl.solve(thm, data=data, diagnose=False)
        if not sol.certified:
            continue
        certified += 1
        closed = [np.array(md["A"]) + np.array(md["B"]) @ sol.design[f"K_{k + 1}"]
                  for k, md in enumerate(data["modes"])]
        value = second_moment_value(closed, data["Pi"], time)
        assert value < (0 if time == "continuous" else 1), (data, value)
        for k, md in enumerate(data["modes"]):
            if not np.any(md["B"]):
                assert np.allclose(sol.design[f"K_{k + 1}"], 0.0)
    assert certified >= len(cases) // 2, f"only {certified} of {len(cases)} certified"


@pytest.mark.slow
@pytest.mark.parametrize("time, thm", MJLS)
def test_every_certified_mjls_design_is_mean_square_stable_many(time, thm):
    test_every_certified_mjls_design_is_mean_square_stable(time, thm, count=40, seed=100)


@pytest.mark.parametrize("time, thm", [("continuous", markov.mjls_hinf_sf_ct), ("discrete", markov.mjls_hinf_sf_dt)])
def test_mjls_hinf_designs_are_mean_square_stable_and_bounded_below_by_each_mode(time, thm):
    """Besides the second-moment test: with Π = 0 (continuous) or P = I (discrete), the modes never
    switch, so γ is at least the best H∞ state-feedback level of each mode alone — here checked
    against python-control's norm of each mode's own closed loop at the recovered gain."""
    rng = np.random.default_rng(5)
    for c in range(6):
        N, n = 2, 2
        modes = []
        for _ in range(N):
            A = rng.standard_normal((n, n)) * (1.0 if time == "continuous" else 0.6)
            modes.append({"A": A.tolist(), "B1": rng.standard_normal((n, 1)).tolist(),
                          "B2": rng.standard_normal((n, 1)).tolist(), "C1": [[1.0, 0.0], [0.0, 0.0]],
                          "D11": [[0.0], [0.0]], "D12": [[0.0], [1.0]]})
        Pi = np.zeros((N, N)) if time == "continuous" else np.eye(N)
        sol = lmidsl.solve(thm, data={"modes": modes, "Pi": Pi.tolist()})
        assert sol.certified
        for k, md in enumerate(modes):
            K = sol.design[f"K_{k + 1}"]
            A, B1, B2 = (np.array(md[x]) for x in ("A", "B1", "B2"))
            C1, D12 = np.array(md["C1"]), np.array(md["D12"])
            cl = control.ss(A + B2 @ K, B1, C1 + D12 @ K, np.zeros((2, 1)), 0 if time == "continuous" else True)
            assert control.norm(cl, "inf") <= sol.gamma * (1 + 1e-6)


# -- T–S fuzzy --------------------------------------------------------------------------------
def fuzzy_cases(count, seed):
    """Rules as the linearisations of one nonlinear plant at several points: a common (A₀, B₀)
    plus perturbations; every other case has all rules open-loop unstable."""
    rng = np.random.default_rng(seed)
    for c in range(count):
        r = int(rng.integers(2, 4))
        A0 = rng.standard_normal((2, 2)) + (1.0 if c % 2 else 0.0) * np.eye(2)
        B0 = rng.standard_normal((2, 1))
        rules = []
        for _ in range(r):
            A = A0 + 0.5 * rng.standard_normal((2, 2))
            B = B0 * (0.5 + rng.random()) + 0.2 * rng.standard_normal((2, 1))
            rules.append({"A": A.tolist(), "B": B.tolist()})
        yield {"rules": rules}


def memberships(x, r):
    """Normalised Gaussian memberships of x₁ centred at r points of [−2, 2]."""
    centres = np.linspace(-2.0, 2.0, r)
    w = np.exp(-((x[0] - centres) ** 2))
    return w / w.sum()


def test_every_certified_fuzzy_design_passes_a_fine_grid_and_a_simulation(count=8, seed=3):
    from lmidsl.certify.indexed_evidence import fuzzy_closed_loop, simplex_grid
    certified = 0
    cases = list(fuzzy_cases(count, seed))
    for data in cases:
        sol = lmidsl.solve(fuzzy.ts_pdc_ct, data=data, diagnose=False)
        if not sol.certified:
            continue
        certified += 1
        r = len(data["rules"])
        As = [np.array(d["A"]) for d in data["rules"]]
        Bs = [np.array(d["B"]) for d in data["rules"]]
        Ks = [sol.design[f"K_{k + 1}"] for k in range(r)]
        P = np.linalg.inv(sol.values["X"])
        for h in simplex_grid(r, 60):
            Acl = fuzzy_closed_loop(As, Bs, Ks, h)
            assert np.linalg.eigvalsh(P @ Acl + Acl.T @ P).max() < 0
        x0 = np.array([1.5, -1.0])

        def f(t, x):
            return fuzzy_closed_loop(As, Bs, Ks, memberships(x, r)) @ x

        out = solve_ivp(f, (0.0, 20.0), x0, rtol=1e-8, atol=1e-12, dense_output=True)
        V = np.einsum("it,ij,jt->t", out.y, P, out.y)
        assert V[-1] < 1e-3 * V[0]
        assert np.all(np.diff(V) <= 1e-9 * V[0])        # V decreases along the trajectory
    assert certified >= len(cases) // 2, f"only {certified} of {len(cases)} certified"


@pytest.mark.slow
def test_every_certified_fuzzy_design_passes_a_fine_grid_and_a_simulation_many():
    test_every_certified_fuzzy_design_passes_a_fine_grid_and_a_simulation(count=30, seed=300)


def test_pendulum_example_is_certified_with_the_grid_check():
    sol = lmidsl.solve(fuzzy.ts_pdc_ct, example="pendulum")
    assert sol.certified and all(c.passed for c in sol.checks)


# -- switched systems ---------------------------------------------------------------------------
def test_switched_decay_rate_holds_under_random_switching():
    rng = np.random.default_rng(2)
    found = 0
    for c in range(6):
        N = 3
        S = rng.standard_normal((2, 2))
        base = -(S @ S.T) - 1.0 * np.eye(2)
        subs = [{"A": (base + 0.4 * rng.standard_normal((2, 2))).tolist()} for _ in range(N)]
        inst = make_instance(switched.switched_clf_ct, None, {"subsystems": subs, "alpha": 0.0}, None)
        result = bisect(inst)
        alpha = result.feasible_end
        if alpha is None:
            # no common quadratic Lyapunov function at α = 0: then some subsystem or some convex
            # combination must be unstable or the common function simply not exist; at least the
            # stability of the subsystems is not refuted by this, so nothing to check
            continue
        found += 1
        P = result.solution.values["P"]
        # α is at most each subsystem's own decay rate
        assert alpha <= min(-np.linalg.eigvals(np.array(s["A"])).real.max() for s in subs) + 1e-6
        kappa = np.linalg.cond(P)
        x = np.array([1.0, -0.7])
        t, dt = 0.0, 1e-3
        x0 = np.linalg.norm(x)
        from scipy.linalg import expm
        steps = [expm(np.array(s["A"]) * dt) for s in subs]
        for _ in range(4000):
            x = steps[int(rng.integers(N))] @ x
            t += dt
            assert np.linalg.norm(x) <= np.sqrt(kappa) * np.exp(-alpha * t) * x0 * (1 + 1e-9)
    assert found >= 4


# -- delays -----------------------------------------------------------------------------------
def test_delay_margin_of_the_classic_example_is_6_1725():
    A, Ad = np.array(delay.CLASSIC["A"]), np.array(delay.CLASSIC["Ad"])
    assert abs(delay_margin(A, Ad) - 6.1725) < 1e-3


@pytest.mark.parametrize("thm, printed", [(delay.delay_jensen, 4.472), (delay.delay_wirtinger, 6.059)])
def test_delay_theorems_give_the_published_maximal_delays(thm, printed):
    result = bisect(make_instance(thm, "classic", None, None))
    assert abs(result.feasible_end - printed) < 1e-3
    assert result.feasible_end <= 6.1725


def delay_cases(count, seed):
    rng = np.random.default_rng(seed)
    made = 0
    while made < count:
        A = rng.standard_normal((2, 2)) - 1.5 * np.eye(2)
        Ad = 0.8 * rng.standard_normal((2, 2))
        if np.linalg.eigvals(A + Ad).real.max() < -0.05 and np.isfinite(delay_margin(A, Ad)):
            made += 1
            yield A, Ad


def test_delay_theorems_never_exceed_the_delay_margin(count=1):
    for A, Ad in delay_cases(count, 4):
        margin = delay_margin(A, Ad)
        hs = []
        for thm in (delay.delay_jensen, delay.delay_wirtinger):
            result = bisect(make_instance(thm, None, {"A": A.tolist(), "Ad": Ad.tolist()}, None),   # no h: bisected
                            upper=min(10.0, margin * 1.5), tol=1e-3)
            h = result.feasible_end or 0.0
            assert h <= margin + 1e-3, (A, Ad, thm.id, h, margin)
            hs.append(h)
        assert hs[0] <= hs[1] + 1e-3        # Wirtinger is never more conservative than Jensen


@pytest.mark.slow
def test_delay_theorems_never_exceed_the_delay_margin_many():
    test_delay_theorems_never_exceed_the_delay_margin(count=12)


# -- H2 output feedback, mixed, energy to peak ------------------------------------------------
def h2syn_norm(data):
    B = np.hstack([data["B1"], data["B2"]])
    C = np.vstack([data["C1"], data["C2"]])
    p1, m1 = np.shape(data["C1"])[0], np.shape(data["B1"])[1]
    D = np.block([[np.zeros((p1, m1)), data["D12"]], [data["D21"], data["D22"]]])
    P = control.ss(data["A"], B, C, D)
    K = control.h2syn(P, np.shape(data["C2"])[0], np.shape(data["B2"])[1])
    cl = P.lft(K)
    return float(np.sqrt(np.trace(cl.C @ control.lyap(cl.A, cl.B @ cl.B.T) @ cl.C.T)))


def h2_case(seed) -> bool:
    """Solve one random plant; a certified design's H2 norm (python-control) lies between h2syn's
    optimum and the certified bound.  Returns whether the LMI optimum was solved accurately and
    then checks it against h2syn within 1e-4 (an 'optimal_inaccurate' optimum is not compared)."""
    plant = random_plant(seed, 3, 2, 1, 2, 1, "continuous", d11=False)
    data = {k: np.array(plant[k], dtype=float) for k in h2_of.H2_PLANT}
    sol = lmidsl.solve(h2_of.h2_of_ct, data={k: v.tolist() for k, v in data.items()})
    ref = h2syn_norm(data)
    if sol.certified:
        loop = lmidsl.closed_loop({**{k: v.tolist() for k, v in data.items()},
                                   "D11": np.zeros((2, 2)).tolist()}, sol.design)
        h2 = float(control.norm(loop, 2))
        assert ref * (1 - 1e-6) <= h2 <= sol.gamma * (1 + 1e-3)
    # the LMI optimum (before any back-off to a better-conditioned controller) is h2syn's
    optimum, status = ((sol.backoff.get("gamma_opt"), sol.backoff.get("status_opt")) if sol.backoff
                       else (sol.gamma, sol.status))
    if status != "optimal" or optimum is None:
        return False
    assert abs(optimum - ref) <= 1e-4 * ref, (seed, optimum, ref)
    return sol.certified


@pytest.mark.parametrize("seed", [21, 22, 23, 24, 25])
def test_h2_output_feedback_matches_h2syn(seed):
    assert h2_case(seed)


@pytest.mark.slow
def test_h2_output_feedback_matches_h2syn_many():
    compared = sum(h2_case(seed) for seed in range(30, 50))
    assert compared >= 14     # measured: 15 of 20 solved accurately and certified (see the report)


def test_mixed_designs_meet_both_bounds(seeds=range(11, 15), least=4):
    """H2/H∞ state feedback on random plants (``seeds``): a certified design keeps the closed
    loop's H∞ norm (python-control) under γ₀ and its H2 norm under the certified level; at least
    ``least`` of them are certified."""
    met = 0
    for seed in seeds:
        ex = mixed._example(seed, True)
        ref = lmidsl.solve(lmidsl.get_theorem("textbook.hinf_sf_ct"),
                           data={k: ex[k] for k in ("A", "B1", "B2", "C1", "D11", "D12")})
        g0 = 1.3 * ref.gamma
        sol = lmidsl.solve(mixed.h2hinf_sf_ct, data={**ex, "gamma0": g0})
        if not sol.certified:
            continue
        met += 1
        d = {k: np.array(v, dtype=float) for k, v in ex.items()}
        K = sol.design["K"]
        Acl = d["A"] + d["B2"] @ K
        hinf = control.norm(control.ss(Acl, d["B1"], d["C1"] + d["D12"] @ K, d["D11"]), "inf")
        h2 = control.norm(control.ss(Acl, d["B1"], d["Cz"] + d["Dz"] @ K, 0), 2)
        assert hinf < g0 and h2 <= sol.gamma * (1 + 1e-6)
    assert met >= least


@pytest.mark.slow
def test_mixed_designs_meet_both_bounds_many():
    test_mixed_designs_meet_both_bounds(range(11, 21), least=8)


def test_energy_to_peak_design_is_below_its_bound_by_the_gramian():
    for seed in range(11, 19):
        ex = mixed._example(seed, False)
        sol = lmidsl.solve(mixed.e2p_sf_ct, data=ex)
        assert sol.certified
        d = {k: np.array(v, dtype=float) for k, v in ex.items()}
        K = sol.design["K"]
        Acl = d["A"] + d["B2"] @ K
        Wc = solve_continuous_lyapunov(Acl, -d["B1"] @ d["B1"].T)
        C = d["Cz"] + d["Dz"] @ K
        peak = np.sqrt(np.linalg.eigvalsh(C @ Wc @ C.T).max())
        assert peak <= sol.gamma * (1 + 1e-6)
        assert peak >= 0.98 * sol.gamma        # the bound is nearly attained (back-off ≤ 1 %)
