"""Robust LMIs over the simplex (HPPD Lyapunov matrices, Pólya's relaxation).

Every number is compared with an independent computation: the expansion with a numeric
evaluation of the stated LMI at random α (the identity Σαᵢ = 1 makes them equal), the claims
with eigenvalues / python-control norms on a grid of the simplex (lmidsl.certify.simplex_grid),
the margins with the grid's own margin.
"""
from __future__ import annotations

import itertools
from math import comb

import numpy as np
import pytest
import sympy as sp

from lmidsl import He, I, InputError, Source
from lmidsl.certify.simplex_grid import grid_evidence, simplex_points
from lmidsl.numeric.evaluate import NumericEvaluator
from lmidsl.pipeline import make_instance, solve, solve_instance
from lmidsl.render.robust_latex import coefficient_lmis_latex, robust_statement_latex
from lmidsl.studies.bisection import bisect
from lmidsl.symbolic.blocks import block_matrix
from lmidsl.symbolic.simplex import (HomogeneousPolynomial, coefficient_blocks, exponents, multi_exponents,
                                     multinomial, vertex_exponents)
from lmidsl.symbolic.symbols import DataMatrix, SymmetricVariable
from lmidsl.theorem.registry import get_theorem
from lmidsl.theorem.robust import RobustTheorem
from lmidsl.theorems.textbook.hpd import random_polytope, spread_polytope


def _lmis_proved(sol) -> bool:
    """A solve without the certification step (certify=False): every coefficient LMI holds and
    is proved at the returned point."""
    return bool(sol.ok and sol.lmis_hold and sol.proved)


# -- the algebra ---------------------------------------------------------------------------------
def test_exponents_and_multinomials():
    for N, g in itertools.product(range(1, 5), range(0, 5)):
        ks = exponents(N, g)
        assert len(ks) == comb(N + g - 1, g) == len(set(ks))
        assert all(sum(k) == g and min(k) >= 0 for k in ks)
    assert multinomial((2, 1, 0)) == 3 and multinomial((2, 2)) == 6 and multinomial((1, 1, 1)) == 6
    # multinomial theorem: (Σ αᵢ)^d = Σ_{|j|=d} d!/j! α^j, checked numerically
    alpha = np.array([0.2, 0.5, 0.9])
    for d in range(5):
        assert sum(multinomial(j) * np.prod(alpha ** np.array(j)) for j in exponents(3, d)) == \
            pytest.approx(alpha.sum() ** d)


def _numeric_forms(sizes, degree, rng, n=3):
    """Statement symbols A (vertex data) and P (HPPD) with their forms and random numbers."""
    A = DataMatrix("A", n, n, "t.alg")
    P = SymmetricVariable("P", n, n, "t.alg")
    values = {}
    vertex = {}
    for v, e in enumerate(vertex_exponents(sizes)):
        s = DataMatrix(f"A_{v}", n, n, "t.alg")
        vertex[e] = s
        values[s.name] = rng.standard_normal((n, n))
    coeffs = {}
    for k in multi_exponents(sizes, (degree,) * len(sizes)):
        s = SymmetricVariable("P_" + "_".join("".join(map(str, p)) for p in k), n, n, "t.alg")
        X = rng.standard_normal((n, n))
        coeffs[k] = s
        values[s.name] = X + X.T
    forms = {A: HomogeneousPolynomial.from_coefficients(vertex, sizes, (1,) * len(sizes)),
             P: HomogeneousPolynomial.from_coefficients(coeffs, sizes, (degree,) * len(sizes))}
    return A, P, forms, values


def _monomial(alphas, m):
    return float(np.prod([a ** k for p, al in zip(m, alphas) for k, a in zip(p, al)]))


@pytest.mark.parametrize("sizes,degree,polya", [((2,), 1, 0), ((3,), 2, 1), ((4,), 3, 2), ((2, 3), 1, 1),
                                                ((3,), 0, 3)])
