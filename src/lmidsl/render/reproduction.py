"""The text of ``lmidsl reproduce``: a summary per paper, the verdict words defined once, then
the rows grouped by provenance, and where the conclusions are (:data:`REPORT`)."""
from __future__ import annotations

from collections import Counter

from ..studies.reproduce import REPRODUCED_TOLERANCE
from ..theorem.values import PROVENANCE
from .table import format_table
from .terminal import Settings, wrap

REPORT = "docs/reproductions.md"
"""The reproduction report: per paper, what was read how, and the conclusions."""

#: the study's verdict (its first words) -> the word shown in the tables
WORDS = {
    "reproduced": "reproduced",
    "printed bound holds": "bound holds",
    "printed bound NOT certified": "bound NOT met",
    "differs from print": "differs",
    "computed (no printed value)": "computed only",
}


def defined_words() -> list[tuple[str, str]]:
    """(word, meaning) of every verdict word the tables use, in the order a reader meets them."""
    tol = f"{100 * REPRODUCED_TOLERANCE:.1f} %"
    return [
        ("reproduced", f"the computed γ is within {tol} of the γ the paper prints"),
        ("bound holds", "the paper prints an upper bound on γ and the computed γ is at or below it "
                        "(a smaller γ is no discrepancy; 'diff' says how much smaller)"),
        ("bound NOT met", f"the computed γ exceeds the printed bound by more than {tol}"),
        ("differs", f"the computed γ is more than {tol} away from the printed γ"),
        ("computed only", "the paper prints no value for this example; γ is computed and certified "
                          "on its own"),
        ("certified", "every LMI proved at the returned point, the analysis counterpart certifies "
                      "the recovered design, and its exact figure does not exceed γ"),
        ("NOT certified", "one of these fails (the row says which)"),
        ("infeasible", "no strictly feasible point exists, proved (a theorem-of-alternatives "
                       "certificate); other words are solver statuses"),
    ]


def shown_verdict(row) -> tuple[str, str | None]:
    """(the verdict cell, a note or None): the study's verdict with its first words replaced by
    the table's word (:data:`WORDS`); what it says in parentheses (e.g. the back-off) and a
    worse outcome than the example expects go to the note."""
    text, note = row.comparison, []
    for study, word in WORDS.items():
        if text.startswith(study):
            text = word + text[len(study):]
            break
    if " (" in text and text.endswith(")") and not text.startswith("error"):
        text, _, extra = text.partition(" (")
        note.append(extra[:-1])
    if not row.as_expected:
        text += ", WORSE than expected"
        note.append(f"the example expects the outcome '{row.expect}', it ended '{row.outcome}'")
    return text, "; ".join(note) or None


def diff_cell(row) -> str | None:
    """Signed relative difference of the computed γ to the printed one (for a printed bound, a
    negative difference is the bound holding with room)."""
    if row.printed_gamma is None or row.computed_gamma is None or not row.printed_gamma:
        return None
    return f"{100 * (row.computed_gamma - row.printed_gamma) / abs(row.printed_gamma):+.2f}%"


def _number(x, spec=".5g") -> str | None:
    return None if x is None else format(x, spec)


def _exact_cell(row) -> str | None:
    if row.exact_kind is None:
        return None
    tag = {"energy_to_peak": "ep", "h_infinity": "H∞"}.get(row.exact_kind, row.exact_kind)
    return f"{row.exact_gamma:.5g} {tag}" if row.exact_gamma is not None else f"∞ {tag}"


def headline(row) -> tuple[float | None, str | None]:
    """(γ, word) of the row's one verdict record, as every command shows them."""
    record = row.verdict or {}
    return record.get("gamma"), record.get("word")


def verdict_cell(row) -> str:
    """The comparison with the paper, then the verdict's own word (``optimal``, ``certified``, ...)
    when the row is certified (an uncertified row says NOT certified and why)."""
    text = shown_verdict(row)[0]
    word = headline(row)[1]
    return text if not row.certified or not word or word in text else f"{text}, {word}"


