"""Proved infeasibility of a theorem's LMIs: a theorem-of-alternatives certificate, verified.

The compiled constraints are S_k(x) = S_k⁰ + Σ_c x_c S_k^c ∈ K_k (:mod:`lmidsl.certify.dual_point`;
S_k = −N_k for an LMI N_k ≺ 0 or ⪯ 0, taken at margin ε = 0).  If z = (Z_k) satisfies

    Z_k ⪰ 0 (k psd),  z_k ≥ 0 (k non-negative),  M z = 0  (Σ_k ⟨Z_k, S_k^c⟩ = 0 for every variable c),
    ⟨Z, S⁰⟩ ≤ 0  and  Σ_{k strict} tr Z_k > 0      (or ⟨Z, S⁰⟩ < 0),

then no x has N_k(x) ≺ 0 for the strict LMIs and N_j(x) ⪯ 0 for the others: for such an x,
⟨Z, S(x)⟩ = ⟨Z, S⁰⟩ ≤ 0 (M z = 0), while ⟨Z, S(x)⟩ ≥ Σ_strict ⟨Z_k, S_k(x)⟩ > 0 since S_k(x) ≻ 0
and Z_k ⪰ 0 is non-zero (with ⟨Z, S⁰⟩ < 0 no x satisfies even the closure).  Conversely such a
certificate exists whenever the strict system is infeasible (the LMIs of a theorem are a
strict system plus a closed one; alternatives theorem, e.g. Boyd et al., *LMIs in System and
Control Theory*, §2.6.1).  The statement is about the strict LMIs themselves, ε → 0: the
strictness margin of the compiled model plays no part, and an objective plays none (the
constraints alone are infeasible).

The certificate is sought from Clarabel's own infeasibility certificate of the model's last
solve (a Farkas ray: z ∈ K, Aᵀz = 0, bᵀz < 0) or else from the alternative SDP

    min ⟨Z, S⁰⟩  s.t.  M z = 0,  Σ_k tr Z_k = 1,  z ∈ K,

and verified on the compiled coefficients in two ways: in balls (the equality corrected exactly
by :func:`~lmidsl.certify.dual_point.corrected_point`, each block shown PSD over the enclosure),
and exactly (:func:`~lmidsl.certify.dual_point.exact_support_point`: a rational point on the
support of the estimate, PSD decided in exact arithmetic) — the route for certificates that are
singular by nature (an unstable mode no input reaches: Z lives on that mode).  A feasible problem
never gets a certificate: the conditions above are checked, not inferred from a status.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import clarabel
import numpy as np
from scipy import sparse

from .face_certificate import DENOMINATORS, exact_face_point
from .dual_point import (DualData, check_cone, dual_data, corrected_point, exact_support_point, last_dual,
                         pairing_bounds, round_down, svec_diagonal, U)

THRESHOLDS = (1e-3, 1e-5, 1e-7)
PATIENT = {"max_iter": 500, "static_regularization_constant": 1e-7}
"""Clarabel settings of the last alternative-SDP estimate."""      # supports tried by the exact route (relative to max |z|)


@dataclass
class InfeasibilityCertificate:
    """Whether the strict LMIs are proved infeasible, how, and the certificate's sizes."""

    proved: bool = False
    why: str = ""
    route: str | None = None          # "balls" or "exact"
    source: str | None = None         # "solver" (Clarabel's certificate) or "alternative" (the SDP)
    pairing: float | None = None      # an upper bound on ⟨Z, S⁰⟩ (≤ 0 for a certificate)
    strict_trace: float | None = None  # a lower bound on Σ_strict tr Z_k
    blocks: int = 0                   # dual blocks, and those the certificate uses (non-zero)
    nonzero_blocks: int = 0
    support: int | None = None        # unknowns on the exact route's support
    unknowns: int = 0
    times: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"proved": self.proved, "why": self.why, "route": self.route, "source": self.source,
                "pairing": self.pairing, "strict_trace": self.strict_trace, "blocks": self.blocks,
                "nonzero_blocks": self.nonzero_blocks, "support": self.support,
                "unknowns": self.unknowns, "times": self.times}


