"""Cross-checking: one instance solved on every backend × solver pair, answers compared.

>>> from lmidsl.studies.cross_check import check
>>> result = check("wang_l2linf.thm3", example="paper-full")
>>> result.agree, [(r.backend, r.solver, r.gamma, r.trusted) for r in result.rows]

Each row is one backend/solver pair solving the same bound instance.  Two levels of belief:

* **certified** — the returned point satisfies every LMI (largest eigenvalue of each ``N`` in
  ``N ≺ 0`` negative, evaluated with numpy, see :func:`lmidsl.solver.solution.lmi_certificate`) and,
  where the theorem has an analysis counterpart, the analysis certifies the recovered filter at
  the synthesis level.  A certified row's γ is a *valid upper bound*; it need not be the optimum.
* **trusted** — certified, *and* the solver claims full accuracy: status ``optimal`` (not
  ``optimal_inaccurate``) from a solver that is not first-order (:func:`lmidsl.solver.backends.is_first_order`).
  A first-order solver (SCS) stops when its scaled residuals are below ~1e-4; on these LMIs its
  point is typically feasible but γ is off by ~1e-2, so its row is shown with its deviation and
  counted as a certified bound only.

The answers compared are γ (the theorem's performance figure) or else the objective.  The
reference is the smallest value among trusted rows (a certified point proves its γ is
attainable, so the smallest one is the best known answer); a trusted row more than
``tolerance`` (relative, default :data:`DEFAULT_TOLERANCE`) above it **disagrees**.  Every row,
trusted or not, shows its relative deviation from the reference, so loose solvers stay visible.
A solver that fails (not installed, raises, returns no point) is a row carrying its error.
"""
from __future__ import annotations

import statistics
import time
import warnings
from dataclasses import dataclass, field

from ..pipeline import make_instance, solve_instance
from ..solver.plan import Plan
from ..certify.verdict import Verdict, judge_agreement
from ..solver.status import OPTIMAL
from ..solver.backends import (BACKENDS, DEFAULT_BACKEND, backend_info, options_for, SOLVER_INFO, backend_sdp_solvers, is_first_order,
                               resolve_solver)
from ..errors import InputError, LmidslError
from .defaults import DEFAULT_TOLERANCE, FIRST_ORDER_CAP
from .parallel import Runner, Task, check_workers, items_as_finished

MIN_CAP = 2.0
"""The shortest time limit a first-order row gets, seconds."""


def capped(solver: str, options: dict, cap: float | None) -> dict:
    """A first-order row's options with the time limit ``cap`` (SCS's ``time_limit_secs``), unless
    the user set one."""
    if cap is None or not is_first_order(solver) or "time_limit_secs" in options:
        return options
    return {**options, "time_limit_secs": cap}

#: Solvers whose "optimal" is a first-order residual test (~1e-4 scaled), not an
#: interior-point duality gap; their certified rows are bounds, never the reference.


