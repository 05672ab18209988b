"""Robust H∞ filtering for uncertain interconnected time-delay systems (seed 004).

The theorem file is :mod:`.theorems`; this package may also hold the paper's own models.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
