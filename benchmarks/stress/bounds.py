"""The proved lower end on a stress set: how often it exists, how wide the bracket is, and whether
every proved end is below an independent optimum.

Cases: the design stress set's bounded-real analyses (``designs.cases()``, truth = the H∞ norm by
SLICOT AB13DD) and its H∞ state-feedback syntheses (truth = the best level the full-information
Riccati bisection achieves: an upper bound on the optimum), and random stable plants
(``cases.system("random", seed, ...)``, n = 8, 12, 16, 24, 32, both time domains; truth = AB13DD).  Each
is solved as a user solves it (``lmidsl.solve``: the verdict's bracket, every route of the lower
end) or, with ``--route dual``, on the direct backend as the pipeline compiles it (declared
scalings applied) and bounded by :func:`lmidsl.certify.dual_bound.lower_bound` alone.  Printed: per
case the proved lower γ, the upper γ, the relative width (upper − lower)/upper, and "FALSE" if a
proved lower end exceeds the truth; then the share proved, the median and worst width over the
proved ones.

    python benchmarks/stress/bounds.py [--budget 600] [--json FILE] [--only brl|sf|random] [--route dual]

Runs against whichever ``lmidsl`` is importable (``PYTHONPATH=.../src`` for another checkout).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from cases import lists, system  # noqa: E402
from designs import cases as design_cases, linf  # noqa: E402

RANDOM = [(n, seed, t) for n in (8, 12, 16, 24, 32) for seed in (1, 2) for t in ("continuous", "discrete")]


def solve_and_bracket(theorem: str, data: dict):
    """(the certified upper end of γ, the proved lower end or None, why none) as a user gets them:
    ``lmidsl.solve`` (every route: the frequency response first where the theorem's LMI is its
    declared bounded-real form, then the duals) and its verdict's bracket."""
    import lmidsl
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = lmidsl.solve(theorem, data=lists(data))
    box = sol.verdict.bracket or {}
    upper = box.get("upper") if box.get("upper_proved") else None
    lower = box.get("lower") if box.get("lower_proved") else None
    method = getattr(sol.bounds, "method", "")
    return upper, lower, (box.get("why") or "") + (f" [{method}]" if method else "")


def solve_and_bound(theorem: str, data: dict):
    """(γ at the SDP optimum, DualBound) on the direct backend, as the pipeline compiles it."""
    from lmidsl.certify.dual_bound import lower_bound, performance_bound
    from lmidsl.numeric.scaling import apply_scaling
    from lmidsl.pipeline import make_instance
    from lmidsl.solver.backends.direct_backend import DirectModel
    from lmidsl.solver.margin import solve_model
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        instance = make_instance(theorem, None, lists(data))
    model = DirectModel(apply_scaling(instance, "auto").scaled)
    sol = solve_model(model)
    bound = lower_bound(model, sol)
    found = None if sol.objective is None else \
        performance_bound(model.instance.theorem, dict(model.instance.params), sol.objective)
    return (None if found is None else found[0]), bound


def all_cases(only: str | None) -> list[dict]:
    out = []
    if only in (None, "brl", "sf"):
        for c in design_cases():
            th, kind = c["theorem"], c["truth"]["kind"]
            if kind not in ("norm", "design"):
                continue                             # (infeasible plants: the other proof's set)
            if th.startswith("textbook.brl_") and only in (None, "brl"):
                out.append(dict(name=c["name"], theorem=th, data=c["data"], truth=c["truth"]["value"]))
            elif th.startswith("textbook.hinf_sf_") and only in (None, "sf"):
                out.append(dict(name=c["name"], theorem=th, data=c["data"], truth=c["truth"]["optimum"]))
    if only in (None, "random"):
        for n, seed, t in RANDOM:
            d = system("random", seed, t, n=n, m=2, p=2)
            out.append(dict(name=f"random/{t[:2]}-n{n}-s{seed}", theorem=f"textbook.brl_{t[0]}t", data=d,
                            truth=linf(*(np.asarray(d[k], dtype=float) for k in "ABCD"), t)))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=float, default=600.0, help="seconds for the whole set")
    parser.add_argument("--only", choices=["brl", "sf", "random"])
    parser.add_argument("--json")
    parser.add_argument("--route", choices=["pipeline", "dual"], default="pipeline",
                        help="pipeline: lmidsl.solve's bracket (every route); dual: the dual route alone")
    args = parser.parse_args(argv)
    end = time.monotonic() + args.budget
    rows = []
    for case in all_cases(args.only):
        if time.monotonic() > end:
            print(f"{case['name']}: skipped (budget)")
            continue
        t0 = time.perf_counter()
        try:
            if args.route == "dual":
                gamma, bound = solve_and_bound(case["theorem"], case["data"])
                low, why = (bound.lower_performance if bound.proved else None), bound.why
            else:
                gamma, low, why = solve_and_bracket(case["theorem"], case["data"])
        except Exception as exc:                      # a stress run reports and goes on
            print(f"{case['name']}: error {type(exc).__name__}: {exc}")
            continue
        width = (gamma - low) / gamma if low is not None and gamma else None
        false = bool(low is not None and low > case["truth"] * (1 + 1e-9))
        rows.append(dict(name=case["name"], gamma=gamma, lower=low, width=width, truth=case["truth"],
                         false=false, seconds=time.perf_counter() - t0, why=why))
        print(f"{case['name']:32s} γ={gamma if gamma is None else f'{gamma:.9g}'} lower={low if low is None else f'{low:.9g}'} "
              f"width={'-' if width is None else f'{width:.2e}'} truth={case['truth']:.9g} "
              f"{'FALSE' if false else 'ok'} {rows[-1]['seconds']:.1f}s {'' if low else why[:90]}", flush=True)
    proved = [r for r in rows if r["lower"] is not None]
    widths = sorted(r["width"] for r in proved)
    print(f"proved {len(proved)}/{len(rows)}; median width "
          f"{'-' if not widths else f'{widths[len(widths) // 2]:.2e}'}; worst "
          f"{'-' if not widths else f'{widths[-1]:.2e}'}; false proofs {sum(r['false'] for r in rows)}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 1 if any(r["false"] for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
