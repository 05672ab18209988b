"""Matrices affine in the decision variables, as sparse coefficient triplets: the algebra of the
direct backend (:mod:`lmidsl.solver.backends.direct_backend`).

The decision vector x stacks the free entries of every decision variable
(:class:`VariableSpace`: all entries of a full matrix, the upper triangle of a symmetric one, the
diagonal of a diagonal one, in consecutive ranges).  An r×c matrix M(x) affine in x is stored as

    vec M(x) = vec M₀ + C x,

with ``vec`` the row-major vectorisation (entry (i, j) at i·c + j) and C sparse, kept as
triplets (row, column, value) whose duplicates add up.  Every operation of the compiling walk
is a linear map on C:

    vec(K M) = (K ⊗ I_c) vec M,          vec(M K) = (I_r ⊗ Kᵀ) vec M       (K a constant),
    vec(Mᵀ) = Π vec M  (Π a permutation),  tr M = Σ_i (vec M)_{i·c+i},
    a block matrix shifts each block's rows to its place,  s·K for a scalar s = (vec K) s,

computed on the triplets with numpy (a product expands each triplet over the nonzeros of K's
matching column or row, then adds duplicates).  A product of two expressions that both depend
on x is not affine; the declaration refuses such theorems (:mod:`lmidsl.symbolic.linearity`)
and this algebra refuses it again as a guard.

:func:`svec_map` gives the PSD-triangle vectorisation of Clarabel (and SCS):
svec(S) = (S_ij for i ≤ j, column by column, off-diagonal entries times √2), taken from the
symmetric part (S + Sᵀ)/2, so that ⟨svec S, svec Z⟩ = tr(S Z).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ...errors import TheoremDefinitionError
from ...numeric.evaluate import assemble_blocks

_INT = np.int64
_EMPTY_I = np.zeros(0, dtype=_INT)
_EMPTY_F = np.zeros(0)


class DecisionVariable:
    """A decision variable: shape, kind, where its free entries sit in x, and the basis B with
    vec X = B x_X (as triplets: row of vec X, index of the free entry)."""

    __slots__ = ("name", "shape", "kind", "offset", "size", "basis_rows", "basis_cols", "free")

    def __init__(self, name: str, shape: tuple, kind: str, offset: int):
        self.name, self.shape, self.kind, self.offset = name, tuple(shape), kind, offset
        self.free = None
        if not self.shape:
            rows = cols = np.zeros(1, dtype=_INT)
        elif kind == "symmetric":
            n = self.shape[0]
            i, j = np.triu_indices(n)
            k = np.arange(len(i), dtype=_INT)
            off = i != j
            rows = np.concatenate([i * n + j, (j * n + i)[off]]).astype(_INT)
            cols = np.concatenate([k, k[off]])
        elif kind == "diagonal":
            n = self.shape[0]
            cols = np.arange(n, dtype=_INT)
            rows = cols * (n + 1)
        else:
            rows = cols = np.arange(self.shape[0] * self.shape[1], dtype=_INT)
        self.basis_rows, self.basis_cols = rows, cols
        self.size = int(cols.max()) + 1

    def expression(self) -> "Affine":
        const = 0.0 if not self.shape else np.zeros(self.shape)
        return Affine(self.shape, const, self.basis_rows, self.basis_cols + self.offset,
                      np.ones(len(self.basis_rows)), variable=self)

    def value(self):
        """X from the free entries (None before a solve)."""
        if self.free is None:
            return None
        if not self.shape:
            return float(self.free[0])
        vec = np.zeros(int(np.prod(self.shape)))
        vec[self.basis_rows] = self.free[self.basis_cols]
        return vec.reshape(self.shape)

    def set_value(self, value) -> None:
        """Take the free entries of a given X (:meth:`free_entries`)."""
        self.free = self.free_entries(value)

    def free_entries(self, value) -> np.ndarray:
        """The free entries of a given X (a symmetric X's upper triangle, a diagonal one's diagonal)."""
        value = np.asarray(value, dtype=float)
        if not self.shape:
            return value.reshape(1)
        if self.kind == "symmetric":
            return value[np.triu_indices(self.shape[0])]
        if self.kind == "diagonal":
            return np.diag(value) if value.ndim == 2 else value.reshape(-1)
        return value.reshape(-1)

    def __repr__(self) -> str:
        return f"DecisionVariable({self.name!r}, {self.shape}, {self.kind!r})"


class VariableSpace:
    """The decision vector x of one model: each new variable takes the next range of entries."""

    def __init__(self):
        self.variables: list[DecisionVariable] = []
        self.size = 0

    def new(self, name: str, shape: tuple, kind: str = "full") -> DecisionVariable:
        variable = DecisionVariable(name, shape, kind, self.size)
        self.variables.append(variable)
        self.size += variable.size
        return variable

    def vector(self) -> np.ndarray:
        """x from the variables' values (NaN where a variable has none)."""
        x = np.full(self.size, np.nan)
        for v in self.variables:
            if v.free is not None:
                x[v.offset: v.offset + v.size] = v.free
        return x


