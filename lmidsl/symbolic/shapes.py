"""Shape arithmetic on symbolic dimensions.

Sympy does not validate products and sums whose dimensions are symbols (``n×n`` times
``k×k`` passes silently), so lmidsl checks conformance itself, structurally: two dimensions
are equal when their difference expands to zero.  With symbolic dimensions this catches
transcription errors in a theorem before any data exist.
"""
from __future__ import annotations

import sympy as sp
from sympy.matrices.expressions.matexpr import MatrixExpr

from ..errors import ShapeMismatchError


def dims_equal(a, b) -> bool:
    """Structural equality of two dimension expressions."""
    return sp.expand(sp.sympify(a) - sp.sympify(b)) == 0


def fmt_shape(shape) -> str:
    return f"{shape[0]}×{shape[1]}"


def check_conformance(expr) -> tuple:
    """Return the shape of a matrix expression after checking every product and sum in it.

    Raises :class:`ShapeMismatchError` naming the offending sub-expression and shapes.
    """
    if not isinstance(expr, MatrixExpr):
        return (1, 1)
    if isinstance(expr, sp.MatMul):
        matrices = [a for a in expr.args if isinstance(a, MatrixExpr)]
        shapes = [check_conformance(a) for a in matrices]
        for (left, ls), (right, rs) in zip(zip(matrices, shapes), zip(matrices[1:], shapes[1:])):
            if not dims_equal(ls[1], rs[0]):
                raise ShapeMismatchError(
                    f"product {left}·{right}: {left} is {fmt_shape(ls)} but {right} is {fmt_shape(rs)}")
        return (shapes[0][0], shapes[-1][1]) if shapes else (1, 1)
    if isinstance(expr, sp.MatAdd):
        terms = list(expr.args)
        shapes = [check_conformance(a) for a in terms]
        for term, shape in zip(terms[1:], shapes[1:]):
            if not (dims_equal(shape[0], shapes[0][0]) and dims_equal(shape[1], shapes[0][1])):
                raise ShapeMismatchError(
                    f"sum {expr}: term {terms[0]} is {fmt_shape(shapes[0])} but {term} is {fmt_shape(shape)}")
        return shapes[0]
    if isinstance(expr, sp.Transpose):
        r, c = check_conformance(expr.arg)
        return (c, r)
    if isinstance(expr, sp.Inverse):
        r, c = check_conformance(expr.arg)
        if not dims_equal(r, c):
            raise ShapeMismatchError(f"inverse of {expr.arg}, which is {fmt_shape((r, c))}")
        return (r, c)
    if isinstance(expr, sp.BlockMatrix):
        blocks = expr.blocks
        for i in range(blocks.rows):
            for j in range(blocks.cols):
                s = check_conformance(blocks[i, j])
                if not dims_equal(s[0], blocks[i, 0].shape[0]) or not dims_equal(s[1], blocks[0, j].shape[1]):
                    raise ShapeMismatchError(
                        f"block matrix {expr}: block ({i + 1},{j + 1}) {blocks[i, j]} is {fmt_shape(s)}")
        return expr.shape
    if isinstance(expr, sp.MatPow):
        r, c = check_conformance(expr.base)
        if not dims_equal(r, c):
            raise ShapeMismatchError(f"power of non-square {expr.base} ({fmt_shape((r, c))})")
        return (r, c)
    return expr.shape
