"""Wang, Cai, Lin, Yang: l2–l∞ filtering for networked systems with missing measurements.

The theorem file is :mod:`.theorems`; this package may also hold the paper's own models.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
