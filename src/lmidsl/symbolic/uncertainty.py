"""Uncertain scalars and matrices that enter an LMI affinely, expanded to their vertices.

A theorem declares an uncertain quantity once, with its bound::

    Delta = thm.uncertain("Delta", bound=beta)          # scalar, |Δ| ≤ β
    Dm = thm.uncertain("Dm", 2, 2, bound=b)             # matrix, |Δ_ij| ≤ b (box)

and writes its LMIs with ``Delta`` as with any other symbol.  Every block must be affine in
each uncertain symbol (checked when the LMI is declared, see :mod:`lmidsl.symbolic.linearity`).  An LMI
``N(Δ) ≺ 0`` that is (multi-)affine in Δ holds on the whole box ``|Δ| ≤ bound`` if and only if
it holds at the vertices with the same decision variables, because N(Δ) is a convex combination
of its vertex values.  The library therefore imposes each LMI that mentions Δ once per vertex
(per *scenario*: polytope vertex × uncertainty vertex), with common variables.

Points are given in units of the bound: Δ = c·bound with c ∈ [−1, 1] (a scalar), or
Δ = bound·C with the entries of C in [−1, 1] (a matrix).  By default all vertices are used
(c ∈ {−1, +1}; for a matrix every sign pattern on its ``pattern``); an instance may choose
other points, e.g. ``Delta=[1]`` (the upper vertex only) or ``Delta=[0]`` (nominal), and
interior points are allowed (then the LMI is evaluated there, not on the whole box).

The substitution Δ → c·bound is symbolic, so a bound that is a parameter expression
(β = (1 − ρ)/(1 + ρ)) stays a backend parameter and can be swept without recompiling.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from .numbers import finite_matrix, is_real_number
from ..errors import InputError, TheoremDefinitionError
from .blocks import BlockMatrixSpec
from .symbols import _TaggedMatrix, _TaggedScalar, _meta_property


class UncertainScalar(_TaggedScalar):
    """An uncertain scalar |Δ| ≤ bound; substituted by its vertex values before compiling."""

    kind = "uncertain"
    bound = _meta_property("bound")


class UncertainMatrix(_TaggedMatrix):
    """An uncertain matrix with entries |Δ_ij| ≤ bound on ``pattern`` (zero elsewhere)."""

    kind = "uncertain"
    bound = _meta_property("bound")
    pattern = _meta_property("pattern")


UNCERTAIN_TYPES = (UncertainScalar, UncertainMatrix)


def uncertain_atoms(expr) -> list:
    """The uncertain symbols in an expression, sorted by name."""
    return sorted({a for a in expr.atoms(sp.Symbol, sp.MatrixSymbol) if isinstance(a, UNCERTAIN_TYPES)},
                  key=lambda s: s.name)


def uncertain_symbol(theorem_id: str, name: str, rows=None, cols=None, *, bound, pattern=None,
                     latex: str | None = None, description: str = ""):
    """A new uncertain scalar (``rows`` None) or matrix symbol |Δ_ij| ≤ bound on ``pattern``."""
    bound = sp.sympify(bound)
    if rows is None:
        symbol = UncertainScalar(name, theorem_id)
        if pattern is not None:
            raise TheoremDefinitionError(f"{theorem_id}: uncertain scalar {name} takes no pattern")
    else:
        cols = rows if cols is None else cols
        try:
            shape = (int(rows), int(cols))
        except TypeError:
            raise TheoremDefinitionError(
                f"{theorem_id}: uncertain matrix {name} needs integer dimensions (its vertices are enumerated)") from None
        symbol = UncertainMatrix(name, *shape, theorem_id)
        pattern = np.ones(shape) if pattern is None else np.asarray(pattern, dtype=float)
        if pattern.shape != shape or not np.all(np.isin(pattern, (0.0, 1.0))):
            raise TheoremDefinitionError(f"{theorem_id}: pattern of {name} must be a {shape} 0/1 matrix")
        symbol.pattern = pattern
    symbol.bound = bound
    symbol.latex_name = latex or name
    symbol.description = description
    return symbol


def vertices(symbol) -> list:
    """All vertices of the box, in units of the bound."""
    if isinstance(symbol, UncertainScalar):
        return [-1.0, 1.0]
    support = list(zip(*np.nonzero(symbol.pattern)))
    out = []
    for signs in itertools.product((-1.0, 1.0), repeat=len(support)):
        C = np.zeros(symbol.pattern.shape)
        for (i, j), s in zip(support, signs):
            C[i, j] = s
        out.append(C)
    return out


def parse_points(theorem, decl, value) -> list:
    """The points (units of the bound) an instance asks for; ``None``/'vertices' = all vertices."""
    symbol = decl.symbol
    name = symbol.name
    if value is None:
        value = decl.extra.get("points")
    if value is None or (isinstance(value, str) and value == "vertices"):
        return vertices(symbol)
    if isinstance(symbol, UncertainScalar):
        items = value if isinstance(value, (list, tuple)) else [value]
        points = []
        for c in items:
            if not is_real_number(c) or not math.isfinite(c):
                raise InputError(f"{theorem.id}: uncertain {name}: points are numbers in units of the bound, "
                                 f"e.g. [-1, 1], got {c!r}")
            if abs(c) > 1 + 1e-12:
                raise InputError(f"{theorem.id}: uncertain {name}: point {c} lies outside [-1, 1] (units of the bound)")
            points.append(float(c))
    else:
        items = value if isinstance(value, list) and value and isinstance(value[0], list) and \
            isinstance(value[0][0], list) else [value]
        points = []
        for C in items:
            C = finite_matrix(C, f"{theorem.id}: uncertain {name}: a point")
            if C.shape != symbol.pattern.shape:
                raise InputError(f"{theorem.id}: uncertain {name}: point is {C.shape}, must be {symbol.pattern.shape}")
            if np.any(np.abs(C) > 1 + 1e-12) or np.any((symbol.pattern == 0) & (C != 0)):
                raise InputError(f"{theorem.id}: uncertain {name}: point outside the box (units of the bound)")
            points.append(C)
    if not points:
        raise InputError(f"{theorem.id}: uncertain {name}: no points given")
    return points


def substitute_value(symbol, point):
    """The sympy expression that replaces ``symbol`` at ``point`` (units of the bound)."""
    if isinstance(symbol, UncertainScalar):
        c = sp.Float(point) if point not in (-1.0, 0.0, 1.0) else sp.Integer(int(point))
        return c * symbol.bound
    return sp.MatMul(symbol.bound, sp.ImmutableMatrix(np.asarray(point).tolist()))


def describe_point(symbol, point) -> str:
    if isinstance(symbol, UncertainScalar):
        return f"{symbol.name}={point:+g}*{symbol.bound}"
    return f"{symbol.name}={symbol.bound}*{np.asarray(point).tolist()}"


@dataclass
class Scenario:
    """One copy of an LMI: a polytope vertex (or None) and values for its uncertain symbols."""

    vertex: int | None = None
    subs: dict = field(default_factory=dict)
    label: str = ""

    def apply(self, expr):
        return expr.xreplace(self.subs) if self.subs else expr


def scenarios(instance, lmi) -> list[Scenario]:
    """Every (polytope vertex × uncertainty point) at which ``lmi`` is imposed."""
    vertex_list = list(range(instance.nvertices)) if lmi.per_vertex else [None]
    symbols = [s for s in uncertain_atoms_of_lmi(lmi)]
    axes = [[(s, p) for p in instance.uncertain.get(s.name, vertices(s))] for s in symbols]
    out = []
    for v in vertex_list:
        for combo in itertools.product(*axes):
            subs = {s: substitute_value(s, p) for s, p in combo}
            label = ", ".join(describe_point(s, p) for s, p in combo)
            out.append(Scenario(v, subs, label))
    return out


def uncertain_atoms_of_lmi(lmi) -> list:
    return sorted({s for s in lmi.symbols() if isinstance(s, UNCERTAIN_TYPES)}, key=lambda s: s.name)


def spec_at(spec, scenario: Scenario):
    """The block matrix spec with the scenario's substitution applied to every block."""
    if not scenario.subs:
        return spec
    return BlockMatrixSpec([[scenario.apply(b) for b in row] for row in spec.lower], spec.sizes,
                           spec.given_as)


def bind_points(theorem, inputs: dict) -> dict:
    """Points per uncertain symbol for an instance (``inputs`` entries are consumed)."""
    out = {}
    for name, decl in getattr(theorem, "uncertain_decl", {}).items():
        out[name] = parse_points(theorem, decl, inputs.pop(name, None))
    return out
