"""Bounded work (issue 40): the size of an expansion estimated from the declaration equals the
member actually built; what exceeds the limits is refused in one line before it is built (and
accepted with the override); the conditioning read off the compiled affine LMIs equals its
definition evaluated block by block; block diagonals filled in place equal the generic block
assembly; the simplex evidence stays within its budget of points."""
from __future__ import annotations

import json

import numpy as np
import pytest

from lmidsl.certify.simplex_grid import domain_points, grid_evidence, grid_size, simplex_points
from lmidsl.errors import InputError
from lmidsl.numeric.evaluate import NumericEvaluator
from lmidsl.numeric.instance import random_point
from lmidsl.pipeline import make_instance
from lmidsl.solver.backends.affine import Affine, VariableSpace, block, block_diagonal
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.solver.conditioning import _block_sizes, _directions, _unit, equilibrate
from lmidsl.theorem.budget import expansion_limits
from lmidsl.theorem.registry import get_theorem
from lmidsl.theorems.textbook.hpd import random_polytope


def mjls_data(N: int, n: int = 2, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    modes = [{"A": (0.5 * rng.standard_normal((n, n))).tolist(), "B": rng.standard_normal((n, 1)).tolist()}
             for _ in range(N)]
    Pi = rng.random((N, N))
    np.fill_diagonal(Pi, 0.0)
    np.fill_diagonal(Pi, -Pi.sum(axis=1))
    return {"modes": modes, "Pi": Pi.tolist()}


def counted(instance) -> tuple:
    """(LMIs, rows of PSD cones, scalar unknowns) of a bound instance's compiled model."""
    model = DirectModel(instance)
    sizes = [c.dim for c in model.problem.cones if c.kind == "psd"]
    return len(instance.theorem.lmis), sum(n * (n + 1) // 2 for n in sizes), model.space.size


# -- the estimate is the member -----------------------------------------------------------------
@pytest.mark.parametrize("theorem, vertices, degree, polya", [
    ("textbook.hpd_stability_ct", 3, 2, 1), ("textbook.hpd_stability_dt", 4, 1, 2),
    ("textbook.hpd_hinf_ct", 3, 2, 0), ("textbook.hpd_stability_ct", 6, 0, 1)])
def test_the_robust_estimate_is_the_member_built(theorem, vertices, degree, polya):
    thm = get_theorem(theorem)
    data = random_polytope(1, n=2, vertices=vertices, inputs=1 if "hinf" in theorem else 0,
                           outputs=1 if "hinf" in theorem else 0)
    if "hinf" in theorem:
        for v in data["vertices"]:
            v["D"] = [[0.0]]
    estimate = thm.estimate((vertices,), degree, polya, data)
    instance = make_instance(thm, data=data, overrides={"degree": degree, "polya": polya})
    assert (estimate.lmis, estimate.psd_rows, estimate.variables) == counted(instance)


@pytest.mark.parametrize("theorem, N", [("textbook.mjls_sf_ct", 3), ("textbook.mjls_sf_dt", 4),
                                        ("textbook.mjls_sf_ct", 7)])
def test_the_index_set_estimate_is_the_member_built(theorem, N):
    from lmidsl.theorem.budget import index_set_estimate
    thm = get_theorem(theorem)
    data = mjls_data(N)
    if theorem.endswith("_dt"):
        P = np.abs(np.array(data["Pi"]))
        data["Pi"] = (P / P.sum(axis=1, keepdims=True)).tolist()
    estimate = index_set_estimate(thm, {"modes": N}, data)
    assert (estimate.lmis, estimate.psd_rows, estimate.variables) == counted(make_instance(thm, data=data))


def test_the_issue_cases_are_refused_before_the_expansion_and_accepted_with_the_override():
    """12 vertices at degree 4, Pólya 4 (the issue: 167,960 LMIs for He(P(α)A(α)), 75,582 for
    P(α) ≻ 0, by C(12 + 9 − 1, 9) and C(12 + 8 − 1, 8)) and a Markov jump theorem of 200 modes
    (400×400 LMIs) are refused in one line naming the estimate and the limit; the override lets
    a case in."""
    from math import comb
    thm = get_theorem("textbook.hpd_stability_ct")
    data = random_polytope(1, n=2, vertices=12)
    with pytest.raises(InputError) as info:
        make_instance(thm, data=data, overrides={"degree": 4, "polya": 4})
    text = str(info.value)
    assert f"{comb(20, 9) + comb(19, 8):,} LMIs" in text and "--max-lmis" in text and "\n" not in text
    assert not any(key[0][0] == (12,) and key[0][1:] == (4, 4) for key in thm._members)     # nothing built
    with pytest.raises(InputError, match="rows of PSD cones"):
        make_instance("textbook.mjls_sf_ct", data=mjls_data(200))
    with pytest.raises(InputError, match="5,000 LMIs"):          # the default limit: 5,733 LMIs
        make_instance(thm, data=data, overrides={"degree": 4, "polya": 0})
    small = random_polytope(1, n=2, vertices=3)
    with pytest.raises(InputError, match="over the limit of 10 LMIs"):
        make_instance(thm, data=small, overrides={"degree": 2, "polya": 1}, max_lmis=10)
    with expansion_limits(max_lmis=10):
        with pytest.raises(InputError):
            make_instance(thm, data=small, overrides={"degree": 2, "polya": 1})
    assert len(make_instance(thm, data=small, overrides={"degree": 2, "polya": 1}, max_lmis=25).theorem.lmis) == 25


def test_the_cli_refuses_with_exit_2_and_one_line(tmp_path, cli):
    path = tmp_path / "hp.json"
    path.write_text(json.dumps(random_polytope(1, n=2, vertices=12)))
    code, _, err = cli("solve", "textbook.hpd_stability_ct", "--data", str(path), "--set", "degree=8",
                       "--set", "polya=8")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "34,512,075 LMIs" in lines[0] and "--max-lmis" in lines[0], err
    code, _, err = cli("solve", "textbook.hpd_stability_ct", "--data", str(path), "--set", "degree=1",
                       "--max-lmis", "5", "--json")
    assert code == 2 and "over the limit of 5 LMIs" in err


# -- conditioning from the affine form ------------------------------------------------------------
def definition_sizes(instance, lmi_index: int, units: dict) -> tuple:
    """c_ij and m_ijX of one LMI by the definition: numpy's walk of each block at 0 and at each
    variable's unit direction (what equilibrate did before it read the compiled form)."""
    theorem = instance.theorem
    lmi = theorem.lmis[lmi_index]
    negative = lmi.negative_form()
    names = list(units)
    zero = dict(instance.data)
    for name in names:
        symbol = theorem.var_decl[name].symbol
        z = 0.0 if np.ndim(units[name]) == 0 else np.zeros(np.shape(units[name]))
        zero[name] = [z] * instance.nvertices if getattr(symbol, "per_vertex", False) else z
    vertex = 0 if lmi.per_vertex and instance.nvertices > 1 else None
    q = negative.nblocks
    c, m = np.zeros((q, q)), np.zeros((q, q, len(names)))
    for i, row in enumerate(negative.lower):
        for j, b in enumerate(row):
            at_zero = np.atleast_2d(NumericEvaluator(instance.dims, zero, instance.params, vertex).visit(b))
            c[i, j] = np.abs(at_zero).max() if at_zero.size else 0.0
            for k, name in enumerate(names):
                point = dict(zero)
                symbol = theorem.var_decl[name].symbol
                point[name] = [units[name]] * instance.nvertices if getattr(symbol, "per_vertex", False) \
                    else units[name]
                value = np.atleast_2d(NumericEvaluator(instance.dims, point, instance.params, vertex).visit(b))
                m[i, j, k] = np.abs(value - at_zero).max() if value.size else 0.0
    return c, m


@pytest.mark.parametrize("theorem, data", [
    ("textbook.brl_ct", {"A": [[-1.0, 2.0, 0.0], [-2.0, -1.0, 0.5], [0.0, 0.0, -3.0]],
                         "B": [[1e-6], [0.0], [1e-6]], "C": [[1e6, 5e5, 0.0]], "D": [[0.0]]}),
    ("textbook.mjls_sf_ct", mjls_data(4)),
    ("textbook.hpd_stability_ct", {**random_polytope(2, n=2, vertices=3), "degree": 2, "polya": 1}),
])
def test_conditioning_sizes_from_the_affine_form_equal_the_definition(theorem, data):
    instance = make_instance(theorem, data=data)
    rng = np.random.default_rng(0)
    variables = {n: d.symbol for n, d in instance.theorem.var_decl.items()
                 if getattr(d.symbol, "kind", None) != "structured"}
    units = {name: _unit(symbol, instance.dims, rng) for name, symbol in variables.items()}
    model = DirectModel(instance)
    u, owner = _directions(model, units, list(units))
    first = {}
    for (label, _, _), N in model.lmi_matrices:
        first.setdefault(label, N)
    for index, lmi in enumerate(instance.theorem.lmis[:6]):
        sizes = [int(s.xreplace(instance.dims)) if hasattr(s, "xreplace") else int(s)
                 for s in lmi.negative_form().sizes]
        c, m = _block_sizes(first[lmi.label], sizes, u, owner, len(units))
        c_ref, m_ref = definition_sizes(instance, index, units)
        lower = np.tril(np.ones(c.shape, dtype=bool))
        np.testing.assert_allclose(c[lower], c_ref[lower], rtol=1e-12, atol=0)
        np.testing.assert_allclose(m[lower], m_ref[lower], rtol=1e-12, atol=1e-300)
    assert equilibrate(instance).as_dict()["variables"] == equilibrate(instance, model).as_dict()["variables"]


def test_the_badly_scaled_plant_keeps_its_conditioning():
    """The brl_ct plant with B ~ 1e-6, C ~ 1e6: the factors are powers of two that balance it
    (the spread narrows by more than 10 bits), as before the affine reading."""
    data = {"A": [[-1.0, 2.0, 0.0], [-2.0, -1.0, 0.5], [0.0, 0.0, -3.0]], "B": [[1e-6], [0.0], [1e-6]],
            "C": [[1e6, 5e5, 0.0]], "D": [[0.0]]}
    proposal = equilibrate(make_instance("textbook.brl_ct", data=data))
    assert not proposal.trivial and proposal.spread[0] - proposal.spread[1] >= 10
    assert all(np.log2(f) == int(np.log2(f)) for f in proposal.variables.values())


# -- block diagonals -------------------------------------------------------------------------------
def test_block_diagonal_filled_in_place_equals_the_generic_assembly():
    rng = np.random.default_rng(3)
    shapes = [(2, 2), (1, 3), (3, 1)]
    values = [rng.standard_normal(s) for s in shapes]
    ev = NumericEvaluator({}, {}, {})
    fast = ev.block_diagonal(values, shapes)
    generic = ev.block([[v if i == j else np.zeros((shapes[i][0], shapes[j][1])) for j in range(3)]
                        for i, v in enumerate(values)])
    assert np.array_equal(fast, generic)
    space = VariableSpace()
    X = space.new("X", (2, 2), "symmetric").expression()
    Y = space.new("Y", (1, 3)).expression()
    affine = [2.0 * X, Y, values[2]]
    x = rng.standard_normal(space.size)
    diag = block_diagonal(affine, shapes)
    ref = block([[a if i == j else np.zeros((shapes[i][0], shapes[j][1])) for j in range(3)]
                 for i, a in enumerate(affine)])
    assert np.array_equal(diag.value(x), ref.value(x))


def test_markov_jump_lmis_compiled_equal_numpy_at_a_random_point():
    """The MJ LMIs (a block diagonal of N − 1 variables) compiled by the direct backend equal
    numpy's walk of the statement at a random point, bit for bit."""
    instance = make_instance("textbook.mjls_sf_ct", data=mjls_data(6))
    model = DirectModel(instance)
    point = random_point(instance, np.random.default_rng(1))
    model.assign(point)
    values = {**instance.data, **point}
    for (label, _, _), N in model.lmi_matrices:
        lmi = next(l for l in instance.theorem.lmis if l.label == label)
        spec = lmi.negative_form()
        ev = NumericEvaluator(instance.dims, values, instance.params)
        lower = [[np.atleast_2d(ev.visit(b)) for b in row] for row in spec.lower]
        q = spec.nblocks
        ref = np.block([[lower[i][j] if j <= i else lower[j][i].T for j in range(q)] for i in range(q)])
        np.testing.assert_allclose(model.expression_value(N), ref, rtol=1e-13, atol=1e-13)


# -- the simplex evidence's budget ----------------------------------------------------------------
def test_grid_points_are_the_compositions_and_the_budget_bounds_many_vertices():
    pts = simplex_points(4, 3)
    assert len(pts) == grid_size((4,), 3) == 20 and np.allclose(pts.sum(axis=1), 1) and pts.min() >= 0
    assert len({tuple(p) for p in pts}) == 20
    points, resolution, drawn = domain_points((12,), 300)
    assert len(points) == 300 and resolution == 2 and drawn == 300 - 78       # vertices + edge midpoints
    assert all(abs(a.sum() - 1) < 1e-12 and a.min() >= 0 for (a,) in points)
    points, resolution, drawn = domain_points((3,), 1500)
    assert drawn == 0 and len(points) == grid_size((3,), resolution) <= 1500


def test_twelve_vertices_evidence_is_bounded_and_finds_an_unstable_point():
    """12 vertices: all Hurwitz except an unstable midpoint of the edge (1, 2) — found by the
    budgeted points (the edge midpoints are in the grid)."""
    rng = np.random.default_rng(0)
    A1 = np.array([[-1.0, 10.0], [0.0, -1.0]])
    A2 = np.array([[-1.0, 0.0], [10.0, -1.0]])
    verts = [{"A": A1.tolist()}, {"A": A2.tolist()}] + [
        {"A": (-np.eye(2) + 0.1 * rng.standard_normal((2, 2))).tolist()} for _ in range(10)]
    for v in verts[:2]:
        assert max(np.linalg.eigvals(np.array(v["A"])).real) < 0
    mid = (A1 + A2) / 2
    assert max(np.linalg.eigvals(mid).real) > 0
    ev = grid_evidence(verts, None, "continuous", max_points=300)
    assert ev.refutes and ev.points == 300 and ev.refine_evaluations <= 4 * 300
