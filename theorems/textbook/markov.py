"""Mode-dependent state feedback of Markov jump linear systems, continuous and discrete time.

The plant jumps between N modes, ẋ = A_θ x + B_θ u (or x⁺ = A_θ x + B_θ u) with θ a Markov
chain: a transition-rate generator Π = [π_ij] (continuous time: π_ij ≥ 0 for j ≠ i, rows sum to
0) or a stochastic matrix Π = [p_ij] (discrete time).  The gain u = K_θ x is mode-dependent.

Continuous time (Costa, Fragoso, Todorov, *Continuous-Time Markov Jump Linear Systems*,
Springer 2013, Ch. 3 and 5; de Souza & Fragoso, "H∞ control for linear systems with Markovian
jumping parameters", Control Theory Adv. Tech. 9, 1993): mean-square stability of the closed
loop iff ∃ Pᵢ ≻ 0 with He(Pᵢ(Aᵢ + BᵢKᵢ)) + Σⱼ π_ij Pⱼ ≺ 0 for every i; with Yᵢ = Pᵢ⁻¹,
Wᵢ = KᵢYᵢ and a Schur complement on Σ_{j≠i} π_ij Yᵢ Yⱼ⁻¹ Yᵢ, for all i ∈ 𝓘:

    [[He(AᵢYᵢ + BᵢWᵢ) + π_ii Yᵢ,  ⋆],
     [col_{j≠i}(√π_ij Yᵢ),         −diag_{j≠i}(Yⱼ)]] ≺ 0,   Kᵢ = WᵢYᵢ⁻¹.

Discrete time (Costa, Fragoso, Marques, *Discrete-Time Markov Jump Linear Systems*,
Springer 2005, Ch. 3 and 7): Σⱼ p_ij (Aᵢ + BᵢKᵢ)ᵀ Pⱼ (Aᵢ + BᵢKᵢ) − Pᵢ ≺ 0, i.e.

    [[−Yᵢ, ⋆], [col_j(√p_ij (AᵢYᵢ + BᵢWᵢ)), −diag_j(Yⱼ)]] ≺ 0.

The H∞ versions (``textbook.mjls_hinf_sf_ct`` / ``_dt``) add the disturbance w and the output
z = C1ᵢx + D11ᵢw + D12ᵢu with the level γ on both diagonal blocks, as in :mod:`.hinf_sf`.

Evidence: the second-moment test of the closed loop (:func:`lmidsl.second_moment`), an
eigenvalue computation that does not use the LMIs; the H∞ designs are also certified by the
bounded real lemma of the jump closed loop with the gains given (``textbook.mjls_hinf_sf_ct_cl`` /
``_dt_cl``, one LMI for all modes with Σⱼ π_ij Pⱼ).  Data: ``{"modes": [{"A": …, "B": …}, …],
"Pi": …}``; a mode with B = 0 (uncontrolled) is allowed (its gain is 0).
"""
from sympy import Ne, sqrt

from lmidsl import He, I, Source, Theorem, diag_over, second_moment, stack_over, sum_over

CFT = ("Costa, Fragoso, Todorov, Continuous-Time Markov Jump Linear Systems, Springer 2013")
CFM = ("Costa, Fragoso, Marques, Discrete-Time Markov Jump Linear Systems, Springer 2005")

# an unstable mode, a stable one and an uncontrolled unstable one (B = 0)
EXAMPLE_MODES = [
    {"A": [[0.0, 1.0], [2.0, -1.0]], "B": [[0.0], [1.0]]},
    {"A": [[-1.0, 0.5], [0.0, -2.0]], "B": [[1.0], [0.0]]},
    {"A": [[0.3, 0.0], [0.1, -1.0]], "B": [[0.0], [0.0]]},
]
EXAMPLE_RATES = [[-3.0, 2.0, 1.0], [1.0, -2.0, 1.0], [4.0, 2.0, -6.0]]
EXAMPLE_PROBABILITIES = [[0.6, 0.3, 0.1], [0.2, 0.7, 0.1], [0.5, 0.3, 0.2]]
EXAMPLE_MODES_DT = [
    {"A": [[1.1, 0.3], [0.0, 0.8]], "B": [[0.0], [1.0]]},
    {"A": [[0.5, 0.0], [0.4, 0.9]], "B": [[1.0], [0.0]]},
    {"A": [[1.05, 0.0], [0.0, 0.5]], "B": [[0.0], [0.0]]},
]


