"""``lmidsl list``: theorems (id, title, paper), their examples and the commands they support.

By default only the papers' own theorems and examples; ``--all`` adds corrected and guessed
readings and illustrations, marked with their provenance.  Reads the cached index of
:mod:`lmidsl.theorem.index` (rebuilt when a theorem file changes), so no theorem file runs."""
from __future__ import annotations

from ..render.catalogue import format_list
from ..render.terminal import echo
from ..theorem.registry import theorem_index
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
    print(format_list(theorems, show_provenance=args.all))
    hidden = len(everything) - len(theorems)
    echo("\nevery theorem supports solve, check, latex and reproduce; 'also' lists the "
         "commands that need a declaration the theorem may lack; the default example is the one a "
         "command uses without --example"
         + (f"; {hidden} theorem(s) that are not the papers' own (corrected or guessed readings, "
            "illustrations) are hidden: lmidsl list --all" if hidden else "") + ".")
    return 0