@dataclass
class CheckRow:
    """One backend/solver pair's answer and how far it can be believed."""

    backend: str
    solver: str
    options: dict = field(default_factory=dict)
    status: str = "not run"
    message: str = ""
    error: str | None = None
    objective: float | None = None
    gamma: float | None = None                         # the verdict's level (the row's one number)
    optimum_level: float | None = None                 # the SDP optimum's level: what rows compare
    lmis: list = field(default_factory=list)          # LMIReport.as_dict() per LMI (and vertex)
    analysis_theorem: str | None = None
    analysis_gamma: float | None = None
    analysis_passed: bool | None = None               # None: theorem has no analysis counterpart
    wall_time: float = 0.0
    solver_time: float | None = None
    backoff_gamma: float | None = None                 # the design's γ when solve backed off
    optimum_lmis: list = field(default_factory=list)   # the optimum's certificate, then
    holds: bool = False                                # the LMIs hold numerically at the point (and the
                                                       # analysis passes): a row to compare, not a proof
    trusted: bool = False
    reason: str = ""                                   # why the LMIs do not hold / the row is not trusted
    value: float | None = None                         # the compared number (γ or objective)
    rel_diff: float | None = None                      # (value − reference) / |reference|
    disagrees: bool = False
    verdict: dict | None = None                        # the row's solve's verdict record
    capped: float | None = None                        # a first-order row's time limit, seconds

    @property
    def name(self) -> str:
        return f"{self.backend}/{self.solver}"

    def max_eig_by_label(self) -> dict:
        """Largest eigenvalue per LMI label (worst over vertices)."""
        out: dict = {}
        for r in self.lmis:
            out[r["label"]] = max(out.get(r["label"], float("-inf")), r["max_eig"])
        return out

    def as_dict(self) -> dict:
        return {
            "backend": self.backend, "solver": self.solver, "options": self.options,
            "status": self.status, "message": self.message, "error": self.error,
            "objective": self.objective, "gamma": self.gamma, "optimum_level": self.optimum_level,
            "lmis": self.lmis,
            "max_eig": self.max_eig_by_label(),
            "analysis": None if self.analysis_passed is None and self.analysis_gamma is None else
            {"theorem": self.analysis_theorem, "gamma": self.analysis_gamma, "passed": self.analysis_passed},
            "wall_time": self.wall_time, "solver_time": self.solver_time,
            "backoff_gamma": self.backoff_gamma,
            "holds": self.holds, "trusted": self.trusted, "reason": self.reason,
            "value": self.value, "rel_diff": self.rel_diff, "disagrees": self.disagrees,
            "verdict": self.verdict, "capped": self.capped,
        }


@dataclass
class CrossCheck:
    """All rows of a cross-check and the verdict."""

    theorem: str
    example: str | None
    compared: str                                      # "gamma" (performance name) or "objective"
    tolerance: float
    rows: list[CheckRow]
    reference: CheckRow | None = None

    @property
    def trusted(self) -> list[CheckRow]:
        return [r for r in self.rows if r.trusted]

    @property
    def disagreeing(self) -> list[CheckRow]:
        return [r for r in self.rows if r.disagrees]

    @property
    def agree(self) -> bool:
        """At least one trusted row, and no trusted row beyond the tolerance."""
        return bool(self.trusted) and not self.disagreeing

    @property
    def spread(self) -> float | None:
        """(max − min)/|min| of the compared value over trusted rows."""
        values = [r.value for r in self.trusted if r.value is not None]
        if len(values) < 1 or self.reference is None:
            return None
        return (max(values) - min(values)) / _scale(min(values))

    @property
    def exit_code(self) -> int:
        """0 when the trusted answers agree, 1 when they disagree or no answer is trusted."""
        return 0 if self.agree else 1

    @property
    def verdict(self) -> Verdict:
        """By the judge (:func:`lmidsl.certify.verdict.judge_agreement`); the headline is the row
        `lmidsl solve`'s own route gives (the default backend and solver) when that row is
        trusted, else the reference row's."""
        default = backend_info(DEFAULT_BACKEND).default.lower()
        own = next((r for r in self.trusted if r.backend == DEFAULT_BACKEND and r.solver.lower() == default
                    and not r.disagrees), self.reference)
        return judge_agreement(self, own)

    def summary(self) -> str:
        """The agreement in one sentence."""
        if not self.trusted:
            counts: dict = {}
            for r in self.rows:
                counts[r.status] = counts.get(r.status, 0) + 1
            seen = ", ".join(f"{k} x{v}" for k, v in counts.items())
            return ("NO TRUSTED ANSWER: no row certifies its point with a solver claiming full "
                    f"accuracy (statuses: {seen})")
        ref = self.reference
        what = f"{self.compared} = {ref.value:.8g} ({ref.name})" if ref and ref.value is not None else "no value"
        if self.disagreeing:
            names = ", ".join(f"{r.name} ({r.value:.8g}, +{r.rel_diff:.2e})" for r in self.disagreeing)
            return (f"DISAGREEMENT beyond {self.tolerance:g} (relative on {self.compared}): best {what}; "
                    f"trusted rows above it: {names}")
        if len(self.trusted) == 1:
            return f"one trusted row only, nothing to compare: {what}"
        spread = self.spread
        # the same solver behind two modelling layers (direct:CLARABEL, cvxpy:CLARABEL) is one
        # solver's opinion twice: say how many different solvers agree
        solvers = len({r.solver.lower() for r in self.trusted})
        return (f"{len(self.trusted)} trusted row(s) of {solvers} solver(s) agree within {self.tolerance:g} "
                f"(relative on {self.compared}): best {what}" + (f", spread {spread:.1e}" if spread is not None else ""))

    def as_dict(self) -> dict:
        return {
            "theorem": self.theorem, "example": self.example, "compared": self.compared,
            "tolerance": self.tolerance,
            "reference": None if self.reference is None else
            {"backend": self.reference.backend, "solver": self.reference.solver, "value": self.reference.value},
            "agree": self.agree, "spread": self.spread, "exit_code": self.exit_code,
            "trusted": [r.name for r in self.trusted],
            "disagreeing": [r.name for r in self.disagreeing],
            "verdict": self.verdict.as_dict(), "gamma": self.verdict.gamma,
            "rows": [r.as_dict() for r in self.rows],
        }


