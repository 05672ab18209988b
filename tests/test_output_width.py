"""Every command's text fits COLUMNS = 80, 100 and 200 (issue 28): each line's width in terminal
cells, and every id and number the JSON carries that the widest text shows appears whole (never
split across lines) at every width.  A study runs once; its text is rendered at each width."""
from __future__ import annotations

import json
import re

import pytest
from rich.cells import cell_len

from lmidsl.cli import main
from lmidsl.render.terminal import configure

WIDTHS = (80, 100, 200)
STRIP = ",;:()[]'\"!"


def tokens(text: str) -> set[str]:
    return {w.strip(STRIP) for w in text.split()} - {""}


def json_tokens(doc) -> set[str]:
    """The ids (strings without spaces) and numbers (in the formats the tables use) of a JSON document."""
    found = set()

    def walk(x):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
        elif isinstance(x, bool) or x is None:
            return
        elif isinstance(x, (int, float)):
            for spec in (".8g", ".6g", ".5g", "g", ".2e", ".3e"):
                found.add(format(x, spec))
        elif isinstance(x, str) and x and " " not in x and len(x) > 2:
            found.add(x)
    walk(doc)
    return found


def texts_at_widths(monkeypatch, render) -> dict[int, str]:
    configure(wide=False)
    out = {}
    for width in WIDTHS:
        monkeypatch.setenv("COLUMNS", str(width))
        out[width] = render()
    return out


def assert_fits_and_whole(texts: dict[int, str], doc=None, must=()):
    for width, text in texts.items():
        too_wide = [(cell_len(line), line) for line in text.splitlines() if cell_len(line) > width]
        assert not too_wide, (width, too_wide[:3])
    widest = tokens(texts[max(texts)])
    shown = {t for t in (json_tokens(doc) if doc is not None else widest) if t in widest}
    if doc is not None:
        # numbers and ids of the JSON that the text shows: a good number of them, the ids asked for
        assert len(shown) >= 3, shown
    for item in must:
        assert item in shown, (item, sorted(shown)[:20])
    ids_and_numbers = {t for t in widest if re.search(r"\d|\w\.\w|_", t)}
    for width, text in texts.items():
        have = tokens(text)
        missing = sorted((shown | ids_and_numbers) - have)
        assert not missing, (width, missing[:10])


def cli_texts(monkeypatch, capsys, *argv, code=0) -> tuple[dict[int, str], dict | None]:
    def render():
        got = main(list(argv))
        out, err = capsys.readouterr()
        assert got == code, err
        return out
    texts = texts_at_widths(monkeypatch, render)
    assert main([*argv, "--json"]) == code
    return texts, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("argv", [("list",), ("list", "--all")])
def test_list_fits_and_is_compact(monkeypatch, capsys, argv):
    texts, doc = cli_texts(monkeypatch, capsys, *argv)
    assert_fits_and_whole(texts, doc, must=("wang_l2linf.thm3", "paper-full", "textbook.brl_ct", "resonant"))
    n = len(doc["theorems"])
    assert len(texts[80].splitlines()) <= 3.2 * n + 5, len(texts[80].splitlines())
    # every example of every theorem is shown, the default one marked; simulate and derive-check named
    flat = " ".join(texts[80].split())
    for t in doc["theorems"]:
        for name in t["examples"]:
            assert name in tokens(texts[80]), (t["id"], name)
    assert "resonant [illustration] (default)" in flat
    simulated = [t["id"] for t in doc["theorems"] if "simulate" in t["commands"]]
    assert "pan_impulsive.thm1" in simulated and "wang_l2linf.thm3" not in simulated
    assert any("derive-check" in t["commands"] for t in doc["theorems"])


def test_check_fits(monkeypatch):
    from lmidsl.render.text import format_check
    from lmidsl.studies.cross_check import check
    result = check("wang_l2linf.thm3", example="paper-full", solvers="clarabel,picos:cvxopt")
    texts = texts_at_widths(monkeypatch, lambda: format_check(result))
    assert_fits_and_whole(texts, result.as_dict(), must=("wang_l2linf.thm3", "paper-full"))
    assert "0.33674" in " ".join(texts[80].split())


def test_reproduce_fits(monkeypatch):
    from lmidsl.render.reproduction import format_reproduction
    from lmidsl.studies.reproduce import reproduce_all
    rows = reproduce_all(None, ["wang_l2linf.thm3", "textbook.brl_ct"], workers=1)
    texts = texts_at_widths(monkeypatch, lambda: format_reproduction(rows))
    assert_fits_and_whole(texts, {"rows": [r.as_dict() for r in rows]},
                          must=("wang_l2linf.thm3", "paper-reduced", "textbook.brl_ct", "random-3x2x2"))


