"""Wang, Cai, Lin, Yang: l2–l∞ filtering for networked systems with missing measurements.

Paper: Wang Wu, Cai Feng-huang, Lin Qiong-bin, Yang Fu-wen (Fuzhou University); readings taken and
results in ``docs/reproductions/000.md``.

Plant (1): x(k+1) = A x + B w,  y = r(k) C x + D w,  z = L x, with r(k) Bernoulli,
Pr{r = 1} = r̄, and a = (1 − r̄) r̄ the variance of r(k).  Filter (4): x̂(k+1) = Af x̂ + Bf y,
ẑ = Cf x̂ of order k, set by the selector E = [I_k; 0] (n × k).

* ``wang_l2linf.thm1``  Theorem 1, (10)–(11): analysis with the filter fixed, min γ² over P.
* ``wang_l2linf.thm3``  Theorem 3, (30)–(31): synthesis, min γ²; recovery (32)
  Af = V2⁻¹Âf, Bf = V2⁻¹B̂f, Cf = Ĉf.
* ``wang_l2linf.cor1``  Corollary 1, (37)–(38): the polytopic version of Theorem 3 with
  vertex-dependent P1, P2, P3 and common V1, V2, V3, Âf, B̂f, Ĉf, γ.

Reading taken (docs/reproductions/000.md): the factor ``a`` appears both off the diagonal
(aPA_cl1, aEB̂fC, aB̂fC) and on the diagonal (−aP, a(P − V − Vᵀ)), exactly as printed; the Schur
complement then weighs A_cl1ᵀPA_cl1 by a²/a = a, as the variance computation requires.
"""
import numpy as np
from lmidsl import ErrorSystem, I, Source, Theorem
from sympy import BlockMatrix, Identity, ZeroMatrix, sqrt

PAPER = "Wang et al., l2-l∞ filtering with missing measurements"
CITATION = "Wang, Cai, Lin, Yang, l2-l∞ filtering for networked systems with missing measurements"

A_PAPER = [[0.0, 0.3], [-0.2, 0.4]]
PLANT = {"A": A_PAPER, "B": [[0.0], [1.0]], "C": [[1.0, 0.0]], "D": [[1.0]], "L": [[1.0, 2.0]]}
FULL_FILTER = {"Af": [[-0.0069, 0.2865], [-0.9725, 0.4557]], "Bf": [[-0.0186], [-0.9235]],
               "Cf": [[-0.9963, -1.9624]]}
REDUCED_FILTER = {"Af": [[0.5253]], "Bf": [[-0.2456]], "Cf": [[-3.5200]]}
PRINTED_AT = "Section 5 (numerical example)"


def _plant(thm: Theorem, per_vertex: bool = False):
    """Dimensions, plant data (1), the Bernoulli parameter r̄ and a = (1 − r̄) r̄."""
    n, m, ny, p, k = thm.dim("n m n_y p k")
    plant = dict(
        A=thm.data("A", n, n, per_vertex=per_vertex, description="state matrix"),
        B=thm.data("B", n, m, per_vertex=per_vertex, description="disturbance input"),
        C=thm.data("C", ny, n, per_vertex=per_vertex, description="measurement matrix"),
        D=thm.data("D", ny, m, per_vertex=per_vertex, description="measurement noise input"),
        L=thm.data("L", p, n, per_vertex=per_vertex, description="estimated output"),
    )
    rbar = thm.param("rbar", latex=r"\bar{r}", domain=(0.0, 1.0), open_domain=True,
                     domain_note="a probability; at 0 or 1, a = 0 and the diagonal blocks "
                                 "a(P - V - V^T) of the printed LMI vanish, so no strict solution exists",
                     description="Pr{r(k) = 1}, probability that the measurement arrives")
    a = thm.derived("a", (1 - rbar) * rbar, latex="a", description="variance of r(k)")
    return (n, m, ny, p, k), plant, rbar, a


