"""Seed 000 (Wang et al.), Theorem 3 / Corollary 1 / Theorem 1, against the paper's printed values.

Tolerances: γ within 0.5 % of the printed value (the paper prints 4 digits and used LMI Lab);
the recovered full-order filter within 5e-3 of the printed matrices (4 printed decimals plus
solver differences); transfer functions compared on the unit circle, since realisations are
only unique up to similarity.
"""
from __future__ import annotations

import numpy as np
import pytest

import lmidsl
from lmidsl.theorem.registry import get_theorem

PRINTED_FULL = {"Af": [[-0.0069, 0.2865], [-0.9725, 0.4557]], "Bf": [[-0.0186], [-0.9235]],
                "Cf": [[-0.9963, -1.9624]]}
PLANT = {"A": [[0.0, 0.3], [-0.2, 0.4]], "B": [[0.0], [1.0]], "C": [[1.0, 0.0]], "D": [[1.0]],
         "L": [[1.0, 2.0]]}


def freq_response(Af, Bf, Cf, points=64):
    Af, Bf, Cf = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (Af, Bf, Cf))
    zs = np.exp(1j * np.linspace(0, np.pi, points))
    return np.array([(Cf @ np.linalg.solve(z * np.eye(Af.shape[0]) - Af, Bf)).ravel() for z in zs])


@pytest.fixture(scope="module", params=["CLARABEL", "CVXOPT"])
def full(request):
    return lmidsl.solve("wang_l2linf.thm3", example="paper-full", solver=request.param)


def test_full_order_gamma_matches_print(full):
    assert full.ok and full.certified
    assert full.gamma == pytest.approx(0.3373, rel=5e-3)


def test_full_order_filter_matches_print(full):
    for name, printed in PRINTED_FULL.items():
        np.testing.assert_allclose(full.recovered[name], printed, atol=5e-3, err_msg=name)
    ours = freq_response(*(full.recovered[k] for k in ("Af", "Bf", "Cf")))
    paper = freq_response(*(PRINTED_FULL[k] for k in ("Af", "Bf", "Cf")))
    assert np.max(np.abs(ours - paper)) < 2e-2 * np.max(np.abs(paper))


def test_full_order_certified_by_theorem1(full):
    assert full.certified  # every LMI's largest eigenvalue is negative at the returned point
    assert full.analysis.theorem == "wang_l2linf.thm1"
    assert full.analysis.passed
    assert full.analysis.gamma == pytest.approx(full.gamma, rel=1e-3)
    assert full.inverted and full.inverted[0]["matrix"] == "V2" and full.inverted[0]["cond"] < 1e3


@pytest.mark.parametrize("solver", ["CLARABEL", "CVXOPT"])
def test_reduced_order_gamma_matches_print(solver):
    sol = lmidsl.solve("wang_l2linf.thm3", example="paper-reduced", solver=solver)
    assert sol.optimum_level == pytest.approx(2.0103, rel=5e-3)       # the synthesis optimum, as printed
    assert sol.recovered["Af"].shape == (1, 1)
    # Theorem 3 is only sufficient for k < n: the analysis certifies a γ at or below the bound
    assert sol.analysis.passed and sol.analysis.gamma <= sol.optimum_level * (1 + 1e-3)
    assert sol.gamma == sol.analysis.gamma                              # the headline is the design's


def test_printed_filters_pass_theorem1_at_printed_gamma():
    full = lmidsl.solve("wang_l2linf.thm1", example="paper-full-printed")
    assert full.gamma == pytest.approx(0.3373, rel=5e-3)
    reduced = lmidsl.solve("wang_l2linf.thm1", example="paper-reduced-printed")
    assert reduced.certified and reduced.gamma <= 2.0103


def test_override_rbar_gives_a_different_certified_optimum():
    base = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    worse = lmidsl.solve("wang_l2linf.thm3", example="paper-full", overrides={"rbar": 0.6})
    assert worse.params["rbar"] == 0.6 and worse.params["a"] == pytest.approx(0.24)
    # fewer measurements arrive: the optimal level must get worse, and stay certified
    assert worse.gamma > base.gamma * 1.05
    assert worse.analysis.passed and worse.analysis.gamma == pytest.approx(worse.gamma, rel=1e-3)


def test_rbar_approaching_one_stays_certified():
    """As r̄ → 1 the loss variance a → 0; the optimum improves and stays certified (r̄ = 1 itself
    is refused: the printed LMI's diagonal blocks a(P − V − Vᵀ) vanish there)."""
    near = lmidsl.solve("wang_l2linf.thm3", example="paper-full", overrides={"rbar": 0.99})
    base = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    assert near.ok and near.certified and near.analysis.passed
    assert near.gamma < base.gamma


ORDER3 = {"A": [[0.5, 0.2, 0.0], [-0.1, 0.3, 0.4], [0.0, -0.2, 0.6]], "B": [[0.1], [0.0], [1.0]],
          "C": [[1.0, 0.0, 1.0]], "D": [[0.5]], "L": [[1.0, 1.0, 0.0]], "rbar": 0.7}


@pytest.mark.parametrize("k", [3, 2, 1])
def test_order3_plant_all_orders_certified(k):
    E = np.eye(3)[:, :k].tolist()
    sol = lmidsl.solve("wang_l2linf.thm3", data={**ORDER3, "E": E})
    assert sol.ok and sol.certified
    assert sol.recovered["Af"].shape == (k, k)
    assert sol.analysis.passed


def test_order3_full_order_beats_reduced_orders():
    """A filter of order k < n embeds in order n with the same transfer function, and full-order
    Theorem 3 is exact for Theorem 2, so the full-order optimum is a lower bound for every k."""
    gammas = {k: lmidsl.solve("wang_l2linf.thm3", data={**ORDER3, "E": np.eye(3)[:, :k].tolist()}).gamma
              for k in (3, 2, 1)}
    assert gammas[3] <= gammas[2] * (1 + 1e-4)
    assert gammas[3] <= gammas[1] * (1 + 1e-4)


def test_corollary1_one_vertex_equals_theorem3():
    cor = lmidsl.solve("wang_l2linf.cor1", example="paper-one-vertex")
    thm = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    assert cor.gamma == pytest.approx(thm.gamma, rel=1e-5)


def test_corollary1_two_vertices_is_robust():
    sol = lmidsl.solve("wang_l2linf.cor1", example="two-vertex")
    vertex_gammas = []
    for vertex in get_theorem("wang_l2linf.cor1").examples["two-vertex"].vertices:
        vertex_gammas.append(lmidsl.solve("wang_l2linf.thm3", data={**vertex, "E": np.eye(2).tolist(),
                                                                   "rbar": 0.8}).gamma)
    # one filter for both vertices cannot beat the best filter of either vertex
    assert sol.gamma >= max(vertex_gammas) * (1 - 1e-4)
    assert {r.vertex for r in sol.lmis} == {1, 2} and all(r.proof == "proved" for r in sol.lmis)
    assert sol.analysis.passed and len(sol.analysis.per_vertex) == 2
    # the analysis holds at each vertex with its own P: it does not cover the polytope
    assert sol.analysis.coverage == "vertex-wise" and sol.verdict.word == "vertex-wise"
    assert not sol.verdict.certified
