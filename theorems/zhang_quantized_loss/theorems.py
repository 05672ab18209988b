"""Zhang, Liu, Du (2023): delta-operator H∞ filtering with random multiple packet loss and
logarithmic quantisation.

Paper: Zhang Duanjin, Liu Mengkai, Du Zheng, J. Zhengzhou Univ. (Eng. Sci.) 2023 (OCR of the LMIs
badly damaged); the forms implemented are those reconstructed in ``docs/reproductions/002.md`` §4.

Plant (2): δx = A_δ x + B_δ w, y = C x, z = D x, sampling period h (x(k+1) = x + h δx).
Quantiser (3)-(4): ỹ = (1 + Δ) y, |Δ| ≤ β = (1 − ρ)/(1 + ρ).  Losses (7): ŷ(k) = ỹ(k − m_k),
up to N consecutive losses, Pr(α_i = 1) = ᾱ.  Filter (8): δx_f = A_f x_f + B_f ŷ, z_f = C_f x_f.
Error system (9): ξ = [x; x_f], Ā = [A_δ 0; B_f(1+Δ)C A_f], Ā₁U' = [0; −B_f(1+Δ)C],
B̄ = [B_δ; 0], C̄ = [D −C_f], a_i = ᾱ^{i/2}, l = √N.

* ``zhang_quantized_loss.thm1``  Theorem 1 (10) with the filter fixed, delay blocks reduced to
  the plant part (docs/reproductions/002.md §4.1), in the scaled form P̃ = hP with the cancellation-free
  ``sym(P̃Ā)`` (ξ, ξ) block; p2 and p3 columns kept by the congruences diag(P2), diag(P3);
  the delay blocks scaled by P̌3 = hP3 with the congruence √h on d_1..d_N and p3 (the increments
  η(k−i) are O(h); unscaled, the optimal P3 is O(1/h)).
  Same block layout as (10): π (the −P̃ column, in place of b1), z, ξ, d_1..d_N, w, p2, p3.
* ``zhang_quantized_loss.thm2``  Theorem 2's method -- congruences Z1 (P column), T (ξ), P2 (p2) and
  the bounds −S⁻¹ ⪯ 𝒮 = −S̄ − S̄ᵀ + S̄ᵀSS̄, −P̌3⁻¹ ⪯ 𝒫̌ at a fixed point (S̄, P̌̄3) -- applied to
  thm1's cancellation-free form; recovery (18) with E12 = I: A_f = H1(S−R)⁻¹, B_f = H2,
  C_f = H3(S−R)⁻¹; linearisation (S̄, P̌̄3) ← (S⁻¹, P̌3⁻¹) for :mod:`lmidsl.studies.bmi`.
* ``zhang_quantized_loss.thm2_literal``  LMI (17) itself (corrected as in docs/reproductions/002.md
  §4.7), rescaled exactly (§4.8: R̃ = hR, S̃ = hS, H̃1 = h²H1, H̃2 = hH2, S̃̄ = S̄/h;
  and as in thm1 P̌3 = hP3, P̌̄3 = P̄3/h with the congruences √h on d_i and 1/√h on p3);
  recovery (18) with E12 = I.  The linearisation point (S̃̄, P̌̄3) ← (S̃⁻¹, P̌3⁻¹) is declared
  for the successive-LMI driver :mod:`lmidsl.studies.bmi`.
* ``zhang_quantized_loss.exact``  the exact change of variables of docs/reproductions/002.md §4.9 (no S̄, P̄3):
  P̃ = [R I; I (R−S)⁻¹], T = [I I; S−R 0], Π = TᵀP̃T = [S S; S R], H1 = A_f(S−R), H2 = B_f,
  H3 = C_f(S−R).  Its optimum is the best γ Theorem 1 certifies over full-order filters.

Each is a family in N (N delay blocks built in a loop); Δ is an uncertain scalar |Δ| ≤ β,
imposed at the points the instance chooses (``Delta=[1]``: the paper's Δ = +β; ``[-1, 1]``:
the whole sector; ``[0]``: nominal).
"""
from lmidsl import He, I, Source, Theorem, TheoremFamily
from .delta import filter_reading
from sympy import BlockMatrix, Rational, ZeroMatrix, sqrt

PAPER = "Zhang, Liu, Du 2023, quantisation and packet loss"
CITATION = ("Zhang, Liu, Du, H∞ filtering for cyber physical systems with random multiple packet "
            "loss with quantization error, J. Zhengzhou Univ. (Eng. Sci.) 2023")

