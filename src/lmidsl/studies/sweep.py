"""Parameter sweeps: compile once, re-solve per grid point.

The instance is bound and (exactly) rescaled once, the backend model compiled once with every
scalar parameter expression as a backend parameter (cvxpy Parameters, DPP), and each grid point
only sets parameter values (``CompiledModel.update(instance.with_params(...))``) and re-solves.
Per point the sweep records γ, status, the certificate (largest LMI eigenvalue at the returned
point, computed with numpy), the solver-call time (the solver with its interface, as cvxpy
measures it), the solver's own time when it reports one, and the total wall time; the overhead
is the total minus the solver call: parameter update, cvxpy's re-use of its compiled form,
reading values and the certificate.
"""
from __future__ import annotations

import csv
import itertools
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..pipeline import make_instance
from ..numeric.proof import PROVED
from ..solver.margin import solve_model
from ..solver.solution import lmi_certificate
from ..solver.backends import choose_backend, get_backend
from ..errors import InputError, Interrupted
from .parallel import (Runner, Task, check_workers, items_as_finished, start_local_workers_early,
                       worker_state)
from .store import JsonLinesStore, atomic_path, atomic_write_text, strict_json
from ..numeric.scaling import apply_scaling


#: the largest grid a sweep runs unless told otherwise (``--max-points``)
MAX_POINTS = 100_000


