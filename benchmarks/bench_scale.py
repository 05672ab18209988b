"""Scale: lmidsl's proved bracket against the cvxpy + Clarabel script a user writes by hand.

For each state dimension n (default 8, 16, 24, 32, 48, 64) and two problems,

* ``brl``: the H∞ norm of a random stable plant (n states, 2 inputs, 2 outputs;
  ``benchmarks/stress/cases.py``'s "random" family, seed n) by the bounded real lemma,
  ``lmidsl solve textbook.brl_ct --data plant.json``;
* ``sf``: H∞ state feedback of a random plant (``cases.plant``, seed n: A with standard normal
  entries, one actuator — very unstable, optimal levels up to 3e5, on which Clarabel fails),
  ``lmidsl solve textbook.hinf_sf_ct --data plant.json``;
* ``sf_mild``: the same on a milder random plant (:func:`mild_plant`: A = N/√n − 0.3 I, a few
  unstable modes, two actuators, two disturbances; Clarabel's optimum is inaccurate, Y near
  singular);
* ``sf_dt``: the same in discrete time (:func:`mild_discrete_plant`, spectral radius 1.05),
  ``lmidsl solve textbook.hinf_sf_dt``;

the command and a hand-written script (:data:`HAND`: the same LMIs in cvxpy, solved by Clarabel,
no certificate, no bound) run as fresh processes, interleaved, in the same run, after one untimed
``lmidsl solve`` per theorem (bytecode and the built theorem cached, as on a user's second run).  Printed per row:
the wall-time ratio lmidsl / hand script, the proved bracket [lower, upper] on γ and its relative
width (upper − lower)/upper (``-`` when the lower end is not proved), the share of lmidsl's wall
time spent proving (point proofs, analysis, the lower bound's wait, from the ``times`` record),
the part of the wall time the ``times`` record does not account for, and an independent γ
(SLICOT AB13DD's H∞ norm for the BRL; for state feedback the closed-loop norm of the
full-information Riccati gain at the least γ, found by bisection, where the Riccati equation has a
stabilising solution — an achieved level, so the optimum is at most it; AB13DD's value or, when
larger, σ_max of the loop's response at 60 digits (:func:`precise_gain`; in discrete time AB13DD's
value alone)) against which the proved lower end is checked.

    python benchmarks/bench_scale.py [--sizes 8 16] [--problems brl sf] [--timeout 600]

The machine this runs on may be shared: only the ratios measured in one run mean anything.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "stress"))
from cases import lists, plant, system  # noqa: E402
from lmidsl.pipeline import TIME_PARTS  # noqa: E402

THEOREMS = {"brl": "textbook.brl_ct", "sf": "textbook.hinf_sf_ct", "sf_mild": "textbook.hinf_sf_ct",
            "sf_dt": "textbook.hinf_sf_dt"}
#: the problems in discrete time (the others are continuous)
DISCRETE = {"sf_dt"}

#: the hand-written scripts: read the plant, build the LMIs in cvxpy, solve with Clarabel, print γ
HAND = {
    "brl": r'''
import json, sys
import cvxpy as cp, numpy as np
d = {k: np.array(v) for k, v in json.load(open(sys.argv[1])).items()}
A, B, C, D = d["A"], d["B"], d["C"], d["D"]
n, m, p = A.shape[0], B.shape[1], C.shape[0]
P = cp.Variable((n, n), symmetric=True); g = cp.Variable()
N = cp.bmat([[A.T @ P + P @ A, P @ B, C.T], [B.T @ P, -g * np.eye(m), D.T], [C, D, -np.eye(p)]])
eps = 1e-7
cons = [N << -eps * np.eye(n + m + p), P >> eps * np.eye(n)]
cp.Problem(cp.Minimize(g), cons).solve(solver=cp.CLARABEL)
print(float(np.sqrt(g.value)))
''',
    "sf": r'''
import json, sys
import cvxpy as cp, numpy as np
d = {k: np.array(v) for k, v in json.load(open(sys.argv[1])).items()}
A, B1, B2, C1, D11, D12 = (d[k] for k in ("A", "B1", "B2", "C1", "D11", "D12"))
n, m1, p1 = A.shape[0], B1.shape[1], C1.shape[0]
Y = cp.Variable((n, n), symmetric=True); W = cp.Variable((B2.shape[1], n)); g = cp.Variable()
AY = A @ Y + B2 @ W
N = cp.bmat([[AY + AY.T, B1, (C1 @ Y + D12 @ W).T], [B1.T, -g * np.eye(m1), D11.T],
             [C1 @ Y + D12 @ W, D11, -g * np.eye(p1)]])
eps = 1e-7
cons = [N << -eps * np.eye(n + m1 + p1), Y >> eps * np.eye(n)]
cp.Problem(cp.Minimize(g), cons).solve(solver=cp.CLARABEL)
K = W.value @ np.linalg.inv(Y.value)
print(float(g.value))
''',
    "sf_dt": r'''
import json, sys
import cvxpy as cp, numpy as np
d = {k: np.array(v) for k, v in json.load(open(sys.argv[1])).items()}
A, B1, B2, C1, D11, D12 = (d[k] for k in ("A", "B1", "B2", "C1", "D11", "D12"))
n, m1, p1 = A.shape[0], B1.shape[1], C1.shape[0]
Y = cp.Variable((n, n), symmetric=True); W = cp.Variable((B2.shape[1], n)); g = cp.Variable()
AY, CY = A @ Y + B2 @ W, C1 @ Y + D12 @ W
N = cp.bmat([[-Y, AY, B1, np.zeros((n, p1))], [AY.T, -Y, np.zeros((n, m1)), CY.T],
             [B1.T, np.zeros((m1, n)), -g * np.eye(m1), D11.T], [np.zeros((p1, n)), CY, D11, -g * np.eye(p1)]])
eps = 1e-7
cons = [N << -eps * np.eye(2 * n + m1 + p1), Y >> eps * np.eye(n)]
cp.Problem(cp.Minimize(g), cons).solve(solver=cp.CLARABEL)
print(float(g.value))
''',
}

#: entries of the ``times`` record that are the proofs' cost (on the main thread or waited for)
PROVING = ("point_proof", "optimum_point_proof", "analysis", "optimum_analysis", "lower_bound_wait",
           "infeasibility_proof")
#: entries that partition the wall time of ``lmidsl solve`` (the others overlap them)
#: (lmidsl.pipeline.TIME_PARTS: the entries after start-up that partition the wall time)
PARTS = ("startup", *TIME_PARTS)


def mild_plant(n: int) -> dict:
    """A state-feedback plant with A = N/√n − 0.3 I (N standard normal, seed 100 + n), B1, B2 of
    two columns, C1 = [N; 0], D12 = [0; I]."""
    rng = np.random.default_rng(100 + n)
    return {"A": rng.standard_normal((n, n)) / np.sqrt(n) - 0.3 * np.eye(n),
            "B1": rng.standard_normal((n, 2)), "B2": rng.standard_normal((n, 2)),
            "C1": np.vstack([rng.standard_normal((2, n)), np.zeros((2, n))]), "D11": np.zeros((4, 2)),
            "D12": np.vstack([np.zeros((2, 2)), np.eye(2)])}


def mild_discrete_plant(n: int) -> dict:
    """:func:`mild_plant` in discrete time: A = N/√n scaled to spectral radius 1.05 (seed 200 + n)."""
    rng = np.random.default_rng(200 + n)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    return {"A": A * (1.05 / max(abs(np.linalg.eigvals(A)))),
            "B1": rng.standard_normal((n, 2)), "B2": rng.standard_normal((n, 2)),
            "C1": np.vstack([rng.standard_normal((2, n)), np.zeros((2, n))]), "D11": np.zeros((4, 2)),
            "D12": np.vstack([np.zeros((2, 2)), np.eye(2)])}


def plant_data(problem: str, n: int) -> dict:
    if problem == "brl":
        return lists(system("random", n, "continuous", n=n, m=2, p=2))
    if problem == "sf_mild":
        return lists(mild_plant(n))
    if problem == "sf_dt":
        return lists(mild_discrete_plant(n))
    return lists(plant(n, "continuous", n=n))


def reference(problem: str, data: dict) -> float | None:
    """An independent γ: AB13DD's H∞ norm (BRL); the full-information Riccati gain's closed-loop
    norm at the bisected least level (state feedback)."""
    d = {k: np.atleast_2d(np.asarray(v, dtype=float)) for k, v in data.items()}
    if problem == "brl":
        from lmidsl.numeric.systems import hinf_norm
        return hinf_norm(d["A"], d["B"], d["C"], d["D"], "continuous")
    from lmidsl.numeric.riccati import full_information_gain
    from lmidsl.numeric.systems import hinf_norm
    A, B1, B2, C1, D11, D12 = (d[k] for k in ("A", "B1", "B2", "C1", "D11", "D12"))
    time = "discrete" if problem in DISCRETE else "continuous"
    best = [np.inf, None]

    def achieved(gamma):
        K = full_information_gain(A, B1, B2, C1, D11, D12, gamma, time)
        if K is None:
            return None
        K = np.atleast_2d(K)
        value = hinf_norm(A + B2 @ K, B1, C1 + D12 @ K, D11, time)
        if value < best[0]:
            best[:] = [value, K]
        return value

    lo, hi = 1e-6, 1.0
    while achieved(hi) is None or not np.isfinite(achieved(hi)):
        lo, hi = hi, hi * 4
        if hi > 1e12:
            return None
    for _ in range(60):
        mid = (lo + hi) / 2
        if achieved(mid) is not None and np.isfinite(achieved(mid)):
            hi = mid
        else:
            lo = mid
    if not np.isfinite(best[0]):
        return None
    K = best[1]
    if time == "discrete":
        return best[0]            # AB13DD's norm (precise_gain evaluates on the imaginary axis)
    return max(best[0], precise_gain(A + B2 @ K, B1, C1 + D12 @ K, D11))


def precise_gain(A, B, C, D, digits: int = 60) -> float:
    """max σ_max(G(jω)) over ω = 0 and AB13DD's peak, G evaluated at ``digits`` digits (mpmath)
    from the doubles as given: a lower bound on ‖G‖∞ that rounding cannot spoil.  Near the
    optimum the Riccati gains are large (closed-loop eigenvalues to −2e7) and AB13DD's norm can be
    low by 5e-6 relative (8 states, `sf_mild`: 9.1825636 where σ_max(G(0)) = 9.1826129)."""
    import mpmath as mp
    from lmidsl.numeric.systems import hinf_peak
    _, peak = hinf_peak(A, B, C, D, "continuous")
    n = A.shape[0]
    best = 0.0
    with mp.workdps(digits):
        Am, Bm, Cm, Dm = (mp.matrix(M.tolist()) for M in (A, B, C, D))
        for w in {0.0, float(peak) if np.isfinite(peak) else 0.0}:
            M = mp.mpc(0, w) * mp.eye(n) - Am
            X = mp.matrix(n, Bm.cols)
            for j in range(Bm.cols):
                col = mp.lu_solve(M, Bm.column(j))
                for i in range(n):
                    X[i, j] = col[i]
            G = Cm * X + Dm
            Gd = np.array([[complex(G[i, j]) for j in range(G.cols)] for i in range(G.rows)])
            best = max(best, float(np.linalg.svd(Gd, compute_uv=False)[0]))
    return best


def run(argv, timeout) -> tuple[float, subprocess.CompletedProcess | None]:
    t0 = time.perf_counter()
    try:
        out = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return time.perf_counter() - t0, None
    return time.perf_counter() - t0, out


def one(problem: str, n: int, where: str, timeout: float) -> dict:
    data = plant_data(problem, n)
    path = os.path.join(where, f"{problem}{n}.json")
    with open(path, "w") as f:
        json.dump(data, f)
    hand_path = os.path.join(where, f"hand_{problem}.py")
    with open(hand_path, "w") as f:
        f.write(HAND[problem if problem in HAND else "sf"])
    hand_wall, hand = run([sys.executable, hand_path, path], timeout)
    wall, out = run([sys.executable, "-m", "lmidsl", "solve", THEOREMS[problem], "--data", path, "--json"], timeout)
    row = {"problem": problem, "n": n, "wall": wall, "hand": hand_wall, "ratio": wall / hand_wall,
           "hand_gamma": float(hand.stdout.split()[-1]) if hand is not None and hand.stdout.strip() else None}
    if row["hand_gamma"] is None:      # the hand script gives the user no γ: its time is not a reference
        row["hand_error"] = "timeout" if hand is None else (hand.stderr.strip().splitlines() or ["no output"])[-1]
    if out is None or not out.stdout.strip():
        row["error"] = "timeout" if out is None else (out.stderr.strip().splitlines() or ["no output"])[-1]
        return row
    sol = json.loads(out.stdout)
    b = sol.get("bounds") or {}
    times = sol.get("times") or {}
    lower, upper = b.get("lower"), b.get("upper")
    row.update(lower=lower if b.get("lower_proved") else None, upper=upper, why=b.get("why"),
               proving=sum(times.get(k, 0.0) for k in PROVING) / wall,
               unaccounted=(wall - sum(times.get(k, 0.0) for k in PARTS)) / wall, times=times)
    if row["lower"] is not None and upper:
        row["width"] = (upper - row["lower"]) / upper
    row["reference"] = reference(problem, data)
    if row["reference"] is not None and row["lower"] is not None:
        row["lower_ok"] = row["lower"] <= row["reference"] * (1 + 1e-9)
    return row


def show(row: dict) -> str:
    f = lambda x, fmt: "-" if x is None else format(x, fmt)   # noqa: E731
    if "error" in row:
        return f"{row['problem']:4} {row['n']:3d}  lmidsl {row['wall']:7.1f} s  hand {row['hand']:6.1f} s  {row['error']}"
    return (f"{row['problem']:4} {row['n']:3d}  {row['ratio']:5.2f}x  (lmidsl {row['wall']:6.1f} s, hand {row['hand']:6.1f} s)  "
            f"[{f(row['lower'], '.8g')}, {f(row['upper'], '.8g')}] width {f(row.get('width'), '.1e')}  "
            f"proving {row['proving']:.0%}  unaccounted {row['unaccounted']:.0%}  "
            f"reference {f(row['reference'], '.8g')}" + ("" if row.get("lower_ok", True) else "  LOWER ABOVE REFERENCE")
            + (f"\n          the hand script gave no γ ({row['hand_error'][:80]}): the ratio is against a failure"
               if "hand_error" in row else "")
            + ("" if row["lower"] is not None else f"\n          lower not proved: {row['why']}"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 24, 32, 48, 64])
    ap.add_argument("--problems", nargs="+", default=["brl", "sf"], choices=sorted(THEOREMS))
    ap.add_argument("--timeout", type=float, default=600.0)
    ap.add_argument("--json", help="also write the rows to this file")
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as where:
        for problem in args.problems:      # untimed: bytecode and the built theorem cached, as a user's second run
            run([sys.executable, "-m", "lmidsl", "solve", THEOREMS[problem], "--no-certify", "--no-bounds"], args.timeout)
        for n in args.sizes:
            for problem in args.problems:
                row = one(problem, n, where, args.timeout)
                rows.append(row)
                print(show(row), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1, default=str)
    bad = [r for r in rows if r.get("lower_ok") is False]
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