def _synthesis(thm: Theorem, per_vertex: bool, labels: tuple[str, str]):
    """LMIs (30)–(31) (or (37)–(38) per vertex), objective min γ², recovery (32)."""
    (n, m, ny, p, k), d, rbar, a = _plant(thm, per_vertex)
    A, B, C, D, L = d["A"], d["B"], d["C"], d["D"], d["L"]
    E = thm.data("E", n, k, latex="E", description="order selector [I_k; 0]")
    P1 = thm.var("P1", n, kind="symmetric", latex="P_1", per_vertex=per_vertex)
    P2 = thm.var("P2", n, k, latex="P_2", per_vertex=per_vertex)
    P3 = thm.var("P3", k, kind="symmetric", latex="P_3", per_vertex=per_vertex)
    V1 = thm.var("V1", n, n, latex="V_1")
    V2 = thm.var("V2", k, k, latex="V_2")
    V3 = thm.var("V3", n, k, latex="V_3")
    Af_hat = thm.var("Af_hat", k, k, latex=r"\hat{A}_f")
    Bf_hat = thm.var("Bf_hat", k, ny, latex=r"\hat{B}_f")
    Cf_hat = thm.var("Cf_hat", p, k, latex=r"\hat{C}_f")
    g = thm.scalar("g", latex=r"\gamma^2", description="squared l2-l∞ level")

    W11 = P1 - V1 - V1.T
    W21 = P2.T - V3.T - V2.T * E.T
    W22 = P3 - V2 - V2.T
    thm.lmi(labels[0], [
        [-P1],
        [-P2.T, -P3],
        [0, 0, -I],
        [V1.T * A + rbar * E * Bf_hat * C, E * Af_hat, V1.T * B + E * Bf_hat * D, W11],
        [V3.T * A + rbar * Bf_hat * C, Af_hat, V3.T * B + Bf_hat * D, W21, W22],
        [a * E * Bf_hat * C, 0, 0, 0, 0, a * W11],
        [a * Bf_hat * C, 0, 0, 0, 0, a * W21, a * W22],
    ])
    thm.lmi(labels[1], [
        [-P1],
        [-P2.T, -P3],
        [L, -Cf_hat, -g * I],
    ])
    thm.positive(P1, P3)
    thm.minimize(g, performance=("gamma", sqrt(g)))
    thm.recover(Af=V2.I * Af_hat, Bf=V2.I * Bf_hat, Cf=Cf_hat)
    thm.certified_by(thm1, design=("Af", "Bf", "Cf"))


# -- Theorem 1: analysis ------------------------------------------------------------------
thm1 = Theorem("wang_l2linf.thm1", "Energy-to-peak analysis with the filter fixed (Theorem 1)",
               Source(PAPER, "Theorem 1, (10)-(11)", CITATION),
               description="min γ² over P > 0 such that (10) and (11) hold for a given filter.")
(_n, _m, _ny, _p, _k), _d, _rbar, _a = _plant(thm1)
Af = thm1.data("Af", _k, _k, latex="A_f", description="filter state matrix")
Bf = thm1.data("Bf", _k, _ny, latex="B_f", description="filter input matrix")
Cf = thm1.data("Cf", _p, _k, latex="C_f", description="filter output matrix")
# error system (5): the paper's names, printed in the LaTeX of (10)-(11)
A_cl0 = thm1.define("A_cl0", BlockMatrix([[_d["A"], ZeroMatrix(_n, _k)], [_rbar * Bf * _d["C"], Af]]),
                    latex="A_{cl0}")
A_cl1 = thm1.define("A_cl1", BlockMatrix([[ZeroMatrix(_n, _n), ZeroMatrix(_n, _k)],
                                          [Bf * _d["C"], ZeroMatrix(_k, _k)]]), latex="A_{cl1}")
