"""Proved LMIs (lmidsl.numeric.proof): ball-arithmetic LDLᵀ at the returned point.

Each case has a known exact answer: the data are the decimals written (0.3 is 3/10), the
point's values are binary floats taken exactly, so float(0.3) − 3/10 < 0 is a theorem.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from flint import arb

import lmidsl
from lmidsl import Source, Theorem
from lmidsl.certify import certify_by_analysis
from lmidsl.numeric.instance import bind
from lmidsl.numeric.proof import NUMERICAL, PROVED, VIOLATED, negative_definite
from lmidsl.solver.solution import lmi_certificate


def _balls(rows):
    return np.array([[arb(x) for x in row] for row in rows], dtype=object)


def test_ldl_verdicts_on_exact_matrices():
    assert negative_definite(_balls([[-1, 0], [0, "-1e-40"]]))[0] == PROVED
    assert negative_definite(_balls([[-1, 0], [0, "1e-40"]]))[0] == VIOLATED
    # singular: eigenvalues 0 and −2; a ball cannot prove definiteness, nor refute it
    assert negative_definite(_balls([[-1, 1], [1, -1]]))[0] == NUMERICAL
    # indefinite only through the off-diagonal coupling: [[−1, 2], [2, −1]] has eigenvalue +1
    assert negative_definite(_balls([[-1, 2], [2, -1]]))[0] == VIOLATED


def _tiny_theorem(tag: str) -> Theorem:
    thm = Theorem(f"prooftest.{tag}", "X − D ≺ 0 and X ≻ 0", Source("test", "(1)"))
    n = thm.dim("n")
    D = thm.data("D", n, n)
    X = thm.var("X", n, kind="symmetric")
    thm.lmi("(1)", [[X - D]])
    return thm


def test_data_are_the_decimals_written_and_the_point_is_exact():
    thm = _tiny_theorem("decimal")
    inst = bind(thm, {"D": [[0.3]]})
    below = lmi_certificate(inst, {"D": np.array([[0.3]]), "X": np.array([[0.3]])}, prove=True)
    # float(0.3) = 0.299999999999999988898 < 3/10: X − D < 0 exactly, although numpy sees 0; the
    # reported λmax is then the one at the proof's precision: float(0.3) − 3/10 exactly
    exact = float(Fraction(0.3) - Fraction(3, 10))
    assert below[0].proof == PROVED and below[0].max_eig == pytest.approx(exact, rel=1e-12) and exact < 0
    above = lmi_certificate(inst, {"D": np.array([[0.3]]),
                                   "X": np.array([[math.nextafter(0.3, 1.0)]])}, prove=True)
    assert above[0].proof == VIOLATED


def test_a_square_root_parameter_is_a_ball():
    thm = Theorem("prooftest.sqrt", "x − √p·I ≺ 0", Source("test", "(1)"))
    n = thm.dim("n")
    thm.data("E", n, n)
    p = thm.param("p", domain=(0.0, 10.0))
    s = thm.derived("s", sp.sqrt(p))
    x = thm.scalar("x")
    thm.lmi("(1)", [[(x - s) * sp.Identity(n)]])
    inst = bind(thm, {"E": [[1.0]], "p": 2.0})
    r = lmi_certificate(inst, {"E": np.array([[1.0]]), "x": math.sqrt(2.0)}, prove=True)
    # math.sqrt(2) = 1.41421356237309514547 > √2 = 1.41421356237309504880...
    assert r[0].proof == VIOLATED
    r = lmi_certificate(inst, {"E": np.array([[1.0]]), "x": math.nextafter(math.sqrt(2.0), 0)},
                        prove=True)
    assert r[0].proof == PROVED


def test_paper_example_is_proved_end_to_end():
    sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    assert sol.proved and all(r.proof == PROVED for r in sol.lmis)
    assert all(r["proof"] == PROVED for r in sol.analysis.lmis)
    certified, reasons = sol.verdict.certified, sol.verdict.reasons
    assert certified, reasons


def test_a_design_that_misses_its_level_is_not_certified():
    """The analysis of a perturbed filter at the synthesis γ: not proved, so not certified."""
    sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    worse = {k: np.asarray(v) * (1.2 if k == "Cf" else 1.0) for k, v in sol.design.items()}
    cert = certify_by_analysis(sol.instance, worse, sol.gamma)
    assert not cert.passed
