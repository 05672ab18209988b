"""Nothing lost, nothing crashes (issue 15): bad input is one line with exit code 2, JSON out is
strict, long runs keep every finished point through an interrupt and resume without solving a
point twice."""
from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from conftest import ROOT
from lmidsl.cli import main
from lmidsl.errors import InputError
from lmidsl.studies.store import JsonLinesStore, strict_json
from lmidsl.render.text import format_timing
from lmidsl.studies.sweep import SweepPoint, SweepResult
from lmidsl.studies.defaults import parse_grid

THM3 = ("wang_l2linf.thm3", "--example", "paper-full")


def run_main(capsys, *argv):
    """The command line in-process: (exit code, stdout, stderr)."""
    try:
        code = main(list(argv))
    except SystemExit as exc:      # argparse
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line(code, err, *fragments, exit_code=2):
    assert code == exit_code, (code, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:"), err
    assert "Traceback" not in err and "internal error" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


# -- non-finite numbers, strings and booleans never get through ------------------------------
@pytest.mark.parametrize("argv,fragments", [
    (["solve", *THM3, "--set", "rbar=NaN"], ["--set rbar", "NaN"]),
    (["solve", *THM3, "--set", "rbar=Infinity"], ["--set rbar", "Infinity"]),
    (["solve", *THM3, "--set", "E=[[NaN],[0]]"], ["--set E", "NaN"]),
    (["solve", *THM3, "--set", "E=[[true],[0]]"], ["data E", "boolean"]),
    (["solve", *THM3, "--set", 'E=[["1"],[0]]'], ["data E", "string"]),
    (["solve", *THM3, "--set", "E=[[1],[0,2]]"], ["data E", "not a numeric matrix"]),
    (["solve", *THM3, "--set", 'rbar="0.5"'], ["parameter rbar", "number"]),
    (["solve", *THM3, "--margin", "nan"], ["--margin"]),
    (["solve", *THM3, "--margin", "0"], ["--margin"]),
    (["solve", *THM3, "--margin", "inf"], ["--margin"]),
    (["sweep", *THM3, "--grid", "rbar=0.6,nan"], ["--grid", "finite"]),
    (["sweep", *THM3, "--grid", "rbar=nan:0.9:3"], ["--grid", "finite"]),
    (["sweep", *THM3, "--grid", "rbar=0.01:0.99:100000000"], ["100000000 points", "--max-points"]),
    (["sweep", *THM3, "--grid", "rbar=0.1:0.9:20", "--grid", "rbar=0.1:0.9:20",
      "--max-points", "100"], ["400 points", "--max-points"]),
    (["verify", *THM3, "--horizon", "0"], ["--horizon"]),
    (["verify", *THM3, "--confidence", "nan"], ["--confidence"]),
    (["reproduce", "--theorem", "nope.thm9"], ["unknown theorem", "nope.thm9"]),
    (["check", *THM3, "--solvers", "bogus"], ["bogus"]),
    (["solve", *THM3, "--solver", "MOSEK"], ["MOSEK", "not installed", "pip install mosek"]),
    (["latex", "wang_l2linf.thm3", "-o", "/etc/hostname/x.tex"], ["/etc/hostname is not a directory"]),
    (["sweep", *THM3, "--grid", "rbar=0.3,0.4", "--out", "/etc/hostname/sub"],
     ["/etc/hostname is not a directory"]),
])
def test_bad_input_is_one_line_exit_2(capsys, argv, fragments):
    code, _, err = run_main(capsys, *argv)
    if code == 2 and err.startswith("error: lmidsl"):      # argparse's own one-line error
        assert len(err.strip().splitlines()) == 1 and all(f in err for f in fragments), err
        return
    assert_one_line(code, err, *fragments)


def test_data_file_with_nan_is_refused(capsys, tmp_path):
    path = tmp_path / "plant.json"
    path.write_text('{"rbar": NaN}')
    code, _, err = run_main(capsys, "solve", *THM3, "--data", str(path))
    assert_one_line(code, err, "--data", "NaN")


def test_ragged_design_file_is_refused(capsys, tmp_path):
    path = tmp_path / "design.json"
    path.write_text(json.dumps({"Af": [[1, 2], [3]], "Bf": [[1], [2]], "Cf": [[1, 2]]}))
    code, _, err = run_main(capsys, "verify", *THM3, "--design", str(path), "--runs", "0")
    assert_one_line(code, err, "--design", "Af")


def test_dimension_must_be_an_integer():
    from lmidsl.symbolic.numbers import finite_matrix, positive_integer
    with pytest.raises(InputError, match="positive integer"):
        positive_integer(2.0, "n")
    with pytest.raises(InputError, match="positive integer"):
        positive_integer(True, "n")
    assert positive_integer(np.int64(3), "n") == 3
    with pytest.raises(InputError, match=r"entry \[1\]\[0\]"):
        finite_matrix([[1.0], [float("inf")]], "A")
    assert finite_matrix(np.eye(2), "A").shape == (2, 2)


# -- strict JSON -----------------------------------------------------------------------------
def test_strict_json_writes_null_and_says_so():
    text = strict_json({"gamma": float("inf"), "points": [1.0, float("nan")], "x": np.float64(2.0)})
    data = json.loads(text)          # strict: would fail on Infinity / NaN tokens
    assert data["gamma"] is None and data["points"] == [1.0, None] and data["x"] == 2.0
    assert any("gamma" in n for n in data["notes"]) and any("points[1]" in n for n in data["notes"])
    assert "Infinity" not in text and "NaN" not in text


def test_sweep_where_every_point_fails_reports_no_division_by_zero():
    points = [SweepPoint({"rbar": v}, "solver_error", None, None, None, 0.0, None, 0.01) for v in (0.1, 0.2)]
    result = SweepResult("t.x", None, "CLARABEL", {"rbar": [0.1, 0.2]}, points)
    timing = result.timing()
    assert math.isnan(timing["overhead_ratio"])
    format_timing(timing)
    assert json.loads(strict_json(result.as_dict()))["proved_points"] == 0


def test_parse_grid_limits():
    assert parse_grid("x=0:1:3") == ("x", [0.0, 0.5, 1.0])
    with pytest.raises(InputError, match="--max-points"):
        parse_grid("x=0:1:11", max_points=10)


# -- theorem files: A.I*A.I, singular inverses -----------------------------------------------
INVERSE_THEOREM = '''
from lmidsl import Theorem, Source, I
thm = Theorem("{stem}.t1", "inverse squared", Source("test", "(1)"))
n = thm.dim("n")
A = thm.data("A", n, n)
P = thm.var("P", n, kind="symmetric")
thm.lmi("(1)", [[A.I * A.I * P + P * (A.I * A.I).T - I]])
thm.example("ok", {{"A": [[2.0, 0.0], [0.0, 4.0]]}})
thm.example("singular", {{"A": [[1.0, 0.0], [0.0, 0.0]]}})
THEOREMS = [thm]
'''


def test_inverse_squared_and_singular_inverse(capsys, tmp_path, monkeypatch):
    (tmp_path / "invsq.py").write_text(INVERSE_THEOREM.format(stem="invsq"))
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", str(tmp_path))
    from lmidsl.pipeline import make_instance
    from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix
    instance = make_instance("invsq.t1", "ok")
    P = np.eye(2)
    M = evaluate_block_matrix(NumericEvaluator(instance.dims, {**instance.data, "P": P}, {}),
                              instance.theorem.lmis[0].spec)
    Ai2 = np.linalg.inv(np.diag([2.0, 4.0])) @ np.linalg.inv(np.diag([2.0, 4.0]))
    assert np.allclose(M, Ai2 @ P + P @ Ai2.T - np.eye(2))
    code, _, err = run_main(capsys, "solve", "invsq.t1", "--example", "singular")
    assert_one_line(code, err, "inverse of A", "singular")


# -- durable, resumable long runs ------------------------------------------------------------
def _env(tmp_path):
    env = dict(os.environ)
    env.pop("LMIDSL_DEBUG", None)
    env["LMIDSL_CACHE_DIR"] = str(tmp_path / "cache")
    return env


def _records(path):
    lines = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return lines[0]["header"], [line["record"] for line in lines[1:]]


def _as_from_a_shell():
    """The child's SIGINT as a shell starts a command: default action, not blocked (whatever an
    earlier test left in this test process: in the whole slow suite the three Ctrl-C tests below
    saw their command run to its end, while they pass alone)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def _interrupt_after(argv, store, n_records, tmp_path, timeout=300, group=False):
    """Run lmidsl, send SIGINT once ``store`` holds ``n_records``; ``group``: to the whole process
    group, as Ctrl-C at a terminal does (workers included), else to lmidsl's process only."""
    proc = subprocess.Popen([sys.executable, "-m", "lmidsl", *argv], cwd=ROOT, env=_env(tmp_path),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=group, preexec_fn=_as_from_a_shell)
    deadline = time.time() + timeout
    while time.time() < deadline and proc.poll() is None:
        if store.exists() and len(store.read_text().splitlines()) >= 1 + n_records:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "finished before it could be interrupted: " + proc.stderr.read()
    if group:
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, out, err


@pytest.mark.slow
def test_ctrl_c_to_a_sweep_on_local_workers_ends_it_cleanly(tmp_path):
    """Ctrl-C reaches every process of the terminal's group: the workers (forked from a fork
    server started with SIGINT ignored) go on quietly, the main process stores what finished,
    closes the cluster, and exits 130 with one message; no process of the run is left."""
    import psutil

    out = tmp_path / "out"
    argv = ["sweep", *THM3, "--grid", "rbar=0.2:0.9:150", "--out", str(out), "--workers", "2"]
    code, _, err = _interrupt_after(argv, out / "sweep.jsonl", 4, tmp_path, group=True)
    assert code == 130, err
    assert "interrupted after" in err and "--resume" in err and "Traceback" not in err
    _, before = _records(out / "sweep.jsonl")
    assert len(before) >= 4
    time.sleep(2)
    left = [p for p in psutil.process_iter(["cmdline", "environ"])
            if (p.info["environ"] or {}).get("LMIDSL_CACHE_DIR") == str(tmp_path / "cache")]
    assert not left, [p.info["cmdline"] for p in left]


@pytest.mark.slow
def test_sweep_interrupted_then_resumed_loses_nothing_and_solves_nothing_twice(tmp_path):
    out = tmp_path / "out"
    argv = ["sweep", *THM3, "--grid", "rbar=0.2:0.9:150", "--out", str(out)]
    code, _, err = _interrupt_after(argv, out / "sweep.jsonl", 4, tmp_path)
    assert code == 130, err
    assert "interrupted after" in err and "sweep.jsonl" in err and "--resume" in err
    assert "Traceback" not in err
    _, before = _records(out / "sweep.jsonl")
    assert len(before) >= 4
    assert not (out / "sweep.csv").exists()          # final files only at the end
    proc = subprocess.run([sys.executable, "-m", "lmidsl", *argv, "--resume", "--json"], cwd=ROOT,
                          env=_env(tmp_path), capture_output=True, text=True, timeout=600)
    assert proc.returncode in (0, 1), proc.stderr
    result = json.loads(proc.stdout)
    assert result["resumed"] == len(before) and result["solved"] == 150 - len(before)
    _, after = _records(out / "sweep.jsonl")
    assert after[:len(before)] == before                               # kept as they were
    keys = [p["params"]["rbar"] for p in after]
    assert len(keys) == len(set(keys)) == 150                          # none twice, none lost
    grid = parse_grid("rbar=0.2:0.9:150")[1]
    assert sorted(keys) == sorted(grid)
    assert [p["params"]["rbar"] for p in result["points"]] == grid     # in grid order
    saved = json.loads((out / "sweep.json").read_text())
    assert len(saved["points"]) == 150
    assert len((out / "sweep.csv").read_text().splitlines()) == 151
    assert (out / "sweep.png").stat().st_size > 0
    # no temporary left (the lock file of --out stays: one run per --out at a time, flock)
    assert not [p for p in out.iterdir() if p.name.startswith(".") and not p.name.endswith(".lock")]


def test_resume_refuses_another_grid(capsys, tmp_path):
    store = JsonLinesStore(tmp_path / "sweep.jsonl")
    store.open({"kind": "sweep", "grid": {"rbar": [0.1]}})
    store.append({"x": 1})
    store.close()
    with open(tmp_path / "sweep.jsonl", "a") as fh:
        fh.write('{"record": {"x": 2')                 # torn by an interrupt
    again = JsonLinesStore(tmp_path / "sweep.jsonl")
    assert again.open({"kind": "sweep", "grid": {"rbar": [0.1]}}, resume=True) == [{"x": 1}]
    again.close()
    with pytest.raises(InputError, match="another run"):
        JsonLinesStore(tmp_path / "sweep.jsonl").open({"kind": "sweep", "grid": {"rbar": [0.2]}}, resume=True)


@pytest.mark.slow
def test_reproduce_interrupted_then_resumed(tmp_path):
    out = tmp_path / "rep"
    argv = ["reproduce", "--theorem", "wang_l2linf.thm3", "--theorem", "wang_l2linf.thm1",
            "--theorem", "wang_l2linf.cor1", "--out", str(out)]
    code, _, err = _interrupt_after(argv, out / "reproduce.jsonl", 1, tmp_path)
    assert code == 130, err
    assert "reproduce.jsonl" in err and "Traceback" not in err
    _, before = _records(out / "reproduce.jsonl")
    proc = subprocess.run([sys.executable, "-m", "lmidsl", *argv, "--resume", "--json"], cwd=ROOT,
                          env=_env(tmp_path), capture_output=True, text=True, timeout=900)
    assert proc.returncode in (0, 1), proc.stderr
    rows = json.loads(proc.stdout)["rows"]
    _, after = _records(out / "reproduce.jsonl")
    assert after[:len(before)] == before
    keys = [(r["theorem"], r["example"]) for r in after]
    assert len(keys) == len(set(keys)) == len(rows)
    assert json.loads((out / "reproduce.json").read_text())["rows"] == rows


# -- theorem files isolated ----------------------------------------------------------------
GOOD = '''
from lmidsl import Theorem, Source
thm = Theorem("{id}", "{title}", Source("test", "(1)"))
n = thm.dim("n")
A = thm.data("A", n, n)
P = thm.var("P", n, kind="symmetric")
thm.lmi("(1)", [[A.T * P * A - P]])
thm.lmi("P > 0", [[-P]])
thm.example("ok", {{"A": [[0.5, 0.0], [0.0, 0.2]]}})
THEOREMS = [thm]
'''


def _user_env(tmp_path, folder):
    """User theorem files in ``folder``, with the test run's cache folder (conftest), where the
    built-in theorems are built already (the user files are entries of their own)."""
    env = _env(tmp_path)
    env["LMIDSL_CACHE_DIR"] = os.environ["LMIDSL_CACHE_DIR"]
    env["LMIDSL_THEOREM_PATH"] = str(folder)
    return env


def _cli(env, *argv):
    proc = subprocess.run([sys.executable, "-m", "lmidsl", *argv], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=600)
    return proc.returncode, proc.stdout, proc.stderr


def test_broken_user_file_is_reported_once_and_skipped(tmp_path):
    folder = tmp_path / "thms"
    folder.mkdir()
    (folder / "good.py").write_text(GOOD.format(id="good.t1", title="a good one"))
    (folder / "broken.py").write_text("from lmidsl import Theorem\nx = 1\ndef f(:\n")
    (folder / "raises.py").write_text("import lmidsl\nx = 1\nraise RuntimeError('boom')\n")
    env = _user_env(tmp_path, folder)
    code, out, err = _cli(env, "list")
    assert code == 0, err
    assert "good.t1" in out and "wang_l2linf.thm3" in out            # built-ins keep working
    lines = err.strip().splitlines()
    assert len(lines) == 2, err                                      # one line per broken file
    assert any("broken.py, line 3" in l and "SyntaxError" in l for l in lines), err
    assert any("raises.py, line 3" in l and "RuntimeError: boom" in l for l in lines), err
    assert "Traceback" not in err
    # solving a theorem of another file executes neither broken file: nothing to report
    code, out, err = _cli(env, "solve", "good.t1", "--example", "ok")
    assert code == 0 and err.strip() == "", err
    # asking for the broken file's theorem is that file's error, in one line
    code, _, err = _cli(env, "solve", "raises.t1")
    assert_one_line(code, err, "raises.py, line 3", "RuntimeError: boom")


def test_duplicate_id_names_both_files(capsys, tmp_path, monkeypatch):
    for name in ("dupa", "dupb"):
        folder = tmp_path / name
        folder.mkdir()
    (tmp_path / "dupa" / "wang_l2linf.py").write_text(GOOD.format(id="wang_l2linf.thm3", title="shadow"))
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", str(tmp_path / "dupa"))
    code, _, err = run_main(capsys, "solve", "wang_l2linf.thm3", "--example", "paper-full")
    assert_one_line(code, err, "wang_l2linf.thm3", "defined twice", "lmidsl.theorems.wang_l2linf",
                    str(tmp_path / "dupa" / "wang_l2linf.py"))
    (tmp_path / "dupb" / "mine.py").write_text(GOOD.format(id="mine.t1", title="one"))
    (tmp_path / "dupa" / "wang_l2linf.py").unlink()
    (tmp_path / "dupa" / "mine.py").write_text(GOOD.format(id="mine.t1", title="two"))
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", f"{tmp_path / 'dupa'}{os.pathsep}{tmp_path / 'dupb'}")
    code, _, err = run_main(capsys, "solve", "mine.t1", "--example", "ok")
    assert_one_line(code, err, "mine.t1", str(tmp_path / "dupa" / "mine.py"), str(tmp_path / "dupb" / "mine.py"))


def test_relative_theorem_path_is_refused(capsys, monkeypatch):
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", "my_theorems")
    code, _, err = run_main(capsys, "solve", *THM3)
    assert_one_line(code, err, "LMIDSL_THEOREM_PATH", "'my_theorems'", "relative")


def test_only_the_file_the_id_names_is_executed(capsys, tmp_path, monkeypatch):
    (tmp_path / "alpha.py").write_text(GOOD.format(id="alpha.t1", title="alpha"))
    (tmp_path / "beta.py").write_text(f"open({str(tmp_path / 'beta-ran')!r}, 'w').close()\nTHEOREMS = []\n")
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", str(tmp_path))
    code, _, err = run_main(capsys, "solve", "alpha.t1", "--example", "ok")
    assert code == 0, err
    assert not (tmp_path / "beta-ran").exists()
    code, _, err = run_main(capsys, "solve", *THM3, "--no-certify")
    assert not (tmp_path / "beta-ran").exists()


def test_nonconforming_integer_dimensions_name_the_file_and_line(capsys, tmp_path, monkeypatch):
    (tmp_path / "shapes.py").write_text(textwrap.dedent('''
        from lmidsl import Theorem, Source
        thm = Theorem("shapes.t1", "bad product", Source("test", "(1)"))
        A = thm.data("A", 2, 3)
        P = thm.var("P", 2, kind="symmetric")
        thm.lmi("(1)", [[A * A.T * P + P * A]])
        THEOREMS = [thm]
        '''))
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", str(tmp_path))
    code, _, err = run_main(capsys, "solve", "shapes.t1")
    assert_one_line(code, err, "shapes.py, line 6")


# -- start-up: only what the command needs ---------------------------------------------------
HEAVY = ("cvxpy", "picos", "matplotlib", "scipy.optimize")

PROBE = '''
import sys
from lmidsl.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
print("MODULES", " ".join(sorted(sys.modules)), file=sys.stderr)
'''


def _modules_after(env, *argv):
    proc = subprocess.run([sys.executable, "-c", PROBE, *argv], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=600)
    line = [l for l in proc.stderr.splitlines() if l.startswith("MODULES ")][-1]
    return proc.stdout, set(line.split()[1:])


def test_help_and_list_do_not_import_the_numerical_stack(tmp_path):
    env = _env(tmp_path)
    out, modules = _modules_after(env, "--help")
    assert "solve" in out and "sweep" in out
    assert not [m for m in modules if m.split(".")[0] in ("cvxpy", "picos", "matplotlib", "sympy", "scipy")]
    cold, _ = _modules_after(env, "list")             # builds the index (loads the theorems)
    warm, modules = _modules_after(env, "list")       # reads it
    assert warm == cold and "wang_l2linf.thm3" in warm
    assert not [m for m in modules if m.startswith(HEAVY) or m == "sympy"], \
        sorted(m for m in modules if m.startswith(HEAVY))


def test_list_index_is_rebuilt_when_a_file_changes(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("LMIDSL_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "thms").mkdir()
    monkeypatch.setenv("LMIDSL_THEOREM_PATH", str(tmp_path / "thms"))
    (tmp_path / "thms" / "mine.py").write_text(GOOD.format(id="mine.t1", title="first title"))
    code, out, _ = run_main(capsys, "list")
    assert code == 0 and "first title" in out
    assert len(list((tmp_path / "cache").glob("theorem-index-*.json"))) == 1
    (tmp_path / "thms" / "mine.py").write_text(GOOD.format(id="mine.t1", title="second title"))
    from lmidsl.theorem import registry
    registry._load_module.cache_clear()               # a new process would not have it loaded
    for name in [m for m in sys.modules if m.startswith("lmidsl_user_theorems_mine")]:
        del sys.modules[name]
    code, out, _ = run_main(capsys, "list")
    assert code == 0 and "second title" in out and "first title" not in out
    assert len(list((tmp_path / "cache").glob("theorem-index-*.json"))) == 1
