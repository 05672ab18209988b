"""Full-order H∞ dynamic output feedback by the Scherer–Gahinet–Chilali change of variables.

References: Scherer, Gahinet, Chilali, "Multiobjective output-feedback control via LMI
optimization", IEEE TAC 42(7):896-911, 1997 (the linearising change of variables, H∞ LMI);
Gahinet & Apkarian, "A linear matrix inequality approach to H∞ control", Int. J. Robust
Nonlinear Control 4:421-448, 1994 (the solvability conditions, both time domains);
Masubuchi, Ohara, Suda, Int. J. Robust Nonlinear Control 8, 1998 (the discrete-time form).

Plant x' = A x + B1 w + B2 u, z = C1 x + D11 w + D12 u, y = C2 x + D21 w + D22 u; controller
xK' = AK xK + BK y, u = CK xK + DK y of order n.  With the blocks of
:func:`lmidsl.output_feedback_blocks` (the closed loop after the congruence by Π₁; A11 = A X + B2 Ĉ,
A12 = A + B2 D̂ C2, A21 = Â, A22 = Y A + B̂ C2, ...), the bounded real lemma becomes, linear in
(X, Y, Â, B̂, Ĉ, D̂, γ) — SGC's own form, with γ (not γ²) on both diagonal blocks,

* continuous:  [[He(A11), *, *, *], [A21 + A12ᵀ, He(A22), *, *], [B1ᵀ, B2ᵀ, −γI, *],
  [C1', C2', D, −γI]] ≺ 0 and [[X, I], [I, Y]] ≻ 0;
* discrete:    [[−X, *, ...], [−I, −Y], [0, 0, −γI], [A11, A12, B1, −X], [A21, A22, B2, −I, −Y],
  [C1', C2', D, 0, 0, −γI]] ≺ 0  (which contains [[X, I], [I, Y]] ≻ 0).

(The form with γ² and −I, equivalent on paper, made Clarabel fail with a solver error on 6 of
the 20 continuous test plants, 2 of which the feasp diagnosis then declared "infeasible"; see
docs/gallery.md.)

These LMIs are for D22 = 0; a plant with D22 ≠ 0 is handled exactly by loop shifting in the
recovery (:func:`lmidsl.output_feedback`, M Nᵀ = I − X Y by the balanced split).  The analysis
counterpart ``textbook.hinf_of_ct_cl`` / ``_dt_cl`` is the bounded real lemma of the closed loop
with the controller given (:func:`lmidsl.closed_loop_matrices`, general D22).
"""
from lmidsl import (He, I, Source, Theorem, closed_loop_matrices, output_feedback,
                    output_feedback_blocks)

from .brl import bounded_real, scale_state
from .plants import random_plant

SGC = ("Scherer, Gahinet, Chilali, Multiobjective output-feedback control via LMI optimization, "
       "IEEE TAC 42(7):896-911, 1997")
PLANT = ("A", "B1", "B2", "C1", "C2", "D11", "D12", "D21", "D22")
CONTROLLER = ("AK", "BK", "CK", "DK")


def generalized_plant(thm: Theorem):
    """The gallery's generalized plant A, B1, B2, C1, C2, D11, D12, D21, D22."""
    n, m1, m2, p1, p2 = thm.dim("n m1 m2 p1 p2")
    shapes = dict(A=(n, n), B1=(n, m1), B2=(n, m2), C1=(p1, n), C2=(p2, n), D11=(p1, m1),
                  D12=(p1, m2), D21=(p2, m1), D22=(p2, m2))
    what = dict(A="state matrix", B1="disturbance input w", B2="control input u",
                C1="performance output z", C2="measured output y", D11="w -> z", D12="u -> z",
                D21="w -> y", D22="u -> y")
    latex = dict(A="A", B1="B_1", B2="B_2", C1="C_1", C2="C_2", D11="D_{11}", D12="D_{12}",
                 D21="D_{21}", D22="D_{22}")
    d = {k: thm.data(k, *shapes[k], latex=latex[k], description=what[k]) for k in PLANT}
    return (n, m1, m2, p1, p2), d


def _analysis(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H∞ norm of the output-feedback closed loop ({time} time)",
                  Source("Boyd et al. 1994", "Sec. 2.7.3 applied to the closed loop of the plant and (AK, BK, CK, DK)",
                         "Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in "
                         "System and Control Theory, SIAM 1994"),
                  time=time, description="the bounded real lemma of the closed loop with the controller given")
    (n, m1, m2, p1, p2), d = generalized_plant(thm)
    nk = thm.dim("nk")
    K = dict(AK=thm.data("AK", nk, nk, latex="A_K", description="controller state matrix"),
             BK=thm.data("BK", nk, p2, latex="B_K", description="controller input matrix"),
             CK=thm.data("CK", m2, nk, latex="C_K", description="controller output matrix"),
             DK=thm.data("DK", m2, p2, latex="D_K", description="controller feedthrough"))
    cl = closed_loop_matrices(*(d[k] for k in PLANT), *(K[k] for k in CONTROLLER))
    names = {"A": r"\mathcal{A}", "B": r"\mathcal{B}", "C": r"\mathcal{C}", "D": r"\mathcal{D}"}
    cl = {k: thm.define(f"{k}_cl", v, latex=names[k]) for k, v in cl.items()}
    bounded_real(thm, "(BRL-cl)", cl["A"], cl["B"], cl["C"], cl["D"], n + nk)
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1", "C2"))
    return thm


