"""One road to a certified point (lmidsl.solver.plan) and one verdict told the same way by every
command (lmidsl.certify.verdict): the order of the road, the headline level, the record's keys,
--no-certify, the words of a design's kind, and the bounded real lemma's headline against
python-control on systems whose SDP route is inaccurate."""
from __future__ import annotations

import json
import re

import control
import numpy as np
import pytest

import lmidsl
from lmidsl.solver.backends import Route, fallback_routes
from lmidsl.solver.plan import Plan
from lmidsl.certify.verdict import CERTIFIED_BOUND, CERTIFIED_WORDS

from conftest import ROOT, run_cli

RECORD_KEYS = {"certified", "word", "gamma", "why", "quantity", "quantity_words", "levels", "reasons", "headline"}


def test_the_road_tries_the_named_or_default_solver_then_the_fallback_routes():
    assert Plan("direct").routes() == [Route("direct", None), *fallback_routes("direct")]
    assert Plan("direct", "CLARABEL").routes() == [Route("direct", "CLARABEL")]
    assert Plan("direct", "CLARABEL", fallbacks=True).routes()[1:] == list(fallback_routes("direct"))


def _brl_data(A, B, C, D):
    return {k: np.atleast_2d(np.asarray(v, dtype=float)).tolist() for k, v in zip("ABCD", (A, B, C, D))}


def _lightly_damped():
    A = np.zeros((4, 4))
    for i, (w, z) in enumerate(((1.0, 1e-4), (7.0, 2e-4))):
        A[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[0, 1], [-w ** 2, -2 * z * w]]
    return A, [[0], [1], [0], [1.0]], [[1, 0, 1, 0.0]], [[0.0]]


def test_a_named_solver_that_stops_early_is_not_the_end_of_the_road():
    """Clarabel stopped after 5 iterations: the plan goes on to the declared closed form (the
    Riccati point), which gives python-control's norm (to 1e-5), certified."""
    A, B, C, D = _lightly_damped()
    norm = control.norm(control.ss(A, B, C, D), "inf", tol=1e-12)
    sol = lmidsl.solve("textbook.brl_ct", data=_brl_data(A, B, C, D), solver="CLARABEL", max_iter=5)
    assert sol.backend == "riccati" and sol.verdict.certified
    assert norm <= sol.verdict.gamma <= norm * (1 + 1e-4)
    assert any("user_limit" in n for n in sol.notes)


def _stress_systems():
    """Stable systems whose SDP route is inaccurate: lightly damped modes, one transfer function
    seen through diag(10^k) (8 decades), the closed loop of a large-gain LQR controller."""
    rng = np.random.default_rng(7)
    out = {"lightly-damped": _lightly_damped()}
    A = np.array([[-1.0, 2.0, 0.0], [0.0, -0.5, 1.0], [0.3, 0.0, -2.0]])
    B, C = np.array([[1.0], [0.5], [-1.0]]), np.array([[1.0, -1.0, 0.5]])
    T = np.diag([1.0, 1e4, 1e8])
    out["scaled-8-decades"] = (T @ A @ np.linalg.inv(T), T @ B, C @ np.linalg.inv(T), [[0.0]])
    Ap = rng.normal(size=(3, 3))
    Bu = rng.normal(size=(3, 1))
    K, *_ = control.lqr(Ap, Bu, np.eye(3), 1e-8 * np.eye(1))      # gains ~1e4
    Acl = Ap - Bu @ K
    out["large-gain-loop"] = (Acl, rng.normal(size=(3, 1)), np.vstack([np.eye(3)[:1], 1e-4 * K]), np.zeros((2, 1)))
    return out


@pytest.mark.parametrize("name", list(_stress_systems()))
def test_bounded_real_headline_is_the_norm_or_says_it_is_a_bound(name):
    A, B, C, D = _stress_systems()[name]
    norm = control.norm(control.ss(A, B, C, D), "inf", tol=1e-12)
    sol = lmidsl.solve("textbook.brl_ct", data=_brl_data(A, B, C, D))
    v = sol.verdict
    assert v.certified, v.reasons
    assert v.gamma >= norm * (1 - 1e-9)                 # a certified level is an upper bound
    assert v.gamma <= norm * (1 + 1e-4) or v.word == CERTIFIED_BOUND, (v.gamma, norm, v.word)


@pytest.mark.slow
def test_solve_verify_reproduce_and_latex_headline_the_same_level():
    """Seed 001, Theorem 2: the level of the delivered (backed-off) filter, certified by Theorem 1,
    is the headline everywhere, within 3e-3 of the optimum 0.38099."""
    _, out, _ = run_cli("solve", "li_delay_dropout.thm2", "--example", "paper", "--json")
    solved = json.loads(out)
    _, out, _ = run_cli("verify", "li_delay_dropout.thm2", "--example", "paper", "--runs", "0", "--json")
    verified = json.loads(out)
    _, out, _ = run_cli("reproduce", "--theorem", "li_delay_dropout.thm2", "--json")
    row = next(r for r in json.loads(out)["rows"] if r["example"] == "paper")
    code, tex, err = run_cli("latex", "li_delay_dropout.thm2", "--example", "paper")
    assert code == 0, err
    in_tex = float(re.search(r"\$\\gamma\$ \((?:optimal|certified)\) & \$([0-9.]+)\$", tex).group(1))
    g = solved["gamma"]
    assert abs(g - 0.38099) <= 3e-3
    assert solved["verdict"]["gamma"] == g and solved["verdict"]["certified"]
    assert verified["verdict"]["gamma"] == pytest.approx(g, rel=1e-6)
    assert row["verdict"]["gamma"] == pytest.approx(g, rel=1e-6) and row["gamma"] == row["verdict"]["gamma"]
    assert in_tex == pytest.approx(g, abs=1e-6)
    assert solved["verdict"]["levels"]["optimum"] == pytest.approx(0.3810009, rel=1e-5)


