"""Li, Wang, Sun: H∞ filter design for networked systems with one-step random delays and
multiple packet dropouts (Acta Automatica Sinica 40(1):155–160, 2014).

Paper: Li Xiu-Ying, Wang Jin-Yu, Sun Shu-Li; readings taken, derivations and results in
``docs/reproductions/001.md``.

Plant (1): x_{k+1} = A x_k + B w_k,  ỹ_k = C1 x_k + C2 w_k,  z_k = D1 x_k + D2 w_k.
Received measurement (2), with independent Bernoulli ξ1,k, ξ2,k (Pr{ξi = 1} = ξ̄i):
y_k = ξ1,k ỹ_k + (1−ξ1,k)(1−ξ1,k−1)ξ2,k ỹ_{k−1} + (1−ξ1,k)[1 − (1−ξ1,k−1)ξ2,k] y_{k−1}.
With ϑ1,k = ξ1,k, ϑ2,k = (1−ξ1,k)ξ2,k+1 (3), the augmented state X_k = [x_k; Y_{k−1}; y_{k−1}]
obeys (5) with Φ̃_k = Φ0 + ϑ1Φ1 + ϑ2Φ2, Γ̃_k = Γ0 + ϑ1Γ1 + ϑ2Γ2, H̃_k = H0 + ϑ1H1 (built below
from the plant data as the paper defines them).  Filter (6): X̂_{k+1} = Af X̂_k + Bf y_k,
ẑ_k = Cf X̂_k + Df y_k.

* ``li_delay_dropout.thm1``  Theorem 1, (9): analysis with the filter fixed.  (9) contains
  N = P⁻¹; the form solved here is its congruence with diag(I, I, P, P, P, P, I, I), which is
  linear in (P, γ²) and exactly equivalent (docs/reproductions/001.md, "The σ weights and the
  LMI form of (9)").
* ``li_delay_dropout.thm2``  Theorem 2, (15) and problem (20): min β = γ² over X, Z, Âf, B̂f,
  Ĉf, D̂f with Λ = [X Z; Z Z]; recovery Af = R⁻¹ÂfZ⁻¹S⁻ᵀ, Bf = R⁻¹B̂f, Cf = ĈfZ⁻¹S⁻ᵀ, Df = D̂f
  with R Sᵀ = I − XZ⁻¹ (R, S from the library's balanced split).

Readings taken (docs/reproductions/001.md): the σi are square roots; the means ϑ̄1 = ξ̄1,
ϑ̄2 = (1 − ξ̄1)ξ̄2; Θ_B̄ carries ϑ̄1 B̂f C2 (the mean of B̃_k); the tilde-means of (9) are the
bar-means.  The measurement y may be rescaled exactly (y = s y'): C1 and C2 produce y, the
filter's Bf and Df consume it; the augmentation then changes by the similarity diag(I, I/s, I/s),
so feasibility and γ are unchanged.
"""
from lmidsl import ErrorSystem, I, Source, Theorem, rs_split
from .simulation import model_2_with_filter_6
from sympy import BlockMatrix, Identity, ZeroMatrix, sqrt

PAPER = "Li, Wang, Sun 2014, random delays and dropouts"
CITATION = ("Li, Wang, Sun, H∞ filter design for networked systems with one-step random delays "
            "and multiple packet dropouts, Acta Automatica Sinica 40(1):155-160, 2014")

