"""``lmidsl list``: theorems (id, title, paper), their examples and the commands they support.

By default only the papers' own theorems and examples; ``--all`` adds corrected and guessed
readings and illustrations, marked with their provenance.  Reads the cached index of
:mod:`lmidsl.theorem.index` (rebuilt when a theorem file changes), so no theorem file runs."""
from __future__ import annotations

from ..render.terminal import echo, wrap
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


def theorem_lines(t: dict, show_provenance: bool) -> list[str]:
    """One theorem: its id and title (wrapped under the title), then its examples (the first is
    the default of every command) and the commands it supports beyond solve/check/latex/sweep."""
    head = t["id"] + ("" if not show_provenance else f" [{t['provenance']}]") + "  " + t["title"]
    examples = [name + ("" if t["example_provenance"][name] == "paper" else f" [{t['example_provenance'][name]}]")
                for name in t["examples"]]
    if examples:
        examples[0] += " (default)"
    parts = ["examples: " + (", ".join(examples) if examples else "none (give --data)")]
    if t.get("commands"):
        parts.append("also: " + ", ".join(t["commands"]))
    return [wrap(head, indent="    "), wrap("    " + "; ".join(parts), indent="      ")]


def format_list(theorems: list[dict], show_provenance: bool = False) -> str:
    """The theorems grouped by paper: the paper once, then two short lines per theorem."""
    out, groups = [], {}
    for t in theorems:
        groups.setdefault(t["id"].split(".")[0], []).append(t)
    for package, members in groups.items():
        papers = {t["source_paper"] for t in members}
        paper = papers.pop() if len(papers) == 1 else f"{len(papers)} sources (lmidsl list --json)"
        out += ["" if out else None, wrap(f"{package}: {paper}", indent="  ")]
        for t in members:
            out += theorem_lines(t, show_provenance)
    return "\n".join(line for line in out if line is not None)


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
