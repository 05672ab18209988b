"""The Python API: bind, compile, solve, recover and certify in one call.

>>> import lmidsl
>>> sol = lmidsl.solve("wang_l2linf.thm3", example="paper-full")
>>> sol.gamma, sol.recovered["Af"], sol.analysis.gamma
"""
from __future__ import annotations

import time

from .solver.backends import choose_backend, get_backend, second_opinion
from .solver.fallback import riccati_point, with_fallbacks
from .solver.status import INFEASIBLE, INFEASIBLE_INACCURATE, NOT_SOLVED
from .certify import certify_by_analysis
from .theorem.checks import run_checks
from .errors import InputError, LmidslError
from .solver.feasibility import diagnosis_needed, feasp
from .numeric.instance import Instance, bind
from .numeric.recovery import recover, recover_design
from .solver.backends.base import DEFAULT_MARGIN
from .solver.conditioning import equilibrate, solve_conditioned
from .solver.margin import solve_model
from .numeric.scaling import apply_scaling
from .theorem.registry import get_example, get_theorem
from .solver.solution import Solution, evaluate_reported, lmi_certificate
from .theorem.theorem import Theorem
from .solver.backoff import DEFAULT_DELTA, backoff_solution, level_solution

AUTO_DELTAS = (DEFAULT_DELTA, 10 * DEFAULT_DELTA)
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
                  overrides: dict | None = None) -> Instance:
    """Bind an example (or data) with overrides to a theorem.  Entries of ``data`` the theorem
    does not use are ignored with an :class:`~lmidsl.errors.UnusedDataWarning`; an unknown
    name in ``overrides`` is an error."""
    thm = as_theorem(theorem)
    if example is None and data is None and thm.examples:
        example = next(iter(thm.examples))
    optional = set(data or {}) - set(overrides or {})      # a data file may serve several theorems
    return bind(thm, instance_inputs(thm, example, data, overrides), example=example,
                optional=optional)


ILL_CONDITIONED = 1e6
"""A recovery inverting a matrix of larger condition number is backed off from (``backoff="auto"``)."""


def solve_instance(instance: Instance, solver: str | None = None, backend: str | None = None,
                   margin: float | None = None, certify: bool = True, scaling="auto",
                   backoff: float | None = None, diagnose: bool = True, **options) -> Solution:
    """Compile, solve, recover the filter and (optionally) certify it by analysis.

    An uncertified solve gets the feasp diagnosis (``diagnose``, see :func:`finish_solution`).
    ``scaling``: the theorem's declared signal scalings ('auto', 'none' or {signal: factor});
    the solver sees the scaled instance, recovered matrices are mapped back
    (:mod:`lmidsl.numeric.scaling`).  ``backoff`` = δ: re-solve at objective ≤ (1 + δ)·optimum for a
    well-conditioned recovery (:mod:`lmidsl.solver.backoff`); ``"auto"``: only when the filter recovered
    at the optimum fails its analysis certificate (or its recovery fails), with δ = 10⁻².
    """
    backend = choose_backend(backend, solver)
    applied = apply_scaling(instance, scaling)
    solution, model = solve_conditioned(applied.scaled, get_backend(backend),
                                        lambda m: solve_model(m, solver, **options), margin)
    base_margin = margin if margin is not None else DEFAULT_MARGIN
    if solver is None:     # no certified point, or a margin-set γ: the other routes
        solution = with_fallbacks(
            model, solution, lambda m, name: solve_model(m, name, **(options if m.backend == backend else {})),
            base_margin)
    solution.scaling = applied
    reason, failed = None, False
    finish = dict(solver=solver, backend=backend, certify=certify, diagnose=diagnose, margin=base_margin)
    if backoff == "auto":
        # back off only when the design recovered at the optimum is not certified, or when its
        # recovery fails or inverts a matrix with condition number above ILL_CONDITIONED; the
        # latter two are known before the analysis, which is then spent on the back-off point only
        conditioned = solution.ok and bool(instance.theorem.conditioned)
        finish_solution(solution, **{**finish, "certify": certify and not conditioned})
        failed = solution.message.startswith("recovery failed")
        cond = solution.design.worst_condition if solution.design is not None else None
        if conditioned and failed:
            reason = solution.message
        elif conditioned and cond is not None and cond > ILL_CONDITIONED:
            reason = f"the recovery at the optimum inverts a matrix of condition number {cond:.3g}"
        elif conditioned:
            finish_solution(solution, **finish)
            if solution.analysis is not None and not solution.analysis.passed:
                reason = (f"{solution.analysis.theorem} did not certify the design recovered at the optimum "
                          f"({solution.analysis.status}, gamma {solution.analysis.gamma})")
        if reason is None:
            return solution
    if backoff is not None and solution.ok:
        if reason is None:
            return backed_off(model, applied, solution, backoff, reason, finish, **options)
        for delta in AUTO_DELTAS:   # a larger δ when the first back-off gives no certified design
            kept = backed_off(model, applied, solution, delta, reason, finish, **options)
            if kept is not solution:
                return kept
        if certify and solution.analysis is None and not failed:
            finish_solution(solution, **finish)      # no back-off point: the optimum's certificate
        return solution
    finish_solution(solution, solver=solver, backend=backend, certify=certify, diagnose=diagnose,
                    margin=base_margin)
    return solution


