"""Rump's verified positive definiteness (lmidsl.numeric.proof) against exact rational arithmetic.

Every float matrix is a rational matrix exactly; python-flint decides its definiteness exactly:
positive definite iff every leading principal minor is positive (Sylvester, ``fmpq_mat.det``), and
not positive definite as soon as one vector x has xᵀAx ≤ 0 in exact arithmetic.  The proof must
never claim a matrix that is not positive definite, and must prove the ones with a margin.
"""
from __future__ import annotations

import numpy as np
import pytest
from flint import fmpq, fmpq_mat

from lmidsl.numeric.enclosure import Enclosure
from lmidsl.numeric.proof import (PROVED, VIOLATED, lower_eigenvalue_bound, prove_negative_definite,
                                  verified_positive_definite)


def _q(x: float) -> fmpq:
    n, d = float(x).as_integer_ratio()
    return fmpq(n, d)


def _exact(A: np.ndarray) -> fmpq_mat:
    return fmpq_mat([[_q(x) for x in row] for row in A])


def exactly_pd(A: np.ndarray) -> bool:
    """Sylvester's criterion on the exact rational matrix."""
    E = _exact(A)
    n = A.shape[0]
    return all(fmpq_mat([[E[i, j] for j in range(k)] for i in range(k)]).det() > 0 for k in range(1, n + 1))


def exact_quadratic_form(A: np.ndarray, x: np.ndarray) -> fmpq:
    xs = [_q(v) for v in x]
    total = fmpq(0)
    for i in range(len(xs)):
        row = fmpq(0)
        for j in range(len(xs)):
            if A[i, j] != 0:
                row += _q(A[i, j]) * xs[j]
        total += xs[i] * row
    return total


def _matrix(n: int, smallest: float, rng, spread: float = 1.0, scaled: bool = False) -> np.ndarray:
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = np.linspace(1.0, 1.0 + spread, n)
    lam[0] = smallest
    A = (Q * lam) @ Q.T
    A = (A + A.T) / 2
    if scaled:                                   # badly scaled: D A D with D over 10 decades
        d = 10.0 ** rng.uniform(-5, 5, n)
        A = A * np.outer(d, d)
        A = (A + A.T) / 2
    return A


@pytest.mark.parametrize("n", [2, 8, 30])
@pytest.mark.parametrize("smallest", [1e-2, 1e-8, 1e-12, 0.0, -1e-12, -1e-8])
@pytest.mark.parametrize("scaled", [False, True])
def test_verdicts_agree_with_exact_arithmetic(n, smallest, scaled):
    rng = np.random.default_rng(n * 7 + int(scaled))
    A = _matrix(n, smallest, rng, scaled=scaled)
    ok, why = verified_positive_definite(A)
    truth = exactly_pd(A)
    assert not (ok and not truth), why          # never a false "positive definite"
    if smallest >= 1e-2 and not scaled:
        assert ok, why                          # a clear margin is proved


@pytest.mark.parametrize("n", [60, 200])
def test_large_indefinite_by_1e_12_is_never_claimed(n):
    rng = np.random.default_rng(n)
    for smallest in (-1e-12, -1e-10):
        for scaled in (False, True):
            state = rng.bit_generator.state
            A = _matrix(n, smallest, rng, scaled=scaled)
            rng.bit_generator.state = state          # the unscaled matrix's eigenvector, rescaled
            A0 = _matrix(n, smallest, rng)
            if scaled:
                rng.bit_generator.state = state
                _matrix(n, smallest, rng, scaled=True)
            x = np.linalg.eigh(A0)[1][:, 0]
            if scaled:
                x = x * np.sqrt(np.diag(A0) / np.diag(A))  # D⁻¹ v, D = diag scaling
            witness = exact_quadratic_form(A, x)
            assert witness <= 0                 # the float matrix is exactly not PD
            assert not verified_positive_definite(A)[0]
            low = lower_eigenvalue_bound(A)
            assert low is None or low < 0       # never a non-negative lower bound


