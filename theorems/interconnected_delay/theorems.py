"""Robust H∞ filtering for uncertain interconnected time-delay systems (seed 004).

Paper: "Robust H-infinity filtering for uncertain interconnected time-delay systems" (authors lost
in the OCR; Shanghai Jiao Tong University and Yanshan University).  The OCR is badly garbled: the
statement below is the reconstruction given in ``docs/reproductions/004.md`` ("Reconstruction of
the statement"), whose tags [READ] / [READ-PARTIAL] / [RECONSTRUCTED] / [GUESS] are repeated here.

Continuous time, N subsystems (1) with norm-bounded uncertainty (2)::

    ẋ_i = (A_i + H_i1 F_i E_i) x_i + Σ_j (A_ij + M_i ΔF_ij N_ij) x_j(t − τ_ij) + B_i w_i
    y_i = (C_i + H_i2 F_i E_i) x_i + D_i w_i,     z_i = L_i x_i,     FᵢᵀFᵢ ≤ I, ΔF_ijᵀΔF_ij ≤ I

and one decentralised filter (3) per subsystem: x̂̇_i = A_fi x̂_i + B_fi y_i, ẑ_i = L_fi x̂_i.

* ``interconnected_delay.thm1``  Theorem 1 in its S-procedure form (15), the filters fixed:
  min Σρ_i (ρ_i = γ_i²) over P_i > 0, Q_ij > 0, ε_i1, ε_i2.  [(8) READ-PARTIAL, (15) completed
  by RECONSTRUCTION, docs/reproductions/004.md.]
* ``interconnected_delay.thm2``  Theorem 2: LMIs (18) for every i, (17) X_i > 0, Y_i − X_i > 0,
  problem (26) min Σρ_i; recovery (25) A_fi = (X_i − Y_i)⁻¹Â_fi, B_fi = (X_i − Y_i)⁻¹B̂_fi,
  L_fi = L̂_fi.  [(18) READ-PARTIAL / RECONSTRUCTED, (25) READ, docs/reproductions/004.md.]
* ``...thm1b`` / ``...thm2b``: "Variant B" of (15) — independent ΔF_ij with one
  multiplier ε_ij per coupling, instead of the paper's single ε_i1 column (Variant A, exact for a
  common ΔF_i(t) over j).
* ``...thm2_r19`` / ``...thm1_r19``: Variant A plus the [GUESS] reading (19) Y_i ≤ ρ_i R_i
  (analysis: U_i P_i U_iᵀ ≤ ρ_i R_i) of the unresolved condition (9)/(19), docs/reproductions/004.md.  The
  default theorems omit (19), i.e. zero initial conditions.

The N LMIs are coupled through the Krasovskii weights: subsystem i's (1,1) block carries
S_i = Σ_j Q_ji, its delay blocks Q_ij.  The uncertainty is removed once, by the library's
S-procedure helper (:mod:`lmidsl.symbolic.sprocedure`): He(PH̄ F Ē) with ε_i2 in the "diag" form
(ε_i2 ĒᵀĒ on the diagonal, column PH̄), He(PM̄ ΔF [N_i1 … N_iN]) with ε_i1 in the "columns"
form (columns ε_i1 Nᵀ and PM̄) — the block layout of (15) and (18).

The theorems are stated for any number of subsystems N (:class:`lmidsl.theorem.family.SubsystemFamily`):
N is the parameter ``N`` if given, else the number of ``A_<i>`` in the data.  Data names: ``A_i``, ``A_i_j`` (= A_ij), ``B_i``, ``C_i``, ``D_i``, ``L_i``,
``HA_i`` (= H_i1, ΔA part), ``HC_i`` (= H_i2, ΔC part), ``E_i``, ``M_i``, ``N_i_j``; delays
``tau_i_j`` are parameters used by the simulation only (the conditions are delay-independent).

The certificate (docs/reproductions/004.md, "What is proved") is the joint bound
Σ‖z̃_i‖² < Σγ_i²‖w_i‖²: besides the analysis LMI, a frequency sweep over the uncertainty
vertices and a time simulation of the delayed network (:mod:`.network`) test it.
"""
from functools import reduce
from operator import add

from sympy import BlockMatrix, Identity, ZeroMatrix, sqrt

from lmidsl import Family, He, I, NormBounded, Source, SubsystemFamily, Theorem, member_label, reported_agree, sprocedure
from .network import FrequencySweepCheck, SimulationCheck

