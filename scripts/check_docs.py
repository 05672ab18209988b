"""The docs are true: their numbers come from the current code, their references exist.

    python scripts/check_docs.py [--reproduce-json FILE] [--write]

Checks (and with ``--write`` rewrites) three things, and fails on any drift:

1. **Generated tables** between ``<!-- generated: reproduce PAPER [PAPER ...] -->`` and
   ``<!-- end generated -->``: the rows of ``lmidsl reproduce --json`` whose theorem belongs to
   one of the PAPERs (``li_delay_dropout``, ...), one line each; ``<!-- generated: bounds -->``:
   every row's bracket (the proved dual end and the optimum's level, 6 digits rounded outwards).
2. **Quoted numbers**: a number followed by ``<!-- = SOURCE -->`` is recomputed from SOURCE and
   written with as many significant digits as the docs show.  SOURCE is
   ``reproduce THEOREM EXAMPLE FIELD`` (a field of that row of ``lmidsl reproduce --json``, or
   ``signed_rel_diff`` = computed/printed − 1; a number followed by `` %`` is in percent) or
   ``json FILE KEY/KEY/...`` (a value in a JSON file of the repository that a script here
   writes, e.g. ``docs/figures/001_mse.json`` by ``scripts/make_figures.py``).
3. **docs/reproductions.md** is ``docs/reproductions/HEADER.md`` followed by
   ``docs/reproductions/0??.md``, with their links made relative to ``docs/``.

It also checks, never rewrites, that every relative link and every repository path quoted
in backticks in README.md and docs/ names a file or folder of the repository (globs and
``{a,b}`` alternatives are expanded): a reader of the repository must be able to open it.

``--reproduce-json``: the output of ``lmidsl reproduce --json`` (CI passes the file its
reproduce step wrote); without it the script runs ``lmidsl reproduce --json`` itself (~2 min).
Exit codes: 0 the docs are true (or were rewritten), 1 drift or a dangling reference (listed),
2 bad input.
"""
from __future__ import annotations

import argparse
import glob
import json
import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PARTS = DOCS / "reproductions"
ASSEMBLED = DOCS / "reproductions.md"

BLOCK = re.compile(r"(<!-- generated: (?P<spec>[^>]*?) -->\n)(?P<body>.*?)(<!-- end generated -->)",
                   re.S)
NUMBER = r"[-−]?(?:\d+(?:\.\d*)?|\.\d+)(?:(?:e|E)[-+−]?\d+| ?× ?10\^?[-−]?\d+)?"
QUOTED = re.compile(rf"(?P<number>{NUMBER})(?P<percent> ?%)?<!-- = (?P<source>[^>]*?) -->(?P<after> ?%)?")
LINK = re.compile(r"\]\((?P<target>[^)\s]+)\)")
CODE = re.compile(r"`(?P<path>[^`\s]+)`")
#: first components of repository paths quoted in backticks
TOP = ("docs/", "src/", "theorems/", "scripts/", "tests/", "benchmarks/", ".ci/", "README.md",
       "pyproject.toml", "NOTES.md", "../")


class BadInput(Exception):
    pass


# -- sources -------------------------------------------------------------------------------
class Sources:
    def __init__(self, reproduce: dict):
        self.rows = reproduce["rows"]

    def row(self, theorem: str, example: str) -> dict:
        for r in self.rows:
            if r["theorem"] == theorem and r["example"] == example:
                return r
        raise BadInput(f"no row {theorem} {example} in the reproduce JSON")

    def value(self, source: str):
        kind, *args = source.split()
        if kind == "reproduce" and len(args) == 3:
            row = dict(self.row(args[0], args[1]))
            if row.get("printed_gamma") and row.get("computed_gamma") is not None:
                row["signed_rel_diff"] = row["computed_gamma"] / row["printed_gamma"] - 1
            if args[2] not in row:
                raise BadInput(f"reproduce rows have no field {args[2]!r}")
            return row[args[2]]
        if kind == "json" and len(args) >= 2:
            file, path = source.split(None, 2)[1:]
            value = json.loads((ROOT / file).read_text())
            for key in path.split("/"):
                value = value[int(key)] if isinstance(value, list) else value[key]
            return value
        raise BadInput(f"unknown source {source!r} (reproduce THEOREM EXAMPLE FIELD | json FILE KEY/KEY)")


def fmt(x, digits: int = 5) -> str:
    return "—" if x is None else f"{x:.{digits}g}"


