"""Takagi–Sugeno fuzzy systems: parallel distributed compensation with the Tanaka–Wang relaxation.

The plant is ẋ = Σᵢ hᵢ(z) (Aᵢ x + Bᵢ u) over r rules (hᵢ ≥ 0, Σ hᵢ = 1) and the PDC controller
u = Σⱼ hⱼ(z) Kⱼ x, so the closed loop is Σᵢ Σⱼ hᵢhⱼ (Aᵢ + BᵢKⱼ) x.  With V = xᵀX⁻¹x and
Mᵢ = KᵢX, Tanaka, Ikeda and Wang's relaxed conditions (K. Tanaka, T. Ikeda, H. O. Wang, "Fuzzy
regulators and fuzzy observers: relaxed stability conditions and LMI-based designs", IEEE
Trans. Fuzzy Systems 6(2):250–265, 1998; K. Tanaka, H. O. Wang, *Fuzzy Control Systems Design
and Analysis*, Wiley 2001, Ch. 3) ask for X ≻ 0, Q ⪰ 0 and

    He(AᵢX + BᵢMᵢ) + (s − 1) Q ≺ 0                         for all i,
    He(AᵢX + BᵢMⱼ) + He(AⱼX + BⱼMᵢ) − 2Q ⪯ 0               for all i < j,

(X ⪰ I stands for X ≻ 0: the conditions are homogeneous in (X, Q, Mᵢ)), with s the number of
rules that fire together; here s = r (always valid; the printed form has
s − 1 = r − 1 with r the size of the rule set).  The pair condition is imposed strictly (a hair
more conservative than ⪯, so that every LMI has a proof).  Kᵢ = MᵢX⁻¹ (signs: u = +Σ hⱼKⱼx).

Evidence: the Lyapunov decrease of the closed loop on a grid of the membership simplex
(:func:`lmidsl.fuzzy_grid`), which does not use the LMIs.  Data ``{"rules": [{"A": …, "B": …}, …]}``.
"""
import math

from lmidsl import He, I, Source, Theorem, fuzzy_grid

TIW = ("Tanaka, Ikeda, Wang, Fuzzy regulators and fuzzy observers: relaxed stability conditions "
       "and LMI-based designs, IEEE Trans. Fuzzy Systems 6(2):250-265, 1998")


def pendulum_rules(m: float = 2.0, M: float = 8.0, l: float = 0.5, g: float = 9.8,
                   beta: float = math.cos(math.radians(88.0))):
    """The two-rule T–S model of the inverted pendulum on a cart (x = (θ, θ̇), rule 1 at θ ≈ 0,
    rule 2 at |θ| ≈ 88°): Wang, Tanaka, Griffin, "An approach to fuzzy control of nonlinear
    systems: stability and design issues", IEEE Trans. Fuzzy Systems 4(1):14–23, 1996."""
    a = 1.0 / (m + M)
    d1 = 4.0 * l / 3.0 - a * m * l
    d2 = 4.0 * l / 3.0 - a * m * l * beta ** 2
    return [{"A": [[0.0, 1.0], [g / d1, 0.0]], "B": [[0.0], [-a / d1]]},
            {"A": [[0.0, 1.0], [2.0 * g / (math.pi * d2), 0.0]], "B": [[0.0], [-a * beta / d2]]}]


ts_pdc_ct = Theorem("textbook.ts_pdc_ct", "T–S fuzzy PDC stabilisation, Tanaka–Wang relaxation",
                    Source("Tanaka, Ikeda & Wang 1998", "relaxed stabilisation conditions (s = r)", TIW),
                    time="continuous", designs="gain",
                    description="X ≻ 0, Q ⪰ 0, Mᵢ: the relaxed PDC conditions for every rule and "
                                "every pair of rules i < j; Kᵢ = MᵢX⁻¹")
n, m = ts_pdc_ct.dim("n m")
R = ts_pdc_ct.index_set("rules", size="r", latex=r"\mathcal{R}", description="rules of the fuzzy model")
i, j = R.indices("i j")
A = ts_pdc_ct.data("A", n, n, over=R, description="state matrix of rule i")
B = ts_pdc_ct.data("B", n, m, over=R, description="input matrix of rule i")
X = ts_pdc_ct.var("X", n, kind="symmetric", description="X = P⁻¹, V = xᵀPx")
Q = ts_pdc_ct.var("Q", n, kind="symmetric", latex="Y", description="relaxation matrix")
Mv = ts_pdc_ct.var("M", m, n, over=R, description="Mᵢ = KᵢX")
ts_pdc_ct.lmi("(C1)", [[He(A[i] * X + B[i] * Mv[i]) + (R.size - 1) * Q]], forall=i)
ts_pdc_ct.lmi("(C2)", [[He(A[i] * X + B[i] * Mv[j]) + He(A[j] * X + B[j] * Mv[i]) - 2 * Q]],
              forall=(i, j), where=i < j)
ts_pdc_ct.lmi("X >= I", [[X - I]], sense=">=", strict=False)   # homogeneous: X ≻ 0 after scaling
ts_pdc_ct.lmi("Q >= 0", [[Q]], sense=">=")
ts_pdc_ct.feasibility()
ts_pdc_ct.recover_each(i, K=Mv[i] * X.I)
ts_pdc_ct.verify_with(fuzzy_grid(X="X", A="A", B="B", K="K", steps=50))
ts_pdc_ct.example("pendulum", {"rules": pendulum_rules()},
                  provenance="illustration",
                  provenance_note="the two-rule inverted-pendulum model of Wang, Tanaka & Griffin 1996 "
                                  "(m = 2, M = 8, 2l = 1, β = cos 88°), computed from its formulas")

THEOREMS = [ts_pdc_ct]
