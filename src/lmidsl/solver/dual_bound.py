"""A proved lower bound on a theorem's optimum from the solver's dual (weak duality, VSDP-style).

For the compiled problem min qᵀx + q₀ s.t. S_k(x) ∈ K_k (:mod:`lmidsl.solver.dual_point`), any
dual z with M z = q exactly and every Z_k ⪰ 0 gives

    qᵀx + q₀ ≥ q₀ − ⟨Z, S⁰⟩     for every feasible x.

Clarabel returns z̃ with M z̃ ≈ q; :func:`~lmidsl.solver.dual_point.corrected_point` encloses an
exact solution z of M z = q near z̃, and :func:`~lmidsl.solver.dual_point.check_cone` proves each
Z_k ⪰ 0 over the enclosure.  At an optimum complementarity puts eigenvalues of Z_k at 0, and the
correction may push them below: then the perturbed problem

    min qᵀx − ε Σ_{k∈F} tr S_k(x)     (F: the blocks that failed)

is solved (its dual Z′ ⪰ 0 gives Z = Z′ + εI, dual feasible for the original with margin ε; the
measured probe of ``docs``/DESIGN "Verdicts": a PSD corrected dual at ε = 1e-7 on the bounded
real lemma), with ε grown from the largest deficit seen, a few tries.  When an eigenvalue is
still negative, VSDP's bound (Jansson, Chaykin, Keil, SIAM J. Numer. Anal. 46(1), 2007) applies
only with an a-priori bound r̄_k ≥ λ_max(S_k) on the primal (``primal_bounds``):
qᵀx + q₀ ≥ q₀ − ⟨Z, S⁰⟩ + Σ_k d_k·min(0, λ_min(Z_k))·r̄_k (d_k the block size).

**Which problem.**  The strict LMIs enter with ε = 0 (their closure): the bound is on the
infimum over the strict set (equal to the closure's minimum when the strict set is non-empty);
the strictness margin of the compiled model is not in it.  The bound is proved for the SDP as
compiled (its double-precision coefficients taken exactly).  A model compiled with conditioning
(:mod:`lmidsl.solver.conditioning`: a congruence T N T with positive power-of-two T and variables
X = s_X X̃) has the same feasible set in the original variables and the same objective values,
so its bound is a bound on the original theorem's optimum; the objective is the theorem's own
(``model.objective``, not the solver's rescaled one).

The headline performance is mapped monotonically: γ = √g gives the lower γ = √max(lower, 0)
(rounded down in ball arithmetic); a performance equal to the objective is the bound itself.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import sympy as sp
from flint import arb, ctx

from .dual_point import (DualData, check_cone, corrected_point, pairing_bounds, round_down)

#: shifts ε tried (in the units of the solver's objective), each at least the last deficit × 10
SHIFT_TRIES = 3
MIN_SHIFT = 1e-9


@dataclass
class DualBound:
    """A lower bound on the objective, proved or not (``why``)."""

    lower: float | None = None            # proved lower bound on the objective (e.g. γ²)
    lower_performance: float | None = None  # the headline performance at ``lower`` (e.g. γ)
    proved: bool = False
    why: str = ""
    epsilon: float = 0.0                  # the dual shift that gave the bound (0: the solver's dual)
    extra_solves: int = 0
    min_eigenvalue: float | None = None   # smallest proved λ_min lower bound over the dual blocks
    residual: float | None = None         # ‖M z̃ − q‖∞ before the exact correction
    correction: float | None = None       # ‖z − z̃‖∞
    attempts: list = field(default_factory=list)   # (ε, worst λ_min) per try
    times: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"lower": self.lower, "lower_performance": self.lower_performance, "proved": self.proved,
                "why": self.why, "epsilon": self.epsilon, "extra_solves": self.extra_solves,
                "min_eigenvalue": self.min_eigenvalue, "residual": self.residual,
                "correction": self.correction, "attempts": self.attempts, "times": self.times}


def performance_lower(theorem, params: dict, lower: float) -> float | None:
    """The headline performance at objective value ``lower``, rounded down, when the theorem's
    performance is a non-decreasing function of its objective (√g, g, c·g with c ≥ 0); else None."""
    if theorem.performance is None or theorem.objective is None:
        return None
    perf, obj = theorem.performance[1], theorem.objective
    saved = ctx.prec
    ctx.prec = 128
    try:
        if perf == obj:
            return lower
        if perf == sp.sqrt(obj):
            return float(arb(max(lower, 0.0)).sqrt().lower()) if lower > 0 else 0.0
        level = sp.Symbol("level_", real=True)
        expr = perf.xreplace({obj: level})
        free = expr.free_symbols - {level}
        values = {s: params[s.name] for s in free if s.name in params}
        if set(values) != free:
            return None
        expr = expr.xreplace(values)
        derivative = sp.diff(expr, level)
        if not (derivative.is_nonnegative or sp.simplify(derivative).is_nonnegative):
            return None
        value = complex(sp.N(expr.xreplace({level: max(lower, 0.0)}), 30))
        if value.imag != 0 or not math.isfinite(value.real):
            return None
        return round_down(value.real * (1 - 1e-15) if value.real > 0 else value.real * (1 + 1e-15), 4)
    finally:
        ctx.prec = saved


def _solver_dual(model):
    """Clarabel's z of the model's last solve of its own problem, or None."""
    last = getattr(model, "_last", None)
    if last is None or last[0] is not model.problem:
        return None
    result = last[1]
    if str(result.status) not in ("Solved", "AlmostSolved"):
        return None
    z = np.asarray(result.z, dtype=float)
    return z if np.all(np.isfinite(z)) else None


class _ShiftedProblem:
    """The compiled problem with q replaced (the same rows and cones)."""

    def __init__(self, problem, q):
        self._base = problem
        self.n, self.A, self.b, self.cones, self.q, self.q0 = problem.n, problem.A, problem.b, problem.cones, q, problem.q0
        self.layout = problem.layout

    def clarabel_cones(self):
        return self._base.clarabel_cones()


def _solve_shifted(model, data: DualData, blocks, eps: float, solver=None, keep=None):
    """Solve min qᵀx − ε Σ_{k∈blocks} tr S_k(x) on the model's problem (Clarabel's units; with a
    support ``keep``, only the traces of its principal submatrices);
    returns its z + ε·e (dual feasible for the original up to rounding), or None.  The model's
    variable values and last result are restored afterwards."""
    problem = model.problem
    e = data.selector(blocks, keep)
    shifted = _ShiftedProblem(problem, problem.q + eps * (problem.A.T @ e))
    saved_values = [v.free for v in model.space.variables]
    saved_last = model._last
    saved_call = getattr(model, "last_solver_call", None)
    try:
        status, _, _, _ = model.run_solver(solver, shifted)
        result = model._last[1] if model._last is not None and model._last[0] is shifted else None
    finally:
        for v, f in zip(model.space.variables, saved_values):
            v.free = f
        model._last = saved_last
        model.last_solver_call = saved_call
    if result is None or status not in ("optimal", "optimal_inaccurate"):
        return None
    z = np.asarray(result.z, dtype=float)
    return z + eps * e if np.all(np.isfinite(z)) else None


def _attempt(data: DualData, z_svec, scale: float, primal_bounds, keep=None):
    """(lower or None, cone check, point, why) for one dual estimate (Clarabel's svec units),
    on the support ``keep`` (None: every unknown)."""
    z0 = data.from_svec(z_svec, scale)
    point = corrected_point(data, z0, data.q_used, keep)
    if point is None:
        return None, None, None, "the equality correction failed (the Gram matrix of the constraints is not provably invertible)"
    cone = check_cone(data, point, keep)
    _, high = pairing_bounds(data, point)
    lower = round_down(data.q0 - high)
    failing = [(b, low) for b, low in zip(data.blocks, cone.lower) if not low >= 0.0]
    if not failing:
        return lower, cone, point, ""
    if primal_bounds is not None:
        penalty = 0.0
        for b, low in failing:
            bound = primal_bounds.get(b.label) if isinstance(primal_bounds, dict) else primal_bounds(b)
            if bound is None or not math.isfinite(low):
                return None, cone, point, f"dual block {b.label} not PSD and no primal bound for it"
            penalty += b.dim * low * bound          # low < 0: Σ λ⁻ r̄ ≥ d·λ_min·r̄
        return round_down(lower + penalty * (1 + 1e-12)), cone, point, ""
    worst = min(failing, key=lambda t: t[1])
    return None, cone, point, (f"dual of {worst[0].label} ({worst[0].kind}) not proved PSD after the exact "
                               f"correction (λ_min ≥ {worst[1]:.3g})")


def lower_bound(model, solution=None, solver=None, tries: int = SHIFT_TRIES,
                primal_bounds=None) -> DualBound:
    """A proved lower bound on the optimum of a direct-backend ``model`` after its solve.

    ``solution`` (optional): the :class:`~lmidsl.solver.solution.Solution` of that solve (only
    its status is read; the dual comes from the model's last Clarabel result).  ``tries``: shifted
    re-solves allowed when the solver's own dual is not proved PSD (module docstring).
    ``primal_bounds``: {LMI label: r̄ ≥ λ_max(S)} or a callable(block) for VSDP's term (default
    none: a block not proved PSD leaves the bound unproved).
    """
    t0 = time.perf_counter()
    out = DualBound()
    if getattr(model, "backend", None) != "direct":
        out.why = f"no dual: the {getattr(model, 'backend', '?')} backend keeps none (direct backend only)"
        return out
    if model.objective is None:
        out.why = "a feasibility problem: no objective to bound"
        return out
    if solution is not None and not getattr(solution, "ok", True):
        out.why = f"the solve did not return an optimum ({solution.status})"
        return out
    z = _solver_dual(model)
    if z is None:
        out.why = "the model's last solve left no dual for its problem"
        return out
    data = DualData(model)
    out.times["setup"] = time.perf_counter() - t0
    if not data.magnitude_ok:
        out.why = "coefficients below 2^-900: rounding bounds do not hold (underflow)"
        return out
    scale = model.equilibration.objective      # the solver minimised objective / scale
    eps, blocks, keep, solves = 0.0, [], None, 0
    while True:
        t1 = time.perf_counter()
        lower, cone, point, why = _attempt(data, z, scale, primal_bounds, keep)
        if lower is None and cone is not None:
            # the face: dual matrices the solver put (near) singular on whole coordinates
            face = data.support(data.from_svec(z, scale))
            if not face.all() and (keep is None or not np.array_equal(face, keep)):
                on_face = _attempt(data, z, scale, primal_bounds, face)
                if on_face[0] is not None or (on_face[1] is not None and on_face[1].worst > cone.worst):
                    (lower, cone, point, why), keep = on_face, face
        out.times[f"verify_{solves}"] = time.perf_counter() - t1
        worst = cone.worst if cone is not None else None
        out.attempts.append({"epsilon": eps, "worst": worst,
                             "face": None if keep is None else int(keep.sum())})
        if point is not None:
            out.residual, out.correction = point.residual, point.correction
        out.min_eigenvalue = worst
        if lower is not None:
            out.lower, out.proved, out.epsilon, out.why = lower, True, eps, ""
            break
        out.why = why
        if cone is None or solves == tries:
            break
        failing = cone.failing(data.blocks)
        blocks = list({id(b): b for b in blocks + failing}.values())
        deficit = max(-low for low in cone.lower if not low >= 0.0)
        deficit = deficit / scale if math.isfinite(deficit) else 0.0
        eps = max(10 * deficit, 10 * eps, MIN_SHIFT * max(1.0, float(np.abs(z).max())))
        t1 = time.perf_counter()
        shifted = _solve_shifted(model, data, blocks, eps, solver, keep)
        out.times[f"shifted_solve_{solves}"] = time.perf_counter() - t1
        solves += 1
        out.extra_solves = solves
        if shifted is None:
            out.why = f"the shifted problem (ε = {eps:.2g}) did not solve; " + why
            break
        z = shifted
    if out.proved:
        theorem = model.instance.theorem
        out.lower_performance = performance_lower(theorem, model.instance.params, out.lower)
    out.times["total"] = time.perf_counter() - t0
    return out


__all__ = ["DualBound", "lower_bound", "performance_lower"]