def reproduce_table(sources: Sources, papers: list[str]) -> str:
    rows = [r for r in sources.rows if r["theorem"].split(".")[0] in papers]
    if not rows:
        raise BadInput(f"no reproduce row for {' '.join(papers)}")
    lines = ["| theorem | example | printed γ | computed γ | certified γ | exact figure | verdict |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['theorem']}` | {r['example']} | {fmt(r['printed_gamma'])} | "
                     f"{fmt(r['computed_gamma'])} | {fmt(r['certified_gamma'])} | "
                     f"{fmt(r['exact_gamma'])} | {r['comparison']} |")
    return "\n".join(lines) + "\n"


def directed(x: float, digits: int, down: bool) -> str:
    """x with ``digits`` significant digits, rounded down (a lower end) or up (an upper end), so
    that the printed bracket still contains the proved one."""
    if x == 0:
        return "0"
    step = 10.0 ** (_exponent(x) - digits + 1)
    k = math.floor(x / step) if down else math.ceil(x / step)
    return f"{k * step:.{digits}g}"


def bound_reason(why: str) -> str:
    """Why the dual end is missing, as a category: the details (a shift that did not solve, one
    the correction ate, λ_min just below 0) vary between machines with the solver's last digits."""
    for key, words in (("left no dual", "the point came from another route"),
                       ("monotone", "the performance is not monotone in the objective"),
                       ("not computed", "not computed")):
        if key in why:
            return words
    return "the dual is not proved in the cone"


def bounds_table(sources: Sources) -> str:
    """Every reproduce row's bracket: the optimum's level and the proved dual bound, 6 significant
    digits rounded outwards (the last digits of a dual bound vary between machines), and which
    end is proved."""
    lines = ["| theorem | example | verdict | lower end | upper end | lower proved | upper proved |",
             "|---|---|---|---|---|---|---|"]
    for r in sources.rows:
        b = r.get("bounds")
        word = (r.get("verdict") or {}).get("word", r.get("outcome", ""))
        if b is None:
            if word == "infeasible":
                lines.append(f"| `{r['theorem']}` | {r['example']} | {word} | — | — | infeasibility proved | — |")
            continue
        lower, upper = b.get("lower"), b.get("upper")
        lo = "—" if lower is None else directed(lower, 6, True)
        hi = "—" if upper is None else directed(upper, 6, False)
        dual = "upper" if b.get("maximised") else "lower"
        proof = {end: "yes" if b.get(f"{end}_proved") else
                 (f"no ({bound_reason(b.get('why', ''))})" if end == dual else "no") for end in ("lower", "upper")}
        lines.append(f"| `{r['theorem']}` | {r['example']} | {word} | {lo} | {hi} | {proof['lower']} | "
                     f"{proof['upper']} |")
    return "\n".join(lines) + "\n"


def block(sources: Sources, spec: str) -> str:
    kind, *args = spec.split()
    if kind == "reproduce" and args:
        return reproduce_table(sources, args)
    if kind == "bounds" and not args:
        return bounds_table(sources)
    raise BadInput(f"unknown generated block {spec!r} (reproduce PAPER [PAPER ...] | bounds)")


# -- quoted numbers ---------------------------------------------------------------------------
def significant(text: str) -> tuple[int, str]:
    """(significant digits, style) of a number as written: style 'e' (1.5e-7), 'x10' (1.5 × 10^-7)
    or 'f' (0.3637)."""
    mant = re.split(r"[eE]| ?× ?10", text)[0].lstrip("-−")
    style = "e" if re.search(r"[eE]", text) else "x10" if "×" in text else "f"
    digits = mant.replace(".", "").lstrip("0")
    return max(len(digits), 1), style


def requote(written: str, value: float, percent: bool) -> str:
    digits, style = significant(written)
    if percent:
        value = 100 * value
    if style == "e":
        mant, exp = f"{value:.{digits - 1}e}".split("e")
        out = f"{mant}e{int(exp)}"
    elif style == "x10":
        mant, exp = f"{value:.{digits - 1}e}".split("e")
        out = f"{mant} × 10^{int(exp)}"
    else:
        decimals = max(digits - 1 - _exponent(value), 0) if value else digits
        out = f"{value:.{decimals}f}"
    if written.startswith("−") or (out.startswith("-") and "−" in written):
        out = out.replace("-", "−")
    return out


def _exponent(x: float) -> int:
    return int(f"{abs(x):e}".split("e")[1])


