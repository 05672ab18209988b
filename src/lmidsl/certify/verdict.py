"""The verdict: one record of what a result proves, decided in one place, told the same way by
every command.

A result (a :class:`~lmidsl.solver.solution.Solution`, a verification, a sweep point, a row of
``check`` or ``reproduce``) carries one :class:`Verdict`:

* ``certified`` — every claim made is proved: the LMIs at the returned point in ball arithmetic,
  and, for a design, the design's level by its analysis counterpart (the analysis LMIs proved with
  the design fixed) and the theorem's declared checks;
* ``word`` — one of :data:`WORDS`;
* ``gamma`` — the *headline*: the level the delivered design is certified for (the analysis
  level), or, for a theorem without a design, the level at the proved point; ``quantity`` says
  what it is (an L2 gain bound, a decay rate, a passivity index, ...; a *prescribed* level for a
  feasibility problem);
* ``levels`` — the other levels, each named for what it is: ``optimum`` (the SDP optimum's level),
  ``backoff`` (the synthesis level of the back-off point the design was recovered at),
  ``analysis`` (the analysis level of the delivered design);
* ``why`` — one sentence; ``reasons`` — what is not proved.

The word is never "optimal" unless optimality is proved (a bracket from a proved dual bound within
tolerance): a certified bound from an inaccurate solver point or a margin-set objective is a
"certified bound".
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..numeric.interconnection import design_kind
from ..errors import ProofConflict
from ..solver.backoff import backoff_cost
from .performance import objective_map
from ..solver.feasibility import FEASP_INFEASIBLE, FEASP_MARGINAL
from ..solver.status import OPTIMAL, SOLVED

OPTIMAL_WORD = "optimal"            # certified, and proved near the optimum (a dual bound)
CERTIFIED = "certified"             # certified; nearness to the optimum not proved / not asked
CERTIFIED_BOUND = "certified bound"  # certified, but the point is known not to be (near) the optimum
NOT_CERTIFIED = "not certified"
REFUTED = "refuted"                 # independent evidence contradicts the claim
DISAGREEMENT = "disagreement"       # trusted answers of several solvers differ (lmidsl check)
VERTEX_WISE = "vertex-wise"         # a polytopic design's analysis holds at each vertex only
INFEASIBLE = "infeasible"
NOT_SOLVED = "not solved"
SKIPPED = "certification skipped"

WORDS = (OPTIMAL_WORD, CERTIFIED, CERTIFIED_BOUND, NOT_CERTIFIED, REFUTED, VERTEX_WISE, DISAGREEMENT,
         INFEASIBLE, NOT_SOLVED, SKIPPED)
CERTIFIED_WORDS = frozenset({OPTIMAL_WORD, CERTIFIED, CERTIFIED_BOUND})

QUANTITIES = {
    "gamma": "the guaranteed gain level γ",
    "h2": "the guaranteed H2 level",
    "nu": "the certified passivity index ν",
    "alpha": "the certified decay rate α",
}
"""What a theorem's declared performance name measures (``Theorem.minimize(performance=...)``)."""

DESIGN, POINT, PRESCRIBED = "design", "point", "prescribed"
HEADLINES = (DESIGN, POINT, PRESCRIBED)
"""Whose level a solve's headline is: the delivered design's (its analysis), the returned point's,
or a level the problem prescribes (a feasibility problem)."""

LEVEL_NAMES = {"optimum": "SDP optimum", "backoff": "back-off point", "analysis": "delivered design (analysis)",
               "claimed": "claimed level", "synthesis": "synthesis point", "exact": "exact figure",
               "feasible_end": "feasible end", "infeasible_end": "infeasible end", "reference": "reference row"}
"""What each named level of a verdict is, in words."""


def quantity_words(name: str | None, feasibility: bool) -> str:
    """Words for the headline quantity; a feasibility problem's level is prescribed, not found."""
    if name is None:
        return "feasibility (no level)"
    words = QUANTITIES.get(name, f"the level {name}")
    return f"{words}, prescribed (a feasibility problem)" if feasibility else words