def test_coefficient_lmis_sum_to_the_stated_lmi_on_the_simplex(sizes, degree, polya):
    """Σ_m α^m N_m equals the stated block matrix at α (numbers drawn at random), on the simplex:
    the homogenisation and Pólya's multiplier with their multinomial coefficients are exact."""
    rng = np.random.default_rng(7)
    A, P, forms, values = _numeric_forms(sizes, degree, rng)
    C = DataMatrix("C", 2, 3, "t.alg")
    values["C"] = rng.standard_normal((2, 3))
    g = sp.Symbol("g")
    spec = block_matrix([[He(P * A) + A.T * P * A], [C * P, -g * sp.Identity(2)]])
    total, coefficients = coefficient_blocks(spec, forms, sizes, polya)
    assert total == tuple(degree + 2 + polya for _ in sizes)
    for _ in range(3):
        alphas = [rng.dirichlet(np.ones(N)) for N in sizes]
        # the stated matrix at α: A(α), P(α) evaluated numerically, then the blocks
        w = np.array([1.0])
        for a in alphas:
            w = np.outer(w, a).reshape(-1)
        A_a = sum(wv * values[f"A_{v}"] for v, wv in enumerate(w))
        P_a = sum(_monomial(alphas, k) * values["P_" + "_".join("".join(map(str, p)) for p in k)]
                  for k in multi_exponents(sizes, (degree,) * len(sizes)))
        stated = np.block([[P_a @ A_a + A_a.T @ P_a + A_a.T @ P_a @ A_a, (values["C"] @ P_a).T],
                           [values["C"] @ P_a, -2.5 * np.eye(2)]])
        ev = NumericEvaluator({}, values, {}, None)
        ev.params = {}
        summed = np.zeros_like(stated)
        for m, lower in coefficients:
            blocks = [[ev.visit(b.xreplace({g: 2.5})) for b in row] for row in lower]
            M = np.block([[blocks[0][0], blocks[1][0].T], [blocks[1][0], blocks[1][1]]])
            summed += _monomial(alphas, m) * M
        assert np.allclose(summed, stated, rtol=1e-10, atol=1e-10)


def test_a_non_polynomial_term_is_refused_at_declaration():
    from lmidsl import TheoremDefinitionError
    thm = RobustTheorem("t.bad", "t", Source("a", "b"), time="continuous")
    n = thm.dim("n")
    alpha = thm.simplex("alpha")
    A = thm.data("A", n, n, over=alpha)
    P = thm.var("P", n, kind="symmetric", over=alpha)
    with pytest.raises(TheoremDefinitionError, match=r"t.bad: LMI \(bad\): .* is not polynomial"):
        thm.lmi("(bad)", [[He(P * A.I)]])
    assert thm.lmis == []


# -- the theorem -------------------------------------------------------------------------------------
def _stability(time="continuous"):
    thm = RobustTheorem(f"t.hpd_{time}", "t", Source("a", "b"), time=time)
    n = thm.dim("n")
    alpha = thm.simplex("alpha")
    A = thm.data("A", n, n, over=alpha)
    P = thm.var("P", n, kind="symmetric", over=alpha)
    thm.lmi("(HPPD)", [[He(P * A)]] if time == "continuous" else [[-P], [P * A, -P]])
    thm.positive(P)
    thm.feasibility()
    return thm


def test_members_have_the_coefficients_and_the_parameters_select_them():
    thm = get_theorem("textbook.hpd_stability_ct")
    data = random_polytope(1, n=3, vertices=4)
    for g, d in ((0, 0), (2, 1), (3, 2)):
        inst = make_instance(thm, data=data, overrides={"degree": g, "polya": d})
        member = inst.theorem
        assert len(member.var_decl) == comb(4 + g - 1, g)                       # P_k, |k| = g
        assert len(member.lmis) == comb(4 + g + d, g + 1 + d) + comb(4 + g + d - 1, g + d)
        assert member.robust.degree == g and member.robust.polya == d
        assert np.array_equal(inst.data["A_3"], np.asarray(data["vertices"][2]["A"]))
    for bad in ({"degree": 1.5}, {"degree": -1}, {"polya": 99}):
        with pytest.raises(InputError):
            make_instance(thm, data=data, overrides=bad)