PLANT = {"Ad": [[-0.31, -0.52], [0.81, -0.90]], "Bd": [[0.53], [0.42]],
         "C": [[4.30, 1.20]], "D": [[0.80, 1.15]]}
H = 1e-4
RHO = 0.75
TABLE1 = {
    2: {"Af": [[-0.3137, -4.5190], [0.0927, 0.8962]], "Bf": [[-0.5455], [-0.1095]],
        "Cf": [[-0.0007, -0.0082]], "gamma": 1.2568, "alpha_bar": 0.5},
    3: {"Af": [[-0.3138, -4.5182], [0.0927, 0.8961]], "Bf": [[-0.1145], [-0.0229]],
        "Cf": [[-0.0006, -0.0082]], "gamma": 1.2584, "alpha_bar": 0.2},
}
PRINTED_AT = "Section 3, Table 1"
DELTA_PAPER = [1]  # the paper substitutes the threshold Δ = +β into the LMI


def _setup(thm: Theorem, N: int):
    """Dimensions, plant data, parameters h, ᾱ, ρ, N, derived β, l, a_i, uncertain Δ."""
    n, ny, nz, nw = thm.dim("n n_y n_z n_w")
    Ad = thm.data("Ad", n, n, latex=r"A_\delta", description="plant state matrix (delta form)")
    Bd = thm.data("Bd", n, nw, latex=r"B_\delta", description="disturbance input (delta form)")
    C = thm.data("C", ny, n, latex="C", description="measurement matrix")
    D = thm.data("D", nz, n, latex="D", description="estimated output")
    h = thm.param("h", latex="h", domain=(1e-12, 10.0), description="sampling period")
    ab = thm.param("alpha_bar", latex=r"\bar\alpha", domain=(0.0, 1.0),
                   description="Pr{α_i(k) = 1}, probability of each further loss")
    rho = thm.param("rho", latex=r"\rho", domain=(1e-9, 1.0), description="quantisation density")
    Nsym = thm.param("N", latex="N", domain=(N, N), default=N, description="maximum number of consecutive losses")
    beta = thm.derived("beta", (1 - rho) / (1 + rho), latex=r"\beta", description="quantisation sector bound")
    l = thm.derived("l", sqrt(Nsym), latex="l", description="l = N^{1/2}")
    a = [thm.derived(f"a{i}", ab ** Rational(i, 2), latex=f"a_{{{i}}}", description=f"a_{i} = ᾱ^({i}/2)")
         for i in range(1, N + 1)]
    Delta = thm.uncertain("Delta", bound=beta, latex=r"\Delta", description="quantisation error, |Δ| ≤ β")
    return (n, ny, nz, nw), (Ad, Bd, C, D), (h, ab, rho, beta, l, a), Delta


def _delay_diagonal(N, P2, P3c, h):
    """−P3 on d_1..d_{N−1}, −(P2 + P3) on d_N, scaled: P̌3 = hP3 and congruence √h on d_i."""
    return [-P3c if i < N - 1 else -(h * P2 + P3c) for i in range(N)]


def _upper(first_rows, N, diag_d, tail):
    """Upper-triangle rows: ``first_rows`` (already full length), then d_1..d_N, then ``tail``.

    ``tail`` is the list of the last rows (w, p2, p3) as the paper prints them after the
    delay blocks; each d_i row is its diagonal block followed by zeros.
    """
    rows = list(first_rows)
    ntail = len(tail[0])
    for i in range(N):
        rows.append([diag_d[i]] + [0] * (N - 1 - i) + [0] * ntail)
    rows += tail
    return rows


