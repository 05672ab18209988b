"""The S-procedure helper (lmidsl.symbolic.sprocedure) against brute force over sampled F.

Soundness: whenever the LMI the helper produces is feasible, the original robust inequality
M + He(H F E) < 0 holds at the returned point for every sampled F with FᵀF ≤ I.
Exactness for one full block (Petersen's lemma): the helper's LMI is infeasible exactly when
some admissible F violates the original, here with an independent criterion.
"""
import numpy as np
import pytest
import sympy as sp

from lmidsl import He, Source, Theorem
from lmidsl.pipeline import make_instance, solve_instance
from lmidsl.errors import NonlinearityError
from lmidsl.symbolic.sprocedure import (FORMS, NormBounded, contraction_samples, robust_matrix,
                                   sprocedure)

SRC = Source("test", "-")


def lyapunov_theorem(form: str, tag: str) -> Theorem:
    """min t s.t. Aᵀ P + P A + He(P H F E) ≤ t I for all ‖F‖ ≤ 1, I ≤ P ≤ 100 I (via the helper)."""
    thm = Theorem(f"test_sproc.{tag}", "robust Lyapunov", SRC, time="continuous")
    n, k, l = thm.dim("n k l")
    A = thm.data("A", n, n)
    H = thm.data("H", n, k)
    E = thm.data("E", l, n)
    P = thm.var("P", n, kind="symmetric")
    t = thm.scalar("t")
    eps = thm.scalar("eps", nonneg=True)
    spec = sprocedure([[He(P * A) - t * sp.Identity(n)]], [NormBounded([P * H], [E], eps, form=form)])
    thm.lmi("robust", spec, sense="<=")
    thm.lmi("P >= I", [[P - sp.Identity(n)]], sense=">=")
    thm.lmi("P <= 100 I", [[P - 100 * sp.Identity(n)]], sense="<=")   # t is homogeneous in (P, ε)
    thm.minimize(t)
    return thm


def random_plant(rng, n=3, k=2, l=2, scale=1.0):
    A = rng.standard_normal((n, n))
    A = A - (np.max(np.linalg.eigvals(A).real) + 1.0) * np.eye(n)   # Hurwitz, margin 1
    return {"A": A.tolist(), "H": (scale * rng.standard_normal((n, k))).tolist(),
            "E": (scale * rng.standard_normal((l, n))).tolist()}


def hinf_norm(A, H, E):
    """sup_ω ‖E (jωI − A)⁻¹ H‖ on a dense grid (independent of any LMI)."""
    w = np.concatenate([[0.0], np.logspace(-3, 3, 3000)])
    n = A.shape[0]
    return max(np.linalg.norm(E @ np.linalg.solve(1j * x * np.eye(n) - A, H), 2) for x in w)


@pytest.mark.parametrize("seed", range(6))
def test_feasible_helper_lmi_holds_for_sampled_F(seed):
    rng = np.random.default_rng(seed)
    data = random_plant(rng, scale=0.6)
    thm = lyapunov_theorem("diag", f"sound{seed}")
    sol = solve_instance(make_instance(thm, data=data), certify=False)
    assert sol.ok
    t = sol.values["t"]
    P = sol.values["P"]
    A, H, E = (np.array(data[x]) for x in "AHE")
    worst = max(np.linalg.eigvalsh(robust_matrix(A.T @ P + P @ A, P @ H, F, E))[-1]
                for F in contraction_samples(2, 2, 3000, rng))
    # the robust inequality holds at the returned P for every sampled admissible F
    assert worst <= t + 1e-6 * max(1.0, abs(t))


@pytest.mark.parametrize("seed", range(6))
def test_helper_lmi_feasible_iff_small_gain(seed):
    """Quadratic stability against a full time-varying block ⟺ ‖E(sI − A)⁻¹H‖∞ < 1."""
    rng = np.random.default_rng(100 + seed)
    data = random_plant(rng)
    A, H, E = (np.array(data[x]) for x in "AHE")
    g = hinf_norm(A, H, E)
    thm = lyapunov_theorem("diag", f"exact{seed}")
    for factor, feasible in ((0.9, True), (1.1, False)):
        scaled = dict(data, E=(factor / g * E).tolist())   # ‖·‖∞ = factor
        sol = solve_instance(make_instance(thm, data=scaled), certify=False)
        assert sol.ok
        assert (sol.values["t"] < 0) == feasible, (factor, sol.values["t"])


