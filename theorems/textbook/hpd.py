"""Robust analysis and synthesis over the simplex with homogeneous polynomially
parameter-dependent (HPPD) Lyapunov matrices and Pólya's relaxation.

For A(α) = Σ αᵢ Aᵢ, α ∈ Λ_N (the unit simplex; data given at the vertices), each theorem is
stated once in α and lmidsl generates the coefficient LMIs (:mod:`lmidsl.theorem.robust`):
P(α) = Σ_{|k|=g} α^k P_k with g = ``degree``, every LMI made homogeneous and multiplied by
(Σ αᵢ)^d, d = ``polya``, every monomial coefficient imposed.  g = 0 is quadratic stability
(one P), g = 1 the affine parameter-dependent Lyapunov matrix; the conditions are only
sufficient, and less conservative as g and d grow (Oliveira & Peres 2007, Theorem 3 and the
convergence result there).  Every claim is tested on a grid of the simplex with python-control
(:mod:`lmidsl.certify.simplex_grid`).

* ``textbook.hpd_stability_ct``: P(α) ≻ 0, A(α)ᵀP(α) + P(α)A(α) ≺ 0 ∀α ⇒ A(α) Hurwitz on Λ_N;
* ``textbook.hpd_stability_dt``: P(α) ≻ 0, [[−P(α), A(α)ᵀP(α)], [P(α)A(α), −P(α)]] ≺ 0
  (A(α)ᵀP(α)A(α) − P(α) ≺ 0 by a Schur complement) ⇒ A(α) Schur (α constant in time);
* ``textbook.hpd_hinf_ct``: the bounded real lemma with P(α):
  [[He(P(α)A(α)), P(α)B(α), C(α)ᵀ], [⋆, −μI, D(α)ᵀ], [⋆, ⋆, −I]] ≺ 0, min μ:
  ‖H(α)‖∞ < √μ ∀α;
* ``textbook.hpd_h2_ct``: He(P(α)A(α)) + C(α)ᵀC(α) ≺ 0 and [[W, B(α)ᵀP(α)], [P(α)B(α), P(α)]] ≻ 0,
  min tr W: ‖H(α)‖₂² < tr W ∀α (P(α) bounds the observability Gramian; D = 0);
* ``textbook.hpd_margin_ct`` / ``_dt``: stability of A₀ + ρ ΔA(α), ΔA(α) = Σ αᵢ ΔAᵢ, bisected on
  ρ: the largest scaling of the uncertainty the conditions certify;
* ``textbook.hpd_sf_dt``: robust state feedback u = Kx with a fixed K and P(α) through the
  dilated condition [[P(α), A(α)G + B(α)Z], [⋆, G + Gᵀ − P(α)]] ≻ 0, K = Z G⁻¹ (de Oliveira,
  Bernussou, Geromel 1999, Theorem 3, with P(α) HPPD instead of affine);
* ``textbook.hpd_sf_ct``: its continuous-time counterpart with a fixed scalar ξ > 0:
  [[He(A(α)G + B(α)Z), P(α) − Gᵀ + ξ(A(α)G + B(α)Z)], [⋆, −ξ(G + Gᵀ)]] ≺ 0, P(α) ≻ 0,
  K = Z G⁻¹.  Derivation: with A_cl = A + BK and Z = KG, multiplying by [I  A_cl] on the left
  and its transpose on the right leaves A_cl P(α) + P(α)A_clᵀ ≺ 0 (the terms in G cancel), and
  −ξ He(G) ≺ 0 makes G invertible (the extended characterisations of Pipeleers, Demeulenaere,
  Swevers, Vandenberghe, Systems & Control Letters 58:510-518, 2009).
"""
import numpy as np
import sympy as sp
from lmidsl import He, I, RobustTheorem, Source, grid_check
from sympy import Trace

OP2007 = ("R. C. L. F. Oliveira, P. L. D. Peres, Parameter-dependent LMIs in robust analysis: "
          "characterization of homogeneous polynomially parameter-dependent solutions via LMI "
          "relaxations, IEEE Transactions on Automatic Control 52(7):1334-1340, 2007")
