#!/usr/bin/env python
"""Build the API reference from the docstrings with pdoc; fail on any warning.

    python scripts/build_api_docs.py [OUTDIR]        (default: build/api)

Documents the curated public face, ``lmidsl`` (its ``__all__``: the names a theorem file and a
user of the Python API need), and the two modules whose docstrings carry the mathematics the
public helpers refer to (the standard changes of variables; designs as python-control systems).
pdoc reports problems (a name it cannot import, a docstring link it cannot resolve, ...) as
Python warnings: they are made errors (``-W error::UserWarning``) and any warning pdoc still
prints fails the build, so the reference builds without warnings or not at all.  Exit code 0 on
success, 1 on a warning or a pdoc error.  Needs pdoc (the ``docs`` extra: ``pip install '.[docs]'``).
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

MODULES = ["lmidsl", "lmidsl.numeric.changes_of_variables", "lmidsl.numeric.interconnection"]
ROOT = Path(__file__).resolve().parent.parent


def build(outdir: Path) -> tuple[int, str]:
    """Run pdoc into ``outdir``; (exit code, what pdoc printed on stderr)."""
    cmd = [sys.executable, "-W", "error::UserWarning", "-m", "pdoc", "--docformat",
           "restructuredtext", "--no-search", *MODULES, "-o", str(outdir)]
    run = subprocess.run(cmd, capture_output=True, text=True)
    return run.returncode, run.stderr


def main(argv: list[str]) -> int:
    outdir = Path(argv[0]) if argv else ROOT / "build" / "api"
    code, stderr = build(outdir)
    warned = [line for line in stderr.splitlines() if "warn" in line.lower()]
    if code != 0 or warned:
        sys.stderr.write(stderr)
        print(f"error: the API reference did not build cleanly (pdoc exit {code}, "
              f"{len(warned)} warning lines)", file=sys.stderr)
        return 1
    print(f"API reference: {outdir / 'index.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
