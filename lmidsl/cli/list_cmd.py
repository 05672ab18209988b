"""``lmidsl list``: theorems (id, title, source) and their examples."""
from __future__ import annotations

from ..theorem.registry import all_theorems
from ..render.report import format_table
from .common import print_json

ORDER = 10


def register(sub):
    p = sub.add_parser("list", help="list theorems and their examples")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.set_defaults(run=run)


def run(args):
    theorems = [t for _, t in sorted(all_theorems().items())]
    if args.json:
        print_json({"theorems": [t.summary() for t in theorems]})
        return 0
    rows = [[t.id, t.title, str(t.source.paper) + " " + t.source.equations, ", ".join(t.examples)]
            for t in theorems]
    print(format_table(["theorem", "title", "source", "examples"], rows))
    return 0
