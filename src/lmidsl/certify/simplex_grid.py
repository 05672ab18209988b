"""Evidence on a grid of the simplex: is a robust claim refuted at some α?

A robust LMI certifies a property for every α ∈ Λ_N (or a product of simplices).  The claim is
tested independently: the system at α, M(α) = Σ_v w_v(α) M_v (w_v(α) = αᵢ on a simplex,
α¹ᵢ α²ⱼ ⋯ at the product vertex (i, j, …) of a multi-simplex), is evaluated at a budget of
points of the domain (``max_points``), the measure computed at each point by numpy /
python-control, and the worst point refined by a pattern search inside the domain (moves
α ± h(eᵢ − eⱼ), h halved down to 1e-6; at most :data:`REFINE_FACTOR` × ``max_points``
evaluations in all).

The points are chosen by what the claim needs, not by the number of the vertices'
combinations: the regular grid {α : αᵢ = kᵢ/r} (C(N + r − 1, r) points per simplex, counted, not
enumerated, to choose r) at the finest r whose grid fits the budget; when that r is below
:data:`FINE_RESOLUTION` (many vertices: r = 1 is the vertices, r = 2 adds the edge midpoints),
the grid is kept and the rest of the budget is drawn uniformly on the domain (Dirichlet(1, …, 1)
per simplex, a fixed seed) — so 12 vertices cost the budget's points, not 12¹¹.  Measures:

* ``"abscissa"``: max Re λ(A(α)), the claim "Hurwitz" is refuted by a value ≥ 0;
* ``"radius"``: max |λ(A(α))|, the claim "Schur" is refuted by a value ≥ 1;
* ``"hinf"``: ‖(A, B, C, D)(α)‖∞ (python-control, SLICOT AB13DD; +∞ where A(α) is unstable),
  a claimed bound γ is refuted by a value > γ(1 + tol);
* ``"h2"``: ‖(A, B, C, D)(α)‖₂ (python-control), likewise.

The grid is evidence, not proof: a claim it does not refute may still be false between grid
points, and a refutation is a concrete α at which the property fails (exact up to the
eigenvalue / norm computation).

:func:`grid_evidence` is the entry point: (a bound instance of a polytopic theorem, or the vertex
systems as dicts; the claimed level; the time domain) → :class:`GridEvidence` (worst α, its
value, whether it refutes).  :func:`grid_check` wraps it as a theorem check
(:meth:`lmidsl.theorem.theorem.Theorem.verify_with`).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from math import comb

import numpy as np

from ..errors import InputError
from ..numeric.systems import hinf_norm
from ..symbolic.simplex import exponents
from ..theorem.checks import CheckResult

MEASURES = ("abscissa", "radius", "hinf", "h2")
STABILITY_LEVEL = {"abscissa": 0.0, "radius": 1.0}


@dataclass
class GridEvidence:
    """The worst point of the domain found, and whether it refutes the claim."""

    measure: str
    time: str
    claim: float | None             # the claimed level (stability: 0 / 1)
    worst_alpha: list               # one list per simplex
    worst_value: float
    refutes: bool
    points: int                     # points evaluated (grid and random; refinement steps not counted)
    resolution: int
    vertex_values: list = field(default_factory=list)
    random_points: int = 0          # of ``points``, drawn uniformly on the domain
    refine_evaluations: int = 0     # evaluations of the pattern search

    def as_dict(self) -> dict:
        return {"measure": self.measure, "time": self.time, "claim": self.claim,
                "worst_alpha": self.worst_alpha, "worst_value": self.worst_value,
                "refutes": self.refutes, "points": self.points, "resolution": self.resolution,
                "random_points": self.random_points, "refine_evaluations": self.refine_evaluations,
                "vertex_values": self.vertex_values}

    def summary(self) -> str:
        where = "; ".join("(" + ", ".join(f"{a:.4f}" for a in s) + ")" for s in self.worst_alpha)
        claim = "" if self.claim is None else f" against the claim {self.claim:.6g}"
        verdict = "refutes" if self.refutes else "does not refute"
        drawn = f" and {self.random_points} random points" if self.random_points else ""
        return (f"{self.measure} on {self.points - self.random_points} grid points (resolution "
                f"{self.resolution}){drawn}, refined: worst {self.worst_value:.6g} at α = {where}{claim}: {verdict}")


# -- the domain ----------------------------------------------------------------------------------
FINE_RESOLUTION = 4
"""A regular grid at least this fine is used alone; a coarser one (many vertices) is completed
by random points up to the budget."""

REFINE_FACTOR = 4
"""The pattern search's evaluations are at most this many times the point budget."""


def simplex_points(N: int, resolution: int) -> np.ndarray:
    """Every α ∈ Λ_N with αᵢ = kᵢ/resolution (C(N + r − 1, r) points, made as the compositions
    of r, not filtered from (r + 1)^(N−1) candidates)."""
    return np.array(exponents(N, resolution), dtype=float).reshape(-1, N) / resolution


def grid_size(sizes: tuple, resolution: int) -> int:
    """The number of points of the regular grid of resolution r on Λ_{N₁} × …, without making it."""
    return int(np.prod([comb(N + resolution - 1, resolution) for N in sizes]))