# -- Theorem 1: analysis -----------------------------------------------------------------
def build_thm1(thm: Theorem, N: int):
    (n, ny, nz, nw), (Ad, Bd, C, D), (h, ab, rho, beta, l, a), Delta = _setup(thm, N)
    Af = thm.data("Af", n, n, latex="A_f", description="filter state matrix (delta form)")
    Bf = thm.data("Bf", n, ny, latex="B_f", description="filter input matrix (delta form)")
    Cf = thm.data("Cf", nz, n, latex="C_f", description="filter output matrix")
    Pt = thm.var("Pt", 2 * n, kind="symmetric", latex=r"\tilde P", description="P̃ = hP")
    P2 = thm.var("P2", n, kind="symmetric", latex="P_2")
    P3 = thm.var("P3c", n, kind="symmetric", latex=r"\check P_3", description="P̌3 = hP3")
    g = thm.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
    Abar = BlockMatrix([[Ad, ZeroMatrix(n, n)], [(1 + Delta) * Bf * C, Af]])
    A1U = BlockMatrix([[ZeroMatrix(n, n)], [-(1 + Delta) * Bf * C]])  # Ā₁Uᵀ
    Bbar = BlockMatrix([[Bd], [ZeroMatrix(n, nw)]])
    Cbar = BlockMatrix([[D, -Cf]])
    UT = BlockMatrix([[I.sized(n)], [ZeroMatrix(n, n)]])  # Uᵀ
    UA = BlockMatrix([[Ad, ZeroMatrix(n, n)]])  # UĀ
    sh = sqrt(h)
    first = [
        # π (−P̃), z, ξ, d_1..d_N, w, p2, p3
        [-Pt, 0, sh * Pt * Abar] + [h * a[i] * Pt * A1U for i in range(N)] + [sh * Pt * Bbar, 0, 0],
        [-I, Cbar] + [0] * N + [0, 0, 0],
        [He(Pt * Abar)] + [sh * a[i] * Pt * A1U for i in range(N)] + [Pt * Bbar, UT * P2, sh * l * UA.T * P3],
    ]
    tail = [[-g * I, 0, 0], [-P2, 0], [-P3]]
    thm.lmi("(10)", _upper(first, N, _delay_diagonal(N, P2, P3, h), tail), triangle="upper",
            description="(10) with delay blocks reduced to U η(k−i), scaled P̃ = hP, cancellation-free")
    thm.positive(Pt, P2, P3)
    thm.minimize(g, performance=("gamma", sqrt(g)))


DELTA_READING_INFEASIBLE = dict(
    expect="infeasible",
    expect_note="read as delta-form matrices the printed filter violates the necessary condition "
                "(I + hĀ Schur) of (10), so Theorem 1 is infeasible for it: docs/reproductions/002.md")


def _printed_examples(thm: Theorem):
    for N, row in TABLE1.items():
        params = {"h": H, "alpha_bar": row["alpha_bar"], "rho": RHO, "N": N}
        for reading in ("delta", "shift"):
            f = filter_reading(row, reading, H)
            suffix = "" if reading == "delta" else "-shift"
            thm.example(f"paper-N{N}-printed{suffix}",
                        {**PLANT, **{k: v.tolist() for k, v in f.items()}, "Delta": DELTA_PAPER},
                        params=params, printed={"gamma_bound": row["gamma"]}, printed_note=PRINTED_AT,
                        **(DELTA_READING_INFEASIBLE if reading == "delta" else {}),
                        description=f"Table 1 filter for N = {N}, printed matrices read as {reading}-form "
                                    f"matrices{' (converted: Af = (A - I)/h, Bf = B/h)' if reading == 'shift' else ''}")


thm1 = TheoremFamily("zhang_quantized_loss.thm1", "Delta-domain H∞ analysis, quantisation and N losses (Theorem 1)",
                     Source(PAPER, "Theorem 1, (10)", CITATION), build_thm1, index="N", default=2,
                     description="min γ² over P̃ = hP > 0, P2 > 0, P3 > 0 with the filter fixed (delta form).")
_printed_examples(thm1)


