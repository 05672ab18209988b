"""Evidence for designs over an index set, independent of the LMIs (``Theorem.verify_with``).

* :func:`second_moment` -- mean-square stability of a Markov jump linear system with the
  recovered mode gains, by the second-moment test: the second moments Qᵢ(t) = E[x xᵀ 1{θ=i}]
  obey a linear equation whose matrix must be Hurwitz (continuous time),
  𝒜 = diag(Aᵢ ⊕ Aᵢ) + Πᵀ ⊗ I_{n²} with A ⊕ A = A ⊗ I + I ⊗ A, or Schur (discrete time),
  𝒯 = (Pᵀ ⊗ I_{n²}) diag(Aᵢ ⊗ Aᵢ) (Costa, Fragoso, Marques, *Discrete-Time Markov Jump Linear
  Systems*, Springer 2005, Th. 3.9; Costa, Fragoso, Todorov, *Continuous-Time Markov Jump Linear
  Systems*, Springer 2013, Th. 3.25).  Aᵢ is the closed loop Aᵢ + BᵢKᵢ.
* :func:`fuzzy_grid` -- the quadratic Lyapunov decrease of a Takagi–Sugeno closed loop
  Σᵢ Σⱼ hᵢ hⱼ (Aᵢ + BᵢKⱼ) with V = xᵀ X⁻¹ x on a grid of the membership simplex (every hᵢ a
  multiple of 1/steps).

Both read the instance's data by the member names (``A_1``, …) and the recovered design.
"""
from __future__ import annotations

import itertools

import numpy as np

from ..theorem.checks import CheckResult


def _members(solution, name: str, source: dict) -> list[np.ndarray]:
    out, k = [], 1
    while f"{name}_{k}" in source:
        out.append(np.atleast_2d(np.asarray(source[f"{name}_{k}"], dtype=float)))
        k += 1
    return out


def closed_loops(solution, A: str = "A", B: str = "B", K: str = "K") -> list[np.ndarray]:
    """Aᵢ + BᵢKᵢ for every member i (Aᵢ alone where the design has no Kᵢ)."""
    data = solution.instance.data
    As, Bs = _members(solution, A, data), _members(solution, B, data)
    Ks = _members(solution, K, solution.design.matrices) if solution.design is not None else []
    return [a + (b @ k if k.size and b.size else 0.0) for a, b, k in zip(As, Bs, Ks)] or As


def second_moment_matrix(closed: list[np.ndarray], rates: np.ndarray, time: str) -> np.ndarray:
    """𝒜 = diag(Aᵢ ⊕ Aᵢ) + Πᵀ ⊗ I (continuous) or 𝒯 = (Pᵀ ⊗ I) diag(Aᵢ ⊗ Aᵢ) (discrete)."""
    n = closed[0].shape[0]
    N = len(closed)
    q = n * n
    blocks = np.zeros((N * q, N * q))
    for k, a in enumerate(closed):
        term = (np.kron(a, np.eye(n)) + np.kron(np.eye(n), a)) if time == "continuous" else np.kron(a, a)
        blocks[k * q:(k + 1) * q, k * q:(k + 1) * q] = term
    coupling = np.kron(np.asarray(rates, dtype=float).T, np.eye(q))
    return blocks + coupling if time == "continuous" else coupling @ blocks


def mean_square_stable(closed, rates, time: str) -> tuple[bool, float]:
    """(stable, the spectral abscissa (continuous) or radius (discrete) of the second-moment matrix)."""
    eig = np.linalg.eigvals(second_moment_matrix(closed, rates, time))
    if time == "continuous":
        value = float(eig.real.max())
        return value < 0, value
    value = float(np.abs(eig).max())
    return value < 1, value


def second_moment(rates: str = "Pi", A: str = "A", B: str = "B", K: str = "K",
                  name: str = "second-moment test"):
    """A check: the recovered mode gains make the Markov jump system mean-square stable."""

    def check(solution) -> CheckResult:
        if solution.design is None:
            return CheckResult(name, False, "no design recovered")
        time = solution.instance.theorem.time
        closed = closed_loops(solution, A, B, K)
        ok, value = mean_square_stable(closed, solution.instance.data[rates], time)
        what = "spectral abscissa" if time == "continuous" else "spectral radius"
        bound = "< 0" if time == "continuous" else "< 1"
        return CheckResult(name, ok, f"{what} of the second-moment matrix {value:.6g} ({bound} required), "
                                     f"{len(closed)} modes", {"value": value})

    check.needs_synthesis = True
    return check


def simplex_grid(r: int, steps: int) -> np.ndarray:
    """Every h ≥ 0 with Σ h = 1 whose entries are multiples of 1/steps."""
    points = [c for c in itertools.product(range(steps + 1), repeat=r - 1) if sum(c) <= steps]
    return np.array([[*c, steps - sum(c)] for c in points], dtype=float) / steps


def fuzzy_closed_loop(As, Bs, Ks, h) -> np.ndarray:
    """Σᵢ Σⱼ hᵢ hⱼ (Aᵢ + BᵢKⱼ)."""
    A = sum(hi * a for hi, a in zip(h, As))
    BK = sum(hi * hj * (b @ k) for hi, b in zip(h, Bs) for hj, k in zip(h, Ks))
    return A + BK


def fuzzy_grid(X: str = "X", A: str = "A", B: str = "B", K: str = "K", steps: int = 20,
               name: str = "Lyapunov decrease on the membership grid"):
    """A check: V = xᵀX⁻¹x decreases along Σᵢ Σⱼ hᵢ hⱼ (Aᵢ + BᵢKⱼ) at every grid point h
    (continuous time: the largest eigenvalue of He(X⁻¹ A_cl(h)) is negative)."""

    def check(solution) -> CheckResult:
        if solution.design is None:
            return CheckResult(name, False, "no design recovered")
        data, design = solution.instance.data, solution.design.matrices
        As, Bs, Ks = _members(solution, A, data), _members(solution, B, data), _members(solution, K, design)
        P = np.linalg.inv(np.asarray(solution.values[X], dtype=float))
        worst = -np.inf
        grid = simplex_grid(len(As), steps)
        for h in grid:
            Acl = fuzzy_closed_loop(As, Bs, Ks, h)
            worst = max(worst, float(np.linalg.eigvalsh(P @ Acl + Acl.T @ P).max()))
        return CheckResult(name, worst < 0, f"largest eigenvalue of He(X⁻¹A_cl(h)) {worst:.4g} on "
                                            f"{len(grid)} membership points", {"worst": worst})

    check.needs_synthesis = True
    return check


__all__ = ["second_moment", "fuzzy_grid", "second_moment_matrix", "mean_square_stable",
           "simplex_grid", "fuzzy_closed_loop", "closed_loops"]
