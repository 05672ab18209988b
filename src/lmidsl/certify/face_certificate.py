"""An infeasibility certificate on an exact face: Z_k = V_k S_k V_kᵀ with V_k rational.

A plant with an unstable mode that no input reaches (a PBH left eigenvector w: wᴴA = λwᴴ,
Re λ ≥ 0 (continuous) or |λ| ≥ 1 (discrete), wᴴB = 0) makes a synthesis LMI infeasible, and the
theorem-of-alternatives certificate lives on the mode: in H∞ state feedback (continuous time)
Z = diag(wwᵀ, 0, 0) on the LMI and 2λ wwᵀ on Y ≻ 0 pair every variable to zero exactly because
wᵀB2 = 0 (discrete time: [λw; w][λw; w]ᵀ on the rows of Y and AY + B2W, (λ² − 1) wwᵀ on Y ≻ 0).
Such a certificate is singular (rank one per block), so an exact correction of a float estimate
on its *entry* support (:func:`lmidsl.certify.dual_point.exact_support_point`) leaves the face and
is not PSD when w is dense (the structure hidden by a change of basis).

Here the face is taken from the estimate itself: in each PSD block of a float estimate Z̃_k the
eigenvectors with eigenvalue above ``rank_tol``·max span a subspace whose reduced echelon basis
is rounded to rationals (the nearest fractions with a bounded denominator: exact when the mode is
rational, as w is for integer data under the library's power-of-two scalings), giving V_k; the unknowns are the symmetric S_k (and the kept entries of non-negative
blocks).  The equalities Σ_k ⟨V_k S_k V_kᵀ, S_k^c⟩ = 0 are solved over the rationals (python-flint),
the solution nearest the estimate's projection is taken with rational coefficients, and then, in
exact arithmetic: S_k ⪰ 0, the pairing ⟨Z, S⁰⟩ and Σ_strict tr Z_k — the conditions of
:mod:`lmidsl.certify.infeasibility`.  Nothing is inferred: a face that is not exact, or a point that
is not PSD, gives no certificate.  A plant that is only *nearly* unstabilisable (wᴴB = 1e-9) is
stabilisable in exact arithmetic, its strict LMIs are feasible, and no certificate exists — none
is found here.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
from flint import fmpq

from .dual_point import DualData, ExactPoint, _exact_rows, _fmpq, _rational_nullspace, exact_psd

DENOMINATORS = (2 ** 10, 10 ** 6, 2 ** 30)
"""Bounds on the denominators tried when rounding a face vector to a rational one."""

MAX_TRIPLETS = 200_000

"""An entry of a face vector may move by up to 0.5/√denominator when rounded (1.6e-2 at 2¹⁰):
the estimate's face is accurate to about the square root of the solver's tolerance, small entries
of the estimate (6.6e-5 where the true face is 0) must round to zero, and a wrong rounding only
fails the exact check — it never makes a certificate."""


def _rational(x: float, denominator: int):
    """The simplest fraction within 0.5/√denominator of x (the first continued-fraction
    convergent that close, its denominator ≤ ``denominator``), or None: noise of 1e-4 in an
    entry whose true value is 0 or 1/3 rounds to 0 or 1/3, not to a nearby fraction /1024."""
    tol = 0.5 / denominator ** 0.5
    h0, h1, k0, k1 = 0, 1, 1, 0          # convergents h/k
    rest = Fraction(float(x))
    while True:
        a = rest.numerator // rest.denominator
        h0, h1, k0, k1 = h1, a * h1 + h0, k1, a * k1 + k0
        if k1 > denominator:
            return None
        if abs(h1 / k1 - x) <= tol:
            return fmpq(h1, k1)
        frac = rest - a
        if frac == 0:
            return None
        rest = 1 / frac


NOISE = 1e-6
"""A block whose eigenvalues are all below this fraction of the estimate's largest entry is taken
as zero (its face is empty): a block the estimate pins at 0 comes back at ~1e-9, and its own
noise would otherwise span a full face (a sector LMI with no rational coefficients as written,
whose unknowns an exact certificate must leave at 0)."""


def _face(Z: np.ndarray, rank_tol: float, denominator: int, floor: float = 0.0):
    """A rational basis (list of columns) of the span of Z's eigenvectors with eigenvalue above
    ``rank_tol``·max and above ``floor``, or None.  The basis is the span's reduced echelon form
    (the identity on pivot rows chosen by QR with column pivoting), so a rational subspace has
    rational entries whatever mixture of it the estimate holds."""
    from scipy.linalg import qr

    w, U = np.linalg.eigh((Z + Z.T) / 2)
    top = float(np.abs(w).max()) if len(w) else 0.0
    if top <= floor:
        return []
    U = U[:, w > max(rank_tol * top, floor)]
    r = U.shape[1]
    if r == 0:
        return []
    pivots = qr(U.T, pivoting=True)[2][:r]
    W = U @ np.linalg.inv(U[pivots, :])
    cols = []
    for a in range(r):
        col = [_rational(x, denominator) for x in W[:, a]]
        if any(x is None for x in col):
            return None
        cols.append(col)
    return cols


def _unknown_entries(b) -> list:
    """(unknown, i, j) of a PSD block's unknowns: entry (i, j), i ≤ j (triu order)."""
    return [(b.offset + j * (j + 1) // 2 + i, i, j) for j in range(b.dim) for i in range(j + 1)]


def _constant(data: DualData) -> dict | None:
    """S⁰ as written paired like a row of M, {unknown: fmpq} (:meth:`DualData.exact_constant`), or
    None when there are no rational coefficients as written."""
    return data.exact_constant()


def exact_face_point(data: DualData, z0: np.ndarray, rank_tol: float = 1e-3,
                     denominator: int = DENOMINATORS[0]) -> ExactPoint | None:
    """An exact z with Z_k = V_k S_k V_kᵀ, M z = 0 (module docstring), or None (no rational face,
    no exact coefficients, too large, or no non-zero solution).  The equalities are the rows of
    M as :func:`lmidsl.certify.dual_point._exact_rows` gives them ({unknown: coefficient})."""
    if data.enclose():
        return None
    scale = float(np.abs(z0).max()) if len(z0) else 0.0
    if scale == 0.0 or sum(len(b.vals) for b in data.blocks) > MAX_TRIPLETS:
        return None
    faces, unknowns = [], 0          # per block: (V columns | kept entries, first unknown of s)
    for b in data.blocks:
        part = b.matrix(z0)
        if b.kind == "psd":
            V = _face(part, rank_tol, denominator, NOISE * scale)
            if V is None:
                return None
            faces.append((V, unknowns))
            unknowns += len(V) * (len(V) + 1) // 2
        else:
            keep = [int(i) for i in np.flatnonzero(part > rank_tol * scale)]
            faces.append((keep, unknowns))
            unknowns += len(keep)
    if unknowns == 0:
        return None
    pairs = {k: [(a, c) for c in range(len(f)) for a in range(c + 1)]
             for k, (b, (f, _)) in enumerate(zip(data.blocks, faces)) if b.kind == "psd"}
    # z_u as a linear map of s: {unknown u: {s index: exact coefficient}}
    lift: dict = {}
    for k, b in enumerate(data.blocks):
        face, first = faces[k]
        if b.kind == "psd":
            for u, i, j in _unknown_entries(b):
                terms = {}
                for t, (a, c) in enumerate(pairs[k]):
                    x = face[a][i] * face[a][j] if a == c else face[a][i] * face[c][j] + face[c][i] * face[a][j]
                    if x != 0:
                        terms[first + t] = x
                if terms:
                    lift[u] = terms
        else:
            for t, e in enumerate(face):
                lift[b.offset + e] = {first + t: fmpq(1)}
    used = np.zeros(data.nz, dtype=bool)          # the unknowns the face can make non-zero
    used[list(lift)] = True
    exact_rows = _exact_rows(data, np.arange(len(data.columns)), used)
    if exact_rows is None:
        return None
    dense = []
    for row in exact_rows:
        eq = {}
        for u, v in row.items():
            for t, x in lift.get(u, {}).items():
                eq[t] = eq.get(t, fmpq(0)) + v * x
        if any(x != 0 for x in eq.values()):
            dense.append([eq.get(t, fmpq(0)) for t in range(unknowns)])
    basis = _rational_nullspace(dense, unknowns)
    if not basis:
        return None
    target = np.zeros(unknowns)      # the estimate projected on the faces: S̃ = V⁺ Z̃ V⁺ᵀ
    for k, b in enumerate(data.blocks):
        face, first = faces[k]
        if b.kind == "psd" and face:
            V = np.array([[float(x) for x in col] for col in face]).T
            pinv = np.linalg.pinv(V)
            S = pinv @ b.matrix(z0) @ pinv.T
            for t, (a, c) in enumerate(pairs[k]):
                target[first + t] = S[a, c]
        elif b.kind != "psd":
            part = b.matrix(z0)
            for t, e in enumerate(face):
                target[first + t] = part[e]
    B = np.array([[float(x) for x in v] for v in basis]).T
    coef, *_ = np.linalg.lstsq(B, target / scale, rcond=None)
    s0 = _constant(data)
    if s0 is None:
        return None
    point = _judge(data, faces, pairs, lift, s0, _combination(basis, coef, unknowns))
    if point.psd:
        return point
    coef = _interior_coefficients(data, faces, pairs, B)      # the estimate's projection is not PSD
    return point if coef is None else _judge(data, faces, pairs, lift, s0, _combination(basis, coef, unknowns))


def _combination(basis, coef, unknowns) -> list:
    """Σ_i q(coef_i) basis_i exactly, q the float's exact rational."""
    s = [fmpq(0)] * unknowns
    for cf, v in zip(coef, basis):
        cq = _fmpq(float(cf))
        if cq != 0:
            for u, x in enumerate(v):
                if x != 0:
                    s[u] += cq * x
    return s


def _interior_coefficients(data: DualData, faces, pairs, B: np.ndarray):
    """Coefficients c of the null-space basis maximising t with every S_k(c) ⪰ t I, the strict
    traces summing to 1 and ⟨Z, S⁰⟩ ≤ 0 (a small SDP on the face, CVXPY/Clarabel), or None."""
    import cvxpy as cp

    c, t = cp.Variable(B.shape[1]), cp.Variable()
    s = B @ c
    constraints, trace, pairing = [], 0, 0
    for k, b in enumerate(data.blocks):
        face, first = faces[k]
        if b.kind == "psd" and face:
            r = len(face)
            V = np.array([[float(x) for x in col] for col in face]).T
            entries = {}
            for u, (a, e) in enumerate(pairs[k]):
                entries[a, e] = entries[e, a] = s[first + u]
            S = cp.bmat([[entries[a, e] for e in range(r)] for a in range(r)])
            constraints.append((S + S.T) / 2 >> t * np.eye(r))
            gram = V.T @ V
            S0 = b.s0.reshape(b.dim, b.dim)
            proj = V.T @ ((S0 + S0.T) / 2) @ V
            tr = cp.sum(cp.multiply(gram, S))
            trace = trace + (tr if b.strict else 0)
            pairing = pairing + cp.sum(cp.multiply(proj, S))
        elif b.kind != "psd" and face:
            part = s[first: first + len(face)]
            constraints.append(part >= t)
            pairing = pairing + b.s0[face] @ part
    if isinstance(trace, int):
        return None
    problem = cp.Problem(cp.Maximize(t), constraints + [trace == 1, pairing <= 0, cp.norm(c, "inf") <= 1e6])
    try:
        problem.solve(solver=cp.CLARABEL)
    except cp.error.SolverError:
        return None
    if c.value is None or t.value is None or t.value < 0:
        return None
    return np.asarray(c.value)


def _judge(data: DualData, faces, pairs, lift, s0, s) -> ExactPoint:
    """The exact cone check, pairing ⟨Z, S⁰⟩ = Σ_u z_u s⁰_u and traces of z = (V_k S_k V_kᵀ)."""
    psd, strict_trace, total_trace = True, fmpq(0), fmpq(0)
    z = {u: sum((x * s[t] for t, x in terms.items()), fmpq(0)) for u, terms in lift.items()}
    z = {u: v for u, v in z.items() if v != 0}
    for k, b in enumerate(data.blocks):
        face, first = faces[k]
        if b.kind == "psd":
            if not face:
                continue
            r = len(face)
            S = [[fmpq(0)] * r for _ in range(r)]
            for t, (a, c) in enumerate(pairs[k]):
                S[a][c] = S[c][a] = s[first + t]
            if not exact_psd(S):
                psd = False
            tr = sum((z.get(b.offset + i * (i + 1) // 2 + i, fmpq(0)) for i in range(b.dim)), fmpq(0))
            total_trace += tr
            if b.strict:
                strict_trace += tr
        else:
            for t in range(len(face)):
                if s[first + t] < 0:
                    psd = False
                total_trace += s[first + t]
    pairing = sum((v * s0[u] for u, v in z.items() if u in s0), fmpq(0))
    return ExactPoint(z, psd, pairing, strict_trace, total_trace)


__all__ = ["exact_face_point"]
