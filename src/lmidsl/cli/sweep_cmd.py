"""``lmidsl sweep``: solve a theorem over a grid of parameters (compiled once)."""
from __future__ import annotations

import sys
from pathlib import Path

from ..errors import InputError
from ..render.report import format_table
from ..studies.store import ensure_writable_dir
from ..studies.sweep import MAX_POINTS, format_timing, parse_grid, sweep
from .common import (add_instance_arguments, add_parallel_arguments, instance_spec, parallel_spec,
                     positive_float, positive_int, print_json)

ORDER = 25


def register(sub):
    p = sub.add_parser("sweep", help="solve over a parameter grid, compiled once")
    add_instance_arguments(p)
    p.add_argument("--grid", action="append", default=[], metavar="NAME=START:STOP:COUNT",
                   help="a parameter grid (repeatable; the sweep is over the product), "
                        "e.g. xi1=0.05:0.95:19 or xi1=0.1,0.5")
    p.add_argument("--solver", help="solver name (default: clarabel)")
    p.add_argument("--backend", default="cvxpy", help="modelling backend")
    p.add_argument("--margin", type=positive_float, help="strictness margin ε")
    p.add_argument("--scaling", default="auto", choices=("auto", "none"), help="exact signal scaling")
    p.add_argument("--out", metavar="DIR",
                   help="write sweep.jsonl (each point as it is solved), then sweep.csv, sweep.json and "
                        "sweep.png here")
    p.add_argument("--resume", action="store_true",
                   help="take the points already in DIR/sweep.jsonl (same theorem, data and grid) and "
                        "solve only the rest")
    p.add_argument("--max-points", type=positive_int, default=MAX_POINTS,
                   help=f"refuse a grid of more points than this (default {MAX_POINTS})")
    p.add_argument("--title", help="title of the figure")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
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

    def progress(items):
        from tqdm import tqdm
        return tqdm(items, desc=f"sweep {args.theorem}", file=sys.stderr, unit="pt",
                    disable=None if not args.json else True)

    result = sweep(args.theorem, grids, solver=args.solver, backend=args.backend, margin=args.margin,
                   scaling=args.scaling, progress=progress, max_points=args.max_points,
                   store=out / "sweep.jsonl" if out else None, resume=args.resume,
                   **parallel_spec(args), **instance_spec(args))
    if out:
        result.write_csv(out / "sweep.csv")
        result.write_json(out / "sweep.json")
        result.figure(out / "sweep.png", title=args.title)
    if args.json:
        print_json(result.as_dict())
    else:
        names = list(result.grid)
        rows = [[*(p.params[n] for n in names), p.status, p.gamma, p.worst_eig] for p in result.points]
        if len(rows) <= 40:
            print(format_table([*names, "status", "gamma", "max eig"], rows))
        ok = [p.gamma for p in result.points if p.gamma is not None]
        print(f"{result.theorem}: {len(result.points)} points, {len(ok)} solved, "
              f"{result.certified_count()} certified (every LMI proved at the returned point)"
              + (f", gamma from {min(ok):.6g} to {max(ok):.6g}" if ok else ""))
        print(format_timing(result.timing()))
        if result.resumed:
            print(f"resumed: {result.resumed} points from {out / 'sweep.jsonl'}, {result.solved} solved now")
        if args.out:
            print(f"wrote {Path(args.out) / 'sweep.csv'}, sweep.json, sweep.png (points as solved: sweep.jsonl)")
    return 0 if result.points and all(p.proved for p in result.points) else 1