def margin_free_constants(data: DualData) -> np.ndarray:
    """svec of S⁰ (margin 0) in the problem's row order (Clarabel's units, off-diagonal × √2)."""
    out = []
    for b in data.blocks:
        if b.kind == "psd":
            d = b.dim
            S = b.s0.reshape(d, d)
            S = (S + S.T) / 2
            iu, ju = np.triu_indices(d)
            v = np.zeros(b.size)
            v[ju * (ju + 1) // 2 + iu] = S[iu, ju] * np.where(iu == ju, 1.0, np.sqrt(2.0))
            out.append(v)
        else:
            out.append(b.s0)
    return np.concatenate(out) if out else np.zeros(0)


def alternative_estimate(model, data: DualData, shift: float = 0.0, solver_options: dict | None = None,
                         zero: np.ndarray | None = None):
    """Solve the alternative SDP (module docstring) with Clarabel, with every block shifted,
    Z_k ⪰ shift·I (an interior certificate survives an exact correction), and the unknowns of the
    mask ``zero`` fixed at 0; returns (z in svec, optimal value) or None."""
    problem = model.problem
    m, n = problem.A.shape
    e = data.selector(data.blocks)
    fixed = np.flatnonzero(zero) if zero is not None else np.zeros(0, dtype=int)
    pin = sparse.csr_matrix((np.ones(len(fixed)), (np.arange(len(fixed)), fixed)), shape=(len(fixed), m))
    A = sparse.vstack([problem.A.T, sparse.csr_matrix(e.reshape(1, -1)), pin, -sparse.identity(m)]).tocsc()
    b = np.concatenate([np.zeros(n), [1.0], np.zeros(len(fixed)), -shift * e])
    cones = [clarabel.ZeroConeT(n + 1 + len(fixed))] + problem.clarabel_cones()
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_threads = 1
    for key, value in (solver_options or {}).items():
        setattr(settings, key, value)
    try:
        result = clarabel.DefaultSolver(sparse.csc_matrix((m, m)), margin_free_constants(data), A, b,
                                        cones, settings).solve()
    except BaseException as exc:                      # Clarabel panics are BaseExceptions
        if type(exc).__name__ != "PanicException" and not isinstance(exc, (ValueError, ArithmeticError)):
            raise
        return None
    if str(result.status) not in ("Solved", "AlmostSolved"):
        return None
    return np.asarray(result.x, dtype=float), float(result.obj_val)


def _strict_trace_lower(data: DualData, point, keep=None) -> float:
    total = 0.0
    for b in data.blocks:
        if b.kind == "psd" and b.strict:
            idx = data.kept_indices(b, keep)
            diag = b.offset + svec_diagonal(b.dim)[idx]
            total += float(np.sum(point.mid[diag] - point.rad[diag] * (1 + 4 * U)))
    return round_down(total * (1 - 1e-12) if total > 0 else total * (1 + 1e-12))


def _verify_balls(data: DualData, z0: np.ndarray, out: InfeasibilityCertificate) -> bool:
    zero = np.zeros(len(data.columns))
    tries = [None]
    face = data.support(z0)
    if not face.all():
        tries.append(face)
    for keep in tries:
        point = corrected_point(data, z0, zero, keep)
        if point is None:
            out.why = data.enclose() or "the equality correction failed (dependent equations not exact)"
            continue
        cone = check_cone(data, point, keep)
        if cone.worst < 0:
            out.why = f"a dual block is not proved PSD after the exact correction (λ_min ≥ {cone.worst:.3g})"
            continue
        _, high = pairing_bounds(data, point)
        trace = _strict_trace_lower(data, point, keep)
        out.pairing, out.strict_trace = high, trace
        if high < 0 or (high <= 0 and trace > 0):
            out.route = "balls"
            out.nonzero_blocks = sum(1 for b in data.blocks
                                     if np.abs(point.mid[b.offset: b.offset + b.size]).max(initial=0) > 0)
            return True
        out.why = f"⟨Z, S⁰⟩ ≤ {high:.3g} and Σ tr Z (strict) ≥ {trace:.3g}: not a certificate"
    return False


def _exact_points(data: DualData, z0: np.ndarray):
    """(where, exact point) on each entry support, then on the rational faces of the estimate's
    blocks (:mod:`lmidsl.certify.face_certificate`: singular certificates of a hidden unreachable
    mode)."""
    for threshold in THRESHOLDS:
        yield f"on the support (threshold {threshold:g})", exact_support_point(data, z0, threshold)
    for denominator in DENOMINATORS:
        yield f"on the rational face (denominators ≤ {denominator})", exact_face_point(data, z0, denominator=denominator)


def _verify_exact(data: DualData, z0: np.ndarray, out: InfeasibilityCertificate) -> bool:
    if data.enclose():
        return False
    for where, point in _exact_points(data, z0):
        if point is None:
            why = data.exact_coefficients().why
            if why and why not in out.why:
                out.why += f"; no exact route: {why}"
            continue
        if not point.psd:
            out.why = f"the exact point {where} is not PSD"
            continue
        if point.pairing < 0 or (point.pairing <= 0 and point.strict_trace > 0):
            out.route, out.support = "exact", len(point.z)
            out.pairing, out.strict_trace = float(point.pairing), float(point.strict_trace)
            blocks = set()
            for u, v in point.z.items():
                if v != 0:
                    blocks.add(next(k for k, b in enumerate(data.blocks) if b.offset <= u < b.offset + b.size))
            out.nonzero_blocks = len(blocks)
            return True
        out.why = (f"exact point {where}: ⟨Z, S⁰⟩ = {float(point.pairing):.3g}, "
                   f"Σ tr Z (strict) = {float(point.strict_trace):.3g}: not a certificate")
    return False


def prove_infeasible(model, shifts=(0.0, 1e-6, 1e-4)) -> InfeasibilityCertificate:
    """Prove that no point satisfies a direct-backend ``model``'s strict LMIs (module docstring).

    Clarabel's certificate from the model's last solve is tried first (when it said infeasible),
    then the alternative SDP with each of ``shifts`` (a shifted certificate is interior, for
    the balls; shift 0 for the exact route on singular certificates).  With conditioning
    (:mod:`lmidsl.solver.conditioning`) the compiled LMIs are T N T with T ≻ 0 and rescaled
    variables: the same feasible set, so the proof holds for the theorem as written.
    """
    t0 = time.perf_counter()
    out = InfeasibilityCertificate()
    data, out.why = dual_data(model)
    if data is not None:
        out.blocks, out.unknowns = len(data.blocks), data.nz
    if out.why:
        return out
    estimates = []
    z = last_dual(model, ("PrimalInfeasible", "AlmostPrimalInfeasible"))
    if z is not None:
        estimates.append(("solver", lambda z=z: z))
    for shift in shifts:
        estimates.append(("alternative", lambda s=shift: alternative_estimate(model, data, s)))
    irrational = data.irrational_unknowns()
    if irrational.any():
        # an LMI with no rational coefficients as written (sin θ of a sector) cannot carry an
        # exact certificate: the alternative of the other LMIs alone (Z = 0 on that one) is one,
        # of a relaxation of the problem, hence of the problem (pole region with a hidden
        # unreachable unstable mode: the half-plane LMI alone is infeasible)
        estimates.append(("alternative", lambda: alternative_estimate(model, data, 0.0, zero=irrational)))
    # Clarabel's defaults stall ("InsufficientProgress") on the alternative SDP of output feedback
    # with an unreachable unstable mode; more iterations and a smaller regularisation solve it
    estimates.append(("alternative", lambda: alternative_estimate(model, data, 0.0, PATIENT)))
    for k, (source, make) in enumerate(estimates):
        t1 = time.perf_counter()
        found = make()
        if source == "alternative":
            if found is None:
                out.why = out.why or "the alternative SDP did not solve"
                continue
            found, value = found
            if value > 1e-6:
                out.why = f"the alternative SDP's optimum is {value:.3g} > 0: no certificate (feasible, or nearly)"
                out.times[f"estimate_{k}"] = time.perf_counter() - t1
                break
        z0 = data.from_svec(found)
        scale = float(np.abs(z0).max())
        if scale == 0:
            continue
        z0 = z0 / scale
        if _verify_balls(data, z0, out) or _verify_exact(data, z0, out):
            out.proved, out.source, out.why = True, source, ""
            out.times[f"estimate_{k}"] = time.perf_counter() - t1
            break
        out.times[f"estimate_{k}"] = time.perf_counter() - t1
    out.times["total"] = time.perf_counter() - t0
    return out


__all__ = ["InfeasibilityCertificate", "prove_infeasible", "alternative_estimate"]
