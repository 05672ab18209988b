"""The standard changes of variables of LMI synthesis, written once.

A synthesis LMI is linear only in transformed variables; after the solve the design is
recovered by inverting the change of variables.  Each helper here gives, for symbols a theorem
file has declared, (i) the blocks of the transformed closed loop that the LMIs are written
with and/or (ii) the recovery formulas (sympy expressions for :meth:`Theorem.recover`), declaring
on the theorem the factorisation the recovery needs (:meth:`Theorem.factor`).  The formulas are
the same in continuous and discrete time: a change of variables is algebra on the closed-loop
matrices, only the LMI that uses it depends on the time domain.

**State feedback** (Bernussou, Peres, Geromel, "A linear programming oriented procedure for
quadratic stabilization of uncertain systems", Systems & Control Letters 13, 1989; Boyd,
El Ghaoui, Feron, Balakrishnan 1994, ch. 7):
u = K x, closed loop A + B2 K, C1 + D12 K.  With Y = P⁻¹ ≻ 0 and W = K Y the congruence
diag(Y, I, ...) of any Lyapunov-type LMI in P replaces P(A + B2K) by (A + B2K)Y = AY + B2W,
which is linear in (Y, W).  Recovery: :func:`state_feedback_gain`, K = W Y⁻¹.

**Full-order dynamic output feedback** (Scherer, Gahinet, Chilali, "Multiobjective
output-feedback control via LMI optimization", IEEE TAC 42(7), 1997; Gahinet, "Explicit
controller formulas for LMI-based H∞ synthesis", Automatica 32(7), 1996; Masubuchi, Ohara,
Suda, "LMI-based controller synthesis: a unified formulation and solution", Int. J. Robust
Nonlinear Control 8, 1998, for both time domains).  Plant
x' = A x + B1 w + B2 u, z = C1 x + D11 w + D12 u, y = C2 x + D21 w + D22 u; controller
xK' = AK xK + BK y, u = CK xK + DK y of the plant's order n.  For D22 = 0 the closed loop is

    𝒜 = [[A + B2 DK C2, B2 CK], [BK C2, AK]],   ℬ = [[B1 + B2 DK D21], [BK D21]],
    𝒞 = [C1 + D12 DK C2, D12 CK],               𝒟 = D11 + D12 DK D21.

Partition the closed-loop Lyapunov matrix 𝒫 = [[Y, N], [Nᵀ, *]] and 𝒫⁻¹ = [[X, M], [Mᵀ, *]]
(so M Nᵀ = I − X Y), and let Π₁ = [[X, I], [Mᵀ, 0]].  Then Π₁ᵀ𝒫Π₁ = [[X, I], [I, Y]] and, with

    Â = N AK Mᵀ + N BK C2 X + Y B2 CK Mᵀ + Y (A + B2 DK C2) X,
    B̂ = N BK + Y B2 DK,     Ĉ = CK Mᵀ + DK C2 X,     D̂ = DK,

the congruence by Π₁ turns every closed-loop block into an affine function of
(X, Y, Â, B̂, Ĉ, D̂) (:func:`output_feedback_blocks`):

    Π₁ᵀ𝒫𝒜Π₁ = [[A X + B2 Ĉ, A + B2 D̂ C2], [Â, Y A + B̂ C2]],   Π₁ᵀ𝒫ℬ = [[B1 + B2 D̂ D21], [Y B1 + B̂ D21]],
    𝒞Π₁ = [C1 X + D12 Ĉ, C1 + D12 D̂ C2],                      𝒟 = D11 + D12 D̂ D21.

Continuous time congruence-transforms 𝒜ᵀ𝒫 + 𝒫𝒜; discrete time the block 𝒫𝒜 of the
Schur-complemented Lyapunov inequality: the same blocks serve both.  [[X, I], [I, Y]] ≻ 0
makes I − X Y nonsingular, so M, N exist; they are any factors of I − X Y
(:data:`mn_split`, the balanced SVD split, which minimises the worse of cond(M), cond(N)).
Recovery (:func:`output_feedback`) inverts the definitions, in order:

    DK = D̂,   CK = (Ĉ − D̂ C2 X) M⁻ᵀ,   BK = N⁻¹ (B̂ − Y B2 D̂),
    AK = N⁻¹ (Â − Y A X − B̂ C2 X − Y B2 Ĉ + Y B2 D̂ C2 X) M⁻ᵀ

(the last after substituting BK and CK into Â's definition).  A plant with D22 ≠ 0 is
handled exactly by loop shifting: the controller K̃ so recovered is designed for
ỹ = y − D22 u, i.e. for the plant with D22 = 0, and u = K̃ (y − D22 u) is the controller

    DK = Δ D̃K,  CK = Δ C̃K,  BK = B̃K (I − D22 DK),  AK = ÃK − B̃K D22 CK,
    Δ = (I + D̃K D22)⁻¹,

which must be well posed (I + D̃K D22 nonsingular; the inverse is reported with its condition).

**Full-order filter** (the filter as a controller in the SGC parametrisation above; the
filtering LMIs of Geromel, de Oliveira, Bernussou, "Robust filtering of discrete-time linear
systems with parameter dependent Lyapunov functions", SIAM J. Control Optim. 41(3), 2002, use
the same kind of change of variables).  Plant
x' = A x + B1 w, z = C1 x + D11 w, y = C2 x + D21 w; filter x̂' = Af x̂ + Bf y,
ẑ = Cf x̂ + Df y; error e = z − ẑ.  This is the output-feedback problem with u = ẑ, B2 = 0,
D12 = −I, D22 = 0: the same 𝒫, Π₁, and (:func:`filter_blocks`, :func:`full_order_filter`)

    Â = N Af Mᵀ + N Bf C2 X + Y A X,   B̂ = N Bf,   Ĉ = Cf Mᵀ + Df C2 X,   D̂ = Df,
    Af = N⁻¹ (Â − Y A X − B̂ C2 X) M⁻ᵀ,   Bf = N⁻¹ B̂,   Cf = (Ĉ − D̂ C2 X) M⁻ᵀ,   Df = D̂.

Every transfer function recovered does not depend on the choice of M, N (another choice is a
similarity of the controller/filter state).  The unit tests (``tests/test_changes_of_variables.py``)
check the congruence identities and the recoveries numerically.
"""
from __future__ import annotations

