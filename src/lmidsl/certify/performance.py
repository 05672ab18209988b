"""The headline performance as a function of the theorem's objective, proved monotone where it
matters and evaluated in ball arithmetic.

A theorem minimises an objective g and reports a performance p = f(g): γ = √g, g itself, c·g, ν
for ``min −ν`` (a maximisation), √β, 1/δ, ...  :func:`objective_map` derives f from the theorem's
declaration (the performance with the objective replaced by the level; a performance that is a
variable of the objective is solved for: ν = −level).  The optimum g* lies in [L, U], L a proved
lower bound on the objective (the dual bound) and U the objective at a proved feasible point, and

* f non-decreasing on [L, U] (side ``"lower"``): p* ∈ [f(L)↓, f(U)↑];
* f non-increasing on [L, U] (side ``"upper"``, a maximised performance): p* ∈ [f(U)↓, f(L)↑];

(↓, ↑: the ball's lower and upper ends, rounded outwards).  Monotonicity is *proved* on the
interval: f' is enclosed in interval arithmetic (python-flint ``arb``) on [L, U], split into pieces
where one ball is too wide, and f must be real and finite there.  Without one of the ends the
interval is unbounded — (−∞, U] with no lower bound, [L, ∞) with no proved point — and f must be
continuous on it with a derivative of one sign (sympy's ``continuous_domain``,
``is_increasing``/``is_decreasing``).  A map not proved monotone gives no bracket; nothing is
clamped.  The one convention: γ = √g is the non-negative root, so its lower end is √max(L, 0).

Everything is derived from the content of the theorem (its performance and objective
expressions and the parameter values), never from the theorem object: a theorem changed after a
solve (``minimize`` again in a notebook) is mapped afresh.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
from flint import arb
from sympy.calculus.util import continuous_domain

from ..numeric.proof import ball_precision, round_down, round_up

_LEVEL = sp.Symbol("level_", real=True)
#: pieces of [L, U] the derivative is enclosed on, at most (split in halves while inconclusive)
MAX_PIECES = 256


class _NoBall(ValueError):
    """An expression python-flint's balls do not evaluate."""


def _ball(expr, level: arb) -> arb:
    """``expr`` (numbers and the level only) in ball arithmetic, the level a ball."""
    if expr == _LEVEL:
        return level
    if expr.is_Integer:
        return arb(int(expr))
    if expr.is_Rational:
        return arb(int(expr.p)) / arb(int(expr.q))
    if expr.is_Float:
        return arb(str(expr))
    if expr == sp.pi:
        return arb.pi()
    if expr == sp.E:
        return arb(1).exp()
    args = [_ball(a, level) for a in expr.args]
    if expr.is_Add:
        return sum(args[1:], args[0])
    if expr.is_Mul:
        out = args[0]
        for a in args[1:]:
            out = out * a
        return out
    if expr.is_Pow:
        base, exponent = args
        e = expr.args[1]
        if e.is_Integer:
            return base ** int(e)
        if e == sp.Rational(1, 2):
            return base.sqrt()
        return (exponent * base.log()).exp()
    functions = {sp.exp: arb.exp, sp.log: arb.log, sp.Abs: abs, sp.sin: arb.sin, sp.cos: arb.cos}
    if expr.func in functions and len(args) == 1:
        return functions[expr.func](args[0])
    raise _NoBall(f"no ball rule for {expr.func.__name__}")


def _interval(lo: float, hi: float) -> arb:
    """A ball containing [lo, hi]."""
    return arb(lo).union(arb(hi))


def _finite(x: arb) -> bool:
    return x.is_finite() and not x.is_nan() if hasattr(x, "is_nan") else x.is_finite()


@dataclass(frozen=True)
class ObjectiveMap:
    """p = f(level) for a theorem's objective; ``kind`` "identity", "sqrt" (γ = √g) or "general"."""

    f: sp.Expr
    derivative: sp.Expr
    kind: str

    def side(self, lower: float | None, upper: float | None) -> str | None:
        """"lower" (f non-decreasing), "upper" (non-increasing) proved on [lower, upper] (an end
        None: unbounded that way), or None when not proved."""
        if self.kind in ("identity", "sqrt"):
            return "lower"
        if _LEVEL not in self.derivative.free_symbols:
            with ball_precision(128):
                try:
                    d = _ball(self.derivative, arb(0))
                except _NoBall:
                    return None
                return "lower" if d >= 0 else ("upper" if d <= 0 else None)
        if lower is None or upper is None or not (math.isfinite(lower) and math.isfinite(upper)):
            return _sympy_side(self.f, lower, upper)
        return _ball_side(self.f, self.derivative, lower, upper)

    def value(self, level: float, direction: str) -> float | None:
        """f(level) rounded ``direction`` ("down" or "up"), or None when f is not real there."""
        if self.kind == "identity":
            return level
        if self.kind == "sqrt" and level <= 0:
            return 0.0
        with ball_precision(128):
            try:
                v = _ball(self.f, arb(level))
            except (_NoBall, ZeroDivisionError, ValueError):
                return None
            if not _finite(v):
                return None
            if direction == "down":
                return round_down(float(v.lower()))
            return round_up(float(v.upper()))


