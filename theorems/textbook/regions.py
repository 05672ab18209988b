"""Pole placement in LMI regions by state feedback (Chilali & Gahinet).

Reference: Chilali & Gahinet, "H∞ design with pole placement constraints: an LMI approach",
IEEE TAC 41(3):358-367, 1996 (LMI regions, the D-stability LMI M_D(A, X) ≺ 0 and its
intersections); Boyd, El Ghaoui, Feron, Balakrishnan 1994, ch. 7 (W = K X).

An LMI region D = {s : L + M s + Mᵀ s̄ ≺ 0} contains every eigenvalue of A iff there is X ≻ 0
with L ⊗ X + M ⊗ (A X) + Mᵀ ⊗ (A X)ᵀ ≺ 0.  For the closed loop A + B2 K with W = K X the
conditions are linear in (X, W); with AX = A X + B2 W:

* half-plane Re s < −α:           He(AX) + 2α X ≺ 0;
* disk |s + q| < r:               [[−r X, q X + AX], [q X + AXᵀ, −r X]] ≺ 0;
* sector |Im s| < −Re s · tan θ:  [[sin θ He(AX), cos θ (AX − AXᵀ)], [cos θ (AXᵀ − AX), sin θ He(AX)]] ≺ 0
  (damping ratio above cos θ).

With one X for all three (Chilali–Gahinet's intersection: sufficient), the eigenvalues of
A + B2 K, K = W X⁻¹, lie in the intersection.  A feasibility problem; the check is the
closed-loop eigenvalues.
"""
from lmidsl import He, Source, Theorem, state_feedback_gain
from sympy import cos, sin

from .brl import scale_state
from .plants import random_plant, subset

CG = ("Chilali, Gahinet, H∞ design with pole placement constraints: an LMI approach, "
      "IEEE TAC 41(3):358-367, 1996")

def region_lmis(thm, AX, X, alpha, q, r, st, ct):
    """The half-plane, disk and sector LMIs of Chilali–Gahinet for AX (= A_cl X), common X ≻ 0."""
    thm.lmi("(half-plane)", [[He(AX) + 2 * alpha * X]])
    thm.lmi("(disk)", [
        [-r * X],
        [q * X + AX.T, -r * X],
    ])
    thm.lmi("(sector)", [
        [st * He(AX)],
        [ct * (AX.T - AX), st * He(AX)],
    ])
    thm.positive(X)
    thm.feasibility()


def region_params(thm):
    """α, q, r, θ and sin θ, cos θ of the region."""
    alpha = thm.param("alpha", latex=r"\alpha", domain=(0.0, 1e6), default=0.5,
                      description="half-plane Re s < -alpha")
    q = thm.param("q", latex="q", domain=(-1e6, 1e6), default=0.0, description="disk centre -q")
    r = thm.param("r", latex="r", domain=(0.0, 1e6), open_domain=True, default=10.0, description="disk radius")
    theta = thm.param("theta", latex=r"\theta", domain=(0.0, 1.5707963267948966), open_domain=True,
                      default=0.7853981633974483, description="sector half-angle (rad)")
    return (alpha, q, r, thm.derived("s_theta", sin(theta), latex=r"\sin\theta"),
            thm.derived("c_theta", cos(theta), latex=r"\cos\theta"))


pole_region_cl_ct = Theorem(
    "textbook.pole_region_cl_ct", "Closed-loop poles of a given state feedback in an LMI region (analysis)",
    Source("Chilali & Gahinet 1996", "D-stability of A + B2 K: common X for the three regions", CG),
    time="continuous",
    description="with K given: find X ≻ 0 with the half-plane, disk and sector LMIs of (A + B2 K) X; "
                "their feasibility proves every eigenvalue of A + B2 K lies in the intersection.")
_na, _ma = pole_region_cl_ct.dim("n m2")
_Acl = (pole_region_cl_ct.data("A", _na, _na, description="state matrix")
        + pole_region_cl_ct.data("B2", _na, _ma, latex="B_2", description="control input u")
        * pole_region_cl_ct.data("K", _ma, _na, description="the state-feedback gain u = K x"))
_Xa = pole_region_cl_ct.var("X", _na, kind="symmetric", description="X = P⁻¹")
region_lmis(pole_region_cl_ct, _Acl * _Xa, _Xa, *region_params(pole_region_cl_ct))

pole_region_sf_ct = Theorem(
    "textbook.pole_region_sf_ct", "State feedback with closed-loop poles in an LMI region (continuous time)",
    Source("Chilali & Gahinet 1996", "LMI regions: half-plane, disk and conic sector, common X", CG),
    time="continuous", designs="gain",
    description="find X ≻ 0, W with the half-plane, disk and sector LMIs of A X + B2 W; "
                "K = W X⁻¹ puts the eigenvalues of A + B2 K in their intersection.")
_n, _m2 = pole_region_sf_ct.dim("n m2")
A = pole_region_sf_ct.data("A", _n, _n, description="state matrix")
B2 = pole_region_sf_ct.data("B2", _n, _m2, latex="B_2", description="control input u")
X = pole_region_sf_ct.var("X", _n, kind="symmetric", description="X = P⁻¹")
W = pole_region_sf_ct.var("W", _m2, _n, description="W = K X")
region_lmis(pole_region_sf_ct, A * X + B2 * W, X, *region_params(pole_region_sf_ct))
pole_region_sf_ct.recover(K=state_feedback_gain(W, X))
pole_region_sf_ct.certified_by(pole_region_cl_ct, design=("K",), criterion="feasible")
scale_state(pole_region_sf_ct, ("A", "B2"), ("A",), recovered_cols=("K",))
pole_region_sf_ct.example("random-4", subset(random_plant(41, 4, 1, 2, 3, 1, "continuous"), ("A", "B2")),
                          params={"alpha": 0.5, "q": 0.0, "r": 10.0, "theta": 0.7853981633974483},
                          provenance="illustration",
                          provenance_note="a random plant, numpy seed 41; region Re s < -0.5, |s| < 10, "
                                          "damping above cos(π/4)")

THEOREMS = [pole_region_sf_ct, pole_region_cl_ct]
