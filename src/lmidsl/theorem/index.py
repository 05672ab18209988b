"""A small cached index of the theorems (ids, titles, sources, examples, provenance) for
``lmidsl list``, so that listing does not execute every theorem file in sympy.

The index is keyed by a hash of the contents of every theorem file (the built-in packages and the
folders on ``LMIDSL_THEOREM_PATH``) and of lmidsl's version: any change to a file, or a file added
or removed, gives another key, and the index is rebuilt by loading the theorems once.  It lives
in ``$LMIDSL_CACHE_DIR``, else ``$XDG_CACHE_HOME/lmidsl``, else ``~/.cache/lmidsl``; a cache that
cannot be written is simply not kept.  An index is not written while a user theorem file fails
to load (its warning must be shown each time).
"""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import tempfile
from pathlib import Path

INDEX_VERSION = 2


def cache_dir() -> Path:
    """Where lmidsl keeps its caches (``LMIDSL_CACHE_DIR`` overrides, for tests and sandboxes)."""
    if os.environ.get("LMIDSL_CACHE_DIR"):
        return Path(os.environ["LMIDSL_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "lmidsl"


def _registry():
    # the registry is light; it is imported here, not at the top, only to keep the index usable
    # from anywhere in the theorem layer without import order concerns
    return importlib.import_module(".registry", __package__)


def index_key() -> str:
    """A hash of every theorem file's path and contents, the theorem path and lmidsl's version."""
    registry = _registry()
    digest = hashlib.sha256(f"lmidsl-index {INDEX_VERSION} {_version()}\n".encode())
    for path in registry.theorem_files():
        digest.update(str(path).encode() + b"\0")
        try:
            digest.update(hashlib.sha256(path.read_bytes()).digest())
        except OSError:
            digest.update(b"unreadable")
    return digest.hexdigest()[:32]


def _version() -> str:
    init = Path(__file__).resolve().parents[1] / "__init__.py"
    try:
        return hashlib.sha256(init.read_bytes()).hexdigest()[:12]
    except OSError:
        return "?"


def supported_commands(thm) -> list[str]:
    """The commands that need a declaration this theorem may lack: ``verify`` (an analysis
    counterpart or an error system), ``simulate`` (a simulator), ``derive-check`` (derivations)."""
    needs = {"verify": thm.analysis is not None or getattr(thm, "certification", None) is not None,
             "simulate": thm.simulator is not None, "derive-check": bool(thm.derivations)}
    return [name for name, has in needs.items() if has]


def _entry(thm, origin: str) -> dict:
    return {**thm.summary(), "source_paper": thm.source.paper, "source_equations": thm.source.equations,
            "commands": supported_commands(thm), "origin": origin}


def build_index() -> list[dict]:
    """The index entries, by loading every theorem (slow: sympy)."""
    origins = _registry().theorem_origins()
    return [_entry(thm, origin) for _, (thm, origin) in sorted(origins.items())]


def theorem_index(use_cache: bool = True) -> list[dict]:
    """The index entries, sorted by id: from the cache when the theorem files are unchanged."""
    if not use_cache:
        return build_index()
    key = index_key()
    path = cache_dir() / f"theorem-index-{key}.json"
    try:
        data = json.loads(path.read_text())
        if data.get("key") == key:
            return data["theorems"]
    except (OSError, ValueError, KeyError, AttributeError):
        pass
    entries = build_index()
    if not _registry().load_problems(unreported=False):
        write_atomically(path, json.dumps({"key": key, "theorems": entries}), replaces="theorem-index-*.json")
    return entries


def write_atomically(path: Path, content: str | bytes, replaces: str | None = None) -> None:
    """Write ``path`` whole or not at all (a temporary file renamed over it), first removing the
    files of its folder matching the glob ``replaces`` (older versions it supersedes).  A cache
    that cannot be written is simply not kept: no error."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        for old in path.parent.glob(replaces) if replaces else ():
            if old != path:
                old.unlink(missing_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-")
        with os.fdopen(fd, "wb" if isinstance(content, bytes) else "w") as fh:
            fh.write(content)
        os.replace(tmp, path)
    except OSError:
        pass
