"""A proved lower bound on a bounded-real-lemma optimum from one frequency (the KYP lemma's dual).

For x' = A x + B w, z = C x + D w and the LMI of the bounded real lemma in the form
:meth:`~lmidsl.theorem.theorem.Theorem.bounded_real_form` declares,

* continuous time: N(P, g) = [[AᵀP + PA, PB, Cᵀ], [BᵀP, −gI, Dᵀ], [C, D, −I]] ⪯ 0,
* discrete time:   N(P, g) = [[−P, 0, AᵀP, Cᵀ], [0, −gI, BᵀP, Dᵀ], [PA, PB, −P, 0], [C, D, 0, −I]] ⪯ 0,

every feasible (P, g) — any symmetric P: neither stability nor minimality is assumed — has

    g ≥ |G(s) u|² / |u|²,   G(s) = C (sI − A)⁻¹ B + D,

for every u ≠ 0 and every s = jω (continuous) or |s| = 1 (discrete) with sI − A invertible:
with x = (sI − A)⁻¹ B u and w = G(s) u, the vector v = [x; u; w] (continuous) or [x; u; s x; w]
(discrete) gives v* N(P, g) v = |w|² − g|u|², because the storage terms cancel
(2 Re(x* P s x) = 0 when Re s = 0; |s|² x* P x − x* P x = 0 when |s| = 1); and v* N v ≤ 0.
At ω = ∞, x = 0 and w = D u.  The dual point Re(v v*) has rank two and satisfies the dual's
equations exactly; the floating-point correction of :mod:`lmidsl.certify.dual_bound` cannot do that
for a low-rank dual (on random plants of 16 states and more its corrected dual misses the cone by
~1e-9 and no interior dual exists within double precision: the primal has near-free directions).

**When the route is taken.**  Only where the theorem's LMI *is* the declared form: one of its LMIs
(not quantified, not per vertex) has, block by block, the blocks of the form built here from the
declared (A, B, C, D, P, g) — sympy must reduce each difference to zero — and the objective is g
itself (min g).  A theorem that declares the form but states another LMI gets no bound from here
(the dual route still runs).  The theorem's other LMIs only shrink the feasible set.

**What is proved.**  G(s)u is evaluated in python-flint's complex ball arithmetic from the data as
written (:class:`~lmidsl.numeric.proof.BallEvaluator`, decimals as the rationals they denote), at
s = jω with ω a double (exact), or s = ((1 − t²) + 2jt)/(1 + t²) with t = tan(θ/2) a double, a
rational point exactly on the unit circle (its ball encloses it).  The frequency is SLICOT's peak
(AB13DD) and u the top right singular vector of G(s) in floating point: any u and s give a valid
bound; these make it tight.  The lower end of the ball of |w|²/|u|² is the bound on g.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp
from flint import acb, acb_mat, arb

from ..numeric.evaluate import NumericEvaluator
from ..numeric.proof import BallEvaluator, ball_precision, round_down
from ..numeric.riccati import balancing_transform
from ..numeric.systems import frequency_variable, hinf_peak
from ..symbolic.blocks import I, block_matrix
from ..symbolic.symbols import DECISION_TYPES, ScalarVariable, SymmetricVariable, expand_derived
from ..symbolic.uncertainty import UNCERTAIN_TYPES, uncertain_atoms_of_lmi
from ..theorem.values import symbols_in

#: working precision (bits) of the ball evaluation
PRECISION = 128


def form_rows(form, time: str) -> list:
    """The lower triangle of the bounded real lemma's N(P, g) ⪯ 0 (module docstring) from the
    declared ``form`` (:class:`~lmidsl.theorem.values.BoundedRealForm`)."""
    P, g = form.storage, form.level
    A, B, C, D = form.system
    if time == "continuous":
        return [[P * A + A.T * P],
                [B.T * P, -g * I],
                [C, D, -I]]
    return [[-P],
            [0, -g * I],
            [P * A, P * B, -P],
            [C, D, 0, -I]]


def _same(a, b) -> bool:
    """Whether sympy reduces a − b to zero (a proof of equality; False when it cannot)."""
    if a == b:
        return True
    try:
        if getattr(a, "shape", None) != getattr(b, "shape", None):
            return False
        difference = sp.expand((a - b).doit())
    except (TypeError, ValueError, AttributeError, sp.ShapeError):
        return False
    return difference == 0 or isinstance(difference, sp.ZeroMatrix) or \
        (getattr(difference, "is_ZeroMatrix", False) is True)


def _data_only(expr) -> bool:
    """Whether ``expr`` involves no decision variable and no uncertain symbol (data, parameters
    and numbers only, derived parameters expanded)."""
    atoms = symbols_in(expand_derived(expr)) if isinstance(expr, sp.Basic) else frozenset()
    return not any(isinstance(a, DECISION_TYPES + UNCERTAIN_TYPES) for a in atoms)


def bounded_real_lmi(theorem):
    """The theorem's LMI that is its declared bounded-real form, block for block, or None (no
    form; a storage that is not a symmetric variable or a level that is not a scalar variable; a
    system with a variable or an uncertain symbol in it; an objective other than the level g; no
    LMI — certain, for every vertex alike, not quantified — that is the form)."""
    form = getattr(theorem, "bounded_real", None)
    if form is None or theorem.objective is None or not _same(sp.sympify(theorem.objective), form.level):
        return None
    if not isinstance(form.storage, SymmetricVariable) or not isinstance(form.level, ScalarVariable) \
            or not all(_data_only(e) for e in form.system):
        return None
    try:
        canonical = block_matrix(form_rows(form, theorem.time), where=f"{theorem.id}: bounded_real_form")
    except Exception:                 # a form whose blocks do not fit: nothing to compare with
        return None
    for lmi in theorem.lmis:
        if getattr(lmi, "quantifier", None) is not None or lmi.per_vertex or uncertain_atoms_of_lmi(lmi):
            continue
        N = lmi.negative_form()
        if N.nblocks != canonical.nblocks:
            continue
        if all(_same(N.lower[i][j], canonical.lower[i][j]) for i in range(N.nblocks) for j in range(i + 1)):
            return lmi
    return None


def _response(A, B, C, D, frequency: float, time: str) -> np.ndarray | None:
    """G(s) in floating point at ω (continuous) or θ (discrete), D at ∞; None where sI − A is
    singular."""
    if math.isinf(frequency):
        return np.atleast_2d(D)
    s = frequency_variable(frequency, time)
    try:
        return np.atleast_2d(C @ np.linalg.solve(s * np.eye(A.shape[0]) - A, B) + D)
    except np.linalg.LinAlgError:
        return None


def _gain(A, B, C, D, frequency: float, time: str) -> float:
    """σ_max(G(s)) in floating point (:func:`_response`); 0 where sI − A is singular."""
    G = _response(A, B, C, D, frequency, time)
    return 0.0 if G is None else float(np.linalg.svd(G, compute_uv=False)[0])


def _refined(A, B, C, D, frequency: float, time: str) -> float:
    """The peak near a frequency, sharpened by Brent's method on σ_max within 1e-3 (relative) of
    it: on a lightly damped mode the peak is narrow, and a frequency off in its last digits loses
    digits of σ_max."""
    from scipy.optimize import minimize_scalar
    if not math.isfinite(frequency) or frequency <= 0:
        return frequency
    width = 1e-3 * frequency
    found = minimize_scalar(lambda w: -_gain(A, B, C, D, w, time), bounds=(frequency - width, frequency + width),
                            method="bounded", options={"xatol": 1e-14 * frequency, "maxiter": 200})
    return float(found.x) if -found.fun > _gain(A, B, C, D, frequency, time) else frequency


def _peak(A, B, C, D, time: str) -> list:
    """Frequencies to try: SLICOT's peaks on the data and on the square-root balanced realisation
    (on a stiff realisation, eigenvalues 5e7 beside 1, AB13DD on the data is off in the seventh
    digit and the balanced one is not: :func:`lmidsl.numeric.riccati.realisation_norm`), each
    refined; 0 and ∞ always (the bound holds at any frequency, an unstable A included)."""
    realisations = [(A, B, C)]
    balanced = balancing_transform(A, B, C, time)
    if balanced is not None:
        T, Ti = balanced
        realisations.append((Ti @ A @ T, Ti @ B, C @ T))
    found = []
    for Ar, Br, Cr in realisations:
        gain, frequency = hinf_peak(Ar, Br, Cr, D, time)
        if math.isfinite(gain) and not math.isnan(frequency):
            found += [frequency, _refined(A, B, C, D, frequency, time)]
    return found + [0.0, math.inf]


def _direction(G: np.ndarray) -> np.ndarray:
    """The top right singular vector of G, in floating point."""
    _, _, vh = np.linalg.svd(G)
    return np.conj(vh[0])


def _ball_gain(Ab, Bb, Cb, Db, u: np.ndarray, frequency: float, time: str):
    """A ball containing |G(s) u|² / |u|² at the exact s of ``frequency`` (module docstring), or
    None when sI − A is not provably invertible."""
    n, m = Bb.shape
    uc = [acb(float(z.real), float(z.imag)) for z in u]
    Bu = [sum((Bb[i, k] * uc[k] for k in range(m)), acb(0)) for i in range(n)]
    Du = [sum((Db[i, k] * uc[k] for k in range(m)), acb(0)) for i in range(Db.shape[0])]
    if math.isinf(frequency) or n == 0:
        w = Du
    else:
        if time == "continuous":
            s = acb(0, frequency)
        else:
            t = arb(math.tan(frequency / 2.0))
            s = acb((1 - t * t) / (1 + t * t), 2 * t / (1 + t * t))
        M = acb_mat([[(s if i == j else acb(0)) - Ab[i, j] for j in range(n)] for i in range(n)])
        try:
            x = M.solve(acb_mat([[b] for b in Bu]))
        except ZeroDivisionError:
            return None
        w = [sum((Cb[i, k] * x[k, 0] for k in range(n)), acb(0)) + Du[i] for i in range(Cb.shape[0])]
    num = sum((abs(z) ** 2 for z in w), arb(0))
    den = sum((abs(z) ** 2 for z in uc), arb(0))
    return num / den


def frequency_lower_bound(instance) -> tuple[float | None, str] | None:
    """(proved lower bound on the theorem's objective g, how it was found) for an instance of a
    theorem whose LMI is its declared bounded-real form (:func:`bounded_real_lmi`), (None, why
    none was found), or None when the route does not apply (no such LMI, several vertices)."""
    theorem = instance.theorem
    if getattr(instance, "nvertices", 1) > 1 or bounded_real_lmi(theorem) is None:
        return None
    try:
        return _bound(instance)
    except (ArithmeticError, ValueError, KeyError, TypeError, np.linalg.LinAlgError) as exc:
        return None, f"the frequency response could not be evaluated ({type(exc).__name__}: {exc})"


def _bound(instance) -> tuple[float | None, str]:
    """:func:`frequency_lower_bound` once the route applies."""
    theorem = instance.theorem
    form = theorem.bounded_real
    ev = NumericEvaluator(instance.dims, dict(instance.data), instance.params)
    A, B, C, D = (np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for e in form.system)
    if not all(np.all(np.isfinite(M)) for M in (A, B, C, D)):
        return None, "the system's data are not finite"
    with ball_precision(PRECISION):
        bev = BallEvaluator(instance.dims, instance.data, instance.params)
        Ab, Bb, Cb, Db = (np.atleast_2d(np.asarray(bev.visit(e), dtype=object)) for e in form.system)
        # the highest floating-point gain first; a ball only until one is finite (each costs a
        # complex ball solve of order n)
        candidates = sorted(set(_peak(A, B, C, D, theorem.time)), reverse=True,
                            key=lambda f: _gain(A, B, C, D, f, theorem.time))
        for frequency in candidates:
            G = _response(A, B, C, D, frequency, theorem.time)
            if G is None:
                continue
            ball = _ball_gain(Ab, Bb, Cb, Db, _direction(G), frequency, theorem.time)
            if ball is None or not ball.is_finite():
                continue
            where = "ω = ∞" if math.isinf(frequency) else (
                f"ω = {frequency:.8g} rad/s" if theorem.time == "continuous" else f"θ = {frequency:.8g} rad/sample")
            return (max(round_down(float(ball.lower())), 0.0),
                    f"the frequency response at {where} (KYP: g ≥ |G(s)u|²/|u|²)")
    return None, "no frequency gave a ball bound"


__all__ = ["bounded_real_lmi", "form_rows", "frequency_lower_bound"]
