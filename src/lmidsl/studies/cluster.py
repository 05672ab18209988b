"""A long-lived Dask cluster on this machine: ``lmidsl cluster start``, ``status``, ``stop``.

``start`` launches ``dask scheduler`` and ``dask worker`` (N processes of one thread each, each
preloading lmidsl and the theorem files: :func:`lmidsl.studies.parallel.dask_setup`; Dask's
nanny sets ``OMP_NUM_THREADS=1`` and its kin before a worker imports numpy) in a session of their
own, so that they outlive the command, and waits until every worker has joined.  Their address
and process ids are kept in a state file (``cluster.json`` in lmidsl's cache folder, or
``--state FILE``).  Later commands use the cluster with ``--scheduler ADDRESS`` and pay no
start-up: the workers are warm, and each compiles a run's model once.  ``stop`` asks the
scheduler to close the cluster, then ends any process it started that is still there.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from ..errors import InputError
from ..theorem.index import cache_dir
from .parallel import _probe_scheduler
from .store import atomic_write_text

#: seconds ``start`` waits for the scheduler's address and then for every worker
START_TIMEOUT = 120
#: seconds ``stop`` waits for the processes to end after asking the scheduler, before SIGTERM
STOP_TIMEOUT = 10


def state_path(state=None) -> Path:
    """The state file: ``state`` if given, else ``cluster.json`` in lmidsl's cache folder."""
    return Path(state) if state else cache_dir() / "cluster.json"


def dask_command(role: str) -> list[str]:
    """``dask scheduler`` / ``dask worker`` of this Python environment."""
    return [sys.executable, "-m", f"distributed.cli.dask_{role}"]


def read_state(state=None) -> dict | None:
    """The recorded cluster (None when none is recorded)."""
    path = state_path(state)
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a cluster state file ({exc})") from None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def start(workers: int, host: str = "127.0.0.1", port: int = 0, state=None) -> dict:
    """Start a scheduler on ``host:port`` (0: a free port) and ``workers`` worker processes;
    return the recorded state (``address``, process ids, log file)."""
    if workers < 1:
        raise InputError(f"--workers must be >= 1, got {workers}")
    path = state_path(state)
    old = read_state(state)
    if old and _alive(old.get("scheduler_pid", -1)):
        raise InputError(f"a cluster is already running at {old['address']} (state {path}); "
                         f"`lmidsl cluster stop` first")
    path.parent.mkdir(parents=True, exist_ok=True)
    address_file = path.with_suffix(".scheduler.json")
    address_file.unlink(missing_ok=True)
    log = path.with_suffix(".log")
    with open(log, "ab") as out:
        common = dict(stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, start_new_session=True)
        scheduler = subprocess.Popen([*dask_command("scheduler"), "--host", host, "--port", str(port),
                                      "--no-dashboard", "--scheduler-file", str(address_file)], **common)
        procs = [scheduler]
        try:
            address = _wait_for_address(address_file, scheduler, log)
            procs.append(subprocess.Popen([*dask_command("worker"), address, "--nworkers", str(workers),
                                           "--nthreads", "1", "--no-dashboard", "--host", host,
                                           "--preload", "lmidsl.studies.parallel"], **common))
            _wait_for_workers(address, workers, procs[1], log)
        except BaseException:
            for proc in procs:
                _end(proc.pid, grace=0)
            raise
    record = {"address": address, "workers": workers, "scheduler_pid": scheduler.pid,
              "worker_pid": procs[1].pid, "log": str(log)}
    atomic_write_text(path, json.dumps(record, indent=1) + "\n")
    return record


def _wait_for_address(address_file: Path, proc, log: Path) -> str:
    deadline = time.monotonic() + START_TIMEOUT
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise InputError(f"dask scheduler exited ({proc.returncode}); see {log}")
        try:
            return json.loads(address_file.read_text())["address"]
        except (OSError, ValueError, KeyError):
            time.sleep(0.1)
    raise InputError(f"dask scheduler gave no address within {START_TIMEOUT} s; see {log}")


def _wait_for_workers(address: str, workers: int, proc, log: Path) -> None:
    from distributed import Client

    with Client(address, timeout=START_TIMEOUT, set_as_default=False) as client:
        deadline = time.monotonic() + START_TIMEOUT
        while len(client.nthreads()) < workers:
            if proc.poll() is not None:
                raise InputError(f"dask worker exited ({proc.returncode}); see {log}")
            if time.monotonic() > deadline:
                raise InputError(f"{len(client.nthreads())} of {workers} workers joined within "
                                 f"{START_TIMEOUT} s; see {log}")
            time.sleep(0.2)


def status(state=None) -> dict | None:
    """The recorded cluster with what its scheduler says now: ``workers_joined``, ``threads``
    (``reachable`` False when it does not answer)."""
    record = read_state(state)
    if record is None:
        return None
    try:
        _probe_scheduler(record["address"], seconds=3)
    except InputError:
        return {**record, "reachable": False, "workers_joined": 0, "threads": 0}
    from distributed import Client
    with Client(record["address"], timeout=5, set_as_default=False) as client:
        threads = client.nthreads()
    return {**record, "reachable": True, "workers_joined": len(threads), "threads": sum(threads.values())}


def stop(state=None) -> dict | None:
    """Close the recorded cluster (the scheduler's shutdown closes its workers); end what is
    left of the processes it started; forget it.  The record, or None when none was kept."""
    record = read_state(state)
    if record is None:
        return None
    try:
        _probe_scheduler(record["address"], seconds=3)
        from distributed import Client
        with Client(record["address"], timeout=5, set_as_default=False) as client:
            client.shutdown()
    except Exception:                   # already gone, or not answering: end the processes below
        pass
    for key in ("worker_pid", "scheduler_pid"):
        _end(record.get(key))
    state_path(state).unlink(missing_ok=True)
    return record


def _end(pid, grace: float = 3.0) -> None:
    """End the process group ``pid`` leads (a process this module started in a session of its
    own, with the processes it started): wait ``grace`` seconds for the group to end by itself,
    then SIGTERM, then SIGKILL."""
    if not isinstance(pid, int) or pid <= 0:
        return
    for sig, wait in ((None, grace), (signal.SIGTERM, STOP_TIMEOUT), (signal.SIGKILL, STOP_TIMEOUT)):
        if sig is not None:
            try:
                os.killpg(pid, sig)
            except (ProcessLookupError, PermissionError):
                return
        deadline = time.monotonic() + wait
        while _group_alive(pid) and time.monotonic() < deadline:
            time.sleep(0.1)
        if not _group_alive(pid):
            return


def _group_alive(pid: int) -> bool:
    """Whether a process of group ``pid`` is left (the leader reaped if it is our child)."""
    try:
        os.waitpid(pid, os.WNOHANG)
    except ChildProcessError:
        pass
    try:
        os.killpg(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