def _not_affine(what: str):
    return TheoremDefinitionError(f"{what} of two expressions in the decision variables is not affine")


def _constant(x) -> np.ndarray | None:
    """x as a numpy constant, or None when it depends on a decision variable."""
    if isinstance(x, Affine):
        return np.asarray(x.const, dtype=float) if not len(x.vals) else None
    return np.asarray(x, dtype=float)


def _is_identity(K: np.ndarray) -> bool:
    return K.shape[0] == K.shape[1] and np.array_equal(K, np.eye(K.shape[0]))


def _sum_duplicates(rows, cols, vals):
    """The triplets with equal (row, column) added up and zeros dropped."""
    if len(rows) < 2:
        return rows, cols, vals
    key = rows * (int(cols.max()) + 1) + cols
    unique, inverse = np.unique(key, return_inverse=True)
    if len(unique) == len(key):
        keep = vals != 0
        return rows[keep], cols[keep], vals[keep]
    summed = np.bincount(inverse, weights=vals, minlength=len(unique))
    first = np.zeros(len(unique), dtype=_INT)
    first[inverse] = np.arange(len(key))
    keep = summed != 0
    return rows[first][keep], cols[first][keep], summed[keep]


def _expand(group, K_groups: np.ndarray, K_others: np.ndarray, K_vals: np.ndarray, ngroups: int):
    """For each triplet t in group ``group[t]``, every nonzero (g, o, v) of K with g = group[t]:
    returns (triplet index t, o, v) per pair.  K's nonzeros must be sorted by g."""
    count = np.bincount(K_groups, minlength=ngroups)
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    reps = count[group]
    t = np.repeat(np.arange(len(group), dtype=_INT), reps)
    within = np.arange(len(t), dtype=_INT) - np.repeat(np.cumsum(reps) - reps, reps)
    k = start[group][t] + within
    return t, K_others[k], K_vals[k]


