"""Search over a theorem's fixed scalars (λ1, λ2, ε, ...): a grid, then a local refinement.

Many synthesis theorems are LMIs only once some scalars are fixed (Pan/Sun's λ1, λ2, ε); the
best level is then

    γ*(θ) = min { γ : the LMIs hold at the scalars θ },      θ* = argmin_θ γ*(θ),

a non-convex problem in θ.  :func:`scalar_search` evaluates γ*(θ) on a grid (serially, or on
Dask workers: one compiled model per worker, the scalars changed as backend parameters), then refines
the best grid point with Nelder–Mead on θ ↦ γ*(θ).  With ``objective="tmin"`` the searched
value is the feasp t*(θ) of :mod:`lmidsl.solver.feasibility` instead (for feasibility theorems at a
prescribed γ: θ with t*(θ) < 0 makes the LMIs strictly feasible).

γ*(θ) is the solver's optimum, the infimum over the closure of the strict set.  Each point is
solved as :meth:`lmidsl.solver.plan.Plan.solve_point` solves (margin escalation; a non-strict LMI
active at the optimum imposed with the margin) and its LMIs are proved at the returned point
(:mod:`lmidsl.numeric.proof`): ``proved`` means every LMI proved, and the result keeps the best
proved point apart.  Points are ranked by the theorem's objective (minimised), so a performance
that decreases with it (a sector bound k = 1/δ, a radius) is ranked best-first too; the
performance is reported under the theorem's own name.  Points where the solver returns no value
count as +∞.
"""
from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..numeric.instance import Instance
from ..solver.backends import choose_backend, get_backend
from ..numeric.proof import PROVED
from ..solver.feasibility import DEFAULT_RADIUS, JointFeasp
from ..solver.plan import Plan
from ..solver.solution import lmi_certificate
from .defaults import OBJECTIVES
from .parallel import Runner, Task



@dataclass
class SearchPoint:
    """One evaluation: the scalars, the searched value, and what the solve said."""

    params: dict
    value: float
    gamma: float | None = None
    status: str = ""
    proved: bool = False              # every LMI proved at the returned point
    worst_eig: float | None = None
    objective: float | None = None     # the minimised objective (the ranking key with "gamma")

    @property
    def key(self) -> float:
        """What is minimised: the objective (or t*); +∞ without a value."""
        if math.isinf(self.value) or self.objective is None:
            return self.value
        return self.objective

    def as_dict(self) -> dict:
        return {"params": self.params, "value": None if math.isinf(self.value) else self.value,
                "gamma": self.gamma, "objective": self.objective, "status": self.status,
                "proved": self.proved, "worst_eig": self.worst_eig}


@dataclass
class SearchResult:
    theorem: str
    example: str | None
    objective: str
    names: list
    grid: list = field(default_factory=list)
    refined: SearchPoint | None = None
    refinement: dict = field(default_factory=dict)
    evaluations: list = field(default_factory=list)
    performance: str = "gamma"     # the theorem's name of the searched value

    @property
    def best_grid(self) -> SearchPoint | None:
        finite = [p for p in self.grid if math.isfinite(p.value)]
        return min(finite, key=lambda p: p.key, default=None)

    @property
    def best(self) -> SearchPoint | None:
        candidates = [p for p in (self.best_grid, self.refined) if p is not None and math.isfinite(p.value)]
        return min(candidates, key=lambda p: p.key, default=None)

    @property
    def best_proved(self) -> SearchPoint | None:
        """The best point whose LMIs are all proved at the returned point (objective "gamma")."""
        ok = [p for p in self.grid + self.evaluations if p.proved and math.isfinite(p.value)]
        return min(ok, key=lambda p: p.key, default=None)

    @property
    def best_feasible(self) -> SearchPoint | None:
        """The best point with t* < 0 (objective "tmin"): strictly feasible numerically, not proved."""
        ok = [p for p in self.grid + self.evaluations if self.objective == "tmin" and p.value < 0]
        return min(ok, key=lambda p: p.key, default=None)

    def as_dict(self) -> dict:
        pick = lambda p: None if p is None else p.as_dict()  # noqa: E731
        return {"theorem": self.theorem, "example": self.example, "objective": self.objective,
                "performance": self.performance, "names": self.names, "best": pick(self.best), "best_grid": pick(self.best_grid),
                "refined": pick(self.refined), "refinement": self.refinement,
                "best_proved": pick(self.best_proved), "best_feasible": pick(self.best_feasible),
                "grid": [p.as_dict() for p in self.grid],
                "evaluations": [p.as_dict() for p in self.evaluations]}


