"""lmidsl: LMI theorems stated once, in the paper's notation; solved, recovered, certified.

A theorem file declares dimensions, data, variables and parameters on a :class:`Theorem`,
writes each LMI as a block triangle (``*`` implicit, ``0``/``I`` sized from their position),
and names its objective, its change of variables (recovery) and its analysis counterpart.
:func:`solve` binds an example or user data, compiles to a backend (cvxpy by default), solves,
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
  :func:`reported_agree`, :class:`CheckResult`) and :class:`SimulationTable`;
* running: :func:`solve`, :func:`verify`, the loops a design closes, as python-control systems
  (:func:`closed_loop`, :func:`filtering_error`, :func:`generalized_plant`; :meth:`Design.as_statespace`), :func:`get_theorem`, :func:`all_theorems`,
  :func:`make_instance`, :func:`solve_instance`;
* results: :class:`Solution`, :class:`Design`, :class:`AnalysisCertificate`, :class:`Verification`;
* errors: :class:`LmidslError` and its kinds.

A theorem file imports only ``lmidsl`` (and its own paper's modules).  The layers below are in
``docs/architecture.md``.
"""
from .certify import AnalysisCertificate, ErrorSystem
from .errors import (InputError, LmidslError, NoResultError, NonlinearityError, ShapeMismatchError,
                     SolverUnavailableError, TheoremDefinitionError)
from .numeric.changes_of_variables import (closed_loop_matrices, filter_blocks, filter_error_matrices,
                                           full_order_filter, loop_shift, mn_split, output_feedback,
                                           output_feedback_blocks, state_feedback_closed_loop,
                                           state_feedback_gain)
from .numeric.design import Design
from .numeric.factorization import balanced_split, rs_split
from .solver.solution import Solution
from .symbolic.blocks import I, He, block_matrix, congruence, diag, schur
from .symbolic.sprocedure import NormBounded, sprocedure
from .theorem.checks import CheckResult, reported_agree
from .theorem.family import Family, SubsystemFamily, TheoremFamily, member_label
from .theorem.registry import all_theorems, get_theorem
from .theorem.theorem import Theorem
from .theorem.values import Example, SimulationTable, Source

__version__ = "0.1.0"

_RUNNING = {"solve": "pipeline", "make_instance": "pipeline", "solve_instance": "pipeline",
            "verify": "studies.verify", "Verification": "studies.verify",
            "closed_loop": "numeric.interconnection", "filtering_error": "numeric.interconnection",
            "generalized_plant": "numeric.interconnection"}

__all__ = ["Theorem", "Source", "Example", "I", "He", "diag", "schur", "congruence",
           "block_matrix", "NormBounded", "sprocedure", "TheoremFamily", "SubsystemFamily",
           "Family", "member_label", "rs_split", "balanced_split", "ErrorSystem",
           "mn_split", "state_feedback_gain", "output_feedback_blocks", "filter_blocks",
           "output_feedback", "loop_shift", "full_order_filter", "closed_loop_matrices",
           "state_feedback_closed_loop", "filter_error_matrices",
           "reported_agree", "CheckResult", "SimulationTable",
           "solve", "verify", "closed_loop", "filtering_error", "generalized_plant", "get_theorem", "all_theorems", "make_instance", "solve_instance",
           "Solution", "Design", "AnalysisCertificate", "Verification",
           "LmidslError", "InputError", "ShapeMismatchError", "NonlinearityError",
           "TheoremDefinitionError", "SolverUnavailableError", "NoResultError"]


def __getattr__(name):
    # PEP 562: running pulls in the whole numerical stack (backends, certification, studies);
    # a theorem file, which imports only the authoring vocabulary, does not pay for it
    if name in _RUNNING:
        import importlib
        return getattr(importlib.import_module(f".{_RUNNING[name]}", __name__), name)
    raise AttributeError(f"module 'lmidsl' has no attribute {name!r}")
