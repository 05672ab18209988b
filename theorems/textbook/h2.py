"""H2 norm by the Gramian LMIs and H2 state feedback, continuous and discrete time.

References: Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and
Control Theory*, SIAM 1994 (output energy and H2-type costs through Lyapunov inequalities);
Scherer & Weiland, *Linear Matrix Inequalities in Control*, lecture notes (H2
nominal performance and H2 state-feedback synthesis); Feron, Balakrishnan, Boyd, El Ghaoui,
"Numerical methods for H2 related problems", ACC 1992 (the change of variables W = K Y for H2).

**Analysis.**  For x' = A x + B w, z = C x + D w with A stable (and D = 0 in continuous time),
the controllability Gramian Wc solves A Wc + Wc Aᵀ + B Bᵀ = 0 (continuous) or
A Wc Aᵀ − Wc + B Bᵀ = 0 (discrete), and ‖G‖₂² = tr(C Wc Cᵀ) (+ tr(D Dᵀ) in discrete time).
Any P with the strict Lyapunov inequality is above Wc, so

* continuous:  min tr Z  s.t.  [[He(A P), B], [Bᵀ, −I]] ≺ 0,  [[Z, C P], [P Cᵀ, P]] ≻ 0;
* discrete:    min tr Z  s.t.  [[−P, A P, B], [P Aᵀ, −P, 0], [Bᵀ, 0, −I]] ≺ 0,
  [[Z, C P, D], [P Cᵀ, P, 0], [Dᵀ, 0, I]] ≻ 0;

gives ‖G‖₂² as the infimum (the Schur complements: A P + P Aᵀ + B Bᵀ ≺ 0, Z ≻ C P Cᵀ (+ D Dᵀ)).

**State feedback.**  The same LMIs for the closed loop (A + B2 K, B1, C1 + D12 K, D11) with
P = Y and W = K Y are linear in (Y, W, Z); K = W Y⁻¹ (:func:`lmidsl.state_feedback_gain`).
Continuous time needs D11 = 0: the theorem takes no D11 and declares the assumption
(``thm.assume(zero("D11", external=True))``), so a plant with D11 ≠ 0 is refused at bind time.  The optimum is the LQR cost with
Q = C1ᵀC1, R = D12ᵀD12, N = C1ᵀD12 (python-control's ``lqr`` / ``dlqr`` are the independent check).
"""
from lmidsl import He, I, Source, Theorem, state_feedback_gain, zero
from sympy import Trace, sqrt

from .brl import scale_state, system_data
from .plants import random_plant, random_system, subset

BOYD = ("Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System and "
        "Control Theory, SIAM 1994")
SW = "Scherer, Weiland, Linear Matrix Inequalities in Control, lecture notes"
D11_WHY = "the continuous-time H2 norm is infinite when D11 ≠ 0"
SF_DATA = {"continuous": ("A", "B1", "B2", "C1", "D12"), "discrete": ("A", "B1", "B2", "C1", "D11", "D12")}


def h2_gramian(thm: Theorem, A, B, C, D, n, p, *, P=None, AP=None, CP=None):
    """Declare Z and the Gramian LMIs of (A, B, C, D) in ``thm.time`` (D ignored in continuous
    time: it must be 0); ``AP`` = A P and ``CP`` = C P may be given (state feedback: A Y + B2 W).
    Objective min tr Z, performance h2 = √tr Z."""
    Z = thm.var("Z", p, kind="symmetric", description="bound on C P Cᵀ (+ D Dᵀ)")
    AP = A * P if AP is None else AP
    CP = C * P if CP is None else CP
    if thm.time == "continuous":
        thm.lmi("(Lyap)", [
            [He(AP)],
            [B.T, -I],
        ])
        thm.lmi("(Z)", [
            [Z],
            [CP.T, P],
        ], sense=">")
    else:
        thm.lmi("(Lyap)", [
            [-P],
            [AP.T, -P],
            [B.T, 0, -I],
        ])
        thm.lmi("(Z)", [
            [Z],
            [CP.T, P],
            [D.T, 0, I],
        ], sense=">")
    thm.positive(P)
    thm.minimize(Trace(Z), performance=("h2", sqrt(Trace(Z))))
    return Z


def _analysis(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H2 norm by the Gramian LMIs ({time} time)",
                  Source("Scherer & Weiland", "H2 performance via the controllability Gramian", SW),
                  time=time, description="min tr Z over P ≻ 0 with the Lyapunov inequality and "
                                         "Z ≻ C P Cᵀ (+ D Dᵀ): the H2 norm squared.")
    if time == "continuous":
        n, m, p = thm.dim("n m p")
        A = thm.data("A", n, n, description="state matrix")
        B = thm.data("B", n, m, description="input matrix (w)")
        C = thm.data("C", p, n, description="output matrix (z)")
        D = None
        thm.assume(zero("D", why="the continuous-time H2 norm is infinite when D ≠ 0", external=True))
    else:
        (n, m, p), (A, B, C, D) = system_data(thm)
    P = thm.var("P", n, kind="symmetric", description="bound on the controllability Gramian")
    h2_gramian(thm, A, B, C, D, n, p, P=P)
    scale_state(thm, ("A", "B"), ("A", "C"))
    return thm


