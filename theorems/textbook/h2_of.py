"""Full-order H2 output feedback, continuous time (Scherer, Gahinet, Chilali 1997, §IV.B).

Plant x' = A x + B1 w + B2 u, z = C1 x + D12 u, y = C2 x + D21 w + D22 u (D11 = 0: the H2 norm
of the closed loop is finite only if its feedthrough vanishes, so D̂ = 0).  In the linearising
variables of :func:`lmidsl.output_feedback_blocks` (X, Y, Â, B̂, Ĉ):

    [[He(AX + B2Ĉ), ⋆, ⋆], [Â + Aᵀ, He(YA + B̂C2), ⋆], [B1ᵀ, (YB1 + B̂D21)ᵀ, −I]] ≺ 0,
    [[X, ⋆, ⋆], [I, Y, ⋆], [C1X + D12Ĉ, C1, Z]] ≻ 0,     min tr Z,

and ‖T_zw‖₂ < √tr Z for the controller of the SGC recovery (M Nᵀ = I − XY, loop-shifted for
D22).  The analysis counterpart ``textbook.h2_of_ct_cl`` is the Gramian LMI of the closed loop
with the controller given; python-control's ``h2syn`` (SLICOT SB10HD) is the independent
check of the optimum.
"""
from sympy import Trace, ZeroMatrix, sqrt

from lmidsl import He, I, Source, Theorem, closed_loop_matrices, output_feedback, output_feedback_blocks

from .brl import scale_state
from .h2 import h2_gramian
from .hinf_of import CONTROLLER, SGC
from .plants import random_plant

H2_PLANT = ("A", "B1", "B2", "C1", "C2", "D12", "D21", "D22")


def h2_plant(thm: Theorem):
    n, m1, m2, p1, p2 = thm.dim("n m1 m2 p1 p2")
    shapes = dict(A=(n, n), B1=(n, m1), B2=(n, m2), C1=(p1, n), C2=(p2, n), D12=(p1, m2),
                  D21=(p2, m1), D22=(p2, m2))
    latex = dict(A="A", B1="B_1", B2="B_2", C1="C_1", C2="C_2", D12="D_{12}", D21="D_{21}", D22="D_{22}")
    return (n, m1, m2, p1, p2), {k: thm.data(k, *shapes[k], latex=latex[k]) for k in H2_PLANT}


def _analysis() -> Theorem:
    thm = Theorem("textbook.h2_of_ct_cl", "H2 norm of the output-feedback closed loop (continuous time)",
                  Source("Scherer & Weiland", "H2 performance of the closed loop with the controller given",
                         "Scherer, Weiland, Linear Matrix Inequalities in Control, lecture notes"),
                  time="continuous", description="the Gramian LMIs of the closed loop (DK = 0)")
    (n, m1, m2, p1, p2), d = h2_plant(thm)
    nk = thm.dim("nk")
    K = dict(AK=thm.data("AK", nk, nk, latex="A_K"), BK=thm.data("BK", nk, p2, latex="B_K"),
             CK=thm.data("CK", m2, nk, latex="C_K"))
    DK = ZeroMatrix(m2, p2)
    D11 = ZeroMatrix(p1, m1)
    cl = closed_loop_matrices(d["A"], d["B1"], d["B2"], d["C1"], d["C2"], D11, d["D12"], d["D21"],
                              d["D22"], K["AK"], K["BK"], K["CK"], DK)
    names = {"A": r"\mathcal{A}", "B": r"\mathcal{B}", "C": r"\mathcal{C}"}
    Acl, Bcl, Ccl = (thm.define(f"{k}_cl", cl[k], latex=names[k]) for k in ("A", "B", "C"))
    P = thm.var("P", n + nk, kind="symmetric")
    h2_gramian(thm, Acl, Bcl, Ccl, None, n + nk, p1, P=P)
    return thm


def _synthesis(analysis: Theorem) -> Theorem:
    thm = Theorem("textbook.h2_of_ct", "Full-order H2 output feedback (continuous time)",
                  Source("Scherer, Gahinet, Chilali 1997", "H2 LMIs with the linearising change of variables",
                         SGC),
                  time="continuous", designs="controller",
                  description="min tr Z over X, Y, Â, B̂, Ĉ (D̂ = 0); controller by the SGC recovery")
    (n, m1, m2, p1, p2), d = h2_plant(thm)
    X = thm.var("X", n, kind="symmetric")
    Y = thm.var("Y", n, kind="symmetric")
    Ah = thm.var("Ah", n, n, latex=r"\hat{A}")
    Bh = thm.var("Bh", n, p2, latex=r"\hat{B}")
    Ch = thm.var("Ch", m2, n, latex=r"\hat{C}")
    Z = thm.var("Z", p1, kind="symmetric")
    Dh = ZeroMatrix(m2, p2)
    b = output_feedback_blocks(X, Y, Ah, Bh, Ch, Dh, d["A"], d["B1"], d["B2"], d["C1"], d["C2"],
                               ZeroMatrix(p1, m1), d["D12"], d["D21"])
    thm.lmi("(H2-OF)", [
        [He(b["A11"])],
        [b["A21"] + b["A12"].T, He(b["A22"])],
        [b["B1"].T, b["B2"].T, -I],
    ])
    thm.lmi("(H2-Z)", [
        [X],
        [I, Y],
        [b["C1"], b["C2"], Z],
    ], sense=">")
    thm.minimize(Trace(Z), performance=("h2", sqrt(Trace(Z))))
    thm.recover(**output_feedback(thm, X, Y, Ah, Bh, Ch, Dh, d["A"], d["B2"], d["C2"], d["D22"]))
    thm.certified_by(analysis, design=CONTROLLER[:3])
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1", "C2"))
    thm.well_conditioned(X, Y)
    plant = random_plant(21, 3, 2, 1, 2, 1, "continuous", d11=False)
    thm.example("random-3", {k: plant[k] for k in H2_PLANT}, provenance="illustration",
                provenance_note="a random plant, numpy seed 21, D11 = 0 (theorems/textbook/plants.py)")
    return thm


h2_of_ct_cl = _analysis()
h2_of_ct = _synthesis(h2_of_ct_cl)

THEOREMS = [h2_of_ct, h2_of_ct_cl]
