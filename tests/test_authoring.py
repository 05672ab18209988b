"""What a new user writing a theorem needs (issue 14, items 4 and 5), each checked against an
independent computation (numpy, python-control):

* a symbol used after the solve (recovery, factorisation, objective, performance, report) must be
  determined by the LMIs: refused at declaration, one line naming theorem and symbol;
* a recovered matrix may be used by a later recovery formula;
* linear functionals in the objective — a weighted trace such as the sum of the entries,
  tr(J Z) with J = 1 1ᵀ — on both backends;
* a data file with entries the theorem does not use: a one-line warning, ignored; an unknown
  ``--set`` name is still an error;
* ``lmidsl solve textbook.hinf_sf_ct --data FILE --json`` gives the gain as matrices and the
  closed loop's norm; the Python API gives python-control systems;
* the LaTeX of a factorisation step defines its matrices, and no "γ = γ".
"""
from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest
from sympy import Trace, sqrt

import lmidsl
from lmidsl import He, I, Source, Theorem, TheoremDefinitionError, UnusedDataWarning
from conftest import run_cli

control = pytest.importorskip("control")

BACKENDS = ["cvxpy", pytest.param("picos", marks=pytest.mark.skipif(
    importlib.util.find_spec("picos") is None, reason="picos is not installed"))]
STABLE = {"A": [[-1.0, 0.5, 0.0], [0.0, -2.0, 1.0], [0.3, 0.0, -1.5]],
          "B": [[1.0, 0.0], [0.5, 1.0], [0.0, 0.2]],
          "C": [[1.0, 0.0, 1.0], [0.0, 1.0, -0.5]]}


def _lyapunov_theorem(tid: str) -> tuple:
    thm = Theorem(tid, "Gramian bound", Source("test", "-"), time="continuous")
    n, m, p = thm.dim("n m p")
    A, B, C = thm.data("A", n, n), thm.data("B", n, m), thm.data("C", p, n)
    P = thm.var("P", n, kind="symmetric")
    Z = thm.var("Z", p, kind="symmetric")
    X = thm.var("X", n, n)                        # in no LMI
    g = thm.scalar("g")                           # in no LMI
    thm.lmi("(lyap)", [[A * P + P * A.T + B * B.T]], sense="<")
    thm.lmi("(schur)", [[Z], [P * C.T, P]], sense=">")
    return thm, (A, B, C, P, Z, X, g)


@pytest.mark.parametrize("use", ["recover", "objective", "performance", "report", "factor"])
def test_a_variable_in_no_lmi_is_refused_where_it_is_used(use):
    thm, (A, B, C, P, Z, X, g) = _lyapunov_theorem(f"authoring.undetermined_{use}")
    act = {"recover": lambda: thm.recover(Af=X.I * P),
           "objective": lambda: thm.minimize(Trace(Z) + g),
           "performance": lambda: thm.minimize(Trace(Z), performance=("gamma", sqrt(g))),
           "report": lambda: thm.report(level=Trace(X)),
           "factor": lambda: thm.factor("R S", lmidsl.rs_split, X)}[use]
    with pytest.raises(TheoremDefinitionError) as info:
        act()
    message = str(info.value)
    assert message.startswith(f"authoring.undetermined_{use}:") and "\n" not in message
    assert "decision variable X" in message or "decision variable g" in message
    thm.minimize(Trace(Z))                        # what the LMIs determine is accepted
    thm.recover(Q=P.I)


