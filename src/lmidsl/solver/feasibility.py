"""Feasibility diagnosis in the manner of LMI Lab's ``feasp``.

For the compiled LMIs ``N_k(x) ≺ 0`` of any theorem the auxiliary problem is

    t* = min t   subject to   N_k(x) ⪯ t I  for every strict LMI k,   N_j(x) ⪯ 0 for the
                              non-strict ones,   ‖x‖₂ ≤ R,

with R the feasibility radius (LMI Lab's ``options(3)``): it keeps t* finite for homogeneous
problems.  The strict LMIs are jointly feasible (within radius R) iff t* < 0; an infeasible
problem therefore comes with a number, t* ≥ 0, the amount by which the best point misses.  When
t* ≥ −margin at R, the radius is enlarged (×100, up to ``max_radius``) before concluding, since a
badly scaled feasible problem may need large variables.  Verdicts:

* "strictly feasible": t* < −margin and numpy finds every strict LMI ⪯ −margin I at the
  returned point: the compiled problem (``N ⪯ −margin I``) has a point;
* "infeasible": t* ≥ −``FEASP_TOL`` (zero up to the solver's accuracy) at a point strictly inside
  the radius: the norm bound is inactive, so t* is the minimum over all x (the problem is convex)
  and no strictly feasible point exists anywhere;
* "undecided (accuracy)": t* ≥ 0 but t* grew with the radius, which exact solves cannot do:
  the solver is inaccurate on this problem and its t* proves nothing;
* "undecided (radius)": t* ≥ −``FEASP_TOL`` but the point lies on the radius even at
  ``max_radius``: a feasible point may need larger variables (a badly scaled problem), so this
  is no proof of infeasibility;
* "marginal" otherwise: t* < 0 but by less than the margin, or a point the numpy check does not
  confirm (solve again with a smaller ``margin``, or rescale the data).

Per LMI the report gives
* ``value``   λ_max(N_k) at the feasp point (the LMIs with value ≈ t* are the binding ones);
* ``alone``   t* of LMI k by itself (≥ 0: this LMI is infeasible on its own);
* ``without`` t* of all LMIs but k (< −margin: dropping k restores feasibility, so k is
  responsible).
The auxiliary problems are built from the same compiled matrices as the solve
(:attr:`lmidsl.solver.backends.base.CompiledModel.lmi_matrices`), so the diagnosis works for every theorem and
backend.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..numeric.evaluate import max_eigenvalue
from ..numeric.instance import Instance
from .solution import lmi_certificate, with_location
from .backends import choose_backend, get_backend
from .status import solved

DEFAULT_RADIUS = 1e6
"""Feasibility radius R (bound on the 2-norm of all decision variables stacked)."""

MAX_RADIUS = 1e10
"""Largest radius tried before a non-negative t* is taken as the answer."""

FEASP_TOL = 1e-9

"""|t*| below this is zero: the solvers' accuracy on these problems is about 1e-9 to 1e-8."""

MAX_DETAILED = 24
"""Above this many compiled LMIs the per-LMI 'alone'/'without' problems are skipped by default."""


FEASP_INFEASIBLE = "infeasible"    # feasp's word: t* >= 0 (radius inactive, consistent); not a proof
FEASP_MARGINAL = "marginal"        # feasp's word: feasible by less than the strictness margin

@dataclass
class LMIMargin:
    label: str
    vertex: int | None
    size: int
    value: float | None
    alone: float | None = None
    without: float | None = None
    binding: bool = False
    responsible: bool = False
    point: str = ""

    @property
    def name(self) -> str:
        return (self.label + (f" @ vertex {self.vertex}" if self.vertex is not None else "")
                + (f" @ {self.point}" if self.point else ""))

    def as_dict(self) -> dict:
        return with_location({"label": self.label, "size": self.size, "value": self.value,
                              "alone": self.alone, "without": self.without, "binding": self.binding,
                              "responsible": self.responsible}, self.vertex, self.point)


