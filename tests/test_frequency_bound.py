"""The frequency-response lower bound of a bounded-real-lemma optimum (lmidsl.certify.frequency_bound).

Independent references: SLICOT AB13DD's H∞ norm (the BRL optimum is its square) from above, and
σ_max(G(jω)) by numpy on a dense frequency grid from below — the proved bound on γ must lie between
the grid's maximum and the norm.  The adversarial theorems declare the bounded-real form but state
another LMI or another objective: the route must refuse them (a bound on the declared system would
be false for the LMI as stated)."""
from __future__ import annotations

import math
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lmidsl
from lmidsl import He, I, Theorem
from lmidsl.certify.frequency_bound import bounded_real_lmi, frequency_lower_bound
from lmidsl.numeric.instance import bind
from lmidsl.numeric.systems import hinf_norm

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks" / "stress"))
from cases import lists, system  # noqa: E402

NORM_SLACK = 1e-9       # AB13DD's relative accuracy (tol 1e-10) and rounding


def _grid_peak(A, B, C, D, time: str) -> float:
    """max σ_max(G) over a dense grid (a lower estimate of the H∞ norm, independent of SLICOT)."""
    if time == "continuous":
        points = 1j * np.concatenate([[0.0], np.logspace(-4, 4, 4000)])
    else:
        points = np.exp(1j * np.linspace(0.0, np.pi, 4000))
    n = A.shape[0]
    return max(np.linalg.svd(C @ np.linalg.solve(s * np.eye(n) - A, B) + D, compute_uv=False)[0] for s in points)


def _instance(theorem_id: str, data: dict):
    thm = lmidsl.get_theorem(theorem_id)
    return bind(thm, data)


@pytest.mark.parametrize("time", ["continuous", "discrete"])
@pytest.mark.parametrize("n,seed", [(6, 1), (16, 2), (32, 3)])
def test_the_bound_lies_between_a_grid_and_slycots_norm(time, n, seed):
    data = lists(system("random", seed, time, n=n, m=2, p=2))
    d = {k: np.atleast_2d(np.asarray(v, dtype=float)) for k, v in data.items()}
    theorem_id = "textbook.brl_ct" if time == "continuous" else "textbook.brl_dt"
    lower, how = frequency_lower_bound(_instance(theorem_id, data))
    norm = hinf_norm(d["A"], d["B"], d["C"], d["D"], time)
    grid = _grid_peak(d["A"], d["B"], d["C"], d["D"], time)
    assert math.sqrt(lower) <= norm * (1 + NORM_SLACK), (lower, norm)
    assert math.sqrt(lower) >= grid * (1 - 1e-12), (lower, grid, how)


def test_a_peak_at_zero_that_slycot_misses_is_still_bounded():
    """A = diag(−1e-9, −1), B = (1e-9, 1), C = (1, 1): G(0) = 2 exactly (SLICOT returns ∞)."""
    data = {"A": [[-1e-9, 0], [0, -1]], "B": [[1e-9], [1]], "C": [[1, 1]], "D": [[0]]}
    lower, _ = frequency_lower_bound(_instance("textbook.brl_ct", data))
    assert lower <= 4 and lower >= 4 * (1 - 1e-12)


def test_decimal_data_are_taken_as_written():
    """G(s) = 0.1/(s + 0.3): the norm is 1/3 exactly as written; the bound on g = γ² is ≤ 1/9."""
    data = {"A": [[-0.3]], "B": [[0.1]], "C": [[1.0]], "D": [[0.0]]}
    lower, _ = frequency_lower_bound(_instance("textbook.brl_ct", data))
    assert Fraction(lower) <= Fraction(1, 9)
    assert lower >= (1 / 9) * (1 - 1e-14)


def _declared(name: str, lmi_rows, objective=None, time: str = "continuous"):
    """A one-state theorem that declares the bounded-real form of (A, B, C, D) but states ``lmi_rows``."""
    thm = Theorem(f"adv.{name}", time=time)
    A, B, C, D = (thm.data(k, 1, 1) for k in "ABCD")
    P = thm.var("P", 1, kind="symmetric")
    g = thm.scalar("g")
    thm.lmi("(L)", lmi_rows(P, g, A, B, C, D))
    thm.positive(P)
    thm.minimize(objective(g) if objective else g, performance=("gamma", sp.sqrt(g)))
    thm.bounded_real_form(P, g, (A, B, C, D))
    thm.example("x", {"A": [[-1.0]], "B": [[1.0]], "C": [[1.0]], "D": [[0.0]]})
    return thm


