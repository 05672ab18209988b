"""Certification of a recovered filter by the theorem's analysis counterpart.

The synthesis theorem names an analysis theorem (``Theorem.certified_by``) in which the filter
is data.  The analysis instance takes the synthesis instance's data and parameters (per vertex
for polytopic theorems) and the recovered filter; minimising its γ² gives the level that the
paper's own analysis certifies for this filter.  For a polytopic synthesis the analysis is run
at every vertex and the worst γ is reported (a vertex-wise certificate).

The minimum sits on the boundary of the strict set, where a solver's point may miss the strict
LMIs by its tolerance.  When it does, the analysis is solved again as a feasibility problem at a
level (the synthesis γ, else the minimum plus the tolerance): a point inside the strict set at
that level is the certificate (``method`` "level").  When the default solver fails numerically,
the fallback routes (:func:`lmidsl.solver.backends.fallback_routes`: other solvers, other
backends) are tried (the certificate is numpy's, whichever route found the point).  An analysis without a certified point carries the feasp diagnosis
(:mod:`lmidsl.solver.feasibility`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..errors import InputError, LmidslError
from ..numeric.instance import Instance, bind
from ..numeric.scaling import apply_scaling
from ..solver.backends import choose_backend, Route, fallback_routes, get_backend, is_first_order
from ..solver.fallback import better, riccati_point
from ..solver.conditioning import equilibrate
from ..solver.feasibility import feasp
from ..solver.margin import solve_model
from ..numeric.proof import PROVED
from ..solver.solution import evaluate_reported, lmi_certificate
from ..solver.status import solved
from ..solver.status import worst as worst_status
from ..theorem.registry import linked_analysis


@dataclass
class AnalysisCertificate:
    """γ certified by the analysis theorem for a fixed filter (None when infeasible)."""

    theorem: str
    status: str
    gamma: float | None
    per_vertex: list = field(default_factory=list)
    lmis: list = field(default_factory=list)
    synthesis_gamma: float | None = None
    tolerance: float = 1e-3
    method: str = "min"
    minimum: float | None = None
    feasp: list = field(default_factory=list)
    solvers: list = field(default_factory=list)
    scaling: dict | None = None   # the analysis instance's own exact signal scaling (lmidsl.numeric.scaling)
    reported: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        """The analysis certifies the design at the synthesis γ (within the relative tolerance):
        solved, and every analysis LMI proved at its point (:mod:`lmidsl.numeric.proof`)."""
        if self.gamma is None or not solved(self.status):
            return False
        if any(r["max_eig"] >= 0 or r.get("proof") != PROVED for r in self.lmis):
            return False
        if self.synthesis_gamma is None:
            return True
        return self.gamma <= self.synthesis_gamma * (1 + self.tolerance)

    def as_dict(self) -> dict:
        return {"theorem": self.theorem, "status": self.status, "gamma": self.gamma,
                "synthesis_gamma": self.synthesis_gamma, "tolerance": self.tolerance,
                "passed": self.passed, "method": self.method, "minimum": self.minimum,
                "solvers": self.solvers,
                "per_vertex": self.per_vertex, "lmis": self.lmis,
                "feasp": [r.as_dict() for r in self.feasp], "scaling": self.scaling,
                "reported": self.reported}


def analysis_inputs(instance: Instance, analysis_theorem, filter_matrices: dict,
                    vertex: int | None = None) -> dict:
    """Inputs of the analysis instance: matching data/params of ``instance`` plus the filter."""
    inputs = {}
    for name in analysis_theorem.data_decl:
        if name in filter_matrices:
            inputs[name] = np.asarray(filter_matrices[name]).tolist()
        elif name in instance.data:
            value = instance.data[name]
            inputs[name] = (value[vertex or 0] if isinstance(value, list) else value).tolist()
        else:
            raise InputError(f"{analysis_theorem.id}: no value for {name} in the synthesis instance or filter")
    for name in analysis_theorem.param_decl:
        inputs[name] = instance.params[name]
    for name in getattr(analysis_theorem, "uncertain_decl", {}):
        if name in instance.uncertain:  # the same uncertainty points as the synthesis
            inputs[name] = [np.asarray(p).tolist() for p in instance.uncertain[name]]
    return inputs


def objective_level(theorem, gamma: float) -> float | None:
    """The objective value at which the theorem's performance equals ``gamma`` (γ² for √g)."""
    if theorem.objective is None or theorem.performance is None:
        return None
    perf, obj = theorem.performance[1], theorem.objective
    if perf == sp.sqrt(obj):
        return gamma ** 2
    if perf == obj:
        return gamma
    level = sp.Symbol("level_", positive=True)
    roots = [r for r in sp.solve(sp.Eq(perf.xreplace({obj: level}), gamma), level) if r.is_real]
    return float(roots[0]) if roots else None


def _attempt(model, solver, synthesis_gamma, tolerance):
    """min γ, then (when its point is not strictly feasible) the level problems."""
    sol = solve_model(model, solver)
    minimum = sol.gamma if sol.ok else None
    if sol.ok and sol.certified:
        return sol, "min", minimum
    levels = []
    if synthesis_gamma is not None:
        levels.append(synthesis_gamma)
    if minimum is not None:
        levels.append(minimum * (1 + tolerance))
    theorem = model.instance.theorem
    for gamma in sorted(set(levels)):
        bound = objective_level(theorem, gamma)
        if bound is None or model.objective is None:
            break
        level_sol = model.solve(solver, problem=model.level_problem(bound))
        if level_sol.ok and level_sol.certified:
            return level_sol, "level", minimum
        if sol.status == "solver_error" and level_sol.status != "solver_error":
            sol = level_sol
    return sol, "min", minimum