# -- Theorem 2: synthesis LMI (17) with fixed S̄, P̄3 ---------------------------------------
def build_thm2_literal(thm: Theorem, N: int):
    (n, ny, nz, nw), (Ad, Bd, C, D), (h, ab, rho, beta, l, a), Delta = _setup(thm, N)
    Sbar = thm.data("Sbar", n, n, latex=r"\tilde{\bar S}", description="linearisation point for S̃⁻¹ (= S̄/h)")
    P3bar = thm.data("P3bar", n, n, latex=r"\check{\bar P}_3", description="linearisation point for P̌3⁻¹ (= P̄3/h)")
    R = thm.var("R", n, kind="symmetric", latex=r"\tilde R", description="R̃ = hR")
    S = thm.var("S", n, kind="symmetric", latex=r"\tilde S", description="S̃ = hS")
    H1 = thm.var("H1", n, n, latex=r"\tilde H_1", description="H̃1 = h²H1")
    H2 = thm.var("H2", n, ny, latex=r"\tilde H_2", description="H̃2 = hH2")
    H3 = thm.var("H3", nz, n, latex="H_3")
    P2 = thm.var("P2", n, kind="symmetric", latex="P_2")
    P3 = thm.var("P3c", n, kind="symmetric", latex=r"\check P_3", description="P̌3 = hP3")
    g = thm.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
    sh = sqrt(h)
    Ssc = -Sbar - Sbar.T + Sbar.T * S * Sbar          # 𝒮 ⪰ −S̃⁻¹
    Psc = -P3bar - P3bar.T + P3bar.T * P3 * P3bar     # 𝒫̌ ⪰ −P̌3⁻¹
    hAI = h * Ad + I.sized(n)
    KH = h * (1 + Delta) * H2 * C
    phi5 = R * hAI + KH + H1 + S - R
    phi6 = R * hAI + KH
    phi4 = [-h * a[i] * (1 + Delta) * H2 * C for i in range(N)]
    first = [
        # b1a, b1b, b2, b3a, b3b, d_1..d_N, w, p2, p3
        [Ssc, -I, 0, hAI, hAI] + [0] * N + [sh * Bd, 0, 0],
        [-R, 0, phi5, phi6] + phi4 + [sh * R * Bd, 0, 0],
        [-I, sh * (D - H3), sh * D] + [0] * N + [0, 0, 0],
        [-S, -S] + [0] * N + [0, sh * P2, h * l * Ad.T],
        [-R] + [0] * N + [0, sh * P2, h * l * Ad.T],
    ]
    tail = [[-g * I, 0, 0], [-P2, 0], [Psc]]
    thm.lmi("(17)", _upper(first, N, _delay_diagonal(N, P2, P3, h), tail), triangle="upper",
            description="(17) corrected (docs/reproductions/002.md, section 4.7) and rescaled exactly (4.8)")
    thm.positive(R, S, P2, P3)
    thm.minimize(g, performance=("gamma", sqrt(g)))
    thm.recover(Af=H1 * (S - R).I / h, Bf=H2 / h, Cf=h * H3 * (S - R).I)
    thm.linearise(Sbar=S.I, P3bar=P3.I)
    thm.certified_by("zhang_quantized_loss.thm1", design=("Af", "Bf", "Cf"))


def _synthesis_variables(thm: Theorem, n, ny, nz, s_meaning: str):
    """R, S, H1 = A_f(S − R), H2 = B_f, H3 = C_f(S − R), P2, P̌3 = hP3 and g = γ²: the variables
    both synthesis routes share (they differ in what S means)."""
    R = thm.var("R", n, kind="symmetric", latex="R", description="(1,1) block of P̃ = hP")
    S = thm.var("S", n, kind="symmetric", latex="S", description=s_meaning)
    H1 = thm.var("H1", n, n, latex="H_1", description="A_f(S − R)")
    H2 = thm.var("H2", n, ny, latex="H_2", description="B_f")
    H3 = thm.var("H3", nz, n, latex="H_3", description="C_f(S − R)")
    P2 = thm.var("P2", n, kind="symmetric", latex="P_2")
    P3 = thm.var("P3c", n, kind="symmetric", latex=r"\check P_3", description="P̌3 = hP3")
    g = thm.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
    return R, S, H1, H2, H3, P2, P3, g


