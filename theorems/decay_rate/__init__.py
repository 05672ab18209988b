"""The decay rate of a linear system (or a polytope of them) by bisection: a textbook GEVP.

The theorem file is :mod:`.theorems`.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