class Evaluator:
    """θ ↦ SearchPoint on one compiled model (built once, scalars updated as parameters)."""

    def __init__(self, instance: Instance, objective: str, backend: str | None = None,
                 solver: str | None = None, margin: float | None = None, radius: float | None = None,
                 options: dict | None = None):
        backend = choose_backend(backend, solver)
        self.instance = instance
        self.objective = objective
        self.solver = solver
        self.options = dict(options or {})
        self.model = get_backend(backend)(instance, margin=margin, reuse=True)
        self.plan = Plan(backend, solver, self.options, margin)
        self.feasp = JointFeasp(self.model, radius or DEFAULT_RADIUS) if objective == "tmin" else None

    def __call__(self, params: dict) -> SearchPoint:
        instance = self.instance.with_params(**params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if self.feasp is not None:         # t*(θ) of the feasp problem: a diagnosis, not a point
                self.model.update(instance)
                t, status = self.feasp.solve(self.solver)
                return SearchPoint(dict(params), math.inf if t is None else t, status=status)
            sol = self.plan.solve_point(self.model, instance)
        value = sol.point_gamma if sol.ok and sol.point_gamma is not None else math.inf
        proved = False
        if sol.ok and sol.lmis_hold:
            proofs = lmi_certificate(instance, {**instance.data, **sol.values}, prove=True)
            proved = bool(proofs) and all(r.proof == PROVED for r in proofs)
        return SearchPoint(dict(params), value, sol.point_gamma, sol.status, proved, sol.worst_eig,
                           sol.objective if sol.ok else None)


class SearchTask(Task):
    """A worker's part of a grid: one :class:`Evaluator` (one compiled model), many points."""

    def __init__(self, evaluator_args: tuple):
        super().__init__()
        self.evaluator_args = evaluator_args

    def setup(self) -> Evaluator:
        return Evaluator(*self.evaluator_args)


def _check(instance: Instance, names) -> None:
    theorem = instance.theorem
    for name in names:
        if name not in theorem.param_decl:
            known = ", ".join(theorem.param_decl) or "none"
            raise InputError(f"{theorem.id}: cannot search over {name!r}: not a scalar parameter "
                             f"(parameters: {known})")


def evaluate_grid(instance: Instance, points: list[dict], evaluator_args: tuple,
                  workers: int | None = None, progress=None,
                  scheduler: str | None = None) -> list[SearchPoint]:
    """Evaluate every point: in this process (``workers`` None or 1), on a Dask LocalCluster of
    ``workers`` processes, or on the cluster at ``scheduler`` (:mod:`lmidsl.studies.parallel`;
    one compiled model per worker).  ``progress``: a wrapper of the results as they come (e.g.
    :class:`lmidsl.render.progress.Progress`), or None."""
    results = [None] * len(points)
    with Runner(workers if len(points) > 1 or scheduler else None, scheduler) as runner:
        done = runner.map(SearchTask(evaluator_args), points)
        for i, point in (progress(done) if progress else done):
            results[i] = point
    return results


def refine(evaluate: Evaluator, start: SearchPoint, names: list, steps: list,
           bounds: list | None = None, maxfev: int = 80, xatol: float = 1e-4) -> tuple[SearchPoint, dict, list]:
    """Nelder–Mead on θ ↦ value from ``start`` (initial simplex from ``steps``)."""
    from scipy.optimize import minimize

    cache: dict = {}
    seen: list = []

    def f(x):
        key = tuple(np.round(x, 12))
        if key not in cache:
            point = evaluate(dict(zip(names, map(float, x))))
            cache[key] = point
            seen.append(point)
        return cache[key].key

    x0 = np.array([start.params[n] for n in names], dtype=float)
    simplex = [x0] + [x0 + np.eye(len(names))[i] * steps[i] for i in range(len(names))]
    if bounds is not None:
        lo = np.array([b[0] if b[0] is not None else -np.inf for b in bounds])
        hi = np.array([b[1] if b[1] is not None else np.inf for b in bounds])
        simplex = [np.clip(x, lo, hi) for x in simplex]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = minimize(f, x0, method="Nelder-Mead", bounds=bounds,
                       options={"initial_simplex": np.array(simplex), "xatol": xatol,
                                "fatol": 1e-7, "maxfev": maxfev})
    best = min(seen, key=lambda p: p.key) if seen else start
    info = {"method": "Nelder-Mead", "nfev": len(seen), "converged": bool(res.success),
            "message": str(res.message)}
    return best, info, seen


def scalar_search(instance: Instance, axes: dict, objective: str | None = None, *,
                  refine_best: bool = False, workers: int | None = None, progress=None,
                  scheduler: str | None = None,
                  solver: str | None = None, backend: str | None = None, margin: float | None = None,
                  radius: float | None = None, maxfev: int = 80, **options) -> SearchResult:
    """Grid over ``axes`` ({name: [values]}), then (``refine_best``) Nelder–Mead from the best point.

    ``objective``: "gamma" (the theorem's performance at its optimum; default when the theorem
    minimises) or "tmin" (feasp t*; default for feasibility theorems).  ``options``: solver
    keyword options of each solve (not of the feasp solves of "tmin", which refuses them).
    ``workers`` / ``scheduler``: where the grid points are evaluated (:func:`evaluate_grid`); the
    refinement is sequential, in this process.
    """
    backend = choose_backend(backend, solver)
    theorem = instance.theorem
    names = list(axes)
    _check(instance, names)
    if objective is None:
        objective = "gamma" if theorem.objective is not None else "tmin"
    if objective not in OBJECTIVES:
        raise InputError(f"unknown search objective {objective!r}; use one of {', '.join(OBJECTIVES)}")
    if objective == "tmin" and options:
        raise InputError("--solver-option: the tmin search solves feasp problems with their own settings")
    if objective == "gamma" and theorem.objective is None:
        raise InputError(f"{theorem.id} has no objective to minimise; search with objective 'tmin'")
    points = [dict(zip(names, combo)) for combo in itertools.product(*(axes[n] for n in names))]
    if not points:
        raise InputError("the grid is empty")
    args = (instance, objective, backend, solver, margin, radius, options)
    result = SearchResult(theorem.id, instance.example, objective, names,
                          performance=theorem.performance[0] if theorem.performance else "objective")
    result.grid = evaluate_grid(instance, points, args, workers, progress, scheduler)
    start = result.best_grid
    if refine_best and start is not None:
        steps = []
        for n in names:
            values = sorted(set(axes[n]))
            gaps = np.diff(values)
            steps.append(float(gaps.min()) if len(gaps) else max(0.1, 0.1 * abs(values[0])))
        bounds = [theorem.param_decl[n].extra.get("domain") or (None, None) for n in names]
        bounds = None if all(b == (None, None) for b in bounds) else bounds
        result.refined, result.refinement, result.evaluations = refine(
            Evaluator(*args), start, names, steps, bounds, maxfev)
    return result


