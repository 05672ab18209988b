"""Cost of the proved lower bound and of the infeasibility proof on the papers' examples.

For each paper example (provenance "paper") the full ``lmidsl.solve`` (bind, solve, recovery,
certificates) is timed, then the compiled direct model is solved again as ``solve_instance``
does and :func:`lmidsl.solver.dual_bound.lower_bound` (or, for an infeasible example,
:func:`lmidsl.solver.infeasibility.prove_infeasible`) is timed on it.  The ratio printed is
(solve + bound) / solve, medians over interleaved repeats; the issue's target is ≤ 1.25.

    python benchmarks/bench_bounds.py [--repeat 3] [--only THEOREM ...]
"""
from __future__ import annotations

import argparse
import statistics
import time
import warnings

import lmidsl
from lmidsl.numeric.scaling import apply_scaling
from lmidsl.pipeline import make_instance
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.solver.dual_bound import lower_bound
from lmidsl.solver.infeasibility import prove_infeasible
from lmidsl.solver.margin import solve_model
from lmidsl.studies.reproduce import row_provenance
from lmidsl.theorem.registry import all_theorems


def paper_examples(only=None):
    for tid, thm in sorted(all_theorems().items()):
        if only and tid not in only:
            continue
        for ex in thm.examples:
            if row_provenance(thm, ex) == "paper":
                yield tid, ex


def measure(tid, ex):
    t0 = time.perf_counter()
    sol = lmidsl.solve(tid, ex)
    full = time.perf_counter() - t0
    model = DirectModel(apply_scaling(make_instance(tid, ex), "auto").scaled)
    msol = solve_model(model)
    t0 = time.perf_counter()
    if msol.ok and model.objective is not None:
        record = lower_bound(model, msol)
        what = "lower"
        detail = (f"{record.lower_performance:.9g}" if record.proved else "-") + f" / {sol.gamma:.9g}" \
            if sol.gamma is not None else "-"
    else:
        record = prove_infeasible(model)
        what = "infeasible"
        detail = "proved" if record.proved else "not proved"
    extra = time.perf_counter() - t0
    return full, extra, what, record.proved, detail


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", nargs="*")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    rows = list(paper_examples(args.only))
    times = {r: ([], []) for r in rows}
    info = {}
    for _ in range(args.repeat):
        for r in rows:
            full, extra, what, proved, detail = measure(*r)
            times[r][0].append(full)
            times[r][1].append(extra)
            info[r] = (what, proved, detail)
    print(f"{'theorem':32} {'example':26} {'proof':10} {'proved':6} {'solve [s]':>9} {'bound [s]':>9} {'ratio':>6}  lower / upper")
    worst = 0.0
    for r in rows:
        full, extra = statistics.median(times[r][0]), statistics.median(times[r][1])
        ratio = (full + extra) / full
        worst = max(worst, ratio)
        what, proved, detail = info[r]
        print(f"{r[0]:32} {r[1]:26} {what:10} {str(proved):6} {full:9.3f} {extra:9.3f} {ratio:6.2f}  {detail}")
    print(f"worst ratio (solve + bound) / solve: {worst:.2f} (target ≤ 1.25)")


if __name__ == "__main__":
    main()
