"""Index sets: declaration checks, instantiation, coefficient structure, printing, zero data.

Numbers are compared with independent computations: numpy's Kronecker product, the textbook
H∞ state-feedback theorem (itself checked against python-control) for a one-mode jump system,
the second-moment matrix assembled here by hand.
"""
from __future__ import annotations

import numpy as np
import pytest
from sympy import Ne, sqrt

import lmidsl
from lmidsl import He, I, Source, Theorem, diag_over, kron, stack_over, sum_over
from lmidsl.errors import InputError, NonlinearityError, ShapeMismatchError, TheoremDefinitionError
from lmidsl.pipeline import make_instance
from lmidsl.render.latex import lmi_latex
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.theorems.textbook import hinf_sf, markov
from lmidsl.theorems.textbook.fuzzy import ts_pdc_ct
from lmidsl.theorems.textbook.plants import random_plant, subset


def _mjls(name="t.mjls"):
    thm = Theorem(name, "MJLS", Source("test", "test"), time="continuous", designs="gain")
    n, m = thm.dim("n m")
    M = thm.index_set("modes", latex=r"\mathcal{N}")
    i, j = M.indices("i j")
    A = thm.data("A", n, n, over=M)
    B = thm.data("B", n, m, over=M)
    Pi = thm.coefficients("Pi", M, structure="generator", latex=r"\pi")
    Y = thm.var("Y", n, kind="symmetric", over=M)
    W = thm.var("W", m, n, over=M)
    return thm, (M, i, j, A, B, Pi, Y, W)


def test_a_free_index_must_be_quantified_or_summed():
    thm, (M, i, j, A, B, Pi, Y, W) = _mjls("t.free")
    with pytest.raises(TheoremDefinitionError, match="the index j is free but not quantified"):
        thm.lmi("(1)", [[He(A[i] * Y[j])]], forall=i)


def test_a_product_of_indexed_variables_is_refused():
    thm, (M, i, j, A, B, Pi, Y, W) = _mjls("t.nonlin")
    with pytest.raises(NonlinearityError, match="not affine"):
        thm.lmi("(1)", [[He(Y[i] * Y[j])]], forall=(i, j))


def test_a_sum_must_conform_symbolically():
    thm, (M, i, j, A, B, Pi, Y, W) = _mjls("t.shape")
    with pytest.raises(ShapeMismatchError):
        thm.lmi("(1)", [[He(A[i] * Y[i]) + sum_over(j, W[j])]], forall=i)


def test_one_statement_gives_one_lmi_per_instance_and_pairs_for_i_below_j():
    data = {"rules": [{"A": [[0.0, 1.0], [1.0, 0.0]], "B": [[0.0], [1.0]]}] * 4}
    inst = make_instance(ts_pdc_ct, None, data, None)
    labels = [l.label for l in inst.theorem.lmis]
    assert sum(l.startswith("(C1") for l in labels) == 4
    assert sum(l.startswith("(C2") for l in labels) == 4 * 3 // 2
    assert "(C2, i=1, j=3)" in labels and "(C2, i=3, j=1)" not in labels


def test_coefficient_structure_is_checked_at_bind_time():
    modes = markov.EXAMPLE_MODES
    with pytest.raises(InputError, match=r"off-diagonal entry \(1, 2\) is -1 < 0"):
        make_instance(markov.mjls_sf_ct, None, {"modes": modes, "Pi": [[1, -1, 0], [1, -1, 0], [0, 0, 0]]}, None)
    with pytest.raises(InputError, match=r"row 1 sums to 1, not 0 \(tolerance 2e-09\)"):
        make_instance(markov.mjls_sf_ct, None, {"modes": modes, "Pi": [[-1, 2, 0], [1, -1, 0], [0, 0, 0]]}, None)
    with pytest.raises(InputError, match=r"row 1 sums to 0.9, not 1"):
        make_instance(markov.mjls_sf_dt, None, {"modes": modes, "Pi": [[0.5, 0.4, 0.0], [0, 1, 0], [0, 0, 1]]}, None)
    with pytest.raises(InputError, match=r"is 2×2 but there are 3 modes"):
        make_instance(markov.mjls_sf_ct, None, {"modes": modes, "Pi": [[-1, 1], [1, -1]]}, None)


def test_unknown_member_data_is_refused_in_one_line():
    with pytest.raises(InputError, match=r"modes\[1\]: 'C' is not data indexed by the modes"):
        make_instance(markov.mjls_sf_ct, None, {"modes": [{"A": [[1.0]], "B": [[1.0]], "C": [[1.0]]}],
                                               "Pi": [[0.0]]}, None)


def test_cli_refuses_a_bad_generator_with_exit_code_2(tmp_path):
    from conftest import run_cli
    import json
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"modes": markov.EXAMPLE_MODES, "Pi": [[1, 0, -1], [0, 0, 0], [0, 0, 0]]}))
    code, out, err = run_cli("solve", "textbook.mjls_sf_ct", "--data", str(path))
    assert code == 2 and len(err.strip().splitlines()) == 1 and "generator" in err


