"""``lmidsl export``: the compiled SDP in SDPA sparse (.dat-s) or CBF, with a JSON map back to
the theorem's LMI labels and variable names (``--check``: read the file back, check that it
states lmidsl's SDP, solve it with cvxpy directly and compare with lmidsl's optimum of the same
SDP: :func:`lmidsl.studies.export.check_round_trip`)."""
from __future__ import annotations

from ..errors import InputError
from ..render.terminal import echo
from ..studies.defaults import FORMATS, OPTIMUM_RTOL
from ..theorem.registry import get_theorem
from .common import add_solve_arguments, instance_spec, print_json, refuse, solve_arguments

ORDER = 75


def register(sub):
    p = sub.add_parser("export", help="write the compiled SDP (SDPA sparse, CBF, or its JSON map)")
    add_solve_arguments(p, solver_help="solver of --check's own solve (default: clarabel)")
    p.add_argument("--format", required=True, choices=FORMATS, help="sdpa (.dat-s), cbf, or json (the map alone)")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="output file")
    p.add_argument("--check", action="store_true",
                   help=f"read the file back: check it states lmidsl's SDP (at three random points), "
                        f"solve it directly with cvxpy and compare with lmidsl's optimum of the same SDP "
                        f"(relative difference <= {OPTIMUM_RTOL:g}); exit 1 otherwise, saying why")
    p.set_defaults(run=run)


def run(args):
    if args.check and args.format == "json":
        raise InputError("--check reads the written SDP back and solves it; --format json writes only "
                         "the map: use --format sdpa or cbf with --check")
    get_theorem(args.theorem)
    # the study, imported once the theorem id is known good (an unknown id is answered from the
    # index, without the solving stack)
    from ..pipeline import make_instance, solve_instance
    from ..render.text import format_export
    from ..studies.export import check_round_trip, export
    instance = make_instance(args.theorem, **instance_spec(args))
    if not args.check:
        refuse(args, "export writes the SDP (compiled by PICOS) and solves nothing; the backend and "
                     "solver flags are for --check's own solve", "--backend", "--solver", "--solver-option")
    solving = solve_arguments(args)
    mapping = export(instance, args.format, args.output, margin=args.margin)
    code = 0
    if args.check:
        solving.pop("margin")                         # the file's own margin is the one checked
        mapping["check"] = check_round_trip(instance, args.output, mapping, **solving)
        verdict = solve_instance(instance, backoff="auto", **solving).verdict   # the instance's, as `solve` gives it
        mapping.update(gamma=verdict.gamma, verdict=verdict.as_dict())
        code = 0 if mapping["check"]["holds"] and verdict.certified else 1
    if args.json:
        print_json(mapping)
        return code
    echo(format_export(mapping, args.output, args.format))
    return code


