"""Stability of ẋ = A x + A_d x(t − h) for every constant delay in [0, h]: Jensen and Wirtinger.

Both use the Lyapunov–Krasovskii functional V = ξᵀPξ + ∫_{t−h}^t xᵀSx + h ∫_{−h}^0 ∫_{t+θ}^t
ẋᵀRẋ and bound the integral term −h∫ẋᵀRẋ from above.  With ζ = (x, x(t − h), ν),
ν = (1/h)∫_{t−h}^t x, F₀ = [A, A_d, 0] (ẋ = F₀ζ), E₁ = [I, −I, 0], E₂ = [I, I, −2I]:

* **Jensen** (K. Gu, V. L. Kharitonov, J. Chen, *Stability of Time-Delay Systems*, Birkhauser
  2003, §3.6; ξ = x, P ∈ Sⁿ): h∫ẋᵀRẋ ≥ (E₁ζ)ᵀR(E₁ζ), and, without ν,

      [[He(PA) + S − R, ⋆, ⋆], [A_dᵀP + R, −S − R, ⋆], [hRA, hRA_d, −R]] ≺ 0.

* **Wirtinger** (A. Seuret, F. Gouaisbaut, "Wirtinger-based integral inequality: application
  to time-delay systems", Automatica 49(9):2860–2866, 2013, Theorem 5): h∫ẋᵀRẋ ≥
  (E₁ζ)ᵀR(E₁ζ) + 3(E₂ζ)ᵀR(E₂ζ), and with ξ = (x, ∫_{t−h}^t x) = G_h ζ, ξ̇ = Hζ,
  G_h = [[I, 0, 0], [0, 0, hI]], H = [[A, A_d, 0], [I, −I, 0]], P ∈ S²ⁿ:

      [[He(G_hᵀPH) + diag(S, −S, 0) − E₁ᵀRE₁ − 3E₂ᵀRE₂, ⋆], [hRF₀, −R]] ≺ 0.

P, S, R ≻ 0.  h multiplies R (and P through G_h): for a fixed h the conditions are LMIs, and
the largest h is found by bisection (``lmidsl solve`` bisects; h needs no value in the data).
On the classic example A = [[−2, 0], [0, −0.9]], A_d = [[−1, 0], [−1, −1]] the printed maximal
delays are 4.472 (Jensen) and 6.059 (Wirtinger, Seuret & Gouaisbaut's Table 1); the true delay
margin is 6.1725 (no stability condition may exceed it).
"""
from sympy import BlockMatrix, Identity, ZeroMatrix

from lmidsl import He, I, Source, Theorem

GKC = "Gu, Kharitonov, Chen, Stability of Time-Delay Systems, Birkhauser 2003"
SG = ("Seuret, Gouaisbaut, Wirtinger-based integral inequality: application to time-delay "
      "systems, Automatica 49(9):2860-2866, 2013")
CLASSIC = {"A": [[-2.0, 0.0], [0.0, -0.9]], "Ad": [[-1.0, 0.0], [-1.0, -1.0]]}


def _common(thm):
    n = thm.dim("n")
    A = thm.data("A", n, n, description="state matrix")
    Ad = thm.data("Ad", n, n, latex="A_d", description="delayed state matrix")
    h = thm.param("h", description="the delay (bisected)", domain=(0.0, 1e3))
    S = thm.var("S", n, kind="symmetric", latex="S")
    R = thm.var("R", n, kind="symmetric", latex="R")
    return n, A, Ad, h, S, R


def _finish(thm, P, S, R, printed):
    thm.positive(P, S, R)
    thm.feasibility(performance=("h", thm.param_decl["h"].symbol))
    thm.bisect("h", lower=0.0, upper=10.0, tol=1e-4, goal="max",
               performance="the largest delay h for which the LMIs are feasible")
    thm.example("classic", CLASSIC, params={"h": 1.0}, printed={"h": printed},
                printed_note="Seuret & Gouaisbaut 2013, Table 1 (Example 1)")


delay_jensen = Theorem("textbook.delay_jensen", "Delay-dependent stability by Jensen's inequality",
                       Source("Gu, Kharitonov & Chen 2003", "§3.6, the Jensen-based delay-dependent condition", GKC),
                       time="continuous",
                       description="max h s.t. the Lyapunov–Krasovskii LMI with Jensen's bound holds")
n, A, Ad, h, S, R = _common(delay_jensen)
P = delay_jensen.var("P", n, kind="symmetric")
delay_jensen.lmi("(J)", [
    [He(P * A) + S - R],
    [Ad.T * P + R, -S - R],
    [h * R * A, h * R * Ad, -R],
])
_finish(delay_jensen, P, S, R, 4.472)

delay_wirtinger = Theorem("textbook.delay_wirtinger", "Delay-dependent stability by Wirtinger's inequality",
                          Source("Seuret & Gouaisbaut 2013", "Theorem 5", SG), time="continuous",
                          description="max h s.t. the Lyapunov–Krasovskii LMI with Wirtinger's bound holds")
n, A, Ad, h, S, R = _common(delay_wirtinger)
P = delay_wirtinger.var("P", 2 * n, kind="symmetric")
In, On = Identity(n), ZeroMatrix(n, n)
Gh = delay_wirtinger.define("G_h", BlockMatrix([[In, On, On], [On, On, h * In]]), latex="G_h")
H = delay_wirtinger.define("H", BlockMatrix([[A, Ad, On], [In, -In, On]]), latex="H")
F0 = delay_wirtinger.define("F_0", BlockMatrix([[A, Ad, On]]), latex="F_0")
E1 = delay_wirtinger.define("E_1", BlockMatrix([[In, -In, On]]), latex="E_1")
E2 = delay_wirtinger.define("E_2", BlockMatrix([[In, In, -2 * In]]), latex="E_2")
Sd = BlockMatrix([[S, On, On], [On, -S, On], [On, On, On]])
delay_wirtinger.lmi("(W)", [
    [He(Gh.T * P * H) + Sd - E1.T * R * E1 - 3 * E2.T * R * E2],
    [h * R * F0, -R],
])
_finish(delay_wirtinger, P, S, R, 6.059)

THEOREMS = [delay_jensen, delay_wirtinger]
