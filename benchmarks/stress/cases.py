"""Stress plants for the verdicts: data nobody tuned for.

Every case is generated from a seed, in continuous or discrete time, in one of these families:

* ``random``        random stable system, entries of size 1;
* ``spread``        the same after a diagonal state scaling x → S x with S spanning 8 orders of
                    magnitude (A → S A S⁻¹, B → S B, C → C S⁻¹): the same transfer function,
                    entries from 1e-4 to 1e4;
* ``io_scaled``     B × s, C / s with s = 10^±6: the same transfer function;
* ``light``         a lightly damped mode (ζ = 1e-3) added to a random system;
* ``near_uncontrollable``  a mode whose input row is 1e-6 (and, for the analysis, a stable one);
* ``huge_gain``     (synthesis) an unstable plant whose stabilising gains are large.

The reference numbers come from python-control (slycot): H∞ norms of the plant (analysis) and
of the closed loop with the recovered gain (synthesis).
"""
from __future__ import annotations

import numpy as np

FAMILIES = ("random", "spread", "io_scaled", "light", "near_uncontrollable")


def _stable(rng, n: int, time: str) -> np.ndarray:
    A = rng.standard_normal((n, n))
    eig = np.linalg.eigvals(A)
    if time == "continuous":
        return A - (max(eig.real) + rng.uniform(0.1, 1.0)) * np.eye(n)
    return A * (rng.uniform(0.3, 0.95) / max(abs(eig)))


def system(family: str, seed: int, time: str, n: int = 4, m: int = 2, p: int = 2) -> dict:
    """A stable system (A, B, C, D) of one family (see the module docstring)."""
    rng = np.random.default_rng(seed)
    A = _stable(rng, n, time)
    B, C = rng.standard_normal((n, m)), rng.standard_normal((p, n))
    D = rng.standard_normal((p, m)) * 0.1
    if family == "spread":
        S = np.diag(np.logspace(-4, 4, n))
        A, B, C = S @ A @ np.linalg.inv(S), S @ B, C @ np.linalg.inv(S)
    elif family == "io_scaled":
        s = 10.0 ** (6 if seed % 2 else -6)
        B, C = B * s, C / s
    elif family == "light":
        zeta, wn = 1e-3, rng.uniform(0.5, 2.0)
        if time == "continuous":
            Am = np.array([[0.0, 1.0], [-wn ** 2, -2 * zeta * wn]])
        else:
            r, th = 1 - zeta * wn * 0.1, wn * 0.3
            Am = r * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
        A = np.block([[A, np.zeros((n, 2))], [np.zeros((2, n)), Am]])
        B = np.vstack([B, rng.standard_normal((2, m))])
        C = np.hstack([C, rng.standard_normal((p, 2))])
    elif family == "near_uncontrollable":
        B[0, :] *= 1e-6
    return {"A": A, "B": B, "C": C, "D": D}


def plant(seed: int, time: str, n: int = 4, huge: bool = False) -> dict:
    """A generalized plant (A, B1, B2, C1, D11, D12) for state feedback; D12 has full column rank
    and C1ᵀD12 = 0 (the regular case).  ``huge``: unstable with a weak actuator (B2 × 1e-3), so
    the optimal gains are large."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    if time == "discrete":
        A = A * (1.3 / max(abs(np.linalg.eigvals(A))))
    B1, B2 = rng.standard_normal((n, 1)), rng.standard_normal((n, 1)) * (1e-3 if huge else 1.0)
    C1 = np.vstack([rng.standard_normal((1, n)), np.zeros((1, n))])
    D11 = np.zeros((2, 1))
    D12 = np.array([[0.0], [1.0]])
    return {"A": A, "B1": B1, "B2": B2, "C1": C1, "D11": D11, "D12": D12}


def lists(data: dict) -> dict:
    return {k: np.asarray(v, dtype=float).tolist() for k, v in data.items()}
