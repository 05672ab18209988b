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

import cvxpy as cp
import numpy as np


from lmidsl.pipeline import make_instance  # noqa: E402
from lmidsl.solver.backends.base import DEFAULT_MARGIN  # noqa: E402
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel  # noqa: E402
from lmidsl.theorem.registry import get_theorem  # noqa: E402

M_IN, NY, P_OUT = 2, 2, 1
RBAR = 0.8


def random_plant(n: int, rng: np.random.Generator) -> dict:
    A = rng.standard_normal((n, n))
    A *= 0.9 / max(abs(np.linalg.eigvals(A)))
    return {"A": A, "B": rng.standard_normal((n, M_IN)), "C": rng.standard_normal((NY, n)),
            "D": rng.standard_normal((NY, M_IN)), "L": rng.standard_normal((P_OUT, n)),
            "E": np.eye(n)}


def hand_written(d: dict, use_parameters: bool) -> cp.Problem:
    """(30), (31), P1 > 0, P3 > 0 and min γ² written directly in cvxpy (E = I, k = n)."""
    A, B, C, D, L, E = (d[k] for k in "ABCDLE")
    n, k, m, p = A.shape[0], E.shape[1], B.shape[1], L.shape[0]
    if use_parameters:
        r = cp.Parameter(value=RBAR)
        a = cp.Parameter(value=(1 - RBAR) * RBAR)
    else:
        r, a = RBAR, (1 - RBAR) * RBAR
    eps = DEFAULT_MARGIN
    P1 = cp.Variable((n, n), symmetric=True)
    P2 = cp.Variable((n, k))
    P3 = cp.Variable((k, k), symmetric=True)
    V1, V2, V3 = cp.Variable((n, n)), cp.Variable((k, k)), cp.Variable((n, k))
    Ah, Bh, Ch = cp.Variable((k, k)), cp.Variable((k, C.shape[0])), cp.Variable((p, k))
    g = cp.Variable()
    W11 = P1 - V1 - V1.T
    W21 = P2.T - V3.T - V2.T @ E.T
    W22 = P3 - V2 - V2.T
    Z = np.zeros
    r41 = V1.T @ A + r * (E @ Bh @ C)
    r42 = E @ Ah
    r43 = V1.T @ B + E @ Bh @ D
    r51 = V3.T @ A + r * (Bh @ C)
    r53 = V3.T @ B + Bh @ D
    r61 = a * (E @ Bh @ C)
    r71 = a * (Bh @ C)
    M30 = cp.bmat([
        [-P1, -P2, Z((n, m)), r41.T, r51.T, r61.T, r71.T],
        [-P2.T, -P3, Z((k, m)), r42.T, Ah.T, Z((k, n)), Z((k, k))],
        [Z((m, n)), Z((m, k)), -np.eye(m), r43.T, r53.T, Z((m, n)), Z((m, k))],
        [r41, r42, r43, W11, W21.T, Z((n, n)), Z((n, k))],
        [r51, Ah, r53, W21, W22, Z((k, n)), Z((k, k))],
        [r61, Z((n, k)), Z((n, m)), Z((n, n)), Z((n, k)), a * W11, a * W21.T],
        [r71, Z((k, k)), Z((k, m)), Z((k, n)), Z((k, k)), a * W21, a * W22],
    ])
    M31 = cp.bmat([[-P1, -P2, L.T], [-P2.T, -P3, -Ch.T], [L, -Ch, -g * np.eye(p)]])
    size30 = 3 * n + 3 * k + m
    cons = [M30 << -eps * np.eye(size30), M31 << -eps * np.eye(n + k + p),
            P1 >> eps * np.eye(n), P3 >> eps * np.eye(k)]
    return cp.Problem(cp.Minimize(g), cons)


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
    header = (f"{'n':>4} {'lmidsl [s]':>11} {'hand [s]':>10} {'ratio':>7} "
              f"{'lmidsl reuse [s]':>17} {'hand+param [s]':>15} {'ratio':>7}")
    print(header)
    print("-" * len(header))
    worst = worst_reuse = 0.0
    for n in args.sizes:
        plant = random_plant(n, rng)
        inputs = {k: v.tolist() for k, v in plant.items()}
        inputs["rbar"] = RBAR

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

        run_lmidsl(), run_lmidsl_reuse(), run_hand(), run_hand(True)  # warm-up (imports, caches)
        t_l, t_h, t_lr, t_hp = timed_interleaved(
            [run_lmidsl, run_hand, run_lmidsl_reuse, lambda: run_hand(True)], args.repeat)
        worst = max(worst, t_l / t_h)
        worst_reuse = max(worst_reuse, t_lr / t_hp)
        print(f"{n:>4} {t_l:>11.4f} {t_h:>10.4f} {t_l / t_h:>7.2f} {t_lr:>17.4f} {t_hp:>15.4f} "
              f"{t_lr / t_hp:>7.2f}", flush=True)
        if args.solve_check:
            model = run_lmidsl()
            model.problem.solve(solver=args.solver)
            prob = run_hand()
            prob.solve(solver=args.solver)
            print(f"     γ² lmidsl {model.problem.value:.8g}  hand {prob.value:.8g}")
    print(f"worst ratio lmidsl/hand: {worst:.2f} (target ≤ 1.30); "
          f"re-solvable models, lmidsl reuse/hand+param: {worst_reuse:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
