"""The strictness margin: strict ``N ≺ 0`` is imposed as ``N ⪯ −ε I``; escalate ε when needed,
reduce it when it, not the problem, sets the optimum.

A solver stops at its own tolerance, so with ε below that tolerance the returned point may
miss a strict LMI by a hair.  :func:`solve_model` then re-solves with ε multiplied by
:data:`MARGIN_ESCALATION` until numpy's certificate holds.

The other way round: with ε too large for the problem's scale (γ* = 1e-9 with data of size 1),
the optimum of the compiled problem is set by ε.  By LP/SDP sensitivity the optimal value moves
by about ε·Σ_k tr Z_k (Z_k the dual matrix of the k-th strict LMI) when ε does; when that exceeds
:data:`MARGIN_INFLUENCE` of the objective, ε is divided by 100 (while the certificate holds, down
to :data:`MIN_MARGIN`), and a γ still set by the margin is flagged (``margin_limited``): a valid
bound, not the optimum.  Only lmidsl's default ε (:data:`~lmidsl.solver.backends.base.DEFAULT_MARGIN`)
is reduced: a margin the caller chose (``--margin``) is honoured — kept, or raised by the
escalation when the certificate needs it, never lowered — and flagged ``margin_limited`` when it
sets the optimum.

A non-strict LMI ``N ⪯ 0`` gets no margin, so when it is active at the optimum the solver's point
sits on its boundary (largest eigenvalue ±1e-10) and no floating-point proof shows ``N ⪯ 0``
there.  :func:`solve_model` then imposes that LMI with the margin too (``N ⪯ −εI``, the same
back-off as a strict one) and re-solves: the point is strictly inside, hence provable, and the
objective moves by about ε·tr Z — the cost, stated in ``Solution.notes``.  When even that gives no
point (an LMI that is singular by construction), the note names the LMI and says why it cannot be
certified at a point.
"""
from __future__ import annotations

from .backends.base import DEFAULT_MARGIN
from .solution import Solution


MARGIN_ESCALATION = (10.0, 100.0, 1000.0)
MARGIN_INFLUENCE = 1e-4
MIN_MARGIN = 1e-14


def margin_influence(model, solution: Solution) -> float | None:
    """ε·Σ tr Z_k relative to |objective| (None for a feasibility problem, or when the backend
    gives no duals)."""
    if solution.objective is None or model.instance.theorem.objective is None:
        return None
    sensitivity = model.margin_sensitivity()
    if sensitivity is None:
        return None
    return model.margin * sensitivity / max(abs(solution.objective), 1e-300)


def solve_model(model, solver: str | None = None, escalate: bool = True,
                restore_margin: bool = False, enough=None, **options) -> Solution:
    """Solve a compiled model; if the point does not satisfy the strict LMIs, re-solve with a
    larger margin.

    Margin escalation: a solver stops at its own tolerance, so with a margin below that
    tolerance the returned point may violate an LMI by a hair (largest eigenvalue ≥ 0).  The
    margin is then multiplied by 10, 100, 1000 (re-solving each time) until the certificate
    holds; the margins tried are reported in ``Solution.notes``, and ``times["solver_calls"]``
    adds up the solver time of every attempt.  ``restore_margin`` puts the model's margin back
    afterwards (a sweep re-solves the same model at the next point).  ``enough``: callable(solution)
    → whether an uncertified point needs no escalation (a certified point from elsewhere is as good).
    """
    solution = model.solve(solver, **options)
    base = model.margin
    tried = [base]
    calls = _solver_call_time(solution)
    before = model.tightened
    solution, calls = _tighten_active_nonstrict(model, solver, solution, calls, **options)
    for factor in (MARGIN_ESCALATION if escalate else ()):
        if not solution.ok or solution.lmis_hold or (enough is not None and enough(solution)):
            break
        model.set_margin(base * factor)
        tried.append(model.margin)
        solution = model.solve(solver, **options)
        calls += _solver_call_time(solution)
    if len(tried) == 1 and solution.ok and solution.lmis_hold and base == DEFAULT_MARGIN:
        solution, calls = _reduce_margin(model, solver, solution, calls, restore_margin, **options)
    elif len(tried) == 1 and solution.ok and solution.lmis_hold:
        _flag_margin_limited(model, solution)   # a margin the caller chose is honoured, never lowered
    elif solution.ok and solution.lmis_hold:
        _flag_margin_limited(model, solution)   # an escalated margin can set the optimum
    solution.times["solver_calls"] = calls
    if len(tried) > 1:
        solution.notes.append(
            "margin escalated " + " -> ".join(f"{m:g}" for m in tried)
            + (" (certificate holds)" if solution.lmis_hold else " (certificate still fails)"))
        if restore_margin:
            model.set_margin(base)
    if restore_margin and model.tightened != before:
        model.tighten(before)
    return solution


