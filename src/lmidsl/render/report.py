"""Human-readable text for solutions and tables (the JSON forms are ``as_dict`` methods)."""
from __future__ import annotations

from ..numeric.interconnection import design_kind
from .table import format_matrix
from ..certify.verdict import DESIGN, LEVEL_NAMES
from ..errors import LmidslError
from ..theorem.registry import get_theorem


def headline_words(sol, verdict) -> str:
    """Whose the headline level is (``verdict.headline``): the delivered design's (its analysis
    level), or the point's."""
    what = verdict.quantity_words or "the level"
    if verdict.headline == DESIGN:
        return f"{what} of the delivered {design_kind(sol.design.kind).noun}, by its analysis"
    if not verdict.certified:
        return f"{what} at the returned point, not certified"
    return f"{what} at the proved point"


def level_words(verdict) -> str:
    """The levels besides the headline, each named (empty when there is only one)."""
    named = [(k, v) for k, v in verdict.levels.items() if v is not None]
    if len(named) < 2 and not (named and named[0][1] != verdict.gamma):
        return ""
    return ", ".join(f"{LEVEL_NAMES.get(k, k)} {v:.8g}" for k, v in named)


def format_solution(sol) -> str:
    """The text of ``lmidsl solve``: the headline as the verdict states it, then each section."""
    head = f"{sol.theorem}" + (f" [{sol.example}]" if sol.example else "")
    lines = [head, f"  backend {sol.backend}, solver {sol.solver}: {sol.status}"
             + (f" ({sol.message})" if sol.message else "")]
    for section in (_headline, _scaling, _backoff, _reported, _lmis, _design, _analysis, _notes):
        lines += section(sol)
    lines.append("  verdict: " + sol.verdict.line())
    if sol.times:
        lines.append("  times: " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in sol.times.items()))
    return "\n".join(lines)


def _headline(sol) -> list[str]:
    """The objective, the headline level (whose it is), the other levels, the bracket, the
    infeasibility proof."""
    verdict, lines = sol.verdict, []
    theorem = sol.instance.theorem if sol.instance is not None else None
    if sol.objective is not None and (theorem is None or theorem.objective is not None):
        lines.append(f"  objective = {sol.objective:.8g}")
    if verdict.gamma is not None:
        lines.append(f"  {verdict.quantity or 'level':<9} = {verdict.gamma:.8g}   ({headline_words(sol, verdict)})")
    levels = level_words(verdict)
    if levels:
        lines.append(f"  levels: {levels}")
    if verdict.bracket_line():
        lines.append(f"  {verdict.bracket_line()}")
    if sol.infeasibility is not None:
        proof = sol.infeasibility
        lines.append("  infeasibility: " + (f"proved ({proof.route}, {proof.source} certificate)" if proof.proved
                                            else f"not proved ({proof.why})"))
    return lines


def _scaling(sol) -> list[str]:
    records = sol.scaling.records if sol.scaling is not None else []
    return [f"  scaling: {rec.signal} = diag({', '.join(f'{f:g}' for f in rec.factors)}) "
            f"{rec.signal}' ({rec.how}); solved on the scaled data, design mapped back" for rec in records]


def _backoff(sol) -> list[str]:
    backoff = sol.backoff
    if not backoff:
        return []
    if backoff.get("failed"):
        return [f"  back-off δ = {backoff['delta']:g} FAILED: {backoff['failed']}; this is the optimum"]
    lines = [f"  back-off δ = {backoff['delta']:g}: objective {backoff['objective_opt']:.8g} -> "
             f"{backoff['objective']:.8g} (gamma {backoff['gamma_opt']:.8g} -> {backoff['gamma']:.8g}), "
             f"{backoff['solves']} solves"]
    if backoff.get("reason"):
        lines.append(f"    automatic back-off: {backoff['reason']}")
    for name, before in backoff["cond_before"].items():
        after = backoff["cond_after"].get(name, {}).get("cond")
        if after is not None:
            lines.append(f"    cond({name}): {before['cond']:.3g} at the optimum -> {after:.3g} at the back-off point")
    rec_before = backoff.get("recovery_cond_before")
    if isinstance(rec_before, list):
        lines.append("    at the optimum the recovery would invert: "
                     + ", ".join(f"{r['matrix']} ({r['cond']:.3g})" for r in rec_before))
    return lines


def _reported(sol) -> list[str]:
    lines = []
    for name, value in sol.reported.items():
        other = sol.analysis.reported.get(name) if sol.analysis is not None else None
        cmp = "" if other is None else f"   (analysis: {other:.8g}, rel. diff {abs(other - value) / max(abs(value), 1e-300):.1e})"
        lines.append(f"  {name:<9} = {value:.8g}{cmp}")
    return lines


def _lmis(sol) -> list[str]:
    """The LMIs at the point (largest eigenvalue, proof) and the feasp diagnosis."""
    lines = []
    if sol.lmis:
        lines.append(f"  LMIs at the returned point (largest eigenvalue of N in N < 0; margin {sol.margin:g}):")
        for r in sol.lmis:
            where = (f" @ vertex {r.vertex}" if r.vertex is not None else "") + (f" @ {r.point}" if r.point else "")
            mark = ("holds" if r.max_eig < 0 else "VIOLATED") + (f", {r.proof}" if r.proof is not None else "")
            lines.append(f"    {r.label + where:<30} {r.max_eig: .3e}  ({r.size}x{r.size}, {mark})")
    if sol.feasp is not None:
        lines.append(format_feasp(sol.feasp, "  "))
    return lines


