"""Verdicts on data nobody here chose: scale, continuous time, symmetry, exit codes.

Every number is compared with an independent computation: python-control's H∞ norm (slycot),
or the exact effect of a rescaling on γ* (B, D → sB, sD multiplies an energy-to-peak or H∞ γ by
s; a state rescaling x → s x changes nothing).
"""
from __future__ import annotations

import json
import re

import control
import numpy as np
import pytest

import lmidsl
from conftest import run_cli
from lmidsl import ErrorSystem, I, Source, Theorem
from lmidsl.errors import TheoremDefinitionError
from lmidsl.numeric.instance import bind

SEED000 = lmidsl.get_theorem("wang_l2linf.thm3").examples["paper-full"]
GAMMA_000 = 0.33674059     # γ* of the seed-000 example (docs/reproductions/000.md), Clarabel


def brl_ct() -> Theorem:
    """Bounded real lemma, continuous time (Boyd et al. 1994, §2.7.3): min γ s.t. P ≻ 0 and
    [[AᵀP + PA, PB, Cᵀ], [BᵀP, −γI, Dᵀ], [C, D, −γI]] ≺ 0; γ* = ‖C(sI − A)⁻¹B + D‖∞."""
    thm = Theorem("verdicts.brl_ct", "Bounded real lemma (continuous time)",
                  Source("Boyd, El Ghaoui, Feron, Balakrishnan 1994", "(2.7.3)"), time="continuous")
    n, m, p = thm.dim("n m p")
    A, B = thm.data("A", n, n), thm.data("B", n, m)
    C, D = thm.data("C", p, n), thm.data("D", p, m)
    P = thm.var("P", n, kind="symmetric")
    g = thm.scalar("g")
    thm.lmi("(BRL)", [[A.T * P + P * A], [B.T * P, -g * I], [C, D, -g * I]])
    thm.positive(P)
    thm.minimize(g, performance=("gamma", g))
    thm.error_system(ErrorSystem(A=A, B=B, C=C, D=D), figure="h_infinity", design=())
    return thm


BRL = brl_ct()
A3 = np.array([[-1.0, 2.0, 0.0], [-2.0, -1.0, 0.5], [0.0, 0.0, -3.0]])
B3 = np.array([[1.0], [0.0], [1.0]])
C3 = np.array([[1.0, 0.5, 0.0]])
D3 = np.array([[0.0]])


@pytest.mark.parametrize("sb,sc", [(1.0, 1.0), (1e-6, 1e6), (1e6, 1e-6), (1e-8, 1.0), (1.0, 1e8)])
def test_bounded_real_lemma_is_scale_free(sb, sc):
    data = {"A": A3.tolist(), "B": (sb * B3).tolist(), "C": (sc * C3).tolist(), "D": D3.tolist()}
    true = control.linfnorm(control.ss(A3, sb * B3, sc * C3, D3))[0]
    sol = lmidsl.solve(BRL, data=data)
    certified, reasons = sol.verdict.certified, sol.verdict.reasons
    assert certified, reasons
    assert sol.gamma == pytest.approx(true, rel=1e-4)
    assert sol.gamma >= true * (1 - 1e-9)          # a certified γ is an upper bound


def test_lightly_damped_plant():
    wn, zeta = 10.0, 1e-3
    A = np.array([[0.0, 1.0], [-wn ** 2, -2 * zeta * wn]])
    B, C, D = np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]]), np.array([[0.0]])
    true = control.linfnorm(control.ss(A, B, C, D))[0]     # 1/(2ζωn²) ≈ 5
    sol = lmidsl.solve(BRL, data={"A": A.tolist(), "B": B.tolist(), "C": C.tolist(), "D": D.tolist()})
    assert sol.verdict.certified, sol.verdict.reasons
    assert sol.gamma == pytest.approx(true, rel=1e-4)