def active_nonstrict(model, solution: Solution) -> list[str]:
    """Labels of the non-strict LMIs not shown to hold at the point (largest eigenvalue ≥ 0)."""
    strict = {lmi.label: lmi.strict for lmi in model.instance.theorem.lmis}
    return sorted({r.label for r in solution.lmis if r.max_eig >= 0 and not strict.get(r.label, True)
                   and r.label not in model.tightened})


def _tighten_active_nonstrict(model, solver, solution: Solution, calls: float, **options):
    """Re-solve with the active non-strict LMIs imposed as ``N ⪯ −εI``; note the cost (the
    objective's change) or, when no point results, which LMI cannot be certified and why."""
    active = active_nonstrict(model, solution) if solution.ok else []
    if not active:
        return solution, calls
    names = ", ".join(active)
    worst = max(r.max_eig for r in solution.lmis if r.label in active)
    model.tighten(model.tightened | set(active))
    tight = model.solve(solver, **options)
    calls += _solver_call_time(tight)
    if not tight.ok:
        model.tighten(model.tightened - set(active))
        solution.notes.append(
            f"the non-strict LMI {names} is active at the optimum (largest eigenvalue {worst:.1e}, on its "
            f"boundary: no proof can show it holds there) and has no point strictly inside ({tight.status}): "
            f"it cannot be certified at a point; declare it strict (strict=True) if the theorem allows")
        return solution, calls
    cost = ""
    if solution.objective is not None and tight.objective is not None:
        change = tight.objective - solution.objective
        cost = (f"; cost: objective {solution.objective:.7g} -> {tight.objective:.7g} "
                f"({change / max(abs(solution.objective), 1e-300):+.1e} relative)")
    tight.notes.append(f"the non-strict LMI {names} is active at the optimum (largest eigenvalue "
                       f"{worst:.1e}, on its boundary): imposed with the margin {model.margin:g} "
                       f"(⪯ −εI) so that its point is strictly inside and provable{cost}")
    return tight, calls


def _reduce_margin(model, solver, solution: Solution, calls: float, restore: bool, **options):
    """Divide ε by 100 while it sets the optimum and the certificate still holds."""
    base = model.margin
    influence = margin_influence(model, solution)
    tried = [base]
    while influence is not None and influence > MARGIN_INFLUENCE and model.margin / 100 >= MIN_MARGIN:
        model.set_margin(model.margin / 100)
        tried.append(model.margin)
        smaller = model.solve(solver, **options)
        calls += _solver_call_time(smaller)
        if not (smaller.ok and smaller.lmis_hold):
            break
        solution, influence = smaller, margin_influence(model, smaller)
    if len(tried) > 1:
        solution.notes.append("margin reduced " + " -> ".join(f"{m:g}" for m in tried)
                              + " (it was setting the optimum)")
    _flag_margin_limited(model, solution, influence)
    if restore and model.margin != base:
        model.set_margin(base)
    return solution, calls


def _flag_margin_limited(model, solution: Solution, influence: float | None = None) -> None:
    """Set ``margin_limited`` (with a note) when ε·Σ tr Z_k exceeds MARGIN_INFLUENCE of the objective."""
    influence = margin_influence(model, solution) if influence is None else influence
    if influence is None:
        influence = _influence_by_difference(model, solution)
    if influence is not None and influence > MARGIN_INFLUENCE:
        solution.margin_limited = True
        solution.notes.append(f"the strictness margin still moves the optimum by {influence:.1e} "
                              "(relative): gamma is a certified bound, not the optimum")


def _influence_by_difference(model, solution: Solution) -> float | None:
    """The margin's influence without duals (a backend that gives none, e.g. PICOS): the
    objective's drop when ε is divided by 100, over |objective|, times 100/99 (the slope of a
    linear dependence on ε); None for a feasibility problem or when the second solve returns no
    point whose LMIs hold (its objective would mean nothing)."""
    if solution.objective is None or model.instance.theorem.objective is None:
        return None
    margin = model.margin
    model.set_margin(margin / 100)
    try:
        smaller = model.solve(solution.solver)
    finally:
        model.set_margin(margin)
    if not (smaller.ok and smaller.lmis_hold) or smaller.objective is None:   # only a point that holds
        return None
    return max(0.0, solution.objective - smaller.objective) / max(abs(solution.objective), 1e-300) * 100 / 99


def _solver_call_time(solution: Solution) -> float:
    return solution.times.get("solver_call", solution.times.get("solver")) or 0.0
