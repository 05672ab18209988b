"""The positive-real (Kalman–Yakubovich–Popov) lemma: passivity and the passivity index.

References: Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and
Control Theory*, SIAM 1994, §2.7.2 (positive-real lemma); Rantzer, "On the Kalman–Yakubovich–
Popov lemma", Systems & Control Letters 28, 1996 (the strict frequency-domain equivalence
used here); Scherer & Weiland, *Linear Matrix Inequalities in Control*, lecture notes (the KYP
lemma, dissipativity with the supply rate 2 wᵀz).

For a square system G = (A, B, C, D) with A stable (Hurwitz / Schur) and (A, B)
controllable, the KYP lemma says: G(jω) + G(jω)* ≻ 2ν I for every ω ∈ ℝ ∪ {∞} (continuous;
z = e^{jω} on the unit circle in discrete time) iff there is a symmetric P with

* continuous:  [[AᵀP + PA, PB − Cᵀ], [BᵀP − C, 2νI − D − Dᵀ]] ≺ 0;
* discrete:    [[AᵀPA − P, AᵀPB − Cᵀ], [BᵀPA − C, BᵀPB + 2νI − D − Dᵀ]] ≺ 0.

So max ν is the input-feedforward passivity index inf_ω λ_min(G + G*)/2 (the largest ν with
G − νI positive real).  G is strictly positive real (passive with margin) iff ν > 0, and then
P ≻ 0 is a storage function of the supply rate 2 wᵀz (Boyd et al. §2.7.2).  P is not
constrained to be positive here: for ν* < 0 the index is still the optimum, without a storage
function.  The independent check is a frequency sweep of the Hermitian part.
"""
from lmidsl import He, I, Source, Theorem

from .brl import scale_state
from .plants import random_system

BOYD = ("Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System and "
        "Control Theory, SIAM 1994")


def _kyp(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"Positive-real (KYP) lemma: passivity index ({time} time)",
                  Source("Boyd et al. 1994", "Sec. 2.7.2, positive-real lemma", BOYD), time=time,
                  description="max ν over symmetric P such that the KYP LMI holds: "
                              "ν = inf_ω λ_min(G + G*)/2; G is strictly positive real iff ν > 0.")
    n, m = thm.dim("n m")
    A = thm.data("A", n, n, description="state matrix")
    B = thm.data("B", n, m, description="input matrix")
    C = thm.data("C", m, n, description="output matrix (square system)")
    D = thm.data("D", m, m, description="feedthrough")
    P = thm.var("P", n, kind="symmetric", description="storage matrix (positive when ν > 0)")
    nu = thm.scalar("nu", latex=r"\nu", description="input-feedforward passivity index")
    if time == "continuous":
        thm.lmi("(KYP)", [
            [He(P * A)],
            [B.T * P - C, 2 * nu * I - D - D.T],
        ])
    else:
        thm.lmi("(KYP)", [
            [A.T * P * A - P],
            [B.T * P * A - C, B.T * P * B + 2 * nu * I - D - D.T],
        ])
    thm.minimize(-nu, performance=("nu", nu))
    scale_state(thm, ("A", "B"), ("A", "C"))
    return thm


def passive_example(seed: int, time: str, n: int = 3, m: int = 2, shift: float = 0.0) -> dict:
    """A random stable square system with D = D0 + shift·I (a larger shift makes it passive)."""
    d = random_system(seed, n, m, m, time)
    d["D"] = [[v + (shift if i == j else 0.0) for j, v in enumerate(row)] for i, row in enumerate(d["D"])]
    return d


kyp_pr_ct = _kyp("kyp_pr_ct", "continuous")
kyp_pr_ct.example("random-3x2", passive_example(31, "continuous", shift=3.0), provenance="illustration",
                  provenance_note="a random stable system with D shifted by 3I, numpy seed 31")
kyp_pr_dt = _kyp("kyp_pr_dt", "discrete")
kyp_pr_dt.example("random-3x2", passive_example(31, "discrete", shift=3.0), provenance="illustration",
                  provenance_note="a random Schur-stable system with D shifted by 3I, numpy seed 31")

THEOREMS = [kyp_pr_ct, kyp_pr_dt]
