"""The installed package finds its theorem files from any directory (``pip install .``)."""
from __future__ import annotations

import json
import os
import shutil
import subprocess

import pytest


def test_installed_console_script_lists_theorems(tmp_path):
    exe = shutil.which("lmidsl")
    if exe is None:
        if os.environ.get("CI"):
            pytest.fail("CI installs the package (pip install .), but no lmidsl console script is on PATH")
        pytest.skip("lmidsl is not installed here (pip install . puts the console script on PATH)")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LMIDSL_THEOREM_PATH")}
    proc = subprocess.run([exe, "list", "--json"], capture_output=True, text=True, cwd=tmp_path,
                          env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    ids = {t["id"] for t in json.loads(proc.stdout)["theorems"]}
    assert {"wang_l2linf.thm1", "wang_l2linf.thm3", "wang_l2linf.cor1"} <= ids
    solved = subprocess.run([exe, "solve", "wang_l2linf.thm3", "--example", "paper-full", "--json"],
                            capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300)
    assert solved.returncode == 0, solved.stderr
    assert abs(json.loads(solved.stdout)["gamma"] - 0.3373) / 0.3373 < 5e-3
