"""The main job: every theorem × example, printed value against computed value, with evidence.

For each example that prints a γ, the theorem is solved; the row holds the printed γ, the
computed γ, their relative difference, the certificate (largest LMI eigenvalue at the returned
point), and for synthesis theorems the γ that the analysis counterpart certifies for the
recovered filter.  ``tolerance`` is the relative difference under which a value counts as
reproduced.  Where the theorem (or its analysis counterpart) declares an error system, the row
also holds the exact mean-square figure of the filter (no LMI, :mod:`lmidsl.certify.figures`),
which must not exceed the computed γ; otherwise the row is not certified.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, fields

from ..pipeline import make_instance, solve
from .bisection import bisect
from ..errors import Interrupted, LmidslError
from ..solver.backends import DEFAULT_BACKEND
from ..solver.status import solved
from ..theorem.registry import all_theorems, get_theorem
from ..theorem.values import OUTCOMES, PROVENANCE
from ..certify.verdict import NOT_SOLVED, judge_error, refute
from .parallel import Runner, Task, check_workers, items_as_finished, start_local_workers_early
from .store import JsonLinesStore
from .verify import figures_for_solution, worst_index

REPRODUCED_TOLERANCE = 5e-3
EXACT_TOLERANCE = 1e-3  # relative: the exact figure may exceed the solved γ by solver accuracy only


@dataclass
class ReproductionRow:
    theorem: str
    example: str
    printed_kind: str
    printed_gamma: float | None
    computed_gamma: float | None
    rel_diff: float | None
    status: str
    worst_eig: float | None
    certified_gamma: float | None
    certified: bool
    comparison: str                 # printed vs computed, in words
    exact_kind: str | None = None
    exact_gamma: float | None = None
    mean_square_stable: bool | None = None
    spectral_radius: float | None = None
    exact_ok: bool | None = None
    provenance: str = "paper"
    expect: str = "certified"
    verdict: dict | None = None     # the solve's verdict record (lmidsl.certify.verdict), refuted by
                                    # an exact figure above the certified level
    bounds: dict | None = None      # the optimum's bracket: proved lower bound, proved optimum level
    wall_time: float | None = None  # seconds the row took where it ran (solve, proofs, evidence)

    @property
    def outcome(self) -> str:
        """One of :data:`~lmidsl.theorem.values.OUTCOMES`."""
        if self.certified:
            return "certified"
        if (self.verdict or {}).get("word") == "infeasible":
            return "infeasible"                # proved (lmidsl.certify.infeasibility)
        if (self.verdict or {}).get("word") == NOT_SOLVED:
            return "not solved"                # no point (feasp's "infeasible" is not a proof)
        if self.computed_gamma is not None or solved(self.status):
            return "not certified"
        return "not solved"

    @property
    def as_expected(self) -> bool:
        """Ends no worse than its example expects (OUTCOMES is ordered best first)."""
        return OUTCOMES.index(self.outcome) <= OUTCOMES.index(self.expect)

    def as_dict(self) -> dict:
        return {**asdict(self), "gamma": (self.verdict or {}).get("gamma"), "outcome": self.outcome,
                "as_expected": self.as_expected}


def _comparison(kind, printed, computed, rel, certified, sol) -> str:
    """The printed value against the computed one, in words; without a point to use, the
    verdict's word (``infeasible`` only when proved)."""
    if not sol.ok:
        return sol.verdict.word
    if printed is None:
        verdict = "computed (no printed value)"
    elif computed is None:
        verdict = "no level computed"
    elif kind == "gamma_bound":
        holds = computed <= printed * (1 + REPRODUCED_TOLERANCE)
        verdict = "printed bound holds" if holds else "printed bound NOT certified"
    else:
        verdict = "reproduced" if rel <= REPRODUCED_TOLERANCE else "differs from print"
    return verdict + ("" if certified else ", NOT certified")


def row_provenance(theorem, example: str) -> str:
    """'paper' when both the theorem and the example are the paper's own, else the theorem's
    provenance if it is not the paper's, else the example's."""
    if theorem.provenance != "paper":
        return theorem.provenance
    return theorem.examples[example].provenance


