"""Pan, Sun: robust H∞ filtering for discrete-time impulsive systems with uncertainty.

Paper: Pan Sheng-tao, Sun Ji-tao (Tongji University); readings taken and results in
``docs/reproductions/003.md``.

Plant (1)-(4): x(k+1) = A x + B ω (k ≠ τ_j), x(τ_j+1) = M x(τ_j), y = C x + D ω,
z = L1 x + L2 ω, with (A, B, M, C, D, L1, L2) in the polytope (5).  Impulsive filter (6)-(8):
x̂(k+1) = Â x̂ + B̂ y (k ≠ τ_j), x̂(τ_j+1) = M̂ x̂(τ_j), ẑ = Ĉ x̂ + D̂ y.  Error system (9)-(12)
with ξ = [x; x̂]: Ā = [[A, 0], [B̂C, Â]], B̄ = [B; B̂D], M̄ = diag(M, M̂), C̄ = [L1 − D̂C, −Ĉ],
D̄ = L2 − D̂D.

* ``pan_impulsive.lemma1``   Lemma 1, (13)-(14): analysis with the filter fixed, min γ² over P > 0.
* ``pan_impulsive.thm1``     Theorem 1, (27)-(28) at every vertex, at the prescribed γ (a
  parameter): the feasibility problem as the paper states it.
* ``pan_impulsive.thm1_min`` the same LMIs with g = γ² a decision variable, min g.

In Theorem 1, λ1, λ2, ε are fixed scalars (parameters: the slack structure (26)); the
vertex-dependent variable is P̂⁽ⁱ⁾ = [[P̂11, P̂12], [P̂12ᵀ, P̂22]], the others are common.  Recovery:
Â = T⁻¹S_A, B̂ = T⁻¹S_B, M̂ = T⁻¹S_M, Ĉ = Ψ⁻ᵀS_C, D̂ = Ψ⁻ᵀS_D.

Readings taken (docs/reproductions/003.md, "Reconstruction of (27)/(28)"): the block layout of
(27)/(28), damaged by the OCR, is the congruence image of (24)/(25) under (26) (checked numerically in
``tests/test_pan_impulsive.py``); P̂⁽ⁱ⁾ > 0 is imposed explicitly (Lemma 1 needs P > 0); the
ε Ψ block of F needs p = m, so the error output and the disturbance share the dimension ``m``
(data with p ≠ m are refused with the shape error naming L1 or L2).
"""
from lmidsl import He, Source, Theorem

from .impulsive import simulate_design
from sympy import BlockMatrix, Identity, ZeroMatrix, sqrt

PAPER = "Pan, Sun, H∞ filtering for impulsive systems"
CITATION = "Pan, Sun, Robust H∞ filtering for discrete-time impulsive systems with uncertainty"
PRINTED_AT = "Section 3 (numerical example)"

PLANT = {"A": [[1.0, 0.01], [-0.05, -0.1]], "B": [[1.0], [0.1]], "M": [[1.0, 0.0], [0.0, 0.8]],
         "C": [[1.0, 0.0]], "D": [[1.0]], "L1": [[1.0, 0.0]], "L2": [[0.0]]}
SCALARS = {"lambda1": 0.2, "lambda2": -0.3, "epsilon": 0.1}
PRINTED_FILTER = {"Ahat": [[0.2955, 0.1235], [1.1128, 0.1294]], "Bhat": [[1.2788], [-0.0368]],
                  "Mhat": [[0.4198, -0.1499], [-1.1959, 0.0066]], "Chat": [[0.0440, -0.0319]],
                  "Dhat": [[0.9551]]}
# Not from the paper.  The jump matrix M = diag(1, 0.8) has the eigenvalue 1, which makes (14) and
# (28) infeasible for every filter (docs/reproductions/003.md); M11 = 0.9 makes the jump map Schur.
# The plant is then written in the state coordinates x' = x/10 (B/10, 10 C, 10 L1; A, M unchanged):
# an exact change of realisation that changes no transfer function and no LMI's feasibility, but
# raises the strict margins above the default 1e-7 (the paper's coordinates give ~2e-8 only).
MODIFIED_PLANT = {**PLANT, "M": [[0.9, 0.0], [0.0, 0.8]], "B": [[0.1], [0.01]],
                  "C": [[10.0, 0.0]], "L1": [[10.0, 0.0]]}