ROLMIP = ("C. M. Agulhari, R. C. L. F. Oliveira, P. L. D. Peres, Robust LMI Parser: a computational "
          "package to construct LMI conditions for uncertain systems, XIX Brazilian Conference on "
          "Automation (CBA), 2012 (github.com/agulhari/ROLMIP)")
DOBG = ("M. C. de Oliveira, J. Bernussou, J. C. Geromel, A new discrete-time robust stability condition, "
        "Systems & Control Letters 37:261-265, 1999")
PIPELEERS = ("G. Pipeleers, B. Demeulenaere, J. Swevers, L. Vandenberghe, Extended LMI characterizations "
             "for stability and performance of linear systems, Systems & Control Letters 58:510-518, 2009")


def random_polytope(seed: int, n: int = 3, vertices: int = 2, time: str = "continuous",
                    spread: float = 1.0, margin: float = 1.0, inputs: int = 0, outputs: int = 0,
                    centre: bool = False) -> dict:
    """{"vertices": [{"A": …}, …]}: a stable centre A₀ (abscissa −``margin`` / radius 1 −
    0.1·``margin``) plus ``spread`` times random directions of unit 2-norm, one per vertex
    (numpy seed ``seed``); with ``inputs``/``outputs``, B and C per vertex, a random centre
    spread likewise (D = 0).  ``centre``: A₀ under "A0" too (not an input of the theorems)."""
    rng = np.random.default_rng(seed)
    A0 = rng.standard_normal((n, n))
    if time == "continuous":
        A0 = A0 - (max(np.linalg.eigvals(A0).real) + margin) * np.eye(n)
    else:
        A0 = (1 - 0.1 * margin) * A0 / max(abs(np.linalg.eigvals(A0)))
    B0, C0 = rng.standard_normal((n, inputs)), rng.standard_normal((outputs, n))

    def spread_of(M0):
        E = rng.standard_normal(M0.shape)
        return (M0 + spread * E / np.linalg.norm(E, 2)).tolist()

    out = []
    for _ in range(vertices):
        v = {"A": spread_of(A0)}
        if inputs:
            v["B"] = spread_of(B0)
        if outputs:
            v["C"] = spread_of(C0)
        out.append(v)
    return {"vertices": out, **({"A0": A0} if centre else {})}


def spread_polytope(seed: int, n: int, vertices: int, time: str, t: float) -> dict:
    """{"vertices": [{"A": Aᵢ(t)}, …]}: Mᵢ(t) = A_c + t Xᵢ (A_c, Xᵢ of :func:`random_polytope`
    with this seed), shifted to spectral abscissa −1 (continuous) or scaled to spectral radius
    0.95 (discrete): every vertex is stable for every t, and the vertices move apart as t
    grows, until some interior point is unstable (benchmarks/stress/hppd_study.py finds where)."""
    data = random_polytope(seed, n=n, vertices=vertices, time=time, spread=1.0, margin=1.0, centre=True)
    out = []
    for v in data["vertices"]:
        M = data["A0"] + t * (np.asarray(v["A"]) - data["A0"])
        eig = np.linalg.eigvals(M)
        A = M - (eig.real.max() + 1.0) * np.eye(n) if time == "continuous" else 0.95 * M / np.abs(eig).max()
        out.append({"A": A.tolist()})
    return {"vertices": out}


def _statement(id, title, equations, time, *, description, degree=1, polya=0, source=OP2007,
               short="Oliveira & Peres 2007", provenance="paper", provenance_note=""):
    """A robust theorem with the dimension n and the simplex α declared."""
    thm = RobustTheorem(id, title, Source(short, equations, source), time=time, degree=degree, polya=polya,
                        description=description, provenance=provenance, provenance_note=provenance_note)
    thm.dim("n")
    thm.simplex("alpha")
    return thm


