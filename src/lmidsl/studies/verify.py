"""Three kinds of evidence for one filter, and the verdict: the engine of ``lmidsl verify``.

For a synthesis theorem the filter is designed (solve + recovery) unless one is supplied (the
example's printed filter, or matrices by name); for an analysis theorem with an error system
(e.g. ``wang_l2linf.thm1``) the filter is part of the data.  Then:

1. the synthesis LMIs at the returned point (numpy, :mod:`lmidsl.certify.synthesis`), when a design was solved;
2. the analysis counterpart with the filter fixed (:mod:`lmidsl.certify.analysis`): the γ it certifies;
3. the exact mean-square figure of the error system (no LMI, :mod:`lmidsl.certify.figures`) and mean-square
   stability, per vertex;
4. a Monte Carlo simulation of the original model with the worst-case (or a chosen)
   disturbance (:mod:`lmidsl.certify.montecarlo`).

The claimed level γ_c is, in this order: ``gamma`` given by the user, the synthesis γ, the
paper's printed γ (``gamma`` or ``gamma_bound``) for a printed or a given design.  A given
design with no level to meet (no ``gamma``, nothing printed) is not certified: the check
``claimed_level`` fails and says so.  The filter is
*certified* when every applicable check passes (relative tolerance ``tol`` on γ):
synthesis LMIs all negative; the analysis is feasible with γ_a ≤ γ_c(1+tol); the error system
is mean-square stable; the exact figure is ≤ γ_c(1+tol) (≤ γ_a when no claim); the Monte Carlo
interval does not lie above γ_c² (ci_low ≤ γ_c²(1+tol)²).  Whether the exact value for the
simulated disturbance lies in the Monte Carlo interval is reported (``agrees_with_exact``) but is
a statistical statement (it fails 1 − confidence of the time) and does not enter the verdict.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..numeric.instance import bind
from ..certify.analysis import analysis_inputs, analysis_theorem_for, certify_by_analysis
from ..certify.declaration import namespace
from ..certify.figures import FIGURES, exact_figure
from ..certify.montecarlo import monte_carlo
from ..certify.synthesis import synthesis_lmis
from ..theorem.registry import linked_analysis
from ..pipeline import as_theorem, make_instance, solve_instance
from ..solver.plan import Plan
from ..solver.status import SOLVED
from ..certify.verdict import Verdict, judge_verification
from ..solver.solution import lmi_certificate
from ..numeric.proof import PROVED
from types import SimpleNamespace
from ..theorem.checks import run_checks

OK_STATUS = SOLVED


@dataclass
class Verification:
    theorem: str
    example: str | None
    mode: str
    design: dict
    claimed_gamma: float | None
    tolerance: float
    synthesis_gamma: float | None = None
    synthesis_status: str | None = None
    lmis: list = field(default_factory=list)
    inverted: list = field(default_factory=list)
    analysis_theorem: str | None = None
    analysis_gamma: float | None = None
    analysis_status: str | None = None
    analysis_lmis: list = field(default_factory=list)
    analysis_per_vertex: list = field(default_factory=list)
    exact: object = None
    exact_per_vertex: list = field(default_factory=list)
    monte_carlo: object = None
    checks: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    backoff: dict | None = None
    kind: str = "unspecified"       # what the theorem designs (lmidsl.numeric.interconnection.DESIGN_KIND_TABLE)

    @property
    def certified(self) -> bool:
        return self.verdict.certified

    @property
    def verdict(self) -> Verdict:
        """The verdict record, by the judge (:func:`lmidsl.certify.verdict.judge_verification`)."""
        return judge_verification(self)

    def as_dict(self) -> dict:
        exact = None
        if self.exact is not None:
            exact = self.exact.as_dict()
            if len(self.exact_per_vertex) > 1:
                exact["per_vertex"] = [f.value for f in self.exact_per_vertex]
        return {
            "theorem": self.theorem, "example": self.example, "mode": self.mode,
            "certified": self.certified, "verdict": self.verdict.as_dict(),
            "gamma": self.verdict.gamma, "checks": self.checks, "tolerance": self.tolerance,
            "claimed_gamma": self.claimed_gamma,
            "synthesis_gamma": self.synthesis_gamma, "synthesis_status": self.synthesis_status,
            "lmis": self.lmis, "inverted": self.inverted,
            "analysis_theorem": self.analysis_theorem, "analysis_gamma": self.analysis_gamma,
            "analysis_status": self.analysis_status, "analysis_lmis": self.analysis_lmis,
            "analysis_per_vertex": self.analysis_per_vertex,
            "exact": exact,
            "monte_carlo": None if self.monte_carlo is None else self.monte_carlo.as_dict(),
            "design": {k: np.asarray(v, dtype=float).tolist() for k, v in self.design.items()},
            "backoff": _backoff_summary(self.backoff),
            "notes": self.notes,
        }


def _backoff_summary(record: dict | None) -> dict | None:
    """The back-off record without the bulky per-LMI list."""
    if record is None:
        return None
    return {k: v for k, v in record.items() if k != "optimum_lmis"}


def analysis_instances_for(instance, filter_matrices: dict) -> list:
    """The analysis theorem's instances (one per vertex) for a synthesis instance and a filter."""
    analysis_thm = analysis_theorem_for(instance)
    vertices = range(instance.nvertices) if instance.nvertices > 1 else [None]
    return [bind(analysis_thm, analysis_inputs(instance, analysis_thm, filter_matrices, v),
                 example=instance.example) for v in vertices]