PAPER = "Interconnected time-delay systems (SJTU / Yanshan)"
CITATION = "Robust H-infinity filtering for uncertain interconnected time-delay systems (SJTU / Yanshan)"
NOTES = "docs/reproductions/004.md"

# -- Section 4 example, with provenance (docs/reproductions/004.md) -------------------------------
READ = {
    # [READ] uncertainty data; E_i printed as "E11", "E21" (docs/reproductions/004.md)
    "E_1": [[0.1, 0.0]], "E_2": [[0.0, -0.02]],
    # [READ] printed as rows; n_i × r_i forces columns
    "M_1": [[0.2], [0.01]], "M_2": [[0.01], [0.03]],
    "N_1_1": [[-0.2, 0.01]], "N_1_2": [[0.03, 0.01]],
    "N_2_1": [[0.1, 0.1]], "N_2_2": [[0.3, 0.01]],
    "D_1": [[0.4]], "D_2": [[0.4]],
    "L_1": [[1.0, 1.0]], "L_2": [[1.0, 1.0]],
    "HC_1": [[0.02]], "HC_2": [[0.01]],           # H_12, H_22: the ΔC parts
}
R_READ = {"R_1": [[0.0003, 0.0], [0.0, 0.0033]], "R_2": [[0.0028, 0.0], [0.0, 0.0007]]}  # [READ]
GUESSED = {
    "A_1": [[-2.0, 8.0], [-7.0, -8.0]],           # [GUESS] rounded from the printed A_f1
    "A_2": [[-5.0, 2.0], [-2.0, -1.0]],           # [GUESS] rounded from the printed A_f2 row 1
    "A_1_1": [[0.1, 0.0], [0.0, 0.1]],            # [GUESS]
    "A_1_2": [[0.1, 0.0], [0.0, 0.8]],            # [GUESS] fragment "A12 = [... 0 0.8]"
    "A_2_1": [[-0.2, 0.1], [0.0, 0.1]],           # [GUESS] fragment "-0.21 0.1"
    "A_2_2": [[0.1, 0.0], [0.0, 0.1]],            # [GUESS]
    "B_1": [[1.0], [0.0]], "B_2": [[0.0], [1.0]],  # [GUESS]
    "C_1": [[-0.1, 1.0]],                         # [GUESS] fragment "[- 0. .. 1 1]"
    "C_2": [[1.0, 0.1]],                          # [GUESS]
    "HA_1": [[0.1], [0.0]], "HA_2": [[0.0], [0.1]],  # [GUESS] H_11, H_21 (ΔA parts) lost
}
TAU_GUESSED = {"tau_1_1": 0.3, "tau_1_2": 0.5, "tau_2_1": 0.4, "tau_2_2": 0.2}  # [GUESS], simulation only
GUESSED_NAMES = sorted(GUESSED) + sorted(TAU_GUESSED)
PAPER_DATA = {**READ, **GUESSED}

PRINTED_GAMMA = 0.037  # "y i = 0.037", read as sqrt(Σγ_i²) (docs/reproductions/004.md); NOT comparable, see below
PRINTED_FILTER = {     # legible parts of the printed filters (docs/reproductions/004.md)
    "Af_1": [[-1.6321, 8.1306], [-6.8832, -7.7953]],   # label lost, inferred from position
    "Lf_1": [[0.0909, 0.0909]], "Lf_2": [[0.0833, 0.0833]],
}
PRINTED_NOTE = (
    "Section 4 prints A_f1, the first row of A_f2 = [-4.8719 2.0034], B_f1(2) = -0.0008, one entry "
    "2.7897 of B_f2, L_f1 = [0.0909 0.0909], L_f2 = [0.0833 0.0833] and 'y i = 0.037' (read as "
    "sqrt(sum gamma_i^2)).  NOT comparable: A_i, A_ij, B_i, C_i, H_i1 and the delays are GUESSED "
    "(lost in the OCR), so no computed number can confirm or refute the printed ones; filters "
    "compare only by transfer function (docs/reproductions/004.md).")
DESCRIPTION = (
    "Section 4 data as reconstructed in docs/reproductions/004.md.  Paper's values [READ]: E_i, M_i, N_ij, D_i, "
    "L_i, H_i2 (HC_i), R_i.  GUESSED (lost in the OCR): " + ", ".join(GUESSED_NAMES) + ".")


