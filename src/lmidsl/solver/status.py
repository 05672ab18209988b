"""What a solve can end in: one name per outcome (the pattern of ``cvxpy/settings.py``).

A backend maps its solver's own status to one of these.  :data:`SOLVED` are the statuses that
return a point; whether the point is trusted is decided by numpy's certificate
(:func:`lmidsl.solver.solution.lmi_certificate`), never by the status alone.  A status is always
a solver's termination word (:data:`TERMINATION_WORDS`): the feasp diagnosis keeps its own words
(:mod:`lmidsl.solver.feasibility`), and the verdict its own (:mod:`lmidsl.certify.verdict`).
"""
from __future__ import annotations

OPTIMAL = "optimal"
OPTIMAL_INACCURATE = "optimal_inaccurate"
INFEASIBLE = "infeasible"
INFEASIBLE_INACCURATE = "infeasible_inaccurate"
UNBOUNDED = "unbounded"
UNBOUNDED_INACCURATE = "unbounded_inaccurate"
SOLVER_ERROR = "solver_error"
USER_LIMIT = "user_limit"      # the solver stopped at an iteration or time limit

SOLVED = frozenset({OPTIMAL, OPTIMAL_INACCURATE})
TERMINATION_WORDS = frozenset({OPTIMAL, OPTIMAL_INACCURATE, INFEASIBLE, INFEASIBLE_INACCURATE, UNBOUNDED,
                               UNBOUNDED_INACCURATE, SOLVER_ERROR, USER_LIMIT})


def solved(status: str) -> bool:
    """The solver returned a point (optimal, or optimal to reduced accuracy)."""
    return status in SOLVED


def worst(statuses) -> str:
    """The status of a set of solves (e.g. one per polytope vertex): the first unsolved one,
    else optimal_inaccurate if any is, else optimal."""
    statuses = list(statuses)
    unsolved = [s for s in statuses if not solved(s)]
    if unsolved:
        return unsolved[0]
    return OPTIMAL if all(s == OPTIMAL for s in statuses) else OPTIMAL_INACCURATE


__all__ = ["OPTIMAL", "OPTIMAL_INACCURATE", "INFEASIBLE", "INFEASIBLE_INACCURATE", "UNBOUNDED",
           "UNBOUNDED_INACCURATE", "SOLVER_ERROR", "USER_LIMIT", "SOLVED", "TERMINATION_WORDS", "solved", "worst"]
