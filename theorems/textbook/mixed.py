"""Mixed H2/H∞ and energy-to-peak (generalized H2) state feedback, continuous time.

Plant x' = A x + B1 w + B2 u with two performance outputs, z∞ = C1 x + D11 w + D12 u (H∞
channel) and z₂ = Cz x + Dz u (H2 or peak channel, no feedthrough from w); u = K x.  With the
common Lyapunov matrix Y = P⁻¹ and W = K Y (Khargonekar & Rotea, "Mixed H2/H∞ control: a convex
optimization approach", IEEE TAC 36(7):824–837, 1991; Scherer, Gahinet, Chilali, IEEE TAC
42(7):896–911, 1997, §IV):

* **mixed H2/H∞** (``textbook.h2hinf_sf_ct``): minimise tr Z subject to the H∞ bound γ₀ (a
  parameter) on z∞ and the H2 Gramian LMIs on z₂:
  [[He(AY + B2W), B1, (C1Y + D12W)ᵀ], [⋆, −I, D11ᵀ], [⋆, ⋆, −γ₀²I]] ≺ 0 (the dual bounded real
  lemma, in which Y has the scale of the Gramian bound of the H2 LMIs; the form with γ on both
  diagonal blocks has Y scaled by γ and may not share Y with the H2 LMIs),
  [[He(AY + B2W), B1], [B1ᵀ, −I]] ≺ 0, [[Z, CzY + DzW], [⋆, Y]] ≻ 0; then ‖T∞‖∞ < γ₀ and
  ‖T₂‖₂ < √tr Z (both bounds for the one gain K = WY⁻¹);
* **energy-to-peak** (``textbook.e2p_sf_ct``, Wilson, "Convolution and Hankel operator norms
  for linear systems", IEEE TAC 34(1), 1989; Rotea, "The generalized H2 control problem",
  Automatica 29(2), 1993): sup ‖z₂(t)‖ / ‖w‖_{L2} = √λmax(C Wc Cᵀ) with Wc the controllability
  Gramian, so minimise g over [[He(AY + B2W), B1], [B1ᵀ, −I]] ≺ 0, [[gI, CzY + DzW], [⋆, Y]] ≻ 0,
  and the peak gain is below √g.

Evidence: python-control's H∞ norm and the Gramian of the closed loop (the checks below).
"""
import numpy as np
from sympy import Trace, sqrt

from lmidsl import CheckResult, He, I, Source, Theorem, state_feedback_gain

from .brl import scale_state
from .plants import random_plant

KR = ("Khargonekar, Rotea, Mixed H2/H∞ control: a convex optimization approach, IEEE TAC "
      "36(7):824-837, 1991")
ROTEA = "Rotea, The generalized H2 control problem, Automatica 29(2):373-385, 1993"
DATA = ("A", "B1", "B2", "C1", "D11", "D12", "Cz", "Dz")


def _plant(thm, hinf: bool):
    n, m1, m2, q = thm.dim("n m1 m2 q")
    d = dict(A=thm.data("A", n, n), B1=thm.data("B1", n, m1, latex="B_1"),
             B2=thm.data("B2", n, m2, latex="B_2"),
             Cz=thm.data("Cz", q, n, latex="C_z", description="H2 / peak output"),
             Dz=thm.data("Dz", q, m2, latex="D_z"))
    if hinf:
        p1 = thm.dim("p1")
        d.update(C1=thm.data("C1", p1, n, latex="C_1", description="H∞ output"),
                 D11=thm.data("D11", p1, m1, latex="D_{11}"), D12=thm.data("D12", p1, m2, latex="D_{12}"))
    return n, q, d


def _closed(solution, name):
    d = {k: np.asarray(v, dtype=float) for k, v in solution.instance.data.items()}
    K = np.asarray(solution.design["K"], dtype=float)
    return d, d["A"] + d["B2"] @ K, K


def _gramian_bound(solution, which: str):
    """√tr(Cz Wc Czᵀ) (H2) or √λmax(Cz Wc Czᵀ) (peak) of the closed loop, by scipy's Lyapunov solver."""
    from scipy.linalg import solve_continuous_lyapunov
    d, Acl, K = _closed(solution, which)
    if np.linalg.eigvals(Acl).real.max() >= 0:
        return np.inf
    Wc = solve_continuous_lyapunov(Acl, -d["B1"] @ d["B1"].T)
    Ccl = d["Cz"] + d["Dz"] @ K
    M = Ccl @ Wc @ Ccl.T
    return float(np.sqrt(np.trace(M) if which == "h2" else np.linalg.eigvalsh((M + M.T) / 2).max()))


def h2_bound_check(solution) -> CheckResult:
    value = _gramian_bound(solution, "h2")
    bound = solution.point_gamma
    return CheckResult("H2 norm by the Gramian", bound is not None and value <= bound * (1 + 1e-6),
                       f"‖T₂‖₂ = {value:.6g} (bound √tr Z = {bound})", {"h2": value})


