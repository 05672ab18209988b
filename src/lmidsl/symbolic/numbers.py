"""Numbers given by the user, checked in one place: finite reals, no silent conversion.

JSON and Python both let strings, booleans and ``NaN``/``Infinity`` pass where a number is meant
(``numpy.array([["1"], [True]], dtype=float)`` converts both); lmidsl refuses them with one line
naming the datum, so a typo never becomes a number.  Used by the binding layer
(:mod:`lmidsl.numeric.instance`) for data, parameters, dimensions and uncertainty points, and for
designs given to ``verify``.
"""
from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import InputError


def is_real_number(value) -> bool:
    """A real number that is not a boolean (Python or numpy)."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def finite_number(value, what: str) -> float:
    """``value`` as a float, or a one-line error naming ``what``."""
    if not is_real_number(value):
        raise InputError(f"{what} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"{what} must be a finite number, got {value}")
    return value


def positive_integer(value, what: str) -> int:
    """``value`` as an int >= 1 (an integer-valued float such as 2.0 is refused: dimensions are
    counts), or a one-line error naming ``what``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral) or value < 1:
        raise InputError(f"{what} must be a positive integer, got {value!r}")
    return int(value)


def _leaf_problem(value, index: str):
    """The first entry of a nested list that is not a finite real number: (index, text) or None."""
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "iuf":
            if value.dtype.kind == "f" and not np.all(np.isfinite(value)):
                bad = tuple(int(i) for i in np.argwhere(~np.isfinite(value))[0])
                return index + "".join(f"[{i}]" for i in bad), "not finite"
            return None
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            problem = _leaf_problem(item, f"{index}[{i}]")
            if problem:
                return problem
        return None
    if not is_real_number(value):
        kind = "a boolean" if isinstance(value, (bool, np.bool_)) else \
            "a string" if isinstance(value, str) else type(value).__name__
        return index, f"{kind} ({value!r}), not a number"
    if not math.isfinite(float(value)):
        return index, f"{value}, not finite"
    return None


def finite_matrix(value, what: str) -> np.ndarray:
    """A 2-d float array of finite real numbers from a number or nested lists, or a one-line
    error naming ``what`` and the entry at fault (ragged rows, strings, booleans, NaN, ∞)."""
    if is_real_number(value):
        return np.array([[finite_number(value, what)]])
    problem = _leaf_problem(value, "")
    if problem:
        raise InputError(f"{what}: entry {problem[0] or ''} is {problem[1]}".replace("entry  is", "is"))
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{what} is not a numeric matrix (rows of different lengths?): "
                         f"{_short(value)}") from None
    if arr.ndim != 2:
        raise InputError(f"{what} must be a matrix given as nested lists (got {arr.ndim}-d "
                         f"{list(arr.shape)}); write a column as [[0],[1]]")
    return arr


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."
