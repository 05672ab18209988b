"""The value types of a theorem statement: its source, LMIs, examples, links and provenance.

Plain data, no behaviour beyond small checks; :class:`~lmidsl.theorem.theorem.Theorem` builds
them from a theorem file's declarations.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from ..errors import TheoremDefinitionError
from ..symbolic.blocks import BlockMatrixSpec
from ..symbolic.walker import structure

TIME_DOMAINS = ("discrete", "continuous")

DESIGN_KINDS = ("filter", "controller", "observer", "gain", "unspecified")
"""What a synthesis theorem's recovery produces (``Theorem(..., designs=...)``)."""

PROVENANCE = {
    "paper": "the paper's own statement",
    "corrected": "a corrected reading of the paper (a typo or an inconsistency repaired)",
    "guessed": "a guessed reading where the paper is ambiguous or incomplete",
    "illustration": "not from the paper: an illustration or a variant for comparison",
}
"""Where a theorem or an example stands relative to its paper; anything but "paper" needs a note."""


OUTCOMES = ("certified", "not certified", "infeasible", "not solved")
"""What solving an example ends in, best first: the solution certified (every LMI proved, the
analysis and checks passed); solved but not certified; proved infeasible (a theorem-of-alternatives certificate); neither
a point proved nor infeasibility proved.  An example declares the outcome it is known to have (``expect``, default
certified); ``lmidsl reproduce`` fails when a row ends worse than that."""


def check_provenance(owner: str, provenance: str, note: str) -> None:
    if provenance not in PROVENANCE:
        raise TheoremDefinitionError(f"{owner}: provenance must be one of {', '.join(PROVENANCE)}, "
                                     f"got {provenance!r}")
    if provenance != "paper" and not note:
        raise TheoremDefinitionError(f"{owner}: provenance {provenance!r} needs a provenance_note "
                                     "saying what differs from the paper")


@dataclass(frozen=True)
class Source:
    """Where a theorem comes from: ``paper``, a short name of the paper (``lmidsl list`` shows it),
    ``equations``, its theorem and equation numbers, and ``citation``, the full reference (authors,
    title, venue), which stands in for the short name where there is room (reports, LaTeX)."""

    paper: str
    equations: str
    citation: str = ""

    def __str__(self):
        return f"{self.citation or self.paper}, {self.equations}"


LATEX_RENDERER: dict = {}
HTML_RENDERER: dict = {}
"""``{"html": f(result) -> str}``: how a result's ``_repr_html_`` writes it (the render layer
registers :func:`lmidsl.render.notebook.html` here when it is imported, as for LaTeX below)."""
"""``{"theorem": f(theorem) -> str, "lmi": f(lmi) -> str}``: how a theorem's and an LMI's
``_repr_latex_`` write them.  The printer lives in the render layer, above this one, which
registers itself here when it is imported (:mod:`lmidsl.render.notebook`; ``lmidsl``'s public face
imports it with :class:`Theorem`), so that this layer never imports the one above it."""


def symbols_in(expr) -> frozenset:
    """``expr.atoms(Symbol, MatrixSymbol)`` (a matrix symbol's dimensions included), each shared
    sub-tree counted once (:func:`~lmidsl.symbolic.walker.structure`): the coefficient LMIs of a
    Pólya relaxation share their products P_k A_i, which sympy's traversal visits every time."""
    out = frozenset((expr,)) if isinstance(expr, (sp.Symbol, sp.MatrixSymbol)) else frozenset()
    for arg in expr.args:
        out |= structure(arg, symbols_in)
    return out