def _design(sol) -> list[str]:
    lines = ["  recovered:"] + [format_matrix(k, v, "    ") for k, v in sol.recovered.items()] if sol.recovered else []
    for inv in sol.inverted:
        note = f" ({inv['note']})" if inv.get("note") else ""
        lines.append(f"  inverted {inv['matrix']}: condition number {inv['cond']:.3g}{note}")
    return lines


def _analysis(sol) -> list[str]:
    """The delivered design's analysis certificate (level or feasibility criterion)."""
    analysis = sol.analysis
    if analysis is None:
        return []
    passed = "certified" if analysis.passed else "NOT certified"
    g = analysis.status if analysis.gamma is None else f"gamma = {analysis.gamma:.8g}"
    if analysis.criterion == "feasible":
        g = "feasible with the design fixed" if analysis.passed else f"{analysis.status}, not proved feasible"
    if analysis.method == "level" and analysis.gamma is not None:
        low = "" if analysis.minimum is None else f", solver minimum {analysis.minimum:.6g} not strictly feasible"
        g += f" (point inside the strict set at level {analysis.synthesis_gamma or analysis.minimum:.6g}{low})"
    via = f" [{', '.join(analysis.solvers)}]" if analysis.solvers else ""
    noun = design_kind(sol.design.kind).noun if sol.design is not None else "design"
    return ([f"  analysis {analysis.theorem}{via} of the recovered {noun}: {g} ({passed})"]
            + [format_feasp(rep, "    ") for rep in analysis.feasp])


def _notes(sol) -> list[str]:
    return ([f"  note: {note}" for note in sol.notes]
            + [f"  check {c.name}: {'passed' if c.passed else 'FAILED'}: {c.summary}" for c in sol.checks])


def format_verification(result) -> str:
    """The text of ``lmidsl verify``: the design, each piece of evidence, the checks, the verdict."""
    def g(x):
        return "—" if x is None else f"{x:.6g}"
    lines = [f"{result.theorem}" + (f" [{result.example}]" if result.example else "") + f"  ({result.mode} {design_kind(result.kind).noun})"]
    lines += [format_matrix(name, M) for name, M in result.design.items()]
    if result.claimed_gamma is not None:
        lines.append(f"  claimed γ            {g(result.claimed_gamma)}")
    if result.synthesis_status is not None:
        lines.append(f"  synthesis            {result.synthesis_status}, γ = {g(result.synthesis_gamma)}")
        for r in result.lmis:
            where = (f" @ vertex {r['vertex']}" if "vertex" in r else "") + \
                    (f" @ {r['point']}" if r.get("point") else "")
            lines.append(f"    {r['label'] + where:<20} λmax = {r['max_eig']: .3e}"
                         f"  ({'holds' if r['max_eig'] < 0 else 'VIOLATED'})")
        for inv in result.inverted:
            lines.append(f"    inverted {inv['matrix']}: condition number {inv['cond']:.3g}")
    if result.analysis_theorem is not None:
        certified = (f"γ = {g(result.analysis_gamma)}" if result.analysis_gamma is not None
                     else "no γ certified")
        lines.append(f"  analysis {result.analysis_theorem}: {result.analysis_status}, {certified}")
    if result.exact is not None:
        e = result.exact
        extra = ""
        if e.details.get("feedback_value") is not None:
            extra = f"; state-feedback disturbances {g(e.details['feedback_value'])}"
        lines.append(f"  exact {e.kind}: γ = {g(e.value) if e.value is not None else '∞'}"
                     f" (squared {g(e.squared)}){extra}")
        measure = "max Re λ(A)" if e.time == "continuous" else "ρ(𝓛)"
        lines.append(f"  mean-square stability: {measure} = {e.spectral_radius:.6g}"
                     f" ({'stable' if e.mean_square_stable else 'UNSTABLE'})")
    mc = result.monte_carlo
    if mc is not None:
        lines.append(f"  Monte Carlo ({mc.runs} runs, {mc.disturbance} disturbance, seed {mc.seed}): "
                     f"ratio {g(mc.ratio)}, {100 * mc.confidence:.0f}% CI [{g(mc.ci_low)}, {g(mc.ci_high)}]"
                     f"; exact for this w {g(mc.expected)} (squared units)")
    lines.append("  checks: " + ", ".join(f"{k} {'ok' if v else ('—' if v is None else 'FAILED')}"
                                         for k, v in result.checks.items()))
    lines += [f"  note: {n}" for n in result.notes]
    lines.append("  verdict: " + result.verdict.line())
    return "\n".join(lines)


def performance_label(theorem_id: str, default: str = "gamma") -> str:
    """The theorem's own name of its performance (gamma, k, radius, nu, ...), for a column header."""
    try:
        theorem = get_theorem(theorem_id)
    except LmidslError:
        return default
    return theorem.performance[0] if theorem.performance else default


def format_feasp(report, indent: str = "  ") -> str:
    """The feasp diagnosis: t*, its word, and per LMI the largest eigenvalue at t*, t* of the LMI
    alone and t* without it (the responsible and binding ones marked)."""
    head = (f"{indent}feasp: t* = {report.tmin:.4g} ({report.verdict}; radius {report.radius:g}, "
            f"margin {report.margin:g})" if report.tmin is not None
            else f"{indent}feasp: undecided (solver status {report.status})")
    lines = [head, f"{indent}  {'LMI':<22} {'λmax at t*':>11} {'alone t*':>11} {'without t*':>11}"]
    fmt = lambda x: f"{x:11.3e}" if x is not None else f"{'-':>11}"  # noqa: E731
    for m in report.lmis:
        flag = "  <- responsible" if m.responsible else ("  (binding)" if m.binding else "")
        lines.append(f"{indent}  {m.name:<22} {fmt(m.value)} {fmt(m.alone)} {fmt(m.without)}{flag}")
    return "\n".join(lines)
