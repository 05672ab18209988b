"""Seed 002 (Zhang/Liu/Du 2023): every number of docs/reproductions/002.md and its figures.

    python scripts/reproduce_002.py [--quick]     # writes docs/reproductions/002_results.json,
                                                  # docs/figures/002_fig3_gamma_vs_N, 002_sim (.png, .pdf)
"""
from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
warnings.filterwarnings("ignore")

from lmidsl.pipeline import make_instance, solve_instance  # noqa: E402
from lmidsl.studies.bmi import successive_lmi  # noqa: E402
from lmidsl.theorems.zhang_quantized_loss.delta import balanced_realisation, filter_reading  # noqa: E402
from lmidsl.theorems.zhang_quantized_loss.netsim import empirical_gain, simulate  # noqa: E402
from lmidsl.theorems.zhang_quantized_loss.quantizer import LogQuantizer  # noqa: E402

Z = "zhang_quantized_loss"
H, RHO, CHI0 = 1e-4, 0.75, 1.3
Q = LogQuantizer(RHO, CHI0)
SETS = {"paper (+β)": [1], "robust (±β)": [-1, 1]}
GAIN_STEPS = 60000  # 6 s of plant time: covers the slow plant modes


def module():
    import importlib
    return importlib.import_module(f"lmidsl.theorems.{Z}.theorems")


def _thm1(filt, N, ab, points):
    inst = make_instance(f"{Z}.thm1", example="paper-N2-printed",
                         overrides={**{k: np.asarray(v).tolist() for k, v in filt.items()},
                                    "N": N, "alpha_bar": ab, "Delta": points})
    sol = solve_instance(inst, certify=False)
    return sol.status, sol.gamma if sol.ok else None, sol.worst_eig


def analyse(filt, N, ab, points):
    """thm1 on a fixed delta-form filter, as given and in a balanced realisation; the lowest γ
    whose point satisfies every LMI (numpy max eigenvalue < 0) is the certificate."""
    tries = {"as recovered": _thm1(filt, N, ab, points)}
    try:
        A, B, C, _ = balanced_realisation(filt["Af"], filt["Bf"], filt["Cf"], H)
        tries["balanced"] = _thm1({"Af": A, "Bf": B, "Cf": C}, N, ab, points)
    except ValueError:
        pass  # not stable in the delta sense
    good = [(g, k) for k, (st, g, we) in tries.items() if g is not None and we is not None and we < 0]
    best = min(good) if good else None
    return {"tries": {k: {"status": st, "gamma": g, "worst_eig": we} for k, (st, g, we) in tries.items()},
            "certified_gamma": best[0] if best else None, "certified_by": best[1] if best else None}


def sim_row(filt, N, ab, seed=1):
    r = simulate(M.PLANT, filt, H, N, ab, steps=100, x0=[-4, -5], quantizer=Q, seed=seed)
    g = empirical_gain(M.PLANT, filt, H, N, ab, steps=GAIN_STEPS, runs=3, quantizer=Q, seed=seed)
    g_beta = empirical_gain(M.PLANT, filt, H, N, ab, steps=GAIN_STEPS, runs=3, delta=1 / 7, seed=seed)
    return {"empirical_gain_fixed_plus_beta": g_beta, "e0": float(r.e[0, 0]), "e30": float(r.e[30, 0]), "e99": float(r.e[99, 0]),
            "zf99": float(r.zf[99, 0]), "z99": float(r.z[99, 0]), "empirical_gain": g}


def printed_filters():
    rows = []
    for N, row in M.TABLE1.items():
        for reading in ("delta", "shift"):
            f = filter_reading(row, reading, H)
            eig = np.abs(np.linalg.eigvals(np.eye(2) + H * f["Af"])).max()
            out = {"N": N, "alpha_bar": row["alpha_bar"], "reading": reading, "printed_gamma": row["gamma"],
                   "max_abs_eig_I_plus_hAf": float(eig)}
            for label, pts in SETS.items():
                out[label] = analyse(f, N, row["alpha_bar"], pts)
            out["sim"] = sim_row(f, N, row["alpha_bar"])
            rows.append(out)
            print(json.dumps(out), flush=True)
    return rows


def route(name, N, ab, points, starts=None):
    """Best γ of one synthesis route; recovered filter certified by thm1 and simulated."""
    t0 = time.perf_counter()
    overrides = {"N": N, "alpha_bar": ab, "Delta": points}
    if name == "exact":
        inst = make_instance(f"{Z}.exact", example="paper-N2", overrides=overrides)
        sol = solve_instance(inst, certify=False)
        history = [sol.gamma]
        stop = sol.status
    else:
        inst = make_instance(f"{Z}.{name}", example="paper-N2", overrides=overrides)
        res = successive_lmi(inst, starts=starts, max_iter=40, rtol=1e-4, certify=False,
                             desc=f"{name} N={N} {points}")
        sol, history, stop = res.best, res.gammas, res.stop_reason
    out = {"route": name, "N": N, "alpha_bar": ab, "points": points, "stop": stop,
           "history": history, "seconds": time.perf_counter() - t0}
    if sol is None or not sol.ok:
        out.update(gamma=None)
        return out
    out["gamma"] = sol.gamma
    out["filter"] = {k: v.tolist() for k, v in sol.recovered.items()}
    out["cond"] = [i["cond"] for i in sol.inverted]
    out["thm1"] = analyse(sol.recovered, N, ab, points)
    out["sim"] = sim_row(sol.recovered, N, ab)
    return out


def figures(results):
    """The two figures of seed 002, drawn by scripts/make_figures.py (PNG and PDF)."""
    from make_figures import FIGURES, fig_002
    fig_002(FIGURES, results)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true", help="N = 1..2 only")
    p.add_argument("--figures-only", action="store_true")
    args = p.parse_args()
    out_path = ROOT / "docs" / "reproductions" / "002_results.json"
    if args.figures_only:
        figures(json.loads(out_path.read_text()))
        return
    results = {"printed": printed_filters(), "routes": []}
    I2 = np.eye(2)
    starts = [{"Sbar": I2, "P3bar": 1e2 * I2}, {"Sbar": 10 * I2, "P3bar": 1e2 * I2}]
    cases = [(N, 0.5) for N in (range(1, 3) if args.quick else range(1, 6))] + [(3, 0.2)]
    for N, ab in cases:
        for pts in SETS.values():
            for name in ("exact", "thm2"):
                r = route(name, N, ab, pts, starts=starts)
                results["routes"].append(r)
                print(json.dumps({k: v for k, v in r.items() if k not in ("history", "filter")}), flush=True)
    lit = route("thm2_literal", 2, 0.5, [-1, 1], starts=starts)
    results["routes"].append(lit)
    print(json.dumps({k: v for k, v in lit.items() if k != "filter"}), flush=True)
    out_path.write_text(json.dumps(results, indent=1))
    figures(results)


M = module()
if __name__ == "__main__":
    main()