@pytest.mark.slow
def test_the_verdict_record_has_the_same_keys_in_every_command(tmp_path):
    records = {}
    _, out, _ = run_cli("solve", "textbook.brl_ct", "--json")
    records["solve"] = json.loads(out)["verdict"]
    _, out, _ = run_cli("verify", "wang_l2linf.thm3", "--example", "paper-full", "--runs", "0", "--json")
    records["verify"] = json.loads(out)["verdict"]
    _, out, _ = run_cli("check", "textbook.brl_ct", "--solvers", "clarabel,cvxopt", "--json")
    check = json.loads(out)
    records["check"], records["check row"] = check["verdict"], check["rows"][0]["verdict"]
    _, out, _ = run_cli("reproduce", "--theorem", "textbook.brl_ct", "--json")
    records["reproduce row"] = json.loads(out)["rows"][0]["verdict"]
    _, out, _ = run_cli("sweep", "wang_l2linf.thm3", "--example", "paper-full", "--grid", "rbar=0.5:0.6:2",
                        "--json", "--out", str(tmp_path / "s"))
    sweep = json.loads(out)
    records["sweep"], records["sweep point"] = sweep["verdict"], sweep["points"][0]["verdict"]
    for where, record in records.items():
        assert set(record) == RECORD_KEYS, where
        assert isinstance(record["certified"], bool) and isinstance(record["word"], str), where


def test_docs_json_lists_the_record_and_the_words():
    """docs/json.md states the record's keys and every verdict word the code can give."""
    from lmidsl.certify.verdict import WORDS
    text = (ROOT / "docs" / "json.md").read_text()
    assert all(f"`{key}`" in text for key in RECORD_KEYS)
    assert all(f"`{word}`" in text for word in WORDS)


def test_no_certify_never_says_certified():
    code, out, _ = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--no-certify")
    assert code == 1 and "CERTIFIED" not in out.replace("CERTIFICATION SKIPPED", "")
    assert "verdict: CERTIFICATION SKIPPED" in out
    code, out, _ = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--no-certify", "--json")
    record = json.loads(out)["verdict"]
    assert code == 1 and record["certified"] is False and record["word"] == "certification skipped"


def test_a_point_level_test_and_the_verdict_are_not_confused():
    sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    assert sol.lmis_hold and sol.certified == sol.verdict.certified is True
    skipped = lmidsl.solve("wang_l2linf.thm3", example="paper-full", certify=False)
    assert skipped.lmis_hold and skipped.certified is False


CONTROLLER_THEOREMS = ["textbook.hinf_sf_ct", "textbook.hinf_of_ct", "textbook.h2_ct_sf",
                       "textbook.pole_region_sf_ct"]


@pytest.mark.parametrize("theorem", CONTROLLER_THEOREMS)
def test_no_filter_in_the_words_of_a_controller_theorem(theorem):
    code, out, err = run_cli("solve", theorem)
    assert code in (0, 1), err
    assert "filter" not in out.lower(), [line for line in out.splitlines() if "filter" in line.lower()]


def test_a_stabilisation_design_is_certified_by_a_feasibility_analysis():
    """Pole placement by state feedback: no level; the analysis LMIs with K fixed are proved, and
    the closed-loop eigenvalues (numpy) lie in the region."""
    sol = lmidsl.solve("textbook.pole_region_sf_ct")
    assert sol.verdict.certified and sol.analysis.criterion == "feasible" and sol.analysis.passed
    data = sol.original_instance.data
    eig = np.linalg.eigvals(data["A"] + data["B2"] @ sol.design["K"])
    p = sol.instance.params
    assert np.all(eig.real < -p["alpha"]) and np.all(np.abs(eig + p["q"]) < p["r"])
    assert np.all(np.abs(eig.imag) < -eig.real * np.tan(p["theta"]))


def test_a_closed_loop_python_control_cannot_form_is_reported_not_raised():
    sol = lmidsl.solve("textbook.hinf_sf_ct")
    sol.design = sol.design.with_matrices({"K": np.full_like(sol.design["K"], np.nan)})
    loop = sol.as_dict()["closed_loop"]
    assert loop is None or "error" in loop or loop["stable"] in (True, False)


def test_every_certified_word_is_a_certified_verdict():
    sol = lmidsl.solve("textbook.brl_ct")
    assert sol.verdict.word in CERTIFIED_WORDS and sol.verdict.certified
