"""Independent points in parallel: in this process, on a Dask ``LocalCluster``, or on a Dask cluster.

A :class:`Task` says how to set a worker up — e.g. bind the theorem and compile its model once,
every grid parameter a backend parameter — and is then applied to many *items* (grid points,
solver rows, theorem examples).  Each process sets a task up once and keeps it (a module-level
cache keyed by ``task.key``, a few tasks at most), so a model is compiled once per worker, not
once per point.  The task is shipped once to each worker (``Client.scatter``, cloudpickle: a
theorem built in Python, not in any file, travels too, with the symbols' metadata).

:class:`Runner` chooses where the items run:

* ``workers`` 1 (the default) and no ``scheduler``: in this process, in order;
* ``workers`` N > 1: a ``LocalCluster`` of N processes with one thread each, started for the run
  and closed after it;
* ``scheduler`` ADDRESS: an existing cluster (``dask scheduler`` and ``dask worker``); every
  worker must import this lmidsl, and a theorem given by id must be in the workers' registry.

Results come back as they finish (``distributed.as_completed``); at most two tasks per worker
thread are in flight, so a grid of 10⁵ points does not sit in the scheduler at once; items are
batched so that a task lasts about :data:`TARGET_TASK_SECONDS` (one item a task while items are
slow, many when they take milliseconds) but holds at most remaining / (2 · worker threads) items
(guided self-scheduling: batches shrink towards the end, so no worker is left with a long last
task while the others idle).
"""
from __future__ import annotations

import collections
import contextlib
import logging
import multiprocessing
from multiprocessing import forkserver
import os
import signal
import sys
import threading
import time
import uuid

from ..errors import InputError
from ..symbolic.symbols import metadata_snapshot, restore_metadata

#: tasks set up and kept per process (each may hold a compiled model)
CACHE_SIZE = 4
#: items are batched so a task lasts about this long (Dask's per-task cost, scheduler and client,
#: is ~6 ms of the main process's CPU, which on a machine with as many workers as cores is taken
#: from a worker)
TARGET_TASK_SECONDS = 1.0
MAX_BATCH = 256
#: connecting to ``--scheduler`` and waiting for its first worker
CONNECT_TIMEOUT = 10
#: the wall time a scheduler has to answer who it is (:func:`_probe_scheduler`)
PROBE_TIMEOUT = 5
WORKER_TIMEOUT = 60

_CACHE: collections.OrderedDict = collections.OrderedDict()


class Task:
    """Subclass and define :meth:`setup`; ``key`` is unique per task object (per run).  The
    symbols' metadata (LaTeX names, definitions, structured expansions: a table of this process)
    travels with the task, so an instance pickled to a worker compiles there as here."""

    def __init__(self):
        self.key = uuid.uuid4().hex
        self.symbols = metadata_snapshot()

    def setup(self):
        """What a worker builds once: a callable ``item → result``."""
        raise NotImplementedError


def worker_state(task: Task):
    """``task.setup()`` of this process, built on first use and kept."""
    state = _CACHE.get(task.key)
    if state is None:
        restore_metadata(task.symbols)
        state = task.setup()
        _CACHE[task.key] = state
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(task.key)
    return state


def run_batch(task: Task, items: list) -> tuple[list, float]:
    """The results of ``items`` on this worker's state of ``task``, and the seconds they took."""
    apply = worker_state(task)
    t0 = time.perf_counter()
    results = [apply(item) for item in items]
    return results, time.perf_counter() - t0


class Results:
    """``(index, result)`` pairs as they finish; ``len`` is the number of items (progress bars)."""

    def __init__(self, generator, size: int):
        self._generator, self._size = generator, size

    def __len__(self) -> int:
        return self._size

    def __iter__(self):
        return self._generator


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def max_local_workers() -> int:
    """The most local worker processes a run may start: one per usable core (each worker solves
    with one thread), and never fewer than 2 (a pool of two on one core is harmless)."""
    return max(2, usable_cores())


def check_workers(workers, scheduler) -> None:
    """``--workers`` an integer from 1 to :func:`max_local_workers` (each local worker is a
    process of ~150 MB: 1000 of them on 2 cores would only exhaust the machine)."""
    if workers is not None and (not isinstance(workers, int) or isinstance(workers, bool) or workers < 1):
        raise InputError(f"--workers must be an integer >= 1, got {workers!r}")
    if workers is not None and not scheduler and workers > max_local_workers():
        raise InputError(f"--workers {workers}: this machine runs at most {max_local_workers()} worker "
                         f"processes ({usable_cores()} usable cores); give --workers {max_local_workers()} "
                         f"or fewer, or --scheduler ADDRESS for a larger cluster")
    if workers is not None and scheduler:
        raise InputError("give --workers N (a local Dask cluster) or --scheduler ADDRESS (an existing "
                         "one), not both")