def _sum(terms):
    return reduce(add, terms)


def _plant(thm: Theorem, N: int):
    """Dimensions, data of (1)–(2) and the delays for N subsystems."""
    fam = Family(thm, N)
    n, m, p, q, k, r = fam.dims("n m p q k r")
    ni = lambda i, *_: n[i]  # noqa: E731
    d = dict(
        A=fam.data("A", ni, ni, description="subsystem state matrix"),
        Ad=fam.data("A", ni, lambda i, j: n[j], pairs=True, latex="A_{{i}{j}}",
                    description="delayed coupling from x_j(t - tau_ij)"),
        B=fam.data("B", ni, lambda i: m[i], description="disturbance input"),
        C=fam.data("C", lambda i: p[i], ni, description="measurement"),
        D=fam.data("D", lambda i: p[i], lambda i: m[i], description="measurement noise input"),
        L=fam.data("L", lambda i: q[i], ni, description="signal to estimate"),
        HA=fam.data("HA", ni, lambda i: k[i], latex="H_{{i}1}", description="ΔA_i = H_i1 F_i E_i"),
        HC=fam.data("HC", lambda i: p[i], lambda i: k[i], latex="H_{{i}2}",
                    description="ΔC_i = H_i2 F_i E_i"),
        E=fam.data("E", lambda i: k[i], ni, description="uncertainty output, F_i is k_i x k_i"),
        M=fam.data("M", ni, lambda i: r[i], description="ΔA_ij = M_i ΔF_ij N_ij"),
        N=fam.data("N", lambda i, j: r[i], lambda i, j: n[j], pairs=True, latex="N_{{i}{j}}",
                   description="coupling uncertainty output"),
    )
    thm.param("N", domain=(N, N), default=N, description="number of subsystems")
    fam.param("tau", pairs=True, latex=r"\tau_{{i}{j}}", domain=(0.0, 1e6),
              description="delay (simulation only: the conditions are delay-independent)")
    return fam, (n, m, p, q, k, r), d


def _coupling_terms(fam, i, H, eps1, zeros_after, variant, N_ij):
    """He(H ΔF N) for the couplings of subsystem i, in the "columns" form of (15)/(18).

    Variant A: one ΔF_i for every j, E = [0 0 | N_i1 … N_iN | 0 …], multiplier ε_i1.
    Variant B: one term per j with its own ε_ij.
    """
    lead = [0] * (len(H) - len(fam) - zeros_after)
    tail = [0] * zeros_after
    if variant == "A":
        return [NormBounded(H=H, E=lead + [N_ij[i, j] for j in fam] + tail, eps=eps1[i],
                            form="columns", name=f"coupling {i}")]
    return [NormBounded(H=H, E=lead + [N_ij[i, j] if jj == j else 0 for jj in fam] + tail,
                        eps=eps1[i, j], form="columns", name=f"coupling {i}{j}") for j in fam]


CONDITION19 = {          # [GUESS] readings of the illegible (9)/(19) (docs/reproductions/004.md): U_i P_i U_iᵀ = Y_i ≤ ...
    "rhoR": lambda rho, R: rho * R,            # the natural reading: H∞ index with transients x_i(0)ᵀR_i x_i(0)
    "R": lambda rho, R: R,
    "rhoRinv": lambda rho, R: rho * R.I,
}


def _bound19(form, rho, R):
    return CONDITION19[form](rho, R)


def _objective(thm, fam, rho):
    """Problem (26): min Σρ_i, reported as sqrt(Σγ_i²), with every γ_i = sqrt(ρ_i)."""
    thm.minimize(_sum(rho[i] for i in fam), performance=("gamma", sqrt(_sum(rho[i] for i in fam))))
    thm.report(**{f"gamma_{i}": sqrt(rho[i]) for i in fam})


def _multipliers(fam, variant):
    eps2 = fam.scalar("eps2", latex=r"\varepsilon_{{i}2}", nonneg=True,
                      description="S-procedure multiplier of F_i (ΔA_i, ΔC_i)")
    if variant == "A":
        eps1 = fam.scalar("eps1", latex=r"\varepsilon_{{i}1}", nonneg=True,
                          description="S-procedure multiplier of the coupling uncertainty")
    else:
        eps1 = fam.scalar("eps1", pairs=True, latex=r"\varepsilon_{{i}{j}}", nonneg=True,
                          description="S-procedure multiplier of ΔF_ij")
    rho = fam.scalar("rho", latex=r"\rho_{{i}}", description="rho_i = gamma_i^2")
    return eps1, eps2, rho


