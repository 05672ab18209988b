"""Independent points in parallel: in this process, on a Dask ``LocalCluster``, or on a Dask cluster.

A :class:`Task` says how to set a worker up — e.g. bind the theorem and compile its model once,
every grid parameter a backend parameter — and is then applied to many *items* (grid points,
solver rows, theorem examples).  Each process sets a task up once and keeps it (a module-level
cache keyed by ``task.key``, a few tasks at most), so a model is compiled once per worker, not
once per point.  The task is shipped once to each worker (``Client.scatter``, cloudpickle: a
theorem built in Python, not in any file, travels too, with the symbols' metadata).

:class:`Runner` chooses where the items run:

* ``workers`` 1 (the default) and no ``scheduler``: in this process, in order;
* ``workers`` N > 1: this process solves the first items; a ``LocalCluster`` of N processes with
  one thread each is started (in the background) only once the items left would pay for its
  start (:data:`START_COST`), this process solving items until its workers have joined, and it
  is closed after the run;
* ``scheduler`` ADDRESS: an existing cluster (``dask scheduler`` and ``dask worker``, or
  ``lmidsl cluster start``: :mod:`lmidsl.studies.cluster`); every worker must import this
  lmidsl (:func:`warm_up` runs on each first; ``--preload lmidsl.studies.parallel`` does it when
  the worker starts), and a theorem given by id must be in the workers' registry.

Results come back as they finish (``distributed.as_completed``); at most two tasks per worker
thread are in flight, so a grid of 10⁵ points does not sit in the scheduler at once; items are
batched so that a task lasts about :data:`TARGET_TASK_SECONDS` (one item a task while items are
slow, many when they take milliseconds) but holds at most remaining / (2 · worker threads) items
(guided self-scheduling: batches shrink towards the end, so no worker is left with a long last
task while the others idle).
"""
from __future__ import annotations

import collections
import logging
import os
import socket
import threading
import time
import uuid

from ..errors import InputError
from ..symbolic.symbols import metadata_snapshot, restore_metadata
from .local_workers import (FORKSERVER_PRELOAD, local_start_method, start_local_workers_early,
                            workers_ignore_ctrl_c)
from ..theorem.registry import all_theorems

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
#: the wall time a local cluster is taken to cost before it helps (its scheduler, the fork
#: server's imports, forking and joining the workers: 1–3 s on 2 cores): a run whose items left
#: would gain less from the workers stays in this process (:meth:`Runner._worth_starting`)
START_COST = 2.0

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


def run_batch(task: Task, items: list) -> tuple[list, tuple]:
    """The results of ``items`` on this worker's state of ``task``, and ``(worker, start, end)``:
    who ran them and when (this worker's clock; the set-up, once per worker, before ``start``)."""
    apply = worker_state(task)
    start = time.time()
    results = [apply(item) for item in items]
    return results, (f"{socket.gethostname()}:{os.getpid()}", start, time.time())


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


def warm_up(theorems: bool = False) -> None:
    """Make this process ready to solve: lmidsl's solving modules imported
    (:data:`FORKSERVER_PRELOAD`), the BLAS and OpenMP pools at one thread (threadpoolctl: for a
    worker started without Dask's nanny, which otherwise sets
    ``OMP_NUM_THREADS=1`` and its kin before the worker imports numpy), and with ``theorems`` the
    theorem files read (``reproduce`` looks theorems up by id on the workers)."""
    import importlib

    for name in FORKSERVER_PRELOAD:
        importlib.import_module(name)
    from threadpoolctl import threadpool_limits
    threadpool_limits(1)
    if theorems:
        all_theorems()


