"""Other routes to a certified point when the first solver gives none.

A *route* is a backend and one of its solvers (:class:`lmidsl.solver.backends.Route`).  The
registry lists, for each backend, the routes tried in order when its default solver returns no
certified point (:func:`lmidsl.solver.backends.fallback_routes`).  Routes cross backends on
purpose: the same solver behind another modelling layer is another problem to the solver.
Measured on the five plants of ``textbook.hinf_of_ct`` where Clarabel returns only inaccurate
points (γ* from 28.6 to 794, X and Y with condition numbers ~1e7 at the optimum): CVXOPT called
through cvxpy fails on all five, CVXOPT called through PICOS (one semidefinite block per LMI)
certifies all five within 2.1e-4 of ``control.hinfsyn``'s γ, proved, in under a second each.

A solver's failure is not a verdict on the problem, and which route found a point does not
matter to the certificate: it is numpy's (and the ball-arithmetic proof's) at the returned point.
:class:`lmidsl.solver.plan.Plan` keeps the first *good* answer (certified, solved to full accuracy, with an
objective that the strictness margin does not set), else the best certified one (lowest
objective: each is a valid bound), else the first answer; its notes say what each route gave.
Once any route has returned a point, first-order routes (SCS) are skipped: they cost seconds to
minutes and their 1e-4-accurate points would not sharpen it (in the papers' reproduction and the
stress suite no kept answer came from SCS); they remain the last resort when no route returned one.

A theorem that declares its bounded-real form (:meth:`Theorem.bounded_real_form`) has one more
route with no SDP at all: :func:`riccati_point` takes the storage P from the Riccati equation at
a level just above python-control's norm and hands the point to the certificate.  Measured on
the stress suite's lightly damped plants (γ ~ 1e3–1e4, poles at radius ~0.9998), where every SDP
solver fails: proved within 1e-5 of the norm in ~10 ms.
"""
from __future__ import annotations

import numpy as np
from threadpoolctl import threadpool_limits
from flint import arb_mat, fmpq

from ..numeric.evaluate import NumericEvaluator
from ..numeric.exact import entries, rational_matrix
from ..numeric.instance import Instance
from ..numeric.proof import PROVED, BallEvaluator, PreciseMatrix
from ..numeric.systems import is_stable
from ..numeric.output_feedback import (balanced_plant, bounded_real_residual, central_controller,
                                       closed_loop as of_closed_loop,
                                       closed_loop_norm, linearising_variables, regularised_plant)
from ..numeric.riccati import (PRECISE_DIGITS, full_information_gain, hinf_norm,
                               precise_full_information_gain, realisation_norm, storage_candidates)
from .backends import Route, get_backend
from .solution import Solution, evaluate_objective, evaluate_performance, lmi_certificate, objective_enclosure
from .status import OPTIMAL


#: the backend name of a point from a closed form (a Riccati equation), not from an SDP solver
CLOSED_FORM = "riccati"


def good(solution: Solution) -> bool:
    """Certified, solved to the solver's full accuracy, and the strictness margin does not set
    the objective (an inaccurate or margin-set optimum is a valid bound but maybe not the optimum)."""
    return bool(solution.ok and solution.lmis_hold and solution.status == OPTIMAL
                and not solution.margin_limited)


def better(first: Solution, second: Solution) -> Solution:
    """The answer to keep of two: a certified one over an uncertified one; of two certified ones,
    the lower objective (each is a valid bound); otherwise the first."""
    ok1, ok2 = first.ok and first.lmis_hold, second.ok and second.lmis_hold
    if ok2 and not ok1:
        return second
    if ok1 and ok2 and first.objective is not None and second.objective is not None \
            and second.objective < first.objective:
        return second
    return first


def route_model(model, route: Route, margin: float | None = None):
    """``model`` itself (its margin reset) when ``route`` uses its backend, else the same
    instance compiled for the route's backend with the same conditioning."""
    if route.backend == model.backend:
        if margin is not None:
            model.set_margin(margin)
        return model
    return get_backend(route.backend)(model.instance, margin=margin if margin is not None else model.margin,
                                      conditioning=model.conditioning)