def _scale(x: float) -> float:
    return max(abs(x), 1e-12)


# -- which rows --------------------------------------------------------------------------
def _backend_solvers(backend: str) -> tuple[list[str], str | None]:
    """(installed SDP solvers of a backend, error text if the backend cannot be used)."""
    try:
        return backend_sdp_solvers(backend), None
    except LmidslError as exc:
        return [], str(exc)


def plan_rows(solvers=None) -> list[tuple[str, str, str | None]]:
    """(backend, solver, error) for each requested row.

    ``solvers`` is None (every backend × every installed SDP solver), or a list / comma-separated
    string of entries ``backend:solver``, ``backend`` (all its SDP solvers) or ``solver`` (every
    backend that has it installed).  An entry no backend can run becomes an error row.
    """
    if isinstance(solvers, str):
        solvers = [s for s in solvers.split(",")]
    entries = [s.strip() for s in (solvers or BACKENDS) if s and s.strip()]
    if not entries:
        raise InputError("--solvers: give at least one backend, solver or backend:solver")
    rows: list[tuple[str, str, str | None]] = []

    def add(backend, solver, error=None):
        key = (backend, solver.lower())
        if all((b, s.lower()) != key for b, s, _ in rows):
            rows.append((backend, solver, error))

    for entry in entries:
        backend, sep, solver = entry.partition(":")
        backend, solver = backend.strip().lower(), solver.strip()
        if sep:
            if backend not in BACKENDS:
                raise InputError(f"--solvers {entry}: unknown backend {backend!r}; available: {', '.join(BACKENDS)}")
            try:
                add(backend, resolve_solver(backend, solver))
            except LmidslError as exc:
                add(backend, solver, str(exc))
        elif backend in BACKENDS:
            names, error = _backend_solvers(backend)
            if error:
                add(backend, "-", error)
            for name in names:
                add(backend, name)
        else:
            name = entry.strip()
            found = False
            for b in BACKENDS:
                names, _ = _backend_solvers(b)
                match = [s for s in names if s.lower() == name.lower()]
                if match:
                    add(b, match[0])
                    found = True
            if not found and name.lower() not in SOLVER_INFO:
                known = sorted({s.lower() for b in BACKENDS for s in _backend_solvers(b)[0]})
                raise InputError(f"--solvers {name}: no backend knows a solver {name!r}; installed: "
                                 f"{', '.join(known) or 'none'} (or a backend: {', '.join(BACKENDS)})")
            if not found:
                errors = []
                for b in BACKENDS:
                    try:
                        resolve_solver(b, name)
                    except LmidslError as exc:
                        errors.append(f"{b}: {exc}")
                add(BACKENDS[0], name, "; ".join(errors) or f"no backend has solver {name!r}")
    return rows


# -- running ------------------------------------------------------------------------------
class CheckTask(Task):
    """The rows of one instance: a worker solves (backend, solver, options) items."""

    def __init__(self, instance, margin, certify: bool):
        super().__init__()
        self.instance, self.margin, self.certify = instance, margin, certify

    def setup(self):
        return self.row

    def row(self, item) -> CheckRow:
        backend, solver, options = item
        return run_row(self.instance, backend, solver, options, margin=self.margin, certify=self.certify)


