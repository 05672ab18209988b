"""Durable outputs of long runs: strict JSON, atomic files, an append-only JSON Lines store.

A long run (a sweep, ``reproduce``) appends each finished point or row to ``<out>/<name>.jsonl``
as soon as it is done (one JSON object a line, flushed at once: an interrupt or a crash of the
process loses at most the point being solved; fsynced at most every :data:`SYNC_SECONDS` and at
the end, so that a system crash loses at most that much, and a cluster's hundred points a second
do not cost a hundred fsyncs, 1–5 ms each, of the process that stores them); ``--resume`` reads the store back and skips what is done.
The first line of a store is a header that says what run it belongs to (e.g. the theorem, the
example, the grid, the lmidsl version): a store is resumed only by the same run, and is
locked while a run uses it.  Every record is signed: an HMAC-SHA256 of its canonical JSON under a
key derived from the run's header and this user's secret (:func:`store_secret`), so that a record
edited after it was written -- even one edited consistently, a solver point scaled so that its
LMIs still hold, a status changed to "infeasible" -- is found on resume, dropped and solved again
with a warning.  Final files (CSV, JSON, PNG) are
written to a temporary file beside the target and renamed over it (``os.replace``), so a reader
never sees half a file, and the output folder is checked writable before the first solve;
files are created with the mode the umask gives (not the temporary file's 0600).

JSON written is strict (``allow_nan=False``): a non-finite number becomes ``null`` and the
object says so under ``"notes"``.
"""
from __future__ import annotations

import contextlib
import fcntl
import hashlib
import hmac
import json
import math
import os
import tempfile
import time
from pathlib import Path

from ..errors import InputError
from ..theorem.index import cache_dir

#: the longest a stored record waits for its fsync (:meth:`JsonLinesStore.append`)
SYNC_SECONDS = 0.5


def _json_default(obj):
    value = float(obj)
    return value if math.isfinite(value) else None


def _finite(obj, path: str, notes: list):
    """``obj`` with every non-finite float replaced by None (its path noted)."""
    if isinstance(obj, dict):
        return {k: _finite(v, f"{path}.{k}" if path else str(k), notes) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v, f"{path}[{i}]", notes) for i, v in enumerate(obj)]
    if hasattr(obj, "tolist") and not isinstance(obj, (str, bytes)):   # numpy arrays and scalars
        return _finite(obj.tolist(), path, notes)
    if isinstance(obj, float) and not math.isfinite(obj):
        notes.append(f"{path or 'value'} = {obj} written as null")
        return None
    return obj


def strict_json(obj, indent: int | None = 2, note: bool = True) -> str:
    """Strict JSON text of ``obj``: non-finite numbers become null, listed under ``"notes"``
    (with ``note``) when ``obj`` is an object."""
    notes: list = []
    clean = _finite(obj, "", notes)
    if notes and note:
        if isinstance(clean, dict):
            previous = clean.get("notes")
            key = "notes" if previous is None or isinstance(previous, list) else "json_notes"
            clean = {**clean, key: list(previous or []) + notes if key == "notes" else notes}
        else:
            clean = {"value": clean, "notes": notes}
    return json.dumps(clean, indent=indent, default=_json_default, allow_nan=False)


def _describe(exc: OSError) -> str:
    return exc.strerror or type(exc).__name__


def ensure_writable_dir(path, option: str = "--out") -> Path:
    """Create ``path`` if needed and check a file can be written in it, before any work."""
    out = Path(path)
    where = option if option.endswith(":") else f"{option} {path}:"
    for parent in [out, *out.parents]:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"{where} {parent} is not a directory")
            break
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=out, prefix=".lmidsl-write-test-"):
            pass
    except OSError as exc:
        raise InputError(f"{where} {out} is not writable ({_describe(exc)})") from None
    return out


def check_output_file(path, option: str = "-o") -> Path:
    """Check that the file ``path`` can be written (its folder is created if needed)."""
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{option} {path}: is a directory")
    ensure_writable_dir(target.parent, option=f"{option} {path}:")
    return target


@contextlib.contextmanager
def atomic_path(path):
    """A temporary path beside ``path``, renamed over it when the block succeeds."""
    target = Path(path)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.stem}-", suffix=target.suffix)
    try:
        os.fchmod(fd, 0o666 & ~current_umask())   # mkstemp's 0600 would survive the rename
    finally:
        os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def current_umask() -> int:
    """The process's umask (read by setting it and putting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write_text(path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file, fsync, rename)."""
    with atomic_path(path) as tmp:
        with open(tmp, "w") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())


def _canonical(obj) -> bytes:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False).encode()


def store_secret() -> bytes:
    """This user's secret for signing stores: 32 random bytes in ``<cache>/store.key`` (mode
    0600), made once (atomically: written beside, then linked); ``b""`` when the cache folder
    cannot hold it (the signature then depends on the run alone: it still finds an edit made
    without recomputing it)."""
    path = cache_dir() / "store.key"
    try:
        return _read_secret(path)
    except OSError:
        pass
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".store.key-")
        try:
            os.write(fd, os.urandom(32))
            os.fsync(fd)
        finally:
            os.close(fd)
        try:
            os.link(tmp, path)              # fails when another process made it first: read that
        except FileExistsError:
            pass
        finally:
            os.unlink(tmp)
        return _read_secret(path)
    except OSError:
        return b""


