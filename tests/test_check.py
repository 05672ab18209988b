"""`lmidsl check`: rows per backend × solver, trust, disagreement flagged, failures as rows."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("picos")

from lmidsl.studies.cross_check import CheckRow, check, compare, options_for, plan_rows  # noqa: E402
from lmidsl.cli.check_cmd import parse_solver_options  # noqa: E402
from lmidsl.errors import InputError  # noqa: E402
import conftest  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
THM3 = ("wang_l2linf.thm3", "--example", "paper-full")


def run_cli(*args):
    """``lmidsl check ARGS``: (exit code, stdout, stderr), in this process (conftest.run_cli)."""
    return conftest.run_cli("check", *args)


@pytest.fixture(scope="module")
def default_check():
    """The default cross-check of Theorem 3 on the paper's example (all backends × SDP solvers)."""
    code, stdout, stderr = run_cli(*THM3, "--json")
    return code, json.loads(stdout)


def test_default_check_rows_and_agreement(default_check):
    code, result = default_check
    rows = result["rows"]
    names = {(r["backend"], r["solver"].lower()) for r in rows}
    assert len(rows) >= 4
    assert ("picos", "cvxopt") in names and ("cvxpy", "clarabel") in names and ("cvxpy", "cvxopt") in names
    trusted = [r for r in rows if r["trusted"]]
    assert len(trusted) >= 3 and any(r["backend"] == "picos" for r in trusted)
    gammas = [r["optimum_level"] for r in trusted]                     # the optima the rows compare
    assert (max(gammas) - min(gammas)) / min(gammas) < 1e-3          # the trusted answers agree
    assert abs(min(gammas) - 0.3367) < 1e-3                            # docs/reproductions/000.md: optimum 0.336741
    assert result["agree"] and result["exit_code"] == 0 and code == 0
    for r in trusted:                                                  # the certificate really holds
        assert all(l["max_eig"] < 0 for l in r["lmis"]) and r["analysis"]["passed"]


