"""Independent points on Dask (lmidsl.studies.parallel): a sweep on a LocalCluster of two
processes gives the serial sweep's points and a complete store; an existing cluster given by
address (spawned workers) resumes a stored sweep; check rows in parallel equal the serial rows; bad --scheduler / --workers input is one line, exit 2.
No timing is asserted (benchmarks/bench_parallel.py measures)."""
from __future__ import annotations

import json
import logging

import pytest

from lmidsl.cli import main
from lmidsl.studies import parallel
from lmidsl.studies.sweep import sweep

THM3 = ("wang_l2linf.thm3", "--example", "paper-full")
GRID = [("rbar", [0.2, 0.35, 0.5, 0.65, 0.8])]


def _records(path):
    lines = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return lines[0]["header"], [line["record"] for line in lines[1:]]


def _gammas(result):
    return [p.gamma for p in result.points]


@pytest.fixture(scope="module")
def serial():
    return sweep("wang_l2linf.thm3", GRID, example="paper-full")


def _numbers(result):
    return [(p.params, p.status, p.gamma, p.objective, p.worst_eig, p.proved, p.verdict.as_dict())
            for p in result.points]


def test_sweep_on_a_local_cluster_equals_the_serial_sweep_and_stores_every_point(serial, tmp_path, monkeypatch):
    """The cluster started after the first point (no start-up cost assumed): points are solved
    in this process while the workers start, the rest on the workers once they have joined;
    every number is the serial one, bit for bit."""
    monkeypatch.setattr(parallel, "START_COST", 0.0)
    store = tmp_path / "sweep.jsonl"
    result = sweep("wang_l2linf.thm3", GRID, example="paper-full", workers=2, store=store)
    assert [p.params for p in result.points] == [p.params for p in serial.points]   # grid order
    assert all(g is not None for g in _gammas(serial))
    assert _numbers(result) == _numbers(serial)
    stats = result.parallel
    assert stats["cluster_started"] and stats["items_here"] >= 1
    assert stats["items_here"] + stats["items_on_workers"] == len(GRID[0][1])
    assert result.solved == len(GRID[0][1]) and result.resumed == 0
    _, records = _records(store)
    assert sorted(r["params"]["rbar"] for r in records) == GRID[0][1]        # each point once


def test_a_sweep_too_small_to_pay_for_workers_starts_none_and_is_the_serial_sweep(serial, monkeypatch):
    """5 points of a few tens of ms: what workers would save is less than their start-up, so no
    cluster is started (a 2×2 sweep on 2 workers costs what it costs serially)."""
    monkeypatch.setattr(parallel, "START_COST", 1e3)
    result = sweep("wang_l2linf.thm3", GRID, example="paper-full", workers=2)
    assert result.parallel["cluster_started"] is False
    assert result.parallel["items_here"] == len(GRID[0][1]) and result.parallel["tasks"] == 0
    assert _numbers(result) == _numbers(serial)


def test_a_resumed_sweep_on_workers_is_the_serial_sweep(serial, tmp_path, monkeypatch):
    """Interrupted serially after two points, resumed on 2 workers: the same numbers."""
    monkeypatch.setattr(parallel, "START_COST", 0.0)
    store = tmp_path / "sweep.jsonl"
    sweep("wang_l2linf.thm3", GRID, example="paper-full", store=store)
    lines = store.read_text().splitlines(keepends=True)
    store.write_text("".join(lines[:3]))
    result = sweep("wang_l2linf.thm3", GRID, example="paper-full", workers=2, store=store, resume=True)
    assert result.resumed == 2 and result.solved == len(GRID[0][1]) - 2
    assert _numbers(result) == _numbers(serial)


@pytest.mark.slow
def test_existing_cluster_by_address_resumes_a_stored_sweep(tmp_path):
    """Spawned workers (a fresh interpreter, no theorem loaded): li_delay_dropout.thm2 has a
    structured variable, whose expansion lives in the symbols' metadata sent with the task."""
    from distributed import LocalCluster

    grid = [("xi1", [0.3, 0.6, 0.9])]
    store = tmp_path / "sweep.jsonl"
    serial = sweep("li_delay_dropout.thm2", grid, example="paper", store=store)
    lines = store.read_text().splitlines(keepends=True)
    store.write_text("".join(lines[:2]))          # the header and one point, as an interrupt leaves it
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.CRITICAL) as cluster:
        result = sweep("li_delay_dropout.thm2", grid, example="paper", store=store, resume=True,
                       scheduler=cluster.scheduler_address)
    assert result.resumed == 1 and result.solved == 2
    assert _numbers(result) == _numbers(serial)
    _, after = _records(store)
    assert sorted(r["params"]["xi1"] for r in after) == grid[0][1]


def _run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


@pytest.mark.parametrize("extra,fragment", [
    (["--scheduler", "nonsense://"], "expected an address"),
    (["--scheduler", "tcp://localhost:x"], "expected an address"),
    (["--scheduler", "tcp://127.0.0.1:9"], "cannot connect"),
    (["--scheduler", "tcp://127.0.0.1:9", "--workers", "2"], "not both"),
    (["--workers", "0"], "--workers"),
])
def test_bad_parallel_input_is_one_line_exit_2(capsys, monkeypatch, extra, fragment):
    monkeypatch.setattr(parallel, "CONNECT_TIMEOUT", 1)
    code, err = _run(capsys, "sweep", *THM3, "--grid", "rbar=0.3,0.5", *extra)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and fragment in lines[0], err


@pytest.mark.slow
def test_check_rows_in_parallel_equal_the_serial_rows():
    from lmidsl.studies.cross_check import check

    serial = check("wang_l2linf.thm3", example="paper-full", solvers="clarabel,cvxopt")
    both = check("wang_l2linf.thm3", example="paper-full", solvers="clarabel,cvxopt", workers=2)
    assert [(r.backend, r.solver) for r in both.rows] == [(r.backend, r.solver) for r in serial.rows]
    assert [r.gamma for r in both.rows] == pytest.approx([r.gamma for r in serial.rows], abs=1e-6)
    assert both.agree == serial.agree


def test_leaving_the_runner_mid_stream_cancels_before_the_client_closes(monkeypatch):
    """An interrupt between two results leaves the result stream suspended; closing the runner
    must finish it (cancelling what is queued) while the client lives, not leave its clean-up to
    the garbage collector, which printed "IOLoop is closed" as a traceback (CI, stop 22)."""
    import gc
    import sys

    from lmidsl.pipeline import make_instance
    from lmidsl.studies.sweep import SweepTask

    ignored = []
    monkeypatch.setattr(sys, "unraisablehook", ignored.append)
    task = SweepTask(make_instance(*THM3[:1], "paper-full"), "direct", None, None, {})
    with pytest.raises(KeyboardInterrupt):
        with parallel.Runner(workers=2) as runner:
            stream = iter(runner.map(task, [{"rbar": r} for r in GRID[0][1]]))
            next(stream)
            raise KeyboardInterrupt
    assert stream.gi_frame is None                    # finished by close(), not left to the collector
    del stream
    gc.collect()
    assert ignored == []