B_cl = thm1.define("B_cl", BlockMatrix([[_d["B"]], [Bf * _d["D"]]]), latex="B_{cl}")
C_cl = thm1.define("C_cl", BlockMatrix([[_d["L"], -Cf]]), latex="C_{cl}")
P = thm1.var("P", _n + _k, kind="symmetric", latex="P")
g1 = thm1.scalar("g", latex=r"\gamma^2", description="squared l2-l∞ level")
thm1.lmi("(10)", [
    [-P],
    [0, -I],
    [P * A_cl0, P * B_cl, -P],
    [_a * P * A_cl1, 0, 0, -_a * P],
])
thm1.lmi("(11)", [
    [-P],
    [C_cl, -g1 * I],
])
thm1.positive(P)
thm1.minimize(g1, performance=("gamma", sqrt(g1)))


def plant_1_with_filter_4(d, w, runs, rng):
    """Plant (1) and filter (4) from zero state, r(k) ~ Bernoulli(r̄) drawn per run and step.

    ``w``: K × m deterministic disturbance; returns e(k) = z(k) − ẑ(k), runs × K × p.
    """
    x = np.zeros((runs, d.A.shape[0]))
    xh = np.zeros((runs, d.Af.shape[0]))
    e = []
    for wk in w:
        r = (rng.random((runs, 1)) < d.rbar).astype(float)   # r(k) ∈ {0, 1}, Pr{r = 1} = r̄
        y = r * (x @ d.C.T) + wk @ d.D.T                       # y = r(k) C x + D w
        e.append(x @ d.L.T - xh @ d.Cf.T)                      # e = L x − Cf x̂
        x, xh = x @ d.A.T + wk @ d.B.T, xh @ d.Af.T + y @ d.Bf.T
    return np.stack(e, axis=1)


# error system (5): A_cl = A_cl0 + (r − r̄) A_cl1 with var(r) = a; index (6): energy to peak
thm1.error_system(ErrorSystem(A=A_cl0, B=B_cl, C=C_cl, noise=[{"A": A_cl1}], covariance=[_a]),
                  figure="energy_to_peak", design=("Af", "Bf", "Cf"), simulate=plant_1_with_filter_4)
thm1.example("paper-full-printed", {**PLANT, **FULL_FILTER}, params={"rbar": 0.8},
             printed={"gamma_bound": 0.3373}, printed_note=PRINTED_AT,
             description="the full-order filter the paper prints, analysed by Theorem 1")
thm1.example("paper-reduced-printed", {**PLANT, **REDUCED_FILTER}, params={"rbar": 0.8},
             printed={"gamma_bound": 2.0103}, printed_note=PRINTED_AT,
             description="the reduced-order filter the paper prints, analysed by Theorem 1")

# -- Theorem 2: analysis with a slack G (the step from Theorem 1 to Theorem 3) -----------
thm2 = Theorem("wang_l2linf.thm2", "Energy-to-peak analysis with a slack matrix G (Theorem 2)",
               Source(PAPER, "Theorem 2, (28)-(29)", CITATION),
               description="min γ² over P > 0 and G such that (28) and (29) hold for a given filter; "
                           "equivalent to Theorem 1 (the paper cites its ref. [9]).")
(_n2, _m2, _ny2, _p2, _k2), _d2, _rbar2, _a2 = _plant(thm2)
Af2 = thm2.data("Af", _k2, _k2, latex="A_f", description="filter state matrix")
Bf2 = thm2.data("Bf", _k2, _ny2, latex="B_f", description="filter input matrix")
Cf2 = thm2.data("Cf", _p2, _k2, latex="C_f", description="filter output matrix")
A_cl0_2 = thm2.define("A_cl0", BlockMatrix([[_d2["A"], ZeroMatrix(_n2, _k2)],
                                            [_rbar2 * Bf2 * _d2["C"], Af2]]), latex="A_{cl0}")
A_cl1_2 = thm2.define("A_cl1", BlockMatrix([[ZeroMatrix(_n2, _n2), ZeroMatrix(_n2, _k2)],
                                            [Bf2 * _d2["C"], ZeroMatrix(_k2, _k2)]]), latex="A_{cl1}")
