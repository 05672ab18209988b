"""One walk over a matrix expression tree, one method per node type.

This is the pattern of sympy's printers: ``visit`` looks up ``_visit_<ClassName>`` along the
class's MRO, so a node type is taught in one place per concern, and a node no method knows
reaches :meth:`Walker.unknown`, which raises a one-line
:class:`~lmidsl.errors.TheoremDefinitionError` naming the node class, the node, the expression
being walked and, when the caller gave it, where (theorem, LMI label, block).

:class:`Walker` is the walk itself (dispatch, a per-walk cache keyed by identity, the error for an
unknown node).  Its subclasses are the concerns:

* :class:`~lmidsl.symbolic.shapes.ShapeWalker` -- the shape of an expression, checking that every
  product, sum, block and trace conforms (at declaration);
* :class:`~lmidsl.symbolic.linearity.DegreeWalker` -- the degree in the decision variables (or in
  an uncertain symbol), checking affinity (at declaration);
* :class:`ExpressionWalker` -- evaluation into an algebra: the numpy evaluator, the cvxpy compiler
  and the PICOS compiler.  The walk is generic; a subclass supplies the leaves (what a data
  matrix, a variable or a parameter becomes) and the few operations its target spells
  differently (block assembly, identity, zeros, inverse, trace).  No expression is ever
  expanded into scalar entries.
"""
from __future__ import annotations

from functools import reduce

import numpy as np
import sympy as sp

from ..errors import TheoremDefinitionError
from .symbols import (DataMatrix, DerivedParam, Dim, Param, ScalarVariable, StructuredVariable,
                      Variable)


_STRUCTURE: dict = {}     # (id(node), how) -> (node, its parts); theorem trees are immutable
_METHODS: dict = {}       # (walker class, node class) -> the _visit_ function, or None


HINTS = {
    "KroneckerProduct": "; for K ⊗ X with K constant use lmidsl.kron(K, X)",
    "Sum": "; for Σ over the members of an index set use lmidsl.sum_over (thm.index_set)",
    "Indexed": "; for A_i over an index set declare thm.data(..., over=thm.index_set(...)) and write A[i]",
    "IndexedBase": "; declare the index set with thm.index_set and the data with over=...",
    "Idx": "; declare indices with M.indices('i j') of an index set M = thm.index_set(...)",
}
"""What to use instead of a sympy node lmidsl has no rule for (appended to the refusal)."""


def structure(expr, parts):
    """``parts(expr)`` computed once per node (a node's operands in the form a walk uses, or a
    property such as what it contains), cached by identity; the entry keeps the node alive, so
    its id stays valid.  Sympy recomputes operands at every access (a block matrix's blocks are
    read through a sympy matrix entry by entry), and the same trees are walked at every point
    of a sweep."""
    key = (id(expr), parts)
    hit = _STRUCTURE.get(key)
    if hit is not None and hit[0] is expr:
        return hit[1]
    value = parts(expr)
    if len(_STRUCTURE) > 100_000:
        _STRUCTURE.clear()
    _STRUCTURE[key] = (expr, value)
    return value


def _signed_terms(expr) -> list:
    """(sign, term) pairs of a sum, with a −1 coefficient taken out of the term, + terms first."""
    terms = []
    for term in expr.args:
        if isinstance(term, sp.MatMul) and term.args[0] == -1:
            terms.append((-1, sp.MatMul(*term.args[1:]) if len(term.args) > 2 else term.args[1]))
        else:
            terms.append((1, term))
    terms.sort(key=lambda st: -st[0])
    return terms


def _diagonal_parts(expr) -> tuple:
    """(block, its rows, its columns) of each block of a ``BlockDiagMatrix`` (sympy computes a
    block's shape anew at every access)."""
    return tuple((b, b.rows, b.cols) for b in expr.args)


def _fits(value, dtype, shape: tuple) -> bool:
    """Whether ``value`` can be written as it is into a ``shape`` block of an array of ``dtype``:
    a numpy array (or number) of that shape (as 2-D) and dtype, or of a real numeric dtype into
    a float array."""
    if not isinstance(value, (np.ndarray, float, int)):
        return False
    value = np.atleast_2d(value)
    kind = value.dtype
    return value.shape == tuple(shape) and (kind == dtype or (dtype.kind == "f" and kind.kind in "fiub"))


def _block_rows(expr) -> list:
    """The blocks of a ``BlockMatrix`` as a list of rows."""
    b = expr.blocks
    return [[b[i, j] for j in range(b.cols)] for i in range(b.rows)]


