"""``lmidsl sweep``: solve a theorem over a grid of parameters (compiled once)."""
from __future__ import annotations

import math

from ..errors import InputError
from ..render.progress import Progress
from ..studies.defaults import MAX_POINTS, parse_grid
from ..studies.local_workers import start_for
from ..studies.store import ensure_writable_dir
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_parallel_arguments, add_solve_arguments, instance_spec,
                     parallel_spec, positive_int, print_json, show_progress, solve_arguments)

ORDER = 25


def register(sub):
    p = sub.add_parser("sweep", help="solve over a parameter grid, compiled once")
    add_solve_arguments(p)
    add_output_arguments(p, progress=True)
    p.add_argument("--grid", action="append", default=[], metavar="NAME=START:STOP:COUNT",
                   help="a parameter grid (repeatable; the sweep is over the product), "
                        "e.g. xi1=0.05:0.95:19 or xi1=0.1,0.5")
    p.add_argument("--scaling", default="auto", choices=("auto", "none"), help="exact signal scaling")
    p.add_argument("--out", metavar="DIR",
                   help="write sweep.jsonl (each point as it is solved), then sweep.csv, sweep.json and "
                        "sweep.png, sweep.pdf here")
    p.add_argument("--resume", action="store_true",
                   help="take the points already in DIR/sweep.jsonl (same theorem, data and grid) and "
                        "solve only the rest")
    p.add_argument("--max-points", type=positive_int, default=MAX_POINTS,
                   help=f"refuse a grid of more points than this (default {MAX_POINTS})")
    p.add_argument("--title", help="title of the figure")
    add_parallel_arguments(p)
    p.set_defaults(run=run)


def run(args):
    if not args.grid:
        raise InputError("sweep: give at least one --grid NAME=START:STOP:COUNT")
    grids = [parse_grid(g, args.max_points) for g in args.grid]
    if args.out and len(grids) > 2:
        raise InputError("sweep: --out draws a figure, which needs one or two --grid parameters")
    if args.resume and not args.out:
        raise InputError("sweep: --resume needs --out DIR (the folder of the interrupted sweep)")
    out = ensure_writable_dir(args.out, "--out") if args.out else None   # before the first solve
    # local workers' fork server first: its imports run beside this process's
    start_for(**parallel_spec(args), items=math.prod(len(values) for _, values in grids))
    get_theorem(args.theorem)
    # the study, imported once the theorem id is known good (an unknown id is answered from the
    # index, without the solving stack)
    from ..render.figures import sweep_figure
    from ..render.text import text
    from ..studies.sweep import sweep

    def progress(combos):
        label = lambda combo: ", ".join(f"{n}={v:g}" for (n, _), v in zip(grids, combo))  # noqa: E731
        return Progress(combos, f"sweep {args.theorem}", label, enabled=show_progress(args))

    result = sweep(args.theorem, grids, scaling=args.scaling, progress=progress, max_points=args.max_points,
                   store=out / "sweep.jsonl" if out else None, resume=args.resume,
                   **parallel_spec(args), **solve_arguments(args), **instance_spec(args))
    if out:
        result.write_csv(out / "sweep.csv")
        result.write_json(out / "sweep.json")
        sweep_figure(result, out / "sweep", title=args.title)
    if args.json:
        print_json(result.as_dict())
    else:
        print(text(result, out=args.out))
    return 0 if result.points and all(p.proved for p in result.points) else 1