@dataclass(frozen=True)
class Verdict:
    certified: bool
    word: str
    gamma: float | None
    why: str
    quantity: str = "gamma"
    quantity_words: str = ""
    levels: dict = field(default_factory=dict)
    reasons: tuple = ()
    bracket: dict | None = None     # the optimum's bracket: lower/upper, each proved or not (why)
    headline: str = ""              # whose level ``gamma`` is: one of HEADLINES ("" for a study's)

    def line(self) -> str:
        """The verdict in one line, the same in every command: WORD [at q = x]: why."""
        level = "" if self.gamma is None or not self.certified else f" at {self.quantity or 'level'} = {self.gamma:.8g}"
        why = self.why if self.certified else "; ".join(self.reasons) or self.why
        return f"{self.word.upper()}{level}: {why}"

    def as_dict(self) -> dict:
        return {"certified": self.certified, "word": self.word, "gamma": self.gamma, "why": self.why,
                "quantity": self.quantity, "quantity_words": self.quantity_words,
                "levels": dict(self.levels), "reasons": list(self.reasons), "headline": self.headline}

    def bracket_line(self) -> str:
        """"optimum in [lo, hi], proved" (or what is not proved), empty without a bracket."""
        b = self.bracket
        if not b:
            return ""
        lo = "?" if b["lower"] is None else f"{b['lower']:.10g}"
        hi = "?" if b["upper"] is None else f"{b['upper']:.10g}"
        proved = [w for w, p in (("lower", b["lower_proved"]), ("upper", b["upper_proved"])) if p]
        state = "proved" if len(proved) == 2 else (f"{proved[0]} end proved" if proved else "not proved")
        dual = "upper" if b.get("maximised") else "lower"
        why = f" ({dual} bound: {b['why']})" if b["why"] and not b[f"{dual}_proved"] else ""
        return f"LMI optimum ({self.quantity or 'objective'}) in [{lo}, {hi}], {state}{why}"


def judge(solution):
    """Set ``solution.verdict`` by :func:`decide` when the result is final (the pipeline's last
    step, as cvxpy's ``unpack_results`` sets the status once); returns the solution."""
    solution.verdict = decide(solution)
    return solution


