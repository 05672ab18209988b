"""``lmidsl list``: theorems (id, title, source) and their examples.

By default only the papers' own theorems and examples; ``--all`` adds corrected and guessed
readings and illustrations, marked with their provenance."""
from __future__ import annotations

from ..render.report import format_table
from ..theorem.registry import all_theorems
from .common import print_json

ORDER = 10


def register(sub):
    p = sub.add_parser("list", help="list theorems and their examples")
    p.add_argument("--all", action="store_true",
                   help="also the variants: corrected and guessed readings, illustrations")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    p.set_defaults(run=run)


def run(args):
    everything = [t for _, t in sorted(all_theorems().items())]
    theorems = everything if args.all else [t for t in everything if t.provenance == "paper"]
    if args.json:
        print_json({"theorems": [t.summary() for t in theorems]})
        return 0
    rows = []
    hidden_examples = 0
    for t in theorems:
        examples = [e for e in t.examples.values() if args.all or e.provenance == "paper"]
        hidden_examples += len(t.examples) - len(examples)
        names = ", ".join(e.name + ("" if e.provenance == "paper" else f" [{e.provenance}]")
                          for e in examples)
        row = [t.id, t.title, f"{t.source.paper}, {t.source.equations}", names]
        if args.all:
            row.insert(1, t.provenance)
        rows.append(row)
    headers = ["theorem", "title", "source", "examples"]
    if args.all:
        headers.insert(1, "provenance")
    print(format_table(headers, rows))
    hidden = len(everything) - len(theorems)
    if hidden or hidden_examples:
        print(f"\n{hidden} theorem(s) and {hidden_examples} example(s) that are not the papers' own "
              "(corrected or guessed readings, illustrations) are hidden: lmidsl list --all")
    return 0
