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
import hashlib
import itertools
import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..pipeline import make_instance
from ..numeric.evaluate import NumericEvaluator
from ..numeric.proof import PROVED
from ..solver.plan import Plan
from ..solver.status import solved
from ..certify.verdict import Verdict, judge_grid, judge_point
from ..solver.solution import evaluate_performance, lmi_certificate
from ..solver.backends import choose_backend, get_backend
from .. import __version__
from ..errors import InputError, Interrupted, LmidslWarning, NoResultError
from .defaults import MAX_POINTS
from .local_workers import start_for
from .parallel import Runner, Task, check_workers, items_as_finished, worker_state
from .store import JsonLinesStore, atomic_path, atomic_write_text, strict_json
from ..numeric.scaling import apply_scaling


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
    values: dict | None = field(default=None, repr=False, compare=False)   # the solver's point (stores)

    @property
    def verdict(self) -> Verdict:
        """By the judge (:func:`lmidsl.certify.verdict.judge_point`)."""
        return judge_point(self.status, self.gamma, self.proved)

    def as_dict(self) -> dict:
        out = dict(self.__dict__)
        out.pop("values")
        out["verdict"] = self.verdict.as_dict()
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "SweepPoint":
        return cls(**{k: v for k, v in d.items() if k != "verdict"})


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
    parallel: dict = field(default_factory=dict)  # a parallel run's own measurements (studies.parallel)

    @classmethod
    def from_dict(cls, d: dict) -> "SweepResult":
        """Read back what :meth:`as_dict` wrote (e.g. to redraw a figure without re-solving)."""
        t = d.get("timing", {})
        return cls(d["theorem"], d.get("example"), d["solver"], d["grid"],
                   [SweepPoint.from_dict(p) for p in d["points"]], t.get("compile", 0.0),
                   t.get("first_point", 0.0), d.get("scaling"), d.get("labels", {}))

    def timing(self) -> dict:
        """Mean per-point times, excluding the first point (it sets up the backend model)."""
        pts = self.points[1:] if len(self.points) > 1 else self.points
        pts = [p for p in pts if p.solver_call is not None] or pts     # not the resumed points
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
                "timing": self.timing(), "proved_points": self.certified_count(),
                "verdict": self.verdict.as_dict(),
                "resumed": self.resumed, "solved": self.solved,
                **({"parallel": self.parallel} if self.parallel else {}),
                "points": [p.as_dict() for p in self.points]}

    @property
    def verdict(self) -> Verdict:
        """By the judge (:func:`lmidsl.certify.verdict.judge_grid`)."""
        return judge_grid(self.points)

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
    size = grid_size(grids)
    if size > max_points:
        raise InputError(f"--grid: {size} points exceed the maximum of {max_points} "
                         f"(raise it with --max-points)")
    # the fork server's imports overlap the binding, the compile and the first points solved here
    at_once = start_for(workers, scheduler, size)
    instance = make_instance(theorem, example, data, overrides)
    thm = instance.theorem
    for name, _ in grids:
        if name not in thm.param_decl:
            raise InputError(f"{thm.id}: --grid {name}: not a parameter (parameters: "
                             f"{', '.join(thm.param_decl) or 'none'})")
    if len({n for n, _ in grids}) != len(grids):
        raise InputError(f"{thm.id}: a grid parameter is given twice")
    _refuse_member_parameters(thm, grids)
    for name, values in grids:  # check domains before compiling
        for v in (min(values), max(values)):
            instance.with_params(**{name: v})
    names = [n for n, _ in grids]
    done: dict = {}
    jsonl = records = run = None
    if store is not None:
        jsonl = JsonLinesStore(store)
        header = store_header(instance, grids, data=data, overrides=overrides, backend=backend,
                              solver=solver, margin=margin, scaling=scaling, options=options)
        run = header["run"]
        records = jsonl.open(header, resume=resume)
    try:
        applied = apply_scaling(instance, scaling)
        if records:
            done = resumed_points(records, run, grids, applied.scaled, dropped=jsonl.problems, path=jsonl.path)
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
            with Runner(workers, scheduler, start_at_once=at_once) as runner:
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
                        try:
                            jsonl.append(store_record(point, run))
                        except OSError as exc:   # a full disk, a store made read-only
                            raise NoResultError(
                                f"sweep stopped after {len(done) - 1} of {len(combos)} points: cannot write "
                                f"{jsonl.path} ({exc.strerror or exc}); the points stored before are kept "
                                f"(make room, then run again with --resume)") from None
        except KeyboardInterrupt:
            where = (f"; they are in {jsonl.path} (run again with --resume to go on)" if jsonl is not None
                     else " and lost (give --out DIR to keep them)")
            raise Interrupted(f"sweep interrupted after {len(done)} of {len(combos)} points{where}") from None
        result.parallel = runner.stats
        result.points = [done[combo] for combo in combos]
    finally:
        if jsonl is not None:
            jsonl.close()
    return result


