"""The direct backend: a bound theorem compiled straight into Clarabel's standard form.

No modelling layer: the compiling walk (:mod:`lmidsl.solver.backends.base`) evaluates every LMI
into the sparse affine algebra of :mod:`lmidsl.solver.backends.affine`, and the problem handed to
the solver is

    minimise  qᵀx   subject to   s = b − A x,   s ∈ K = K₁ × … × K_m,

one cone per constraint: an LMI N(x) ⪯ −εI is svec(−N(x) − εI) in the PSD-triangle cone of
its size, a non-negative scalar variable or a level bound "objective ≤ β" is a non-negative
cone, and feasp's radius bound ‖x‖ ≤ R a second-order cone.  x stacks the free entries of every
decision variable (:class:`~lmidsl.solver.backends.affine.DecisionVariable`).  This is the
problem cvxpy builds for Clarabel from the same LMIs (symmetric variables by their upper
triangles, one PSD cone per LMI), without cvxpy's canonicalisation and without importing cvxpy;
the cvxpy and PICOS backends stay for cross-checks and as fallback routes.

Parameters are numbers here (as in the PICOS backend): :meth:`DirectModel.update` and
:meth:`DirectModel.set_margin` recompile, which is cheap.  Solver options are Clarabel's settings
by name (``max_iter``, ``tol_gap_rel``, ...), as with cvxpy's Clarabel interface.
"""
from __future__ import annotations

import os
import time

import clarabel
import numpy as np
from scipy import sparse

from ...errors import InputError, SolverUnavailableError
from . import backend_info
from .affine import Affine, Cone, VariableSpace, block, block_diagonal
from .base import BackendCompiler, CompiledModel, classify, solver_crashed
from ..status import (INFEASIBLE, INFEASIBLE_INACCURATE, OPTIMAL, OPTIMAL_INACCURATE, UNBOUNDED,
                      UNBOUNDED_INACCURATE, USER_LIMIT, SOLVER_ERROR, SOLVED)

DEFAULT_SOLVER = backend_info("direct").default

#: Clarabel's linear-algebra threads (0: by problem size, :func:`solver_threads`, as in local
#: Dask workers, so that a parallel run gives the serial run's numbers).
THREADS = int(os.environ.get("LMIDSL_SOLVER_THREADS", "0") or 0)

#: Below this many PSD-cone rows (svec entries, all LMIs together) one thread is faster than
#: Clarabel's default of every core; measured on 2 cores (seed 000 family, Theorem 3 of seed 001):
#: 1486 rows 0.15 s on 1 thread vs 0.17 s on 2, 2294 rows 1.82 s vs 2.04 s, 4386 rows 9.6 s vs
#: 9.4 s, and n = 20 (16,000 rows) 55 s vs 40 s.
SINGLE_THREAD_ROWS = 3000


#: Clarabel's threads above SINGLE_THREAD_ROWS: a fixed number, not "every core" (0): Clarabel's
#: answer depends on its thread count (n = 10 of seed 000's family, 2,294 rows: objective
#: 8.298465416 on one thread, 8.298459366 on two, each repeatable), so "every core" would make
#: the numbers depend on the machine
LARGE_PROBLEM_THREADS = 2


def solver_threads(problem) -> int:
    """Clarabel's ``max_threads`` for ``problem``: ``LMIDSL_SOLVER_THREADS`` if set, else one
    thread for small problems (thread start-up costs more than it saves) and
    :data:`LARGE_PROBLEM_THREADS` for large ones -- never a number that depends on the machine."""
    if THREADS:
        return THREADS
    psd_rows = sum(c.size for c in problem.cones if c.kind == "psd")
    return 1 if psd_rows < SINGLE_THREAD_ROWS else LARGE_PROBLEM_THREADS

#: Clarabel's statuses, named as the other backends name them (cvxpy's mapping of the same solver)
_STATUS = {
    "Solved": OPTIMAL,
    "AlmostSolved": OPTIMAL_INACCURATE,
    "PrimalInfeasible": INFEASIBLE,
    "AlmostPrimalInfeasible": INFEASIBLE_INACCURATE,
    "DualInfeasible": UNBOUNDED,
    "AlmostDualInfeasible": UNBOUNDED_INACCURATE,
    "MaxIterations": USER_LIMIT,
    "MaxTime": USER_LIMIT,
}


def sdp_solvers() -> list[str]:
    """The SDP solvers this backend calls directly (the module needs Clarabel to load at all)."""
    return ["CLARABEL"]


def resolve_solver(name: str | None) -> str:
    """The solver's name (case-insensitive), or a one-line error."""
    name = name or DEFAULT_SOLVER
    for candidate in sdp_solvers():
        if candidate.lower() == name.lower():
            return candidate
    raise SolverUnavailableError(
        f"unknown solver {name!r} for backend direct (it calls Clarabel only; use --backend cvxpy "
        f"or picos for {name})")