def test_the_stated_form_is_recognised_however_it_is_written():
    thm = _declared("honest", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -g * I], [C, D, -I]])
    assert bounded_real_lmi(thm) is not None
    sol = lmidsl.solve(thm)
    assert sol.bounds.method == "frequency" and sol.bounds.proved
    box = sol.verdict.bracket
    assert box["lower"] <= 1.0 <= box["upper"] and box["upper"] - box["lower"] < 1e-5


@pytest.mark.parametrize("name,rows,objective,optimum", [
    # the level enters as 2g: the optimum is g = 1/2, the declared system's bound would say 1
    ("twice", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -2 * g * I], [C, D, -I]], None, 0.5),
    # the output enters halved: ‖G/2‖² = 1/4
    ("halved", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -g * I], [C / 2, D, -I]], None, 0.25),
    # the objective is g/4 (γ² = g still declared): the optimum of the objective is 1/4
    ("objective", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -g * I], [C, D, -I]], lambda g: g / 4, 0.25),
])
def test_a_form_the_lmi_does_not_state_gives_no_frequency_bound(name, rows, objective, optimum):
    thm = _declared(name, rows, objective)
    assert bounded_real_lmi(thm) is None
    sol = lmidsl.solve(thm)
    assert sol.bounds is None or sol.bounds.method != "frequency"
    assert sol.objective == pytest.approx(optimum, rel=1e-5)
    if sol.bounds is not None and sol.bounds.proved:
        assert sol.bounds.lower <= optimum * (1 + 1e-9)


def test_an_extra_lmi_only_raises_the_optimum():
    """P ⪰ 10 on top of the form: the optimum rises to min g = P²/(2P − 1) at P = 10, 100/19; the
    frequency bound stays the norm's 1, below it."""
    thm = _declared("extra", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -g * I], [C, D, -I]])
    P = thm.var_decl["P"].symbol
    thm.lmi("(floor)", [[P - 10 * I]], sense=">")
    assert bounded_real_lmi(thm) is not None
    sol = lmidsl.solve(thm)
    assert sol.objective == pytest.approx(100 / 19, rel=1e-5)
    assert frequency_lower_bound(sol.instance)[0] <= 1.0
    # loose by 5×: the dual route runs too, and its tighter bound is kept
    assert sol.bounds.proved and sol.bounds.method == "dual"
    assert 100 / 19 * (1 - 1e-5) <= sol.bounds.lower <= 100 / 19


def test_an_uncertain_system_gives_no_frequency_bound():
    """A + δ with |δ| ≤ 0.5 imposed at both vertices: the declared system is not one system."""
    thm = Theorem("adv.uncertain", time="continuous")
    A, B, C, D = (thm.data(k, 1, 1) for k in "ABCD")
    d = thm.uncertain("d", bound=0.5)
    P = thm.var("P", 1, kind="symmetric")
    g = thm.scalar("g")
    Ad = A + d * sp.Identity(1)
    thm.lmi("(L)", [[He(P * Ad)], [B.T * P, -g * I], [C, D, -I]])
    thm.positive(P)
    thm.minimize(g, performance=("gamma", sp.sqrt(g)))
    thm.bounded_real_form(P, g, (Ad, B, C, D))
    assert bounded_real_lmi(thm) is None


def test_a_form_with_a_variable_in_its_system_is_refused():
    thm = _declared("variable", lambda P, g, A, B, C, D: [[He(P * A)], [B.T * P, -g * I], [C, D, -I]])
    X = thm.var("X", 1, 1)
    form = thm.bounded_real
    thm.bounded_real_form(form.storage, form.level, (form.system[0], form.system[1], X, form.system[3]))
    assert bounded_real_lmi(thm) is None



def test_which_bound_record_is_kept():
    """The higher proved bound; of two unproved, the kept model's (first) reason, except that a
    dual's reason replaces the frequency route's."""
    from lmidsl.certify.dual_bound import DualBound, _preferred
    first, later = DualBound(why="first"), DualBound(why="later")
    assert _preferred(_preferred(None, first), later) is first
    frequency = DualBound(why="frequency", method="frequency")
    assert _preferred(frequency, later) is later
    low, high = DualBound(lower=1.0, proved=True), DualBound(lower=2.0, proved=True)
    assert _preferred(first, low) is low and _preferred(low, first) is low
    assert _preferred(low, high) is high and _preferred(high, low) is high