@dataclass
class LMI:
    """A labelled block LMI ``M < 0`` (or ``M > 0``) as the paper writes it."""

    label: str
    spec: BlockMatrixSpec
    sense: str = "<"
    strict: bool = True
    description: str = ""
    per_vertex: bool = False
    _negative: BlockMatrixSpec | None = field(default=None, repr=False, compare=False)
    _symbols: frozenset | None = field(default=None, repr=False, compare=False)

    def negative_form(self) -> BlockMatrixSpec:
        """The matrix N with the LMI stated as N ≺ 0 (N = M for '<', N = −M for '>'); built once."""
        if self.sense in ("<", "<="):
            return self.spec
        if self._negative is None:
            lower = [[-b for b in row] for row in self.spec.lower]
            self._negative = BlockMatrixSpec(lower, self.spec.sizes, self.spec.given_as)
        return self._negative

    def _repr_latex_(self) -> str | None:
        """The LMI in LaTeX for a notebook, by the printer the render layer registers in
        :data:`LATEX_RENDERER` (None: the plain repr)."""
        render = LATEX_RENDERER.get("lmi")
        return None if render is None else render(self)

    def symbols(self) -> set:
        """Every symbol in the LMI's blocks (computed once; an LMI does not change)."""
        if self._symbols is None:
            atoms = frozenset()
            for row in self.spec.lower:
                for b in row:
                    atoms |= structure(b, symbols_in)
            self._symbols = atoms
        return self._symbols


@dataclass
class Example:
    """A named numerical instance with the values the paper prints.

    ``data`` maps data names to matrices (nested lists) and dimension names to integers;
    ``vertices`` lists per-vertex data for polytopic theorems; ``params`` the scalar parameters;
    ``printed`` the paper's printed results, with ``printed_note`` saying where they are
    printed: ``gamma`` is an optimum to reproduce, ``gamma_bound`` a level the paper claims
    for a fixed filter (the analysis must certify a γ at or below it), and matrices by name.
    """

    name: str
    data: dict
    params: dict = field(default_factory=dict)
    printed: dict = field(default_factory=dict)
    vertices: list | None = None
    description: str = ""
    printed_note: str = ""
    provenance: str = "paper"
    provenance_note: str = ""
    expect: str = "certified"
    expect_note: str = ""

    def __post_init__(self):
        check_provenance(f"example {self.name}", self.provenance, self.provenance_note)
        if self.expect not in OUTCOMES:
            raise TheoremDefinitionError(f"example {self.name}: expect must be one of "
                                         f"{', '.join(OUTCOMES)}, got {self.expect!r}")
        if self.expect != "certified" and not self.expect_note:
            raise TheoremDefinitionError(f"example {self.name}: expect={self.expect!r} needs an "
                                         "expect_note saying why (a finding, with its evidence)")

    def inputs(self) -> dict:
        merged = dict(self.data)
        merged.update(self.params)
        if self.vertices is not None:
            merged["vertices"] = self.vertices
        return merged


@dataclass(frozen=True)
class BoundedRealForm:
    """The theorem's LMIs are the bounded real lemma of ``system`` = (A, B, C, D) (expressions of
    data) with storage ``storage`` (a symmetric variable) and level ``level`` = γ² (a scalar
    variable), in the theorem's time domain; see :meth:`Theorem.bounded_real_form`."""

    storage: Any
    level: Any
    system: tuple


@dataclass(frozen=True)
class StateFeedbackForm:
    """The theorem's LMIs are the H∞ state-feedback LMIs of ``plant`` = (A, B1, B2, C1, D11, D12)
    in the form with −γI on both diagonal blocks, Y = P⁻¹ and W = K Y; see
    :meth:`Theorem.state_feedback_form`."""

    Y: Any
    W: Any
    level: Any
    plant: tuple


@dataclass(frozen=True)
class OutputFeedbackForm:
    """The theorem's LMIs are the full-order H∞ output-feedback LMIs of ``plant`` = (A, B1, B2, C1,
    C2, D11, D12, D21) in the linearising variables (X, Y, Â, B̂, Ĉ, D̂) of Scherer, Gahinet and
    Chilali, with −γI on both diagonal blocks; see :meth:`Theorem.output_feedback_form`."""

    X: Any
    Y: Any
    Ah: Any
    Bh: Any
    Ch: Any
    Dh: Any
    level: Any
    plant: tuple


