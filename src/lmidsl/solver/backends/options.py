"""Solver options checked before any solve: every value a finite JSON value, and, where the
solver states its settings, a known name with a value of the setting's type.

Clarabel (direct backend, and cvxpy's Clarabel interface, which sets the same fields) states its
settings in ``clarabel.DefaultSettings()``: an ``int`` field is an unsigned count (``max_iter``,
``max_threads``: Clarabel stores them as u32), a ``float`` one a non-negative tolerance, step or
limit, a ``bool`` one a switch.  PICOS states its options in ``picos.modeling.options.OPTIONS``
with a type and a check of its own (numbers there are counts, tolerances or time
limits: also refused when negative).  Other solvers (through cvxpy) take keyword arguments that
no table lists; their values are still checked to be finite.
"""
from __future__ import annotations

import json
import math

import clarabel

from ...errors import InputError


#: keywords of cvxpy's own ``Problem.solve`` (not the solver's), passed through unchecked
CVXPY_KEYWORDS = frozenset({"warm_start", "canon_backend", "ignore_dpp", "enforce_dpp"})


def finite_value(value, where: str):
    """``value`` itself when every number in it is finite (JSON's 1e400 is inf), else one line."""
    if isinstance(value, float) and not math.isfinite(value):
        raise InputError(f"{where}: not a finite number (it overflows a double)" if math.isinf(value)
                         else f"{where}: not a finite number")
    if isinstance(value, list):
        for item in value:
            finite_value(item, where)
    if isinstance(value, dict):
        for item in value.values():
            finite_value(item, where)
    return value


def solver_settings(backend: str, solver: str) -> dict | None:
    """name -> checker(value) -> message or None, for the settings ``backend:solver`` states;
    None when it states none (the options are passed on unchecked)."""
    solver = (solver or "").lower()
    if solver == "clarabel" and backend in ("direct", "cvxpy"):
        return _clarabel_settings()
    if backend == "picos":
        return _picos_settings()
    return None


def _clarabel_settings() -> dict:
    defaults = clarabel.DefaultSettings()
    out = {}
    for name in dir(defaults):
        if name.startswith("_") or callable(getattr(defaults, name)):
            continue
        out[name] = _typed(type(getattr(defaults, name)))
    return out


def _typed(kind):
    """A checker for a Clarabel field of Python type ``kind``."""
    def check(value):
        if kind is bool:
            return None if isinstance(value, bool) else "expected true or false"
        if kind is int:
            ok = isinstance(value, int) and not isinstance(value, bool) and 0 <= value < 2 ** 32
            return None if ok else "expected an integer from 0 to 4294967295"
        if kind is float:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool) and value >= 0
            return None if ok else "expected a number >= 0"
        if kind is str:
            return None if isinstance(value, str) else "expected a string"
        return None if isinstance(value, kind) else f"expected a {kind.__name__}"
    return check


def _picos_settings() -> dict:
    """PICOS's options: (name, type, default, doc[, check]) in ``OPTIONS``."""
    from picos.modeling.options import OPTIONS

    def checker(kind, test):
        kinds = kind if isinstance(kind, tuple) else (kind,)
        label = "/".join(getattr(k, "__name__", str(k)) for k in kinds)

        def check(value):
            typed = isinstance(value, kinds) and not (isinstance(value, bool) and bool not in kinds) \
                or (float in kinds and isinstance(value, int) and not isinstance(value, bool))
            if typed and isinstance(value, (int, float)) and not isinstance(value, bool) and value < 0:
                return "expected a number >= 0"       # counts, tolerances, time limits
            try:
                ok = typed and (test is None or test(value))
            except Exception:
                ok = False
            return None if ok else f"expected a valid {label}"
        return check
    return {o[0]: checker(o[1], o[4] if len(o) > 4 else None) for o in OPTIONS}


def check_solver_options(backend: str, solver: str, options: dict) -> None:
    """One line for an option ``backend:solver`` does not know or a value of the wrong type."""
    settings = solver_settings(backend, solver)
    for key, value in options.items():
        if backend == "cvxpy" and key in CVXPY_KEYWORDS:
            continue
        where = f"--solver-option {key}={_show(value)} ({backend}:{solver})"
        finite_value(value, where)
        if settings is None:
            continue
        if key not in settings:
            close = sorted(k for k in settings if k.split("_")[0] == key.split("_")[0])[:4]
            raise InputError(f"{where}: unknown option" + (f" (e.g. {', '.join(close)})" if close else ""))
        problem = settings[key](value)
        if problem:
            raise InputError(f"{where}: {problem}")


def _show(value) -> str:
    try:
        return json.dumps(value)
    except ValueError:
        return repr(value)


__all__ = ["check_solver_options", "finite_value", "solver_settings"]
