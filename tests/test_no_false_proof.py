"""No false proof (issue 33): adversarial user theorems against the proved bracket.

Every proved end is compared with an optimum computed independently, in exact rational arithmetic
from the decimals the theorem was written with (``fractions.Fraction``), never with a solver's
word: affine and solved performance maps with negative optima, maximised maps (√β, 1/δ), a map
that is not monotone across the bracket, a theorem changed between two solves, data that cancel
as written but not as compiled (both for an optimum and for feasibility), a weakly driven mode
that python-control cannot measure, a constant LMI on every backend, and a property test over
random small theorems."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings, strategies as st

import lmidsl
from lmidsl import Theorem
from lmidsl.errors import ProofConflict
from lmidsl.certify.performance import objective_map, performance_bound, performance_side
from lmidsl.certify.verdict import bracket

I1 = sp.Identity(1)


def _scalar_theorem(name: str, floor: str, performance) -> Theorem:
    """min g subject to g > floor (a 1×1 LMI), the performance a function of g."""
    thm = Theorem(name)
    g = thm.scalar("g")
    c = thm.data("c", 1, 1)
    thm.lmi([[c - g * I1]])
    thm.minimize(g, performance=("p", performance(g)))
    thm.example("x", {"c": [[float(floor)]]})
    return thm


def _contains(box: dict, exact: Fraction) -> None:
    """Every proved end of ``box`` on the right side of the exact optimum."""
    if box["lower_proved"]:
        assert Fraction(box["lower"]) <= exact, (box, exact)
    if box["upper_proved"]:
        assert Fraction(box["upper"]) >= exact, (box, exact)


@pytest.mark.parametrize("floor, performance, exact", [
    ("-3", lambda g: 2 * g, Fraction(-6)),                  # affine, negative optimum
    ("-3", lambda g: -5 * g + 1, Fraction(16)),              # decreasing affine: a maximised reading
    ("0.1", lambda g: sp.sqrt(g), None),                     # γ = √g
    ("-2.5", lambda g: g / 3 - sp.Rational(1, 7), Fraction(-5, 6) - Fraction(1, 7)),
])
def test_affine_and_root_maps_bracket_the_exact_optimum(floor, performance, exact):
    sol = lmidsl.solve(_scalar_theorem("adv.map", floor, performance))
    box = sol.verdict.bracket
    assert box["lower_proved"] and box["upper_proved"], box
    if exact is None:                                          # √0.1: compare in balls
        from flint import arb
        root = arb("0.1").sqrt()
        assert box["lower"] <= float(root.lower()) and box["upper"] >= float(root.upper())
    else:
        _contains(box, exact)
        assert float(box["upper"] - box["lower"]) <= 1e-5 * max(1.0, abs(float(exact)))


def test_a_solved_map_with_a_negative_optimum():
    """min 2h with performance γ = h (sympy solves the objective for h): optimum −3."""
    thm = Theorem("adv.solved")
    h, c = thm.scalar("h"), thm.data("c", 1, 1)
    thm.lmi([[c - h * I1]])
    thm.minimize(2 * h, performance=("gamma", h))
    thm.example("x", {"c": [[-3.0]]})
    box = lmidsl.solve(thm).verdict.bracket
    assert box["lower_proved"] and box["upper_proved"]
    _contains(box, Fraction(-3))


@pytest.mark.parametrize("kind", ["sqrt_beta", "one_over_delta"])
def test_maximised_maps_get_the_right_direction(kind):
    """A maximised performance written as a monotone map: the ellipsoid radius √β (max β ≤ 4,
    radius 2) and the sector bound k = 1/δ (min δ ≥ 1/4, k = 4): the point is the lower end."""
    thm = Theorem(f"adv.{kind}")
    c = thm.data("c", 1, 1)
    if kind == "sqrt_beta":
        beta = thm.scalar("beta")
        thm.lmi([[beta * I1 - c]])                  # β < c
        thm.minimize(-beta, performance=("r", sp.sqrt(beta)))
        thm.example("x", {"c": [[4.0]]})
        exact = Fraction(2)
    else:
        delta = thm.scalar("delta")
        thm.lmi([[c - delta * I1]])                 # δ > c
        thm.minimize(delta, performance=("k", 1 / delta))
        thm.example("x", {"c": [[0.25]]})
        exact = Fraction(4)
    sol = lmidsl.solve(thm)
    box = sol.verdict.bracket
    assert box["maximised"], box
    assert box["lower_proved"] and box["upper_proved"], box
    _contains(box, exact)
    assert "not a monotone" not in sol.verdict.bracket_line()


def test_a_map_not_monotone_across_the_bracket_gives_no_end():
    """p = (g + 3)² at the optimum g* = −3: f' changes sign inside [L, U] — no bracket is claimed."""
    sol = lmidsl.solve(_scalar_theorem("adv.square", "-3", lambda g: (g + 3) ** 2))
    box = sol.verdict.bracket
    assert not box["lower_proved"] and not box["upper_proved"], box
    assert "not proved monotone" in box["why"]


