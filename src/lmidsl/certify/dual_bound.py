"""A proved lower bound on a theorem's optimum from the solver's dual (weak duality, VSDP-style).

For the compiled problem min qᵀx + q₀ s.t. S_k(x) ∈ K_k (:mod:`lmidsl.certify.dual_point`), any
dual z with M z = q exactly and every Z_k ⪰ 0 gives

    qᵀx + q₀ ≥ q₀ − ⟨Z, S⁰⟩     for every feasible x.

Clarabel returns z̃ with M z̃ ≈ q; :func:`~lmidsl.certify.dual_point.corrected_point` encloses an
exact solution z of M z = q near z̃, and :func:`~lmidsl.certify.dual_point.check_cone` proves each
Z_k ⪰ 0 over the enclosure.  At an optimum complementarity puts eigenvalues of Z_k at 0, and the
correction may push them below: then the perturbed problem

    min qᵀx − ε Σ_{k∈F} tr S_k(x)     (F: the blocks that failed)

is solved (its dual Z′ ⪰ 0 gives Z = Z′ + εI, dual feasible for the original with margin ε).
Its value is lower by about ε·tr S(x_ε), which grows fast with ε, so the solver's dual z_a
(nearly PSD, value near the optimum) and the shifted one z_b (PSD with margin) are combined:
both satisfy M z = q exactly, λ_min is concave, and the least θ with
(1 − θ) λ_min(Z_a,k) + θ λ_min(Z_b,k) ≥ 0 for every block loses only θ·(v_a − v_b), θ ≈ deficit/ε.
ε starts at SHIFT_START times the deficit and grows (or shrinks after a proof, while the loss
exceeds LOSS_TARGET); dual blocks the solver made singular on whole coordinates are taken on
their face (:meth:`~lmidsl.certify.dual_point.DualData.support`: a shift off the face makes the
shifted problem unbounded).  When an eigenvalue is
still negative, VSDP's bound (Jansson, Chaykin, Keil, SIAM J. Numer. Anal. 46(1), 2007) applies
only with an a-priori bound r̄_k ≥ λ_max(S_k) on the primal (``primal_bounds``):
qᵀx + q₀ ≥ q₀ − ⟨Z, S⁰⟩ + Σ_k d_k·min(0, λ_min(Z_k))·r̄_k (d_k the block size).

**Degenerate optima: the interior route, then the objective cut.**  At the bounded real lemma's
optimum Z_P = 0 and Z_N has rank 1 or 2, and the shifted problems are nearly unbounded (P grows
along weakly controllable directions at almost no cost): Clarabel solves them only to a relative
accuracy, so their duals are off by about ε itself and the correction eats the shift.  When the
shifts prove nothing, or less than within LOSS_TARGET, :func:`_interior_route` solves one small
SDP instead, min ⟨Δ, S(x̂)⟩ over Δ ⪰ I on the near-null space of the solver's dual with
M Δ = c q (c ≥ 0) at the solver's point x̂; (Z_a + sΔ)/(1 + sc) satisfies the equations for every
s, and a few s of the proved deficit δ make it PSD, at a loss of about s⟨Δ, S(x̂)⟩ (the margin is
O(1) in Δ, so the solver's accuracy does not eat it).  A tight re-solve of the main problem
(residual ~1e-13 against ~1e-8) gives a smaller δ along the same Δ.  When Δ does not exist within
the solver's precision (the SDP reported infeasible: the primal has near-free directions, as on
random plants from 16 states on) the bound says so.  Last, the shifted re-solves run with one more
constraint, qᵀx + q₀ ≤ U (U a little above the point's objective, :data:`CUT_SLACK`;
:meth:`~lmidsl.certify.dual_point.DualData.with_objective_cut`), which keeps them bounded; a
bound L of the cut problem gives min(L, U) for the original, with no assumption on U (a feasible
x above U is above min(L, U)).  Measured on random stable plants (bounded real lemma, 2 inputs,
2 outputs): n = 8 and 12 prove within 2e-7 … 7e-5 (before: 3 of 8); n ≥ 16 do not.

**Which problem.**  The strict LMIs enter with ε = 0 (their closure): the bound is on the
infimum over the strict set (equal to the closure's minimum when the strict set is non-empty);
the strictness margin of the compiled model is not in it.  A model compiled with conditioning
(:mod:`lmidsl.solver.conditioning`: a congruence T N T with positive power-of-two T and variables
X = s_X X̃) has the same feasible set in the original variables and the same objective values,
so its bound is a bound on the original theorem's optimum; the objective is the theorem's own
(``model.objective``, not the solver's rescaled one).

The headline performance is mapped through :mod:`lmidsl.certify.performance`: a map proved
non-decreasing on [lower, the point's objective] gives a lower bound on the performance (rounded
down in ball arithmetic; γ = √g gives √max(lower, 0)), a map proved non-increasing (a maximised
performance, min −ν) an upper bound (rounded up); a map not proved monotone gives none.

**Which problem.**  The LMIs and the objective *as written* (:mod:`lmidsl.certify.as_written`):
the correction and the pairing carry the radius by which each compiled coefficient may differ
from the one as written, so the bound holds for the data the user wrote, decimals read as the
rationals they denote — the same problem the LMIs at the point are proved for.

**When.**  :class:`PendingBound` runs all this on a worker thread from the end of the main solve
(the pipeline recovers and certifies meanwhile), and tries the other model the plan solved (as
written or conditioned) when the kept model's bound is unproved or loose.
"""
from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field

from types import SimpleNamespace

import clarabel
import numpy as np
from scipy import sparse

from ..numeric.proof import round_down, round_up
from ..solver.backends.direct_backend import SolverCrash, clarabel_solve
from .performance import performance_bound, performance_lower
from .verdict import OPTIMAL_GAP, dual_gap
from .frequency_bound import frequency_lower_bound
from .dual_point import U, DualData, check_cone, svec_diagonal, dual_data, corrected_point, last_dual, pairing_bounds

