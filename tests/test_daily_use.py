"""The Python API as kind as the command line (issue 39): LMIs written with cvxpy's operators
(``A.T @ P + P @ A << 0``, ``P >> 0``), a single matrix where ``[[M]]`` is meant, ``sol[P]`` /
``sol.value(P)``, and every authoring slip of the issue as one lmidsl error naming what is at
fault — never a raw sympy error.  Every γ is compared with python-control's H∞ norm."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from sympy import sqrt

import lmidsl
from conftest import run_cli
from lmidsl import I, LmidslError, ShapeMismatchError, Theorem, TheoremDefinitionError

control = pytest.importorskip("control")

A = np.array([[0.0, 1.0], [-2.0, -0.4]])
B = np.array([[0.0], [1.0]])
C = np.array([[1.0, 0.0]])
D = np.zeros((1, 1))
NORM = control.norm(control.ss(A, B, C, D), "inf")


def quick(name):
    thm = Theorem(name, time="continuous")
    return thm, thm.var("P", 2, kind="symmetric"), thm.scalar("g")


def test_operators_build_the_lmis_and_the_solution_reads_like_cvxpy():
    thm, P, g = quick("daily.ops")
    # the Lyapunov block written as a cvxpy user types it, then embedded with the BRL's rows
    lyapunov = A.T @ P + P @ A
    thm.lmi("(BRL)", [[lyapunov], [B.T @ P, -g * I], [C, D, -I]])
    thm.lmi(P >> 0)                                          # a single matrix: no [[...]]
    thm.lmi(0 << P + I, sense=">")                           # P + I ≻ 0, the sense agreeing
    thm.lmi(P <= 1e3 * I)                                    # non-strict: I·1e3 − P ⪰ 0
    assert [(l.label, l.sense, l.strict) for l in thm.lmis] == [
        ("(BRL)", "<", True), ("(2)", ">", True), ("(3)", ">", True), ("(4)", "<=", False)]
    sol = lmidsl.solve(thm.minimize(g, performance=("gamma", sqrt(g))))
    assert sol.verdict.certified, sol.verdict.reasons
    assert abs(sol.gamma - NORM) <= 1e-5 * NORM, (sol.gamma, NORM)
    # sol[P], sol.value(P), sol.value("P") and the value of an expression (cvxpy's expr.value)
    assert np.array_equal(sol[P], sol.value("P")) and np.array_equal(sol[P], sol.value(P))
    assert sol.value(g) == pytest.approx(sol.gamma ** 2, rel=1e-6)
    lyap = sol.value(lyapunov)
    assert np.allclose(lyap, A.T @ sol[P] + sol[P] @ A, atol=1e-12)
    assert np.linalg.eigvalsh(sol[P]).min() > 0
    with pytest.raises(LmidslError, match=r"daily\.ops: no value of Q .*variables and recovered matrices: P, g"):
        sol["Q"]


def test_strict_comparisons_are_lmis_too():
    thm, P, g = quick("daily.strict")
    thm.lmi(A.T @ P + P @ A < -1e-3 * I)          # strict, like <<
    thm.lmi(P > 0)
    sol = lmidsl.solve(thm)
    assert sol.verdict.certified, sol.verdict.reasons
    Pv = sol[P]
    assert np.linalg.eigvalsh(A.T @ Pv + Pv @ A).max() < 0 and np.linalg.eigvalsh(Pv).min() > 0


SLIPS = [
    # (what the user wrote, the error class, what the message must say)
    ("sizes: B @ P (2×1 times 2×2)", lambda t, P, g: t.lmi([[A.T @ P + P @ A], [B @ P, -g * I]]),
     ShapeMismatchError, [r"daily\.slips", r"product M\d+ @ P", "2×1", "2×2"]),
    ("a sum of two sizes", lambda t, P, g: P + B, ShapeMismatchError, [r"daily\.slips", r"sum P \+ M\d+", "2×2", "2×1"]),
    ("block sizes inside the LMI", lambda t, P, g: t.lmi("(X)", [[A.T @ P + P @ A], [B.T @ P, -g * I], [P, B.T, -I]]),
     ShapeMismatchError, [r"daily\.slips: LMI \(X\): block \(3,2\)", "1×2", r"block row 3 has size 2"]),
    ("A.T.dot(P): numpy's dot", lambda t, P, g: A.T.dot(P), TheoremDefinitionError,
     [r"daily\.slips", "numpy cannot take P", r"A\.T @ P"]),
    ("np.dot", lambda t, P, g: np.dot(A, P), TheoremDefinitionError, ["numpy cannot take P"]),
    ("a matrix inequality as a truth value", lambda t, P, g: bool(P >> 0), TheoremDefinitionError,
     ["is a matrix inequality, not a truth value", r"Theorem\.lmi"]),
    ("a scalar comparison", lambda t, P, g: t.lmi(g > 0), TheoremDefinitionError,
     [r"daily\.slips: LMI \(\d\)", "a scalar comparison is not an LMI"]),
    ("an inequality inside the blocks", lambda t, P, g: t.lmi([[P >> 0]]), TheoremDefinitionError,
     [r"block \(1,1\)", "an inequality inside the blocks"]),
    ("two senses", lambda t, P, g: t.lmi(P >> 0, sense="<"), TheoremDefinitionError, ["already states its sense"]),
    ("not affine", lambda t, P, g: t.lmi(P @ P << 0), TheoremDefinitionError,
     [r"daily\.slips: LMI \(\d\) block \(1,1\)", "not affine"]),
    ("a block matrix against a matrix", lambda t, P, g: lmidsl.block_matrix([[P]]) << P, TheoremDefinitionError,
     ["compare a block matrix with 0"]),
]


@pytest.mark.parametrize("what, slip, kind, says", SLIPS, ids=[s[0] for s in SLIPS])
def test_every_authoring_slip_is_one_lmidsl_line(what, slip, kind, says):
    thm, P, g = quick("daily.slips")
    with pytest.raises(kind) as caught:
        slip(thm, P, g)
    message = str(caught.value)
    assert "\n" not in message and len(message) < 400, message
    for pattern in says:
        assert __import__("re").search(pattern, message), (pattern, message)


def test_a_wrong_shape_set_on_the_command_line_blames_that_matrix():
    # the theorem's A is n×n; a 3×3 A against 2-state B, C: A is blamed, not B
    code, _, err = run_cli("solve", "textbook.brl_ct", "--set", "A=[[1,2,3],[4,5,6],[7,8,9]]")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "data A is 3×3 but must be n×n = 2×2" in err and "data B" not in err, err
    code, _, err = run_cli("solve", "textbook.brl_ct", "--set", "B=[[1],[2],[3]]")
    assert code == 2 and "data B is 3×1" in err, err


def test_solution_html_outside_ipython():
    script = ("import lmidsl, numpy as np\n"
              "from lmidsl import I, Theorem\n"
              "t = Theorem('daily.html', time='continuous'); P = t.var('P', 2, kind='symmetric')\n"
              "t.lmi(np.array([[0., 1.], [-2., -.4]]).T @ P + P @ np.array([[0., 1.], [-2., -.4]]) << 0)\n"
              "t.lmi(P >> I)\n"
              "sol = lmidsl.solve(t)\n"
              "import sys; assert 'IPython' not in sys.modules\n"
              "html = sol._repr_html_()\n"
              "print(html)\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "<table" in out.stdout and "daily.html" in out.stdout and "CERTIFIED" in out.stdout.upper()
