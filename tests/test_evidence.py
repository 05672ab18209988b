"""Claims tested against independent evidence (lmidsl.certify.evidence): a wrong robust theorem
(vertex-wise Lyapunov matrices, no coupling) is refuted on a polytope whose worst case is inside
it; the extended (slack-variable) bounded real lemma on the same polytope is certified at a level
at least the grid maximum; python-control's norms are the independent computation."""
from __future__ import annotations

import itertools
import json

import control
import numpy as np
import pytest

import lmidsl
from conftest import ROOT, run_cli

FIXTURE = str(ROOT / "tests" / "fixtures" / "robust_brl")


def _polytope(seed: int = 120) -> list:
    """Three stable 2-state discrete-time vertices (numpy seed 120): vertex norms ≤ 2.87, the
    norm inside the simplex reaches 5.44 near α = (0.56, 0.44, 0)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(3):
        A = rng.normal(size=(2, 2))
        A *= rng.uniform(0.5, 0.85) / max(abs(np.linalg.eigvals(A)))
        out.append({"A": A.tolist(), "B": [[1.0], [0.0]], "C": [[0.0, 1.0]], "D": [[0.0]]})
    return out


def _grid_max(vertices, resolution=40) -> float:
    """max over α = k/resolution of python-control's H∞ norm of Σ αᵢ (Aᵢ, B, C, D)."""
    best = 0.0
    for k in itertools.product(range(resolution + 1), repeat=2):
        if sum(k) > resolution:
            continue
        a = np.array([*k, resolution - sum(k)]) / resolution
        A = sum(w * np.array(v["A"]) for w, v in zip(a, vertices))
        sys = control.ss(A, vertices[0]["B"], vertices[0]["C"], vertices[0]["D"], True)
        best = max(best, control.norm(sys, "inf", tol=1e-10))
    return best


@pytest.fixture(autouse=True)
def _theorem_path(monkeypatch):
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", FIXTURE)


def test_the_polytope_has_its_worst_case_inside():
    vertices = _polytope()
    vertex_max = max(control.norm(control.ss(v["A"], v["B"], v["C"], v["D"], True), "inf") for v in vertices)
    assert _grid_max(vertices) > 1.8 * vertex_max


def test_a_vertex_wise_robust_claim_is_refuted(tmp_path):
    vertices = _polytope()
    sol = lmidsl.solve("robust.vertexwise_brl_dt", data={"vertices": vertices})
    assert all(r.proof == "proved" for r in sol.lmis)          # its LMIs do hold ...
    assert sol.verdict.word == "refuted" and not sol.verdict.certified   # ... its claim does not
    worst = sol.evidence[0]
    assert worst.refutes and worst.value > sol.gamma * 1.5
    assert worst.value >= _grid_max(vertices) * (1 - 1e-6)   # refined: at least a coarser grid's maximum
    path = tmp_path / "poly.json"
    path.write_text(json.dumps({"vertices": vertices}))
    code, out, err = run_cli("solve", "robust.vertexwise_brl_dt", "--data", str(path),
                             env={"LMIDSL_THEOREM_PATH": FIXTURE})
    assert code == 1, err
    assert "verdict: REFUTED" in out and "refutes" in out.replace("\n", " ")


def test_the_extended_bounded_real_lemma_covers_the_polytope():
    vertices = _polytope()
    sol = lmidsl.solve("robust.extended_brl_dt", data={"vertices": vertices})
    assert sol.verdict.certified and sol.verdict.word in ("certified", "optimal")
    assert sol.verdict.gamma >= _grid_max(vertices) * (1 - 1e-6)
    assert not sol.evidence[0].refutes


def test_the_extended_lemma_is_the_norm_on_one_vertex():
    v = _polytope()[0]
    sol = lmidsl.solve("robust.extended_brl_dt", data={"vertices": [v]})
    norm = control.norm(control.ss(v["A"], v["B"], v["C"], v["D"], True), "inf", tol=1e-12)
    assert sol.verdict.certified and norm <= sol.verdict.gamma <= norm * (1 + 1e-4)


def test_the_exact_gain_and_instability_agree_with_numpy_on_a_benign_system():
    """exact_gain (python-flint balls) against numpy's σ_max of C(jωI − A)⁻¹B + D in doubles on a
    well-conditioned system (both to 1e-12), and proved_unstable on a stable, an unstable and a
    marginal (eigenvalue 0: not provably outside) matrix, in both time domains."""
    from flint import arb
    from lmidsl.certify.evidence import exact_gain, proved_unstable
    from lmidsl.numeric.proof import decimal_ball, object_array
    rng = np.random.default_rng(7)
    A = rng.normal(size=(5, 5)) - 4 * np.eye(5)
    B, C, D = rng.normal(size=(5, 2)), rng.normal(size=(3, 5)), rng.normal(size=(3, 2))
    balls = {k: object_array(M, decimal_ball) for k, M in zip("ABCD", (A, B, C, D))}
    omegas = [0.0, 0.7, 3.0]
    expected = max(np.linalg.svd(C @ np.linalg.solve(1j * w * np.eye(5) - A, B) + D, compute_uv=False)[0]
                   for w in omegas)
    assert abs(exact_gain(balls, omegas, "continuous") - expected) <= 1e-12 * expected
    assert not proved_unstable(balls["A"], "continuous")
    assert proved_unstable(object_array(A + 8 * np.eye(5), decimal_ball), "continuous")
    assert not proved_unstable(object_array(np.diag([0.0, -1.0]), lambda x: arb(x)), "continuous")
    assert proved_unstable(object_array(np.diag([1.01, 0.5]), decimal_ball), "discrete")
    assert not proved_unstable(object_array(np.diag([0.99, 0.5]), decimal_ball), "discrete")
