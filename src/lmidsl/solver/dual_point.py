"""Dual points of a compiled theorem, made exactly feasible for the equalities and proved in the cone.

The shared mathematics of the proved lower bound (:mod:`lmidsl.solver.dual_bound`) and of the
proved infeasibility (:mod:`lmidsl.solver.infeasibility`).  A direct-backend model
(:class:`~lmidsl.solver.backends.direct_backend.DirectModel`) holds every constraint as an
affine matrix S_k(x) = S_k⁰ + Σ_c x_c S_k^c that must lie in a cone K_k: S_k = −N_k for an LMI
N_k(x) ⪯ 0 (the closure ε = 0 of a strict LMI: the margin is not part of this problem), a vector
s_k ≥ 0 for a non-negative scalar variable.  For dual matrices Z_k ∈ K_k (K self-dual) and the
objective qᵀx + q₀,

    ⟨Z, S(x)⟩ = ⟨Z, S⁰⟩ + Σ_c x_c (M z)_c,      (M z)_c = Σ_k ⟨Z_k, S_k^c⟩,

so whenever M z = q exactly, every feasible x has qᵀx + q₀ = ⟨Z, S(x)⟩ − ⟨Z, S⁰⟩ + q₀ ≥ q₀ − ⟨Z, S⁰⟩
(weak duality), and whenever M z = 0 exactly, ⟨Z, S(x)⟩ = ⟨Z, S⁰⟩ for every x (the theorem of
alternatives).  The unknowns z are the upper triangles of the Z_k (entry (a, b), a ≤ b, at
b(b+1)/2 + a: Clarabel's svec order without its √2) and the entries of the non-negative duals.

**What is proved, and about which problem.**  The data are the compiled coefficients (the
floats S_k^c, S_k⁰, q of the model, each computed once from the theorem's data in double
precision): the bounds hold for the SDP as compiled, exactly.  A float dual estimate z̃ is
corrected by z = z̃ + D w with D = Mᵀ (the minimum-norm direction) and w enclosing the exact
solution of (M D) w = q − M z̃: M z̃ and M D are computed in floating point with the a-priori
rounding bounds γ_k = k u/(1 − k u) (Higham, *Accuracy and Stability of Numerical Algorithms*,
§3.1), doubled for safety, and the linear system is solved in python-flint's ball arithmetic
(``arb_mat.solve``) or, for many equations, by a verified floating-point Cholesky
(:func:`lmidsl.numeric.proof.verified_spd_solve`), so the exact z = z̃ + D w* lies in the computed
enclosure [z] and M z = q holds exactly for it.  Each Z_k is then shown positive semidefinite for
every point of its enclosure by Rump's verified Cholesky of Z_mid − sI with Z_rad folded into the
shift (:func:`lmidsl.numeric.proof.lower_eigenvalue_bound`: λ_min ≥ s).  Floating-point rounding is to nearest
(numpy), which the γ_k bounds assume; underflow is excluded by checking magnitudes.

:func:`exact_support_point` instead projects a float estimate exactly (python-flint ``fmpq``) onto
M z = 0 on a support chosen from the estimate (principal submatrices of each Z_k), and checks
the cone exactly: the route for certificates that are singular by nature (an unstable mode that
no input reaches puts the alternative's Z on the mode's invariant subspace).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from scipy import sparse
from flint import arb, arb_mat, fmpq, fmpq_mat

from ..numeric.proof import ball_precision, lower_eigenvalue_bound, round_down, round_up, verified_spd_solve

from .backends.direct_backend import psd_diagonal
from .feasibility import compiled_lmis

U = 2.0 ** -53                  # unit roundoff of double precision (round to nearest)
TINY = 2.0 ** -900              # below this a product may lose its relative error bound (underflow)
BALL_PRECISION = 128


def gamma(k: int) -> float:
    """2·γ_k, γ_k = k u / (1 − k u): twice Higham's bound for k rounded operations (the factor 2
    absorbs the rounding of the bound itself)."""
    return 2.0 * k * U / (1.0 - k * U)


def triu_index(d: int) -> np.ndarray:
    """For entry (i, j) of a d×d matrix (row-major), the index of (min, max) in svec order."""
    i, j = np.divmod(np.arange(d * d), d)
    lo, hi = np.minimum(i, j), np.maximum(i, j)
    return hi * (hi + 1) // 2 + lo


def svec_diagonal(d: int) -> np.ndarray:
    """Positions of the diagonal entries in svec order."""
    k = np.arange(d)
    return k * (k + 1) // 2 + k


@dataclass
class Block:
    """One constraint S(x) = S⁰ + Σ_c x_c S^c ∈ K as triplets (entry of vec S, variable, value)."""

    kind: str               # "psd" (S is dim×dim, vec row-major) or "nonneg" (S is a vector)
    dim: int
    rows: np.ndarray
    cols: np.ndarray
    vals: np.ndarray
    s0: np.ndarray          # flat: d² entries (psd) or d (nonneg)
    strict: bool = False
    label: str = ""
    offset: int = 0         # first unknown of this block in z

    @property
    def size(self) -> int:
        """Number of unknowns: d(d+1)/2 (psd) or d."""
        return self.dim * (self.dim + 1) // 2 if self.kind == "psd" else self.dim

    def unknown_of_entry(self) -> np.ndarray:
        """For each entry of vec S, the unknown of z it pairs with (both triangles share one)."""
        return (triu_index(self.dim) if self.kind == "psd" else np.arange(self.dim)) + self.offset

    def matrix(self, z: np.ndarray) -> np.ndarray:
        """Z (psd, symmetric) or the vector (nonneg) from this block's unknowns of z."""
        part = z[self.offset: self.offset + self.size]
        if self.kind != "psd":
            return part
        return part[triu_index(self.dim)].reshape(self.dim, self.dim)


