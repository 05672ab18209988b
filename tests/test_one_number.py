"""One number and one word per result, everywhere (issue 39).

For one theorem with a design (zhang_quantized_loss.thm2 on its paper example: a filter recovered
and certified by the analysis theorem thm1), the γ and the verdict word read from ``solve``,
``verify``, ``reproduce`` (text and JSON), ``check`` (text and JSON), ``latex --json``,
``search``, ``successive`` (one step: the same LMI at the example's point) and, in Python,
``sol.gamma`` and ``repr(sol)`` are one number and one word: the delivered filter's level, as
its analysis certifies it.  That level is compared with an independent computation: the analysis
theorem solved again with the delivered filter as data, by a second solver (CVXOPT).

A sweep recovers no design: its points claim the level at the synthesis point, and are named so —
that level must be the SDP optimum ``solve`` reports as ``optimum_level`` (within the solvers'
1e-5), never presented as the design's level.
"""
from __future__ import annotations

import pytest

import lmidsl
from conftest import run_cli, run_cli_json
from lmidsl.certify.analysis import certify_by_analysis

T, E = "zhang_quantized_loss.thm2", "paper-N2"

pytestmark = pytest.mark.slow


def _pair(record: dict) -> tuple:
    return record["gamma"], record["word"]


def test_gamma_and_word_agree_in_every_command_and_in_python():
    sol = lmidsl.solve(T, example=E)
    gamma, word = sol.gamma, sol.verdict.word
    assert sol.verdict.certified and word in ("certified", "optimal", "certified bound"), sol.verdict.why
    # independent: the analysis theorem with the delivered filter fixed, solved by a second solver
    # (CVXOPT through cvxpy, not the default direct/Clarabel road), certifies the same level
    second = certify_by_analysis(sol.original_instance, dict(sol.design), sol.point_gamma,
                                 solver="CVXOPT", backend="cvxpy")
    assert second.passed and second.gamma == pytest.approx(gamma, rel=1e-4), (second.gamma, gamma)
    assert gamma != sol.optimum_level            # a design theorem: the headline is not the optimum
    assert f"gamma={gamma:.8g}" in repr(sol) and word.upper() in repr(sol)

    seen = {"python": (gamma, word)}
    doc = run_cli_json("solve", T, "--example", E)
    seen["solve"] = (doc["gamma"], doc["verdict"]["word"])
    assert doc["verdict"]["gamma"] == doc["gamma"]
    seen["verify"] = _pair(run_cli_json("verify", T, "--example", E)["verdict"])
    rows = [r for r in run_cli_json("reproduce", "--theorem", T, "--no-progress")["rows"] if r["example"] == E]
    seen["reproduce --json"] = _pair(rows[0]["verdict"])
    check = run_cli_json("check", T, "--example", E, "--solvers", "direct:clarabel")
    seen["check --json"] = (check["rows"][0]["gamma"], check["rows"][0]["verdict"]["word"])
    latex = run_cli_json("latex", T, "--example", E)
    seen["latex --json"] = _pair(latex["verdict"])
    search = run_cli_json("search", T, "--example", E, "--grid", "rho=0.75:0.75:1")
    seen["search --json"] = _pair(search["verdict"])
    successive = run_cli_json("successive", T, "--example", E, "--max-iter", "1", "--no-progress")
    seen["successive --json"] = _pair(successive["verdict"])
    for where, (g, w) in seen.items():
        assert g == pytest.approx(gamma, rel=1e-9) and w == word, (where, g, w, gamma, word)

    # the text: the same number (printed to 8 digits) and word
    shown = f"{gamma:.8g}"
    code, out, err = run_cli("reproduce", "--theorem", T, "--no-progress", env={"COLUMNS": "200"})
    assert code == 0, err
    line = next(l for l in out.splitlines() if l.startswith(T) and shown in l)   # the example on the next line
    assert word in line, line
    code, out, err = run_cli("check", T, "--example", E, "--solvers", "direct:clarabel", env={"COLUMNS": "200"})
    assert code == 0, err
    row = next((l for l in out.splitlines() if "direct:CLARABEL" in l and shown in l), out)
    assert shown in row and word in row, row
    code, out, err = run_cli("solve", T, "--example", E)
    assert f"gamma     = {shown}" in out and f"verdict: {word.upper()} at gamma = {shown}" in " ".join(out.split())


def test_a_sweep_claims_the_synthesis_point_level_and_names_it():
    sol = lmidsl.solve(T, example=E)
    sweep = run_cli_json("sweep", T, "--example", E, "--grid", "rho=0.75:0.75:1", "--no-progress")
    point = sweep["points"][0]
    assert point["verdict"]["gamma"] == point["gamma"] == sweep["verdict"]["gamma"]
    assert point["verdict"]["word"] == sweep["verdict"]["word"] == "certified"
    assert point["gamma"] == pytest.approx(sol.optimum_level, rel=1e-5)
