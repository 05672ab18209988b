"""``lmidsl reproduce``: every theorem × example against the paper's printed values.

The text output leads with a summary a referee can read (one line per paper: printed values,
what was computed, what was certified), the verdict words defined once, then the rows; the
conclusions are in the reproduction report (:data:`lmidsl.render.reproduction.REPORT`).  ``--json`` gives the rows as the
study returns them.
"""
from __future__ import annotations

import importlib

from ..errors import InputError
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_parallel_arguments, add_solve_arguments, default_local_workers,
                     parallel_spec, print_json, refuse, show_progress, solve_arguments)


def _heavy(name: str):
    """The study and its renderers, imported once the arguments and theorem ids are known good
    (an unknown ``--theorem`` is answered without the solver stack)."""
    return importlib.import_module(f"lmidsl.{name}")

ORDER = 30


def register(sub):
    p = sub.add_parser("reproduce", help="reproduce every example of every theorem")
    add_solve_arguments(p, theorem=False, solver_help="solver name (default: clarabel)")
    add_output_arguments(p, progress=True)
    p.add_argument("--theorem", action="append", help="only this theorem id (repeatable)")
    p.add_argument("--out", metavar="DIR",
                   help="write reproduce.jsonl (each row as it is done) and reproduce.json here")
    p.add_argument("--resume", action="store_true",
                   help="keep the rows already in DIR/reproduce.jsonl and run only the rest")
    add_parallel_arguments(p, default_workers=default_local_workers())
    p.set_defaults(run=run)


def run(args):
    for tid in args.theorem or []:
        get_theorem(tid)                  # an unknown id is a one-line error, before any heavy import
    store, study = _heavy("studies.store"), _heavy("studies.reproduce")
    Progress, render = _heavy("render.progress").Progress, _heavy("render.reproduction")
    refuse(args, f"reproduce solves each example on its own data, to compare with what the paper "
                 f"prints; solve other data with `lmidsl solve` or `lmidsl verify` (see {render.REPORT})",
           "--data", "--set")
    if args.resume and not args.out:
        raise InputError("reproduce: --resume needs --out DIR (the folder of the interrupted run)")
    out = store.ensure_writable_dir(args.out, "--out") if args.out else None   # before the first solve
    solving = solve_arguments(args)

    def progress(jobs):
        return Progress(jobs, "reproduce", lambda job: f"{job[0]} [{job[1]}]", enabled=show_progress(args))

    rows = study.reproduce_all(solving.pop("solver"), args.theorem, progress,
                         store=out / "reproduce.jsonl" if out else None, resume=args.resume,
                         **parallel_spec(args), **solving)
    document = {"tolerance": study.REPRODUCED_TOLERANCE, "rows": [r.as_dict() for r in rows]}
    if out:
        store.atomic_write_text(out / "reproduce.json", store.strict_json(document))
    if args.json:
        print_json(document)
    else:
        print(render.format_reproduction(rows))
    # a row that ends as its example expects (a documented finding, e.g. a paper's own example
    # proved infeasible) is not a failure of the job; a row worse than that, or one that could
    # not be run at all, is
    return 0 if all(r.as_expected and r.comparison != "error" for r in rows) else 1