def test_proved_lmis_are_the_coefficient_lmis():
    data = spread_polytope(2302, 2, 3, "continuous", 0.5)
    sol = solve("textbook.hpd_stability_ct", data=data, overrides={"degree": 2, "polya": 1})
    assert sol.verdict.certified, sol.verdict.reasons
    labels = {r.label for r in sol.lmis}
    assert labels == {l.label for l in sol.instance.theorem.lmis}
    assert all("α^" in label for label in labels) and all(r.proof == "proved" for r in sol.lmis)
    assert [c.name for c in sol.checks] == ["simplex grid"] and sol.checks[0].passed


def test_the_grid_check_refutes_an_unstable_polytope():
    """The check a gallery theorem runs fails (and so does the verdict) when some α is unstable,
    whatever the LMIs said: A(α) of two Hurwitz vertices with an unstable midpoint."""
    from types import SimpleNamespace
    from lmidsl.certify.simplex_grid import grid_check
    a = 3.0     # midpoint [[-1, a/2], [a/2, -1]] has the eigenvalue a/2 - 1 > 0
    vertices = [{"A": [[-1.0, a], [0.0, -1.0]]}, {"A": [[-1.0, 0.0], [a, -1.0]]}]
    inst = make_instance("textbook.hpd_stability_ct", data={"vertices": vertices})
    result = grid_check()(SimpleNamespace(instance=inst, gamma=None, design=None))
    assert not result.passed
    assert result.details["worst_alpha"][0] == pytest.approx([0.5, 0.5], abs=1e-4)
    assert result.details["worst_value"] == pytest.approx(a / 2 - 1, abs=1e-6)


def test_multi_simplex_domain():
    thm = RobustTheorem("t.ms", "t", Source("a", "b"), time="continuous")
    n = thm.dim("n")
    a, b = thm.simplex("alpha", size="Na"), thm.simplex("beta", size="Nb")
    A = thm.data("A", n, n, over=(a, b))
    P = thm.var("P", n, kind="symmetric", over=(a, b))
    thm.lmi("(HPPD)", [[He(P * A)]])
    thm.positive(P)
    thm.feasibility()
    rng = np.random.default_rng(1)
    A0 = rng.standard_normal((3, 3))
    A0 -= (max(np.linalg.eigvals(A0).real) + 1) * np.eye(3)
    E1, E2 = rng.standard_normal((3, 3)), rng.standard_normal((3, 3))
    V = [{"A": (A0 + s1 * E1 + s2 * E2).tolist()} for s1 in (-0.4, 0.4) for s2 in (-0.4, 0.4)]
    inst = make_instance(thm, data={"vertices": V, "Na": 2, "Nb": 2, "degree": 1})
    assert len(inst.theorem.var_decl) == 4 and inst.theorem.robust.sizes == (2, 2)
    assert _lmis_proved(solve_instance(inst, certify=False))
    ev = grid_evidence(inst)
    assert not ev.refutes and ev.worst_value < 0
    with pytest.raises(InputError, match="4 vertices, but 3"):
        make_instance(thm, data={"vertices": V[:3], "Na": 2, "Nb": 2})


# -- soundness and the gain with the degree (generated polytopes) -----------------------------------
def _threshold(case, resolution=12):
    """The t at which the grid first finds an unstable point (bisection)."""
    seed, n, N, time = case

    def stable(t):
        return not grid_evidence(spread_polytope(seed, n, N, time, t)["vertices"], None, time,
                                 resolution=resolution).refutes
    lo, hi = 0.0, 1.0
    while stable(hi):
        lo, hi = hi, 2 * hi
        assert hi < 100, "no unstable point found: choose another case"
    for _ in range(16):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