def parse_grid(text: str, max_points: int = MAX_POINTS) -> tuple[str, list[float]]:
    """'xi1=0.05:0.95:19' (start:stop:count, inclusive) or 'xi1=0.1,0.5,0.9' → (name, values);
    finite numbers only, at most ``max_points`` values."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name or not spec:
        raise InputError(f"--grid {text!r}: expected NAME=START:STOP:COUNT or NAME=V1,V2,...")
    try:
        if ":" in spec:
            start, stop, count = spec.split(":")
            count = int(count)
            if count < 1:
                raise ValueError
            ends = [float(start), float(stop)]
            if not all(math.isfinite(v) for v in ends):
                raise InputError(f"--grid {text!r}: START and STOP must be finite numbers")
            if count > max_points:
                raise InputError(f"--grid {text!r}: {count} points exceed the maximum of {max_points} "
                                 f"(raise it with --max-points)")
            values = np.linspace(ends[0], ends[1], count).tolist()
        else:
            values = [float(v) for v in spec.split(",")]
            if not all(math.isfinite(v) for v in values):
                raise InputError(f"--grid {text!r}: values must be finite numbers (no nan, inf)")
    except ValueError:
        raise InputError(f"--grid {text!r}: expected NAME=START:STOP:COUNT (COUNT ≥ 1) or NAME=V1,V2,...") from None
    return name, [round(v, 12) for v in values]


def grid_size(grids: list) -> int:
    return math.prod(len(values) for _, values in grids)


def _ratio(a: float, b: float) -> float:
    """a / b, NaN when b is zero or not a number (no ZeroDivisionError on a sweep that failed)."""
    return a / b if b and math.isfinite(b) else float("nan")


@dataclass
class SweepPoint:
    params: dict
    status: str
    gamma: float | None
    objective: float | None
    worst_eig: float | None
    solver_call: float | None
    solver_internal: float | None
    total: float
    proved: bool = False          # every LMI proved at the point (lmidsl.numeric.proof)
    prove_time: float = 0.0

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class SweepResult:
    theorem: str
    example: str | None
    solver: str
    grid: dict
    points: list = field(default_factory=list)
    compile_time: float = 0.0
    first_solve: float = 0.0
    scaling: dict | None = None
    labels: dict = field(default_factory=dict)   # parameter name → LaTeX name (figure axes)
    resumed: int = 0                             # points taken from the store (--resume)
    solved: int = 0                              # points solved by this run

    @classmethod
    def from_dict(cls, d: dict) -> "SweepResult":
        """Read back what :meth:`as_dict` wrote (e.g. to redraw a figure without re-solving)."""
        t = d.get("timing", {})
        return cls(d["theorem"], d.get("example"), d["solver"], d["grid"],
                   [SweepPoint(**p) for p in d["points"]], t.get("compile", 0.0),
                   t.get("first_point", 0.0), d.get("scaling"), d.get("labels", {}))

    def timing(self) -> dict:
        """Mean per-point times, excluding the first point (it sets up the backend model)."""
        pts = self.points[1:] if len(self.points) > 1 else self.points
        calls = [p.solver_call for p in pts if p.solver_call is not None]
        internal = [p.solver_internal for p in pts if p.solver_internal is not None]
        total = float(np.mean([p.total for p in pts])) if pts else float("nan")
        call = float(np.mean(calls)) if calls else float("nan")
        out = {"points_timed": len(pts), "total_per_point": total, "solver_call_per_point": call,
               "overhead_per_point": total - call, "overhead_ratio": _ratio(total - call, call),
               "compile": self.compile_time, "first_point": self.first_solve}
        if internal:
            own = float(np.mean(internal))
            out.update(solver_internal_per_point=own, overhead_vs_solver_internal=_ratio(total - own, own))
        return out

    def as_dict(self) -> dict:
        return {"theorem": self.theorem, "example": self.example, "solver": self.solver,
                "grid": self.grid, "labels": self.labels, "scaling": self.scaling,
                "timing": self.timing(), "certified": self.certified_count(),
                "resumed": self.resumed, "solved": self.solved,
                "points": [p.as_dict() for p in self.points]}

    def certified_count(self) -> int:
        """Points whose every LMI is proved at the returned point (ball arithmetic)."""
        return sum(1 for p in self.points if p.proved)

    def gamma_array(self) -> np.ndarray:
        """γ on the grid as an array of shape (len(values) for each grid parameter)."""
        shape = [len(v) for v in self.grid.values()]
        return np.array([np.nan if p.gamma is None else p.gamma for p in self.points]).reshape(shape)

    def write_csv(self, path) -> None:
        """The points as CSV, written atomically (a reader never sees half a file)."""
        names = list(self.grid)
        with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(names + ["status", "gamma", "objective", "worst_eig", "solver_call_s",
                                "solver_internal_s", "total_s"])
            for p in self.points:
                w.writerow([p.params[n] for n in names] + [p.status, p.gamma, p.objective, p.worst_eig,
                                                            p.solver_call, p.solver_internal, p.total])

    def write_json(self, path) -> None:
        """The result as strict JSON, written atomically."""
        atomic_write_text(path, strict_json(self.as_dict()))


def sweep(theorem, grids: list, example: str | None = None, data: dict | None = None,
          overrides: dict | None = None, solver: str | None = None, backend: str | None = None,
          margin: float | None = None, scaling="auto", progress=None, store=None,
          resume: bool = False, max_points: int = MAX_POINTS, workers: int | None = None,
          scheduler: str | None = None, **options) -> SweepResult:
    """Solve ``theorem`` at every point of the product of ``grids`` = [(name, values), ...].

    ``store``: a JSON Lines file (:class:`~lmidsl.studies.store.JsonLinesStore`) to which each
    point is appended as soon as it is solved; with ``resume`` the points already in it (same
    theorem, example, data and grid) are taken from it, not solved again.  Ctrl-C ends the sweep
    with :class:`~lmidsl.errors.Interrupted`, whose message says how many points are kept where.

    ``workers`` N > 1: the points are solved on a Dask ``LocalCluster`` of N processes, each
    compiling the model once; ``scheduler``: on an existing Dask cluster
    (:mod:`lmidsl.studies.parallel`).  Points are stored as they finish, in any order; the
    result lists them in grid order.
    """
    backend = choose_backend(backend, solver)
    check_workers(workers, scheduler)
    start_local_workers_early(workers, scheduler)
    size = grid_size(grids)
    if size > max_points:
        raise InputError(f"--grid: {size} points exceed the maximum of {max_points} "
                         f"(raise it with --max-points)")
    instance = make_instance(theorem, example, data, overrides)
    thm = instance.theorem
    for name, _ in grids:
        if name not in thm.param_decl:
            raise InputError(f"{thm.id}: --grid {name}: not a parameter (parameters: "
                             f"{', '.join(thm.param_decl) or 'none'})")
    if len({n for n, _ in grids}) != len(grids):
        raise InputError(f"{thm.id}: a grid parameter is given twice")
    for name, values in grids:  # check domains before compiling
        for v in (min(values), max(values)):
            instance.with_params(**{name: v})
    names = [n for n, _ in grids]
    done: dict = {}
    jsonl = None
    if store is not None:
        jsonl = JsonLinesStore(store)
        header = {"kind": "sweep", "theorem": thm.id, "example": instance.example, "data": data,
                  "overrides": overrides, "grid": {n: list(v) for n, v in grids}, "backend": backend,
                  "solver": solver, "margin": margin, "scaling": scaling}
        for record in jsonl.open(header, resume=resume):
            point = SweepPoint(**record)
            done[tuple(point.params[n] for n in names)] = point
    try:
        applied = apply_scaling(instance, scaling)
        task = SweepTask(applied.scaled, backend, margin, solver, options)
        # compiled here too: errors surface before any dispatch, and a serial sweep uses this model
        local = worker_state(task)
        result = SweepResult(thm.id, instance.example, local.model.solver_name(solver),
                             {n: list(v) for n, v in grids}, compile_time=local.compile_time,
                             scaling=applied.as_dict(),
                             labels={n: thm.param_decl[n].latex for n, _ in grids})
        result.resumed = len(done)
        combos = list(itertools.product(*[v for _, v in grids]))
        todo = [combo for combo in combos if combo not in done]
        try:
            with Runner(workers, scheduler) as runner:
                solved = runner.map(task, [dict(zip(names, combo)) for combo in todo])
                finished: dict = {}
                combos_done = items_as_finished(solved, todo, finished.__setitem__)
                for combo in (progress(combos_done) if progress else combos_done):
                    point = finished.popitem()[1]      # the one result put just before its combo
                    if result.solved == 0:
                        result.first_solve = point.total
                    result.solved += 1
                    done[combo] = point
                    if jsonl is not None:
                        jsonl.append(point.as_dict())
        except KeyboardInterrupt:
            where = (f"; they are in {jsonl.path} (run again with --resume to go on)" if jsonl is not None
                     else " and lost (give --out DIR to keep them)")
            raise Interrupted(f"sweep interrupted after {len(done)} of {len(combos)} points{where}") from None
        result.points = [done[combo] for combo in combos]
    finally:
        if jsonl is not None:
            jsonl.close()
    return result


class SweepTask(Task):
    """A worker's part of a sweep: the (scaled) instance compiled once, re-solved per point."""

    def __init__(self, base, backend: str, margin, solver, options: dict):
        super().__init__()
        self.base, self.backend, self.margin, self.solver, self.options = base, backend, margin, solver, options

    def setup(self) -> "SweepSolver":
        return SweepSolver(self)