B_cl2 = thm2.define("B_cl", BlockMatrix([[_d2["B"]], [Bf2 * _d2["D"]]]), latex="B_{cl}")
C_cl2 = thm2.define("C_cl", BlockMatrix([[_d2["L"], -Cf2]]), latex="C_{cl}")
P_2 = thm2.var("P", _n2 + _k2, kind="symmetric", latex="P")
G_2 = thm2.var("G", _n2 + _k2, _n2 + _k2, latex="G", description="slack matrix")
g2 = thm2.scalar("g", latex=r"\gamma^2", description="squared l2-l∞ level")
thm2.lmi("(28)", [
    [-P_2],
    [0, -I],
    [G_2.T * A_cl0_2, G_2.T * B_cl2, P_2 - G_2 - G_2.T],
    [_a2 * G_2.T * A_cl1_2, 0, 0, _a2 * (P_2 - G_2 - G_2.T)],
])
thm2.lmi("(29)", [
    [-P_2],
    [C_cl2, -g2 * I],
])
thm2.positive(P_2)
thm2.minimize(g2, performance=("gamma", sqrt(g2)))
thm2.example("paper-full-printed", {**PLANT, **FULL_FILTER}, params={"rbar": 0.8},
             printed={"gamma_bound": 0.3373}, printed_note=PRINTED_AT,
             description="the full-order filter the paper prints, analysed by Theorem 2")
# (10) => (28): G = P is one slack (the converse, (28) => (10), is the slack lemma of the paper's
# ref. [9]: P - G - G^T <= -G^T P^-1 G, an inequality that no identity check can state)
thm2.derived_from(thm1, "(10)", "(28)", substitute={G_2: P},
                  note="(28) at G = P is (10): the direction (10) => (28) of the equivalence")
thm2.derived_from(thm1, "(11)", "(29)", note="(29) is (11)")

# -- Theorem 3: synthesis -----------------------------------------------------------------
thm3 = Theorem("wang_l2linf.thm3", "Full- and reduced-order l2-l∞ filter synthesis (Theorem 3)",
               Source(PAPER, "Theorem 3, (30)-(32)", CITATION),
               description="min γ² subject to (30), (31), P1 > 0, P3 > 0; filter order k = columns of E.",
               designs="filter")
_synthesis(thm3, per_vertex=False, labels=("(30)", "(31)"))
thm3.example("paper-full", {**PLANT, "E": [[1.0, 0.0], [0.0, 1.0]]}, params={"rbar": 0.8},
             printed={"gamma": 0.3373, **FULL_FILTER}, printed_note=PRINTED_AT,
             description="full order, E = I2")
thm3.example("paper-reduced", {**PLANT, "E": [[1.0], [0.0]]}, params={"rbar": 0.8},
             printed={"gamma": 2.0103, **REDUCED_FILTER}, printed_note=PRINTED_AT,
             description="reduced order k = 1, E = [1; 0]")

# -- Corollary 1: polytopic synthesis ----------------------------------------------------
cor1 = Theorem("wang_l2linf.cor1", "Polytopic l2-l∞ filter synthesis (Corollary 1)",
               Source(PAPER, "Corollary 1, (36)-(38)", CITATION),
               description="(30)-(31) at every vertex with vertex-dependent P1i, P2i, P3i and common "
                           "V1, V2, V3, Âf, B̂f, Ĉf, γ.", designs="filter")
_synthesis(cor1, per_vertex=True, labels=("(37)", "(38)"))
cor1.example("paper-one-vertex", {"E": [[1.0, 0.0], [0.0, 1.0]]}, params={"rbar": 0.8},
             vertices=[dict(PLANT)],
             printed={"gamma": 0.3373}, printed_note="Theorem 3's printed γ: one vertex is Theorem 3",
             description="the paper's plant as a one-vertex polytope (must equal Theorem 3)")
