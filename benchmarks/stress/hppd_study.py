"""HPPD robust stability on generated polytopes, checked against a grid of the simplex.

For each (time domain, n, N vertices, seed): ``spread_polytope`` of theorems/textbook/hpd.py,
vertices Aᵢ(t) = A_c + tXᵢ shifted (continuous: spectral abscissa −1) or scaled (discrete:
spectral radius 0.95), so that every vertex is stable for every t while the vertices move apart
as t grows.  The grid of the simplex
(lmidsl.certify.simplex_grid: eigenvalues at every grid point, refined; independent of the
LMIs) gives t*, where an unstable point first appears (bisection).  Two polytopes per case:

* "stable": t = 0.5, 0.7, 0.85, 0.97 t*, robustly stable by the grid;
* "interior-unstable": t = 1.03 t*, stable vertices and an unstable point inside (the grid's).

Each is solved by textbook.hpd_stability_ct/dt for (g, d) in DEGREES; a certificate (every LMI
proved at the returned point) on a polytope the grid finds unstable is a wrong verdict.
Prints the table of certified fractions; ``--json PATH`` writes the raw rows.

``margins``: for A₀ + ρΔA(α) (textbook.hpd_margin_ct/dt; A₀ the mean of vertices with an
unstable interior point), the largest ρ certified per (g, d) by
lmidsl's bisection, divided by the grid's margin ρ* (an upper bound of the true margin); a
certified ρ above ρ* would be a wrong verdict.

Usage: python benchmarks/stress/hppd_study.py [--seeds 4] [--json out.json]
       python benchmarks/stress/hppd_study.py margins [--seeds 2] [--json out.json]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from lmidsl.certify.simplex_grid import grid_evidence  # noqa: E402
from lmidsl.pipeline import make_instance, solve_instance  # noqa: E402
from theorems.textbook.hpd import hpd_stability_ct, hpd_stability_dt, random_polytope, spread_polytope  # noqa: E402

DEGREES = ((0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (3, 0), (3, 1))
CASES = [(2, 3), (2, 4), (3, 3), (3, 4), (4, 3), (4, 4), (6, 3)]
SOLVER = "CLARABEL"     # named: no fallback routes (a failure counts as not certified), to keep the run short
FACTORS = (("stable", 0.5), ("stable", 0.7), ("stable", 0.85), ("stable", 0.97), ("interior-unstable", 1.03))


def vertices_at(case: tuple, t: float) -> list:
    seed, n, N, time_ = case
    return spread_polytope(seed, n, N, time_, t)["vertices"]


def grid_threshold(case: tuple, resolution: int, hi: float = 1.0) -> float | None:
    """The t at which the grid first finds an unstable point (bisection, 20 steps); None when
    none up to t = 64."""
    def stable(t):
        return not grid_evidence(vertices_at(case, t), None, case[3], resolution=resolution).refutes
    lo = 0.0
    while stable(hi):
        if hi >= 64:
            return None
        lo, hi = hi, 2 * hi
    for _ in range(20):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


def certify(theorem, vertices: list, g: int, d: int) -> bool:
    inst = make_instance(theorem, data={"vertices": vertices, "degree": g, "polya": d})
    sol = solve_instance(inst, certify=False, diagnose=False, solver=SOLVER)
    return bool(sol.ok and sol.lmis_hold and sol.proved)     # every coefficient LMI proved


def run(seeds: int, resolution: int = 16, first: int = 0) -> list:
    rows = []
    for time_ in ("continuous", "discrete"):
        theorem = hpd_stability_ct if time_ == "continuous" else hpd_stability_dt
        for n, N in CASES:
            for seed in range(first, first + seeds):
                case = (1000 * n + 100 * N + seed, n, N, time_)
                t_star = grid_threshold(case, resolution)
                if t_star is None:
                    continue
                for kind, factor in FACTORS:
                    vertices = vertices_at(case, factor * t_star)
                    ev = grid_evidence(vertices, None, time_, resolution=resolution)
                    if ev.refutes != (kind == "interior-unstable"):
                        continue
                    row = {"time": time_, "n": n, "N": N, "seed": seed, "kind": kind, "t": factor * t_star, "factor": factor, "case_seed": case[0],
                           "grid_worst": ev.worst_value, "grid_alpha": ev.worst_alpha, "certified": {}}
                    t0 = time.perf_counter()
                    for g, d in DEGREES:
                        row["certified"][f"{g},{d}"] = certify(theorem, vertices, g, d)
                    row["seconds"] = time.perf_counter() - t0
                    rows.append(row)
                    print(json.dumps(row), flush=True)
    return rows


def table(rows: list) -> str:
    lines = ["| time | polytopes | kind (t/t*) | " + " | ".join(f"g={g}, d={d}" for g, d in DEGREES) + " |",
             "|---|---|---|" + "---|" * len(DEGREES)]
    for time_ in ("continuous", "discrete"):
        for kind, factor in FACTORS:
            sel = [r for r in rows if r["time"] == time_ and r["kind"] == kind and r["factor"] == factor]
            if not sel:
                continue
            cells = [f"{sum(r['certified'][f'{g},{d}'] for r in sel)}/{len(sel)}" for g, d in DEGREES]
            lines.append(f"| {time_} | {len(sel)} | {kind} ({factor}) | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    rows = run(args.seeds, first=args.first_seed)
    wrong = [r for r in rows if r["kind"] == "interior-unstable" and any(r["certified"].values())]
    print(table(rows))
    print(f"wrong verdicts (an unstable polytope certified): {len(wrong)}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))




# -- margins: the largest scaling certified per degree, against the grid's ------------------------------
MARGIN_DEGREES = ((0, 0), (1, 0), (2, 0), (2, 1), (3, 0))
TIMES = ("continuous", "discrete")
MARGIN_CASES = [(n, N) for n, N in ((2, 3), (3, 3), (3, 4), (4, 4), (6, 3))]


def margin_case(seed: int, n: int, N: int, time_: str) -> dict | None:
    """A₀ and ΔAᵢ for textbook.hpd_margin_*: the vertices Vᵢ of ``spread_polytope`` at 1.5 t*
    (stable vertices, an unstable point inside), A₀ their mean, ΔAᵢ = Vᵢ − A₀: the margin is
    set by interior points, where the degree of P(α) matters.  None when the family has no t*."""
    t_star = grid_threshold((seed, n, N, time_), 12)
    if t_star is None:
        return None
    V = [np.asarray(v["A"]) for v in spread_polytope(seed, n, N, time_, 1.5 * t_star)["vertices"]]
    A0 = sum(V) / len(V)
    return {"A0": A0.tolist(), "vertices": [{"dA": (Vi - A0).tolist()} for Vi in V]}


def grid_margin(data: dict, time_: str, resolution: int = 16, steps: int = 30) -> float:
    """The largest ρ with every grid point of A₀ + ρΔA(α) stable (bisection; an upper bound of
    the true margin up to the grid's resolution)."""
    A0 = np.asarray(data["A0"])

    def stable(rho):
        V = [{"A": A0 + rho * np.asarray(v["dA"])} for v in data["vertices"]]
        return not grid_evidence(V, None, time_, resolution=resolution).refutes
    lo, hi = 0.0, 1.0
    while stable(hi):
        lo, hi = hi, 2 * hi
    for _ in range(steps):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return hi


def run_margins(seeds: int) -> list:
    from lmidsl.studies.bisection import bisect
    rows = []
    for time_ in TIMES:
        theorem = "textbook.hpd_margin_ct" if time_ == "continuous" else "textbook.hpd_margin_dt"
        for n, N in MARGIN_CASES:
            for seed in range(seeds):
                data = margin_case(1000 * n + 100 * N + seed, n, N, time_)
                if data is None:
                    continue
                rho_star = grid_margin(data, time_)
                if rho_star < 1e-6:         # A₀ itself unstable: no margin to certify
                    continue
                row = {"time": time_, "n": n, "N": N, "seed": seed, "grid_margin": rho_star, "margins": {}}
                for g, d in MARGIN_DEGREES:
                    inst = make_instance(theorem, data={**data, "degree": g, "polya": d})
                    res = bisect(inst, lower=0.0, upper=1.5 * rho_star, tol=1e-3 * rho_star, solver=SOLVER)
                    row["margins"][f"{g},{d}"] = [res.feasible_end, res.infeasible_end]
                rows.append(row)
                print(json.dumps(row), flush=True)
    return rows


def margin_table(rows: list) -> str:
    lines = ["| time | polytopes | " + " | ".join(f"g={g}, d={d}" for g, d in MARGIN_DEGREES) + " |",
             "|---|---|" + "---|" * len(MARGIN_DEGREES)]
    for time_ in ("continuous", "discrete"):
        sel = [r for r in rows if r["time"] == time_ and r["grid_margin"] > 1e-6]
        if not sel:
            continue
        cells = []
        for g, d in MARGIN_DEGREES:
            ratios = [(r["margins"][f"{g},{d}"][0] or 0.0) / r["grid_margin"] for r in sel]
            cells.append(f"{np.mean(ratios):.3f} (min {min(ratios):.3f})")
        lines.append(f"| {time_} | {len(sel)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def margins_main():
    global TIMES
    ap = argparse.ArgumentParser(description="certified margins per degree against the grid's")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--time", choices=("continuous", "discrete"), action="append")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(sys.argv[2:])
    TIMES = tuple(args.time or TIMES)
    rows = run_margins(args.seeds)
    above = [r for r in rows for k, (f, _) in r["margins"].items() if f is not None and f > r["grid_margin"]]
    print(margin_table(rows))
    print(f"certified margins above the grid's (wrong verdicts): {len(above)}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    margins_main() if sys.argv[1:2] == ["margins"] else main()
