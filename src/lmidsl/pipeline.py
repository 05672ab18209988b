"""The Python API: bind, compile, solve, recover and certify in one call.

>>> import lmidsl
>>> sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
>>> sol.gamma, sol.recovered["Af"], sol.analysis.gamma
"""
from __future__ import annotations

import dataclasses
import time

from .certify.dual_bound import PendingBound
from .certify.infeasibility import prove_infeasible
from .solver.fallback import CLOSED_FORM
from .solver.plan import Plan
from .certify.verdict import headline_level, judge
from .certify import certify_by_analysis
from .certify.evidence import claim_evidence
from .theorem.budget import expansion_limits
from .theorem.checks import run_checks
from .errors import InputError, LmidslError
from .solver.feasibility import diagnosis_needed
from .numeric.instance import Instance, bind
from .numeric.recovery import recover, recover_design
from .numeric.scaling import apply_scaling
from .theorem.registry import get_example, get_theorem
from .solver.solution import Solution, evaluate_reported, lmi_certificate
from .theorem.theorem import Theorem
from .solver.backoff import AUTO_DELTAS, SEARCHED, backoff_solution, level_solution

"""δ of the automatic back-off, in order: hinf_of_ct plant-14 (γ* = 5554.6) gets no certified
controller at 1 % (the loop's controller has ‖A_K‖ ~ 3e7) and one at 10 %."""


def as_theorem(theorem) -> Theorem:
    """A Theorem, given itself or its id."""
    return theorem if isinstance(theorem, Theorem) else get_theorem(theorem)


def instance_inputs(theorem: Theorem, example: str | None = None, data: dict | None = None,
                    overrides: dict | None = None) -> dict:
    """Inputs from an example or a data dictionary, with single names overridden."""
    if example is not None and data is not None:
        raise InputError(f"{theorem.id}: give an example or a data file, not both")
    if data is not None:
        if not isinstance(data, dict):
            raise InputError(f"{theorem.id}: the data must be a JSON object of names to values")
        inputs = dict(data)
    elif example is not None:
        inputs = get_example(theorem, example).inputs()
    else:
        if not theorem.examples:
            raise InputError(f"{theorem.id}: no example; give --data")
        inputs = next(iter(theorem.examples.values())).inputs()
    for name, value in (overrides or {}).items():
        inputs[name] = value
    return inputs


def make_instance(theorem, example: str | None = None, data: dict | None = None,
                  overrides: dict | None = None, *, max_lmis: int | None = None,
                  max_psd_rows: int | None = None) -> Instance:
    """Bind an example (or data) with overrides to a theorem.  Entries of ``data`` the theorem
    does not use are ignored with an :class:`~lmidsl.errors.UnusedDataWarning`; an unknown
    name in ``overrides`` is an error.  An index set's member or a Pólya relaxation larger than
    ``max_lmis`` LMIs or ``max_psd_rows`` rows of PSD cones is refused before it is built
    (:mod:`lmidsl.theorem.budget`; None: the current limits)."""
    thm = as_theorem(theorem)
    if example is None and data is None and thm.examples:
        example = next(iter(thm.examples))
    optional = set(data or {}) - set(overrides or {})      # a data file may serve several theorems
    with expansion_limits(max_lmis, max_psd_rows):
        return bind(thm, instance_inputs(thm, example, data, overrides), example=example,
                    optional=optional)


ILL_CONDITIONED = 1e6
"""A recovery inverting a matrix of larger condition number is backed off from (``backoff="auto"``)."""


