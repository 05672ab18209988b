"""Scale-out of ``lmidsl sweep``: 1 worker, 2 Dask workers, and a plain process-pool loop.

The sweep is seed 001's (docs/reproductions/001.md): ``li_delay_dropout.thm2 --example paper``
over ξ1 × ξ2 = (0.05:0.95:N)², N = 19 by default.  Each run is a fresh process, timed from the
outside (wall time, start-up and imports included), interleaved, medians over ``--runs``:

* ``serial``: ``lmidsl sweep ... --workers 1`` (one process, one compiled model);
* ``dask-2``: ``lmidsl sweep ... --workers 2`` (a Dask LocalCluster of two processes, each
  compiling once; points stream back and are stored as they finish);
* ``pool-2``: the reference a user would write: ``concurrent.futures.ProcessPoolExecutor`` of
  two forked processes, each compiling the same model once in its initializer, ``map`` over
  the points (this file, ``--reference-pool``).

Printed per variant: wall time, speedup over ``serial``, and overheads relative to the solver
time (``solver call``, the solver with its cvxpy interface, as the sweep records per point):

* ``in-point``: Σ(point total − solver call) / Σ solver call — parameter update, reading the
  values, the certificate (the sweep's own per-point overhead);
* ``end-to-end``: (wall × workers − Σ solver call) / Σ solver call — everything else, start-up,
  compile, proofs, scheduling and idle workers included.

Usage: ``python benchmarks/bench_parallel.py [--grid 19] [--runs 5] [--workers 2]``; quick:
``--grid 7 --runs 3``.  Nothing here is asserted; the machine's load is printed with the numbers.
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


def command(variant: str, n: int, workers: int) -> list[str]:
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
    from lmidsl.studies.sweep import SweepTask, parse_grid

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


def run_once(variant: str, n: int, workers: int) -> dict:
    t0 = time.perf_counter()
    proc = subprocess.run(command(variant, n, workers), cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{variant} failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
    points = json.loads(proc.stdout)["points"]
    calls = sum(p["solver_call"] or 0.0 for p in points)
    totals = sum(p["total"] for p in points)
    used = 1 if variant == "serial" else workers
    return {"wall": wall, "points": len(points), "solver_call": calls,
            "in_point": (totals - calls) / calls, "end_to_end": (wall * used - calls) / calls,
            "per_point_call": calls / len(points), "prove": sum(p.get("prove_time", 0.0) for p in points),
            "gammas": [p["gamma"] for p in points]}


def machine() -> str:
    model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                  if line.startswith("model name")), "unknown CPU")
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    return f"{os.cpu_count()} CPUs ({model}); load average {load}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grid", type=int, default=19, help="points per axis (19: seed 001's sweep)")
    parser.add_argument("--runs", type=int, default=5, help="interleaved runs per variant (median)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--reference-pool", type=int, metavar="W", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.reference_pool:
        print(json.dumps(reference_pool(args.reference_pool, args.grid)))
        return
    variants = ["serial", f"dask-{args.workers}", f"pool-{args.workers}"]
    print(f"{THEOREM} [{EXAMPLE}] sweep {args.grid}x{args.grid} = {args.grid ** 2} points, "
          f"{args.runs} interleaved run(s); {machine()}", flush=True)
    runs: dict = {v: [] for v in variants}
    for r in range(args.runs):
        order = variants[r % 3:] + variants[:r % 3]          # rotate: no variant always first
        for v in order:
            runs[v].append(run_once(v, args.grid, args.workers))
            print(f"  run {r + 1} {v:8s} {runs[v][-1]['wall']:8.2f} s", file=sys.stderr, flush=True)
    med = {v: {k: statistics.median(x[k] for x in runs[v]) for k in
               ("wall", "in_point", "end_to_end", "per_point_call", "prove")} for v in variants}
    print(f"{'variant':9s} {'wall s':>8s} {'speedup':>8s} {'solver call/pt ms':>18s} "
          f"{'in-point ovh':>13s} {'end-to-end ovh':>15s} {'proofs s':>9s}")
    for v in variants:
        m = med[v]
        print(f"{v:9s} {m['wall']:8.2f} {med['serial']['wall'] / m['wall']:8.2f} "
              f"{1e3 * m['per_point_call']:18.1f} {100 * m['in_point']:12.1f}% "
              f"{100 * m['end_to_end']:14.1f}% {m['prove']:9.2f}")
    reference = runs["serial"][0]["gammas"]
    worst = max(abs(a - b) for v in variants for x in runs[v] for a, b in zip(x["gammas"], reference)
                if a is not None and b is not None)
    print(f"largest |γ - γ serial| over every run: {worst:.2e}; machine after: {machine()}")


if __name__ == "__main__":
    main()
