"""Plants for the textbook gallery: seeded random systems and classic closed-form examples.

One naming convention serves every gallery theorem, so one plant dictionary can be given to
any of them (each theorem takes the names it declares):

* a system ``A, B, C, D``:  x' = A x + B w,  z = C x + D w;
* a generalized plant ``A, B1, B2, C1, C2, D11, D12, D21, D22``:
  x' = A x + B1 w + B2 u,  z = C1 x + D11 w + D12 u,  y = C2 x + D21 w + D22 u;
* designs: a controller ``AK, BK, CK, DK`` (state feedback: ``K``), a filter ``Af, Bf, Cf, Df``.

Everything here is plain numpy with a fixed seed; nothing is solved.  The generators are used
by the theorem files' examples and by ``tests/test_textbook.py``, which checks every result
against python-control.
"""
from __future__ import annotations

import numpy as np


def _lists(**matrices) -> dict:
    return {k: np.asarray(v, dtype=float).tolist() for k, v in matrices.items()}


def _stable_matrix(rng, n: int, time: str, radius: float = 0.9) -> np.ndarray:
    """A random state matrix, Hurwitz (continuous) or Schur (discrete), not normal."""
    A = rng.standard_normal((n, n))
    eig = np.linalg.eigvals(A)
    if time == "continuous":
        return A - (max(eig.real) + 0.1 + rng.random()) * np.eye(n)
    return radius * A / max(abs(eig))


def random_system(seed: int, n: int = 3, m: int = 2, p: int = 2, time: str = "continuous",
                  kind: str = "generic") -> dict:
    """A random stable system A, B, C, D (data lists), reproducible from ``seed``.

    ``kind``: ``"generic"``; ``"lightly-damped"`` (a pair of poles with damping ratio 0.01
    added to a generic part, continuous; poles at radius 0.995 near the unit circle, discrete);
    ``"wide-scale"`` (a generic system seen through the diagonal change of coordinates
    T = diag(10^k), k spread over [-2, 2], so entries span several orders of magnitude: the
    transfer function, and the H∞ norm, are those of the generic system).
    """
    rng = np.random.default_rng(seed)
    A = _stable_matrix(rng, n, time)
    B = rng.standard_normal((n, m))
    C = rng.standard_normal((p, n))
    D = 0.5 * rng.standard_normal((p, m))
    if kind == "lightly-damped":
        if time == "continuous":
            wn, zeta = 1.0 + rng.random(), 0.01
            block = np.array([[0.0, wn], [-wn, -2 * zeta * wn]])
        else:
            r, th = 0.995, 0.3 + rng.random()
            block = r * np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])
        A = np.block([[A, np.zeros((n, 2))], [np.zeros((2, n)), block]])
        B = np.vstack([B, rng.standard_normal((2, m))])
        C = np.hstack([C, rng.standard_normal((p, 2))])
    elif kind == "wide-scale":
        T = np.diag(10.0 ** np.linspace(-2, 2, n))
        Ti = np.linalg.inv(T)
        A, B, C = T @ A @ Ti, T @ B, C @ Ti
    elif kind != "generic":
        raise ValueError(f"unknown kind {kind!r}")
    return _lists(A=A, B=B, C=C, D=D)


def brl_cases(time: str, count: int = 10) -> list[tuple[str, dict]]:
    """(name, system) for the bounded-real-lemma tests: generic systems of orders 1..6 and
    1..3 inputs/outputs, plus one lightly damped and one wide-scale system."""
    cases = []
    for k in range(count - 2):
        n, m, p = 1 + k % 6, 1 + k % 3, 1 + (k + 1) % 3
        cases.append((f"random-{k}", random_system(100 + k, n, m, p, time)))
    cases.append(("lightly-damped", random_system(200, 3, 1, 1, time, "lightly-damped")))
    cases.append(("wide-scale", random_system(300, 4, 2, 2, time, "wide-scale")))
    return cases


def second_order(zeta: float = 0.05, wn: float = 1.0) -> tuple[dict, float]:
    """G(s) = wn² / (s² + 2ζ wn s + wn²) in controllable form, and its H∞ norm.

    |G(jω)|² = wn⁴ / ((wn² − ω²)² + (2ζ wn ω)²); for ζ < 1/√2 the denominator is least at
    ω² = wn²(1 − 2ζ²), where it is 4ζ²(1 − ζ²) wn⁴: the resonant peak 1 / (2ζ √(1 − ζ²)).
    For ζ ≥ 1/√2 the peak is |G(0)| = 1.
    """
    A = [[0.0, 1.0], [-wn ** 2, -2 * zeta * wn]]
    norm = 1.0 / (2 * zeta * np.sqrt(1 - zeta ** 2)) if zeta < 1 / np.sqrt(2) else 1.0
    return _lists(A=A, B=[[0.0], [1.0]], C=[[wn ** 2, 0.0]], D=[[0.0]]), float(norm)


