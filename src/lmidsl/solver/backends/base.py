"""What every backend shares: the compiling walk, the parameter store, the solve bookkeeping.

A backend subclasses :class:`CompiledModel` and fills in a handful of hooks (make a variable,
a parameter, a block matrix, an LMI constraint, a problem; solve; read a value).  Everything
else -- which sub-trees are constants (folded once with numpy), which scalar sub-expressions
of parameters become one backend parameter each (so that changing r̄ re-solves without
rebuilding, and products of parameters stay DPP-compliant), per-vertex instantiation (polytope vertices × points of uncertain symbols),
the strictness margin, and the backend-independent certificate -- lives here.

Strictness policy: a strict LMI ``N ≺ 0`` is imposed as ``N ⪯ −ε I`` and ``X ≻ 0`` as
``X ⪰ ε I`` with ``ε = margin`` (default :data:`DEFAULT_MARGIN`), an absolute number applied
after any exact rescaling of the data; non-strict LMIs get ε = 0.  Whatever the solver says,
the reported certificate is the largest eigenvalue of each N at the returned point.
"""
from __future__ import annotations

import time

import numpy as np
import sympy as sp

from ...numeric.instance import Instance
from ...numeric.evaluate import NumericEvaluator
from ..solution import Solution, evaluate_performance, lmi_certificate, objective_enclosure
from ..equilibration import Equilibration
from ..status import solved
from ...symbolic.parameter_values import parameter_value
from ...symbolic.symbols import DECISION_TYPES, DerivedParam, Param, ScalarVariable, StructuredVariable
from ...symbolic.uncertainty import scenarios
from ...symbolic.walker import ExpressionWalker, structure


def solver_crashed(exc: BaseException, expected: tuple = ()) -> bool:
    """Whether ``exc`` is a solver's own crash (a status "solver_error", not an lmidsl bug):
    one of ``expected``, or a Rust solver's panic (Clarabel's "Eigval error"), which pyo3 raises
    as ``PanicException``, a BaseException, so ``except Exception`` does not see it."""
    return isinstance(exc, expected) or type(exc).__name__ == "PanicException"

DEFAULT_MARGIN = 1e-7


def _times(value, factor: float):
    return value if factor == 1.0 else value * factor


def classify(expr) -> tuple[bool, bool]:
    """(contains a decision variable, contains a parameter), the parameters inside a structured
    variable's expansion included.

    Cached per node by identity (:func:`~lmidsl.symbolic.walker.structure`): theorem trees are
    immutable and compiled again at every bind, and sympy's deep equality is too slow to pay on
    every lookup.
    """
    return structure(expr, _classify)


def _classify(expr) -> tuple[bool, bool]:
    if isinstance(expr, (sp.Symbol, sp.MatrixSymbol)):          # a leaf: what it is
        return (isinstance(expr, DECISION_TYPES),
                isinstance(expr, (Param, DerivedParam)) or
                isinstance(expr, StructuredVariable) and classify(expr.expansion)[1])
    decision = parameter = False                                # from its arguments, each cached
    for arg in expr.args:
        d, p = classify(arg)
        decision, parameter = decision or d, parameter or p
    return decision, parameter


class BackendCompiler(ExpressionWalker):
    """The compiling walk: constants folded with numpy, parameters and variables from the model."""

    def __init__(self, model: "CompiledModel", vertex: int | None):
        super().__init__(model.instance.dims, vertex)
        self.model = model
        self.constants = NumericEvaluator(model.instance.dims, model.instance.data, {}, vertex)

    def _dispatch(self, expr):
        has_decision, has_param = classify(expr)
        if not has_decision:
            if not has_param:
                return self.constants.visit(expr)
            if not isinstance(expr, sp.MatrixExpr) and not expr.has(sp.MatrixSymbol):
                return self.model.parameter_for(expr)  # a scalar of parameters only (not r·tr(W))
            if isinstance(expr, (sp.Inverse, sp.MatPow)):
                return self.folded(expr)
        return super()._dispatch(expr)

    def folded(self, expr):
        """A matrix of data and parameters that no backend algebra spells, (r I + D Dᵀ)⁻¹ with
        r a parameter: its number at the instance's parameter values; the model then compiles
        again when the parameters change (:meth:`CompiledModel.update`)."""
        self.model.folded_parameters = True
        evaluator = NumericEvaluator(self.dims, self.model.instance.data, self.model.instance.params, self.vertex)
        return evaluator.visit(expr)

    def context(self) -> str:
        theorem = self.model.instance.theorem.id
        lmi = self.model.current_lmi
        return f"{theorem}: LMI {lmi[0]}" if lmi else theorem

    def data(self, symbol):
        return self.constants.data(symbol)

    def variable(self, symbol):
        """The backend variable X̃, times the variable's conditioning factor s_X."""
        variable = self.model.variable_for(symbol, self.vertex)
        factor = self.model.equilibration.variable(symbol.name)
        return variable if factor == 1.0 else factor * variable

    scalar_variable = variable

    def parameter(self, symbol):
        return self.model.parameter_for(symbol)

    def identity(self, n):
        return np.eye(n)

    def block(self, rows):
        return self.model.assemble(rows)

    def congruence(self, value, factor: float):
        """A walked block times the conditioning's factor t_i t_j."""
        return _times(value, factor)


