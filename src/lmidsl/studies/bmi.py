"""BMI by successive LMIs: solve at a linearisation point, move the point, repeat.

A theorem whose LMI holds only at a fixed point X̄ of a bilinear term declares the data that
form the point and their update from a solved point (``Theorem.linearise(Sbar=S.I)``).  Typical
case: −S⁻¹ ⪯ −S̄ − S̄ᵀ + S̄ᵀSS̄ for every S̄, with equality at S̄ = S⁻¹.  When, as there, the
previous solution stays feasible at the updated point, the sequence of optimal γ is
non-increasing; the driver stops when γ stops improving:

    (γ_{k−1} − γ_k) ≤ rtol · γ_{k−1} + atol,   or k = max_iter,   or the LMI becomes infeasible,
    or γ_k − γ_{k−1} > rtol · γ_{k−1} + atol (a rise: an inaccurate step moved the point)

and keeps the best *certified* solution met, with the history of γ: every iterate whose LMIs hold
numerically is a candidate; after the iteration the candidates are finished (recovery, proofs,
analysis certificate: the verdict) from the lowest γ up, and the first whose verdict is certified is
the result (``best_iteration`` says which iterate it was).  An iterate lower than it that the
verdict does not certify is reported, not returned.  Each step is solved as ``solve`` solves one LMI problem: as
written and equilibrated (:meth:`~lmidsl.solver.plan.Plan.solve`), with margin
escalation; the linearisation point can spread the coefficients over 2⁵⁰, where the problem as
written ends in the solver's "insufficient progress".  ``starts`` runs the iteration from
several initial points (the paper's "choose several suitable S̄, P̄3") and keeps the best.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from ..numeric.instance import Instance
from ..numeric.evaluate import NumericEvaluator
from ..certify.verdict import judge
from ..pipeline import finish_solution
from ..solver.plan import Plan


@dataclass
class Step:
    iteration: int
    status: str
    gamma: float | None
    worst_eig: float | None
    seconds: float
    start: int = 0

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class BMIResult:
    """Best solution met, the history of every solve, and why the iteration stopped."""

    best: object | None
    history: list[Step] = field(default_factory=list)
    stop_reason: str = ""
    point: dict = field(default_factory=dict)   # the linearisation point of the best solve
    best_start: int | None = None
    best_iteration: int | None = None            # which iterate (of its start) the best is
    rejected: list = field(default_factory=list)  # (start, iteration, γ, why) of lower, uncertified iterates

    @property
    def gammas(self) -> list:
        return [s.gamma for s in self.history]

    @property
    def gamma(self):
        return None if self.best is None else self.best.gamma

    def as_dict(self) -> dict:
        return {"gamma": self.gamma, "stop_reason": self.stop_reason, "best_start": self.best_start,
                "best_iteration": self.best_iteration,
                "rejected": [{"start": s, "iteration": k, "gamma": g, "why": why} for s, k, g, why in self.rejected],
                "history": [s.as_dict() for s in self.history]}


def with_data(instance: Instance, values: dict) -> Instance:
    """The instance with some data matrices replaced (same shapes)."""
    data = dict(instance.data)
    for name, value in values.items():
        if name not in data:
            raise InputError(f"{instance.theorem.id}: unknown data {name}")
        value = np.atleast_2d(np.asarray(value, dtype=float))
        if value.shape != np.shape(data[name]):
            raise InputError(f"{instance.theorem.id}: data {name} must stay {np.shape(data[name])}, got {value.shape}")
        data[name] = value
    return replace(instance, data=data)


def next_point(instance: Instance, values: dict) -> dict:
    """The linearisation point given by the theorem's update formulas at a solved point."""
    point = dict(instance.data)
    point.update(values)
    ev = NumericEvaluator(instance.dims, point, instance.params)
    out = {}
    for name, expr in instance.theorem.linearisation.items():
        M = np.atleast_2d(ev.visit(expr))
        out[name] = (M + M.T) / 2 if getattr(instance.theorem.data_decl[name].symbol, "is_symmetric", False) else M
    return out


def successive_lmi(instance: Instance, *, starts: list[dict] | None = None, max_iter: int = 30,
                   rtol: float = 1e-4, atol: float = 0.0, solver: str | None = None,
                   backend: str | None = None, margin: float | None = None, progress=None,
                   desc: str | None = None, certify: bool = True) -> BMIResult:
    """Iterate the theorem's LMI over its linearisation point; return the best solution.

    ``starts``: initial points (dicts of the linearisation data); default: the instance's data.
    The best solution gets the theorem's recovery and analysis certificate (``certify``).
    ``progress``: called with a line per solve (e.g. :class:`lmidsl.render.progress.Stages`).
    """
    plan = Plan(backend, solver, {}, margin)

    theorem = instance.theorem
    if not theorem.linearisation:
        raise InputError(f"{theorem.id}: declares no linearisation point (Theorem.linearise)")
    starts = starts or [{}]
    result = BMIResult(None)
    candidates = []                 # (γ, start, iteration, solution, linearisation point)
    for s, start in enumerate(starts):
        current = with_data(instance, start)
        previous = None
        reason = f"max_iter = {max_iter}"
        for k in range(max_iter):
            t0 = time.perf_counter()
            # each step solved as `solve` solves: as written and conditioned, margin escalation
            sol, _ = plan.solve(current)
            result.history.append(Step(k, sol.status if sol.lmis_hold or not sol.ok else "LMIs violated",
                                       sol.point_gamma, sol.worst_eig, time.perf_counter() - t0, s))
            if progress:
                progress(f"{desc or theorem.id}: start {s}, iteration {k + 1}/{max_iter}, "
                         + (f"gamma {sol.point_gamma:.6g}" if sol.point_gamma else sol.status))
            if not sol.ok or sol.point_gamma is None:
                reason = f"{sol.status} at iteration {k}"
                break
            # only a point that satisfies every LMI (numpy eigenvalues) may become the best;
            # an uncertified point still gives a valid next linearisation point
            if sol.lmis_hold:
                candidates.append((sol.point_gamma, s, k, sol,
                                   {n: np.asarray(current.data[n]) for n in theorem.linearisation}))
            if previous is not None and sol.point_gamma - previous > rtol * previous + atol:
                # exact solves never rise (the previous solution stays feasible): an
                # inaccurate step moved the point; going on would follow the error
                reason = (f"gamma rose at iteration {k} ({previous:.6g} -> {sol.point_gamma:.6g}): the "
                          f"solver's accuracy is reached")
                break
            if previous is not None and previous - sol.point_gamma <= rtol * previous + atol:
                reason = f"converged at iteration {k} (improvement below rtol = {rtol:g})"
                break
            previous = sol.point_gamma
            current = with_data(current, next_point(current, sol.values))
        result.stop_reason += ("; " if result.stop_reason else "") + f"start {s}: {reason}"
    for gamma, s, k, sol, point in sorted(candidates, key=lambda c: (c[0], c[1], c[2])):
        judge(finish_solution(sol, plan=plan, certify=certify))
        result.best, result.best_start, result.best_iteration, result.point = sol, s, k, point
        if sol.verdict.certified or not certify:
            break
        result.rejected.append((s, k, gamma, sol.verdict.reasons[0] if sol.verdict.reasons else sol.verdict.word))
    else:
        if candidates:           # none certified: the lowest, with its verdict saying why
            gamma, s, k, sol, point = min(candidates, key=lambda c: (c[0], c[1], c[2]))
            result.best, result.best_start, result.best_iteration, result.point = sol, s, k, point
    return result
