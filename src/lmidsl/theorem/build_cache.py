"""A cache of built theorems, so that a second ``lmidsl solve`` does not run the theorem file in
sympy again.

Building a theorem module executes its file: every ``*`` of a block matrix is a sympy ``MatMul``
with its canonicalisation, 0.1–0.3 s per paper.  The result, the module's ``THEOREMS`` (each
carries its symbols' metadata when pickled: ``Theorem.__getstate__``), is pickled once with
cloudpickle and loaded in its place when nothing it was built from has changed:

* **Key** = SHA-256 of the cache format, Python's and sympy's versions, the content of every
  ``*.py`` file of lmidsl itself (the classes being pickled), and the path and content of every
  file of the theorem module (a package: every file under its folder, data included).
* **Dependencies**: the modules the theorem file imported from outside the Python installation
  and outside lmidsl (a user's own helper package) are recorded with their content hashes when the
  entry is written, and checked when it is read: a changed helper rebuilds.  A theorem file that
  reads a data file outside its own folder is not tracked: set ``LMIDSL_CACHE=off``.
* Functions and classes of the theorem module (simulators, recoveries, lambdas of families) are
  pickled **by value** (``cloudpickle.register_pickle_by_value``), so loading the entry does not
  import, and so execute, the theorem file; the library's own functions are pickled by reference.
* An entry that cannot be read (another format, a truncated file) is removed and the module is
  built; a module that cannot be pickled is simply not cached.  One entry per module is kept,
  and at most :data:`MAX_ENTRIES` in all.
* **One theorem alone**: the entry also holds each theorem pickled on its own (with what it
  links to, e.g. the analysis theorem it names, and its symbols' metadata: the form a Dask worker
  receives), so that ``lmidsl solve textbook.brl_ct`` unpickles one theorem, not the 53 of the
  package (:func:`load_one`).  It is read under the same key and the same dependency check as
  the whole module: a theorem file that changed is never answered from the cache.

Where: ``cache_dir()/theorems`` (:mod:`.index`: ``LMIDSL_CACHE_DIR``, ``XDG_CACHE_HOME``,
``~/.cache/lmidsl``).  ``LMIDSL_CACHE=off`` (or ``0``, ``no``) turns the cache off.
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import pickle
import re
import sys
import sysconfig
from functools import lru_cache
from pathlib import Path

from .index import cache_dir, write_atomically

FORMAT = 2
MAX_ENTRIES = 200          # theorem modules with an entry; the least recently written go first
_LMIDSL_ROOT = Path(__file__).resolve().parents[1]


def enabled() -> bool:
    """False when ``LMIDSL_CACHE`` says off."""
    return os.environ.get("LMIDSL_CACHE", "on").strip().lower() not in ("off", "0", "no", "false")


def _file_digest(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return "unreadable"


def _sympy_release() -> str:
    """Where sympy is installed and its ``__init__``'s size and time (another release, another
    key), without importing sympy."""
    spec = importlib.util.find_spec("sympy")
    origin = Path(spec.origin) if spec and spec.origin else None
    if origin is None:
        return "no sympy"
    stat = origin.stat()
    return f"{origin} {stat.st_size} {stat.st_mtime_ns}"


@lru_cache(maxsize=None)
def _library_fingerprint() -> str:
    """A hash of Python's and sympy's releases and of every ``*.py`` file of the lmidsl package
    (its classes are what is pickled)."""
    digest = hashlib.sha256(f"lmidsl-theorems {FORMAT} {sys.version} {_sympy_release()}".encode())
    for path in sorted(_LMIDSL_ROOT.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        digest.update(str(path.relative_to(_LMIDSL_ROOT)).encode() + b"\0")
        digest.update(path.read_bytes())
    return digest.hexdigest()


def entry_key(label: str, files: list[Path]) -> str:
    """The key of a module's entry: the library fingerprint, its label, its files' contents."""
    digest = hashlib.sha256(_library_fingerprint().encode() + label.encode() + b"\0")
    for path in files:
        digest.update(str(path).encode() + b"\0" + _file_digest(path).encode())
    return digest.hexdigest()[:32]


def _slug(label: str) -> str:
    """A file-name-safe name for the module (one entry per module is kept)."""
    tail = re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(label).name or label)[-40:]
    return f"{tail}-{hashlib.sha256(label.encode()).hexdigest()[:8]}"


def _entry_path(label: str, key: str) -> Path:
    return cache_dir() / "theorems" / f"{_slug(label)}-{key}.pickle"


def _entry(label: str, files: list[Path]) -> dict | None:
    """The entry of the module ``label`` built from ``files`` when it is valid (this format, its
    recorded dependencies unchanged), else None; a damaged entry is removed."""
    if not enabled():
        return None
    path = _entry_path(label, entry_key(label, files))
    try:
        data = path.read_bytes()
    except OSError:
        return None
    try:
        entry = pickle.loads(data)
        if entry["format"] != FORMAT or any(_file_digest(Path(p)) != h for p, h in entry["dependencies"]):
            return None
    except Exception:       # a stale or damaged entry is rebuilt, never trusted
        path.unlink(missing_ok=True)
        return None
    entry["path"] = path
    return entry


def _unpickled(entry: dict, data: bytes):
    try:
        return pickle.loads(data)
    except Exception:       # a damaged entry is rebuilt, never trusted
        entry["path"].unlink(missing_ok=True)
        return None


def load(label: str, files: list[Path]) -> list | None:
    """The cached theorems of the module ``label`` built from ``files``, or None.  (Unpickling a
    :class:`~lmidsl.theorem.theorem.Theorem` restores its symbols' metadata.)"""
    entry = _entry(label, files)
    return None if entry is None else _unpickled(entry, entry["theorems"])


#: :func:`load_one`'s answer when the module, as its files are now, defines no theorem of that id
ABSENT = object()


def load_one(label: str, files: list[Path], theorem_id: str):
    """The theorem ``theorem_id`` of the module ``label`` built from ``files``, unpickled alone;
    :data:`ABSENT` when the valid entry holds no theorem of that id; None when there is no valid
    entry (the module must be read)."""
    entry = _entry(label, files)
    if entry is None:
        return None
    if theorem_id not in entry["alone"]:
        return ABSENT
    return _unpickled(entry, entry["alone"][theorem_id])


def _installation_paths() -> list[Path]:
    names = ("stdlib", "platstdlib", "purelib", "platlib")
    return [Path(p).resolve() for p in {sysconfig.get_paths()[n] for n in names} if p]


def _dependencies(new_modules: list[str], own_files: list[Path]) -> list[tuple[str, str]]:
    """(file, hash) of the modules imported while building that belong neither to the Python
    installation, nor to lmidsl, nor to the theorem module itself."""
    skip = _installation_paths() + [_LMIDSL_ROOT]
    own = {p.resolve() for p in own_files}
    out = []
    for name in new_modules:
        file = getattr(sys.modules.get(name), "__file__", None)
        if not file:
            continue
        path = Path(file).resolve()
        if path in own or any(path.is_relative_to(root) for root in skip):
            continue
        out.append((str(path), _file_digest(path)))
    return sorted(set(out))


def store(label: str, files: list[Path], module, theorems: list, new_modules: list[str]) -> None:
    """Write the entry of ``module`` (its functions and classes by value); silently skipped when
    the theorems cannot be pickled or the cache cannot be written.  ``new_modules``: the modules
    imported while it was built."""
    if not enabled():
        return
    try:
        import cloudpickle
    except ImportError:
        return
    cloudpickle.register_pickle_by_value(module)
    try:
        pickled = cloudpickle.dumps(theorems, protocol=pickle.HIGHEST_PROTOCOL)
        alone = {}
        for theorem in theorems:         # the first of an id, as the registry keeps it
            if theorem.id not in alone:
                alone[theorem.id] = cloudpickle.dumps(theorem, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:
        return
    finally:
        cloudpickle.unregister_pickle_by_value(module)
    path = _entry_path(label, entry_key(label, files))
    entry = {"format": FORMAT, "dependencies": _dependencies(new_modules, files), "theorems": pickled,
             "alone": alone}
    data = pickle.dumps(entry, protocol=pickle.HIGHEST_PROTOCOL)
    write_atomically(path, data, replaces=f"{_slug(label)}-*.pickle")      # one entry per module
    _evict(path.parent)


def _evict(folder: Path) -> None:
    """Keep the newest :data:`MAX_ENTRIES` entries (theorem files that moved or were deleted
    leave entries no key will ask for again)."""
    try:
        entries = sorted(folder.glob("*.pickle"), key=lambda p: p.stat().st_mtime, reverse=True)
        for old in entries[MAX_ENTRIES:]:
            old.unlink(missing_ok=True)
    except OSError:
        pass
