"""Shape arithmetic on symbolic dimensions.

Sympy does not validate products and sums whose dimensions are symbols (``n×n`` times
``k×k`` passes silently), so lmidsl checks conformance itself, structurally: two dimensions
are equal when their difference expands to zero.  With symbolic dimensions this catches
transcription errors in a theorem before any data exist.

The rules, one ``_visit_<Class>`` of :class:`ShapeWalker` each (shapes are (rows, cols); a
scalar is 1×1):

* a symbol (data, variable, its LaTeX-named kin), ``I_n``, ``0_{n×k}``, an explicit matrix: its
  declared shape;
* a product ``M₁ M₂ ⋯`` (scalar factors aside): the columns of each factor equal the rows of the
  next; the shape is rows(M₁) × cols(M_last);
* a sum: every term has the shape of the first;
* ``Mᵀ``: the shape swapped; ``M⁻¹`` and ``M^k``: M square;
* a block matrix: every block (i, j) has the rows of block (i, 1) and the columns of block (1, j);
* ``tr(M)``: M square, the trace is a scalar;
* scalar nodes (numbers, symbols, +, ·, powers, functions such as sqrt): 1×1, after checking
  the matrices inside them (a trace in a coefficient).

Any other node is refused (:meth:`~lmidsl.symbolic.walker.Walker.unknown`): a node the library
has no rule for would otherwise be accepted here and fail later, at compile time.
"""
from __future__ import annotations

import sympy as sp
from sympy.matrices.expressions.matexpr import MatrixExpr

from ..errors import ShapeMismatchError
from .indexed import count
from .walker import Walker

SCALAR = (1, 1)


def dims_equal(a, b) -> bool:
    """Structural equality of two dimension expressions."""
    return sp.expand(sp.sympify(a) - sp.sympify(b)) == 0


def fmt_shape(shape) -> str:
    return f"{shape[0]}×{shape[1]}"


class ShapeWalker(Walker):
    """The shape of an expression, every product, sum, block and trace in it checked."""

    action = "check the shape of"

    def mismatch(self, message: str):
        return self.error(ShapeMismatchError, message)

    def _square(self, arg, what: str):
        r, c = self.visit(arg)
        if not dims_equal(r, c):
            raise self.mismatch(what.format(arg=arg, shape=fmt_shape((r, c))))
        return (r, c)

    # -- matrix leaves ----------------------------------------------------------------
    def _visit_MatrixSymbol(self, expr):
        return expr.shape

    def _visit_Identity(self, expr):
        return expr.shape

    def _visit_ZeroMatrix(self, expr):
        return expr.shape

    def _visit_MatrixBase(self, expr):
        return expr.shape

    # -- matrix operations ------------------------------------------------------------
    def _visit_MatMul(self, expr):
        for a in expr.args:
            if not isinstance(a, MatrixExpr):
                self.visit(a)  # a scalar factor: check the matrices inside it (tr(W Z) P)
        matrices = [a for a in expr.args if isinstance(a, MatrixExpr)]
        shapes = [self.visit(a) for a in matrices]
        for (left, ls), (right, rs) in zip(zip(matrices, shapes), zip(matrices[1:], shapes[1:])):
            if not dims_equal(ls[1], rs[0]):
                raise self.mismatch(
                    f"product {left}·{right}: {left} is {fmt_shape(ls)} but {right} is {fmt_shape(rs)}")
        return (shapes[0][0], shapes[-1][1]) if shapes else SCALAR

    def _visit_MatAdd(self, expr):
        terms = list(expr.args)
        shapes = [self.visit(a) for a in terms]
        for term, shape in zip(terms[1:], shapes[1:]):
            if not (dims_equal(shape[0], shapes[0][0]) and dims_equal(shape[1], shapes[0][1])):
                raise self.mismatch(
                    f"sum {expr}: term {terms[0]} is {fmt_shape(shapes[0])} but {term} is {fmt_shape(shape)}")
        return shapes[0]

    def _visit_Transpose(self, expr):
        r, c = self.visit(expr.arg)
        return (c, r)

    def _visit_Inverse(self, expr):
        return self._square(expr.arg, "inverse of {arg}, which is {shape}")

    def _visit_MatPow(self, expr):
        return self._square(expr.base, "power of non-square {arg} ({shape})")

    def _visit_BlockMatrix(self, expr):  # BlockDiagMatrix too (a subclass)
        blocks = expr.blocks
        for i in range(blocks.rows):
            for j in range(blocks.cols):
                s = self.visit(blocks[i, j])
                if not dims_equal(s[0], blocks[i, 0].shape[0]) or not dims_equal(s[1], blocks[0, j].shape[1]):
                    raise self.mismatch(
                        f"block matrix {expr}: block ({i + 1},{j + 1}) {blocks[i, j]} is {fmt_shape(s)}")
        return expr.shape

    # -- over an index (symbolic/indexed.py) -----------------------------------------------------
    def _index_op(self, expr):
        """Σ, stack, diag over an index: the body's shape may not depend on the index."""
        r, c = self.visit(expr.body)
        if expr.index in (sp.sympify(r).free_symbols | sp.sympify(c).free_symbols):
            raise self.mismatch(f"{expr}: the shape of {expr.body} depends on the index {expr.index}")
        if expr.condition is not None:
            count(expr.index, expr.size, expr.condition)   # a range the library can count
        return expr.shape

    _visit_IndexSum = _visit_IndexStack = _visit_IndexDiag = _index_op

    def _visit_Coefficient(self, expr):   # π_ij, a scalar
        return SCALAR

    def _visit_MatrixElement(self, expr):  # M[a, b] of a matrix, a scalar
        self.visit(expr.parent)
        return SCALAR

    # -- matrix to scalar -----------------------------------------------------------------
    def _visit_Trace(self, expr):
        self._square(expr.arg, "trace of {arg}, which is {shape}")
        return SCALAR

    # -- scalars --------------------------------------------------------------------------
    def _visit_Atom(self, expr):  # numbers, scalar symbols (variables, parameters, dimensions)
        return SCALAR

    def _scalar_op(self, expr):
        for a in expr.args:
            self.visit(a)
        return SCALAR

    _visit_Add = _visit_Mul = _visit_Pow = _scalar_op
    _visit_Application = _scalar_op  # sqrt, exp, Abs, Max, ... of scalars


def check_conformance(expr, where: str = "") -> tuple:
    """Return the shape of a matrix expression after checking every product and sum in it.

    Raises :class:`ShapeMismatchError` naming the offending sub-expression and shapes, and
    :class:`~lmidsl.errors.TheoremDefinitionError` for a node lmidsl has no rule for; ``where``
    (theorem, LMI, block) prefixes the message.
    """
    return ShapeWalker(where).visit(sp.sympify(expr))
