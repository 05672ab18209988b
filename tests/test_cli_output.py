"""The command line's output for people (issue 18): tables that fit 100 columns off a terminal,
no BrokenPipeError on a closed pipe, ``--version``, one set of flags for every solving command,
``--timeout``, progress off a terminal, and the short ``repr`` of results."""
from __future__ import annotations

import json
import re
import os
import subprocess
import sys
from dataclasses import fields
from importlib.metadata import version

import pytest
from rich.cells import cell_len

from conftest import ROOT, run_cli
from lmidsl.cli import build_parser
from lmidsl.cli.common import COMMON_FLAGS, parse_solver_options
from lmidsl.render.reproduction import format_reproduction
from lmidsl.render.table import format_table
from lmidsl.render.terminal import configure
from lmidsl.studies.reproduce import ReproductionRow

#: every command that solves (derive-check works in exact arithmetic and solves nothing)
SOLVING = ("solve", "verify", "check", "sweep", "search", "reproduce", "latex", "simulate", "export")
WIDTH = {"COLUMNS": "100"}


def assert_fits(text: str, width: int = 100):
    too_wide = [(cell_len(line), line) for line in text.splitlines() if cell_len(line) > width]
    assert not too_wide, too_wide[:3]


def assert_one_line_error(code, err, *fragments, exit_code=2):
    assert code == exit_code, (code, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and "Traceback" not in err, err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


@pytest.mark.parametrize("argv", [("list",), ("list", "--all")])
def test_list_fits_100_columns(argv):
    code, out, err = run_cli(*argv, env=WIDTH)
    assert code == 0, err
    assert_fits(out)
    assert "wang_l2linf.thm3" in out          # ids are never folded
    assert "\x1b[" not in out                 # no colour off a terminal


def test_list_fits_without_columns_and_wide_prints_everything():
    env = {k: v for k, v in os.environ.items() if k != "COLUMNS"}
    proc = subprocess.run([sys.executable, "-m", "lmidsl", "list"], capture_output=True, text=True,
                          env=env, cwd=ROOT, timeout=600)
    assert proc.returncode == 0 and proc.stdout
    assert_fits(proc.stdout)
    code, out, _ = run_cli("list", "--wide", env=WIDTH)
    assert code == 0
    assert max(cell_len(line) for line in out.splitlines()) > 100     # titles on one line
    assert any("Full- and reduced-order l2-l∞ filter synthesis (Theorem 3)" in line for line in out.splitlines())


def test_reproduce_fits_100_columns_and_leads_with_a_summary():
    code, out, err = run_cli("reproduce", "--theorem", "wang_l2linf.thm3", "--theorem", "wang_l2linf.thm1",
                             env=WIDTH)
    assert code == 0, err
    assert_fits(out)
    lines = out.splitlines()
    assert "docs/reproductions.md" in lines[0] + lines[1]
    summary = next(i for i, line in enumerate(lines) if line.startswith("paper "))
    assert lines[summary + 2].startswith("wang_l2linf ")          # one line per paper
    verdicts = lines.index("Verdicts:")
    assert summary < verdicts < next(i for i, line in enumerate(lines) if line.startswith("PAPER:"))
    definitions = "\n".join(lines[verdicts:verdicts + 12])
    for word in ("reproduced", "bound holds", "computed only", "certified"):
        assert f"  {word} " in definitions, word
    table = out[out.index("PAPER:"):]
    assert "-32.37%" in table and "bound holds" in table          # the printed bound holds, with room
    assert "computed (no printed value)" not in out
    # progress off a terminal: one line per finished row, on stderr (rows finish in any order
    # on the default 2 workers)
    assert re.search(r"reproduce \[[1-4]/4\] wang_l2linf\.thm1 \[paper-full-printed\]", err), err


def _row(**kw):
    base = dict(theorem="zhang_quantized_loss.thm2_literal", example="paper-N3-robust-long-name",
                printed_kind="gamma", printed_gamma=1.2584, computed_gamma=0.850646, rel_diff=0.324,
                status="optimal", worst_eig=-9.99e-8, certified_gamma=0.85, certified=False,
                comparison="differs from print, NOT certified (filter from the back-off at γ 0.8512)",
                exact_kind="h_infinity", exact_gamma=0.81, provenance="paper")
    base.update(kw)
    return ReproductionRow(**{f.name: base[f.name] for f in fields(ReproductionRow) if f.name in base})


def test_reproduction_text_fits_any_row_and_reads_clearly(monkeypatch):
    rows = [_row(), _row(theorem="wang_l2linf.thm1", example="paper-reduced-printed", printed_kind="gamma_bound",
                         printed_gamma=2.0103, computed_gamma=1.35951, certified=True,
                         comparison="printed bound holds"),
            _row(theorem="textbook.brl_dt", example="random-3", printed_gamma=None, certified=True,
                 comparison="computed (no printed value)", provenance="illustration", expect="certified"),
            _row(theorem="textbook.quadstab_dt", example="interval-3", printed_gamma=None, computed_gamma=None,
                 status="infeasible", comparison="infeasible", verdict={"certified": False, "word": "infeasible", "gamma": None, "why": "proved"}, provenance="illustration")]
    configure(wide=False)
    for width in (80, 100):
        monkeypatch.setenv("COLUMNS", str(width))
        text = format_reproduction(rows)
        assert_fits(text, width)
    assert "bound holds" in text and "-32.37%" in text and "computed only" in text
    flat = " ".join(text.split())                     # words, whatever the wrapping
    assert "WORSE than expected" in flat and "expects the outcome 'certified', it ended 'infeasible'" in flat
    assert "filter from the back-off at γ 0.8512" in flat     # the verdict's parenthesis, as a note
    assert "0.850646" not in text and "0.85065" in text        # five significant digits


def test_table_cells_are_measured_in_terminal_cells():
    text = format_table(["matrix", "note"], [["P̂", "x"], ["S̄ᵀ", "y"], ["Af", "z"]], width=100, color=False)
    rows = text.splitlines()[2:]
    # P̂ is two code points in one cell: the second column starts at the same cell in every row
    assert len({cell_len(row[:row.rindex(row.split()[-1])]) for row in rows}) == 1, text


def test_check_fits_100_columns():
    code, out, err = run_cli("check", "wang_l2linf.thm3", "--example", "paper-full",
                             "--solvers", "clarabel,picos:cvxopt", env=WIDTH)
    assert code == 0, err
    assert_fits(out)
    assert "0.3367405" in out                        # numbers are never folded
    assert "largest eigenvalue of each LMI" in out
    assert "check [3/3] picos:cvxopt" in err         # clarabel: on the direct and cvxpy backends


def test_closed_pipe_is_not_an_error():
    # the reader is gone before the command writes: the write fails with EPIPE
    proc = subprocess.Popen([sys.executable, "-m", "lmidsl", "list", "--all"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=ROOT)
    proc.stdout.close()
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert b"BrokenPipe" not in err and b"Traceback" not in err, err
    # as a user types it
    shell = subprocess.run(["bash", "-c", f"{sys.executable} -m lmidsl list | head -1; exit ${{PIPESTATUS[0]}}"],
                           capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert shell.returncode == 0, shell.stderr
    assert shell.stdout.startswith("interconnected_delay: ") and len(shell.stdout.splitlines()) == 1
    assert "error" not in shell.stderr


def test_version():
    code, out, err = run_cli("--version")
    assert code == 0, err
    assert out.strip() == f"lmidsl {version('lmidsl')}"


def _subparser(command):
    parser = build_parser([command])
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return sub.choices[command]


@pytest.mark.parametrize("command", SOLVING)
def test_every_solving_command_takes_the_common_flags(command):
    options = {s for action in _subparser(command)._actions for s in action.option_strings}
    assert set(COMMON_FLAGS) <= options, set(COMMON_FLAGS) - options
    argv = [command] + ([] if command == "reproduce" else ["wang_l2linf.thm3"]) + [
        "--backend", "cvxpy", "--solver", "clarabel", "--solver-option", "max_iter=50", "--margin", "1e-7",
        "--data", "x.json", "--set", "rbar=0.5", "--json", "--timeout", "60"]
    if command in ("sweep", "search"):
        argv += ["--grid", "rbar=0.1:0.9:3"]
    if command == "export":
        argv += ["--format", "sdpa", "-o", "x.dat-s"]
    args = build_parser(argv).parse_args(argv)
    assert (args.backend, args.solver, args.margin, args.data, args.json, args.timeout) == \
        ("cvxpy", "clarabel", 1e-7, "x.json", True, 60.0)
    assert args.overrides == ["rbar=0.5"] and args.solver_options == ["max_iter=50"]


def test_check_takes_solver_as_well_as_solvers():
    code, out, err = run_cli("check", "wang_l2linf.thm3", "--example", "paper-full", "--solver", "clarabel",
                             "--json")
    assert code == 0, err
    rows = json.loads(out)["rows"]
    assert [(r["backend"], r["solver"]) for r in rows] == [("direct", "CLARABEL"), ("cvxpy", "CLARABEL")]


def test_a_flag_a_command_cannot_honour_is_refused_in_one_line():
    assert_one_line_error(*run_cli("reproduce", "--set", "rbar=0.5")[::2], "--set", "reproduce")
    assert_one_line_error(*run_cli("latex", "wang_l2linf.thm3", "--solver", "scs")[::2], "--solver",
                          "--example")
    assert_one_line_error(*run_cli("export", "wang_l2linf.thm3", "--format", "json", "-o", "/tmp/x.json",
                                   "--solver", "scs")[::2], "--solver", "--check")
    assert_one_line_error(*run_cli("solve", "wang_l2linf.thm3", "--solver-option", "scs:eps=1")[::2],
                          "--solver-option", "CLARABEL")


def test_solver_options_reach_the_solver():
    code, out, err = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--solver", "clarabel",
                             "--solver-option", "max_iter=2", "--json")
    assert code == 1, err                                   # two iterations do not reach the optimum
    assert json.loads(out)["status"] != "optimal"
    assert parse_solver_options(["max_iter=5", "clarabel:tol_gap_rel=1e-9"]) == \
        {"": {"max_iter": 5}, "clarabel": {"tol_gap_rel": 1e-9}}


def test_timeout_stops_with_one_line_and_exit_1():
    code, _, err = run_cli("reproduce", "--timeout", "0.5", process=True)   # the clock covers start-up
    assert code == 1, err
    assert err.strip().splitlines()[-1].startswith("error: --timeout 0.5: stopped after 0.5 s"), err
    assert "Traceback" not in err


def test_solution_repr_is_one_line_and_theorem_has_latex():
    import lmidsl
    sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
    text = repr(sol)
    assert "\n" not in text and len(text) < 200, text
    assert text.startswith("<Solution wang_l2linf.thm3 [paper-full]: optimal, gamma=0.33674") and ("OPTIMAL" in text or "CERTIFIED" in text)
    theorem = lmidsl.get_theorem("wang_l2linf.thm3")
    latex = theorem._repr_latex_()
    assert latex.startswith("$$") and latex.endswith("$$") and "\\begin{bmatrix}" in latex
    assert "lmidisplay" not in latex and "fitlmi" not in latex     # no macros of the document's preamble
    assert repr(theorem).startswith("<Theorem wang_l2linf.thm3:")


@pytest.mark.parametrize("fired,expected", [(False, 130), (True, 1)])
def test_a_late_interrupt_never_kills_the_command_by_sigint(fired, expected):
    """A KeyboardInterrupt that escapes the command after it handled its own (a late signal in the
    clean-up, a second Ctrl-C) ends the process with an exit code — 1 after a deadline, 130 for an
    interrupt — never by SIGINT (Python's exit for an unhandled KeyboardInterrupt, seen as −2)."""
    import subprocess
    import sys
    script = ("import lmidsl.cli as c\n"
              f"c.Deadline.fired = {fired}\n"
              "def late(argv=None):\n    raise KeyboardInterrupt\n"
              "c.main = late\nc.console_main()\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == expected, (done.returncode, done.stderr)
    assert "Traceback" not in done.stderr
    assert ("error: interrupted" in done.stderr) == (not fired)


def test_a_sigint_after_the_command_ended_does_not_change_its_exit_code():
    """The command is over (exit 1 decided): a SIGINT reaching the process during the clean-up
    (Dask's workers closing, the interpreter's exit) leaves the exit code as it was."""
    import subprocess
    import sys
    script = ("import os, signal\nimport lmidsl.cli as c\n"
              "c.main = lambda argv=None: 1\n"
              "def ended():\n    os.kill(os.getpid(), signal.SIGINT)\n    return True\n"
              "c._background_work_ended = ended\nc.console_main()\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, (done.returncode, done.stderr)
    assert "Traceback" not in done.stderr