#: the environment of local workers: Clarabel's threads by problem size, as in a serial run
#: (lmidsl.solver.backends.direct_backend.solver_threads: one thread below 3,000 PSD rows, two
#: above), so that a parallel sweep gives the serial sweep's numbers bit for bit
WORKER_ENV: dict = {}
WORKER_CONFIG = {"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "1s",
                 "distributed.worker.memory.monitor-interval": "1s",
                 "distributed.admin.system-monitor.interval": "2s",
                 "distributed.scheduler.work-stealing": False,
                 "distributed.scheduler.active-memory-manager.start": False,
                 "distributed.deploy.cluster-repr-interval": "10s"}
"""Dask settings of a local cluster, which shares the machine's cores with its own workers:

* no statistical profiler (it samples the worker thread's stack every 10 ms and takes the GIL
  from cvxpy's Python canonicalisation) and a 1 s event-loop tick.  Measured on seed 001's
  model, 2 workers on 2 idle cores: 0.246–0.261 s per solve with Dask's defaults, 0.237–0.251 s
  without (a plain process pool: 0.236–0.241 s);
* the nannies' memory monitor every 1 s (not 0.1 s), the system monitor every 2 s, no work
  stealing (at most two tasks per worker thread are queued: nothing to steal) and no active
  memory manager (nothing is replicated but the task itself).  An idle cluster of 2 workers
  then costs 14 ms of CPU a second instead of 36 ms."""


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


def start_local_workers_early(workers: int | None, scheduler: str | None) -> None:
    """Start the fork server of a local parallel run now (a no-op otherwise): its imports then
    run while this process binds and compiles the theorem, and the cluster's workers fork from
    it as soon as the cluster starts.  It starts with SIGINT ignored, which its workers inherit
    (:func:`_workers_ignore_ctrl_c`), and with :data:`FORKSERVER_ENV`."""
    if scheduler or workers is None or workers < 2 or local_start_method() != "forkserver":
        return
    forkserver.set_forkserver_preload(FORKSERVER_PRELOAD)
    saved = {k: os.environ.get(k) for k in FORKSERVER_ENV}
    os.environ.update(FORKSERVER_ENV)
    try:
        with _workers_ignore_ctrl_c():
            forkserver.ensure_running()
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