def said(solution: Solution) -> str:
    """One route's outcome in a note."""
    verdict = "" if not solution.ok else (", not certified" if not solution.lmis_hold
                                          else (", gamma set by the margin" if solution.margin_limited else ""))
    objective = f" ({solution.objective:.8g})" if solution.ok and solution.objective is not None else ""
    return f"{solution.backend}/{solution.solver}: {solution.status}{objective}{verdict}"


def declares_closed_form(theorem) -> bool:
    """The theorem declares a Riccati route (its bounded-real, state- or output-feedback form)."""
    return any(form is not None for form in (theorem.state_feedback, theorem.output_feedback, theorem.bounded_real))


RICCATI_LEVELS = (1e-6, 1e-5, 3e-5, 9e-5, 1e-3)
"""Levels γ = ‖G‖∞ (1 + r) tried first by the Riccati route, then the synthesis γ (and + tolerance).
The first sets how far above a design's norm its analysis certifies it (with 1e-5 first, a
16-state state-feedback design proved 1e-6 above its optimum was reported 1.1e-5 above it).  The
others serve stiff realisations, where a margin of ε = 1e-5 of the room is below the Riccati
solution's rounding (stress set, brl_ct/light-1: proved at 9e-5, not at 1e-5)."""


def riccati_point(instance: Instance, synthesis_gamma, tolerance):
    """A certified point from a Riccati equation, no SDP, or None (no declared form, an unstable
    system, or no level certifies).  A theorem declaring its state-feedback form:
    :func:`state_feedback_point`.  One declaring its bounded-real form
    (:meth:`Theorem.bounded_real_form`): P from the bounded-real Riccati equation
    (:mod:`lmidsl.numeric.riccati`) at the levels python-control's norm × (1 + r), r in
    :data:`RICCATI_LEVELS` (γ then states the design's own norm, as the analysis minimum
    would), and the synthesis γ × (1 + r₀) (r₀ the first of them), γ and γ (1 + tolerance), in
    increasing order.  A level above the synthesis γ but below SLICOT's norm is tried with the
    synthesis γ as the norm that sets the Riccati margin ε: on the stiff loop of a 60-digit
    state-feedback gain SLICOT's norm, from the loop summed in doubles, was 1 % above the norm
    (76,143 where the exact loop's is below 75,390)."""
    if instance.theorem.state_feedback is not None:
        return state_feedback_point(instance)
    if instance.theorem.output_feedback is not None:
        return output_feedback_point(instance)
    form = instance.theorem.bounded_real
    if form is None or instance.nvertices > 1 or \
            set(instance.theorem.var_decl) != {form.storage.name, form.level.name}:
        return None          # the Riccati point is the storage of one system's bounded real lemma
    ev = NumericEvaluator(instance.dims, dict(instance.data), instance.params)
    A, B, C, D = (np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for e in form.system)
    time = instance.theorem.time
    norm, measured = realisation_norm(A, B, C, D, time)
    if norm is None:
        return None
    levels = [norm * (1 + r) for r in RICCATI_LEVELS]
    if synthesis_gamma is not None:
        levels += [synthesis_gamma * (1 + RICCATI_LEVELS[0]), synthesis_gamma, synthesis_gamma * (1 + tolerance)]
    written = _as_written(instance, form.system)
    for gamma in sorted(set(levels)):
        seed = norm if norm < gamma else synthesis_gamma
        if seed is None or not seed < gamma:
            continue
        for how, P in storage_candidates(A, B, C, D, gamma ** 2, time, seed, lambda balls: written()):
            values = {form.storage.name: P, form.level.name: gamma ** 2}
            sol = _certified_point(instance, values)
            if sol is not None:
                sol.notes.append(f"P from the bounded-real Riccati equation at γ = {gamma:.10g} "
                                 f"({measured} {norm:.10g}; {how})"
                                 + ("; P is proved as an exact rational matrix: its rounded doubles, as "
                                    "exported, may not satisfy the LMI" if getattr(P, "exact", None) is not None
                                    else ""))
                return sol
    return None


def _as_written(instance: Instance, expressions):
    """A function returning ``expressions`` (the declared form's system) as python-flint ball
    matrices at the current precision, the data read as the proof reads them (decimals as written):
    the realisation whose exact storage :func:`~lmidsl.numeric.riccati.precise_storage` computes."""
    def balls():
        ev = BallEvaluator(instance.dims, dict(instance.data), instance.params)
        return tuple(arb_mat(np.atleast_2d(np.asarray(ev.visit(e), dtype=object)).tolist()) for e in expressions)
    return balls


