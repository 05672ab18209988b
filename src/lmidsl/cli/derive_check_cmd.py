"""``lmidsl derive-check``: is each LMI a theorem derives from another theorem (congruence,
Schur complement, change of variables; ``Theorem.derived_from``) exactly what the derivation
gives?  Both sides at random rational points in exact arithmetic (Schwartz–Zippel), the
recovery included; the first block that differs is named with both expressions."""
from __future__ import annotations

from ..errors import InputError
from ..render.terminal import echo
from ..theorem.registry import get_theorem
from .common import print_json

ORDER = 80


def register(sub):
    p = sub.add_parser("derive-check", help="check a theorem's stated derivations exactly")
    p.add_argument("theorem", help="theorem id, e.g. wang_l2linf.thm3")
    p.add_argument("--points", type=int, default=3, help="random rational points per dimension set (default 3)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--dims", metavar="n=2,k=1", help="dimensions to check at (default: every example's)")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.set_defaults(run=run)


def parse_dims(text: str | None) -> dict | None:
    if not text:
        return None
    out = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        if not sep or not value.strip().isdigit() or int(value) < 1:
            raise InputError(f"--dims {text!r}: expected NAME=POSITIVE_INTEGER[,...]")
        out[name.strip()] = int(value)
    return out


def run(args):
    if args.points < 1:
        raise InputError("--points must be at least 1")
    get_theorem(args.theorem)          # an unknown id is a one-line error, before sympy's checks are imported
    from ..studies.derivation import check_theorem
    results = check_theorem(args.theorem, points=args.points, seed=args.seed, dims=parse_dims(args.dims))
    code = 0 if all(r.holds for r in results) else 1
    if args.json:
        print_json({"theorem": args.theorem, "holds": code == 0, "derivations": [r.as_dict() for r in results]})
        return code
    for r in results:
        head = f"{r.theorem} {r.label} from {r.source} {r.source_label}"
        if r.verdict == "exact":
            dims = "; ".join(",".join(f"{k}={v}" for k, v in d.items()) for d in r.dims)
            echo(f"{head}: exact ({r.points} random rational points; dims {dims})")
        elif r.block is not None:
            e = r.entry or {}
            echo(f"{head}: DIFFERS at block ({r.block[0]},{r.block[1]})")
            echo(f"    {r.label}:      {r.target_expr}")
            echo(f"    derivation: {r.derived_expr}")
            echo(f"    entry ({e.get('row')},{e.get('col')}): {e.get('target')} vs {e.get('derived')}")
        else:
            echo(f"{head}: {r.verdict.upper()}: {r.message}")
        for rec in r.recovery:
            echo(f"    recovery {rec['name']}: {rec['verdict']}" +
                  (f" ({rec.get('formula', '')} = {rec['expected']})" if rec["expected"] else ""))
        if r.free:
            echo(f"    ({', '.join(r.free)}: irrational definitions, drawn as free scalars — "
                  f"an identity for all their values)")
        if r.note:
            echo(f"    ({r.note})")
    return code