@contextlib.contextmanager
def _workers_ignore_ctrl_c():
    """Worker processes started here ignore SIGINT (inherited): Ctrl-C at a terminal reaches the
    whole process group, and this process alone ends the run (keeping what is stored) and closes
    the cluster; workers would only print tracebacks.  Not from a thread other than the main one."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def dashboard_options() -> dict:
    """A local cluster's dashboard: none unless ``LMIDSL_DASK_DASHBOARD`` (``--dashboard``) names
    an address.  Without it the scheduler's HTTP server (health and metrics routes, which Dask
    starts even with no dashboard, on port 8787 by default) listens on a free port of the
    loopback interface: no "Port 8787 is already in use" warning when another cluster runs."""
    address = os.environ.get("LMIDSL_DASK_DASHBOARD")
    if address:
        return {"dashboard_address": address}
    return {"dashboard_address": None, "scheduler_kwargs": {"dashboard": False, "dashboard_address": "127.0.0.1:0"}}


def _check_address(address: str) -> None:
    """A scheduler address Dask can parse (a malformed one is bad input, before any connection)."""
    from distributed.comm import parse_address
    from distributed.comm.registry import backends

    try:
        scheme, location = parse_address(address, strict=False)
    except Exception:
        scheme = location = ""
    host, _, port = location.rpartition(":")
    schemes = sorted(set(backends) - {"inproc"})           # inproc: this process only
    if scheme not in schemes or not (host and port.isdigit()):
        raise InputError(f"--scheduler {address!r}: expected an address such as tcp://HOST:8786 "
                         f"(schemes: {', '.join(schemes)})")


def _probe_scheduler(address: str, seconds: float | None = None) -> None:
    """Ask ``address`` who it is (Dask's ``identity`` message) within ``seconds`` of wall time
    (default :data:`PROBE_TIMEOUT`), before a Client is made: a Client's own timeout does not
    cover the handshake, so a port that accepts and never answers held it forever, and an HTTP
    server's reply read as a Dask frame header asked for 3 EiB.  One line when it is not a Dask
    scheduler."""
    from distributed.comm import connect
    from distributed.compatibility import asyncio_run
    from distributed.utils import wait_for

    seconds = PROBE_TIMEOUT if seconds is None else seconds

    async def identity():
        comm = await connect(address, timeout=seconds / 2)     # its retries end first: "cannot connect"
        try:
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            comm.abort()

    try:
        reply = asyncio_run(wait_for(identity(), seconds))
    except TimeoutError:
        raise InputError(f"--scheduler {address}: no Dask scheduler answered within {seconds:g} s") from None
    except OSError as exc:            # refused, unreachable
        reason = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise InputError(f"--scheduler {address}: cannot connect ({reason})") from None
    except Exception as exc:          # MemoryError, ValueError...: not Dask's protocol
        reason = " ".join(str(exc).split())[:120] or type(exc).__name__
        raise InputError(f"--scheduler {address}: not a Dask scheduler ({type(exc).__name__}: {reason})") from None
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        raise InputError(f"--scheduler {address}: not a Dask scheduler (it answered {str(reply)[:80]!r})")


class Runner:
    """Where independent items run (see the module doc); a context manager that starts and
    closes the cluster::

        with Runner(workers=2) as runner:
            for index, result in runner.map(task, items):
                ...
    """

    def __init__(self, workers: int | None = None, scheduler: str | None = None):
        check_workers(workers, scheduler)
        self.workers = 1 if workers is None else workers
        self.scheduler = scheduler or None
        self._cluster = self._client = None
        self._streams: list = []      # the open result generators, closed before the client

    @property
    def parallel(self) -> bool:
        return self.scheduler is not None or self.workers > 1

    def describe(self) -> str:
        if self.scheduler:
            return f"Dask cluster at {self.scheduler} ({self._threads()} worker threads)"
        return f"{self.workers} Dask worker processes (LocalCluster)" if self.parallel else "serial"

    def __enter__(self) -> "Runner":
        if not self.parallel:
            return self
        from distributed import Client, LocalCluster
        if self.scheduler is None:
            import dask
            with dask.config.set({"distributed.worker.multiprocessing-method": local_start_method(),
                                  **WORKER_CONFIG}), \
                    _workers_ignore_ctrl_c():
                self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                             silence_logs=logging.CRITICAL, env=WORKER_ENV,
                                             **dashboard_options())
            self._client = Client(self._cluster, set_as_default=False)
            return self
        _check_address(self.scheduler)
        _probe_scheduler(self.scheduler)
        try:
            self._client = Client(self.scheduler, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except Exception as exc:   # OSError, TimeoutError, ValueError for a malformed address
            reason = " ".join(str(exc).split()) or type(exc).__name__
            raise InputError(f"--scheduler {self.scheduler}: cannot connect ({reason[:200]})") from None
        try:
            self._client.wait_for_workers(1, timeout=WORKER_TIMEOUT)
        except Exception:
            self.close()
            raise InputError(f"--scheduler {self.scheduler}: no worker joined within {WORKER_TIMEOUT} s "
                             f"(start some with `dask worker {self.scheduler}`)") from None
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        for stream in self._streams:  # runs their `finally` (cancel) while the client still lives
            stream.close()
        self._streams = []
        for thing in (self._client, self._cluster):
            if thing is not None:
                try:
                    thing.close()
                except Exception:        # closing after an interrupt: nothing left to save
                    pass
        self._client = self._cluster = None

    def _threads(self) -> int:
        return max(1, sum(self._client.nthreads().values())) if self._client is not None else 1

    def map(self, task: Task, items: list) -> Results:
        """``(index, result)`` for each of ``items``: in order when serial, as they finish else."""
        items = list(items)
        if not self.parallel:
            return Results(((i, worker_state(task)(item)) for i, item in enumerate(items)), len(items))
        if self._client is None:
            raise RuntimeError("Runner.map outside its `with` block")
        stream = self._dask_map(task, items)
        self._streams.append(stream)
        return Results(stream, len(items))

    def _dask_map(self, task: Task, items: list):
        from distributed import as_completed

        client = self._client
        shared = client.scatter(task, broadcast=True, hash=False)
        queue = collections.deque(enumerate(items))
        batch, threads, checked = 1, self._threads(), time.monotonic()
        indices: dict = {}
        finished = as_completed(loop=client.loop)

        def submit() -> None:
            while queue and len(indices) < 2 * threads:
                size = max(1, min(batch, -(-len(queue) // (2 * threads))))   # ⌈remaining / 2P⌉
                chunk = [queue.popleft() for _ in range(min(size, len(queue)))]
                future = client.submit(run_batch, shared, [item for _, item in chunk], pure=False)
                indices[future] = [i for i, _ in chunk]
                finished.add(future)

        try:
            submit()
            for future in finished:
                results, seconds = future.result()
                done = indices.pop(future)
                per_item = seconds / max(1, len(done))
                batch = max(1, min(MAX_BATCH, int(TARGET_TASK_SECONDS / max(per_item, 1e-6))))
                if time.monotonic() - checked > 2:        # an adaptive cluster may have grown
                    threads, checked = self._threads(), time.monotonic()
                yield from zip(done, results)
                submit()
        finally:
            _cancel_quietly(client, list(indices) + [shared])


def _cancel_quietly(client, futures: list) -> None:
    """Cancel ``futures`` unless the client is already gone.  The generator that owns them may be
    closed by the garbage collector after ``Runner.close`` (an interrupt): cancelling then would
    print "IOLoop is closed" as an ignored exception, and there is nothing left to cancel."""
    if client.status not in ("running", "connecting"):
        return
    try:
        client.cancel(futures)
    except Exception:            # closed between the check and the call: the same situation
        pass


def items_as_finished(results: Results, items: list, put) -> Results:
    """The ``items`` themselves, in the order their ``results`` come back (a lazy iterable with a
    ``len``, for a progress wrapper that labels items); ``put(index, result)`` is called for
    each just before its item is yielded."""
    def generate():
        for index, result in results:
            put(index, result)
            yield items[index]
    return Results(generate(), len(results))