# -- robust stability ----------------------------------------------------------------------------
hpd_stability_ct = _statement(
    "textbook.hpd_stability_ct", "Robust stability over the simplex with an HPPD Lyapunov matrix (continuous time)",
    "Theorem 3 (HPPD P(α), Polya relaxation)", "continuous",
    description="find P(α) = Σ α^k P_k ≻ 0 with A(α)ᵀP(α) + P(α)A(α) ≺ 0 for all α in the simplex")
_thm = hpd_stability_ct
_n, _alpha = _thm.dims["n"], _thm.simplices[0]
_A = _thm.data("A", _n, _n, over=_alpha, description="vertex state matrices A_i")
_P = _thm.var("P", _n, kind="symmetric", over=_alpha, description="HPPD Lyapunov matrix")
_thm.lmi("(HPPD)", [[He(_P * _A)]])
_thm.positive(_P)
_thm.feasibility()
_thm.verify_with(grid_check())

hpd_stability_dt = _statement(
    "textbook.hpd_stability_dt", "Robust stability over the simplex with an HPPD Lyapunov matrix (discrete time)",
    "Theorem 3, discrete-time form (HPPD P(α), Polya relaxation)", "discrete",
    description="find P(α) ≻ 0 with [[−P(α), A(α)ᵀP(α)], [P(α)A(α), −P(α)]] ≺ 0 for all α in the simplex")
_thm = hpd_stability_dt
_n, _alpha = _thm.dims["n"], _thm.simplices[0]
_A = _thm.data("A", _n, _n, over=_alpha, description="vertex state matrices A_i")
_P = _thm.var("P", _n, kind="symmetric", over=_alpha, description="HPPD Lyapunov matrix")
_thm.lmi("(HPPD)", [
    [-_P],
    [_P * _A, -_P],
])
_thm.positive(_P)
_thm.feasibility()
_thm.verify_with(grid_check())


# -- robust stability margin ------------------------------------------------------------------------
def _margin(id, time):
    thm = _statement(
        id, f"Robust stability margin over the simplex with an HPPD Lyapunov matrix ({time} time)",
        "Theorem 3 applied to A₀ + ρΔA(α), bisection on ρ", time,
        description="the largest ρ for which A₀ + ρ Σ αᵢ ΔAᵢ is certified robustly stable",
        provenance="illustration",
        provenance_note="the stability conditions of Theorem 3 on a polytope scaled by ρ; the "
                        "bisection on ρ is lmidsl's, as in the papers' tables of maximal ranges")
    n, alpha = thm.dims["n"], thm.simplices[0]
    A0 = thm.data("A0", n, n, latex="A_0", description="nominal state matrix")
    dA = thm.data("dA", n, n, over=alpha, latex=r"\Delta A(\alpha)", description="vertex deviations ΔA_i")
    rho = thm.param("rho", latex=r"\rho", domain=(0, 1e6), default=1.0, description="scaling of the uncertainty")
    P = thm.var("P", n, kind="symmetric", over=alpha, description="HPPD Lyapunov matrix")
    A = A0 + rho * dA
    if time == "continuous":
        thm.lmi("(HPPD)", [[He(P * A)]])
    else:
        thm.lmi("(HPPD)", [[-P], [P * A, -P]])
    thm.positive(P)
    thm.feasibility()
    thm.bisect("rho", lower=0.0, upper=10.0, tol=1e-4)
    return thm


hpd_margin_ct = _margin("textbook.hpd_margin_ct", "continuous")
hpd_margin_dt = _margin("textbook.hpd_margin_dt", "discrete")


# -- robust H∞ and H2 analysis -----------------------------------------------------------------------
hpd_hinf_ct = _statement(
    "textbook.hpd_hinf_ct", "Robust H∞ bound over the simplex with an HPPD Lyapunov matrix (continuous time)",
    "the bounded real lemma with P(α) (HPPD), Polya relaxation", "continuous",
    description="min μ: [[He(P(α)A(α)), P(α)B(α), C(α)ᵀ], [⋆, −μI, D(α)ᵀ], [⋆, ⋆, −I]] ≺ 0 for all α",
    provenance="illustration",
    provenance_note="the H∞ counterpart of Theorem 3 (the standard bounded real lemma with an HPPD "
                    "P(α)), as generated by ROLMIP for these papers")