class CompiledModel:
    """A bound theorem compiled once for one backend; parameters can be changed and re-solved.

    Every scalar expression of parameters is one backend parameter, so :meth:`update` changes
    numbers in place (cvxpy: DPP, compiled once).  The strictness margin is a backend parameter
    too when ``reuse=True`` (a model re-solved many times, e.g. a sweep); a one-shot model keeps it
    a number and recompiles in the rare :meth:`set_margin`.  (Folding the parameters of one-shot
    models into constants canonicalises ~10 % faster in cvxpy, but changes the rounding of the
    problem data enough to make Clarabel fail on seed 002's successive LMIs: measured, not done.)
    Backends that cannot change numbers in place (PICOS) recompile on every change.
    """

    backend = "abstract"
    compiler_class = BackendCompiler
    #: whether :meth:`set_parameter` changes a number inside a built problem (cvxpy); otherwise
    #: parameters are numbers and a problem with new ones is built again (PICOS, direct)
    mutable_parameters = True
    solved_once = False      # whether the last solve returned a point (values() reads it)
    folded_parameters = False  # a parameter inside an inverse was compiled as a number
    tightened: frozenset = frozenset()  # non-strict LMIs imposed with the margin (tighten())

    def __init__(self, instance: Instance, margin: float | None = None, reuse: bool = False,
                 conditioning: Equilibration | None = None):
        """``conditioning``: the congruence and variable scaling to compile with
        (:func:`lmidsl.solver.conditioning.equilibrate`); None compiles the theorem as written."""
        self.instance = instance
        self.conditioning = conditioning
        self.equilibration = conditioning if conditioning is not None else Equilibration()
        self.reuse = reuse  # True: the backend keeps its compiled form for re-solves (sweeps)
        self.margin = DEFAULT_MARGIN if margin is None else float(margin)
        self._variables: dict = {}
        self._compile()

    def _compile(self) -> None:
        """The walk: every LMI at every vertex and scenario, the objective, the problem.  The
        variables made so far are kept (a backend that recompiles on :meth:`update` reuses them)."""
        t0 = time.perf_counter()
        instance = self.instance
        self._parameters: dict = {}
        self._congruence: dict = {}   # LMI key -> diagonal of T (the congruence of conditioning)
        self.constraints: list = []
        self.lmi_matrices: list = []  # ((label, vertex, point), assembled backend expression N)
        self.current_lmi = None       # (label, vertex, point) being compiled, for error messages
        theorem = instance.theorem
        # a model that is re-solved keeps ε as a backend parameter; a one-shot model a number
        self._margin_parameter = self.new_parameter("margin", self.margin) if self.reuse else self.margin
        for key, lmi, negative, compiler, rows, t in self.walk_lmis(lambda v: self.compiler_class(self, v)):
            size = sum(compiler.size(s) for s in negative.sizes)
            eps = self._margin_parameter if lmi.strict or lmi.label in self.tightened else None
            N = self.assemble(rows)
            self.lmi_matrices.append((key, N))
            self._congruence[key] = np.concatenate(
                [np.full(compiler.size(s), t[i]) for i, s in enumerate(negative.sizes)])
            self.constraints.append((key, self.lmi_constraint(N, size, eps)))
        objective = None
        if theorem.objective is not None:
            objective = self.compiler_class(self, None).visit(theorem.objective)
        self.objective = objective
        scaled = objective if objective is None or self.equilibration.objective == 1.0 \
            else objective * (1.0 / self.equilibration.objective)
        self.problem = self.make_problem(scaled, [c for _, c in self.constraints])
        self.compile_time = time.perf_counter() - t0

    def walk_lmis(self, compiler_for):
        """Every LMI at every polytope vertex and uncertainty point, walked by
        ``compiler_for(vertex)``: yields (key, lmi, its form N ≺ 0, the compiler, the rows of
        walked blocks, the factors t).  The congruence T N T of :mod:`lmidsl.solver.conditioning` is applied
        (block (i, j) times t_i t_j, :meth:`BackendCompiler.congruence`), and the upper triangle
        holds the transposes of the lower one.  The compile and the enclosure of its coefficients
        (:mod:`lmidsl.certify.as_written`) walk the same blocks in the same order."""
        for index, lmi in enumerate(self.instance.theorem.lmis):
            negative = lmi.negative_form()
            t = [self.equilibration.row(index, i) for i in range(negative.nblocks)]
            for scenario in scenarios(self.instance, lmi):  # polytope vertices x uncertainty points
                key = (lmi.label, scenario.vertex, scenario.label)
                self.current_lmi = key
                compiler = compiler_for(scenario.vertex)
                lower = [[compiler.congruence(compiler.visit(scenario.apply(b)), t[i] * t[j])
                          for j, b in enumerate(row)] for i, row in enumerate(negative.lower)]
                rows = [[lower[i][j] if j <= i else compiler.transpose(lower[j][i])
                         for j in range(negative.nblocks)] for i in range(negative.nblocks)]
                yield key, lmi, negative, compiler, rows, t
        self.current_lmi = None

    # -- shared bookkeeping -------------------------------------------------------------
    def variable_for(self, symbol, vertex):
        per_vertex = getattr(symbol, "per_vertex", False)
        key = (symbol.name, vertex if per_vertex else None)
        if key not in self._variables:
            if isinstance(symbol, ScalarVariable):
                decl = self.instance.theorem.var_decl[symbol.name]
                self._variables[key] = self.new_scalar(symbol.name, decl.extra.get("nonneg", False))
            else:
                shape = tuple(int(sp.sympify(d).xreplace(self.instance.dims)) for d in symbol.shape)
                label = symbol.name if key[1] is None else f"{symbol.name}_{key[1] + 1}"
                self._variables[key] = self.new_variable(label, shape, symbol.kind)
        return self._variables[key]

    def _parameter_value(self, expr) -> float:
        params = self.instance.params
        if isinstance(expr, (Param, DerivedParam)):
            return float(params[expr.name])
        return parameter_value(expr, params)

    def parameter_for(self, expr):
        """One backend parameter per distinct scalar expression of parameters."""
        if expr not in self._parameters:
            self._parameters[expr] = self.new_parameter(str(expr), self._parameter_value(expr))
        return self._parameters[expr]

    def set_margin(self, margin: float) -> None:
        """Change the strictness margin ε (in place when ``reuse``, else by recompiling)."""
        if not self.reuse:
            self.__init__(self.instance, margin=margin, reuse=False, conditioning=self.conditioning)
            return
        self.margin = float(margin)
        self.set_parameter(self._margin_parameter, self.margin)

    def tighten(self, labels) -> None:
        """Impose the non-strict LMIs ``labels`` as ``N ⪯ −εI`` too, and compile again: a
        non-strict LMI active at the optimum leaves the solver's point on its boundary, where no
        proof can show ``N ⪯ 0`` (:func:`lmidsl.solver.margin.solve_model`)."""
        self.tightened = frozenset(labels)
        self._compile()

    def update(self, instance: Instance) -> None:
        """Take new parameter values (same data and dimensions) without recompiling (unless a
        parameter sits inside an inverse: then compile again)."""
        self.instance = instance
        if self.folded_parameters:
            self._compile()
            return
        for expr, p in self._parameters.items():
            self.set_parameter(p, self._parameter_value(expr))

    def values(self) -> dict:
        """Solved values of every declared decision variable (per-vertex ones as lists)."""
        out = {}
        for name, decl in self.instance.theorem.var_decl.items():
            symbol = decl.symbol
            if symbol.kind == "structured":
                continue
            if getattr(symbol, "per_vertex", False):
                keys = [(name, v) for v in range(self.instance.nvertices)]
                if all(k in self._variables for k in keys):
                    out[name] = [self._unscaled(name, self._variables[k]) for k in keys]
            elif (name, None) in self._variables:
                out[name] = self._unscaled(name, self._variables[(name, None)])
        return out

    def _unscaled(self, name: str, variable):
        """X = s_X X̃ from the backend variable X̃.  A variable the solved problem does not
        constrain (W₃ in B₃W₃ with the datum B₃ = 0: the compiled problem has no entry of it)
        has no value from the solver; any value is as good, and it is 0."""
        value = self.value_of(variable)
        if value is None and self.solved_once:
            shape = tuple(getattr(variable, "shape", ()))
            value = np.zeros(shape) if shape else 0.0
        factor = self.equilibration.variable(name)
        return value if value is None or factor == 1.0 else value * factor

    def assign(self, values: dict) -> None:
        """Give the backend variables values (same layout as :meth:`values`), e.g. to compare
        the assembled LMI matrices of two backends at one point (golden tests)."""
        for (name, vertex), variable in self._variables.items():
            value = values[name]
            if vertex is not None:
                value = value[vertex]
            self.set_value(variable, np.asarray(value, dtype=float) / self.equilibration.variable(name))

    def lmi_values(self) -> dict:
        """Numeric value of every assembled LMI matrix N at the current variable values (the
        conditioning congruence undone: the theorem's own N)."""
        out = {}
        for key, N in self.lmi_matrices:
            d = self._congruence[key]
            value = self.expression_value(N)
            if value is not None:           # None: a variable of N has no value
                out[key] = np.asarray(value, dtype=float) / np.outer(d, d)
        return out

    def level_problem(self, bound: float):
        """The feasibility problem 'every LMI, and objective ≤ bound': a point inside the strict
        set at a prescribed level rather than on its boundary at the optimum."""
        return self.make_problem(None, [c for _, c in self.constraints] + [self.objective <= bound])

    def solve(self, solver: str | None = None, problem=None, **options) -> Solution:
        """Solve (``problem``: default the compiled one), then evaluate the certificate at the
        returned point with numpy."""
        instance = self.instance
        t0 = time.perf_counter()
        status, objective, message, solver_time = self.run_solver(solver, problem, **options)
        if problem is None and objective is not None:
            objective *= self.equilibration.objective      # the compiled objective was divided
        wall = time.perf_counter() - t0
        solution = Solution(instance.theorem.id, instance.example, self.backend,
                            self.solver_name(solver), status, objective, margin=self.margin,
                            message=message, params=dict(instance.params), instance=instance)
        solution.times = {"compile": self.compile_time, "solve": wall}
        if not self.equilibration.trivial:
            solution.conditioning = self.equilibration.as_dict()
        if solver_time is not None:
            solution.times["solver"] = solver_time
        if getattr(self, "last_solver_call", None) is not None:
            solution.times["solver_call"] = self.last_solver_call  # incl. the solver's interface
        self.solved_once = solved(status)
        if solved(status):
            t1 = time.perf_counter()
            values = self.values()
            solution.values = values
            point = dict(instance.data)
            point.update(values)
            solution.congruence = self._congruence
            numbers = self.lmi_values() if self.backend == "direct" else None    # the affine form's values
            solution.lmis = lmi_certificate(instance, point, congruence=self._congruence, matrices=numbers)
            solution.point_gamma = evaluate_performance(instance, point)
            solution.objective_bounds = objective_enclosure(instance, point)
            if solution.point_gamma is None and instance.theorem.performance is not None:
                solution.notes.append(f"{instance.theorem.performance[0]} is not real at the returned "
                                      f"point ({instance.theorem.performance[1]} with a negative radicand)")
            solution.times["certificate"] = time.perf_counter() - t1
        return solution

    # -- backend hooks ------------------------------------------------------------------
    def new_variable(self, name: str, shape: tuple, kind: str):
        raise NotImplementedError

    def new_scalar(self, name: str, nonneg: bool):
        raise NotImplementedError

    def new_parameter(self, name: str, value: float):
        raise NotImplementedError

    def set_parameter(self, parameter, value: float) -> None:
        raise NotImplementedError

    def assemble(self, rows):
        raise NotImplementedError

    def lmi_constraint(self, N, size: int, eps):
        """N ⪯ −eps·I (eps a backend parameter) or N ⪯ 0 when eps is None."""
        raise NotImplementedError

    def make_problem(self, objective, constraints):
        raise NotImplementedError

    def run_solver(self, solver, problem=None, **options):
        """Solve ``problem`` (default: the compiled one); return (status, objective value,
        message, solver time or None); may set ``self.last_solver_call`` to the wall time of the
        solver call with its interface."""
        raise NotImplementedError

    def margin_sensitivity(self) -> float | None:
        """d(objective)/dε at the last solve: Σ_k tr Z_k over the strict LMIs' dual matrices
        (the objective moves by about ε·Σ tr Z_k because of the margin), None if unknown."""
        return None

    def shifted_lmi_constraint(self, N, t, size: int):
        """``N ⪯ t I`` for a scalar variable ``t`` (auxiliary problems such as feasp)."""
        return self.lmi_constraint(N - t * np.eye(size), size, None)

    def norm_bound(self, radius: float):
        """‖(all decision variables stacked)‖₂ ≤ radius: the feasibility radius of LMI Lab's feasp."""
        raise NotImplementedError

    def solver_name(self, solver) -> str:
        raise NotImplementedError

    def value_of(self, variable):
        raise NotImplementedError

    def set_value(self, variable, value) -> None:
        raise NotImplementedError

    def expression_value(self, expression):
        raise NotImplementedError