class DualData:
    """The constraints and objective of a direct-backend model as :class:`Block` s, and the
    adjoint map z ↦ M z over the variables the problem uses (rows of M: ``columns``)."""

    def __init__(self, model):
        self.model = model
        problem = model.problem
        self.problem = problem
        blocks = []
        lmis = compiled_lmis(model)
        for c in lmis:
            N = c.N
            if hasattr(N, "vals"):
                blocks.append(Block("psd", c.size, np.asarray(N.rows), np.asarray(N.cols), -np.asarray(N.vals),
                                    -np.asarray(N.const, dtype=float).reshape(-1), c.strict, c.label))
            else:
                blocks.append(Block("psd", c.size, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0),
                                    -np.asarray(N, dtype=float).reshape(-1), c.strict, c.label))
        for cone in getattr(model, "_nonneg", []):
            blocks.append(Block("nonneg", cone.dim, np.asarray(cone.rows), np.asarray(cone.cols),
                                np.asarray(cone.vals), np.asarray(cone.const, dtype=float).reshape(-1),
                                False, "nonneg"))
        offset = 0
        for b in blocks:
            b.offset = offset
            offset += b.size
        self.blocks, self.nz = blocks, offset
        # the problem's cones follow the same order (LMIs, then non-negative variables)
        kinds = [(c.kind, c.dim) for c in problem.cones]
        if kinds != [(b.kind, b.dim) for b in blocks]:
            raise ValueError("the model's cones do not match its LMIs and non-negative variables")
        rows, cols, vals = [], [], []
        for b in blocks:
            rows.append(b.cols)
            cols.append(b.unknown_of_entry()[b.rows])
            vals.append(b.vals)
        rows = np.concatenate(rows) if rows else np.zeros(0, np.int64)
        cols = np.concatenate(cols) if cols else np.zeros(0, np.int64)
        vals = np.concatenate(vals) if vals else np.zeros(0)
        objective = model.objective
        nvar = model.space.size
        self.q = np.zeros(nvar)
        self.q0 = 0.0
        self.has_objective = objective is not None
        if hasattr(objective, "vals"):
            # exact sums of the objective's coefficients per variable (fsum is correctly rounded;
            # a duplicate-free objective, the usual case, is copied exactly)
            ocols = np.asarray(objective.cols)
            ovals = np.asarray(objective.vals, dtype=float)
            for c in np.unique(ocols):
                self.q[c] = math.fsum(ovals[ocols == c])
            self.q0 = float(objective.const)
        elif objective is not None:
            self.q0 = float(objective)
        used = np.zeros(nvar, dtype=bool)
        used[rows] = True
        used[self.q != 0] = True
        self.columns = np.flatnonzero(used)
        where = np.full(nvar, -1)
        where[self.columns] = np.arange(len(self.columns))
        r = where[rows]
        self.terms = np.bincount(r, minlength=len(self.columns))   # rounded operations per row
        shape = (len(self.columns), self.nz)
        self.M = sparse.csr_matrix((vals, (r, cols)), shape=shape)
        self.Mabs = sparse.csr_matrix((np.abs(vals), (r, cols)), shape=shape)
        self.q_used = self.q[self.columns]
        self.magnitude_ok = not np.any((np.abs(vals) > 0) & (np.abs(vals) < TINY))

    # -- clarabel's dual in these unknowns -----------------------------------------------
    def from_svec(self, z_svec: np.ndarray, scale: float = 1.0) -> np.ndarray:
        """Clarabel's z (svec, off-diagonal entries times √2) as the unknowns z (times ``scale``)."""
        z = np.array(z_svec, dtype=float) * scale
        for b in self.blocks:
            if b.kind == "psd":
                part = z[b.offset: b.offset + b.size]
                mask = np.ones(b.size, dtype=bool)
                mask[svec_diagonal(b.dim)] = False
                part[mask] /= math.sqrt(2.0)
        return z

    def support(self, z0: np.ndarray, threshold: float = 1e-6) -> np.ndarray:
        """A mask of the unknowns kept: in each psd block the principal submatrix of the indices
        whose diagonal exceeds ``threshold`` times the largest diagonal entry of any block (a PSD
        matrix with a zero diagonal entry has a zero row and column), in a non-negative block the
        entries above it.  Dual matrices that complementarity makes singular (an inactive P ≻ 0
        has Z_P = 0; a primal direction that grows a block at no cost) are then solved for on
        their face, with the rest exactly 0."""
        top = 0.0
        for b in self.blocks:
            part = z0[b.offset: b.offset + b.size]
            diag = part[svec_diagonal(b.dim)] if b.kind == "psd" else part
            if len(diag):
                top = max(top, float(diag.max()))
        keep = np.ones(self.nz, dtype=bool)
        if top <= 0:
            return keep
        for b in self.blocks:
            part = z0[b.offset: b.offset + b.size]
            if b.kind != "psd":
                keep[b.offset: b.offset + b.size] = part > threshold * top
                continue
            small = part[svec_diagonal(b.dim)] <= threshold * top
            if small.any():
                i, j = np.divmod(np.arange(b.dim * b.dim), b.dim)
                drop = small[i] | small[j]
                keep[b.offset + triu_index(b.dim)[drop]] = False
        return keep

    def kept_indices(self, block: Block, keep: np.ndarray | None) -> np.ndarray:
        """The rows/columns of a psd block's principal submatrix on the support."""
        if keep is None:
            return np.arange(block.dim)
        return np.flatnonzero(keep[block.offset + svec_diagonal(block.dim)])

    def selector(self, blocks, keep: np.ndarray | None = None) -> np.ndarray:
        """The svec vector with 1 on the diagonals of the given psd blocks and on every entry of
        the given non-negative blocks (the direction of a shift Z → Z + εI)."""
        e = np.zeros(self.nz)
        for b in blocks:
            if b.kind == "psd":
                e[b.offset + svec_diagonal(b.dim)] = 1.0
            else:
                e[b.offset: b.offset + b.size] = 1.0
        return e if keep is None else e * keep



