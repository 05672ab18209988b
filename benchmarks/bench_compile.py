"""Build+compile time of lmidsl against a hand-written cvxpy model of the same LMIs.

The family is Theorem 3 of seed 000 ((30), (31), P1 > 0, P3 > 0, min γ²) with E = I (full
order) on random stable plants of order n.  For each n, measured in the same run:

* ``lmidsl``: bind the data to the (already loaded) theorem, compile to a ``cvxpy.Problem``
  (``CvxpyModel``), and let cvxpy produce the solver's problem data (``get_problem_data``),
  which is the work done before the solver starts;
* ``hand``: the same LMIs written by hand in cvxpy with numeric constants, then
  ``get_problem_data``;
* ``hand+param``: the hand-written model with r̄ and a as ``cp.Parameter`` (what one writes
  to sweep r̄ without rebuilding), against lmidsl's ``reuse=True`` model (what ``lmidsl sweep``
  builds: every scalar parameter expression and the margin are ``cp.Parameter``).

Times are medians of CPU time over interleaved repeats; ratios are lmidsl / hand.  Usage:
``python benchmarks/bench_compile.py [--sizes 2 5 10 20 40 80] [--repeat 5] [--solver CLARABEL]``.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import cvxpy as cp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


from lmidsl.pipeline import make_instance  # noqa: E402
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel  # noqa: E402
from lmidsl.solver.backends.direct_backend import DirectModel  # noqa: E402
from lmidsl.theorem.registry import get_theorem  # noqa: E402

from hand_thm3 import RBAR, hand_written, random_plant  # noqa: E402


def timed_interleaved(fns, repeat: int) -> list[float]:
    """Median CPU time of each function, the functions run in turn so load affects all alike.

    CPU time of this process (``time.process_time``), not wall time: other processes on the
    machine then disturb the ratio much less.
    """
    samples = [[] for _ in fns]
    for _ in range(repeat):
        for i, fn in enumerate(fns):
            t0 = time.process_time()
            fn()
            samples[i].append(time.process_time() - t0)
    return [statistics.median(s) for s in samples]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[2, 5, 10, 20, 40, 80])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--solver", default="CLARABEL")
    ap.add_argument("--solve-check", action="store_true",
                    help="also solve both models once and compare γ² (sanity check of the reference)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    theorem = get_theorem("wang_l2linf.thm3")
    print(f"theorem file loaded once (all theorems of the folder) in {time.perf_counter() - t0:.3f} s "
          f"(not included below)")
    rng = np.random.default_rng(1)
    header = (f"{'n':>4} {'direct [s]':>11} {'cvxpy be. [s]':>14} {'hand [s]':>10} {'direct/hand':>12} "
              f"{'cvxpy be./hand':>15} {'cvxpy reuse [s]':>16} {'hand+param [s]':>15} {'ratio':>7}")
    print(header)
    print("-" * len(header))
    worst = worst_cvxpy = worst_reuse = 0.0
    for n in args.sizes:
        plant = random_plant(n, rng)
        inputs = {k: v.tolist() for k, v in plant.items()}
        inputs["rbar"] = RBAR

        def run_direct():
            return DirectModel(make_instance(theorem, data=inputs))   # the standard form is built

        def run_lmidsl():
            model = CvxpyModel(make_instance(theorem, data=inputs))
            model.problem.get_problem_data(args.solver)
            return model

        def run_lmidsl_reuse():
            model = CvxpyModel(make_instance(theorem, data=inputs), reuse=True)
            model.problem.get_problem_data(args.solver)
            return model

        def run_hand(param=False):
            prob = hand_written(plant, param)
            prob.get_problem_data(args.solver)
            return prob

        run_direct(), run_lmidsl(), run_lmidsl_reuse(), run_hand(), run_hand(True)  # warm-up (imports, caches)
        t_d, t_l, t_h, t_lr, t_hp = timed_interleaved(
            [run_direct, run_lmidsl, run_hand, run_lmidsl_reuse, lambda: run_hand(True)], args.repeat)
        worst = max(worst, t_d / t_h)
        worst_cvxpy = max(worst_cvxpy, t_l / t_h)
        worst_reuse = max(worst_reuse, t_lr / t_hp)
        print(f"{n:>4} {t_d:>11.4f} {t_l:>14.4f} {t_h:>10.4f} {t_d / t_h:>12.2f} {t_l / t_h:>15.2f} "
              f"{t_lr:>16.4f} {t_hp:>15.4f} {t_lr / t_hp:>7.2f}", flush=True)
        if args.solve_check:
            direct = run_direct().solve()
            model = run_lmidsl()
            model.problem.solve(solver=args.solver)
            prob = run_hand()
            prob.solve(solver=args.solver)
            print(f"     γ² direct {direct.objective:.8g}  cvxpy backend {model.problem.value:.8g}  "
                  f"hand {prob.value:.8g}")
    print(f"worst ratio direct/hand: {worst:.2f} (target ≤ 0.5); cvxpy backend/hand: {worst_cvxpy:.2f}; "
          f"re-solvable models, cvxpy reuse/hand+param: {worst_reuse:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