@dataclass
class FeasibilityReport:
    """t* of the feasp problem, the verdict, and the per-LMI margins."""

    tmin: float | None
    status: str
    margin: float
    radius: float
    lmis: list[LMIMargin] = field(default_factory=list)
    solver: str = ""

    radii: list = field(default_factory=list)
    point_certified: bool = False
    point_norm: float | None = None   # ‖x‖₂ of the feasp point (all variables stacked)
    refuted_by: str | None = None     # a certified point found another way (e.g. "Riccati")

    @property
    def inconsistent(self) -> bool:
        """t* grew with the radius by more than 10 % (and 1e-6, and 1e-14 R): impossible for exact solves (a
        larger ball contains the smaller one), so the solver is inaccurate on this problem and
        t* proves nothing."""
        found = [(r, t) for r, t in self.radii if t is not None]
        # a solve at radius R resolves t to about 1e-14 R (double precision on variables of size R)
        return any(later > earlier + 0.1 * abs(earlier) + 1e-6 + 1e-14 * r
                   for i, (_, earlier) in enumerate(found) for r, later in found[i + 1:])

    @property
    def at_radius(self) -> bool:
        """The norm bound ‖x‖₂ ≤ R is active at the feasp point (then t* is not a global minimum)."""
        return self.point_norm is not None and self.point_norm >= 0.99 * self.radius

    @property
    def feasible(self) -> bool:
        """Strictly feasible with the compiled margin: t* < −margin, and numpy confirms every strict
        LMI ⪯ −margin I at the returned point (the solver's t* alone is not a certificate)."""
        return self.tmin is not None and self.tmin < -self.margin and self.point_certified

    @property
    def infeasible(self) -> bool:
        """No strictly feasible point: t* ≥ 0 up to the solver accuracy, with the radius inactive
        and t* consistent across the radii tried."""
        return (self.tmin is not None and self.tmin >= -FEASP_TOL and not self.at_radius
                and not self.inconsistent)

    @property
    def rules_out(self) -> bool:
        """The diagnosis rules the point out: no strictly feasible point (:data:`FEASP_INFEASIBLE`,
        not a proof) or feasible by less than the margin (:data:`FEASP_MARGINAL`)."""
        return self.verdict in (FEASP_INFEASIBLE, FEASP_MARGINAL)

    @property
    def verdict(self) -> str:
        if self.refuted_by:
            return f"feasible (a {self.refuted_by} point satisfies every LMI)"
        if self.tmin is None:
            return "undecided"
        if self.feasible:
            return "strictly feasible"
        if self.tmin >= -FEASP_TOL and self.at_radius:
            return "undecided (radius)"
        if self.infeasible:
            return FEASP_INFEASIBLE
        if self.tmin >= -FEASP_TOL:
            return "undecided (accuracy)"    # t* inconsistent across radii
        return FEASP_MARGINAL

    @property
    def responsible(self) -> list[str]:
        return [m.name for m in self.lmis if m.responsible]

    def as_dict(self) -> dict:
        return {"tmin": self.tmin, "verdict": self.verdict, "feasible": self.feasible,
                "refuted_by": self.refuted_by,
                "point_certified": self.point_certified, "point_norm": self.point_norm,
                "status": self.status, "margin": self.margin, "radius": self.radius,
                "radii": self.radii,
                "solver": self.solver, "responsible": self.responsible,
                "lmis": [m.as_dict() for m in self.lmis]}


class JointFeasp:
    """The joint feasp problem built once on a compiled model; re-solved after
    :meth:`~lmidsl.solver.backends.base.CompiledModel.update` (parameters are backend parameters)."""

    def __init__(self, model, radius: float = DEFAULT_RADIUS):
        self.model = model
        self.radius = radius
        self._build()

    def _build(self):
        model = self.model
        self._source = model.lmi_matrices
        self.t = model.new_scalar("t_feasp", False)
        constraints = [model.shifted_lmi_constraint(c.N, self.t, c.size) if c.strict
                       else model.lmi_constraint(c.N, c.size, None) for c in compiled_lmis(model)]
        constraints.append(model.norm_bound(self.radius))
        self.problem = model.make_problem(self.t, constraints)

    def solve(self, solver=None, **options):
        """(t*, solver status); t* None when the solver returns no value."""
        if self.model.lmi_matrices is not self._source:   # the backend recompiled on update
            self._build()
        status, value, _, _ = self.model.run_solver(solver, self.problem, **options)
        ok = solved(status) and value is not None
        return (float(value) if ok else None), status


@dataclass
class CompiledLMI:
    """One compiled LMI ``N ⪯ 0`` of a model (from ``CompiledModel.lmi_matrices``)."""

    label: str
    vertex: int | None
    N: object
    size: int
    strict: bool
    point: str = ""

    @property
    def key(self) -> tuple:
        """(label, 1-based vertex or None, point): the key of :class:`~lmidsl.solver.solution.LMIReport`."""
        return (self.label, None if self.vertex is None else self.vertex + 1, self.point)


def compiled_lmis(model) -> list[CompiledLMI]:
    """The model's assembled LMI matrices with their sizes and strictness."""
    by_label = {lmi.label: lmi for lmi in model.instance.theorem.lmis}
    dims = model.instance.dims
    out = []
    for key, N in model.lmi_matrices:
        label, vertex = key[0], key[1]
        point = key[2] if len(key) > 2 else ""
        lmi = by_label[label]
        size = sum(int(sp.sympify(s).xreplace(dims)) for s in lmi.negative_form().sizes)
        out.append(CompiledLMI(label, vertex, N, size, lmi.strict, point or ""))
    return out


def _tmin(model, chosen, radius, solver, options):
    """min t s.t. the chosen strict LMIs ⪯ tI, the chosen non-strict ones ⪯ 0, ‖x‖ ≤ R."""
    t = model.new_scalar("t_feasp", False)
    constraints = []
    for c in chosen:
        if c.strict:
            constraints.append(model.shifted_lmi_constraint(c.N, t, c.size))
        else:
            constraints.append(model.lmi_constraint(c.N, c.size, None))
    constraints.append(model.norm_bound(radius))
    problem = model.make_problem(t, constraints)
    status, value, _, _ = model.run_solver(solver, problem, **options)
    ok = solved(status) and value is not None
    if not ok:
        return None, status
    achieved = _achieved_t(model, chosen)
    # the returned point realises t = max λ_max(N) over the strict LMIs: t* is at most that,
    # whatever the solver's objective says (an "optimal" Clarabel point on pan_impulsive.lemma1's
    # (13) alone had t = 8.4e-5 and λ_max = −0.0079, its residual 0.013 at ‖x‖ ~ 8e5)
    return (min(float(value), achieved) if achieved is not None else float(value)), status


