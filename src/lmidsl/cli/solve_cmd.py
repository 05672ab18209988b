"""``lmidsl solve``: bind, compile, solve, recover and certify one instance."""
from __future__ import annotations

import argparse

from ..render.terminal import wrap
from ..theorem.registry import get_theorem
from .common import add_solve_arguments, instance_spec, parse_overrides, print_json, process_age, solve_arguments

ORDER = 20


def register(sub):
    p = sub.add_parser("solve", help="solve a theorem on an example or data")
    add_solve_arguments(p)
    p.add_argument("--scaling", default="auto", choices=("auto", "none"),
                   help="exact signal rescaling declared by the theorem, applied and undone by lmidsl "
                        "(default auto)")
    add_backoff_argument(p)
    p.add_argument("--no-bounds", action="store_true",
                   help="skip the proved lower bound on the optimum (the dual bound) and the "
                        "infeasibility proof; the verdict then never says 'optimal'")
    p.add_argument("--no-certify", action="store_true", help="skip the analysis certificate")
    p.set_defaults(run=run)


def add_backoff_argument(p):
    """``--backoff``: one meaning and one default wherever a design is delivered (solve, verify)."""
    p.add_argument("--backoff", type=backoff_argument, metavar="DELTA|auto|none", default="auto",
                   help="re-solve at objective <= (1+DELTA)*optimum, minimising the condition number "
                        "of what the recovery inverts (e.g. 1e-2); 'auto' (default): only when the "
                        "design recovered at the optimum is not certified or is ill-conditioned; "
                        "'none': never")


def backoff_argument(text):
    if text == "auto":
        return text
    if text == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number or 'auto', got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"expected a positive number or 'auto', got {text!r}")
    return value


def run(args):
    spec = getattr(get_theorem(args.theorem), "bisection", None)     # a family has none
    if spec is not None and spec.parameter not in parse_overrides(args.overrides):
        return run_bisection(args)     # a GEVP: bisect on the declared parameter (--set it to solve at one value)
    # the solving stack, imported once the theorem id is known good (an unknown id is answered
    # from the index, without sympy); the startup reported counts it
    from ..pipeline import solve
    startup = process_age()
    sol = solve(args.theorem, certify=not args.no_certify, scaling=args.scaling, backoff=args.backoff,
                bounds=not args.no_bounds,
                **solve_arguments(args), **instance_spec(args))
    if startup is not None:     # interpreter start, imports, argument parsing: before the solve
        sol.times = {"startup": startup, **sol.times}
    if args.json:
        print_json(sol.as_dict())
    else:
        from ..render.report import format_solution     # rich's tables: needed once there is a result
        print(wrap(format_solution(sol)))
    return 0 if sol.verdict.certified else 1


def run_bisection(args):
    from ..pipeline import make_instance
    from ..render.bisection import format_bisection
    from ..studies.bisection import bisect
    result = bisect(make_instance(args.theorem, **instance_spec(args)), **solve_arguments(args))
    if args.json:
        print_json(result.as_dict())
    else:
        print(wrap(format_bisection(result)))
    return 0 if result.holds else 1
