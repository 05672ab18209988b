"""Rate-bounded LPV conditions: the derivative of an HPPD matrix over the rate polytope, the
expansion without product-vertex duplication, scheduled gains, and the gallery theorems.

Independent judges: the stated LMI evaluated at (α, α̇) equals the combination
Σ α^m β^m N_m of the generated coefficient LMIs (exact identity of the expansion); Ṗ against a
central finite difference of P along α + t·α̇; the scheduled gain against K(α)Y(α) = W(α) with
Y, W summed here from their coefficients; simulations written here (scipy) under a parameter
moving at the rate bound, with V = xᵀP(α(t))x computed here.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lmidsl
from lmidsl.certify.rate_bounded import AtAlpha, scheduled
from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix
from lmidsl.symbolic.simplex import rate_vertices
from lmidsl.theorems.textbook import lpv

STAB, SF = lpv.lpv_stability_ct, lpv.lpv_sf_ct


def _solve(thm, example, **overrides):
    return lmidsl.solve(thm, example=example, overrides=overrides or None, diagnose=False)


@pytest.fixture(scope="module")
def stab():
    return _solve(STAB, "switching-pair", degree=2)


@pytest.fixture(scope="module")
def sf():
    return _solve(SF, "unstable-plant")


def test_rate_vertices_are_the_vertices_of_the_rate_polytope():
    for N in (2, 3, 4):
        H = np.array(rate_vertices(N))
        assert np.all(H.sum(axis=1) == 0) and np.all(np.abs(H) <= 1)
        # every vertex is an extreme point: not in the convex hull of the others (an LP)
        from scipy.optimize import linprog
        for k in range(len(H)):
            others = np.delete(H, k, axis=0)
            res = linprog(np.zeros(len(others)), A_eq=np.vstack([others.T, np.ones(len(others))]),
                          b_eq=np.append(H[k], 1.0), bounds=(0, None))
            assert not res.success
    assert len(rate_vertices(2)) == 2 and len(rate_vertices(3)) == 6


def test_no_product_vertex_duplication():
    member = _solve(STAB, "switching-pair").instance.theorem
    labels = [l.label for l in member.lmis]
    # N = 2, g = 1: degree 2 in α (3 monomials) × 2 rate vertices, and 2 for P(α) ≻ 0
    assert sum(l.startswith("(LPV)") for l in labels) == 6
    assert sum(l.startswith("P > 0") for l in labels) == 2 and len(labels) == 8


def test_the_expansion_is_the_stated_lmi(stab):
    member = stab.instance.theorem
    info = member.robust
    at = AtAlpha(stab)
    b = stab.instance.params["b"]
    H = np.array(rate_vertices(2), dtype=float)
    inst = stab.instance
    point = {**inst.data, **stab.values}
    coefficient = {l.label: evaluate_block_matrix(NumericEvaluator(inst.dims, point, inst.params), l.negative_form())
                   for l in member.lmis}
    stated = STAB.lmis[0]
    rng = np.random.default_rng(3)
    for _ in range(20):
        a1 = rng.random()
        alpha = np.array([a1, 1 - a1])
        beta1 = rng.random()
        beta = np.array([beta1, 1 - beta1])
        rate = b * beta @ H
        direct = evaluate_block_matrix(NumericEvaluator(inst.dims, at([alpha], [rate]), inst.params),
                                       stated.negative_form())
        combined = sum(np.prod(alpha ** np.array(m[0])) * np.prod(beta ** np.array(m[1])) * coefficient[label]
                       for m, label in info.coefficients["(LPV)"])
        assert np.allclose(direct, combined, atol=1e-9 * np.abs(direct).max())


def test_the_derivative_is_the_rate_of_change_of_P(stab):
    at = AtAlpha(stab)
    rng = np.random.default_rng(5)
    for _ in range(10):
        a1 = 0.1 + 0.8 * rng.random()
        alpha = np.array([a1, 1 - a1])
        h = np.array([0.07, -0.07])
        eps = 1e-5
        fd = (at([alpha + eps * h])["P"] - at([alpha - eps * h])["P"]) / (2 * eps)
        assert np.allclose(at([alpha], [h])["dP"], fd, atol=1e-8)


def test_rate_bounded_stability_certified_and_checked_by_our_own_simulation(stab):
    assert stab.verdict.certified and all(c.passed for c in stab.checks)
    data = lpv.OSCILLATOR["vertices"]
    A1, A2 = (np.array(v["A"]) for v in data)
    at = AtAlpha(stab)
    b = stab.instance.params["b"]

    def a2(t):                                   # triangle wave 0 → 1 → 0 at the rate bound
        s = (t * b) % 2.0
        return s if s <= 1 else 2 - s

    f = lambda t, x: ((1 - a2(t)) * A1 + a2(t) * A2) @ x   # noqa: E731
    sol = solve_ivp(f, (0, 40), [1.0, 0.5], rtol=1e-10, atol=1e-12, dense_output=True, max_step=0.05)
    ts = np.linspace(0, 40, 800)
    V = [x @ at([np.array([1 - a2(t), a2(t)])])["P"] @ x for t, x in zip(ts, sol.sol(ts).T)]
    assert np.all(np.diff(V) < 0) and V[-1] < 1e-2 * V[0]


def test_the_certificate_shrinks_with_the_rate_and_needs_a_varying_P():
    fast = _solve(STAB, "switching-pair", b=10.0)
    quadratic = _solve(STAB, "switching-pair", degree=0, b=0.01)
    assert not fast.verdict.certified and not quadratic.verdict.certified


def test_scheduled_gain_and_closed_loop_under_a_varying_parameter(sf):
    assert sf.verdict.certified and all(c.passed for c in sf.checks)
    info = sf.instance.theorem.robust
    Yk = {k: np.asarray(sf.values[c.name]) for k, c in info.coefficient_vars["Y"].items()}
    Wk = {k: np.asarray(sf.values[c.name]) for k, c in info.coefficient_vars["W"].items()}
    verts = lpv.PLANT["vertices"]
    A = [np.array(v["A"]) for v in verts]
    B = [np.array(v["B"]) for v in verts]
    b = sf.instance.params["b"]

    def YW(a):     # degree 1: Y(α) = α₁Y_10 + α₂Y_01
        return (a[0] * Yk[((1, 0),)] + a[1] * Yk[((0, 1),)], a[0] * Wk[((1, 0),)] + a[1] * Wk[((0, 1),)])

    for a1 in np.linspace(0, 1, 11):
        a = np.array([a1, 1 - a1])
        Y, W = YW(a)
        K = scheduled(sf, "K", [a])
        assert np.allclose(K @ Y, W, atol=1e-10)
    # the open loop is unstable at both vertices; the scheduled closed loop converges under a
    # sinusoidal parameter at the rate bound, and V = xᵀY(α)⁻¹x decreases
    assert all(np.linalg.eigvals(a).real.max() > 0 for a in A)

    def a2(t):
        return 0.5 + 0.5 * np.sin(2 * b * t)

    def f(t, x):
        a = np.array([1 - a2(t), a2(t)])
        return (a[0] * A[0] + a[1] * A[1] + (a[0] * B[0] + a[1] * B[1]) @ scheduled(sf, "K", [a])) @ x

    sol = solve_ivp(f, (0, 15), [1.0, -1.0], rtol=1e-9, atol=1e-12, dense_output=True, max_step=0.05)
    ts = np.linspace(0, 15, 300)
    V = [x @ np.linalg.inv(YW(np.array([1 - a2(t), a2(t)]))[0]) @ x for t, x in zip(ts, sol.sol(ts).T)]
    assert np.all(np.diff(V) < 0) and V[-1] < 1e-6 * V[0]
