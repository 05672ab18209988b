"""Every sentence a command prints about a result, from one printer (sympy's ``Printer`` pattern:
one ``_print_<Class>`` method per result class, found along the class's MRO).

:func:`text` prints any result: a :class:`~lmidsl.solver.solution.Solution` and a verification
(:mod:`.report`), a bisection (:mod:`.bisection`), the feasp diagnosis, a cross-check of solvers,
a sweep (its points, timing and parallel measurements), a scalar search, a successive-LMI run and
an export.  The headline of each is its verdict's (:mod:`lmidsl.certify.verdict`): nothing here
works a verdict out again.
"""
from __future__ import annotations

import math
from pathlib import Path

from .bisection import format_bisection
from .report import format_feasp, format_solution, format_verification, performance_label
from .table import format_matrix, format_table
from .terminal import Settings, wrap


class TextPrinter:
    """``doprint(result, **options)``: the text of ``result`` by the ``_print_<Class>`` method of
    the first class in its MRO that has one."""

    def doprint(self, result, **options) -> str:
        for cls in type(result).__mro__:
            method = getattr(self, f"_print_{cls.__name__}", None)
            if method is not None:
                return method(result, **options)
        raise TypeError(f"no text printer for {type(result).__name__}")

    def _print_Solution(self, sol, **_):
        return format_solution(sol)

    def _print_Verification(self, result, **_):
        return format_verification(result)

    def _print_BisectionResult(self, result, **_):
        return format_bisection(result)

    def _print_FeasibilityReport(self, report, indent: str = "  ", **_):
        return format_feasp(report, indent)

    def _print_CrossCheck(self, result, **_):
        return format_check(result)

    def _print_SweepResult(self, result, out=None, **_):
        return format_sweep(result, out)

    def _print_SearchResult(self, result, top: int = 8, **_):
        return format_result(result, top)

    def _print_BMIResult(self, result, theorem_id: str = "", **_):
        return format_successive(result, theorem_id)


def text(result, **options) -> str:
    """The text of any result (:class:`TextPrinter`)."""
    return TextPrinter().doprint(result, **options)


def _fmt(x, spec=".6g"):
    return "" if x is None else format(x, spec)


def format_check(result) -> str:
    labels: list[str] = []
    for r in result.rows:
        for label in r.max_eig_by_label():
            if label not in labels:
                labels.append(label)
    # the objective only at full width (--wide) when it is not the compared value itself
    objective = Settings.wide and result.compared != "objective"
    compared = "optimum" if result.compared == "objective" else f"optimum {result.compared}"
    headers = ["backend:solver", "status"] + (["objective"] if objective else []) + [
        compared, "max eig", "gamma", "verdict", "time s", "trust", "rel diff"]
    rows = []
    for r in result.rows:
        eigs = [e for e in r.max_eig_by_label().values() if e is not None]
        word = (r.verdict or {}).get("word", "")
        rel = "" if r.rel_diff is None else f"{r.rel_diff:+.1e}" + (" !" if r.disagrees else "")
        rows.append([f"{r.backend}:{r.solver}", r.status] + ([_fmt(r.objective, ".8g")] if objective else [])
                    + [_fmt(r.value, ".8g"), _fmt(max(eigs) if eigs else None, ".2e"), _fmt(r.gamma, ".8g"),
                       word, f"{r.wall_time:.2f}", "yes" if r.trusted else "no", rel])
    # the largest eigenvalue of each LMI: one row per LMI, one column per solver row (a table of
    # labels x solvers stays narrow where one column per label would not)
    solved = [r for r in result.rows if r.max_eig_by_label()]
    eig_rows = [[label] + [_fmt(r.max_eig_by_label().get(label), ".2e") for r in solved] for label in labels]
    title = f"{result.theorem}" + (f" [{result.example}]" if result.example else "")
    status, analysis_column = 1, len(headers) - 4           # status and verdict wrap; ids and numbers never
    lines = [title, format_table(headers, rows, nowrap=tuple(i for i in range(len(headers))
                                                             if i not in (status, analysis_column))), ""]
    if eig_rows:
        lines += ["largest eigenvalue of each LMI at the returned point (N < 0 holds when negative):",
                  format_table(["LMI"] + [f"{r.backend}:{r.solver}" for r in solved], eig_rows), ""]
    backed = [f"  {r.name}: γ {r.backoff_gamma:.8g}" for r in result.rows if r.backoff_gamma is not None]
    if backed:
        lines += ["designs from the automatic back-off (the design recovered at the optimum was not "
                  "certified; as `lmidsl solve`): status and the optimum are the optimum's, max eig "
                  "the back-off point's:"] + backed + [""]
    notes = [f"  {r.name}: {r.error or r.reason}" + (f" ({r.message})" if r.message and not r.error else "")
             for r in result.rows if not r.trusted]
    if notes:
        lines += ["not trusted:"] + notes + [""]
    lines.append("verdict: " + result.verdict.line())
    lines.append("(gamma and verdict: the row's one verdict, as `lmidsl solve` gives it — for a design, the level "
                 "its analysis counterpart certifies; trust: the LMIs hold at the point (and the analysis "
                 "passes), status optimal, a non-first-order solver; rel diff: the optimum against the best "
                 "trusted optimum; '!' marks a disagreement)")
    return wrap("\n".join(lines))