def exact_figures(analysis_instances: list) -> list:
    """The exact figure of each analysis instance's declared error system."""
    out = []
    for ai in analysis_instances:
        link = ai.theorem.certification
        out.append(exact_figure(link.figure, link.system.evaluate(ai)))
    return out


def worst_index(figures: list) -> int:
    return max(range(len(figures)), key=lambda i: np.inf if figures[i].value is None else figures[i].value)


def figures_for_solution(solution) -> list | None:
    """Exact figures (per vertex) of the filter in a solved instance, or None if not declared.

    For an analysis theorem with an error system the filter is the instance's data; for a
    synthesis theorem it is the recovered filter, put into the analysis counterpart.  The solver
    saw the signal-scaled instance, but the recovered filter is in the original coordinates
    (:func:`lmidsl.pipeline.finish_solution`), so the original instance is paired with it.
    """

    scaling = solution.scaling
    instance = scaling.original if scaling is not None else solution.instance
    thm = instance.theorem
    if thm.certification is not None:
        return exact_figures([instance])
    if thm.analysis is None or not solution.recovered:
        return None
    if linked_analysis(thm).certification is None:
        return None
    fil = {n: solution.recovered[n] for n in thm.analysis.design}
    return exact_figures(analysis_instances_for(instance, fil))


def _proved(report: dict) -> bool:
    """An LMI report (dict) that holds numerically and is proved in ball arithmetic."""
    return report["max_eig"] < 0 and report.get("proof") == PROVED


def _set_analysis(result: Verification, status: str, gamma, lmis: list) -> None:
    """Record the analysis; a γ counts only if every analysis LMI holds strictly at the point."""
    result.analysis_lmis = lmis
    violated = [r for r in lmis if not _proved(r)]
    if status not in OK_STATUS or gamma is None:
        result.analysis_status, result.analysis_gamma = status, None
    elif violated:
        worst = max(violated, key=lambda r: r["max_eig"])
        result.analysis_status = (f"{status}, LMI {worst['label']} not proved at the returned point "
                                  f"(λmax = {worst['max_eig']:.3g}, {worst.get('proof')}): not certified")
        result.analysis_gamma = None
        result.notes.append(f"the analysis solver returned γ = {gamma:.6g} at a point where its LMIs "
                            f"are not proved to hold; not certified")
    else:
        result.analysis_status, result.analysis_gamma = status, gamma


def _as_design(names: tuple, given: dict, where: str) -> dict:
    missing = [n for n in names if n not in given]
    if missing:
        raise InputError(f"{where}: the design needs {', '.join(names)}; missing {', '.join(missing)}")
    out = {}
    for n in names:
        arr = np.atleast_2d(np.asarray(given[n], dtype=float))
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{where}: design matrix {n} has non-finite entries")
        out[n] = arr
    return out


def _disturbance(choice, figure, horizon: int, m: int):
    """(w, label) for the Monte Carlo: 'worst', 'impulse' or an array (K × m)."""
    if isinstance(choice, str) and choice == "worst" and figure.worst_disturbance is not None:
        return figure.worst_disturbance, "worst-case"
    if isinstance(choice, str) and choice in ("worst", "impulse"):
        w = np.zeros((horizon, m))
        w[0, :] = 1.0 / np.sqrt(m)
        return w, "impulse" if choice == "impulse" else "impulse (no worst case: not mean-square stable)"
    w = np.atleast_2d(np.asarray(choice, dtype=float))
    if w.shape[1] != m:
        if w.shape[0] == m:
            w = w.T
        else:
            raise InputError(f"the disturbance must have {m} column(s) (one row per step), got {list(w.shape)}")
    return w, "given"


