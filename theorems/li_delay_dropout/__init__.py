"""Li, Wang, Sun: H∞ filter design for networked systems with one-step random delays and

The theorem file is :mod:`.theorems`; this package may also hold the paper's own models.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