# -- Theorem 2 on the cancellation-free statement of (10) ---------------------------------
def build_thm2(thm: Theorem, N: int):
    """The proof of Theorem 2 (congruences Z1 on the P column, T on ξ, P2 on p2; bounds 𝒮, 𝒫)
    applied to thm1's cancellation-free form instead of the literal (10) (docs/reproductions/002.md
    §4.2, §4.6)."""
    (n, ny, nz, nw), (Ad, Bd, C, D), (h, ab, rho, beta, l, a), Delta = _setup(thm, N)
    Sbar = thm.data("Sbar", n, n, latex=r"\bar S", description="linearisation point for S⁻¹")
    P3bar = thm.data("P3bar", n, n, latex=r"\check{\bar P}_3", description="linearisation point for P̌3⁻¹")
    R, S, H1, H2, H3, P2, P3, g = _synthesis_variables(thm, n, ny, nz,
                                                       "inverse of the (1,1) block of P̃⁻¹")
    sh = sqrt(h)
    Ssc = -Sbar - Sbar.T + Sbar.T * S * Sbar          # 𝒮 ⪰ −S⁻¹
    Psc = -P3bar - P3bar.T + P3bar.T * P3 * P3bar     # 𝒫̌ ⪰ −P̌3⁻¹
    KH = (1 + Delta) * H2 * C
    A_ab = R * Ad + KH + H1
    A_bb = R * Ad + KH
    first = [
        # πa, πb (Z1ᵀP̃Z1 = [S⁻¹ I; I R]), z, ξa, ξb, d_1..d_N, w, p2, p3
        [Ssc, -I, 0, sh * Ad, sh * Ad] + [0] * N + [sh * Bd, 0, 0],
        [-R, 0, sh * A_ab, sh * A_bb] + [-h * a[i] * KH for i in range(N)] + [sh * R * Bd, 0, 0],
        [-I, D - H3, D] + [0] * N + [0, 0, 0],
        [He(S * Ad), S * Ad + A_ab.T] + [0] * N + [S * Bd, P2, sh * l * Ad.T],
        [He(A_bb)] + [-sh * a[i] * KH for i in range(N)] + [R * Bd, P2, sh * l * Ad.T],
    ]
    tail = [[-g * I, 0, 0], [-P2, 0], [Psc]]
    thm.lmi("(17)-cf", _upper(first, N, _delay_diagonal(N, P2, P3, h), tail), triangle="upper",
            description="(17)'s congruences and bounds on the cancellation-free form of (10)")
    thm.positive(R, S, P2, P3)
    thm.minimize(g, performance=("gamma", sqrt(g)))
    thm.recover(Af=H1 * (S - R).I, Bf=H2, Cf=H3 * (S - R).I)
    thm.linearise(Sbar=S.I, P3bar=P3.I)
    thm.certified_by("zhang_quantized_loss.thm1", design=("Af", "Bf", "Cf"))


# -- exact change of variables (docs/reproductions/002.md §4.9) ---------------------------
def build_exact(thm: Theorem, N: int):
    (n, ny, nz, nw), (Ad, Bd, C, D), (h, ab, rho, beta, l, a), Delta = _setup(thm, N)
    R, S, H1, H2, H3, P2, P3, g = _synthesis_variables(thm, n, ny, nz,
                                                       "S = R − ((2,2) block of P̃)⁻¹")
    Pi = thm.structured("Pi", [[S, S], [S, R]], latex=r"\Pi", symmetric=True, description="TᵀP̃T")
    sh = sqrt(h)
    KH = (1 + Delta) * H2 * C
    A_ab = R * Ad + KH + H1       # 𝒜 = [[S A, S A], [R A + KH + H1, R A + KH]]
    A_bb = R * Ad + KH
    first = [
        # πa, πb (−Π), z, ξa, ξb, d_1..d_N, w, p2, p3
        [-S, -S, 0, sh * S * Ad, sh * S * Ad] + [0] * N + [sh * S * Bd, 0, 0],
        [-R, 0, sh * A_ab, sh * A_bb] + [-h * a[i] * KH for i in range(N)] + [sh * R * Bd, 0, 0],
        [-I, D - H3, D] + [0] * N + [0, 0, 0],
        [He(S * Ad), S * Ad + A_ab.T] + [0] * N + [S * Bd, P2, sh * l * Ad.T * P3],
        [He(A_bb)] + [-sh * a[i] * KH for i in range(N)] + [R * Bd, P2, sh * l * Ad.T * P3],
    ]
    tail = [[-g * I, 0, 0], [-P2, 0], [-P3]]
    thm.lmi("(10)-exact", _upper(first, N, _delay_diagonal(N, P2, P3, h), tail), triangle="upper",
            description="Theorem 1 after the congruence diag(T, I, ..., I) and H1, H2, H3 (docs/reproductions/002.md, section 4.9)")
    thm.positive(Pi, P2, P3)
    thm.minimize(g, performance=("gamma", sqrt(g)))
    thm.recover(Af=H1 * (S - R).I, Bf=H2, Cf=H3 * (S - R).I)
    thm.certified_by("zhang_quantized_loss.thm1", design=("Af", "Bf", "Cf"))


