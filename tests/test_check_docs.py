"""scripts/check_docs.py: the docs' numbers are regenerated from the code, their references exist."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("check_docs", ROOT / "scripts" / "check_docs.py")
check_docs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(check_docs)

ROWS = {"rows": [{"theorem": "li_delay_dropout.thm2", "example": "paper", "printed_gamma": 0.3813,
                  "computed_gamma": 0.3810009235, "certified_gamma": 0.3810355301,
                  "exact_gamma": 0.3640331032, "comparison": "reproduced"}]}


@pytest.mark.parametrize("written,value,percent,expected", [
    ("0.3637", 0.3640331, False, "0.3640"),
    ("0.381003", 0.3810355, False, "0.381036"),
    ("9.98e-4", 9.9812e-4, False, "9.98e-4"),
    ("−0.08", -0.00078436, True, "−0.08"),
    ("2.008285", 2.0082854678, False, "2.008285"),
])
def test_requote_keeps_the_digits_and_style_written(written, value, percent, expected):
    assert check_docs.requote(written, value, percent) == expected


def test_drift_is_found_and_rewritten():
    sources = check_docs.Sources(ROWS)
    text = ("exact 0.3637<!-- = reproduce li_delay_dropout.thm2 paper exact_gamma --> and "
            "(−0.08<!-- = reproduce li_delay_dropout.thm2 paper signed_rel_diff --> %)\n"
            "<!-- generated: reproduce li_delay_dropout -->\nold\n<!-- end generated -->\n")
    problems = []
    new = check_docs.fix_text(text, sources, "x.md", problems)
    assert len(problems) == 2                      # 0.3637 → 0.3640 and the table; −0.08 holds
    assert "0.3640<!-- = reproduce" in new and "| `li_delay_dropout.thm2` | paper | 0.3813 | 0.381 |" in new
    again = []
    assert check_docs.fix_text(new, sources, "x.md", again) == new and not again


def test_unknown_source_is_bad_input():
    with pytest.raises(check_docs.BadInput):
        check_docs.fix_text("1.0<!-- = nowhere x -->", check_docs.Sources(ROWS), "x.md", [])


def test_dangling_references_are_listed():
    md = ROOT / "docs" / "reproductions" / "x.md"
    text = ("[fig](../figures/002_sim.png) [gone](../figures/none.png) `NOTES.md` "
            "`docs/figures/001_fig4/sweep.{csv,json}` `docs/reproductions/0??.md` `../shared/a.md`")
    out = check_docs.dangling(md, text)
    assert len(out) == 3 and "none.png" in out[0] and "NOTES.md" in out[1] and "shared" in out[2]


def test_reproductions_md_is_the_assembly_of_its_parts():
    parts = {p: p.read_text() for p in (ROOT / "docs" / "reproductions").glob("*.md")}
    assert check_docs.assembled(parts) == (ROOT / "docs" / "reproductions.md").read_text()


def test_bounds_table_rounds_outwards_and_swaps_ends_for_a_maximised_performance():
    """The bracket table: the ends rounded outwards to 6 digits (the printed bracket still holds the
    proved one), the dual end on the side the performance's direction puts it, infeasible rows with
    their proof, feasibility rows left out, unproved dual ends with a reason category."""
    assert check_docs.directed(0.3367396291, 6, True) == "0.336739"
    assert check_docs.directed(0.3367405920, 6, False) == "0.336741"
    assert check_docs.directed(-10.96267307, 6, False) == "-10.9626"
    rows = {"rows": [
        {"theorem": "a.min", "example": "e", "verdict": {"word": "optimal"},
         "bounds": {"lower": 0.3367396291, "upper": 0.336740592, "lower_proved": True, "upper_proved": True,
                    "why": "", "maximised": False}},
        {"theorem": "a.max", "example": "e", "verdict": {"word": "optimal"},
         "bounds": {"lower": 1.84410114, "upper": 1.84410122, "lower_proved": True, "upper_proved": True,
                    "why": "", "maximised": True}},
        {"theorem": "a.loose", "example": "e", "verdict": {"word": "certified"},
         "bounds": {"lower": None, "upper": 1.27117, "lower_proved": False, "upper_proved": True,
                    "why": "the shifted problem (ε = 2.9e-08) did not solve; dual of (10) ...", "maximised": False}},
        {"theorem": "a.none", "example": "e", "verdict": {"word": "infeasible"}, "bounds": None},
        {"theorem": "a.feas", "example": "e", "verdict": {"word": "certified"}, "bounds": None}]}
    table = check_docs.bounds_table(check_docs.Sources(rows))
    assert "| `a.min` | e | optimal | 0.336739 | 0.336741 | yes | yes |" in table
    assert "| `a.max` | e | optimal | 1.8441 | 1.84411 | yes | yes |" in table
    assert "| `a.loose` | e | certified | — | 1.27117 | no (the dual is not proved in the cone) | yes |" in table
    assert "| `a.none` | e | infeasible |" in table and "a.feas" not in table
