"""Quasi-convex problems by bisection on a scalar parameter (LMI Lab's ``gevp``, YALMIP's
``bisection``): e.g. the decay rate, max α s.t. AᵀP + PA + 2αP ≺ 0, P ≻ 0, where α multiplies
the decision variable P and the problem is not an SDP in (α, P) jointly.

A theorem declares the parameter with :meth:`~lmidsl.theorem.theorem.Theorem.bisect`.  The
theorem is compiled once with the parameter as a backend parameter (cvxpy: DPP, so every step
re-uses the compiled problem) and re-solved at each midpoint.  Feasibility at a step is decided
by THE certificate (:func:`lmidsl.solver.solution.lmi_certificate` at the returned point, with
the margin escalation of :mod:`lmidsl.solver.margin`), not by the solver's status.  The set of
feasible values is assumed to be an interval with one end at ``lower`` (``goal="max"``) or at
``upper`` (``goal="min"``) — true for a GEVP (feasibility at λ implies it at every λ' on the
feasible side).  The result is the bracket [feasible end, infeasible end] of width ≤ tol and
the certified (and ball-arithmetic proved, :mod:`lmidsl.numeric.proof`) point at the feasible end.

:func:`grid` evaluates the same certificate on a grid of values, for comparison.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

from ..errors import InputError
from ..numeric.instance import Instance
from ..pipeline import finish_solution
from ..solver.backends import get_backend
from ..certify.infeasibility import prove_infeasible
from ..solver.plan import Plan
from ..solver.solution import Solution
from ..certify.verdict import Verdict, judge, judge_bisection
from ..theorem.values import Bisection


@dataclass
class BisectionResult:
    theorem: str
    example: str | None
    parameter: str
    goal: str
    lower: float
    upper: float
    tol: float
    feasible_end: float | None = None        # the best certified value found
    infeasible_end: float | None = None      # the nearest value found without a certified point
    steps: list = field(default_factory=list)   # {value, feasible, status, worst_eig}
    solution: Solution | None = None        # certified (and proved) point at the feasible end
    message: str = ""
    infeasible_end_proof: object = None      # lmidsl.certify.infeasibility.InfeasibilityCertificate
    compile_time: float = 0.0
    total_time: float = 0.0

    @property
    def interval(self) -> tuple:
        ends = (self.feasible_end, self.infeasible_end)
        return tuple(sorted(e for e in ends if e is not None))

    @property
    def holds(self) -> bool:
        """A certified, proved point at the feasible end."""
        return self.verdict.certified

    @property
    def feasible_end_proved(self) -> bool:
        return self.holds

    @property
    def infeasible_end_proved(self) -> bool:
        return bool(self.infeasible_end_proof is not None and self.infeasible_end_proof.proved)

    @property
    def verdict(self) -> Verdict:
        """The verdict record, by the judge (:func:`lmidsl.certify.verdict.judge_bisection`)."""
        return judge_bisection(self)

    def as_dict(self) -> dict:
        return {"theorem": self.theorem, "example": self.example, "parameter": self.parameter,
                "goal": self.goal, "lower": self.lower, "upper": self.upper, "tol": self.tol,
                "feasible_end": self.feasible_end, "infeasible_end": self.infeasible_end,
                "interval": list(self.interval), "steps": self.steps, "message": self.message,
                "holds": self.holds, "feasible_end_proved": self.feasible_end_proved,
                "infeasible_end_proved": self.infeasible_end_proved,
                "infeasible_end_proof": None if self.infeasible_end_proof is None else self.infeasible_end_proof.as_dict(),
                "verdict": self.verdict.as_dict(), "gamma": self.verdict.gamma,
                "compile_time": self.compile_time, "total_time": self.total_time,
                "solution": None if self.solution is None else self.solution.as_dict()}


class _Stepper:
    """One compiled model, re-solved at parameter values along the plan's road; the certificate
    decides."""

    def __init__(self, instance: Instance, parameter: str, plan: Plan):
        t0 = time.perf_counter()
        self.instance = instance
        self.parameter = parameter
        self.plan = plan
        self.model = get_backend(plan.backend)(instance, margin=plan.margin, reuse=True)
        self.compile_time = time.perf_counter() - t0
        self.steps: list = []

    def solve_at(self, value: float) -> Solution:
        """The plan's answer at ``value`` (:meth:`lmidsl.solver.plan.Plan.solve`; the compiled
        model is updated for the first route).  A solver's failure is not a verdict: without a
        named solver the fallback routes are tried before "no" (a bisection that takes a failure
        for infeasibility brackets the wrong value)."""
        instance = self.instance.with_params(**{self.parameter: float(value)})
        solution, _ = self.plan.solve(instance, model=self.model)
        return solution

    def feasible(self, value: float) -> bool:
        """A certified point at ``value``?"""
        solution = self.solve_at(value)
        ok = bool(solution.ok and solution.lmis_hold)
        self.steps.append({"value": float(value), "feasible": ok, "status": solution.status,
                           "solver": solution.solver, "worst_eig": solution.worst_eig})
        return ok


def _spec(theorem, lower, upper, tol, goal, parameter=None) -> Bisection:
    spec = theorem.bisection
    if parameter is not None:            # any scalar parameter, given here rather than declared
        if parameter not in theorem.param_decl:
            raise InputError(f"{theorem.id}: {parameter} is not a parameter of the theorem")
        if lower is None or upper is None:
            raise InputError(f"{theorem.id}: bisection on {parameter} needs lower and upper")
        spec = Bisection(parameter, lower, upper, tol or 1e-4, goal or "max")
    if spec is None:
        raise InputError(f"{theorem.id} declares no bisection parameter (Theorem.bisect)")
    spec = replace(spec, **{k: v for k, v in {"lower": lower, "upper": upper, "tol": tol,
                                              "goal": goal}.items() if v is not None})
    if not (spec.lower < spec.upper and spec.tol > 0):
        raise InputError(f"{theorem.id}: bisection needs lower < upper and tol > 0 "
                         f"(got [{spec.lower}, {spec.upper}], tol {spec.tol})")
    return spec


def bisect(instance: Instance, *, lower: float | None = None, upper: float | None = None,
           tol: float | None = None, goal: str | None = None, parameter: str | None = None,
           solver: str | None = None, backend: str | None = None, margin: float | None = None,
           **options) -> BisectionResult:
    """Bisect the theorem's declared parameter (or ``parameter``) on ``instance`` (see the
    module docstring); ``lower``, ``upper``, ``tol``, ``goal`` override the declaration."""
    plan = Plan(backend, solver, options, margin, infeasible_ends=True)
    t0 = time.perf_counter()
    theorem = instance.theorem
    spec = _spec(theorem, lower, upper, tol, goal, parameter)
    stepper = _Stepper(instance, spec.parameter, plan)
    result = BisectionResult(theorem.id, instance.example, spec.parameter, spec.goal, spec.lower,
                             spec.upper, spec.tol, compile_time=stepper.compile_time)
    # feasible side: small values for "max", large values for "min"
    good, bad = (spec.lower, spec.upper) if spec.goal == "max" else (spec.upper, spec.lower)
    if not stepper.feasible(good):
        result.infeasible_end = good
        result.message = f"no certified point at {spec.parameter} = {good:g}: infeasible on the whole interval"
    elif stepper.feasible(bad):
        result.feasible_end = bad
        result.message = (f"certified at {spec.parameter} = {bad:g}, the end of the interval: "
                          f"the threshold lies beyond it (widen the interval)")
    else:
        while abs(bad - good) > spec.tol:
            mid = 0.5 * (good + bad)
            if stepper.feasible(mid):
                good = mid
            else:
                bad = mid
        result.feasible_end, result.infeasible_end = good, bad
    result.steps = stepper.steps
    contradictions = [st["value"] for st in stepper.steps if st["feasible"] and result.infeasible_end is not None
                      and (st["value"] - result.infeasible_end) * (1 if spec.goal == "max" else -1) >= 0]
    if contradictions:
        result.message += (f" feasibility is not monotone in the steps (certified at {contradictions} beyond "
                           f"the infeasible end): the bracket is not trustworthy")
    if result.feasible_end is not None:
        solution = stepper.solve_at(result.feasible_end)
        solution.notes.append(f"bisection on {spec.parameter}: {len(stepper.steps)} solves of one compiled "
                              f"model; certificate at the feasible end {result.feasible_end:.10g}")
        result.solution = judge(finish_solution(solution, plan=plan, certify=True, diagnose=False))
    if result.infeasible_end is not None:       # the other end of the bracket, proved where possible
        stepper.solve_at(result.infeasible_end)
        result.infeasible_end_proof = prove_infeasible(stepper.model)
    result.total_time = time.perf_counter() - t0
    return result


def grid(instance: Instance, values, *, parameter: str | None = None, solver: str | None = None,
         backend: str | None = None, margin: float | None = None, **options) -> list[dict]:
    """The certificate at each value of the declared bisection parameter (or ``parameter``),
    compiled once."""
    spec = instance.theorem.bisection
    if parameter is None and spec is None:
        raise InputError(f"{instance.theorem.id} declares no bisection parameter (Theorem.bisect)")
    plan = Plan(backend, solver, options, margin, infeasible_ends=True)
    stepper = _Stepper(instance, parameter or spec.parameter, plan)
    for v in values:
        stepper.feasible(float(v))
    return stepper.steps


def grid_threshold(steps: list[dict], goal: str = "max") -> float | None:
    """The best feasible value of a grid (largest for "max", smallest for "min")."""
    feasible = [s["value"] for s in steps if s["feasible"]]
    if not feasible:
        return None
    return max(feasible) if goal == "max" else min(feasible)


__all__ = ["BisectionResult", "bisect", "grid", "grid_threshold"]
