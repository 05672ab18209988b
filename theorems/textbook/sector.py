"""Maximised performances: the circle criterion's largest sector, and the largest ball inside an
invariant ellipsoid of a saturated feedback.

Both minimise an objective whose performance *decreases* with it (k = 1/δ, radius √β for
min −β): the optimum's point is the lower end of the performance's bracket and a dual bound its
upper end (:func:`lmidsl.certify.verdict.bracket`).

* ``textbook.circle_sector`` — Lur'e system ẋ = Ax + Bu, y = Cx + Du, u = −φ(t, y) with φ in the
  sector [0, k] (SISO).  Circle criterion (Khalil, *Nonlinear Systems*, 3rd ed., Thm 7.1; Boyd et
  al. 1994, §8.2): with A Hurwitz, absolute stability holds if G(s) + 1/k is strictly positive
  real, i.e. by the KYP lemma if there is P ≻ 0 with
  [[AᵀP + PA, PB − Cᵀ], [BᵀP − C, −D − Dᵀ − 2δ]] ≺ 0, δ = 1/k.  min δ gives
  k* = 1/δ* = −1 / min_ω Re G(jω) (when that minimum is negative): the check is a frequency
  sweep (python-control).
* ``textbook.saturated_ellipsoid`` — ẋ = Ax + B sat(Kx), one input, K given.  Hu, Lin & Chen,
  Automatica 38(2):351–359, 2002 (the auxiliary feedback H, Y = HQ): the ellipsoid
  E = {xᵀQ⁻¹x ≤ 1} is contractively invariant if there are Q ≻ 0, Y with
  He(AQ + BKQ) ≺ 0, He(AQ + BY) ≺ 0 (the two vertices of the saturation's convex hull) and
  [[1, Y], [Yᵀ, Q]] ⪰ 0 (|Hx| ≤ 1 on E).  max β with Q ⪰ βI: the ball of radius √β lies in E,
  so every trajectory from it converges to 0.  The check is a simulation from the ball.
"""
from sympy import sqrt

from lmidsl import He, I, Source, Theorem

BOYD = ("Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System and "
        "Control Theory, SIAM 1994")
HLC = ("Hu, Lin, Chen, An analysis and design method for linear systems subject to actuator "
       "saturation and disturbance, Automatica 38(2):351-359, 2002")

circle_sector = Theorem(
    "textbook.circle_sector", "Circle criterion: the largest sector [0, k] of absolute stability",
    Source("Boyd et al. 1994", "Sec. 8.2, circle criterion via the KYP lemma", BOYD), time="continuous",
    description="max k = 1/δ over P ≻ 0 such that G + 1/k is strictly positive real (KYP)")
_n = circle_sector.dim("n")
_A = circle_sector.data("A", _n, _n, description="state matrix (Hurwitz)")
_B = circle_sector.data("B", _n, 1, description="input matrix")
_C = circle_sector.data("C", 1, _n, description="output matrix")
_D = circle_sector.data("D", 1, 1, description="feedthrough")
_P = circle_sector.var("P", _n, kind="symmetric", description="Lyapunov matrix")
_delta = circle_sector.scalar("delta", latex=r"\delta", description="δ = 1/k")
circle_sector.lmi("(KYP)", [
    [He(_P * _A)],
    [_B.T * _P - _C, -_D - _D.T - 2 * _delta * I],
])
circle_sector.positive(_P)
circle_sector.minimize(_delta, performance=("k", 1 / _delta))
circle_sector.example("third-order", {
    "A": [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-6.0, -11.0, -6.0]],   # (s + 1)(s + 2)(s + 3)
    "B": [[0.0], [0.0], [1.0]], "C": [[6.0, 0.0, 0.0]], "D": [[0.0]]},
    provenance="illustration", provenance_note="G(s) = 6/((s+1)(s+2)(s+3)); k* = −1/min_ω Re G(jω)")

saturated_ellipsoid = Theorem(
    "textbook.saturated_ellipsoid", "Largest ball in an invariant ellipsoid of a saturated feedback",
    Source("Hu, Lin & Chen 2002", "the auxiliary-feedback condition (H, Y = HQ), one input", HLC),
    time="continuous",
    description="max radius √β over Q ⪰ βI, Y with He(AQ + BKQ) ≺ 0, He(AQ + BY) ≺ 0, "
                "[[1, Y], [Yᵀ, Q]] ⪰ 0: the ball of radius √β lies in a contractively invariant ellipsoid")
_n2 = saturated_ellipsoid.dim("n")
_A2 = saturated_ellipsoid.data("A", _n2, _n2, description="state matrix")
_B2 = saturated_ellipsoid.data("B", _n2, 1, description="input matrix (saturated input)")
_K2 = saturated_ellipsoid.data("K", 1, _n2, description="state feedback, u = sat(Kx)")
_Q = saturated_ellipsoid.var("Q", _n2, kind="symmetric", description="ellipsoid E = {xᵀQ⁻¹x ≤ 1}")
_Y = saturated_ellipsoid.var("Y", 1, _n2, description="Y = HQ, H the auxiliary feedback")
_beta = saturated_ellipsoid.scalar("beta", latex=r"\beta", description="squared radius of the ball in E")
saturated_ellipsoid.lmi("(sat, D=1)", [[He(_A2 * _Q + _B2 * _K2 * _Q)]])
saturated_ellipsoid.lmi("(sat, D=0)", [[He(_A2 * _Q + _B2 * _Y)]])
saturated_ellipsoid.lmi("(linear region)", [[I], [_Y.T, _Q]], sense=">=", strict=False)
saturated_ellipsoid.lmi("(ball)", [[_Q - _beta * I]], sense=">=", strict=False)
saturated_ellipsoid.minimize(-_beta, performance=("radius", sqrt(_beta)))
saturated_ellipsoid.example("unstable-2", {
    "A": [[0.0, 1.0], [1.0, 0.0]], "B": [[0.0], [1.0]], "K": [[-2.0, -2.0]]},
    provenance="illustration", provenance_note="an unstable saddle; A + BK has a double pole at −1")

THEOREMS = [circle_sector, saturated_ellipsoid]
