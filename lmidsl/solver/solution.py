"""The result of a solve, and the backend-independent certificate.

After any backend returns a point, every LMI is re-evaluated with numpy at that point
(:func:`lmi_certificate`): its largest eigenvalue in the form ``N ≺ 0`` is the number a user
trusts, whatever status the solver printed.  A point certifies the strict LMIs when every such
eigenvalue is negative.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..numeric.design import Design
from ..numeric.instance import Instance
from ..numeric.evaluate import NumericEvaluator, evaluate_block_matrix, max_eigenvalue
from ..symbolic.uncertainty import scenarios, spec_at


def with_location(d: dict, vertex: int | None, point: str) -> dict:
    """Add where an LMI instance is imposed (polytope vertex, uncertainty point) to its dict."""
    if vertex is not None:
        d["vertex"] = vertex
    if point:
        d["point"] = point
    return d


@dataclass
class LMIReport:
    label: str
    max_eig: float
    size: int
    vertex: int | None = None
    point: str = ""  # values of uncertain symbols, e.g. "Delta=+1*beta"

    def as_dict(self) -> dict:
        return with_location({"label": self.label, "max_eig": self.max_eig, "size": self.size},
                             self.vertex, self.point)


@dataclass
class Solution:
    """What a solve returns: status, objective, γ, per-LMI eigenvalues, values, recovery."""

    theorem: str
    example: str | None
    backend: str
    solver: str
    status: str
    objective: float | None = None
    gamma: float | None = None
    lmis: list[LMIReport] = field(default_factory=list)
    values: dict = field(default_factory=dict)
    design: Design | None = None    # the recovered filter/controller (original coordinates)
    times: dict = field(default_factory=dict)
    margin: float = 0.0
    message: str = ""
    params: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    instance: Instance | None = None
    solver_status: str | None = None
    feasp: object | None = None
    scaling: object = None          # lmidsl.numeric.scaling.AppliedScaling (instance is the scaled one)
    backoff: dict | None = None     # lmidsl.solver.backoff record when the point is a back-off point
    reported: dict = field(default_factory=dict)
    checks: list = field(default_factory=list)

    @property
    def recovered(self):
        """The recovered matrices by name (the :class:`Design`; empty when nothing was recovered)."""
        return self.design if self.design is not None else {}

    @property
    def inverted(self) -> list:
        """Condition numbers of the matrices the recovery inverted."""
        return list(self.design.inverted) if self.design is not None else []

    @property
    def ok(self) -> bool:
        return self.status in ("optimal", "optimal_inaccurate")

    @property
    def certified(self) -> bool:
        """True when the returned point satisfies every strict LMI (all max_eig < 0)."""
        return bool(self.lmis) and all(r.max_eig < 0 for r in self.lmis)

    @property
    def worst_eig(self) -> float | None:
        return max((r.max_eig for r in self.lmis), default=None)

    def as_dict(self) -> dict:
        def listify(v):
            if isinstance(v, list):
                return [listify(x) for x in v]
            return np.asarray(v).tolist()

        return {
            "theorem": self.theorem,
            "example": self.example,
            "backend": self.backend,
            "solver": self.solver,
            "status": self.status,
            "solver_status": self.solver_status or self.status,
            "message": self.message,
            "objective": self.objective,
            "gamma": self.gamma,
            "params": self.params,
            "margin": self.margin,
            "certified": self.certified,
            "lmis": [r.as_dict() for r in self.lmis],
            "recovered": {k: listify(v) for k, v in self.recovered.items()},
            "inverted": self.inverted,
            "design": self.design.as_dict() if self.design is not None else None,
            "values": {k: listify(v) for k, v in self.values.items()},
            "times": self.times,
            "feasp": self.feasp.as_dict() if self.feasp is not None else None,
            "notes": self.notes,
            "scaling": self.scaling.as_dict() if self.scaling is not None else None,
            "backoff": self.backoff,
            "reported": self.reported,
            "checks": [c.as_dict() for c in self.checks],
        }


def lmi_certificate(instance: Instance, values: dict) -> list[LMIReport]:
    """Largest eigenvalue of every LMI (form N ≺ 0) at the given point, evaluated in numpy."""
    reports = []
    for lmi in instance.theorem.lmis:
        negative = lmi.negative_form()
        for sc in scenarios(instance, lmi):
            v = sc.vertex
            ev = NumericEvaluator(instance.dims, values, instance.params, vertex=v)
            M = evaluate_block_matrix(ev, spec_at(negative, sc))
            reports.append(LMIReport(lmi.label, max_eigenvalue(M), M.shape[0],
                                     None if v is None else v + 1, sc.label))
    return reports


def evaluate_performance(instance: Instance, values: dict):
    """The theorem's performance figure (e.g. γ = √g) at a point, or None."""
    perf = instance.theorem.performance
    if perf is None:
        return None
    ev = NumericEvaluator(instance.dims, values, instance.params)
    value = complex(np.asarray(ev.visit(perf[1])).reshape(()))
    if value.imag != 0 or not np.isfinite(value.real):
        return None  # e.g. γ = √g with g < 0 at the solver's point: no real level to report
    return value.real


def evaluate_reported(instance: Instance, values: dict) -> dict:
    """The theorem's reported values (``Theorem.report``) at a point."""
    ev = NumericEvaluator(instance.dims, values, instance.params)
    return {name: float(ev.visit(expr)) for name, expr in instance.theorem.reported.items()}