def _checks(thm, N, variant):
    common = variant == "A"
    thm.verify_with(FrequencySweepCheck(N, common_coupling=common),
                    SimulationCheck(N, common_coupling=common))


# -- Theorem 1 (15): analysis with the filters fixed -------------------------------------------
def _title(base: str, variant: str, condition19) -> str:
    extra = [] if variant == "A" else ["variant B: one multiplier per coupling"]
    if condition19:
        extra.append(f"with the GUESSED (19) form {condition19!r}")
    return base + (" - " + "; ".join(extra) if extra else "")


def build_thm1(thm: Theorem, N: int, variant: str = "A", condition19: str | None = None) -> None:
    """Declare Theorem 1 (15) for N subsystems on ``thm``."""
    fam, (n, m, p, q, k, r), d = _plant(thm, N)
    Af = fam.data("Af", lambda i: n[i], lambda i: n[i], latex="A_{f{i}}", description="filter state matrix")
    Bf = fam.data("Bf", lambda i: n[i], lambda i: p[i], latex="B_{f{i}}", description="filter input matrix")
    Lf = fam.data("Lf", lambda i: q[i], lambda i: n[i], latex="L_{f{i}}", description="filter output matrix")
    P = fam.var("P", lambda i: 2 * n[i], kind="symmetric", description="Lyapunov matrix of [x_i; x̂_i]")
    Q = fam.var("Q", lambda i, j: n[j], pairs=True, kind="symmetric", latex="Q_{{i}{j}}",
                description="Krasovskii weight of x_j(t - tau_ij)")
    eps1, eps2, rho = _multipliers(fam, variant)

    def lmi15(i):
        """(15): rows x_fi, x_j(t − τ_ij) (j = 1..N), w_i, z̃_i; then the S-procedure columns."""
        ni = n[i]
        Abar = BlockMatrix([[d["A"][i], ZeroMatrix(ni, ni)], [Bf[i] * d["C"][i], Af[i]]])   # (4)
        Bbar = BlockMatrix([[d["B"][i]], [Bf[i] * d["D"][i]]])
        Hbar = BlockMatrix([[d["HA"][i]], [Bf[i] * d["HC"][i]]])
        Ebar = BlockMatrix([[d["E"][i], ZeroMatrix(k[i], ni)]])                              # (5)
        Mbar = BlockMatrix([[d["M"][i]], [ZeroMatrix(ni, r[i])]])
        U = BlockMatrix([[Identity(ni), ZeroMatrix(ni, ni)]])
        Lbar = BlockMatrix([[d["L"][i], -Lf[i]]])
        S = _sum(Q[j, i] for j in fam)                        # Σ_j Q_ji: weight on x_i
        rows = [[He(P[i] * Abar) + U.T * S * U]]
        for j in fam:
            Adbar = BlockMatrix([[d["Ad"][i, j]], [ZeroMatrix(ni, n[j])]])
            rows.append([(P[i] * Adbar).T] + [0] * (j - 1) + [-Q[i, j]])
        rows.append([(P[i] * Bbar).T] + [0] * N + [-rho[i] * I])
        rows.append([Lbar] + [0] * (N + 1) + [-I])
        zeros = [0] * (N + 2)
        terms = [NormBounded(H=[P[i] * Hbar] + zeros, E=[Ebar] + zeros, eps=eps2[i], form="diag",
                             name=f"F_{i}")]
        terms += _coupling_terms(fam, i, [P[i] * Mbar] + zeros, eps1, 2, variant, d["N"])
        return sprocedure(rows, terms, where=f"{thm.id}: LMI {member_label('(15)', i)}")

    fam.lmis("(15)", lmi15)
    thm.positive(*[P[i] for i in fam])
    thm.positive(*[Q[i, j] for i, j in fam.pairs])
    if condition19:
        R = fam.data("R", lambda i: n[i], lambda i: n[i], symmetric=True, description="given R_i > 0 of (9)")
        for i in fam:
            U = BlockMatrix([[Identity(n[i]), ZeroMatrix(n[i], n[i])]])
            thm.lmi(member_label("(9)", i), [[U * P[i] * U.T - _bound19(condition19, rho[i], R[i])]],
                    sense="<=")
    _objective(thm, fam, rho)
    _checks(thm, N, variant)