def test_sweep_fits(monkeypatch):
    from lmidsl.render.text import format_sweep
    from lmidsl.studies.sweep import sweep
    from lmidsl.studies.defaults import parse_grid
    result = sweep("wang_l2linf.thm3", [parse_grid("rbar=0.1,0.5", 10)])
    texts = texts_at_widths(monkeypatch, lambda: format_sweep(result))
    assert_fits_and_whole(texts, result.as_dict(), must=("wang_l2linf.thm3",))


@pytest.mark.parametrize("argv", [
    ("derive-check", "wang_l2linf.thm3"),
    ("simulate", "pan_impulsive.thm1", "--example", "modified", "--horizon", "40"),
    ("search", "wang_l2linf.thm3", "--grid", "rbar=0.1:0.5:3"),
    ("successive", "zhang_quantized_loss.thm2", "--example", "paper-N2-robust", "--set", "N=1",
     "--start", '{"Sbar": 1, "P3bar": 100}', "--max-iter", "4"),
])
def test_other_commands_fit(monkeypatch, capsys, argv):
    texts, doc = cli_texts(monkeypatch, capsys, *argv)
    assert_fits_and_whole(texts, doc, must=(argv[1],))


def test_export_fits(monkeypatch, capsys, tmp_path):
    monkeypatch.chdir(tmp_path)
    texts, doc = cli_texts(monkeypatch, capsys, "export", "wang_l2linf.thm3", "--example", "paper-full",
                           "--format", "sdpa", "-o", "thm3.dat-s", "--check")
    assert_fits_and_whole(texts, doc, must=("thm3.dat-s",))


@pytest.mark.parametrize("argv", [
    ("solve", "textbook.brl_ct"),
    ("verify", "textbook.h2_ct_sf"),
])
def test_solve_and_verify_fit(monkeypatch, capsys, argv):
    """Every line fits; every id and number of the JSON that the text shows is whole (the
    timings differ from run to run and are left out of the comparison, not of the width check)."""
    texts, doc = cli_texts(monkeypatch, capsys, *argv)
    for width, text in texts.items():
        assert all(len(line) <= width for line in text.splitlines()), width
    steady = {w: re.sub(r"(?ms)^  times:.*?(?=^  \S|\Z)", "", t) for w, t in texts.items()}
    assert_fits_and_whole(steady, doc)


def _random_table(rng):
    """Headers and rows of random words, numbers and dotted ids, some cells several words long."""
    words = ["optimal", "infeasible", "certified", "NOT", "bound", "holds", "γ", "P̂", "x", "analysis"]
    def token():
        kind = rng.integers(4)
        if kind == 0:
            return f"{rng.standard_normal() * 10.0 ** int(rng.integers(-8, 8)):.6g}"
        if kind == 1:
            return f"paper{rng.integers(9)}.thm{rng.integers(99)}_{'x' * int(rng.integers(0, 12))}"
        return str(rng.choice(words))
    ncols = int(rng.integers(1, 9))
    headers = [" ".join(token() for _ in range(int(rng.integers(1, 3)))) for _ in range(ncols)]
    rows = [[" ".join(token() for _ in range(int(rng.integers(1, 5)))) for _ in range(ncols)]
            for _ in range(int(rng.integers(1, 6)))]
    return headers, rows


@pytest.mark.parametrize("seed", range(40))
def test_random_tables_fit_and_keep_every_word(seed):
    """format_table on random tables at random widths: every line fits (unless one word alone is
    wider than the width), and every word of every cell and header is printed whole."""
    import numpy as np
    from lmidsl.render.table import format_table
    rng = np.random.default_rng(seed)
    headers, rows = _random_table(rng)
    for width in (int(rng.integers(16, 60)), 80, int(rng.integers(81, 220))):
        text = format_table(headers, rows, width=width, color=False)
        for line in text.splitlines():
            assert cell_len(line) <= width or len(line.split()) == 1, (width, line)
        printed = tokens(text)
        stacked = not any(set(line.strip()) == {"-"} for line in text.splitlines())
        for cell in [*headers[stacked:], *(c for row in rows for c in row)]:   # stacked: rows head their block
            for word in cell.split():
                assert word.strip(STRIP) in printed, (width, word, text)