def _refuse_member_parameters(member, grids: list) -> None:
    """A parameter that selects the theorem's member (an HPPD degree, Pólya's exponent: the
    size of the expansion) is fixed in the member a sweep compiles once; a grid over other values
    is one line naming the value fixed here and the domain the theorem declares."""
    family = getattr(member, "family", None) or getattr(member, "template", None)
    for name, values in grids:
        fixed = member.param_decl[name].extra.get("domain")
        declared = family.param_decl[name].extra.get("domain") if family is not None and \
            name in family.param_decl else None
        if fixed is None or declared is None or fixed[0] != fixed[1] or tuple(fixed) == tuple(declared):
            continue
        if any(v != fixed[0] for v in values):
            raise InputError(f"{member.id}: --grid {name}: {name} selects the theorem's member (the "
                             f"size of its expansion), fixed at {name} = {fixed[0]:g} for this sweep; "
                             f"give another with --set {name}=K (an integer in [{declared[0]:g}, "
                             f"{declared[1]:g}]), one sweep per value")


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
        self.plan = Plan(task.backend, task.solver, task.options, task.margin)

    def __call__(self, params: dict) -> SweepPoint:
        return _solve_point(self.plan, self.model, self.task.base, params)


def _solve_point(plan: Plan, model, base, params: dict) -> SweepPoint:
    t1 = time.perf_counter()
    sol = plan.solve_point(model, base.with_params(**params))
    total = time.perf_counter() - t1
    internal = sol.times.get("solver")
    call = sol.times["solver_calls"]
    t2 = time.perf_counter()
    reports = lmi_certificate(sol.instance, {**sol.instance.data, **sol.values}, prove=True) \
        if sol.ok and sol.lmis_hold else []
    proved = bool(reports) and all(r.proof == PROVED for r in reports)
    # the worst eigenvalue of the statement at the point: the number a resumed run recomputes
    # from the stored point (_certificate_problem), bit for bit
    worst = max(r.max_eig for r in reports) if reports else sol.worst_eig
    return SweepPoint(params, sol.status, sol.point_gamma, sol.objective, worst, call,
                      internal if internal != call else None, total, proved, time.perf_counter() - t2,
                      values=sol.values if proved else None)


# -- the store of a sweep: identity, records, resume --------------------------------------
def store_header(instance, grids: list, **run) -> dict:
    """What identifies a sweep: theorem, example, a hash of the bound data and parameters, the
    grid, the solve settings and the lmidsl version; ``run``: a hash of all of it, which every
    record carries."""
    bound = strict_json({"data": instance.data, "params": instance.params}, indent=None, note=False)
    header = {"kind": "sweep", "theorem": instance.theorem.id, "example": instance.example,
              "data_sha256": hashlib.sha256(bound.encode()).hexdigest(),
              "grid": {n: list(v) for n, v in grids}, "lmidsl": __version__,
              **{k: v for k, v in run.items() if k not in ("data",)}}
    header["run"] = hashlib.sha256(strict_json(header, indent=None, note=False).encode()).hexdigest()[:16]
    return header


def store_record(point: SweepPoint, run: str) -> dict:
    """A store line: the point's numbers, the solver's point (``values``, for a proved point:
    its certificate is proved again on resume) and the run it belongs to."""
    return {**{k: v for k, v in point.as_dict().items() if k != "verdict"}, "values": point.values, "run": run}


_NUMBERS = ("gamma", "objective", "worst_eig", "solver_call", "solver_internal", "total", "prove_time")


def record_problem(record, run: str, grid_sets: dict) -> str | None:
    """Why a stored record cannot be taken as it is (None: its shape and numbers are sound)."""
    if not isinstance(record, dict):
        return "not an object"
    keys = set(SweepPoint.__dataclass_fields__) | {"run"}
    if set(record) != keys:
        return "keys " + ", ".join(sorted(set(record) ^ keys)) + " missing or extra"
    if record["run"] != run:
        return "from another run"
    params = record["params"]
    if not isinstance(params, dict) or set(params) != set(grid_sets):
        return "parameters are not the grid's"
    for name, value in params.items():
        if not isinstance(value, (int, float)) or isinstance(value, bool) or value not in grid_sets[name]:
            return f"{name} = {value!r} is not a point of the grid"
    for name in _NUMBERS:
        value = record[name]
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                  or not math.isfinite(value)):
            return f"{name} = {value!r} is not a finite number"
    if not isinstance(record["status"], str) or not isinstance(record["proved"], bool):
        return "status or proved of the wrong type"
    if record["proved"] and not isinstance(record["values"], dict):
        return "a proved point without its values"
    return None