@pytest.mark.slow
@pytest.mark.parametrize("case,inside,expected", [
    ((2302, 2, 3, "continuous"), 0.97, {(0, 0): False, (1, 0): True, (2, 1): True}),
    ((2300, 2, 3, "discrete"), 0.7, {(0, 0): False, (1, 0): False, (2, 1): True}),
])
def test_stable_vertices_unstable_interior_are_never_certified(case, inside, expected):
    """Vertices stable for every t (spread_polytope); t* where the grid first finds an unstable
    point.  Inside (t < t*): robustly stable by the grid, not quadratically stable, certified by
    a degree high enough (discrete time: the affine P(α) fails where degree 2 with Pólya 1
    succeeds).  Outside (1.05 t*): an unstable point inside the simplex, never certified."""
    seed, n, N, time = case
    t_star = _threshold(case)
    thm = "textbook.hpd_stability_ct" if time == "continuous" else "textbook.hpd_stability_dt"
    inside_vertices = spread_polytope(seed, n, N, time, inside * t_star)["vertices"]
    assert not grid_evidence(inside_vertices, None, time).refutes
    certified = {gd: _lmis_proved(solve(thm, data={"vertices": inside_vertices},
                                        overrides={"degree": gd[0], "polya": gd[1]}, certify=False,
                                        diagnose=False)) for gd in expected}
    assert certified == expected
    # just outside: stable vertices, an unstable interior point; never certified
    t = 1.05 * t_star
    vertices = spread_polytope(seed, n, N, time, t)["vertices"]
    ev = grid_evidence(vertices, None, time)
    level = 0.0 if time == "continuous" else 1.0
    assert ev.refutes and all(v < level for v in ev.vertex_values)     # the grid's unstable α, inside
    assert max(max(a) for a in ev.worst_alpha) < 1 - 1e-6
    for g, d in ((0, 0), (1, 0), (2, 1), (3, 1)):
        sol = solve(thm, data={"vertices": vertices}, overrides={"degree": g, "polya": d}, certify=False,
                    diagnose=False)
        assert not _lmis_proved(sol), (g, d)


# -- robust performance ------------------------------------------------------------------------------
def test_robust_hinf_bound_between_grid_maximum_and_affine_bound():
    data = random_polytope(11, n=3, vertices=3, spread=0.8, inputs=1, outputs=1)
    for v in data["vertices"]:
        v["D"] = [[0.0]]
    gammas = {}
    for g in (0, 1, 2):
        sol = solve("textbook.hpd_hinf_ct", data=data, overrides={"degree": g}, certify=False)
        assert _lmis_proved(sol)
        gammas[g] = sol.gamma
    ev = grid_evidence(make_instance("textbook.hpd_hinf_ct", data=data), gammas[2], measure="hinf",
                       max_points=400)
    assert not ev.refutes
    assert ev.worst_value <= gammas[2] * (1 + 1e-6)
    assert gammas[2] <= gammas[1] * (1 + 1e-6) and gammas[1] <= gammas[0] * (1 + 1e-6)


def test_robust_h2_bound_above_the_grid_maximum():
    data = random_polytope(12, n=3, vertices=2, spread=0.5, inputs=2, outputs=1)
    sol = solve("textbook.hpd_h2_ct", data=data, overrides={"degree": 1})
    assert sol.verdict.certified, sol.verdict.reasons
    ev = grid_evidence(sol.instance, sol.gamma, measure="h2", max_points=400)
    assert not ev.refutes and ev.worst_value <= sol.gamma * (1 + 1e-6)
    assert sol.gamma <= 1.05 * ev.worst_value                    # and not far above here


@pytest.mark.parametrize("theorem,time", [("textbook.hpd_sf_dt", "discrete"), ("textbook.hpd_sf_ct", "continuous")])
def test_robust_state_feedback_gain_stabilises_the_polytope(theorem, time):
    data = random_polytope(3, n=3, vertices=3, time=time, inputs=1, margin=-1.0, spread=0.3)
    sol = solve(theorem, data=data, overrides={"degree": 2}, certify=False)
    assert _lmis_proved(sol)
    K = np.asarray(sol.design["K"])
    loop = [{"A": np.asarray(v["A"]) + np.asarray(v["B"]) @ K} for v in data["vertices"]]
    ev = grid_evidence(loop, None, time)
    assert not ev.refutes
    open_loop = grid_evidence([{"A": v["A"]} for v in data["vertices"]], None, time)
    assert open_loop.refutes                                     # the gain did something