cor1.example("two-vertex", {"E": [[1.0, 0.0], [0.0, 1.0]]}, params={"rbar": 0.8},
             vertices=[{**PLANT, "A": [[0.0, 0.3], [-0.25, 0.35]]},
                       {**PLANT, "A": [[0.0, 0.3], [-0.15, 0.45]]}],
             provenance="illustration", provenance_note="not from the paper: A's second row varied by ±0.05 around the paper's plant",
             expect="not certified",
             expect_note="vertex-wise: the analysis (Theorem 1, the filter fixed) is solved at each vertex with "
                         "its own Lyapunov matrix, which does not prove the level inside the polytope",
             description="not from the paper: A's second row varied by ±0.05 around the paper's plant")


# -- the proof of Theorem 3: congruence of (28)-(29) and the change of variables (33)-(34) ---
def _state_theorem3_proof(thm3: Theorem, source: Theorem, labels=("(30)", "(31)")):
    """(30) = T1ᵀ (28) T1, T1 = diag(J, I, J, J), and (31) = T2ᵀ (29) T2, T2 = diag(J, I), with
    G = [[V1, V3 M⁻¹G22], [M Eᵀ, G22]] (33), J = diag(I, G22⁻¹M), JᵀPJ = [[P1, P2], [P2ᵀ, P3]],
    V2 = MᵀG22⁻¹M (34), Âf = MᵀAf G22⁻¹M, B̂f = MᵀBf, Ĉf = Cf G22⁻¹M; recovery (32) returns the
    filter in the coordinates x̂' = (G22⁻¹M)⁻¹x̂: Af' = S⁻¹AfS, Bf' = S⁻¹Bf, Cf' = CfS, S = G22⁻¹M."""
    n, k = source.dims["n"], source.dims["k"]
    v = {name: decl.symbol for name, decl in thm3.var_decl.items()}
    E = thm3.data_decl["E"].symbol
    src = {name: decl.symbol for name, decl in {**source.var_decl, **source.data_decl}.items()}
    M = thm3.auxiliary("M", k, k, description="invertible k x k of the slack structure (33)")
    G22 = thm3.auxiliary("G22", k, k, latex="G_{22}", description="invertible k x k block of G (33)")
    S = G22.I * M
    J = BlockMatrix([[Identity(n), ZeroMatrix(n, k)], [ZeroMatrix(k, n), S]])
    J_inv = BlockMatrix([[Identity(n), ZeroMatrix(n, k)], [ZeroMatrix(k, n), M.I * G22]])
    Af, Bf, Cf = src["Af"], src["Bf"], src["Cf"]
    substitute = {
        src["G"]: BlockMatrix([[v["V1"], v["V3"] * M.I * G22], [M * E.T, G22]]),          # (33)
        src["P"]: J_inv.T * BlockMatrix([[v["P1"], v["P2"]], [v["P2"].T, v["P3"]]]) * J_inv,  # (34)
        v["V2"]: M.T * G22.I * M,                                                            # (34)
        v["Af_hat"]: M.T * Af * G22.I * M, v["Bf_hat"]: M.T * Bf, v["Cf_hat"]: Cf * G22.I * M,
    }
    recovers = {"Af": S.I * Af * S, "Bf": S.I * Bf, "Cf": Cf * S}
    thm3.derived_from(source, "(28)", labels[0], congruence=[J, I, J, J], substitute=substitute,
                      recovers=recovers, note="proof of Theorem 3: T1 = diag(J, I, J, J) on (28)")
    thm3.derived_from(source, "(29)", labels[1], congruence=[J, I], substitute=substitute,
                      recovers=recovers, note="proof of Theorem 3: T2 = diag(J, I) on (29)")


_state_theorem3_proof(thm3, thm2)
_state_theorem3_proof(cor1, thm2, labels=("(37)", "(38)"))

THEOREMS = [thm1, thm2, thm3, cor1]