# -- Theorem 2 (18): synthesis ----------------------------------------------------------------
def build_thm2(thm: Theorem, N: int, variant: str = "A", condition19: str | None = None,
               suffix: str = "") -> None:
    """Declare Theorem 2 (17), (18), (25), (26) for N subsystems on ``thm``."""
    fam, (n, m, p, q, k, r), d = _plant(thm, N)
    A, Ad, B, C, D, L = d["A"], d["Ad"], d["B"], d["C"], d["D"], d["L"]
    ni = lambda i: n[i]  # noqa: E731
    X = fam.var("X", ni, kind="symmetric")
    Y = fam.var("Y", ni, kind="symmetric")
    Ah = fam.var("Af_hat", ni, ni, latex=r"\hat{A}_{f{i}}")
    Bh = fam.var("Bf_hat", ni, lambda i: p[i], latex=r"\hat{B}_{f{i}}")
    Lh = fam.var("Lf_hat", lambda i: q[i], ni, latex=r"\hat{L}_{f{i}}")
    Q = fam.var("Q", lambda i, j: n[j], pairs=True, kind="symmetric", latex="Q_{{i}{j}}",
                description="Krasovskii weight of x_j(t - tau_ij)")
    eps1, eps2, rho = _multipliers(fam, variant)

    def lmi18(i):
        """(18): rows x, x̂ (congruence image), x_j(t − τ_ij), w_i, z̃_i; then S-procedure columns."""
        S = _sum(Q[j, i] for j in fam)                                     # S_i = Σ_j Q_ji
        rows = [
            [He(X[i] * A[i]) + S],                                                     # H_i1 (1,1)
            [A[i].T * X[i] + Y[i] * A[i] + Bh[i] * C[i] + Ah[i] + S,                   # H_i1 (2,1)
             He(Y[i] * A[i] + Bh[i] * C[i]) + S],                                      # H_i1 (2,2)
        ]
        for j in fam:                                                                  # H_i2, H_i4
            rows.append([(X[i] * Ad[i, j]).T, (Y[i] * Ad[i, j]).T] + [0] * (j - 1) + [-Q[i, j]])
        rows.append([(X[i] * B[i]).T, (Y[i] * B[i] + Bh[i] * D[i]).T] + [0] * N + [-rho[i] * I])
        rows.append([L[i] - Lh[i], L[i]] + [0] * (N + 1) + [-I])
        zeros = [0] * (N + 2)
        terms = [NormBounded(H=[X[i] * d["HA"][i], Y[i] * d["HA"][i] + Bh[i] * d["HC"][i]] + zeros,
                             E=[d["E"][i], d["E"][i]] + zeros, eps=eps2[i], form="diag", name=f"F_{i}")]
        terms += _coupling_terms(fam, i, [X[i] * d["M"][i], Y[i] * d["M"][i]] + zeros, eps1, 2,
                                 variant, d["N"])                                 # H_i3, H_i5, H_i6
        return sprocedure(rows, terms, where=f"{thm.id}: LMI {member_label('(18)', i)}")

    fam.lmis("(18)", lmi18)
    for i in fam:                                       # (17): X_i > 0, Y_i − X_i > 0 (P_i > 0)
        thm.lmi(member_label("(17)", i), [[X[i]], [0, Y[i] - X[i]]], sense=">")
    thm.positive(*[Q[i, j] for i, j in fam.pairs])
    if condition19:
        R = fam.data("R", ni, ni, symmetric=True, description="given R_i > 0 of (19)")
        for i in fam:
            thm.lmi(member_label("(19)", i), [[Y[i] - _bound19(condition19, rho[i], R[i])]], sense="<=")
    _objective(thm, fam, rho)
    thm.recover(**{name: expr for i in fam for name, expr in (
        (f"Af_{i}", (X[i] - Y[i]).I * Ah[i]),                                  # (25)
        (f"Bf_{i}", (X[i] - Y[i]).I * Bh[i]),
        (f"Lf_{i}", Lh[i]))})
    filt = tuple(f"{b}_{i}" for i in fam for b in ("Af", "Bf", "Lf"))
    thm.certified_by(f"interconnected_delay.thm1{suffix}", design=filt)
    _checks(thm, N, variant)
    thm.verify_with(reported_agree())


