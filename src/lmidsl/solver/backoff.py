"""Back-off: give up a hair of γ for a recovery that is well conditioned.

At the exact optimum of a synthesis LMI the matrices that the recovery inverts can be nearly
singular (seed 001: Z and X − Z have eigenvalues ~1e-6 next to ~1e-1, because the plant has
states that influence nothing, so the optimum is approached only on the boundary).  A filter
recovered there is numerically wild although it is "optimal".  A theorem declares the
positive definite expressions its recovery inverts (``Theorem.well_conditioned(Z, X − Z)``);
for a relative back-off δ > 0 and the optimum β* of the objective, this module solves

    min κ   s.t.  the theorem's LMIs,   objective ≤ β* + δ|β*|,   t I ⪯ E_i ⪯ κ I  (all i)

for fixed t > 0, and chooses t by golden-section search on log t to minimise κ(t)/t, which
bounds cond(E_i) for every i.  κ(t) is convex and nondecreasing in t, so κ(t)/t is
quasi-convex and the search finds its minimum over t ∈ [10⁻⁶ t_max, t_max], where t_max is the
largest t feasible at all.  On a backend with mutable parameters (cvxpy) t is one, and each step
re-solves without recompiling; elsewhere (direct, PICOS) each step assembles the problem again.
For the objective γ² (β), δ on β means about δ/2 on γ.  Default δ = 10⁻² (≈ 0.5 % on γ): with
10⁻³ the slab objective ≤ (1 + δ)β* is so thin that CVXOPT fails on every conditioning solve
for seed 001 and Clarabel reports "inaccurate"; if every solve fails, the optimum is returned
with the failure recorded.

The record reports the condition numbers of every E_i before (at the optimum) and after, and
the solves it took.  The verdict states what the back-off costs: the delivered design's certified
level against the SDP optimum's level (:func:`backoff_cost`).

:func:`level_solution` is the other method: the *level problem* "every LMI, objective ≤ β* + δ|β*|"
with no objective of its own, in one solve along the default and the fallback routes
(:mod:`lmidsl.solver.fallback`).  An interior-point solver returns a central point of that slab,
away from the boundary where the recovery's matrices are singular; it does not minimise the
condition numbers, only moves off the boundary.  Measured on ``textbook.hinf_of_ct`` plant-6
(γ* = 794.055 by hinfsyn, I − XY singular at the optimum): the search fails with Clarabel; the
level problem at δ = 10⁻³ through PICOS/CVXOPT gives γ = 794.82 and a controller whose closed
loop has norm 794.50 (python-control).  Which method runs first is decided by
:func:`lmidsl.pipeline.backed_off`: the level problem for the automatic back-off (one solve
instead of about fifteen), the search for a δ the user gives; the other when the first gives no
certified point.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..errors import InputError, LmidslError
from ..numeric.evaluate import NumericEvaluator, eigenvalues
from .status import SOLVER_ERROR, solved

GOLDEN = (math.sqrt(5) - 1) / 2


def condition_numbers(instance, values: dict) -> dict:
    """cond(E_i) (2-norm) of the theorem's well-conditioned expressions at a point."""
    point = dict(instance.data)
    point.update(values)
    ev = NumericEvaluator(instance.dims, point, instance.params)
    out = {}
    for expr in instance.theorem.conditioned:
        eig = eigenvalues(ev.visit(expr))
        out[str(expr)] = {"cond": float(eig[-1] / eig[0]) if eig[0] > 0 else float("inf"),
                          "min_eig": float(eig[0]), "max_eig": float(eig[-1])}
    return out


DEFAULT_DELTA = 1e-2

AUTO_DELTAS = (1e-3, 3e-3, 1e-2, 3e-2, 1e-1)
"""The automatic back-off's ladder: the smallest δ whose point gives a design certified by its
analysis is kept (a back-off buys a well-conditioned recovery and no more).  Each rung is the level
problem (one solve per route); the condition-minimising search (about fifteen solves) runs only at
the rungs of :data:`SEARCHED`, where the slab is thick enough for it (at 10⁻³ CVXOPT fails on every
conditioning solve of seed 001).  The 10⁻² → 10⁻¹ ladder it replaces delivered designs 2.9–12.8 %
above the optimum on published plants where 10⁻³ certifies."""

SEARCHED = frozenset({DEFAULT_DELTA, 1e-1})


