"""Robust stability of a polytope of matrices: quadratic stability and the dilated
(parameter-dependent) discrete-time condition.

References: Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and
Control Theory*, SIAM 1994, §5.1 (quadratic stability of a polytopic LDI: one P for all
vertices); de Oliveira, Bernussou, Geromel, "A new discrete-time robust stability condition",
Systems & Control Letters 37:261-265, 1999 (the dilated condition with vertex-dependent Pᵢ and a
common slack G).

For A(λ) = Σ λᵢ Aᵢ, λ in the unit simplex:

* ``textbook.quadstab_ct``: P ≻ 0 with AᵢᵀP + PAᵢ ≺ 0 at every vertex ⇒ A(λ) Hurwitz for all λ;
* ``textbook.quadstab_dt``: P ≻ 0 with [[−P, AᵢᵀP], [PAᵢ, −P]] ≺ 0 (AᵢᵀPAᵢ − P ≺ 0) ⇒ A(λ) Schur;
* ``textbook.dilated_dt``: Pᵢ ≻ 0, G with [[Pᵢ, AᵢᵀGᵀ], [GAᵢ, G + Gᵀ − Pᵢ]] ≻ 0 at every vertex
  ⇒ A(λ) Schur, with the parameter-dependent Lyapunov matrix P(λ) = Σ λᵢ Pᵢ.  Taking Pᵢ = G = P
  recovers quadratic stability, so the dilated condition is never more conservative.

All three are feasibility problems and only sufficient; the independent check grids the polytope
(spectral abscissa / radius of A(λ)).
"""
import numpy as np
from lmidsl import He, Source, Theorem

BOYD = ("Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System and "
        "Control Theory, SIAM 1994")
DOBG = ("de Oliveira, Bernussou, Geromel, A new discrete-time robust stability condition, "
        "Systems & Control Letters 37:261-265, 1999")


def _polytope(thm: Theorem):
    n = thm.dim("n")
    return n, thm.data("A", n, n, per_vertex=True, description="vertex state matrix A_i")


quadstab_ct = Theorem("textbook.quadstab_ct", "Quadratic stability of a polytope (continuous time)",
                      Source("Boyd et al. 1994", "Sec. 5.1, quadratic stability of a polytopic LDI", BOYD),
                      time="continuous", description="find P ≻ 0 with A_iᵀP + PA_i ≺ 0 at every vertex")
_n, _A = _polytope(quadstab_ct)
_P = quadstab_ct.var("P", _n, kind="symmetric", description="common Lyapunov matrix")
quadstab_ct.lmi("(QS)", [[He(_P * _A)]])
quadstab_ct.positive(_P)
quadstab_ct.feasibility()

quadstab_dt = Theorem("textbook.quadstab_dt", "Quadratic stability of a polytope (discrete time)",
                      Source("Boyd et al. 1994", "Sec. 5.1, quadratic stability of a polytopic LDI", BOYD),
                      time="discrete", description="find P ≻ 0 with A_iᵀPA_i − P ≺ 0 at every vertex")
_n, _A = _polytope(quadstab_dt)
_P = quadstab_dt.var("P", _n, kind="symmetric", description="common Lyapunov matrix")
quadstab_dt.lmi("(QS)", [
    [-_P],
    [_P * _A, -_P],
])
quadstab_dt.positive(_P)
quadstab_dt.feasibility()

dilated_dt = Theorem("textbook.dilated_dt", "Dilated robust stability condition (discrete time)",
                     Source("de Oliveira, Bernussou, Geromel 1999", "the dilated LMI with P_i and a slack G", DOBG),
                     time="discrete",
                     description="find P_i ≻ 0 and G with [[P_i, A_iᵀGᵀ], [GA_i, G + Gᵀ − P_i]] ≻ 0 at every vertex")
_n, _A = _polytope(dilated_dt)
_Pi = dilated_dt.var("P", _n, kind="symmetric", per_vertex=True, latex="P",
                     description="vertex Lyapunov matrix (P(λ) = Σ λ_i P_i)")
_G = dilated_dt.var("G", _n, _n, description="slack variable, common to the vertices")
dilated_dt.lmi("(dOBG)", [
    [_Pi],
    [_G * _A, _G + _G.T - _Pi],
], sense=">")
dilated_dt.positive(_Pi)
dilated_dt.feasibility()


def interval_polytope(seed: int, n: int = 3, radius: float = 0.9, spread: float = 0.5, time: str = "discrete"):
    """Two vertices A0 ± spread·E with A0 stable (spectral radius ``radius`` / abscissa −1) and E
    random of unit 2-norm: {"vertices": [{"A": ...}, {"A": ...}]}."""
    rng = np.random.default_rng(seed)
    A0 = rng.standard_normal((n, n))
    if time == "discrete":
        A0 = radius * A0 / max(abs(np.linalg.eigvals(A0)))
    else:
        A0 = A0 - (max(np.linalg.eigvals(A0).real) + 1.0) * np.eye(n)
    E = rng.standard_normal((n, n))
    E = spread * E / np.linalg.norm(E, 2)
    return {"vertices": [{"A": (A0 + E).tolist()}, {"A": (A0 - E).tolist()}]}


quadstab_ct.example("interval-3", interval_polytope(51, time="continuous"), provenance="illustration",
                    provenance_note="A0 ± E, numpy seed 51 (theorems/textbook/polytopic.py)")
# seed 71, spread 0.35: robustly stable (spectral radius ≤ 0.9421 on a 401-point grid of the
# segment), not quadratically stable, stable by the dilated condition — chosen among seeds
# 60..74 to show the difference
_INTERVAL = interval_polytope(71, spread=0.35)
quadstab_dt.example("interval-3", _INTERVAL, provenance="illustration",
                    provenance_note="A0 ± E, numpy seed 71, spread 0.35 (theorems/textbook/polytopic.py); "
                                    "robustly stable but not quadratically stable",
                    expect="infeasible",
                    expect_note="not quadratically stable: with I ⪯ P ⪯ 10⁴I, min t s.t. A_iᵀPA_i − P ⪯ tI "
                                "at both vertices is 0.239 > 0 (Clarabel, CVXOPT and SCS agree; "
                                "tests/test_textbook.py); feasp finds no strictly feasible point")
dilated_dt.example("interval-3", _INTERVAL, provenance="illustration",
                   provenance_note="A0 ± E, numpy seed 71, spread 0.35 (theorems/textbook/polytopic.py); "
                                   "robustly stable, not quadratically stable, feasible here")

THEOREMS = [quadstab_ct, quadstab_dt, dilated_dt]
