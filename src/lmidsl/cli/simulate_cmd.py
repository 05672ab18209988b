"""``lmidsl simulate``: the theorem's own simulation of its model with the design.

A theorem declares its simulator (``Theorem.simulated_by``); this command binds the instance,
designs (solves and recovers) when the theorem is a synthesis, and prints the simulator's table:
one row per scenario the simulator runs (e.g. impulse sequences for an impulsive filter).
"""
from __future__ import annotations

from ..errors import InputError, NoResultError
from ..render.terminal import echo
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_solve_arguments, instance_spec, nonnegative_int, positive_int,
                     print_json, refuse, solve_arguments)

ORDER = 40


def register(sub):
    p = sub.add_parser("simulate", help="simulate the design with the theorem's own model")
    add_solve_arguments(p, solver_help="solver for a synthesis theorem (default: clarabel)")
    add_output_arguments(p)
    p.add_argument("--scenario", "--impulses", dest="scenario", action="append", default=[],
                   metavar="KIND", help="a scenario of the theorem's simulator (repeatable), e.g. "
                   "impulse sequences none, all[:K], periodic:P, random:p, explicit:k1,k2,...")
    p.add_argument("--horizon", type=positive_int, default=200, help="number of samples (default 200)")
    p.add_argument("--disturbance", default="noise", help="test disturbance, e.g. pulse, noise, sine, step")
    p.add_argument("--seed", type=nonnegative_int, default=0, help="seed of random scenarios and noise")
    p.set_defaults(run=run)


def run(args):
    if args.horizon < 1:
        raise InputError("--horizon must be at least 1")
    get_theorem(args.theorem)          # an unknown id is a one-line error, before the solving stack is imported
    from ..pipeline import make_instance, solve_instance
    from ..render.table import format_table
    instance = make_instance(args.theorem, **instance_spec(args))
    theorem = instance.theorem
    solving = solve_arguments(args)
    if theorem.simulator is None:
        raise InputError(f"{theorem.id} declares no simulation of its model (Theorem.simulated_by)")
    design = None
    if not theorem.recovery:
        refuse(args, f"{theorem.id} designs nothing, so the simulation solves nothing", "--backend",
               "--solver", "--solver-option", "--margin")
    if theorem.recovery:
        sol = solve_instance(instance, certify=False, **solving)
        if not sol.ok or sol.design is None:
            raise NoResultError(f"{theorem.id}: no design to simulate ({sol.status}"
                                + (f": {sol.message}" if sol.message else "") + ")")
        design = sol.design
    table = theorem.simulator(instance, design, scenarios=args.scenario or None,
                              horizon=args.horizon, disturbance=args.disturbance, seed=args.seed)
    if args.json:
        print_json({"theorem": theorem.id, "example": instance.example, "horizon": args.horizon,
                    "disturbance": args.disturbance, "rows": table.rows, "notes": table.notes})
        return 0
    echo(f"{theorem.id}" + (f" [{instance.example}]" if instance.example else "")
          + f": horizon {args.horizon}, test disturbance {args.disturbance}")
    rows = [["" if r.get(k) is None else r[k] for k in table.columns] for r in table.rows]
    print(format_table(list(table.columns.values()), rows))
    for note in table.notes:
        echo("\n" + note)
    return 0