def verify(theorem, example: str | None = None, data: dict | None = None, overrides: dict | None = None,
           design=None, gamma: float | None = None, runs: int = 10000, seed: int | None = 0,
           confidence: float = 0.95, disturbance="worst", horizon: int = 50,
           solver: str | None = None, backend: str | None = None, backoff="auto", margin: float | None = None,
           progress=None, **options) -> Verification:
    """Certify a designed, printed (``design='printed'``) or given (``design={name: matrix}``) design
    (a filter, controller, ...).

    ``backoff`` (designed filters only) is passed to :func:`lmidsl.pipeline.solve_instance`: δ, or
    ``"auto"`` (back off only when the optimum's filter fails its analysis certificate).
    ``margin`` and ``options`` (solver keyword options) go to the solve of the synthesis (or of
    the analysis theorem whose design is data); the analysis counterpart of a synthesis is solved
    as :func:`~lmidsl.certify.certify_by_analysis` does, with ``solver`` and ``backend``.
    ``progress(stage)`` is called with each stage's name as it starts (synthesis, analysis,
    exact figure, Monte Carlo).
    """
    plan = Plan(backend, solver, options, margin)
    step = progress or (lambda stage: None)

    thm = as_theorem(theorem)
    instance = make_instance(thm, example, data, overrides)
    kind = thm.designs or ("filter" if thm.certification is not None else None)   # an error system: a filter's
    ex = thm.examples.get(instance.example) if instance.example else None
    printed = ex.printed if ex is not None else {}
    if runs < 0:
        raise InputError(f"{thm.id}: --runs must be >= 0")
    if not 0 < confidence < 1:
        raise InputError(f"{thm.id}: the confidence level must be in (0, 1)")

    extra = []                                 # results of the theorem's own checks
    if thm.certification is not None:          # an analysis theorem: the filter is data
        link, analysis_thm = thm.certification, thm
        tol = thm.analysis.gamma_tolerance if thm.analysis else 1e-3
        if design is None or design == "printed":
            mode = "printed" if ex is not None and "gamma_bound" in printed else "data"
            if design == "printed" and all(n in printed for n in link.design):
                instance = make_instance(thm, example, data, {**(overrides or {}),
                                                              **{n: printed[n] for n in link.design}})
        else:
            mode = "given"
            fil = _as_design(link.design, design, thm.id)
            instance = make_instance(thm, example, data, {**(overrides or {}),
                                                          **{k: v.tolist() for k, v in fil.items()}})
        fil = {n: np.asarray(instance.data[n]) for n in link.design}
        claimed = gamma
        if claimed is None:                       # the level the example prints
            claimed = printed.get("gamma_bound", printed.get("gamma"))
        result = Verification(thm.id, instance.example, mode, fil, claimed, tol, analysis_theorem=thm.id,
                              kind=kind)
        step(f"analysis ({thm.id})")
        sol, _ = plan.solve(instance)
        reports = (lmi_certificate(instance, {**instance.data, **sol.values}, prove=True)
                   if sol.ok else sol.lmis)
        _set_analysis(result, sol.status, sol.point_gamma if sol.ok else None,
                      [r.as_dict() for r in reports])
        analysis_instances = [instance]
    elif thm.analysis is not None:             # a synthesis theorem with an analysis counterpart
        analysis_thm = linked_analysis(thm)
        link = analysis_thm.certification
        tol = thm.analysis.gamma_tolerance
        names = instance.theorem.analysis.design     # a member of an index set: K_1 … K_N
        result = Verification(thm.id, instance.example, "designed", {}, gamma, tol, kind=kind,
                              analysis_theorem=analysis_thm.id)
        if design is None:
            step(f"synthesis ({thm.id})")
            sol = solve_instance(instance, certify=True, backoff=backoff, plan=plan)
            result.synthesis_status = sol.status
            if sol.backoff is not None:
                result.backoff = sol.backoff
                if "gamma" in sol.backoff:
                    result.notes.append(f"filter recovered at the back-off point (δ = {sol.backoff['delta']:g}"
                                        f" on the objective; optimum γ {sol.backoff['gamma_opt']:.6g})")
                else:
                    result.notes.append(f"back-off failed: {sol.backoff.get('failed')}; the optimum's filter")
            if not sol.ok:
                result.checks = {"synthesis_lmis": False, "analysis": None}
                result.notes.append(f"the synthesis did not solve ({sol.status}); no filter to certify")
                return result
            result.synthesis_gamma = sol.point_gamma
            result.lmis = synthesis_lmis(sol)
            result.inverted = sol.inverted
            fil = {n: np.atleast_2d(sol.recovered[n]) for n in names}
            if result.claimed_gamma is None:
                result.claimed_gamma = sol.point_gamma
        elif design == "printed":
            if not all(n in printed for n in names):
                raise InputError(f"{thm.id}: example {instance.example!r} prints no filter ({', '.join(names)})")
            result.mode = "printed"
            fil = _as_design(names, printed, f"{thm.id} example {instance.example}")
            if result.claimed_gamma is None:
                result.claimed_gamma = printed.get("gamma", printed.get("gamma_bound"))
        else:
            result.mode = "given"
            fil = _as_design(names, design, thm.id)
            if result.claimed_gamma is None:      # the level the example prints, if any
                result.claimed_gamma = printed.get("gamma", printed.get("gamma_bound"))
        result.design = fil
        step(f"analysis ({analysis_thm.id})")
        cert = sol.analysis if design is None and sol.analysis is not None else \
            certify_by_analysis(instance, fil, result.claimed_gamma, plan=plan)
        _set_analysis(result, cert.status, cert.gamma, cert.lmis)
        result.analysis_per_vertex = cert.per_vertex
        analysis_instances = analysis_instances_for(instance, fil)
        extra = _theorem_checks(thm, instance, fil, cert, sol if design is None else None)
    else:
        raise InputError(f"{thm.id} declares neither an analysis counterpart (certified_by) "
                         "nor an error system (error_system): nothing to verify against")

    ref = result.claimed_gamma if result.claimed_gamma is not None else result.analysis_gamma
    checks = {}
    if result.synthesis_status is not None:
        checks["synthesis_lmis"] = bool(result.lmis) and all(_proved(r) for r in result.lmis)
    if result.mode == "given" and result.claimed_gamma is None:
        checks["claimed_level"] = False
        result.notes.append("no level to certify the given design against: give --gamma "
                            "(the example prints none)")
    checks["analysis"] = bool(result.analysis_gamma is not None and (result.claimed_gamma is None
                                               or result.analysis_gamma <= result.claimed_gamma * (1 + tol)))
    if link is None:
        result.notes.append(f"{analysis_thm.id} declares no error system: no exact figure"
                            + ("" if thm.checks else ", no simulation"))
    else:
        step("exact figure")
        figures = exact_figures(analysis_instances)
        worst = worst_index(figures)
        result.exact, result.exact_per_vertex = figures[worst], figures
        exact = result.exact
        checks["mean_square_stable"] = all(f.mean_square_stable for f in figures)
        if ref is not None:
            checks["exact_within_gamma"] = exact.value is not None and exact.value <= ref * (1 + tol)
        if result.analysis_gamma is not None:
            checks["exact_below_analysis"] = (exact.value is not None
                                              and exact.value <= result.analysis_gamma * (1 + tol))
        if len(figures) > 1:
            result.notes.append("exact figure: the worst vertex (the polytope's interior is not searched)")
        if link.simulate is not None and runs > 0 and exact.time == "continuous":
            result.notes.append("no Monte Carlo in continuous time (the exact figure is python-control's)")
        elif link.simulate is not None and runs > 0:
            step(f"Monte Carlo ({runs} runs)")
            ai = analysis_instances[worst]
            sys = ai.theorem.certification.system.evaluate(ai)
            w, label = _disturbance(disturbance, exact, horizon, sys.m)
            mc = monte_carlo(link.simulate, namespace(ai), w, link.figure, runs=runs, seed=seed,
                             confidence=confidence, expected_trajectory=sys.mean_square_output(w),
                             disturbance=label)
            mc.vertex = worst + 1 if len(figures) > 1 else None
            result.monte_carlo = mc
            if ref is not None:
                checks["monte_carlo"] = bool(mc.ci_low <= (ref * (1 + tol)) ** 2)
    for res in extra:                      # the theorem's own checks (Theorem.verify_with)
        checks[res.name.replace(" ", "_")] = res.passed
        result.notes.append(f"{res.name}: {res.summary}")
    result.checks = checks
    return result


def _theorem_checks(thm, instance, fil: dict, cert, sol) -> list:
    """Run ``thm.checks`` on the filter: the designed solution, or a stand-in for a printed or
    given filter whose reported values (e.g. the γ_i) come from the analysis."""


    if not thm.checks:
        return []
    if cert.status not in OK_STATUS:
        return []
    designed = sol is not None
    if sol is None:
        sol = SimpleNamespace(instance=instance, values={}, recovered=fil,
                              reported=dict(cert.reported), analysis=cert)
    else:
        sol.analysis = cert
    return run_checks(sol, designed=designed)


__all__ = ["verify", "Verification", "FIGURES"]
