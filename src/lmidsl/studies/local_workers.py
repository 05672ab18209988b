"""How local Dask workers start: a fork server that has imported lmidsl's solving stack forks
each worker process (:func:`start_local_workers_early`), with one BLAS thread, SIGINT ignored and
its output in a log file.

Kept apart from :mod:`lmidsl.studies.parallel` and light to import (the standard library only):
the command line starts the fork server before it imports sympy and the solving stack, so that
the fork server's imports run beside its own (``lmidsl sweep --workers N``).
"""
from __future__ import annotations

import contextlib
import multiprocessing
from multiprocessing import forkserver
import os
import signal
import sys
import threading

from ..errors import InputError
from ..theorem.index import cache_dir

#: what the fork server imports once, before it forks the local workers (each then starts with
#: them imported: a sweep's worker needs no import to unpickle its task and compile)
FORKSERVER_PRELOAD = ["distributed.nanny", "distributed.worker", "lmidsl.studies.sweep",
                      "lmidsl.solver.backends.direct_backend", "lmidsl.numeric.proof"]
#: the environment the fork server starts with, so its workers inherit it: one thread per
#: worker in the BLAS and OpenMP pools (what Dask sets before spawning a worker,
#: ``distributed.nanny.pre-spawn-environ``, which reaches a forked worker only this way).  Not
#: Dask's ``MALLOC_TRIM_THRESHOLD_=65536``: it returns freed memory to the system at once, and
#: Clarabel, which allocates and frees its KKT system at every solve, was 2.5 % slower with it
#: (seed 001's model, 95 points on 2 workers, twice: 208.3 / 204.4 ms against 202.4 / 199.1 ms)
FORKSERVER_ENV = {"OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def local_start_method() -> str:
    """How a LocalCluster starts its worker processes: ``forkserver`` unless
    ``LMIDSL_DASK_START`` says ``spawn`` or ``fork``.

    * ``forkserver``: a fresh single-threaded interpreter imports lmidsl once
      (:data:`FORKSERVER_PRELOAD`, started early by :func:`start_local_workers_early`) and forks
      each worker from itself: workers start with everything imported, and no process with
      live threads is forked;
    * ``spawn``: each worker is a fresh interpreter that imports lmidsl itself (1–2 s a worker);
    * ``fork``: workers are forks of this process — fastest, with the compiled model inherited,
      but forking a process with live threads can hang the child: one forked worker did, after
      its parent had solved (docs/performance.md)."""
    method = os.environ.get("LMIDSL_DASK_START") or "forkserver"
    if method not in multiprocessing.get_all_start_methods():
        raise InputError(f"LMIDSL_DASK_START={method!r}: not a start method here "
                         f"({', '.join(multiprocessing.get_all_start_methods())})")
    return method


#: a run of at least this many items per worker starts its local workers at once: the fork
#: server as early as the caller can (:func:`start_for`), and the cluster with the first item
#: (``Runner(start_at_once=True)``); a smaller run starts them only once its first items, timed
#: in the calling process, show that the workers would pay for their start
EARLY_START_ITEMS = 4


def start_for(workers: int | None, scheduler: str | None, items: int) -> bool:
    """Whether a run of ``items`` on ``workers`` local workers starts them at once; if so, the
    fork server is started now (:func:`start_local_workers_early`; a no-op when it runs)."""
    at_once = bool(workers) and workers > 1 and not scheduler and items >= EARLY_START_ITEMS * workers
    if at_once:
        start_local_workers_early(workers, scheduler)
    return at_once


_STARTED = False
"""Whether this process has started its fork server (:func:`start_local_workers_early`)."""


def start_local_workers_early(workers: int | None, scheduler: str | None) -> None:
    """Start the fork server of a local parallel run now (a no-op otherwise): its imports then
    run while this process binds and compiles the theorem, and the cluster's workers fork from
    it as soon as the cluster starts.  It starts with SIGINT ignored, which its workers inherit
    (:func:`workers_ignore_ctrl_c`), and with :data:`FORKSERVER_ENV`."""
    global _STARTED
    if scheduler or workers is None or workers < 2 or local_start_method() != "forkserver" or _STARTED:
        return                 # (started already: a second call would only truncate the log again)
    _STARTED = True
    forkserver.set_forkserver_preload(FORKSERVER_PRELOAD)
    saved = {k: os.environ.get(k) for k in FORKSERVER_ENV}
    os.environ.update(FORKSERVER_ENV)
    try:
        with workers_ignore_ctrl_c(), workers_write_to_log():
            forkserver.ensure_running()
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


def worker_log() -> str:
    """Where local worker processes write what they print: ``local-workers.log`` in lmidsl's
    cache folder (os.devnull when it cannot be created)."""
    try:
        cache_dir().mkdir(parents=True, exist_ok=True)
        return str(cache_dir() / "local-workers.log")
    except OSError:
        return os.devnull


@contextlib.contextmanager
def workers_write_to_log():
    """Processes started here write their stdout and stderr to :func:`worker_log` (inherited by
    the fork server and every worker it forks), not to this command's.  A reader of this
    command's output through a pipe (``lmidsl sweep ... --json | jq``, a test harness) otherwise
    waits, after this process has ended, until the last worker has shut down and closed its copy
    of the pipe.  This process's own descriptors are restored as soon as the child is started."""
    try:
        log = os.open(worker_log(), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    except OSError:
        log = os.open(os.devnull, os.O_WRONLY)
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    saved = [os.dup(fd) for fd in (1, 2)]
    try:
        for fd in (1, 2):
            os.dup2(log, fd)
        yield
    finally:
        for fd, copy in zip((1, 2), saved):
            os.dup2(copy, fd)
            os.close(copy)
        os.close(log)


@contextlib.contextmanager
def workers_ignore_ctrl_c():
    """Worker processes started here ignore SIGINT (inherited): Ctrl-C at a terminal reaches the
    whole process group, and this process alone ends the run (keeping what is stored) and closes
    the cluster; workers would only print tracebacks.  Not from a thread other than the main one."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    # SIGINT blocked first: a Ctrl-C while the workers start stays pending (Linux queues a blocked
    # signal even while it is ignored) and reaches this process once the mask is restored, instead
    # of being discarded — the cluster starts lazily, mid-run, and a Ctrl-C that fell in this window
    # was lost (the run went on to its end: the slow suite's Ctrl-C tests, at load)
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    previous = signal.getsignal(signal.SIGINT)
    try:      # set inside the try: an interrupt (a deadline's) right after it still restores it
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