@pytest.mark.parametrize("factor", [1e8, 1e-8])
def test_seed000_disturbance_scaled(factor):
    """B, D → sB, sD: the energy-to-peak γ* is multiplied by s exactly."""
    data = dict(SEED000.data)
    data["B"] = (factor * np.asarray(data["B"])).tolist()
    data["D"] = (factor * np.asarray(data["D"])).tolist()
    sol = lmidsl.solve("wang_l2linf.thm3", data={**data, **SEED000.params})
    assert sol.status != "infeasible"
    assert sol.verdict.certified, sol.verdict.reasons
    assert sol.gamma == pytest.approx(factor * GAMMA_000, rel=1e-4)
    assert not sol.margin_limited


def test_seed000_state_scaled():
    """x → s x (A unchanged, B → sB, C → C/s, L → L/s): γ* unchanged."""
    s = 1e-8
    data = dict(SEED000.data)
    data["B"] = (s * np.asarray(data["B"])).tolist()
    data["C"] = (np.asarray(data["C"]) / s).tolist()
    data["L"] = (np.asarray(data["L"]) / s).tolist()
    sol = lmidsl.solve("wang_l2linf.thm3", data={**data, **SEED000.params})
    assert sol.verdict.certified, sol.verdict.reasons
    assert sol.gamma == pytest.approx(GAMMA_000, rel=1e-4)


def test_verify_respects_continuous_time():
    """The exact figure of a continuous-time error system is its H∞ norm (python-control), not
    a discrete-time formula applied to a Hurwitz matrix."""
    data = {"A": A3.tolist(), "B": B3.tolist(), "C": C3.tolist(), "D": D3.tolist()}
    result = lmidsl.verify(BRL, data=data, runs=0)
    true = control.linfnorm(control.ss(A3, B3, C3, D3))[0]
    assert result.exact.time == "continuous" and result.exact.mean_square_stable
    assert result.exact.value == pytest.approx(true, rel=1e-9)
    assert result.analysis_gamma == pytest.approx(true, rel=1e-4)
    assert result.certified, result.checks


def test_asymmetric_diagonal_block_at_a_later_vertex_is_refused():
    thm = Theorem("verdicts.asym", "a per-vertex datum in a diagonal block", Source("test", "(1)"))
    n = thm.dim("n")
    Q = thm.data("Q", n, n, per_vertex=True)
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("(1)", [[P + Q]])
    with pytest.raises(TheoremDefinitionError) as err:
        bind(thm, {"vertices": [{"Q": [[1.0, 0.0], [0.0, 1.0]]}, {"Q": [[1.0, 2.0], [0.0, 1.0]]}]})
    # Q is not declared symmetric, so P + Q is symmetric at vertex 1 only by these data: refused
    # there, naming the LMI, the block and the fix (issue 40's check of declared kinds)
    assert "(1)" in str(err.value) and "(1,1)" in str(err.value) and "symmetric=True" in str(err.value)


# -- exit codes: 0 certified, 1 not certified / infeasible, 2 bad input ----------------------
def test_exit_code_certified_solve():
    code, out, err = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["verdict"]["certified"] and all(l["proof"] == "proved" for l in data["lmis"])


def test_exit_code_infeasible_solve():
    code, out, err = run_cli("solve", "pan_impulsive.thm1", "--example", "paper")
    assert code == 1, err
    assert "verdict: INFEASIBLE" in out and "CERTIFIED" not in out


def test_exit_code_bad_input():
    code, _, err = run_cli("solve", "wang_l2linf.thm3", "--example", "nope")
    assert code == 2 and err.startswith("error:")


def test_exit_code_verify_of_a_design_that_misses_the_printed_level(tmp_path):
    worse = {"Af": [[-0.0069, 0.2865], [-0.9725, 0.4557]], "Bf": [[-0.0186], [-0.9235]],
             "Cf": [[-1.5, -2.5]]}
    path = tmp_path / "worse.json"
    path.write_text(json.dumps(worse))
    code, out, err = run_cli("verify", "wang_l2linf.thm3", "--example", "paper-full",
                             "--design", str(path), "--runs", "0")
    assert code == 1, (out, err)


