"""Symbolic linearity check: an LMI block must be affine in the decision variables.

The degree of an expression in the decision variables is computed on the expression tree, one
``_visit_<Class>`` of :class:`DegreeWalker` per rule:

* a decision variable (full, symmetric, diagonal, structured, scalar) has degree 1; data,
  parameters, dimensions, numbers, ``I`` and ``0`` degree 0 -- so parameters and data may
  multiply variables freely (``r̄ A P`` is affine in P);
* a product (``MatMul``, ``Mul``, Hadamard) adds the degrees of its factors: the product of two
  decision-variable factors (``P V``, ``g·g``) has degree 2;
* a sum and a block matrix take the largest degree of their terms / blocks;
* a transpose and a trace keep the degree (``tr(M)`` is linear in M, so ``tr(W Z)`` is affine
  in Z when W is data);
* the inverse of an expression containing a decision variable is not affine at all (an error,
  whatever the degree); the inverse of data is degree 0;
* a power ``M^k`` of an expression of degree d > 0 has degree k·d for an integer k ≥ 0; a negative
  or non-integer power of a decision variable is an error, and so is a decision variable in an
  exponent;
* any other function (sqrt, exp, ...) of a decision variable is an error; of constants, degree 0.

The same walk counts the degree in one uncertain symbol (``kinds`` a set of symbols): an
uncertain symbol must enter every LMI affinely, so that imposing the LMI at the vertices of its
box covers the whole box (:mod:`lmidsl.symbolic.uncertainty`).

A node the walker has no rule for is refused (:meth:`~lmidsl.symbolic.walker.Walker.unknown`).
"""
from __future__ import annotations

import sympy as sp
from sympy.matrices.expressions.matexpr import MatrixExpr

from ..errors import NonlinearityError
from .symbols import DECISION_TYPES
from .uncertainty import uncertain_atoms
from .walker import Walker


def _is_counted(expr, kinds) -> bool:
    """``kinds`` is a tuple of symbol classes or a set of particular symbols."""
    if isinstance(kinds, (set, frozenset)):
        return expr in kinds
    return isinstance(expr, kinds)


def _decision_atoms(expr, kinds=DECISION_TYPES) -> list:
    return sorted({a for a in expr.atoms(sp.Symbol, sp.MatrixSymbol) if _is_counted(a, kinds)},
                  key=str)


class DegreeWalker(Walker):
    """The degree of an expression in the symbols of ``kinds`` (default: the decision variables).

    ``kinds`` is a tuple of classes or a set of symbols.  Raises :class:`NonlinearityError` on
    an inverse or a function of such a symbol.
    """

    action = "check the linearity of"

    def __init__(self, kinds=DECISION_TYPES, where: str = ""):
        super().__init__(where)
        self.kinds = kinds

    def nonlinear(self, message: str):
        return self.error(NonlinearityError, message)

    # -- leaves -------------------------------------------------------------------------
    def _symbol(self, expr):
        return 1 if _is_counted(expr, self.kinds) else 0

    _visit_MatrixSymbol = _symbol   # data, variables, structured, uncertain matrices
    _visit_Symbol = _symbol         # scalar variables, parameters, dimensions, uncertain scalars

    def _constant(self, expr):
        return 0

    _visit_Atom = _constant         # numbers and the other argument-free nodes
    _visit_Identity = _visit_ZeroMatrix = _constant

    def _visit_MatrixBase(self, expr):  # an explicit matrix: its entries
        return max((self.visit(e) for e in expr), default=0)

    # -- products, sums, blocks --------------------------------------------------------------
    def _product(self, expr):
        return sum(self.visit(a) for a in expr.args)

    _visit_MatMul = _visit_Mul = _visit_HadamardProduct = _product

    def _visit_MatAdd(self, expr):
        return max((self.visit(a) for a in expr.args), default=0)

    _visit_Add = _visit_MatAdd

    def _visit_BlockMatrix(self, expr):  # BlockDiagMatrix too (a subclass)
        return max((self.visit(b) for b in expr.blocks), default=0)

    def _visit_Coefficient(self, expr):     # π_ij: data
        return 0

    def _index_op(self, expr):             # Σ, stack, diag over an index: the body's degree
        return self.visit(expr.body)

    _visit_IndexSum = _visit_IndexStack = _visit_IndexDiag = _index_op

    def _visit_MatrixElement(self, expr):
        return self.visit(expr.parent)

    # -- degree-preserving maps ----------------------------------------------------------------
    def _visit_Transpose(self, expr):
        return self.visit(expr.arg)

    def _visit_Trace(self, expr):
        return self.visit(expr.arg)

    # -- inverse and powers --------------------------------------------------------------------
    def _visit_Inverse(self, expr):
        if self.visit(expr.arg) > 0:
            raise self.nonlinear(
                f"{expr} is the inverse of an expression in the decision variables "
                f"{', '.join(map(str, _decision_atoms(expr.arg, self.kinds)))}")
        return 0

    def _power(self, expr):
        base, exp = expr.args
        d = self.visit(base)
        if d == 0:
            if self.visit(exp) > 0:
                raise self.nonlinear(f"{expr} has a decision variable in an exponent")
            return 0
        if exp.is_Integer and exp >= 0:
            return d * int(exp)
        raise self.nonlinear(f"{expr} is a non-integer or negative power of a decision variable")

    _visit_MatPow = _visit_Pow = _power

    # -- other functions ----------------------------------------------------------------------
    def _visit_Application(self, expr):  # sqrt is a Pow; exp, Abs, Max, ...
        if any(self.visit(a) > 0 for a in expr.args if isinstance(a, (sp.Expr, MatrixExpr))):
            raise self.nonlinear(f"{expr} applies {type(expr).__name__} to a decision variable")
        return 0


def degree(expr, kinds=DECISION_TYPES) -> int:
    """Degree of ``expr`` in the symbols of ``kinds`` (default: the decision variables).

    ``kinds`` is a tuple of classes or a set of symbols.  Raises on an inverse of such a symbol.
    """
    return DegreeWalker(kinds).visit(expr)


def _nonlinear_culprit(expr, walker: DegreeWalker):
    """The smallest product/power in ``expr`` whose degree exceeds one."""
    for sub in sp.postorder_traversal(expr):
        if isinstance(sub, (sp.MatMul, sp.Mul, sp.MatPow, sp.Pow)):
            try:
                if walker.visit(sub) > 1:
                    return sub
            except NonlinearityError:
                return sub
    return None


def check_affine(expr, where: str = "") -> None:
    """Raise :class:`NonlinearityError` unless ``expr`` is affine in the decision variables
    and affine in each uncertain symbol (the vertex argument of :mod:`lmidsl.symbolic.uncertainty`).

    ``where`` (theorem, LMI, block) prefixes the message.
    """
    for u in uncertain_atoms(expr):
        if DegreeWalker({u}, where).visit(expr) > 1:
            raise NonlinearityError(
                (f"{where}: " if where else "")
                + f"{expr} is not affine in the uncertain {u}: its vertices would not cover the box")
    walker = DegreeWalker(DECISION_TYPES, where)
    d = walker.visit(expr)
    if d > 1:
        culprit = _nonlinear_culprit(expr, walker) or expr
        names = ", ".join(map(str, _decision_atoms(culprit)))
        raise walker.nonlinear(f"{culprit} is not affine: it multiplies the decision variables {names}")