def _hinf_modes(modes):
    out = []
    for md in modes:
        n = len(md["A"])
        out.append({"A": md["A"], "B1": [[1.0] if r == 0 else [0.0] for r in range(n)],
                    "B2": md["B"], "C1": [[1.0] + [0.0] * (n - 1), [0.0] * n],
                    "D11": [[0.0], [0.0]], "D12": [[0.0], [1.0]]})
    return out


def mjls_state_feedback(time: str, hinf: bool) -> Theorem:
    suffix = "ct" if time == "continuous" else "dt"
    name = f"textbook.mjls_{'hinf_' if hinf else ''}sf_{suffix}"
    title = (f"Mode-dependent {'H∞' if hinf else 'stabilising'} state feedback of a Markov jump "
             f"system ({time} time)")
    book = CFT if time == "continuous" else CFM
    thm = Theorem(name, title, Source("Costa et al. (MJLS)", "mode-dependent state feedback, "
                                      "Yᵢ = Pᵢ⁻¹, Wᵢ = KᵢYᵢ" + (", bounded real lemma" if hinf else ""), book),
                  time=time, designs="gain",
                  description="for all modes i: the coupled Lyapunov inequalities of the closed loop, "
                              "Schur-complemented over the other modes")
    n = thm.dim("n")
    M = thm.index_set("modes", size="N", latex=r"\mathcal{N}", description="modes of the Markov chain")
    i, j = M.indices("i j")
    A = thm.data("A", n, n, over=M, description="state matrix of mode i")
    if hinf:
        m1, m2, p1 = thm.dim("m1 m2 p1")
        B1 = thm.data("B1", n, m1, over=M, latex="B_1", description="disturbance input of mode i")
        B = thm.data("B2", n, m2, over=M, latex="B_2", description="control input of mode i")
        C1 = thm.data("C1", p1, n, over=M, latex="C_1", description="performance output of mode i")
        D11 = thm.data("D11", p1, m1, over=M, latex="D_{11}")
        D12 = thm.data("D12", p1, m2, over=M, latex="D_{12}")
    else:
        m2 = thm.dim("m")
        B = thm.data("B", n, m2, over=M, description="input matrix of mode i")
    if time == "continuous":
        Pi = thm.coefficients("Pi", M, structure="generator", latex=r"\pi",
                              description="transition-rate generator")
    else:
        Pi = thm.coefficients("Pi", M, structure="stochastic", latex="p",
                              description="transition probabilities")
    Y = thm.var("Y", n, kind="symmetric", over=M, description="Yᵢ = Pᵢ⁻¹")
    W = thm.var("W", m2, n, over=M, description="Wᵢ = KᵢYᵢ")
    AY = A[i] * Y[i] + B[i] * W[i]
    g = thm.scalar("gamma", latex=r"\gamma", description="H∞ level") if hinf else None
    if time == "continuous":
        couple = stack_over(j, sqrt(Pi[i, j]) * Y[i], Ne(j, i))
        others = -diag_over(j, Y[j], Ne(j, i))
        if hinf:
            thm.lmi("(MJ)", [
                [He(AY) + Pi[i, i] * Y[i]],
                [B1[i].T, -g * I],
                [C1[i] * Y[i] + D12[i] * W[i], D11[i], -g * I],
                [couple, 0, 0, others],
            ], forall=i)
        else:
            thm.lmi("(MJ)", [
                [He(AY) + Pi[i, i] * Y[i]],
                [couple, others],
            ], forall=i)
    else:
        if hinf:
            thm.lmi("(MJ)", [
                [-Y[i]],
                [0, -g * I],
                [stack_over(j, sqrt(Pi[i, j]) * AY), stack_over(j, sqrt(Pi[i, j]) * B1[i]),
                 -diag_over(j, Y[j])],
                [C1[i] * Y[i] + D12[i] * W[i], D11[i], 0, -g * I],
            ], forall=i)
        else:
            thm.lmi("(MJ)", [
                [-Y[i]],
                [stack_over(j, sqrt(Pi[i, j]) * AY), -diag_over(j, Y[j])],
            ], forall=i)
    if hinf:
        thm.positive(Y[i])
    else:
        # the stabilisation LMIs are homogeneous in (Y, W): Yᵢ ⪰ I is Yᵢ ≻ 0 after scaling, and
        # gives the solver a bounded-below problem (measured: infeasible cases that ended in a
        # solver error with Yᵢ ≻ 0 are then reported infeasible)
        thm.lmi("Y >= I", [[Y[i] - I]], sense=">=", strict=False, forall=i)
    if hinf:
        thm.minimize(g, performance=("gamma", g))
    else:
        thm.feasibility()
    thm.recover_each(i, K=W[i] * Y[i].I)
    thm.well_conditioned(Y[i])
    thm.verify_with(second_moment(rates="Pi", A="A", B="B2" if hinf else "B", K="K"))
    modes = EXAMPLE_MODES if time == "continuous" else EXAMPLE_MODES_DT
    rates = EXAMPLE_RATES if time == "continuous" else EXAMPLE_PROBABILITIES
    thm.example("three-modes", {"modes": _hinf_modes(modes) if hinf else modes, "Pi": rates},
                provenance="illustration",
                provenance_note="three modes chosen for the gallery: an unstable controlled mode, a "
                                "stable one and an unstable uncontrolled one (B = 0)")
    return thm