def random_points(sizes: tuple, count: int, rng: np.random.Generator) -> list:
    """``count`` points drawn uniformly on Λ_{N₁} × … (Dirichlet(1, …, 1) per simplex), each a
    tuple of one α per simplex."""
    draws = [rng.dirichlet(np.ones(N), size=count) for N in sizes]
    return [tuple(d[k] for d in draws) for k in range(count)]


def domain_points(sizes: tuple, max_points: int, seed: int = 0) -> tuple:
    """(points, resolution, how many are random): the regular grid at the finest resolution
    whose grid fits ``max_points`` (at least the vertices), completed by uniform random points up
    to ``max_points`` when that resolution is below :data:`FINE_RESOLUTION` (see the module
    docstring)."""
    resolution = 1
    while resolution < 200 and grid_size(sizes, resolution + 1) <= max_points:
        resolution += 1
    points = list(itertools.product(*(simplex_points(N, resolution) for N in sizes)))
    extra = max_points - len(points) if resolution < FINE_RESOLUTION else 0
    if extra > 0:
        points += random_points(sizes, extra, np.random.default_rng(seed))
    return points, resolution, max(extra, 0)


def vertex_weights(alphas: tuple) -> np.ndarray:
    """w_v(α) at the product vertices, first simplex slowest (the order of the vertex data)."""
    w = np.array([1.0])
    for a in alphas:
        w = np.outer(w, a).reshape(-1)
    return w


def at(vertex_systems: list, alphas: tuple) -> dict:
    """The system at α: Σ_v w_v(α) M_v for every matrix name."""
    w = vertex_weights(alphas)
    return {name: sum(wv * np.asarray(v[name], dtype=float) for wv, v in zip(w, vertex_systems))
            for name in vertex_systems[0]}


# -- measures ------------------------------------------------------------------------------------
def measure_value(system: dict, measure: str, time: str) -> float:
    """The measure of one system (see the module docstring); +∞ for a norm of an unstable one;
    ArithmeticError when the norm of a stable one does not come out finite."""
    A = np.atleast_2d(system["A"])
    eig = np.linalg.eigvals(A)
    abscissa, radius = float(np.max(eig.real)), float(np.max(np.abs(eig)))
    if measure == "abscissa":
        return abscissa
    if measure == "radius":
        return radius
    if (abscissa >= 0) if time == "continuous" else (radius >= 1):
        return float("inf")
    B, C = np.atleast_2d(system["B"]), np.atleast_2d(system["C"])
    D = np.atleast_2d(system.get("D", np.zeros((C.shape[0], B.shape[1]))))
    if measure == "hinf":
        value = hinf_norm(A, B, C, D, time)     # SLICOT AB13DD, without importing python-control
    else:
        import control     # 1–2 s to import: only when an H2 norm is computed
        value = float(control.norm(control.ss(A, B, C, D, 0 if time == "continuous" else True), 2))
    if not np.isfinite(value):
        # a stable system has a finite norm: an infinite one is a failed computation, not evidence
        raise ArithmeticError(f"the {measure} norm of a stable system came out {value}")
    return value


def _moves(sizes: tuple) -> list:
    """Directions e_i − e_j inside each simplex (as flat vectors over the concatenated α)."""
    total, offset, out = sum(sizes), 0, []
    for N in sizes:
        for i, j in itertools.permutations(range(N), 2):
            d = np.zeros(total)
            d[offset + i], d[offset + j] = 1.0, -1.0
            out.append(d)
        offset += N
    return out


def _split(flat: np.ndarray, sizes: tuple) -> tuple:
    return tuple(np.split(flat, np.cumsum(sizes)[:-1]))


def worst_point(vertex_systems: list, sizes: tuple, measure: str, time: str, *, resolution: int | None = None,
                refine: int = 3, max_points: int = 20000) -> tuple:
    """(worst flat α, its value, number of points, resolution, random points, refinement
    evaluations): the points (:func:`domain_points`, or the regular grid of ``resolution``), then
    a pattern search from the ``refine`` best of them, within :data:`REFINE_FACTOR` ×
    ``max_points`` evaluations."""
    if resolution is None:
        combos, resolution, drawn = domain_points(sizes, max_points)
    else:
        combos, drawn = list(itertools.product(*(simplex_points(N, resolution) for N in sizes))), 0
    flats = [np.concatenate(combo) for combo in combos]
    values = np.array([measure_value(at(vertex_systems, combo), measure, time) for combo in combos])
    order = np.argsort(-values)[:max(refine, 1)]
    best_alpha, best = flats[order[0]], float(values[order[0]])
    if np.isinf(best):
        return best_alpha, best, len(flats), resolution, drawn, 0
    moves = _moves(sizes)
    budget, used = REFINE_FACTOR * max_points, 0
    for start in order:
        alpha, value = flats[start].copy(), float(values[start])
        h, steps = 0.5 / resolution, 0
        while h > 1e-6 and steps < 400 and not np.isinf(value) and used < budget:
            steps += 1
            trials = [t for t in (alpha + h * d for d in moves) if t.min() >= 0][:budget - used]
            used += len(trials)
            scores = [measure_value(at(vertex_systems, _split(t, sizes)), measure, time) for t in trials]
            k = int(np.argmax(scores)) if scores else -1
            if k >= 0 and scores[k] > value:           # the steepest move, or a smaller step
                alpha, value = trials[k], scores[k]
            else:
                h /= 2
        if value > best:
            best_alpha, best = alpha, value
    return best_alpha, best, len(flats), resolution, drawn, used