def test_exit_code_sweep_every_point_proved(tmp_path):
    code, out, err = run_cli("sweep", "wang_l2linf.thm3", "--example", "paper-full",
                             "--grid", "rbar=0.5:0.9:3", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["proved_points"] == 3 and all(p["proved"] for p in data["points"])
    assert data["verdict"]["certified"] and all(p["verdict"]["certified"] for p in data["points"])


def test_exit_code_reproduce_follows_the_expected_outcomes():
    code, out, err = run_cli("reproduce", "--theorem", "pan_impulsive.lemma1", "--json")
    assert code == 0, err                      # the paper's printed filter: infeasible, as declared
    rows = json.loads(out)["rows"]
    assert {r["example"]: r["outcome"] for r in rows}["paper-printed"] == "infeasible"
    assert all(r["as_expected"] for r in rows)


def test_a_solver_panic_is_a_solver_error_and_the_next_solver_answers(monkeypatch):
    """Clarabel (Rust) panics with pyo3's PanicException, a BaseException: it must become the
    status "solver_error" of that solver, and `solve` must go on to the other solvers."""
    import cvxpy as cp
    from lmidsl.solver.backends import direct_backend

    class PanicException(BaseException):
        pass

    real_solve = cp.Problem.solve

    def panicking(self, *args, **kwargs):
        if kwargs.get("solver") == "CLARABEL":
            raise PanicException("Eigval error: Eigen(1)")
        return real_solve(self, *args, **kwargs)

    monkeypatch.setattr(cp.Problem, "solve", panicking)

    class PanickingClarabel:                    # the direct backend's call of Clarabel
        def __init__(self, *args, **kwargs):
            raise PanicException("Eigval error: Eigen(1)")

    monkeypatch.setattr(direct_backend.clarabel, "DefaultSolver", PanickingClarabel)
    data = {"A": A3.tolist(), "B": B3.tolist(), "C": C3.tolist(), "D": D3.tolist()}
    true = control.linfnorm(control.ss(A3, B3, C3, D3))[0]
    sol = lmidsl.solve(BRL, data=data)
    assert sol.solver != "CLARABEL" and sol.certified
    assert abs(sol.gamma - true) <= 1e-4 * true


def test_a_named_solver_alone_cannot_declare_infeasible():
    """The stress suite's lightly damped discrete plant (benchmarks/stress/cases.py, family
    "light", seed 0: stable, a pole at radius 0.99982): with solver="CLARABEL" Clarabel fails and
    its feasp says t* = 0.32 > 0, but CVXOPT's feasp finds the LMI strictly feasible, so the
    verdict may not be "infeasible" (it was, when only an unnamed solver got a second opinion)."""
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[1] / "benchmarks" / "stress" / "cases.py"
    spec = importlib.util.spec_from_file_location("stress_cases", path)
    cases = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(cases)
    data = cases.system("light", 0, "discrete")
    assert max(abs(np.linalg.eigvals(data["A"]))) < 1
    sol = lmidsl.solve("textbook.brl_dt", data=cases.lists(data), solver="CLARABEL")
    assert sol.status != "infeasible", sol.notes


def test_a_wide_bracket_is_not_blamed_on_the_back_off_alone():
    """δ = 0.01: the delivered level is 1 % above the lower end; the verdict names the SDP
    optimum's own distance to the dual end (tiny here) and the back-off's cost separately."""
    thm = lmidsl.get_theorem("textbook.hinf_sf_ct")
    sol = lmidsl.solve(thm, example=next(iter(thm.examples)), backoff=0.01)
    why = sol.verdict.why
    box = sol.verdict.bracket
    said = re.search(r"itself is ([0-9.e+-]+) from the proved dual end", why)
    assert said is not None, why
    optimum_part = (box["upper"] - box["lower"]) / box["upper"]     # box["upper"]: the SDP optimum
    assert float(said.group(1)) == pytest.approx(optimum_part, rel=0.2, abs=1e-9), (why, box)
    assert float(said.group(1)) < 1e-3 < (sol.gamma - box["lower"]) / box["lower"]
    assert "the back-off (δ = 0.01) costs" in why, why
