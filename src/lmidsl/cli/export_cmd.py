"""``lmidsl export``: the compiled SDP in SDPA sparse (.dat-s) or CBF, with a JSON map back to
the theorem's LMI labels and variable names (``--check``: read the file back, solve it with
cvxpy directly and compare with the theorem's own optimum)."""
from __future__ import annotations

from ..errors import InputError
from ..pipeline import make_instance, solve_instance
from ..render.terminal import echo
from ..studies.export import FORMATS, export, read_back, solve_sdpa_cvxpy
from .common import add_solve_arguments, instance_spec, print_json, refuse, solve_arguments

ORDER = 75
RTOL = 1e-6


def register(sub):
    p = sub.add_parser("export", help="write the compiled SDP (SDPA sparse, CBF, or its JSON map)")
    add_solve_arguments(p, solver_help="solver of --check's own solve (default: clarabel)")
    p.add_argument("--format", required=True, choices=FORMATS, help="sdpa (.dat-s), cbf, or json (the map alone)")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="output file")
    p.add_argument("--check", action="store_true",
                   help=f"read the file back, solve it directly with cvxpy and compare with "
                        f"`lmidsl solve` (relative difference <= {RTOL:g}; exit 1 otherwise)")
    p.set_defaults(run=run)


def run(args):
    if args.check and args.format == "json":
        raise InputError("--check reads the written SDP back and solves it; --format json writes only "
                         "the map: use --format sdpa or cbf with --check")
    instance = make_instance(args.theorem, **instance_spec(args))
    if not args.check:
        refuse(args, "export writes the SDP (compiled by PICOS) and solves nothing; the backend and "
                     "solver flags are for --check's own solve", "--backend", "--solver", "--solver-option")
    solving = solve_arguments(args)
    mapping = export(instance, args.format, args.output, margin=args.margin)
    code = 0
    if args.check:
        value, _ = solve_sdpa_cvxpy(read_back(args.output))
        own = solve_instance(instance, certify=False, diagnose=False, **solving)
        ref = own.objective
        if instance.theorem.objective is None:       # feasibility: both routes find a point
            rel, holds = None, bool(own.ok and own.certified)
        else:
            rel = abs(value - ref) / max(abs(ref), 1e-12) if ref is not None else None
            holds = rel is not None and rel <= RTOL
        mapping["check"] = {"file_optimum": value, "lmidsl_optimum": ref, "relative_difference": rel,
                            "holds": holds}
        code = 0 if mapping["check"]["holds"] else 1
    if args.json:
        print_json(mapping)
        return code
    echo(format_export(mapping, args.output, args.format))
    return code


def format_export(mapping: dict, output: str, fmt: str) -> str:
    """What was written, block by block, and the --check comparison (wrapped to the width)."""
    lines = [f"wrote {output} ({fmt}; {mapping['nvars']} scalar variables, {len(mapping['blocks'])} blocks)"
             + ("" if fmt == "json" else f"; map {output}.map.json")]
    for b in mapping["blocks"]:
        lines.append(f"  block {b['block']}: " + (f"LMI {b['lmi']}" if "lmi" in b else b["kind"])
                     + (f" vertex {b['vertex']}" if b.get("vertex") else "")
                     + (f" {b['scenario']}" if b.get("scenario") else ""))
    if "check" in mapping:
        c = mapping["check"]
        if c["relative_difference"] is None:
            lines.append(f"  read back and solved by cvxpy: a point found; lmidsl: "
                         f"{'a certified point' if c['holds'] else 'no certified point'}")
        else:
            lines.append(f"  read back and solved by cvxpy: {c['file_optimum']:.10g} vs lmidsl "
                         f"{c['lmidsl_optimum']:.10g} (relative {c['relative_difference']:.2e}: "
                         f"{'same' if c['holds'] else 'DIFFERENT'})")
    return "\n".join(lines)
