"""PICOS backend: golden comparison of the compiled LMI matrices with cvxpy and numpy, and the
same optimum as cvxpy on the paper's examples."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

pytest.importorskip("picos")

from lmidsl import I, Source, Theorem  # noqa: E402
from conftest import run_cli  # noqa: E402
from lmidsl.pipeline import make_instance  # noqa: E402
from lmidsl.solver.backends import get_backend  # noqa: E402
from lmidsl.errors import SolverUnavailableError  # noqa: E402
from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def toy_theorem() -> Theorem:
    """Not from a paper: covers a diagonal variable, a nonneg scalar, a parameter and a derived one."""
    thm = Theorem("test_picos.toy", "toy LMIs", Source("none", "none"))
    n, m = thm.dim("n m")
    A = thm.data("A", n, n)
    B = thm.data("B", n, m)
    P = thm.var("P", n, kind="symmetric")
    Q = thm.var("Q", n, kind="diagonal")
    K = thm.var("K", m, n)
    t = thm.scalar("t", nonneg=True)
    rho = thm.param("rho", domain=(0.0, 1.0))
    b = thm.derived("b", rho * (1 - rho))
    thm.lmi("(1)", [
        [-P + rho * Q],
        [A * P + B * K, -P],
        [b * K, 0, -t * I],
    ])
    thm.lmi("(2)", [[Q - b * t * sp.Identity(n)]], sense=">")
    thm.positive(P)
    thm.minimize(t)
    thm.example("toy", {"A": [[0.5, 1.0, 0.0], [0.0, -0.3, 0.2], [0.1, 0.0, 0.8]],
                        "B": [[1.0], [0.0], [2.0]]}, params={"rho": 0.3})
    return thm


def random_point(instance, rng) -> dict:
    """A random value for every declared decision variable (structure respected)."""
    point = {}
    for name, decl in instance.theorem.var_decl.items():
        symbol = decl.symbol
        if symbol.kind == "structured":
            continue
        if symbol.kind == "scalar":
            value = float(rng.normal())
            point[name] = abs(value) if decl.extra.get("nonneg") else value
            continue
        shape = tuple(int(sp.sympify(d).xreplace(instance.dims)) for d in symbol.shape)

        def draw():
            M = rng.normal(size=shape)
            if symbol.kind == "symmetric":
                return (M + M.T) / 2
            if symbol.kind == "diagonal":
                return np.diag(np.diag(M))
            return M

        point[name] = [draw() for _ in range(instance.nvertices)] if getattr(symbol, "per_vertex", False) else draw()
    return point


def numpy_lmis(instance, point) -> dict:
    """The LMI matrices N evaluated directly by the numpy walk (independent of both backends)."""
    out = {}
    values = dict(instance.data)
    values.update(point)
    for lmi in instance.theorem.lmis:
        for v in (range(instance.nvertices) if lmi.per_vertex else [None]):
            ev = NumericEvaluator(instance.dims, values, instance.params, vertex=v)
            out[(lmi.label, v, "")] = evaluate_block_matrix(ev, lmi.negative_form())
    return out


CASES = [("wang_l2linf.thm3", "paper-full"), ("wang_l2linf.thm3", "paper-reduced"),
         ("wang_l2linf.cor1", "two-vertex"), ("wang_l2linf.thm1", "paper-full-printed"),
         (None, "toy")]


@pytest.mark.parametrize("theorem,example", CASES)
def test_golden_same_lmi_matrices(theorem, example):
    """cvxpy and PICOS assemble the same N for every LMI at the same random point (and numpy agrees)."""
    instance = make_instance(theorem or toy_theorem(), example)
    cvx = get_backend("cvxpy")(instance)
    pic = get_backend("picos")(instance)
    assert [k for k, _ in cvx.lmi_matrices] == [k for k, _ in pic.lmi_matrices]
    rng = np.random.default_rng(4)
    for _ in range(2):
        point = random_point(instance, rng)
        cvx.assign(point)
        pic.assign(point)
        a, b, ref = cvx.lmi_values(), pic.lmi_values(), numpy_lmis(instance, point)
        for key in ref:
            assert a[key].shape == b[key].shape == ref[key].shape, key
            scale = max(1.0, np.abs(ref[key]).max())
            np.testing.assert_allclose(a[key], ref[key], rtol=0, atol=1e-12 * scale, err_msg=str(key))
            np.testing.assert_allclose(b[key], ref[key], rtol=0, atol=1e-12 * scale, err_msg=str(key))


def test_picos_update_recompiles_with_new_parameters():
    """After update(r̄ = 0.6) both backends assemble the N of a fresh r̄ = 0.6 build."""
    base = make_instance("wang_l2linf.thm3", "paper-full")
    changed = base.with_params(rbar=0.6)
    point = random_point(base, np.random.default_rng(7))
    ref = numpy_lmis(changed, point)
    for backend in ("cvxpy", "picos"):
        model = get_backend(backend)(base)
        model.update(changed)
        model.assign(point)
        got = model.lmi_values()
        for key in ref:
            np.testing.assert_allclose(got[key], ref[key], atol=1e-12, err_msg=f"{backend} {key}")


@pytest.mark.parametrize("example", ["paper-full", "paper-reduced"])
def test_picos_cvxopt_same_gamma_as_cvxpy(example):
    """Same γ as cvxpy/Clarabel (rel diff < 1e-4), certificate holds, same analysis verdict."""
    instance = make_instance("wang_l2linf.thm3", example)
    from lmidsl.pipeline import solve_instance
    ref = solve_instance(instance, "clarabel", "cvxpy")
    sol = solve_instance(instance, "cvxopt", "picos")
    assert sol.backend == "picos" and sol.solver == "cvxopt" and sol.ok
    assert abs(sol.optimum_level - ref.optimum_level) / ref.optimum_level < 1e-4
    assert sol.certified
    assert sol.analysis is not None and sol.analysis.passed
    for name in ("Af", "Bf", "Cf"):
        assert sol.recovered[name].shape == ref.recovered[name].shape


def test_cli_solve_picos_matches_cvxpy():
    """`lmidsl solve wang_l2linf.thm3 --example paper-full --backend picos --solver cvxopt`."""
    def run(*extra):
        code, out, err = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--json", *extra)
        assert code == 0, err
        return json.loads(out)
    picos_sol = run("--backend", "picos", "--solver", "cvxopt")
    cvxpy_sol = run()
    assert picos_sol["backend"] == "picos" and picos_sol["certified"]
    assert abs(picos_sol["gamma"] - cvxpy_sol["gamma"]) / cvxpy_sol["gamma"] < 1e-4
    assert picos_sol["certified"] and picos_sol["analysis"]["passed"]


@pytest.mark.parametrize("solver", ["clarabel", "SCS"])
def test_picos_refuses_clarabel_and_scs_in_one_line(solver):
    instance = make_instance("wang_l2linf.thm3", "paper-full")
    with pytest.raises(SolverUnavailableError, match=r"PICOS 2\.\d+(\.\d+)? has no interface for solver"):
        get_backend("picos")(instance).solve(solver)
    code, _, err = run_cli("solve", "wang_l2linf.thm3", "--example", "paper-full", "--backend", "picos",
                           "--solver", solver)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "has no interface" in lines[0] and "--backend cvxpy" in lines[0]


def test_picos_refuses_an_asymmetric_diagonal_block():
    """PICOS will not constrain a structurally asymmetric matrix; the error names the LMI."""
    from lmidsl.errors import TheoremDefinitionError
    thm = Theorem("test_picos.asym", "asymmetric", Source("none", "none"))
    n = thm.dim("n")
    A = thm.data("A", n, n)
    X = thm.var("X", n, n)
    thm.lmi("(9)", [[A * X]])
    thm.example("e", {"A": [[1.0, 2.0], [0.0, 1.0]]})
    with pytest.raises(TheoremDefinitionError, match=r"LMI \(9\)"):
        get_backend("picos")(make_instance(thm, "e"))


def test_picos_matches_cvxpy_on_seed001_with_scaling():
    """Issue 4: li_delay_dropout.thm2 (UPS data, automatic output scaling) on both backends."""
    from lmidsl.pipeline import solve
    cvx = solve("li_delay_dropout.thm2", example="paper", certify=False, backoff=None)
    pic = solve("li_delay_dropout.thm2", example="paper", backend="picos", solver="cvxopt", certify=False, backoff=None)
    assert pic.ok and pic.lmis_hold and pic.backend == "picos"
    assert abs(pic.gamma - cvx.gamma) / cvx.gamma < 1e-4
    assert abs(cvx.gamma - 0.3813) / 0.3813 < 5e-3
