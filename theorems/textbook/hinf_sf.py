"""H∞ state feedback, continuous and discrete time: K = W Y⁻¹.

References: Gahinet & Apkarian, "A linear matrix inequality approach to H∞ control", Int. J.
Robust Nonlinear Control 4, 1994 (state feedback as the special case C2 = I, D21 = 0);
Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and Control
Theory*, SIAM 1994, ch. 7 (state-feedback synthesis, the change of variables W = K Y);
Scherer & Weiland, *Linear Matrix Inequalities in Control*, lecture notes (state feedback
synthesis by the bounded real lemma).

Plant x' = A x + B1 w + B2 u, z = C1 x + D11 w + D12 u with u = K x: the closed loop is
(A + B2K, B1, C1 + D12K, D11).  The bounded real lemma (:mod:`.brl`) in P, congruence-
transformed by diag(Y, I, I) (continuous) or diag(Y, I, Y, I) (discrete) with Y = P⁻¹ and
W = K Y, gives LMIs linear in (Y, W, γ) — in the form with γ on both diagonal blocks, as
Gahinet & Apkarian write it:

* continuous:  [[He(AY + B2W), B1, (C1Y + D12W)ᵀ], [B1ᵀ, −γI, D11ᵀ], [C1Y + D12W, D11, −γI]] ≺ 0;
* discrete:    [[−Y, 0, *, *], [0, −γI, *, *], [AY + B2W, B1, −Y, 0], [C1Y + D12W, D11, 0, −γI]] ≺ 0;

and Y ≻ 0.  (The form with γ² and −I, equivalent on paper, made Clarabel fail with a solver
error on one continuous and one discrete test plant of the ten; see docs/gallery.md.)  Recovery K = W Y⁻¹ (:func:`lmidsl.state_feedback_gain`).  The analysis
counterpart ``textbook.hinf_sf_ct_cl`` / ``_dt_cl`` is the bounded real lemma of the closed
loop with K given.
"""
from lmidsl import He, I, Source, Theorem, state_feedback_closed_loop, state_feedback_gain

from .brl import bounded_real, scale_state
from .plants import random_plant, subset

GA = ("Gahinet, Apkarian, A linear matrix inequality approach to H∞ control, "
      "Int. J. Robust Nonlinear Control 4:421-448, 1994")
SF_DATA = ("A", "B1", "B2", "C1", "D11", "D12")


def sf_plant(thm: Theorem):
    """A, B1, B2, C1, D11, D12 of the gallery's generalized plant (no measurement: y = x)."""
    n, m1, m2, p1 = thm.dim("n m1 m2 p1")
    d = dict(A=thm.data("A", n, n, description="state matrix"),
             B1=thm.data("B1", n, m1, latex="B_1", description="disturbance input w"),
             B2=thm.data("B2", n, m2, latex="B_2", description="control input u"),
             C1=thm.data("C1", p1, n, latex="C_1", description="performance output z"),
             D11=thm.data("D11", p1, m1, latex="D_{11}", description="w -> z feedthrough"),
             D12=thm.data("D12", p1, m2, latex="D_{12}", description="u -> z feedthrough"))
    return (n, m1, m2, p1), d


def _analysis(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H∞ norm of the state-feedback closed loop ({time} time)",
                  Source("Boyd et al. 1994", "Sec. 2.7.3 applied to the closed loop (A + B2K, B1, C1 + D12K, D11)",
                         "Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in "
                         "System and Control Theory, SIAM 1994"),
                  time=time, description="the bounded real lemma of the closed loop with the gain K given")
    (n, m1, m2, p1), d = sf_plant(thm)
    K = thm.data("K", m2, n, description="state-feedback gain u = K x")
    cl = state_feedback_closed_loop(d["A"], d["B1"], d["B2"], d["C1"], d["D11"], d["D12"], K)
    Acl = thm.define("A_cl", cl["A"], latex=r"A_{cl}")
    Ccl = thm.define("C_cl", cl["C"], latex=r"C_{cl}")
    bounded_real(thm, "(BRL-cl)", Acl, cl["B"], Ccl, cl["D"], n)
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1", "K"))
    return thm


def _synthesis(name: str, time: str, analysis: Theorem) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H∞ state feedback ({time} time)",
                  Source("Gahinet & Apkarian 1994", "state-feedback case of the bounded real lemma, "
                         "W = K Y", GA),
                  time=time, designs="gain",
                  description="min γ² over Y ≻ 0, W such that the closed loop with K = W Y⁻¹ has "
                              "H∞ norm below γ.")
    (n, m1, m2, p1), d = sf_plant(thm)
    A, B1, B2, C1, D11, D12 = (d[k] for k in SF_DATA)
    Y = thm.var("Y", n, kind="symmetric", description="Y = P⁻¹")
    W = thm.var("W", m2, n, description="W = K Y")
    g = thm.scalar("gamma", latex=r"\gamma", description="H∞ level")
    if time == "continuous":
        thm.lmi("(SF)", [
            [He(A * Y + B2 * W)],
            [B1.T, -g * I],
            [C1 * Y + D12 * W, D11, -g * I],
        ])
    else:
        thm.lmi("(SF)", [
            [-Y],
            [0, -g * I],
            [A * Y + B2 * W, B1, -Y],
            [C1 * Y + D12 * W, D11, 0, -g * I],
        ])
    thm.positive(Y)
    thm.minimize(g, performance=("gamma", g))
    thm.recover(K=state_feedback_gain(W, Y))
    thm.certified_by(analysis, design=("K",))
    thm.state_feedback_form(Y, W, g, (A, B1, B2, C1, D11, D12))
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1"), recovered_cols=("K",))
    thm.well_conditioned(Y)
    thm.example("random-3", subset(random_plant(11, 3, 2, 1, 2, 1, time), SF_DATA),
                provenance="illustration",
                provenance_note="a random plant, numpy seed 11 (theorems/textbook/plants.py)")
    return thm


hinf_sf_ct_cl = _analysis("hinf_sf_ct_cl", "continuous")
hinf_sf_ct = _synthesis("hinf_sf_ct", "continuous", hinf_sf_ct_cl)
hinf_sf_dt_cl = _analysis("hinf_sf_dt_cl", "discrete")
hinf_sf_dt = _synthesis("hinf_sf_dt", "discrete", hinf_sf_dt_cl)

THEOREMS = [hinf_sf_ct, hinf_sf_ct_cl, hinf_sf_dt, hinf_sf_dt_cl]