def backed_off(model, applied, optimum: Solution, delta: float, reason: str | None, finish: dict,
               **options) -> Solution:
    """The design at objective ≤ (1 + δ)·optimum (:mod:`lmidsl.solver.backoff`) by two methods:
    the *level problem* (the LMIs and that bound, no objective, along the fallback routes: one
    solve, a central point of the slab) and the *condition-minimising search* (golden section on
    t in t I ⪯ E ⪯ κ I: about 15 solves).

    ``reason`` (an automatic back-off): the level problem first, the search when its point is not
    certified; a point is kept only if certified — it must not cost a certificate, and an
    uncertified back-off point (a thin slab, an inaccurate solve) can be worse than the optimum
    (hinf_of_dt plant-2: an unstable controller where the optimum's is stable); otherwise the
    optimum is returned with the notes (:func:`solve_instance` certifies it if it has not yet).  Seed 001 at δ = 1 %:
    the level point has cond(Z), cond(X − Z) = 130, 675 and γ 0.38287 in 0.14 s; the search
    136, 137 and γ 0.38290 in 3.4 s.  Without ``reason`` (the user's δ) the search first, the
    level problem when it fails, and the answer is returned as it is."""
    solver = finish["solver"]
    instance = optimum.instance
    automatic = reason is not None
    t0 = time.perf_counter()

    def search():
        try:
            found = backoff_solution(model, optimum, delta, solver, **options)
        except LmidslError as exc:
            if not automatic:     # a back-off the user asked for: their δ is at fault
                raise
            optimum.notes.append(f"automatic back-off failed: {exc}")
            return None
        return None if found is optimum else found

    def level():
        found = level_solution(model, optimum, delta, solver, **options)
        if found is None:
            optimum.notes.append(f"the level problem at objective ≤ (1 + {delta:g}) × optimum gave no "
                                 "certified point on any route")
        return found

    methods = [("level problem", level), ("condition-minimising search", search)]
    candidate = None
    for name, method in (methods if automatic else methods[::-1]):
        found = method()
        if found is None:
            continue
        finish_solution(found, **finish)
        if automatic and not found.verdict()[0]:
            optimum.notes.append(f"the {name}'s back-off point is not certified: {'; '.join(found.verdict()[1])}")
            continue
        found.backoff["method"] = name
        candidate = found
        break
    if candidate is None:
        if automatic:
            optimum.notes.append("no certified back-off point: the optimum's design is kept")
        elif optimum.design is None and optimum.analysis is None:
            finish_solution(optimum, **finish)       # the user's back-off failed: the optimum
        return optimum
    candidate.times["backoff"] = time.perf_counter() - t0
    if reason:
        candidate.backoff["reason"] = reason
    if instance.theorem.recovery:
        try:
            candidate.backoff["recovery_cond_before"] = recover(applied.scaled, optimum.values)[1]
        except LmidslError as exc:
            candidate.backoff["recovery_cond_before"] = f"recovery failed: {exc}"
    return candidate