class Affine:
    """M(x) = M₀ + (C x reshaped): see the module docstring.  ``shape`` is ``()`` for a scalar;
    ``variable`` is set when M is exactly one decision variable.  numpy defers to these
    operators (``__array_ufunc__ = None``), so ``K @ M`` and ``s * M`` with numpy constants on
    the left land here."""

    __array_ufunc__ = None
    __slots__ = ("shape", "const", "rows", "cols", "vals", "variable")

    def __init__(self, shape, const, rows=_EMPTY_I, cols=_EMPTY_I, vals=_EMPTY_F, variable=None):
        self.shape = tuple(shape)
        self.const = const
        self.rows, self.cols, self.vals = rows, cols, vals
        self.variable = variable

    def _with(self, shape, const, rows, cols, vals) -> "Affine":
        return Affine(shape, const, rows, cols, vals)

    @property
    def T(self) -> "Affine":
        if len(self.shape) < 2:
            return self
        r, c = self.shape
        i, j = np.divmod(self.rows, c)
        return self._with((c, r), self.const.T, j * r + i, self.cols, self.vals)

    # -- sums ---------------------------------------------------------------------------
    def __add__(self, other):
        if not isinstance(other, Affine):
            other = np.asarray(other, dtype=float)
            if other.shape != self.shape:
                raise ValueError(f"cannot add shapes {self.shape} and {other.shape}")
            return self._with(self.shape, self.const + other, self.rows, self.cols, self.vals)
        if other.shape != self.shape:
            raise ValueError(f"cannot add shapes {self.shape} and {other.shape}")
        return self._with(self.shape, self.const + other.const, np.concatenate([self.rows, other.rows]),
                          np.concatenate([self.cols, other.cols]), np.concatenate([self.vals, other.vals]))

    __radd__ = __add__

    def __neg__(self):
        return self._with(self.shape, -self.const, self.rows, self.cols, -self.vals)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    # -- products -----------------------------------------------------------------------
    def __mul__(self, other):
        """s·M: a number times this, or this scalar times a constant matrix."""
        k = _constant(other)
        if k is None:
            if len(self.vals):
                raise _not_affine("the product")
            return other * self.const
        if k.ndim == 0:
            s = float(k)
            return self._with(self.shape, self.const * s, self.rows, self.cols, self.vals * s)
        if self.shape:
            raise ValueError(f"cannot multiply a {self.shape} matrix by a {k.shape} matrix elementwise")
        flat = k.reshape(-1)
        nz = np.flatnonzero(flat).astype(_INT)                # vec(K s) = vec(K) s
        rows = np.repeat(nz, len(self.vals))
        cols = np.tile(self.cols, len(nz))
        vals = np.outer(flat[nz], self.vals).reshape(-1)
        return self._with(k.shape, self.const * k, rows, cols, vals)

    __rmul__ = __mul__

    def __truediv__(self, other):
        return self * (1.0 / float(other))

    def __matmul__(self, other):
        """M K: entry (i, j) of M goes to (i, b) times K_jb."""
        K = _constant(other)
        if K is None:
            if len(self.vals):
                raise _not_affine("the matrix product")
            return other.__rmatmul__(self.const)
        K = np.atleast_2d(K)
        r, c = self.shape
        if K.shape[0] != c:
            raise ValueError(f"cannot multiply {self.shape} by {K.shape}")
        if _is_identity(K):
            return self
        q = K.shape[1]
        i, j = np.divmod(self.rows, c)
        kj, kb = np.nonzero(K)                                 # sorted by the row j of K
        t, b, kv = _expand(j, kj.astype(_INT), kb.astype(_INT), K[kj, kb], c)
        rows, cols, vals = _sum_duplicates(i[t] * q + b, self.cols[t], self.vals[t] * kv)
        return self._with((r, q), self.const @ K, rows, cols, vals)

    def __rmatmul__(self, other):
        """K M: entry (i, j) of M goes to (a, j) times K_ai."""
        K = np.atleast_2d(np.asarray(other, dtype=float))
        r, c = self.shape
        if K.shape[1] != r:
            raise ValueError(f"cannot multiply {K.shape} by {self.shape}")
        if _is_identity(K):
            return self
        i, j = np.divmod(self.rows, c)
        ki, ka = np.nonzero(K.T)                               # sorted by the column i of K
        t, a, kv = _expand(i, ki.astype(_INT), ka.astype(_INT), K[ka, ki], r)
        rows, cols, vals = _sum_duplicates(a * c + j[t], self.cols[t], self.vals[t] * kv)
        return self._with((K.shape[0], c), K @ self.const, rows, cols, vals)

    def __pow__(self, exponent):
        if float(exponent) == 1.0:
            return self
        raise _not_affine("a power")

    def trace(self) -> "Affine":
        r, c = self.shape
        i, j = np.divmod(self.rows, c)
        on = i == j
        return self._with((), float(np.trace(self.const)), np.zeros(int(on.sum()), dtype=_INT),
                          self.cols[on], self.vals[on])

    def __le__(self, other):
        """``self ≤ other`` for scalars: the constraint other − self ≥ 0."""
        return Cone.nonneg(as_affine(other, ()) - self)

    def __ge__(self, other):
        return Cone.nonneg(self - as_affine(other, ()))

    # -- values -------------------------------------------------------------------------
    def value(self, x: np.ndarray):
        """M at the decision vector x (None where x has no value for a variable M uses)."""
        const = np.asarray(self.const, dtype=float).reshape(-1)
        used = x[self.cols]
        if np.isnan(used).any():
            return None
        vec = const + np.bincount(self.rows, weights=self.vals * used, minlength=len(const))
        return float(vec[0]) if not self.shape else vec.reshape(self.shape)

    def __repr__(self) -> str:
        return f"Affine({self.shape}, {len(self.vals)} coefficients)"


def as_affine(x, shape: tuple) -> Affine:
    """x as an :class:`Affine` of ``shape`` (a constant when it is a number or an array)."""
    if isinstance(x, Affine):
        return x
    const = np.asarray(x, dtype=float)
    return Affine(shape, float(const) if not shape else np.broadcast_to(const, shape).copy())