def resumed_points(records: list, run: str, grids: list, scaled, dropped=0, path=None) -> dict:
    """The stored points that stand: sound records (:func:`record_problem`), each once, whose
    certificate is proved again at the stored solver point (every LMI in ball arithmetic, and
    the performance figure recomputed there equal to the stored one).

    Every number a resumed point carries is recomputed at its stored point (γ, objective, worst
    eigenvalue, prove time); its status is kept only when it is a solved status (the point is
    proved); its times are this run's: none (``solver_call`` None, left out of
    :meth:`SweepResult.timing`).  A point whose objective is above both its stored neighbours'
    along a grid axis (a local maximum of a minimised objective: a suboptimal point, stored by a
    solver that stopped early or by an edit) is not trusted as optimal and is solved again (a
    true local maximum costs one solve).  A record that is not proved (an infeasible or
    uncertified point) cannot be checked and is solved again, as is every record that fails;
    one warning line says how many and why.  ``dropped``: the store's lines not taken, {reason:
    count} (:attr:`~lmidsl.studies.store.JsonLinesStore.problems`) or their number."""
    names = [n for n, _ in grids]
    grid_sets = {n: set(v) for n, v in grids}
    done: dict = {}
    problems: dict = {}
    if dropped:
        problems.update(dropped if isinstance(dropped, dict) else {"not a record": dropped})
    for record in records:
        reason = record_problem(record, run, grid_sets)
        key = tuple(record["params"][n] for n in names) if reason is None else None
        if reason is None and key in done:
            reason = "a point stored twice"
        if reason is None and not record["proved"]:
            reason = "not proved (solved again)"
        if reason is None and not solved(record["status"]):
            reason = f"status {record['status']!r} with a proved point"
        recomputed = None
        if reason is None:
            reason, recomputed = _certificate_problem(record, scaled)
        if reason is not None:
            problems[reason] = problems.get(reason, 0) + 1
            if reason == "a point stored twice":
                done.pop(key, None)
            continue
        record = {k: v for k, v in record.items() if k not in ("run", "values")}
        done[key] = SweepPoint(**{**record, **recomputed, "solver_call": None, "solver_internal": None,
                                  "total": 0.0})      # times: this run's (none), not the store's
    for key in _local_maxima(done, grids):
        done.pop(key)
        reason = "its objective is above both its neighbours' (not trusted as optimal)"
        problems[reason] = problems.get(reason, 0) + 1
    bad = {k: v for k, v in problems.items() if k != "not proved (solved again)"}
    if bad:
        warnings.warn(f"--resume: {sum(bad.values())} stored record(s) of {path} are solved again ("
                      + "; ".join(f"{n}: {k}" for k, n in bad.items()) + ")", LmidslWarning, stacklevel=2)
    return done


#: relative excess over both neighbours that makes a resumed objective a suspicious local maximum
NEIGHBOUR_TOLERANCE = 1e-6


def _local_maxima(done: dict, grids: list) -> list:
    """The grid points of ``done`` whose objective exceeds both stored neighbours' along some
    axis by more than :data:`NEIGHBOUR_TOLERANCE` (relative)."""
    out = []
    for key, point in done.items():
        if point.objective is None:
            continue
        for axis, (_, values) in enumerate(grids):
            k = values.index(key[axis])
            if not 0 < k < len(values) - 1:
                continue
            around = [done.get(key[:axis] + (values[j],) + key[axis + 1:]) for j in (k - 1, k + 1)]
            if all(p is not None and p.objective is not None and point.objective - p.objective
                   > NEIGHBOUR_TOLERANCE * max(abs(p.objective), 1e-12) for p in around):
                out.append(key)
                break
    return out


def _certificate_problem(record: dict, scaled) -> tuple[str | None, dict | None]:
    """(None, the numbers recomputed at the record's stored point: objective, worst eigenvalue)
    when every LMI is proved there and γ recomputed there is the stored γ; else (what failed, None)."""
    try:
        instance = scaled.with_params(**record["params"])
        values = {}
        for name, value in record["values"].items():
            decl = instance.theorem.var_decl.get(name)
            if decl is None:
                return "values of an unknown variable", None
            per_vertex = getattr(decl.symbol, "per_vertex", False)
            values[name] = [np.asarray(v, dtype=float) for v in value] if per_vertex else \
                (float(value) if not isinstance(value, list) else np.asarray(value, dtype=float))
        point = {**instance.data, **values}
        t0 = time.perf_counter()
        reports = lmi_certificate(instance, point, prove=True)
        prove_time = time.perf_counter() - t0
        gamma = evaluate_performance(instance, point)
        objective = None if instance.theorem.objective is None else float(np.asarray(
            NumericEvaluator(instance.dims, point, instance.params).visit(instance.theorem.objective)).reshape(()))
    except Exception as exc:           # a malformed stored point is a failed record, not a crash
        return f"its stored point does not evaluate ({type(exc).__name__})", None
    if not reports or not all(r.proof == PROVED for r in reports):
        return "its LMIs are not proved at the stored point", None
    stored = record["gamma"]
    if (gamma is None) != (stored is None) or gamma is not None and not math.isclose(gamma, stored, rel_tol=1e-9, abs_tol=1e-300):
        return "its gamma is not the one at the stored point", None
    return None, {"gamma": gamma, "objective": objective, "worst_eig": max(r.max_eig for r in reports),
                  "prove_time": prove_time}