def _solve_one(instance, solver, backend, synthesis_gamma, tolerance):
    """(solution, method, min γ, route used): the requested solver, else the default and the
    fallback routes (:mod:`lmidsl.solver.fallback`); each on the analysis as written and, where
    :func:`equilibrate` proposes one, conditioned — the certified answer with the lower γ is kept
    (each is a valid certificate)."""
    routes = [Route(backend, solver)] if solver is not None else \
        [Route(backend, None), *fallback_routes(backend)]
    proposal = equilibrate(instance)
    conditionings = [None] if proposal.trivial else [None, proposal]
    def certified(sol):
        return sol.ok and sol.certified

    if solver is None:          # no SDP where the Riccati equation gives the point
        riccati = riccati_point(instance, synthesis_gamma, tolerance)
        if riccati is not None and (synthesis_gamma is None or riccati.gamma <= synthesis_gamma * (1 + tolerance)):
            return riccati, "riccati", riccati.gamma, "riccati/scipy ARE"

    def enough(sol):       # certified at the synthesis level: no other route can do better
        return certified(sol) and (synthesis_gamma is None or sol.gamma is not None
                                   and sol.gamma <= synthesis_gamma * (1 + tolerance))

    result = None
    for route in routes:
        if solver is None and is_first_order(route.solver or ""):
            # SCS's 1e-4-accurate points did not certify an analysis in the papers' reproduction
            # (75 % of its time once went there), nor in the gallery: the route costs seconds
            # (a solver the user names is used, first-order or not)
            continue
        for conditioning in conditionings:
            try:
                model = get_backend(route.backend)(instance, conditioning=conditioning)
                sol, method, minimum = _attempt(model, route.solver, synthesis_gamma, tolerance)
            except LmidslError:      # a fallback backend or solver that is not installed
                break
            if result is None or better(result[0], sol) is sol:
                result = (sol, method, minimum, f"{sol.backend}/{sol.solver}")
        if enough(result[0]):
            break
    return result


def analysis_theorem_for(instance: Instance):
    """The analysis counterpart of ``instance.theorem``; for a family (:mod:`lmidsl.theorem.family`), the
    member matching the instance (its data names may depend on the family index)."""
    analysis = linked_analysis(instance.theorem)
    if hasattr(analysis, "specialise"):
        analysis = analysis.specialise({**instance.data, **instance.params})
    return analysis


def certify_by_analysis(instance: Instance, filter_matrices: dict, synthesis_gamma=None,
                        solver: str | None = None, backend: str | None = None) -> AnalysisCertificate:
    """Solve the analysis counterpart of ``instance.theorem`` with ``filter_matrices`` fixed."""
    backend = choose_backend(backend, solver)
    link = instance.theorem.analysis
    analysis = analysis_theorem_for(instance)
    vertices = range(instance.nvertices) if instance.nvertices > 1 else [None]
    gammas, statuses, lmis, methods, minima, reports, solvers, scalings, reported = [], [], [], [], [], [], [], [], []
    for v in vertices:
        sub = bind(analysis, analysis_inputs(instance, analysis, filter_matrices, v),
                   example=instance.example)
        scaled = apply_scaling(sub, "auto")
        scalings.append(scaled.as_dict())
        sol, method, minimum, used = _solve_one(scaled.scaled, solver, backend, synthesis_gamma,
                                                link.gamma_tolerance)
        solvers.append(used)
        if not (sol.ok and sol.certified):
            report = feasp(scaled.scaled, backend=backend, solver=solver)
            reports.append(report)
            if report.verdict in ("infeasible", "marginal"):
                sol.status = report.verdict
        statuses.append(sol.status)
        gammas.append(sol.gamma)
        methods.append(method)
        minima.append(minimum)
        if sol.ok:
            sol.lmis = lmi_certificate(scaled.scaled, {**scaled.scaled.data, **sol.values}, prove=True,
                                       congruence=sol.congruence)
        lmis += [dict(r.as_dict(), vertex=None if v is None else v + 1) for r in sol.lmis]
        if sol.ok and analysis.reported:
            reported.append(evaluate_reported(scaled.scaled, {**scaled.scaled.data, **sol.values}))
    status = worst_status(statuses)
    worst = max(gammas) if solved(status) and all(g is not None for g in gammas) else None
    minimum = max(minima) if all(m is not None for m in minima) else None
    return AnalysisCertificate(analysis.id, status, worst,
                               per_vertex=gammas if len(gammas) > 1 else [],
                               lmis=lmis, synthesis_gamma=synthesis_gamma,
                               tolerance=link.gamma_tolerance,
                               scaling=scalings[0] if scalings else None,
                               method="level" if "level" in methods else "min",
                               minimum=minimum, feasp=reports,
                               solvers=sorted(set(solvers)),
                               reported=reported[0] if len(reported) == 1 else {})