def _state_feedback(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H2 state feedback ({time} time)",
                  Source("Scherer & Weiland", "H2 state-feedback synthesis, W = K Y", SW),
                  time=time, designs="gain",
                  description="min tr Z over Y ≻ 0, W: the Gramian LMIs of the closed loop with "
                              "K = W Y⁻¹.")
    n, m1, m2, p1 = thm.dim("n m1 m2 p1")
    A = thm.data("A", n, n, description="state matrix")
    B1 = thm.data("B1", n, m1, latex="B_1", description="disturbance input w")
    B2 = thm.data("B2", n, m2, latex="B_2", description="control input u")
    C1 = thm.data("C1", p1, n, latex="C_1", description="performance output z")
    D11 = thm.data("D11", p1, m1, latex="D_{11}", description="w -> z") if time == "discrete" else None
    D12 = thm.data("D12", p1, m2, latex="D_{12}", description="u -> z")
    Y = thm.var("Y", n, kind="symmetric", description="Y = P, the closed-loop Gramian bound")
    W = thm.var("W", m2, n, description="W = K Y")
    h2_gramian(thm, A, B1, C1, D11, n, p1, P=Y, AP=A * Y + B2 * W, CP=C1 * Y + D12 * W)
    if time == "continuous":
        thm.assume(zero("D11", why=D11_WHY, external=True))
    thm.recover(K=state_feedback_gain(W, Y))
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1"), recovered_cols=("K",))
    thm.certified_by(f"textbook.h2_{'ct' if time == 'continuous' else 'dt'}_sf_cl", design=("K",))
    thm.example("random-3", subset(random_plant(11, 3, 2, 1, 2, 1, time), SF_DATA[time]),
                provenance="illustration",
                provenance_note="a random plant, numpy seed 11 (theorems/textbook/plants.py)")
    return thm


def _sf_analysis(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H2 norm of the state-feedback closed loop ({time} time)",
                  Source("Scherer & Weiland", "H2 performance of (A + B2K, B1, C1 + D12K, D11)", SW),
                  time=time, description="the Gramian LMIs of the closed loop with the gain K given")
    n, m1, m2, p1 = thm.dim("n m1 m2 p1")
    A = thm.data("A", n, n)
    B1 = thm.data("B1", n, m1, latex="B_1")
    B2 = thm.data("B2", n, m2, latex="B_2")
    C1 = thm.data("C1", p1, n, latex="C_1")
    D11 = thm.data("D11", p1, m1, latex="D_{11}") if time == "discrete" else None
    D12 = thm.data("D12", p1, m2, latex="D_{12}")
    K = thm.data("K", m2, n, description="state-feedback gain u = K x")
    if time == "continuous":
        thm.assume(zero("D11", why=D11_WHY, external=True))
    Acl = thm.define("A_cl", A + B2 * K, latex=r"A_{cl}")
    Ccl = thm.define("C_cl", C1 + D12 * K, latex=r"C_{cl}")
    P = thm.var("P", n, kind="symmetric")
    h2_gramian(thm, Acl, B1, Ccl, D11, n, p1, P=P)
    scale_state(thm, ("A", "B1", "B2"), ("A", "C1", "K"))
    return thm


h2_ct = _analysis("h2_ct", "continuous")
h2_ct.example("random-3x2x2", {k: v for k, v in random_system(7, 3, 2, 2, "continuous").items() if k != "D"},
              provenance="illustration",
              provenance_note="a random stable system, numpy seed 7, D dropped (theorems/textbook/plants.py)")
h2_dt = _analysis("h2_dt", "discrete")
h2_dt.example("random-3x2x2", random_system(7, 3, 2, 2, "discrete"), provenance="illustration",
              provenance_note="a random Schur-stable system, numpy seed 7 (theorems/textbook/plants.py)")
h2_ct_sf_cl = _sf_analysis("h2_ct_sf_cl", "continuous")
h2_ct_sf = _state_feedback("h2_ct_sf", "continuous")
h2_dt_sf_cl = _sf_analysis("h2_dt_sf_cl", "discrete")
h2_dt_sf = _state_feedback("h2_dt_sf", "discrete")

THEOREMS = [h2_ct, h2_dt, h2_ct_sf, h2_ct_sf_cl, h2_dt_sf, h2_dt_sf_cl]