def solve_instance(instance: Instance, solver: str | None = None, backend: str | None = None,
                   margin: float | None = None, certify: bool = True, scaling="auto",
                   backoff: float | None = None, diagnose: bool = True, plan: Plan | None = None,
                   bounds: bool = True, **options) -> Solution:
    """Compile, solve (the plan's one road, :mod:`lmidsl.solver.plan`), recover the design and
    (optionally) certify it by analysis.

    ``scaling``: the theorem's declared signal scalings ('auto', 'none' or {signal: factor});
    the solver sees the scaled instance, recovered matrices are mapped back
    (:mod:`lmidsl.numeric.scaling`).  ``backoff`` = δ: re-solve at objective ≤ (1 + δ)·optimum for a
    well-conditioned recovery (:mod:`lmidsl.solver.backoff`); ``"auto"``: only when the design
    recovered at the optimum fails its analysis certificate, its recovery fails or inverts a matrix
    of condition number above :data:`ILL_CONDITIONED` (the smallest δ of :data:`lmidsl.solver.backoff.AUTO_DELTAS` that certifies).
    ``plan`` (default: from ``backend``, ``solver``, ``margin`` and ``options``) decides every solve.
    ``bounds``: the other side of the answer — a proved lower bound on the optimum from the
    solver's dual (:mod:`lmidsl.certify.dual_bound`), and for a solve without a point a proved
    infeasibility certificate (:mod:`lmidsl.certify.infeasibility`); direct backend only.
    """
    plan = plan or Plan(backend, solver, options, margin)
    if bounds and plan.infeasibility_proof is None:       # a proved infeasibility ends the road
        plan = dataclasses.replace(plan, infeasibility_proof=prove_infeasible)
    applied = apply_scaling(instance, scaling)
    solved = []
    solution, model = plan.solve(applied.scaled, solved=solved)
    solution.scaling = applied
    solution.certify = certify
    finish = dict(plan=plan, certify=certify, diagnose=diagnose)
    if not (bounds and certify and solution.ok and instance.theorem.objective is not None):
        return judge(_recover_and_certify(model, applied, solution, backoff, bounds, finish))
    # the bound reads the models' duals now (a back-off or level solve replaces them) and runs on
    # a worker thread while the design is recovered and certified
    pending = PendingBound(model, solution, [m for m in solved if m is not model], solution.point_gamma,
                           instance=instance)
    try:
        final = _recover_and_certify(model, applied, solution, backoff, bounds, finish)
    except BaseException:             # an interrupt, a deadline, an error: the bound is not wanted
        pending.cancel()
        raise
    t0 = time.perf_counter()
    solution.bounds = final.bounds = pending.result()
    final.times["lower_bound_wait"] = time.perf_counter() - t0
    final.times["lower_bound"] = solution.bounds.times.get("total", 0.0)
    return judge(final)


def _recover_and_certify(model, applied, solution: Solution, backoff, bounds: bool, finish: dict) -> Solution:
    """After the optimum: recovery and certificates, the back-off when needed (``solve_instance``),
    and the infeasibility proof for a solve without a point."""
    instance = solution.instance
    if backoff is None or not solution.ok:
        finish_solution(solution, **finish)
        if backoff is None and solution.message.startswith("recovery failed"):
            solution.message += "; a back-off (--backoff) may recover a well-conditioned design"
        if bounds and not solution.ok and solution.infeasibility is None:   # (not tried on the road)
            t0 = time.perf_counter()
            solution.infeasibility = prove_infeasible(model)
            solution.times["infeasibility_proof"] = time.perf_counter() - t0
        return solution
    if backoff != "auto":
        return backed_off(model, applied, solution, backoff, None, finish)
    if not finish["certify"]:
        # the automatic back-off keeps a point only once it is certified; with nothing certified
        # (--no-certify) it could only spend its solves (seed 001: 38 solves, 11.9 s against 4.6 s)
        finish_solution(solution, **finish)
        return solution
    reason = _backoff_reason(solution, instance, finish)
    if reason is None:
        return solution
    t0 = time.perf_counter()
    closed = closed_form_design(solution, reason, finish)
    if closed is not None and solution.point_gamma is not None and \
            closed.verdict.gamma <= solution.point_gamma * (1 + AUTO_DELTAS[0]):
        return closed                  # as close as the first rung of the back-off could come
    failed = solution.message.startswith("recovery failed")
    started = time.perf_counter()
    for delta in AUTO_DELTAS:   # the smallest δ that gives a certified design
        kept = backed_off(model, applied, solution, delta, reason, finish, searched=delta in SEARCHED,
                          started=started)
        if kept is not solution:
            # (kept was judged by backed_off: an automatic back-off keeps only a certified point)
            if closed is None or kept.verdict.gamma <= closed.verdict.gamma:
                kept.times["backoff"] += started - t0      # with the closed form's design, not kept
                return kept
            break
    if closed is not None:
        closed.times["backoff"] = time.perf_counter() - started      # the back-off's solves, not kept
        return closed
    solution.times["backoff"] = time.perf_counter() - t0    # the solves of a back-off that kept nothing
    if finish["certify"] and solution.analysis is None and not failed:
        certify_point(solution, finish["plan"])     # no back-off point: the optimum's certificate
    if failed:                                   # never advise what was just tried
        solution.message += (f"; the automatic back-off (δ = {AUTO_DELTAS[0]:g} to {AUTO_DELTAS[-1]:g}) "
                             "gave no certified design either")
    return solution


