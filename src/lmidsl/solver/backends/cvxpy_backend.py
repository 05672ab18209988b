"""The cvxpy backend: a bound theorem as a ``cvxpy.Problem`` with parameters kept as Parameters.

Node mapping (the rest is in :mod:`lmidsl.solver.backends.base`): a block matrix is ``cp.bmat``, an
LMI ``N ⪯ −εI`` is ``N << -ε I``, a trace is ``cp.trace``, variables are ``cp.Variable`` with
``symmetric=True`` or ``diag=True`` as declared, scalar parameter expressions are ``cp.Parameter``.  The problem is
DPP-compliant, so changing parameters and re-solving reuses cvxpy's compiled form.
"""
from __future__ import annotations

import warnings

import cvxpy as cp
import numpy as np

from ...errors import SolverUnavailableError
from . import backend_info, default_options
from .base import BackendCompiler, CompiledModel, solver_crashed
from ..status import INFEASIBLE, OPTIMAL, OPTIMAL_INACCURATE, SOLVER_ERROR

DEFAULT_SOLVER = backend_info("cvxpy").default

_STATUS = {
    cp.OPTIMAL: OPTIMAL,
    cp.OPTIMAL_INACCURATE: OPTIMAL_INACCURATE,
    cp.INFEASIBLE: INFEASIBLE,
    cp.INFEASIBLE_INACCURATE: "infeasible_inaccurate",
    cp.UNBOUNDED: "unbounded",
    cp.UNBOUNDED_INACCURATE: "unbounded_inaccurate",
}


def sdp_solvers() -> list[str]:
    """Installed cvxpy solvers that accept semidefinite constraints."""
    from cvxpy.reductions.solvers.defines import INSTALLED_CONIC_SOLVERS, SOLVER_MAP_CONIC
    out = []
    for name in INSTALLED_CONIC_SOLVERS:
        cones = {c.__name__ for c in getattr(SOLVER_MAP_CONIC.get(name), "SUPPORTED_CONSTRAINTS", [])}
        if cones & {"PSD", "SvecPSD"}:
            out.append(name)
    return out


def resolve_solver(name: str | None) -> str:
    """The cvxpy name of an installed SDP solver (case-insensitive), or a clear error."""
    if name is None:
        name = DEFAULT_SOLVER
    available = sdp_solvers()
    for candidate in available:
        if candidate.lower() == name.lower():
            return candidate
    installed = [s for s in cp.installed_solvers() if s.lower() == name.lower()]
    if installed:
        raise SolverUnavailableError(
            f"solver {name!r} is installed but cannot solve SDPs; cvxpy SDP solvers here: {', '.join(available)}")
    raise SolverUnavailableError(
        f"unknown solver {name!r} for backend cvxpy; installed SDP solvers: {', '.join(available)}")


class CvxpyCompiler(BackendCompiler):
    """The shared compiling walk with cvxpy's spelling of the trace."""

    def trace(self, a):
        return cp.trace(a) if isinstance(a, cp.Expression) else super().trace(a)


class CvxpyModel(CompiledModel):
    backend = "cvxpy"
    compiler_class = CvxpyCompiler

    def new_variable(self, name, shape, kind):
        if kind == "symmetric":
            return cp.Variable(shape, name=name, symmetric=True)
        if kind == "diagonal":
            return cp.Variable(shape, name=name, diag=True)
        return cp.Variable(shape, name=name)

    def new_scalar(self, name, nonneg):
        return cp.Variable(name=name, nonneg=nonneg)

    def new_parameter(self, name, value):
        return cp.Parameter(name=name, value=value)

    def set_parameter(self, parameter, value):
        parameter.value = value

    def assemble(self, rows):
        return cp.bmat(rows)

    def lmi_constraint(self, N, size, eps):
        return N << (-eps * np.eye(size) if eps is not None else np.zeros((size, size)))

    def make_problem(self, objective, constraints):
        return cp.Problem(cp.Minimize(objective if objective is not None else 0), constraints)

    def solver_name(self, solver):
        return resolve_solver(solver)

    def run_solver(self, solver, problem=None, **options):
        name = resolve_solver(solver)
        problem = self.problem if problem is None else problem
        try:
            with warnings.catch_warnings():
                # cvxpy warns "Solution may be inaccurate"; the status and certificate say so
                warnings.simplefilter("ignore", UserWarning)
                problem.solve(solver=name, **{**default_options(name), **options})
        except BaseException as exc:
            # a solver's own numerical crash (CVXOPT divides by zero on badly scaled LMIs,
            # Clarabel panics) is a failure of that solver, not of lmidsl: a status
            if not solver_crashed(exc, (cp.error.SolverError, ArithmeticError, ValueError,
                                        np.linalg.LinAlgError)):
                raise
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return SOLVER_ERROR, None, text or "solver failed", None
        status = _STATUS.get(problem.status, str(problem.status))
        # wall time of the solver call including its interface (cvxpy's own measurement)
        self.last_solver_call = getattr(problem, "_solve_time", None)
        stats = problem.solver_stats
        value = problem.value
        objective = float(value) if value is not None and np.isfinite(value) else None
        solver_time = getattr(stats, "solve_time", None)
        return status, objective, "", solver_time if solver_time is not None else self.last_solver_call

    def margin_sensitivity(self):
        total = 0.0
        for key, constraint in self.constraints:
            dual = constraint.dual_value
            if dual is None:
                return None
            total += float(np.trace(np.atleast_2d(dual)))
        return abs(total) * self.equilibration.objective   # duals of the scaled objective

    def norm_bound(self, radius):
        parts = [cp.reshape(v, (1,), order="F") if v.ndim == 0 else cp.vec(v, order="F")
                 for v in self._variables.values()]
        return cp.norm(cp.hstack(parts), 2) <= radius

    def value_of(self, variable):
        value = variable.value
        if value is None:
            return None
        if hasattr(value, "toarray"):
            value = value.toarray()
        return np.asarray(value, dtype=float) if np.ndim(value) else float(value)

    def set_value(self, variable, value):
        value = np.asarray(value, dtype=float)
        if variable.attributes.get("diag"):
            value = np.diag(np.diag(value)) if value.ndim == 2 else np.diag(value)
        variable.value = value if value.ndim else float(value)

    def expression_value(self, expression):
        value = expression.value
        return value.toarray() if hasattr(value, "toarray") else np.asarray(value, dtype=float)