def first_order_dt(a: float = 0.8, b: float = 1.0) -> tuple[dict, float]:
    """G(z) = b / (z − a), |a| < 1, and its H∞ norm |b| / (1 − |a|) (peak at z = sign(a))."""
    return _lists(A=[[a]], B=[[b]], C=[[1.0]], D=[[0.0]]), float(abs(b) / (1 - abs(a)))


def random_plant(seed: int, n: int = 3, m1: int = 2, m2: int = 1, p1: int = 2, p2: int = 1,
                 time: str = "continuous", d11: bool = True, d22: bool = False) -> dict:
    """A random generalized plant A, B1, B2, C1, C2, D11, D12, D21, D22 (data lists).

    A is generic (typically unstable); (A, B2) stabilizable and (C2, A) detectable
    generically.  D12 (p1 × m2, p1 ≥ m2) has full column rank and D21 (p2 × m1, m1 ≥ p2) full
    row rank (singular values in [0.5, 1.5]), the assumptions of python-control's
    ``hinfsyn`` (SLICOT SB10AD); the imaginary-axis rank conditions hold generically.
    ``d11``: D11 random (else 0); ``d22``: D22 random (else 0).  Discrete time: A is scaled
    to spectral radius 1.2 (unstable, so the controller has work to do).
    """
    if p1 < m2 or m1 < p2:
        raise ValueError("need p1 >= m2 (D12 full column rank) and m1 >= p2 (D21 full row rank)")
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    if time == "discrete":
        A = 1.2 * A / max(abs(np.linalg.eigvals(A)))

    def full_rank(rows, cols):
        U, _ = np.linalg.qr(rng.standard_normal((rows, rows)))
        V, _ = np.linalg.qr(rng.standard_normal((cols, cols)))
        S = np.zeros((rows, cols))
        k = min(rows, cols)
        S[:k, :k] = np.diag(0.5 + rng.random(k))
        return U @ S @ V.T

    return _lists(A=A, B1=rng.standard_normal((n, m1)), B2=rng.standard_normal((n, m2)),
                  C1=rng.standard_normal((p1, n)), C2=rng.standard_normal((p2, n)),
                  D11=0.3 * rng.standard_normal((p1, m1)) if d11 else np.zeros((p1, m1)),
                  D12=full_rank(p1, m2), D21=full_rank(p2, m1),
                  D22=0.3 * rng.standard_normal((p2, m2)) if d22 else np.zeros((p2, m2)))


def plant_cases(time: str, count: int = 20, max_order: int = 8) -> list[tuple[str, dict]]:
    """(name, generalized plant) for the synthesis tests: orders 1..``max_order``, 1..2
    controls and measurements, one more performance output than controls (p1 = m2 + 1) and
    p2 or p2 + 1 disturbances; every third with D22 ≠ 0, every fourth with D11 = 0.

    p1 > m2 on purpose: with D12 and D21 both square and invertible the controller can
    reconstruct x and w from y and cancel z, the optimal γ is 0 and not attained (python-
    control's hinfsyn test plant is such a case).
    """
    cases = []
    for k in range(count):
        n = 1 + k % max_order
        m2, p2 = 1 + k % 2, 1 + (k // 2) % 2
        m1, p1 = p2 + k % 2, m2 + 1
        cases.append((f"plant-{k}", random_plant(1000 + k, n, m1, m2, p1, p2, time,
                                                 d11=k % 4 != 3, d22=k % 3 == 2)))
    return cases


def subset(data: dict, names) -> dict:
    """The entries of ``data`` a theorem declares (one plant file serves every theorem)."""
    return {k: data[k] for k in names if k in data}


def filter_cases(time: str, count: int = 10) -> list[tuple[str, dict]]:
    """(name, plant) for the filtering tests: a stable A (orders 1..6), B1, C1 (1..2 outputs z),
    C2 (1..2 measurements y), D11 and D21 with full row rank (m1 = p2 + 1 disturbances)."""
    cases = []
    for k in range(count):
        rng = np.random.default_rng(2000 + k)
        n, p1, p2 = 1 + k % 6, 1 + k % 2, 1 + (k // 2) % 2
        m1 = p2 + 1
        A = _stable_matrix(rng, n, time)
        U, _ = np.linalg.qr(rng.standard_normal((p2, p2)))
        V, _ = np.linalg.qr(rng.standard_normal((m1, m1)))
        S = np.hstack([np.diag(0.5 + rng.random(p2)), np.zeros((p2, m1 - p2))])
        cases.append((f"filter-{k}", _lists(A=A, B1=rng.standard_normal((n, m1)),
                                            C1=rng.standard_normal((p1, n)), C2=rng.standard_normal((p2, n)),
                                            D11=0.3 * rng.standard_normal((p1, m1)), D21=U @ S @ V.T)))
    return cases
