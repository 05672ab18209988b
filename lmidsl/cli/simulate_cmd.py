"""``lmidsl simulate``: an impulsive filter against impulse sequences and disturbances.

The theorem's instance must hold the impulsive plant (A, B, M, C, D, L1, L2, see
:mod:`lmidsl.impulsive`).  A synthesis theorem is solved first and its recovered filter is
simulated; an analysis theorem (the filter given as data) is simulated as given.  For each
impulse sequence the command prints the lifted ℓ2 gain over the horizon (the worst disturbance)
and the energy ratio ‖e‖/‖ω‖ for the chosen test disturbance.
"""
from __future__ import annotations

from ..pipeline import make_instance, solve_instance
from ..errors import InputError
from lmidsl.theorems.pan_impulsive.impulsive import (FILTER_NAMES, PLANT_NAMES, disturbance, error_system, lifted_gain,
                         parse_impulses, simulate)
from ..render.report import format_table
from .common import add_instance_arguments, instance_spec, print_json

ORDER = 40


def register(sub):
    p = sub.add_parser("simulate", help="simulate an impulsive filter (theorems with plant A, B, M, C, D, L1, L2)")
    add_instance_arguments(p)
    p.add_argument("--impulses", action="append", default=[], metavar="KIND",
                   help="none, all[:K], periodic:P, random:p, explicit:k1,k2,... (repeatable; "
                        "default: none, periodic:5, random:0.2, all)")
    p.add_argument("--horizon", type=int, default=200, help="number of samples (default 200)")
    p.add_argument("--disturbance", default="noise", help="pulse, noise, sine or step (default noise)")
    p.add_argument("--seed", type=int, default=0, help="seed of random impulses and noise")
    p.add_argument("--solver", help="solver for a synthesis theorem (default: clarabel)")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.set_defaults(run=run)


def filter_and_plants(instance, solver=None):
    """[(vertex label, matrices)] with the recovered (synthesis) or given (analysis) filter."""
    theorem = instance.theorem
    names = set(instance.data) | set(theorem.recovery)
    missing = [k for k in PLANT_NAMES + FILTER_NAMES if k not in names]
    if missing:
        raise InputError(f"{theorem.id}: not an impulsive filtering theorem (no {', '.join(missing)})")
    if theorem.recovery:
        sol = solve_instance(instance, solver=solver, certify=False)
        if not sol.ok:
            raise InputError(f"{theorem.id}: no filter to simulate (status {sol.status})")
        filt = {k: sol.recovered[k] for k in FILTER_NAMES if k in sol.recovered}
    else:
        filt = {k: instance.data[k] for k in FILTER_NAMES if k in instance.data}
    out = []
    for v in range(instance.nvertices):
        plant = {k: (instance.data[k][v] if isinstance(instance.data[k], list) else instance.data[k])
                 for k in PLANT_NAMES}
        out.append((None if instance.nvertices == 1 else v + 1, {**plant, **filt}))
    return out


def run(args):
    if args.horizon < 1:
        raise InputError("--horizon must be at least 1")
    instance = make_instance(args.theorem, **instance_spec(args))
    kinds = args.impulses or ["none", "periodic:5", "random:0.2", "all"]
    rows = []
    for vertex, matrices in filter_and_plants(instance, args.solver):
        system = error_system(matrices)
        w = disturbance(args.disturbance, args.horizon, system.ninput, seed=args.seed)
        for kind in kinds:
            E = parse_impulses(kind, args.horizon, args.seed)
            gain, _ = lifted_gain(system, E)
            ratio = simulate(system, w, E).energy_ratio
            rows.append({"vertex": vertex, "impulses": kind, "count": int(E.sum()),
                         "lifted_gain": gain, "energy_ratio": ratio})
    if args.json:
        print_json({"theorem": instance.theorem.id, "example": instance.example,
                    "horizon": args.horizon, "disturbance": args.disturbance, "rows": rows})
        return 0
    print(f"{instance.theorem.id}" + (f" [{instance.example}]" if instance.example else "")
          + f": horizon {args.horizon}, test disturbance {args.disturbance}")
    table = [[r["vertex"] or "", r["impulses"], r["count"], r["lifted_gain"], r["energy_ratio"]] for r in rows]
    print(format_table(["vertex", "impulses", "#", "worst gain (lifted)", f"‖e‖/‖ω‖ ({args.disturbance})"], table))
    print("\nworst gain: largest singular value of ω(0..N-1) -> e(0..N-1) for that impulse sequence "
          "(a lower bound of the robust H∞ level).")
    return 0
