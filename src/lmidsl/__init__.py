"""lmidsl: LMI theorems stated once, in the paper's notation; solved, recovered, certified.

A theorem file declares dimensions, data, variables and parameters on a :class:`Theorem`,
writes each LMI as a block triangle (``*`` implicit, ``0``/``I`` sized from their position),
and names its objective, its change of variables (recovery) and its analysis counterpart.
:func:`solve` binds an example or user data, compiles to a backend (by default ``direct``,
lmidsl's own standard form for Clarabel; ``cvxpy`` or ``picos`` on request), solves,
recovers the :class:`Design` and certifies it; :func:`verify` gathers independent evidence.

The public face, by use:

* authoring a theorem: :class:`Theorem`, :class:`Source`, :class:`Example`, ``I``, :func:`He`,
  :func:`diag`, :func:`schur`, :func:`congruence`, :func:`block_matrix`, :class:`NormBounded`,
  :func:`sprocedure`, the families (:class:`TheoremFamily`, :class:`SubsystemFamily`,
  :class:`Family`, :func:`member_label`), the factorisations of a recovery (:func:`rs_split`,
  :func:`balanced_split`), the standard changes of variables of synthesis
  (:mod:`lmidsl.numeric.changes_of_variables`: :func:`state_feedback_gain`,
  :func:`output_feedback_blocks`, :func:`output_feedback`, :func:`filter_blocks`,
  :func:`full_order_filter`, the closed loops for analysis), the declared certificates (:class:`ErrorSystem`,
  :func:`reported_agree`, :class:`CheckResult`, :func:`grid_check`, :func:`rate_grid_check`,
  :func:`rate_simulation_check`, :func:`zero`), the system figures a check reads
  (:func:`default_grid`, :func:`is_stable`, :func:`peak_gain`), :class:`SimulationTable` and the
  house style of a simulation's figure (:func:`figure`, :func:`legend`, :func:`save_figure`,
  ``WIDE_FIGURE``);
* running: :func:`solve`, :func:`verify`, the loops a design closes, as python-control systems
  (:func:`closed_loop`, :func:`filtering_error`, :func:`generalized_plant`; :meth:`Design.as_statespace`), :func:`get_theorem`, :func:`all_theorems`,
  :func:`make_instance`, :func:`solve_instance`;
* results: :class:`Solution`, :class:`Design`, :class:`AnalysisCertificate`, :class:`Verification`;
* LaTeX: :func:`theorem_latex` (a complete document), :func:`lmi_latex` (one LMI);
* errors: :class:`LmidslError` and its kinds; warnings: :class:`LmidslWarning`
  (:class:`UnusedDataWarning`: data a theorem does not use, ignored).

A theorem file imports only ``lmidsl`` (and its own paper's modules).  The layers below are in
``docs/architecture.md``.
"""
from .errors import (InputError, LmidslError, LmidslWarning, NoResultError, NonlinearityError,
                     ShapeMismatchError, SolverUnavailableError, TheoremDefinitionError,
                     UnusedDataWarning)

import importlib as _importlib
import sys as _sys

__version__ = "0.1.0"