def dual_data(model) -> tuple:
    """(DualData of a direct-backend ``model`` or None, why it cannot be used — '' when it can):
    the conic data both proofs (the dual bound, the infeasibility certificate) work on, refused for
    another backend, for cones other than LMIs and non-negative variables, and for coefficients so
    small that the rounding bounds fail (the data are then returned with the reason)."""
    if getattr(model, "backend", None) != "direct":
        return None, f"the {getattr(model, 'backend', '?')} backend keeps no conic data (direct backend only)"
    try:
        data = DualData(model)
    except ValueError as exc:
        return None, f"the model's cones are not all LMIs and non-negative variables ({exc})"
    if not data.magnitude_ok:
        return data, "coefficients below 2^-900: rounding bounds do not hold (underflow)"
    return data, ""

def last_dual(model, statuses: tuple, shifted: bool = False) -> np.ndarray | None:
    """Clarabel's z (svec) from the model's last solve of its own problem when that solve ended
    in one of ``statuses``, or None.  ``shifted``: a main solve with a dual shift ε
    (``DirectModel.dual_shift``) returns Z′; Z = Z′ + εI is the theorem's dual."""
    last = getattr(model, "_last", None)
    if last is None or last[0] is not model.problem or str(last[1].status) not in statuses:
        return None
    z = np.asarray(last[1].z, dtype=float)
    if shifted and getattr(model, "last_shift", 0.0):
        z = z + model.last_shift * psd_diagonal(model.problem)
    return z if np.all(np.isfinite(z)) and np.abs(z).max(initial=0.0) > 0 else None