import sympy as sp
from sympy import Identity, ZeroMatrix

from .factorization import Factorization, balanced_split, square_pair


mn_split = Factorization(
    "balanced M Nᵀ split",
    "M, N nonsingular with M Nᵀ = I − X Y; balanced SVD split, cond(M) = cond(N) = √cond(I − XY)",
    square_pair,
    lambda M: balanced_split(M, "I - X Y"),
)
"""M, N with M Nᵀ = I − X Y (the Scherer–Gahinet–Chilali factorisation), balanced SVD split."""


def state_feedback_gain(W, Y):
    """K = W Y⁻¹: the state-feedback gain from W = K Y, Y = P⁻¹ ≻ 0."""
    return W * Y.I


def _identity(n):
    return Identity(n)


def output_feedback_blocks(X, Y, Ah, Bh, Ch, Dh, A, B1, B2, C1, C2, D11, D12, D21) -> dict:
    """The closed loop after the congruence by Π₁, affine in (X, Y, Â, B̂, Ĉ, D̂).

    Returns sympy blocks: ``A11`` = A X + B2 Ĉ, ``A12`` = A + B2 D̂ C2, ``A21`` = Â,
    ``A22`` = Y A + B̂ C2, ``B1`` = B1 + B2 D̂ D21, ``B2`` = Y B1 + B̂ D21,
    ``C1`` = C1 X + D12 Ĉ, ``C2`` = C1 + D12 D̂ C2, ``D`` = D11 + D12 D̂ D21
    (Π₁ᵀ𝒫𝒜Π₁ = [[A11, A12], [A21, A22]], Π₁ᵀ𝒫ℬ = [[B1], [B2]], 𝒞Π₁ = [C1, C2], 𝒟 = D), and
    ``P11`` = X, ``P22`` = Y (Π₁ᵀ𝒫Π₁ = [[X, I], [I, Y]]).  ``B2``/``D12`` may be None (a filter
    with its own signs: use :func:`filter_blocks`).
    """
    return {
        "A11": A * X + B2 * Ch, "A12": A + B2 * Dh * C2, "A21": Ah, "A22": Y * A + Bh * C2,
        "B1": B1 + B2 * Dh * D21, "B2": Y * B1 + Bh * D21,
        "C1": C1 * X + D12 * Ch, "C2": C1 + D12 * Dh * C2, "D": D11 + D12 * Dh * D21,
        "P11": X, "P22": Y,
    }


def filter_blocks(X, Y, Ah, Bh, Ch, Dh, A, B1, C1, C2, D11, D21) -> dict:
    """:func:`output_feedback_blocks` with B2 = 0, D12 = −I: the filtering-error system."""
    return {
        "A11": A * X, "A12": A, "A21": Ah, "A22": Y * A + Bh * C2,
        "B1": B1, "B2": Y * B1 + Bh * D21,
        "C1": C1 * X - Ch, "C2": C1 - Dh * C2, "D": D11 - Dh * D21,
        "P11": X, "P22": Y,
    }


