"""``lmidsl check``: solve one instance on every backend × solver and compare the answers.

Exit code 0 when the trusted rows agree, 1 when they disagree (or none is trusted), 2 on bad
input.  See :mod:`lmidsl.studies.cross_check` for what "certified" and "trusted" mean.
"""
from __future__ import annotations

from ..render.progress import Progress
from ..studies.defaults import DEFAULT_TOLERANCE, FIRST_ORDER_CAP
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_parallel_arguments, add_solve_arguments, check_options_for_rows, instance_spec,
                     parallel_spec, parse_solver_options, positive_float, print_json, show_progress)

ORDER = 25


def register(sub):
    p = sub.add_parser("check", help="solve on every backend x solver and compare (exit 1 on disagreement)")
    add_solve_arguments(p, solver_help="compare only this solver (on --backend, or on every backend "
                        "that has it); with --solvers, added to that list")
    add_output_arguments(p, progress=True)
    p.add_argument("--solvers", metavar="LIST",
                   help="comma-separated backend:solver, backend or solver entries "
                        "(default: every backend with every installed SDP solver), e.g. "
                        "clarabel,scs,picos:cvxopt")
    p.add_argument("--tolerance", type=positive_float, default=DEFAULT_TOLERANCE,
                   help=f"relative tolerance on gamma among trusted rows (default {DEFAULT_TOLERANCE:g})")
    p.add_argument("--no-certify", action="store_true", help="skip the analysis certificate")
    p.add_argument("--first-order-cap", type=float, default=FIRST_ORDER_CAP, metavar="FACTOR",
                   help="time limit of a first-order row (SCS, never trusted) as a multiple of the "
                        f"interior-point rows' median time (default {FIRST_ORDER_CAP:g}; 0: no limit); a capped row says so")
    add_parallel_arguments(p)
    p.set_defaults(run=run)


def requested_rows(args) -> str | None:
    """``--solvers`` with the entry that ``--backend`` and ``--solver`` make (backend:solver, or
    either alone); None: every backend with every installed solver."""
    entries = [e for e in (args.solvers or "").split(",") if e.strip()]
    if args.backend or args.solver:
        entries.append(":".join(x for x in (args.backend, args.solver) if x))
    return ",".join(entries) or None


def run(args):
    def progress(plan):
        return Progress(plan, "check", lambda row: f"{row[0]}:{row[1]}", enabled=show_progress(args))

    options = parse_solver_options(args.solver_options)
    get_theorem(args.theorem)
    # the study, imported once the theorem id is known good (an unknown id is answered from the
    # index, without the solving stack)
    from ..render.text import text
    from ..studies.cross_check import check, plan_rows
    check_options_for_rows(plan_rows(requested_rows(args)), options)    # bad options: exit 2 first
    result = check(args.theorem, solvers=requested_rows(args),
                   options=options, tolerance=args.tolerance,
                   margin=args.margin, certify=not args.no_certify, progress=progress,
                   first_order_cap=max(args.first_order_cap, 0.0),
                   **parallel_spec(args), **instance_spec(args))
    if args.json:
        print_json(result.as_dict())
    else:
        print(text(result))
    return result.exit_code