def block(rows) -> Affine:
    """The block matrix [[M_ij]] of constants and affine blocks: each block's rows moved to its place."""
    cells = [[x if isinstance(x, Affine) else np.atleast_2d(np.asarray(x, dtype=float)) for x in row]
             for row in rows]
    heights = [row[0].shape[0] for row in cells]
    widths = [x.shape[1] for x in cells[0]]
    total_c = sum(widths)
    const = assemble_blocks([[x.const if isinstance(x, Affine) else x for x in row] for row in cells])
    parts_r, parts_c, parts_v = [], [], []
    r0 = 0
    for i, row in enumerate(cells):
        c0 = 0
        for j, x in enumerate(row):
            if x.shape != (heights[i], widths[j]):
                raise ValueError(f"block ({i + 1},{j + 1}) has shape {x.shape}, expected {(heights[i], widths[j])}")
            if isinstance(x, Affine) and len(x.vals):
                bi, bj = np.divmod(x.rows, widths[j])
                parts_r.append((r0 + bi) * total_c + c0 + bj)
                parts_c.append(x.cols)
                parts_v.append(x.vals)
            c0 += widths[j]
        r0 += heights[i]
    if not parts_r:
        return Affine(const.shape, const)
    return Affine(const.shape, const, np.concatenate(parts_r), np.concatenate(parts_c), np.concatenate(parts_v))


def block_diagonal(values: list, shapes: list) -> Affine:
    """diag(M₁, …, M_k) of constants and affine blocks: each block's entries moved to its place
    on the diagonal (O(k) blocks, where :func:`block` with zero blocks would take k²)."""
    total_r, total_c = sum(r for r, _ in shapes), sum(c for _, c in shapes)
    const = np.zeros((total_r, total_c))
    parts_r, parts_c, parts_v = [], [], []
    r0 = c0 = 0
    for k, (x, (r, c)) in enumerate(zip(values, shapes)):
        value = x.const if isinstance(x, Affine) else x
        if np.shape(np.atleast_2d(value)) != (r, c):
            raise ValueError(f"diagonal block {k + 1} has shape {np.shape(np.atleast_2d(value))}, expected {(r, c)}")
        const[r0:r0 + r, c0:c0 + c] = value
        if isinstance(x, Affine) and len(x.vals):
            bi, bj = np.divmod(x.rows, c)
            parts_r.append((r0 + bi) * total_c + c0 + bj)
            parts_c.append(x.cols)
            parts_v.append(x.vals)
        r0, c0 = r0 + r, c0 + c
    if not parts_r:
        return Affine(const.shape, const)
    return Affine(const.shape, const, np.concatenate(parts_r), np.concatenate(parts_c), np.concatenate(parts_v))


@lru_cache(maxsize=64)
def svec_map(n: int) -> tuple[np.ndarray, np.ndarray]:
    """For each entry (i, j) of vec S (row-major): its position in svec S (upper triangle, column
    by column: (min, max) at max(max+1)/2 + min) and its weight in svec of (S + Sᵀ)/2 (1 on the
    diagonal, √2/2 off it: S_ij and S_ji both land on the same entry)."""
    i, j = np.divmod(np.arange(n * n, dtype=_INT), n)
    lo, hi = np.minimum(i, j), np.maximum(i, j)
    return hi * (hi + 1) // 2 + lo, np.where(i == j, 1.0, np.sqrt(2.0) / 2)


class Cone:
    """A conic constraint s(x) ∈ K on an affine vector s = const + C x (C as triplets):
    ``kind`` 'psd' (s = svec S, S ``dim``×``dim``), 'nonneg' (s ≥ 0) or 'soc' (‖s[1:]‖ ≤ s[0])."""

    __slots__ = ("kind", "dim", "rows", "cols", "vals", "const")

    def __init__(self, kind: str, dim: int, rows, cols, vals, const):
        self.kind, self.dim = kind, dim
        self.rows, self.cols, self.vals, self.const = rows, cols, vals, np.asarray(const, dtype=float)

    @classmethod
    def psd(cls, S: Affine) -> "Cone":
        """S(x) ⪰ 0 as svec S(x) in the PSD-triangle cone (of the symmetric part of S)."""
        n = S.shape[0]
        position, weight = svec_map(n)
        const = np.bincount(position, weights=weight * np.asarray(S.const, dtype=float).reshape(-1),
                            minlength=n * (n + 1) // 2)
        return cls("psd", n, position[S.rows], S.cols, S.vals * weight[S.rows], const)

    @classmethod
    def nonneg(cls, s: Affine) -> "Cone":
        const = np.atleast_1d(np.asarray(s.const, dtype=float)).reshape(-1)
        return cls("nonneg", len(const), s.rows, s.cols, s.vals, const)

    @property
    def size(self) -> int:
        return len(self.const)


__all__ = ["Affine", "Cone", "DecisionVariable", "VariableSpace", "as_affine", "block", "block_diagonal", "svec_map"]