def reproduce_one(theorem_id: str, example: str, solver: str | None = None, **solve_options) -> ReproductionRow:
    """One row: ``theorem_id`` solved on ``example`` (``solve_options``: backend, margin and
    solver keyword options, as :func:`lmidsl.pipeline.solve` takes them)."""
    theorem = get_theorem(theorem_id)
    provenance = row_provenance(theorem, example)
    expect = theorem.examples[example].expect
    printed_values = theorem.examples[example].printed
    kind = "gamma_bound" if "gamma_bound" in printed_values else "gamma"
    printed = printed_values.get(kind)
    try:
        spec = getattr(theorem, "bisection", None)    # a GEVP: bisected as `lmidsl solve` does
        if spec is not None and spec.parameter not in theorem.examples[example].params:
            bisection = bisect(make_instance(theorem, example), solver=solver, **solve_options)
            if bisection.solution is None:
                raise LmidslError(bisection.verdict.why)
            sol = bisection.solution
        else:
            sol = solve(theorem, example=example, solver=solver, backoff="auto", **solve_options)
    except LmidslError as exc:
        return ReproductionRow(theorem_id, example, kind, printed, None, None, f"error: {exc}", None,
                               None, False, "error", provenance=provenance, expect=expect,
                               verdict=judge_error(str(exc)).as_dict())
    # after an automatic back-off the optimum is what compares with the printed value
    computed = (sol.backoff or {}).get("gamma_opt", sol.point_gamma) if sol.backoff else sol.point_gamma
    rel = None
    if printed is not None and computed is not None:
        rel = abs(computed - printed) / abs(printed)
    analysis = sol.analysis
    certified = sol.verdict.certified      # every LMI proved, the analysis and the checks pass
    figure = _exact(sol)
    exact_ok = None
    if figure is not None and sol.point_gamma is not None:
        exact_ok = figure.value is not None and figure.value <= sol.point_gamma * (1 + EXACT_TOLERANCE)
        certified = certified and exact_ok
    verdict = _comparison(kind, printed, computed, rel, certified, sol)
    if exact_ok is False:
        verdict += (", NOT mean-square stable" if figure.value is None
                    else ", exact figure EXCEEDS γ")
    if sol.backoff and "gamma" in sol.backoff:
        verdict += f" (design from the back-off at γ {sol.backoff['gamma']:.6g})"
    record = sol.verdict
    if exact_ok is False:
        why = "not mean-square stable" if figure.value is None else \
            f"the exact figure {figure.value:.6g} exceeds the certified level"
        record = refute(record, why)
    row = ReproductionRow(theorem_id, example, kind, printed, computed, rel, sol.status,
                          sol.worst_eig, analysis.gamma if analysis is not None else None, certified,
                          verdict, provenance=provenance, expect=expect, verdict=record.as_dict(),
                          bounds=record.bracket)
    if figure is not None:
        row.exact_kind, row.exact_gamma = figure.kind, figure.value
        row.mean_square_stable, row.spectral_radius = figure.mean_square_stable, figure.spectral_radius
        row.exact_ok = exact_ok
    return row


def _exact(sol):
    """The exact figure (worst vertex) of the solved filter, when the theorem declares one."""

    if not sol.ok:
        return None
    figures = figures_for_solution(sol)
    return None if not figures else figures[worst_index(figures)]


class ReproduceTask(Task):
    """Rows of ``reproduce``: a worker runs (theorem id, example) items with one solver and the
    same solve options (:func:`reproduce_one`)."""

    def __init__(self, solver: str | None, solve_options: dict | None = None):
        super().__init__()
        self.solver, self.solve_options = solver, dict(solve_options or {})

    def setup(self):
        return self.row

    def row(self, job) -> ReproductionRow:
        start = time.perf_counter()
        row = reproduce_one(*job, self.solver, **self.solve_options)
        row.wall_time = time.perf_counter() - start
        return row


def reproduce_all(solver: str | None = None, theorems: list[str] | None = None, progress=None,
                  store=None, resume: bool = False, workers: int | None = None,
                  scheduler: str | None = None, **solve_options):
    """Rows for every theorem × example (optionally only the listed theorem ids), the papers'
    own first, then corrected and guessed readings, then illustrations (:data:`PROVENANCE`).

    ``store``: a JSON Lines file each row is appended to when it is done; with ``resume`` the rows
    already there (same solver and theorem selection) are kept, not run again.  Ctrl-C ends the
    job with :class:`~lmidsl.errors.Interrupted` saying how many rows are kept where.
    ``progress(jobs)`` wraps the (theorem id, example) pairs that are run, in the order they
    finish (e.g. a progress bar); ``solve_options``: see :func:`reproduce_one`.
    ``workers`` / ``scheduler``: rows run in parallel on Dask (:mod:`lmidsl.studies.parallel`;
    workers find the theorems by id in their own registry), stored as they finish."""
    check_workers(workers, scheduler)
    start_local_workers_early(workers, scheduler)
    order = list(PROVENANCE)
    for tid in theorems or []:
        get_theorem(tid)                  # an unknown id is a one-line error, not zero rows
    jobs = [(tid, ex) for tid, thm in sorted(all_theorems().items())
            if theorems is None or tid in theorems for ex in thm.examples]
    jobs.sort(key=lambda job: order.index(row_provenance(get_theorem(job[0]), job[1])))
    done = {}
    jsonl = None
    if store is not None:
        jsonl = JsonLinesStore(store)
        header = {"kind": "reproduce", "solver": solver, "theorems": sorted(theorems) if theorems else None}
        chosen = {k: v for k, v in solve_options.items()      # defaults leave the header as it was
                  if v is not None and (k, v) != ("backend", DEFAULT_BACKEND)}
        if chosen:
            header["options"] = chosen
        names = {f.name for f in fields(ReproductionRow)}
        for record in jsonl.open(header, resume=resume):
            row = ReproductionRow(**{k: v for k, v in record.items() if k in names})
            done[(row.theorem, row.example)] = row
    todo = [job for job in jobs if job not in done]
    try:
        with Runner(workers, scheduler) as runner:
            finished = items_as_finished(runner.map(ReproduceTask(solver, solve_options), todo), todo,
                                         lambda index, row: done.__setitem__(todo[index], row))
            for job in (progress(finished) if progress else finished):
                if jsonl is not None:
                    jsonl.append(done[job].as_dict())
    except KeyboardInterrupt:
        where = (f"; they are in {jsonl.path} (run again with --resume to go on)" if jsonl is not None
                 else " and lost (give --out DIR to keep them)")
        raise Interrupted(f"reproduce interrupted after {len(done)} of {len(jobs)} rows{where}") from None
    finally:
        if jsonl is not None:
            jsonl.close()
    return [done[job] for job in jobs]
