"""``lmidsl successive`` (issue 28): the BMI iteration from the command line.  Its γ is compared
with the optimum of the exact (linear) change of variables of the same theorem, an independent
route to the same bound (docs/reproductions/002.md)."""
from __future__ import annotations

import json

from conftest import run_cli
from lmidsl.pipeline import make_instance, solve_instance

Z = "zhang_quantized_loss"


def test_successive_reaches_the_exact_optimum_and_is_certified():
    code, out, err = run_cli("successive", f"{Z}.thm2", "--example", "paper-N2-robust", "--set", "N=1",
                             "--start", '{"Sbar": 1, "P3bar": 100}', "--max-iter", "25", "--json")
    assert code == 0, err
    doc = json.loads(out)
    gammas = [s["gamma"] for s in doc["history"] if s["gamma"] is not None]
    assert len(gammas) >= 2 and doc["gamma"] == min(gammas)
    exact = solve_instance(make_instance(f"{Z}.exact", example="paper-N2-robust", overrides={"N": 1}),
                           certify=False)
    assert exact.gamma * (1 - 1e-4) <= doc["gamma"] <= exact.gamma * 1.001, (doc["gamma"], exact.gamma)
    assert doc["verdict"]["certified"] is True


def test_successive_text_and_bad_input():
    code, out, err = run_cli("successive", f"{Z}.thm2", "--example", "paper-N2-robust", "--set", "N=1",
                             "--start", '{"Sbar": 1, "P3bar": 100}', "--max-iter", "3", env={"COLUMNS": "80"})
    assert code in (0, 1), err
    assert "stopped: start 0:" in " ".join(out.split()) and "iteration" in out
    assert max(len(line) for line in out.splitlines()) <= 80
    code, _, err = run_cli("successive", "textbook.brl_ct")
    assert code == 2 and "declares no linearisation point" in err and len(err.strip().splitlines()) == 1
    code, _, err = run_cli("successive", f"{Z}.thm2", "--example", "paper-N2-robust", "--start", '{"S": 1}')
    assert code == 2 and "not a datum of the linearisation point" in err
