"""HPPD robust stability on generated polytopes, checked against a grid of the simplex.

For each (time domain, n, N vertices, seed): ``spread_polytope`` of theorems/textbook/hpd.py,
vertices Aᵢ(t) = A_c + tXᵢ shifted (continuous: spectral abscissa −1) or scaled (discrete:
spectral radius 0.95), so that every vertex is stable for every t while the vertices move apart
as t grows.  The grid of the simplex
(lmidsl.certify.simplex_grid: eigenvalues at every grid point, refined; independent of the
LMIs) gives t*, where an unstable point first appears (bisection).  Two polytopes per case:

* "stable": t = 0.97 t* and t = 0.995 t*, robustly stable by the grid;
* "interior-unstable": t = 1.03 t*, stable vertices and an unstable point inside (the grid's).

Each is solved by textbook.hpd_stability_ct/dt for (g, d) in DEGREES; a certificate (every LMI
proved at the returned point) on a polytope the grid finds unstable is a wrong verdict.
Prints the table of certified fractions; ``--json PATH`` writes the raw rows.

Usage: python benchmarks/stress/hppd_study.py [--seeds 4] [--json out.json]
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
from theorems.textbook.hpd import hpd_stability_ct, hpd_stability_dt, spread_polytope  # noqa: E402

DEGREES = ((0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (3, 0), (3, 1))
CASES = [(n, N) for n in (2, 3, 4, 6) for N in (2, 3, 4)]


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
    sol = solve_instance(inst, certify=False, diagnose=False)
    return bool(sol.verdict()[0])


def run(seeds: int, resolution: int = 16) -> list:
    rows = []
    for time_ in ("continuous", "discrete"):
        theorem = hpd_stability_ct if time_ == "continuous" else hpd_stability_dt
        for n, N in CASES:
            for seed in range(seeds):
                case = (1000 * n + 100 * N + seed, n, N, time_)
                t_star = grid_threshold(case, resolution)
                if t_star is None:
                    continue
                for kind, factor in (("stable", 0.97), ("stable", 0.995), ("interior-unstable", 1.03)):
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
                    print(json.dumps({k: row[k] for k in ("time", "n", "N", "seed", "kind", "grid_worst")}),
                          row["certified"], flush=True)
    return rows


def table(rows: list) -> str:
    lines = ["| time | polytopes | kind (t/t*) | " + " | ".join(f"g={g}, d={d}" for g, d in DEGREES) + " |",
             "|---|---|---|" + "---|" * len(DEGREES)]
    for time_ in ("continuous", "discrete"):
        for kind, factor in (("stable", 0.97), ("stable", 0.995), ("interior-unstable", 1.03)):
            sel = [r for r in rows if r["time"] == time_ and r["kind"] == kind and r["factor"] == factor]
            if not sel:
                continue
            cells = [f"{sum(r['certified'][f'{g},{d}'] for r in sel)}/{len(sel)}" for g, d in DEGREES]
            lines.append(f"| {time_} | {len(sel)} | {kind} ({factor}) | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    rows = run(args.seeds)
    wrong = [r for r in rows if r["kind"] == "interior-unstable" and any(r["certified"].values())]
    print(table(rows))
    print(f"wrong verdicts (an unstable polytope certified): {len(wrong)}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
