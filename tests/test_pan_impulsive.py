"""Seed 003 (Pan/Sun, impulsive H∞ filtering): the LMIs, the paper's example, the modified example.

Reference numbers are independent computations: the congruence of Lemma 3's (24)/(25) written
in numpy, the analytic bounds derived in docs/reproductions/003.md, the frequency response of
the flow-only error system, and the lifted ℓ2 gain of the simulated impulsive system.
"""
import json

import numpy as np
import pytest

from lmidsl.pipeline import make_instance, solve
from lmidsl.cli import main
from lmidsl.errors import ShapeMismatchError
from lmidsl.theorems.pan_impulsive.impulsive import error_system, impulse_sequence, lifted_gain, simulate
from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix
from lmidsl.theorem.registry import get_theorem

from conftest import load_theorem_module  # noqa: E402

PRINTED_DHAT = 0.9551


PI = load_theorem_module("pan_impulsive", "pan_impulsive_test_copy")


@pytest.mark.parametrize("seed", [1, 2])
def test_27_28_are_the_congruence_image_of_24_25(seed):
    """(27)/(28) = diag(Tc, I, Tc, I)ᵀ (24)/(25) diag(Tc, I, Tc, I) with F, G from (26) (docs/reproductions/003.md)."""
    rng = np.random.default_rng(seed)
    n, m, r = 2, 1, 1
    rnd = lambda *s: rng.standard_normal(s)  # noqa: E731
    A, B, M, C, D, L1, L2 = rnd(n, n), rnd(n, m), rnd(n, n), rnd(r, n), rnd(r, m), rnd(m, n), rnd(m, m)
    lam1, lam2, eps, gam = 0.7, -0.4, 0.3, 1.3
    R, W, T, Psi = rnd(n, n), rnd(n, n), rnd(n, n), rnd(m, m)
    Ah, Bh, Mh, Ch, Dh = rnd(n, n), rnd(n, r), rnd(n, n), rnd(m, n), rnd(m, r)
    Phat = rnd(2 * n, 2 * n)
    Phat = Phat + Phat.T
    Z, I = np.zeros((n, n)), np.eye(n)
    Tc = np.block([[I, Z], [I, -I]])
    P = Tc.T @ Phat @ Tc
    Phi = np.block([[R, W], [Z, T.T]]) @ Tc
    Lam = np.block([[lam1 * I, Z], [Z, lam2 * I]])
    F = np.block([[Lam @ Phi, np.zeros((2 * n, m))], [np.zeros((m, 2 * n)), eps * Psi]])
    G = np.block([[Phi, np.zeros((2 * n, m))], [np.zeros((m, 2 * n)), Psi]])
    Ab = np.block([[A, Z], [Bh @ C, Ah]])
    Bb = np.vstack([B, Bh @ D])
    Mb = np.block([[M, Z], [Z, Mh]])
    Cb = np.hstack([L1 - Dh @ C, -Ch])
    Db = L2 - Dh @ D
    At = np.block([[Ab, Bb], [Cb, Db]])
    Mt = np.block([[Mb, np.zeros((2 * n, m))], [Cb, Db]])
    big = lambda X, s: np.block([[P, np.zeros((2 * n, m))], [np.zeros((m, 2 * n)), s * np.eye(m)]])  # noqa: E731

    def lemma3(Xt):
        return np.block([[-big(P, gam ** 2) + Xt.T @ F + F.T @ Xt, -F.T + Xt.T @ G],
                         [-F + G.T @ Xt, big(P, 1.0) - (G + G.T)]])

    k = 2 * n + m
    Tb = np.zeros((2 * k, 2 * k))
    Tb[:2 * n, :2 * n], Tb[2 * n:k, 2 * n:k] = Tc, np.eye(m)
    Tb[k:k + 2 * n, k:k + 2 * n], Tb[k + 2 * n:, k + 2 * n:] = Tc, np.eye(m)
    values = {"P11": [Phat[:n, :n]], "P12": [Phat[:n, n:]], "P22": [Phat[n:, n:]], "R": R, "W": W,
              "T": T, "Psi": Psi, "S_A": T @ Ah, "S_B": T @ Bh, "S_M": T @ Mh, "S_C": Psi.T @ Ch,
              "S_D": Psi.T @ Dh}
    data = {k_: v.tolist() for k_, v in dict(A=A, B=B, M=M, C=C, D=D, L1=L1, L2=L2).items()}
    inst = make_instance("pan_impulsive.thm1", data={**data, "lambda1": lam1, "lambda2": lam2,
                                                      "epsilon": eps, "gamma": gam})
    point = {**inst.data, **values}
    lmis = {lmi.label: lmi for lmi in inst.theorem.lmis}
    for label, Xt in (("(27)", At), ("(28)", Mt)):
        N = evaluate_block_matrix(NumericEvaluator(inst.dims, point, inst.params, vertex=0), lmis[label].spec)
        ref = Tb.T @ lemma3(Xt) @ Tb
        assert np.abs(N - ref).max() < 1e-12 * max(1.0, np.abs(ref).max())


