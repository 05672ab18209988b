"""``lmidsl list``: theorems (id, title, source) and their examples.

By default only the papers' own theorems and examples; ``--all`` adds corrected and guessed
readings and illustrations, marked with their provenance.  Reads the cached index of
:mod:`lmidsl.theorem.index` (rebuilt when a theorem file changes), so no theorem file runs."""
from __future__ import annotations

from ..render.table import format_table
from ..render.terminal import echo
from ..theorem.index import theorem_index
from .common import add_output_arguments, print_json

ORDER = 10


def register(sub):
    p = sub.add_parser("list", help="list theorems and their examples")
    p.add_argument("--all", action="store_true",
                   help="also the variants: corrected and guessed readings, illustrations")
    p.add_argument("--json", action="store_true", help="one JSON object on stdout")
    add_output_arguments(p)
    p.set_defaults(run=run)


def run(args):
    everything = theorem_index()      # cached: no theorem file runs when none has changed
    theorems = everything if args.all else [t for t in everything if t["provenance"] == "paper"]
    if args.json:
        keys = ("origin", "source_paper", "source_equations")
        print_json({"theorems": [{k: v for k, v in t.items() if k not in keys} for t in theorems]})
        return 0
    rows = []
    hidden_examples = 0
    for t in theorems:
        examples = [(name, t["example_provenance"][name]) for name in t["examples"]]
        shown = [(name, prov) for name, prov in examples if args.all or prov == "paper"]
        hidden_examples += len(examples) - len(shown)
        names = ", ".join(name + ("" if prov == "paper" else f" [{prov}]") for name, prov in shown)
        row = [t["id"], t["title"], f"{t['source_paper']}, {t['source_equations']}", names]
        if args.all:
            row.insert(1, t["provenance"])
        rows.append(row)
    headers = ["theorem", "title", "source", "examples"]
    if args.all:
        headers.insert(1, "provenance")
    print(format_table(headers, rows, nowrap=(0,)))
    hidden = len(everything) - len(theorems)
    if hidden or hidden_examples:
        echo(f"\n{hidden} theorem(s) and {hidden_examples} example(s) that are not the papers' own "
              "(corrected or guessed readings, illustrations) are hidden: lmidsl list --all")
    return 0