def test_scalar_block_exact_against_vertices():
    """Numeric M with rank-one H, E: ∃ε ⟺ M ± He(hE) < 0 at F = ±1 (the vertices are exact)."""
    rng = np.random.default_rng(7)
    thm = Theorem("test_sproc.numeric", "numeric Petersen", SRC)
    n, one = thm.dim("n one")
    M = thm.data("M", n, n, symmetric=True)
    h = thm.data("h", n, one)
    e = thm.data("e", one, n)
    t = thm.scalar("t")
    eps = thm.scalar("eps", nonneg=True)
    thm.lmi("S", sprocedure([[M - t * sp.Identity(n)]], [NormBounded([h], [e], eps, form="columns")]), sense="<=")
    thm.minimize(t)
    agree = 0
    for _ in range(25):
        X = rng.standard_normal((4, 4))
        Mv = -(X @ X.T) - 0.2 * np.eye(4)
        hv, ev = rng.standard_normal((4, 1)), rng.standard_normal((1, 4))
        brute = max(np.linalg.eigvalsh(robust_matrix(Mv, hv, np.array([[f]]), ev))[-1] for f in (-1.0, 1.0))
        if abs(brute) < 1e-3:
            continue
        sol = solve_instance(make_instance(thm, data={"M": Mv.tolist(), "h": hv.tolist(), "e": ev.tolist()}),
                             certify=False)
        assert (sol.values["t"] < 0) == (brute < 0)
        agree += 1
    assert agree >= 20


@pytest.mark.parametrize("form", FORMS)
def test_all_forms_agree(form):
    """Every form states M + ε⁻¹HHᵀ + εEᵀE < 0 (dual forms with ε ↔ ε⁻¹): same optimum."""
    rng = np.random.default_rng(3)
    thm = Theorem(f"test_sproc.form_{form.replace('-', '_')}", "forms", SRC)
    n, k = thm.dim("n k")
    M = thm.data("M", n, n, symmetric=True)
    H = thm.data("H", n, k)
    E = thm.data("E", k, n)
    t = thm.scalar("t")
    eps = thm.scalar("eps", nonneg=True)
    thm.lmi("S", sprocedure([[M - t * sp.Identity(n)]], [NormBounded([H], [E], eps, form=form)]), sense="<=")
    thm.minimize(t)
    X = rng.standard_normal((3, 3))
    data = {"M": (-(X @ X.T) - np.eye(3)).tolist(), "H": rng.standard_normal((3, 2)).tolist(),
            "E": rng.standard_normal((2, 3)).tolist()}
    sol = solve_instance(make_instance(thm, data=data), certify=False)
    # reference: min over ε of λmax(M + ε⁻¹HHᵀ + εEᵀE), by a scalar search
    Mv, Hv, Ev = (np.array(data[x]) for x in "MHE")
    grid = np.logspace(-3, 3, 4000)
    ref = min(np.linalg.eigvalsh(Mv + Hv @ Hv.T / e + e * Ev.T @ Ev)[-1] for e in grid)
    assert sol.values["t"] == pytest.approx(ref, abs=2e-3 * max(1, abs(ref)))


def test_layout_of_the_columns_form():
    """[M, εEᵀ, H; εE, −εI, 0; Hᵀ, 0, −εI]: the block layout of (15)."""
    n, k = 2, 1
    M = sp.MatrixSymbol("M", n, n)
    H = sp.MatrixSymbol("H", n, k)
    E = sp.MatrixSymbol("E", k, n)
    eps = sp.Symbol("eps")
    spec = sprocedure([[M]], [NormBounded([H], [E], eps, form="columns")])
    assert spec.sizes == [2, 1, 1]
    assert spec.lower[1][0] == eps * E
    assert spec.lower[2][0] == H.T
    assert spec.lower[1][1] == -eps * sp.Identity(1)
    assert isinstance(spec.lower[2][1], sp.ZeroMatrix)


def test_wrong_form_is_refused_with_the_block_named():
    """The dual form puts ε next to H = P H₀ (two variables multiplied): refused at declaration."""
    thm = Theorem("test_sproc.bad", "bad", SRC, time="continuous")
    n, k = thm.dim("n k")
    A, H, E = thm.data("A", n, n), thm.data("H", n, k), thm.data("E", k, n)
    P = thm.var("P", n, kind="symmetric")
    eps = thm.scalar("eps", nonneg=True)
    spec = sprocedure([[He(P * A)]], [NormBounded([P * H], [E], eps, form="dual-columns")])
    with pytest.raises(NonlinearityError, match=r"LMI robust block \(3,1\)"):
        thm.lmi("robust", spec)
