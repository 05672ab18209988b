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
:func:`with_fallbacks` keeps the first *good* answer (certified, solved to full accuracy, with an
objective that the strictness margin does not set), else the best certified one (lowest
objective: each is a valid bound), else the first answer; its notes say what each route gave.
Once a certified answer is in hand, first-order routes (SCS) are skipped: they cost minutes and
would not sharpen it.
"""
from __future__ import annotations

from ..errors import LmidslError
from .backends import Route, fallback_routes, get_backend, is_first_order
from .solution import Solution
from .status import OPTIMAL


def good(solution: Solution) -> bool:
    """Certified, solved to the solver's full accuracy, and the strictness margin does not set
    the objective (an inaccurate or margin-set optimum is a valid bound but maybe not the optimum)."""
    return bool(solution.ok and solution.certified and solution.status == OPTIMAL
                and not solution.margin_limited)


def better(first: Solution, second: Solution) -> Solution:
    """The answer to keep of two: a certified one over an uncertified one; of two certified ones,
    the lower objective (each is a valid bound); otherwise the first."""
    ok1, ok2 = first.ok and first.certified, second.ok and second.certified
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
    verdict = "" if not solution.ok else (", not certified" if not solution.certified
                                          else (", gamma set by the margin" if solution.margin_limited else ""))
    objective = f" ({solution.objective:.8g})" if solution.ok and solution.objective is not None else ""
    return f"{solution.backend}/{solution.solver}: {solution.status}{objective}{verdict}"


def with_fallbacks(model, first: Solution, solve, margin: float | None = None) -> Solution:
    """``first`` if :func:`good`, else the fallback routes of ``model``'s backend in order:
    ``solve(route_model, solver)`` returns a Solution; a route whose backend or solver is not
    installed is skipped.  See the module docstring for which answer is kept."""
    if good(first):
        return first
    kept, tried = first, [said(first)]
    for route in fallback_routes(model.backend):
        if route.backend == first.backend and route.solver.lower() == (first.solver or "").lower():
            continue
        if kept.ok and kept.certified and is_first_order(route.solver):
            continue           # a first-order solver would not sharpen a certified bound, only cost time
        try:
            other = solve(route_model(model, route, margin), route.solver)
        except LmidslError:        # not installed here
            continue
        tried.append(said(other))
        kept = better(kept, other)
        if good(other):
            break
    if kept is first:
        first.notes.append("no route returned a better certified point: " + "; ".join(tried))
    else:
        kept.notes.append(f"the default route gave {tried[0]}; kept {said(kept)} (tried: "
                          + "; ".join(tried[1:]) + ")")
    return kept


__all__ = ["better", "good", "route_model", "said", "with_fallbacks"]