def test_scs_is_shown_with_its_deviation_but_not_a_disagreement(default_check):
    _, result = default_check
    scs = [r for r in result["rows"] if r["solver"].lower() == "scs"]
    if not scs:
        pytest.skip("SCS not installed")
    row = scs[0]
    assert not row["trusted"] and not row["disagrees"]
    if row["optimum_level"] is not None:                               # its γ and deviation are visible
        assert row["rel_diff"] is not None
        assert row["rel_diff"] >= -1e-6                                # never below the certified optimum
    assert row["reason"]
    # capped by default at a small multiple of the interior-point rows' time, and it says so
    exact = sorted(r["wall_time"] for r in result["rows"] if r["solver"].lower() != "scs" and not r["error"])
    assert row["capped"] >= 2.0 and "capped at" in row["reason"]
    assert row["capped"] == pytest.approx(max(3 * exact[(len(exact) - 1) // 2], 2.0), rel=0.5)


def test_forced_disagreement_is_flagged():
    """Clarabel with a loose duality-gap tolerance stops early yet reports 'optimal': its point is
    feasible (certified) but γ is ~3e-3 above the optimum, beyond 1e-3 -> flagged, exit code 1.
    CVXOPT (PICOS) with 10 iterations returns a certified point with status optimal_inaccurate:
    shown with its deviation, not counted."""
    result = check("wang_l2linf.thm3", example="paper-full",
                   solvers="cvxpy:clarabel,cvxpy:cvxopt,picos:cvxopt",
                   options={"cvxpy:clarabel": {"tol_gap_rel": 1.0, "tol_gap_abs": 1.0},
                            "picos:cvxopt": {"max_iterations": 10}})
    rows = {r.name: r for r in result.rows}
    loose, good, capped = rows["cvxpy/CLARABEL"], rows["cvxpy/CVXOPT"], rows["picos/cvxopt"]
    assert loose.trusted and loose.disagrees and loose.rel_diff > 1e-3
    assert good.trusted and not good.disagrees
    assert result.reference is good
    assert not capped.trusted and not capped.disagrees and capped.rel_diff is not None
    assert capped.rel_diff > 1e-3                                      # visible, not hidden
    assert not result.agree and result.exit_code == 1
    assert "DISAGREEMENT" in result.summary() and "cvxpy/CLARABEL" in result.summary()


def test_forced_disagreement_cli_exit_code():
    code, stdout, _ = run_cli(*THM3, "--solvers", "clarabel,picos:cvxopt",
                              "--solver-option", "cvxpy:clarabel:tol_gap_rel=1.0",
                              "--solver-option", "clarabel:tol_gap_abs=1.0")
    assert code == 1
    assert "DISAGREEMENT" in stdout and "!" in stdout


def test_failing_solvers_are_rows_not_crashes():
    result = check("wang_l2linf.thm3", example="paper-full",
                   solvers=["picos:scs", "cvxpy:clarabel", "picos:cvxopt"],
                   options={"picos:cvxopt": {"no_such_option": 1}})
    rows = {r.name: r for r in result.rows}
    assert rows["picos/scs"].status == "error" and "no interface" in rows["picos/scs"].error
    assert rows["picos/cvxopt"].status == "error" and "no_such_option" in rows["picos/cvxopt"].error
    assert rows["cvxpy/CLARABEL"].trusted
    assert result.exit_code == 0                                       # one trusted answer, nothing disagrees


def test_iteration_limited_row_without_point():
    """Clarabel stopped after 3 iterations has no point: an untrusted row, not a crash."""
    result = check("wang_l2linf.thm3", example="paper-full", solvers="cvxpy:clarabel",
                   options={"clarabel": {"max_iter": 3}})
    (row,) = result.rows
    assert not row.holds and not row.trusted and row.gamma is None
    assert result.exit_code == 1 and "NO TRUSTED" in result.summary()


def _row(name, value, trusted, holds=True):
    b, s = name.split("/")
    return CheckRow(b, s, value=value, gamma=value, trusted=trusted, holds=holds)


def test_compare_reference_is_the_smallest_trusted_value():
    rows = [_row("a/x", 1.0005, True), _row("b/y", 1.0, True), _row("c/z", 1.002, True),
            _row("d/scs", 1.05, False), _row("e/w", 0.9, False, holds=False)]
    ref = compare(rows, 1e-3)
    assert ref is rows[1]
    assert [r.disagrees for r in rows] == [False, False, True, False, False]
    assert rows[3].rel_diff == pytest.approx(0.05) and rows[4].rel_diff == pytest.approx(-0.1)


def test_plan_rows_entries():
    rows = plan_rows("picos:cvxopt,clarabel")
    assert ("picos", "cvxopt", None) in rows and ("cvxpy", "CLARABEL", None) in rows
    both = plan_rows("cvxopt")                                         # a bare solver: every backend with it
    assert {(b, s.lower()) for b, s, e in both} == {("cvxpy", "cvxopt"), ("picos", "cvxopt")}
    (bad,) = plan_rows("picos:clarabel")
    assert bad[2] and "no interface" in bad[2]
    with pytest.raises(InputError, match="unknown backend"):
        plan_rows("nosuch:cvxopt")


def test_solver_option_parsing():
    opts = parse_solver_options(["clarabel:max_iter=5", "picos:cvxopt:rel_ipm_opt_tol=0.5",
                                 "cvxpy:scs:acceleration_lookback=-10", "clarabel:direct_solve_method=qdldl"])
    assert opts == {"clarabel": {"max_iter": 5, "direct_solve_method": "qdldl"},
                    "picos:cvxopt": {"rel_ipm_opt_tol": 0.5}, "cvxpy:scs": {"acceleration_lookback": -10}}
    assert options_for("cvxpy", "CLARABEL", opts) == {"max_iter": 5, "direct_solve_method": "qdldl"}
    assert options_for("cvxpy", "CVXOPT", opts) == {}
    assert options_for("picos", "cvxopt", opts) == {"rel_ipm_opt_tol": 0.5}
    # without a solver an option is for every row (the flag every solving command shares)
    assert parse_solver_options(["max_iter=5"]) == {"": {"max_iter": 5}}
    assert options_for("picos", "cvxopt", {"": {"max_iter": 5}, "cvxopt": {"max_iter": 7}}) == {"max_iter": 7}
    for bad in (["max_iter"], ["clarabel:=5"]):
        with pytest.raises(InputError):
            parse_solver_options(bad)


def test_bad_input_exits_2():
    code, _, stderr = run_cli(*THM3, "--solvers", "nosuch:x")
    assert code == 2 and stderr.startswith("error:") and len(stderr.strip().splitlines()) == 1


def test_check_backs_off_and_compares_the_optima():
    """H∞ filter, random-3: at the optimum the recovered filter is not certified on any row (its
    analysis γ was 7572 and 416 against 2.665), so `check` said NO TRUSTED ANSWER (exit 1) while
    `lmidsl solve` certified a design.  Now each row (one named solver, no closed form) backs off;
    the value compared is the optimum's, which the solvers agree on, and each design is certified
    at its back-off point.  `solve` delivers the closed form's filter instead of a back-off
    (pipeline.closed_form_design), 1e-6 above the proved optimum: no worse than the row's design."""
    from lmidsl.pipeline import solve

    result = check("textbook.hinf_filter_ct", example="random-3", solvers="direct:clarabel,picos:cvxopt")
    alone = solve("textbook.hinf_filter_ct", "random-3")
    assert alone.verdict.certified and not alone.backoff
    direct = next(r for r in result.rows if r.backend == "direct")
    assert direct.backoff_gamma is not None and direct.holds and direct.trusted
    assert direct.optimum_level <= alone.point_gamma      # the SDP's optimum, below the closed form's point
    assert direct.optimum_level < direct.backoff_gamma <= direct.optimum_level * 1.011   # δ = 1 % on γ²
    assert alone.gamma * (1 - 1e-9) <= direct.gamma <= alone.gamma * (1 + 1e-3)
    assert direct.optimum_lmis and max(r["max_eig"] for r in direct.optimum_lmis) < 0
    assert result.agree and result.exit_code == 0
    for row in result.rows:
        if row.value is not None and row.holds:
            assert abs(row.value - direct.value) <= 1e-3 * direct.value