def dask_setup(server=None) -> None:
    """Dask's preload hook: ``dask worker ADDRESS --preload lmidsl.studies.parallel`` gives a
    worker that has imported lmidsl and read the theorem files before its first task
    (:func:`warm_up`); ``lmidsl cluster start`` starts its workers so."""
    warm_up(theorems=True)


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

    A local cluster starts in the background (its scheduler and client in a thread, its workers
    forked by the fork server as soon as they can): meanwhile this process solves items itself
    (the *local lane*), and it goes on doing so while fewer than ``workers`` worker threads have
    joined, so that this process and the workers together never use more than ``workers`` cores.
    A 4-point sweep is then done before its workers are up and costs no more than a serial one.
    ``stats`` (after a run): what the run measured of itself (:func:`format_stats`)."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None, start_at_once: bool = False):
        check_workers(workers, scheduler)
        self.workers = 1 if workers is None else workers
        self.scheduler = scheduler or None
        self.start_at_once = start_at_once   # a local cluster launched with the first item, untimed
        self._cluster = self._client = None
        self._streams: list = []      # the open result generators, closed before the client
        self._starter = self._start_error = self._config = None
        self._entered = 0.0
        self._launched = False
        self._entered_unix = 0.0
        self.stats: dict = {}

    @property
    def parallel(self) -> bool:
        return self.scheduler is not None or self.workers > 1

    def describe(self) -> str:
        if self.scheduler:
            return f"Dask cluster at {self.scheduler} ({self._threads()} worker threads)"
        return f"{self.workers} Dask worker processes (LocalCluster)" if self.parallel else "serial"

    def __enter__(self) -> "Runner":
        self._entered = time.monotonic()
        self._entered_unix = time.time()
        if not self.parallel:
            return self
        if self.scheduler is None:
            return self               # started by map when the work needs it (_worth_starting)
        from distributed import Client
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
        try:
            self._client.run(warm_up)     # every worker ready before the first task
        except Exception as exc:      # a worker without lmidsl: one line, before any task
            self.close()
            reason = " ".join(str(exc).split())[:160] or type(exc).__name__
            raise InputError(f"--scheduler {self.scheduler}: a worker cannot import lmidsl ({reason}); "
                             f"every worker needs this lmidsl installed (docs/performance.md)") from None
        return self

    def _start_local(self) -> None:
        """Start a ``LocalCluster`` of ``workers`` processes.  With the fork server (the default)
        its scheduler and client start in a thread and its workers join as they come up (the
        fork server ignores SIGINT, which its workers inherit); with ``spawn`` or ``fork``
        here, all at once, with SIGINT ignored while they start."""
        import dask
        import distributed   # noqa: F401  its defaults in dask.config before the settings below
        # (a dask.config.set made first would drop them when it is undone: KeyError 'comm' later)
        self._launched = True
        start_local_workers_early(self.workers, None)
        method = local_start_method()
        self._config = dask.config.set({"distributed.worker.multiprocessing-method": method, **WORKER_CONFIG})
        self._config.__enter__()                   # nannies read it when they start: kept until close
        if method == "forkserver":
            self._starter = threading.Thread(target=self._start_cluster, args=(0,), daemon=True,
                                             name="lmidsl-cluster-start")
            self._starter.start()
            return
        with workers_ignore_ctrl_c():
            self._start_cluster(self.workers)
        if self._start_error is not None:
            raise self._start_error

    def _start_cluster(self, first: int) -> None:
        """The cluster with ``first`` workers started at once, and the client; then scaled to
        ``workers`` (in the background).  An error is kept for :meth:`_live` to raise."""
        from distributed import Client, LocalCluster
        try:
            cluster = LocalCluster(n_workers=first, threads_per_worker=1, processes=True,
                                   silence_logs=logging.CRITICAL, env=WORKER_ENV, **dashboard_options())
            try:
                client = Client(cluster, set_as_default=False)
                if first < self.workers:
                    cluster.scale(self.workers)
            except BaseException:
                cluster.close()
                raise
            self._cluster, self._client = cluster, client
        except BaseException as exc:        # reported by the thread that uses the cluster
            self._start_error = exc

    def _live(self, threads: int):
        """The client and the worker threads joined so far (``threads``: the last count), once
        the cluster is up; ``(None, 0)`` while it starts."""
        if self._start_error is not None:
            error, self._start_error = self._start_error, None
            raise error
        client = self._client
        if client is None:
            return None, 0
        return client, (threads if threads >= self.workers and not self.scheduler else self._threads())

    def _worth_starting(self, remaining: int, per_item: float | None) -> bool:
        """Start a local cluster once the items left, at the mean time of those solved here,
        would take longer than its start plus their time on ``workers`` processes:
        ``remaining · t · (1 − 1/workers) > START_COST · max(1, load / cores)`` (before any item
        is timed: not yet).  On a machine whose run queue is longer than its cores the workers'
        imports get only a share of a core, so their start costs that much longer (measured:
        25 s at load 18 on 2 cores, 2–3 s idle)."""
        if per_item is None:
            return False
        crowding = max(1.0, os.getloadavg()[0] / usable_cores()) if hasattr(os, "getloadavg") else 1.0
        return remaining * per_item * (1 - 1 / self.workers) > START_COST * crowding

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Close the result streams, then the client and a local cluster.  A parallel run's
        ``stats`` get the wall-clock times (Unix) it was entered and closed, and the close's
        seconds, so that a caller timing the whole process sees where its time went."""
        started = time.perf_counter()
        for stream in self._streams:  # runs their `finally` (cancel) while the client still lives
            stream.close()
        self._streams = []
        self._entered = 0.0
        if self._starter is not None:     # at most the scheduler's start (< 1 s): workers are scaled
            self._starter.join()          # in the background and closed with the cluster
            self._starter = None
        for thing in (self._client, self._cluster):
            if thing is not None:
                try:
                    thing.close()
                except Exception:        # closing after an interrupt: nothing left to save
                    pass
        self._client = self._cluster = None
        if self._config is not None:
            self._config.__exit__(None, None, None)
            self._config = None
        if self.stats and "close" not in self.stats:
            self.stats.update(entered_unix=self._entered_unix, close=time.perf_counter() - started,
                              closed_unix=time.time())

    def _threads(self) -> int:
        return max(0, sum(self._client.nthreads().values())) if self._client is not None else 0

    def map(self, task: Task, items: list) -> Results:
        """``(index, result)`` for each of ``items``: in order when serial, as they finish else."""
        items = list(items)
        if not self.parallel:
            return Results(((i, worker_state(task)(item)) for i, item in enumerate(items)), len(items))
        if not self._entered:
            raise RuntimeError("Runner.map outside its `with` block")
        stream = self._dask_map(task, items)
        self._streams.append(stream)
        return Results(stream, len(items))

    def _dask_map(self, task: Task, items: list):
        """The items on the cluster, and in this process while the cluster is short of workers
        (:class:`Runner`); batches by guided self-scheduling (the module doc).  Dask is imported
        only once a cluster is launched (a short run that stays here does not pay for it)."""
        queue = collections.deque(enumerate(items))
        client = shared = finished = None
        batch, threads, checked = 1, 0, 0.0
        indices: dict = {}
        meter = _Meter(self._entered)
        local_lane = self.scheduler is None
        if not local_lane:
            self._launched = True

        def submit() -> None:
            while queue and len(indices) < 2 * threads:
                size = max(1, min(batch, -(-len(queue) // (2 * threads))))   # ⌈remaining / 2P⌉
                chunk = [queue.popleft() for _ in range(min(size, len(queue)))]
                future = client.submit(run_batch, shared, [item for _, item in chunk], pure=False)
                indices[future] = [i for i, _ in chunk]
                finished.add(future)

        try:
            while queue or indices:
                if local_lane and not self._launched and \
                        (self.start_at_once or self._worth_starting(len(queue), meter.per_item())):
                    meter.launched = time.monotonic() - self._entered
                    self._start_local()
                now = time.monotonic()
                if self._launched and now - checked > (2.0 if threads >= self.workers else 0.05):
                    client, threads = self._live(threads)
                    checked = now
                    if threads:
                        meter.joined(threads, self.workers if local_lane else threads)
                if threads and finished is None:
                    from distributed import as_completed
                    shared = client.scatter(task, broadcast=True, hash=False)
                    finished = as_completed(loop=client.loop)
                if finished is not None:
                    submit()
                if queue and local_lane and threads < self.workers and \
                        not (finished is not None and finished.has_ready()):
                    index, item = queue.popleft()
                    yield index, meter.local(task, item)
                    continue
                if finished is None:
                    time.sleep(0.01)      # no worker yet, and the local lane is closed
                    continue
                future = next(finished)
                results, (worker, start, end) = future.result()
                done = indices.pop(future)
                meter.task(worker, start, end, len(done))
                per_item = (end - start) / max(1, len(done))
                batch = max(1, min(MAX_BATCH, int(TARGET_TASK_SECONDS / max(per_item, 1e-6))))
                yield from zip(done, results)
        finally:
            self.stats = meter.summary(self.workers if not self.scheduler else threads, self._launched)
            if client is not None:
                _cancel_quietly(client, list(indices) + ([shared] if shared is not None else []))


class _Meter:
    """What a parallel run measures of itself: items solved here (the local lane) and on the
    workers, tasks, the workers' intervals (their own clocks), this process's CPU time apart
    from the local lane, and when the first worker joined.

    * *tail idle*: Σ over workers of (last end of any worker − that worker's last end): the
      worker time lost at the end of the run;
    * *gap per task*: the mean time a worker waited between two consecutive tasks (its own
      clock): the scheduler's per-task cost as a worker sees it (at most two tasks per worker
      thread are in flight, so a worker whose next task is queued waits only for Dask);
    * *main CPU per task*: this process's CPU (client, and a local cluster's scheduler; storing
      and progress of the caller included) per task."""

    def __init__(self, entered: float):
        self.entered = entered
        self.started = time.monotonic()
        self.cpu0 = time.process_time()
        self.local_cpu = self.local_wall = 0.0
        self.items_local = self.items_remote = self.tasks = 0
        self.first_worker = self.all_workers = self.launched = None
        self.intervals: dict = collections.defaultdict(list)

    def joined(self, threads: int, wanted: int) -> None:
        """``threads`` worker threads of the ``wanted`` have joined (the times since the runner
        was entered: the first, and the last once all have)."""
        if self.first_worker is None:
            self.first_worker = time.monotonic() - self.entered
        if self.all_workers is None and threads >= wanted:
            self.all_workers = time.monotonic() - self.entered

    def local(self, task: Task, item):
        cpu, wall = time.process_time(), time.perf_counter()
        result = worker_state(task)(item)
        self.local_cpu += time.process_time() - cpu
        self.local_wall += time.perf_counter() - wall
        self.items_local += 1
        return result

    def per_item(self) -> float | None:
        """The mean wall time of an item solved here (None before the first)."""
        return self.local_wall / self.items_local if self.items_local else None

    def task(self, worker: str, start: float, end: float, items: int) -> None:
        self.tasks += 1
        self.items_remote += items
        self.intervals[worker].append((start, end))

    def summary(self, slots: int, started: bool) -> dict:
        wall = time.monotonic() - self.started
        main_cpu = time.process_time() - self.cpu0 - self.local_cpu
        ends = {w: max(e for _, e in spans) for w, spans in self.intervals.items()}
        last = max(ends.values(), default=0.0)
        gaps = [b[0] - a[1] for spans in self.intervals.values()
                for a, b in zip(sorted(spans), sorted(spans)[1:])]
        busy = sum(e - s for spans in self.intervals.values() for s, e in spans)
        return {"workers": slots, "cluster_started": started, "items_here": self.items_local, "items_on_workers": self.items_remote,
                "tasks": self.tasks, "wall": wall,
                "cluster_launched": self.launched, "first_worker_joined": self.first_worker,
                "all_workers_joined": self.all_workers,
                "worker_busy": busy,
                "tail_idle": sum(last - e for e in ends.values()),
                "gap_per_task": sum(max(0.0, g) for g in gaps) / len(gaps) if gaps else None,
                "main_cpu": main_cpu, "main_cpu_per_task": main_cpu / self.tasks if self.tasks else None}


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
