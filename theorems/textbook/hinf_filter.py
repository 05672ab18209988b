"""Full-order H∞ filtering, continuous and discrete time.

References: Geromel, de Oliveira, Bernussou, "Robust filtering of discrete-time linear systems
with parameter dependent Lyapunov functions", SIAM J. Control Optim. 41(3):700-711, 2002 (H2
and H∞ full-order filters by LMIs, discrete time); Scherer, Gahinet, Chilali, IEEE TAC
42(7):896-911, 1997 (the change of variables, here with the filter as a controller).

Plant x' = A x + B1 w, z = C1 x + D11 w, y = C2 x + D21 w (A stable); filter
x̂' = Af x̂ + Bf y, ẑ = Cf x̂ + Df y of order n; error e = z − ẑ.  The filter is the output-feedback
controller of the plant with u = ẑ, B2 = 0, D12 = −I, so the LMIs are those of
:mod:`.hinf_of` with the blocks of :func:`lmidsl.filter_blocks` (A11 = A X, A12 = A, A21 = Â,
A22 = Y A + B̂ C2, B1, Y B1 + B̂ D21, C1 X − Ĉ, C1 − D̂ C2, D11 − D̂ D21), and the recovery
:func:`lmidsl.full_order_filter` (M Nᵀ = I − X Y):
Af = N⁻¹(Â − Y A X − B̂ C2 X) M⁻ᵀ, Bf = N⁻¹B̂, Cf = (Ĉ − D̂ C2 X) M⁻ᵀ, Df = D̂.
The analysis counterpart is the bounded real lemma of the error system
(:func:`lmidsl.filter_error_matrices`).
"""
from sympy import Identity, ZeroMatrix

from lmidsl import Source, Theorem, filter_blocks, filter_error_matrices, full_order_filter

from .brl import bounded_real, scale_state
from .hinf_of import full_order_hinf_lmis, full_order_variables
from .plants import filter_cases

GDB = ("Geromel, de Oliveira, Bernussou, Robust filtering of discrete-time linear systems with "
       "parameter dependent Lyapunov functions, SIAM J. Control Optim. 41(3):700-711, 2002")
PLANT = ("A", "B1", "C1", "C2", "D11", "D21")
FILTER = ("Af", "Bf", "Cf", "Df")


def filtering_plant(thm: Theorem):
    n, m1, p1, p2 = thm.dim("n m1 p1 p2")
    shapes = dict(A=(n, n), B1=(n, m1), C1=(p1, n), C2=(p2, n), D11=(p1, m1), D21=(p2, m1))
    latex = dict(A="A", B1="B_1", C1="C_1", C2="C_2", D11="D_{11}", D21="D_{21}")
    what = dict(A="state matrix (stable)", B1="disturbance input w", C1="signal to estimate z",
                C2="measurement y", D11="w -> z", D21="w -> y")
    return (n, m1, p1, p2), {k: thm.data(k, *shapes[k], latex=latex[k], description=what[k]) for k in PLANT}


def _analysis(name: str, time: str) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"H∞ norm of the filtering error ({time} time)",
                  Source("Boyd et al. 1994", "Sec. 2.7.3 applied to the filtering-error system",
                         "Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in "
                         "System and Control Theory, SIAM 1994"),
                  time=time, description="the bounded real lemma of the error system with the filter given")
    (n, m1, p1, p2), d = filtering_plant(thm)
    nf = thm.dim("nf")
    F = dict(Af=thm.data("Af", nf, nf, latex="A_f"), Bf=thm.data("Bf", nf, p2, latex="B_f"),
             Cf=thm.data("Cf", p1, nf, latex="C_f"), Df=thm.data("Df", p1, p2, latex="D_f"))
    e = filter_error_matrices(*(d[k] for k in PLANT), *(F[k] for k in FILTER))
    names = {"A": r"\mathcal{A}", "B": r"\mathcal{B}", "C": r"\mathcal{C}", "D": r"\mathcal{D}"}
    e = {k: thm.define(f"{k}_e", v, latex=names[k]) for k, v in e.items()}
    bounded_real(thm, "(BRL-e)", e["A"], e["B"], e["C"], e["D"], n + nf)
    scale_state(thm, ("A", "B1"), ("A", "C1", "C2"))
    return thm


def _synthesis(name: str, time: str, analysis: Theorem) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"Full-order H∞ filter ({time} time)",
                  Source("Geromel, de Oliveira, Bernussou 2002", "full-order H∞ filter, change of variables", GDB),
                  time=time, designs="filter",
                  description="min γ over X, Y, Â, B̂, Ĉ, D̂; the filter by the full-order recovery "
                              "(M Nᵀ = I − X Y).")
    (n, m1, p1, p2), d = filtering_plant(thm)
    X, Y, Ah, Bh, Ch, Dh, g = full_order_variables(thm, n, p2, p1)
    b = filter_blocks(X, Y, Ah, Bh, Ch, Dh, *(d[k] for k in PLANT))
    full_order_hinf_lmis(thm, "(F)", b, g, X, Y)
    thm.minimize(g, performance=("gamma", g))
    # the filter is the controller of the plant with u = ẑ: B2 = 0, D12 = −I
    thm.output_feedback_form(X, Y, Ah, Bh, Ch, Dh, g, (d["A"], d["B1"], ZeroMatrix(n, p1), d["C1"], d["C2"],
                                                      d["D11"], -Identity(p1), d["D21"]))
    thm.recover(**full_order_filter(thm, X, Y, Ah, Bh, Ch, Dh, d["A"], d["C2"]))
    thm.certified_by(analysis, design=FILTER)
    scale_state(thm, ("A", "B1"), ("A", "C1", "C2"))
    thm.well_conditioned(X, Y)
    thm.example("random-3", dict(filter_cases(time)[2][1]), provenance="illustration",
                provenance_note="a random stable plant, numpy seed 2002 (theorems/textbook/plants.py)")
    return thm


hinf_filter_ct_cl = _analysis("hinf_filter_ct_cl", "continuous")
hinf_filter_ct = _synthesis("hinf_filter_ct", "continuous", hinf_filter_ct_cl)
hinf_filter_dt_cl = _analysis("hinf_filter_dt_cl", "discrete")
hinf_filter_dt = _synthesis("hinf_filter_dt", "discrete", hinf_filter_dt_cl)

THEOREMS = [hinf_filter_ct, hinf_filter_ct_cl, hinf_filter_dt, hinf_filter_dt_cl]
