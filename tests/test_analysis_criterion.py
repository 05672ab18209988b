"""The analysis certificate's criterion is inferred from the analysis theorem: a feasibility
analysis certifies a design by its LMIs proved ("feasible"), a minimising one by its level.

The design is judged independently by the closed loop's eigenvalues (numpy)."""
from __future__ import annotations

import numpy as np

import lmidsl
from lmidsl import He, Source, Theorem

A = [[0.0, 1.0], [2.0, -1.0]]
B = [[0.0], [1.0]]


def _pair(name, synthesis_minimises):
    cl = Theorem(f"{name}_cl", "Lyapunov", Source("t", "t"), time="continuous")
    n, m = cl.dim("n m")
    a, b, k = cl.data("A", n, n), cl.data("B", n, m), cl.data("K", m, n)
    P = cl.var("P", n, kind="symmetric")
    cl.lmi("(L)", [[He(P * (a + b * k))]])
    cl.positive(P)
    cl.feasibility()
    sf = Theorem(name, "stabilising state feedback", Source("t", "t"), time="continuous", designs="gain")
    n, m = sf.dim("n m")
    a, b = sf.data("A", n, n), sf.data("B", n, m)
    Y = sf.var("Y", n, kind="symmetric")
    W = sf.var("W", m, n)
    if synthesis_minimises:                 # min t: He(AY + BW) ⪯ t·I-like slack, a level with no analysis twin
        t = sf.scalar("t")
        sf.lmi("(S)", [[He(a * Y + b * W) - t * lmidsl.I]])
        sf.lmi("(B)", [[(t + 1) * lmidsl.I]], sense=">", sizes=[1])
        sf.minimize(t, performance=("t", t))
    else:
        sf.lmi("(S)", [[He(a * Y + b * W)]])
        sf.feasibility()
    sf.positive(Y)
    sf.recover(K=W * Y.I)
    sf.certified_by(cl, design=("K",))      # no criterion: inferred
    sf.example("unstable", {"A": A, "B": B})
    return sf


def test_a_feasibility_analysis_certifies_by_its_proved_lmis_without_a_declared_criterion():
    for minimises in (False, True):
        sol = lmidsl.solve(_pair(f"t.crit{int(minimises)}", minimises), example="unstable", diagnose=False)
        closed = np.array(A) + np.array(B) @ sol.design["K"]
        assert np.linalg.eigvals(closed).real.max() < 0
        assert sol.analysis.criterion == "feasible" and sol.analysis.passed
        assert sol.verdict.certified, sol.verdict.why


def test_a_minimising_analysis_keeps_the_level_criterion():
    from lmidsl.theorems.textbook import hinf_sf
    sol = lmidsl.solve(hinf_sf.hinf_sf_ct, example=next(iter(hinf_sf.hinf_sf_ct.examples)), diagnose=False)
    assert sol.analysis.criterion == "level"
    assert sol.analysis.gamma <= sol.analysis.synthesis_gamma * (1 + 1e-3)
