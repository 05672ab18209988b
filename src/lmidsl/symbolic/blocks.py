"""Block matrices written as the paper writes them.

A symmetric block matrix is given as one triangle, row by row, with the mirrored ``*`` blocks
left out::

    [[-P],
     [0,        -I],
     [P * A,    P * B,   -P]]

``0`` and ``I`` (also ``-I``, ``g * I``) are sized from their block row and column.  The
sizes of the block rows are read off the blocks that have a shape; a row whose size nothing
fixes is an error.  The result keeps the triangle (for printing with ``\\star``) and gives the
full block (i, j) = block (j, i)ᵀ for the other triangle.

An LMI may also be written with cvxpy's operators on a matrix expression (or a
:class:`BlockMatrixSpec`): ``A.T @ P + P @ A << 0`` and ``P >> 0`` are strict (≺, ≻: imposed with
the strictness margin, as ``sense="<"``), so are ``<`` and ``>``; ``<=`` and ``>=`` are
non-strict (⪯, ⪰).  Each builds a :class:`MatrixInequality` that ``Theorem.lmi`` takes.

Helpers: ``He(X) = X + Xᵀ``, ``diag(...)``, ``schur(M, k)`` (Schur complement of the diagonal
block k), ``congruence(T, M) = Tᵀ M T`` block by block for block-diagonal ``T``.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy import Identity, ZeroMatrix

from ..errors import ShapeMismatchError, TheoremDefinitionError
from .shapes import dims_equal, fmt_shape
from .symbols import as_symbolic, theorem_of


class SizedIdentity:
    """The marker ``I``: an identity block sized from its position, times a scalar."""

    def __init__(self, coefficient=1):
        self.coefficient = sp.sympify(coefficient)

    def __neg__(self):
        return SizedIdentity(-self.coefficient)

    def __mul__(self, other):
        if isinstance(other, (int, float, sp.Expr)) and not isinstance(other, sp.MatrixExpr):
            return SizedIdentity(self.coefficient * other)
        return NotImplemented

    __rmul__ = __mul__

    # next to a matrix expression, I takes the size of that matrix: X - g*I, I + X
    def _with(self, other, sign_self, sign_other):
        if isinstance(other, sp.MatrixExpr):
            return sign_other * other + sign_self * self.sized(other.shape[0])
        return NotImplemented

    def __add__(self, other):
        return self._with(other, 1, 1)

    __radd__ = __add__

    def __sub__(self, other):
        return self._with(other, 1, -1)

    def __rsub__(self, other):
        return self._with(other, -1, 1)

    def sized(self, n):
        return self.coefficient * Identity(n) if self.coefficient != 1 else Identity(n)

    def __repr__(self):
        return "I" if self.coefficient == 1 else f"{self.coefficient}*I"


I = SizedIdentity()


def _is_zero_marker(entry) -> bool:
    return isinstance(entry, (int, float)) and entry == 0 or (
        isinstance(entry, sp.Expr) and not isinstance(entry, sp.MatrixExpr) and entry == 0)


def He(X: sp.MatrixExpr) -> sp.MatrixExpr:
    """He(X) = X + Xᵀ."""
    return X + X.T


def diag(*blocks: sp.MatrixExpr) -> sp.MatrixExpr:
    """Block-diagonal matrix diag(X₁, …, X_q)."""
    return sp.BlockDiagMatrix(*blocks)


@dataclass
class BlockMatrixSpec:
    """A symmetric block matrix given by one triangle.

    ``lower[i][j]`` (j ≤ i) is the block the theorem wrote; ``sizes[i]`` the size of block row i.
    ``explicit[i][j]`` is False for the blocks that were ``0``/``I`` markers.
    """

    lower: list[list[sp.MatrixExpr]]
    sizes: list[sp.Expr]
    given_as: str = "lower"

    @property
    def nblocks(self) -> int:
        return len(self.sizes)

    def block(self, i: int, j: int) -> sp.MatrixExpr:
        """Block (i, j) of the full symmetric matrix (0-based)."""
        if j <= i:
            return self.lower[i][j]
        return self.lower[j][i].T

    def full(self) -> list[list[sp.MatrixExpr]]:
        return [[self.block(i, j) for j in range(self.nblocks)] for i in range(self.nblocks)]

    def as_sympy(self) -> sp.BlockMatrix:
        return sp.BlockMatrix(self.full())


def _rows_from_upper(rows):
    """Transpose an upper-triangle listing (row i holds blocks (i, i..q)) into lower form."""
    q = len(rows)
    for i, row in enumerate(rows):
        if len(row) != q - i:
            raise ShapeMismatchError(
                f"upper-triangle row {i + 1} has {len(row)} blocks, expected {q - i}")
    lower = [[None] * (i + 1) for i in range(q)]
    for i, row in enumerate(rows):
        for off, entry in enumerate(row):
            j = i + off
            lower[j][i] = entry if _is_marker(entry) else entry.T
    return lower


def _is_marker(entry) -> bool:
    return isinstance(entry, SizedIdentity) or _is_zero_marker(entry)


def block_matrix(rows, *, triangle: str = "lower", sizes=None, where: str = "") -> BlockMatrixSpec:
    """Build a :class:`BlockMatrixSpec` from one triangle of blocks.

    ``rows[i]`` holds blocks (i, 0..i) for ``triangle="lower"`` (the usual ``*``-above layout)
    or blocks (i, i..q-1) for ``triangle="upper"``.  ``sizes`` optionally states the block sizes.
    ``where`` prefixes error messages (theorem id and LMI label).  A :class:`BlockMatrixSpec`
    (e.g. built by :func:`lmidsl.symbolic.sprocedure.sprocedure`) is accepted and re-checked.
    """
    prefix = f"{where}: " if where else ""
    if isinstance(rows, BlockMatrixSpec):
        sizes = rows.sizes if sizes is None else sizes
        rows, triangle = rows.lower, "lower"
    rows = [list(r) if isinstance(r, (list, tuple)) else [r] for r in rows]
    if triangle == "upper":
        lower = _rows_from_upper(rows)
    elif triangle == "lower":
        lower = rows
        for i, row in enumerate(lower):
            if len(row) != i + 1:
                raise ShapeMismatchError(
                    f"{prefix}row {i + 1} of the lower triangle has {len(row)} blocks, expected {i + 1}")
    else:
        raise ValueError("triangle must be 'lower' or 'upper'")
    q = len(lower)
    found = [None] * q if sizes is None else [sp.sympify(s) for s in sizes]
    origin = [None] * q

    def note(index, size, i, j, expr):
        if found[index] is None:
            found[index] = size
            origin[index] = (i, j, expr)
        elif not dims_equal(found[index], size):
            ref = origin[index]
            ref_txt = f"block ({ref[0] + 1},{ref[1] + 1}) {ref[2]}" if ref else "the stated sizes"
            raise ShapeMismatchError(
                f"{prefix}block ({i + 1},{j + 1}) {expr} is {fmt_shape(expr.shape)}, but block "
                f"{'row' if index == i else 'column'} {index + 1} has size {found[index]} "
                f"(from {ref_txt})")

    for i in range(q):
        for j in range(i + 1):
            entry = lower[i][j]
            if _is_marker(entry):
                continue
            if not isinstance(entry, sp.MatrixExpr):
                raise ShapeMismatchError(
                    f"{prefix}block ({i + 1},{j + 1}) is {entry!r}, not a matrix expression, 0 or I")
            rows_, cols_ = entry.shape
            note(i, rows_, i, j, entry)
            note(j, cols_, i, j, entry)
    for i in range(q):
        if found[i] is None:
            raise ShapeMismatchError(
                f"{prefix}the size of block row {i + 1} is not fixed by any block; give an explicit "
                f"block there or pass sizes=[...]")
    sized = []
    for i in range(q):
        row = []
        for j in range(i + 1):
            entry = lower[i][j]
            if isinstance(entry, SizedIdentity):
                if i != j and not dims_equal(found[i], found[j]):
                    raise ShapeMismatchError(
                        f"{prefix}block ({i + 1},{j + 1}) is I but its block is "
                        f"{found[i]}×{found[j]}, not square")
                entry = entry.sized(found[i])
            elif _is_zero_marker(entry):
                entry = ZeroMatrix(found[i], found[j])
            row.append(entry)
        sized.append(row)
    return BlockMatrixSpec(sized, found, triangle)


class MatrixInequality:
    """``lhs ≺ rhs`` (``sense`` '<'), ``lhs ≻ rhs`` ('>'), or non-strict ('<=', '>='), written with
    operators; ``Theorem.lmi`` declares it as the one-block LMI ``lhs − rhs`` (a
    :class:`BlockMatrixSpec` keeps its blocks, with ``rhs`` 0).  ``rhs`` may be 0, ``I``
    (``g * I``, sized from ``lhs``), a matrix expression or a numpy array."""

    SIGNS = {"<": "≺", ">": "≻", "<=": "⪯", ">=": "⪰"}

    def __init__(self, lhs, rhs, sense: str):
        self.sense = sense
        if isinstance(lhs, BlockMatrixSpec):
            if not _is_zero_marker(rhs):
                raise TheoremDefinitionError(
                    f"a block matrix {self.SIGNS[sense]} {rhs!r}: compare a block matrix with 0 "
                    f"(move the right-hand side into its blocks)")
            self.lhs, self.rhs, self.rows = lhs, 0, lhs
            return
        rhs = as_symbolic(rhs)
        if isinstance(rhs, SizedIdentity):
            rhs = rhs.sized(lhs.shape[0])
        self.lhs, self.rhs = lhs, rhs
        self.rows = [[lhs if _is_zero_marker(rhs) else lhs - rhs]]

    def __bool__(self):
        owner = theorem_of(self.lhs if isinstance(self.lhs, sp.Basic) else sp.S.Zero)
        raise TheoremDefinitionError(
            f"{owner + ': ' if owner else ''}{self} is a matrix inequality, not a truth value: declare "
            f"it with Theorem.lmi(...)")

    def __repr__(self):
        lhs = "block matrix" if isinstance(self.lhs, BlockMatrixSpec) else str(self.lhs)
        return f"{lhs} {self.SIGNS[self.sense]} {self.rhs}"


def _inequality(sense: str):
    """``self OP other`` as the :class:`MatrixInequality` ``self sense other``."""

    def method(self, other):
        if isinstance(other, (MatrixInequality, list, tuple)):
            return NotImplemented
        return MatrixInequality(self, other, sense)
    return method


# cvxpy's convention on matrices (``X << Y``: X ≺ Y; ``0 << P``: P ≻ 0), and the comparison
# operators (sympy's would build a scalar relational and fail on a matrix, "Invalid comparison of
# non-real"; Python reflects ``0 < P`` to ``P > 0`` itself)
for _target in (sp.MatrixExpr, BlockMatrixSpec):
    for _name, _sense in (("__lshift__", "<"), ("__rshift__", ">"), ("__rlshift__", ">"), ("__rrshift__", "<"),
                          ("__lt__", "<"), ("__gt__", ">"), ("__le__", "<="), ("__ge__", ">=")):
        setattr(_target, _name, _inequality(_sense))


def schur(M: BlockMatrixSpec, k: int) -> BlockMatrixSpec:
    """Schur complement of the diagonal block k (0-based): M_rest − M_·k M_kk⁻¹ M_k·.

    Only an LMI when ``M_kk`` is data; the linearity check rejects it otherwise.
    """
    keep = [i for i in range(M.nblocks) if i != k]
    inv = M.block(k, k).I
    lower = [[M.block(i, j) - M.block(i, k) * inv * M.block(k, j) for j in keep[: a + 1]]
             for a, i in enumerate(keep)]
    return BlockMatrixSpec(lower, [M.sizes[i] for i in keep])


def congruence(T_blocks, M: BlockMatrixSpec) -> BlockMatrixSpec:
    """Tᵀ M T for block-diagonal T = diag(T_blocks): block (i, j) becomes T_iᵀ M_ij T_j."""
    if len(T_blocks) != M.nblocks:
        raise ShapeMismatchError(
            f"congruence: {len(T_blocks)} diagonal blocks for a {M.nblocks}-block matrix")
    lower = [[T_blocks[i].T * M.block(i, j) * T_blocks[j] for j in range(i + 1)]
             for i in range(M.nblocks)]
    return BlockMatrixSpec(lower, [T.shape[1] for T in T_blocks])
