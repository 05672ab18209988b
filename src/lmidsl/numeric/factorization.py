"""Numerical factorisations used by recovery formulas, written once.

A change of variables often needs two nonsingular matrices with a prescribed product, e.g.
``R Sᵀ = I − X Z⁻¹`` (full-order H∞ filters, Scherer/Gahinet–Apkarian style).  Every choice
gives the same filter transfer function (the realisations differ by a similarity), but not the
same numerical quality: the recovery inverts R and S.

:data:`rs_split` takes the **balanced SVD split**: with M = U Σ Vᵀ,

    R = U Σ^{1/2},   S = V Σ^{1/2},   so  R Sᵀ = U Σ Vᵀ = M.

Then cond(R) = cond(S) = cond(M)^{1/2}.  Since cond(M) ≤ cond(R)·cond(S) for any factorisation,
this minimises the larger of the two condition numbers; the textbook choice S = I, R = M puts
all of cond(M) into R.  U and V are orthogonal, so no further error is amplified.
Each call reports cond(M), cond(R) and cond(S).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import mpmath
import numpy as np

from ..errors import LmidslError
from .exact import midpoint
from .proof import PreciseMatrix


class FactorizationError(LmidslError):
    """A factorisation that cannot be computed (singular or non-square argument)."""


@dataclass(frozen=True)
class Factorization:
    """A named factorisation: ``shapes(*arg_shapes)`` gives the output shapes (symbolic),
    ``function(*arrays)`` returns (outputs, report) with report a list of {matrix, cond, note}."""

    name: str
    description: str
    shapes: Callable
    function: Callable
    #: the relation the outputs satisfy, for LaTeX: ``{0}``, ``{1}`` the outputs, ``{a0}`` the argument
    relation: str = "{0} {1}^{{T}} = {a0}"

    def __call__(self, *arrays):
        return self.function(*arrays)


def _cond(M) -> float:
    s = np.linalg.svd(np.atleast_2d(M), compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else float("inf")


def balanced_split(M: np.ndarray, label: str = "M"):
    """R, S with R Sᵀ = M and cond(R) = cond(S) = cond(M)^{1/2} (SVD split).  A
    :class:`~lmidsl.numeric.proof.PreciseMatrix` M is split from its exact value
    (:func:`_precise_split`)."""
    if getattr(M, "exact", None) is not None:
        return _precise_split(M, label)
    M = np.atleast_2d(np.asarray(M, dtype=float))
    if M.shape[0] != M.shape[1]:
        raise FactorizationError(f"R Sᵀ = {label}: {label} is {M.shape[0]}×{M.shape[1]}, not square")
    U, s, Vt = np.linalg.svd(M)
    if s[-1] <= s[0] * np.finfo(float).eps * M.shape[0]:
        raise FactorizationError(f"R Sᵀ = {label}: {label} is numerically singular "
                                 f"(cond {_cond(M):.3g})")
    root = np.sqrt(s)
    R = U * root
    S = Vt.T * root
    report = [{"matrix": label, "cond": _cond(M),
               "note": f"factored as R Sᵀ by the balanced SVD split, cond(R) = cond(S) = {_cond(R):.3g}"}]
    return (R, S), report


SPLIT_DIGITS = 100
"""Decimal digits of the high-precision SVD of an exact M (mpmath): M = I − X Y at an
output-feedback point near a singular optimum had singular values from 1.4e14 down to 3.6e-7
(COMPleib AC7), which doubles cannot resolve."""


def _precise_split(M, label: str):
    """The balanced split of an exact M (a PreciseMatrix), by mpmath's SVD at
    :data:`SPLIT_DIGITS` digits; R and S are returned exactly (PreciseMatrix of the mpmath
    results as rationals), so that the recovery formulas evaluated in ball arithmetic use the
    very factors whose product is M to ~1e-100."""
    exact = np.atleast_2d(M.exact)
    if exact.shape[0] != exact.shape[1]:
        raise FactorizationError(f"R Sᵀ = {label}: {label} is {exact.shape[0]}×{exact.shape[1]}, not square")
    with mpmath.workdps(SPLIT_DIGITS):
        Mm = mpmath.matrix([[mpmath.mpf(int(x.p)) / int(x.q) for x in row] for row in exact])
        U, s, V = mpmath.svd_r(Mm)
        if s[s.rows - 1] <= s[0] * mpmath.mpf(10) ** (-SPLIT_DIGITS // 2):
            raise FactorizationError(f"R Sᵀ = {label}: {label} is singular to {SPLIT_DIGITS // 2} digits")
        root = [mpmath.sqrt(x) for x in s]
        R = [[midpoint(U[i, j] * root[j]) for j in range(U.cols)] for i in range(U.rows)]
        S = [[midpoint(V[j, i] * root[j]) for j in range(V.rows)] for i in range(V.cols)]
        cond_M, cond_R = float(s[0] / s[s.rows - 1]), float(root[0] / root[-1])
    report = [{"matrix": label, "cond": cond_M,
               "note": f"factored as R Sᵀ by the balanced SVD split at {SPLIT_DIGITS} digits, "
                       f"cond(R) = cond(S) = {cond_R:.3g}"}]
    return (PreciseMatrix.of(R), PreciseMatrix.of(S)), report


def square_pair(shape):
    """Shapes of the two factors of a square split M = R Sᵀ of an (r × c) matrix: r × r, c × c."""
    rows, cols = shape
    return [(rows, rows), (cols, cols)]


def _split_i_minus_xzinv(M):
    """The balanced split of M = I − XZ⁻¹ (a named function, so that theorems pickle)."""
    return balanced_split(M, "I - X Z^-1")


rs_split = Factorization(
    "balanced R Sᵀ split",
    "R, S nonsingular with R Sᵀ = M; balanced SVD split, cond(R) = cond(S) = √cond(M)",
    square_pair,
    _split_i_minus_xzinv,
)
