"""The largest expansion accepted (LMIs, rows of PSD cones), per command run: a light module (no
sympy), so that the command line reads its flags without loading the symbolic stack; the
estimates themselves are in :mod:`lmidsl.theorem.budget`."""
from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

from ..errors import InputError

MAX_LMIS = 5_000
MAX_PSD_ROWS = 500_000


@dataclass(frozen=True)
class Limits:
    """The largest expansion accepted: LMIs, and rows of the PSD cones."""

    max_lmis: int = MAX_LMIS
    max_psd_rows: int = MAX_PSD_ROWS


_LIMITS: ContextVar = ContextVar("lmidsl_expansion_limits", default=Limits())


def current_limits() -> Limits:
    return _LIMITS.get()


def _limits_from(max_lmis, max_psd_rows) -> Limits:
    base = _LIMITS.get()
    out = {}
    for name, value, default in (("max_lmis", max_lmis, base.max_lmis),
                                 ("max_psd_rows", max_psd_rows, base.max_psd_rows)):
        if value is None:
            out[name] = default
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) or value < 1:
            raise InputError(f"{name} must be a positive integer, got {value!r}")
        out[name] = int(value)
    return Limits(**out)


@contextmanager
def expansion_limits(max_lmis: int | None = None, max_psd_rows: int | None = None):
    """The limits inside a ``with`` block (None keeps the current one)."""
    token = _LIMITS.set(_limits_from(max_lmis, max_psd_rows))
    try:
        yield _LIMITS.get()
    finally:
        _LIMITS.reset(token)


def set_limits(max_lmis: int | None = None, max_psd_rows: int | None = None) -> Limits:
    """The limits from now on in this context (a command's whole run)."""
    _LIMITS.set(_limits_from(max_lmis, max_psd_rows))
    return _LIMITS.get()


__all__ = ["Limits", "MAX_LMIS", "MAX_PSD_ROWS", "current_limits", "expansion_limits", "set_limits"]