def decide(solution) -> Verdict:
    """The verdict of a solution (see the module docstring).  Reads: status, the LMI proofs, the
    design and its analysis (duck-typed: ``passed``, ``gamma``, ``theorem``, ``status``), the
    theorem's checks, whether certification was asked for, the back-off record, the margin flag."""
    theorem = solution.instance.theorem if solution.instance is not None else None
    name = theorem.performance[0] if theorem is not None and theorem.performance else None
    feasibility = theorem is not None and theorem.objective is None
    words = quantity_words(name, feasibility and getattr(theorem, "bisection", None) is None)
    analysis = solution.analysis
    levels = {"optimum": optimum_level(solution)}
    if backed_off(solution):
        levels["backoff"] = solution.point_gamma
    if analysis is not None:
        levels["analysis"] = analysis.gamma
    delivers = bool(theorem is not None and theorem.recovery)
    headline = headline_level(solution)

    box = bracket(solution)
    whose = DESIGN if design_certified_level(solution) is not None else (
        PRESCRIBED if feasibility and getattr(theorem, "bisection", None) is None else POINT)

    def verdict(certified, word, why, reasons=()):
        why = with_backoff_cost(why, solution, headline) if certified else why
        return Verdict(certified, word, headline, why, name or "", words, levels, tuple(reasons), box, whose)

    if not solution.ok:
        proof, diagnosis = solution.infeasibility, solution.feasp
        if proof is not None and proof.proved:
            why = (f"infeasible, proved: a theorem-of-alternatives certificate (Z ⪰ 0, Z ≠ 0, "
                   f"tr(F_i Z) = 0, tr(F_0 Z) ≥ 0) verified {'exactly' if proof.route == 'exact' else 'in ball arithmetic'}"
                   " for the data as written")
            return verdict(False, INFEASIBLE, why, [why])
        said = diagnosis.verdict if diagnosis is not None else None
        if said == FEASP_INFEASIBLE:
            why = ("feasp finds no strictly feasible point; infeasibility not proved"
                   + (f" ({proof.why})" if proof is not None and proof.why else ""))
            return verdict(False, NOT_SOLVED, why, [why])
        if said == FEASP_MARGINAL:
            return verdict(False, NOT_SOLVED, "feasible only by less than the strictness margin",
                           [f"feasp: {said}"])
        feasp_said = f"; feasp: {said}" if said else ""
        return verdict(False, NOT_SOLVED, f"no point was returned ({solution.status}{feasp_said})",
                       [f"status {solution.status}{feasp_said}"])
    reasons = not_proved(solution)
    if not solution.certify:
        why = "certification was skipped (--no-certify): nothing is claimed"
        return verdict(False, SKIPPED, why, [why])
    refuting = [e for e in solution.evidence if e.refutes]
    if refuting:
        why = f"{refuting[0].name}: {refuting[0].summary}"
        return verdict(False, REFUTED, why, [why] + reasons)
    if reasons:
        return verdict(False, NOT_CERTIFIED, reasons[0], reasons)
    if analysis is not None and getattr(analysis, "coverage", "") == "vertex-wise":
        why = (f"{analysis.theorem} certifies the design at each vertex with its own Lyapunov matrix; "
               "the polytope's interior is not covered by a proof")
        return verdict(False, VERTEX_WISE, why, [why])
    if delivers and analysis is not None:
        what = (f"the delivered {design_kind(solution.design.kind if solution.design is not None else None).noun}"
                f" is certified by {analysis.theorem}")
        what += "" if analysis.gamma is None else f" at {name or 'level'} = {analysis.gamma:.8g}"
    elif delivers:
        what = "every LMI proved at the returned point; the design has no analysis counterpart"
    else:
        what = "every LMI proved at the returned point"
    maximised = bool(box and box["maximised"])
    dual_end = None if box is None else box["upper" if maximised else "lower"]
    if box is not None and box["upper_proved" if maximised else "lower_proved"] and headline is not None \
            and dual_end is not None:
        gap = dual_gap(dual_end, headline, maximised)
        where = f"the optimum is in [{box['lower']:.10g}, {box['upper']:.10g}]"
        if gap < -OPTIMAL_GAP:
            if not distinct_analysis(solution):
                raise ProofConflict(f"{theorem.id}: the level {headline!r} is proved beyond the proved dual end "
                                    f"{dual_end!r} of the same problem: a bug in lmidsl, not a certificate")
            # the analysis theorem certifies the design beyond the synthesis LMIs' proved optimum
            # (zhang_quantized_loss.thm2 paper-N3: 0.0695 against [0.14984, 0.14985]): true, and
            # not "optimal" — the bracket bounds the synthesis SDP, not the best design
            side = "above" if maximised else "below"
            return verdict(True, CERTIFIED, f"{what}, {side} the synthesis LMIs' own optimum ({where}, "
                                            "proved): the analysis is less conservative than the synthesis")
        if gap <= OPTIMAL_GAP:
            return verdict(True, OPTIMAL_WORD, f"{what}; optimal within {max(gap, 0.0):.1e}: {where}, proved")
        cost = ""
        optimum = optimum_level(solution)
        if "backoff" in levels and optimum is not None:
            # the width is the back-off's (delivered over the SDP optimum: with_backoff_cost says it)
            # plus the SDP optimum's own distance to the dual bound, said here: never the whole on
            # the back-off
            cost = (f"; the SDP optimum {optimum:.10g} itself is "
                    f"{max(dual_gap(dual_end, optimum, maximised), 0.0):.1e} from the proved dual end")
        end = "below its upper end" if maximised else "above its lower end"
        loose = solution.bounds.tighter_why if solution.bounds is not None else ""
        loose = f"; not tightened: {loose}" if loose else ""
        return verdict(True, CERTIFIED_BOUND, f"{what}; {where} (proved), {gap:.1e} {end}{cost}{loose}")
    bound_reason = loose_reason(solution)
    if bound_reason:
        return verdict(True, CERTIFIED_BOUND, f"{what}; a bound, not known to be the optimum: {bound_reason}")
    return verdict(True, CERTIFIED, what)


OPTIMAL_GAP = 1e-4
"""A certified level within this relative gap of the proved lower bound is called optimal."""


def dual_gap(dual_end: float, level: float, maximised: bool) -> float:
    """How far ``level`` is from the proved dual end of the bracket, towards the worse side,
    relative to |level|: (level − lower)/|level| for a minimised performance, (upper − level)/|level|
    for a maximised one.  Negative: the level is beyond the dual bound."""
    return ((dual_end - level) if maximised else (level - dual_end)) / max(abs(level), 1e-300)


def distinct_analysis(solution) -> bool:
    """A distinct analysis theorem certified a recovered design (the only way a headline can lie
    beyond the synthesis LMIs' own proved optimum)."""
    theorem = solution.instance.theorem if solution.instance is not None else None
    analysis = solution.analysis
    return bool(theorem is not None and theorem.recovery and analysis is not None and analysis.passed
                and analysis.theorem != theorem.id)


def backed_off(solution) -> bool:
    """The point is a back-off point (its record keeps the optimum's level and proofs)."""
    return "gamma" in (solution.backoff or {})