def test_large_near_singular_is_proved_and_the_bound_is_exact():
    rng = np.random.default_rng(3)
    A = _matrix(200, 1e-9, rng)
    assert verified_positive_definite(A)[0]
    low = lower_eigenvalue_bound(A)
    assert low is not None and 0 < low <= 1e-9 * (1 + 1e-3)
    B = _matrix(40, 1e-6, rng)
    low = lower_eigenvalue_bound(B)
    shifted = B - low * np.eye(40)
    # A − sI in exact arithmetic (s exact float): PD iff λ_min > s
    E = _exact(B)
    for i in range(40):
        E[i, i] = E[i, i] - _q(low)
    assert all(fmpq_mat([[E[i, j] for j in range(k)] for i in range(k)]).det() > 0 for k in range(1, 41))
    assert np.linalg.eigvalsh(shifted)[0] > 0


def test_an_enclosure_holding_a_singular_matrix_is_not_proved():
    mid = np.array([[1.0, 0.999], [0.999, 1.0]])          # λ_min = 0.001
    wide = np.array([[0.0, 0.002], [0.002, 0.0]])          # holds [[1, 1.001], [1.001, 1]]: indefinite
    narrow = np.array([[0.0, 0.0005], [0.0005, 0.0]])
    assert not verified_positive_definite(mid, wide)[0]
    assert verified_positive_definite(mid, narrow)[0]
    # a diagonal radius that reaches 0
    assert not verified_positive_definite(np.diag([1.0, 1e-6]), np.diag([0.0, 2e-6]))[0]
    low = lower_eigenvalue_bound(mid, narrow)
    assert low is not None and 0 < low <= 0.001 - 0.0005 + 1e-12


def test_violated_needs_an_exactly_negative_quadratic_form():
    N = Enclosure(np.array([[-1.0, 2.0], [2.0, -1.0]]))     # eigenvalue +1: N ≺ 0 fails
    assert prove_negative_definite(N)[0] == VIOLATED
    assert prove_negative_definite(Enclosure(np.array([[-1.0, 0.5], [0.5, -1.0]])))[0] == PROVED
    # N = 0 ± tiny: neither proved nor refuted by the fast route (the balls decide)
    assert prove_negative_definite(Enclosure(np.zeros((2, 2)), np.full((2, 2), 1e-20))) is None


@pytest.mark.parametrize("smallest", [1.0, 1e-6, 1e-10])
def test_verified_solve_encloses_the_exact_solution(smallest):
    """G⁻¹b in exact rational arithmetic (fmpq_mat.solve) lies in the enclosure, or no enclosure."""
    from lmidsl.numeric.proof import verified_spd_solve
    rng = np.random.default_rng(int(-np.log10(smallest)))
    n = 25
    G = _matrix(n, smallest, rng)
    b = rng.standard_normal(n)
    found = verified_spd_solve(G, np.zeros((n, n)), b, np.zeros(n))
    if smallest >= 1e-6:
        assert found is not None
    if found is None:
        return
    mid, rad = found
    exact = _exact(G).solve(fmpq_mat([[_q(x)] for x in b]))
    for i in range(n):
        assert abs(exact[i, 0] - _q(mid[i])) <= _q(rad[i])


def test_verified_solve_componentwise_radii_enclose_and_are_tighter():
    """A solution whose components span 12 decades (G well conditioned, b graded): each
    component's radius from the componentwise sharpening still encloses the exact rational
    solution, and the small components get radii far below the norm-wise bound."""
    from lmidsl.numeric.proof import verified_spd_solve
    rng = np.random.default_rng(5)
    n = 30
    G = _matrix(n, 1e-2, rng)
    x = np.logspace(0, -12, n) * rng.choice([-1.0, 1.0], n)
    b = G @ x
    G_rad = np.full((n, n), 1e-15)
    b_rad = np.abs(b) * 1e-15
    mid, rad = verified_spd_solve(G, G_rad, b, b_rad)
    assert rad.max() > rad.min() * 10              # not one norm-wise number for all
    exact = _exact(G).solve(fmpq_mat([[_q(v)] for v in b]))
    for i in range(n):
        assert abs(exact[i, 0] - _q(mid[i])) <= _q(rad[i])
