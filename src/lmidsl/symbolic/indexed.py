"""Indexed symbols, sums and stacks over an index: the vocabulary of "for all i ∈ 𝓘".

A theorem about N modes (rules, vertices, subsystems) states one LMI with a free index i and a
quantifier; the library instantiates it for i = 1, …, N when N is known (at bind time, from
the data), see :mod:`lmidsl.theorem.index_set`.  The nodes here are what such an LMI is written
with:

* :class:`Index` -- an index symbol (``i``, ``j``) ranging over an index set {1, …, N};
* indexed matrices ``A[i]``, ``P[j]``, ``Q[i, j]`` -- matrix symbols of the declared kinds
  (data, full / symmetric / diagonal variables) carrying their indices, so that the shape and
  linearity checks see them as what they are;
* :class:`Coefficient` -- a scalar entry of a coefficient matrix, ``π_ij = Pi[i, j]``;
* :class:`IndexSum` (Σ_{j: cond} body), :class:`IndexStack` (the column of the bodies stacked
  vertically) and :class:`IndexDiag` (their block diagonal), whose sizes are symbolic counts of
  the range (N − 1 for j ≠ i, i − 1 for j < i, N for all j);
* :func:`kron` -- a Kronecker product with a constant matrix, expanded to a block matrix.

:func:`instantiate` replaces the indices by numbers: indexed symbols by the member symbols a
resolver gives (``A_3``), coefficients by entries of the coefficient data matrix, sums by
sums, stacks and diagonals by block matrices (an empty range gives a 0-sized block, which the
caller drops).  Its cost is one rebuild of the tree per instance: compile time linear in the
number of instances.
"""
from __future__ import annotations

import sympy as sp
from sympy.core.symbol import Str
from sympy.matrices.expressions.matexpr import MatrixExpr

from ..errors import TheoremDefinitionError
from .symbols import (DataMatrix, DiagonalVariable, RecoveredMatrix, SymmetricDataMatrix,
                      SymmetricVariable, Variable, _Described)


class Index(sp.Symbol):
    """An index ranging over an index set {1, …, N}; ``set_name`` names the set."""

    def __new__(cls, name: str, set_name: str = "", tag: str = "", size=None):
        obj = sp.Symbol.__xnew__(cls, name, integer=True, positive=True)
        obj._set_name = set_name
        obj._tag = tag
        obj._size = size
        return obj

    @property
    def size(self):
        """The size N of the index set (a dimension symbol)."""
        return self._size

    @property
    def set_name(self) -> str:
        return getattr(self, "_set_name", "")

    def _hashable_content(self):
        return super()._hashable_content() + (self.set_name, getattr(self, "_tag", ""))

    def __getnewargs_ex__(self):
        return (self.name, self.set_name, getattr(self, "_tag", ""), self._size), {}


class _IndexedMatrix:
    """Mixin: a tagged matrix symbol with a fifth argument, the tuple of its indices."""

    def __new__(cls, name, rows, cols, tag="", indices=()):
        rows, cols = sp.sympify(rows), sp.sympify(cols)
        name, tag = (x if isinstance(x, Str) else Str(str(x)) for x in (name, tag))
        return sp.Basic.__new__(cls, name, rows, cols, tag,
                                sp.Tuple(*[sp.sympify(k) for k in indices]))

    @property
    def indices(self) -> tuple:
        return tuple(self.args[4])

    @property
    def free_symbols(self):
        return {self} | set().union(*(k.free_symbols for k in self.indices))


class IndexedData(_IndexedMatrix, DataMatrix):
    """``A[i]``: a datum of member i."""


class IndexedSymmetricData(_IndexedMatrix, SymmetricDataMatrix):
    """``R[i]``: a symmetric datum of member i."""


class IndexedVariable(_IndexedMatrix, Variable):
    """``W[i]``: a full decision matrix of member i."""


class IndexedSymmetricVariable(_IndexedMatrix, SymmetricVariable):
    """``P[i]``: a symmetric decision matrix of member i."""


class IndexedDiagonalVariable(_IndexedMatrix, DiagonalVariable):
    """``D[i]``: a diagonal decision matrix of member i."""


class IndexedRecovered(_IndexedMatrix, RecoveredMatrix):
    """``K[i]``: a matrix recovered for member i."""


INDEXED_TYPES = (IndexedData, IndexedSymmetricData, IndexedVariable, IndexedSymmetricVariable,
                 IndexedDiagonalVariable, IndexedRecovered)