@dataclass
class BallPoint:
    """An enclosure [z] = z_mid ± z_rad that contains an exact z with M z = target."""

    mid: np.ndarray
    rad: np.ndarray
    residual: float          # ‖M z̃ − target‖∞ before the correction
    correction: float        # ‖z − z̃‖∞


#: equations from which the correction's linear system is solved in floating point first
FAST_SOLVE_MIN = 120


def _gram_system(M, Mabs, t: np.ndarray, k: np.ndarray, z0: np.ndarray) -> tuple:
    """(r, r_rad, G, G_rad, M, Mabs): the residual r = M z̃ − t and the Gram matrix G = M Mᵀ in
    floating point with their a-priori rounding bounds (module docstring)."""
    kmax = int(k.max()) + 2 if len(k) else 2
    r = M @ z0 - t
    r_rad = gamma(kmax + 1) * (Mabs @ np.abs(z0) + np.abs(t)) + TINY
    D = M.T.tocsr()
    G = (M @ D).toarray()
    kd = int(np.diff(D.tocsc().indptr).max()) + 2 if D.nnz else 2
    G_rad = gamma(max(kmax, kd) + 2) * (Mabs @ Mabs.T).toarray() + TINY
    return r, r_rad, G, G_rad, M, Mabs


def corrected_point(data: DualData, z0: np.ndarray, target: np.ndarray,
                    keep: np.ndarray | None = None) -> BallPoint | None:
    """[z] ∋ z* = z̃ + D w* with M z* = target exactly, D = Mᵀ (the minimum-norm direction; see
    the module docstring); None when M Mᵀ is not provably non-singular (dependent variables).
    ``keep`` (:meth:`DualData.support`): z is exactly 0 off the support, and D = M[:, keep]ᵀ.
    (A congruence direction Z̃ H Z̃, which keeps Z̃'s near-zero eigenvalues, was tried and fails:
    the residual has components that only those directions reach, so the system is near singular.)"""
    M, Mabs = data.M, data.Mabs
    if keep is not None:
        z0 = np.where(keep, z0, 0.0)
        mask = sparse.diags(keep.astype(float))
        M, Mabs = (M @ mask).tocsr(), (Mabs @ mask).tocsr()
    live = np.asarray((Mabs.sum(axis=1) > 0)).ravel()
    if np.any(~live & (target != 0)):
        return None                      # a variable in the objective and in no kept constraint
    rows = np.flatnonzero(live)
    M, Mabs, t = M[live], Mabs[live], target[live]
    # many equations: at LAPACK speed (lmidsl.numeric.proof.verified_spd_solve: a verified
    # Cholesky of M Mᵀ, a norm-wise radius); few, or dependent ones, or a failed proof: the balls
    # below (componentwise radii, tighter; O(n³) ball operations)
    fast = None
    if M.shape[0] >= FAST_SOLVE_MIN:
        r, r_rad, G, G_rad, _, _ = _gram_system(M, Mabs, t, data.terms[rows], z0)
        fast = verified_spd_solve(G, G_rad, -r, r_rad)
    if fast is not None:
        w_mid, w_rad = fast
    else:
        independent = _independent_equations(data, M, t, rows, keep)
        if independent is None:            # no exact dependency: the balls decide on every equation
            independent = np.arange(M.shape[0])
        r, r_rad, G, G_rad, M, Mabs = _gram_system(M[independent], Mabs[independent], t[independent],
                                                   data.terms[rows[independent]], z0)
        n = G.shape[0]
        if n == 0:
            return BallPoint(z0.copy(), np.zeros_like(z0), 0.0, 0.0)
        with ball_precision(BALL_PRECISION):
            Gb = arb_mat([[arb(G[i, j], G_rad[i, j]) for j in range(n)] for i in range(n)])
            rhs = arb_mat([[arb(-r[i], r_rad[i])] for i in range(n)])
            try:
                w = Gb.solve(rhs)
            except ZeroDivisionError:
                return None
            w_mid = np.array([float(w[i, 0].mid()) for i in range(n)])     # rounded to nearest
            w_rad = np.array([round_up(float(w[i, 0].rad())) for i in range(n)]) + np.abs(w_mid) * 2 * U + TINY
    w_rad = np.array([round_up(x) for x in w_rad])
    D, Dabs = M.T.tocsr(), Mabs.T.tocsr()
    step = D @ w_mid
    mid = z0 + step
    kd = int(np.diff(D.indptr).max()) + 2 if D.nnz else 2
    reach = Dabs @ np.ones(len(w_mid))
    rad = (Dabs @ w_rad) * (1 + gamma(kd)) + gamma(kd + 1) * (np.abs(z0) + Dabs @ np.abs(w_mid))
    rad += TINY * ((z0 != 0) | (reach > 0))         # (an exact 0 untouched by D stays exactly 0)
    return BallPoint(mid, rad, float(np.abs(r).max()) if len(r) else 0.0, float(np.abs(step).max()) if len(step) else 0.0)


