"""Cost of the proved lower bound and of the infeasibility proof on the papers' examples.

For each paper example (provenance "paper") the full ``lmidsl.solve`` (bind, solve, recovery,
certificates, evidence) is timed with its bounds (the default) and with ``bounds=False`` (the
CLI's ``--no-bounds``), interleaved, medians over the repeats.  Two ratios are printed:

* wall: what the user waits, (solve with bounds) / (solve without).  The lower bound runs on a
  worker thread from the end of the main solve (:class:`lmidsl.solver.dual_bound.PendingBound`),
  beside recovery and certification, so on a machine with a free core much of it is hidden;
* cpu: the process's CPU time (every thread), the work the bound adds whatever the machine.

The issue's target is wall ≤ 1.25 per example; the summary also gives the ratio of the sums
(a whole ``reproduce`` run's cost).

    python benchmarks/bench_bounds.py [--repeat 3] [--only THEOREM ...]
"""
from __future__ import annotations

import argparse
import statistics
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
    print(f"worst wall ratio {worst:.2f} (target ≤ 1.25); over all examples: wall {sums[0] / sums[1]:.2f}, "
          f"cpu {sums[2] / sums[3]:.2f}")


if __name__ == "__main__":
    main()