def _achieved_t(model, chosen) -> float | None:
    """max λ_max(N) over the chosen strict LMIs at the model's current point (numpy), or None
    when a chosen non-strict LMI does not hold there (to 1e-9 of its scale)."""
    worst = None
    for c in chosen:
        N = model.expression_value(c.N)
        if N is None:
            return None
        top = max_eigenvalue(N)
        if not c.strict:
            if top > 1e-9 * max(1.0, float(np.abs(N).max())):
                return None
            continue
        worst = top if worst is None else max(worst, top)
    return worst


def stacked_norm(values: dict) -> float:
    """‖x‖₂ of all decision variables stacked (per-vertex copies included)."""
    parts = []
    for value in values.values():
        for v in (value if isinstance(value, list) else [value]):
            if v is not None:
                parts.append(np.ravel(np.asarray(v, dtype=float)))
    return float(np.linalg.norm(np.concatenate(parts))) if parts else 0.0


def feasp(instance: Instance, backend: str | None = None, solver: str | None = None,
          radius: float = DEFAULT_RADIUS, margin: float | None = None, detail: bool | None = None,
          max_radius: float = MAX_RADIUS, conditioning=None, **options) -> FeasibilityReport:
    """The feasp diagnosis of ``instance`` (see the module docstring).

    ``detail`` (default: when there are at most :data:`MAX_DETAILED` compiled LMIs) adds the
    per-LMI 'alone' and 'without' problems.  ``conditioning``: solve the auxiliary problems on
    the conditioned LMIs (:mod:`lmidsl.solver.conditioning`); t* is then in their units.
    """
    backend = choose_backend(backend, solver)

    model = get_backend(backend)(instance, margin=margin, conditioning=conditioning)
    compiled = compiled_lmis(model)
    def point_values(tmin):
        """λ_max of every LMI at the returned point, with numpy (the certificate)."""
        if tmin is None:
            return {}
        point = dict(instance.data)
        point.update(model.values())
        return {(r.label, r.vertex, getattr(r, "point", "") or ""): r.max_eig
                for r in lmi_certificate(instance, point, congruence=model._congruence)}

    def certified(values):
        strict = [values.get(c.key) for c in compiled if c.strict]
        return bool(values) and all(v is not None and v < -model.margin for v in strict)

    radii = []
    while True:
        tmin, status = _tmin(model, compiled, radius, solver, options)
        values = point_values(tmin)
        radii.append([radius, tmin])
        if certified(values) or radius * 100 > max_radius:
            break
        radius *= 100
    found = [r for r in radii if r[1] is not None]
    if found and not certified(values):
        # a larger radius did not give a certified point: keep the smallest radius that reaches
        # the least t* (large radii cost accuracy)
        least = min(r[1] for r in found)
        chosen = next(r for r in found if r[1] <= least + 1e-6 * max(1.0, abs(least)) + FEASP_TOL)
        if chosen[0] != radius:
            radius = chosen[0]
            tmin, status = _tmin(model, compiled, radius, solver, options)
            values = point_values(tmin)
    report = FeasibilityReport(tmin, status, model.margin, radius, solver=model.solver_name(solver),
                               radii=radii, point_certified=certified(values),
                               point_norm=stacked_norm(model.values()) if tmin is not None else None)
    tol = max(1e-6 * max(1.0, abs(tmin or 0.0)), 10 * model.margin)
    for c in compiled:
        value = values.get(c.key)
        binding = tmin is not None and value is not None and c.strict and value >= tmin - tol
        report.lmis.append(LMIMargin(c.label, c.key[1], c.size, value, binding=binding, point=c.point))
    if detail is None:
        detail = len(compiled) <= MAX_DETAILED
    if detail and len(compiled) > 1:
        for k, (c, m) in enumerate(zip(compiled, report.lmis)):
            if c.strict:
                m.alone, _ = _tmin(model, [c], radius, solver, options)
            rest = compiled[:k] + compiled[k + 1:]
            if any(r.strict for r in rest):
                m.without, _ = _tmin(model, rest, radius, solver, options)
    if not report.feasible and tmin is not None:
        limit = -FEASP_TOL if report.infeasible else -model.margin
        for m in report.lmis:
            alone_bad = m.alone is not None and m.alone >= limit
            without_ok = m.without is not None and m.without < limit
            m.responsible = alone_bad or without_ok
        if not any(m.responsible for m in report.lmis):
            for m in report.lmis:   # jointly infeasible: the binding LMIs share the blame
                m.responsible = m.binding
    return report


def diagnosis_needed(solution) -> bool:
    """A solve calls for the diagnosis when the solver did not return a certified point."""
    return not (solution.ok and solution.lmis_hold)