DEPENDENT = 1e-11     # a pivot of the Gram matrix below this (relative) marks a dependent equation


def _independent_equations(data: DualData, M, t: np.ndarray, rows: np.ndarray, keep) -> np.ndarray | None:
    """Indices of equations (rows of M) to solve; the others must follow from them *exactly*.

    Variables that enter only in a fixed combination (X − B̂ on a face of the dual) make M Mᵀ
    singular.  A pivoted QR of M Mᵀ picks independent rows; each other row i is written as
    Σ_j c_j (row j) with c rounded to rationals, and the identity row_i = Σ c_j row_j,
    t_i = Σ c_j t_j is checked in exact arithmetic on the compiled coefficients (then M z = t on
    the independent rows implies it on row i).  None when a dependency is not exact."""
    from scipy.linalg import qr

    n = M.shape[0]
    if n == 0:
        return np.arange(0)
    G = (M @ M.T).toarray()
    _, R, order = qr(G, pivoting=True)
    diag = np.abs(np.diag(R))
    rank = int(np.sum(diag > DEPENDENT * diag[0])) if diag[0] > 0 else 0
    if rank == n:
        return np.arange(n)
    chosen, others = np.sort(order[:rank]), order[rank:]
    exact = _exact_rows(data, rows, keep)
    coef = np.linalg.lstsq(G[np.ix_(chosen, chosen)], G[np.ix_(chosen, others)], rcond=None)[0]
    for col, i in enumerate(others):
        combo = {}
        rhs = _fmpq(t[i])
        for j, c in zip(chosen, coef[:, col]):
            if abs(c) < 1e-9:
                continue
            f = Fraction(float(c)).limit_denominator(1 << 20)
            cq = fmpq(f.numerator, f.denominator)
            for u, v in exact[j].items():
                combo[u] = combo.get(u, fmpq(0)) + cq * v
            rhs -= cq * _fmpq(t[j])
        if rhs != 0 or any(combo.get(u, fmpq(0)) != v for u, v in exact[i].items()) or \
                any(v != 0 and u not in exact[i] for u, v in combo.items()):
            return None
    return chosen


