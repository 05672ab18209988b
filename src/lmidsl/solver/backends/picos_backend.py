"""The PICOS backend: a bound theorem as a ``picos.Problem``.

Node mapping (the rest is the shared walk of :mod:`lmidsl.solver.backends.base`): a block matrix is
``picos.block``, an LMI ``N ⪯ −εI`` is ``N << -ε I``, a trace is ``picos.trace``, variables are
``picos.RealVariable`` / ``picos.SymmetricVariable`` (a diagonal variable is ``picos.diag`` of a
vector), and a matrix product is PICOS's ``*`` (in PICOS ``@`` is the Kronecker product, so the
walk's ``@`` must not reach a PICOS expression).  PICOS refuses an LMI whose matrix is not
structurally symmetric; that refusal is turned into an error naming the theorem and the LMI.

Parameters: PICOS 2.6 has no parameter object whose value can change inside a built problem
(its ``Constant`` is immutable, and a ``RealVariable`` frozen with ``frozen()`` gives a *new*
expression).  A scalar parameter expression (r̄, a = (1 − r̄) r̄, …) is therefore compiled as a
plain number, and :meth:`PicosModel.update` recompiles the model with the new values.

Solvers: whatever PICOS has installed that accepts LMI constraints (:func:`sdp_solvers`; CVXOPT
here, MOSEK/SMCP/QICS when installed).  PICOS 2.6 has no interface to Clarabel or SCS; asking for
them gives a one-line error that says so.
"""
from __future__ import annotations

from functools import lru_cache

import cvxopt
import numpy as np
import picos

from ...errors import InputError, SolverUnavailableError, TheoremDefinitionError
from . import backend_info
from .base import BackendCompiler, CompiledModel, solver_crashed
from ..status import INFEASIBLE, OPTIMAL, OPTIMAL_INACCURATE, SOLVER_ERROR, solved

DEFAULT_SOLVER = backend_info("picos").default

#: Options lmidsl passes unless the user overrides them.  PICOS's own defaults (all tolerances
#: 1e-8, up to 10⁶ iterations) make CVXOPT stall on these LMIs and then fail in its LDL retry;
#: CVXOPT's own defaults (the ones cvxpy uses too) let both backends run CVXOPT identically.
SOLVER_DEFAULTS = {
    "cvxopt": {"abs_ipm_opt_tol": 1e-7, "rel_ipm_opt_tol": 1e-6, "rel_prim_fsb_tol": 1e-7,
               "rel_dual_fsb_tol": 1e-7, "max_iterations": 100},
}


@lru_cache(maxsize=1)
def sdp_solvers() -> tuple[str, ...]:
    """Installed PICOS solvers that accept a semidefinite (LMI) constraint."""
    from picos.solvers import all_solvers
    X = picos.SymmetricVariable("X", 2)
    probe = picos.Problem()
    probe.set_objective("min", picos.trace(X))
    probe.add_constraint(X >> np.eye(2))
    footprint = probe.footprint
    return tuple(name for name, cls in sorted(all_solvers().items())
                 if cls.available() and cls.supports(footprint))


def resolve_solver(name: str | None) -> str:
    """The PICOS name of an installed SDP solver (case-insensitive), or a one-line error."""
    from picos.solvers import all_solvers
    if name is None:
        name = DEFAULT_SOLVER
    key = name.lower()
    available = sdp_solvers()
    if key in available:
        return key
    listed = ", ".join(available) or "none"
    if key not in all_solvers():
        raise SolverUnavailableError(
            f"PICOS {picos.__version__} has no interface for solver {name!r}; PICOS SDP solvers "
            f"installed here: {listed} (use --backend cvxpy for {name})")
    if not all_solvers()[key].available():
        raise SolverUnavailableError(
            f"PICOS solver {name!r} is not installed; PICOS SDP solvers installed here: {listed}")
    raise SolverUnavailableError(
        f"PICOS solver {name!r} cannot solve SDPs; PICOS SDP solvers installed here: {listed}")


def _is_picos(x) -> bool:
    return isinstance(x, picos.expressions.Expression)


class PicosCompiler(BackendCompiler):
    """The shared compiling walk with PICOS's spelling of the matrix product and trace."""

    def matmul(self, a, b):
        if _is_picos(a) or _is_picos(b):
            return a * b  # PICOS: * is the matrix product, @ the Kronecker product
        return a @ b

    def trace(self, a):
        return picos.trace(a) if _is_picos(a) else super().trace(a)