# Section 4: the UPS model of the paper's ref. [14]
UPS = {
    "A": [[0.9226, -0.6330, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    "B": [[1.0], [0.0], [0.0]],
    "C1": [[23.737, 20.287, 0.0]],
    "C2": [[0.3]],
    "D1": [[-0.3, 0.1, 0.0]],
    "D2": [[0.1]],
}
PRINTED_AT = "Section 4 (simulation example)"


AUGMENTED_LATEX = {"Phi0": r"\Phi_0", "Phi1": r"\Phi_1", "Phi2": r"\Phi_2", "Gamma0": r"\Gamma_0",
                   "Gamma1": r"\Gamma_1", "Gamma2": r"\Gamma_2", "H0": "H_0", "H1": "H_1",
                   "D1bar": r"\bar{D}_1", "Phibar": r"\bar{\Phi}", "Gammabar": r"\bar{\Gamma}",
                   "Hbar": r"\bar{H}"}


def _model(thm: Theorem):
    """Plant (1), probabilities, the weights of Theorem 1 and the augmented matrices of (5)."""
    n, r, p, m = thm.dim("n r p m")
    A = thm.data("A", n, n, description="plant state matrix")
    B = thm.data("B", n, p, description="disturbance input")
    C1 = thm.data("C1", r, n, latex="C_1", description="measurement matrix")
    C2 = thm.data("C2", r, p, latex="C_2", description="measurement disturbance input")
    D1 = thm.data("D1", m, n, latex="D_1", description="estimated output")
    D2 = thm.data("D2", m, p, latex="D_2", description="estimated-output disturbance input")
    xi1 = thm.param("xi1", latex=r"\bar{\xi}_1", domain=(0.0, 1.0), default=0.7,
                    description="Pr{ξ1,k = 1}: measurement received on time")
    xi2 = thm.param("xi2", latex=r"\bar{\xi}_2", domain=(0.0, 1.0), default=0.8,
                    description="Pr{ξ2,k = 1}: a late measurement is received one step late")
    th1 = thm.derived("th1", xi1, latex=r"\bar{\vartheta}_1", description="E ϑ1,k (Remark 3)")
    th2 = thm.derived("th2", (1 - xi1) * xi2, latex=r"\bar{\vartheta}_2",
                      description="E ϑ2,k (Remark 3)")
    s1 = thm.derived("sigma1", sqrt(xi1 * (1 - xi1) * (1 - xi2)), latex=r"\sigma_1")
    s2 = thm.derived("sigma2", sqrt((1 - xi1) ** 2 * (1 - xi2) * xi2), latex=r"\sigma_2")
    s3 = thm.derived("sigma3", sqrt(xi1 * xi2 * (1 - xi1)), latex=r"\sigma_3")
    s4 = thm.derived("sigma4", sqrt(xi1 * (1 - xi1)), latex=r"\sigma_4")

    Onr, Orn, Orr, Ir = ZeroMatrix(n, r), ZeroMatrix(r, n), ZeroMatrix(r, r), Identity(r)
    Ozero = ZeroMatrix(n, n)
    aug = dict(
        Phi0=BlockMatrix([[A, Onr, Onr], [Orn, Ir, Orr], [Orn, Ir, Orr]]),
        Phi1=BlockMatrix([[Ozero, Onr, Onr], [C1, -Ir, Orr], [C1, -Ir, Orr]]),
        Phi2=BlockMatrix([[Ozero, Onr, Onr], [C1, -Ir, Orr], [Orn, Orr, Orr]]),
        Gamma0=BlockMatrix([[B], [ZeroMatrix(r, p)], [ZeroMatrix(r, p)]]),
        Gamma1=BlockMatrix([[ZeroMatrix(n, p)], [C2], [C2]]),
        Gamma2=BlockMatrix([[ZeroMatrix(n, p)], [C2], [ZeroMatrix(r, p)]]),
        H0=BlockMatrix([[Orn, Ir, Orr]]),
        H1=BlockMatrix([[C1, -Ir, Orr]]),
        D1bar=BlockMatrix([[D1, ZeroMatrix(m, r), ZeroMatrix(m, r)]]),
    )
    aug["Phibar"] = aug["Phi0"] + th1 * aug["Phi1"] + th2 * aug["Phi2"]
    aug["Gammabar"] = aug["Gamma0"] + th1 * aug["Gamma1"] + th2 * aug["Gamma2"]
    aug["Hbar"] = aug["H0"] + th1 * aug["H1"]
    # named as the paper names them, so the LaTeX of the LMIs reads like (9) and (15)
    for name, tex in AUGMENTED_LATEX.items():
        aug[name] = thm.define(name, aug[name], latex=tex)
    dims = dict(n=n, r=r, p=p, m=m, na=n + 2 * r)
    plant = dict(A=A, B=B, C1=C1, C2=C2, D1=D1, D2=D2)
    weights = dict(th1=th1, th2=th2, s1=s1, s2=s2, s3=s3, s4=s4)
    return dims, plant, weights, aug


# -- Theorem 1: analysis (9), in the congruent form linear in P -----------------------------
thm1 = Theorem("li_delay_dropout.thm1", "Mean-square H∞ analysis with the filter fixed (Theorem 1)",
               Source(PAPER, "Theorem 1, (9)", CITATION),
               description="min γ² over P > 0 such that (9) holds; (9) after the congruence "
                           "diag(I, I, P, P, P, P, I, I), which removes N = P⁻¹.")
_d, _pl, _w, _aug = _model(thm1)
_na, _r, _m = _d["na"], _d["r"], _d["m"]
Af = thm1.data("Af", _na, _na, latex="A_f", description="filter state matrix")
Bf = thm1.data("Bf", _na, _r, latex="B_f", description="filter input matrix")
Cf = thm1.data("Cf", _m, _na, latex="C_f", description="filter output matrix")
Df = thm1.data("Df", _m, _r, latex="D_f", description="filter feedthrough")
_Z = ZeroMatrix(_na, _na)
A0 = BlockMatrix([[_aug["Phi0"], _Z], [Bf * _aug["H0"], Af]])
A1 = BlockMatrix([[_aug["Phi1"], _Z], [Bf * _aug["H1"], _Z]])
A2 = BlockMatrix([[_aug["Phi2"], _Z], [ZeroMatrix(_na, _na), _Z]])
B0 = BlockMatrix([[_aug["Gamma0"]], [ZeroMatrix(_na, _d["p"])]])
B1 = BlockMatrix([[_aug["Gamma1"]], [Bf * _pl["C2"]]])
B2 = BlockMatrix([[_aug["Gamma2"]], [ZeroMatrix(_na, _d["p"])]])
G0 = BlockMatrix([[_aug["D1bar"] - Df * _aug["H0"], -Cf]])
G1 = BlockMatrix([[-Df * _aug["H1"], ZeroMatrix(_m, _na)]])
F0 = _pl["D2"]
F1 = -Df * _pl["C2"]
Abar = A0 + _w["th1"] * A1 + _w["th2"] * A2
Bbar = B0 + _w["th1"] * B1 + _w["th2"] * B2
Gbar = G0 + _w["th1"] * G1
Fbar = F0 + _w["th1"] * F1
P = thm1.var("P", 2 * _na, kind="symmetric", latex="P", description="Lyapunov matrix of η = [X; X̂]")
g1 = thm1.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
thm1.lmi("(9)", [
    [-P],
    [0, -g1 * I],
    [P * Abar, P * Bbar, -P],
    [_w["s1"] * P * A1, _w["s1"] * P * B1, 0, -P],
    [_w["s2"] * P * A2, _w["s2"] * P * B2, 0, 0, -P],
    [_w["s3"] * P * (A1 - A2), _w["s3"] * P * (B1 - B2), 0, 0, 0, -P],
    [Gbar, Fbar, 0, 0, 0, 0, -I],
    [_w["s4"] * G1, _w["s4"] * F1, 0, 0, 0, 0, 0, -I],
], description="(9) congruent with diag(I, I, P, P, P, P, I, I)")
thm1.positive(P)

# (9) as printed, with N = P⁻¹ on the diagonal: not an LMI in P, so not solved (and not listed);
# it is the source of the congruence above, checked by `lmidsl derive-check li_delay_dropout.thm1`
printed9 = Theorem("li_delay_dropout.thm1_printed", "Theorem 1, (9) as printed (N = P⁻¹)",
                   Source(PAPER, "Theorem 1, (9)", CITATION),
                   description="(9) with N as a symbol; thm1 is its congruence with diag(I, I, P, P, P, P, I, I)")
N9 = printed9.var("N", 2 * _na, kind="symmetric", latex="N", description="N = P⁻¹")
printed9.lmi("(9)", [
    [-P],
    [0, -g1 * I],
    [Abar, Bbar, -N9],
    [_w["s1"] * A1, _w["s1"] * B1, 0, -N9],
    [_w["s2"] * A2, _w["s2"] * B2, 0, 0, -N9],
    [_w["s3"] * (A1 - A2), _w["s3"] * (B1 - B2), 0, 0, 0, -N9],
    [Gbar, Fbar, 0, 0, 0, 0, -I],
    [_w["s4"] * G1, _w["s4"] * F1, 0, 0, 0, 0, 0, -I],
])
thm1.derived_from(printed9, "(9)", "(9)", congruence=[I, I, P, P, P, P, I, I], substitute={N9: P.I},
                  note="the printed (9) (N = P⁻¹) and the form solved: congruence diag(I, I, P, P, P, P, I, I)")
thm1.minimize(g1, performance=("gamma", sqrt(g1)))
thm1.scale_signal("y", rows=("C1", "C2"), cols=("Bf", "Df"),
                  description="received measurement y = s·y' (exact: similarity of the augmentation)")
# error system (7) with the centred noises ν_i = ϑ_i − ϑ̄_i: (ϑ1, ϑ2) ∈ {(1,0), (0,1), (0,0)}, i.i.d.
# over k, so var ϑ_i = ϑ̄_i(1 − ϑ̄_i) and cov(ϑ1, ϑ2) = −ϑ̄1ϑ̄2 (ϑ1ϑ2 = 0; Remark 3).  Index: H∞
_t1, _t2 = _w["th1"], _w["th2"]
thm1.error_system(ErrorSystem(A=Abar, B=Bbar, C=Gbar, D=Fbar,
                              noise=[{"A": A1, "B": B1, "C": G1, "D": F1}, {"A": A2, "B": B2}],
                              covariance=[[_t1 * (1 - _t1), -_t1 * _t2], [-_t1 * _t2, _t2 * (1 - _t2)]]),
                  figure="h_infinity", design=("Af", "Bf", "Cf", "Df"), simulate=model_2_with_filter_6)

# -- Theorem 2: synthesis (15), problem (20) --------------------------------------------------
thm2 = Theorem("li_delay_dropout.thm2", "H∞ filter synthesis with random delays and dropouts (Theorem 2)",
               Source(PAPER, "Theorem 2, (15), (20)", CITATION),
               description="min β = γ² subject to (15); filter from Af = R⁻¹ÂfZ⁻¹S⁻ᵀ, Bf = R⁻¹B̂f, "
                           "Cf = ĈfZ⁻¹S⁻ᵀ, Df = D̂f with R Sᵀ = I − XZ⁻¹.", designs="filter")
d, pl, w, aug = _model(thm2)
na, r, m = d["na"], d["r"], d["m"]
X = thm2.var("X", na, kind="symmetric", latex="X")
Z = thm2.var("Z", na, kind="symmetric", latex="Z")
Af_hat = thm2.var("Af_hat", na, na, latex=r"\hat{A}_f")
Bf_hat = thm2.var("Bf_hat", na, r, latex=r"\hat{B}_f")
Cf_hat = thm2.var("Cf_hat", m, na, latex=r"\hat{C}_f")
Df_hat = thm2.var("Df_hat", m, r, latex=r"\hat{D}_f")
beta = thm2.scalar("beta", latex=r"\beta", description="β = γ², squared H∞ level")
Lam = thm2.structured("Lambda", [[X, Z], [Z, Z]], latex=r"\Lambda", symmetric=True)

Phibar, Hbar, Gammabar = aug["Phibar"], aug["Hbar"], aug["Gammabar"]
Phi1, Phi2, H1 = aug["Phi1"], aug["Phi2"], aug["H1"]
Gamma1, Gamma2 = aug["Gamma1"], aug["Gamma2"]
C2, D2, D1bar = pl["C2"], pl["D2"], aug["D1bar"]
th1, s1, s2, s3, s4 = w["th1"], w["s1"], w["s2"], w["s3"], w["s4"]


def _theta_A(top, bottom, extra=None):
    """[[top, top (+ extra)], [bottom, bottom]] — the shape of every Θ_A block of (15)."""
    return BlockMatrix([[top, top + extra if extra is not None else top], [bottom, bottom]])


Theta_Abar = thm2.define("Theta_Abar", _theta_A(X * Phibar + Bf_hat * Hbar, Z * Phibar, Af_hat),
                         latex=r"\Theta_{\bar A}")
Theta_A1 = thm2.define("Theta_A1", s1 * _theta_A(X * Phi1 + Bf_hat * H1, Z * Phi1), latex=r"\Theta_{A_1}")
Theta_A2 = thm2.define("Theta_A2", s2 * _theta_A(X * Phi2, Z * Phi2), latex=r"\Theta_{A_2}")
Theta_A12 = thm2.define("Theta_A12", s3 * _theta_A(X * (Phi1 - Phi2) + Bf_hat * H1, Z * (Phi1 - Phi2)),
                        latex=r"\Theta_{A_{1,2}}")
Theta_Bbar = thm2.define("Theta_Bbar", BlockMatrix([[X * Gammabar + th1 * Bf_hat * C2], [Z * Gammabar]]),
                         latex=r"\Theta_{\bar B}")
Theta_B1 = thm2.define("Theta_B1", s1 * BlockMatrix([[X * Gamma1 + Bf_hat * C2], [Z * Gamma1]]),
                       latex=r"\Theta_{B_1}")
Theta_B2 = thm2.define("Theta_B2", s2 * BlockMatrix([[X * Gamma2], [Z * Gamma2]]), latex=r"\Theta_{B_2}")
Theta_B12 = thm2.define("Theta_B12", s3 * BlockMatrix([[X * (Gamma1 - Gamma2) + Bf_hat * C2],
                                                      [Z * (Gamma1 - Gamma2)]]), latex=r"\Theta_{B_{1,2}}")
Theta_Gbar = thm2.define("Theta_Gbar", BlockMatrix([[D1bar - Df_hat * Hbar, D1bar - Df_hat * Hbar - Cf_hat]]),
                         latex=r"\Theta_{\bar G}")
Theta_G1 = thm2.define("Theta_G1", s4 * BlockMatrix([[-Df_hat * H1, -Df_hat * H1]]), latex=r"\Theta_{G_1}")
Theta_Fbar = thm2.define("Theta_Fbar", D2 - th1 * Df_hat * C2, latex=r"\Theta_{\bar F}")
Theta_F1 = thm2.define("Theta_F1", -s4 * Df_hat * C2, latex=r"\Theta_{F_1}")

thm2.lmi("(15)", [
    [-Lam],
    [0, -beta * I],
    [Theta_Abar, Theta_Bbar, -Lam],
    [Theta_A1, Theta_B1, 0, -Lam],
    [Theta_A2, Theta_B2, 0, 0, -Lam],
    [Theta_A12, Theta_B12, 0, 0, 0, -Lam],
    [Theta_Gbar, Theta_Fbar, 0, 0, 0, 0, -I],
    [Theta_G1, Theta_F1, 0, 0, 0, 0, 0, -I],
], description="(15) with γ² = β; Λ1 = diag(−Λ, −Λ, −Λ, −Λ), Λ2 = diag(−I, −I) written out")
thm2.minimize(beta, performance=("gamma", sqrt(beta)))
R, S = thm2.factor("R S", rs_split, Identity(na) - X * Z.I,
                   description="R Sᵀ = I − XZ⁻¹ (balanced split, lmidsl.numeric.factorization)")
thm2.recover(Af=R.I * Af_hat * Z.I * S.I.T, Bf=R.I * Bf_hat, Cf=Cf_hat * Z.I * S.I.T, Df=Df_hat)
thm2.certified_by("li_delay_dropout.thm1", design=("Af", "Bf", "Cf", "Df"), gamma_tolerance=1e-2)
thm2.scale_signal("y", rows=("C1", "C2"), recovered_cols=("Bf", "Df"),
                  description="received measurement y = s·y' (exact: similarity of the augmentation)")
thm2.well_conditioned(Z, X - Z)
thm2.example("paper", dict(UPS), params={"xi1": 0.7, "xi2": 0.8},
             printed={"gamma": 0.3813}, printed_note=PRINTED_AT,
             description="UPS model, on time 0.7, one-step delay 0.072, loss 0.228")


def _state_theorem2_proof():
    """The proof of Theorem 2, (16)-(19): with RSᵀ = I − XZ⁻¹, Y = Z⁻¹, Σ1 = [[X, I], [Rᵀ, 0]],
    Σ2 = [[I, Y], [0, Sᵀ]], P = Σ1Σ2⁻¹, the congruence diag(Σ2, I, Σ1, Σ1, Σ1, Σ1, I, I) of the
    printed (9) is (19) = (18), and diag(I, Z) on each Π block turns (18) into (15), with
    Âf = RAfSᵀZ, B̂f = RBf, Ĉf = CfSᵀZ, D̂f = Df (so the recovery of Theorem 2 is the identity)."""
    I_na, O_na = Identity(na), ZeroMatrix(na, na)
    R_ = thm2.auxiliary("R", na, na, description="R of RSᵀ = I − XZ⁻¹ (17), drawn at random")
    Y = Z.I
    S_ = (I_na - Y * X) * R_.I.T                       # then R Sᵀ = I − XZ⁻¹
    Sigma1 = BlockMatrix([[X, I_na], [R_.T, O_na]])
    Sigma2 = BlockMatrix([[I_na, Y], [O_na, S_.T]])
    D = BlockMatrix([[I_na, O_na], [O_na, Z]])
    substitute = {P: Sigma1 * Sigma2.I, N9: (Sigma1 * Sigma2.I).I,
                  Af_hat: R_ * Af * S_.T * Z, Bf_hat: R_ * Bf, Cf_hat: Cf * S_.T * Z, Df_hat: Df,
                  beta: g1, R: R_, S: S_}
    T1, T2 = Sigma2 * D, Sigma1 * D
    thm2.derived_from(printed9, "(9)", "(15)", congruence=[T1, I, T2, T2, T2, T2, I, I],
                      substitute=substitute,
                      note="proof of Theorem 2: (9) -> (19) by diag(Σ2, I, Σ1, ...), (18) -> (15) by diag(I, Z)")


_state_theorem2_proof()

THEOREMS = [thm1, thm2]
