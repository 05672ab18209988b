"""Certification of a recovered filter by the theorem's analysis counterpart.

The synthesis theorem names an analysis theorem (``Theorem.certified_by``) in which the filter
is data.  The analysis instance takes the synthesis instance's data and parameters (per vertex
for polytopic theorems) and the recovered filter; minimising its γ² gives the level that the
paper's own analysis certifies for this filter.  For a polytopic synthesis the analysis is run
at every vertex and the worst γ is reported: a *vertex-wise* certificate (``coverage``), which does
not prove the level inside the polytope; the verdict says so and does not call it certified
(:mod:`lmidsl.certify.verdict`).

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

from ..errors import InputError
from ..numeric.instance import Instance, bind
from ..numeric.scaling import apply_scaling
from ..solver.feasibility import feasp
from ..solver.plan import Plan
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
    criterion: str = "level"      # "feasible": a stabilisation design, no level to certify
    coverage: str = "system"      # "vertex-wise": one analysis per polytope vertex (its own Lyapunov matrix)

    @property
    def passed(self) -> bool:
        """The analysis certifies the design at the synthesis γ (within the relative tolerance):
        solved, and every analysis LMI proved at its point (:mod:`lmidsl.numeric.proof`); for the
        criterion "feasible" (a stabilisation design) no level is asked."""
        if not solved(self.status) or not self.lmis or (self.gamma is None and self.criterion != "feasible"):
            return False
        if any(r["max_eig"] >= 0 or r.get("proof") != PROVED for r in self.lmis):
            return False
        if self.synthesis_gamma is None or self.gamma is None:
            return True
        return self.gamma <= self.synthesis_gamma * (1 + self.tolerance)

    def as_dict(self) -> dict:
        return {"theorem": self.theorem, "status": self.status, "gamma": self.gamma,
                "synthesis_gamma": self.synthesis_gamma, "tolerance": self.tolerance,
                "passed": self.passed, "method": self.method, "minimum": self.minimum,
                "solvers": self.solvers,
                "per_vertex": self.per_vertex, "lmis": self.lmis,
                "feasp": [r.as_dict() for r in self.feasp], "scaling": self.scaling,
                "reported": self.reported, "criterion": self.criterion, "coverage": self.coverage}


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


def certificate_criterion(link, analysis) -> str:
    """The criterion declared on the link, else the analysis theorem's own: "feasible" for a
    feasibility problem (its LMIs proved with the design fixed), "level" for a minimisation (its
    level must meet the synthesis level)."""
    if link.criterion is not None:
        return link.criterion
    return "feasible" if analysis.objective is None else "level"


def analysis_theorem_for(instance: Instance):
    """The analysis counterpart of ``instance.theorem``; for a family (:mod:`lmidsl.theorem.family`), the
    member matching the instance (its data names may depend on the family index)."""
    analysis = linked_analysis(instance.theorem)
    if hasattr(analysis, "specialise"):
        analysis = analysis.specialise({**instance.data, **instance.params})
    return analysis


def certify_by_analysis(instance: Instance, filter_matrices: dict, synthesis_gamma=None,
                        solver: str | None = None, backend: str | None = None,
                        plan: Plan | None = None) -> AnalysisCertificate:
    """Solve the analysis counterpart of ``instance.theorem`` with ``filter_matrices`` fixed, along
    the plan's road (:meth:`lmidsl.solver.plan.Plan.point_at_level`; default plan: from
    ``backend`` and ``solver``)."""
    plan = plan or Plan(backend, solver)
    link = instance.theorem.analysis
    analysis = analysis_theorem_for(instance)
    criterion = certificate_criterion(link, analysis)
    if criterion == "feasible":      # a stabilisation design: no level to meet
        synthesis_gamma = None
    vertices = range(instance.nvertices) if instance.nvertices > 1 else [None]
    gammas, statuses, lmis, methods, minima, reports, solvers, scalings, reported = [], [], [], [], [], [], [], [], []
    for v in vertices:
        sub = bind(analysis, analysis_inputs(instance, analysis, filter_matrices, v),
                   example=instance.example)
        scaled = apply_scaling(sub, "auto")
        scalings.append(scaled.as_dict())
        sol, method, minimum, used = plan.point_at_level(scaled.scaled, synthesis_gamma,
                                                         link.gamma_tolerance, objective_level)
        solvers.append(used)
        if not (sol.ok and sol.lmis_hold):
            report = feasp(scaled.scaled, backend=plan.backend, solver=plan.solver)
            reports.append(report)
            sol.feasp = report
        statuses.append(sol.feasp.verdict if sol.feasp is not None and sol.feasp.rules_out else sol.status)
        gammas.append(sol.point_gamma)
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
                               reported=reported[0] if len(reported) == 1 else {},
                               criterion=criterion,
                               coverage="vertex-wise" if len(gammas) > 1 else "system")
