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
