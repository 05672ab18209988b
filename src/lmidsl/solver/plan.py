"""The one road to a certified point.

Every caller that needs a solved, certified point — a solve, the analysis certificate of a design,
``verify``, a bisection step, a successive-LMI step, the back-off's level problem — asks a
:class:`Plan`.  A plan is built once from the backend, the solver (named or not), the solver
options and the strictness margin, and tries, in this stated order:

1. the named (or the backend's default) solver on the theorem **as written**, then on the
   **conditioned** LMIs where :func:`~lmidsl.solver.conditioning.equilibrate` proposes an exact
   congruence/variable scaling (both are solved: on badly scaled data the answer as written can
   be a certified bound far above the optimum);
2. when no solver was named, the backend's **fallback routes** (other solvers, other modelling
   layers; :func:`~lmidsl.solver.backends.fallback_routes`) until one gives a *good* answer
   (certified, solved to full accuracy, the margin not setting the objective) — skipped, with
   the margin's escalation, when the first route's optimum is inaccurate and the closed form of
   step 3 (then computed, once) is certified within :data:`CLOSED_FORM_GAP` of its objective; the
   fallback routes also when that point is certified and the model has more than
   :data:`CLOSED_FORM_MAX_UNKNOWNS` unknowns, whatever the first answer;
3. the theorem's declared **closed forms** (a Riccati point, :mod:`lmidsl.solver.fallback`),
   always — also when the user named a solver, and also after a *good* SDP answer: a solver's
   "optimal" is no proof of optimality, and on the closed loop of a helicopter model with its
   H∞ controller (norm 1.7651) Clarabel's certified, "optimal" point of the bounded real lemma
   was at γ = 722.97; the Riccati point costs milliseconds to a second and is certified the
   same way (its LMIs proved at the point it builds), and the lower certified level is kept.

Of all answers the *better* one is kept (:func:`~lmidsl.solver.fallback.better`: certified over
uncertified, then the lower objective — each certified objective is a valid bound).  The notes
of the kept solution say what each route gave.

A plan asked for a point **at a given level** (:meth:`Plan.point_at_level`, the analysis
certificate of a design) tries the closed form first, since it needs no SDP, and the level
problem when the minimum sits on the boundary of the strict set.  :meth:`Plan.level` is the level
problem "every LMI, objective ≤ β" along the same routes (the back-off).  :meth:`Plan.diagnose`
is the feasp diagnosis of a solve that gave no certified point.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

from ..errors import LmidslError
from .backends import Route, choose_backend, fallback_routes, get_backend, is_first_order, second_opinion
from .backends.base import DEFAULT_MARGIN
from .conditioning import equilibrate
from .fallback import CLOSED_FORM, better, declares_closed_form, good, riccati_point, route_model, said
from .feasibility import FEASP_INFEASIBLE, diagnosis_needed, feasp
from .margin import solve_model
from .solution import Solution
from .status import INFEASIBLE, INFEASIBLE_INACCURATE, OPTIMAL_INACCURATE, SOLVER_ERROR


#: a certified closed-form point within this relative gap of an *inaccurate* first answer's
#: objective is kept without escalating the margin and without the fallback routes: they could
#: lower the level by less than the gap, at many times the cost (H∞ state feedback at 32 states,
#: Clarabel inaccurate: three escalations 5.7 s and CVXOPT 58 s, the Riccati point 0.5 s and 4e-5
#: above the proved lower end).  An accurate answer that misses the strict LMIs by a hair is
#: escalated as before (its certified point is usually closer than the closed form's).
CLOSED_FORM_GAP = 1e-4
#: with a certified closed-form point in hand, a model with more scalar unknowns than this gets no
#: fallback routes, whatever the first route's answer: the dense interior-point fallback (CVXOPT)
#: costs ~m³ + m²Σn_k² per iteration (state feedback at 48 states, m = 1273, Clarabel's solver
#: error: no answer in 600 s, where the Riccati point took 28 s and the hand script 18 s; at 24
#: states, m = 325, Clarabel's solver error: three fallbacks 13.4 s, the best 79546 against the
#: Riccati point's certified 76316.5)
CLOSED_FORM_MAX_UNKNOWNS = 300


class _ClosedForm:
    """The theorem's closed-form point (:func:`riccati_point`), computed once, when first asked
    (a road that ends earlier — a proved infeasibility, a bisection's "infeasible" — never pays
    for it); ``seconds``: the time it took."""

    def __init__(self, instance, declared: bool):
        self.instance, self.declared = instance, declared
        self.seconds, self._done, self._point = 0.0, False, None

    def point(self) -> Solution | None:
        if self.declared and not self._done:
            t0 = time.perf_counter()
            self._point = riccati_point(self.instance, None, 0.0)
            self.seconds, self._done = time.perf_counter() - t0, True
        return self._point


def _close_enough(first: Solution, closed: _ClosedForm) -> bool:
    """Whether ``first`` is an inaccurate optimum and the closed form's point is certified at most
    :data:`CLOSED_FORM_GAP` above its objective (the point is computed only for such a ``first``)."""
    if first.status != OPTIMAL_INACCURATE or first.objective is None or not closed.declared:
        return False
    point = closed.point()
    return _certified(point) and first.objective >= point.objective - CLOSED_FORM_GAP * abs(point.objective)


def _certified(solution: Solution | None) -> bool:
    return solution is not None and solution.ok and solution.lmis_hold and solution.objective is not None


def _too_large(model) -> bool:
    """More scalar unknowns than :data:`CLOSED_FORM_MAX_UNKNOWNS` (None: the backend does not say)."""
    unknowns = getattr(getattr(model, "problem", None), "n", None)
    return unknowns is not None and unknowns > CLOSED_FORM_MAX_UNKNOWNS


@dataclass
class Plan:
    """Backend, solver, options and margin of every solve on the road (see the module docstring).

    ``fallbacks``: try the fallback routes (default: when no solver is named).
    ``closed_forms``: try the theorem's declared closed forms (a cross-check of one named
    solver turns them off, so that its row is that solver's answer).
    ``infeasible_ends``: a solver's "infeasible" ends the road, the first route's or a fallback's
    after the first failed (a bisection step: the bracket's infeasible end is then the solver's
    word, reported as such, not a proof; the feasible end is always a certified, proved point).
    ``infeasibility_proof``: callable(model) → certificate (``.proved``), tried on the model whose
    solver said "infeasible" before any other route: a proved infeasibility ends the road (each
    fallback route, SCS included, could only fail to find a point; reproduce's infeasible rows
    spent two thirds of their time there).  The proof lives above this layer: the pipeline passes
    :func:`lmidsl.certify.infeasibility.prove_infeasible`; the certificate is kept in the
    solution's ``infeasibility``."""

    backend: str
    solver: str | None = None
    options: dict = field(default_factory=dict)
    margin: float | None = None
    fallbacks: bool | None = None
    closed_forms: bool = True
    infeasible_ends: bool = False
    infeasibility_proof: Callable | None = None

    def __post_init__(self):
        self.backend = choose_backend(self.backend, self.solver)
        if self.fallbacks is None:
            self.fallbacks = self.solver is None

    @property
    def base_margin(self) -> float:
        return self.margin if self.margin is not None else DEFAULT_MARGIN

    def routes(self) -> list[Route]:
        """The routes in order: the named or default solver, then (with ``fallbacks``) the backend's."""
        first = [Route(self.backend, self.solver)]
        return first + (list(fallback_routes(self.backend)) if self.fallbacks else [])

    def _solve_model(self, model, solver, **extra):
        options = self.options if model.backend == self.backend else {}
        return solve_model(model, solver, **{**options, **extra})

    # -- the optimum --------------------------------------------------------------------------
    def solve(self, instance, restore_margin: bool = False, model=None, solved: list | None = None):
        """(solution, model) of ``instance``: steps 1–3 of the module docstring.  ``model``: a
        compiled model of the plan's backend to update to ``instance`` instead of compiling it
        as written (a bisection re-solves one compiled model).  ``solved``: a list that receives
        the models solved as written and conditioned (the one not kept still holds its dual: a
        second proved lower bound when the kept model's is loose).  The kept solution's ``times``
        gain the road's own: ``road_closed_form``, ``road_as_written``, ``road_conditioned``,
        ``road_other_routes`` (compiles included), so that its record accounts for the wall time of every route tried."""
        road = {}
        closed = _ClosedForm(instance, self.closed_forms and declares_closed_form(instance.theorem))
        enough = None if not closed.declared else (lambda sol: _close_enough(sol, closed))
        t0 = time.perf_counter()
        model_class = get_backend(self.backend)
        if model is not None:
            model.update(instance)
            model.set_margin(self.base_margin)       # undo escalations of the previous step
            plain = model
        else:
            plain = model_class(instance, margin=self.margin)
        solution = self._solve_model(plain, self.solver, restore_margin=restore_margin, enough=enough)
        model = plain
        solved = [] if solved is None else solved
        solved.append(plain)
        proposal = equilibrate(instance, plain)
        road["road_as_written"] = time.perf_counter() - t0 - closed.seconds
        if not proposal.trivial:
            t1, spent = time.perf_counter(), closed.seconds
            conditioned = model_class(instance, margin=self.margin, conditioning=proposal)
            other = self._solve_model(conditioned, self.solver, restore_margin=restore_margin, enough=enough)
            solved.append(conditioned)
            road["road_conditioned"] = time.perf_counter() - t1 - (closed.seconds - spent)
            kept = better(solution, other)
            before, after = proposal.spread
            kept.notes.append(f"conditioning (coefficient spread 2^{before:.0f} -> 2^{after:.0f}): as written "
                              f"{said(solution)}; conditioned {said(other)}; kept "
                              + ("the conditioned" if kept is other else "as written"))
            solution, model = kept, (conditioned if kept is other else plain)
        t2, spent = time.perf_counter(), closed.seconds
        kept = self._other_routes(model, solution, closed)
        proving = solution.times.get("infeasibility_proof", 0.0)       # a part of its own
        road["road_other_routes"] = time.perf_counter() - t2 - proving - (closed.seconds - spent)
        if closed.seconds:
            road["road_closed_form"] = closed.seconds
        if proving:
            road["infeasibility_proof"] = proving
        kept.times.update(road)
        return kept, model

    def solve_point(self, model, instance) -> Solution:
        """A parametric study's point (a sweep, a scalar search): ``model``, compiled once with the
        parameters as backend parameters, updated to ``instance`` and solved with margin escalation
        (the strict LMIs must hold at the point).  No other route and no conditioning: each would
        compile again at every point; a point that is not good says so, and ``solve`` at that point
        takes the whole road."""
        model.update(instance)
        return self._solve_model(model, self.solver, restore_margin=True)

    def _other_routes(self, model, first: Solution, closed: _ClosedForm) -> Solution:
        """The fallback routes (step 2) while the answer is not good, and ``closed``, the closed
        form (step 3)."""
        if (good(first) and not closed.declared) or (self.infeasible_ends and first.status == INFEASIBLE):
            return first
        if first.status == INFEASIBLE and self.infeasibility_proof is not None:
            t0 = time.perf_counter()
            first.infeasibility = self.infeasibility_proof(model)
            first.times["infeasibility_proof"] = time.perf_counter() - t0
            if first.infeasibility.proved:
                first.notes.append("no other route tried: the infeasibility is proved on the first route's model")
                return first
        kept, tried = first, [said(first)]
        point = closed.point()
        if point is not None:
            tried.append(said(point))
        points = first.ok           # some route returned a point (certified or not)
        suffices = _close_enough(first, closed) or (_certified(point) and _too_large(model))
        for route in (self.routes()[1:] if self.fallbacks and not good(first) and not suffices
                      else []):
            if route.backend == first.backend and route.solver.lower() == (first.solver or "").lower():
                continue
            if points and is_first_order(route.solver):
                continue           # a first-order point (1e-4 accurate) would not sharpen a point in hand
            try:
                other = self._solve_model(route_model(model, route, self.base_margin), route.solver)
            except LmidslError:        # not installed here
                continue
            tried.append(said(other))
            points = points or other.ok
            kept = better(kept, other)
            if good(other) or (self.infeasible_ends and other.status == INFEASIBLE):
                break          # a bisection step after a solver error: the first "infeasible" ends it
        if point is not None:
            kept = better(kept, point)
            if kept is not point and _certified(point):
                kept.closed_form = point      # its design, should the kept point's need a back-off
        if len(tried) == 1:
            return first
        if kept is first and not good(first):
            first.notes.append("no other route returned a better certified point: " + "; ".join(tried))
        else:
            kept.notes.append(f"the first route gave {tried[0]}; kept {said(kept)} (tried: "
                              + "; ".join(tried[1:]) + ")")
        return kept

    # -- a point at a level ---------------------------------------------------------------------
    def level(self, model, bound: float):
        """The first certified point of "every LMI, objective ≤ ``bound``" (no objective) along the
        routes (first-order solvers skipped); None when no route certifies one.  Returns
        (solution, the model it was solved on, what each route gave)."""
        if model.objective is None:
            return None, model, []
        tried = []
        for route in self.routes():
            if route.solver is not None and is_first_order(route.solver):
                continue
            try:
                level_model = route_model(model, route)
                new = level_model.solve(route.solver, problem=level_model.level_problem(bound),
                                        **(self.options if route.backend == self.backend else {}))
            except LmidslError:
                continue
            tried.append(f"{new.backend}/{new.solver}: {new.status}" + ("" if new.lmis_hold else ", not certified"))
            if new.ok and new.lmis_hold:
                return new, level_model, tried
        return None, model, tried

    def point_at_level(self, instance, target_gamma: float | None, tolerance: float, objective_level):
        """A certified point of an analysis ``instance`` whose level is at most ``target_gamma``
        (1 + ``tolerance``) if one can be found, else the best: (solution, method, minimum, route).

        The closed form first (no SDP); then each route, as written and conditioned: the minimum,
        and when its point misses the strict set, the level problem at the target and at the
        minimum (1 + tolerance) (``objective_level(theorem, γ)`` maps a level to the objective)."""
        def enough(sol):
            return sol.ok and sol.lmis_hold and (target_gamma is None or sol.point_gamma is not None
                                                 and sol.point_gamma <= target_gamma * (1 + tolerance))

        if self.closed_forms:
            closed = riccati_point(instance, target_gamma, tolerance)
            if closed is not None and (target_gamma is None or closed.point_gamma <= target_gamma * (1 + tolerance)):
                return closed, CLOSED_FORM, closed.point_gamma, f"{CLOSED_FORM}/scipy ARE"
        proposal = equilibrate(instance)
        conditionings = [None] if proposal.trivial else [None, proposal]
        result = None
        for route in self.routes():
            if self.solver is None and is_first_order(route.solver or ""):
                # SCS's 1e-4-accurate points did not certify an analysis in the papers' reproduction
                # nor in the gallery: the route costs seconds (a solver the user names is used)
                continue
            for conditioning in conditionings:
                try:
                    model = get_backend(route.backend)(instance, conditioning=conditioning)
                    sol, method, minimum = self._min_then_level(model, route.solver, target_gamma,
                                                                tolerance, objective_level)
                except LmidslError:      # a fallback backend or solver that is not installed
                    break
                if result is None or better(result[0], sol) is sol:
                    result = (sol, method, minimum, f"{sol.backend}/{sol.solver}")
            if result is not None and enough(result[0]):
                break
        return result

    def _min_then_level(self, model, solver, target_gamma, tolerance, objective_level):
        """min γ, then (when its point is not strictly feasible) the level problems."""
        sol = self._solve_model(model, solver)
        minimum = sol.point_gamma if sol.ok else None
        if sol.ok and sol.lmis_hold:
            return sol, "min", minimum
        levels = sorted({g for g in (target_gamma, None if minimum is None else minimum * (1 + tolerance))
                         if g is not None})
        for gamma in levels:
            bound = objective_level(model.instance.theorem, gamma)
            if bound is None or model.objective is None:
                break
            level_sol = model.solve(solver, problem=model.level_problem(bound))
            if level_sol.ok and level_sol.lmis_hold:
                return level_sol, "level", minimum
            if sol.status == SOLVER_ERROR and level_sol.status != SOLVER_ERROR:
                sol = level_sol
        return sol, "min", minimum

    # -- no certified point: the diagnosis -------------------------------------------------------
    def diagnose(self, solution: Solution) -> None:
        """The feasp diagnosis of a solve without a certified point, in place.

        feasp as written, then on the conditioned LMIs (an infeasibility verdict must survive the
        conditioning), then a second solver (one solver's t* ≥ 0 is not a proof: Clarabel called a
        stable plant with a pole at radius 0.99982 "infeasible", CVXOPT found it strictly
        feasible), then the closed form (a Riccati point satisfying every LMI refutes any
        "infeasible").  The diagnosis is kept in ``solution.feasp``; ``status`` stays the
        solver's termination word (a diagnosis that rules the point out makes ``solution.ok``
        false)."""
        if not diagnosis_needed(solution):
            return
        instance = solution.instance
        feasp_margin = self.base_margin
        report = feasp(instance, backend=self.backend, solver=self.solver, margin=feasp_margin)
        proposal = equilibrate(instance)
        if report.verdict == FEASP_INFEASIBLE and not proposal.trivial:
            conditioned = feasp(instance, backend=self.backend, solver=self.solver, detail=False,
                                margin=feasp_margin, conditioning=proposal)
            if conditioned.verdict != FEASP_INFEASIBLE:
                solution.notes.append(f"feasp as written said infeasible (t* = {report.tmin:.3g}); on the "
                                      f"conditioned LMIs: {conditioned.verdict} (t* = {conditioned.tmin})")
                report = conditioned
        other = second_opinion(self.backend, report.solver) if report.verdict == FEASP_INFEASIBLE else None
        if other is not None:
            second = feasp(instance, backend=other.backend, solver=other.solver, detail=False,
                           margin=feasp_margin)
            if second.verdict != FEASP_INFEASIBLE:
                solution.notes.append(f"feasp with {report.solver} said infeasible (t* = {report.tmin:.3g}); "
                                      f"with {second.solver}: {second.verdict} (t* = {second.tmin}): "
                                      "not a proof of infeasibility")
                report = second
        if report.verdict == FEASP_INFEASIBLE and self.closed_forms:
            witness = riccati_point(instance, None, 0.0)
            if witness is not None:
                solution.notes.append(f"feasp said infeasible (t* = {report.tmin:.3g}), but a point from the "
                                      f"Riccati equation satisfies every LMI (gamma {witness.point_gamma:.8g}): "
                                      f"the problem is feasible; {solution.solver} did not solve it")
                report.refuted_by = "Riccati"
        solution.feasp = report
        if not report.rules_out and solution.status in (INFEASIBLE, INFEASIBLE_INACCURATE) and not report.refuted_by:
            solution.notes.append(f"{solution.solver} said {solution.status}; feasp: {report.verdict}: "
                                  "not a proof of infeasibility")


__all__ = ["Plan"]
