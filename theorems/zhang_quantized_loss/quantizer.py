"""The logarithmic quantiser (3) and its sector bound.

Levels {±χ_i : χ_i = ρ^i χ0, i ∈ ℤ} ∪ {0}, 0 < ρ < 1, χ0 > 0, β = (1 − ρ)/(1 + ρ)::

    q(v) = χ_i        if χ_i/(1 + β) < v ≤ χ_i/(1 − β),
    q(0) = 0,   q(v) = −q(−v) for v < 0.

The intervals tile (0, ∞) (χ_{i+1}/(1 − β) = χ_i/(1 + β)), and on each of them
|q(v) − v| ≤ β|v|, i.e. q(v) = (1 + Δ)v with |Δ| ≤ β: the sector model (4).
"""
from __future__ import annotations

import numpy as np


class LogQuantizer:
    """Elementwise logarithmic quantiser with density ``rho`` and level ``chi0``."""

    def __init__(self, rho: float, chi0: float = 1.0):
        if not 0 < rho < 1 or chi0 <= 0:
            raise ValueError("need 0 < rho < 1 and chi0 > 0")
        self.rho = float(rho)
        self.chi0 = float(chi0)
        self.beta = (1 - self.rho) / (1 + self.rho)

    def level_index(self, v):
        """The index i of the level of |v| (v ≠ 0): i = ⌊log(|v|(1 − β)/χ0) / log ρ⌋."""
        a = np.abs(np.asarray(v, dtype=float))
        return np.floor(np.log(a * (1 - self.beta) / self.chi0) / np.log(self.rho))

    def __call__(self, v):
        v = np.asarray(v, dtype=float)
        out = np.zeros_like(v)
        nz = v != 0
        if np.any(nz):
            out[nz] = np.sign(v[nz]) * self.chi0 * self.rho ** self.level_index(v[nz])
        return out

    def relative_error(self, v):
        """Δ = q(v)/v − 1 (0 where v = 0); |Δ| ≤ β."""
        v = np.asarray(v, dtype=float)
        out = np.zeros_like(v)
        nz = v != 0
        out[nz] = self(v[nz]) / v[nz] - 1
        return out
