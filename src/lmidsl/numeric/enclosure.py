"""Midpoint–radius enclosures of matrices in floating point, without changing the rounding mode.

An :class:`Enclosure` ⟨m, r⟩ (float arrays, r ≥ 0) stands for every real matrix X with
|X − m| ≤ r entrywise.  The operations return an enclosure of every exact result, in the manner
of S. M. Rump, "Fast and parallel interval arithmetic" (BIT 39, 1999), with the rounding errors of
round-to-nearest bounded a priori instead of by directed rounding (Higham, *Accuracy and
Stability of Numerical Algorithms*, §3.1: a dot product of length k computed in any order errs by
at most γ_k |a|ᵀ|b|, γ_k = k u/(1 − k u), u = 2⁻⁵³; underflow adds at most 2⁻¹⁰⁷⁴ per operation):

* ⟨a, r⟩ ± ⟨b, s⟩ = ⟨fl(a ± b), r + s + u|fl(a ± b)|⟩;
* ⟨a, r⟩ ∘ ⟨b, s⟩ (entrywise) = ⟨fl(a∘b), |a| s + r (|b| + s) + u|fl(a∘b)|⟩;
* ⟨A, R⟩ ⟨B, S⟩ (inner dimension k) = ⟨fl(AB), |A| (S + γ_k |B|) + R (|B| + S)⟩;

every radius, itself computed in floating point from non-negative terms in at most m operations,
is multiplied by 1 + 2γ_{m+2} (the exact value is at most the computed one over 1 − γ_m) and
increased by (m + 2)·2⁻¹⁰²² (underflow).  A result that overflows has an infinite or NaN radius
and proves nothing.  The cost is three or four floating-point products per product: the
assembly of an LMI at a point at numpy speed, for :func:`lmidsl.numeric.proof.prove_block_matrix`.

:class:`EnclosureEvaluator` walks a theorem's expressions into enclosures: data are the decimals
written (the float x encloses its shortest decimal with radius 2u|x|), the point's values are
exact, and every scalar subexpression (parameters, derived scalars, numbers) is evaluated in ball
arithmetic (:class:`lmidsl.numeric.proof.BallEvaluator`) and enclosed; an inverse is taken in balls.
"""
from __future__ import annotations

import math

import numpy as np
from flint import arb

from .evaluate import assemble_blocks

U = 2.0 ** -53                     # unit roundoff, round to nearest
REALMIN = 2.0 ** -1022             # smallest normal double: bounds every underflow error used here


def gamma(k: int) -> float:
    """γ_k = k u / (1 − k u) (Higham): the relative error bound of k rounded operations."""
    return k * U / (1.0 - k * U)


def up(r, m: int):
    """A float upper bound of the exact non-negative quantity whose float value (m operations) is r."""
    return np.asarray(r) * (1.0 + 2.0 * gamma(m + 2)) + (m + 2) * REALMIN