def run_row(instance, backend: str, solver: str, options: dict, margin=None, certify=True) -> CheckRow:
    """Solve one row; every failure is recorded in the row, never raised."""
    row = CheckRow(backend, solver, dict(options))
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:  # solver warnings go into the row
            warnings.simplefilter("always")
            # the automatic back-off of `lmidsl solve`, except for a first-order solver (its
            # point is not accurate enough for the back-off's level problem and search)
            automatic = certify and not is_first_order(solver)
            plan = Plan(backend, solver, options, margin, fallbacks=False, closed_forms=False)
            # nor its proved dual bound: a first-order row is never trusted, and the bound's own
            # solves would each take up to the row's time limit
            sol = solve_instance(instance, certify=certify, backoff="auto" if automatic else None, plan=plan,
                                 bounds=not is_first_order(solver))
    except LmidslError as exc:
        row.status, row.error = "error", str(exc)
    except Exception as exc:  # a solver crash is an answer too: a row with its error
        text = str(exc).splitlines()[0] if str(exc) else ""
        row.status, row.error = "error", f"{type(exc).__name__}: {text}".rstrip(": ")
    else:
        notes = [sol.message] if sol.message else []
        for w in caught:
            text = str(w.message).split(".")[0].strip()
            if text and text not in notes:
                notes.append(text)
        row.status, row.message = sol.status, "; ".join(notes)
        row.objective, row.optimum_level = sol.objective, sol.point_gamma
        backoff = sol.backoff or {}
        if "objective_opt" in backoff:
            # as `lmidsl solve`: the design recovered at the optimum was not certified, so the
            # design is the back-off point's; the value compared is the optimum's, on which the
            # solvers must agree (back-off points of different solvers differ by up to δ)
            row.objective, row.optimum_level = backoff["objective_opt"], backoff.get("gamma_opt")
            row.status = backoff.get("status_opt", row.status)     # the solve whose value is compared
            row.backoff_gamma = sol.point_gamma
            row.optimum_lmis = list(backoff.get("optimum_lmis") or [])
            row.message = "; ".join([*notes, f"design from the automatic back-off at {_gamma_text(sol)}"])
        row.lmis = [r.as_dict() for r in sol.lmis]
        row.verdict = sol.verdict.as_dict()
        row.gamma = row.verdict["gamma"]
        row.solver_time = sol.times.get("solver")
        analysis = sol.analysis
        if analysis is not None:
            row.analysis_theorem, row.analysis_gamma = analysis.theorem, analysis.gamma
            row.analysis_passed = analysis.passed
        _judge(row, sol, instance)
    row.wall_time = time.perf_counter() - t0
    if row.error:
        row.reason = "error"
    return row


def _judge(row: CheckRow, sol, instance) -> None:
    """Set certified / trusted and the reason for each verdict."""
    theorem = instance.theorem
    if not sol.ok:
        row.reason = f"no point (status {sol.status})"
        return
    if not sol.lmis:
        row.reason = "no certificate evaluated"
        return
    worst = max(sol.lmis, key=lambda r: r.max_eig)
    if worst.max_eig >= 0:
        where = f" @ vertex {worst.vertex}" if worst.vertex is not None else ""
        row.reason = f"certificate fails: max eig of {worst.label}{where} = {worst.max_eig:+.2e}"
        return
    if row.optimum_lmis and max(r["max_eig"] for r in row.optimum_lmis) >= 0:
        row.reason = "certificate fails at the optimum (the back-off point's holds)"
        return
    needs_analysis = theorem.analysis is not None and bool(theorem.recovery)
    if needs_analysis and row.analysis_passed is False:
        g = "infeasible" if row.analysis_gamma is None else f"gamma {row.analysis_gamma:.6g}"
        row.reason = f"analysis does not certify the recovered design ({g})"
        return
    row.holds = True
    if row.status != OPTIMAL:
        row.reason = f"certified bound only: solver status {row.status}"
    elif is_first_order(row.solver):
        row.reason = "certified bound only: first-order solver (low accuracy)"
    else:
        row.trusted = True
        row.reason = "trusted"