def mjls_hinf_analysis(time: str) -> Theorem:
    """The bounded real lemma of the Markov jump closed loop with the mode gains Kᵢ given:
    continuous time [[He(PᵢA_cl,i) + Σⱼ π_ij Pⱼ, PᵢB1ᵢ, C_cl,iᵀ], [⋆, −γI, D11ᵢᵀ], [⋆, ⋆, −γI]] ≺ 0;
    discrete time [[−Pᵢ, ⋆, ⋆, ⋆], [0, −γI, ⋆, ⋆], [col_j(√p_ij PⱼA_cl,i), col_j(√p_ij PⱼB1ᵢ),
    −diag_j(Pⱼ), ⋆], [C_cl,i, D11ᵢ, 0, −γI]] ≺ 0, for all i (the same references)."""
    suffix = "ct" if time == "continuous" else "dt"
    book = CFT if time == "continuous" else CFM
    thm = Theorem(f"textbook.mjls_hinf_sf_{suffix}_cl", f"H∞ level of a Markov jump closed loop ({time} time)",
                  Source("Costa et al. (MJLS)", "bounded real lemma of the closed loop, mode gains given", book),
                  time=time, description="for all modes i: the coupled bounded real inequalities with Kᵢ given")
    n, m1, m2, p1 = thm.dim("n m1 m2 p1")
    M = thm.index_set("modes", size="N", latex=r"\mathcal{N}")
    i, j = M.indices("i j")
    A = thm.data("A", n, n, over=M)
    B1 = thm.data("B1", n, m1, over=M, latex="B_1")
    B2 = thm.data("B2", n, m2, over=M, latex="B_2")
    C1 = thm.data("C1", p1, n, over=M, latex="C_1")
    D11 = thm.data("D11", p1, m1, over=M, latex="D_{11}")
    D12 = thm.data("D12", p1, m2, over=M, latex="D_{12}")
    K = thm.data("K", m2, n, over=M, description="the gain of mode i")
    Pi = thm.coefficients("Pi", M, structure="generator" if time == "continuous" else "stochastic",
                          latex=r"\pi" if time == "continuous" else "p")
    P = thm.var("P", n, kind="symmetric", over=M)
    g = thm.scalar("gamma", latex=r"\gamma")
    Acl = A[i] + B2[i] * K[i]
    Ccl = C1[i] + D12[i] * K[i]
    if time == "continuous":
        thm.lmi("(MJ-BRL)", [
            [He(P[i] * Acl) + sum_over(j, Pi[i, j] * P[j])],
            [B1[i].T * P[i], -g * I],
            [Ccl, D11[i], -g * I],
        ], forall=i)
    else:
        thm.lmi("(MJ-BRL)", [
            [-P[i]],
            [0, -g * I],
            [stack_over(j, sqrt(Pi[i, j]) * P[j] * Acl), stack_over(j, sqrt(Pi[i, j]) * P[j] * B1[i]),
             -diag_over(j, P[j])],
            [Ccl, D11[i], 0, -g * I],
        ], forall=i)
    thm.positive(P[i])
    thm.minimize(g, performance=("gamma", g))
    return thm


mjls_sf_ct = mjls_state_feedback("continuous", hinf=False)
mjls_sf_dt = mjls_state_feedback("discrete", hinf=False)
mjls_hinf_sf_ct = mjls_state_feedback("continuous", hinf=True)
mjls_hinf_sf_dt = mjls_state_feedback("discrete", hinf=True)
mjls_hinf_sf_ct_cl = mjls_hinf_analysis("continuous")
mjls_hinf_sf_dt_cl = mjls_hinf_analysis("discrete")
mjls_hinf_sf_ct.certified_by(mjls_hinf_sf_ct_cl, design=("K",))
mjls_hinf_sf_dt.certified_by(mjls_hinf_sf_dt_cl, design=("K",))

THEOREMS = [mjls_sf_ct, mjls_sf_dt, mjls_hinf_sf_ct, mjls_hinf_sf_dt, mjls_hinf_sf_ct_cl, mjls_hinf_sf_dt_cl]