# -- entry points ----------------------------------------------------------------------------------
def vertex_systems_of(instance, names=("A", "B", "C", "D")) -> tuple:
    """(vertex systems, sizes) of a bound polytopic instance: the per-vertex data among ``names``
    (a datum common to the vertices repeated), and the simplex sizes (a robust member's, else one
    simplex of all vertices)."""
    robust = getattr(instance.theorem, "robust", None)
    sizes = robust.sizes if robust is not None else (instance.nvertices,)
    count = int(np.prod(sizes))
    systems = [{} for _ in range(count)]
    for name in names:
        if name not in instance.data:
            continue
        value = instance.data[name]
        for v in range(count):
            systems[v][name] = value[v] if isinstance(value, list) else value
    return systems, tuple(sizes)


def grid_evidence(source, claim: float | None = None, time: str | None = None, *, measure: str | None = None,
                  sizes: tuple | None = None, resolution: int | None = None, tolerance: float = 1e-6,
                  max_points: int = 20000) -> GridEvidence:
    """Test a robust claim on a grid of the domain.

    ``source``: a bound :class:`~lmidsl.numeric.instance.Instance` of a polytopic theorem (its
    vertex data A, B, C, D; the time domain from the theorem) or a list of vertex systems (dicts
    with "A" and, for norms, "B", "C", optionally "D"; ``sizes`` their simplices, default one
    simplex).  ``claim``: the claimed level (a norm bound γ); None for a stability claim.
    ``measure``: default "abscissa"/"radius" for stability, "hinf" for a level.  A refutation
    is a worst value ≥ 0 (abscissa), ≥ 1 (radius) or > claim·(1 + tolerance) (norms)."""
    if isinstance(source, list):
        systems, sizes = source, tuple(sizes or (len(source),))
    else:
        systems, found = vertex_systems_of(source)
        sizes = tuple(sizes or found)
        time = time or source.theorem.time
    if time not in ("continuous", "discrete"):
        raise InputError(f"grid evidence: time must be 'continuous' or 'discrete', got {time!r}")
    if int(np.prod(sizes)) != len(systems):
        raise InputError(f"grid evidence: {len(systems)} vertex systems for a domain of sizes {sizes}")
    if measure is None:
        measure = ("abscissa" if time == "continuous" else "radius") if claim is None else "hinf"
    if measure not in MEASURES:
        raise InputError(f"grid evidence: measure must be one of {', '.join(MEASURES)}")
    alpha, value, points, resolution, drawn, used = worst_point(systems, sizes, measure, time,
                                                                resolution=resolution, max_points=max_points)
    if measure in STABILITY_LEVEL:
        level = STABILITY_LEVEL[measure]
        refutes = value >= level
    else:
        level = claim
        refutes = claim is not None and value > claim * (1 + tolerance)
    vertex_values = [measure_value(s, measure, time) for s in systems]
    return GridEvidence(measure, time, level, [list(map(float, a)) for a in _split(alpha, sizes)],
                        float(value), bool(refutes), points, resolution, vertex_values, drawn, used)


def grid_check(measure: str | None = None, *, closed_loop=None, name: str = "simplex grid",
               resolution: int | None = None, max_points: int | None = None):
    """A theorem check (:meth:`~lmidsl.theorem.theorem.Theorem.verify_with`): the solution's
    claim — robust stability, or the level ``solution.gamma`` for a norm measure — tested by
    :func:`grid_evidence` on the instance's vertex systems.  ``closed_loop(system, design)``
    maps a vertex system and the recovered design to the system to test (e.g. A + B K).
    ``max_points``: default 1500 for eigenvalues, 300 for norms (python-control, ~5 ms a norm)."""

    def check(solution) -> CheckResult:
        systems, sizes = vertex_systems_of(solution.instance)
        if closed_loop is not None:
            systems = [closed_loop(s, solution.design) for s in systems]
        norm = measure in ("hinf", "h2")
        claim = solution.point_gamma if norm else None
        if norm and claim is None:
            return CheckResult(name, False, "no level to test")
        points = max_points or (300 if norm else 1500)
        evidence = grid_evidence(systems, claim, solution.instance.theorem.time, measure=measure,
                                 sizes=sizes, resolution=resolution, max_points=points)
        return CheckResult(name, not evidence.refutes, evidence.summary(), evidence.as_dict())

    return check


__all__ = ["GridEvidence", "grid_evidence", "grid_check", "worst_point", "simplex_points", "domain_points",
           "grid_size", "random_points", "measure_value", "vertex_systems_of", "at"]