ROUNDING = 1e-9
"""A positive numpy λmax below this fraction of the LMI's ‖N‖₂ may be rounding (double precision
resolves ~1e-16‖N‖₂ per entry; n² entries and ill-conditioned P add decades); above it the
candidate is dropped without a proof."""


def _certified_point(instance: Instance, values: dict) -> Solution | None:
    """A Solution (backend "riccati") at ``values`` when every LMI holds there, else None: by
    numpy's eigenvalues, or, where one of them is within rounding of 0 (|λmax| ≤ ROUNDING ‖N‖₂:
    a stiff realisation, entries ~1e16, margin ~1e-7), by the ball-arithmetic proof of every LMI
    (:func:`lmi_certificate` with ``prove``).  COMPleib NN5, output feedback: numpy's λmax
    −5.5e-11 at ‖N‖₂ = 4.4e16 hid a closed-loop storage the ball LDLᵀ refutes; taken, it left the
    design uncertified where the next level's storage is proved.
    A point holding exact values (:class:`~lmidsl.numeric.proof.PreciseMatrix`) is always proved:
    its doubles are only its rounding, and numpy's −1e-11 at the rounded output-feedback point of a
    random plant hid an exact point that violates the LMI (a negative pivot of −4.7e-12 in balls),
    which was then kept over the SDP's proved point.
    Its objective is the theorem's objective evaluated at the point (and enclosed, as a solver's
    is), never the form's level: a theorem may declare a form and minimise 2γ, whose closed-form
    point was kept over the SDP's with its level (half its objective) as the objective."""
    point = {**instance.data, **values}
    lmis = lmi_certificate(instance, point)
    precise = any(getattr(v, "exact", None) is not None for v in values.values())
    unresolved = any(abs(r.max_eig) <= ROUNDING * r.scale for r in lmis)
    if lmis and (precise or unresolved or not all(r.max_eig < 0 for r in lmis)):
        if not precise and any(r.max_eig > ROUNDING * r.scale for r in lmis):
            return None          # violated beyond what rounding explains: no proof is tried
        lmis = lmi_certificate(instance, point, prove=True)
        if not all(r.proof == PROVED for r in lmis):
            return None
    if not (lmis and all(r.max_eig < 0 for r in lmis)):
        return None
    objective = evaluate_objective(instance, point)
    if objective is None and instance.theorem.objective is not None:
        return None
    return Solution(instance.theorem.id, instance.example, CLOSED_FORM, "scipy ARE", OPTIMAL,
                    objective=objective, point_gamma=evaluate_performance(instance, point), lmis=lmis,
                    values=values, params=dict(instance.params), instance=instance,
                    objective_bounds=objective_enclosure(instance, point))


SF_BISECTION_STEPS = 60
SF_MARGINS = (1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1)


def gain_point(P2, K, gamma: float):
    """(Y, W) = (γ P₂⁻¹, K Y): the state-feedback variables of a closed loop's storage P₂.  When
    P₂ is exact (:class:`~lmidsl.numeric.proof.PreciseMatrix`: the 60-digit Hamiltonian route of a
    stiff loop) Y and W are computed exactly in rationals (python-flint ``fmpq_mat``), so that the
    congruence that makes them satisfy the LMIs is exact too; otherwise in floating point.  K may
    be exact itself (an object array of ``fmpq``)."""
    if getattr(P2, "exact", None) is None:
        Y = gamma * np.linalg.inv(P2)
        Y = (Y + Y.T) / 2
        return Y, np.asarray(K, dtype=float) @ Y
    try:
        Yq = rational_matrix(P2).inv() * fmpq(*float(gamma).as_integer_ratio())
    except ZeroDivisionError:
        return gain_point(np.asarray(P2, dtype=float), K, gamma)
    Wq = rational_matrix(K) * Yq
    return PreciseMatrix.of(entries(Yq)), PreciseMatrix.of(entries(Wq))