def _exact_rows(data: DualData, rows: np.ndarray, keep) -> list[dict]:
    """The given rows of M (positions in ``data.columns``) exactly: {unknown: fmpq}, the sums of
    the compiled triplets, restricted to the support ``keep``."""
    position = np.full(data.model.space.size, -1)
    position[data.columns[rows]] = np.arange(len(rows))
    out = [dict() for _ in rows]
    for b in data.blocks:
        unknown = b.unknown_of_entry()[b.rows]
        r = position[b.cols]
        hit = r >= 0
        if keep is not None:
            hit &= keep[unknown]
        for i, u, v in zip(r[hit], unknown[hit], b.vals[hit]):
            d = out[int(i)]
            d[int(u)] = d.get(int(u), fmpq(0)) + _fmpq(v)
    return [{u: v for u, v in d.items() if v != 0} for d in out]


def proved_min_eigenvalue(S: np.ndarray, S_rad: np.ndarray | None = None) -> float | None:
    """A proved lower bound on λ_min over the symmetric matrices |X − S| ≤ S_rad (S's floats
    taken exactly): Rump's verified Cholesky of the shifted enclosure
    (:func:`lmidsl.numeric.proof.lower_eigenvalue_bound`); None when no shift is proved."""
    if S.shape[0] and not np.abs(S).max() and (S_rad is None or not S_rad.any()):
        return 0.0
    return lower_eigenvalue_bound(S, S_rad)


@dataclass
class ConeCheck:
    """λ_min lower bounds of every block over the enclosure, proved."""

    lower: list = field(default_factory=list)      # per block: proved lower bound on λ_min (or min entry)

    @property
    def worst(self) -> float:
        return min(self.lower) if self.lower else math.inf

    def failing(self, blocks) -> list:
        return [b for b, low in zip(blocks, self.lower) if not low >= 0.0]


def check_cone(data: DualData, point: BallPoint, keep: np.ndarray | None = None) -> ConeCheck:
    """For each block, a proved lower bound on λ_min(Z) (psd) or min z (nonneg) over [z]; with
    a support ``keep``, λ_min of the principal submatrix on it (the rest of Z is exactly 0)."""
    out = ConeCheck()
    for b in data.blocks:
        if b.kind == "psd":
            idx = data.kept_indices(b, keep)
            if len(idx) == 0:
                out.lower.append(math.inf)           # exactly 0 on the support: no constraint
                continue
            Zm = b.matrix(point.mid)[np.ix_(idx, idx)]
            Zr = b.matrix(point.rad)[np.ix_(idx, idx)]
            low = proved_min_eigenvalue(Zm, Zr)
            out.lower.append(-math.inf if low is None else low)
        else:
            part = point.mid[b.offset: b.offset + b.size]
            part_r = point.rad[b.offset: b.offset + b.size]
            if not b.size:
                out.lower.append(math.inf)
                continue
            low = np.where(part_r == 0, part, part - part_r * (1 + 4 * U))    # exact where rad = 0
            out.lower.append(float(low.min()) if not part_r.any() else round_down(float(low.min())))
    return out


