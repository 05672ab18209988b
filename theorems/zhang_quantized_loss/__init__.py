"""Zhang, Liu, Du (2023): delta-operator H∞ filtering with random multiple packet loss and

The theorem file is :mod:`.theorems`; this package may also hold the paper's own models.
"""
from .theorems import THEOREMS

__all__ = ["THEOREMS"]