def finish_solution(solution: Solution, solver=None, backend=None, certify=True,
                    diagnose=True, margin: float | None = None) -> Solution:
    """Feasibility diagnosis, recovery (mapped back through any scaling) and analysis
    certificate, in place.

    When the solver returns no certified point, the feasp diagnosis (:mod:`lmidsl.solver.feasibility`)
    is attached; if it finds no strictly feasible point, ``status`` becomes "infeasible" (or
    "marginal": feasible by less than the margin); the solver's own word stays in
    ``solver_status``.  An infeasible problem is a result, not an error.
    """
    backend = choose_backend(backend, solver)
    instance = solution.instance
    original = solution.scaling.original if solution.scaling is not None else instance
    solution.analysis = None
    if diagnose and diagnosis_needed(solution):
        t0 = time.perf_counter()
        feasp_margin = solution.margin if margin is None else margin
        report = feasp(instance, backend=backend, solver=solver, margin=feasp_margin)
        proposal = equilibrate(instance)
        if report.verdict == "infeasible" and not proposal.trivial:
            # an infeasibility verdict must survive the conditioning
            conditioned = feasp(instance, backend=backend, solver=solver, detail=False,
                                margin=feasp_margin, conditioning=proposal)
            if conditioned.verdict != "infeasible":
                solution.notes.append(f"feasp as written said infeasible (t* = {report.tmin:.3g}); on the "
                                      f"conditioned LMIs: {conditioned.verdict} (t* = {conditioned.tmin})")
                report = conditioned
        other = second_opinion(backend, report.solver) if report.verdict == "infeasible" else None
        if other is not None:
            # ... and a second solver's, also when the user named one: one solver's t* ≥ 0 is not
            # a proof (solver="CLARABEL" called a stable plant with a pole at radius 0.99982
            # "infeasible"; CVXOPT finds it strictly feasible)
            second = feasp(instance, backend=other.backend, solver=other.solver, detail=False,
                           margin=feasp_margin)
            if second.verdict != "infeasible":
                solution.notes.append(f"feasp with {report.solver} said infeasible (t* = {report.tmin:.3g}); "
                                      f"with {second.solver}: {second.verdict} (t* = {second.tmin}): "
                                      "not a proof of infeasibility")
                report = second
        if report.verdict == "infeasible":
            # a point from a Riccati equation that satisfies every LMI refutes any "infeasible"
            # (stress plants, light family, discrete: feasp with CVXOPT and with Clarabel both said
            # t* ≥ 0 on stable plants whose bounded-real LMI the Riccati point satisfies)
            witness = riccati_point(instance, None, 0.0)
            if witness is not None:
                solution.notes.append(f"feasp said infeasible (t* = {report.tmin:.3g}), but a point from the "
                                      f"Riccati equation satisfies every LMI (gamma {witness.gamma:.8g}): "
                                      f"the problem is feasible; {solution.solver} did not solve it")
                report.refuted_by = "Riccati"
        solution.feasp = report
        if report.verdict in ("infeasible", "marginal"):
            solution.solver_status = solution.status
            solution.status = report.verdict
        elif solution.status in (INFEASIBLE, INFEASIBLE_INACCURATE):
            # the solver's "infeasible" is a claim; the diagnosis did not confirm it
            solution.solver_status = solution.status
            solution.status = NOT_SOLVED
            if not report.refuted_by:
                solution.notes.append(f"{solution.solver} said {solution.solver_status}; feasp: {report.verdict}: "
                                      "not a proof of infeasibility")
        solution.times["feasp"] = time.perf_counter() - t0
    if solution.ok:
        # THE certificate again, now proved in ball arithmetic (lmidsl.numeric.proof)
        solution.lmis = lmi_certificate(instance, {**instance.data, **solution.values}, prove=True,
                                        congruence=solution.congruence)
    if solution.ok and instance.theorem.reported:
        solution.reported = evaluate_reported(instance, {**instance.data, **solution.values})
    if solution.ok and instance.theorem.recovery:
        t0 = time.perf_counter()
        undo = solution.scaling.undo if solution.scaling is not None else None
        try:
            solution.design = recover_design(instance, solution.values, undo, solver=solution.solver,
                                             backend=solution.backend,
                                             backoff=(solution.backoff or {}).get("delta"))
        except LmidslError as exc:
            solution.message = f"recovery failed: {exc}"
            return solution
        solution.times["recover"] = time.perf_counter() - t0
        if certify and instance.theorem.analysis is not None:
            t0 = time.perf_counter()
            solution.analysis = certify_by_analysis(original, solution.recovered, solution.gamma,
                                                    solver=solver, backend=backend)
            solution.times["analysis"] = time.perf_counter() - t0
    if certify and solution.ok and instance.theorem.checks:
        t0 = time.perf_counter()
        solution.checks = run_checks(solution)
        solution.times["checks"] = time.perf_counter() - t0
    return solution


def solve(theorem, example: str | None = None, data: dict | None = None,
          overrides: dict | None = None, solver: str | None = None, backend: str | None = None,
          margin: float | None = None, certify: bool = True, scaling="auto",
          backoff="auto", diagnose: bool = True, **options) -> Solution:
    """Solve a theorem on an example or data; returns a :class:`Solution`.  By default
    (``backoff="auto"``) a design that its analysis does not certify at the optimum, or whose
    recovery is ill-conditioned, is recovered at γ² ≤ (1 + 10⁻²) γ*² instead (both reported)."""
    t0 = time.perf_counter()
    instance = make_instance(theorem, example, data, overrides)
    bind_time = time.perf_counter() - t0
    solution = solve_instance(instance, solver, backend, margin, certify, scaling, backoff,
                              diagnose=diagnose, **options)
    solution.times = {"bind": bind_time, **solution.times}
    return solution
