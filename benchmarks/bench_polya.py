"""Compile time of an HPPD robust stability problem against the same coefficient LMIs by hand.

The problem: textbook.hpd_stability_ct on a 4-vertex polytope of 6×6 matrices, P(α) of degree
g = 3 (20 coefficient matrices), Pólya's d (default 1): He(P(α)A(α)) ≺ 0 and P(α) ≻ 0 as
coefficient LMIs (56 + 35 of them at d = 1).  Measured in one run, medians of CPU time over
interleaved repeats:

* ``lmidsl``: the member built from the statement (the expansion in α: homogenisation, Pólya,
  the coefficient LMIs, from an empty cache), the data bound, and the model compiled by the
  default (direct, Clarabel standard form) backend — everything before the solver starts;
* ``lmidsl/cvxpy``: the same through the cvxpy backend, then cvxpy's ``get_problem_data``;
* ``hand``: the coefficient LMIs written by hand in cvxpy (loops over the monomials with the
  multinomial coefficients), then ``get_problem_data(CLARABEL)``.

Ratios are lmidsl / hand (target ≤ 2).  Peak memory (tracemalloc) of one build of each.  The
hand-written model is also solved and its feasibility compared with lmidsl's.
Usage: python benchmarks/bench_polya.py [--degree 3] [--polya 1] [--n 6] [--vertices 4] [--repeat 5]

``--end-to-end --n 2 [--timeout 120]``: the whole ``lmidsl.solve`` of textbook.hpd_stability_ct at
3, 6, 12 vertices x g = 1-3 x d = 0-2, each in a bounded child process (:mod:`end_to_end`: wall,
CPU, peak resident memory, the times record, or the refusal with its estimate).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
import tracemalloc
from math import comb
from pathlib import Path

import cvxpy as cp
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from lmidsl.numeric.instance import bind  # noqa: E402
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel  # noqa: E402
from lmidsl.solver.backends.direct_backend import DirectModel  # noqa: E402
from lmidsl.symbolic.simplex import exponents, multinomial  # noqa: E402
from lmidsl.theorem.registry import get_theorem  # noqa: E402
from lmidsl.theorems.textbook.hpd import random_polytope  # noqa: E402

MARGIN = 1e-7


def lmidsl_build(data, g, d, backend=DirectModel, problem_data=False):
    theorem = get_theorem("textbook.hpd_stability_ct")
    theorem._members.clear()                       # the expansion in α is part of the work
    instance = bind(theorem, {**data, "degree": g, "polya": d})
    model = backend(instance)
    if problem_data:
        model.problem.get_problem_data(cp.CLARABEL)
    return model


def hand_build(data, g, d):
    """He(P(α)A(α)) ≺ 0 and P(α) ≻ 0 on Λ_N, Pólya of degree d, by hand."""
    A = [np.asarray(v["A"]) for v in data["vertices"]]
    N, n = len(A), A[0].shape[0]
    P = {k: cp.Variable((n, n), symmetric=True) for k in exponents(N, g)}
    units = [tuple(int(i == j) for j in range(N)) for i in range(N)]
    cons = []
    # He(P A): degree g + 1, times (Σα)^d
    for m in exponents(N, g + 1 + d):
        terms = []
        for j in exponents(N, d):
            rest = tuple(a - b for a, b in zip(m, j))
            if min(rest) < 0:
                continue
            w = multinomial(j)
            for i, e in enumerate(units):
                k = tuple(a - b for a, b in zip(rest, e))
                if min(k) < 0:
                    continue
                terms.append(w * (P[k] @ A[i] + A[i].T @ P[k]))
        cons.append(cp.sum(terms) << -MARGIN * np.eye(n))
    # P(α): degree g, times (Σα)^d
    for m in exponents(N, g + d):
        terms = []
        for j in exponents(N, d):
            k = tuple(a - b for a, b in zip(m, j))
            if min(k) >= 0:
                terms.append(multinomial(j) * P[k])
        cons.append(cp.sum(terms) >> MARGIN * np.eye(n))
    problem = cp.Problem(cp.Minimize(0), cons)
    problem.get_problem_data(cp.CLARABEL)
    return problem


def cpu(fn):
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def peak_memory(fn) -> float:
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / 2 ** 20


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--degree", type=int, default=3)
    ap.add_argument("--polya", type=int, default=1)
    ap.add_argument("--n", type=int, default=6)
    ap.add_argument("--vertices", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--end-to-end", action="store_true",
                    help="instead: lmidsl.solve of textbook.hpd_stability_ct (n = --n) at 3, 6, 12 vertices x "
                         "degree 1-3 x Polya 0-2, each in a child process bounded by --timeout: wall, CPU, peak "
                         "memory, the times record, or the refusal with its estimate")
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args()
    if args.end_to_end:
        import end_to_end
        print(end_to_end.load())
        for N in (3, 6, 12):
            data = random_polytope(1, n=args.n, vertices=N, spread=0.5)
            for g in (1, 2, 3):
                for d in (0, 1, 2):
                    out = end_to_end.run("textbook.hpd_stability_ct", data, {"degree": g, "polya": d},
                                         timeout=args.timeout)
                    print(end_to_end.line(f"N={N} g={g} d={d}", out), flush=True)
        return
    g, d, N = args.degree, args.polya, args.vertices
    data = random_polytope(7, n=args.n, vertices=N, spread=0.5)
    count = comb(N + g + d, g + 1 + d) + comb(N + g + d - 1, g + d)
    print(f"HPPD stability, n = {args.n}, N = {N}, g = {g}, d = {d}: {comb(N + g - 1, g)} coefficient "
          f"matrices, {count} coefficient LMIs")
    runs = {"lmidsl": lambda: lmidsl_build(data, g, d),
            "lmidsl/cvxpy": lambda: lmidsl_build(data, g, d, CvxpyModel, problem_data=True),
            "hand": lambda: hand_build(data, g, d)}
    for fn in runs.values():        # warm-up: imports, caches of the libraries
        fn()
    times = {name: [] for name in runs}
    for _ in range(args.repeat):
        for name, fn in runs.items():
            times[name].append(cpu(fn))
    med = {name: statistics.median(ts) for name, ts in times.items()}
    memory = {name: peak_memory(fn) for name, fn in runs.items()}
    for name in runs:
        print(f"{name:13s} {1e3 * med[name]:8.1f} ms   peak memory {memory[name]:6.1f} MiB")
    print(f"ratio lmidsl / hand:        {med['lmidsl'] / med['hand']:.2f}  (target ≤ 2)")
    print(f"ratio lmidsl/cvxpy / hand:  {med['lmidsl/cvxpy'] / med['hand']:.2f}")
    hand = hand_build(data, g, d)
    hand.solve(solver=cp.CLARABEL)
    model = lmidsl_build(data, g, d)
    sol = model.solve()
    print(f"feasible: hand {hand.status}, lmidsl {sol.status} (every coefficient LMI holds: {sol.lmis_hold})")


if __name__ == "__main__":
    main()