def optimum_level(solution):
    """The level at the SDP optimum: the back-off record's for a back-off point, else the point's."""
    return solution.backoff.get("gamma_opt") if backed_off(solution) else solution.point_gamma


def design_certified_level(solution):
    """The level the delivered design's analysis certifies, or None (no design, or not passed)."""
    analysis = solution.analysis
    theorem = solution.instance.theorem if solution.instance is not None else None
    if theorem is None or not theorem.recovery or analysis is None or not analysis.passed:
        return None
    return analysis.gamma


def headline_level(solution):
    """THE headline: the delivered design's certified level, else the level at the point."""
    level = design_certified_level(solution)
    return solution.point_gamma if level is None else level


def bracket(solution) -> dict | None:
    """The optimum's bracket [lower, upper] in the headline quantity, both ends about the problem
    as written (:mod:`lmidsl.certify.as_written`), mapped through the performance proved monotone
    on the interval between them (:mod:`lmidsl.certify.performance`).

    One end is the optimum's point: proved when every LMI is proved there (the back-off point's
    record keeps the optimum's proofs and objective), its level f(objective) rounded outwards from
    the point's objective enclosed in balls.  The other is the proved dual bound
    (:mod:`lmidsl.certify.dual_bound`) mapped through f — the lower end for a non-decreasing f, the
    upper end for a non-increasing one (``maximised``: min −ν, √β, 1/δ).  Without a direction
    proved on that interval neither end is placed.  A proved lower end above a proved upper end is
    a :class:`~lmidsl.errors.ProofConflict`.  None for a feasibility problem."""
    theorem = solution.instance.theorem if solution.instance is not None else None
    if theorem is None or theorem.objective is None or not solution.ok:
        return None
    params = solution.params or {}
    level = optimum_level(solution)
    lmis = ([r.get("proof") for r in solution.backoff.get("optimum_lmis") or []] if backed_off(solution)
            else [r.proof for r in solution.lmis])
    point_proved = bool(lmis) and all(p == "proved" for p in lmis)
    point = solution.backoff.get("objective_bounds_opt") if backed_off(solution) else solution.objective_bounds
    at_point = point if point_proved and point is not None else None
    b = solution.bounds
    lower = b.lower if b is not None and b.proved else None
    performance = objective_map(theorem, params)     # one proof of the direction serves both ends
    side = None if performance is None else performance.side(lower, None if at_point is None else at_point[1])
    dual, why = None, ""
    if b is None:
        why = "not computed (--no-bounds, or not the direct backend)"
    elif not b.proved:
        why = b.why
    elif side is None:
        why = (f"{theorem.performance[0] if theorem.performance else 'the performance'} is not proved monotone "
               "in the objective between the dual bound and the point")
    else:
        dual = performance.value(lower, "down" if side == "lower" else "up")
        why = "" if dual is not None else "the performance is not real at the dual bound"
    if side is None:
        return {"lower": None, "upper": None, "lower_proved": False, "upper_proved": False,
                "why": why, "maximised": False}
    if at_point is not None:
        end = performance.value(at_point[1], "up" if side == "lower" else "down")
        level = end if end is not None else level
        point_proved = end is not None
    maximised = side == "upper"
    box = ({"lower": level, "upper": dual, "lower_proved": point_proved, "upper_proved": dual is not None,
            "why": why, "maximised": True} if maximised else
           {"lower": dual, "upper": level, "lower_proved": dual is not None, "upper_proved": point_proved,
            "why": why, "maximised": False})
    if box["lower_proved"] and box["upper_proved"] and box["lower"] > box["upper"]:
        raise ProofConflict(f"{theorem.id}: the proved lower end {box['lower']!r} of the optimum's bracket is above "
                            f"its proved upper end {box['upper']!r} ({'the point' if maximised else 'the dual bound'} "
                            f"against {'the dual bound' if maximised else 'the point'}): a bug in lmidsl, not a certificate")
    useless = "" if maximised else useless_lower_end(box["lower"] if box["lower_proved"] else None, level)
    if useless:
        box["lower_proved"], box["why"] = False, useless
    return box


def with_backoff_cost(why: str, solution, headline) -> str:
    """``why`` with the back-off's cost against the SDP optimum appended, for a back-off point
    (:func:`lmidsl.solver.backoff.backoff_cost`): every certified back-off verdict says it."""
    cost = backoff_cost(solution.backoff, headline) if backed_off(solution) else ""
    return f"{why}; {cost}" if cost else why