# Not from the paper: a plain observer per subsystem for the analysis example,
# A_fi = A_i - K_i C_i (Hurwitz for the GUESSED A_i, C_i), B_fi = K_i, L_fi = L_i.
OBSERVER_GAINS = {1: [[0.0], [1.0]], 2: [[1.0], [0.0]]}


def _observer() -> dict:
    out = {}
    for i, K in OBSERVER_GAINS.items():
        A, C = PAPER_DATA[f"A_{i}"], PAPER_DATA[f"C_{i}"]
        out[f"Af_{i}"] = [[A[r][c] - K[r][0] * C[0][c] for c in range(2)] for r in range(2)]
        out[f"Bf_{i}"] = K
        out[f"Lf_{i}"] = PAPER_DATA[f"L_{i}"]
    return out


VARIANTS = {"": ("A", None), "b": ("B", None), "_r19": ("A", "rhoR")}
PROVENANCE = {
    "": {},
    "b": {"provenance": "illustration",
          "provenance_note": "Variant B: independent ΔF_ij with one multiplier ε_ij per coupling, "
                             "instead of the paper's single ε_i1 column (Variant A)"},
    "_r19": {"provenance": "guessed",
             "provenance_note": "Variant A plus the guessed reading Y_i ≤ ρ_i R_i of the OCR-damaged "
                                "condition (19); the paper's own theorems omit (19) (zero initial conditions)"},
}


EXPECT = {"": {}, "b": {},
          "_r19": {"expect": "not certified",
                   "expect_note": "with the guessed (19) the recovered filters are stiff (X_i − Y_i nearly "
                                  "singular) and their analysis is numerically infeasible "
                                  "(docs/reproductions/004.md)"}}


def _thm1_family(suffix: str) -> SubsystemFamily:
    variant, condition19 = VARIANTS[suffix]
    thm = SubsystemFamily(
        f"interconnected_delay.thm1{suffix}",
        _title("Robust H∞ analysis of decentralised filters on a delayed interconnection (Theorem 1, (15))",
               variant, condition19),
        Source(PAPER, "Theorem 1, (8), (15)", CITATION),
        lambda t, N: build_thm1(t, N, variant, condition19), key="A", default=2, time="continuous",
        **PROVENANCE[suffix],
        description="min Σρ_i over P_i > 0, Q_ij > 0, ε such that (15) holds for every i "
                    f"(variant {variant}; filters A_fi, B_fi, L_fi fixed).")
    data = {**PAPER_DATA, **(R_READ if condition19 else {}), **_observer()}
    thm.example("observer", data, params=dict(TAU_GUESSED), provenance="illustration", **EXPECT[suffix],
                provenance_note="the paper prints no filter for Theorem 1's analysis",
                description="not from the paper: decentralised observers A_fi = A_i - K_i C_i, "
                            "B_fi = K_i, L_fi = L_i (K_1 = [0; 1], K_2 = [1; 0]) on the Section 4 "
                            "data.  " + DESCRIPTION)
    return thm


def _thm2_family(suffix: str) -> SubsystemFamily:
    variant, condition19 = VARIANTS[suffix]
    thm = SubsystemFamily(
        f"interconnected_delay.thm2{suffix}",
        _title("Decentralised robust H∞ filters for a delayed interconnection (Theorem 2, (18), (26))",
               variant, condition19),
        Source(PAPER, "Theorem 2, (17), (18), (25), (26)", CITATION),
        lambda t, N: build_thm2(t, N, variant, condition19, suffix), key="A", default=2,
        time="continuous", designs="filter", **PROVENANCE[suffix],
        description="min Σρ_i subject to (18) and (17) for every i, jointly (the Q_ij are shared); "
                    f"recovery (25) (variant {variant}).  N = number of subsystems (default: the "
                    "number of A_<i> given).")
    thm.example("paper", {**PAPER_DATA, **(R_READ if condition19 else {})}, params=dict(TAU_GUESSED),
                **EXPECT[suffix],
                printed=dict(PRINTED_FILTER), printed_note=PRINTED_NOTE, description=DESCRIPTION)
    return thm


thm1 = _thm1_family("")
thm2 = _thm2_family("")
thm1b = _thm1_family("b")
thm2b = _thm2_family("b")
thm1_r19 = _thm1_family("_r19")
thm2_r19 = _thm2_family("_r19")

THEOREMS = [thm1, thm2, thm1b, thm2b, thm1_r19, thm2_r19]