def test_monotonicity_is_proved_on_the_interval_only():
    thm = _scalar_theorem("adv.inverse", "0.25", lambda g: 1 / g)
    found = objective_map(thm, {})
    assert found.side(0.25, 2.0) == "upper"
    assert found.side(-1.0, 2.0) is None               # 1/g is not monotone across 0
    assert performance_side(thm, {}, None, 2.0) is None  # (−∞, 2] contains the pole
    assert performance_bound(thm, {}, -1.0, 2.0) is None


def test_a_theorem_changed_between_solves_is_mapped_afresh():
    """``minimize`` again on the same Theorem object (a notebook): the new map, not a cached one."""
    thm = _scalar_theorem("adv.mutated", "1", lambda g: g)
    first = lmidsl.solve(thm).verdict.bracket
    _contains(first, Fraction(1))
    g = next(iter(thm.objective.free_symbols))
    thm.minimize(g, performance=("p", 8 * g))
    second = lmidsl.solve(thm).verdict.bracket
    assert second["lower_proved"] and second["upper_proved"]
    _contains(second, Fraction(8))
    assert second["lower"] > 7.99


def _cancelling(kind: str) -> Theorem:
    """K·(a + b − c) with a, b, c = 0.1, 0.2, 0.3 and K = 1e20: 0 as written, ~5551 as compiled."""
    thm = Theorem(f"adv.cancel_{kind}")
    a, b, c, K = (thm.data(n, 1, 1) for n in "abcK")
    if kind == "optimum":
        g = thm.scalar("g")
        thm.lmi([[K * (a + b - c) + (1 - g) * I1]])        # g > 1 + K(a + b − c) = 1 as written
        thm.minimize(g, performance=("g", g))
    else:
        P = thm.var("P", 1, kind="symmetric")
        thm.lmi([[K * (a + b - c) * P - I1]])              # −1 < 0 as written: holds for every P
        thm.lmi([[I1 - P]])                                 # P > 1
    thm.example("x", {"a": [[0.1]], "b": [[0.2]], "c": [[0.3]], "K": [[1e20]]})
    return thm


def test_cancelling_data_optimum_is_not_proved_above_the_optimum_as_written():
    sol = lmidsl.solve(_cancelling("optimum"))
    box = sol.verdict.bracket
    _contains(box, Fraction(1))                            # the optimum as written is 1
    assert sol.verdict.word != "optimal"


def test_cancelling_data_feasible_as_written_is_never_proved_infeasible():
    sol = lmidsl.solve(_cancelling("feasibility"))
    assert sol.verdict.word != "infeasible"
    assert sol.infeasibility is None or not sol.infeasibility.proved
    # P = 2: the LMIs as written hold (the point proof's own balls)
    from lmidsl.numeric.proof import prove_block_matrix, PROVED
    inst = sol.instance
    for lmi in inst.theorem.lmis:
        verdict, _ = prove_block_matrix((inst.dims, {**inst.data, "P": [[2.0]]}, inst.params, None),
                                        lmi.negative_form(), True)
        assert verdict == PROVED


