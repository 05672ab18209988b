"""Finding theorems.

A *theorem module* defines ``THEOREMS``, a list of :class:`~lmidsl.theorem.theorem.Theorem`.  It is
either a plain ``*.py`` file or a package (a folder with ``__init__.py``: a paper with its own
models and simulators beside its theorem file).  Theorem modules are looked for in

1. the built-in package ``lmidsl.theorems`` (the repository's ``theorems/`` folder, one package
   per paper);
2. every folder listed in the environment variable ``LMIDSL_THEOREM_PATH``
   (``os.pathsep``-separated), so users keep their own theorem files outside the project.

A theorem id is ``<module>.<name>``; :func:`get_theorem` loads only the module its id names
(and everything only when that module does not define it), so solving one theorem does not
execute every theorem file.  When two modules define the same id the built-in one wins.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil
import sys
from functools import lru_cache
from pathlib import Path

from ..errors import InputError, LmidslError
from .theorem import Theorem

BUILTIN_PACKAGE = "lmidsl.theorems"


def theorem_dirs() -> list[Path]:
    """The user folders on ``LMIDSL_THEOREM_PATH`` that exist."""
    dirs = []
    for entry in os.environ.get("LMIDSL_THEOREM_PATH", "").split(os.pathsep):
        if entry and Path(entry).is_dir() and Path(entry).resolve() not in dirs:
            dirs.append(Path(entry).resolve())
    return dirs


@lru_cache(maxsize=None)
def _module_locations(dirs: tuple) -> dict[str, list]:
    """Module name -> where it is: ('builtin', name) or ('file', path) / ('package', folder)."""
    found: dict[str, list] = {}
    builtin = importlib.import_module(BUILTIN_PACKAGE)
    for info in pkgutil.iter_modules(builtin.__path__):
        found.setdefault(info.name, []).append(("builtin", info.name))
    for directory in dirs:
        for path in sorted(Path(directory).iterdir()):
            if path.name.startswith(("_", ".")):
                continue
            if path.suffix == ".py":
                found.setdefault(path.stem, []).append(("file", path))
            elif (path / "__init__.py").is_file():
                found.setdefault(path.name, []).append(("package", path))
    return found


def _import(kind: str, where):
    """Import one theorem module (a user file or package under a private, unique name)."""
    if kind == "builtin":
        return importlib.import_module(f"{BUILTIN_PACKAGE}.{where}")
    name = f"lmidsl_user_theorems_{where.stem}_{abs(hash(str(where)))}"
    if name in sys.modules:
        return sys.modules[name]
    if kind == "package":
        spec = importlib.util.spec_from_file_location(
            name, where / "__init__.py", submodule_search_locations=[str(where)])
    else:
        spec = importlib.util.spec_from_file_location(name, where)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module   # a package's relative imports look itself up here
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


@lru_cache(maxsize=None)
def _load_module(module_name: str, dirs: tuple) -> dict[str, Theorem]:
    """The theorems of every module called ``module_name``, by id (the first definition wins)."""
    found: dict[str, Theorem] = {}
    for kind, where in _module_locations(dirs).get(module_name, []):
        try:
            module = _import(kind, where)
        except LmidslError as exc:
            label = where if kind == "builtin" else Path(where).name
            raise type(exc)(f"theorem file {label}: {exc}") from None
        for thm in getattr(module, "THEOREMS", []):
            found.setdefault(thm.id, thm)
    return found


def _dirs_key() -> tuple:
    return tuple(str(d) for d in theorem_dirs())


def all_theorems() -> dict[str, Theorem]:
    """Every theorem found, by id."""
    dirs = _dirs_key()
    found: dict[str, Theorem] = {}
    for module_name in _module_locations(dirs):
        for tid, thm in _load_module(module_name, dirs).items():
            found.setdefault(tid, thm)
    return found


def get_theorem(theorem_id: str) -> Theorem:
    """The theorem with this id, or an error listing the known ids."""
    module_name = theorem_id.split(".", 1)[0]
    dirs = _dirs_key()
    if module_name in _module_locations(dirs):
        theorems = _load_module(module_name, dirs)
        if theorem_id in theorems:
            return theorems[theorem_id]
    theorems = all_theorems()
    if theorem_id not in theorems:
        raise InputError(f"unknown theorem {theorem_id!r}; known: {', '.join(sorted(theorems))}")
    return theorems[theorem_id]


def linked_analysis(theorem: Theorem) -> Theorem:
    """The analysis counterpart a theorem names in ``certified_by``: the Theorem object it was
    given, else the theorem with that id."""
    link = theorem.analysis
    return link.target if link.target is not None else get_theorem(link.theorem)


def get_example(theorem: Theorem, name: str):
    if name not in theorem.examples:
        known = ", ".join(theorem.examples) or "none"
        raise InputError(f"{theorem.id}: unknown example {name!r}; examples: {known}")
    return theorem.examples[name]


__all__ = ["all_theorems", "get_theorem", "get_example", "linked_analysis", "theorem_dirs"]
