"""A real Dask cluster, started as a user starts one: ``dask scheduler`` and two ``dask worker``
processes, each its own OS command, on the loopback interface at a free port.  ``sweep``
(resumed too), ``check`` and ``reproduce --theorem`` with ``--scheduler ADDRESS`` give the serial
run's numbers exactly, point by point and row by row.  Then ``lmidsl cluster start/status/stop``
(the long-lived cluster of the CLI) on its own.  Every process started here is ended (bounded
waits, SIGKILL last) whatever the outcome."""
from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from lmidsl.cli import main

SWEEP = ["sweep", "li_delay_dropout.thm2", "--example", "paper",
         "--grid", "xi1=0.3,0.6", "--grid", "xi2=0.3,0.6"]
CHECK = ["check", "wang_l2linf.thm3", "--example", "paper-full", "--solvers", "clarabel,cvxopt"]
REPRODUCE = ["reproduce", "--theorem", "textbook.brl_ct"]
START_TIMEOUT = 90


def _dask(role: str) -> list[str]:
    """The ``dask`` command of this environment (``python -m`` of its module if not on disk)."""
    exe = Path(sys.executable).with_name("dask")
    return [str(exe), role] if exe.exists() else [sys.executable, "-m", f"distributed.cli.dask_{role}"]


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _end(proc) -> None:
    """SIGTERM to the process's group, SIGKILL after 10 s."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        if proc.poll() is not None:
            return
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """``dask scheduler`` and two ``dask worker`` commands; yields the scheduler's address."""
    from distributed import Client

    log = tmp_path_factory.mktemp("cluster") / "dask.log"
    address = f"tcp://127.0.0.1:{_free_port()}"
    procs = []
    with open(log, "wb") as out:
        def launch(*argv):
            procs.append(subprocess.Popen(list(argv), stdout=out, stderr=subprocess.STDOUT,
                                          stdin=subprocess.DEVNULL, start_new_session=True))
        try:
            launch(*_dask("scheduler"), "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
                   "--no-dashboard")
            for _ in range(2):
                launch(*_dask("worker"), address, "--nthreads", "1", "--no-dashboard", "--host", "127.0.0.1",
                       "--preload", "lmidsl.studies.parallel", "--death-timeout", str(START_TIMEOUT))
            with Client(address, timeout=START_TIMEOUT, set_as_default=False) as client:
                client.wait_for_workers(2, timeout=START_TIMEOUT)
                assert len(client.nthreads()) == 2
            yield address
        except Exception:
            out.flush()
            print(log.read_text()[-3000:])
            raise
        finally:
            for proc in reversed(procs):
                _end(proc)
    assert all(proc.poll() is not None for proc in procs)


def _json(capsys, *argv):
    code = main([*argv, "--json", "--no-progress"])
    out = capsys.readouterr().out
    return code, json.loads(out)


def _points(result):
    return [(p["params"], p["status"], p["gamma"], p["objective"], p["worst_eig"], p["proved"],
             p["verdict"]) for p in result["points"]]


def _untimed(row):
    """A row without what depends on the machine's speed (its times)."""
    return {k: v for k, v in row.items() if "time" not in k}


def test_sweep_on_a_real_cluster_gives_every_serial_number_exactly(scheduler, capsys):
    code, serial = _json(capsys, *SWEEP, "--workers", "1")
    code_c, clustered = _json(capsys, *SWEEP, "--scheduler", scheduler)
    assert code_c == code == 0
    assert all(p["gamma"] is not None for p in serial["points"])
    assert _points(clustered) == _points(serial)                    # bit for bit, in grid order
    assert clustered["parallel"]["items_on_workers"] == 4 and clustered["parallel"]["items_here"] == 0


def test_a_sweep_resumed_on_a_real_cluster_gives_the_serial_numbers(scheduler, capsys, tmp_path):
    code, serial = _json(capsys, *SWEEP, "--workers", "1", "--out", str(tmp_path / "a"))
    store = tmp_path / "a" / "sweep.jsonl"
    lines = store.read_text().splitlines(keepends=True)
    store.write_text("".join(lines[:2]))             # the header and one point: an interrupted run
    code_c, resumed = _json(capsys, *SWEEP, "--scheduler", scheduler, "--out", str(tmp_path / "a"), "--resume")
    assert code_c == code
    assert resumed["resumed"] == 1 and resumed["solved"] == 3
    assert _points(resumed) == _points(serial)


def test_check_on_a_real_cluster_gives_the_serial_rows(scheduler, capsys):
    code, serial = _json(capsys, *CHECK)
    code_c, clustered = _json(capsys, *CHECK, "--scheduler", scheduler)
    assert code_c == code
    assert len(serial["rows"]) >= 2 and all(r["gamma"] is not None for r in serial["rows"])
    assert [_untimed(r) for r in clustered["rows"]] == [_untimed(r) for r in serial["rows"]]


def test_reproduce_on_a_real_cluster_gives_the_serial_rows(scheduler, capsys):
    code, serial = _json(capsys, *REPRODUCE, "--workers", "1")
    code_c, clustered = _json(capsys, *REPRODUCE, "--scheduler", scheduler)
    assert code_c == code == 0
    assert [r["computed_gamma"] for r in serial["rows"]] and all(r["certified"] for r in serial["rows"])
    assert [_untimed(r) for r in clustered["rows"]] == [_untimed(r) for r in serial["rows"]]


@pytest.mark.slow
def test_cluster_command_starts_serves_and_stops_a_cluster(tmp_path, capsys):
    """``lmidsl cluster start`` (two workers, separate processes), a sweep on it, ``status``,
    ``stop``: its processes are gone and the state forgotten."""
    state = str(tmp_path / "cluster.json")
    assert main(["cluster", "start", "--workers", "1", "--state", state, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    try:
        assert record["address"].startswith("tcp://127.0.0.1:")
        assert main(["cluster", "status", "--state", state, "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["workers_joined"] == 1
        code, serial = _json(capsys, *SWEEP[:6], "--workers", "1")
        code_c, clustered = _json(capsys, *SWEEP[:6], "--scheduler", record["address"])
        assert code_c == code and _points(clustered) == _points(serial)
    finally:
        assert main(["cluster", "stop", "--state", state]) == 0
    for pid in (record["scheduler_pid"], record["worker_pid"]):
        with pytest.raises(ProcessLookupError):
            os.killpg(pid, 0)
    assert not Path(state).exists()
    assert main(["cluster", "status", "--state", state]) == 2