def _ball_side(f, derivative, lower: float, upper: float) -> str | None:
    """The sign of f' on [lower, upper], proved piece by piece; f real and finite there."""
    signs = set()
    pieces = [(lower, upper)]
    done = 0
    with ball_precision(128):
        while pieces:
            a, b = pieces.pop()
            try:
                d = _ball(derivative, _interval(a, b))
                v = _ball(f, _interval(a, b))
            except (_NoBall, ZeroDivisionError, ValueError):
                return None
            if _finite(d) and _finite(v) and (d >= 0 or d <= 0):
                signs.add("lower" if d >= 0 else "upper")
                done += 1
                if len(signs) > 1:
                    return None
                continue
            if len(pieces) + done >= MAX_PIECES or not b > a:
                return None
            middle = a + (b - a) / 2
            if not a < middle < b:
                return None
            pieces += [(a, middle), (middle, b)]
    return signs.pop() if signs else None


@lru_cache(maxsize=512)
def _sympy_side(f, lower: float | None, upper: float | None) -> str | None:
    """The sign of f' on an unbounded interval, by sympy: f continuous on all of it, then
    ``is_increasing`` / ``is_decreasing``."""
    lo = -sp.oo if lower is None or not math.isfinite(lower) else sp.Rational(lower)
    hi = sp.oo if upper is None or not math.isfinite(upper) else sp.Rational(upper)
    if not lo < hi:
        return None
    interval = sp.Interval(lo, hi)
    try:
        if continuous_domain(f, _LEVEL, interval) != interval:
            return None
        if sp.is_increasing(f, interval, _LEVEL):
            return "lower"
        if sp.is_decreasing(f, interval, _LEVEL):
            return "upper"
    except (NotImplementedError, TypeError, ValueError):
        return None
    return None


def _params_key(params: dict) -> tuple:
    return tuple(sorted((k, v) for k, v in params.items() if isinstance(v, (int, float))))


def objective_map(theorem, params: dict) -> ObjectiveMap | None:
    """The performance as a function of the objective's value (module docstring), or None (no
    objective or performance, or a performance that is not a function of the objective alone)."""
    if theorem is None or theorem.performance is None or theorem.objective is None:
        return None
    return _objective_map(theorem.performance[1], theorem.objective, _params_key(params))


@lru_cache(maxsize=256)
def _objective_map(perf, obj, params: tuple) -> ObjectiveMap | None:
    if perf == obj:
        return ObjectiveMap(_LEVEL, sp.Integer(1), "identity")
    if perf == sp.sqrt(obj):
        return ObjectiveMap(sp.sqrt(_LEVEL), 1 / (2 * sp.sqrt(_LEVEL)), "sqrt")
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
    expr = expr.xreplace({s: sp.Rational(repr(float(values[s.name]))) for s in free})
    if _LEVEL not in expr.free_symbols and expr.free_symbols:
        return None
    return ObjectiveMap(expr, sp.diff(expr, _LEVEL), "general")


def performance_side(theorem, params: dict, lower: float | None = None, upper: float | None = None) -> str | None:
    """"lower" when the performance is proved non-decreasing in the objective on [lower, upper]
    (a dual bound bounds it from below), "upper" when non-increasing (a maximisation), None when
    neither is proved."""
    found = objective_map(theorem, params)
    return None if found is None else found.side(lower, upper)


def performance_bound(theorem, params: dict, lower: float, upper: float | None = None) -> tuple[float, str] | None:
    """The performance at a proved lower bound ``lower`` on the objective, and which side of the
    optimum's performance it bounds: ("lower", f(lower)↓) when f is proved non-decreasing on
    [lower, upper] (``upper``: the objective at a proved feasible point, or None), ("upper",
    f(lower)↑) when non-increasing; None when neither is proved or f(lower) is not real."""
    found = objective_map(theorem, params)
    if found is None:
        return None
    side = found.side(lower, upper)
    if side is None:
        return None
    value = found.value(lower, "down" if side == "lower" else "up")
    return None if value is None else (value, side)


def performance_lower(theorem, params: dict, lower: float, upper: float | None = None) -> float | None:
    """The proved lower bound on the performance at objective ``lower`` (an increasing map), or None."""
    found = performance_bound(theorem, params, lower, upper)
    return found[0] if found is not None and found[1] == "lower" else None


__all__ = ["ObjectiveMap", "objective_map", "performance_side", "performance_bound", "performance_lower"]