def state_feedback_point(instance: Instance) -> Solution | None:
    """A certified point of a theorem declaring its state-feedback form
    (:meth:`Theorem.state_feedback_form`), from the full-information Riccati equation.

    γ_R = the least level at which that equation has a stabilising solution X ⪰ 0 whose gain
    stabilises the plant (bisection on log γ, :data:`SF_BISECTION_STEPS` Riccati solves).  A gain
    K whose closed loop has the norm ν makes the LMIs feasible at every level above ν: with P₂ the
    closed loop's bounded-real storage at γ² (:func:`lmidsl.numeric.riccati.storage_candidates`),
    Y = γ P₂⁻¹, W = K Y and level γ (the −γI form is the γ²-form scaled by 1/γ and
    congruence-transformed by diag(P⁻¹, I, I)).  Tried, for r in :data:`SF_MARGINS`: the gain of
    least ν the bisection met at γ = ν (1 + r) (its ν can be below γ_R: random 8-state plant,
    83.8504 against 83.8677), then the gain at γ_R (1 + r) at that level.  The first point that
    satisfies every LMI is returned.  Before them, when the least ν is more than
    :data:`PRECISE_SF_TRIGGER` above γ_e, the least level at which the equation has its solution
    (however large the gain's ν, which doubles compute wrongly there): the 60-digit route,
    :func:`_precise_state_feedback_point`."""
    form = instance.theorem.state_feedback
    ev = NumericEvaluator(instance.dims, dict(instance.data), instance.params)
    A, B1, B2, C1, D11, D12 = (np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for e in form.plant)
    time = instance.theorem.time
    plant = _as_written(instance, form.plant)

    least = []                               # (ν, K): the stabilising gain of least closed-loop norm met

    def loop(gamma):
        K = full_information_gain(A, B1, B2, C1, D11, D12, gamma, time)
        if K is None:
            return None
        norm = hinf_norm(A + B2 @ K, B1, C1 + D12 @ K, D11, time)
        if norm is None or not np.isfinite(norm):
            return None
        if not least or norm < least[0][0]:     # any stabilising gain is a point at a level above ν
            least[:] = [(norm, K)]
        return (K, norm) if norm < gamma else None

    hi = max(np.linalg.norm(D11, 2), 1e-300) * 2 if np.any(D11) else 1.0
    for _ in range(80):                     # an upper level: double until the loop closes
        if loop(hi) is not None:
            break
        hi *= 2
    else:
        return None
    lo = hi / 2
    while lo > 1e-12 * hi and loop(lo) is not None:
        hi, lo = lo, lo / 2
    for _ in range(SF_BISECTION_STEPS):
        mid = np.sqrt(lo * hi)
        if loop(mid) is not None:
            hi = mid
        else:
            lo = mid
        if hi / lo - 1 < 1e-9:
            break
    if time == "continuous" and A.shape[0] <= PRECISE_SF_MAX_STATES and least:
        exists = _existence_level(lambda g: full_information_gain(A, B1, B2, C1, D11, D12, g, time) is not None,
                                  lo, hi)
        if least[0][0] > exists * (1 + PRECISE_SF_TRIGGER):
            sol = _precise_state_feedback_point(instance, (A, B1, B2, C1, D11, D12), plant, exists,
                                                least[0][0] * (1 + SF_MARGINS[0]))
            if sol is not None:
                return sol
    for r in SF_MARGINS:
        tries = [(least[0][0] * (1 + r), least[0])] if least else []
        closed = loop(hi * (1 + r))
        if closed is not None:
            tries.append((hi * (1 + r), (closed[1], closed[0])))
        for gamma, (norm, K) in tries:
            Acl, Ccl = A + B2 @ K, C1 + D12 @ K

            def written(balls, K=K):          # the closed loop the proof reads: A + B2 K exactly
                Ab, B1b, B2b, C1b, D11b, D12b = plant()
                Kb = balls(K, written=False)
                return Ab + B2b * Kb, B1b, C1b + D12b * Kb, D11b

            for _, P2 in storage_candidates(Acl, B1, Ccl, D11, gamma ** 2, time, norm, written):
                Y, W = gain_point(P2, K, gamma)
                values = {form.Y.name: Y, form.W.name: W, form.level.name: gamma}
                sol = _certified_point(instance, values)
                if sol is not None:
                    sol.notes.append(f"Y, W from the full-information Riccati gain at the level γ = {gamma:.10g} "
                                     f"(Riccati optimum ≈ {hi:.10g}; the gain's closed loop norm {norm:.10g})")
                    return sol
    return None




