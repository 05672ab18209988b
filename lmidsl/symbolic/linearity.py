"""Symbolic linearity check: an LMI block must be affine in the decision variables.

The degree of an expression in the decision variables is computed on the expression tree:
a product adds degrees, a sum takes the largest, a transpose keeps it, the inverse of an
expression that contains a decision variable is not affine at all.  Parameters and data may
multiply variables freely.
"""
from __future__ import annotations

import sympy as sp
from sympy.matrices.expressions.matexpr import MatrixExpr

from ..errors import NonlinearityError
from .symbols import DECISION_TYPES
from .uncertainty import uncertain_atoms


def _is_counted(expr, kinds) -> bool:
    """``kinds`` is a tuple of symbol classes or a set of particular symbols."""
    if isinstance(kinds, (set, frozenset)):
        return expr in kinds
    return isinstance(expr, kinds)


def _decision_atoms(expr, kinds=DECISION_TYPES) -> list:
    return sorted({a for a in expr.atoms(sp.Symbol, sp.MatrixSymbol) if _is_counted(a, kinds)},
                  key=str)


def degree(expr, kinds=DECISION_TYPES) -> int:
    """Degree of ``expr`` in the symbols of ``kinds`` (default: the decision variables).

    ``kinds`` is a tuple of classes or a set of symbols.  Raises on an inverse of such a symbol.
    """
    if _is_counted(expr, kinds):
        return 1
    if isinstance(expr, (sp.MatrixSymbol, sp.Number, sp.Symbol)) or not expr.args:
        return 0
    if isinstance(expr, (sp.MatMul, sp.Mul, sp.HadamardProduct)):
        return sum(degree(a, kinds) for a in expr.args)
    if isinstance(expr, (sp.MatAdd, sp.Add, sp.BlockMatrix)):
        parts = expr.blocks if isinstance(expr, sp.BlockMatrix) else expr.args
        return max((degree(a, kinds) for a in parts), default=0)
    if isinstance(expr, sp.Transpose):
        return degree(expr.arg, kinds)
    if isinstance(expr, sp.Inverse):
        if degree(expr.arg, kinds) > 0:
            raise NonlinearityError(
                f"{expr} is the inverse of an expression in the decision variables "
                f"{', '.join(map(str, _decision_atoms(expr.arg, kinds)))}")
        return 0
    if isinstance(expr, (sp.MatPow, sp.Pow)):
        base, exp = expr.args
        d = degree(base, kinds)
        if d == 0:
            if degree(exp, kinds) > 0:
                raise NonlinearityError(f"{expr} has a decision variable in an exponent")
            return 0
        if exp.is_Integer and exp >= 0:
            return d * int(exp)
        raise NonlinearityError(f"{expr} is a non-integer or negative power of a decision variable")
    if any(degree(a, kinds) > 0 for a in expr.args if isinstance(a, (sp.Expr, MatrixExpr))):
        raise NonlinearityError(f"{expr} applies {type(expr).__name__} to a decision variable")
    return 0


def _nonlinear_culprit(expr):
    """The smallest product/power in ``expr`` whose degree exceeds one."""
    best = None
    for sub in sp.postorder_traversal(expr):
        if isinstance(sub, (sp.MatMul, sp.Mul, sp.MatPow, sp.Pow)):
            try:
                if degree(sub) > 1:
                    best = sub
                    break
            except NonlinearityError:
                best = sub
                break
    return best


def check_affine(expr) -> None:
    """Raise :class:`NonlinearityError` unless ``expr`` is affine in the decision variables
    and affine in each uncertain symbol (the vertex argument of :mod:`lmidsl.symbolic.uncertainty`)."""
    for u in uncertain_atoms(expr):
        if degree(expr, {u}) > 1:
            raise NonlinearityError(f"{expr} is not affine in the uncertain {u}: its vertices would not cover the box")
    d = degree(expr)
    if d > 1:
        culprit = _nonlinear_culprit(expr) or expr
        names = ", ".join(map(str, _decision_atoms(culprit)))
        raise NonlinearityError(f"{culprit} is not affine: it multiplies the decision variables {names}")
