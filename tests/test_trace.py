"""Traces (sympy's ``Trace``) in objectives and LMI blocks, through every walker.

The check is the H2 norm of a stable continuous-time system G = (A, B, C, 0) from its
controllability Gramian W_c (A W_c + W_c Aᵀ + B Bᵀ = 0): ‖G‖₂² = tr(C W_c Cᵀ).  Every P with
A P + P Aᵀ + B Bᵀ ≺ 0 satisfies P ≻ W_c, so

    ‖G‖₂² = inf tr(Z)  subject to  A P + P Aᵀ + B Bᵀ ≺ 0,  [[Z, C P], [P Cᵀ, P]] ≻ 0,

the second LMI being Z ≻ C P Cᵀ by a Schur complement (P ≻ 0).  This textbook LMI is written
here, not taken from a paper; its optimum is compared with python-control's H2 norm and, for the
weighted variant, with the Gramian computed by scipy.
"""
from __future__ import annotations

import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
import scipy.linalg
from sympy import Trace, sqrt

import lmidsl.pipeline as api
from lmidsl import I, Source, Theorem
from lmidsl.certify.analysis import objective_level
from lmidsl.errors import NonlinearityError, ShapeMismatchError, TheoremDefinitionError
from lmidsl.numeric.evaluate import NumericEvaluator
from lmidsl.render.latex import lmi_latex, printer_for
from lmidsl.render.latex_document import theorem_latex
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel
from lmidsl.symbolic.linearity import degree
from lmidsl.symbolic.shapes import check_conformance

control = pytest.importorskip("control")

BACKENDS = ["cvxpy", pytest.param("picos", marks=pytest.mark.skipif(
    importlib.util.find_spec("picos") is None, reason="picos is not installed"))]


def h2_theorem() -> Theorem:
    thm = Theorem("test_trace.h2", "H2 norm by the controllability Gramian",
                  Source("none (textbook)", "H2 norm"), time="continuous")
    n, m, p = thm.dim("n m p")
    A = thm.data("A", n, n)
    B = thm.data("B", n, m)
    C = thm.data("C", p, n)
    P = thm.var("P", n, kind="symmetric")
    Z = thm.var("Z", p, kind="symmetric")
    thm.lmi("(lyap)", [[A * P + P * A.T + B * B.T]], sense="<")
    thm.lmi("(schur)", [[Z], [P * C.T, P]], sense=">")
    thm.minimize(Trace(Z), performance=("h2", sqrt(Trace(Z))))
    return thm


def weighted_theorem() -> Theorem:
    """min g + ρ tr(W) s.t. the Gramian LMIs and g − tr(W Z) − ρ tr(Z) > 0 (a trace in a
    block, a weighted trace, a parameter times a trace, a constant trace of data)."""
    thm = Theorem("test_trace.weighted", "weighted trace", Source("none (textbook)", "H2 norm"),
                  time="continuous")
    n, m, p = thm.dim("n m p")
    A = thm.data("A", n, n)
    B = thm.data("B", n, m)
    C = thm.data("C", p, n)
    W = thm.data("W", p, p)
    P = thm.var("P", n, kind="symmetric")
    Z = thm.var("Z", p, kind="symmetric")
    g = thm.scalar("g")
    rho = thm.param("rho", latex=r"\rho")
    thm.lmi("(lyap)", [[A * P + P * A.T + B * B.T]], sense="<")
    thm.lmi("(schur)", [[Z], [P * C.T, P]], sense=">")
    thm.lmi("(level)", [[(g - Trace(W * Z) - rho * Trace(Z)) * I]], sense=">", sizes=[1])
    thm.minimize(g + rho * Trace(W))
    return thm