@dataclass
class AnalysisLink:
    """The analysis theorem that certifies a recovered design.

    The analysis instance takes every datum and parameter of the synthesis instance whose name
    it declares, plus the recovered matrices named in ``design``.  ``target`` is the analysis
    :class:`Theorem` itself when the theorem file passed the object (an id is looked up).
    """

    theorem: str
    design: tuple
    gamma_tolerance: float = 1e-3
    target: Any = None
    criterion: str | None = None  # "level": the analysis certifies γ; "feasible": its LMIs hold; None: inferred


@dataclass
class ErrorSystemLink:
    """The error (or closed-loop) system of a theorem whose data include the design.

    ``system`` is a :class:`lmidsl.certify.ErrorSystem` in the theorem's symbols, ``figure`` the
    exact figure that applies ('energy_to_peak' or 'h_infinity'), ``design`` the names of the
    design's matrices among the data, ``simulate(d, w, runs, rng)`` the original model with the
    design in numpy (for Monte Carlo; optional).
    """

    system: Any
    figure: str
    design: tuple
    simulate: Any = None


FIGURES = ("energy_to_peak", "h_infinity")


@dataclass
class FactorStep:
    """A recovery step: ``names`` = ``factorization(*args)`` with ``args`` evaluated numerically."""

    names: tuple
    factorization: Any
    args: tuple


@dataclass
class SignalScaling:
    """An exact change of units of one signal, u = S u' with S = diag(s) > 0.

    Data in ``rows`` produce the signal (M' = S⁻¹M), data in ``cols`` consume it (M' = M S);
    recovered matrices are mapped back: ``recovered_cols`` (consumers) M = M' S⁻¹,
    ``recovered_rows`` (producers) M = S M'.  The theorem author asserts that this substitution
    is a change of coordinates under which the theorem's conditions and γ are invariant.
    """

    signal: str
    rows: tuple = ()
    cols: tuple = ()
    recovered_rows: tuple = ()
    recovered_cols: tuple = ()
    description: str = ""


@dataclass
class Declaration:
    symbol: Any
    latex: str
    description: str
    extra: dict = field(default_factory=dict)


@dataclass
class SimulationTable:
    """What a theorem's own simulator returns (``lmidsl simulate``): one row per run.

    ``columns`` maps each row key to its column heading; ``notes`` explain the columns.
    """

    columns: dict
    rows: list
    notes: list = field(default_factory=list)

    def as_dict(self) -> dict:
        return {"columns": self.columns, "rows": self.rows, "notes": self.notes}


@dataclass
class Derivation:
    """How the LMI ``label`` of a theorem derives from LMI ``source_label`` of ``source``
    (``Theorem.derived_from``; checked by ``lmidsl derive-check``, :mod:`lmidsl.studies.derivation`).

    Stated: ``label`` ≡ Tᵀ · schur(source LMI) · T with T = diag(``congruence``), once the symbols
    in ``substitute`` are replaced by their definitions.  Symbols of the same name in the two
    theorems are the same object (the plant data, γ²); ``substitute`` maps a symbol of either
    theorem (or an auxiliary one, ``Theorem.auxiliary``) to an expression of the others — the
    change of variables (Âf = MᵀAf G22⁻¹M) and the structure of a slack (G = [[V1, ...], ...]).
    ``schur``: 1-based blocks of the source LMI eliminated by Schur complements, before the
    congruence.  ``recovers``: what the theorem's recovery formulas must give on the substituted
    point (default: the source's symbol of the same name — recover ∘ substitute = identity; a
    realisation may legitimately differ by a similarity, which is then stated here).
    """

    label: str
    source: Any
    source_label: str
    congruence: tuple | None = None
    substitute: dict = field(default_factory=dict)
    schur: tuple = ()
    recovers: dict = field(default_factory=dict)
    note: str = ""


@dataclass
class Bisection:
    """A scalar parameter on which the theorem is bisected (a GEVP / quasi-convex problem):
    the LMIs are feasible for ``parameter`` on one side of a threshold, which the bisection
    brackets within ``tol`` inside [``lower``, ``upper``].  ``goal`` "max" (the default: the
    largest feasible value, e.g. a decay rate) or "min" (the smallest)."""

    parameter: str
    lower: float
    upper: float
    tol: float = 1e-4
    goal: str = "max"
    performance: str = ""