def _gamma_text(sol) -> str:
    value = sol.point_gamma if sol.point_gamma is not None else sol.objective
    return "no value" if value is None else f"{'γ' if sol.point_gamma is not None else 'objective'} {value:.8g}"


def compare(rows: list[CheckRow], tolerance: float) -> CheckRow | None:
    """Reference = smallest compared value among trusted rows; set rel_diff and disagreement."""
    trusted = [r for r in rows if r.trusted and r.value is not None]
    reference = min(trusted, key=lambda r: r.value, default=None)
    if reference is None:
        return None
    for r in rows:
        if r.value is not None:
            r.rel_diff = (r.value - reference.value) / _scale(reference.value)
            r.disagrees = r.trusted and r.rel_diff > tolerance
    return reference


def check(theorem, example: str | None = None, data: dict | None = None,
          overrides: dict | None = None, solvers=None, options: dict | None = None,
          tolerance: float = DEFAULT_TOLERANCE, margin: float | None = None,
          certify: bool = True, progress=None, workers: int | None = None,
          scheduler: str | None = None, first_order_cap: float = FIRST_ORDER_CAP) -> CrossCheck:
    """Solve one instance on every requested backend × solver and compare the answers.

    ``solvers``: see :func:`plan_rows`.  ``options``: ``{"clarabel": {...}}`` or
    ``{"cvxpy:clarabel": {...}}``, passed to that row's solve (backend-specific names, e.g.
    cvxpy's ``max_iter`` for Clarabel, PICOS's ``max_iterations``); the key ``""`` is for every
    row.  ``progress(plan)`` wraps the planned (backend, solver, error) rows that are solved, in
    the order they finish (e.g. a progress bar).  ``workers`` / ``scheduler``: the rows run in
    parallel on Dask (:mod:`lmidsl.studies.parallel`); each row's ``time s`` is then measured on
    a machine shared with the other rows.  ``first_order_cap``: a first-order solver's row (SCS,
    never trusted) runs after the others with a time limit of this multiple of the slowest
    interior-point rows' median wall time (at least :data:`MIN_CAP` seconds; 0: no limit; an explicit
    ``time_limit_secs`` option wins); a capped row says so.
    """
    check_workers(workers, scheduler)
    if not tolerance > 0:
        raise InputError(f"--tolerance must be positive, got {tolerance}")
    instance = make_instance(theorem, example, data, overrides)
    thm = instance.theorem
    compared = thm.performance[0] if thm.performance is not None else "objective"
    plan = plan_rows(solvers)
    rows = [CheckRow(backend, solver, status="error", error=error, reason="error") if error else None
            for backend, solver, error in plan]
    todo = [i for i, row in enumerate(rows) if row is None]
    exact = [i for i in todo if not is_first_order(plan[i][1])]
    first_order = [i for i in todo if is_first_order(plan[i][1])]
    with Runner(workers if len(todo) > 1 or scheduler else None, scheduler) as runner:
        task = CheckTask(instance, margin, certify)

        def run(indices, cap=None):
            items = [(plan[i][0], plan[i][1], capped(plan[i][1], options_for(plan[i][0], plan[i][1], options), cap))
                     for i in indices]

            def put(index, row):
                rows[indices[index]] = row
                backend, solver, _ = plan[indices[index]]
                if cap is not None and "time_limit_secs" not in options_for(backend, solver, options):
                    row.capped = cap
                    row.reason += f"; capped at {cap:.1f} s ({first_order_cap:g}× the interior-point time)"

            finished = items_as_finished(runner.map(task, items), [plan[i] for i in indices], put)
            for _ in (progress(finished) if progress else finished):
                pass

        run(exact)
        # a first-order row (SCS) is never trusted: it gets a small multiple of the interior-point
        # rows' time, not the minutes it can take on these LMIs (0 or no interior-point row: no cap)
        times = [rows[i].wall_time for i in exact if rows[i].error is None]
        run(first_order, max(first_order_cap * statistics.median(times), MIN_CAP) if first_order_cap and times else None)
    for r in rows:
        r.value = r.optimum_level if thm.performance is not None else r.objective
    reference = compare(rows, tolerance)
    return CrossCheck(thm.id, instance.example, compared, tolerance, rows, reference)
