"""Dual points of a compiled theorem, made exactly feasible for the equalities and proved in the cone.

The shared mathematics of the proved lower bound (:mod:`lmidsl.certify.dual_bound`) and of the
proved infeasibility (:mod:`lmidsl.certify.infeasibility`).  A direct-backend model
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

**What is proved, and about which problem.**  The bounds hold for the SDP *as written*: the
theorem's data and parameters as the decimals the user wrote.  The compiled coefficients (the
floats S_k^c, S_k⁰, q) differ from those by at most the radii of :mod:`lmidsl.certify.as_written`
(``Mrad``, ``s0_rad``, ``q_rad``), which the correction and the pairing carry; the rational
routes take the coefficients as written exactly (:meth:`DualData.exact_row`).  A float dual estimate z̃ is
corrected by z = z̃ + D w with D = Mᵀ (the compiled M: a fixed direction) and w enclosing the
solution of (M' D) w = q' − M' z̃ for every M', q' within the radii of M, q: M z̃ and M D are
computed in floating point with the a-priori
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

from ..solver.backends.direct_backend import psd_diagonal
from .as_written import (EnclosureUnavailable, ExactCoefficients, coefficient_bounds, irrational_grid, radii,
                        snapshot)
from ..solver.feasibility import compiled_lmis
from ..numeric.exact import to_matrix

U = 2.0 ** -53                  # unit roundoff of double precision (round to nearest)
TINY = 2.0 ** -900              # below this a product may lose its relative error bound (underflow)
BALL_PRECISION = 128
OBJECTIVE_CUT = "objective cut"      # the label of DualData.with_objective_cut's block


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
    s0_rad: np.ndarray | None = None   # |S⁰ as written − s0| entrywise (DualData.enclose)

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
        self._snapshot = snapshot(model)
        self._enclosed: str | None = None
        self._exact: dict = {}
        self._exact_rows: dict = {}

    # -- the problem as written ---------------------------------------------------------
    def enclose(self) -> str:
        """Relate the compiled coefficients to the data as written (:mod:`lmidsl.certify.as_written`),
        once: sets ``Mrad`` (|M as written − M| entrywise), ``q_rad``, ``q0_rad`` and each block's
        ``s0_rad``.  Returns '' or why the proofs cannot be about the data as written (then they
        are not made)."""
        if self._enclosed is not None:
            return self._enclosed
        try:
            bounds = coefficient_bounds(self._snapshot)
        except EnclosureUnavailable as exc:
            self._enclosed = f"the compiled coefficients cannot be related to the data as written ({exc})"
            return self._enclosed
        psd = [b for b in self.blocks if b.kind == "psd"]
        if len(bounds.lmis) != len(psd):
            self._enclosed = "the walk of the problem as written saw other LMIs than the compile"
            return self._enclosed
        position = np.full(self.model.space.size, -1)
        position[self.columns] = np.arange(len(self.columns))
        rows, cols, vals = [], [], []
        for b, R in zip(psd, bounds.lmis):
            rad, crad = radii(R)
            if len(rad):
                r = position[R.cols]
                if np.any((r < 0) & (rad > 0)):
                    self._enclosed = (f"LMI {b.label}: a variable the compile dropped may enter it as written "
                                      "(a coefficient that cancels in floating point)")
                    return self._enclosed
                rows.append(r[r >= 0])
                cols.append(triu_index(b.dim)[R.rows[r >= 0]] + b.offset)
                vals.append(rad[r >= 0])
            b.s0_rad = np.broadcast_to(crad, (b.dim, b.dim)).reshape(-1).copy()
        for b in self.blocks:
            if b.s0_rad is None:
                b.s0_rad = np.zeros_like(b.s0)          # a non-negative variable: x ≥ 0, exact
        shape = self.M.shape
        if rows:
            self.Mrad = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                          shape=shape)
            self.Mrad.data = self.Mrad.data * (1 + 1e-12)          # the sum of radii, rounded
        else:
            self.Mrad = sparse.csr_matrix(shape)
        self.q_rad = np.zeros(len(self.columns))
        self.q0_rad = 0.0
        if bounds.objective is not None:
            rad, crad = radii(bounds.objective)
            if len(rad):
                r = position[bounds.objective.cols]
                np.add.at(self.q_rad, r[r >= 0], rad[r >= 0])
                self.q_rad *= 1 + 1e-12
            self.q0_rad = float(np.max(crad, initial=0.0)) * (1 + 1e-12)
        self._enclosed = ""
        return ""

    def exact_coefficients(self, free: dict | None = None) -> ExactCoefficients:
        """The LMIs and objective as written in rational arithmetic (built once, when first asked);
        ``free``: values for the derived parameters with irrational definitions (a point of
        :meth:`identity_points`)."""
        key = None if free is None else tuple(sorted((k, str(v)) for k, v in free.items()))
        if key not in self._exact:
            self._exact[key] = ExactCoefficients(self._snapshot, free)
        return self._exact[key]

    def identity_points(self) -> list | None:
        """Where an identity between coefficients as written is checked exactly: [None] (the true
        coefficients are rational), the grid of :func:`~lmidsl.certify.as_written.irrational_grid`
        (irrational parameters taken as free symbols), or None (neither)."""
        exact = self.exact_coefficients()
        if not exact.why and not exact.irrational():
            return [None]
        if exact.why and "NotRational" not in exact.why:
            return None
        return irrational_grid(self._snapshot) or None

    def irrational_unknowns(self) -> np.ndarray:
        """A mask of the unknowns of the LMIs with no rational coefficients as written (an exact
        certificate must be zero there)."""
        mask = np.zeros(self.nz, dtype=bool)
        psd = [b for b in self.blocks if b.kind == "psd"]
        for k in self.exact_coefficients().irrational():
            b = psd[k]
            mask[b.offset: b.offset + b.size] = True
        return mask

    def exact_row(self, c: int, free: dict | None = None):
        """(row c of M as written — {unknown: fmpq}, q_c as written), or None (no rational
        coefficients: ``exact_coefficients().why``); ``free`` as in :meth:`exact_coefficients`.
        S = −N: the unknown of entry (a, b), a ≤ b, pairs with S_ab + S_ba (a < b) or S_aa."""
        return self.exact_combination({c: fmpq(1)}, free)

    def exact_combination(self, weights: dict, free: dict | None = None):
        """(Σ_c w_c · row c of M as written, Σ_c w_c q_c) for ``weights`` = {column c: fmpq w_c},
        from one walk of the LMIs at x = Σ_c w_c e_c (:meth:`ExactCoefficients.combination`), or
        None as :meth:`exact_row`."""
        key = (tuple(sorted((int(c), str(w)) for c, w in weights.items())),
               None if free is None else tuple(sorted((k, str(v)) for k, v in free.items())))
        if key in self._exact_rows:
            return self._exact_rows[key]
        found = self.exact_coefficients(free).combination(weights)
        if found is None:
            return None
        lmis, q = found
        row = {}
        psd = iter(lmis)
        for b in self.blocks:
            if b.label == OBJECTIVE_CUT:              # s0 − qᵀx ≥ 0: −q_c as written
                if q is not None and q != 0:
                    row[b.offset] = row.get(b.offset, fmpq(0)) - q
                continue
            if b.kind != "psd":
                for c, w in weights.items():           # x_c ≥ 0: coefficient 1, exactly
                    hit = b.cols == c
                    for e, v in zip(b.rows[hit], b.vals[hit]):
                        row[b.offset + int(e)] = row.get(b.offset + int(e), fmpq(0)) + w * _fmpq(v)
                continue
            cells = next(psd)
            if cells is not None:                     # an irrational LMI: see irrational_unknowns
                _add_pairing(row, cells, b)
        row = {u: v for u, v in row.items() if v != 0}
        self._exact_rows[key] = (row, fmpq(0) if q is None else q)
        return self._exact_rows[key]

    def exact_constant(self) -> dict | None:
        """S⁰ as written paired like a row ({unknown: fmpq}: ⟨Z, S⁰⟩ = Σ z_u s_u), or None."""
        found = self.exact_coefficients().constant()
        if found is None:
            return None
        out = {}
        psd = iter(found[0])
        for b in self.blocks:
            if b.kind == "psd":
                cells = next(psd)
                if cells is not None:                 # an irrational LMI: see irrational_unknowns
                    _add_pairing(out, cells, b)
        return out

    def with_objective_cut(self, s0: float) -> "DualData | None":
        """These data with one more constraint, the objective cut s0 − qᵀx ≥ 0 (that is,
        qᵀx + q₀ ≤ U with U = q₀ + s0, q₀ as written), as a non-negative block of dimension 1
        after the others (its dual μ ≥ 0 is the last unknown; its coefficients −q carry the
        objective's radii ``q_rad``, its constant s0 is exact); None when :meth:`enclose` failed.  Every bound of the cut problem L gives min(L, U) for the
        original: a feasible x with objective ≤ U is feasible for the cut problem, one above U is
        above min(L, U) — no assumption on U (an U below the optimum only gives U back)."""
        if self.enclose() or not math.isfinite(s0):
            return None
        out = object.__new__(type(self))
        out.__dict__.update(self.__dict__)
        out._exact_rows = {}                       # the rows now pair with μ too
        live = np.flatnonzero((self.q_used != 0) | (self.q_rad > 0))
        cut = Block("nonneg", 1, np.zeros(len(live), np.int64), self.columns[live], -self.q_used[live],
                    np.array([float(s0)]), False, OBJECTIVE_CUT, self.nz, np.zeros(1))
        out.blocks, out.nz = self.blocks + [cut], self.nz + 1
        column = sparse.csr_matrix((-self.q_used[live], (live, np.zeros(len(live), np.int64))),
                                   shape=(len(self.columns), 1))
        out.M = sparse.hstack([self.M, column]).tocsr()
        out.Mabs = sparse.hstack([self.Mabs, abs(column)]).tocsr()
        radius = sparse.csr_matrix((self.q_rad[live], (live, np.zeros(len(live), np.int64))),
                                   shape=(len(self.columns), 1))
        out.Mrad = sparse.hstack([self.Mrad, radius]).tocsr()
        out.terms = self.terms + (self.q_used != 0)
        return out

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
            if b.label == OBJECTIVE_CUT:
                continue                        # μ = 0 at the optimum; the shifted duals need it
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



def _add_pairing(row: dict, cells, b: Block, sign: int = -1) -> None:
    """Add the pairing of ``sign``·N with Z_b to ``row`` ({unknown: fmpq}), N given by its cells
    [(row offset, column offset, fmpq_mat)]: entry (p, q) of S = −N pairs with the unknown of
    (min(p, q), max(p, q)), so both triangles add up (S_pq + S_qp off the diagonal)."""
    for r0, c0, C in cells:
        C = to_matrix(C)
        width = C.ncols()
        for index, v in enumerate(C.entries()):
            if v != 0:
                p, q = r0 + index // width, c0 + index % width
                u = b.offset + max(p, q) * (max(p, q) + 1) // 2 + min(p, q)
                row[u] = row.get(u, fmpq(0)) + (v if sign > 0 else -v)


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


def _gram_system(M, Mabs, Mrad, t: np.ndarray, t_rad: np.ndarray, k: np.ndarray, z0: np.ndarray) -> tuple:
    """(r, r_rad, G, G_rad, M, Mabs): the residual r = M z̃ − t and the Gram matrix G = M Mᵀ in
    floating point, with radii covering their rounding (a-priori bounds, module docstring) and
    every M′, t′ within ``Mrad``, ``t_rad`` of M, t (the equations as written, D = Mᵀ fixed)."""
    kmax = int(k.max()) + 2 if len(k) else 2
    r = M @ z0 - t
    r_rad = (gamma(kmax + 1) * (Mabs @ np.abs(z0) + np.abs(t))
             + (Mrad @ np.abs(z0) + t_rad) * (1 + gamma(kmax + 2)) + TINY)
    D = M.T.tocsr()
    Dabs = Mabs.T.tocsr()
    G = (M @ D).toarray()
    kd = int(np.diff(D.tocsc().indptr).max()) + 2 if D.nnz else 2
    G_rad = (gamma(max(kmax, kd) + 2) * (Mabs @ Dabs).toarray()
             + (Mrad @ Dabs).toarray() * (1 + gamma(max(kmax, kd) + 2)) + TINY)
    return r, r_rad, G, G_rad, M, Mabs


def corrected_point(data: DualData, z0: np.ndarray, target: np.ndarray,
                    keep: np.ndarray | None = None) -> BallPoint | None:
    """[z] ∋ z* = z̃ + D w* with M z* = target exactly, D = Mᵀ (the minimum-norm direction; see
    the module docstring); None when M Mᵀ is not provably non-singular (dependent variables).
    ``keep`` (:meth:`DualData.support`): z is exactly 0 off the support, and D = M[:, keep]ᵀ.
    (A congruence direction Z̃ H Z̃, which keeps Z̃'s near-zero eigenvalues, was tried and fails:
    the residual has components that only those directions reach, so the system is near singular.)"""
    if data.enclose():
        return None                      # no proof about the data as written
    M, Mabs, Mrad = data.M, data.Mabs, data.Mrad
    t_rad = data.q_rad if target is data.q_used else np.zeros(len(target))
    if keep is not None:
        z0 = np.where(keep, z0, 0.0)
        mask = sparse.diags(keep.astype(float))
        M, Mabs, Mrad = (M @ mask).tocsr(), (Mabs @ mask).tocsr(), (Mrad @ mask).tocsr()
    live = np.asarray(((Mabs + Mrad).sum(axis=1) > 0)).ravel()
    if np.any(~live & ((target != 0) | (t_rad > 0))):
        return None                      # a variable in the objective and in no kept constraint
    rows = np.flatnonzero(live)
    M, Mabs, Mrad, t, t_rad = M[live], Mabs[live], Mrad[live], target[live], t_rad[live]
    # many equations: at LAPACK speed (lmidsl.numeric.proof.verified_spd_solve: a verified
    # Cholesky of M Mᵀ, a norm-wise radius); few, or dependent ones, or a failed proof: the balls
    # below (componentwise radii, tighter; O(n³) ball operations)
    fast = None
    if M.shape[0] >= FAST_SOLVE_MIN:
        r, r_rad, G, G_rad, _, _ = _gram_system(M, Mabs, Mrad, t, t_rad, data.terms[rows], z0)
        # M′Mᵀ is not symmetric when M′ ≠ M: a symmetric radius ≥ |E + Eᵀ|/2 proves wᵀ(G + E)w ≥ s‖w‖²,
        # so σ_min(G + E) ≥ s for every E with |E| ≤ G_rad, and the solve's bound holds as stated
        fast = verified_spd_solve(G, np.maximum(G_rad, G_rad.T), -r, r_rad)
    if fast is not None:
        w_mid, w_rad = fast
    else:
        independent = _independent_equations(data, M, target is data.q_used, rows, keep)
        if independent is None:            # no exact dependency: the balls decide on every equation
            independent = np.arange(M.shape[0])
        r, r_rad, G, G_rad, M, Mabs = _gram_system(M[independent], Mabs[independent], Mrad[independent],
                                                   t[independent], t_rad[independent],
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


def _independent_equations(data: DualData, M, target_is_q: bool, rows: np.ndarray, keep) -> np.ndarray | None:
    """Indices of equations (rows of M) to solve; the others must follow from them *exactly*.

    Variables that enter only in a fixed combination (X − B̂ on a face of the dual) make M Mᵀ
    singular.  A pivoted QR of M Mᵀ picks independent rows; each other row i is written as
    Σ_j c_j (row j) with c rounded to rationals, and the identity row_i = Σ c_j row_j,
    t_i = Σ c_j t_j is checked in exact arithmetic on the coefficients as written (then M z = t
    on the independent rows implies it on row i; the target t is the objective's q or 0).  None
    when a dependency is not exact."""
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
    points = data.identity_points()
    if points is None:
        return None
    coef = np.linalg.lstsq(G[np.ix_(chosen, chosen)], G[np.ix_(chosen, others)], rcond=None)[0]
    combination = {}
    for col, i in enumerate(others):
        terms = []
        for j, c in zip(chosen, coef[:, col]):
            if abs(c) >= 1e-9:
                f = Fraction(float(c)).limit_denominator(1 << 20)
                terms.append((j, fmpq(f.numerator, f.denominator)))
        combination[i] = terms
    # row_i − Σ c_j row_j as written, from one walk at x = e_i − Σ c_j e_j per dependency and point
    for free in points:                  # the identities at every point: then as written
        if free is None and _irrational_kept(data, keep):
            return None
        for i, terms in combination.items():
            weights = {int(data.columns[rows[i]]): fmpq(1)}
            for j, cq in terms:
                c = int(data.columns[rows[j]])
                weights[c] = weights.get(c, fmpq(0)) - cq
            found = data.exact_combination(weights, free)
            if found is None:
                return None
            difference, rhs = found
            if (target_is_q and rhs != 0) or any(v != 0 and (keep is None or keep[u]) for u, v in difference.items()):
                return None
    return chosen


def _irrational_kept(data: DualData, keep) -> bool:
    """Whether an unknown of an LMI with no rational coefficients is on the support ``keep``."""
    irrational = data.irrational_unknowns()
    return bool(irrational.any() and (keep is None or np.any(keep & irrational)))


def _exact_rows(data: DualData, rows: np.ndarray, keep, free: dict | None = None) -> list[dict] | None:
    """The given rows of M (positions in ``data.columns``) as written, exactly: {unknown: fmpq},
    restricted to the support ``keep``; None when there are no rational coefficients
    (:class:`~lmidsl.certify.as_written.ExactCoefficients`) on the kept unknowns."""
    if free is None and _irrational_kept(data, keep):
        return None
    out = []
    for row in rows:
        found = data.exact_row(int(data.columns[row]), free)
        if found is None:
            return None
        out.append(found[0] if keep is None else {u: v for u, v in found[0].items() if keep[u]})
    return out


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
    mids, rads, s0s, s0r = [], [], [], []
    for b in data.blocks:
        idx = b.unknown_of_entry()
        mids.append(point.mid[idx])
        rads.append(point.rad[idx])
        s0s.append(b.s0)
        s0r.append(b.s0_rad if b.s0_rad is not None else np.zeros_like(b.s0))
    if not mids:
        return 0.0, 0.0
    zm, zr, s0, s0_rad = np.concatenate(mids), np.concatenate(rads), np.concatenate(s0s), np.concatenate(s0r)
    count = len(zm) + 2
    total = float(np.dot(zm, s0))
    # S⁰ as written is within s0_rad of the compiled s0 (DualData.enclose)
    err = (float(np.dot(np.abs(s0) + s0_rad, zr)) + float(np.dot(s0_rad, np.abs(zm)))) * (1 + gamma(count)) \
        + gamma(count) * float(np.dot(np.abs(s0), np.abs(zm))) + TINY
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
    to rationals; the cone and the pairing are then checked in exact arithmetic, with the
    coefficients as written (:meth:`DualData.exact_row`)."""
    if data.enclose():
        return None
    s0 = data.exact_constant()
    if s0 is None or any(b.kind != "psd" and np.any(b.s0) for b in data.blocks):
        return None
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
    # the variables whose coefficients may be non-zero on the support as written (compiled or radius)
    touching = ((data.Mabs + data.Mrad)[:, support]).tocsr()
    candidates = np.flatnonzero(np.diff(touching.indptr))
    on_support = np.zeros(data.nz, dtype=bool)
    on_support[support] = True
    exact = _exact_rows(data, candidates, on_support)
    if exact is None:
        return None
    rows = [[row.get(int(u), fmpq(0)) for u in support] for row in exact]
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
        else:
            for i in range(b.size):
                v = z.get(b.offset + i)
                if v is None:
                    continue
                if v < 0:
                    psd = False
                total_trace += v
    for u, v in z.items():                 # ⟨Z, S⁰⟩ as written (a non-negative block's S⁰ is 0)
        if v != 0 and u in s0:
            pairing += v * s0[u]
    return ExactPoint(z, psd, pairing, strict_trace, total_trace)


__all__ = ["DualData", "dual_data", "Block", "last_dual", "BallPoint", "corrected_point", "check_cone", "pairing_bounds",
           "proved_min_eigenvalue", "exact_support_point", "ExactPoint", "exact_psd"]