PRECISE_SF_TRIGGER = 1e-6
"""The float route's least closed-loop norm ν, relative to the level γ_e where the full-information
equation first has its solution, above which the 60-digit route is tried first (random 16-state
plant, two actuators: ν is 1e-5 above γ_e, the 60-digit gain at γ_e (1 + 1e-6) is proved)."""
PRECISE_SF_MARGINS = (1e-6, 1e-5, 1e-4, 1e-3, 1e-2)
PRECISE_SF_MAX_STATES = 32
"""The largest state dimension given the 60-digit route: one solve costs 0.2 s at 16 states, 1.3 s
at 32 and 5–8 s at 48, where on a random two-actuator plant only the gain at γ_e (1 + 1e-3) was
confirmed in doubles (its gains grow like 1/r: 6e8 at r = 1e-6)."""
PRECISE_SF_UNCONFIRMED_STATES = 24
"""Up to this many states the 60-digit gain's loop needs only to be stable summed in doubles: the
analysis of the delivered design proves the stiff loop's storage by the 120-digit Hamiltonian
(24 states, one actuator, gains ~1e10: loops 8 % above their levels by SLICOT in doubles, every
design certified within 1.6e-5 of the proved optimum).  Above it the loop's level must be
confirmed in doubles (:func:`_checkable_in_doubles`): at 32 states with one actuator the analysis
found no storage of such a loop in 200 s, and the design went uncertified where the
double-precision route's gain was certified."""
PRECISE_SF_CONFIRM = 1e-6
PRECISE_SF_EPS = 1e-9
"""ε of Q = C₁ᵀC₁ + εI relative to max(‖C₁ᵀC₁‖, 1) in the 60-digit route: the point is exact, so
any ε > 0 makes the LMI strict; ε moves the level at which a solution exists (1e-7 moved it 3e-6
above γ_e on a 16-state plant, so that no solution existed at γ_e (1 + 1e-6))."""


def _checkable_in_doubles(arrays: tuple, K: np.ndarray, gamma: float) -> bool:
    """Whether the loop (A + B₂K, B₁, C₁ + D₁₂K, D₁₁) summed in doubles is one double-precision
    numerics can check: stable, and above :data:`PRECISE_SF_UNCONFIRMED_STATES` states with SLICOT's
    H∞ norm (+∞ when not stable) at most γ (1 + :data:`PRECISE_SF_CONFIRM`)."""
    A, B1, B2, C1, D11, D12 = arrays
    if A.shape[0] <= PRECISE_SF_UNCONFIRMED_STATES:
        return is_stable(A + B2 @ K, "continuous")
    return hinf_norm(A + B2 @ K, B1, C1 + D12 @ K, D11, "continuous") <= gamma * (1 + PRECISE_SF_CONFIRM)


def _existence_level(exists, lo: float, hi: float, steps: int = 40) -> float:
    """The least level (to 1e-9 relative) at which ``exists(γ)`` holds, ``exists(hi)`` being true:
    halving below ``lo`` until it fails, then bisection on log γ."""
    while lo > 1e-12 * hi and exists(lo):
        hi, lo = lo, lo / 2
    for _ in range(steps):
        mid = np.sqrt(lo * hi)
        lo, hi = (lo, mid) if exists(mid) else (mid, hi)
        if hi / lo - 1 < 1e-9:
            break
    return hi


