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

**State feedback.**  For the H∞ state-feedback LMIs in the form
:meth:`~lmidsl.theorem.theorem.Theorem.state_feedback_form` declares (level γ on both diagonal
blocks, Y = P⁻¹, W = K Y; module :mod:`textbook.hinf_sf`), every feasible (Y, W, γ) — any
symmetric Y, any W — has

    γ ≥ |P11(s)ᵀ r| / |r|   for every r ≠ 0 with P12(s)ᵀ r = 0,

P11(s) = C1 (sI − A)⁻¹ B1 + D11 and P12(s) = C1 (sI − A)⁻¹ B2 + D12 at s = jω or |s| = 1: with
p = (sI − Aᵀ)⁻¹ C1ᵀ r, the vector v = [p; q; r] (discrete: [s p; q; p; r]) makes the W terms
2 Re((B2ᵀp + D12ᵀr)* W p) vanish (B2ᵀp + D12ᵀr = P12(s)ᵀ r = 0) and the Y terms too
(2 Re(s̄) p*Yp = 0; discrete: (2|s|² − |s|² − 1) p*Yp = 0), leaving
2 Re(q*h) − γ(|q|² + |r|²) ≤ 0 with h = P11(s)ᵀ r, whose maximum over q = (|r|/|h|) h gives the
bound.  That is the part of the disturbance's effect no control input can cancel, frequency by
frequency: the optimum when it is set by the Hamiltonian's imaginary-axis eigenvalues (on stable
plants often), far below it when it is set by stabilisation (an unstable plant's optimum, where
Y grows without bound: there :mod:`lmidsl.certify.hamiltonian_bound` gives a dual point from
the Hamiltonian's stable eigenvectors (continuous time) or an interpolation certificate (discrete time), and the higher bound is kept).  In the
balls r = r₀ − P̄12 (P12ᵀ P̄12)⁻¹ P12ᵀ r₀ is the exact projection of a floating-point r₀ onto the
kernel, so the bound is that of an exact dual vector.

**Output feedback.**  The full-order H∞ LMI in the linearising variables
(:meth:`~lmidsl.theorem.theorem.Theorem.output_feedback_form`; Scherer, Gahinet, Chilali 1997:
A11 = AX + B2Ĉ, A12 = A + B2D̂C2, A22 = YA + B̂C2, B1' = B1 + B2D̂D21, B2' = YB1 + B̂D21,
C1' = C1X + D12Ĉ, C2' = C1 + D12D̂C2, D' = D11 + D12D̂D21) contains two state-feedback LMIs:

* *full information*: its rows and columns of X, w and z (continuous: 1, 3, 4; discrete: 1, 3,
  4, 6) are the state-feedback form of (A, B1, B2, C1, D11, D12) with Y = X, W = Ĉ, and B1, D11
  replaced by B1 + B2W₂, D11 + D12W₂ with W₂ = D̂D21;
* *full control*: its rows and columns of Y, z and w (continuous: 2, 4, 3) are the same form for
  the dual plant (Aᵀ, C1ᵀ, C2ᵀ, B1ᵀ, D11ᵀ, D21ᵀ) with W = B̂ᵀ and W₂ = D̂ᵀD12ᵀ.

A dual vector of the state-feedback bounds above (frequency response, Hamiltonian, interpolation),
padded with zeros in the other rows, is a dual vector of the output-feedback LMI: the W₂ terms are
2 Re((B2ᵀp + D12ᵀr)* W₂ q), zero by the same identity B2ᵀp + D12ᵀr = 0 that removes the W
terms, and no other variable (Â, and Y or X) meets those rows.  The sign of the Y terms needs
X ⪰ 0 (Y ⪰ 0 for full control), which holds when −X is a diagonal block of one of the theorem's
LMIs ((XY) ≻ 0 in continuous time, the LMI itself in discrete time): a principal block of a
negative semidefinite matrix is negative semidefinite, and the dual point [[M, 0], [0, 0]] on
that LMI takes up the X terms.  So γ ≥ max(full-information bound, full-control bound): tight
where the optimum is set by one of the two Riccati equations, not where it is set by the
coupling ρ(XY) < γ².

In discrete time the full-control rows (2, 3, 5, 6), [[−Y], [0, −γI], [YA + B̂C2, YB1 + B̂D21, −Y],
[C2', D', 0, −γI]], carry YA, not AY, and are checked directly: for points |sᵢ| > 1 (|s| = 1 for
the frequency bound) and qᵢ in the kernel of P21(sᵢ) = C2(sᵢI − A)⁻¹B1 + D21, the vectors
vᵢ = [aᵢ; qᵢ; sᵢaᵢ; rᵢ] with aᵢ = (sᵢI − A)⁻¹B1qᵢ remove B̂ and D̂ (C2aᵢ + D21qᵢ = 0), the Y terms
of Σ Gᵢⱼ vⱼ*Nvᵢ are tr(M A*YA) with A = [aᵢ] and Mᵢⱼ = Gᵢⱼ(sᵢs̄ⱼ − 1), the all-ones matrix for the
Pick kernel G, and rᵢ = κP11(sᵢ)qᵢ gives γ ≥ √(tr(G H*H)/tr(G Q*Q)), H = [P11(sᵢ)qᵢ]: the numbers
of the state-feedback certificates of the dual plant, whose P12(s)ᵀ is P21(s) and P11(s)ᵀ is
P11(s).

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
from .coupling_bound import coupling_bound
from .hamiltonian_bound import (exact_entries, full_column_rank, inner, interpolation_bound, projected_response, proved_root, stabilisation_bound,
                                transfer)
from ..numeric.proof import BallEvaluator, ball_precision, round_down
from ..numeric.riccati import balancing_transform
from ..numeric.systems import frequency_variable, hinf_peak
from ..symbolic.blocks import I, block_matrix
from ..symbolic.symbols import DECISION_TYPES, ScalarVariable, SymmetricVariable, expand_derived
from ..symbolic.uncertainty import UNCERTAIN_TYPES, uncertain_atoms_of_lmi
from ..theorem.values import symbols_in

#: working precision (bits) of the ball evaluation
PRECISION = 128
#: precision (bits) of the output-feedback plant's balls: the coupled certificate's stable
#: subspaces can be so ill-conditioned that data balls 2⁻¹²⁸ wide leave its enclosure useless
#: (COMPleib's AC7); its own working precision rises as needed (coupling_bound.ENCLOSURE_LADDER)
COUPLING_DATA_PRECISION = 1024


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


def state_feedback_rows(form, time: str) -> list:
    """The lower triangle of the H∞ state-feedback LMI N(Y, W, γ) ⪯ 0 (module docstring) from the
    declared ``form`` (:class:`~lmidsl.theorem.values.StateFeedbackForm`)."""
    Y, W, g = form.Y, form.W, form.level
    A, B1, B2, C1, D11, D12 = form.plant
    if time == "continuous":
        return [[A * Y + B2 * W + (A * Y + B2 * W).T],
                [B1.T, -g * I],
                [C1 * Y + D12 * W, D11, -g * I]]
    return [[-Y],
            [0, -g * I],
            [A * Y + B2 * W, B1, -Y],
            [C1 * Y + D12 * W, D11, 0, -g * I]]


def output_feedback_rows(form, time: str) -> list:
    """The lower triangle of the full-order H∞ output-feedback LMI (module docstring) from the
    declared ``form`` (:class:`~lmidsl.theorem.values.OutputFeedbackForm`), written out here from
    the change of variables, not taken from the theorem."""
    X, Y, Ah, Bh, Ch, Dh, g = form.X, form.Y, form.Ah, form.Bh, form.Ch, form.Dh, form.level
    A, B1, B2, C1, C2, D11, D12, D21 = form.plant
    A11, A12, A22 = A * X + B2 * Ch, A + B2 * Dh * C2, Y * A + Bh * C2
    Bw1, Bw2 = B1 + B2 * Dh * D21, Y * B1 + Bh * D21
    Cz1, Cz2, Dzw = C1 * X + D12 * Ch, C1 + D12 * Dh * C2, D11 + D12 * Dh * D21
    if time == "continuous":
        return [[A11 + A11.T],
                [Ah + A12.T, A22 + A22.T],
                [Bw1.T, Bw2.T, -g * I],
                [Cz1, Cz2, Dzw, -g * I]]
    return [[-X],
            [-I, -Y],
            [0, 0, -g * I],
            [A11, A12, Bw1, -X],
            [Ah, A22, Bw2, -I, -Y],
            [Cz1, Cz2, Dzw, 0, 0, -g * I]]


def bounded_real_lmi(theorem):
    """The theorem's LMI that is its declared bounded-real form, block for block, or None (no
    form; a storage that is not a symmetric variable or a level that is not a scalar variable; a
    system with a variable or an uncertain symbol in it; an objective other than the level g; no
    LMI — certain, for every vertex alike, not quantified — that is the form)."""
    form = getattr(theorem, "bounded_real", None)
    if form is None or not _level_is_objective(theorem, form.level):
        return None
    if not isinstance(form.storage, SymmetricVariable) or not all(_data_only(e) for e in form.system):
        return None
    return _lmi_in_form(theorem, lambda: form_rows(form, theorem.time), "bounded_real_form")


def state_feedback_lmi(theorem):
    """The theorem's LMI that is its declared H∞ state-feedback form, block for block, or None
    (as :func:`bounded_real_lmi`: Y a symmetric variable, W a variable, the level γ a scalar
    variable and the objective, the plant data only)."""
    form = getattr(theorem, "state_feedback", None)
    if form is None or not _level_is_objective(theorem, form.level):
        return None
    if not isinstance(form.Y, SymmetricVariable) or not isinstance(form.W, DECISION_TYPES) \
            or not all(_data_only(e) for e in form.plant):
        return None
    return _lmi_in_form(theorem, lambda: state_feedback_rows(form, theorem.time), "state_feedback_form")


def output_feedback_lmi(theorem):
    """The theorem's LMI that is its declared output-feedback form, block for block, or None (as
    :func:`bounded_real_lmi`: X and Y symmetric variables, Â, B̂, Ĉ, D̂ variables, the level γ a
    scalar variable and the objective, the plant data only)."""
    form = getattr(theorem, "output_feedback", None)
    if form is None or not _level_is_objective(theorem, form.level):
        return None
    if not all(isinstance(v, SymmetricVariable) for v in (form.X, form.Y)) or \
            not all(isinstance(v, DECISION_TYPES) for v in (form.Ah, form.Bh, form.Ch, form.Dh)) or \
            not all(_data_only(e) for e in form.plant):
        return None
    return _lmi_in_form(theorem, lambda: output_feedback_rows(form, theorem.time), "output_feedback_form")


def _certain_forms(theorem):
    """(LMI, its negative form) for each of the theorem's LMIs that is certain, for every vertex
    alike and not quantified: the only ones a declared form or a sign can be read from."""
    for lmi in theorem.lmis:
        if getattr(lmi, "quantifier", None) is None and not lmi.per_vertex and not uncertain_atoms_of_lmi(lmi):
            yield lmi, lmi.negative_form()


def _positive(theorem, Y) -> bool:
    """Whether one of the theorem's certain LMIs has −Y as a diagonal block of its negative form,
    so that Y ⪰ 0 on its feasible set (Y ≻ 0 itself, or [[X, I], [I, Y]] ≻ 0)."""
    return any(_same(N.lower[k][k], -Y) for _, N in _certain_forms(theorem) for k in range(N.nblocks))


def _coupled(theorem, X, Y) -> bool:
    """Whether one of the theorem's certain LMIs is [[X, I], [I, Y]] ⪰ 0 itself (its negative form
    [[−X], [−I, −Y]])."""
    return any(N.nblocks == 2 and _same(N.lower[0][0], -X) and _same(N.lower[1][1], -Y) and
               _same(N.lower[1][0], -sp.Identity(X.shape[0])) for _, N in _certain_forms(theorem))


def _level_is_objective(theorem, level) -> bool:
    """Whether the theorem minimises ``level``, a scalar variable, itself."""
    return theorem.objective is not None and isinstance(level, ScalarVariable) and \
        _same(sp.sympify(theorem.objective), level)


def _lmi_in_form(theorem, rows, name: str):
    """The theorem's LMI — certain, for every vertex alike, not quantified — whose blocks sympy
    proves equal to ``rows()``, or None."""
    try:
        canonical = block_matrix(rows(), where=f"{theorem.id}: {name}")
    except Exception:                 # a form whose blocks do not fit: nothing to compare with
        return None
    for lmi, N in _certain_forms(theorem):
        if N.nblocks == canonical.nblocks and \
                all(_same(N.lower[i][j], canonical.lower[i][j]) for i in range(N.nblocks) for j in range(i + 1)):
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
    uc = exact_entries(u)
    Bu = [sum((Bb[i, k] * uc[k] for k in range(m)), acb(0)) for i in range(n)]
    Du = [sum((Db[i, k] * uc[k] for k in range(m)), acb(0)) for i in range(Db.shape[0])]
    if math.isinf(frequency) or n == 0:
        w = Du
    else:
        s = _exact_point(frequency, time)
        M = acb_mat([[(s if i == j else acb(0)) - Ab[i, j] for j in range(n)] for i in range(n)])
        try:
            x = M.solve(acb_mat([[b] for b in Bu]))
        except ZeroDivisionError:
            return None
        w = [sum((Cb[i, k] * x[k, 0] for k in range(n)), acb(0)) + Du[i] for i in range(Cb.shape[0])]
    num = sum((abs(z) ** 2 for z in w), arb(0))
    den = sum((abs(z) ** 2 for z in uc), arb(0))
    return num / den


def frequency_lower_bound(instance, level: float | None = None) -> tuple[float | None, str] | None:
    """(proved lower bound on the theorem's objective, how it was found) for an instance of a
    theorem whose LMI is its declared bounded-real form (:func:`bounded_real_lmi`), H∞
    state-feedback form (:func:`state_feedback_lmi`) or H∞ output-feedback form
    (:func:`output_feedback_lmi`), (None, why none was found), or None when
    the route does not apply (no such LMI, several vertices).  ``level``: the objective at the
    solver's point, if known (a hint for where to search; the bound does not depend on it)."""
    theorem = instance.theorem
    if getattr(instance, "nvertices", 1) > 1:
        return None
    data_precision = PRECISION
    if bounded_real_lmi(theorem) is not None:
        bound, system = _bound, theorem.bounded_real.system
    elif state_feedback_lmi(theorem) is not None:
        form = theorem.state_feedback
        stabilising = _positive(theorem, form.Y)
        bound = lambda floats, balls, time: _state_feedback_bound(floats, balls, time, stabilising)  # noqa: E731
        system = form.plant
    elif output_feedback_lmi(theorem) is not None:
        form = theorem.output_feedback
        # discrete time: the form's rows (X, Y) are −[[X, I], [I, Y]] itself
        coupled = theorem.time == "discrete" or _coupled(theorem, form.X, form.Y)
        positive = _positive(theorem, form.X), _positive(theorem, form.Y), coupled
        bound = lambda floats, balls, time: _output_feedback_bound(floats, balls, time, *positive, level)  # noqa: E731
        system = form.plant
        data_precision = COUPLING_DATA_PRECISION
    else:
        return None
    try:
        ev = NumericEvaluator(instance.dims, dict(instance.data), instance.params)
        floats = [np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for e in system]
        if not all(np.all(np.isfinite(M)) for M in floats):
            return None, "the system's data are not finite"
        with ball_precision(data_precision):
            bev = BallEvaluator(instance.dims, instance.data, instance.params)
            balls = [np.atleast_2d(np.asarray(bev.visit(e), dtype=object)) for e in system]
        with ball_precision(PRECISION):
            return bound(floats, balls, theorem.time)
    except (ArithmeticError, ValueError, KeyError, TypeError, np.linalg.LinAlgError) as exc:
        return None, f"the frequency response could not be evaluated ({type(exc).__name__}: {exc})"


def _where(frequency: float, time: str) -> str:
    return "ω = ∞" if math.isinf(frequency) else (
        f"ω = {frequency:.8g} rad/s" if time == "continuous" else f"θ = {frequency:.8g} rad/sample")


def _exact_point(frequency: float, time: str):
    """The exact s of a frequency as a ball: jω (ω a double) or ((1 − t²) + 2jt)/(1 + t²) with
    t = tan(θ/2) a double (a rational point on the unit circle)."""
    if time == "continuous":
        return acb(0, frequency)
    t = arb(math.tan(frequency / 2.0))
    return acb((1 - t * t) / (1 + t * t), 2 * t / (1 + t * t))


def _bound(floats: list, balls: list, time: str) -> tuple[float | None, str]:
    """:func:`frequency_lower_bound` of the bounded real lemma (on g = γ²)."""
    A, B, C, D = floats
    Ab, Bb, Cb, Db = balls
    # the highest floating-point gain first; a ball only until one is finite (each costs a
    # complex ball solve of order n)
    candidates = sorted(set(_peak(A, B, C, D, time)), reverse=True,
                        key=lambda f: _gain(A, B, C, D, f, time))
    for frequency in candidates:
        G = _response(A, B, C, D, frequency, time)
        if G is None:
            continue
        ball = _ball_gain(Ab, Bb, Cb, Db, _direction(G), frequency, time)
        if ball is None or not ball.is_finite():
            continue
        return (max(round_down(float(ball.lower())), 0.0),
                f"the frequency response at {_where(frequency, time)} (KYP: g ≥ |G(s)u|²/|u|²)")
    return None, "no frequency gave a ball bound"


#: frequencies of the state-feedback bound's search: a logarithmic grid over the plant's modal
#: frequencies, two decades beyond each end (continuous), or over (0, π) (discrete)
GRID_POINTS = 400


def _uncancelled(floats: list, frequency: float, time: str):
    """(σ, r₀): the largest |P11(s)ᵀ r| / |r| over r in the kernel of P12(s)ᵀ in floating
    point, and its maximiser r₀ (module docstring); (0, None) where sI − A is singular or the
    kernel is {0}."""
    from scipy.linalg import null_space
    if math.isinf(frequency):
        P11, P12 = floats[4], floats[5]
    else:
        try:
            P11, P12 = transfer(floats, frequency_variable(frequency, time))
        except np.linalg.LinAlgError:
            return 0.0, None
    N = null_space(P12.T)
    if N.size == 0:
        return 0.0, None
    _, sv, vh = np.linalg.svd(P11.T @ N)
    return float(sv[0]), N @ np.conj(vh[0])


def _state_feedback_candidates(floats: list, time: str) -> list:
    """Frequencies to try, best first: the grid's top three, each refined by Brent's method
    between its neighbours, and 0 and ∞ (continuous) or 0 and π (discrete)."""
    from scipy.optimize import minimize_scalar
    A = floats[0]
    if time == "continuous":
        modes = np.abs(np.linalg.eigvals(A)) if A.size else np.array([1.0])
        modes = modes[modes > 0] if np.any(modes > 0) else np.array([1.0])
        grid = np.logspace(np.log10(modes.min()) - 2, np.log10(modes.max()) + 2, GRID_POINTS)
        ends = [0.0, math.inf]
    else:
        grid = np.linspace(0.0, math.pi, GRID_POINTS + 1)[1:-1]
        ends = [0.0, math.pi]
    values = [_uncancelled(floats, w, time)[0] for w in grid]
    found = []
    for k in np.argsort(values)[::-1][:3]:
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
        best = minimize_scalar(lambda w: -_uncancelled(floats, w, time)[0], bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-13 * max(hi, 1e-300), "maxiter": 200})
        found += [float(best.x), float(grid[k])]
    return sorted(set(found + ends), reverse=True, key=lambda w: _uncancelled(floats, w, time)[0])


def _ball_uncancelled(balls: list, r0: np.ndarray, frequency: float, time: str):
    """A ball containing |P11(s)ᵀ r|² / |r|² for r the exact projection of ``r0`` onto the kernel
    of P12(s)ᵀ at the exact s of ``frequency``, or None when sI − A or P12ᵀ P̄12 is not provably
    invertible."""
    found = projected_response(balls, None if math.isinf(frequency) else _exact_point(frequency, time), r0)
    if found is None:
        return None
    r, h = found
    return inner(h, h).real / inner(r, r).real


def _state_feedback_bound(floats: list, balls: list, time: str, stabilising: bool) -> tuple[float | None, str]:
    """:func:`frequency_lower_bound` of the H∞ state-feedback LMI (on γ itself): the frequency
    response's bound and, with Y ⪰ 0 among the LMIs (``stabilising``), the Hamiltonian's
    (continuous time) or the interpolation certificate's (discrete time;
    :mod:`lmidsl.certify.hamiltonian_bound`), the higher."""
    found = _uncancelled_bound(floats, balls, time)
    if not stabilising:
        return found
    start = found[0] or 0.0
    other = stabilisation_bound(floats, balls, start) if time == "continuous" and full_column_rank(floats[5]) \
        else interpolation_bound(floats, balls, start, time)
    if other[0] is not None and (found[0] is None or other[0] > found[0]):
        return other
    return found


def _output_feedback_bound(floats: list, balls: list, time: str, x_positive: bool, y_positive: bool,
                           coupled: bool, level: float | None = None) -> tuple[float | None, str]:
    """:func:`frequency_lower_bound` of the output-feedback LMI (module docstring): the highest of
    the full-information bound on (A, B1, B2, C1, D11, D12), the full-control bound on the dual
    plant (Aᵀ, C1ᵀ, C2ᵀ, B1ᵀ, D11ᵀ, D21ᵀ) and, with [[X, I], [I, Y]] ⪰ 0 among the LMIs or inside
    the form (``coupled``), the coupled certificate of :mod:`lmidsl.certify.coupling_bound`
    (``level``: the SDP's level, where its search starts)."""
    def parts(M):
        A, B1, B2, C1, C2, D11, D12, D21 = M
        return [A, B1, B2, C1, D11, D12], [A.T, C1.T, C2.T, B1.T, D11.T, D21.T]

    (fi, fc), (fi_balls, fc_balls) = parts(floats), parts(balls)
    found = [("full information", _state_feedback_bound(fi, fi_balls, time, x_positive)),
             ("full control", _state_feedback_bound(fc, fc_balls, time, y_positive))]
    if coupled:
        start = max([lower for _, (lower, _) in found if lower is not None], default=0.0)
        found.append(("coupled", coupling_bound(fi, fi_balls, fc, fc_balls, max(start, 1e-6), time, level)))
    proved = [(lower, f"{name}: {how}") for name, (lower, how) in found if lower is not None]
    if proved:
        return max(proved, key=lambda item: item[0])
    return None, "; ".join(f"{name}: {how}" for name, (_, how) in found)


def _uncancelled_bound(floats: list, balls: list, time: str) -> tuple[float | None, str]:
    """The frequency response's bound on γ (module docstring, state feedback)."""
    for frequency in _state_feedback_candidates(floats, time):
        sigma, r0 = _uncancelled(floats, frequency, time)
        if r0 is None or sigma <= 0:
            continue
        lower = proved_root(_ball_uncancelled(balls, r0, frequency, time))
        if lower is None:
            continue
        return (lower,
                f"the frequency response at {_where(frequency, time)} (γ ≥ |P11(s)ᵀr|/|r| on the kernel "
                f"of P12(s)ᵀ: what no control input cancels)")
    return None, "no frequency gave a ball bound (no direction that the control input cannot cancel)"


__all__ = ["bounded_real_lmi", "form_rows", "frequency_lower_bound", "output_feedback_lmi", "output_feedback_rows",
           "state_feedback_lmi", "state_feedback_rows"]