def backoff_solution(model, solution, delta: float, solver=None, iterations: int = 12,
                     decades: float = 6.0, **options):
    """A new :class:`~lmidsl.solver.solution.Solution` at the back-off point (see module docstring).

    Written on the backend hooks (variables, ``lmi_constraint``, ``make_problem``), so it runs on
    any backend; t is a backend parameter where the backend has mutable ones (cvxpy: one compile,
    every step re-solves), else each step assembles the problem again (direct: milliseconds)."""
    instance = model.instance
    theorem = instance.theorem
    if not theorem.conditioned:
        raise InputError(f"{theorem.id}: declares no well_conditioned expressions; back-off has nothing to improve")
    if theorem.objective is None or solution.objective is None:
        raise InputError(f"{theorem.id}: back-off needs an optimal objective value")
    if not delta > 0:
        raise InputError(f"--backoff must be a positive relative margin, got {delta}")
    compiler = model.compiler_class(model, None)
    objective = compiler.visit(theorem.objective)
    blocks = []
    for expr in theorem.conditioned:
        size = int(sp.sympify(expr.shape[0]).xreplace(instance.dims))
        blocks.append((compiler.visit(expr), np.eye(size), size))
    beta_opt = float(solution.objective)
    bound = beta_opt + delta * abs(beta_opt)
    base = [c for _, c in model.constraints] + [objective <= bound]
    name = model.solver_name(solver)

    t_var = model.new_scalar("t_backoff", False)
    # max t s.t. E ⪰ t I: t I − E ⪯ 0; the backend's own call: a solver's crash is a status
    status, _, message, _ = model.run_solver(name, problem=model.make_problem(
        -t_var, base + [model.lmi_constraint(t_var * Id - E, n, None) for E, Id, n in blocks]), **options)
    if status == SOLVER_ERROR:
        solution.backoff = {"delta": delta, "failed": f"{name} failed on the first conditioning solve "
                            f"({message}); try another solver or a larger δ", "solves": 1}
        return solution
    solves = 1
    t_value = model.value_of(t_var) if solved(status) else None
    if t_value is None or not t_value > 0:
        raise LmidslError(f"{theorem.id}: back-off: no point with objective ≤ {bound:.6g} and positive "
                          f"definite {', '.join(map(str, theorem.conditioned))}")
    t_max = float(t_value)

    kappa = model.new_scalar("kappa_backoff", False)
    upper = [model.lmi_constraint(E - kappa * Id, n, None) for E, Id, n in blocks]    # E ⪯ κ I

    def conditioning_problem(t):
        """min κ s.t. the LMIs, objective ≤ bound, t I ⪯ E ⪯ κ I."""
        return model.make_problem(kappa, base + [model.lmi_constraint(t * Id - E, n, None)
                                                 for E, Id, n in blocks] + upper)

    if model.mutable_parameters:
        t_param = model.new_parameter("t_backoff_level", t_max)
        fixed = conditioning_problem(t_param)

        def problem_at(t):
            model.set_parameter(t_param, t)
            return fixed
    else:
        problem_at = conditioning_problem

    def ratio(u):
        nonlocal solves
        t = math.exp(u)
        status, *_ = model.run_solver(name, problem=problem_at(t), **options)
        if status == SOLVER_ERROR:
            return math.inf
        solves += 1
        value = model.value_of(kappa) if solved(status) else None
        return math.inf if value is None else float(value) / t

    lo, hi = math.log(t_max) - decades * math.log(10), math.log(t_max * (1 - 1e-3))
    a, b = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    fa, fb = ratio(a), ratio(b)
    for _ in range(iterations):
        if fa <= fb:
            hi, b, fb = b, a, fa
            a = hi - GOLDEN * (hi - lo)
            fa = ratio(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + GOLDEN * (hi - lo)
            fb = ratio(b)
    best = a if fa <= fb else b
    if not math.isfinite(min(fa, fb)):
        solution.backoff = {"delta": delta, "failed": f"every conditioning solve failed with {name} "
                            f"(objective ≤ {bound:.6g}); try a larger δ", "solves": solves}
        return solution
    t_best = math.exp(best)
    saved = model.problem
    model.problem = problem_at(t_best)
    try:
        new = model.solve(solver, **options)
    finally:
        model.problem = saved
    solves += 1
    value = model.expression_value(objective) if new.ok else None
    new.objective = None if value is None else float(np.asarray(value).reshape(-1)[0])
    new.times["solve"] = new.times.get("solve", 0.0)
    before = condition_numbers(instance, solution.values)
    after = condition_numbers(instance, new.values) if new.ok else {}
    k_value = model.value_of(kappa) if new.ok else None
    new.backoff = {
        "delta": delta, "objective_opt": beta_opt, "objective_bound": bound,
        "objective": new.objective, "gamma_opt": solution.point_gamma, "gamma": new.point_gamma,
        "status_opt": solution.status,
        "t": t_best, "t_max": t_max, "kappa": float(k_value) if k_value is not None else None,
        "cond_before": before, "cond_after": after, "solves": solves,
        "optimum_lmis": [r.as_dict() for r in solution.lmis],
        "objective_bounds_opt": solution.objective_bounds,
    }
    new.scaling = solution.scaling
    return new


def backoff_cost(record: dict | None, delivered) -> str:
    """The back-off's cost in words: the delivered level against the SDP optimum's level (empty
    without a back-off point or a level)."""
    record = record or {}
    optimum = record.get("gamma_opt")
    if "gamma" not in record or optimum is None or delivered is None or not optimum:
        return ""
    cost = delivered / optimum - 1
    return (f"the back-off (δ = {record.get('delta', 0):g}) costs {100 * cost:.3g} % over the SDP optimum "
            f"{optimum:.8g}")


def level_solution(model, optimum, delta: float, plan):
    """The first certified point of the level problem at objective ≤ β* + δ|β*| along the plan's
    routes (:meth:`lmidsl.solver.plan.Plan.level`); None when no route certifies one.  See the
    module docstring."""
    if optimum.objective is None or model.objective is None:
        return None
    beta_opt = float(optimum.objective)
    bound = beta_opt + delta * abs(beta_opt)
    new, level_model, tried = plan.level(model, bound)
    if new is None:
        return None
    value = level_model.expression_value(level_model.objective)
    new.objective = None if value is None else float(np.asarray(value).reshape(-1)[0])
    new.backoff = {
        "delta": delta, "method": "level problem", "objective_opt": beta_opt,
        "objective_bound": bound, "objective": new.objective, "gamma_opt": optimum.point_gamma,
        "status_opt": optimum.status,
        "gamma": new.point_gamma, "cond_before": condition_numbers(model.instance, optimum.values),
        "cond_after": condition_numbers(model.instance, new.values), "solves": len(tried),
        "tried": tried, "optimum_lmis": [r.as_dict() for r in optimum.lmis],
        "objective_bounds_opt": optimum.objective_bounds}
    new.scaling = optimum.scaling
    return new