class Coefficient(_Described, sp.Expr):
    """``π_ij``: entry (i, j) of a coefficient matrix given as data (1-based indices)."""

    is_commutative = True
    is_real = True

    def __new__(cls, name: str, tag: str, *indices):
        name, tag = (x if isinstance(x, Str) else Str(str(x)) for x in (name, tag))
        return sp.Expr.__new__(cls, name, tag, *[sp.sympify(k) for k in indices])

    @property
    def name(self) -> str:
        return self.args[0].name

    @property
    def tag(self) -> str:
        return self.args[1].name

    @property
    def indices(self) -> tuple:
        return tuple(self.args[2:])


# -- ranges of an index ----------------------------------------------------------------------
def count(index: Index, size, where) -> sp.Expr:
    """The number of values of ``index`` in {1, …, size} satisfying ``where`` (a relation with
    one other index or a number, or None), symbolically: N, N − 1 (j ≠ i), i − 1 (j < i), ..."""
    size = sp.sympify(size)
    if where is None or where is sp.true:
        return size
    rel = where
    if not isinstance(rel, sp.core.relational.Relational):
        raise TheoremDefinitionError(f"the range of {index} must be a relation such as Ne({index}, i) "
                                     f"or {index} < i, got {where}")
    lhs, rhs = rel.lhs, rel.rhs
    if lhs != index:
        if rhs != index:
            raise TheoremDefinitionError(f"the range condition {where} does not mention {index}")
        rel = rel.reversed
        lhs, rhs = rel.lhs, rel.rhs
    other = rhs
    if isinstance(rel, sp.Ne):
        return size - 1
    if isinstance(rel, sp.Eq):
        return sp.Integer(1)
    if isinstance(rel, sp.StrictLessThan):
        return other - 1
    if isinstance(rel, sp.LessThan):
        return other
    if isinstance(rel, sp.StrictGreaterThan):
        return size - other
    if isinstance(rel, sp.GreaterThan):
        return size - other + 1
    raise TheoremDefinitionError(f"unsupported range condition {where}")


def holds(condition, env: dict) -> bool:
    """Whether a condition on indices holds at the numbers ``env`` gives them."""
    if condition is None:
        return True
    value = sp.sympify(condition).xreplace(env)
    if value not in (sp.true, sp.false):
        raise TheoremDefinitionError(f"the condition {condition} is not decided by {env}")
    return bool(value)


class _IndexOp(MatrixExpr):
    """An operation over the values of an index: args (body, index, size, condition)."""

    symbol = "op"

    def __new__(cls, body, index: Index, size, where=None):
        body = sp.sympify(body)
        if not isinstance(body, MatrixExpr):
            raise TheoremDefinitionError(f"{cls.__name__} over {index}: the body {body} is not a matrix")
        if not isinstance(index, Index):
            raise TheoremDefinitionError(f"{cls.__name__}: {index} is not an index of an index set")
        cond = sp.true if where is None else where
        return sp.Basic.__new__(cls, body, index, sp.sympify(size), cond)

    @property
    def body(self):
        return self.args[0]

    @property
    def index(self) -> Index:
        return self.args[1]

    @property
    def size(self):
        return self.args[2]

    @property
    def condition(self):
        return None if self.args[3] is sp.true else self.args[3]

    @property
    def count(self):
        return count(self.index, self.size, self.condition)

    def values(self, env: dict) -> list[int]:
        """The values of the index in range at ``env`` (the other indices bound)."""
        n = int(sp.sympify(self.size).xreplace(env))
        return [k for k in range(1, n + 1) if holds(self.condition, {**env, self.index: k})]

    @property
    def free_symbols(self):
        inner = self.body.free_symbols | (self.args[3].free_symbols if self.args[3] is not sp.true else set())
        return (inner - {self.index}) | self.size.free_symbols

    def _eval_transpose(self):
        return None


class IndexSum(_IndexOp):
    """Σ_{j ∈ 𝓘, cond} body: the shape of the body."""

    @property
    def shape(self):
        return self.body.shape


class IndexStack(_IndexOp):
    """The bodies for the index values in range stacked vertically (a block column)."""

    @property
    def shape(self):
        return (self.count * self.body.shape[0], self.body.shape[1])


class IndexDiag(_IndexOp):
    """The block diagonal of the bodies for the index values in range."""

    @property
    def shape(self):
        return (self.count * self.body.shape[0], self.count * self.body.shape[1])


def sum_over(index: Index, body, where=None):
    """Σ_{index, where} body (e.g. ``sum_over(j, Pi[i, j] * P[j], Ne(j, i))``)."""
    return IndexSum(body, index, index_size(index), where)


def stack_over(index: Index, body, where=None):
    """The block column of ``body`` for the values of ``index`` in range (e.g. √π_ij Y_i, j ≠ i)."""
    return IndexStack(body, index, index_size(index), where)