_thm = hpd_hinf_ct
_n, _alpha = _thm.dims["n"], _thm.simplices[0]
_m, _p = _thm.dim("m p")
_A = _thm.data("A", _n, _n, over=_alpha)
_B = _thm.data("B", _n, _m, over=_alpha)
_C = _thm.data("C", _p, _n, over=_alpha)
_D = _thm.data("D", _p, _m, over=_alpha)
_P = _thm.var("P", _n, kind="symmetric", over=_alpha, description="HPPD storage matrix")
_mu = _thm.scalar("mu", latex=r"\mu", description="μ = γ²")
_thm.lmi("(BRL)", [
    [He(_P * _A)],
    [_B.T * _P, -_mu * I],
    [_C, _D, -I],
])
_thm.positive(_P)
_thm.minimize(_mu, performance=("gamma", sp.sqrt(_mu)))
_thm.verify_with(grid_check("hinf"))

hpd_h2_ct = _statement(
    "textbook.hpd_h2_ct", "Robust H2 bound over the simplex with an HPPD Lyapunov matrix (continuous time)",
    "the observability-Gramian LMIs with P(α) (HPPD), Polya relaxation", "continuous",
    description="min tr W: He(P(α)A(α)) + C(α)ᵀC(α) ≺ 0, [[W, B(α)ᵀP(α)], [P(α)B(α), P(α)]] ≻ 0 for all α",
    provenance="illustration",
    provenance_note="the H2 counterpart of Theorem 3 (observability Gramian bounded by an HPPD P(α), "
                    "a common W), as generated by ROLMIP for these papers; D = 0")
_thm = hpd_h2_ct
_n, _alpha = _thm.dims["n"], _thm.simplices[0]
_m, _p = _thm.dim("m p")
_A = _thm.data("A", _n, _n, over=_alpha)
_B = _thm.data("B", _n, _m, over=_alpha)
_C = _thm.data("C", _p, _n, over=_alpha)
_P = _thm.var("P", _n, kind="symmetric", over=_alpha, description="HPPD bound of the observability Gramian")
_W = _thm.var("W", _m, kind="symmetric", description="bound of BᵀP(α)B, common to all α")
_thm.lmi("(Gramian)", [[He(_P * _A) + _C.T * _C]])
_thm.lmi("(W)", [
    [_W],
    [_P * _B, _P],
], sense=">")
_thm.minimize(Trace(_W), performance=("h2", sp.sqrt(Trace(_W))))
_thm.verify_with(grid_check("h2"))


# -- robust state feedback through dilated conditions -----------------------------------------------------
def _closed_loop(system, design):
    return {"A": np.asarray(system["A"]) + np.asarray(system["B"]) @ np.asarray(design["K"])}


def _sf(id, time):
    if time == "discrete":
        equations, source, short = "Theorem 3 (state feedback), with an HPPD P(α)", DOBG, "de Oliveira et al. 1999"
        note = "the vertex P_i of the paper replaced by an HPPD P(α) of degree g (g = 1: the paper's)"
    else:
        equations, source, short = "the extended (dilated) stability LMI, Theorem 1 type, with P(α)", PIPELEERS, \
            "Pipeleers et al. 2009"
        note = "the dilated continuous-time condition with a fixed scalar ξ, derived in theorems/textbook/hpd.py"
    thm = RobustTheorem(id, f"Robust state feedback with an HPPD Lyapunov matrix and a fixed gain ({time} time)",
                        Source(short, equations, source), time=time, degree=1, polya=0, designs="gain",
                        description="a gain K = Z G⁻¹ stabilising A(α) + B(α)K for all α, with P(α) HPPD and a "
                                    "common slack G", provenance="illustration", provenance_note=note)
    n, m = thm.dim("n m")
    alpha = thm.simplex("alpha")
    A = thm.data("A", n, n, over=alpha)
    B = thm.data("B", n, m, over=alpha)
    P = thm.var("P", n, kind="symmetric", over=alpha, description="HPPD Lyapunov matrix")
    G = thm.var("G", n, n, description="slack variable, common to all α")
    Z = thm.var("Z", m, n, description="Z = K G")
    if time == "discrete":
        thm.lmi("(dOBG)", [
            [P],
            [G.T * A.T + Z.T * B.T, G + G.T - P],
        ], sense=">")
    else:
        xi = thm.param("xi", latex=r"\xi", domain=(0, 1e6), open_domain=True, default=1.0,
                       description="fixed scalar of the dilation")
        AG = A * G + B * Z
        thm.lmi("(dilated)", [
            [He(AG)],
            [P - G + xi * AG.T, -xi * (G + G.T)],
        ])
        thm.positive(P)
    thm.feasibility()
    thm.recover(K=Z * G.I)
    thm.verify_with(grid_check(closed_loop=_closed_loop))
    return thm