MODIFIED_SCALARS = {"lambda1": 0.3, "lambda2": 0.3, "epsilon": 0.0}   # best t* of the scalar search
MODIFIED_MIN_SCALARS = {"lambda1": 0.6, "lambda2": 0.6, "epsilon": 0.0}  # best certified γ of the search
MODIFIED_COMMON = {k: v for k, v in MODIFIED_PLANT.items() if k != "A"}
TWO_VERTICES = [{"A": MODIFIED_PLANT["A"]}, {"A": [[0.95, 0.01], [-0.05, -0.1]]}]   # A11 ∈ {1, 0.95}

FILTER = ("Ahat", "Bhat", "Mhat", "Chat", "Dhat")


def _plant(thm: Theorem, *, same_pm: bool, per_vertex: bool):
    """Dimensions and the plant (1)-(4); ``same_pm``: one dimension m for z and ω ((26) needs p = m)."""
    if same_pm:
        n, m, r = thm.dim("n m r")
        p = m
    else:
        n, m, r, p = thm.dim("n m r p")
    kw = {"per_vertex": per_vertex}
    d = dict(
        A=thm.data("A", n, n, description="state matrix between impulses", **kw),
        B=thm.data("B", n, m, description="disturbance input", **kw),
        M=thm.data("M", n, n, description="jump matrix at the impulse instants", **kw),
        C=thm.data("C", r, n, description="measurement matrix", **kw),
        D=thm.data("D", r, m, description="measurement noise input", **kw),
        L1=thm.data("L1", p, n, latex="L_1", description="estimated signal, state part", **kw),
        L2=thm.data("L2", p, m, latex="L_2", description="estimated signal, disturbance part", **kw),
    )
    return (n, m, r, p), d


# -- Lemma 1: analysis with the filter fixed ------------------------------------------------
lemma1 = Theorem("pan_impulsive.lemma1", "H∞ analysis of the impulsive filtering-error system (Lemma 1)",
                 Source(PAPER, "Lemma 1, (12)-(14)", CITATION),
                 description="min γ² over P > 0 with (13) (flow map) and (14) (jump map) for a given "
                             "impulsive filter; one P for both maps, so any impulse sequence.")
(_n, _m, _r, _p), _d = _plant(lemma1, same_pm=False, per_vertex=False)
Ahat = lemma1.data("Ahat", _n, _n, latex=r"\hat{A}", description="filter state matrix")
Bhat = lemma1.data("Bhat", _n, _r, latex=r"\hat{B}", description="filter input matrix")
Mhat = lemma1.data("Mhat", _n, _n, latex=r"\hat{M}", description="filter jump matrix")
Chat = lemma1.data("Chat", _p, _n, latex=r"\hat{C}", description="filter output matrix")
Dhat = lemma1.data("Dhat", _p, _r, latex=r"\hat{D}", description="filter feedthrough")
A_bar = BlockMatrix([[_d["A"], ZeroMatrix(_n, _n)], [Bhat * _d["C"], Ahat]])
B_bar = BlockMatrix([[_d["B"]], [Bhat * _d["D"]]])
M_bar = BlockMatrix([[_d["M"], ZeroMatrix(_n, _n)], [ZeroMatrix(_n, _n), Mhat]])
C_bar = BlockMatrix([[_d["L1"] - Dhat * _d["C"], -Chat]])
D_bar = _d["L2"] - Dhat * _d["D"]
P = lemma1.var("P", 2 * _n, kind="symmetric", latex="P", description="Lyapunov matrix of ξ = [x; x̂]")
g_l = lemma1.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
# (13): Ãᵀ diag(P, I) Ã − diag(P, γ² I) < 0 with Ã = [[Ā, B̄], [C̄, D̄]], written by blocks (ξ, ω)
lemma1.lmi("(13)", [
    [A_bar.T * P * A_bar + C_bar.T * C_bar - P],
    [B_bar.T * P * A_bar + D_bar.T * C_bar, B_bar.T * P * B_bar + D_bar.T * D_bar - g_l * Identity(_m)],
], description="flow map, k ≠ τ_j")
# (14): the same with M̃ = [[M̄, 0], [C̄, D̄]]
lemma1.lmi("(14)", [
    [M_bar.T * P * M_bar + C_bar.T * C_bar - P],
    [D_bar.T * C_bar, D_bar.T * D_bar - g_l * Identity(_m)],
], description="jump map, k = τ_j")
lemma1.positive(P)
lemma1.minimize(g_l, performance=("gamma", sqrt(g_l)))
lemma1.example("paper-printed", {**PLANT, **PRINTED_FILTER}, printed={"gamma_bound": 0.5},
               printed_note=PRINTED_AT, expect="infeasible",
               expect_note="Lemma 1 is infeasible at every γ for the printed filter: feasp t* = (1 − D̂)², "
                           "LMI (14) responsible (docs/reproductions/003.md)",
               description="the filter the paper prints for γ = 0.5, analysed by Lemma 1")
