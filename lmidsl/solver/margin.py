"""The strictness margin: strict ``N ≺ 0`` is imposed as ``N ⪯ −ε I``; escalate ε when needed.

A solver stops at its own tolerance, so with ε below that tolerance the returned point may
miss a strict LMI by a hair.  :func:`solve_model` then re-solves with ε multiplied by
:data:`MARGIN_ESCALATION` until numpy's certificate holds.
"""
from __future__ import annotations

from .solution import Solution


MARGIN_ESCALATION = (10.0, 100.0, 1000.0)


def solve_model(model, solver: str | None = None, escalate: bool = True,
                restore_margin: bool = False, **options) -> Solution:
    """Solve a compiled model; if the point does not satisfy the strict LMIs, re-solve with a
    larger margin.

    Margin escalation: a solver stops at its own tolerance, so with a margin below that
    tolerance the returned point may violate an LMI by a hair (largest eigenvalue ≥ 0).  The
    margin is then multiplied by 10, 100, 1000 (re-solving each time) until the certificate
    holds; the margins tried are reported in ``Solution.notes``, and ``times["solver_calls"]``
    adds up the solver time of every attempt.  ``restore_margin`` puts the model's margin back
    afterwards (a sweep re-solves the same model at the next point).
    """
    solution = model.solve(solver, **options)
    base = model.margin
    tried = [base]
    calls = _solver_call_time(solution)
    for factor in (MARGIN_ESCALATION if escalate else ()):
        if not solution.ok or solution.certified:
            break
        model.set_margin(base * factor)
        tried.append(model.margin)
        solution = model.solve(solver, **options)
        calls += _solver_call_time(solution)
    solution.times["solver_calls"] = calls
    if len(tried) > 1:
        solution.notes.append(
            "margin escalated " + " -> ".join(f"{m:g}" for m in tried)
            + (" (certificate holds)" if solution.certified else " (certificate still fails)"))
        if restore_margin:
            model.set_margin(base)
    return solution


def _solver_call_time(solution: Solution) -> float:
    return solution.times.get("solver_call", solution.times.get("solver")) or 0.0