def _precise_state_feedback_point(instance: Instance, arrays: tuple, plant, level: float,
                                  ceiling: float) -> Solution | None:
    """The point (Y, W, γ) = (γ X⁻¹, K Y, γ) of the full-information Riccati solution X and gain K
    computed at 60 digits and kept exactly (:func:`~lmidsl.numeric.riccati.precise_full_information_gain`:
    X is the loop's bounded-real storage at γ², so no second Riccati equation is solved for the
    stiff loop), at γ = ``level`` (1 + r), r in :data:`PRECISE_SF_MARGINS`, below ``ceiling`` (the
    double-precision route's first level: a published 10-state plant's 60-digit point was proved
    only at r = 1e-3, 9.5e-4 above the double-precision gain's), skipping a level whose
    gain, rounded to the doubles it is delivered in, closes a loop that is unstable summed in doubles
    or, above :data:`PRECISE_SF_UNCONFIRMED_STATES` states, whose level doubles do not confirm
    (:func:`_checkable_in_doubles`; the exact loop is stable, but no double-precision check of the
    design — SLICOT's norm, the balancing — could then see it); None when none is proved.
    ``arrays``: the plant (A, B₁, B₂, C₁, D₁₁, D₁₂) in doubles; ``plant()``: in balls as written."""
    form = instance.theorem.state_feedback
    A, B1, B2, C1, D11, D12 = arrays
    eps = PRECISE_SF_EPS * max(np.linalg.norm(C1.T @ C1, 2), 1.0)
    for r in PRECISE_SF_MARGINS:
        gamma = level * (1 + r)
        if gamma >= ceiling:
            break
        found = precise_full_information_gain(A, B1, B2, C1, D11, D12, gamma, eps, lambda balls: plant())
        if found is None:
            continue
        K, X = found
        if not _checkable_in_doubles(arrays, np.array([[float(x) for x in row] for row in K]), gamma):
            continue    # the delivered gain's loop, summed in doubles, must be one numerics can check
        Y, W = gain_point(PreciseMatrix.of(X), K, gamma)
        sol = _certified_point(instance, {form.Y.name: Y, form.W.name: W, form.level.name: gamma})
        if sol is not None:
            sol.notes.append(f"Y, W from the full-information Riccati equation at the level γ = {gamma:.10g}, "
                             f"solved at {PRECISE_DIGITS} digits (its solution exists from ≈ {level:.10g}; in "
                             "double precision the gains' closed loops scatter above their levels)")
            return sol
    return None


OF_REGULARISATION = (0.0, 1e-4, 1e-6, 1e-8)
"""ε of the regularised plant (:func:`~lmidsl.numeric.output_feedback.regularised_plant`) relative
to the size of the plant's input and output matrices; 0: the plant as written (SLICOT needs it
regular)."""
OF_MARGINS = (1e-5, 1e-4, 1e-3, 1e-2)
OF_BISECTION_STEPS = 50
OF_LEVELS = 6
"""The levels ν (1 + r) tried, lowest first (each costs its storages' Riccati equations and the
exact conversion: on a 24-state plant with γ* ~ 1e10, whose closed-loop storages have condition
numbers ~1e18 and none is a point, the twelve levels cost 8 s)."""
OF_MET = 1e-6
"""A central controller at the level γ meets it when its closed loop's norm is at most γ (1 + this):
the central controller's norm is γ itself, and SLICOT's came out up to ~1e-6 above it (random
plant: 4294.50557 at γ = 4294.5); any stabilising controller is then kept at its own norm."""
OF_BISECTION_TOLERANCE = 1e-7
"""The bisection's relative width: below the smallest margin of :data:`OF_MARGINS`."""


