"""``lmidsl verify``: certify a designed, printed or given design by independent evidence."""
from __future__ import annotations

import json

from ..errors import InputError
from ..symbolic.numbers import finite_matrix
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_solve_arguments, instance_spec, nonnegative_int, positive_float,
                     positive_int, print_json, probability, show_progress, solve_arguments, strict_loads)
from .solve_cmd import add_backoff_argument
from ..render.terminal import wrap

ORDER = 25


def register(sub):
    p = sub.add_parser("verify", help="certify a design: synthesis LMIs, analysis, exact figure, Monte Carlo")
    add_solve_arguments(p)
    add_output_arguments(p, progress=True)
    p.add_argument("--design", "--filter", dest="design", metavar="FILE.json|printed",
                   help="certify these matrices instead of a fresh design: a JSON object of name -> "
                        "matrix (or the JSON of `solve`/`verify`), or 'printed' for the example's printed filter")
    p.add_argument("--gamma", type=positive_float, help="the level γ claimed for the filter (default: synthesis or printed γ)")
    p.add_argument("--runs", type=nonnegative_int, default=10000, help="Monte Carlo runs (0: no simulation; default 10000)")
    p.add_argument("--seed", type=nonnegative_int, default=0, help="random seed of the simulation (default 0)")
    p.add_argument("--confidence", type=probability, default=0.95, help="confidence level of the interval (default 0.95)")
    p.add_argument("--disturbance", default="worst", metavar="worst|impulse|FILE.json",
                   help="simulated disturbance: the exact worst case (default), a unit impulse, or a "
                        "JSON list of w(k) rows")
    p.add_argument("--horizon", type=positive_int, default=50, help="steps simulated with an impulse (default 50)")
    add_backoff_argument(p)
    p.set_defaults(run=run)


def _load_json(path: str, option: str):
    try:
        with open(path) as fh:
            return strict_loads(fh.read(), f"{option} {path}")
    except OSError as exc:
        raise InputError(f"{option} {path}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{option} {path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None


def load_design(arg: str | None):
    """None, 'printed', or a dict of matrices (also accepts the JSON of `solve` / `verify`)."""
    if arg is None or arg == "printed":
        return arg
    data = _load_json(arg, "--design")
    if isinstance(data, dict):
        design = data.get("design")
        if isinstance(design, dict) and isinstance(design.get("matrices"), dict):
            return _checked(design["matrices"], arg)            # the JSON of `solve`
        for key in ("design", "filter", "recovered"):   # of `verify`, and of older versions
            if isinstance(data.get(key), dict) and data[key]:
                return _checked(data[key], arg)
        return _checked(data, arg)
    raise InputError(f"--design {arg}: expected a JSON object of the design's matrices by name")


def _checked(matrices: dict, arg: str) -> dict:
    """Every matrix of a design file is a rectangular array of finite numbers (one line if not)."""
    for name, value in matrices.items():
        finite_matrix(value, f"--design {arg}: matrix {name}")
    return matrices


def load_disturbance(arg: str):
    if arg in ("worst", "impulse"):
        return arg
    data = _load_json(arg, "--disturbance")
    if isinstance(data, dict) and "w" in data:
        data = data["w"]
    if not isinstance(data, list) or not data:
        raise InputError(f"--disturbance {arg}: expected a JSON list of w(k) (numbers or rows)")
    rows = [[x] if not isinstance(x, list) else x for x in data]
    finite_matrix(rows, f"--disturbance {arg}")
    return rows


def run(args):
    get_theorem(args.theorem)          # an unknown id is a one-line error, before the solving stack is imported
    from ..render.progress import Stages
    from ..render.report import format_verification
    from ..studies.verify import verify
    design, disturbance = load_design(args.design), load_disturbance(args.disturbance)
    solving, spec = solve_arguments(args), instance_spec(args)
    with Stages(f"verify {args.theorem}", enabled=show_progress(args)) as stages:
        result = verify(args.theorem, design=design, gamma=args.gamma, runs=args.runs, seed=args.seed,
                        confidence=args.confidence, disturbance=disturbance, horizon=args.horizon,
                        backoff=args.backoff, progress=stages, **solving, **spec)
    if args.json:
        print_json(result.as_dict())
    else:
        print(wrap(format_verification(result)))
    return 0 if result.certified else 1