lemma1.example("modified-printed", {**MODIFIED_PLANT, **PRINTED_FILTER},
               provenance="illustration", provenance_note="not from the paper: the printed filter on the plant with M11 = 0.9",
               description="not from the paper: the printed filter on the plant with M11 = 0.9")


# -- Theorem 1: synthesis ---------------------------------------------------------------------
def _theorem1(thm: Theorem, *, minimise: bool):
    """LMIs (27), (28) at every vertex, P̂⁽ⁱ⁾ > 0, recovery, certification by Lemma 1."""
    (n, m, r, p), d = _plant(thm, same_pm=True, per_vertex=True)
    A, B, M, C, D, L1, L2 = (d[k] for k in ("A", "B", "M", "C", "D", "L1", "L2"))
    lam1 = thm.param("lambda1", latex=r"\lambda_1", description="slack scalar of Λ = diag(λ1 I, λ2 I)")
    lam2 = thm.param("lambda2", latex=r"\lambda_2", description="slack scalar of Λ = diag(λ1 I, λ2 I)")
    eps = thm.param("epsilon", latex=r"\epsilon", description="slack scalar of F's (2,2) block εΨ")
    P11 = thm.var("P11", n, kind="symmetric", latex=r"\hat{P}_{11}", per_vertex=True)
    P12 = thm.var("P12", n, n, latex=r"\hat{P}_{12}", per_vertex=True)
    P22 = thm.var("P22", n, kind="symmetric", latex=r"\hat{P}_{22}", per_vertex=True)
    R = thm.var("R", n, n, latex="R")
    W = thm.var("W", n, n, latex="W")
    T = thm.var("T", n, n, latex="T")
    S_A = thm.var("S_A", n, n, latex="S_A")
    S_M = thm.var("S_M", n, n, latex="S_M")
    S_B = thm.var("S_B", n, r, latex="S_B")
    S_C = thm.var("S_C", p, n, latex="S_C")
    S_D = thm.var("S_D", p, r, latex="S_D")
    Psi = thm.var("Psi", p, p, latex=r"\Psi")
    if minimise:
        g = thm.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
    else:
        gamma = thm.param("gamma", latex=r"\gamma", domain=(0.0, float("inf")),
                          description="prescribed H∞ level")
        g = gamma ** 2

    Pi1 = -g * Identity(m) + eps * (Psi.T * L2 + L2.T * Psi - S_D * D - D.T * S_D.T)
    Pi2 = P22 + He(T)
    Pi3 = Identity(p) - He(Psi)
    out_1 = Psi.T * L1 - S_D * C - S_C          # Ψᵀ(L1 − D̂C − Ĉ) after the change of variables
    out_w = -eps * Psi + Psi.T * L2 - S_D * D
    thm.lmi("(27)", [
        [lam1 * He(R.T * A) - P11],
        [lam1 * W.T * A + lam2 * (S_B * C + S_A) - P12.T, -lam2 * He(S_A) - P22],
        [eps * out_1 + lam1 * B.T * R, eps * S_C + lam1 * B.T * W + lam2 * D.T * S_B.T, Pi1],
        [-lam1 * R + R.T * A, -lam1 * W - lam2 * T.T, R.T * B, P11 - He(R)],
        [W.T * A + S_B * C + S_A, lam2 * T.T - S_A, W.T * B + S_B * D, P12.T - (W.T + T), Pi2],
        [out_1, S_C, out_w, 0, 0, Pi3],
    ], description="flow map at vertex i (congruence image of (24))")
    thm.lmi("(28)", [
        [lam1 * He(R.T * M) - P11],
        [lam1 * W.T * M + lam2 * S_M - P12.T, -lam2 * He(S_M) - P22],
        [eps * out_1, eps * S_C, Pi1],
        [-lam1 * R + R.T * M, -lam1 * W - lam2 * T.T, 0, P11 - He(R)],
        [W.T * M + S_M, lam2 * T.T - S_M, 0, P12.T - (W.T + T), Pi2],
        [out_1, S_C, out_w, 0, 0, Pi3],
    ], description="jump map at vertex i (congruence image of (25))")
    thm.lmi("P̂ > 0", [[P11], [P12.T, P22]], sense=">",
            description="P̂⁽ⁱ⁾ = T_cᵀ P⁽ⁱ⁾ T_c > 0 (Lemma 1 needs P > 0; docs/reproductions/003.md)")
    if minimise:
        thm.minimize(g, performance=("gamma", sqrt(g)))
    else:
        thm.feasibility(performance=("gamma", gamma))
    thm.recover(Ahat=T.I * S_A, Bhat=T.I * S_B, Mhat=T.I * S_M,
                Chat=Psi.T.I * S_C, Dhat=Psi.T.I * S_D)
    thm.certified_by("pan_impulsive.lemma1", design=FILTER)


