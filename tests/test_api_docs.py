"""The API reference builds from the docstrings with pdoc, without a warning, and documents the
whole public face (``lmidsl.__all__``, which pdoc reads through the lazy PEP 562 imports)."""
from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

import lmidsl

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "scripts" / "build_api_docs.py"


def test_public_face_is_all_of_the_lazy_table():
    """Every lazily imported public name is in ``__all__`` (else pdoc, and ``from lmidsl import *``,
    would not see it), and every name of ``__all__`` resolves."""
    assert set(lmidsl._LAZY) <= set(lmidsl.__all__)
    for name in lmidsl.__all__:
        assert getattr(lmidsl, name) is not None, name


@pytest.mark.skipif(importlib.util.find_spec("pdoc") is None, reason="pdoc is not installed (docs extra)")
def test_api_reference_builds_without_warnings(tmp_path):
    run = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path)], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "warn" not in run.stderr.lower(), run.stderr[-3000:]
    page = (tmp_path / "lmidsl.html").read_text(encoding="utf-8")
    documented = set(re.findall(r'<section id="([A-Za-z_][A-Za-z0-9_]*)"', page))
    missing = sorted(set(lmidsl.__all__) - documented)
    assert not missing, f"public names pdoc did not document: {missing}"
    assert (tmp_path / "lmidsl" / "numeric" / "changes_of_variables.html").exists()