def test_p_not_equal_m_is_refused_with_the_block_named():
    data = {**PI.PLANT, "L1": [[1.0, 0.0], [0.0, 1.0]], "L2": [[0.0], [0.0]],
            **PI.SCALARS, "gamma": 0.5}
    with pytest.raises(ShapeMismatchError, match="L1"):
        make_instance("pan_impulsive.thm1", data=data)


def test_printed_filter_lemma1_infeasible_with_the_jump_map_responsible():
    """(14) at ξ = [e1; 0] equals (1 − D̂)² whatever P: the feasp t* is that number."""
    sol = solve("pan_impulsive.lemma1", "paper-printed")
    assert sol.feasp.verdict == "infeasible" and not sol.ok      # feasp's word (the solver's: sol.status)
    report = sol.feasp
    bound = (1 - PRINTED_DHAT) ** 2
    assert report.tmin >= bound * (1 - 1e-3)
    assert report.tmin == pytest.approx(bound, rel=2e-2)
    assert report.responsible == ["(14)"]


def test_printed_filter_cannot_meet_half_by_simulation():
    """A single disturbance sample at an impulse instant gives e = −D̂ ω: ratio |D̂| > 0.5."""
    system = error_system({**PI.PLANT, **PI.PRINTED_FILTER})
    E = impulse_sequence("explicit", 20, instants=[3])
    w = np.zeros((20, 1))
    w[3] = 1.0
    assert simulate(system, w, E).energy_ratio == pytest.approx(PRINTED_DHAT, abs=1e-12)
    # all impulses after one disturbance sample: e → (1 − D̂) x1(1) ≠ 0, energy grows without bound
    E = impulse_sequence("all", 400, start=1)
    traj = simulate(system, np.eye(400, 1), E)
    assert np.allclose(traj.e[100:, 0], (1 - PRINTED_DHAT) * 1.0, atol=1e-9)


def test_printed_filter_flow_only_norm_matches_lemma1_on_the_schur_jump_plant():
    """Lemma 1 with M11 = 0.9 certifies ≈ the H∞ norm of the flow-only error system (~78.4 at ω = 0)."""
    system = error_system({**PI.PLANT, **PI.PRINTED_FILTER})
    w = np.linspace(0, np.pi, 4001)
    hinf = max(abs((system.Cbar @ np.linalg.solve(np.exp(1j * x) * np.eye(4) - system.Abar, system.Bbar)
                    + system.Dbar)[0, 0]) for x in w)
    sol = solve("pan_impulsive.lemma1", "modified-printed")
    assert sol.certified
    assert hinf * (1 - 1e-4) <= sol.gamma <= hinf * 1.01
    assert hinf > 70


def test_theorem1_paper_example_is_infeasible_and_json_says_so(capsys):
    code = main(["solve", "pan_impulsive.thm1", "--example", "paper", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1
    assert out["feasp"]["verdict"] == "infeasible"
    feasp = out["feasp"]
    assert feasp["tmin"] > 0.05
    by_label = {m["label"]: m for m in feasp["lmis"]}
    assert by_label["(28)"]["alone"] > 0.05          # the jump LMI alone is infeasible
    assert "(28) @ vertex 1" in feasp["responsible"]


def test_theorem1_min_paper_closure_forces_gamma_one():
    """With M11 = 1, (28)'s (e1, ω) block forces D̂ = 1 in the closure, hence γ ≥ |D̂| = 1."""
    inst = make_instance("pan_impulsive.thm1_min", "paper")
    from lmidsl.solver.backends import get_backend
    sol = get_backend("cvxpy")(inst).solve("CLARABEL")
    if sol.point_gamma is not None:          # the solver's boundary point, when it returns one
        from lmidsl.certify.verdict import judge
        assert sol.point_gamma >= 1 - 1e-3
        assert not judge(sol).verdict.certified
    from lmidsl.solver.feasibility import feasp
    assert feasp(inst, detail=False).verdict == "infeasible"


def test_modified_example_pipeline_certified_and_simulated():
    sol = solve("pan_impulsive.thm1", "modified")
    assert sol.ok and sol.certified
    assert sol.analysis.passed and sol.analysis.gamma <= 0.5
    system = error_system({**PI.MODIFIED_PLANT, **{k: sol.recovered[k] for k in PI.FILTER}})
    for kind in ("none", "periodic", "random", "all"):
        gain, _ = lifted_gain(system, impulse_sequence(kind, 120, period=4))
        assert gain <= sol.analysis.gamma * (1 + 1e-6)


def test_paper_scalars_fail_on_the_modified_plant_too():
    """λ1 ≠ λ2 (the paper's 0.2, −0.3): Theorem 1 cannot reach γ = 0.5 even with a Schur jump map."""
    from lmidsl.solver.feasibility import feasp
    inst = make_instance("pan_impulsive.thm1", "modified", overrides=dict(PI.SCALARS))
    report = feasp(inst, detail=False)
    assert report.verdict == "infeasible" and report.tmin > 0.1


def test_examples_declare_the_printed_values():
    thm = get_theorem("pan_impulsive.thm1")
    ex = thm.examples["paper"]
    assert ex.params == {"lambda1": 0.2, "lambda2": -0.3, "epsilon": 0.1, "gamma": 0.5}
    assert ex.printed["Dhat"] == [[PRINTED_DHAT]]