PAPER_INFEASIBLE = ("Theorem 1 is infeasible on the paper's example at its scalars λ1 = 0.2, λ2 = −0.3, "
                    "ε = 0.1: feasp t* = 0.125, (27) and (28) responsible (docs/reproductions/003.md)")

thm1 = Theorem("pan_impulsive.thm1", "Robust impulsive H∞ filter at a prescribed γ (Theorem 1)",
               Source(PAPER, "Theorem 1, (26)-(28)", CITATION),
               description="feasibility of (27), (28), P̂⁽ⁱ⁾ > 0 at every vertex for given γ, λ1, λ2, ε.",
               designs="filter")
_theorem1(thm1, minimise=False)
thm1.example("paper", dict(PLANT), params={**SCALARS, "gamma": 0.5},
             printed=dict(PRINTED_FILTER), printed_note=PRINTED_AT, expect="infeasible",
             expect_note=PAPER_INFEASIBLE,
             description="the paper's example: one vertex, γ = 0.5, λ1 = 0.2, λ2 = −0.3, ε = 0.1")
thm1.example("modified", dict(MODIFIED_PLANT), params={**MODIFIED_SCALARS, "gamma": 0.5},
             provenance="illustration", provenance_note="not from the paper: M11 = 0.9 (Schur jump map), γ = 0.5, scalars from the scalar search",
             description="not from the paper: M11 = 0.9 (Schur jump map), γ = 0.5, scalars "
                         "from the scalar search (docs/reproductions/003.md)")
VERTEX_WISE_NOTE = ("vertex-wise: the analysis (Lemma 1, the filter fixed) is solved at each vertex with its own "
                    "Lyapunov matrix, which does not prove the level inside the polytope")

thm1.example("modified-two-vertex", MODIFIED_COMMON, params={**MODIFIED_SCALARS, "gamma": 1.0},
             vertices=TWO_VERTICES,
             provenance="illustration", provenance_note="not from the paper: M11 = 0.9 and A11 ∈ {1, 0.95}, γ = 1 (γ = 0.5 is infeasible)",
             expect="not certified", expect_note=VERTEX_WISE_NOTE,
             description="not from the paper: M11 = 0.9 and A11 ∈ {1, 0.95}, γ = 1 (γ = 0.5 is infeasible)")

thm1_min = Theorem("pan_impulsive.thm1_min", "Robust impulsive H∞ filter, min γ (Theorem 1)",
                   Source(PAPER, "Theorem 1, (26)-(28)", CITATION),
                   description="min γ² subject to (27), (28), P̂⁽ⁱ⁾ > 0 at every vertex for given λ1, λ2, ε.",
                   designs="filter", provenance="illustration",
                   provenance_note="Theorem 1's LMIs with γ² minimised; the paper prescribes γ")
_theorem1(thm1_min, minimise=True)
thm1_min.example("paper", dict(PLANT), params=dict(SCALARS),
                 printed_note="the paper prescribes γ = 0.5 and prints no optimum",
                 expect="not solved",
                 expect_note=PAPER_INFEASIBLE + "; with γ free no theorem-of-alternatives certificate is "
                             "found (the exact route's point is not PSD), so infeasibility is not proved "
                             "here (it is for Theorem 1 at γ = 0.5)",
                 description="the paper's example at its scalars, γ minimised")
thm1_min.example("modified", dict(MODIFIED_PLANT), params=dict(MODIFIED_MIN_SCALARS),
                 provenance="illustration", provenance_note="not from the paper: M11 = 0.9 (Schur jump map), searched scalars",
                 description="not from the paper: M11 = 0.9 (Schur jump map), searched scalars")
thm1_min.example("modified-two-vertex", MODIFIED_COMMON, params=dict(MODIFIED_SCALARS),
                 vertices=TWO_VERTICES,
                 provenance="illustration", provenance_note="not from the paper: M11 = 0.9 and A11 ∈ {1, 0.95}",
                 expect="not certified", expect_note=VERTEX_WISE_NOTE,
                 description="not from the paper: M11 = 0.9 and A11 ∈ {1, 0.95}")

for _thm in (lemma1, thm1, thm1_min):
    _thm.simulated_by(simulate_design)

THEOREMS = [lemma1, thm1, thm1_min]
