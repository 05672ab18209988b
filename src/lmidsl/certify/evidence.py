"""Claims tested against independent evidence.

The LMIs proved at a point prove what the theorem says they prove — if the theorem is right.  A
theorem that declares its system states a claim that can be tested without its LMIs:

* **bounded-real form** (:meth:`~lmidsl.theorem.theorem.Theorem.bounded_real_form`): the system
  (A, B, C, D) has H∞ norm at most the level γ.  For one system, SLICOT AB13DD's norm (python-control's
  routine, called directly: python-control itself is not imported); for a
  polytope (data per vertex, A(α) = Σ αᵢ Aᵢ, …), the norm on a grid of the simplex refined around
  its maximum (:func:`lmidsl.certify.simplex_grid.grid_evidence`): the claim is "for every α".
* **a design with a loop** (its kind in :data:`~lmidsl.numeric.interconnection.DESIGN_KIND_TABLE`)
  whose analysis counterpart declares a bounded-real form (so the level is an H∞ level): the closed
  loop (or filtering-error system) formed by the generic lower LFT
  (:func:`lmidsl.numeric.interconnection.lower_lft`, checked against python-control's in the
  tests) has H∞ norm at most the headline
  level — for a polytopic plant on the grid of the simplex (the loop's matrices are affine in the
  plant's, so the vertex loops span it).

A value beyond the claimed level (relative tolerance :data:`TOLERANCE`: the norm's own accuracy,
far below any solver's) **refutes** the claim: the verdict is "refuted", the point and its value
are shown.  Evidence that does not refute is evidence, not proof (the grid may miss the worst α).
A computation that fails or gives a value that is not finite for a stable system is "evidence
unavailable", never a refutation.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..numeric.evaluate import NumericEvaluator
from ..numeric.interconnection import design_kind, design_loop
from ..numeric.riccati import realisation_norm
from ..theorem.registry import get_theorem
from .simplex_grid import grid_evidence, measure_value

TOLERANCE = 1e-6
"""Relative excess of a computed norm over the claimed level that refutes (python-control's norm
is computed to 1e-10 relative here; a proved level is never below the true norm)."""

MAX_GRID_POINTS = 4000
"""Grid points of the simplex evaluated at most (the refinement adds a few hundred)."""


@dataclass
class Evidence:
    """One independent test of a claim."""

    name: str
    claim: float | None
    value: float | None
    refutes: bool
    summary: str
    details: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"name": self.name, "claim": self.claim, "value": self.value, "refutes": self.refutes,
                "summary": self.summary, "details": self.details}


def _system(instance, values: dict, exprs, vertex) -> dict:
    ev = NumericEvaluator(instance.dims, {**instance.data, **values}, instance.params, vertex=vertex)
    return {k: np.atleast_2d(np.asarray(ev.visit(e), dtype=float)) for k, e in zip("ABCD", exprs)}


def _norm_evidence(name: str, systems: list, claim: float, time: str) -> Evidence:
    """The H∞ norm of one system, or on a grid of the simplex of several vertex systems."""
    if len(systems) == 1:
        value = measure_value(systems[0], "hinf", time)
        refutes = bool(value > claim * (1 + TOLERANCE))
        how = "SLICOT AB13DD, python-control's routine"
        if refutes and np.isfinite(value):
            # AB13DD on a stiff realisation is off by 1e-5 to 50 % (lmidsl.numeric.riccati.
            # realisation_norm): a refutation must hold on the balanced realisation too
            s = systems[0]
            other, _ = realisation_norm(s["A"], s["B"], s["C"], s.get("D"), time)
            if other is not None and not other > claim * (1 + TOLERANCE):
                how += f", on the balanced realisation (the data as written give {value:.10g})"
                value, refutes = other, False
        return Evidence(name, claim, float(value), refutes,
                        f"the H∞ norm ({how}) {value:.10g} against the claimed level {claim:.10g}: "
                        + ("refutes" if refutes else "does not refute"))
    grid = grid_evidence(systems, claim, time, measure="hinf", tolerance=TOLERANCE,
                         max_points=MAX_GRID_POINTS)
    return Evidence(name + " on a grid of the simplex", claim, grid.worst_value, grid.refutes,
                    grid.summary(), grid.as_dict())


def bounded_real_evidence(solution) -> Evidence | None:
    """The declared bounded-real claim ‖(A, B, C, D)‖∞ ≤ γ at the solved level, or None."""
    instance = solution.instance
    form = instance.theorem.bounded_real
    if form is None or solution.point_gamma is None or not solution.ok:
        return None
    vertices = range(instance.nvertices) if instance.nvertices > 1 else [None]
    systems = [_system(instance, solution.values, form.system, v) for v in vertices]
    return _norm_evidence("the declared system's H∞ norm", systems, solution.point_gamma, instance.theorem.time)


def design_evidence(solution, level: float | None) -> Evidence | None:
    """The delivered design's loop against ``level``, or None (no design, no loop for its kind,
    the data not a plant in the gallery's names, or no level)."""
    design = solution.design
    if design is None or level is None or design_kind(design.kind).loop is None:
        return None
    analysis = solution.analysis
    if analysis is None or get_theorem(analysis.theorem).bounded_real is None:
        return None          # the level is not known to be an H∞ level
    original = solution.original_instance
    per_vertex = [k for k, v in original.data.items() if isinstance(v, list)]
    if per_vertex:
        count = original.nvertices
        loops = [design_loop({k: (v[i] if isinstance(v, list) else v) for k, v in original.data.items()}, design)
                 for i in range(count)]
    else:
        loops = [design_loop(original.data, design)]
    if any(loop is None for loop in loops):
        return None
    systems = [{"A": np.atleast_2d(s.A), "B": np.atleast_2d(s.B), "C": np.atleast_2d(s.C),
                "D": np.atleast_2d(s.D)} for s in loops]
    words = design_kind(design.kind).loop_words
    return _norm_evidence(f"the {words}'s H∞ norm", systems, level, original.theorem.time)


def claim_evidence(solution, level: float | None) -> list[Evidence]:
    """Every independent test of the solution's claims that the theorem's declarations allow;
    ``level``: the level claimed for the delivered design (the headline)."""
    out = []
    for test in (lambda: bounded_real_evidence(solution), lambda: design_evidence(solution, level)):
        try:
            found = test()
        except Exception as exc:    # an ill-posed loop or SLICOT refusing a system is no evidence either way
            found = Evidence("independent norm", level, None, False,
                             f"evidence unavailable: {type(exc).__name__}: {exc}")
        if found is not None:
            out.append(found)
    return out


__all__ = ["Evidence", "claim_evidence", "bounded_real_evidence", "design_evidence", "TOLERANCE"]
