"""lmidsl: LMI theorems stated once, in the paper's notation; solved, recovered, certified.

A theorem file declares dimensions, data, variables and parameters on a :class:`Theorem`,
writes each LMI as a block triangle (``*`` implicit, ``0``/``I`` sized from their position),
and names its objective, recovery formulas and analysis counterpart.  :func:`solve` binds an
example or user data, compiles to a backend (cvxpy by default), solves, recovers the filter
and certifies it.
"""
from .symbolic.blocks import I, He, block_matrix, congruence, diag, schur
from .errors import LmidslError
from .theorem.theorem import Example, Source, Theorem

__version__ = "0.1.0"

__all__ = ["I", "He", "diag", "schur", "congruence", "block_matrix", "Theorem", "Source",
           "Example", "LmidslError", "solve", "make_instance", "solve_instance", "get_theorem",
           "all_theorems"]


def __getattr__(name):
    # the API pulls in the backends (cvxpy); theorem files import only the symbolic layer
    if name in ("solve", "make_instance", "solve_instance"):
        from . import api
        return getattr(api, name)
    if name in ("get_theorem", "all_theorems"):
        from . import registry
        return getattr(registry, name)
    raise AttributeError(name)