#: shifted re-solves tried: ε = SHIFT_START × the deficit of the solver's dual (in the units of
#: the solver's objective), then × SHIFT_GROWTH while the shifted dual is not proved PSD (÷ 30 when
#: the shifted problem does not solve: near unbounded).  Small shifts keep the shifted dual's value
#: close: its loss ε·tr S(x_ε) grows faster than ε, since x_ε runs off along near-free directions.
SHIFT_TRIES = 4
SHIFT_START = 10.0
SHIFT_GROWTH = 4.0
#: the face of the solver's dual is shifted first when its deficit is at most this many times the
#: full one's (li_delay_dropout.thm2: 33×, the face proves and a full shift is unbounded;
#: wang_l2linf.cor1: 85×, the full support proves); the other support is shifted when this one fails
FACE_TOLERANCE = 50.0
#: once proved, a further smaller shift is tried while the bound is below the solver's own dual
#: value by more than this (relative)
LOSS_TARGET = 1e-5
MIN_SHIFT = 1e-9
#: the shifted re-solves stop (and a running one is cut by Clarabel's time_limit) once the bound has
#: taken BUDGET_FACTOR times the main solve's time plus BUDGET_FLOOR seconds: the bound runs beside
#: the main thread and should not make the user wait much longer than the solve.  A bound that has
#: not proved by then rarely proves later (random 24- and 32-state BRL: shifted solves of 10–25 s
#: that run to the iteration limit, none proved); the paper examples prove in well under 3 s
#: the shifted solves whose dual iterate is corrected and checked (the proof does not rely on the
#: status); an iterate that stalled is taken only with the objective cut (without it a stall is
#: the mark of an unbounded shifted problem, and the face is tried instead)
USABLE_STATUS = ("Solved", "AlmostSolved", "InsufficientProgress")
CUT_ONLY_STATUS = ("InsufficientProgress",)
#: Clarabel's tolerances for the tight re-solve of the main problem (:func:`_interior_route`):
#: its dual's residual, hence the correction, drops from ~1e-8 to ~1e-13 on a bounded real lemma
TIGHT = dict(tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12, tol_ktratio=1e-10, max_iter=300)
#: eigenvalues of the dual estimate at most this fraction of its largest (over all blocks) span the
#: near-null space on which the interior direction must be ⪰ I
NULL_FRACTION = 1e-6
#: steps s = k·δ tried along the interior direction (δ the dual's proved eigenvalue deficit)
INTERIOR_STEPS = (1.25, 2.0, 4.0, 10.0, 30.0, 100.0)
#: the objective cut's level U above the point's objective (relative): the cut keeps the shifted
#: problems bounded (module docstring) and is inactive at the optimum
CUT_SLACK = 1e-2
BUDGET_FACTOR = 1.0
BUDGET_FLOOR = 3.0
#: the interior route (two solves) may run past the shifts' budget by this many main solves and
#: INTERIOR_FLOOR seconds: the shifts rarely prove where it is needed (random plants), and they
#: would leave it nothing
INTERIOR_FACTOR = 2.0
INTERIOR_FLOOR = 1.0


@dataclass
class DualBound:
    """A lower bound on the objective, proved or not (``why``)."""

    lower: float | None = None            # proved lower bound on the objective (e.g. γ²)
    lower_performance: float | None = None  # the performance at ``lower`` (e.g. γ): a proved lower
                                            # bound on the best performance (an increasing map)
    upper_performance: float | None = None  # ... a proved upper bound on it when the performance
                                            # decreases with the objective (a maximisation: min −ν)
    proved: bool = False
    why: str = ""
    epsilon: float = 0.0                  # the dual shift that gave the bound (0: the solver's dual)
    theta: float = 0.0                    # weight of the shifted duals in the combination
    extra_solves: int = 0
    min_eigenvalue: float | None = None   # smallest proved λ_min lower bound over the dual blocks
    residual: float | None = None         # ‖M z̃ − q‖∞ before the exact correction
    correction: float | None = None       # ‖z − z̃‖∞
    attempts: list = field(default_factory=list)   # (ε, worst λ_min) per try
    times: dict = field(default_factory=dict)
    route: str = ""                       # the model whose dual gave it, when not the kept one
    mapped_upto: float | None = None      # the performance map is proved monotone on [lower, this]
    method: str = "dual"                  # "dual" (a dual point) or "frequency" (frequency_bound)
    how: str = ""                         # the frequency route: where the bound was evaluated
    tighter_why: str = ""                 # a proved bound kept: why the other route gave none tighter

    def as_dict(self) -> dict:
        return {"lower": self.lower, "lower_performance": self.lower_performance,
                "upper_performance": self.upper_performance, "proved": self.proved,
                "why": self.why, "epsilon": self.epsilon, "theta": self.theta, "extra_solves": self.extra_solves,
                "min_eigenvalue": self.min_eigenvalue, "residual": self.residual,
                "correction": self.correction, "attempts": self.attempts, "times": self.times,
                "route": self.route, "mapped_upto": self.mapped_upto, "method": self.method, "how": self.how,
                "tighter_why": self.tighter_why}

    def gap_to(self, level: float | None) -> float | None:
        """How far the optimum's ``level`` is from the proved performance bound, relatively (≥ 0
        when consistent; negative: the level is beyond the bound); None without a proved bound."""
        if level is None or not self.proved:
            return None
        if self.lower_performance is not None:
            return dual_gap(self.lower_performance, level, maximised=False)
        if self.upper_performance is not None:
            return dual_gap(self.upper_performance, level, maximised=True)
        return None


class _ShiftedProblem:
    """The compiled problem with q replaced (the same rows and cones)."""

    def __init__(self, problem, q):
        self._base = problem
        self.n, self.A, self.b, self.cones, self.q, self.q0 = problem.n, problem.A, problem.b, problem.cones, q, problem.q0

    def clarabel_cones(self):
        return self._base.clarabel_cones()