def diag_over(index: Index, body, where=None):
    """The block diagonal of ``body`` for the values of ``index`` in range (e.g. diag(Y_j), j ≠ i)."""
    return IndexDiag(body, index, index_size(index), where)


def index_size(index: Index):
    if not isinstance(index, Index) or index.size is None:
        raise TheoremDefinitionError(f"{index} is not an index of a declared index set")
    return index.size


def kron(K, X):
    """K ⊗ X for a constant matrix K (nested lists, numpy or sympy) and a matrix expression X:
    the block matrix [K_ab X] (zero blocks where K_ab = 0); X ⊗ K when X is the constant."""
    def explicit(M):
        if isinstance(M, MatrixExpr) and not isinstance(M, sp.MatrixBase):
            return None
        return sp.Matrix(M)
    Kc, Xc = explicit(K), explicit(X)
    if Kc is not None and Xc is None:
        r, c = X.shape
        rows = [[Kc[a, b] * X if Kc[a, b] != 0 else sp.ZeroMatrix(r, c) for b in range(Kc.cols)]
                for a in range(Kc.rows)]
        return sp.BlockMatrix(rows) if (Kc.rows, Kc.cols) != (1, 1) else rows[0][0]
    if Xc is not None and Kc is None:
        # X ⊗ K = P (K ⊗ X) Q for permutations; with K symbolic only the block form is exact:
        # [X_ab K]
        r, c = K.shape
        rows = [[Xc[a, b] * K if Xc[a, b] != 0 else sp.ZeroMatrix(r, c) for b in range(Xc.cols)]
                for a in range(Xc.rows)]
        return sp.BlockMatrix(rows) if (Xc.rows, Xc.cols) != (1, 1) else rows[0][0]
    if Kc is not None and Xc is not None:
        return sp.ImmutableMatrix(sp.kronecker_product(Kc, Xc))
    raise TheoremDefinitionError(f"kron({K}, {X}): one factor must be a constant matrix")


# -- instantiation ------------------------------------------------------------------------
def free_indices(expr) -> set:
    """The index symbols free in ``expr`` (bound ones, of sums and stacks, excluded)."""
    return {s for s in sp.sympify(expr).free_symbols if isinstance(s, Index)}


def instantiate(expr, env: dict, resolve, coefficient):
    """``expr`` with the indices replaced by the numbers ``env`` gives them.

    ``resolve(symbol, numbers)`` gives the member symbol of an indexed matrix (``A`` at (3,) →
    ``A_3``); ``coefficient(name, numbers)`` the scalar of a coefficient entry.  Sums become
    sums (an empty range: a zero matrix), stacks and diagonals block matrices (an empty range:
    ``None`` for the caller to drop the block, or a 0-sized zero matrix inside an expression).
    """
    memo: dict = {}
    bound = set(env)

    def go(e):
        key = id(e)
        hit = memo.get(key)
        if hit is not None and hit[0] is e:
            return hit[1]
        out = _go(e)
        memo[key] = (e, out)
        return out

    def _go(e):
        if isinstance(e, sp.Symbol) and e in env:      # an index, or the size N of an index set
            return sp.Integer(env[e])
        if isinstance(e, INDEXED_TYPES):
            return resolve(e, tuple(int(sp.sympify(k).xreplace(env)) for k in e.indices))
        if isinstance(e, Coefficient):
            return coefficient(e, tuple(int(sp.sympify(k).xreplace(env)) for k in e.indices))
        if isinstance(e, _IndexOp):
            values = e.values(env)
            bodies = [instantiate(e.body, {**env, e.index: k}, resolve, coefficient) for k in values]
            if isinstance(e, IndexSum):
                if not bodies:
                    return sp.ZeroMatrix(*[sp.sympify(d).xreplace(env) for d in e.body.shape])
                return sp.MatAdd(*bodies).doit(deep=False) if len(bodies) > 1 else bodies[0]
            if not bodies:
                r, c = (sp.sympify(d).xreplace(env) for d in e.shape)
                return sp.ZeroMatrix(r, c)
            if isinstance(e, IndexStack):
                return sp.BlockMatrix([[b] for b in bodies]) if len(bodies) > 1 else bodies[0]
            return sp.BlockDiagMatrix(*bodies) if len(bodies) > 1 else bodies[0]
        if not e.args or isinstance(e, (sp.MatrixSymbol, sp.Symbol)):
            return e
        if not (e.free_symbols & bound or e.has(Coefficient, _IndexOp)):
            return e
        return e.func(*[go(a) for a in e.args])

    return go(sp.sympify(expr))


__all__ = ["Index", "Coefficient", "IndexSum", "IndexStack", "IndexDiag", "sum_over", "stack_over",
           "diag_over", "kron", "instantiate", "free_indices", "INDEXED_TYPES", "count", "holds"]