def test_one_mode_jump_system_is_the_textbook_hinf_state_feedback():
    """N = 1: the stack over j ≠ i is empty (its block row is dropped) and the theorem is the
    H∞ state-feedback LMI of textbook.hinf_sf_ct, whose γ python-control confirms elsewhere."""
    for seed in (11, 12, 13):
        plant = subset(random_plant(seed, 3, 2, 1, 2, 1, "continuous"), hinf_sf.SF_DATA)
        ref = lmidsl.solve(hinf_sf.hinf_sf_ct, data=plant, backoff=None)
        mode = {"A": plant["A"], "B1": plant["B1"], "B2": plant["B2"], "C1": plant["C1"],
                "D11": plant["D11"], "D12": plant["D12"]}
        sol = lmidsl.solve(markov.mjls_hinf_sf_ct, data={"modes": [mode], "Pi": [[0.0]]}, backoff=None)
        assert sol.ok and ref.ok      # both optima (the design at the optimum may be ill-conditioned)
        assert abs(sol.optimum_level - ref.optimum_level) <= 1e-4 * ref.optimum_level
        delivered = lmidsl.solve(markov.mjls_hinf_sf_ct, data={"modes": [mode], "Pi": [[0.0]]})
        assert delivered.certified and delivered.analysis.gamma <= delivered.gamma * (1 + 1e-3)


def test_an_uncontrolled_mode_with_zero_input_matrix_gets_a_zero_gain():
    sol = lmidsl.solve(markov.mjls_sf_ct, example="three-modes")
    assert sol.certified
    assert np.allclose(sol.design["K_3"], 0.0)
    closed = [np.array(md["A"]) + np.array(md["B"]) @ sol.design[f"K_{k + 1}"]
              for k, md in enumerate(markov.EXAMPLE_MODES)]
    Pi = np.array(markov.EXAMPLE_RATES)
    n = 2
    big = np.zeros((3 * n * n, 3 * n * n))
    for k, a in enumerate(closed):
        big[4 * k:4 * k + 4, 4 * k:4 * k + 4] = np.kron(a, np.eye(n)) + np.kron(np.eye(n), a)
    big += np.kron(Pi.T, np.eye(n * n))
    assert np.linalg.eigvals(big).real.max() < 0


def test_sum_over_matches_the_sum_written_out():
    """Σ_j π_ij Y_j compiled equals the same sum written by hand, entry by entry."""
    thm, (M, i, j, A, B, Pi, Y, W) = _mjls("t.sum")
    thm.lmi("(S)", [[He(A[i] * Y[i]) + sum_over(j, Pi[i, j] * Y[j])]], forall=i)
    thm.feasibility()
    rng = np.random.default_rng(0)
    data = {"modes": [{"A": rng.standard_normal((2, 2)).tolist(), "B": [[1.0], [0.0]]} for _ in range(3)],
            "Pi": [[-3.0, 1.0, 2.0], [0.5, -1.0, 0.5], [1.0, 1.0, -2.0]]}
    inst = make_instance(thm, None, data, None)
    model = DirectModel(inst)
    values = {f"Y_{k}": (lambda X: X + X.T)(rng.standard_normal((2, 2))) for k in (1, 2, 3)}
    values.update({f"W_{k}": rng.standard_normal((1, 2)) for k in (1, 2, 3)})
    model.assign(values)
    got = model.lmi_values()
    Pi = np.array(data["Pi"])
    for k in range(3):
        Ak = np.array(data["modes"][k]["A"])
        expect = Ak @ values[f"Y_{k + 1}"] + (Ak @ values[f"Y_{k + 1}"]).T + sum(
            Pi[k, l] * values[f"Y_{l + 1}"] for l in range(3))
        assert np.allclose(got[(f"(S, i={k + 1})", None, "")], expect)


def test_kron_with_a_constant_matrix_is_numpys_kron():
    thm = Theorem("t.kron", "kron", Source("t", "t"), time="continuous")
    n = thm.dim("n")
    X = thm.var("X", n, kind="symmetric")
    L = [[1.0, 0.5], [0.5, -2.0]]
    thm.lmi("(K)", [[kron(L, X)]], sense="<=", strict=False)
    thm.feasibility()
    inst = make_instance(thm, None, {"n": 3}, None)
    model = DirectModel(inst)
    Xv = np.arange(9.0).reshape(3, 3)
    Xv = Xv + Xv.T
    model.assign({"X": Xv})
    (value,) = model.lmi_values().values()
    assert np.allclose(value, np.kron(np.array(L), Xv))