#: the ``times`` entries of a point's own stages (prove, recover, certify): with the plan's road
#: (``road_*``), start-up, bind, a back-off and the lower bound's wait they partition the wall time
STAGE_TIMES = ("feasp", "point_proof", "recover", "analysis", "checks", "evidence")
#: the ``times`` entries that partition a solve's wall time after start-up (``total``): the plan's
#: road (:meth:`lmidsl.solver.plan.Plan.solve`), the point's stages, the optimum's road and stages
#: behind a back-off point (``optimum_*``), the back-off's own solves, the wait for the lower bound
ROAD_TIMES = ("road_closed_form", "road_as_written", "road_conditioned", "road_other_routes")
TIME_PARTS = ("bind", *ROAD_TIMES, *STAGE_TIMES, *(f"optimum_{k}" for k in ROAD_TIMES + STAGE_TIMES),
              "backoff", "lower_bound_wait", "infeasibility_proof")


def _backoff_reason(solution: Solution, instance: Instance, finish: dict) -> str | None:
    """Why the automatic back-off is needed (None: it is not; the optimum is then certified).
    Recovery failure and ill-conditioning are known before the analysis, which is then spent on
    the back-off point only; each stage of the optimum runs once."""
    if not instance.theorem.conditioned:
        finish_solution(solution, **finish)
        return None
    plan = finish["plan"]
    prove_point(solution, plan, finish["diagnose"])
    if not recover_point(solution):
        return solution.message
    cond = solution.design.worst_condition if solution.design is not None else None
    if cond is not None and cond > ILL_CONDITIONED and not (solution.backend == CLOSED_FORM and finish["certify"]):
        return f"the recovery at the optimum inverts a matrix of condition number {cond:.3g}"
    # a closed form's point is built from its design (W = K Y): however ill-conditioned Y, the
    # analysis of the recovered design decides, and a back-off's SDP would only move away from it
    if finish["certify"]:
        certify_point(solution, plan)
    if solution.analysis is not None and not solution.analysis.passed:
        return (f"{solution.analysis.theorem} did not certify the design recovered at the optimum "
                f"({solution.analysis.status}, gamma {solution.analysis.gamma})")
    return None


def closed_form_design(optimum: Solution, reason: str, finish: dict) -> Solution | None:
    """The theorem's closed-form point that the road computed beside the optimum and did not keep
    (``Solution.closed_form``), finished and judged, for when the optimum's design needs a back-off
    (``reason``); None when there is none or its design is not certified.  A closed form's point is
    built from its design (W = K Y), so its recovery needs no back-off: COMPleib AC3, H∞ state
    feedback: the SDP optimum's recovery was ill-conditioned, the back-off's design 3.8e-4 above
    the proved optimum, the Riccati gain's 1e-6 above it.  Its record holds the optimum's road and
    stages under ``optimum_*`` (the ``times`` record partitions the wall time)."""
    point = optimum.closed_form
    if point is None or optimum.objective is None:
        return None
    point.scaling, point.certify = optimum.scaling, optimum.certify
    finish_solution(point, **finish)
    if not judge(point).verdict.certified:
        optimum.notes.append("the closed form's design is not certified either: "
                             + "; ".join(point.verdict.reasons))
        return None
    point.notes.append(f"the design recovered at the SDP optimum needed a back-off ({reason}); the closed "
                       "form's design is delivered")
    point.times.update({f"optimum_{k}": v for k, v in optimum.times.items()
                        if k.startswith("road_") or k in STAGE_TIMES})
    return point