class SweepSolver:
    """The model of a :class:`SweepTask`, compiled with its parameters as backend parameters."""

    def __init__(self, task: SweepTask):
        self.task = task
        model_class = get_backend(task.backend)  # imports the backend: not part of the compile time
        t0 = time.perf_counter()
        self.model = model_class(task.base, margin=task.margin, reuse=True)  # parameters stay backend parameters
        self.compile_time = time.perf_counter() - t0

    def __call__(self, params: dict) -> SweepPoint:
        task = self.task
        return _solve_point(self.model, task.base, params, task.solver, task.options)


def _solve_point(model, base, params: dict, solver, options) -> SweepPoint:
    t1 = time.perf_counter()
    model.update(base.with_params(**params))
    # with margin escalation, as a single solve: a point must satisfy the strict LMIs
    sol = solve_model(model, solver, restore_margin=True, **options)
    total = time.perf_counter() - t1
    internal = sol.times.get("solver")
    call = sol.times["solver_calls"]
    t2 = time.perf_counter()
    proved = sol.ok and sol.certified and all(
        r.proof == PROVED for r in lmi_certificate(sol.instance, {**sol.instance.data, **sol.values},
                                                   prove=True))
    return SweepPoint(params, sol.status, sol.gamma, sol.objective, sol.worst_eig, call,
                      internal if internal != call else None, total, proved, time.perf_counter() - t2)


def format_timing(t: dict) -> str:
    lines = [f"compile {t['compile'] * 1e3:.1f} ms once; first point {t['first_point'] * 1e3:.1f} ms "
             "(it includes setting up the backend model)",
             f"per point (mean of {t['points_timed']}): total {t['total_per_point'] * 1e3:.1f} ms, "
             f"solver call {t['solver_call_per_point'] * 1e3:.1f} ms, overhead "
             f"{t['overhead_per_point'] * 1e3:.1f} ms = {100 * t['overhead_ratio']:.1f} % of the solver call"]
    if "solver_internal_per_point" in t and math.isfinite(t["solver_internal_per_point"]):
        lines.append(f"(solver's own reported time {t['solver_internal_per_point'] * 1e3:.1f} ms; "
                     f"everything else {100 * t['overhead_vs_solver_internal']:.1f} % of it)")
    return "\n".join(lines)
