"""Finding theorem files.

Theorem files are plain Python modules that define ``THEOREMS``, a list of
:class:`~lmidsl.theorem.Theorem`.  They are looked for in

1. the installed package ``lmidsl.theorems`` (``pip install .`` maps the repository's
   ``theorems/`` folder there),
2. the ``theorems/`` folder beside the ``lmidsl`` package (a source checkout),
3. every folder listed in the environment variable ``LMIDSL_THEOREM_PATH`` (os.pathsep-separated),
   so users can keep their own theorem files outside the project.
"""
from __future__ import annotations

import importlib.util
import os
from functools import lru_cache
from pathlib import Path

from .errors import InputError, LmidslError
from .theorem import Theorem


def theorem_dirs() -> list[Path]:
    dirs = []
    here = Path(__file__).resolve().parent
    for candidate in (here / "theorems", here.parent / "theorems"):
        if candidate.is_dir() and candidate not in dirs:
            dirs.append(candidate)
    for entry in os.environ.get("LMIDSL_THEOREM_PATH", "").split(os.pathsep):
        if entry and Path(entry).is_dir():
            dirs.append(Path(entry).resolve())
    return dirs


def _load_module(path: Path):
    name = f"lmidsl_theorem_{path.stem}_{abs(hash(str(path)))}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@lru_cache(maxsize=None)
def _load_all(key: tuple) -> dict[str, Theorem]:
    found: dict[str, Theorem] = {}
    for directory in key:
        for path in sorted(Path(directory).glob("*.py")):
            if path.name.startswith("_"):
                continue
            try:
                module = _load_module(path)
            except LmidslError as exc:
                raise type(exc)(f"theorem file {path.name}: {exc}") from None
            for thm in getattr(module, "THEOREMS", []):
                if thm.id in found:
                    continue  # the first folder wins (installed copy before a user path)
                found[thm.id] = thm
    return found


def all_theorems() -> dict[str, Theorem]:
    """Every theorem found, by id."""
    return _load_all(tuple(str(d) for d in theorem_dirs()))


def get_theorem(theorem_id: str) -> Theorem:
    """The theorem with this id, or an error listing the known ids."""
    theorems = all_theorems()
    if theorem_id not in theorems:
        raise InputError(f"unknown theorem {theorem_id!r}; known: {', '.join(sorted(theorems))}")
    return theorems[theorem_id]


def get_example(theorem: Theorem, name: str):
    if name not in theorem.examples:
        known = ", ".join(theorem.examples) or "none"
        raise InputError(f"{theorem.id}: unknown example {name!r}; examples: {known}")
    return theorem.examples[name]


__all__ = ["all_theorems", "get_theorem", "get_example", "theorem_dirs"]
