"""The code blocks of the documentation run as printed.

``docs/tutorial.md`` and ``docs/guide.md``: every ```` ```python ```` block is executed, in the
order of the file, in one namespace per file (a block may use what an earlier one defined), so
the asserts inside the blocks — which compare lmidsl's numbers with python-control's — are tests.
A block that is not meant to run is marked ```` ```python no-run ```` (a fragment that needs a
context the page does not give); there are few, and this test counts them.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
FENCE = re.compile(r"^```python([^\n]*)\n(.*?)^```\s*$", re.M | re.S)
PAGES = {"tutorial.md": 0, "guide.md": 2}     # page -> the no-run blocks it may have


def blocks(page: str) -> list[tuple[int, str, bool]]:
    """(line, code, runs) for every python block of ``docs/<page>``."""
    text = (DOCS / page).read_text(encoding="utf-8")
    out = []
    for match in FENCE.finditer(text):
        info = match.group(1).split()
        line = text.count("\n", 0, match.start()) + 1
        out.append((line, match.group(2), "no-run" not in info))
    return out


def test_blocks_are_found_and_few_are_exempt():
    for page, allowed in PAGES.items():
        found = blocks(page)
        assert found, f"docs/{page}: no python block"
        assert sum(not runs for _, _, runs in found) <= allowed, f"docs/{page}: too many no-run blocks"
    assert sum(runs for _, _, runs in blocks("tutorial.md")) >= 6


@pytest.mark.parametrize("page", sorted(PAGES))
def test_code_blocks_run_in_order(page, tmp_path, monkeypatch):
    pytest.importorskip("control")
    pytest.importorskip("slycot")
    monkeypatch.chdir(tmp_path)              # a block that writes a file writes it here
    namespace: dict = {"__name__": f"docs_{page.replace('.', '_')}"}
    for line, code, runs in blocks(page):
        if not runs:
            continue
        try:
            exec(compile(code, f"docs/{page}:{line}", "exec"), namespace)
        except Exception as exc:   # name the block: the traceback shows its lines
            raise AssertionError(f"docs/{page}, the python block at line {line} failed: "
                                 f"{type(exc).__name__}: {exc}") from exc