def _read_secret(path: Path) -> bytes:
    secret = path.read_bytes()
    if len(secret) != 32:
        raise OSError(f"{path}: not a store key")
    return secret


def record_signature(key: bytes, record: dict) -> str:
    """HMAC-SHA256 of a record's canonical JSON (sorted keys, no spaces) under ``key``."""
    return hmac.new(key, _canonical(record), hashlib.sha256).hexdigest()


#: why a line of a store was not taken (counted in ``JsonLinesStore.problems``)
NOT_A_RECORD = "not a record"
EDITED = "edited after it was written (its signature does not match)"


class JsonLinesStore:
    """An append-only JSON Lines file: a header line, then one record a line.

    ``open(header, resume)``: without ``resume`` a previous store is replaced; with ``resume`` its
    header must equal ``header`` (same run) and its records are returned.  A line that is not a
    record (cut short by an interrupt, not JSON, not an object) or whose signature does not match
    (edited: module docstring) is dropped and counted in ``dropped``, by reason in ``problems``
    (its point is solved again).  While open, the store is locked
    (``.<store>.lock`` beside it, an advisory ``flock``): a second run on the same ``--out`` is refused.
    """

    def __init__(self, path):
        self.path = Path(path)
        self._fh = None
        self._lock = None
        self._synced = 0.0              # time.monotonic() of the last fsync
        self._key = b""
        self.dropped = 0
        self.problems: dict[str, int] = {}

    def _acquire(self) -> None:
        lock = open(self.path.with_name(f".{self.path.name}.lock"), "a+")
        try:
            fcntl.flock(lock.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            lock.close()
            raise InputError(f"{self.path}: in use by another lmidsl run (one run per --out at a time; "
                             f"wait for it or give another --out)") from None
        self._lock = lock

    def open(self, header: dict, resume: bool = False) -> list[dict]:
        header = json.loads(strict_json(header, indent=None, note=False))
        self._acquire()
        try:
            return self._open(header, resume)
        except OSError as exc:            # the store a folder, a read-only file, a full disk
            self.close()
            raise InputError(f"{self.path}: cannot write the store ({_describe(exc)})") from None
        except BaseException:
            self.close()
            raise

    def _open(self, header: dict, resume: bool) -> list[dict]:
        records: list[dict] = []
        self._key = hmac.new(store_secret(), _canonical(header), hashlib.sha256).digest()
        if resume and self.path.exists():
            lines = self._read_lines()
            first = _parse_line(lines[0]) if lines else None
            if not isinstance(first, dict) or first.get("header") != header:
                raise InputError(f"--resume: {self.path} belongs to another run (different theorem, "
                                 f"example, data, grid or lmidsl version) or is not a store; remove it "
                                 f"or drop --resume")
            for line in lines[1:]:
                entry = _parse_line(line)
                if not (isinstance(entry, dict) and set(entry) == {"record", "sig"}
                        and isinstance(entry["record"], dict) and isinstance(entry["sig"], str)):
                    self._drop(NOT_A_RECORD)
                elif not hmac.compare_digest(entry["sig"], record_signature(self._key, entry["record"])):
                    self._drop(EDITED)
                else:
                    records.append(entry["record"])
            # rewrite with the records kept only, then append
            atomic_write_text(self.path, strict_json(first, indent=None, note=False) + "\n"
                              + "".join(self._line(r) for r in records))
        else:
            atomic_write_text(self.path, strict_json({"header": header}, indent=None, note=False) + "\n")
        self._fh = open(self.path, "a")
        return records

    def _read_lines(self) -> list[str]:
        try:
            data = self.path.read_bytes()
        except OSError as exc:
            raise InputError(f"--resume: {self.path}: cannot read the store ({_describe(exc)})") from None
        return data.decode("utf-8", errors="replace").splitlines()

    def _drop(self, reason: str) -> None:
        self.dropped += 1
        self.problems[reason] = self.problems.get(reason, 0) + 1

    def _line(self, record: dict) -> str:
        """A record's line: the record as strict JSON (as read back) and its signature."""
        record = json.loads(strict_json(record, indent=None, note=False))
        return strict_json({"record": record, "sig": record_signature(self._key, record)},
                           indent=None, note=False) + "\n"

    def append(self, record: dict) -> None:
        self._fh.write(self._line(record))
        self._fh.flush()
        now = time.monotonic()
        if now - self._synced >= SYNC_SECONDS:
            os.fsync(self._fh.fileno())
            self._synced = now

    def close(self) -> None:
        if self._fh is not None:
            with contextlib.suppress(OSError):
                os.fsync(self._fh.fileno())
            try:
                self._fh.close()
            except OSError:           # a full disk: what was fsynced before is kept
                pass
            self._fh = None
        if self._lock is not None:
            self._lock.close()          # releases the flock
            self._lock = None


def _parse_line(line: str):
    """One line's JSON value (finite numbers only), or None when it is not JSON."""
    def refuse(constant):
        raise ValueError(constant)
    try:
        return json.loads(line, parse_constant=refuse)
    except ValueError:
        return None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
