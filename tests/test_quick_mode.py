"""Quick mode (issue 28): numpy arrays written directly in LMIs are constant data, ``Theorem(id)``
needs only an id, ``thm.lmi(rows)`` labels itself, and ``lmidsl.solve(thm)`` solves a theorem
with no declared example.  Every γ is compared with python-control's H∞ norm."""
from __future__ import annotations

import numpy as np
import pytest
from sympy import sqrt

import lmidsl
from lmidsl import I, Theorem
from lmidsl.render.latex import lmi_latex
from lmidsl.symbolic.symbols import ConstantMatrix

control = pytest.importorskip("control")


def quick_brl(A, B, C, D, name):
    thm = Theorem(name, time="continuous")
    P, g = thm.var("P", A.shape[0], kind="symmetric"), thm.scalar("g")
    thm.lmi([[A.T * P + P * A], [B.T * P, -g * I], [C, D, -I]])
    thm.lmi([[P]], sense=">")
    return thm.minimize(g, performance=("gamma", sqrt(g)))


def random_stable(rng, n, m, p):
    A = rng.standard_normal((n, n))
    A -= (max(np.linalg.eigvals(A).real) + 0.3 + rng.random()) * np.eye(n)
    return A, rng.standard_normal((n, m)), rng.standard_normal((p, n)), 0.3 * rng.standard_normal((p, m))


@pytest.mark.parametrize("seed", range(6))
def test_quick_bounded_real_lemma_gives_python_controls_norm(seed):
    rng = np.random.default_rng(seed)
    n, m, p = 2 + seed % 3, 1 + seed % 2, 1 + (seed + 1) % 2
    A, B, C, D = random_stable(rng, n, m, p)
    thm = quick_brl(A, B, C, D, f"quick.brl{seed}")
    assert [l.label for l in thm.lmis] == ["(1)", "(2)"]          # labelled in order
    assert list(thm.examples) == ["data"]                         # the constants are its data
    sol = lmidsl.solve(thm)
    norm = control.norm(control.ss(A, B, C, D), "inf")
    assert sol.proved, sol
    assert abs(sol.gamma - norm) <= 1e-5 * norm, (sol.gamma, norm)


def test_constants_are_shared_and_transposes_recognised():
    A = np.array([[0.0, 1.0], [-2.0, -0.7]])
    thm = Theorem("quick.shared")
    P = thm.var("P", 2, kind="symmetric")
    thm.lmi([[A.T * P + P * A]])
    constants = [s for s in thm.lmis[0].symbols() if isinstance(s, ConstantMatrix)]
    assert len(constants) == 1                                    # A and A.T: one constant
    assert np.array_equal(np.array(thm.examples["data"].data[constants[0].name]), A)
    latex = lmi_latex(thm, "(1)")
    name = constants[0].latex_name
    assert f"{name}^{{T}} P" in latex and f"P {name}" in latex, latex
    assert thm.title == "quick.shared"                            # an id is enough


def test_quick_mode_errors_name_the_lmi_and_block():
    thm = Theorem("quick.bad")
    P = thm.var("P", 2, kind="symmetric")
    with pytest.raises(lmidsl.LmidslError, match=r"quick.bad: LMI \(1\).*\(2,1\)"):
        thm.lmi([[P], [np.ones((3, 3)), -I]])              # a 3×3 constant below a 2×2 block
