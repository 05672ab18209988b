"""The Theorem object: one paper theorem, stated once, in the paper's notation.

A theorem file creates a :class:`Theorem`, declares dimensions, data, decision variables and
scalar parameters, writes each LMI as a block triangle with the paper's label, states the
objective, the recovery formulas and (optionally) the analysis theorem that certifies the
recovered design, and lists named examples with the values the paper prints.

Every LMI is checked when it is declared: each block's products, sums and traces must conform
(symbolic dimensions, see :mod:`lmidsl.symbolic.shapes`) and each block must be affine in the decision
variables (:mod:`lmidsl.symbolic.linearity`).  Errors name the theorem, the LMI label and the block.
The objective is checked the same way (and must be a scalar); recovery formulas and factor
arguments for shapes.  A sympy node the library has no rule for is refused at declaration.
"""
from __future__ import annotations

from typing import Any

import sympy as sp

from ..symbolic.blocks import BlockMatrixSpec, MatrixInequality, block_matrix
from ..errors import TheoremDefinitionError
from ..symbolic.linearity import check_affine
from ..symbolic.shapes import check_conformance, dims_equal, fmt_shape
from ..symbolic.uncertainty import uncertain_symbol
from ..symbolic.symbols import (ConstantMatrix, DataMatrix, DerivedParam, as_symbolic, DiagonalVariable, Dim, Param, RecoveredMatrix,
                      ScalarVariable, StructuredVariable, SymmetricDataMatrix, SymmetricVariable,
                      Variable, metadata_snapshot, restore_metadata)
from . import index_set as _ix
from .members import specialise
from .values import (DESIGN_KINDS, FIGURES, LATEX_RENDERER, LMI, TIME_DOMAINS, AnalysisLink, Bisection, BoundedRealForm,
                     OutputFeedbackForm, StateFeedbackForm, Declaration, Derivation, ErrorSystemLink, Example, FactorStep, SignalScaling, Source,
                     check_provenance)