def backed_off(model, applied, optimum: Solution, delta: float, reason: str | None, finish: dict,
               searched: bool = True, started: float | None = None) -> Solution:
    """The design at objective ≤ (1 + δ)·optimum (:mod:`lmidsl.solver.backoff`) by two methods:
    the *level problem* (the LMIs and that bound, no objective, along the plan's routes: one
    solve, a central point of the slab) and the *condition-minimising search* (golden section on
    t in t I ⪯ E ⪯ κ I: about 15 solves).

    ``reason`` (an automatic back-off): the level problem first, the search when its point is not
    certified; a point is kept only if certified — it must not cost a certificate, and an
    uncertified back-off point (a thin slab, an inaccurate solve) can be worse than the optimum
    (hinf_of_dt plant-2: an unstable controller where the optimum's is stable); otherwise the
    optimum is returned with the notes.  Seed 001 at δ = 1 %: the level point has cond(Z),
    cond(X − Z) = 130, 675 and γ 0.38287 in 0.14 s; the search 136, 137 and γ 0.38290 in 3.4 s.
    Without ``reason`` (the user's δ) the search first, the level problem when it fails, and the
    answer is returned as it is.  ``searched=False``: the level problem only (a rung of the automatic
    ladder, :data:`lmidsl.solver.backoff.AUTO_DELTAS`).  ``started``: when the back-off began (the
    ladder's first rung), for its time."""
    plan = finish["plan"]
    instance = optimum.instance
    automatic = reason is not None
    t0 = time.perf_counter() if started is None else started

    def search():
        try:
            found = backoff_solution(model, optimum, delta, plan.solver, **plan.options)
        except LmidslError as exc:
            if not automatic:     # a back-off the user asked for: their δ is at fault
                raise
            optimum.notes.append(f"automatic back-off failed: {exc}")
            return None
        return None if found is optimum else found

    def level():
        found = level_solution(model, optimum, delta, plan)
        if found is None:
            optimum.notes.append(f"the level problem at objective ≤ (1 + {delta:g}) × optimum gave no "
                                 "certified point on any route")
        return found

    methods = [("level problem", level), ("condition-minimising search", search)][:2 if searched else 1]
    candidate = None
    for name, method in (methods if automatic else methods[::-1]):
        found = method()
        if found is None:
            continue
        found.certify = optimum.certify
        started = time.perf_counter()
        finish_solution(found, **finish)
        finished = time.perf_counter() - started     # recorded under the stages' own names
        if automatic and not judge(found).verdict.certified:    # judged again with the bounds, if kept
            optimum.notes.append(f"the {name}'s back-off point is not certified: {'; '.join(found.verdict.reasons)}")
            continue
        found.backoff["method"] = name
        candidate = found
        break
    if candidate is None:
        if automatic:
            optimum.notes.append("no certified back-off point: the optimum's design is kept")
        elif optimum.design is None and optimum.analysis is None:
            finish_solution(optimum, **finish)       # the user's back-off failed: the optimum, not yet finished
        return optimum
    # the back-off's own solves (and candidates not kept); the kept point's stages are under their
    # names, the optimum's road and stages under optimum_*: the record partitions the wall time
    candidate.bounds = optimum.bounds
    if reason:
        candidate.backoff["reason"] = reason
    if instance.theorem.recovery:
        try:
            candidate.backoff["recovery_cond_before"] = recover(applied.scaled, optimum.values)[1]
        except LmidslError as exc:
            candidate.backoff["recovery_cond_before"] = f"recovery failed: {exc}"
    candidate.times["backoff"] = time.perf_counter() - t0 - finished
    candidate.times.update({f"optimum_{k}": v for k, v in optimum.times.items()
                            if k.startswith("road_") or k in STAGE_TIMES})
    return candidate