def _method_for(walker_cls, node_cls):
    """The first ``_visit_<Class>`` along the node class's MRO (cached per class pair)."""
    key = (walker_cls, node_cls)
    try:
        return _METHODS[key]
    except KeyError:
        pass
    method = None
    for cls in node_cls.__mro__:
        method = getattr(walker_cls, f"_visit_{cls.__name__}", None)
        if method is not None:
            break
    _METHODS[key] = method
    return method


class Walker:
    """Visit a sympy expression tree with one ``_visit_<Class>`` method per node type.

    ``where`` (e.g. ``"paper.thm1: LMI (9) block (2,1)"``) prefixes every error the walk raises.
    Results are cached by identity for the life of the walker: a shared sub-tree is walked once,
    and no deep sympy equality is ever evaluated (the cache keeps the expressions alive, so ids
    are stable).
    """

    #: what the walker does to a node, for the error raised on a node it has no rule for
    action = "walk"

    def __init__(self, where: str = ""):
        self.where = where
        self._cache: dict = {}  # id(expr) -> (expr, value)
        self._root = None       # the expression the outermost visit started from

    # -- entry point -----------------------------------------------------------------
    def visit(self, expr):
        key = id(expr)
        hit = self._cache.get(key)
        if hit is not None:
            return hit[1]
        outermost = self._root is None
        if outermost:
            self._root = expr
        try:
            result = self._dispatch(expr)
        finally:
            if outermost:
                self._root = None
        self._cache[key] = (expr, result)
        return result

    def _dispatch(self, expr):
        method = _method_for(type(self), type(expr))
        if method is None:
            return self.unknown(expr)
        return method(self, expr)

    # -- errors --------------------------------------------------------------------------
    def context(self) -> str:
        """Where the walk is (theorem, LMI, block), for error messages; '' when unknown."""
        return self.where

    def error(self, cls, message: str):
        """An error of class ``cls`` whose message is prefixed by :meth:`context`."""
        where = self.context()
        return cls(f"{where}: {message}" if where else message)

    def unknown(self, expr):
        """The fallback for a node no ``_visit_`` method knows: a one-line definition error."""
        root = self._root
        inside = ""
        if root is not None and root is not expr:
            text = str(root)
            inside = f" in {text if len(text) <= 200 else text[:200] + '...'}"
        hint = HINTS.get(type(expr).__name__, "")
        raise self.error(TheoremDefinitionError,
                         f"{type(self).__name__} cannot {self.action} {type(expr).__name__}: "
                         f"{expr}{inside} (lmidsl has no rule for this sympy node{hint})")


