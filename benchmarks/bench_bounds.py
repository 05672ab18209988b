"""Cost of the proved lower bound and of the infeasibility proof on the papers' examples.

For each paper example (provenance "paper") the full ``lmidsl.solve`` (bind, solve, recovery,
certificates, evidence) is timed with its bounds (the default) and with ``bounds=False`` (the
CLI's ``--no-bounds``), interleaved, medians over the repeats.  Two ratios are printed:

* wall: what the user waits, (solve with bounds) / (solve without).  The lower bound runs on a
  worker thread from the end of the main solve (:class:`lmidsl.certify.dual_bound.PendingBound`),
  beside recovery and certification, so on a machine with a free core much of it is hidden;
* cpu: the process's CPU time (every thread), the work the bound adds whatever the machine.

and the command a user types, ``lmidsl solve THEOREM --example EXAMPLE`` against the same
with ``--no-bounds`` (fresh processes, interleaved: start-up, bind, solve, certificates, output).
The issue's target (≤ 1.25) is on ``solve``, the command; the library's ratio is the cost of the
bound alone, which start-up does not dilute.  The summary also gives the ratio of the sums (a
whole ``reproduce`` run's cost).

    python benchmarks/bench_bounds.py [--repeat 3] [--only THEOREM ...] [--no-cli]
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
import warnings

import lmidsl
from lmidsl.studies.reproduce import row_provenance
from lmidsl.theorem.registry import all_theorems


def paper_examples(only=None):
    for tid, thm in sorted(all_theorems().items()):
        if only and tid not in only:
            continue
        for ex in thm.examples:
            if row_provenance(thm, ex) == "paper":
                yield tid, ex


def measure(tid, ex, bounds: bool):
    w0, c0 = time.perf_counter(), time.process_time()
    sol = lmidsl.solve(tid, ex, bounds=bounds)
    return time.perf_counter() - w0, time.process_time() - c0, sol


def command(tid, ex, bounds: bool, where: str) -> float:
    """Wall time of ``lmidsl solve`` in a fresh process (any exit code: a verdict, not a failure)."""
    argv = [sys.executable, "-m", "lmidsl", "solve", tid, "--example", ex] + ([] if bounds else ["--no-bounds"])
    t0 = time.perf_counter()
    subprocess.run(argv, cwd=where, capture_output=True, check=False)
    return time.perf_counter() - t0


def describe(sol) -> tuple[str, str]:
    """(what was proved, lower / upper or the infeasibility verdict)."""
    if sol.infeasibility is not None:
        return "infeasible", "proved" if sol.infeasibility.proved else "not proved"
    b = sol.bounds
    if b is None:
        return "-", "-"
    lower = f"{b.lower_performance:.9g}" if b.proved and b.lower_performance is not None else "-"
    upper = "-" if sol.gamma is None else f"{sol.gamma:.9g}"
    return f"lower ({b.extra_solves})", f"{lower} / {upper}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", nargs="*")
    parser.add_argument("--no-cli", action="store_true", help="skip the command-line timings")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    rows = list(paper_examples(args.only))
    for r in rows:                               # warm the caches (imports, compiled members)
        measure(*r, True)
    runs = {r: {True: [], False: []} for r in rows}
    info = {}
    for _ in range(args.repeat):
        for r in rows:
            for bounds in (True, False):
                wall, cpu, sol = measure(*r, bounds)
                runs[r][bounds].append((wall, cpu))
                if bounds:
                    info[r] = describe(sol)
    print(f"{'theorem':28} {'example':24} {'proof':11} {'with [s]':>8} {'without':>8} {'wall':>5} {'cpu':>5}  lower / upper")
    worst, sums = 0.0, [0.0, 0.0, 0.0, 0.0]
    for r in rows:
        med = {b: (statistics.median(w for w, _ in runs[r][b]), statistics.median(c for _, c in runs[r][b]))
               for b in (True, False)}
        wall, cpu = med[True][0] / med[False][0], med[True][1] / max(med[False][1], 1e-9)
        worst = max(worst, wall)
        sums = [sums[0] + med[True][0], sums[1] + med[False][0], sums[2] + med[True][1], sums[3] + med[False][1]]
        what, detail = info[r]
        print(f"{r[0]:28} {r[1]:24} {what:11} {med[True][0]:8.3f} {med[False][0]:8.3f} {wall:5.2f} {cpu:5.2f}  {detail}")
    print(f"library: worst wall ratio {worst:.2f}; over all examples: wall {sums[0] / sums[1]:.2f}, "
          f"cpu {sums[2] / sums[3]:.2f}")
    if args.no_cli:
        return
    with tempfile.TemporaryDirectory() as where:
        for r in rows:                           # warm lmidsl's theorem cache
            command(*r, True, where)
        cli = {r: {True: [], False: []} for r in rows}
        for _ in range(args.repeat):
            for r in rows:
                for bounds in (True, False):
                    cli[r][bounds].append(command(*r, bounds, where))
    print(f"\n{'lmidsl solve':53} {'with [s]':>8} {'without':>8} {'ratio':>5}")
    worst, total = 0.0, [0.0, 0.0]
    for r in rows:
        w, wo = statistics.median(cli[r][True]), statistics.median(cli[r][False])
        worst = max(worst, w / wo)
        total = [total[0] + w, total[1] + wo]
        print(f"{r[0]:28} {r[1]:24} {w:8.3f} {wo:8.3f} {w / wo:5.2f}")
    print(f"command: worst ratio {worst:.2f} (target ≤ 1.25); over all examples {total[0] / total[1]:.2f}")


if __name__ == "__main__":
    main()