def output_feedback_point(instance: Instance) -> Solution | None:
    """A certified point of a theorem declaring its output-feedback form
    (:meth:`Theorem.output_feedback_form`), from SLICOT's central controllers.

    The plant is taken in the state coordinates SLICOT's TB01ID balances
    (:func:`~lmidsl.numeric.output_feedback.balanced_plant`; the controllers are the same, and the
    point is mapped back exactly).  For each ε of :data:`OF_REGULARISATION` (0 only where SLICOT
    accepts the plant as written), the least level at which SLICOT returns a controller for the
    ε-regularised plant whose closed loop
    meets the level is bisected on log γ; of all controllers met on the way, the one whose closed
    loop *with the plant as written* has the least norm ν is kept (any stabilising controller
    gives a point above its ν).  At γ = ν (1 + r), r in :data:`OF_MARGINS`, the closed loop's
    bounded-real storage (:func:`~lmidsl.numeric.riccati.storage_candidates`) gives the linearising
    variables (:func:`~lmidsl.numeric.output_feedback.linearising_variables`); the first point at
    which every LMI of the theorem is proved is returned.  On singular plants (D21 = 0, most of
    COMPleib) this is the right design where the SDP's point, at an unattained optimum, is not."""
    form = instance.theorem.output_feedback
    names = {v.name for v in (form.X, form.Y, form.Ah, form.Bh, form.Ch, form.Dh, form.level)}
    if instance.nvertices > 1 or set(instance.theorem.var_decl) != names:
        return None
    ev = NumericEvaluator(instance.dims, dict(instance.data), instance.params)
    plant = tuple(np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for e in form.plant)
    time = instance.theorem.time
    balanced, scale = balanced_plant(plant)    # the same controllers; its closed loops better scaled
    with threadpool_limits(1):               # SLICOT's small LAPACK calls: 10× slower on a loaded
        controllers = _controllers(balanced, time)   # machine with the BLAS pool's threads spinning
    tries = sorted(((norm * (1 + r), norm, K, eps) for norm, K, eps in controllers
                    for r in OF_MARGINS), key=lambda t: t[0])[:OF_LEVELS]
    for gamma, norm, K, eps in tries:
        loop = of_closed_loop(balanced, K)
        for how, P2 in storage_candidates(*loop, gamma ** 2, time, norm):
            if getattr(P2, "exact", None) is None and bounded_real_residual(loop, P2, gamma ** 2, time) > ROUNDING:
                continue        # the closed loop's LMI fails beyond rounding: so would its congruence
            variables = linearising_variables(P2, gamma, balanced, K, scale)
            if variables is None:
                continue
            values = {getattr(form, k).name: v for k, v in variables.items()}
            values[form.level.name] = gamma
            sol = _certified_point(instance, values)
            if sol is not None:
                plant_said = "the plant as written" if eps == 0 else f"the plant regularised with ε = {eps:.3g}"
                sol.notes.append(f"X, Y, Â, B̂, Ĉ, D̂ from SLICOT's central controller for {plant_said} "
                                 f"and its closed loop's storage at the level γ = {gamma:.10g} (the closed "
                                 f"loop's norm {norm:.10g}; {how}; the plant's state balanced by SLICOT TB01ID)")
                return sol
    return None


def _controllers(plant: tuple, time: str) -> list:
    """[(ν, K, ε)]: for each ε of :data:`OF_REGULARISATION`, of SLICOT's central controllers met
    while bisecting the least level of the ε-regularised plant, the one of least closed-loop norm
    ν with the plant as written.  ε = 0 only for a regular plant (D12 of full column rank, D21 of
    full row rank); the smaller ε stop once a smaller ε gave a larger ν (the regularised optimum
    falls with ε, so a larger ν is SLICOT's accuracy failing: AC3's ν was 2.96779, 2.98116 and
    3.60594 at ε = 1e-4, 1e-6, 1e-8 of the scale)."""
    A, B1, B2, C1, C2, D11, D12, D21 = plant
    scale = max(np.linalg.norm(M, 2) for M in (B1, B2, C1, C2)) or 1.0
    regular = (np.linalg.matrix_rank(D12) == D12.shape[1] and np.linalg.matrix_rank(D21) == D21.shape[0])
    found = []

    def met(problem, gamma, eps):
        K = central_controller(problem, gamma, time)
        if K is None:
            return False
        problem_norm = closed_loop_norm(problem, K, time)
        if problem_norm is None or not problem_norm <= gamma * (1 + OF_MET):
            return False
        norm = closed_loop_norm(plant, K, time)
        if norm is not None and (not best or norm < best[0][0]):
            best[:] = [(norm, K, eps)]
        return True

    for fraction in OF_REGULARISATION:
        if fraction == 0 and not regular:
            continue
        eps, best = fraction * scale, []
        problem = plant if eps == 0 else regularised_plant(plant, eps)
        hi = max(np.linalg.norm(D11, 2), 1e-3 * scale)
        for _ in range(40):                  # an upper level: multiply until a controller meets it
            if met(problem, hi, eps):
                break
            hi *= 4
        else:
            continue
        lo = hi / 4
        while lo > 1e-12 * hi and met(problem, lo, eps):
            hi, lo = lo, lo / 4
        for _ in range(OF_BISECTION_STEPS):
            mid = np.sqrt(lo * hi)
            lo, hi = (lo, mid) if met(problem, mid, eps) else (mid, hi)
            if hi / lo - 1 < OF_BISECTION_TOLERANCE:
                break
        if best and found and eps > 0 and found[-1][2] > 0 and best[0][0] > found[-1][0]:
            break
        found += best
    return found


__all__ = ["CLOSED_FORM", "better", "declares_closed_form", "good", "output_feedback_point", "riccati_point", "route_model", "said", "state_feedback_point"]
