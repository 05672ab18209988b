"""The result of a solve, and the backend-independent certificate.

After any backend returns a point, every LMI is re-evaluated with numpy at that point
(:func:`lmi_certificate`): its largest eigenvalue in the form ``N ≺ 0`` is the number a user
trusts, whatever status the solver printed.  A point certifies the strict LMIs when every such
eigenvalue is negative.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, LmidslError
from ..numeric.design import Design
from ..theorem.values import HTML_RENDERER
from ..numeric.instance import Instance
from ..numeric.interconnection import design_kind, design_loop, loop_summary
from ..numeric.proof import (PRECISION, PROVED, BallEvaluator, accurate_max_eigenvalue, ball_precision,
                             prove_block_matrix, round_down, round_up)
from ..numeric.evaluate import NumericEvaluator, eigenvalues, evaluate_block_matrix
from ..symbolic.uncertainty import scenarios, spec_at
from .status import solved


def with_location(d: dict, vertex: int | None, point: str) -> dict:
    """Add where an LMI instance is imposed (polytope vertex, uncertainty point) to its dict."""
    if vertex is not None:
        d["vertex"] = vertex
    if point:
        d["point"] = point
    return d


@dataclass
class LMIReport:
    label: str
    max_eig: float
    size: int
    vertex: int | None = None
    point: str = ""  # values of uncertain symbols, e.g. "Delta=+1*beta"
    scale: float = 1.0  # ‖N‖₂ (largest |eigenvalue|), for the relative margin
    proof: str | None = None  # proved / numerical only / violated (lmidsl.numeric.proof); None: not tried
    proof_note: str = ""

    @property
    def relative(self) -> float:
        """λ_max(N) / max(1, ‖N‖₂): the margin relative to the size of the LMI."""
        return self.max_eig / max(1.0, self.scale)

    def as_dict(self) -> dict:
        out = {"label": self.label, "max_eig": self.max_eig, "relative": self.relative,
               "size": self.size}
        if self.proof is not None:
            out["proof"], out["proof_note"] = self.proof, self.proof_note
        return with_location(out, self.vertex, self.point)


@dataclass
class Solution:
    """What a solve returns: status, objective, γ, per-LMI eigenvalues, values, recovery."""

    theorem: str
    example: str | None
    backend: str
    solver: str
    status: str
    objective: float | None = None
    point_gamma: float | None = None  # the performance (γ = √g) at the returned point; the headline is ``gamma``
    lmis: list[LMIReport] = field(default_factory=list)
    values: dict = field(default_factory=dict)
    design: Design | None = None    # the recovered filter/controller (original coordinates)
    times: dict = field(default_factory=dict)
    margin: float = 0.0
    message: str = ""
    params: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    instance: Instance | None = None
    feasp: object | None = None
    scaling: object = None          # lmidsl.numeric.scaling.AppliedScaling (instance is the scaled one)
    backoff: dict | None = None     # lmidsl.solver.backoff record when the point is a back-off point
    reported: dict = field(default_factory=dict)
    checks: list = field(default_factory=list)
    margin_limited: bool = False    # the strictness margin, not the problem, sets the optimum
    congruence: dict = field(default_factory=dict, repr=False)  # of the conditioning, per LMI key
    conditioning: dict | None = None  # the exact congruence/variable scaling (solver/conditioning)
    analysis: object = None         # lmidsl.certify.AnalysisCertificate of the recovered design
    certify: bool = True            # certification asked for (False: --no-certify)
    evidence: list = field(default_factory=list)   # lmidsl.certify.evidence.Evidence: claims tested independently
    bounds: object = None           # lmidsl.certify.dual_bound.DualBound: proved lower bound on the optimum
    objective_bounds: tuple | None = None  # [lo, hi] ∋ the objective at the point, data as written (proved)
    infeasibility: object = None    # lmidsl.certify.infeasibility.InfeasibilityCertificate
    verdict: object = None          # lmidsl.certify.verdict.Verdict: set once, by the judge, when the result is final
    closed_form: Solution | None = field(default=None, repr=False)  # the closed form's point when the road kept another

    @property
    def gamma(self) -> float | None:
        """THE level, the verdict's (``verdict.gamma``): what the delivered design is certified for
        (its analysis level), else the level at the returned point.  The other levels keep their
        names: ``optimum_level`` (the SDP optimum's), ``backoff_level`` (the back-off point's),
        ``point_gamma`` (the returned point's)."""
        return self.judged.gamma

    @property
    def judged(self):
        """The verdict, which the judge (:func:`lmidsl.certify.verdict.judge`) sets once when the
        result is final; reading a level before that is a programming error, not a user's."""
        if self.verdict is None:
            raise RuntimeError(f"{self.theorem}: this solution has not been judged yet "
                               "(lmidsl.certify.verdict.judge)")
        return self.verdict

    @property
    def optimum_level(self) -> float | None:
        """The level at the SDP optimum (for a back-off point, the optimum it backed off from)."""
        return self.judged.levels.get("optimum")

    @property
    def backoff_level(self) -> float | None:
        """The synthesis level at the back-off point the design was recovered at, or None."""
        return self.judged.levels.get("backoff")

    def value(self, item):
        """The value at the returned point of a decision variable (the symbol or its name), of a
        recovered matrix (``"K"``, or the symbol ``recover`` returned), or of any expression of
        the theorem's symbols (``A.T @ P + P @ A``): a numpy array, a float for 1×1 — cvxpy's
        ``expr.value``, YALMIP's ``value(P)``.  ``sol[P]`` is the same."""
        name = item if isinstance(item, str) else getattr(item, "name", None)
        if isinstance(item, str) and item in self.values:
            return _plain(self.values[item])
        if name is not None and self.design is not None and name in self.design and name not in self.values:
            return self.design[name]
        if not isinstance(item, str) and self.instance is not None and hasattr(item, "free_symbols"):
            point = {**self.instance.data, **self.values}
            try:
                return _plain(NumericEvaluator(self.instance.dims, point, self.instance.params).visit(item))
            except (KeyError, LmidslError):
                pass
        known = sorted(self.values) + sorted(self.design or {})
        raise InputError(f"{self.theorem}: no value of {item} in this solution (variables and recovered "
                         f"matrices: {', '.join(known) or 'none'})")

    __getitem__ = value

    @property
    def recovered(self):
        """The recovered matrices by name (the :class:`Design`; empty when nothing was recovered)."""
        return self.design if self.design is not None else {}

    @property
    def inverted(self) -> list:
        """Condition numbers of the matrices the recovery inverted."""
        return list(self.design.inverted) if self.design is not None else []

    @property
    def ok(self) -> bool:
        """A point to use: the solver returned one (``status``, its termination word) and the feasp
        diagnosis, where it ran, does not rule it out (``feasp.rules_out``)."""
        return solved(self.status) and not (self.feasp is not None and self.feasp.rules_out)

    @property
    def lmis_hold(self) -> bool:
        """Every strict LMI holds numerically at the returned point (all max_eig < 0): the
        point-level test the plan uses to compare routes (the proof is in ``lmis[i].proof``)."""
        return bool(self.lmis) and all(r.max_eig < 0 for r in self.lmis)

    @property
    def proved(self) -> bool:
        """Every LMI was proved to hold at the returned point (:mod:`lmidsl.numeric.proof`)."""
        return bool(self.lmis) and all(r.proof == PROVED for r in self.lmis)

    @property
    def certified(self) -> bool:
        """Every claim proved (``verdict.certified``)."""
        return self.judged.certified

    @property
    def original_instance(self) -> Instance | None:
        """The instance in the data's own coordinates (the solver may have seen a signal-scaled one)."""
        return self.scaling.original if self.scaling is not None else self.instance

    def closed_loop(self):
        """The loop the design closes with the plant of the data, as a python-control
        ``StateSpace`` (w → z for a controller or gain, w → e for a filter, formed by
        the lower LFT, :func:`lmidsl.numeric.interconnection.design_loop`); None when there is no
        design or the data are not a plant in the gallery's names."""
        loop = self._loop()
        return None if loop is None else loop.as_statespace()

    def _loop(self):
        """The closed loop as a :class:`~lmidsl.numeric.interconnection.Realisation`, or None."""
        if self.design is None or self.instance is None:
            return None
        return design_loop(self.original_instance.data, self.design)

    @property
    def worst_eig(self) -> float | None:
        return max((r.max_eig for r in self.lmis), default=None)

    def _loop_dict(self) -> dict | None:
        """The closed loop's summary; a loop that cannot be formed (ill posed) or measured is reported as
        such (writing a result never fails on it)."""
        try:
            system = self._loop()
            return None if system is None else loop_summary(system, design_kind(self.design.kind).signal)
        except Exception as exc:     # an ill-posed loop or SLICOT refusing it is a finding
            return {"error": f"the closed loop could not be formed or measured: {type(exc).__name__}: {exc}"}

    def __repr__(self) -> str:
        """One line: theorem [example], status, γ or objective, verdict, backend/solver (the
        full report: :func:`lmidsl.render.report.format_solution`; the data: :meth:`as_dict`)."""
        where = f" [{self.example}]" if self.example else ""
        v = self.verdict
        if v is None:
            return f"<Solution {self.theorem}{where}: {self.status}, not judged yet; {self.backend}/{self.solver}>"
        value = (f", gamma={v.gamma:.8g}" if v.gamma is not None else "") + (
            f", objective={self.objective:.8g}" if self.objective is not None and self.objective != v.gamma else "")
        verdict = v.word.upper() + ("" if v.certified or not v.reasons else f" ({v.reasons[0]})")
        design = f", design {', '.join(self.design)}" if self.design is not None and len(self.design) else ""
        return (f"<Solution {self.theorem}{where}: {self.status}{value}, {verdict}{design}; "
                f"{self.backend}/{self.solver}>")

    def _repr_html_(self) -> str | None:
        """The verdict, levels, design and LMIs as a small HTML table (any front end that asks for
        ``_repr_html_``: Jupyter, VS Code, nbconvert, a plain ``display``), by the renderer the
        render layer registers in :data:`~lmidsl.theorem.values.HTML_RENDERER`; None without one."""
        render = HTML_RENDERER.get("html")
        return None if render is None else render(self)

    def as_dict(self) -> dict:
        def listify(v):
            if isinstance(v, list):
                return [listify(x) for x in v]
            return np.asarray(v).tolist()

        verdict = self.judged
        return {
            "theorem": self.theorem,
            "example": self.example,
            "backend": self.backend,
            "solver": self.solver,
            "status": self.status,
            "message": self.message,
            "objective": self.objective,
            "gamma": verdict.gamma,
            "point_gamma": self.point_gamma,
            "params": self.params,
            "margin": self.margin,
            "certified": verdict.certified,
            "lmis_hold": self.lmis_hold,
            "proved": self.proved,
            "margin_limited": self.margin_limited,
            "conditioning": self.conditioning,
            "verdict": verdict.as_dict(),
            "analysis": self.analysis.as_dict() if self.analysis is not None else None,
            "lmis": [r.as_dict() for r in self.lmis],
            "recovered": {k: listify(v) for k, v in self.recovered.items()},
            "inverted": self.inverted,
            "design": self.design.as_dict() if self.design is not None else None,
            "closed_loop": self._loop_dict(),
            "values": {k: listify(v) for k, v in self.values.items()},
            "times": self.times,
            "feasp": self.feasp.as_dict() if self.feasp is not None else None,
            "notes": self.notes,
            "scaling": self.scaling.as_dict() if self.scaling is not None else None,
            "backoff": self.backoff,
            "reported": self.reported,
            "checks": [c.as_dict() for c in self.checks],
            "evidence": [e.as_dict() for e in self.evidence],
            "bounds": verdict.bracket,
            "lower_bound": self.bounds.as_dict() if self.bounds is not None else None,
            "infeasibility": self.infeasibility.as_dict() if self.infeasibility is not None else None,
        }


def _plain(value):
    """A 1×1 result as a float, anything else as a numpy array."""
    array = np.asarray(value, dtype=float)
    return float(array.reshape(())) if array.size == 1 and array.ndim <= 2 and array.shape in ((), (1,), (1, 1)) else array


def lmi_certificate(instance: Instance, values: dict, prove: bool = False,
                    congruence: dict | None = None, matrices: dict | None = None) -> list[LMIReport]:
    """Largest eigenvalue of every LMI (form N ≺ 0) at the given point, evaluated in numpy, at
    every polytope vertex and uncertainty scenario the LMI is imposed at; with ``prove``, each
    is also proved or refuted in ball arithmetic (:mod:`lmidsl.numeric.proof`).

    ``congruence`` maps an LMI's (label, vertex, point) to the diagonal d of the conditioning
    congruence (:mod:`lmidsl.solver.conditioning`): the eigenvalues are then those of
    D N D, which has the same sign pattern (Sylvester) and far less rounding on badly scaled
    data; the proof always uses N itself.

    ``matrices`` maps (label, vertex, point) to N already evaluated at this point (the compiled
    affine form's value, :meth:`~lmidsl.solver.backends.base.CompiledModel.lmi_values`): its
    eigenvalues are taken instead of walking the statement again; the proofs always walk the
    statement (the exact data)."""
    reports = []
    for lmi in instance.theorem.lmis:
        negative = lmi.negative_form()
        for sc in scenarios(instance, lmi):
            v = sc.vertex
            spec = spec_at(negative, sc)
            M = (matrices or {}).get((lmi.label, v, sc.label))
            if M is None:
                M = evaluate_block_matrix(NumericEvaluator(instance.dims, values, instance.params, vertex=v), spec)
            d = (congruence or {}).get((lmi.label, v, sc.label))
            eigs = eigenvalues(M if d is None else M * np.outer(d, d))
            report = LMIReport(lmi.label, float(eigs[-1]), M.shape[0],
                               None if v is None else v + 1, sc.label,
                               float(np.max(np.abs(eigs))))
            if prove:
                args = (instance.dims, values, instance.params, v)
                report.proof, report.proof_note = prove_block_matrix(args, spec, lmi.strict)
                if report.proof == PROVED and not report.max_eig < 0:
                    # numpy's eigenvalue is rounding (entries ~1e16 around a margin ~1e-7): the
                    # proof is right; report the eigenvalue computed at the proof's precision
                    accurate = accurate_max_eigenvalue(args, spec)
                    if accurate is not None and accurate < 0:
                        report.max_eig = accurate
                        report.proof_note += "; λmax in 212-bit arithmetic (numpy's is rounding)"
            reports.append(report)
    return reports


def _real_at(instance: Instance, values: dict, expr):
    """A scalar expression of the theorem at a point, or None where it is not a finite real."""
    value = complex(np.asarray(NumericEvaluator(instance.dims, values, instance.params).visit(expr)).reshape(()))
    if value.imag != 0 or not np.isfinite(value.real):
        return None  # e.g. γ = √g with g < 0 at the solver's point: no real level to report
    return value.real


def evaluate_performance(instance: Instance, values: dict):
    """The theorem's performance figure (e.g. γ = √g) at a point, or None."""
    perf = instance.theorem.performance
    return None if perf is None else _real_at(instance, values, perf[1])


def evaluate_objective(instance: Instance, values: dict):
    """The theorem's objective at a point (None: no objective, or not a finite real there)."""
    objective = instance.theorem.objective
    return None if objective is None else _real_at(instance, values, objective)


def objective_enclosure(instance: Instance, values: dict) -> tuple[float, float] | None:
    """[lo, hi] containing the theorem's objective at a point exactly (the point's doubles taken
    exactly, the data and parameters as written), or None (no objective, or no ball for it)."""
    objective = instance.theorem.objective
    if objective is None:
        return None
    with ball_precision(PRECISION):
        try:
            value = BallEvaluator(instance.dims, values, instance.params).visit(objective)
        except (ZeroDivisionError, ValueError, TypeError, KeyError):
            return None
        value = np.asarray(value, dtype=object).reshape(-1)[0]
        if not value.is_finite():
            return None
        return round_down(float(value.lower())), round_up(float(value.upper()))


def evaluate_reported(instance: Instance, values: dict) -> dict:
    """The theorem's reported values (``Theorem.report``) at a point."""
    ev = NumericEvaluator(instance.dims, values, instance.params)
    return {name: float(ev.visit(expr)) for name, expr in instance.theorem.reported.items()}