def _synthesis_examples(thm: Theorem, start: dict | None = None, expect: dict | None = None):
    """The Table 1 cases; ``expect`` maps an example name to its known (outcome, note)."""
    expect = expect or {}

    def known(name):
        outcome, note = expect.get(name, ("certified", ""))
        return {"expect": outcome, "expect_note": note}

    for N, row in TABLE1.items():
        params = {"h": H, "alpha_bar": row["alpha_bar"], "rho": RHO, "N": N}
        printed = {"gamma": row["gamma"], "Af": row["Af"], "Bf": row["Bf"], "Cf": row["Cf"]}
        thm.example(f"paper-N{N}", {**PLANT, **(start or {}), "Delta": DELTA_PAPER}, params=params,
                    printed=printed, printed_note=PRINTED_AT, **known(f"paper-N{N}"),
                    description=f"case {N - 1} of Section 3: N = {N}, ᾱ = {row['alpha_bar']}, Δ = +β as in the paper")
        thm.example(f"paper-N{N}-robust", {**PLANT, **(start or {}), "Delta": [-1, 1]}, params=params,
                    **known(f"paper-N{N}-robust"),
                    provenance="illustration", provenance_note="the paper imposes Δ = +β only",
                    description=f"not printed: as paper-N{N} but with the LMI imposed on the whole sector |Δ| ≤ β")


thm2 = TheoremFamily("zhang_quantized_loss.thm2", "Delta-domain H∞ filter synthesis with fixed S̄, P̄3 (Theorem 2)",
                     Source(PAPER, "Theorem 2, (17)-(18), on the cancellation-free form of (10)", CITATION), build_thm2,
                     index="N", default=2, designs="filter",
                     description="min γ² subject to (17)'s bounded LMI at a fixed point (S̄, P̌̄3), written on the "
                                 "cancellation-free form of (10); iterate with lmidsl.studies.bmi (S̄, P̌̄3) ← (S⁻¹, P̌3⁻¹).")
_synthesis_examples(thm2, start={"Sbar": [[1.0, 0.0], [0.0, 1.0]], "P3bar": [[1e4, 0.0], [0.0, 1e4]]})

thm2_literal = TheoremFamily(
    "zhang_quantized_loss.thm2_literal", "Theorem 2, LMI (17) as printed (corrected, exactly rescaled)",
    Source(PAPER, "Theorem 2, (17)-(18)", CITATION), build_thm2_literal, index="N", default=2,
    designs="filter", provenance="corrected",
    provenance_note="LMI (17) as printed with its OCR-damaged blocks corrected and exactly rescaled; "
                    "numerically fragile at h = 1e-4 (thm2 is the same method on the cancellation-free form)",
    description="(17) with its b1/b3 blocks as printed: (hA+I) terms cancel to O(h) inside O(1) entries, "
                "so at h = 1e-4 the LMI's margin at the tight point is ~1e-15 relative (see docs/reproductions/002.md).")
LITERAL_FRAGILE = ("LMI (17) as printed cancels (hA + I) terms to O(h) inside O(1) entries: at "
                   "h = 1e-4 the solvers fail or return an uncertified point (docs/reproductions/002.md)")
_synthesis_examples(thm2_literal, start={"Sbar": [[1.0, 0.0], [0.0, 1.0]], "P3bar": [[1e4, 0.0], [0.0, 1e4]]},
                    expect={"paper-N2": ("not solved", LITERAL_FRAGILE),
                            "paper-N2-robust": ("not solved", LITERAL_FRAGILE),
                            "paper-N3": ("not certified", LITERAL_FRAGILE),
                            "paper-N3-robust": ("not solved", LITERAL_FRAGILE)})

exact = TheoremFamily("zhang_quantized_loss.exact", "Delta-domain H∞ filter synthesis, exact change of variables",
                      Source(PAPER, "Theorem 1 (10), exact change of variables", CITATION), build_exact,
                      index="N", default=2, designs="filter", provenance="illustration",
                      provenance_note="not in the paper: an exact change of variables for Theorem 1 "
                                      "(no fixed S̄, P̄3), the best γ Theorem 1 certifies over full-order filters",
                      description="min γ² over Π = [S S; S R] > 0, H1, H2, H3, P2, P3: the best γ of Theorem 1 "
                                  "over full-order filters.")
MARGIN_DOMINATED = ("with Δ = +β the infimum is not attained: γ is set by the strictness margin and "
                    "the recovered filter is not certified by Theorem 1 (docs/reproductions/002.md)")
_synthesis_examples(exact, expect={"paper-N2": ("not certified", MARGIN_DOMINATED),
                                   "paper-N3": ("not certified", MARGIN_DOMINATED)})

THEOREMS = [thm1, thm2, exact, thm2_literal]
