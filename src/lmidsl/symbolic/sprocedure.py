"""Norm-bounded uncertainty: the S-procedure (Petersen's lemma) stated once.

A robust LMI with a norm-bounded term,

    M + He(H F(t) E) < 0   for every F(t) with F(t)ᵀF(t) ≤ I,

where ``M`` is a block matrix, ``H`` a block column (k columns) and ``E`` a block row (l rows)
in the same block partition, holds if and only if (Petersen's lemma; for one full block F) there
is a scalar ε > 0 with

    M + ε⁻¹ H Hᵀ + ε Eᵀ E < 0.

The term is made affine in the decision variables by Schur complements.  The forms offered
(``form=``), with the new block rows appended at the end of ``M``:

* ``"diag"``:     [M + ε EᵀE, H; Hᵀ, −εI] < 0      (E data; H may contain variables, e.g. P H)
* ``"columns"``:  [M, εEᵀ, H; εE, −εI, 0; Hᵀ, 0, −εI] < 0   (E data; H may contain variables)
* ``"dual-diag"``:    [M + ε HHᵀ, Eᵀ; E, −εI] < 0    (H data; E may contain variables)
* ``"dual-columns"``: [M, Eᵀ, εH; E, −εI, 0; εHᵀ, 0, −εI] < 0   (H data)

Each is equivalent to M + ε⁻¹HHᵀ + εEᵀE < 0 (the dual forms use ε ↔ ε⁻¹).  Several terms
(independent blocks F₁, F₂, …, each with its own ε) are applied one after the other; with more
than one block the condition is only sufficient.  Whether the result is affine is checked by
:meth:`lmidsl.theorem.theorem.Theorem.lmi`, which names the block when a form does not fit the data.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp
from sympy import ZeroMatrix

from .blocks import BlockMatrixSpec, _is_zero_marker, block_matrix
from ..errors import ShapeMismatchError, TheoremDefinitionError

FORMS = ("diag", "columns", "dual-diag", "dual-columns")


@dataclass
class NormBounded:
    """One term He(H F E) with FᵀF ≤ I and its multiplier ε.

    ``H``: one entry per block row of M (a matrix expression or ``0``), all with the same number
    of columns k; ``E``: one entry per block column (``0`` or a matrix with l rows).  F is k × l.
    ``eps``: the scalar decision variable ε (declared by the theorem, ``nonneg=True``).
    """

    H: list
    E: list
    eps: sp.Expr
    form: str = "diag"
    name: str = ""

    def __post_init__(self):
        if self.form not in FORMS:
            raise TheoremDefinitionError(f"norm-bounded term {self.name}: form {self.form!r} is not one of {FORMS}")


def _width(entries, axis, what, name) -> sp.Expr:
    sizes = {e.shape[axis] for e in entries if not _is_zero_marker(e)}
    if not sizes:
        raise ShapeMismatchError(f"norm-bounded term {name}: {what} has no non-zero block")
    if len(sizes) > 1:
        raise ShapeMismatchError(f"norm-bounded term {name}: the blocks of {what} have different "
                                 f"{'column' if axis else 'row'} counts {sorted(map(str, sizes))}")
    return sizes.pop()


def _sized(entries, sizes, other, axis):
    """Replace 0 markers by zero blocks: column entries (axis 0) are sizes[r] × other."""
    out = []
    for e, s in zip(entries, sizes):
        if _is_zero_marker(e):
            e = ZeroMatrix(s, other) if axis == 0 else ZeroMatrix(other, s)
        out.append(e)
    return out


def _add(a, b):
    if isinstance(a, ZeroMatrix):
        return b
    return a + b


def sprocedure(rows, terms, *, sizes=None, where: str = "") -> BlockMatrixSpec:
    """The S-procedure form of ``rows`` (one lower triangle) + Σ He(H_t F_t E_t).

    Returns a :class:`BlockMatrixSpec` to hand to ``Theorem.lmi``: the blocks of M (with
    ε EᵀE added for the "diag" form, ε HHᵀ for "dual-diag"), followed by the new block rows of
    every term in order.
    """
    spec = rows if isinstance(rows, BlockMatrixSpec) else block_matrix(rows, sizes=sizes, where=where)
    lower = [list(r) for r in spec.lower]
    sizes = list(spec.sizes)
    q0 = len(sizes)
    for t, term in enumerate(terms):
        name = term.name or f"{t + 1}"
        if len(term.H) != q0 or len(term.E) != q0:
            raise ShapeMismatchError(
                f"{where + ': ' if where else ''}norm-bounded term {name}: H has {len(term.H)} and E has "
                f"{len(term.E)} blocks, but the matrix has {q0} block rows")
        k = _width(term.H, 1, "H", name)
        l = _width(term.E, 0, "E", name)
        H = _sized(term.H, sizes[:q0], k, 0)
        E = _sized(term.E, sizes[:q0], l, 1)
        eps = term.eps
        q = len(sizes)
        if term.form in ("diag", "dual-diag"):
            for i in range(q0):
                for j in range(i + 1):
                    if term.form == "diag":
                        extra = eps * E[i].T * E[j] if not (_is_zero(E[i]) or _is_zero(E[j])) else None
                    else:
                        extra = eps * H[i] * H[j].T if not (_is_zero(H[i]) or _is_zero(H[j])) else None
                    if extra is not None:
                        lower[i][j] = _add(lower[i][j], extra)
            new = [H[j].T for j in range(q0)] if term.form == "diag" else [E[j] for j in range(q0)]
            width = k if term.form == "diag" else l
            new += [ZeroMatrix(width, sizes[j]) for j in range(q0, q)]
            new.append(-eps * sp.Identity(width))
            lower.append(new)
            sizes.append(width)
        else:
            if term.form == "columns":
                first, first_w = [eps * E[j] for j in range(q0)], l
                second, second_w = [H[j].T for j in range(q0)], k
            else:
                first, first_w = [E[j] for j in range(q0)], l
                second, second_w = [eps * H[j].T for j in range(q0)], k
            first = [ZeroMatrix(first_w, sizes[j]) if _is_zero(b) else b for j, b in enumerate(first)]
            second = [ZeroMatrix(second_w, sizes[j]) if _is_zero(b) else b for j, b in enumerate(second)]
            row1 = first + [ZeroMatrix(first_w, sizes[j]) for j in range(q0, q)] + [-eps * sp.Identity(first_w)]
            row2 = (second + [ZeroMatrix(second_w, sizes[j]) for j in range(q0, q)]
                    + [ZeroMatrix(second_w, first_w), -eps * sp.Identity(second_w)])
            lower += [row1, row2]
            sizes += [first_w, second_w]
    return BlockMatrixSpec(lower, sizes, spec.given_as)


def _is_zero(block) -> bool:
    return isinstance(block, ZeroMatrix) or _is_zero_marker(block)


# -- numerics: the robust matrix at a given F, and admissible samples ----------------------

def robust_matrix(M: np.ndarray, H: np.ndarray, F: np.ndarray, E: np.ndarray) -> np.ndarray:
    """M + H F E + (H F E)ᵀ for numeric matrices."""
    HFE = H @ F @ E
    return M + HFE + HFE.T


def contraction_samples(k: int, l: int, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Admissible F (k × l, ‖F‖ ≤ 1): ±I-like extreme points, random ones on and inside the ball.

    The extreme points of {F : FᵀF ≤ I} are the matrices with all singular values 1 (orthogonal
    for square F); a quarter of the random samples are scaled inside the ball.
    """
    out = []
    eye = np.eye(k, l)
    out += [eye, -eye]
    for s in range(count):
        G = rng.standard_normal((k, l))
        U, _, Vt = np.linalg.svd(G, full_matrices=False)
        F = U @ Vt
        if s % 4 == 3:
            F = F * rng.uniform(0.0, 1.0)
        out.append(F)
    return out