hpd_sf_ct = _sf("textbook.hpd_sf_ct", "continuous")
hpd_sf_dt = _sf("textbook.hpd_sf_dt", "discrete")

# -- examples ------------------------------------------------------------------------------------------
_NOTE = "generated by theorems/textbook/hpd.py; robustness checked on a grid of the simplex (python-control)"
hpd_stability_ct.example(
    "spread-3", spread_polytope(2302, 2, 3, "continuous", 4.95), params={"degree": 2, "polya": 1},
    provenance="illustration",
    provenance_note="spread_polytope(seed 2302, n 2, N 3, t = 4.95): every vertex has abscissa −1, an interior "
                    "point is unstable from t* = 5.108 (grid, resolution 40); robustly stable here, not "
                    "quadratically stable (g = 0 infeasible); " + _NOTE)
from .polytopic import interval_polytope  # noqa: E402
hpd_stability_dt.example(
    "interval-3", interval_polytope(71, spread=0.35), params={"degree": 1, "polya": 0},
    provenance="illustration",
    provenance_note="the example of textbook.dilated_dt (A0 ± E, seed 71): robustly stable, not quadratically "
                    "stable; " + _NOTE)
_hinf = random_polytope(11, n=3, vertices=3, spread=0.8, inputs=1, outputs=1)
for _v in _hinf["vertices"]:
    _v["D"] = [[0.0]]
hpd_hinf_ct.example("random-3", _hinf, params={"degree": 2, "polya": 0}, provenance="illustration",
                    provenance_note="random_polytope(seed 11, n 3, N 3, spread 0.8); " + _NOTE)
hpd_h2_ct.example("random-2", random_polytope(12, n=3, vertices=2, spread=0.5, inputs=2, outputs=1),
                  params={"degree": 1, "polya": 0}, provenance="illustration",
                  provenance_note="random_polytope(seed 12, n 3, N 2, spread 0.5); " + _NOTE)
for _thm, _time in ((hpd_sf_ct, "continuous"), (hpd_sf_dt, "discrete")):
    _thm.example("unstable-3", random_polytope(3, n=3, vertices=3, time=_time, inputs=1, margin=-1.0, spread=0.3),
                 params={"degree": 2, "polya": 0}, provenance="illustration",
                 provenance_note="random_polytope(seed 3, n 3, N 3, an unstable centre, spread 0.3); " + _NOTE)
for _thm, _time in ((hpd_margin_ct, "continuous"), (hpd_margin_dt, "discrete")):
    _parts = random_polytope(5, n=3, vertices=3, time=_time, spread=1.0, margin=1.0, centre=True)
    _thm.example("random-3", {"A0": _parts["A0"].tolist(),
                              "vertices": [{"dA": (np.asarray(v["A"]) - _parts["A0"]).tolist()}
                                           for v in _parts["vertices"]]},
                 params={"degree": 2, "polya": 0}, provenance="illustration",
                 provenance_note="A0 and ΔA_i of random_polytope(seed 5, n 3, N 3, spread 1); " + _NOTE)

THEOREMS = [hpd_stability_ct, hpd_stability_dt, hpd_margin_ct, hpd_margin_dt, hpd_hinf_ct, hpd_h2_ct,
            hpd_sf_ct, hpd_sf_dt]
