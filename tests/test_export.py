"""`lmidsl export`: the compiled SDP written (PICOS' SDPA writer; CBF from the same numbers),
read back by our own readers and solved directly by cvxpy: same optimum within 1e-6 relative."""
import json

import pytest

from lmidsl.cli import main
from lmidsl.pipeline import make_instance, solve_instance
from lmidsl.studies.export import export, read_back, solve_sdpa_cvxpy, variables_from_x
from lmidsl.solver.solution import lmi_certificate

CASES = [("wang_l2linf.thm3", "paper-full"), ("li_delay_dropout.thm2", "paper"),
         ("interconnected_delay.thm2", "paper")]


@pytest.mark.parametrize("theorem_id,example", CASES)
def test_round_trip_same_optimum(theorem_id, example, tmp_path):
    instance = make_instance(theorem_id, example)
    own = solve_instance(instance, certify=False, diagnose=False).objective
    for fmt, suffix in (("sdpa", "dat-s"), ("cbf", "cbf")):
        path = tmp_path / f"p.{suffix}"
        export(instance, fmt, path)
        value, _ = solve_sdpa_cvxpy(read_back(path))
        assert abs(value - own) <= 1e-6 * abs(own), (fmt, value, own)


def test_map_names_blocks_and_variables(tmp_path):
    instance = make_instance("wang_l2linf.thm3", "paper-full")
    path = tmp_path / "w.dat-s"
    mapping = export(instance, "sdpa", path)
    assert [b["lmi"] for b in mapping["blocks"]] == ["(30)", "(31)", "P1 > 0", "P3 > 0"]
    assert [b["size"] for b in mapping["blocks"]] == [13, 5, 2, 2]
    assert {v["name"] for v in mapping["variables"]} == {"g", "P1", "P2", "P3", "V1", "V2", "V3",
                                                         "Af_hat", "Bf_hat", "Cf_hat"}
    assert json.loads((tmp_path / "w.dat-s.map.json").read_text())["nvars"] == mapping["nvars"] == 31
    # the file's solution mapped back through the map satisfies the theorem's own LMIs
    _, x = solve_sdpa_cvxpy(read_back(path))
    values = variables_from_x(mapping, x)
    reports = lmi_certificate(instance, {**instance.data, **values})
    assert all(r.max_eig < 1e-6 for r in reports), [(r.label, r.max_eig) for r in reports]


def test_cli_export_check(tmp_path, capsys):
    out = tmp_path / "w.cbf"
    assert main(["export", "wang_l2linf.thm3", "--example", "paper-full", "--format", "cbf",
                 "-o", str(out), "--check"]) == 0
    assert "same" in capsys.readouterr().out
    assert main(["export", "wang_l2linf.thm3", "--example", "paper-full", "--format", "sdpa",
                 "-o", str(tmp_path / "w.txt")]) == 2


def test_feasibility_problem_check(tmp_path, capsys):
    """A feasibility problem (decay rate at the example's α = 0.5): both routes find a point."""
    assert main(["export", "decay_rate.quadratic", "--example", "single", "--format", "sdpa",
                 "-o", str(tmp_path / "d.dat-s"), "--check"]) == 0
    assert "a certified point" in capsys.readouterr().out
