"""A non-strict LMI active at the optimum is certified like a strict one, and `search` reports
the true best certified level.

The theorem: a peak bound of ẋ = Ax + Bw, ‖w(t)‖ ≤ 1 (Boyd et al. 1994, §6.1.3): for α > 0,
[[AᵀP + PA + αP, PB], [BᵀP, −αI]] ≺ 0 and P ≻ 0 make {xᵀPx ≤ 1} invariant, and the output
bound [[P, Cᵀ], [C, g I]] ⪰ 0 (written non-strict, as the paper does) gives ‖Cx‖² ≤ g on it.
For fixed α the infimum of g is λmax(C X Cᵀ), X the solution of the Lyapunov equation
(A + α/2 I)X + X(A + α/2 I)ᵀ + BBᵀ/α = 0 (X = P⁻¹ at the boundary): computed here with scipy,
independently of the LMIs.  The output bound is active at every optimum.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov
from sympy import sqrt

import lmidsl
from lmidsl import He, I, Source, Theorem
from lmidsl.pipeline import make_instance
from lmidsl.render.text import format_result
from lmidsl.studies.search import scalar_search

A = [[0.0, 1.0], [-2.0, -1.0]]
B = [[0.0], [1.0]]
C = [[1.0, 0.0]]


def _peak_theorem(name="t.peak"):
    thm = Theorem(name, "Peak bound", Source("Boyd et al. 1994", "§6.1.3"), time="continuous")
    n, m, p = thm.dim("n m p")
    a, b, c = thm.data("A", n, n), thm.data("B", n, m), thm.data("C", p, n)
    alpha = thm.param("alpha", latex=r"\alpha", domain=(0, 100))
    P = thm.var("P", n, kind="symmetric")
    g = thm.scalar("g")
    thm.lmi("(inv)", [[He(P * a) + alpha * P], [b.T * P, -alpha * I]])
    thm.lmi("(out)", [[P], [c, g * I]], sense=">=", strict=False)
    thm.positive(P)
    thm.minimize(g, performance=("peak", sqrt(g)))
    thm.example("osc", {"A": A, "B": B, "C": C}, params={"alpha": 0.5})
    return thm


def exact_g(alpha):
    a = np.array(A) + alpha / 2 * np.eye(2)
    X = solve_continuous_lyapunov(a, -np.array(B) @ np.array(B).T / alpha)
    return float(np.linalg.eigvalsh(np.array(C) @ X @ np.array(C).T).max())


def test_the_active_nonstrict_output_bound_is_certified_and_the_cost_stated():
    sol = lmidsl.solve(_peak_theorem(), example="osc", diagnose=False)
    g_star = exact_g(0.5)
    assert sol.verdict.certified, sol.notes
    g = sol.objective
    assert g_star * (1 - 1e-7) <= g <= g_star * (1 + 1e-4)       # feasible, hence ≥ the infimum
    out = [r for r in sol.lmis if r.label == "(out)"]
    assert out and all(r.max_eig < 0 and r.proof == "proved" for r in out)
    note = next(n for n in sol.notes if "non-strict LMI (out)" in n)
    assert "cost: objective" in note and "relative" in note


def test_search_reports_the_true_best_certified_level_under_the_performance_name():
    inst = make_instance(_peak_theorem("t.peak_search"), "osc", None, None)
    alphas = [0.2, 0.35, 0.5, 0.65, 0.8]
    result = scalar_search(inst, {"alpha": alphas}, workers=1, progress=False)
    exact = {a: np.sqrt(exact_g(a)) for a in alphas}
    for p in result.grid:
        assert p.proved, p
        assert p.value == pytest.approx(exact[p.params["alpha"]], rel=1e-4)
    best = result.best_proved
    a_star = min(exact, key=exact.get)
    assert best.params["alpha"] == a_star and best.value == pytest.approx(exact[a_star], rel=1e-4)
    text = format_result(result)
    assert "peak =" in text and "γ" not in text