def full_order_variables(thm: Theorem, n, inputs, outputs):
    """X, Y (n × n symmetric), Â (n × n), B̂ (n × inputs), Ĉ (outputs × n), D̂ (outputs × inputs)
    and the H∞ level γ: the linearising variables of a full-order controller or filter, whose
    input is the measurement (``inputs`` = p2) and whose output is u or the estimate."""
    X = thm.var("X", n, kind="symmetric")
    Y = thm.var("Y", n, kind="symmetric")
    Ah = thm.var("Ah", n, n, latex=r"\hat{A}")
    Bh = thm.var("Bh", n, inputs, latex=r"\hat{B}")
    Ch = thm.var("Ch", outputs, n, latex=r"\hat{C}")
    Dh = thm.var("Dh", outputs, inputs, latex=r"\hat{D}")
    g = thm.scalar("gamma", latex=r"\gamma", description="H∞ level")
    return X, Y, Ah, Bh, Ch, Dh, g


def full_order_hinf_lmis(thm: Theorem, label: str, b: dict, g, X, Y):
    """The full-order H∞ LMI in the linearising variables (Scherer, Gahinet, Chilali 1997; the
    filter case of Geromel et al. is the same with its own blocks ``b``): continuous time
    [[He(A11)], [A21 + A12ᵀ, He(A22)], [B1ᵀ, B2ᵀ, −γI], [C1, C2, D, −γI]] ≺ 0 with [[X, I], [I, Y]] ≻ 0
    ("(XY)"); discrete time the 6×6 block form with −X, −Y on the diagonal."""
    if thm.time == "continuous":
        thm.lmi(label, [
            [He(b["A11"])],
            [b["A21"] + b["A12"].T, He(b["A22"])],
            [b["B1"].T, b["B2"].T, -g * I],
            [b["C1"], b["C2"], b["D"], -g * I],
        ])
        thm.lmi("(XY)", [
            [X],
            [I, Y],
        ], sense=">")
    else:
        thm.lmi(label, [
            [-X],
            [-I, -Y],
            [0, 0, -g * I],
            [b["A11"], b["A12"], b["B1"], -X],
            [b["A21"], b["A22"], b["B2"], -I, -Y],
            [b["C1"], b["C2"], b["D"], 0, 0, -g * I],
        ])


def _synthesis(name: str, time: str, analysis: Theorem) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"Full-order H∞ output feedback ({time} time)",
                  Source("Scherer, Gahinet, Chilali 1997", "H∞ LMI with the linearising change of variables",
                         SGC),
                  time=time, designs="controller",
                  description="min γ over X, Y, Â, B̂, Ĉ, D̂; controller by the SGC recovery "
                              "(M Nᵀ = I − X Y), loop-shifted for D22.")
    (n, m1, m2, p1, p2), d = generalized_plant(thm)
    X, Y, Ah, Bh, Ch, Dh, g = full_order_variables(thm, n, p2, m2)
    b = output_feedback_blocks(X, Y, Ah, Bh, Ch, Dh, d["A"], d["B1"], d["B2"], d["C1"], d["C2"],
                               d["D11"], d["D12"], d["D21"])
    full_order_hinf_lmis(thm, "(OF)", b, g, X, Y)
    thm.minimize(g, performance=("gamma", g))
    thm.output_feedback_form(X, Y, Ah, Bh, Ch, Dh, g, tuple(d[k] for k in PLANT[:-1]))
    thm.recover(**output_feedback(thm, X, Y, Ah, Bh, Ch, Dh, d["A"], d["B2"], d["C2"], d["D22"]))
    thm.certified_by(analysis, design=CONTROLLER)
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1", "C2"))
    thm.well_conditioned(X, Y)
    return thm


hinf_of_ct_cl = _analysis("hinf_of_ct_cl", "continuous")
hinf_of_ct = _synthesis("hinf_of_ct", "continuous", hinf_of_ct_cl)
hinf_of_dt_cl = _analysis("hinf_of_dt_cl", "discrete")
hinf_of_dt = _synthesis("hinf_of_dt", "discrete", hinf_of_dt_cl)

hinf_of_ct.example("random-3", random_plant(21, 3, 2, 1, 2, 1, "continuous"),
                   provenance="illustration",
                   provenance_note="a random plant, numpy seed 21 (theorems/textbook/plants.py)")
hinf_of_dt.example("random-3", random_plant(21, 3, 2, 1, 2, 1, "discrete"),
                   provenance="illustration",
                   provenance_note="a random plant, numpy seed 21 (theorems/textbook/plants.py)")

THEOREMS = [hinf_of_ct, hinf_of_ct_cl, hinf_of_dt, hinf_of_dt_cl]
