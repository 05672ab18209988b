"""``lmidsl successive``: a BMI by successive LMIs (:mod:`lmidsl.studies.bmi`).

For a theorem that declares a linearisation point (``Theorem.linearise``, e.g. S̄ = S⁻¹): solve
the LMI at the point, move the point to the solution's update, repeat until γ stops improving;
keep the best certified solution (its design certified by the analysis counterpart, as `solve`
does).  ``--start`` gives initial points (repeatable): a JSON object of the point's data, a
number c meaning c·I.  Exit code 0 when the best solution is certified, 1 otherwise.
"""
from __future__ import annotations

import sys

import numpy as np

from ..errors import InputError
from ..render.progress import Stages
from ..render.terminal import echo, is_terminal
from ..theorem.registry import get_theorem
from .common import (add_output_arguments, add_solve_arguments, instance_spec, positive_float, positive_int,
                     print_json, refuse, show_progress, solve_arguments, strict_loads)

ORDER = 45


def register(sub):
    p = sub.add_parser("successive", help="a BMI by successive LMIs over the theorem's linearisation point")
    add_solve_arguments(p)
    add_output_arguments(p, progress=True)
    p.add_argument("--start", action="append", default=[], metavar="JSON",
                   help='an initial linearisation point (repeatable), e.g. \'{"Sbar": 1, "P3bar": 100}\' '
                        "(a number c is c·I); default: the example's own point")
    p.add_argument("--max-iter", type=positive_int, default=30, help="iterations per start (default 30)")
    p.add_argument("--rtol", type=positive_float, default=1e-4,
                   help="stop when γ improves by less than this, relative (default 1e-4)")
    p.add_argument("--no-certify", action="store_true", help="skip the analysis certificate of the best design")
    p.set_defaults(run=run)


def parse_start(text: str, instance) -> dict:
    """One ``--start``: the linearisation data by name, a number c meaning c·I of the datum's shape."""
    point = strict_loads(text, "--start")
    if not isinstance(point, dict):
        raise InputError(f"--start {text}: expected a JSON object of the linearisation point's data")
    names = list(instance.theorem.linearisation)
    out = {}
    for name, value in point.items():
        if name not in names:
            raise InputError(f"--start: {name!r} is not a datum of the linearisation point ({', '.join(names)})")
        shape = np.shape(instance.data[name])
        out[name] = float(value) * np.eye(*shape) if isinstance(value, (int, float)) else np.asarray(value, float)
    return out


def run(args):
    refuse(args, "each step is solved with the solver's defaults (studies.bmi)", "--solver-option")
    get_theorem(args.theorem)
    # the study, imported once the theorem id is known good (an unknown id is answered from the
    # index, without the solving stack)
    from ..pipeline import make_instance
    from ..render.text import text
    from ..studies.bmi import successive_lmi
    instance = make_instance(args.theorem, **instance_spec(args))
    if not instance.theorem.linearisation:
        raise InputError(f"{instance.theorem.id} declares no linearisation point (Theorem.linearise): "
                         "its LMIs are solved by `lmidsl solve`")
    starts = [parse_start(text, instance) for text in args.start] or None
    solving = solve_arguments(args)
    with Stages(f"successive {instance.theorem.id}", enabled=show_progress(args) and is_terminal(sys.stderr)) as steps:
        result = successive_lmi(instance, starts=starts, max_iter=args.max_iter, rtol=args.rtol,
                                solver=solving["solver"], backend=solving["backend"], margin=solving["margin"],
                                progress=steps, certify=not args.no_certify)
    best = result.best
    certified = best is not None and best.verdict.certified
    if args.json:
        print_json({"theorem": instance.theorem.id, "example": instance.example, **result.as_dict(),
                    "verdict": None if best is None else best.verdict.as_dict(),
                    "best": None if best is None else best.as_dict()})
    else:
        echo(f"{instance.theorem.id}" + (f" [{instance.example}]" if instance.example else "")
             + f": successive LMIs over {', '.join(instance.theorem.linearisation)}")
        print(text(result, theorem_id=instance.theorem.id))
    return 0 if certified else 1