def hinf_bound_check(solution) -> CheckResult:
    import control
    d, Acl, K = _closed(solution, "hinf")
    g0 = solution.instance.params["gamma0"]
    sys = control.ss(Acl, d["B1"], d["C1"] + d["D12"] @ K, d["D11"])
    value = float(control.norm(sys, "inf")) if np.linalg.eigvals(Acl).real.max() < 0 else np.inf
    return CheckResult("H∞ norm by python-control", value < g0, f"‖T∞‖∞ = {value:.6g} (bound γ₀ = {g0:g})",
                       {"hinf": value})


def peak_bound_check(solution) -> CheckResult:
    value = _gramian_bound(solution, "peak")
    bound = solution.point_gamma
    return CheckResult("energy-to-peak gain by the Gramian", bound is not None and value <= bound * (1 + 1e-6),
                       f"√λmax(C Wc Cᵀ) = {value:.6g} (bound √g = {bound})", {"peak": value})


for check in (h2_bound_check, hinf_bound_check, peak_bound_check):
    check.needs_synthesis = True


def _example(seed: int, hinf: bool) -> dict:
    p = random_plant(seed, 3, 2, 1, 2, 1, "continuous")
    rng = np.random.default_rng(seed + 1000)
    out = {k: p[k] for k in ("A", "B1", "B2")}
    out["Cz"] = rng.standard_normal((2, 3)).tolist()
    out["Dz"] = [[0.0], [1.0]]
    if hinf:
        out.update(C1=p["C1"], D11=p["D11"], D12=p["D12"])
    return out


h2hinf_sf_ct = Theorem("textbook.h2hinf_sf_ct", "Mixed H2/H∞ state feedback (continuous time)",
                       Source("Khargonekar & Rotea 1991", "mixed H2/H∞ state feedback with a common "
                              "Lyapunov matrix, W = K Y", KR),
                       time="continuous", designs="gain",
                       description="min tr Z over Y ≻ 0, W with ‖T∞‖∞ < γ₀ on z∞ and the H2 Gramian LMIs on z₂")
n, q, d = _plant(h2hinf_sf_ct, hinf=True)
Y = h2hinf_sf_ct.var("Y", n, kind="symmetric", description="Y = P⁻¹ (common)")
W = h2hinf_sf_ct.var("W", d["B2"].shape[1], n, description="W = K Y")
Z = h2hinf_sf_ct.var("Z", q, kind="symmetric")
g0 = h2hinf_sf_ct.param("gamma0", latex=r"\gamma_0", description="the H∞ bound on z∞", domain=(0, 1e6),
                        open_domain=True)
AY = d["A"] * Y + d["B2"] * W
h2hinf_sf_ct.lmi("(Hinf)", [
    [He(AY)],
    [d["B1"].T, -I],
    [d["C1"] * Y + d["D12"] * W, d["D11"], -g0 ** 2 * I],
])
h2hinf_sf_ct.lmi("(H2)", [[He(AY)], [d["B1"].T, -I]])
h2hinf_sf_ct.lmi("(Z)", [[Z], [(d["Cz"] * Y + d["Dz"] * W).T, Y]], sense=">")
h2hinf_sf_ct.positive(Y)
h2hinf_sf_ct.minimize(Trace(Z), performance=("h2", sqrt(Trace(Z))))
h2hinf_sf_ct.recover(K=state_feedback_gain(W, Y))
h2hinf_sf_ct.verify_with(h2_bound_check, hinf_bound_check)
h2hinf_sf_ct.well_conditioned(Y)
h2hinf_sf_ct.example("random-3", _example(11, True), params={"gamma0": 8.0}, provenance="illustration",
                     provenance_note="a random plant, numpy seeds 11 and 1011 (theorems/textbook/mixed.py)")

e2p_sf_ct = Theorem("textbook.e2p_sf_ct", "Energy-to-peak (generalized H2) state feedback (continuous time)",
                    Source("Rotea 1993", "generalized H2 state feedback, W = K Y", ROTEA),
                    time="continuous", designs="gain",
                    description="min g over Y ≻ 0, W: the L2 → L∞ gain of the closed loop is below √g")
n, q, d = _plant(e2p_sf_ct, hinf=False)
Y = e2p_sf_ct.var("Y", n, kind="symmetric", description="Y = P⁻¹")
W = e2p_sf_ct.var("W", d["B2"].shape[1], n, description="W = K Y")
g = e2p_sf_ct.scalar("g", latex=r"\gamma^2", description="squared energy-to-peak level")
AY = d["A"] * Y + d["B2"] * W
e2p_sf_ct.lmi("(Gram)", [[He(AY)], [d["B1"].T, -I]])
e2p_sf_ct.lmi("(Peak)", [[g * I], [(d["Cz"] * Y + d["Dz"] * W).T, Y]], sense=">")
e2p_sf_ct.positive(Y)
e2p_sf_ct.minimize(g, performance=("peak", sqrt(g)))
e2p_sf_ct.recover(K=state_feedback_gain(W, Y))
e2p_sf_ct.verify_with(peak_bound_check)
e2p_sf_ct.well_conditioned(Y)
e2p_sf_ct.example("random-3", _example(11, False), provenance="illustration",
                  provenance_note="a random plant, numpy seeds 11 and 1011 (theorems/textbook/mixed.py)")

THEOREMS = [h2hinf_sf_ct, e2p_sf_ct]