class _CutProblem:
    """The compiled problem (Clarabel's units: b − Ax ∈ K, objective qᵀx/scale) with the objective
    cut s0 − scale·qᵀx ≥ 0 as one more non-negative row after the others
    (:meth:`~lmidsl.certify.dual_point.DualData.with_objective_cut`, in the constraints' units)."""

    def __init__(self, problem, scale: float, s0: float):
        self._base = problem
        self.n, self.q, self.q0 = problem.n, problem.q, problem.q0
        row = sparse.csc_matrix(scale * np.asarray(problem.q, dtype=float).reshape(1, -1))
        self.A = sparse.vstack([problem.A, row]).tocsc()
        self.b = np.append(problem.b, s0)
        self.cones = list(problem.cones) + [SimpleNamespace(kind="nonneg", dim=1, size=1)]

    def clarabel_cones(self):
        return self._base.clarabel_cones() + [clarabel.NonnegativeConeT(1)]


def _solve_shifted(problem, data: DualData, blocks, eps: float, keep=None, max_iter: int | None = None,
                   time_limit: float = math.inf):
    """Solve min qᵀx − ε Σ_{k∈blocks} tr S_k(x) on the compiled ``problem`` (Clarabel's units;
    with a support ``keep``, only the traces of its principal submatrices); returns its z + ε·e
    (dual feasible for the original up to rounding), or None.  Touches no model (a worker
    thread runs it while the main thread goes on with the model)."""
    e = data.selector(blocks, keep)
    shifted = _ShiftedProblem(problem, problem.q + eps * (problem.A.T @ e))
    try:
        options = {"max_iter": max_iter} if max_iter else {}
        if math.isfinite(time_limit):
            options["time_limit"] = max(time_limit, 0.5)
        result = clarabel_solve(shifted, **options)
    except SolverCrash:
        return None
    if str(result.status) not in USABLE_STATUS or (str(result.status) in CUT_ONLY_STATUS and
                                                   not isinstance(problem, _CutProblem)):
        return None
    z = np.asarray(result.z, dtype=float)
    return z + eps * e if np.all(np.isfinite(z)) else None


@dataclass
class _Candidate:
    """A corrected dual point: its proved value q₀ − ⟨Z, S⁰⟩ (whatever its cone) and cone check."""

    value: float
    cone: object
    point: object
    keep: object


def _candidate(data: DualData, z_svec, scale: float, keep=None) -> _Candidate | None:
    """The exact correction of one dual estimate (Clarabel's svec units), on the support
    ``keep`` (None: every unknown); None when the correction fails."""
    return _candidate_of(data, data.from_svec(z_svec, scale), keep)


def _candidate_of(data: DualData, z: np.ndarray, keep=None) -> _Candidate | None:
    """:func:`_candidate` for an estimate in the unknowns z of ``data`` (its own units)."""
    point = corrected_point(data, z, data.q_used, keep)
    if point is None:
        return None
    _, high = pairing_bounds(data, point)
    return _Candidate(round_down(round_down(data.q0 - data.q0_rad) - high), check_cone(data, point, keep), point, keep)


class _InteriorProblem:
    """min ⟨Δ, S(x̂)⟩ s.t. Δ_k ⪰ W_k (every cone), M Δ = c q, c ≥ 0 — in Clarabel's form
    (b − A(Δ, c) ∈ {0} × K × ℝ₊; Δ and W in the unknowns of :class:`DualData`, svec's √2 in the
    rows); W = I when not given."""

    def __init__(self, data: DualData, weight: np.ndarray, floor: np.ndarray | None = None):
        nq, nz = data.M.shape
        q = sparse.csr_matrix(data.q_used.reshape(-1, 1))
        rows = [sparse.hstack([data.M, -q])]
        b = [np.zeros(nq)]
        self.cones = [SimpleNamespace(kind="zero", dim=nq, size=nq)]
        for blk in data.blocks:
            scale = np.ones(blk.size)
            ones = np.ones(blk.size)
            if blk.kind == "psd":
                scale[:] = math.sqrt(2.0)
                scale[svec_diagonal(blk.dim)] = 1.0
                ones = np.zeros(blk.size)
                ones[svec_diagonal(blk.dim)] = 1.0
            if floor is not None:
                ones = floor[blk.offset: blk.offset + blk.size]
            block = sparse.csr_matrix((-scale, (np.arange(blk.size), blk.offset + np.arange(blk.size))),
                                      shape=(blk.size, nz + 1))
            rows.append(block)
            b.append(-ones * scale)                 # s = svec(Δ_k) − svec(W_k) ⪰ 0
            self.cones.append(SimpleNamespace(kind=blk.kind, dim=blk.dim, size=blk.size))
        rows.append(sparse.csr_matrix(([-1.0], ([0], [nz])), shape=(1, nz + 1)))
        b.append(np.zeros(1))
        self.cones.append(SimpleNamespace(kind="nonneg", dim=1, size=1))
        self.A = sparse.vstack(rows).tocsc()
        self.b = np.concatenate(b)
        self.n = nz + 1
        self.q = np.append(weight, 0.0)
        self.q0 = 0.0

    def clarabel_cones(self):
        kinds = {"psd": clarabel.PSDTriangleConeT, "nonneg": clarabel.NonnegativeConeT,
                 "zero": clarabel.ZeroConeT}
        return [kinds[c.kind](c.dim) for c in self.cones]