# -- the margin ----------------------------------------------------------------------------------------
def test_margin_by_bisection_below_the_grid_margin_and_growing_with_the_degree():
    parts = random_polytope(5, n=3, vertices=3, time="continuous", spread=1.0, margin=1.0, centre=True)
    A0 = parts["A0"]
    data = {"A0": A0.tolist(), "vertices": [{"dA": (np.asarray(v["A"]) - A0).tolist()} for v in parts["vertices"]]}

    def grid_stable(rho):
        V = [{"A": A0 + rho * np.asarray(v["dA"])} for v in data["vertices"]]
        return not grid_evidence(V, None, "continuous", resolution=20).refutes
    lo, hi = 0.0, 10.0
    for _ in range(30):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if grid_stable(mid) else (lo, mid)
    margins = []
    for g in (0, 1, 2):
        inst = make_instance("textbook.hpd_margin_ct", data=data, overrides={"degree": g})
        res = bisect(inst, lower=0.0, upper=10.0, tol=1e-3)
        assert res.holds and res.infeasible_end - res.feasible_end <= 1e-3
        margins.append(res.feasible_end)
    assert margins[0] <= margins[1] + 1e-3 and margins[1] <= margins[2] + 1e-3
    assert margins[2] <= hi + 1e-9          # never above the true margin (the grid's, an upper bound)


# -- printing --------------------------------------------------------------------------------------------
def test_latex_of_the_statement_and_of_the_coefficients():
    thm = get_theorem("textbook.hpd_stability_ct")
    text = robust_statement_latex(thm)
    assert r"P(\alpha) A(\alpha) + A(\alpha)^{T} P(\alpha) < 0" in text
    assert r"P(\alpha) = \sum_{|k| = g} \alpha^{k} P_{k}" in text
    assert r"\text{for all } \alpha \in \Lambda_{N}" in text
    member = thm.member((2,), 1, 1)
    text = robust_statement_latex(thm, member)
    assert "homogeneous of degree 2, times" in text and "4 coefficient LMIs" in text
    coefficients = coefficient_lmis_latex(member)
    assert (r"P_{10} A_{1} + A_{1}^{T} P_{10} + P_{10} A_{2} + A_{2}^{T} P_{10} + P_{01} A_{1} + "
            r"A_{1}^{T} P_{01} < 0 \qquad \text{(HPPD), } \alpha^{(21)}") in coefficients


def test_grid_points_cover_the_simplex():
    pts = simplex_points(3, 4)
    assert len(pts) == comb(3 + 4 - 1, 4) and np.allclose(pts.sum(axis=1), 1) and pts.min() >= 0


# -- a published number: YALMIP's robust Pólya test --------------------------------------------------
def test_yalmip_robust_polya_example():
    """YALMIP's test suite, test_robust_4.m (github.com/yalmip/YALMIP): A(t) = [[-1, 1 + t1 + 0.1 t2],
    [0, -2 + 0.9 t1]], t in the simplex, P(t) = t1 P1 + t2 P2, A'P + PA ⪯ −I, P ⪰ 0, min trace P(t)
    (the worst case over t), robust.polya = 1: YALMIP asserts max(tr P1, tr P2) = 1.8203 (±1e-2).
    Here stated once in α; the vertices are A at t = (1, 0) and (0, 1)."""
    thm = RobustTheorem("t.yalmip", "YALMIP test_robust_4", Source("YALMIP", "test_robust_4.m"),
                        time="continuous", degree=1, polya=1)
    n = thm.dim("n")
    alpha = thm.simplex("alpha")
    A = thm.data("A", n, n, over=alpha)
    P = thm.var("P", n, kind="symmetric", over=alpha)
    tau = thm.scalar("tau")
    thm.lmi("(Lyapunov)", [[He(P * A) + I]], sense="<=")
    thm.lmi("(P)", [[P]], sense=">=")
    thm.lmi("(objective)", [[(tau - sp.Trace(P)) * I]], sense=">=", sizes=[1])
    thm.minimize(tau)
    vertices = [{"A": [[-1, 2], [0, -1.1]]}, {"A": [[-1, 1.1], [0, -2]]}]
    sol = solve(thm, data={"vertices": vertices}, certify=False)
    assert sol.ok
    traces = [np.trace(sol.values["P_10"]), np.trace(sol.values["P_01"])]
    assert max(traces) == pytest.approx(1.8203, abs=1e-4)
    assert sol.values["tau"] == pytest.approx(max(traces), rel=1e-6)
