"""Proved infeasibility (lmidsl.certify.infeasibility) against independent evidence.

* pan_impulsive.thm1 as printed (seed 003): proved infeasible (the certificate has ⟨Z, S⁰⟩ < 0:
  even the closure of the LMIs is empty);
* plants with an unstable mode that B2 cannot reach — the PBH test (rank [A − λI, B2] < n at an
  unstable λ, numpy) confirms no gain stabilises them — H∞ and H2 state feedback, both time
  domains: proved infeasible;
* feasible problems (random stabilisable plants, plants with an uncontrollable but stable mode,
  stable systems for the bounded real lemma, the paper examples that solve) never get a proof.
"""
from __future__ import annotations

import numpy as np
import pytest

from lmidsl.certify.infeasibility import prove_infeasible
from lmidsl.theorems.textbook.h2 import SF_DATA as H2_SF_DATA
from lmidsl.theorems.textbook.hinf_sf import SF_DATA
from lmidsl.theorems.textbook.plants import brl_cases, plant_cases, subset

from dual_models import pbh_unstabilisable, solved_model, unstabilisable_plant

TIMES = ("continuous", "discrete")
SHORT = {"continuous": "ct", "discrete": "dt"}


def _sf_theorems(time):
    return [(f"textbook.hinf_sf_{SHORT[time]}", SF_DATA), (f"textbook.h2_{SHORT[time]}_sf", H2_SF_DATA[time])]


def test_pan_impulsive_thm1_paper_is_proved_infeasible():
    model, sol = solved_model("pan_impulsive.thm1", "paper")
    cert = prove_infeasible(model)
    assert cert.proved, cert.why
    assert cert.pairing < 0 and cert.nonzero_blocks >= 1


#: (time, states, hidden states, the hidden block's least real part / modulus)
UNSTABILISABLE = {"continuous": [(3, 1, 0.5), (5, 1, 1.0), (4, 2, 0.5), (4, 1, 0.0)],
                  "discrete": [(3, 1, 1.3), (5, 1, 2.0), (4, 2, 1.3)]}


@pytest.mark.parametrize("time", TIMES)
def test_unstabilisable_plants_are_proved_infeasible(time):
    """An unreachable block with every eigenvalue unstable (or one on the boundary, continuous
    time: then only the strict LMIs are infeasible, the certificate has ⟨Z, S⁰⟩ = 0)."""
    rng = np.random.default_rng(17 if time == "continuous" else 18)
    for n, hidden, mode in UNSTABILISABLE[time]:
        d = unstabilisable_plant(rng, n, time, mode, hidden=hidden)
        assert pbh_unstabilisable(d["A"], d["B2"], time)
        for theorem, names in _sf_theorems(time):
            model, _ = solved_model(theorem, data=subset(d, names))
            cert = prove_infeasible(model)
            assert cert.proved, (theorem, n, hidden, mode, cert.why)
            assert cert.pairing <= 0 and (cert.pairing < 0 or cert.strict_trace > 0)


@pytest.mark.parametrize("time", TIMES)
def test_feasible_problems_get_no_infeasibility_proof(time):
    rng = np.random.default_rng(19 if time == "continuous" else 20)
    problems = []
    for _, plant in plant_cases(time, count=8):
        problems += [(theorem, subset(plant, names)) for theorem, names in _sf_theorems(time)]
    for _ in range(3):   # an uncontrollable but stable mode: stabilisable, feasible
        d = unstabilisable_plant(rng, 4, time, -0.5 if time == "continuous" else 0.5)
        assert not pbh_unstabilisable(d["A"], d["B2"], time)
        problems += [(theorem, subset(d, names)) for theorem, names in _sf_theorems(time)]
    problems += [(f"textbook.brl_{SHORT[time]}", d) for _, d in brl_cases(time)]
    for theorem, data in problems:
        model, sol = solved_model(theorem, data=data)
        cert = prove_infeasible(model)
        assert not cert.proved, (theorem, sol.status, cert.as_dict())


@pytest.mark.parametrize("theorem, example", [("wang_l2linf.thm3", "paper-full"),
                                              # paper-scale: five alternative SDPs of seed 001's
                                              # 16-variable problem, ~25 s of Clarabel
                                              pytest.param("li_delay_dropout.thm2", "paper",
                                                           marks=pytest.mark.slow),
                                              ("interconnected_delay.thm2", "paper")])
def test_solved_paper_examples_get_no_infeasibility_proof(theorem, example):
    model, sol = solved_model(theorem, example)
    assert sol.ok and sol.lmis_hold
    assert not prove_infeasible(model).proved


def test_conditioned_model_keeps_the_proof():
    """The congruence T N T (T ≻ 0) and the variable scaling leave the feasible set unchanged:
    the unstabilisable plant with B2, B1 × 1e4 and C1 × 1e-4 is proved infeasible as conditioned."""
    rng = np.random.default_rng(21)
    d = unstabilisable_plant(rng, 3, "continuous", 0.5)
    d = dict(d, B2=(1e4 * np.array(d["B2"])).tolist(), B1=(1e4 * np.array(d["B1"])).tolist(),
             C1=(1e-4 * np.array(d["C1"])).tolist())
    model, _ = solved_model("textbook.h2_ct_sf", data=subset(d, H2_SF_DATA["continuous"]),
                            conditioning=True, scaling="none")
    assert not model.equilibration.trivial
    cert = prove_infeasible(model)
    assert cert.proved, cert.why


def test_quadratic_stability_of_a_switching_pair_is_proved_infeasible():
    """textbook.quadstab_dt interval-3 (two Schur vertices, radii 0.86 and 0.94): a common
    quadratic Lyapunov function would make every product of the vertices contract, but a product
    of length ≤ 8 has spectral radius^(1/k) above 1 (a lower bound on the joint spectral radius,
    computed with numpy), so the LMIs are infeasible; the solve says so with a proof."""
    import itertools

    import lmidsl
    from lmidsl.pipeline import make_instance
    vertices = np.array(make_instance("textbook.quadstab_dt", "interval-3").data["A"], dtype=float)
    rho = lambda M: float(max(abs(np.linalg.eigvals(M))))
    assert max(rho(A) for A in vertices) < 1
    jsr_lower = max(rho(np.linalg.multi_dot([vertices[i] for i in word] + [np.eye(3)])) ** (1 / len(word))
                    for k in range(1, 9) for word in itertools.product(range(2), repeat=k))
    assert jsr_lower > 1.0
    sol = lmidsl.solve("textbook.quadstab_dt", "interval-3")
    assert sol.infeasibility is not None and sol.infeasibility.proved, sol.infeasibility
    assert sol.verdict.word == "infeasible"


def test_a_proved_infeasibility_ends_the_road():
    """A = diag(1, −2) has an unstable mode (numpy's eigenvalues), so no P ≻ 0 has AᵀP + PA ≺ 0:
    once the first route's "infeasible" is proved, no fallback route is tried (they could only
    fail to find a point; reproduce's infeasible rows spent two thirds of their time there)."""
    import lmidsl
    from lmidsl import Theorem
    A = np.array([[1.0, 0.0], [0.0, -2.0]])
    assert np.linalg.eigvals(A).real.max() > 0
    thm = Theorem("adv.unstable_lyapunov")
    P = thm.var("P", 2, kind="symmetric")
    thm.lmi([[A.T @ P + P @ A]])
    thm.lmi([[P]], sense=">")
    sol = lmidsl.solve(thm)
    assert sol.infeasibility is not None and sol.infeasibility.proved
    assert any(n.startswith("no other route tried") for n in sol.notes), sol.notes
    assert sol.verdict.word == "infeasible"