def pairing_bounds(data: DualData, point: BallPoint) -> tuple[float, float]:
    """Proved [lo, hi] ∋ ⟨Z, S⁰⟩ = Σ_k ⟨Z_k, S_k⁰⟩ over the enclosure."""
    total, err, count = 0.0, 0.0, 0
    mids, rads, s0s = [], [], []
    for b in data.blocks:
        idx = b.unknown_of_entry()
        mids.append(point.mid[idx])
        rads.append(point.rad[idx])
        s0s.append(b.s0)
    if not mids:
        return 0.0, 0.0
    zm, zr, s0 = np.concatenate(mids), np.concatenate(rads), np.concatenate(s0s)
    count = len(zm) + 2
    total = float(np.dot(zm, s0))
    err = float(np.dot(np.abs(s0), zr)) * (1 + gamma(count)) + gamma(count) * float(np.dot(np.abs(s0), np.abs(zm))) + TINY
    return round_down(total - round_up(err)), round_up(total + round_up(err))


# -- the exact route -------------------------------------------------------------------

def _fmpq(x: float) -> fmpq:
    n, d = float(x).as_integer_ratio()
    return fmpq(n, d)


def _rational_nullspace(rows: list[list[fmpq]], ncols: int) -> list[list[fmpq]]:
    """A basis of {u : R u = 0} over the rationals (from the reduced row echelon form)."""
    if not rows:
        basis = []
        for j in range(ncols):
            v = [fmpq(0)] * ncols
            v[j] = fmpq(1)
            basis.append(v)
        return basis
    R = fmpq_mat(len(rows), ncols, [x for row in rows for x in row])
    E, rank = R.rref()
    pivots = []
    for i in range(rank):
        for j in range(ncols):
            if E[i, j] != 0:
                pivots.append(j)
                break
    free = [j for j in range(ncols) if j not in set(pivots)]
    basis = []
    for f in free:
        v = [fmpq(0)] * ncols
        v[f] = fmpq(1)
        for i, p in enumerate(pivots):
            v[p] = -E[i, f]
        basis.append(v)
    return basis


def exact_psd(Z: list[list[fmpq]]) -> bool:
    """Whether a rational symmetric matrix is positive semidefinite, exactly (LDLᵀ with symmetric
    pivoting on the largest diagonal; a zero pivot needs a zero remaining column)."""
    A = [row[:] for row in Z]
    n = len(A)
    active = list(range(n))
    while active:
        p = max(active, key=lambda i: A[i][i])
        d = A[p][p]
        if d < 0:
            return False
        if d == 0:
            return all(A[i][j] == 0 for i in active for j in active)
        active.remove(p)
        for i in active:
            f = A[i][p] / d
            if f == 0:
                continue
            for j in active:
                A[i][j] -= f * A[p][j]
    return True


@dataclass
class ExactPoint:
    """An exact rational z on a support with M z = target, its blocks' PSD verdicts."""

    z: dict                  # unknown index -> fmpq (the support; zero elsewhere)
    psd: bool
    pairing: fmpq            # ⟨Z, S⁰⟩ exactly
    strict_trace: fmpq       # Σ over strict LMIs of tr Z_k exactly
    total_trace: fmpq


