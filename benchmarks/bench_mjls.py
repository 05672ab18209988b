"""Compile time of an indexed theorem (a 10-mode Markov jump design, n = 4) against the same LMIs
written by hand in cvxpy.

The theorem is ``textbook.mjls_hinf_sf_ct``: for every mode i one LMI with a block column of
√π_ij Y_i and a block diagonal of Y_j over the 9 other modes (N LMIs of N + 2 block rows), plus
Y_i ≻ 0.  Measured in the same run, medians of CPU time over interleaved repeats:

* ``first``: the first bind of an N-mode input (the member theorem is instantiated from the one
  quantified statement, then compiled to the direct backend's standard form);
* ``direct``: bind (member cached) + compile to the direct backend's standard form (what
  Clarabel is handed);
* ``cvxpy be.``: bind + compile with the cvxpy backend + ``get_problem_data``;
* ``hand``: the same LMIs typed in cvxpy with numeric constants (Python loops over the modes),
  then ``get_problem_data``.

A ``--solve-check`` run also solves both and compares γ.  Usage:
``python benchmarks/bench_mjls.py [--modes 10] [--n 4] [--repeat 7] [--solve-check]``.

``--end-to-end 10,30,60,200 --n 2 [--timeout 120]``: the whole ``lmidsl.solve`` of
``textbook.mjls_sf_ct`` per number of modes, each in a bounded child process
(:mod:`end_to_end`: wall, CPU, peak resident memory, the times record — or the refusal with
its estimate, :mod:`lmidsl.theorem.budget`).
"""
from __future__ import annotations

import argparse
import statistics
import time

import cvxpy as cp
import numpy as np

from lmidsl.pipeline import make_instance
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.theorem.registry import get_theorem

MARGIN = 1e-7


def random_mjls(N: int, n: int, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    modes = []
    for _ in range(N):
        modes.append({"A": (0.5 * rng.standard_normal((n, n))).tolist(), "B1": rng.standard_normal((n, 1)).tolist(),
                      "B2": rng.standard_normal((n, 1)).tolist(),
                      "C1": np.vstack([np.eye(1, n), np.zeros((1, n))]).tolist(),
                      "D11": [[0.0], [0.0]], "D12": [[0.0], [1.0]]})
    Pi = rng.random((N, N))
    np.fill_diagonal(Pi, 0.0)
    np.fill_diagonal(Pi, -Pi.sum(axis=1))
    return {"modes": modes, "Pi": Pi.tolist()}


def hand_written(data: dict) -> cp.Problem:
    """The LMIs of mjls_hinf_sf_ct typed by hand."""
    modes, Pi = data["modes"], np.array(data["Pi"])
    N = len(modes)
    n = len(modes[0]["A"])
    Y = [cp.Variable((n, n), symmetric=True) for _ in range(N)]
    W = [cp.Variable((1, n)) for _ in range(N)]
    g = cp.Variable()
    cons = []
    for i, md in enumerate(modes):
        A, B1, B2, C1, D11, D12 = (np.array(md[k]) for k in ("A", "B1", "B2", "C1", "D11", "D12"))
        AY = A @ Y[i] + B2 @ W[i]
        others = [j for j in range(N) if j != i]
        col = cp.vstack([np.sqrt(Pi[i, j]) * Y[i] for j in others])
        p1, m1 = C1.shape[0], B1.shape[1]
        top = cp.bmat([
            [AY + AY.T + Pi[i, i] * Y[i], B1, (C1 @ Y[i] + D12 @ W[i]).T],
            [B1.T, -g * np.eye(m1), D11.T],
            [C1 @ Y[i] + D12 @ W[i], D11, -g * np.eye(p1)],
        ])
        k = (N - 1) * n
        diag = cp.bmat([[(-Y[j] if a == b else np.zeros((n, n))) for b, j in enumerate(others)]
                        for a, _ in enumerate(others)])
        left = cp.vstack([col.T, np.zeros((m1 + p1, k))]).T if False else cp.hstack(
            [col, np.zeros((k, m1 + p1))])
        M = cp.bmat([[top, left.T], [left, diag]])
        size = n + m1 + p1 + k
        cons.append(M << -MARGIN * np.eye(size))
        cons.append(Y[i] >> MARGIN * np.eye(n))
    return cp.Problem(cp.Minimize(g), cons)


def timed_interleaved(fns, repeat: int) -> list[float]:
    samples = [[] for _ in fns]
    for _ in range(repeat):
        for k, fn in enumerate(fns):
            t0 = time.process_time()
            fn()
            samples[k].append(time.process_time() - t0)
    return [statistics.median(s) for s in samples]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modes", type=int, default=10)
    ap.add_argument("--n", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--solve-check", action="store_true")
    ap.add_argument("--end-to-end", metavar="N,N,...",
                    help="instead: lmidsl.solve of textbook.mjls_sf_ct with these numbers of modes (n = --n), "
                         "each in a child process bounded by --timeout: wall, CPU, peak memory, the times record "
                         "(or the refusal with its estimate)")
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args(argv)
    if args.end_to_end:
        import end_to_end
        print(end_to_end.load())
        for N in (int(k) for k in args.end_to_end.split(",")):
            data = random_mjls(N, args.n)
            data = {"modes": [{"A": m["A"], "B": m["B2"]} for m in data["modes"]], "Pi": data["Pi"]}
            print(end_to_end.line(f"mjls_sf_ct N={N}, n={args.n}",
                                  end_to_end.run("textbook.mjls_sf_ct", data, timeout=args.timeout)), flush=True)
        return 0
    thm = get_theorem("textbook.mjls_hinf_sf_ct")
    data = random_mjls(args.modes, args.n)

    t0 = time.process_time()
    inst = make_instance(thm, None, data, None)
    DirectModel(inst)
    first = time.process_time() - t0

    def direct():
        DirectModel(make_instance(thm, None, data, None))

    def cvxpy_backend():
        CvxpyModel(make_instance(thm, None, data, None)).problem.get_problem_data(cp.CLARABEL)

    def hand():
        hand_written(data).get_problem_data(cp.CLARABEL)

    t_direct, t_cvxpy, t_hand = timed_interleaved([direct, cvxpy_backend, hand], args.repeat)
    print(f"{args.modes} modes, n = {args.n}: {len(inst.theorem.lmis)} LMIs instantiated from one statement")
    print(f"{'first [s]':>10} {'direct [s]':>11} {'cvxpy be. [s]':>14} {'hand [s]':>9} "
          f"{'direct/hand':>12} {'cvxpy be./hand':>15} {'first/hand':>11}")
    print(f"{first:10.4f} {t_direct:11.4f} {t_cvxpy:14.4f} {t_hand:9.4f} {t_direct / t_hand:12.2f} "
          f"{t_cvxpy / t_hand:15.2f} {first / t_hand:11.2f}")
    print(f"ratio direct/hand {t_direct / t_hand:.2f}, cvxpy backend/hand {t_cvxpy / t_hand:.2f} (target ≤ 2)")
    if args.solve_check:
        import lmidsl
        sol = lmidsl.solve(thm, data=data, backoff=None)
        prob = hand_written(data)
        prob.solve(solver=cp.CLARABEL)
        print(f"gamma lmidsl {sol.gamma:.6f}, hand-written cvxpy {prob.value:.6f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
