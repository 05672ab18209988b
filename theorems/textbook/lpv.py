"""Rate-bounded LPV systems: stability and gain-scheduled state feedback with a parameter-
dependent Lyapunov matrix and a bound on the rate of the parameter.

ẋ = A(α(t))x (+ B(α(t))u), α(t) ∈ Λ_N (A(α) = Σ αᵢAᵢ), |α̇ᵢ(t)| ≤ b.  For one scheduling
parameter θ ∈ [θ₁, θ₂] with Aᵢ = A(θᵢ): α₂ = (θ − θ₁)/(θ₂ − θ₁) and |θ̇| ≤ ν is b = ν/(θ₂ − θ₁).
With V = xᵀP(α)x, V̇ = xᵀ(He(P(α)A(α)) + Ṗ(α, α̇))x, Ṗ = Σᵢ ∂P/∂αᵢ α̇ᵢ, so

* ``textbook.lpv_stability_ct`` (Geromel & Colaneri 2006, a parameter-dependent Lyapunov matrix with bounded rates,
  here HPPD of degree g):
  P(α) ≻ 0 and He(P(α)A(α)) + Ṗ(α, α̇) ≺ 0 for all α ∈ Λ_N and α̇ ∈ b·H_N
  ⇒ x(t) → 0 for every parameter trajectory within the rate bound;
* ``textbook.lpv_sf_ct`` (gain-scheduled state feedback, Y(α) = P(α)⁻¹, W(α) = K(α)Y(α); Wu,
  Yang, Packard & Becker 1996 with Y(α) HPPD): Y(α) ≻ 0 and
  He(A(α)Y(α) + B(α)W(α)) − Ẏ(α, α̇) ≺ 0 ∀α, α̇ ⇒ with K(α) = W(α)Y(α)⁻¹ the closed loop is
  stable for every such trajectory (d/dt Y⁻¹ = −Y⁻¹ẎY⁻¹, then a congruence by Y).  The gain
  needs α(t) measured: it is *scheduled*, recovered at each α.

Each LMI is imposed for every α and every rate vertex: the member expands over Λ_N × Λ_M
(M = the vertices of H_N) with the data over α alone.  The evidence: the stated LMIs on a dense
(α, α̇) grid, and simulations under the fastest admitted parameter and a sinusoid
(:mod:`lmidsl.certify.rate_bounded`).
"""
from lmidsl import He, RobustTheorem, Source, rate_grid_check, rate_simulation_check

GC2006 = ("J. C. Geromel, P. Colaneri, Robust stability of time varying polytopic systems, "
          "Systems & Control Letters 55(1):81-85, 2006")
WU1996 = ("F. Wu, X. H. Yang, A. Packard, G. Becker, Induced L2-norm control for LPV systems with "
          "bounded parameter variation rates, Int. J. Robust and Nonlinear Control 6(9-10):983-998, 1996")

# both vertices stable (eigenvalues −0.1 ± j√2 and the same for every frozen α), but a fast
# parameter destabilises: the classic switching pair
OSCILLATOR = {"vertices": [{"A": [[-0.1, 1.0], [-2.0, -0.1]]}, {"A": [[-0.1, 2.0], [-1.0, -0.1]]}]}
# an unstable plant whose unstable mode moves with θ; one input
PLANT = {"vertices": [{"A": [[0.0, 1.0], [1.0, -0.5]], "B": [[0.0], [1.0]]},
                      {"A": [[0.5, 2.0], [-1.0, 0.2]], "B": [[0.2], [1.0]]}]}

lpv_stability_ct = RobustTheorem(
    "textbook.lpv_stability_ct", "Stability of a rate-bounded LPV system with an HPPD Lyapunov matrix",
    Source("Geromel & Colaneri 2006", "parameter-dependent Lyapunov matrix, bounded rates; P(α) HPPD", GC2006),
    time="continuous", degree=1,
    description="find P(α) ≻ 0 with He(P(α)A(α)) + Ṗ(α, α̇) ≺ 0 for all α in the simplex and |α̇ᵢ| ≤ b")
_n = lpv_stability_ct.dim("n")
_alpha = lpv_stability_ct.simplex("alpha")
_A = lpv_stability_ct.data("A", _n, _n, over=_alpha, description="vertex state matrices A_i")
_rate = lpv_stability_ct.rate(_alpha, bound="b", default=0.1)
_P = lpv_stability_ct.var("P", _n, kind="symmetric", over=_alpha, description="HPPD Lyapunov matrix")
_dP = lpv_stability_ct.derivative(_P, _rate)
lpv_stability_ct.lmi("(LPV)", [[He(_P * _A) + _dP]])
lpv_stability_ct.positive(_P)
lpv_stability_ct.feasibility()
lpv_stability_ct.verify_with(rate_grid_check(), rate_simulation_check(A="A", lyapunov="P"))
lpv_stability_ct.example("switching-pair", OSCILLATOR, params={"b": 0.1}, provenance="illustration",
                         provenance_note="two oscillators, stable for every frozen α, destabilised by "
                                         "switching; b = 0.1")

lpv_sf_ct = RobustTheorem(
    "textbook.lpv_sf_ct", "Gain-scheduled state feedback of a rate-bounded LPV system",
    Source("Wu et al. 1996", "parameter-dependent Lyapunov, bounded rates; Y(α) HPPD, K(α) = W(α)Y(α)⁻¹",
           WU1996),
    time="continuous", degree=1,
    description="find Y(α) ≻ 0, W(α) with He(A(α)Y(α) + B(α)W(α)) − Ẏ(α, α̇) ≺ 0 for all α and "
                "|α̇ᵢ| ≤ b; K(α) = W(α)Y(α)⁻¹")
_n = lpv_sf_ct.dim("n")
_m = lpv_sf_ct.dim("m")
_alpha = lpv_sf_ct.simplex("alpha")
_A = lpv_sf_ct.data("A", _n, _n, over=_alpha, description="vertex state matrices")
_B = lpv_sf_ct.data("B", _n, _m, over=_alpha, description="vertex input matrices")
_rate = lpv_sf_ct.rate(_alpha, bound="b", default=0.5)
_Y = lpv_sf_ct.var("Y", _n, kind="symmetric", over=_alpha, description="Y(α) = P(α)⁻¹")
_W = lpv_sf_ct.var("W", _m, _n, over=_alpha, description="W(α) = K(α)Y(α)")
_dY = lpv_sf_ct.derivative(_Y, _rate)
lpv_sf_ct.lmi("(LPV-SF)", [[He(_A * _Y + _B * _W) - _dY]])
lpv_sf_ct.positive(_Y)
lpv_sf_ct.feasibility()
lpv_sf_ct.recover_scheduled(K=_W * _Y.I)
lpv_sf_ct.verify_with(rate_grid_check(), rate_simulation_check(A="A", B="B", K="K", lyapunov="Y", inverse=True))
lpv_sf_ct.example("unstable-plant", PLANT, params={"b": 0.5}, provenance="illustration",
                  provenance_note="an unstable plant at both vertices; b = 0.5")

THEOREMS = [lpv_stability_ct, lpv_sf_ct]