def exact_support_point(data: DualData, z0: np.ndarray, threshold: float, max_unknowns: int = 400) -> ExactPoint | None:
    """Round a float estimate z̃ (with M z̃ ≈ 0) to an exact z on its support and check the cone.

    Support: in each psd block the indices whose diagonal exceeds ``threshold``·max|z̃| (a PSD
    matrix with a zero diagonal entry has a zero row) — the principal submatrix Z[I, I]; in a
    non-negative block the entries above the threshold.  z is the point of {z on the support :
    M z = 0} (a rational null space) nearest to z̃ in least squares, its coefficients rounded
    to rationals; the cone and the pairing are then checked in exact arithmetic."""
    scale = float(np.abs(z0).max()) if len(z0) else 0.0
    if scale == 0.0:
        return None
    support = []
    for b in data.blocks:
        part = z0[b.offset: b.offset + b.size]
        if b.kind == "psd":
            diag = part[svec_diagonal(b.dim)]
            keep = np.flatnonzero(diag > threshold * scale)
            for jj, j in enumerate(keep):
                for i in keep[: jj + 1]:
                    support.append(b.offset + j * (j + 1) // 2 + i)
        else:
            support.extend((b.offset + np.flatnonzero(part > threshold * scale)).tolist())
    if not support or len(support) > max_unknowns:
        return None
    support = np.array(sorted(support))
    where = np.full(data.nz, -1)
    where[support] = np.arange(len(support))
    exact: dict = {}                    # (variable, support position) -> the exact sum of triplets
    for b in data.blocks:
        unknown = b.unknown_of_entry()[b.rows]
        hit = where[unknown] >= 0
        for c, j, v in zip(b.cols[hit], where[unknown[hit]], b.vals[hit]):
            key = (int(c), int(j))
            exact[key] = exact.get(key, fmpq(0)) + _fmpq(v)
    variables = sorted({c for c, _ in exact})
    row_of = {c: i for i, c in enumerate(variables)}
    rows = [[fmpq(0)] * len(support) for _ in variables]
    for (c, j), v in exact.items():
        rows[row_of[c]][j] = v
    rows = [row for row in rows if any(x != 0 for x in row)]
    basis = _rational_nullspace(rows, len(support))
    if not basis:
        return None
    B = np.array([[float(x) for x in v] for v in basis]).T          # support × k
    target = z0[support]
    coef, *_ = np.linalg.lstsq(B, target, rcond=None)
    z = {}
    for idx in range(len(support)):
        z[int(support[idx])] = fmpq(0)
    for c, v in zip(coef, basis):
        cq = _fmpq(float(c))
        if cq == 0:
            continue
        for idx, x in enumerate(v):
            if x != 0:
                z[int(support[idx])] += cq * x
    psd = True
    pairing = fmpq(0)
    strict_trace = fmpq(0)
    total_trace = fmpq(0)
    for b in data.blocks:
        if b.kind == "psd":
            d = b.dim
            idx = [i for i in range(d) if (b.offset + i * (i + 1) // 2 + i) in z]
            if not idx:
                continue
            Z = [[z.get(b.offset + max(i, j) * (max(i, j) + 1) // 2 + min(i, j), fmpq(0)) for j in idx] for i in idx]
            if not exact_psd(Z):
                psd = False
            tr = sum((Z[k][k] for k in range(len(idx))), fmpq(0))
            total_trace += tr
            if b.strict:
                strict_trace += tr
            for a, i in enumerate(idx):
                for c_, j in enumerate(idx):
                    s = b.s0[i * d + j]
                    if s != 0 and Z[a][c_] != 0:
                        pairing += Z[a][c_] * _fmpq(s)
        else:
            for i in range(b.size):
                v = z.get(b.offset + i)
                if v is None:
                    continue
                if v < 0:
                    psd = False
                total_trace += v
                if b.s0[i] != 0:
                    pairing += v * _fmpq(b.s0[i])
    return ExactPoint(z, psd, pairing, strict_trace, total_trace)


__all__ = ["DualData", "dual_data", "Block", "last_dual", "BallPoint", "corrected_point", "check_cone", "pairing_bounds",
           "proved_min_eigenvalue", "exact_support_point", "ExactPoint", "exact_psd"]
