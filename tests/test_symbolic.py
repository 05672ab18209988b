"""The symbolic layer: symmetric variables, block triangles, sizing, shape and linearity checks."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from lmidsl import I, He, Source, Theorem, block_matrix, congruence, diag, schur
from lmidsl.errors import NonlinearityError, ShapeMismatchError, TheoremDefinitionError
from lmidsl.numeric.instance import bind
from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix
from lmidsl.solver.backends.cvxpy_backend import CvxpyModel


def small_theorem(tid="t.small"):
    thm = Theorem(tid, "small", Source("none", "(1)"))
    n, m = thm.dim("n m")
    A = thm.data("A", n, n)
    B = thm.data("B", n, m)
    P = thm.var("P", n, kind="symmetric")
    g = thm.scalar("g")
    return thm, (n, m), A, B, P, g


def test_symmetric_variable_is_its_own_transpose():
    thm, _, A, _, P, _ = small_theorem()
    assert P.T is P
    assert (A.T * P).T == P * A
    V = thm.var("V", 3, 3)
    assert V.T != V


def test_symbols_of_different_theorems_never_mix():
    t1 = Theorem("t.one", "", Source("x", "y"))
    t2 = Theorem("t.two", "", Source("x", "y"))
    r1, r2 = t1.param("r"), t2.param("r")
    a1 = t1.derived("a", r1 * (1 - r1))
    a2 = t2.derived("a", 2 * r2)
    assert a1 != a2 and a1.definition != a2.definition
    n = t1.dim("n")
    P1 = t1.var("P", n, kind="symmetric", per_vertex=True)
    n2 = t2.dim("n")
    P2 = t2.var("P", n2, kind="symmetric")
    assert (-P1).args[1].per_vertex is True and (-P2).args[1].per_vertex is False


def test_block_triangle_sizes_markers_from_row_and_column():
    thm, (n, m), A, B, P, g = small_theorem()
    spec = block_matrix([[-P], [0, -I], [P * A, P * B, -P]])
    assert spec.sizes == [n, m, n]
    assert spec.lower[1][1] == -sp.Identity(m)
    assert spec.block(0, 2) == (P * A).T
    assert spec.lower[1][0] == sp.ZeroMatrix(m, n)


def test_upper_triangle_input_equals_lower():
    thm, (n, m), A, B, P, g = small_theorem()
    lower = block_matrix([[-P], [B.T * P, -g * I]])
    upper = block_matrix([[-P, P * B], [-g * I]], triangle="upper")
    assert lower.sizes == upper.sizes
    assert sp.simplify(lower.lower[1][0] - upper.lower[1][0]) == sp.ZeroMatrix(m, n)


def test_unsizable_marker_row_is_an_error():
    thm, (n, m), A, B, P, g = small_theorem()
    with pytest.raises(ShapeMismatchError, match="size of block row 2 is not fixed"):
        block_matrix([[-P], [0, -I]])


def test_shape_error_names_lmi_and_block():
    thm, (n, m), A, B, P, g = small_theorem()
    with pytest.raises(ShapeMismatchError, match=r"t.small: LMI \(7\) block \(2,1\)"):
        thm.lmi("(7)", [[-P], [B * P, -I]])  # B is n×m, P is n×n: B·P does not conform


def test_row_size_conflict_is_reported():
    thm, (n, m), A, B, P, g = small_theorem()
    with pytest.raises(ShapeMismatchError, match=r"block \(2,2\)"):
        thm.lmi("(8)", [[-P], [B.T * P, -P]])


def test_nonlinear_products_and_inverses_refused():
    thm, (n, m), A, B, P, g = small_theorem()
    V = thm.var("V", n, n)
    with pytest.raises(NonlinearityError, match=r"LMI \(9\) block \(2,1\).*not affine.*P, V"):
        thm.lmi("(9)", [[-P], [V * P, -P]])
    with pytest.raises(NonlinearityError, match="inverse"):
        thm.lmi("(10)", [[-P], [P.I * A, -P]])
    with pytest.raises(NonlinearityError, match="not affine"):
        thm.lmi("(11)", [[-g * g * sp.Identity(n)]])
    # a parameter may multiply a variable; the inverse of data is fine
    r = thm.param("r")
    thm.lmi("(12)", [[-P], [r * A.I * P, -P]])


def test_helpers_he_diag_schur_congruence():
    thm, (n, m), A, B, P, g = small_theorem()
    assert He(A) == A + A.T
    D = diag(A, B.T * B)
    assert D.shape == (n + m, n + m)
    spec = block_matrix([[-P], [A, -sp.Identity(n)]])
    s = schur(spec, 1)  # −P − Aᵀ(−I)⁻¹A = −P + AᵀA
    inst_vals = {"A": np.array([[0.5, 0.1], [0.0, 0.3]]), "P": np.eye(2)}
    ev = NumericEvaluator({n: 2, m: 1}, inst_vals, {})
    np.testing.assert_allclose(ev.visit(s.lower[0][0]), -np.eye(2) + inst_vals["A"].T @ inst_vals["A"])
    T = thm.data("T", n, n)
    c = congruence([T, sp.Identity(n)], spec)
    assert c.lower[1][0] == A * T


def test_non_symmetric_diagonal_block_refused_at_bind():
    thm, (n, m), A, B, P, g = small_theorem("t.asym")
    V = thm.var("V", n, n)
    thm.lmi("(1)", [[P - V]])
    with pytest.raises(TheoremDefinitionError, match=r"LMI \(1\) diagonal block \(1,1\).*not symmetric"):
        bind(thm, {"A": [[1.0, 0.0], [0.0, 1.0]], "B": [[1.0], [0.0]]})


def test_compiled_matrix_equals_numpy_evaluation():
    """The cvxpy expression of every LMI equals the numpy evaluation of the same blocks."""
    from lmidsl.pipeline import make_instance
    from lmidsl.numeric.instance import random_point
    inst = make_instance("wang_l2linf.thm3", "paper-reduced")
    model = CvxpyModel(inst)
    point = random_point(inst, np.random.default_rng(3))
    for (name, _), var in model._variables.items():
        var.value = point[name] if np.ndim(point[name]) else point[name]
    for lmi, ((label, _, _), con) in zip(inst.theorem.lmis, model.constraints):
        ev = NumericEvaluator(inst.dims, point, inst.params)
        expected = evaluate_block_matrix(ev, lmi.negative_form())
        size = expected.shape[0]
        compiled = con.args[0].value  # (−εI) − N  ⪰ 0  is stored as  −εI − N
        np.testing.assert_allclose(-compiled - model.margin * np.eye(size), expected, atol=1e-10,
                                   err_msg=label)


def test_parameter_change_resolves_without_rebuilding():
    from lmidsl.pipeline import make_instance
    inst = make_instance("wang_l2linf.thm3", "paper-full")
    model = CvxpyModel(inst, reuse=True)
    first = model.solve()
    problem = model.problem
    model.update(inst.with_params(rbar=0.6))
    second = model.solve()
    assert model.problem is problem
    fresh = CvxpyModel(inst.with_params(rbar=0.6)).solve()
    assert second.point_gamma == pytest.approx(fresh.point_gamma, rel=1e-6)
    assert second.point_gamma > first.point_gamma


def test_structured_and_diagonal_variables_solve():
    """Λ = [[X, Z], [Z, Z]] (seed 001's structure) and a diagonal D compile, solve and keep
    their structure: minimise trace-free γ² with Λ ≻ 0 and AᵀΛA − Λ + D ≺ 0, D ≻ I."""
    import lmidsl.pipeline as api
    thm = Theorem("t.struct", "structured", Source("none", "(1)"))
    n = thm.dim("n")
    A = thm.data("A", 2 * n, 2 * n)
    X = thm.var("X", n, kind="symmetric")
    Z = thm.var("Z", n, kind="symmetric")
    D = thm.var("D", 2 * n, kind="diagonal")
    Lam = thm.structured("Lambda", [[X, Z], [Z, Z]], symmetric=True, latex=r"\Lambda")
    assert Lam.T is Lam
    g = thm.scalar("g")
    thm.lmi("(1)", [[-Lam], [Lam * A, -Lam + D]], sizes=[2 * n, 2 * n])
    thm.lmi("(2)", [[Lam - g * I]], sense="<")
    thm.lmi("(3)", [[D - I]], sense=">")
    thm.positive(Lam)
    thm.minimize(g)
    A0 = np.diag([0.5, 0.3, -0.2, 0.1])
    sol = api.solve(thm, data={"A": A0.tolist(), "n": 2})
    assert sol.ok and sol.certified
    Dv = sol.values["D"]
    assert np.allclose(Dv, np.diag(np.diag(Dv)))
    assert np.all(np.diag(Dv) >= 1 - 1e-6)
    Xv, Zv = sol.values["X"], sol.values["Z"]
    Lv = np.block([[Xv, Zv], [Zv, Zv]])
    assert np.linalg.eigvalsh(Lv)[0] > 0
    assert sol.objective == pytest.approx(np.linalg.eigvalsh(Lv)[-1], rel=1e-4)


def test_unknown_node_is_a_one_line_definition_error():
    """A sympy node no walker has a rule for is refused where it is declared, naming the
    theorem, the LMI, the block, the node class and the expression -- never a bare TypeError."""
    thm, (n, m), A, B, P, g = small_theorem("t.unknown")
    with pytest.raises(TheoremDefinitionError) as info:
        thm.lmi("(u)", [[-P], [B.T * P, -g * I], [0, 0, sp.HadamardProduct(A, A.T) - P]])
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith("t.unknown: LMI (u) block (3,3): ")
    assert "HadamardProduct: HadamardProduct(A, A.T)" in message
    with pytest.raises(TheoremDefinitionError, match=r"t.unknown: objective .*Determinant: Determinant\(P\)"):
        thm.minimize(sp.Determinant(P))
    with pytest.raises(TheoremDefinitionError, match=r"t.unknown: recovery of K: .*KroneckerProduct"):
        thm.recover(K=sp.KroneckerProduct(A, A))
    # the numeric evaluator (and the compilers, its subclasses) fall back the same way
    ev = NumericEvaluator({n: 2}, {"A": np.eye(2)}, {})
    with pytest.raises(TheoremDefinitionError, match=r"NumericEvaluator cannot evaluate HadamardProduct"):
        ev.visit(sp.HadamardProduct(A, A.T) + A)