def useless_lower_end(lower, level) -> str:
    """Why a proved lower end of a positive minimised level says nothing useful (empty: it does):
    it is ≤ 0 (−1.2e-271 under an optimum of 1e-7 is true and useless), or the bracket is wider
    than its lower end (the level more than twice the bound).  Such an end is reported as "no
    useful lower bound", never as a proved bracket."""
    if lower is None or level is None or not level > 0:
        return ""
    if lower <= 0:
        return f"no useful lower bound (the proved lower end {lower:.3g} is not positive)"
    if level - lower > lower:
        return f"no useful lower bound (the proved lower end {lower:.6g} is less than half the level)"
    return ""


def not_proved(solution) -> list[str]:
    """What keeps a solved point from being certified (empty: nothing).

    The claim of a design theorem is "the recovered design meets γ".  When the analysis
    counterpart proves exactly that, the claim stands even if the synthesis LMIs hold only
    numerically at the returned point (a back-off point that misses the strictness margin by
    1e-8): those LMIs are then evidence, not the proof."""
    reasons = []
    analysis = solution.analysis
    design_proved = analysis is not None and analysis.passed
    unproved = [] if design_proved else [r for r in solution.lmis if r.proof != "proved"]
    for r in unproved[:3]:
        where = f" @ vertex {r.vertex}" if r.vertex is not None else ""
        reasons.append(f"LMI {r.label}{where} {r.proof or 'not proved'}"
                       + (f" ({r.proof_note})" if r.proof_note else ""))
    if len(unproved) > 3:
        reasons.append(f"{len(unproved) - 3} more LMIs not proved")
    if not solution.lmis:
        reasons.append("no LMI certificate")
    if solution.message.startswith("recovery failed"):
        reasons.append(solution.message)
    if analysis is not None and not analysis.passed:
        reasons.append(f"the analysis {analysis.theorem} does not certify the design "
                       f"({analysis.status}, {('gamma ' + format(analysis.gamma, '.6g')) if analysis.gamma is not None else 'no level'})")
    reasons += [f"check {c.name} failed" for c in solution.checks if not c.passed]
    return reasons


def loose_reason(solution) -> str:
    """Why a certified level is only a bound (empty: no known reason): the solver's point is
    inaccurate, or the strictness margin sets the objective."""
    theorem = solution.instance.theorem if solution.instance is not None else None
    if theorem is None or theorem.objective is None:
        return ""
    status = (solution.backoff or {}).get("status_opt", solution.status)
    if solution.margin_limited:
        return "the strictness margin sets the objective"
    if status != OPTIMAL:
        if backed_off(solution) and solution.status != status:
            return (f"the solver's point at the optimum is {status} (the back-off point's status "
                    f"{solution.status} says nothing of the optimum)")
        return f"the solver's point is {status}"
    return ""


__all__ = ["Verdict", "decide", "headline_level", "optimum_level", "design_certified_level", "bracket", "WORDS", "CERTIFIED_WORDS", "QUANTITIES", "quantity_words", "not_proved"]


# -- the judge of every other result: one function a study, each reading the study's record ----
# (duck-typed: this layer sits below the studies).  "certified" is always "every claim proved".

def judge_error(message: str) -> Verdict:
    """A result that could not be computed (an error of the input or of a solver)."""
    return Verdict(False, NOT_SOLVED, None, message, reasons=(message,))


def refute(verdict: Verdict, why: str) -> Verdict:
    """``verdict`` contradicted by independent evidence (an exact figure above the level)."""
    return Verdict(False, REFUTED, verdict.gamma, why, verdict.quantity, verdict.quantity_words,
                   verdict.levels, (why,), verdict.bracket)


def judge_point(status: str, gamma, proved: bool) -> Verdict:
    """A sweep point proves the level at its point (every LMI in ball arithmetic); a sweep
    recovers no design, so nothing more is claimed."""
    if status not in SOLVED:
        return Verdict(False, NOT_SOLVED, None, f"no point was returned ({status})", reasons=(f"status {status}",))
    if not proved:
        return Verdict(False, NOT_CERTIFIED, gamma, "not every LMI is proved at the point",
                       reasons=("LMIs not proved at the point",))
    return Verdict(True, CERTIFIED, gamma, "every LMI proved at the point (a sweep recovers no design)")