def row_cells(row, wide: bool) -> list:
    """The cells of one row (the largest LMI eigenvalue only in ``wide`` tables): the SDP optimum
    (what compares with the print) and the verdict's γ, the one every command shows."""
    cells = [f"{row.theorem}\n  {row.example}", _number(row.printed_gamma, "g"),
             _number(row.computed_gamma), diff_cell(row)]
    if wide:
        cells.append(_number(row.worst_eig, ".2e"))
    return cells + [_number(headline(row)[0], ".8g"), _exact_cell(row), verdict_cell(row)]


def paper_of(theorem_id: str) -> str:
    return theorem_id.split(".")[0]


def summary_rows(rows) -> list[list]:
    """One row per paper: examples, printed values, matched, differing, computed, certified,
    ended as expected."""
    papers: dict[str, Counter] = {}
    for r in rows:
        c = papers.setdefault(paper_of(r.theorem), Counter())
        word = shown_verdict(r)[0].split(",")[0]
        c["rows"] += 1
        c["printed"] += r.printed_gamma is not None
        c["matched"] += word in ("reproduced", "bound holds")
        c["differs"] += word in ("differs", "bound NOT met")
        c["computed"] += r.computed_gamma is not None
        c["certified"] += bool(r.certified)
        c["expected"] += bool(r.as_expected)
    return [[paper, c["rows"], c["printed"], c["matched"], c["differs"], c["certified"],
             f"{c['expected']}/{c['rows']}"] for paper, c in papers.items()]


SUMMARY_HEADERS = ["paper", "rows", "printed", "matched", "differs", "certified", "expected"]


def row_headers(wide: bool) -> list[str]:
    return (["theorem\n  example", "printed\nγ", "optimum\nγ", "diff"] + (["max\neig"] if wide else [])
            + ["γ", "exact\nγ", "verdict"])


def format_reproduction(rows) -> str:
    """Summary, definitions, rows, counts and the pointer to :data:`REPORT`."""
    out = [wrap(f"Reproduction of the printed values: {len(rows)} examples. The conclusions, paper "
                f"by paper, are in {REPORT}."), "",
           format_table(SUMMARY_HEADERS, summary_rows(rows), nowrap=(0,)), "",
           wrap("rows: examples; printed: examples whose paper prints γ; matched: reproduced, or the "
                "printed bound holds; certified: the computed γ is certified; expected: ends no worse "
                "than the example declares (a paper's example known to fail counts as expected)."), "",
           "Verdicts:"]
    width = max(len(word) for word, _ in defined_words())
    out += [wrap(f"  {word:<{width}}  {meaning}") for word, meaning in defined_words()]
    wide = Settings.wide
    headers = row_headers(wide)
    numbers = tuple(range(len(headers) - 2))     # the exact γ and the verdict wrap between words
    for provenance, meaning in PROVENANCE.items():
        group = [r for r in rows if r.provenance == provenance]
        if not group:
            continue
        notes = [(r, shown_verdict(r)[1]) for r in group]
        out += ["", wrap(f"{provenance.upper()}: {meaning} ({len(group)} rows)"),
                format_table(headers, [row_cells(r, wide) for r in group], nowrap=numbers)]
        out += [wrap(f"  {r.theorem} [{r.example}]: {note}") for r, note in notes if note]
    out += ["", wrap("optimum γ: the SDP optimum, compared with the print; diff: (optimum − printed) / "
                     "printed; γ: the verdict's level, the one every command shows (for a design, "
                     "its analysis counterpart's γ); 'exact γ' is the filter's exact "
                     "mean-square figure without any LMI (ep: energy-to-peak, H∞: energy-to-energy; "
                     "∞: not mean-square stable)" + ("; 'max eig': the largest eigenvalue of any LMI "
                                                     "at the returned point" if wide else "; --wide adds "
                                                     "the largest LMI eigenvalue") + ".")]
    counts = Counter(shown_verdict(r)[0].split(",")[0] for r in rows)
    out += ["", wrap("; ".join(f"{n} {v}" for v, n in counts.most_common()) + f" ({len(rows)} rows)")]
    return "\n".join(out)