def random_stable(seed: int, n: int = 4, m: int = 2, p: int = 2):
    """A random (A, B, C) with A Hurwitz (spectral abscissa in [-1.5, -0.5])."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    A -= (np.max(np.linalg.eigvals(A).real) + 0.5 + rng.uniform()) * np.eye(n)
    return A, rng.normal(size=(n, m)), rng.normal(size=(p, n))


def gramian(A, B):
    return scipy.linalg.solve_continuous_lyapunov(A, -B @ B.T)


@pytest.mark.parametrize("backend", BACKENDS)
def test_h2_norm_by_trace_matches_python_control(backend):
    thm = h2_theorem()
    worst = 0.0
    for seed in (0, 1, 2):
        A, B, C = random_stable(seed)
        reference = control.norm(control.ss(A, B, C, np.zeros((C.shape[0], B.shape[1]))), 2)
        sol = api.solve(thm, data={"A": A.tolist(), "B": B.tolist(), "C": C.tolist()},
                        backend=backend)
        assert sol.ok and sol.certified, (seed, sol.status)
        assert sol.objective == pytest.approx(sol.gamma ** 2, rel=1e-9)  # tr(Z) and √tr(Z)
        worst = max(worst, abs(sol.gamma - reference) / reference)
    assert worst < 1e-5  # measured: ≈ 2.4e-7 on both backends (the strictness margin)


@pytest.mark.parametrize("backend", BACKENDS)
def test_trace_in_a_block_weighted_and_times_a_parameter(backend):
    thm = weighted_theorem()
    A, B, C = random_stable(0)
    W = np.diag([2.0, 0.5])
    rho = 0.3
    sol = api.solve(thm, data={"A": A.tolist(), "B": B.tolist(), "C": C.tolist(), "W": W.tolist(),
                               "rho": rho}, backend=backend)
    Y = C @ gramian(A, B) @ C.T
    expected = np.trace(W @ Y) + rho * np.trace(Y) + rho * np.trace(W)
    assert sol.ok and sol.certified
    assert sol.objective == pytest.approx(expected, rel=1e-5)


def test_trace_parameter_is_updated_without_recompiling():
    """ρ·tr(W) and ρ·tr(Z) keep ρ a cvxpy parameter: a new ρ re-solves the same problem."""
    A, B, C = random_stable(1)
    W = np.diag([1.0, 3.0])
    inst = api.make_instance(weighted_theorem(), data={"A": A.tolist(), "B": B.tolist(),
                                                       "C": C.tolist(), "W": W.tolist(), "rho": 0.3})
    model = CvxpyModel(inst, reuse=True)
    problem = model.problem
    model.solve()
    model.update(inst.with_params(rho=0.6))
    sol = model.solve()
    assert model.problem is problem
    Y = C @ gramian(A, B) @ C.T
    assert sol.objective == pytest.approx(np.trace(W @ Y) + 0.6 * (np.trace(Y) + np.trace(W)), rel=1e-5)


def test_trace_objective_performance_and_level():
    thm = h2_theorem()
    assert objective_level(thm, 1.5) == pytest.approx(2.25)  # h2 = √tr(Z): level γ²
    p = thm.dims["p"]
    Zv = np.array([[2.0, 0.3], [0.3, 1.0]])
    ev = NumericEvaluator({p: 2}, {"Z": Zv}, {})
    assert ev.visit(thm.performance[1]) == pytest.approx(np.sqrt(3.0))
    assert ev.visit(Trace(thm.var_decl["Z"].symbol) + p) == pytest.approx(5.0)  # tr(Z) + p


def test_trace_rules_of_the_shape_and_linearity_walkers():
    thm = Theorem("test_trace.rules", "rules", Source("none", "none"))
    n, m = thm.dim("n m")
    A = thm.data("A", n, n)
    B = thm.data("B", n, m)
    P = thm.var("P", n, kind="symmetric")
    V = thm.var("V", n, n)
    assert check_conformance(Trace(A * P) * A + P) == (n, n)
    assert degree(Trace(A * P)) == 1 and degree(Trace(A)) == 0 and degree(Trace(P) * P) == 2
    with pytest.raises(ShapeMismatchError, match=r"test_trace.rules: objective Trace\(B\): trace of B, which is n×m"):
        thm.minimize(Trace(B))
    with pytest.raises(ShapeMismatchError, match=r"LMI \(t1\) block \(1,1\): product B·P"):
        thm.lmi("(t1)", [[Trace(B * P) * A - P]])
    with pytest.raises(NonlinearityError, match=r"LMI \(t2\) block \(1,1\): P\*V is not affine.*P, V"):
        thm.lmi("(t2)", [[Trace(P * V) * A - P]])
    with pytest.raises(NonlinearityError, match=r"objective .*not affine.*P, V"):
        thm.minimize(Trace(P * V))
    with pytest.raises(TheoremDefinitionError, match=r"objective P is n×n, not a scalar"):
        thm.minimize(P)
    thm.lmi("(t3)", [[Trace(A * P) * A - P]])  # affine: accepted
    thm.minimize(Trace(P) + 2 * Trace(A.T * P * A))
    assert thm.objective == Trace(P) + 2 * Trace(A.T * P * A)


def test_trace_objective_latex():
    thm = h2_theorem()
    assert printer_for(thm).doprint(thm.objective) == r"\operatorname{tr}(Z)"
    assert ("Minimise $\\operatorname{tr}(Z)$ subject to the conditions above. "
            "The performance level is $h_2 = \\sqrt{\\operatorname{tr}(Z)}$.") in theorem_latex(thm)
    w = weighted_theorem()
    assert printer_for(w).doprint(w.objective) == r"\rho \operatorname{tr}(W) + g"  # sympy's term order
    level = lmi_latex(w, "(level)")
    assert r"\operatorname{tr}(W Z)" in level and r"\rho \operatorname{tr}(Z)" in level


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex is not installed")
def test_trace_document_compiles(tmp_path):
    (tmp_path / "weighted.tex").write_text(theorem_latex(weighted_theorem()))
    proc = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "weighted.tex"],
                          cwd=tmp_path, capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          timeout=120)
    assert proc.returncode == 0, [l for l in proc.stdout.splitlines() if l.startswith("!")][:3]
