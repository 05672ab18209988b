"""The headline performance as a function of the theorem's objective: its direction, and its value
at a proved bound on the objective.

A theorem minimises an objective g and reports a performance p(g): γ = √g, g itself, c·g, or ν for
``min −ν`` (a maximisation).  A proved lower bound g ≥ L on the optimum becomes

* p ≥ p(L) (rounded down) when p is non-decreasing in g — side ``"lower"``;
* p ≤ p(L) (rounded up) when p is non-increasing — side ``"upper"`` (the optimum's point is then
  the lower end of the performance's bracket, the dual bound its upper end).

The direction is a property of the theorem and its parameters, known with or without a bound:
:func:`performance_side` orients the bracket (:func:`lmidsl.solver.verdict.bracket`) and
:func:`performance_bound` maps the dual bound (:mod:`lmidsl.solver.dual_bound`).
"""
from __future__ import annotations

import math
from functools import lru_cache

import sympy as sp
from flint import arb

from ..numeric.proof import ball_precision, round_down, round_up

_LEVEL = sp.Symbol("level_", real=True)


@lru_cache(maxsize=256)
def _as_function_of_objective(theorem, params: tuple):
    """(p as an expression in the objective's value ``level_``, side) or None when p is not shown
    monotone in it.  A performance that is a variable of the objective is solved for (ν = −level)."""
    if theorem.performance is None or theorem.objective is None:
        return None
    perf, obj = theorem.performance[1], theorem.objective
    values = dict(params)
    expr = perf.xreplace({obj: _LEVEL})
    unknown = [s for s in expr.free_symbols - {_LEVEL} if s.name not in values]
    if len(unknown) == 1 and unknown[0] in obj.free_symbols:
        solved = sp.solve(sp.Eq(obj, _LEVEL), unknown[0])
        if len(solved) != 1:
            return None
        expr = expr.xreplace({unknown[0]: solved[0]})
    free = expr.free_symbols - {_LEVEL}
    if any(s.name not in values for s in free):
        return None
    expr = expr.xreplace({s: values[s.name] for s in free})
    derivative = sp.diff(expr, _LEVEL)
    if derivative.is_nonnegative or sp.simplify(derivative).is_nonnegative:
        return expr, "lower"
    if derivative.is_nonpositive or sp.simplify(derivative).is_nonpositive:
        return expr, "upper"
    return None


def _key(params: dict) -> tuple:
    return tuple(sorted((k, v) for k, v in params.items() if isinstance(v, (int, float))))


def performance_side(theorem, params: dict) -> str | None:
    """"lower" when the performance is non-decreasing in the objective (a dual bound bounds it from
    below), "upper" when non-increasing (a maximisation), None when neither is shown."""
    if theorem.performance is not None and theorem.objective is not None:
        perf, obj = theorem.performance[1], theorem.objective
        if perf == obj or perf == sp.sqrt(obj):
            return "lower"
    found = _as_function_of_objective(theorem, _key(params))
    return None if found is None else found[1]


def performance_bound(theorem, params: dict, lower: float) -> tuple[float, str] | None:
    """The headline performance at objective value ``lower`` and which side of the best
    performance it bounds: ("lower", value rounded down) when the performance is a non-decreasing
    function of the objective (√g, g, c·g with c ≥ 0), ("upper", value rounded up) when it is
    non-increasing (a maximisation written min −ν with performance ν); None when neither is
    shown."""
    if theorem.performance is None or theorem.objective is None:
        return None
    perf, obj = theorem.performance[1], theorem.objective
    with ball_precision(128):
        if perf == obj:
            return lower, "lower"
        if perf == sp.sqrt(obj):
            return (round_down(float(arb(lower).sqrt().lower())) if lower > 0 else 0.0), "lower"
    found = _as_function_of_objective(theorem, _key(params))
    if found is None:
        return None
    expr, side = found
    value = complex(sp.N(expr.xreplace({_LEVEL: max(lower, 0.0) if side == "lower" else lower}), 30))
    if value.imag != 0 or not math.isfinite(value.real):
        return None
    v = value.real
    if side == "lower":
        return round_down(v * (1 - 1e-15) if v > 0 else v * (1 + 1e-15), 4), side
    return round_up(v * (1 + 1e-15) if v > 0 else v * (1 - 1e-15), 4), side


def performance_lower(theorem, params: dict, lower: float) -> float | None:
    """The proved lower bound on the performance at objective ``lower`` (an increasing map), or None."""
    found = performance_bound(theorem, params, lower)
    return found[0] if found is not None and found[1] == "lower" else None


__all__ = ["performance_side", "performance_bound", "performance_lower"]
