"""``lmidsl search``: grid (and Nelder–Mead refinement) over a theorem's fixed scalars."""
from __future__ import annotations

import sys

from ..errors import InputError
from ..render.progress import Progress
from ..render.terminal import is_terminal, wrap
from ..studies.defaults import OBJECTIVES, parse_grid
from ..theorem.registry import get_theorem
from .common import (add_parallel_arguments, add_solve_arguments, instance_spec, parallel_spec,
                     positive_int, print_json, solve_arguments)

ORDER = 25


def register(sub):
    p = sub.add_parser("search", help="search a theorem's fixed scalars (grid, then Nelder-Mead)")
    add_solve_arguments(p)
    p.add_argument("--grid", action="append", default=[], metavar="NAME=a:b:n",
                   help="grid axis: n points from a to b, or NAME=v1,v2,... (repeatable)")
    p.add_argument("--refine", action="store_true", help="Nelder-Mead refinement from the best grid point")
    p.add_argument("--objective", choices=OBJECTIVES,
                   help="gamma (optimal level; default when the theorem minimises) or tmin (feasp t*)")
    p.add_argument("--maxfev", type=positive_int, default=80, help="refinement evaluations (default 80)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_parallel_arguments(p)
    p.set_defaults(run=run)


def _bar(points):
    """A bar over the grid's points as they come back, on a terminal only."""
    return Progress(points, "scalar search", label=lambda _: "", enabled=is_terminal(sys.stderr))


def run(args):
    if not args.grid:
        raise InputError("search: give at least one --grid NAME=a:b:n")
    axes = dict(parse_grid(g) for g in args.grid)
    get_theorem(args.theorem)
    # the study, imported once the theorem id is known good (an unknown id is answered from the
    # index, without the solving stack)
    from ..pipeline import make_instance, solve_instance
    from ..render.text import text
    from ..studies.search import scalar_search
    instance = make_instance(args.theorem, **instance_spec(args))
    result = scalar_search(instance, axes, args.objective, refine_best=args.refine,
                           **parallel_spec(args), progress=None if args.no_progress or args.json else _bar,
                           maxfev=args.maxfev, **solve_arguments(args))
    best = result.best_proved or result.best_feasible or result.best
    solution = None if best is None else solve_instance(instance.with_params(**best.params), backoff="auto",
                                                        **solve_arguments(args))
    verdict = None if solution is None else solution.verdict      # the best point's, as `solve` gives it
    if args.json:
        print_json({**result.as_dict(), "verdict": None if verdict is None else verdict.as_dict(),
                    "gamma": None if verdict is None else verdict.gamma})
    else:
        print(wrap(text(result)))
        if verdict is not None:
            print(wrap(f"verdict at {best.params}: {verdict.line()}"))
    return 0 if verdict is not None and verdict.certified else 1
