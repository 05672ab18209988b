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

from flint import acb, acb_mat

from ..numeric.evaluate import NumericEvaluator
from ..numeric.interconnection import ball_loop, design_kind, design_loop
from ..numeric.proof import PRECISION, BallEvaluator, ball_precision
from ..numeric.riccati import balancing_transform, realisation_norm
from ..numeric.systems import hinf_peak
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


def _peak_frequencies(s: dict, time: str) -> list[float]:
    """ω = 0 and SLICOT AB13DD's peak frequencies on the realisation as given and balanced."""
    out = [0.0]
    realisations = [(s["A"], s["B"], s["C"])]
    balanced = balancing_transform(s["A"], s["B"], s["C"], time)
    if balanced is not None:
        T, Ti = balanced
        realisations.append((Ti @ s["A"] @ T, Ti @ s["B"], s["C"] @ T))
    for A, B, C in realisations:
        _, peak = hinf_peak(A, B, C, s.get("D"), time)
        if np.isfinite(peak):
            out.append(float(peak))
    return out


def _complex_balls(M: np.ndarray) -> acb_mat:
    return acb_mat([[acb(x) for x in row] for row in np.atleast_2d(M).tolist()])


def exact_gain(system: dict, frequencies, time: str) -> float | None:
    """max over ``frequencies`` of σ_max(G), G = C (sI − A)⁻¹ B + D at s = jω (continuous) or
    e^{jω} (discrete), for a system of python-flint balls (the data as written), the resolvent
    solved in :data:`~lmidsl.numeric.proof.PRECISION`-bit ball arithmetic: each value is the
    exact system's gain at that frequency (to ~1e-60), so their maximum is a lower bound on its H∞
    norm that no rounding of the realisation can spoil; None when a solve is not possible."""
    with ball_precision(PRECISION):
        A, B, C, D = (_complex_balls(system[k]) for k in "ABCD")
        n = A.nrows()
        best = 0.0
        for w in frequencies:
            s = acb(0, w) if time == "continuous" else acb(0, w).exp()
            try:
                G = C * (s * acb_mat(n, n, [1 if i == j else 0 for i in range(n) for j in range(n)]) - A).solve(B) + D
            except ZeroDivisionError:
                return None
            mid = np.array([[complex(float(G[i, j].real.mid()), float(G[i, j].imag.mid()))
                             for j in range(G.ncols())] for i in range(G.nrows())])
            best = max(best, float(np.linalg.svd(mid, compute_uv=False)[0]))
    return best


def proved_unstable(A: np.ndarray, time: str) -> bool:
    """Whether an eigenvalue of the ball matrix A (the data as written) is proved outside the
    stability region (python-flint's ``acb_mat.eig``, enclosures at :data:`PRECISION` bits)."""
    with ball_precision(PRECISION):
        try:
            eigenvalues = _complex_balls(A).eig(nonstop=True)
        except (ValueError, ZeroDivisionError):
            return False
        if time == "continuous":
            return any(e.real.is_finite() and e.real > 0 for e in eigenvalues)
        return any(e.is_finite() and abs(e) > 1 for e in eigenvalues)


def _norm_evidence(name: str, systems: list, claim: float, time: str, exact=None) -> Evidence:
    """The H∞ norm of one system, or on a grid of the simplex of several vertex systems.
    ``exact()``: the one system in python-flint balls (the data as written), which a refutation
    must survive (:func:`exact_gain` at SLICOT's peak frequencies)."""
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
        if refutes and not np.isfinite(value) and exact is not None and not proved_unstable(exact()["A"], time):
            how += ("; the loop summed in doubles is unstable, the exact one is not proved unstable "
                    f"({PRECISION}-bit eigenvalue enclosures): no refutation")
            refutes = False
        elif refutes and np.isfinite(value) and exact is not None:
            # and for the exact system: a loop closed by a gain of entries 1e10, summed in doubles,
            # is another system (SLICOT: 119,444 where the exact loop's peak is 75,375.698)
            confirmed = exact_gain(exact(), _peak_frequencies(systems[0], time), time)
            if confirmed is not None and not confirmed > claim * (1 + TOLERANCE):
                how += (f"; the exact system's σ_max at SLICOT's peak frequencies is {confirmed:.10g} "
                        f"({PRECISION}-bit balls): the doubles' {value:.10g} is rounding, no refutation")
                value, refutes = confirmed, False
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

    def exact():
        ev = BallEvaluator(instance.dims, {**instance.data, **solution.values}, instance.params)
        with ball_precision(PRECISION):
            return {k: np.atleast_2d(np.asarray(ev.visit(e), dtype=object)) for k, e in zip("ABCD", form.system)}
    return _norm_evidence("the declared system's H∞ norm", systems, solution.point_gamma, instance.theorem.time,
                          exact if len(systems) == 1 else None)


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

    def exact():
        with ball_precision(PRECISION):
            loop = ball_loop(original.data, design)
            return {"A": loop.A, "B": loop.B, "C": loop.C, "D": loop.D}
    return _norm_evidence(f"the {words}'s H∞ norm", systems, level, original.theorem.time,
                          exact if not per_vertex else None)


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


__all__ = ["Evidence", "claim_evidence", "bounded_real_evidence", "design_evidence", "exact_gain", "proved_unstable", "TOLERANCE"]
