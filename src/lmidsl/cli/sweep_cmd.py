"""``lmidsl sweep``: solve a theorem over a grid of parameters (compiled once)."""
from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..render.figures import sweep_figure
from ..render.progress import Progress
from ..render.report import performance_label
from ..render.table import format_table
from ..render.terminal import wrap
from ..studies.parallel import format_stats
from ..studies.store import ensure_writable_dir
from ..studies.sweep import MAX_POINTS, format_timing, parse_grid, sweep
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


MAX_ROWS = 40
"""A sweep of more points prints only its summary (the points are in --json and --out)."""


def format_sweep(result, out=None) -> str:
    """The points (up to :data:`MAX_ROWS`), the summary, the timing and the files written."""
    names = list(result.grid)
    table = []
    if len(result.points) <= MAX_ROWS:
        rows = [[*(p.params[n] for n in names), p.status, p.gamma, p.worst_eig] for p in result.points]
        table.append(format_table([*names, "status", performance_label(result.theorem), "max eig"], rows))
    lines = []
    ok = [p.gamma for p in result.points if p.gamma is not None]
    lines.append(f"{result.theorem}: {len(result.points)} points, {len(ok)} solved, "
                 f"{result.certified_count()} certified (every LMI proved at the returned point)"
                 + (f", {performance_label(result.theorem)} from {min(ok):.6g} to {max(ok):.6g}" if ok else ""))
    lines.append(format_timing(result.timing()))
    if result.parallel:
        lines.append(format_stats(result.parallel))
    if result.resumed:
        lines.append(f"resumed: {result.resumed} points from {Path(out) / 'sweep.jsonl'}, "
                     f"{result.solved} solved now")
    if out:
        lines.append(f"wrote {Path(out) / 'sweep.csv'}, sweep.json, sweep.png, sweep.pdf "
                     "(points as solved: sweep.jsonl)")
    return "\n".join(table + [wrap(line) for line in lines])


def run(args):
    if not args.grid:
        raise InputError("sweep: give at least one --grid NAME=START:STOP:COUNT")
    grids = [parse_grid(g, args.max_points) for g in args.grid]
    if args.out and len(grids) > 2:
        raise InputError("sweep: --out draws a figure, which needs one or two --grid parameters")
    if args.resume and not args.out:
        raise InputError("sweep: --resume needs --out DIR (the folder of the interrupted sweep)")
    out = ensure_writable_dir(args.out, "--out") if args.out else None   # before the first solve

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
        print(format_sweep(result, args.out))
    return 0 if result.points and all(p.proved for p in result.points) else 1