def output_feedback(thm, X, Y, Ah, Bh, Ch, Dh, A, B2, C2, D22=None, *,
                    factor_names: str = "M N") -> dict:
    """Recovery formulas {AK, BK, CK, DK} of the SGC change of variables (both time domains).

    Declares ``M, N = thm.factor(factor_names, mn_split, I − X Y)`` on ``thm`` and returns the
    formulas for ``thm.recover(**...)``.  With ``D22`` (a datum) the loop-shifted controller
    for the plant with that D22 is returned (see the module docstring).
    """
    n = X.shape[0]
    M, N = thm.factor(factor_names, mn_split, _identity(n) - X * Y,
                      description="M Nᵀ = I − X Y (balanced SVD split, lmidsl.numeric.changes_of_variables)")
    DK = Dh
    CK = (Ch - Dh * C2 * X) * M.T.I
    BK = N.I * (Bh - Y * B2 * Dh)
    AK = N.I * (Ah - Y * A * X - Bh * C2 * X - Y * B2 * Ch + Y * B2 * Dh * C2 * X) * M.T.I
    if D22 is None:
        return {"AK": AK, "BK": BK, "CK": CK, "DK": DK}
    return loop_shift(AK, BK, CK, DK, D22)


def loop_shift(AK, BK, CK, DK, D22) -> dict:
    """The controller u = K̃(y − D22 u) as a controller of y: {AK, BK, CK, DK} (see above)."""
    delta = (_identity(DK.shape[0]) + DK * D22).I
    DKs = delta * DK
    CKs = delta * CK
    return {"AK": AK - BK * D22 * CKs, "BK": BK * (_identity(D22.shape[0]) - D22 * DKs),
            "CK": CKs, "DK": DKs}


def full_order_filter(thm, X, Y, Ah, Bh, Ch, Dh, A, C2, *, factor_names: str = "M N") -> dict:
    """Recovery formulas {Af, Bf, Cf, Df} of the full-order filter (both time domains);
    declares ``M, N`` (M Nᵀ = I − X Y) on ``thm``."""
    n = X.shape[0]
    M, N = thm.factor(factor_names, mn_split, _identity(n) - X * Y,
                      description="M Nᵀ = I − X Y (balanced SVD split, lmidsl.numeric.changes_of_variables)")
    return {"Af": N.I * (Ah - Y * A * X - Bh * C2 * X) * M.T.I, "Bf": N.I * Bh,
            "Cf": (Ch - Dh * C2 * X) * M.T.I, "Df": Dh}


def closed_loop_matrices(A, B1, B2, C1, C2, D11, D12, D21, D22, AK, BK, CK, DK) -> dict:
    """The closed loop of the plant with u = K y (general D22, well-posed loop), as sympy
    expressions {A, B, C, D}; for analysis theorems, where the controller is data:

        R = (I − DK D22)⁻¹,  R̃ = (I − D22 DK)⁻¹,
        𝒜 = [[A + B2 R DK C2, B2 R CK], [BK R̃ C2, AK + BK R̃ D22 CK]],
        ℬ = [[B1 + B2 R DK D21], [BK R̃ D21]],  𝒞 = [C1 + D12 R DK C2, D12 R CK],
        𝒟 = D11 + D12 R DK D21.
    """
    R = (_identity(DK.shape[0]) - DK * D22).I
    Rt = (_identity(D22.shape[0]) - D22 * DK).I
    return {
        "A": sp.BlockMatrix([[A + B2 * R * DK * C2, B2 * R * CK], [BK * Rt * C2, AK + BK * Rt * D22 * CK]]),
        "B": sp.BlockMatrix([[B1 + B2 * R * DK * D21], [BK * Rt * D21]]),
        "C": sp.BlockMatrix([[C1 + D12 * R * DK * C2, D12 * R * CK]]),
        "D": D11 + D12 * R * DK * D21,
    }


def state_feedback_closed_loop(A, B1, B2, C1, D11, D12, K) -> dict:
    """The closed loop of x' = A x + B1 w + B2 u, z = C1 x + D11 w + D12 u with u = K x."""
    return {"A": A + B2 * K, "B": B1, "C": C1 + D12 * K, "D": D11}


def filter_error_matrices(A, B1, C1, C2, D11, D21, Af, Bf, Cf, Df) -> dict:
    """The filtering-error system e = z − ẑ, state (x, x̂), as sympy expressions {A, B, C, D}."""
    n, k = A.shape[0], Af.shape[0]
    return {
        "A": sp.BlockMatrix([[A, ZeroMatrix(n, k)], [Bf * C2, Af]]),
        "B": sp.BlockMatrix([[B1], [Bf * D21]]),
        "C": sp.BlockMatrix([[C1 - Df * C2, -Cf]]),
        "D": D11 - Df * D21,
    }


__all__ = ["mn_split", "state_feedback_gain", "output_feedback_blocks", "filter_blocks",
           "output_feedback", "loop_shift", "full_order_filter", "closed_loop_matrices",
           "state_feedback_closed_loop", "filter_error_matrices"]
