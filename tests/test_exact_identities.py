"""Exact identities between the coefficients as written (lmidsl.certify.as_written, dual_point).

* the points that decide a polynomial identity in the irrational parameters: the principal
  lattice {a : Σ aᵢ ≤ D} is unisolvent for total degree ≤ D (the Vandermonde matrix of the
  monomials at its points has full rank, in exact arithmetic — flint's fmpq_mat, independent of
  the module's induction argument);
* a combination Σ w_c · row c computed from one walk at x = Σ w_c e_c equals the same combination
  of the rows computed one by one (exactly, in rationals), for li_delay_dropout.thm2 whose σ's
  are irrational as written (evaluated at the grid's points);
* the bound that uses these identities on li_delay_dropout.thm2 is unchanged and below the
  optimum of an independent solve.
"""
from __future__ import annotations

import itertools

import numpy as np
import pytest
from flint import fmpq, fmpq_mat

from lmidsl.certify.as_written import _principal_lattice, irrational_grid, snapshot
from lmidsl.certify.dual_bound import lower_bound
from lmidsl.certify.dual_point import dual_data

from dual_models import solved_model


def _monomials(k: int, total: int):
    return [a for a in itertools.product(range(total + 1), repeat=k) if sum(a) <= total]


@pytest.mark.parametrize("k,total", [(1, 0), (1, 3), (2, 1), (2, 3), (3, 2), (4, 1), (4, 2)])
def test_principal_lattice_is_unisolvent(k, total):
    points = _principal_lattice(k, total)
    monomials = _monomials(k, total)
    assert len(points) == len(monomials)
    V = fmpq_mat(len(points), len(monomials),
                 [fmpq(int(np.prod([p ** e for p, e in zip(point, exps)]))) for point in points for exps in monomials])
    assert V.rank() == len(monomials)


def test_lattice_not_enough_for_higher_degree():
    """One degree more than the lattice's: a non-zero polynomial vanishes on it (so the degree
    used must bound the true one): Π_{j ≤ D} (σ₁ + … + σ_k − k − j) of degree D + 1."""
    k, total = 3, 2
    for point in _principal_lattice(k, total):
        assert np.prod([sum(point) - k - j for j in range(total + 1)]) == 0


@pytest.fixture(scope="module")
def li_model():
    return solved_model("li_delay_dropout.thm2", "paper")


def test_li_grid_uses_the_lattice(li_model):
    """Four σ's of degree 1 each and in all: 5 points (the tensor grid has 16)."""
    model, _ = li_model
    grid = irrational_grid(snapshot(model))
    assert grid is not None and len(grid) == 5
    assert {frozenset(p) for p in grid} == {frozenset({"sigma1", "sigma2", "sigma3", "sigma4"})}


def test_combination_equals_rows_combined(li_model):
    model, _ = li_model
    data, why = dual_data(model)
    assert not why, why
    rng = np.random.default_rng(3)
    points = data.identity_points()
    assert points
    for free in points[:2]:
        columns = [int(c) for c in rng.choice(data.columns, size=3, replace=False)]
        weights = {c: fmpq(int(rng.integers(-5, 6)), int(rng.integers(1, 7))) for c in columns}
        row, q = data.exact_combination(weights, free)
        expected, expected_q = {}, fmpq(0)
        for c, w in weights.items():
            single, qc = data.exact_row(c, free)
            for u, v in single.items():
                expected[u] = expected.get(u, fmpq(0)) + w * v
            expected_q += w * qc
        expected = {u: v for u, v in expected.items() if v != 0}
        assert row == expected
        assert q == expected_q


def test_li_bound_below_optimum(li_model):
    """The bound (its dependent equations checked at the lattice's points) is proved and below
    the optimum of the problem solved with the conditioning (a second, independent solve)."""
    model, sol = li_model
    bound = lower_bound(model, sol)
    assert bound.proved, bound.why
    _, other = solved_model("li_delay_dropout.thm2", "paper", conditioning=True)
    assert bound.lower <= min(sol.objective, other.objective) * (1 + 1e-9)
    assert (min(sol.objective, other.objective) - bound.lower) / bound.lower < 1e-4
