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


def index_key(files) -> str:
    """A hash of every theorem file's path and contents (``files``: the registry's), the theorem
    path and lmidsl's version."""
    digest = hashlib.sha256(f"lmidsl-index {INDEX_VERSION} {_version()}\n".encode())
    for path in files:
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


def index_entries(origins: dict) -> list[dict]:
    """The index entries of loaded theorems (``origins``: id → (theorem, origin)), sorted by id."""
    return [_entry(thm, origin) for _, (thm, origin) in sorted(origins.items())]


def cached_index(key: str) -> list[dict] | None:
    """The entries stored under ``key`` (:func:`index_key`), or None."""
    try:
        data = json.loads((cache_dir() / f"theorem-index-{key}.json").read_text())
        if data.get("key") == key:
            return data["theorems"]
    except (OSError, ValueError, KeyError, AttributeError):
        pass
    return None


def store_index(key: str, entries: list[dict]) -> None:
    """Keep ``entries`` under ``key``, replacing older indexes."""
    write_atomically(cache_dir() / f"theorem-index-{key}.json", json.dumps({"key": key, "theorems": entries}),
                     replaces="theorem-index-*.json")


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