def finish_solution(solution: Solution, plan: Plan | None = None, certify: bool = True,
                    diagnose: bool = True, solver=None, backend=None, margin: float | None = None) -> Solution:
    """The point's stages, each run once, in place: the feasp diagnosis and the LMIs proved at the
    point (:func:`prove_point`), the recovery mapped back through any scaling
    (:func:`recover_point`), and with ``certify`` the analysis certificate, the theorem's checks and
    the independent evidence (:func:`certify_point`).  ``plan`` (default: from ``backend``,
    ``solver`` and ``margin``) is the road every solve takes."""
    plan = plan or Plan(backend, solver, {}, margin)
    prove_point(solution, plan, diagnose)
    if recover_point(solution) and certify:
        certify_point(solution, plan)
    return solution


def prove_point(solution: Solution, plan: Plan, diagnose: bool = True) -> None:
    """Feasibility diagnosis (:meth:`Plan.diagnose`) of a solve without a certified point; every
    LMI proved in ball arithmetic at a returned point (:mod:`lmidsl.numeric.proof`); the reported values."""
    instance = solution.instance
    if diagnose and diagnosis_needed(solution):
        t0 = time.perf_counter()
        plan.diagnose(solution)
        solution.times["feasp"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    if solution.ok:
        solution.lmis = lmi_certificate(instance, {**instance.data, **solution.values}, prove=True,
                                        congruence=solution.congruence)
    if solution.ok and instance.theorem.reported:
        solution.reported = evaluate_reported(instance, {**instance.data, **solution.values})
    solution.times["point_proof"] = time.perf_counter() - t0


def recover_point(solution: Solution) -> bool:
    """The design recovered at the point (mapped back through any scaling); False when the
    recovery fails (the message says why), True otherwise."""
    instance = solution.instance
    if not (solution.ok and instance.theorem.recovery):
        return True
    t0 = time.perf_counter()
    undo = solution.scaling.undo if solution.scaling is not None else None
    try:
        solution.design = recover_design(instance, solution.values, undo, solver=solution.solver,
                                         backend=solution.backend,
                                         backoff=(solution.backoff or {}).get("delta"))
    except LmidslError as exc:
        solution.message = f"recovery failed: {exc}"
        return False
    solution.times["recover"] = time.perf_counter() - t0
    return True


def certify_point(solution: Solution, plan: Plan) -> None:
    """The delivered design's analysis certificate, the theorem's checks and the independent
    evidence of the claimed level."""
    instance = solution.instance
    if not solution.ok:
        return
    if solution.design is not None and instance.theorem.analysis is not None:
        t0 = time.perf_counter()
        solution.analysis = certify_by_analysis(solution.original_instance, solution.recovered,
                                                solution.point_gamma, plan=plan)
        solution.times["analysis"] = time.perf_counter() - t0
    if instance.theorem.checks:
        t0 = time.perf_counter()
        solution.checks = run_checks(solution)
        solution.times["checks"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    solution.evidence = claim_evidence(solution, headline_level(solution))
    if solution.evidence:
        solution.times["evidence"] = time.perf_counter() - t0


def solve(theorem, example: str | None = None, data: dict | None = None,
          overrides: dict | None = None, solver: str | None = None, backend: str | None = None,
          margin: float | None = None, certify: bool = True, scaling="auto",
          backoff="auto", diagnose: bool = True, bounds: bool = True, max_lmis: int | None = None,
          max_psd_rows: int | None = None, **options) -> Solution:
    """Solve a theorem on an example or data; returns a :class:`Solution`.  By default
    (``backoff="auto"``) a design that its analysis does not certify at the optimum, or whose
    recovery is ill-conditioned, is recovered at γ² ≤ (1 + 10⁻²) γ*² instead (both reported).
    ``max_lmis``, ``max_psd_rows``: the limits of :func:`make_instance`."""
    t0 = time.perf_counter()
    instance = make_instance(theorem, example, data, overrides, max_lmis=max_lmis, max_psd_rows=max_psd_rows)
    bind_time = time.perf_counter() - t0
    solution = solve_instance(instance, solver, backend, margin, certify, scaling, backoff,
                              diagnose=diagnose, bounds=bounds, **options)
    solution.times = {"bind": bind_time, **solution.times, "total": time.perf_counter() - t0}
    return solution