def psd_diagonal(problem) -> np.ndarray:
    """The vector with 1 on the diagonal entries of every PSD cone of ``problem`` (svec order):
    e with eᵀs = Σ_k tr S_k."""
    e, r0 = np.zeros(problem.A.shape[0]), 0
    for cone in problem.cones:
        if cone.kind == "psd":
            k = np.arange(cone.dim)
            e[r0 + k * (k + 1) // 2 + k] = 1.0
        r0 += cone.size
    return e


class ConicProblem:
    """min qᵀx + q₀ s.t. b − A x ∈ K, assembled from an objective and :class:`Cone` constraints.

    x here holds only the variables the problem uses (a feasp variable created later is not in
    the main problem): ``layout`` maps each used variable to its range.
    """

    def __init__(self, space: VariableSpace, objective: Affine | None, cones: list[Cone]):
        self.objective, self.cones = objective, cones
        used = np.zeros(space.size, dtype=bool)
        for part in cones + ([objective] if isinstance(objective, Affine) else []):
            used[part.cols] = True
        self.layout, column, n = {}, np.full(space.size, -1, dtype=np.int64), 0
        for v in space.variables:
            if used[v.offset: v.offset + v.size].any():
                self.layout[v] = n
                column[v.offset: v.offset + v.size] = np.arange(n, n + v.size)
                n += v.size
        self.n = n
        offsets = np.cumsum([0] + [c.size for c in cones])
        rows = np.concatenate([c.rows + o for c, o in zip(cones, offsets)]) if cones else np.zeros(0, np.int64)
        cols = np.concatenate([column[c.cols] for c in cones]) if cones else np.zeros(0, np.int64)
        vals = np.concatenate([-c.vals for c in cones]) if cones else np.zeros(0)   # s = b − A x
        self.A = sparse.csc_matrix((vals, (rows, cols)), shape=(int(offsets[-1]), n))  # duplicates add up
        self.b = np.concatenate([c.const for c in cones]) if cones else np.zeros(0)
        self.q, self.q0 = np.zeros(n), 0.0
        if isinstance(objective, Affine):
            self.q = np.bincount(column[objective.cols], weights=objective.vals, minlength=n)
            self.q0 = float(objective.const)
        elif objective is not None:
            self.q0 = float(objective)

    def clarabel_cones(self) -> list:
        kinds = {"psd": clarabel.PSDTriangleConeT, "nonneg": clarabel.NonnegativeConeT,
                 "soc": clarabel.SecondOrderConeT}
        return [kinds[c.kind](c.dim) for c in self.cones]


class DirectCompiler(BackendCompiler):
    """The shared compiling walk into the affine algebra; the value of a sub-expression without
    parameters is kept in the model across recompiles (:meth:`DirectModel.update`)."""

    def _dispatch(self, expr):
        if classify(expr)[1]:
            return super()._dispatch(expr)
        static = self.model._static
        key = (id(expr), self.vertex)
        hit = static.get(key)
        if hit is not None and hit[0] is expr:
            return hit[1]
        value = super()._dispatch(expr)
        if len(static) > 100_000:        # scenario copies of uncertain LMIs are new trees each time
            static.clear()
        static[key] = (expr, value)
        return value

    def trace(self, a):
        return a.trace() if isinstance(a, Affine) else super().trace(a)

    def block_diagonal(self, values, shapes):
        return block_diagonal(values, shapes)


class SolverCrash(Exception):
    """Clarabel raised on a problem (the first line of its message)."""


def clarabel_solve(problem, q=None, **options):
    """Clarabel's result for min qᵀx s.t. b − Ax ∈ K on ``problem`` (its own q by default), with
    the given Clarabel settings; raises :class:`SolverCrash` when Clarabel fails on the data, and
    :class:`~lmidsl.errors.InputError` for an unknown setting.  Touches no model: the proved lower
    bound's shifted solves call it from a worker thread (Clarabel releases the GIL)."""
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_threads = solver_threads(problem)
    for key, value in options.items():
        if not hasattr(settings, key):
            raise InputError(f"unknown Clarabel setting {key!r} (e.g. max_iter, tol_gap_rel, tol_feas)")
        setattr(settings, key, value)
    try:
        P = sparse.csc_matrix((problem.n, problem.n))
        return clarabel.DefaultSolver(P, problem.q if q is None else q, problem.A, problem.b,
                                      problem.clarabel_cones(), settings).solve()
    except BaseException as exc:
        if not solver_crashed(exc, (ArithmeticError, ValueError, np.linalg.LinAlgError)):
            raise
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise SolverCrash(text or "solver failed") from exc


class DirectModel(CompiledModel):
    backend = "direct"
    compiler_class = DirectCompiler
    mutable_parameters = False
    #: the dual shift ε of the main problem's solves (Clarabel's units; 0: none).  With ε > 0 the
    #: solver minimises qᵀx − ε Σ_k tr S_k(x) over the PSD cones S_k = −N_k − margin·I: its dual
    #: Z′ ⪰ 0 gives Z = Z′ + εI, a dual of the theorem with margin ε, from which
    #: :func:`lmidsl.certify.dual_bound.lower_bound` proves a lower bound without a second solve
    #: (the point is pushed inside by as little; the objective reported is the theorem's own,
    #: qᵀx + q₀ at the returned point).  Opt-in: off by default.
    dual_shift = 0.0

    def __init__(self, instance, margin=None, reuse=False, conditioning=None):
        self.space = VariableSpace()
        self._nonneg: list[Cone] = []
        self._last = None          # (problem, clarabel solution) of the last solve
        self.last_shift = 0.0      # the dual shift ε of that solve (see dual_shift)
        self._static: dict = {}    # (id, vertex) -> value of a parameter-free sub-expression
        super().__init__(instance, margin, reuse, conditioning)

    # -- leaves ------------------------------------------------------------------------
    def new_variable(self, name, shape, kind):
        return self.space.new(name, shape, kind).expression()

    def new_scalar(self, name, nonneg):
        x = self.space.new(name, ()).expression()
        if nonneg:
            self._nonneg.append(Cone.nonneg(x))
        return x

    def new_parameter(self, name, value):
        return float(value)           # numbers: update() recompiles

    def set_parameter(self, parameter, value):
        raise NotImplementedError("direct-backend parameters are numbers; update() recompiles")

    def update(self, instance) -> None:
        """New parameter values (same data): compile again, with the same variables and the
        parameter-free sub-expressions from the last compile (Clarabel has no parameters)."""
        self.instance = instance
        self._compile()

    def set_margin(self, margin: float) -> None:
        self.margin = float(margin)
        self._compile()

    # -- assembly ----------------------------------------------------------------------
    def assemble(self, rows):
        return block(rows)

    def lmi_constraint(self, N, size, eps):
        """N ⪯ −εI as svec(−N − εI) in the PSD-triangle cone."""
        S = -N if isinstance(N, Affine) else Affine((size, size), -np.asarray(N, dtype=float))
        if eps:
            S = S - eps * np.eye(size)
        return Cone.psd(S)

    def make_problem(self, objective, constraints):
        return ConicProblem(self.space, objective, list(constraints) + self._nonneg)

    def norm_bound(self, radius):
        """‖(vec of every decision variable, stacked)‖₂ ≤ R: (R, vec X₁, vec X₂, …) in a second-order cone."""
        rows, cols, r0 = [], [], 1
        for x in self._variables.values():
            v = x.variable
            rows.append(v.basis_rows + r0)
            cols.append(v.basis_cols + v.offset)
            r0 += int(np.prod(v.shape)) if v.shape else 1
        const = np.zeros(r0)
        const[0] = radius
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        return Cone("soc", r0, rows, cols, np.ones(len(rows)), const)

    # -- solving -------------------------------------------------------------------------
    def solver_name(self, solver):
        return resolve_solver(solver)

    def run_solver(self, solver, problem=None, **options):
        resolve_solver(solver)
        problem = self.problem if problem is None else problem
        for v in self.space.variables:
            v.free = None
        shift = self.dual_shift if problem is self.problem else 0.0
        q = problem.q + shift * (problem.A.T @ psd_diagonal(problem)) if shift else problem.q
        t0 = time.perf_counter()
        try:
            result = clarabel_solve(problem, q, **options)
        except SolverCrash as exc:
            return SOLVER_ERROR, None, str(exc), None
        self.last_solver_call = time.perf_counter() - t0
        self._last, self.last_shift = (problem, result), shift
        status = _STATUS.get(str(result.status), SOLVER_ERROR)
        message = "" if status != SOLVER_ERROR else f"CLARABEL: {result.status}"
        objective = None
        if status in SOLVED:
            x = np.asarray(result.x, dtype=float)
            for v, o in problem.layout.items():
                v.free = x[o: o + v.size]
            objective = float(result.obj_val) + problem.q0 if not shift else float(problem.q @ x) + problem.q0
            if not np.isfinite(objective):
                objective = None
        return status, objective, message, float(result.solve_time)

    def margin_sensitivity(self):
        """Σ_k tr Z_k over the LMIs' duals Z_k (in svec, the diagonal entries are unscaled)."""
        if self._last is None or self._last[0] is not self.problem:
            return None
        problem, result = self._last
        z = np.asarray(result.z, dtype=float)
        lmis = {id(c) for _, c in self.constraints}
        total, r0 = 0.0, 0
        for cone in problem.cones:
            if id(cone) in lmis:
                n = cone.dim
                diagonal = np.cumsum(np.arange(1, n + 1)) - 1       # (j, j) is the last of column j
                total += float(np.sum(z[r0 + diagonal]))
            r0 += cone.size
        if not np.isfinite(total):
            return None
        return abs(total) * self.equilibration.objective

    def value_of(self, variable):
        return variable.variable.value()

    def set_value(self, variable, value):
        variable.variable.set_value(value)

    def expression_value(self, expression):
        if not isinstance(expression, Affine):
            return np.asarray(expression, dtype=float)
        value = expression.value(self.space.vector())
        return None if value is None else np.asarray(value, dtype=float)