MAX_ROWS = 40
"""A sweep of more points prints only its summary (the points are in --json and --out)."""


def format_sweep(result, out=None) -> str:
    """The points (up to :data:`MAX_ROWS`), the summary, the timing and the files written."""
    names = list(result.grid)
    table = []
    if len(result.points) <= MAX_ROWS:
        rows = [[*(p.params[n] for n in names), p.status, p.gamma, p.worst_eig] for p in result.points]
        table.append(format_table([*names, "status", performance_label(result.theorem), "max eig"], rows))
    lines = []
    ok = [p.gamma for p in result.points if p.gamma is not None]
    lines.append(f"{result.theorem}: {len(result.points)} points, {len(ok)} solved, "
                 f"{result.certified_count()} certified (every LMI proved at the returned point)"
                 + (f", {performance_label(result.theorem)} from {min(ok):.6g} to {max(ok):.6g}" if ok else ""))
    lines.append(format_timing(result.timing()))
    if result.parallel:
        lines.append(format_stats(result.parallel))
    if result.resumed:
        lines.append(f"resumed: {result.resumed} points from {Path(out) / 'sweep.jsonl'}, "
                     f"{result.solved} solved now")
    if out:
        lines.append(f"wrote {Path(out) / 'sweep.csv'}, sweep.json, sweep.png, sweep.pdf "
                     "(points as solved: sweep.jsonl)")
    return "\n".join(table + [wrap(line) for line in lines])


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


def format_stats(stats: dict) -> str:
    """One line of a parallel run's own measurements (:class:`_Meter`)."""
    if not stats:
        return ""
    if not stats["cluster_started"]:
        return (f"parallel: all {stats['items_here']} items solved in this process (workers would not "
                f"have paid for their start-up)")
    first, every, launched = (stats.get(k) for k in ("first_worker_joined", "all_workers_joined", "cluster_launched"))
    gap, per_task = stats["gap_per_task"], stats["main_cpu_per_task"]
    joined = "none joined" if first is None else f"first joined after {first:.1f} s" + \
        (f", all after {every:.1f} s" if every is not None else "")
    parts = [f"parallel: {stats['items_here']} items here while workers started ("
             + (f"launched at {launched:.1f} s, " if launched is not None else "") + joined + ")",
             f"{stats['items_on_workers']} on workers in {stats['tasks']} tasks",
             f"tail idle {stats['tail_idle']:.2f} worker-s of {stats['worker_busy']:.1f} busy"]
    if gap is not None:
        parts.append(f"{gap * 1e3:.1f} ms between tasks")
    if per_task is not None:
        parts.append(f"this process {stats['main_cpu']:.2f} s CPU ({per_task * 1e3:.1f} ms a task)")
    return "; ".join(parts)