def test_a_weakly_driven_mode_is_not_refuted_by_a_failed_norm():
    """A = diag(−1e-9, −1), B = (1e-9, 1), C = (1, 1): H∞ norm 2; slycot returns ∞ — unavailable."""
    data = {"A": [[-1e-9, 0], [0, -1]], "B": [[1e-9], [1]], "C": [[1, 1]], "D": [[0]]}
    sol = lmidsl.solve("textbook.brl_ct", data=data)
    assert sol.verdict.word != "refuted"
    assert not any(e.refutes for e in sol.evidence)
    box = sol.verdict.bracket
    _contains(box, Fraction(2))


@pytest.mark.parametrize("backend", ["direct", "cvxpy", "picos"])
def test_a_constant_lmi_compiles_on_every_backend(backend):
    A = np.array([[-1.0, 0.5], [0.0, -2.0]])
    thm = Theorem("adv.constant")
    P = thm.var("P", 2, kind="symmetric")
    thm.lmi([[A.T @ P + P @ A]])
    thm.lmi([[P]], sense=">")
    thm.lmi([[-sp.Identity(2)]])
    sol = lmidsl.solve(thm, backend=backend)
    assert sol.proved and sol.verdict.certified


def test_a_proved_lower_end_above_a_proved_upper_end_is_an_internal_error():
    sol = lmidsl.solve(_scalar_theorem("adv.conflict", "2", lambda g: g))
    assert sol.bounds.proved
    sol.bounds.lower = sol.objective_bounds[1] + 1.0        # a forged bound above the point
    with pytest.raises(ProofConflict) as caught:
        bracket(sol)
    assert caught.value.exit_code == 3


# -- property: random small theorems ----------------------------------------------------------

decimals = st.integers(-400, 400).map(lambda k: Fraction(k, 100))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(b=decimals, shift=decimals, slope=st.sampled_from([Fraction(1), Fraction(2), Fraction(-1), Fraction(1, 3)]),
       cancel=st.booleans())
def test_random_theorems_never_prove_beyond_the_exact_optimum(b, shift, slope, cancel):
    """min g s.t. [[g − s, b], [b, 1]] ⪰ 0 (+ K·(x + y − z)·I with x + y = z as written, when
    ``cancel``): g* = s + b² exactly; performance p = slope·g, so p* = slope·(s + b²)."""
    thm = Theorem("adv.random")
    g = thm.scalar("g")
    B, S, K, x, y, z = (thm.data(n, 1, 1) for n in ("B", "S", "K", "x", "y", "z"))
    thm.lmi([[g * I1 - S - K * (x + y - z)], [B, I1]], sense=">")
    thm.minimize(g, performance=("p", sp.Rational(slope.numerator, slope.denominator) * g))
    thm.example("x", {"B": [[float(b)]], "S": [[float(shift)]], "K": [[1e18 if cancel else 0.0]],
                      "x": [[0.1]], "y": [[0.2]], "z": [[0.3]]})
    sol = lmidsl.solve(thm)
    box = sol.verdict.bracket
    if box is not None:
        _contains(box, slope * (shift + b * b))


def test_an_indexed_theorem_changed_after_a_solve_gets_a_new_member():
    """The member built for some sizes is not reused once the template gains an LMI."""
    from lmidsl import He
    thm = Theorem("adv.indexed", time="continuous")
    n = thm.dim("n")
    M = thm.index_set("modes")
    i = M.indices("i")
    A = thm.data("A", n, n, over=M)
    Y = thm.var("Y", n, kind="symmetric", over=M)
    thm.lmi("(1)", [[He(A[i] * Y[i])]], forall=i)
    inputs = {"modes": [{"A": [[-1.0]]}, {"A": [[-2.0]]}]}
    first = thm.specialise(inputs)
    thm.lmi("(2)", [[Y[i]]], sense=">", forall=i)
    second = thm.specialise(inputs)
    assert second is not first
    assert len(second.lmis) == 2 * len(first.lmis)