def judge_grid(points) -> Verdict:
    """A sweep (points with ``proved`` and ``gamma``): certified when every point's LMIs are
    proved; the headline is the largest proved level (proved at every point of the grid), the
    smallest is named ``best``."""
    bad = [p for p in points if not p.proved]
    proved_levels = [p.gamma for p in points if p.proved and p.gamma is not None]
    gamma = max(proved_levels, default=None)
    named = {"best": min(proved_levels, default=None), "worst": gamma}
    if points and not bad:
        return Verdict(True, CERTIFIED, gamma, f"every LMI proved at all {len(points)} points", levels=named)
    why = f"{len(bad)} of {len(points)} points not proved" if points else "no point"
    return Verdict(False, NOT_CERTIFIED, gamma, why, levels=named, reasons=(why,))


def judge_bisection(result) -> Verdict:
    """A bisection on a scalar (:mod:`lmidsl.studies.bisection`): the headline is the feasible
    end, proved by the judged solution there; the other end is where no route returned a certified
    point (proved infeasible only with its own certificate)."""
    levels = {"feasible_end": result.feasible_end, "infeasible_end": result.infeasible_end}
    words = quantity_words(result.parameter, False) + f" ({result.goal}imised by bisection)"
    solution = result.solution
    if solution is not None and solution.judged.certified:
        why = f"a proved point at {result.parameter} = {result.feasible_end:.10g}"
        if result.infeasible_end is not None:
            why += (f"; infeasible at {result.infeasible_end:.10g}, proved" if result.infeasible_end_proved
                    else f"; none found at {result.infeasible_end:.10g} (not proved infeasible)")
        return Verdict(True, CERTIFIED, result.feasible_end, why, result.parameter, words, levels)
    if solution is None:
        return Verdict(False, NOT_SOLVED, None, result.message or "no certified point on the interval",
                       result.parameter, words, levels, (result.message or "no certified point",))
    reasons = solution.judged.reasons
    return Verdict(False, NOT_CERTIFIED, result.feasible_end, "; ".join(reasons), result.parameter, words,
                   levels, tuple(reasons))


def judge_verification(result) -> Verdict:
    """A verification of a design (:mod:`lmidsl.studies.verify`): the headline is the level the
    analysis certifies for the design; an exact figure above the claim refutes it."""
    levels = {"claimed": result.claimed_gamma, "synthesis": result.synthesis_gamma,
              "analysis": result.analysis_gamma, "exact": None if result.exact is None else result.exact.value}
    if result.backoff and "gamma_opt" in result.backoff:
        levels = {"optimum": result.backoff["gamma_opt"], "backoff": result.backoff.get("gamma"), **levels}
    failed = [k for k, v in result.checks.items() if v is False]
    certified = bool(result.checks) and result.checks.get("analysis") is True and all(
        v for v in result.checks.values() if v is not None)
    if certified:
        word, why = CERTIFIED, (f"the {result.mode} {design_kind(result.kind).noun} is certified by "
                                f"{result.analysis_theorem}"
                                + (", its exact figure and the simulation agree" if result.exact is not None else ""))
    elif result.checks.get("exact_within_gamma") is False and result.exact is not None:
        word, why = REFUTED, f"the exact figure {result.exact.value} exceeds the claimed level {result.claimed_gamma}"
    elif result.synthesis_status is not None and result.synthesis_status not in SOLVED:
        word, why = NOT_SOLVED, f"the synthesis did not solve ({result.synthesis_status})"
    else:
        word, why = NOT_CERTIFIED, "failed: " + ", ".join(failed) if failed else "nothing certified"
    return Verdict(certified, word, result.analysis_gamma, why, "gamma", QUANTITIES["gamma"], levels,
                   tuple(f"check {k} failed" for k in failed))


def judge_agreement(result, own_row) -> Verdict:
    """A cross-check of solvers (:mod:`lmidsl.studies.cross_check`): certified when the trusted
    rows agree; the headline is ``own_row``'s judged level (the row `lmidsl solve`'s own route
    gives, so that `check` and `solve` print one number)."""
    record = None if own_row is None else own_row.verdict
    gamma = None if record is None else record["gamma"]
    quantity = "" if record is None else record["quantity"]
    word = CERTIFIED if result.agree else (DISAGREEMENT if result.disagreeing else NOT_CERTIFIED)
    reasons = () if result.agree else (result.summary(),)
    reference = result.reference
    return Verdict(result.agree, word, gamma, result.summary(), quantity, "",
                   {"reference": None if reference is None else reference.value}, reasons)