def format_result(result, top: int = 8) -> str:
    """A short text report: the best grid points, the refined point, the best certified one."""
    value_name = result.performance if result.objective == "gamma" else "t*"

    def line(p) -> str:
        params = ", ".join(f"{k} = {v:.6g}" for k, v in p.params.items())
        val = "none" if math.isinf(p.value) else f"{p.value:.6g}"
        cert = "" if result.objective == "tmin" else (" proved" if p.proved else " not proved")
        return f"{value_name} = {val:<12} at {params}  ({p.status}{cert})"

    ranked = sorted(result.grid, key=lambda p: p.key)
    lines = [f"{result.theorem}" + (f" [{result.example}]" if result.example else "")
             + f": search over {', '.join(result.names)} ({len(result.grid)} grid points, "
             f"objective {value_name})",
             "  best grid points:"]
    lines += [f"    {line(p)}" for p in ranked[:top]]
    if result.refined is not None:
        info = result.refinement
        lines.append(f"  refined ({info.get('method')}, {info.get('nfev')} evaluations): {line(result.refined)}")
    best = result.best
    lines.append(f"  best: {line(best)}" if best is not None else "  best: no point gave a value")
    cert = result.best_proved or result.best_feasible
    what = "proved (every LMI proved at the point)" if result.objective == "gamma" else "strictly feasible (t* < 0)"
    lines.append(f"  best {what}: {line(cert)}" if cert is not None else f"  no {what} point")
    return "\n".join(lines)


def format_successive(result, theorem_id: str) -> str:
    """The history (one row per solve), why it stopped, and the best solution."""
    starts = len({s.start for s in result.history}) > 1
    rows = [([s.start] if starts else []) + [s.iteration, s.status, s.gamma, None if s.worst_eig is None
                                              else f"{s.worst_eig:.2e}"] for s in result.history]
    lines = [format_table((["start"] if starts else []) + ["iteration", "status", performance_label(theorem_id),
                                                           "max eig"], rows),
             "", wrap(f"stopped: {result.stop_reason}")]
    best = result.best
    if best is None:
        lines.append(wrap(f"{theorem_id}: no point where every LMI holds (largest eigenvalue < 0) was met"))
        return "\n".join(lines)
    for start, k, gamma, why in result.rejected:
        lines.append(wrap(f"iteration {k}" + (f" (start {start})" if starts else "") + f": gamma {gamma:.8g} "
                          f"is lower but not certified ({why})"))
    lines.append(wrap(f"best certified point: iteration {result.best_iteration}"
                      + (f" (start {result.best_start})" if starts else "") + f", gamma = {best.gamma:.8g}"
                      if best.verdict.certified else
                      f"best point (not certified): iteration {result.best_iteration}, gamma = {best.gamma:.8g}"))
    lines.append(wrap(f"verdict: {best.verdict.line()}"))
    analysis = best.analysis
    if analysis is not None:
        lines.append(wrap(f"analysis {analysis.theorem}: gamma = {analysis.gamma:.8g}"
                          + ("" if analysis.passed else " (does not certify the design)")))
    for name, value in (best.recovered or {}).items():
        lines.append(format_matrix(name, value))
    return "\n".join(lines)


def format_export(mapping: dict, output: str, fmt: str) -> str:
    """What was written, block by block, and the --check comparison (wrapped to the width)."""
    lines = [f"wrote {output} ({fmt}; {mapping['nvars']} scalar variables, {len(mapping['blocks'])} blocks)"
             + ("" if fmt == "json" else f"; map {output}.map.json")]
    for b in mapping["blocks"]:
        lines.append(f"  block {b['block']}: " + (f"LMI {b['lmi']}" if "lmi" in b else b["kind"])
                     + (f" vertex {b['vertex']}" if b.get("vertex") else "")
                     + (f" {b['scenario']}" if b.get("scenario") else ""))
    if "check" in mapping:
        c = mapping["check"]
        said = (f"the file states lmidsl's SDP (identity {c['identity_error']:.1e} at three random points)"
                if c.get("identity_error") is not None else "")
        if c.get("relative_difference") is not None:
            said += (f"; solved by cvxpy: {c['file_optimum']:.10g} vs lmidsl {c['lmidsl_optimum']:.10g} "
                     f"(relative {c['relative_difference']:.2e}: {'same' if c['holds'] else 'DIFFERENT'})")
        if "lmidsl_certified" in c:
            said += (f"; solved by cvxpy: a point found; lmidsl: "
                     f"{'a certified point' if c['lmidsl_certified'] else 'no certified point'}")
        lines.append("  read back: " + "; ".join(x for x in (said, c["reason"]) if x))
    if "verdict" in mapping:
        lines.append(f"verdict (lmidsl solve of the instance): {mapping['verdict']['word'].upper()}"
                     + (f" at gamma = {mapping['gamma']:.8g}" if mapping["gamma"] is not None else ""))
    return "\n".join(lines)