def _null_floor(data: DualData, z: np.ndarray) -> np.ndarray:
    """W_k = V_k V_kᵀ per block (svec, the unknowns of ``data``), V_k the eigenvectors of the dual
    estimate's Z_k with eigenvalues at most :data:`NULL_FRACTION` of the largest over all blocks
    (a non-negative block: 1 where its entry is that small, else 0)."""
    parts, top = [], 0.0
    for blk in data.blocks:
        if blk.kind == "psd":
            w, V = np.linalg.eigh(blk.matrix(z)) if blk.dim else (np.zeros(0), np.zeros((0, 0)))
        else:
            w, V = z[blk.offset: blk.offset + blk.size], None
        parts.append((w, V))
        top = max(top, float(np.abs(w).max(initial=0.0)))
    floor = np.zeros(data.nz)
    for blk, (w, V) in zip(data.blocks, parts):
        null = w <= NULL_FRACTION * top
        if blk.kind == "psd":
            W = V[:, null] @ V[:, null].T
            i, j = np.triu_indices(blk.dim)
            floor[blk.offset + j * (j + 1) // 2 + i] = W[i, j]
        else:
            floor[blk.offset: blk.offset + blk.size] = null.astype(float)
    return floor


def _interior_dual(job: _BoundJob, data: DualData, z: np.ndarray, slack) -> tuple | None:
    """(Δ, c): the least-cost Δ of :class:`_InteriorProblem` at the solver's point x̂ (its slacks
    S(x̂), Clarabel's svec), with Δ ⪰ I on the near-null space of the dual estimate z
    (:func:`_null_floor`).  Added to a dual Z_a with λ_min ≥ −δ on that space,
    (Z_a + sΔ)/(1 + sc) (s a few δ) satisfies the equations and is in the cone, and loses about
    s⟨Δ, S(x̂)⟩: the point's own slacks weighted by Δ, not the primal's reach along near-free
    directions that a shifted re-solve pays for.  None when there are no slacks or the solve
    fails."""
    if slack is None or len(slack) < data.nz:
        return None
    weight = np.array(slack[: data.nz], dtype=float)
    for blk in data.blocks:
        if blk.kind == "psd":           # ⟨Δ, S⟩ = Σ diag + 2 Σ off-diag; Clarabel's s has √2 off it
            part = weight[blk.offset: blk.offset + blk.size]
            mask = np.ones(blk.size, dtype=bool)
            mask[svec_diagonal(blk.dim)] = False
            part[mask] *= math.sqrt(2.0)
    if not np.all(np.isfinite(weight)):
        return None
    problem = _InteriorProblem(data, weight, _null_floor(data, z))
    options = {"max_iter": job.max_iter} if job.max_iter else {}
    left = job.interior_budget - (time.perf_counter() - job.t0)
    if math.isfinite(left):
        options["time_limit"] = max(left, 0.5)
    try:
        result = clarabel_solve(problem, **options)
    except SolverCrash:
        return None
    x = np.asarray(result.x, dtype=float)
    job.interior_status = str(result.status)
    # the iterate is only a direction for the exact correction: a stalled one may do
    if str(result.status) not in USABLE_STATUS + ("NumericalError",) or not np.all(np.isfinite(x)) or not x[-1] >= 0:
        return None
    return x[:-1], float(x[-1])


def _interior_route(job: _BoundJob, data: DualData, a: _Candidate, out: DualBound):
    """The solver's dual made PSD along the least-cost interior direction (:func:`_interior_dual`,
    one small SDP); when that proves nothing or a loose bound, the main problem re-solved to tight
    tolerances (one solve: a dual whose deficit, hence the step, is smaller) along the same
    direction.  The proved candidate of least loss, or None (and ``job.interior_why``)."""
    cancel = getattr(job, "cancel", None)
    if cancel is not None and cancel.is_set():
        raise BoundCancelled
    z_a = data.from_svec(job.z, job.scale)
    t1 = time.perf_counter()
    found = _interior_dual(job, data, z_a, job.slack)
    out.times["interior_solve"] = time.perf_counter() - t1
    out.extra_solves += 1
    if found is None:
        job.interior_why = ("no dual direction with an eigenvalue margin at the solver's point (Clarabel: "
                            f"{getattr(job, 'interior_status', 'no solve')}): the primal has near-free directions, "
                            "so any dual in the cone loses more than the solver's accuracy allows")
        return None
    best = _along(data, z_a, a, found, out, "interior")
    if best is not None and a.value - best.value <= LOSS_TARGET * max(abs(a.value), 1e-300):
        return best
    t0 = time.perf_counter()
    left = job.interior_budget - (time.perf_counter() - job.t0)
    if left <= 0:
        return best
    try:
        tight = clarabel_solve(job.problem, **dict(TIGHT, time_limit=max(left, 0.5)) if math.isfinite(left) else TIGHT)
        zt = np.asarray(tight.z, dtype=float)
    except SolverCrash:
        zt = None
    out.times["tight_solve"] = time.perf_counter() - t0
    out.extra_solves += 1
    if zt is None or not np.all(np.isfinite(zt)):
        return best
    z_t = data.from_svec(zt, job.scale)
    t1 = time.perf_counter()
    c = _candidate_of(data, z_t)
    _record(out, c, 0.0, route="tight")
    out.times["verify_tight"] = time.perf_counter() - t1
    if c is None:
        return best
    other = c if c.cone.worst >= 0 else _along(data, z_t, c, found, out, "tight interior")
    if other is not None and (best is None or other.value > best.value):
        best = other
    return best


def _along(data: DualData, z: np.ndarray, a: _Candidate, found: tuple, out: DualBound, label: str):
    """The first of (z + sΔ)/(1 + sc), s = k·δ for k in :data:`INTERIOR_STEPS` (δ the proved
    deficit of ``a``, the correction of z), proved in the cone (the loss grows with s), or None."""
    deficit = -a.cone.worst
    if not math.isfinite(deficit) or deficit <= 0:
        return None
    delta, c = found
    t1 = time.perf_counter()
    best = None
    for multiple in INTERIOR_STEPS:
        step = multiple * deficit
        cand = _candidate_of(data, (z + step * delta) / (1.0 + step * c))
        _record(out, cand, step, route=label)
        if cand is not None and cand.cone.worst >= 0:
            best = cand
            break
    out.times[f"verify_{label.replace(' ', '_')}"] = time.perf_counter() - t1
    return best


def _shift_once(job: _BoundJob, data: DualData, blocks, eps: float, keep, scale: float, out: DualBound,
                record, label) -> tuple[bool, _Candidate | None]:
    """One shifted solve on the support ``keep`` and the exact correction of its dual: (whether
    the shifted problem solved, the corrected candidate or None), counted and timed in ``out``;
    :class:`BoundCancelled` when the job was cancelled (checked before each shifted solve)."""
    cancel = getattr(job, "cancel", None)          # PendingBound's event (set: stop here)
    if cancel is not None and cancel.is_set():
        raise BoundCancelled
    t0 = time.perf_counter()
    left = job.budget - (time.perf_counter() - job.t0)      # the budget bounds the solve too
    shifted = _solve_shifted(job.problem, data, blocks, eps, keep, job.max_iter, left)
    out.times[f"shifted_solve_{label}"] = time.perf_counter() - t0
    out.extra_solves += 1
    if shifted is None:
        return False, None
    t0 = time.perf_counter()
    b = _candidate(data, shifted, scale, keep)
    record(b, eps)
    out.times[f"verify_shifted_{label}"] = time.perf_counter() - t0
    return True, b


def _first_shift(job: _BoundJob, data: DualData, cand: _Candidate, scale: float, out: DualBound, record):
    """The first shift on the support of ``cand``: [(cand, 0), (its shifted candidate, ε)], or None
    when the shifted problem does not solve or its correction fails."""
    deficit = -cand.cone.worst / scale if math.isfinite(cand.cone.worst) else 1e-6
    eps = max(SHIFT_START * deficit, MIN_SHIFT)
    _, b = _shift_once(job, data, cand.cone.failing(data.blocks), eps, cand.keep, scale, out, record,
                       "other_support")
    return None if b is None else [(cand, 0.0), (b, eps)]


def _vsdp(data: DualData, a: _Candidate, primal_bounds) -> float | None:
    """VSDP's bound q₀ − ⟨Z, S⁰⟩ + Σ_k d_k·min(0, λ_min(Z_k))·r̄_k with r̄_k ≥ λ_max(S_k) given."""
    penalty = 0.0
    for b, low in zip(data.blocks, a.cone.lower):
        if low >= 0.0:
            continue
        bound = primal_bounds.get(b.label) if isinstance(primal_bounds, dict) else primal_bounds(b)
        if bound is None or not math.isfinite(low):
            return None
        penalty += b.dim * low * bound
    return round_down(a.value + penalty * (1 + 1e-12))


def _pair(a: _Candidate, b: _Candidate) -> tuple[float, float] | None:
    """(θ, bound) for z = (1 − θ) z_a + θ z_b, the least θ that makes every block's bound
    (1 − θ) a_k + θ b_k ≥ 0 (checked in floats with its rounding error), or None."""
    lo, hi = 0.0, 1.0
    for ak, bk in zip(a.cone.lower, b.cone.lower):
        if ak >= 0 and bk >= 0:
            continue                                   # (an empty block: +∞ on both sides)
        if not (math.isfinite(ak) and math.isfinite(bk)):
            if ak < 0 and not (bk > 0):
                return None
            if bk < 0 and not (ak > 0):
                return None
            if ak == math.inf:
                hi = min(hi, 1.0 - 1e-12)
            elif bk == math.inf:
                lo = max(lo, 1e-12)
            continue
        if ak < 0:
            if bk <= 0:
                return None
            lo = max(lo, -ak / (bk - ak))
        else:
            hi = min(hi, ak / (ak - bk))
    theta = min(1.0, lo * (1 + 1e-6) + 1e-300) if lo > 0 else 0.0
    if theta > hi:
        return None
    for ak, bk in zip(a.cone.lower, b.cone.lower):
        if ak >= 0 and bk >= 0:
            continue
        x, y = (1 - theta) * ak, theta * bk
        if x + y - 8 * U * (abs(x) + abs(y)) < 0:
            return None
    value = (1 - theta) * a.value + theta * b.value
    return theta, round_down(value - 8 * U * (abs(a.value) + abs(b.value) + abs(value)))


def _combine(candidates: list) -> tuple[float, float] | None:
    """(weight of the shifted duals, bound) for the best z = (1 − θ) z_i + θ z_j over pairs of
    corrected dual points on one support (a point alone when it is proved in the cone): each
    satisfies M z = q exactly, so z does; λ_min is concave, so λ_min(Z_k) ≥ (1 − θ) λ_k(i) + θ λ_k(j)
    with λ_k the proved bounds, and the value is (1 − θ) v_i + θ v_j.  The solver's dual (nearly
    PSD, value near the optimum) and a shifted dual (PSD with margin ε, value lower by about
    ε·tr S) give a bound that loses only about θ·(v_a − v_b), θ ≈ deficit/ε."""
    best = None
    for i, a in enumerate(candidates):
        if a.cone.worst >= 0 and (best is None or a.value > best[1]):
            best = (0.0 if i == 0 else 1.0, a.value)
        for b in candidates[i + 1:]:
            found = _pair(a, b)
            if found is not None and (best is None or found[1] > best[1]):
                best = (found[0] if i == 0 else 1.0, found[1])
    return best


@dataclass
class _BoundJob:
    """What the bound needs from a solved model, read as soon as the solve ends (a later solve on
    the model replaces its dual): the conic data, the solver's dual z̃ (svec), the solver's
    objective units, the compiled problem, the theorem, and the record being filled."""

    data: DualData
    z: np.ndarray
    scale: float
    problem: object
    theorem: object
    params: dict
    max_iter: int | None
    out: DualBound
    t0: float
    upper: float | None = None       # the objective at the solve's point, rounded up (as written)
    budget: float = math.inf            # seconds from t0 after which no further shift is tried
    objective: float | None = None     # the solver's objective at its point (the theorem's units)
    slack: np.ndarray | None = None    # the solver's slacks S(x̂) (Clarabel's svec)
    interior_budget: float = math.inf  # seconds from t0 after which the interior route is not started


def _prepare(model, solution) -> _BoundJob | DualBound:
    """The job for ``model`` after its solve, or the record saying why there is no bound."""
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
    z = last_dual(model, ("Solved", "AlmostSolved"), shifted=True)
    if z is None:
        out.why = "the model's last solve left no dual for its problem"
        return out
    data, out.why = dual_data(model)
    out.times["setup"] = time.perf_counter() - t0
    if out.why:
        return out
    iterations = getattr(model._last[1], "iterations", None)
    # a shifted problem that does not solve runs to the iteration limit: allow it four times the
    # main solve's iterations and some (the stress set's slowest proving one, a discrete ζ = 0.001
    # plant: 72 against 22), not Clarabel's default 200
    max_iter = 4 * int(iterations) + 40 if iterations else None
    point = getattr(solution, "objective_bounds", None)
    solve_time = getattr(model._last[1], "solve_time", None)
    budget = BUDGET_FACTOR * float(solve_time) + BUDGET_FLOOR if solve_time else math.inf
    interior_budget = budget + INTERIOR_FACTOR * float(solve_time) + INTERIOR_FLOOR if solve_time else math.inf
    objective = getattr(model._last[1], "obj_val", None)
    if objective is not None:
        objective = (float(objective) + model.problem.q0) * model.equilibration.objective
    return _BoundJob(data, z, model.equilibration.objective, model.problem, model.instance.theorem,
                     dict(model.instance.params), max_iter, out, t0, None if point is None else point[1], budget,
                     objective, np.asarray(getattr(model._last[1], "s", None), dtype=float), interior_budget)


def lower_bound(model, solution=None, tries: int = SHIFT_TRIES, primal_bounds=None) -> DualBound:
    """A proved lower bound on the optimum of a direct-backend ``model`` after its solve.

    ``solution`` (optional): the :class:`~lmidsl.solver.solution.Solution` of that solve (only
    its status is read; the dual comes from the model's last Clarabel result).  ``tries``: shifted
    re-solves allowed when the solver's own dual is not proved PSD (module docstring).
    ``primal_bounds``: {LMI label: r̄ ≥ λ_max(S)} or a callable(block) for VSDP's term (default
    none: a block not proved PSD leaves the bound unproved).
    """
    job = _prepare(model, solution)
    return job if isinstance(job, DualBound) else _bound(job, tries, primal_bounds)


class BoundCancelled(Exception):
    """A pending bound was cancelled (an interrupt, a deadline, the interpreter's exit)."""


#: the pending bounds whose worker may still run (cancelled and waited for at exit)
_PENDING: set = set()
_PENDING_LOCK = threading.Lock()


class PendingBound:
    """The proved lower bound of a solve, computed on a worker thread from the end of the main
    solve while the pipeline recovers and certifies the design (the shifted re-solves are Clarabel
    calls, which release the GIL; ball arithmetic takes
    :func:`~lmidsl.numeric.proof.ball_precision`'s lock).  ``result()`` waits for it; an
    exception in the worker is raised there.

    ``others``: the other models solved on the way (as written or conditioned: the same feasible
    set and objective in the theorem's variables, :meth:`lmidsl.solver.plan.Plan.solve`).  When the
    kept model's bound is unproved or loose — more than
    :data:`~lmidsl.certify.verdict.OPTIMAL_GAP` below ``level``, the optimum's level — each
    other model's dual is tried in turn and the highest proved bound is kept: the plan's next
    road for the bracket (zhang_quantized_loss.thm2 paper-N3: 0.148147 from the conditioned
    model, 0.149843 from the one as written, against the level 0.149846).

    **Ending at any moment.**  The worker is not a daemon: a daemon thread still inside Clarabel
    (Rust, through PyO3) when the interpreter exits is ended by ``pthread_exit``, whose forced
    unwinding PyO3's panic guard catches, and the process aborts ("FATAL: exception not
    rethrown", exit 134).  Instead :meth:`cancel` (an interrupt in :meth:`result`, the caller's
    own interrupt, :func:`cancel_pending` at the interpreter's exit) stops the worker before its
    next shifted solve, and the one in flight finishes (its iterations are capped at four times
    the main solve's)."""

    def __init__(self, model, solution, others=(), level: float | None = None, tries: int = SHIFT_TRIES,
                 instance=None):
        # now: a later solve on the model (back-off, level problem) replaces its dual
        jobs = [_prepare(model, solution)] + [_prepare(m, None) for m in others]
        point = getattr(solution, "objective_bounds", None)
        self._frequency = None if instance is None else (instance, None if point is None else point[1])
        self._cancel = threading.Event()
        for job in jobs:
            if isinstance(job, _BoundJob):
                job.cancel = self._cancel           # read by _shift_once before each shifted solve
        self._done = None
        self._error = None
        self._thread = threading.Thread(target=self._run, args=(jobs, others, level, tries), daemon=False,
                                        name="lmidsl-lower-bound")
        with _PENDING_LOCK:
            _PENDING.add(self)
        self._thread.start()

    def _run(self, jobs, others, level, tries):
        try:
            start = time.perf_counter()
            best = None if self._frequency is None else frequency_route(*self._frequency)
            for job in jobs:         # the duals' time budgets count from here, not from before the
                if isinstance(job, _BoundJob):       # frequency route (a singular plant's: seconds)
                    job.t0 += time.perf_counter() - start
            for k, job in enumerate(jobs):
                if self._cancel.is_set():
                    raise BoundCancelled
                if best is not None and best.proved and (best.gap_to(level) is None or
                                                          best.gap_to(level) <= OPTIMAL_GAP):
                    break                 # tight, or no level to be loose against
                bound = job if isinstance(job, DualBound) else _bound(job, tries, None)
                if k:
                    bound.route = "conditioned" if others[k - 1].conditioning is not None else "as written"
                best = _preferred(best, bound)
            self._done = best
        except BoundCancelled:
            self._done = DualBound(why="not computed: cancelled (interrupted)")
        except BaseException as exc:      # re-raised in the caller's thread by result()
            self._error = exc
        finally:
            with _PENDING_LOCK:
                _PENDING.discard(self)

    def cancel(self) -> None:
        """Stop the worker before its next shifted solve (the one in flight finishes)."""
        self._cancel.set()

    def join(self, timeout: float | None = None) -> bool:
        """Wait for the worker (at most ``timeout`` seconds); whether it has ended."""
        if self._thread is not None:
            self._thread.join(timeout)
            return not self._thread.is_alive()
        return True

    def result(self) -> DualBound:
        if self._thread is not None:
            try:
                while self._thread.is_alive():      # in steps: an interrupt is taken at once
                    self._thread.join(0.2)
            except BaseException:
                self.cancel()
                raise
            self._thread = None
        if self._error is not None:
            raise self._error
        return self._done


def _preferred(best: DualBound | None, bound: DualBound) -> DualBound:
    """The record to keep of two: the higher proved bound; of two unproved, the kept model's
    (the first dual tried) — its reason is the one to print — over the frequency route's."""
    if best is None:
        return bound
    if bound.proved:
        kept, other = (bound, best) if not best.proved or bound.lower > best.lower else (best, bound)
    else:
        kept, other = (bound, best) if not best.proved and best.method == "frequency" else (best, bound)
    if kept.proved and not other.proved and other.why:
        kept.tighter_why = f"the {other.method} bound was not proved ({other.why})"
    return kept


def cancel_pending(wait: float | None = None) -> bool:
    """Cancel every pending bound and wait for their workers (at most ``wait`` seconds in all;
    None: until each has ended); whether all have ended.  Run at the interpreter's exit before
    its non-daemon threads are joined, and by the command line when a command ends."""
    with _PENDING_LOCK:
        pending = list(_PENDING)
    for bound in pending:
        bound.cancel()
    end = None if wait is None else time.monotonic() + wait
    for bound in pending:
        if not bound.join(None if end is None else max(0.0, end - time.monotonic())):
            return False
    return True


if hasattr(threading, "_register_atexit"):      # before threading joins non-daemon threads
    threading._register_atexit(cancel_pending)


def _record(out: DualBound, c: _Candidate | None, eps: float, **extra) -> None:
    """One tried dual point in ``out.attempts`` (its shift, proved λ_min, support size)."""
    out.attempts.append({"epsilon": eps, "worst": None if c is None else c.cone.worst,
                         "face": None if c is None or c.keep is None else int(c.keep.sum()), **extra})
    if c is not None:
        out.residual, out.correction, out.min_eigenvalue = c.point.residual, c.point.correction, c.cone.worst


def _search(job: _BoundJob, tries: int, primal_bounds) -> None:
    """The solver's dual corrected and checked, then the shifted re-solves (module docstring),
    filling ``job.out``."""
    data, z, scale, out = job.data, job.z, job.scale, job.out
    t1 = time.perf_counter()

    def record(c: _Candidate | None, eps: float):
        _record(out, c, eps)

    def proved(value: float, eps: float):
        out.lower, out.proved, out.epsilon, out.why = value, True, eps, ""

    a = _candidate(data, z, scale)
    record(a, 0.0)
    job.first = a                                         # the full support (the interior route)
    other = None                                          # the support not chosen, tried second
    if a is not None and a.cone.worst < 0:
        face = data.support(data.from_svec(z, scale))     # dual blocks the solver made singular
        if not face.all():
            on_face = _candidate(data, z, scale, face)
            record(on_face, 0.0)
            # preferred unless much worse: a shift off the face makes the shifted problem
            # unbounded (the direction that makes those duals singular grows for free); much
            # worse means the dropped entries were needed (wang_l2linf.thm3: −3e-10 → −2.6e-8)
            if on_face is not None and on_face.cone.worst >= FACE_TOLERANCE * a.cone.worst:
                a, other = on_face, a
            else:
                other = on_face
    out.times["verify_solver_dual"] = time.perf_counter() - t1
    if a is None:
        out.why = "the equality correction failed (the Gram matrix of the constraints is not provably invertible)"
    elif a.cone.worst >= 0:
        proved(a.value, 0.0)
    elif primal_bounds is not None and _vsdp(data, a, primal_bounds) is not None:
        proved(_vsdp(data, a, primal_bounds), 0.0)
    else:
        failing = a.cone.failing(data.blocks)
        worst = min(zip(a.cone.lower, data.blocks), key=lambda t: t[0])
        out.why = (f"dual of {worst[1].label} ({worst[1].kind}) not proved PSD after the exact "
                   f"correction (λ_min ≥ {worst[0]:.3g})")
        deficit = -a.cone.worst / scale if math.isfinite(a.cone.worst) else 1e-6
        eps = max(SHIFT_START * deficit, MIN_SHIFT * max(1.0, float(np.abs(z).max())))
        face = data.support(data.from_svec(z, scale))
        pool, eaten = [a], 0
        tried_other = other is None

        def switch(to):
            """Shift on the other support from now on: its candidate alone, or with the shifted
            candidate of its first try (resumed past that shift)."""
            nonlocal a, pool, eps, failing, eaten
            if isinstance(to, list):
                a, pool, eps = to[0][0], [c for c, _ in to], to[-1][1] * SHIFT_GROWTH
            else:
                a, pool = to, [to]
                eps = max(SHIFT_START * -a.cone.worst / scale, MIN_SHIFT) if math.isfinite(a.cone.worst) else eps
            failing, eaten = a.cone.failing(data.blocks), 0

        for attempt in range(tries):
            if time.perf_counter() - job.t0 > job.budget:
                out.why = (f"the time budget ({BUDGET_FACTOR:g}× the solve + {BUDGET_FLOOR:g} s) ran out after "
                           f"{out.extra_solves} shifted solves; " + out.why.split("; ")[-1])
                break
            solved, b = _shift_once(job, data, failing, eps, a.keep, scale, out, record, attempt)
            if not tried_other and (b is None or _combine(pool + [b]) is None):
                # this support's first shift failed: the other support's first shift, before
                # larger shifts here (which support proves is not known in advance: the BRL
                # stress set mostly the full one, wang_l2linf.cor1 two-vertex the full one after
                # a failed face)
                tried_other = True
                first = _first_shift(job, data, other, scale, out, record)
                if first is not None and _combine([c for c, _ in first]) is not None:
                    found = _combine([c for c, _ in first])
                    switch(first)
                    other = None
                    proved(found[1], first[1][1])
                    out.theta = found[0]
                    if a.value - out.lower <= LOSS_TARGET * max(abs(a.value), 1e-300):
                        break
                    eps = first[1][1] / (SHIFT_GROWTH * 2)   # proved: a smaller shift may lose less
                    continue
                # a switch to the other support resumes past its shift; none when it did not solve
                other = first
            if not solved:
                # unbounded: a primal direction grows a block at no cost, every dual is singular
                # there; shift on the face of the solver's dual instead
                if a.keep is None and not face.all() and (other is not None or not tried_other):
                    to = other if other is not None else _candidate(data, z, scale, face)
                    other = None
                    if to is not None:
                        switch(to)
                        if a.cone.worst >= 0:
                            proved(a.value, 0.0)
                            break
                        continue
                if attempt + 1 < tries and "did not solve" not in out.why:
                    out.why = f"the shifted problem (ε = {eps:.2g}) did not solve; " + out.why
                    eps /= 30          # near unbounded: a smaller shift (the combination needs little)
                    continue
                out.why = f"the shifted problem (ε = {eps:.2g}) did not solve; " + out.why.split("; ")[-1]
                break
            if b is None:
                break
            pool.append(b)
            combined = _combine(pool)
            if combined is not None and (not out.proved or combined[1] > out.lower):
                proved(combined[1], eps)
                out.theta = combined[0]
                if a.value - out.lower <= LOSS_TARGET * max(abs(a.value), 1e-300):
                    break
                eps /= SHIFT_GROWTH * 2       # proved: a smaller shift may lose less
                continue
            if out.proved:
                break                          # a smaller shift did not improve: keep the bound
            eaten += b.cone.worst <= -0.3 * eps * scale
            if eaten >= 2 and other is None:
                # twice the correction ate the shift on the last support: a larger ε is eaten too
                # (zhang_quantized_loss.thm1 paper-N2-printed-shift: λ_min ≈ −2ε at each ε)
                out.why = "the exact correction eats every shift (λ_min ≈ −ε); " + out.why.split("; ")[-1]
                break
            if other is not None and eaten >= 2:
                # twice the correction ate the shift (λ_min ≈ −ε/2, growing with ε): this support
                # drops entries the shifted duals need, or keeps ones they cannot have; the other
                switch(other)
                other = None
                continue
            eps *= SHIFT_GROWTH


def _bound(job: _BoundJob, tries: int, primal_bounds) -> DualBound:
    """The bound itself (module docstring), from a prepared job: the shifted re-solves on the
    compiled problem; when they prove nothing or a loose bound, the interior route (a tight
    re-solve and the least-cost interior direction, :func:`_interior_route`); when still nothing,
    the shifted re-solves on the problem with the objective cut, whose bound L counts as
    min(L, U) — each while the budget allows."""
    data, z, scale, out, t0 = job.data, job.z, job.scale, job.out, job.t0

    t1 = time.perf_counter()
    unrelated = data.enclose()
    out.times["enclosure"] = time.perf_counter() - t1
    if unrelated:
        out.why = unrelated
        out.times["total"] = time.perf_counter() - t0
        return out
    _search(job, tries, primal_bounds)
    first = getattr(job, "first", None)
    if first is not None and first.cone.worst < 0 and primal_bounds is None and \
            (not out.proved or first.value - out.lower > LOSS_TARGET * max(abs(first.value), 1e-300)) and \
            time.perf_counter() - job.t0 < job.interior_budget:
        inner = _interior_route(job, data, first, out)
        if inner is not None and inner.cone.worst >= 0 and (not out.proved or inner.value > out.lower):
            out.lower, out.proved, out.epsilon, out.theta, out.why = inner.value, True, 0.0, 0.0, ""
        elif not out.proved and getattr(job, "interior_why", ""):
            out.why = job.interior_why + "; " + out.why
    level = job.upper if job.upper is not None else job.objective
    if not out.proved and level is not None and math.isfinite(level) and \
            time.perf_counter() - job.t0 < job.budget:
        s0 = round_up(round_up(level + CUT_SLACK * max(abs(level), abs(data.q0), 1e-300)) - data.q0)
        cut = data.with_objective_cut(s0)
        if cut is not None:
            ceiling = round_down(round_down(data.q0 - data.q0_rad) + s0)    # ≤ U as written
            cut_out = DualBound()
            sub = _BoundJob(cut, np.append(z, 0.0), scale, _CutProblem(job.problem, scale, s0), job.theorem,
                            job.params, job.max_iter, cut_out, job.t0, job.upper, job.budget, job.objective)
            sub.cancel = getattr(job, "cancel", None)
            _search(sub, tries, primal_bounds)
            out.attempts += [dict(a, cut=True) for a in cut_out.attempts]
            out.extra_solves += cut_out.extra_solves
            out.times.update({f"cut_{k}": v for k, v in cut_out.times.items()})
            if cut_out.proved:
                # the cut problem's bound L gives min(L, U) (DualData.with_objective_cut)
                out.lower, out.proved, out.epsilon, out.theta, out.why = \
                    min(cut_out.lower, ceiling), True, cut_out.epsilon, cut_out.theta, ""
                out.residual, out.correction, out.min_eigenvalue = cut_out.residual, cut_out.correction, cut_out.min_eigenvalue
            else:
                out.why += "; with the objective cut: " + cut_out.why.split("; ")[0]
    if out.proved:
        out.why = ""                  # (a failed later try does not explain a proved bound)
        _map_performance(out, job.theorem, job.params, job.upper)
    out.times["total"] = time.perf_counter() - t0
    return out


def _map_performance(out: DualBound, theorem, params: dict, upper: float | None) -> None:
    """The performance at a proved bound: the map is proved monotone on [lower, the point's
    objective ``upper``]; the verdict uses it only when that point is proved feasible (else
    [lower, ∞), :func:`lmidsl.certify.verdict.bracket`)."""
    out.mapped_upto = upper
    found = performance_bound(theorem, params, out.lower, upper)
    if found is not None:
        setattr(out, f"{found[1]}_performance", found[0])


def frequency_route(instance, upper: float | None) -> DualBound | None:
    """The frequency-response bound (:mod:`lmidsl.certify.frequency_bound`) as a record, for an
    instance whose theorem's LMI is its declared bounded-real form; None for any other.  It needs
    no dual, so it also bounds a point from another backend or a Riccati route."""
    t0 = time.perf_counter()
    found = frequency_lower_bound(instance, upper)
    if found is None:
        return None
    out = DualBound(method="frequency")
    lower, how = found
    if lower is None:
        out.why = f"frequency response: {how}"
    else:
        out.lower, out.proved, out.how = lower, True, how
        _map_performance(out, instance.theorem, instance.params, upper)
    out.times["frequency"] = out.times["total"] = time.perf_counter() - t0
    return out


__all__ = ["DualBound", "lower_bound", "PendingBound", "BoundCancelled", "cancel_pending",
           "performance_bound", "performance_lower"]