class Theorem:
    """A theorem: declarations, LMIs, objective, recovery, analysis counterpart, examples."""

    def __init__(self, id: str, title: str | None = None, source: Source | None = None, *, description: str = "",
                 time: str = "discrete", designs: str | None = None,
                 sample_time: float | None = None, provenance: str = "paper",
                 provenance_note: str = ""):
        if time not in TIME_DOMAINS:
            raise TheoremDefinitionError(f"{id}: time must be one of {TIME_DOMAINS}, got {time!r}")
        if designs is not None and designs not in DESIGN_KINDS:
            raise TheoremDefinitionError(f"{id}: designs must be one of {DESIGN_KINDS}, got {designs!r}")
        check_provenance(id, provenance, provenance_note)
        self.id = id
        self.title = id if title is None else title                  # quick mode: an id is enough
        self.source = Source("stated in Python", "") if source is None else source
        self.description = description
        self.time = time
        self.designs = designs              # what the recovery produces: filter, controller, ...
        self.sample_time = sample_time      # of a discrete-time design (None: unspecified)
        self.provenance = provenance
        self.provenance_note = provenance_note
        self.dims: dict[str, Dim] = {}
        self.data_decl: dict[str, Declaration] = {}
        self.var_decl: dict[str, Declaration] = {}
        self.param_decl: dict[str, Declaration] = {}
        self.derived_decl: dict[str, Declaration] = {}
        self.notation: dict[str, Declaration] = {}
        self.uncertain_decl: dict[str, Declaration] = {}
        self.lmis: list[LMI] = []
        self.objective: sp.Expr | None = None
        self.performance: tuple[str, sp.Expr] | None = None
        self.recovery: dict[str, sp.MatrixExpr] = {}
        self.recovered_decl: dict[str, Declaration] = {}   # recovered matrices, as symbols
        self.recovery_steps: list = []          # ("formula", name) or FactorStep, in order
        self.intermediate_decl: dict[str, Declaration] = {}
        self.scalings: list[SignalScaling] = []
        self.conditioned: list[sp.MatrixExpr] = []
        self.analysis: AnalysisLink | None = None
        self.bounded_real: BoundedRealForm | None = None   # Theorem.bounded_real_form
        self.state_feedback: StateFeedbackForm | None = None  # Theorem.state_feedback_form
        self.output_feedback: OutputFeedbackForm | None = None  # Theorem.output_feedback_form
        self.certification: ErrorSystemLink | None = None
        self.simulator = None                  # Theorem.simulated_by
        self.linearisation: dict[str, sp.MatrixExpr] = {}
        self.examples: dict[str, Example] = {}
        self.reported: dict[str, sp.Expr] = {}
        self.checks: list = []
        self.index_sets: dict = {}             # name -> IndexSet (theorem/index_set.py)
        self.indexed_decl: dict = {}           # name -> IndexedFamily (A[i], P[i], K[i])
        self.coefficient_decl: dict = {}       # name -> CoefficientFamily (Pi[i, j])
        self.indexed_recovery: dict = {}       # name -> (formula, family, quantifier)
        self._members: dict = {}               # sizes -> member theorem (index sets)
        self.assumptions: list = []           # Theorem.assume (lmidsl.theorem.assumptions)

    # -- pickling ----------------------------------------------------------------------
    def __getstate__(self) -> dict:
        """A pickled theorem (the build cache, a Dask worker) carries the metadata of its symbols
        (LaTeX names, descriptions, definitions), which lives in a table of this process: its
        own and those of another theorem's symbols its LMIs use (a printed form written with the
        solved theorem's variables)."""
        tags = {self.id, f"{self.id}#derivation"}
        tags |= {getattr(s, "tag", None) for lmi in self.lmis for s in lmi.symbols()}
        return {**self.__dict__, "_members": {}, "_symbol_metadata": metadata_snapshot(tags)}

    def __setstate__(self, state: dict) -> None:
        state = dict(state)
        restore_metadata(state.pop("_symbol_metadata", {}))
        self.__dict__.update(state)

    # -- declarations -------------------------------------------------------------------
    def __repr__(self) -> str:
        return f"<Theorem {self.id}: {self.title} ({len(self.lmis)} LMIs)>"

    def _repr_latex_(self) -> str | None:
        """The theorem's LMIs in LaTeX (Jupyter shows them typeset), by the printer registered
        in :data:`LATEX_RENDERER`; None (the plain repr) when none is registered."""
        render = LATEX_RENDERER.get("theorem")
        return None if render is None else render(self)

    def _check_new(self, name: str):
        taken = (self.dims.keys() | self.data_decl.keys() | self.var_decl.keys()
                 | self.param_decl.keys() | self.derived_decl.keys() | self.notation.keys()
                 | self.uncertain_decl.keys() | self.intermediate_decl.keys()
                 | self.recovered_decl.keys() | getattr(self, "indexed_decl", {}).keys()
                 | getattr(self, "coefficient_decl", {}).keys())
        if name in taken:
            raise TheoremDefinitionError(f"{self.id}: the name {name!r} is declared twice")

    def dim(self, names: str) -> Dim | tuple[Dim, ...]:
        """Declare dimensions: ``n, k = thm.dim("n k")``."""
        made = []
        for name in names.split():
            self._check_new(name)
            self.dims[name] = Dim(name)
            made.append(self.dims[name])
        return made[0] if len(made) == 1 else tuple(made)

    @staticmethod
    def _describe(symbol, latex, description):
        symbol.latex_name = latex or symbol.name
        symbol.description = description
        return symbol

    def data(self, name: str, rows, cols, *, latex: str | None = None, description: str = "",
             symmetric: bool = False, per_vertex: bool = False, over=None) -> DataMatrix:
        """Declare a given matrix of shape rows × cols (dimension symbols or integers); ``over``
        an index set (or a tuple of them): one matrix per member, ``A[i]`` (see
        :mod:`lmidsl.theorem.index_set`)."""
        self._check_new(name)
        if over is not None:
            return self._indexed(name, "data", rows, cols, over, latex, description, symmetric)
        cls = SymmetricDataMatrix if symmetric else DataMatrix
        symbol = self._describe(cls(name, rows, cols, self.id), latex, description)
        symbol.per_vertex = per_vertex
        self.data_decl[name] = Declaration(symbol, symbol.latex_name, description)
        return symbol

    def var(self, name: str, rows, cols=None, *, kind: str = "full", latex: str | None = None,
            description: str = "", per_vertex: bool = False, over=None):
        """Declare a decision matrix; ``kind`` is 'full', 'symmetric' or 'diagonal'; ``over`` an
        index set (or a tuple of them): one variable per member, ``P[i]``."""
        self._check_new(name)
        classes = {"full": Variable, "symmetric": SymmetricVariable, "diagonal": DiagonalVariable}
        if kind not in classes:
            raise TheoremDefinitionError(f"{self.id}: variable {name}: unknown kind {kind!r}")
        cols = rows if cols is None else cols
        if kind != "full" and sp.expand(sp.sympify(rows) - sp.sympify(cols)) != 0:
            raise TheoremDefinitionError(f"{self.id}: {kind} variable {name} must be square")
        if over is not None:
            return self._indexed(name, kind, rows, cols, over, latex, description)
        symbol = self._describe(classes[kind](name, rows, cols, self.id), latex,
                                 description)
        symbol.per_vertex = per_vertex
        self.var_decl[name] = Declaration(symbol, symbol.latex_name, description)
        return symbol

    def scalar(self, name: str, *, latex: str | None = None, description: str = "",
               nonneg: bool = False) -> ScalarVariable:
        """Declare a scalar decision variable (e.g. g = γ², a multiplier ε)."""
        self._check_new(name)
        symbol = self._describe(ScalarVariable(name, self.id), latex, description)
        self.var_decl[name] = Declaration(symbol, symbol.latex_name, description, {"nonneg": nonneg})
        return symbol

    def structured(self, name: str, rows, *, latex: str | None = None, description: str = "",
                   symmetric: bool = False) -> StructuredVariable:
        """Declare a named matrix assembled from other variables, e.g. Λ = [[X, Z], [Z, Z]]."""
        self._check_new(name)
        expansion = sp.BlockMatrix(rows)
        shape = check_conformance(expansion, where=f"{self.id}: structured variable {name}")
        symbol = self._describe(StructuredVariable(name, *shape, self.id), latex,
                                 description)
        symbol.expansion = expansion
        symbol.symmetric = symmetric
        symbol.per_vertex = any(getattr(a, "per_vertex", False) for a in expansion.atoms(sp.MatrixSymbol))
        self.var_decl[name] = Declaration(symbol, symbol.latex_name, description)
        return symbol

    def param(self, name: str, *, latex: str | None = None, description: str = "",
              domain: tuple[float, float] | None = None, open_domain: bool = False,
              domain_note: str = "", default: float | None = None) -> Param:
        """Declare a scalar parameter.

        ``domain`` = (low, high) is checked at bind time, closed unless ``open_domain``;
        ``domain_note`` says why (it is printed with the error).
        """
        self._check_new(name)
        symbol = self._describe(Param(name, self.id), latex, description)
        self.param_decl[name] = Declaration(symbol, symbol.latex_name, description,
                                            {"domain": domain, "open": open_domain,
                                             "note": domain_note, "default": default})
        return symbol

    def derived(self, name: str, definition, *, latex: str | None = None,
                description: str = "") -> DerivedParam:
        """Declare a named scalar defined from parameters, e.g. a = (1 − r̄) r̄."""
        self._check_new(name)
        symbol = self._describe(DerivedParam(name, self.id), latex, description)
        symbol.definition = sp.sympify(definition)
        self.derived_decl[name] = Declaration(symbol, symbol.latex_name, description)
        return symbol

    def define(self, name: str, expr, *, latex: str | None = None, description: str = ""):
        """Name a matrix expression as the paper does (A_cl0 = [[A, 0], [r̄ B_f C, A_f]]).

        Returns ``expr`` unchanged: LMIs and the compiler see the expression; the LaTeX
        printer prints ``latex`` in its place and states the definition below the LMI.
        """
        self._check_new(name)
        self.notation[name] = Declaration(expr, latex or name, description)
        return expr

    def uncertain(self, name: str, rows=None, cols=None, *, bound, pattern=None, points=None,
                  latex: str | None = None, description: str = ""):
        """Declare an uncertain scalar |Δ| ≤ bound (or matrix |Δ_ij| ≤ bound) entering affinely.

        Every LMI that mentions it is imposed at the vertices (or at the ``points`` an instance
        chooses, in units of the bound) with common variables; see :mod:`lmidsl.symbolic.uncertainty`.
        """
        self._check_new(name)
        symbol = uncertain_symbol(self.id, name, rows, cols, bound=bound, pattern=pattern,
                                  latex=latex, description=description)
        self.uncertain_decl[name] = Declaration(symbol, symbol.latex_name, description,
                                                {"bound": symbol.bound, "points": points})
        return symbol

    # -- index sets (theorem/index_set.py) -------------------------------------------------
    def index_set(self, name: str, *, key: str | None = None, size: str = "N",
                  latex: str | None = None, description: str = ""):
        """Declare an index set {1, …, N} (modes, rules, subsystems); N is the length of the list
        of objects under ``key`` (default: the name) in the data.  ``size`` names N (it may
        appear in LMIs: ``(M.size - 1) * X``)."""
        self._check_new(name)
        if name in self.index_sets:
            raise TheoremDefinitionError(f"{self.id}: the index set {name} is declared twice")
        made = _ix.IndexSet(self, name, key or name, size, latex, description)
        self.index_sets[name] = made
        return made

    def _indexed(self, name, kind, rows, cols, over, latex, description, symmetric=False):
        sets = tuple(over) if isinstance(over, (tuple, list)) else (over,)
        for s in sets:
            if not isinstance(s, _ix.IndexSet) or self.index_sets.get(s.name) is not s:
                raise TheoremDefinitionError(f"{self.id}: {name}: over={s!r} is not an index set "
                                             f"of this theorem")
        family = _ix.IndexedFamily(self, name, kind, rows, cols, sets, latex, description, symmetric)
        self.indexed_decl[name] = family
        # the template declares the generic member A[i] (printing: tables of data and variables)
        generic = family[tuple(s.generic_index for s in sets)]
        table = self.data_decl if kind == "data" else self.var_decl
        table[name] = Declaration(generic, family.latex, description, {"indexed": True})
        return family

    def coefficients(self, name: str, over, *, structure: str | None = None,
                     latex: str | None = None, matrix_latex: str | None = None,
                     description: str = "", diagonal: str = "given"):
        """Declare a matrix of scalar coefficients over an index set, used as ``Pi[i, j]``; bound
        as one N×N datum whose ``structure`` ('generator', 'stochastic', 'nonnegative') is
        checked at bind time; ``diagonal="complete"``: the diagonal completes each row
        (π_ii = −Σ_{j≠i} π_ij, :mod:`lmidsl.theorem.structure`); ``latex`` names the entries
        (π → π_ij), ``matrix_latex`` the matrix (Π)."""
        self._check_new(name)
        if not isinstance(over, _ix.IndexSet):
            raise TheoremDefinitionError(f"{self.id}: coefficients {name}: over must be an index set")
        family = _ix.CoefficientFamily(self, name, over, structure, latex, description, diagonal)
        self.coefficient_decl[name] = family
        symbol = self._describe(DataMatrix(f"{name}#matrix", over.size, over.size, self.id),
                                matrix_latex or name, description)
        self.data_decl[name] = Declaration(symbol, symbol.latex_name, description, {"indexed": True})
        return family

    def specialise(self, inputs: dict) -> "Theorem":
        """The theorem for these inputs: itself, or the member of a family the inputs select
        (:func:`lmidsl.theorem.members.specialise`, the one family protocol)."""
        return specialise(self, inputs)

    def member_rule(self):
        """How this theorem selects its members (:mod:`lmidsl.theorem.members`): by the sizes of
        its index sets, or None (no family)."""
        return _ix.IndexSetRule() if self.index_sets else None

    def fingerprint(self) -> tuple:
        """What a derived object (a member, a map of the objective) depends on, by content or by
        the identity of immutable parts: a theorem changed after a solve (another ``minimize``, one
        more LMI, a new recovery) gets a new fingerprint, so nothing built from it is reused."""
        return (tuple(id(l) for l in self.lmis), self.objective, self.performance,
                tuple(self.var_decl), tuple(self.data_decl), tuple(self.param_decl), tuple(self.derived_decl),
                tuple((k, v) for k, v in self.recovery.items()), len(self.recovery_steps),
                len(self.assumptions), tuple(self.index_sets), tuple(self.indexed_decl))

    def inputs_for(self, inputs: dict) -> dict:
        """The inputs in this theorem's own names (a member of an indexed theorem flattens
        ``"modes": [{"A": …}, …]`` into ``A_1, …``); unchanged for any other theorem."""
        template = getattr(self, "template", None)
        if template is None:
            return inputs
        return _ix.flatten_inputs(template, inputs, self.member_sizes)

    def determined(self) -> set:
        """The decision variables the LMIs declared so far determine: every variable in an LMI
        block (a structured variable's entries included)."""
        seen: set = set()
        for lmi in self.lmis:
            for symbol in lmi.symbols():
                seen.add(symbol)
                if isinstance(symbol, StructuredVariable):
                    seen |= symbol.expansion.atoms(sp.Symbol, sp.MatrixSymbol)
        return seen

    def _check_determined(self, expr, what: str):
        """Refuse (one line) a decision variable in ``expr`` that no LMI declared so far
        mentions: its value at the solution would be whatever the solver left there.  ``what``
        says where the expression is used ("the recovery of Af", "the objective")."""
        determined = self.determined()
        names = {getattr(s, "name", None) for s in determined}
        for symbol in sorted(sp.sympify(expr).atoms(sp.Symbol, sp.MatrixSymbol), key=str):
            if (isinstance(symbol, (Variable, ScalarVariable, StructuredVariable))
                    and symbol not in determined
                    and not (len(getattr(symbol, "args", ())) > 4 and symbol.name in names)):
                raise TheoremDefinitionError(
                    f"{self.id}: {what} uses the decision variable {symbol.name}, which is in no "
                    f"LMI declared before it, so the LMIs do not determine it (declare the LMIs "
                    f"first, or use a variable of the LMIs)")

    # -- conditions ---------------------------------------------------------------------
    def lmi(self, label, rows=None, *, sense: str | None = None, triangle: str = "lower", sizes=None,
            strict: bool = True, description: str = "", forall=None, where=None) -> LMI:
        """Declare the block LMI ``label``: one triangle of blocks, ``sense`` '<' (default) or '>'
        (strict, imposed with the margin), '<=' or '>=' (non-strict).  ``thm.lmi(rows)`` labels
        it itself: (1), (2), ...; a single matrix is the one-block LMI ``[[M]]``; an inequality
        written with operators (``A.T @ P + P @ A << 0``, ``P >> 0``, ``X <= Y``:
        :class:`~lmidsl.symbolic.blocks.MatrixInequality`) gives its own sense; a numpy array in
        a block is constant data (:func:`~lmidsl.symbolic.symbols.constant_matrix`), given in the
        example 'data'.

        With indices (:meth:`index_set`): ``forall`` the quantified indices (default: every free
        index), ``where`` a condition on them (``i < j``, ``Ne(i, j)``); one LMI per instance
        at bind time."""
        condition = where
        if rows is None:
            label, rows = f"({len(self.lmis) + 1})", label
        where = f"{self.id}: LMI {label}"
        rows, sense = self._lmi_rows(where, rows, sense)
        if sense not in ("<", ">", "<=", ">="):
            raise TheoremDefinitionError(f"{where}: sense must be '<', '>', '<=' or '>=', got {sense!r}")
        if any(l.label == label for l in self.lmis):
            raise TheoremDefinitionError(f"{self.id}: LMI label {label} is used twice")
        given = isinstance(rows, BlockMatrixSpec)
        if not given:      # each block's own products and sums first: a block's size is then its own
            for i, row in enumerate(rows):
                for j, blk in enumerate(row if isinstance(row, list) else [row]):
                    if isinstance(blk, sp.MatrixExpr):
                        check_conformance(blk, where=f"{where} block ({i + 1},{j + 1 + (i if triangle == 'upper' else 0)})")
        spec = block_matrix(rows, triangle=triangle, sizes=sizes, where=where)
        for i, row in enumerate(spec.lower):
            for j, blk in enumerate(row):
                at = f"{where} block ({i + 1},{j + 1})"
                if given:
                    check_conformance(blk, where=at)
                check_affine(blk, where=at)
        lmi = LMI(label, spec, sense, strict and sense in ("<", ">"), description)
        if any(isinstance(a, RecoveredMatrix) for a in lmi.symbols()):
            raise TheoremDefinitionError(f"{where}: uses a recovery intermediate (declared by factor)")
        lmi.per_vertex = any(getattr(s, "per_vertex", False) for s in lmi.symbols())
        quantifier = _ix.quantifier_for(self.id, f"LMI {label}", [b for r in spec.lower for b in r],
                                        forall, condition)
        if quantifier is not None:
            lmi.quantifier = quantifier
        self._declare_constants(lmi.symbols())
        self.lmis.append(lmi)
        return lmi

    @staticmethod
    def _lmi_rows(where: str, rows, sense):
        """The rows of an LMI as ``block_matrix`` takes them, and its sense: an inequality written
        with operators gives both, a single matrix is ``[[M]]``; every other slip is one line."""
        if isinstance(rows, MatrixInequality):
            if sense is not None and sense != rows.sense:
                raise TheoremDefinitionError(f"{where}: {rows} already states its sense "
                                             f"{rows.sense!r}; sense={sense!r} contradicts it")
            rows, sense = rows.rows, rows.sense
        sense = "<" if sense is None else sense
        if isinstance(rows, (sp.MatrixExpr, BlockMatrixSpec)) or type(rows).__module__ == "numpy":
            rows = rows if isinstance(rows, BlockMatrixSpec) else [[as_symbolic(rows)]]
        elif isinstance(rows, (bool, sp.logic.boolalg.Boolean)) or not isinstance(rows, (list, tuple)):
            raise TheoremDefinitionError(
                f"{where}: expected blocks [[...], ...], a matrix or an inequality such as "
                f"A.T @ P + P @ A << 0, got {type(rows).__name__} {rows!r}"
                + (" (a scalar comparison is not an LMI: compare a matrix, e.g. P >> 0)"
                   if isinstance(rows, (bool, sp.logic.boolalg.Boolean)) else ""))
        if isinstance(rows, BlockMatrixSpec):
            return rows, sense
        out = []
        for i, row in enumerate(rows):
            for j, blk in enumerate(row if isinstance(row, (list, tuple)) else [row]):
                if isinstance(blk, MatrixInequality):
                    raise TheoremDefinitionError(
                        f"{where} block ({i + 1},{j + 1}): {blk} is an inequality inside the blocks: "
                        f"write thm.lmi([[...]] , sense=...) or thm.lmi(M << 0), the inequality outside")
            out.append([as_symbolic(b) for b in row] if isinstance(row, (list, tuple)) else as_symbolic(row))
        return out, sense

    def _declare_constants(self, symbols) -> None:
        """Declare the numpy constants an LMI uses as data, their values in the example 'data'."""
        for c in sorted((s for s in symbols if isinstance(s, ConstantMatrix)), key=lambda s: s.name):
            if c.name not in self.data_decl:
                self.data_decl[c.name] = Declaration(c, c.latex_name, c.description)
                example = self.examples.get("data") or self.example(
                    "data", {}, description="the constants written in the LMIs")
                example.data[c.name] = c.value

    def assume(self, assumption):
        """Declare a hypothesis on the data (:mod:`lmidsl.theorem.assumptions`: ``zero("D11")``,
        ``stable("A")``, ``full_rank(...)``), checked when data are bound: exit 2 if it fails; its
        datum must be declared before (or the assumption marked ``external=True``)."""
        assumption.check_declared(self)
        self.assumptions.append(assumption)
        return assumption

    def positive(self, *variables, label: str | None = None, forall=None, where=None) -> list[LMI]:
        """Declare ``X > 0`` for each variable (labelled 'X > 0' unless ``label`` is given);
        ``P[i]`` of an index set: for every i."""
        return [self.lmi(label or f"{v.name} > 0", [[v]], sense=">", forall=forall, where=where)
                for v in variables]

    def minimize(self, objective, *, performance: tuple[str, Any] | None = None):
        """Minimise a scalar objective affine in the decision variables (``g``, ``g1 + g2``,
        ``Trace(Z)``, ``Trace(W*Z) + g``); ``performance`` = (name, expr) e.g. ('gamma', √g) or
        ('h2', √tr(Z)).  Checked like an LMI block: shapes, a 1×1 result, affinity."""
        objective = sp.sympify(objective)
        where = f"{self.id}: objective {objective}"
        shape = check_conformance(objective, where=where)
        if not (dims_equal(shape[0], 1) and dims_equal(shape[1], 1)):
            raise TheoremDefinitionError(f"{where} is {fmt_shape(shape)}, not a scalar "
                                         f"(minimise a scalar of it, e.g. Trace(...))")
        check_affine(objective, where=where)
        self._check_determined(objective, "the objective")
        self.objective = objective
        self._set_performance(performance)
        return self                           # lmidsl.solve(thm.minimize(g)) in quick mode

    def feasibility(self, *, performance: tuple[str, Any] | None = None):
        """A feasibility problem (no objective); ``performance`` = (name, expr) names the level
        the LMIs are stated at, e.g. ('gamma', γ) for a prescribed γ parameter."""
        self.objective = None
        self._set_performance(performance)

    def _set_performance(self, performance):
        if performance is not None:
            name, expr = performance[0], sp.sympify(performance[1])
            check_conformance(expr, where=f"{self.id}: performance {name}")
            self._check_determined(expr, f"the performance {name}")
            self.performance = (name, expr)

    def report(self, **values):
        """Named scalar values evaluated at the solution, e.g. ``gamma_1=sqrt(rho_1)``.

        They are printed with the solution and, when the analysis theorem declares the same
        names, compared with the analysis values.
        """
        for name, expr in values.items():
            expr = sp.sympify(expr)
            self._check_determined(expr, f"the report of {name}")
            self.reported[name] = expr

    def verify_with(self, *checks):
        """Extra certificates run after recovery: callables ``check(solution) -> CheckResult``
        (frequency sweeps, simulations; see :mod:`lmidsl.theorem.checks`)."""
        self.checks.extend(checks)

    def recover_each(self, forall, **formulas):
        """Recovery formulas for every member, e.g. ``K = thm.recover_each(i, K=W[i] * Y[i].I)``
        (Kᵢ = WᵢYᵢ⁻¹ for every i); returns the indexed families (``K[i]``)."""
        made = []
        q = _ix.quantifier_for(self.id, "recovery", list(formulas.values()), forall, None)
        if q is None:
            raise TheoremDefinitionError(f"{self.id}: recover_each: no index in {list(formulas)}")
        for name, expr in formulas.items():
            where = f"{self.id}: recovery of {name}"
            shape = check_conformance(expr, where=where)
            self._check_determined(expr, f"the recovery of {name}")
            self._check_new(name)
            sets = tuple(self.index_sets[k.set_name] for k in q.indices)
            family = _ix.IndexedFamily(self, name, "recovered", shape[0], shape[1], sets, None, "")
            self.indexed_decl[name] = family
            self.indexed_recovery[name] = (sp.sympify(expr), family, q)
            self.recovery[name] = sp.sympify(expr)      # printed as K = W_i Y_i^{-1}
            self.recovery_steps.append(("formula", name))
            made.append(family)
        return made[0] if len(made) == 1 else tuple(made)

    def recover(self, **formulas):
        """Recovery formulas, e.g. ``Af=V2.I * Af_hat``: evaluated after the solve, in order.

        Returns the recovered matrices as symbols (one, or a tuple in the order given), which
        later recovery formulas may use: ``K = thm.recover(K=W * Y.I)`` then
        ``thm.recover(F=K * C)``.  Every decision variable a formula uses must be in an LMI
        declared before it (else the LMIs would not determine the design).
        """
        symbols = []
        for name, expr in formulas.items():
            where = f"{self.id}: recovery of {name}"
            shape = check_conformance(expr, where=where)
            self._check_determined(expr, f"the recovery of {name}")
            if name in self.recovery:
                raise TheoremDefinitionError(f"{where}: {name} is recovered twice")
            self._check_new(name)
            symbol = self._describe(RecoveredMatrix(name, *shape, self.id), None, "")
            self.recovered_decl[name] = Declaration(symbol, symbol.latex_name, "")
            self.recovery[name] = expr
            self.recovery_steps.append(("formula", name))
            symbols.append(symbol)
        return symbols[0] if len(symbols) == 1 else tuple(symbols)

    def factor(self, names: str, factorization, *args, latex: str | None = None,
               description: str = ""):
        """Recovery intermediates computed by a library factorisation, e.g.
        ``R, S = thm.factor("R S", rs_split, I - X*Z.I)`` for R Sᵀ = I − X Z⁻¹.

        ``factorization`` is a :class:`lmidsl.numeric.factorization.Factorization`; its arguments are
        matrix expressions evaluated at the solved point.  The returned symbols may be used in
        later recovery formulas (``Af = R.I * Af_hat * ...``).
        """
        names = names.split()
        shapes = [check_conformance(a, where=f"{self.id}: factor {' '.join(names)}") for a in args]
        for a in args:
            self._check_determined(a, f"the factorisation {' '.join(names)}")
        out = factorization.shapes(*shapes)
        if len(out) != len(names):
            raise TheoremDefinitionError(
                f"{self.id}: factor {' '.join(names)}: {factorization.name} gives {len(out)} matrices")
        symbols = []
        latex = (latex or "").split() or names
        for name, shape, tex in zip(names, out, latex):
            self._check_new(name)
            symbol = self._describe(RecoveredMatrix(name, *shape, self.id), tex, description)
            self.intermediate_decl[name] = Declaration(symbol, symbol.latex_name, description)
            symbols.append(symbol)
        self.recovery_steps.append(FactorStep(tuple(names), factorization, tuple(args)))
        return symbols[0] if len(symbols) == 1 else tuple(symbols)

    def scale_signal(self, signal: str, *, rows=(), cols=(), recovered_rows=(), recovered_cols=(),
                     description: str = "") -> SignalScaling:
        """Declare an exact rescaling of ``signal`` the library may apply and undo (see
        :class:`SignalScaling` and :mod:`lmidsl.numeric.scaling`)."""
        for name in (*rows, *cols):
            if name not in self.data_decl:
                raise TheoremDefinitionError(f"{self.id}: scaling of {signal}: {name} is not declared data")
        decl = SignalScaling(signal, tuple(rows), tuple(cols), tuple(recovered_rows),
                             tuple(recovered_cols), description)
        self.scalings.append(decl)
        return decl

    def well_conditioned(self, *exprs):
        """Positive definite expressions the recovery inverts (e.g. Z and X − Z); the back-off
        (:mod:`lmidsl.solver.backoff`) improves their conditioning at a γ slightly above the optimum."""
        for expr in exprs:
            at = f"{self.id}: well_conditioned {expr}"
            check_conformance(expr, where=at)
            check_affine(expr, where=at)
            self.conditioned.append(expr)

    def bounded_real_form(self, storage, level, system: tuple):
        """Declare that the LMIs are the bounded real lemma of ``system`` = (A, B, C, D) with
        storage ``storage`` ≻ 0 and level ``level`` = γ² (continuous: He(PA) ⊕ −gI ⊕ −I with
        the couplings PB, C, D; discrete: the Stein form).  Besides an SDP solver, the library
        may then take P from the Riccati equation at a given level
        (:mod:`lmidsl.numeric.riccati`) and prove the LMIs at that point: a certificate that
        does not depend on an SDP solver's accuracy."""
        at = f"{self.id}: bounded_real_form"
        if storage.name not in self.var_decl or level.name not in self.var_decl:
            raise TheoremDefinitionError(f"{at}: {storage} and {level} must be declared variables")
        if len(system) != 4:
            raise TheoremDefinitionError(f"{at}: system must be (A, B, C, D)")
        for expr in system:
            check_conformance(expr, where=at)
        self.bounded_real = BoundedRealForm(storage, level, tuple(system))

    def state_feedback_form(self, Y, W, level, plant: tuple):
        """Declare that the LMIs are the H∞ state-feedback LMIs of ``plant`` = (A, B1, B2, C1, D11,
        D12) (Gahinet–Apkarian: the closed loop's bounded real lemma with −γI on both diagonal
        blocks, congruence-transformed by Y = P⁻¹, W = K Y) with ``level`` = γ.  The library may
        then build a point from the full-information Riccati equation
        (:func:`lmidsl.numeric.riccati.full_information_gain`) when no SDP solver gives one."""
        at = f"{self.id}: state_feedback_form"
        if any(v.name not in self.var_decl for v in (Y, W, level)):
            raise TheoremDefinitionError(f"{at}: {Y}, {W} and {level} must be declared variables")
        if len(plant) != 6:
            raise TheoremDefinitionError(f"{at}: plant must be (A, B1, B2, C1, D11, D12)")
        for expr in plant:
            check_conformance(expr, where=at)
        self.state_feedback = StateFeedbackForm(Y, W, level, tuple(plant))

    def output_feedback_form(self, X, Y, Ah, Bh, Ch, Dh, level, plant: tuple):
        """Declare that the LMIs are the full-order H∞ output-feedback LMIs of ``plant`` = (A, B1,
        B2, C1, C2, D11, D12, D21) in the linearising variables of Scherer, Gahinet and Chilali
        (:func:`lmidsl.output_feedback_blocks`; −γI on both diagonal blocks, ``level`` = γ).  The
        library may then prove a lower bound on γ from the full-information and full-control
        problems the LMI contains (:mod:`lmidsl.certify.frequency_bound`)."""
        at = f"{self.id}: output_feedback_form"
        if any(v.name not in self.var_decl for v in (X, Y, Ah, Bh, Ch, Dh, level)):
            raise TheoremDefinitionError(f"{at}: {X}, {Y}, {Ah}, {Bh}, {Ch}, {Dh} and {level} must be "
                                         f"declared variables")
        if len(plant) != 8:
            raise TheoremDefinitionError(f"{at}: plant must be (A, B1, B2, C1, C2, D11, D12, D21)")
        for expr in plant:
            check_conformance(expr, where=at)
        self.output_feedback = OutputFeedbackForm(X, Y, Ah, Bh, Ch, Dh, level, tuple(plant))

    def linearise(self, **updates):
        """Data that are a linearisation point, with their update from a solved point.

        E.g. ``Sbar=S.I``: after a solve, the datum ``Sbar`` is replaced by ``S⁻¹`` and the LMI
        is solved again (BMI by successive LMIs, :mod:`lmidsl.studies.bmi`).
        """
        for name, expr in updates.items():
            if name not in self.data_decl:
                raise TheoremDefinitionError(f"{self.id}: linearisation point {name} is not declared data")
            check_conformance(expr, where=f"{self.id}: linearisation of {name}")
            self.linearisation[name] = expr

    def certified_by(self, theorem, design: tuple, gamma_tolerance: float = 1e-3,
                     criterion: str | None = None):
        """Name the analysis theorem (a :class:`Theorem`, or the id of one in another file) that
        certifies the recovered ``design`` matrices, which it takes as data.  ``criterion``:
        "level" (the analysis certifies the synthesis γ within ``gamma_tolerance``), "feasible"
        (a stabilisation design: the analysis LMIs proved with the design fixed, no level), or
        None (default): inferred from the analysis theorem — "feasible" when it is a feasibility
        problem, "level" when it minimises (:func:`lmidsl.certify.analysis.certificate_criterion`)."""
        if criterion not in (None, "level", "feasible"):
            raise TheoremDefinitionError(f"{self.id}: certified_by: criterion must be 'level' or 'feasible'")
        target = theorem if isinstance(theorem, Theorem) else None
        self.analysis = AnalysisLink(theorem.id if target is not None else str(theorem), tuple(design),
                                     gamma_tolerance, target, criterion)

    def error_system(self, system, *, figure: str, design: tuple, simulate=None):
        """Declare the error system (data + design -> stochastic system), its figure and simulation."""
        if figure not in FIGURES:
            raise TheoremDefinitionError(f"{self.id}: error_system: figure must be one of {', '.join(FIGURES)}")
        missing = [f for f in design if f not in self.data_decl]
        if missing:
            raise TheoremDefinitionError(f"{self.id}: error_system: design matrices {missing} are not declared data")
        self.certification = ErrorSystemLink(system, figure, tuple(design), simulate)

    def simulated_by(self, simulator):
        """Declare the paper's own simulation of its original model with a design, used by
        ``lmidsl simulate``: ``simulator(instance, design, *, scenarios, horizon, disturbance,
        seed) -> SimulationTable``, where ``design`` is the recovered design (None for an
        analysis theorem: the design is in the instance's data) and ``scenarios`` the runs asked
        for (None: the simulator's defaults)."""
        self.simulator = simulator

    def example(self, name: str, data: dict, *, params: dict | None = None,
                printed: dict | None = None, vertices: list | None = None,
                description: str = "", printed_note: str = "", provenance: str = "paper",
                provenance_note: str = "", expect: str = "certified", expect_note: str = "") -> Example:
        """Attach a named example with the values the paper prints (``provenance``: see
        :data:`~lmidsl.theorem.values.PROVENANCE`; an example not from the paper says so)."""
        ex = Example(name, data, params or {}, printed or {}, vertices, description, printed_note,
                     provenance, provenance_note, expect, expect_note)
        self.examples[name] = ex
        return ex

    # -- queries ------------------------------------------------------------------------
    @property
    def variables(self) -> list:
        return [d.symbol for d in self.var_decl.values()]

    @property
    def per_vertex_names(self) -> set:
        return {n for n, d in self.data_decl.items() if d.symbol.per_vertex}

    def first_use(self, symbol) -> str:
        """'LMI (30) block (4,3) V1.T*B' for the first block that mentions ``symbol``."""
        for lmi in self.lmis:
            for i, row in enumerate(lmi.spec.lower):
                for j, blk in enumerate(row):
                    if symbol in blk.atoms(sp.MatrixSymbol, sp.Symbol):
                        return f"LMI {lmi.label} block ({i + 1},{j + 1}) {blk}"
        for name, expr in self.recovery.items():
            if symbol in expr.atoms(sp.MatrixSymbol):
                return f"the recovery of {name}"
        return "no LMI"

    def summary(self) -> dict:
        return {"id": self.id, "title": self.title, "source": str(self.source),
                "time": self.time, "designs": self.designs, "provenance": self.provenance,
                "provenance_note": self.provenance_note, "examples": list(self.examples),
                "example_provenance": {n: e.provenance for n, e in self.examples.items()}}

    # -- research declarations: derivations, bisection ---------------------------------------
    derivations: tuple = ()
    bisection: Bisection | None = None

    def auxiliary(self, name: str, rows, cols=None, *, latex: str | None = None,
                  description: str = "") -> DataMatrix:
        """A matrix that only a derivation mentions (M, G22 of a slack's structure): drawn at
        random by ``lmidsl derive-check``, never bound, compiled or solved."""
        symbol = DataMatrix(name, rows, rows if cols is None else cols, f"{self.id}#derivation")
        return self._describe(symbol, latex, description)

    def derived_from(self, source, source_label: str, label: str, *, congruence=None,
                     substitute: dict | None = None, schur=(), recovers: dict | None = None,
                     note: str = "") -> Derivation:
        """State that LMI ``label`` of this theorem is Tᵀ·schur(``source_label``)·T of ``source``
        after ``substitute`` (see :class:`~lmidsl.theorem.values.Derivation`); ``congruence`` is
        the list of T's diagonal blocks (``I`` sized from the block), ``schur`` 1-based source
        blocks to eliminate, ``recovers`` what each recovery formula must give."""
        where = f"{self.id}: derivation of {label} from {getattr(source, 'id', source)} {source_label}"
        if not isinstance(source, Theorem):
            raise TheoremDefinitionError(f"{where}: the source must be a Theorem object")
        labels = {l.label: l for l in source.lmis}
        if source_label not in labels:
            raise TheoremDefinitionError(f"{where}: {source.id} has no LMI {source_label}")
        if not any(l.label == label for l in self.lmis):
            raise TheoremDefinitionError(f"{where}: no LMI {label} in {self.id}")
        substitute = dict(substitute or {})
        for key, expr in substitute.items():
            if not isinstance(key, (sp.MatrixSymbol, sp.Symbol)):
                raise TheoremDefinitionError(f"{where}: substitute keys are symbols, got {key}")
            shape = check_conformance(sp.sympify(expr), where=f"{where}: substitute {key}")
            if isinstance(key, sp.MatrixSymbol) and not (dims_equal(shape[0], key.shape[0])
                                                          and dims_equal(shape[1], key.shape[1])):
                raise TheoremDefinitionError(f"{where}: {key} is {fmt_shape(key.shape)}, "
                                             f"its substitute {expr} is {fmt_shape(shape)}")
        schur = tuple(int(k) for k in schur)
        nsource = labels[source_label].spec.nblocks
        if any(not 1 <= k <= nsource for k in schur):
            raise TheoremDefinitionError(f"{where}: schur blocks must be in 1..{nsource}")
        if congruence is not None:
            congruence = tuple(congruence)
            for t in congruence:
                if isinstance(t, sp.MatrixExpr):
                    check_conformance(t, where=f"{where}: congruence block {t}")
        recovers = dict(recovers or {})
        unknown = [n for n in recovers if n not in self.recovery]
        if unknown:
            raise TheoremDefinitionError(f"{where}: recovers {unknown}: not recovered by {self.id}")
        d = Derivation(label, source, source_label, congruence, substitute, schur, recovers, note)
        self.derivations = (*self.derivations, d)
        return d

    def bisect(self, parameter: str, *, lower: float, upper: float, tol: float = 1e-4,
               goal: str = "max", performance: str = "") -> Bisection:
        """Solve by bisection on the scalar parameter ``parameter`` (it may multiply decision
        variables: a generalised eigenvalue problem, LMI Lab's ``gevp``): ``lmidsl solve`` finds
        the largest (``goal="max"``) or smallest (``"min"``) value in [lower, upper] at which the
        LMIs have a certified point, to ``tol`` (:mod:`lmidsl.studies.bisection`)."""
        if parameter not in self.param_decl:
            raise TheoremDefinitionError(f"{self.id}: bisect: {parameter} is not a declared parameter")
        if goal not in ("max", "min"):
            raise TheoremDefinitionError(f"{self.id}: bisect: goal must be 'max' or 'min'")
        if not (lower < upper and tol > 0):
            raise TheoremDefinitionError(f"{self.id}: bisect: need lower < upper and tol > 0")
        self.bisection = Bisection(parameter, float(lower), float(upper), float(tol), goal, performance)
        extra = self.param_decl[parameter].extra
        if extra.get("default") is None:
            # the bisection sets the parameter: data need not give it (bound at the feasible end)
            extra["default"] = float(lower) if goal == "max" else float(upper)
        return self.bisection