class Enclosure:
    """⟨mid, rad⟩: every X with |X − mid| ≤ rad (see the module docstring)."""

    __slots__ = ("mid", "rad")
    __array_priority__ = 100       # numpy defers ``float * Enclosure`` to our __rmul__

    def __init__(self, mid, rad=None):
        self.mid = np.asarray(mid, dtype=float)
        self.rad = np.zeros_like(self.mid) if rad is None else np.asarray(rad, dtype=float)

    @classmethod
    def point(cls, x):
        """The exact floats x (radius 0)."""
        return cls(x)

    @classmethod
    def decimal(cls, x):
        """The decimals the floats x were written as: |d − x| ≤ u|x| (+ 2⁻¹⁰⁷⁴ if subnormal)."""
        m = np.asarray(x, dtype=float)
        return cls(m, np.where(m == 0.0, 0.0, 2.0 * U * np.abs(m) + 2.0 ** -1074))

    @classmethod
    def of_ball(cls, ball):
        """The enclosure of an arb ball (a float midpoint, the ball's radius and the midpoint's
        rounding rounded up)."""
        m = float(ball.mid())
        dist = (ball - m).abs_upper()          # an arb upper bound of |X − m| over the ball
        r = float(dist)
        return cls(m, math.nextafter(math.nextafter(r, math.inf), math.inf) if r else 0.0)

    @classmethod
    def of_balls(cls, balls):
        """The enclosure of an array of arb balls (or of one ball)."""
        a = np.asarray(balls, dtype=object)
        if a.ndim == 0:
            return cls.of_ball(a.item())
        parts = [cls.of_ball(b) for b in a.ravel()]
        return cls(np.array([p.mid for p in parts]).reshape(a.shape),
                   np.array([p.rad for p in parts]).reshape(a.shape))

    def balls(self):
        """An object array of arb balls enclosing this enclosure (for the ball fallbacks)."""
        out = np.empty(self.mid.shape, dtype=object)
        for idx, m in np.ndenumerate(self.mid):
            out[idx] = arb(float(m), float(self.rad[idx]))
        return out

    # -- shape ---------------------------------------------------------------------------
    @property
    def shape(self):
        return self.mid.shape

    @property
    def T(self):
        return Enclosure(self.mid.T, self.rad.T)

    def atleast_2d(self) -> "Enclosure":
        return Enclosure(np.atleast_2d(self.mid), np.atleast_2d(self.rad))

    def __getitem__(self, idx):
        return Enclosure(self.mid[idx], self.rad[idx])

    @property
    def finite(self) -> bool:
        return bool(np.all(np.isfinite(self.mid)) and np.all(np.isfinite(self.rad)))

    # -- arithmetic ----------------------------------------------------------------------
    @staticmethod
    def _wrap(x) -> "Enclosure":
        if isinstance(x, Enclosure):
            return x
        return Enclosure.point(x)      # a float operand is exact (numbers reach us as balls)

    def __neg__(self):
        return Enclosure(-self.mid, self.rad)

    def _sum(self, other, sign: float):
        o = self._wrap(other)
        mid = self.mid + sign * o.mid
        return Enclosure(mid, up(self.rad + o.rad + U * np.abs(mid), 3))

    def __add__(self, other):
        return self._sum(other, 1.0)

    __radd__ = __add__

    def __sub__(self, other):
        return self._sum(other, -1.0)

    def __rsub__(self, other):
        return (-self)._sum(other, 1.0)

    def __mul__(self, other):
        o = self._wrap(other)
        mid = self.mid * o.mid
        rad = np.abs(self.mid) * o.rad + self.rad * (np.abs(o.mid) + o.rad) + U * np.abs(mid)
        return Enclosure(mid, up(rad, 5))

    __rmul__ = __mul__

    def __matmul__(self, other):
        o = self._wrap(other)
        A, B = np.atleast_2d(self.mid), np.atleast_2d(o.mid)
        k = A.shape[1]
        absB = np.abs(B)
        mid = A @ B
        rad = np.abs(A) @ (np.atleast_2d(o.rad) + gamma(k) * absB) + np.atleast_2d(self.rad) @ (absB + np.atleast_2d(o.rad))
        return Enclosure(mid, up(rad, 2 * k + 4))

    def __rmatmul__(self, other):
        return self._wrap(other) @ self


def assemble(rows) -> Enclosure:
    """[[E_ij]] from rows of enclosures (midpoints and radii assembled alike, exactly)."""
    rows = [[Enclosure._wrap(b).atleast_2d() for b in row] for row in rows]
    return Enclosure(assemble_blocks([[b.mid for b in row] for row in rows]),
                     assemble_blocks([[b.rad for b in row] for row in rows]))


def symmetric_part(N: Enclosure, sign: float = 1.0) -> Enclosure:
    """An enclosure of sign·(X + Xᵀ)/2 over every X in N (halving is exact barring underflow)."""
    mid = sign * (N.mid + N.mid.T) / 2
    return Enclosure(mid, up((N.rad + N.rad.T) / 2 + U * np.abs(mid), 4))


__all__ = ["Enclosure", "assemble", "symmetric_part", "gamma", "up", "U", "REALMIN"]
