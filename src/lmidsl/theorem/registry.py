"""Finding theorems.

A *theorem module* defines ``THEOREMS``, a list of :class:`~lmidsl.theorem.theorem.Theorem`.  It is
either a plain ``*.py`` file or a package (a folder with ``__init__.py``: a paper with its own
models and simulators beside its theorem file).  Theorem modules are looked for in

1. the built-in package ``lmidsl.theorems`` (the repository's ``theorems/`` folder, one package
   per paper);
2. every folder listed in the environment variable ``LMIDSL_THEOREM_PATH``
   (``os.pathsep``-separated), so users keep their own theorem files outside the project.

A theorem id is ``<module>.<name>``; :func:`get_theorem` executes only the modules called
``<module>`` (and every module only when none of them defines the id), so solving one theorem does
not execute every theorem file.  A module whose files (and lmidsl) are unchanged since it was last
built is not executed at all: its theorems come from the build cache (:mod:`.build_cache`).

A theorem file is code and runs with the user's rights; lmidsl isolates one file from another
but does not sandbox it.  A user file that fails to load (a syntax error, an exception) is
skipped, its problem recorded once (file, line, exception: :func:`load_problems`, which the
command line prints as one warning line) so that the built-in theorems and the other files keep
working; so is a file that calls ``sys.exit`` or raises ``KeyboardInterrupt``, and one still
running after :func:`load_timeout` seconds (it runs in a thread with that deadline); asking for a theorem that only a broken file could define is that file's error.  Two
modules defining the same id is an error naming both files, also when one is built in and
the id is asked for by name.  Entries of ``LMIDSL_THEOREM_PATH``
must be absolute folders (a relative one would depend on the current directory); one that does
not exist or is not a folder is a one-line warning.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil
import ctypes
import sys
import threading
import traceback
import warnings
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, LmidslError, LmidslWarning, did_you_mean
from . import build_cache, index

if TYPE_CHECKING:       # the registry itself never builds a theorem: `lmidsl list` reads an index
    from .theorem import Theorem

BUILTIN_PACKAGE = "lmidsl.theorems"


def theorem_dirs() -> list[Path]:
    """The user folders on ``LMIDSL_THEOREM_PATH`` (a relative entry is an error; one that does
    not exist or is not a folder is a one-line warning, once)."""
    dirs = []
    for entry in os.environ.get("LMIDSL_THEOREM_PATH", "").split(os.pathsep):
        if not entry:
            continue
        if not os.path.isabs(entry):
            raise InputError(f"LMIDSL_THEOREM_PATH entry {entry!r} is relative; give absolute folders "
                             f"(e.g. {os.path.abspath(entry)})")
        if not Path(entry).is_dir():
            _warn_once(entry, f"LMIDSL_THEOREM_PATH entry {entry} "
                       + ("is not a folder" if Path(entry).exists() else "does not exist") + "; ignored")
        elif Path(entry).resolve() not in dirs:
            dirs.append(Path(entry).resolve())
    return dirs


_WARNED: set = set()


def _warn_once(key: str, message: str) -> None:
    if key not in _WARNED:
        _WARNED.add(key)
        warnings.warn(message, LmidslWarning, stacklevel=3)


class TheoremFileError(InputError):
    """A user theorem file that cannot be loaded (syntax error, exception while it runs)."""

    def __init__(self, message: str, path: str):
        super().__init__(message)
        self.path = path


_PROBLEMS: dict[str, TheoremFileError] = {}    # file -> why it was skipped
_REPORTED: set = set()


def load_problems(unreported: bool = True) -> list[TheoremFileError]:
    """The user theorem files skipped because they failed to load (each reported once: with
    ``unreported``, those not yet returned, which are then marked reported)."""
    if not _PROBLEMS:
        return []
    current = {str(where) for places in _module_locations(_dirs_key()).values() for _, where in places}
    out = [e for path, e in _PROBLEMS.items() if path in current and (not unreported or path not in _REPORTED)]
    if unreported:
        _REPORTED.update(e.path for e in out)
    return out


def _file_error(exc: BaseException, where: Path, kind: str) -> TheoremFileError:
    """One line: the file, the line in it, the exception."""
    root = where if kind == "package" else where.parent
    if isinstance(exc, SyntaxError) and exc.filename:
        path, line = exc.filename, exc.lineno
    else:
        frames = [f for f in traceback.extract_tb(exc.__traceback__)
                  if Path(f.filename).resolve().is_relative_to(root.resolve())
                  and (kind == "package" or Path(f.filename).resolve() == where.resolve())]
        path, line = (frames[-1].filename, frames[-1].lineno) if frames else (str(where), None)
    at = f"{path}" + (f", line {line}" if line else "")
    what = str(exc) if isinstance(exc, (LmidslError, UserFileExit, LoadTimeout)) else f"{type(exc).__name__}: {exc}"
    return TheoremFileError(f"theorem file {at}: {what}", str(where))


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
        _run_with_deadline(lambda: spec.loader.exec_module(module), where)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def load_timeout() -> float:
    """Seconds a user theorem file may take to load (``LMIDSL_THEOREM_LOAD_TIMEOUT``, default
    :data:`LOAD_TIMEOUT`)."""
    try:
        value = float(os.environ.get("LMIDSL_THEOREM_LOAD_TIMEOUT", LOAD_TIMEOUT))
    except ValueError:
        value = LOAD_TIMEOUT
    return value if value > 0 else LOAD_TIMEOUT


#: a user theorem file still running after this many seconds is stopped and skipped
LOAD_TIMEOUT = 20.0


class UserFileExit(Exception):
    """``sys.exit()`` or ``raise KeyboardInterrupt`` in a user theorem file: reported, not obeyed."""


class LoadTimeout(Exception):
    """A user theorem file that did not finish loading within :func:`load_timeout`."""


def _run_with_deadline(run, where) -> None:
    """``run()`` (executing a user file) in a thread, waited for :func:`load_timeout` seconds.
    A file still running then gets ``SystemExit`` raised inside its thread (Python stops a loop
    of Python code there; a file blocked in C code stays, as a daemon thread) and is skipped;
    ``SystemExit`` and ``KeyboardInterrupt`` raised by the file itself are reported as its error,
    not obeyed (``lmidsl list`` printed nothing and exited 0 for a file calling ``sys.exit(0)``)."""
    outcome: list = []

    def target():
        try:
            run()
            outcome.append(None)
        except BaseException as exc:         # noqa: BLE001 - reported by the caller
            outcome.append(exc)

    thread = threading.Thread(target=target, name=f"lmidsl-load-{Path(where).name}", daemon=True)
    thread.start()
    seconds = load_timeout()
    thread.join(seconds)
    if thread.is_alive():
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread.ident), ctypes.py_object(SystemExit))
        thread.join(1.0)
        raise LoadTimeout(f"did not finish loading within {seconds:g} s (stopped and skipped; "
                          f"LMIDSL_THEOREM_LOAD_TIMEOUT sets the limit)")
    error = outcome[0] if outcome else None
    if isinstance(error, (SystemExit, KeyboardInterrupt)):
        what = f"sys.exit({error.code!r})" if isinstance(error, SystemExit) else "KeyboardInterrupt"
        raise UserFileExit(f"{what} while loading (a theorem file must not end the program)") \
            .with_traceback(error.__traceback__) from None
    if error is not None:
        raise error


def _theorems_of(kind: str, where) -> list:
    """The ``THEOREMS`` of one theorem module: from the build cache (:mod:`.build_cache`) when
    nothing it was built from changed, else by executing the module (and caching the result)."""
    label, files = _label(kind, where), _location_files(kind, where)
    cached = build_cache.load(label, files)
    if cached is not None:
        return cached
    modules_before = set(sys.modules)
    module = _import(kind, where)
    theorems = list(getattr(module, "THEOREMS", []))
    build_cache.store(label, files, module, theorems, [m for m in sys.modules if m not in modules_before])
    return theorems


@lru_cache(maxsize=None)
def _load_alone(module_name: str, theorem_id: str, dirs: tuple) -> tuple | None:
    """(Theorem, file) of ``theorem_id`` read alone from its module's build-cache entry
    (:func:`.build_cache.load_one`: one theorem unpickled, not the whole package); (None, file)
    when that entry, valid for the module's files as they are, holds no theorem of that id; None
    when the module must be read: its theorems are already loaded in this process (one object per
    theorem), two modules share the name, or the cache has no valid entry.  Read once per process,
    as :func:`_load_module` loads a module once."""
    places = _module_locations(dirs)[module_name]
    if (module_name, dirs) in _LOADED or len(places) != 1:
        return None
    kind, where = places[0]
    theorem = build_cache.load_one(_label(kind, where), _location_files(kind, where), theorem_id)
    if theorem is None:
        return None
    return (None if theorem is build_cache.ABSENT else theorem), _label(kind, where)


#: the (module name, theorem path) whose theorems :func:`_load_module` has loaded in this process
_LOADED: set = set()


def _label(kind: str, where) -> str:
    return f"{BUILTIN_PACKAGE}.{where}" if kind == "builtin" else str(where)


@lru_cache(maxsize=None)
def _load_module(module_name: str, dirs: tuple) -> dict[str, tuple]:
    """The theorems of every module called ``module_name``: id -> (Theorem, file).  A user file
    that fails to load is skipped and recorded (:func:`load_problems`); an id defined twice is
    an error naming both files."""
    found: dict[str, tuple] = {}
    _LOADED.add((module_name, dirs))
    for kind, where in _module_locations(dirs).get(module_name, []):
        try:
            theorems = _theorems_of(kind, where)
        except (KeyboardInterrupt, SystemExit):
            raise
        except BaseException as exc:
            if kind == "builtin":
                if isinstance(exc, LmidslError):
                    raise type(exc)(f"theorem file {where}: {exc}") from None
                raise
            _PROBLEMS.setdefault(str(where), _file_error(exc, Path(where), kind))
            continue
        for thm in theorems:
            _add(found, thm, _label(kind, where))
    return found


def _add(found: dict, thm, origin: str) -> None:
    if thm.id in found and found[thm.id][1] != origin:
        raise InputError(f"theorem id {thm.id!r} is defined twice: in {found[thm.id][1]} and in {origin}; "
                         f"rename one")
    found.setdefault(thm.id, (thm, origin))


def _dirs_key() -> tuple:
    return tuple(str(d) for d in theorem_dirs())


def theorem_origins() -> dict[str, tuple]:
    """Every theorem found, by id: (Theorem, the file or package that defines it)."""
    dirs = _dirs_key()
    found: dict[str, tuple] = {}
    for module_name in _module_locations(dirs):
        for tid, (thm, origin) in _load_module(module_name, dirs).items():
            _add(found, thm, origin)
    return found


def all_theorems() -> dict[str, Theorem]:
    """Every theorem found, by id (user files that fail to load are skipped: :func:`load_problems`)."""
    return {tid: thm for tid, (thm, _) in theorem_origins().items()}


def theorem_files() -> list[Path]:
    """Every file whose content decides what the theorems are (for the cached index of ``list``)."""
    return [f for places in _module_locations(_dirs_key()).values() for kind, where in places
            for f in _location_files(kind, where)]


def _location_files(kind: str, where) -> list[Path]:
    """The files of one theorem module: the file, or every file under the package's folder
    (its modules and any data files it reads)."""
    if kind == "builtin":
        package = Path(importlib.util.find_spec(BUILTIN_PACKAGE).submodule_search_locations[0])
        where = package / where if (package / where).is_dir() else package / f"{where}.py"
    where = Path(where)
    if where.is_dir():
        return sorted(f for f in where.rglob("*") if f.is_file() and "__pycache__" not in f.parts
                      and not f.name.startswith(".") and f.suffix not in (".pyc", ".pyo"))
    return [where]


def theorem_index(use_cache: bool = True) -> list[dict]:
    """The entries of ``lmidsl list``, sorted by id: from the cache (:mod:`.index`) while no
    theorem file changes, else by loading every theorem (slow: sympy)."""
    key = index.index_key(theorem_files()) if use_cache else None
    entries = index.cached_index(key) if use_cache else None
    if entries is None:
        entries = index.index_entries(theorem_origins())
        if use_cache and not load_problems(unreported=False):
            index.store_index(key, entries)
    return entries


def _indexed_ids() -> list[str] | None:
    """Every theorem id, from the index of ``lmidsl list`` (:mod:`.index`: cached while no theorem
    file changes, so no theorem file runs); None when a theorem file fails to load (its own error
    must then be shown)."""
    ids = [entry["id"] for entry in theorem_index()]
    return None if load_problems(unreported=False) else ids


def get_theorem(theorem_id: str) -> Theorem:
    """The theorem with this id, or an error listing the known ids.  Only the module the id
    names is read (from the build cache, the one theorem alone); an id it does not define is
    answered from the index of ``lmidsl list``, without running or reading every theorem file."""
    module_name = theorem_id.split(".", 1)[0]
    dirs = _dirs_key()
    if module_name in _module_locations(dirs):
        alone = _load_alone(module_name, theorem_id, dirs)
        if alone is not None and alone[0] is not None:
            _refuse_redefinition(theorem_id, alone[1], dirs)
            return alone[0]
        if alone is None:                # not answered by the cache: the module is read
            theorems = _load_module(module_name, dirs)
            if theorem_id in theorems:
                _refuse_redefinition(theorem_id, theorems[theorem_id][1], dirs)
                return theorems[theorem_id][0]
            for _, where in _module_locations(dirs)[module_name]:   # the file named by the id is broken
                if str(where) in _PROBLEMS:
                    _REPORTED.add(str(where))
                    raise _PROBLEMS[str(where)]
    known = _indexed_ids()
    if known is not None and theorem_id not in known:
        raise InputError(f"unknown theorem {theorem_id!r}{did_you_mean(theorem_id, known)}; "
                         f"`lmidsl list` shows the {len(known)} theorems")
    theorems = all_theorems()
    if theorem_id not in theorems:
        problems = load_problems(unreported=False)
        if len(problems) == 1:          # the broken file may be the one that defines it
            _REPORTED.add(problems[0].path)
            raise problems[0]
        if problems:
            _REPORTED.update(p.path for p in problems)
            raise InputError(f"unknown theorem {theorem_id!r}; theorem files that failed to load: "
                             + "; ".join(str(p) for p in problems))
        raise InputError(f"unknown theorem {theorem_id!r}{did_you_mean(theorem_id, theorems)}; "
                         f"`lmidsl list` shows the {len(theorems)} theorems")
    return theorems[theorem_id]


def _refuse_redefinition(theorem_id: str, origin: str, dirs: tuple) -> None:
    """A user module of another name that defines ``theorem_id`` too is an error naming both
    (it was silently ignored by ``solve``, which executes only the module the id names).  Only
    user modules whose source mentions the id are executed to see (the others stay unexecuted;
    an id computed at run time is found by ``lmidsl list``, which loads every file)."""
    for module_name, places in _module_locations(dirs).items():
        if module_name == theorem_id.split(".", 1)[0] or not any(
                kind != "builtin" and _mentions(kind, where, theorem_id) for kind, where in places):
            continue
        other = _load_module(module_name, dirs).get(theorem_id)
        if other is not None and other[1] != origin:
            raise InputError(f"theorem id {theorem_id!r} is defined twice: in {origin} and in {other[1]}; "
                             f"rename one")


def _mentions(kind: str, where, text: str) -> bool:
    """Whether a Python file of a theorem module contains ``text`` (read, not executed)."""
    for path in _location_files(kind, where):
        if path.suffix == ".py":
            try:
                if text in path.read_text(errors="replace"):
                    return True
            except OSError:
                continue
    return False


def linked_analysis(theorem: Theorem) -> Theorem:
    """The analysis counterpart a theorem names in ``certified_by``: the Theorem object it was
    given, else the theorem with that id."""
    link = theorem.analysis
    return link.target if link.target is not None else get_theorem(link.theorem)


def get_example(theorem: Theorem, name: str):
    if name not in theorem.examples:
        known = ", ".join(theorem.examples) or "none"
        raise InputError(f"{theorem.id}: unknown example {name!r}{did_you_mean(name, theorem.examples)}; "
                         f"examples: {known}")
    return theorem.examples[name]


__all__ = ["all_theorems", "get_theorem", "get_example", "linked_analysis", "theorem_dirs",
           "theorem_origins", "theorem_files", "load_problems", "TheoremFileError"]
