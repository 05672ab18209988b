"""Certification of a recovered filter by the theorem's analysis counterpart.

The synthesis theorem names an analysis theorem (``Theorem.certified_by``) in which the filter
is data.  The analysis instance takes the synthesis instance's data and parameters (per vertex
for polytopic theorems) and the recovered filter; minimising its γ² gives the level that the
paper's own analysis certifies for this filter.  For a polytopic synthesis the analysis is run
at every vertex and the worst γ is reported (a vertex-wise certificate).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..instance import Instance, bind
from ..scaling import apply_scaling
from ..solution import evaluate_reported


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
    scaling: dict | None = None   # the analysis instance's own exact signal scaling (lmidsl.scaling)
    reported: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        """The analysis certifies the filter at the synthesis γ (within the relative tolerance)."""
        if self.gamma is None or self.status not in ("optimal", "optimal_inaccurate"):
            return False
        if any(r["max_eig"] >= 0 for r in self.lmis):
            return False
        if self.synthesis_gamma is None:
            return True
        return self.gamma <= self.synthesis_gamma * (1 + self.tolerance)

    def as_dict(self) -> dict:
        return {"theorem": self.theorem, "status": self.status, "gamma": self.gamma,
                "synthesis_gamma": self.synthesis_gamma, "tolerance": self.tolerance,
                "passed": self.passed, "per_vertex": self.per_vertex, "lmis": self.lmis,
                "scaling": self.scaling, "reported": self.reported}


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


def analysis_theorem_for(instance: Instance):
    """The analysis counterpart of ``instance.theorem``; for a family (:mod:`lmidsl.family`), the
    member matching the instance (its data names may depend on the family index)."""
    from ..registry import get_theorem

    analysis = get_theorem(instance.theorem.analysis.theorem)
    if hasattr(analysis, "specialise"):
        analysis = analysis.specialise({**instance.data, **instance.params})
    return analysis


def certify_by_analysis(instance: Instance, filter_matrices: dict, synthesis_gamma=None,
                        solver: str | None = None, backend: str = "cvxpy") -> AnalysisCertificate:
    """Solve the analysis counterpart of ``instance.theorem`` with ``filter_matrices`` fixed."""
    from ..api import solve_model
    from ..backends import get_backend

    link = instance.theorem.analysis
    analysis = analysis_theorem_for(instance)
    vertices = range(instance.nvertices) if instance.nvertices > 1 else [None]
    gammas, statuses, lmis, scalings, reported = [], [], [], [], []
    for v in vertices:
        sub = bind(analysis, analysis_inputs(instance, analysis, filter_matrices, v),
                   example=instance.example)
        scaled = apply_scaling(sub, "auto")
        scalings.append(scaled.as_dict())
        sol = solve_model(get_backend(backend)(scaled.scaled), solver)
        statuses.append(sol.status)
        gammas.append(sol.gamma)
        lmis += [dict(r.as_dict(), vertex=None if v is None else v + 1) for r in sol.lmis]
        if sol.ok and analysis.reported:
            reported.append(evaluate_reported(scaled.scaled, {**scaled.scaled.data, **sol.values}))
    ok = all(s in ("optimal", "optimal_inaccurate") for s in statuses)
    worst = max(gammas) if ok and all(g is not None for g in gammas) else None
    if ok:
        status = "optimal" if all(s == "optimal" for s in statuses) else "optimal_inaccurate"
    else:
        status = next(s for s in statuses if s not in ("optimal", "optimal_inaccurate"))
    return AnalysisCertificate(analysis.id, status, worst,
                               per_vertex=gammas if len(gammas) > 1 else [],
                               lmis=lmis, synthesis_gamma=synthesis_gamma,
                               tolerance=link.gamma_tolerance, scaling=scalings[0] if scalings else None,
                               reported=reported[0] if len(reported) == 1 else {})
