"""``lmidsl check``: solve one instance on every backend × solver and compare the answers.

Exit code 0 when the trusted rows agree, 1 when they disagree (or none is trusted), 2 on bad
input.  See :mod:`lmidsl.studies.cross_check` for what "certified" and "trusted" mean.
"""
from __future__ import annotations

import json

from ..studies.cross_check import DEFAULT_TOLERANCE, check
from ..errors import InputError
from ..render.report import format_table
from .common import (add_instance_arguments, add_parallel_arguments, instance_spec, parallel_spec,
                     positive_float, print_json)

ORDER = 25


def register(sub):
    p = sub.add_parser("check", help="solve on every backend x solver and compare (exit 1 on disagreement)")
    add_instance_arguments(p)
    p.add_argument("--solvers", metavar="LIST",
                   help="comma-separated backend:solver, backend or solver entries "
                        "(default: every backend with every installed SDP solver), e.g. "
                        "clarabel,scs,picos:cvxopt")
    p.add_argument("--solver-option", dest="solver_options", action="append", default=[],
                   metavar="[BACKEND:]SOLVER:KEY=VALUE",
                   help="an option for one solver's rows, VALUE as JSON (e.g. clarabel:max_iter=5, "
                        "picos:cvxopt:max_iterations=3); repeatable")
    p.add_argument("--tolerance", type=positive_float, default=DEFAULT_TOLERANCE,
                   help=f"relative tolerance on gamma among trusted rows (default {DEFAULT_TOLERANCE:g})")
    p.add_argument("--margin", type=positive_float, help="strictness margin ε (N <= -ε I); default 1e-7")
    p.add_argument("--no-certify", action="store_true", help="skip the analysis certificate")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    add_parallel_arguments(p)
    p.set_defaults(run=run)


def parse_solver_options(items: list[str]) -> dict:
    """``[backend:]solver:key=value`` items as ``{"[backend:]solver": {key: value}}``."""
    out: dict = {}
    for item in items:
        left, sep, text = item.partition("=")
        target, colon, key = left.rpartition(":")
        if not sep or not colon or not target.strip() or not key.strip():
            raise InputError(f"--solver-option {item!r}: expected [BACKEND:]SOLVER:KEY=VALUE")
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            value = text
        out.setdefault(target.strip().lower(), {})[key.strip()] = value
    return out


def _fmt(x, spec=".6g"):
    return "" if x is None else format(x, spec)


def format_check(result) -> str:
    labels: list[str] = []
    for r in result.rows:
        for label in r.max_eig_by_label():
            if label not in labels:
                labels.append(label)
    headers = ["backend", "solver", "status", "objective", result.compared]
    headers += [f"eig {label}" for label in labels]
    headers += ["analysis", "time s", "cert", "trust", "rel diff"]
    rows = []
    for r in result.rows:
        eigs = r.max_eig_by_label()
        analysis = "" if r.analysis_passed is None else (
            ("infeasible" if r.analysis_gamma is None else _fmt(r.analysis_gamma, ".6g"))
            + ("" if r.analysis_passed else " (fails)"))
        rel = "" if r.rel_diff is None else f"{r.rel_diff:+.1e}" + (" !" if r.disagrees else "")
        rows.append([r.backend, r.solver, r.status, _fmt(r.objective, ".8g"), _fmt(r.value, ".8g")]
                    + [_fmt(eigs.get(label), ".2e") for label in labels]
                    + [analysis, f"{r.wall_time:.2f}", "yes" if r.certified else "no",
                       "yes" if r.trusted else "no", rel])
    title = f"{result.theorem}" + (f" [{result.example}]" if result.example else "")
    lines = [title, format_table(headers, rows), ""]
    notes = [f"  {r.name}: {r.error or r.reason}" + (f" ({r.message})" if r.message and not r.error else "")
             for r in result.rows if not r.trusted]
    if notes:
        lines += ["not trusted:"] + notes + [""]
    lines.append(result.verdict())
    lines.append("(cert: every LMI's largest eigenvalue < 0 and the analysis certifies the recovered filter; "
                 "trust: cert + status optimal from a non-first-order solver; rel diff against the best "
                 f"trusted {result.compared}; '!' marks a disagreement)")
    return "\n".join(lines)


def run(args):
    result = check(args.theorem, solvers=args.solvers,
                   options=parse_solver_options(args.solver_options), tolerance=args.tolerance,
                   margin=args.margin, certify=not args.no_certify, **parallel_spec(args),
                   **instance_spec(args))
    if args.json:
        print_json(result.as_dict())
    else:
        print(format_check(result))
    return result.exit_code
