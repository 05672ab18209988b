"""Pan, Sun: robust H∞ filtering for discrete-time impulsive systems with uncertainty.

The theorem file is :mod:`.theorems`; this package may also hold the paper's own models.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