def test_an_entry_of_plain_data_is_a_scalar_coefficient():
    """``Pd[0, 1]`` of a data matrix (sympy's MatrixElement) compiles to the number."""
    thm = Theorem("t.elem", "elem", Source("t", "t"), time="continuous")
    n = thm.dim("n")
    A = thm.data("A", n, n)
    Pd = thm.data("Pd", 2, 2)
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("(E)", [[He(P * A) + Pd[0, 1] * P]])
    thm.positive(P)
    thm.feasibility()
    ok = lmidsl.solve(thm, data={"A": [[-1.0, 0.0], [0.0, -2.0]], "Pd": [[0.0, 1.5], [0.0, 0.0]]})
    bad = lmidsl.solve(thm, data={"A": [[-1.0, 0.0], [0.0, -2.0]], "Pd": [[0.0, 2.5], [0.0, 0.0]]})
    assert ok.certified          # A + 0.75 I is Hurwitz
    assert not bad.certified     # A + 1.25 I is not


@pytest.mark.parametrize("backend", ["direct", "cvxpy", "picos"])
def test_a_parameter_inside_an_inverse_compiles_on_every_backend(backend):
    thm = Theorem(f"t.inv_{backend}", "inv", Source("t", "t"), time="continuous")
    n, m = thm.dim("n m")
    A = thm.data("A", n, n)
    D = thm.data("D", n, m)
    r = thm.param("r", domain=(0.01, 100))
    g = thm.scalar("g")
    # min g s.t. (r I + D Dᵀ)⁻¹ ⪯ g I: the largest eigenvalue of (r I + D Dᵀ)⁻¹, 1/r here
    thm.lmi("(inv)", [[(r * I + D * D.T).I - g * I]], sense="<=", strict=False)
    thm.minimize(g)
    data = {"A": [[-1.0, 0.0], [0.0, -2.0]], "D": [[1.0], [0.0]]}
    for value in (0.5, 4.0):
        sol = lmidsl.solve(thm, data={**data, "r": value}, backend=backend)
        assert abs(sol.objective - 1.0 / value) < 1e-5 * max(1.0, 1.0 / value)


def test_direct_model_update_recompiles_a_folded_parameter():
    thm = Theorem("t.inv_update", "inv", Source("t", "t"), time="continuous")
    n, m = thm.dim("n m")
    D = thm.data("D", n, m)
    r = thm.param("r", domain=(0.01, 100))
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("(inv)", [[(r * I + D * D.T).I - P]], sense="<=", strict=False)
    thm.feasibility()
    inst = make_instance(thm, None, {"D": [[1.0], [0.0]], "r": 1.0}, None)
    model = DirectModel(inst, reuse=True)
    model.update(inst.with_params(r=3.0))
    model.assign({"P": np.zeros((2, 2))})
    (value,) = model.lmi_values().values()
    assert np.allclose(value, np.linalg.inv(3.0 * np.eye(2) + np.array([[1.0, 0.0], [0.0, 0.0]])))


def test_latex_prints_one_quantified_lmi_with_its_ranges():
    text = lmi_latex(markov.mjls_sf_ct, "(MJ)")
    assert r"\forall\, i \in \mathcal{N}" in text
    assert r"\operatorname{col}_{j \in \mathcal{N}, j \neq i}\left(\sqrt{\pi_{ij}} Y_i\right)" in text
    assert r"-\operatorname{diag}_{j \in \mathcal{N}, j \neq i}\left(Y_j\right)" in text
    pair = lmi_latex(ts_pdc_ct, "(C2)")
    assert pair.endswith(r",\quad \forall\, i, j \in \mathcal{R},\ i < j")
    assert "A_j X" in pair and "B_i M_j" in pair


def test_latex_keeps_named_matrices_under_a_transpose_and_states_the_bisection():
    from lmidsl.render.latex import bisection_latex
    from lmidsl.theorems.textbook.delay import delay_wirtinger
    text = lmi_latex(delay_wirtinger, "(W)")
    assert "G_h^{T} P H + H^{T} P G_h" in text and "E_1^{T} R E_1" in text
    goal = bisection_latex(delay_wirtinger)
    assert goal.startswith(r"Maximise $h \in [0, 10]$")


def test_member_is_built_once_per_size():
    a = markov.mjls_sf_ct.specialise({"modes": markov.EXAMPLE_MODES})
    b = markov.mjls_sf_ct.specialise({"modes": markov.EXAMPLE_MODES})
    c = markov.mjls_sf_ct.specialise({"modes": markov.EXAMPLE_MODES[:2]})
    assert a is b and a is not c
    assert len([l for l in c.lmis if l.label.startswith("(MJ")]) == 2
    # flattened inputs (A_1, ..., as an analysis counterpart passes them) select the same member
    flat = {f"A_{k + 1}": md["A"] for k, md in enumerate(markov.EXAMPLE_MODES)}
    assert markov.mjls_sf_ct.specialise(flat) is a