class PicosModel(CompiledModel):
    backend = "picos"
    compiler_class = PicosCompiler
    mutable_parameters = False

    def __init__(self, instance, margin=None, reuse=False, conditioning=None):
        self._scalars: set[str] = set()
        super().__init__(instance, margin, reuse, conditioning)

    # -- leaves ----------------------------------------------------------------------
    def new_variable(self, name, shape, kind):
        if kind == "symmetric":
            return picos.SymmetricVariable(name, shape[0])
        if kind == "diagonal":
            return picos.diag(picos.RealVariable(name, shape[0]))
        return picos.RealVariable(name, shape)

    def new_scalar(self, name, nonneg):
        self._scalars.add(name)
        return picos.RealVariable(name, lower=0 if nonneg else None)

    def new_parameter(self, name, value):
        return float(value)  # folded; see the module docstring

    def set_parameter(self, parameter, value):
        raise NotImplementedError("PICOS parameters are numbers; update() recompiles")

    def update(self, instance) -> None:
        """Take new parameter values: PICOS cannot change a built problem's numbers, so recompile."""
        self.__init__(instance, margin=self.margin, reuse=self.reuse, conditioning=self.conditioning)

    def set_margin(self, margin: float) -> None:
        """A new strictness margin: recompile (see :meth:`update`)."""
        self.__init__(self.instance, margin=margin, reuse=self.reuse, conditioning=self.conditioning)

    # -- assembly ----------------------------------------------------------------------
    def assemble(self, rows):
        if not any(_is_picos(x) for row in rows for x in row):
            return np.block([[np.atleast_2d(x) for x in row] for row in rows])
        return picos.block(rows)

    def lmi_constraint(self, N, size, eps):
        if not _is_picos(N):                   # a block without a decision variable: a constant LMI
            N = picos.Constant(np.atleast_2d(np.asarray(N, dtype=float)))
        try:
            return N << (-eps * np.eye(size) if eps is not None else np.zeros((size, size)))
        except ValueError as exc:
            label = self.current_lmi[0] if self.current_lmi else "?"
            raise TheoremDefinitionError(
                f"{self.instance.theorem.id}: LMI {label}: PICOS refuses the assembled matrix "
                f"({str(exc).splitlines()[0]})") from None

    def make_problem(self, objective, constraints):
        problem = picos.Problem()
        for c in constraints:
            problem.add_constraint(c)
        if objective is None or not _is_picos(objective):
            problem.set_objective("find")
        else:
            problem.set_objective("min", objective)
        return problem

    # -- solving -------------------------------------------------------------------------
    def solver_name(self, solver):
        return resolve_solver(solver)

    def run_solver(self, solver, problem=None, **options):
        name = resolve_solver(solver)
        problem = self.problem if problem is None else problem
        from picos.modeling.options import OPTIONS
        known = {o[0] for o in OPTIONS}
        unknown = sorted(set(options) - known)
        if unknown:
            raise InputError(f"unknown PICOS option(s) {', '.join(unknown)}; see picos.Options "
                             "(e.g. max_iterations, rel_ipm_opt_tol, abs_prim_fsb_tol)")
        settings = {"verbosity": 0, "primals": None, "duals": False,
                    **SOLVER_DEFAULTS.get(name, {}), **options}
        try:
            solution = problem.solve(solver=name, **settings)
        except BaseException as exc:  # any PICOS/solver failure is a status, not a crash
            if not solver_crashed(exc, (Exception,)):
                raise
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return SOLVER_ERROR, None, text, None
        primal, problem_status = solution.primalStatus, solution.problemStatus
        raw = solution.info.get("cvxopt_sol", {}) or {}
        message = f"{name}: {raw['status']}" if raw.get("status") not in (None, "optimal") else ""
        if problem_status == "infeasible":
            status = INFEASIBLE
        elif problem_status == "unbounded":
            status = "unbounded"
        elif primal == "optimal":
            status = OPTIMAL
        elif primal in ("feasible", "unknown", "premature") and solution.primals and \
                all(v is not None for v in solution.primals.values()):
            status = OPTIMAL_INACCURATE  # a point exists; the numpy certificate decides
        else:
            status = SOLVER_ERROR
            message = message or f"{name}: {solution.claimedStatus}"
        objective = None
        if solved(status):
            try:
                value = problem.value
                objective = float(value) if value is not None and np.isfinite(value) else None
            except Exception:
                objective = None
        return status, objective, message, solution.searchTime

    def norm_bound(self, radius):
        parts = [v.vec for v in self._variables.values()]
        return abs(picos.block([[p] for p in parts])) <= radius

    def value_of(self, variable):
        try:
            value = variable.value
        except Exception:  # not valued
            return None
        if value is None:
            return None
        arr = np.array(value, dtype=float)
        if getattr(variable, "name", None) in self._scalars:
            return float(arr.reshape(-1)[0])
        return arr.reshape(variable.shape)

    def set_value(self, variable, value):
        value = np.asarray(value, dtype=float)
        if not isinstance(variable, picos.expressions.BaseVariable):  # diag(x) of a diagonal variable
            (variable,) = variable.mutables
            value = np.diag(value) if value.ndim == 2 else value
        variable.value = value.reshape(variable.shape) if value.ndim else float(value)

    def expression_value(self, expression):
        if not _is_picos(expression):
            return np.asarray(expression, dtype=float)
        value = expression.value
        if isinstance(value, cvxopt.spmatrix):       # PICOS gives a sparse CVXOPT matrix for some values
            value = cvxopt.matrix(value)
        return np.array(value, dtype=float).reshape(expression.shape)
