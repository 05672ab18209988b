"""``lmidsl check``: solve one instance on every backend × solver and compare the answers.

Exit code 0 when the trusted rows agree, 1 when they disagree (or none is trusted), 2 on bad
input.  See :mod:`lmidsl.studies.cross_check` for what "certified" and "trusted" mean.
"""
from __future__ import annotations

from ..studies.cross_check import DEFAULT_TOLERANCE, FIRST_ORDER_CAP, check, plan_rows
from ..render.progress import Progress
from ..render.table import format_table
from ..render.terminal import Settings, wrap
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


def _fmt(x, spec=".6g"):
    return "" if x is None else format(x, spec)


def format_check(result) -> str:
    labels: list[str] = []
    for r in result.rows:
        for label in r.max_eig_by_label():
            if label not in labels:
                labels.append(label)
    # the objective only at full width (--wide) when it is not the compared value itself
    objective = Settings.wide and result.compared != "objective"
    compared = "optimum" if result.compared == "objective" else f"optimum {result.compared}"
    headers = ["backend:solver", "status"] + (["objective"] if objective else []) + [
        compared, "max eig", "gamma", "verdict", "time s", "trust", "rel diff"]
    rows = []
    for r in result.rows:
        eigs = [e for e in r.max_eig_by_label().values() if e is not None]
        word = (r.verdict or {}).get("word", "")
        rel = "" if r.rel_diff is None else f"{r.rel_diff:+.1e}" + (" !" if r.disagrees else "")
        rows.append([f"{r.backend}:{r.solver}", r.status] + ([_fmt(r.objective, ".8g")] if objective else [])
                    + [_fmt(r.value, ".8g"), _fmt(max(eigs) if eigs else None, ".2e"), _fmt(r.gamma, ".8g"),
                       word, f"{r.wall_time:.2f}", "yes" if r.trusted else "no", rel])
    # the largest eigenvalue of each LMI: one row per LMI, one column per solver row (a table of
    # labels x solvers stays narrow where one column per label would not)
    solved = [r for r in result.rows if r.max_eig_by_label()]
    eig_rows = [[label] + [_fmt(r.max_eig_by_label().get(label), ".2e") for r in solved] for label in labels]
    title = f"{result.theorem}" + (f" [{result.example}]" if result.example else "")
    status, analysis_column = 1, len(headers) - 4           # status and verdict wrap; ids and numbers never
    lines = [title, format_table(headers, rows, nowrap=tuple(i for i in range(len(headers))
                                                             if i not in (status, analysis_column))), ""]
    if eig_rows:
        lines += ["largest eigenvalue of each LMI at the returned point (N < 0 holds when negative):",
                  format_table(["LMI"] + [f"{r.backend}:{r.solver}" for r in solved], eig_rows), ""]
    backed = [f"  {r.name}: γ {r.backoff_gamma:.8g}" for r in result.rows if r.backoff_gamma is not None]
    if backed:
        lines += ["designs from the automatic back-off (the design recovered at the optimum was not "
                  "certified; as `lmidsl solve`): status and the optimum are the optimum's, max eig "
                  "the back-off point's:"] + backed + [""]
    notes = [f"  {r.name}: {r.error or r.reason}" + (f" ({r.message})" if r.message and not r.error else "")
             for r in result.rows if not r.trusted]
    if notes:
        lines += ["not trusted:"] + notes + [""]
    lines.append("verdict: " + result.verdict.line())
    lines.append("(gamma and verdict: the row's one verdict, as `lmidsl solve` gives it — for a design, the level "
                 "its analysis counterpart certifies; trust: certified + status optimal from a non-first-order "
                 f"solver; rel diff: the optimum against the best trusted optimum; '!' marks a disagreement)")
    return wrap("\n".join(lines))


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
    check_options_for_rows(plan_rows(requested_rows(args)), options)    # bad options: exit 2 first
    result = check(args.theorem, solvers=requested_rows(args),
                   options=options, tolerance=args.tolerance,
                   margin=args.margin, certify=not args.no_certify, progress=progress,
                   first_order_cap=max(args.first_order_cap, 0.0),
                   **parallel_spec(args), **instance_spec(args))
    if args.json:
        print_json(result.as_dict())
    else:
        print(format_check(result))
    return result.exit_code
