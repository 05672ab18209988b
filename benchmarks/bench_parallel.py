"""Scale-out of ``lmidsl sweep``: the fixed cost and the efficiency of Dask against a plain
process pool.

The sweep is seed 001's (docs/reproductions/001.md): ``li_delay_dropout.thm2 --example paper``
over ξ1 × ξ2 = (0.05:0.95:G)², G = 19 by default.  Each run is a fresh process, timed from the
outside (wall time, start-up and imports included), interleaved, medians over ``--runs``:

* ``serial``: ``lmidsl sweep ... --workers 1`` (one process, one compiled model): N = 1 of Dask;
* ``dask-N``: ``lmidsl sweep ... --workers N`` (this process solves points while the local
  cluster starts, then N worker processes, each compiling once; points stored as they finish);
* ``pool-N``: the floor a user would write: ``concurrent.futures.ProcessPoolExecutor`` of N
  forked processes, each compiling the model once in its initializer, ``map`` over the points
  (this file, ``--reference-pool``); ``pool-1`` is its N = 1.

* ``cluster-N``: ``lmidsl sweep ... --scheduler ADDRESS`` on a cluster of N workers started
  once, untimed, before the runs (``lmidsl cluster start --workers N``, ``--cluster N``): the
  fixed cost a user pays who keeps a cluster across commands.

N runs over 1, 2, 4, ... up to the usable cores (``--workers`` caps it; ``--counts 1,4,16`` names
them; ``--pool-counts`` the pool's, ``--pool-counts ''`` none).  Printed: per variant
the wall time, the efficiency wall(1) / (N · wall(N)) against its own family's N = 1, overheads
relative to the solver time, and for Dask what the run measured of itself (points solved in the
main process, tail idle, the gap between tasks on a worker, the main process's CPU per task);
per family the least-squares fit wall = a + b / N: ``a`` the fixed cost (start-up, imports,
compile, close, and what does not parallelise), ``b`` the parallel work.  ``--small`` adds the
2×2 sweep, serial against 2 workers (target: no slower than serial + 1 s).

Usage: ``python benchmarks/bench_parallel.py [--grid 19] [--runs 3] [--workers 2] [--small]``;
quick: ``--grid 7 --runs 2``.  Nothing here is asserted; the machine's load is printed with the
numbers (on a shared machine, read ratios measured in one run, not absolute times).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

THEOREM, EXAMPLE = "li_delay_dropout.thm2", "paper"
ROOT = Path(__file__).resolve().parents[1]


def grid_args(n: int) -> list[str]:
    return ["--grid", f"xi1=0.05:0.95:{n}", "--grid", f"xi2=0.05:0.95:{n}"]


def command(variant: str, n: int, workers: int, scheduler: str | None = None) -> list[str]:
    if variant == "cluster":
        return [sys.executable, "-m", "lmidsl", "sweep", THEOREM, "--example", EXAMPLE, *grid_args(n),
                "--scheduler", scheduler, "--json"]
    if variant == "serial":
        return [sys.executable, "-m", "lmidsl", "sweep", THEOREM, "--example", EXAMPLE, *grid_args(n),
                "--workers", "1", "--json"]
    if variant.startswith("dask"):
        return [sys.executable, "-m", "lmidsl", "sweep", THEOREM, "--example", EXAMPLE, *grid_args(n),
                "--workers", str(workers), "--json"]
    return [sys.executable, __file__, "--reference-pool", str(workers), "--grid", str(n)]


def reference_pool(workers: int, n: int) -> dict:
    """The process-pool loop: each worker compiles once (initializer), then solves its points."""
    import itertools
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from lmidsl.numeric.scaling import apply_scaling
    from lmidsl.pipeline import make_instance
    from lmidsl.solver.backends import DEFAULT_BACKEND
    from lmidsl.studies.sweep import SweepTask
    from lmidsl.studies.defaults import parse_grid

    grids = [parse_grid(g) for g in (f"xi1=0.05:0.95:{n}", f"xi2=0.05:0.95:{n}")]
    base = apply_scaling(make_instance(THEOREM, EXAMPLE), "auto").scaled
    points = [dict(zip(("xi1", "xi2"), combo)) for combo in itertools.product(*[v for _, v in grids])]
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(workers, mp_context=context, initializer=_pool_init,
                             initargs=(SweepTask(base, DEFAULT_BACKEND, None, None, {}),)) as pool:
        solved = list(pool.map(_pool_solve, points))
    return {"points": [p.as_dict() for p in solved]}


_POOL: dict = {}


def _pool_init(task) -> None:
    _POOL["solve"] = task.setup()


def _pool_solve(params):
    return _POOL["solve"](params)


def run_once(variant: str, n: int, workers: int, grid: list[str] | None = None,
             scheduler: str | None = None) -> dict:
    argv = command(variant, n, workers, scheduler) if grid is None else \
        [sys.executable, "-m", "lmidsl", "sweep", THEOREM, "--example", EXAMPLE, *grid,
         "--workers", str(workers), "--json"]
    t0, unix0 = time.perf_counter(), time.time()
    proc = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True)
    wall, unix1 = time.perf_counter() - t0, time.time()
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{variant} failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
    result = json.loads(proc.stdout)
    points = result["points"]
    calls = sum(p["solver_call"] or 0.0 for p in points)
    totals = sum(p["total"] for p in points)
    used = 1 if variant == "serial" else workers
    stats = result.get("parallel", {})
    # outside the runner: start-up (imports, binding, compile) before it, the close and exit after
    outside = wall - stats["wall"] if stats.get("wall") else None
    phases = {"before": stats["entered_unix"] - unix0, "runner": stats["wall"], "close": stats["close"],
              "exit": unix1 - stats["closed_unix"]} if "closed_unix" in stats else None
    return {"wall": wall, "outside": outside, "phases": phases, "points": len(points), "solver_call": calls,
            "in_point": (totals - calls) / calls, "end_to_end": (wall * used - calls) / calls,
            "per_point_call": calls / len(points), "prove": sum(p.get("prove_time", 0.0) for p in points),
            "gammas": [p["gamma"] for p in points], "verdicts": [p.get("verdict") for p in points],
            "parallel": result.get("parallel", {})}


def fit(walls: dict) -> tuple[float, float]:
    """Least squares of wall(N) = a + b / N over the N measured: (a, b)."""
    import numpy as np

    ns = sorted(walls)
    if len(ns) < 2:
        return float("nan"), float("nan")
    design = np.array([[1.0, 1.0 / n] for n in ns])
    (a, b), *_ = np.linalg.lstsq(design, np.array([walls[n] for n in ns]), rcond=None)
    return float(a), float(b)


def start_cluster(workers: int, state: Path) -> str:
    """A cluster of ``workers`` kept across the runs (``lmidsl cluster start``): its address."""
    proc = subprocess.run([sys.executable, "-m", "lmidsl", "cluster", "start", "--workers", str(workers),
                           "--state", str(state)], cwd=ROOT, capture_output=True, text=True)
    if proc.returncode:
        raise SystemExit(f"cluster start failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
    return proc.stdout.strip()


def stop_cluster(state: Path) -> None:
    subprocess.run([sys.executable, "-m", "lmidsl", "cluster", "stop", "--state", str(state)], cwd=ROOT,
                   capture_output=True, text=True)


def counts(text: str | None, default: list[int]) -> list[int]:
    return default if text is None else [int(x) for x in text.split(",") if x.strip()]


def worker_counts(cap: int) -> list[int]:
    """1, 2, 4, ... up to ``cap`` (and ``cap`` itself)."""
    ns, n = [], 1
    while n < cap:
        ns.append(n)
        n *= 2
    return ns + [cap]


def machine() -> str:
    model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                  if line.startswith("model name")), "unknown CPU")
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return f"{cores} usable CPUs ({model}); load average {load}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grid", type=int, default=19, help="points per axis (19: seed 001's sweep)")
    parser.add_argument("--runs", type=int, default=3, help="interleaved runs per variant (median)")
    parser.add_argument("--workers", type=int, help="the largest N (default: the usable cores)")
    parser.add_argument("--counts", help="the N of dask-N, comma-separated (default: 1, 2, 4, ... cores)")
    parser.add_argument("--pool-counts", help="the N of pool-N (default: as --counts; '' for none)")
    parser.add_argument("--cluster", type=int, metavar="N", help="also cluster-N: sweeps on a cluster of "
                        "N workers started once before the runs")
    parser.add_argument("--json-out", metavar="FILE", help="write every run's measurements here")
    parser.add_argument("--small", action="store_true", help="also the 2x2 sweep, serial and 2 workers")
    parser.add_argument("--reference-pool", type=int, metavar="W", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.reference_pool:
        print(json.dumps(reference_pool(args.reference_pool, args.grid)))
        return
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    ns = counts(args.counts, worker_counts(args.workers or max(2, cores)))
    pool_ns = counts(args.pool_counts, ns)
    variants = ["serial"] + [f"dask-{n}" for n in ns if n > 1] + [f"pool-{n}" for n in pool_ns] + \
        ([f"cluster-{args.cluster}"] if args.cluster else [])
    print(f"{THEOREM} [{EXAMPLE}] sweep {args.grid}x{args.grid} = {args.grid ** 2} points, "
          f"{args.runs} interleaved run(s); {machine()}", flush=True)
    scheduler = state = None
    if args.cluster:
        import tempfile
        state = Path(tempfile.mkdtemp()) / "cluster.json"
        t0 = time.perf_counter()
        scheduler = start_cluster(args.cluster, state)
        print(f"cluster of {args.cluster} workers started in {time.perf_counter() - t0:.1f} s (untimed "
              f"in cluster-{args.cluster}): {scheduler}", flush=True)
    runs: dict = {v: [] for v in variants}
    try:
        for r in range(args.runs):
            k = r % len(variants)
            for v in variants[k:] + variants[:k]:             # rotate: no variant always first
                n = 1 if v == "serial" else int(v.split("-")[1])
                runs[v].append(run_once(v.split("-")[0] if v != "serial" else v, args.grid, n,
                                        scheduler=scheduler))
                print(f"  run {r + 1} {v:10s} {runs[v][-1]['wall']:8.2f} s", file=sys.stderr, flush=True)
    finally:
        if state is not None:
            stop_cluster(state)
    if args.json_out:
        Path(args.json_out).write_text(json.dumps({"machine": machine(), "grid": args.grid, "runs": runs}))
    med = {v: {k: statistics.median(x[k] for x in runs[v]) for k in
               ("wall", "in_point", "end_to_end", "per_point_call", "prove")} for v in variants}
    families = {"dask": {1: med["serial"]["wall"], **{n: med[f"dask-{n}"]["wall"] for n in ns if n > 1}},
                "pool": {n: med[f"pool-{n}"]["wall"] for n in pool_ns}}
    print(f"{'variant':11s} {'wall s':>8s} {'speed-up':>9s} {'effic.':>7s} {'solver call/pt ms':>18s} "
          f"{'in-point ovh':>13s} {'end-to-end ovh':>15s} {'proofs s':>9s} {'outside s':>10s}")
    for v in variants:
        m = med[v]
        family, n = ("dask", 1) if v == "serial" else (v.split("-")[0], int(v.split("-")[1]))
        # against the family's own N = 1 where it has one, else against serial
        one = families.get(family, {}).get(1, med["serial"]["wall"])
        outside = [x["outside"] for x in runs[v] if x["outside"] is not None]
        print(f"{v:11s} {m['wall']:8.2f} {one / m['wall']:8.2f}x {100 * one / (n * m['wall']):6.1f}% "
              f"{1e3 * m['per_point_call']:18.1f} {100 * m['in_point']:12.1f}% {100 * m['end_to_end']:14.1f}% "
              f"{m['prove']:9.2f} " + (f"{statistics.median(outside):10.2f}" if outside else f"{'-':>10s}"))
    for family, walls in families.items():
        a, b = fit(walls)
        print(f"fit {family}: wall = a + b/N with a = {a:.2f} s (fixed cost), b = {b:.2f} s "
              f"({1e3 * b / args.grid ** 2:.1f} ms a point), over N = {sorted(walls)}")
    if args.cluster:
        v = f"cluster-{args.cluster}"
        b = families["dask"].get(1, med["serial"]["wall"])
        print(f"{v}: fixed cost a = wall - wall(1)/N = {med[v]['wall'] - b / args.cluster:.2f} s "
              f"(b taken as the serial wall)")
    for v in variants:
        for x in runs[v]:
            if x["parallel"]:
                from lmidsl.render.text import format_stats
                print(f"{v}: {format_stats(x['parallel'])}")
            if x.get("phases"):
                print(f"{v}: phases (s): " + ", ".join(f"{k} {t:.2f}" for k, t in x["phases"].items()))
    reference = runs["serial"][0]
    same = all(x["gammas"] == reference["gammas"] and x["verdicts"] == reference["verdicts"]
               for v in variants if not v.startswith("pool") for x in runs[v])
    worst = max(abs(a - b) for v in variants for x in runs[v] for a, b in zip(x["gammas"], reference["gammas"])
                if a is not None and b is not None)
    print(f"every point's γ and verdict identical to serial on Dask: {same}; largest |γ - γ serial| "
          f"(pool included): {worst:.2e}")
    if args.small:
        grid = ["--grid", "xi1=0.3,0.6", "--grid", "xi2=0.3,0.6"]
        small = {1: [], 2: []}
        for r in range(args.runs):
            for w in ((1, 2) if r % 2 == 0 else (2, 1)):
                small[w].append(run_once("small", 2, w, grid)["wall"])
        s1, s2 = (statistics.median(small[w]) for w in (1, 2))
        print(f"2x2 sweep: serial {s1:.2f} s, 2 workers {s2:.2f} s: {s2 - s1:+.2f} s (target <= +1 s)")
    print(f"machine after: {machine()}")


if __name__ == "__main__":
    main()