class ExpressionWalker(Walker):
    """Evaluate a sympy matrix/scalar expression into some algebra (numpy, cvxpy, picos)."""

    action = "evaluate"

    def __init__(self, dims: dict, vertex: int | None = None, where: str = ""):
        super().__init__(where)
        self.dims = dims
        self.vertex = vertex  # one walker per vertex: the cache holds one vertex's values
        self._sizes: dict = {}

    def size(self, dim) -> int:
        """A dimension expression as an integer under the bound dimensions (memoised: a block
        matrix asks for the same few dimensions hundreds of times)."""
        try:
            return self._sizes[dim]
        except KeyError:
            value = self._sizes[dim] = int(sp.sympify(dim).xreplace(self.dims))
            return value

    # -- operations a target may spell differently ---------------------------------------
    def add(self, a, b):
        return a + b

    def matmul(self, a, b):
        return a @ b

    def scale(self, c, a):
        return c * a

    def transpose(self, a):
        return a.T

    def identity(self, n: int):
        return np.eye(n)

    def zeros(self, r: int, c: int):
        return np.zeros((r, c))

    def block(self, rows):
        raise NotImplementedError

    def inverse(self, a, expr):
        raise NotImplementedError(f"{type(self).__name__} cannot invert {expr}")

    def trace(self, a):
        """tr(a) of a square matrix value (numpy here; the compilers spell it for their algebra)."""
        return float(np.trace(np.atleast_2d(a)))

    # -- leaves (subclasses) ----------------------------------------------------------
    def data(self, symbol):
        raise NotImplementedError

    def variable(self, symbol):
        raise NotImplementedError

    def scalar_variable(self, symbol):
        raise NotImplementedError

    def parameter(self, symbol):
        raise NotImplementedError

    # -- matrix nodes -------------------------------------------------------------------
    def _visit_DataMatrix(self, expr: DataMatrix):
        return self.data(expr)

    def _visit_Variable(self, expr: Variable):
        return self.variable(expr)

    def _visit_StructuredVariable(self, expr: StructuredVariable):
        return self.visit(expr.expansion)

    def subtract(self, a, b):
        return a - b

    def negate(self, a):
        return -a

    def _visit_MatAdd(self, expr):
        # a − b rather than a + (−1)·b: one node fewer per term in the target algebra
        terms = structure(expr, _signed_terms)
        sign, first = terms[0]
        total = self.visit(first) if sign > 0 else self.negate(self.visit(first))
        for sign, term in terms[1:]:
            total = self.add(total, self.visit(term)) if sign > 0 else self.subtract(total, self.visit(term))
        return total

    def _visit_MatMul(self, expr):
        coeff, matrices = structure(expr, sp.MatMul.as_coeff_matrices)
        product = reduce(self.matmul, (self.visit(m) for m in matrices))
        if coeff == 1:
            return product
        if coeff == -1:
            return self.negate(product)
        return self.scale(self.visit(coeff), product)

    def _visit_Transpose(self, expr):
        return self.transpose(self.visit(expr.arg))

    def _visit_Inverse(self, expr):
        return self.inverse(self.visit(expr.arg), expr.arg)

    def _visit_MatPow(self, expr):
        base, exp = expr.args
        if exp == -1:
            return self.inverse(self.visit(base), base)
        if not (exp.is_Integer and exp != 0):
            raise self.error(TheoremDefinitionError, f"{type(self).__name__} cannot evaluate the power "
                             f"{expr}: only integer powers (A.I*A.I is A**-2)")
        # sympy folds A.I*A.I into A**-2: the inverse, then its power
        value = self.inverse(self.visit(base), base) if exp < 0 else self.visit(base)
        return reduce(self.matmul, [value] * abs(int(exp)))

    def _visit_Identity(self, expr):
        return self.identity(self.size(expr.rows))

    def _visit_ZeroMatrix(self, expr):
        return self.zeros(self.size(expr.rows), self.size(expr.cols))

    def _visit_BlockMatrix(self, expr):
        return self.block([[self.visit(b) for b in row] for row in structure(expr, _block_rows)])

    def _visit_BlockDiagMatrix(self, expr):
        parts = structure(expr, _diagonal_parts)
        return self.block_diagonal([self.visit(b) for b, _, _ in parts],
                                   [(self.size(r), self.size(c)) for _, r, c in parts])

    def block_diagonal(self, values: list, shapes: list):
        """diag(M₁, …, M_k) from the blocks' values and their (rows, cols): filled into one zero
        matrix when the target's values are numpy arrays (O(k) blocks placed, not k² blocks
        assembled), else the generic block matrix with zero blocks off the diagonal."""
        out = self.zeros(sum(r for r, _ in shapes), sum(c for _, c in shapes))
        if isinstance(out, np.ndarray) and all(_fits(v, out.dtype, shape) for v, shape in zip(values, shapes)):
            r0 = c0 = 0
            for v, (r, c) in zip(values, shapes):
                out[r0:r0 + r, c0:c0 + c] = v
                r0, c0 = r0 + r, c0 + c
            return out
        return self.block([[v if i == j else self.zeros(shapes[i][0], shapes[j][1])
                            for j in range(len(values))] for i, v in enumerate(values)])

    def _visit_MatrixBase(self, expr):
        return np.array(expr.tolist(), dtype=float)

    def _visit_Trace(self, expr):
        # tr(M) is linear in M: the target's trace of the evaluated argument
        return self.trace(self.visit(expr.arg))

    def _visit_MatrixElement(self, expr):
        # an entry of a matrix (π_ij of a coefficient matrix): a number of a constant matrix
        return self.element(self.visit(expr.parent), int(expr.i), int(expr.j), expr)

    def element(self, a, i: int, j: int, expr):
        return np.asarray(a)[i, j]

    # -- scalar nodes -------------------------------------------------------------------
    def _visit_Number(self, expr):
        return float(expr)

    def _visit_NumberSymbol(self, expr):
        return float(expr)

    def _visit_Dim(self, expr: Dim):
        # a dimension in a scalar, e.g. tr(Z + I_n) = tr(Z) + n
        return float(self.size(expr))

    def _visit_Param(self, expr: Param):
        return self.parameter(expr)

    def _visit_DerivedParam(self, expr: DerivedParam):
        return self.parameter(expr)

    def _visit_ScalarVariable(self, expr: ScalarVariable):
        return self.scalar_variable(expr)

    def _visit_Add(self, expr):
        return reduce(self.add, (self.visit(a) for a in expr.args))

    def _visit_Mul(self, expr):
        return reduce(lambda a, b: a * b, (self.visit(a) for a in expr.args))

    def _visit_Pow(self, expr):
        base, exp = expr.args
        return self.visit(base) ** float(exp)
