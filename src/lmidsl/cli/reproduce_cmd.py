"""``lmidsl reproduce``: every theorem × example against the paper's printed values."""
from __future__ import annotations

import sys
from collections import Counter

from ..studies.reproduce import REPRODUCED_TOLERANCE, reproduce_all
from ..render.report import format_table
from ..theorem.values import PROVENANCE
from ..errors import InputError
from ..studies.store import atomic_write_text, ensure_writable_dir, strict_json
from .common import add_parallel_arguments, check_solver_argument, parallel_spec, print_json

ORDER = 30


def register(sub):
    p = sub.add_parser("reproduce", help="reproduce every example of every theorem")
    p.add_argument("--solver", help="solver name (default: clarabel)")
    p.add_argument("--theorem", action="append", help="only this theorem id (repeatable)")
    p.add_argument("--out", metavar="DIR",
                   help="write reproduce.jsonl (each row as it is done) and reproduce.json here")
    p.add_argument("--resume", action="store_true",
                   help="keep the rows already in DIR/reproduce.jsonl and run only the rest")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    add_parallel_arguments(p)
    p.set_defaults(run=run)


def _exact_cell(row) -> str | None:
    if row.exact_kind is None:
        return None
    tag = {"energy_to_peak": "ep", "h_infinity": "H∞"}.get(row.exact_kind, row.exact_kind)
    return f"{row.exact_gamma:.6g} ({tag})" if row.exact_gamma is not None else f"∞ ({tag})"


def run(args):
    progress = None
    if not args.json and sys.stderr.isatty():
        from tqdm import tqdm
        progress = lambda jobs: tqdm(jobs, desc="reproducing", file=sys.stderr)  # noqa: E731
    if args.resume and not args.out:
        raise InputError("reproduce: --resume needs --out DIR (the folder of the interrupted run)")
    out = ensure_writable_dir(args.out, "--out") if args.out else None   # before the first solve
    check_solver_argument(args)
    rows = reproduce_all(args.solver, args.theorem, progress,
                         store=out / "reproduce.jsonl" if out else None, resume=args.resume,
                         **parallel_spec(args))
    document = {"tolerance": REPRODUCED_TOLERANCE, "rows": [r.as_dict() for r in rows]}
    if out:
        atomic_write_text(out / "reproduce.json", strict_json(document))
    if args.json:
        print_json(document)
    else:
        headers = ["theorem", "example", "printed γ", "computed γ", "rel. diff",
                   "max eig", "certified γ", "exact γ", "verdict"]
        for provenance, meaning in PROVENANCE.items():
            group = [r for r in rows if r.provenance == provenance]
            if not group:
                continue
            table = [[r.theorem, r.example, r.printed_gamma, r.computed_gamma,
                      None if r.rel_diff is None else f"{100 * r.rel_diff:.2f} %",
                      r.worst_eig, r.certified_gamma, _exact_cell(r),
                      r.verdict + ("" if r.as_expected else f"  [WORSE than expected: {r.expect}]")]
                     for r in group]
            print(f"\n{provenance.upper()}: {meaning} ({len(group)} rows)")
            print(format_table(headers, table))
        print(f"\n'reproduced' means within {100 * REPRODUCED_TOLERANCE:.1f} % of the printed γ; "
              "'certified γ' is the analysis counterpart's γ for the recovered filter;\n"
              "'exact γ' is the filter's exact mean-square figure without any LMI "
              "(ep: energy-to-peak, H∞: energy-to-energy; ∞: not mean-square stable).")
        counts = Counter(r.verdict.split(",")[0].split(" (")[0] for r in rows)
        print("\n" + "; ".join(f"{n} {v}" for v, n in counts.most_common()) + f" ({len(rows)} rows)")
    # a row that ends as its example expects (a documented finding, e.g. a paper's own example
    # proved infeasible) is not a failure of the job; a row worse than that, or one that could
    # not be run at all, is
    return 0 if all(r.as_expected and r.verdict != "error" for r in rows) else 1
