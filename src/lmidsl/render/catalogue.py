"""The theorem catalogue of ``lmidsl list``: light (no solver stack), so the list prints fast."""
from __future__ import annotations

from .terminal import wrap


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