def test_a_recovered_matrix_may_use_another():
    thm, (A, B, C, P, Z, X, g) = _lyapunov_theorem("authoring.chain")
    thm.minimize(Trace(Z))
    Q = thm.recover(Q=P.I)                        # P⁻¹
    CQ = thm.recover(CQ=C * Q)                    # uses the recovered Q
    thm.recover(twice=2 * CQ)                     # and one more level
    sol = lmidsl.solve(thm, data=STABLE, backoff=None)
    assert sol.ok and sol.certified
    Qn = np.linalg.inv(sol.values["P"])
    assert np.allclose(sol.design["Q"], Qn, rtol=1e-9, atol=1e-12)
    assert np.allclose(sol.design["CQ"], np.array(STABLE["C"]) @ Qn, rtol=1e-9, atol=1e-12)
    assert np.allclose(sol.design["twice"], 2 * np.array(STABLE["C"]) @ Qn, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_sum_of_entries_by_a_weighted_trace(backend):
    """min tr(J Z) with J = 1 1ᵀ over Z ⪰ C P Cᵀ, P ≻ W_c is 1ᵀ C W_c Cᵀ 1 = ‖1ᵀ G‖₂²."""
    thm, (A, B, C, P, Z, X, g) = _lyapunov_theorem(f"authoring.sum_{backend}")
    J = thm.data("J", Z.shape[0], Z.shape[0], symmetric=True)
    thm.minimize(Trace(J * Z))
    p = len(STABLE["C"])
    sol = lmidsl.solve(thm, data={**STABLE, "J": np.ones((p, p)).tolist()}, backend=backend)
    assert sol.ok and sol.certified
    row = np.ones((1, p)) @ np.array(STABLE["C"])
    h2 = control.norm(control.ss(STABLE["A"], STABLE["B"], row, np.zeros((1, 2))), 2)
    assert abs(sol.objective - h2 ** 2) <= 1e-4 * h2 ** 2
    assert sol.objective >= h2 ** 2 * (1 - 1e-6)


def test_unused_data_warn_and_are_ignored_in_the_python_api():
    thm, (A, B, C, P, Z, X, g) = _lyapunov_theorem("authoring.extra")
    thm.minimize(Trace(Z))
    with pytest.warns(UnusedDataWarning, match="authoring.extra: .*D, E"):
        sol = lmidsl.solve(thm, data={**STABLE, "D": [[0.0]], "E": [[1.0]]})
    assert sol.ok and sol.certified
    with pytest.raises(lmidsl.InputError, match="unknown data or parameter 'E'"):
        lmidsl.solve(thm, data=STABLE, overrides={"E": [[1.0]]})


def _plant():
    from lmidsl.theorems.textbook.plants import random_plant
    return {k: np.asarray(v).tolist() for k, v in random_plant(11, 3, 2, 1, 2, 1, "continuous").items()}


def _hinf(A, B, C, D) -> float:
    return float(control.norm(control.ss(A, B, C, D), "inf", tol=1e-10))


def test_cli_hinf_sf_json_gives_the_gain_and_the_closed_loop_norm(tmp_path):
    plant = _plant()                                  # a full generalized plant: C2, D21, D22 unused
    path = tmp_path / "plant.json"
    path.write_text(json.dumps(plant))
    code, stdout, stderr = run_cli("solve", "textbook.hinf_sf_ct", "--data", str(path), "--json")
    assert code == 0, stderr
    lines = [l for l in stderr.splitlines() if "lmidsl" in l or l.startswith(("warning", "error"))]
    assert lines == ["warning: textbook.hinf_sf_ct: ignoring data the theorem does not use: C2, D21, D22"]
    out = json.loads(stdout)
    assert out["verdict"]["certified"], out["verdict"]
    K = np.array(out["design"]["matrices"]["K"])
    assert out["design"]["kind"] == "gain" and K.shape == (1, 3)
    A, B1, B2, C1, D11, D12 = (np.array(plant[k]) for k in ("A", "B1", "B2", "C1", "D11", "D12"))
    Acl = A + B2 @ K
    assert np.all(np.linalg.eigvals(Acl).real < 0)
    norm = _hinf(Acl, B1, C1 + D12 @ K, D11)        # formed by hand, not by lmidsl
    loop = out["closed_loop"]
    assert loop["stable"] and loop["signal"] == "w -> z"
    assert abs(loop["hinf_norm"] - norm) <= 1e-6 * norm
    assert norm <= out["gamma"] * (1 + 1e-6)

    code, _, stderr = run_cli("solve", "textbook.hinf_sf_ct", "--data", str(path), "--set", "C3=[[1]]")
    assert code == 2
    assert stderr.strip().splitlines()[-1].startswith("error: textbook.hinf_sf_ct: unknown data or parameter 'C3'")
    assert "Traceback" not in stderr


def test_python_api_gives_statespace_systems():
    plant = _plant()
    with pytest.warns(UnusedDataWarning):
        sol = lmidsl.solve("textbook.hinf_sf_ct", data=plant)
    Kss = sol.design.as_statespace()
    assert isinstance(Kss, control.StateSpace) and Kss.nstates == 0 and Kss.isctime()
    assert np.allclose(Kss.D, sol.design["K"])
    loop = sol.closed_loop()
    assert isinstance(loop, control.StateSpace)
    K = sol.design["K"]
    A, B1, B2, C1, D11, D12 = (np.array(plant[k]) for k in ("A", "B1", "B2", "C1", "D11", "D12"))
    norm = _hinf(A + B2 @ K, B1, C1 + D12 @ K, D11)
    assert abs(float(control.norm(loop, "inf", tol=1e-10)) - norm) <= 1e-6 * norm
    assert sol.as_dict()["closed_loop"]["hinf_norm"] == pytest.approx(norm, rel=1e-6)


def test_latex_of_a_factor_step_defines_its_matrices():
    doc = lmidsl.theorem_latex("textbook.hinf_of_ct")
    recovery = doc[doc.index("Controller recovery"):]
    assert "Let $M$, $N$ be nonsingular with $M N^{T} = I - X Y$" in recovery
    assert recovery.index("Let $M$") < recovery.index("A_K =")       # defined before use
    assert r"\gamma = \gamma" not in doc and "Filter recovery" not in doc
    h2 = lmidsl.theorem_latex("textbook.brl_ct")
    # γ² is the objective: "γ is the square root of the optimal value", never "γ = √γ²"
    assert r"\sqrt{\gamma^2}" not in h2 and "square root of the optimal value" in h2