#: every public name, by the module that defines it: imported when first used (PEP 562), so
#: ``lmidsl --help`` and ``lmidsl list`` do not pay for sympy, cvxpy, scipy or matplotlib, and a
#: theorem file, which imports only the authoring vocabulary, does not pay for the running stack
_LAZY = {
    "AnalysisCertificate": "certify", "ErrorSystem": "certify",
    "Design": "numeric.design", "balanced_split": "numeric.factorization", "rs_split": "numeric.factorization",
    "Solution": "solver.solution",
    "I": "symbolic.blocks", "He": "symbolic.blocks", "block_matrix": "symbolic.blocks",
    "congruence": "symbolic.blocks", "diag": "symbolic.blocks", "schur": "symbolic.blocks",
    "NormBounded": "symbolic.sprocedure", "sprocedure": "symbolic.sprocedure",
    "second_moment": "certify.indexed_evidence", "fuzzy_grid": "certify.indexed_evidence",
    "sum_over": "symbolic.indexed", "stack_over": "symbolic.indexed", "diag_over": "symbolic.indexed",
    "kron": "symbolic.indexed",
    "CheckResult": "theorem.checks", "reported_agree": "theorem.checks",
    "Family": "theorem.family", "SubsystemFamily": "theorem.family", "TheoremFamily": "theorem.family",
    "member_label": "theorem.family", "RobustTheorem": "theorem.robust",
    "all_theorems": "theorem.registry", "get_theorem": "theorem.registry",
    "Theorem": "theorem.theorem",
    "Example": "theorem.values", "SimulationTable": "theorem.values", "Source": "theorem.values",
    "solve": "pipeline", "make_instance": "pipeline", "solve_instance": "pipeline",
    "verify": "studies.verify", "Verification": "studies.verify",
    "closed_loop": "numeric.interconnection", "filtering_error": "numeric.interconnection",
    "generalized_plant": "numeric.interconnection",
    "theorem_latex": "render.latex_document", "lmi_latex": "render.latex",
    # evidence a theorem file declares, and the figures of its simulation
    "zero": "theorem.assumptions", "grid_check": "certify.simplex_grid",
    "rate_grid_check": "certify.rate_bounded", "rate_simulation_check": "certify.rate_bounded",
    "default_grid": "numeric.systems", "is_stable": "numeric.systems", "peak_gain": "numeric.systems",
    "figure": "render.style", "legend": "render.style", "save_figure": "render.style:save",
    "WIDE_FIGURE": "render.style:WIDE",
}
_LAZY.update({name: "numeric.changes_of_variables" for name in (
    "closed_loop_matrices", "filter_blocks", "filter_error_matrices", "full_order_filter", "loop_shift",
    "mn_split", "output_feedback", "output_feedback_blocks", "state_feedback_closed_loop",
    "state_feedback_gain")})

__all__ = ["Theorem", "Source", "Example", "I", "He", "diag", "schur", "congruence",
           "block_matrix", "NormBounded", "sprocedure", "TheoremFamily", "SubsystemFamily",
           "Family", "member_label", "RobustTheorem", "rs_split", "balanced_split", "ErrorSystem",
           "mn_split", "state_feedback_gain", "output_feedback_blocks", "filter_blocks",
           "output_feedback", "loop_shift", "full_order_filter", "closed_loop_matrices",
           "state_feedback_closed_loop", "filter_error_matrices",
           "reported_agree", "CheckResult", "second_moment", "fuzzy_grid", "sum_over", "stack_over",
           "diag_over", "kron", "SimulationTable", "zero", "grid_check", "rate_grid_check",
           "rate_simulation_check", "default_grid", "is_stable", "peak_gain", "figure", "legend",
           "save_figure", "WIDE_FIGURE",
           "solve", "verify", "closed_loop", "filtering_error", "generalized_plant", "get_theorem", "all_theorems", "make_instance", "solve_instance",
           "Solution", "Design", "AnalysisCertificate", "Verification", "theorem_latex", "lmi_latex",
           "LmidslError", "InputError", "ShapeMismatchError", "NonlinearityError",
           "TheoremDefinitionError", "SolverUnavailableError", "NoResultError",
           "LmidslWarning", "UnusedDataWarning"]


#: the modules whose names hand theorems to the user: with them comes the notebook display, which
#: registers the LaTeX printer for ``Theorem._repr_latex_`` and ``LMI._repr_latex_`` (the theorem layer cannot import the render layer)
_WITH_LATEX = ("theorem.", "pipeline", "studies.")


def __getattr__(name):
    if name in _LAZY:
        import importlib
        module, _, attribute = _LAZY[name].partition(":")     # "module:attribute" when named otherwise
        value = getattr(importlib.import_module(f".{module}", __name__), attribute or name)
        if module.startswith(_WITH_LATEX):
            importlib.import_module(".render.notebook", __name__)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'lmidsl' has no attribute {name!r}")


if "IPython" in _sys.modules:        # a notebook: results display as HTML (render.notebook)
    _importlib.import_module(".render.notebook", __name__).register_ipython()


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