def fix_text(text: str, sources: Sources, where: str, problems: list) -> str:
    def sub_block(m):
        new = block(sources, m.group("spec"))
        if new != m.group("body"):
            problems.append(f"{where}: generated table '{m.group('spec')}' drifted")
        return m.group(1) + new + m.group(4)

    def sub_number(m):
        value = sources.value(m.group("source"))
        if not isinstance(value, (int, float)):
            raise BadInput(f"{where}: {m.group('source')} is {value!r}, not a number")
        new = requote(m.group("number"), float(value), bool(m.group("percent") or m.group("after")))
        if new != m.group("number"):
            problems.append(f"{where}: {m.group('number')} should be {new} ({m.group('source')})")
        return new + (m.group("percent") or "") + f"<!-- = {m.group('source')} -->" + (m.group("after") or "")

    return QUOTED.sub(sub_number, BLOCK.sub(sub_block, text))


def assembled(parts: dict[Path, str]) -> str:
    """docs/reproductions.md: HEADER.md and the seed files, their links made relative to docs/."""
    names = [PARTS / "HEADER.md"] + sorted(p for p in parts if re.fullmatch(r"\d{3}\.md", p.name))
    text = "".join(parts[p] for p in names)
    return re.sub(r"\]\(\.\./", "](", text)


# -- references -----------------------------------------------------------------------------
def _expand(path: str) -> list[str]:
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [q for alt in m.group(1).split(",") for q in _expand(path[:m.start()] + alt + path[m.end():])]


def _exists(path: Path) -> bool:
    return any(glob.glob(str(p)) for p in map(Path, _expand(str(path))))


def dangling(md: Path, text: str) -> list[str]:
    out = []
    for m in LINK.finditer(text):
        target = m.group("target").split("#")[0]
        if not target or re.match(r"[a-z]+:", target):
            continue
        if not _exists(md.parent / target):
            out.append(f"{md.relative_to(ROOT)}: link ({m.group('target')}) names nothing in the repository")
    for m in CODE.finditer(text):
        path = m.group("path").rstrip(".,;:")
        if not path.startswith(TOP) or "<" in path or "DIR" in path:
            continue
        path = path.split("::")[0].split(":")[0]
        if not (_exists(ROOT / path) or _exists(md.parent / path)):
            out.append(f"{md.relative_to(ROOT)}: `{m.group('path')}` names nothing in the repository")
    return out


# -- main -----------------------------------------------------------------------------------
def load_reproduce(path: str | None) -> dict:
    if path is None:
        proc = subprocess.run(["lmidsl", "reproduce", "--json"], capture_output=True, text=True,
                              cwd="/tmp")
        text = proc.stdout
    else:
        text = Path(path).read_text()
    try:
        data = json.loads(text)
        data["rows"]
    except (ValueError, KeyError, TypeError) as exc:
        raise BadInput(f"not the JSON of `lmidsl reproduce --json`: {exc}") from None
    return data


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--reproduce-json", metavar="FILE", help="output of `lmidsl reproduce --json`")
    ap.add_argument("--write", action="store_true", help="rewrite the drifted numbers and tables")
    args = ap.parse_args(argv)
    try:
        sources = Sources(load_reproduce(args.reproduce_json))
        problems: list[str] = []
        files = sorted(p for p in DOCS.rglob("*.md") if p != ASSEMBLED)
        new = {}
        for md in files:
            text = md.read_text()
            new[md] = fix_text(text, sources, str(md.relative_to(ROOT)), problems)
        parts = {p: t for p, t in new.items() if p.parent == PARTS}
        whole = assembled(parts)
        if whole != ASSEMBLED.read_text():
            problems.append("docs/reproductions.md is not HEADER.md + 0??.md (run with --write)")
        new[ASSEMBLED] = whole
        refs = []
        for md in [ROOT / "README.md", *files, ASSEMBLED]:
            refs += dangling(md, new.get(md, md.read_text()))
    except BadInput as exc:
        print(f"check_docs: {exc}", file=sys.stderr)
        return 2
    if args.write:
        for md, text in new.items():
            if md.read_text() != text:
                md.write_text(text)
                print(f"rewrote {md.relative_to(ROOT)}")
        problems = []
    for line in problems + refs:
        print(line)
    if problems or refs:
        print(f"check_docs: {len(problems)} drifted, {len(refs)} dangling references", file=sys.stderr)
        return 1
    print("check_docs: the docs' generated tables, quoted numbers and references are true")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
