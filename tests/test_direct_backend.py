"""The direct backend (lmidsl's own standard form, handed to Clarabel): the assembled LMI
matrices equal numpy's evaluation of the block matrices; the affine algebra's operations equal
numpy's on random values; solving gives cvxpy's optimum; feasp, level problems, margins and
updates work as on the other backends; bad options are one line."""
from __future__ import annotations

import numpy as np
import pytest

from lmidsl.errors import InputError, SolverUnavailableError
from lmidsl.numeric.evaluate import NumericEvaluator
from lmidsl.numeric.instance import random_point
from lmidsl.numeric.scaling import apply_scaling
from lmidsl.pipeline import make_instance, solve
from lmidsl.solver.backends import get_backend, second_opinion, Route
from lmidsl.solver.backends.affine import Affine, Cone, VariableSpace, block, svec_map
from lmidsl.solver.feasibility import feasp
from lmidsl.solver.status import solved
from lmidsl.symbolic.uncertainty import scenarios

CASES = [("wang_l2linf.thm3", "paper-full"), ("wang_l2linf.thm3", "paper-reduced"),
         ("wang_l2linf.cor1", "two-vertex"), ("wang_l2linf.thm1", "paper-full-printed"),
         ("li_delay_dropout.thm2", "paper"), ("textbook.hinf_of_ct", None), ("textbook.h2_dt_sf", None),
         ("pan_impulsive.thm1", None), ("zhang_quantized_loss.thm2", None), ("interconnected_delay.thm2", None),
         ("textbook.pole_region_sf_ct", None)]


def numpy_lmis(instance, point) -> dict:
    """Every LMI's N at every vertex and uncertainty scenario, by numpy's walk (no backend)."""
    values = {**instance.data, **point}
    out = {}
    for lmi in instance.theorem.lmis:
        spec = lmi.negative_form()
        for scenario in scenarios(instance, lmi):
            ev = NumericEvaluator(instance.dims, values, instance.params, vertex=scenario.vertex)
            lower = [[np.atleast_2d(ev.visit(scenario.apply(b))) for b in row] for row in spec.lower]
            q = spec.nblocks
            out[(lmi.label, scenario.vertex, scenario.label)] = np.block(
                [[lower[i][j] if j <= i else lower[j][i].T for j in range(q)] for i in range(q)])
    return out


@pytest.mark.parametrize("theorem,example", CASES)
def test_golden_lmi_matrices_equal_numpy(theorem, example):
    instance = make_instance(theorem, example)
    model = get_backend("direct")(instance)
    rng = np.random.default_rng(7)
    for _ in range(2):
        point = random_point(instance, rng)
        model.assign(point)
        got, ref = model.lmi_values(), numpy_lmis(instance, point)
        assert set(got) == set(ref)
        for key in ref:
            scale = max(1.0, np.abs(ref[key]).max())
            np.testing.assert_allclose(got[key], ref[key], rtol=0, atol=1e-12 * scale, err_msg=str(key))


def _random_affine(space, rng, shape):
    X = space.new(f"X{len(space.variables)}", shape, "full").expression()
    return X + rng.normal(size=shape)


def test_algebra_equals_numpy_on_random_values():
    """K M, M K, Mᵀ, s·K, tr M, blocks and sums of affine matrices equal the same numpy
    operations on their values, including products that create duplicate triplets."""
    rng = np.random.default_rng(3)
    space = VariableSpace()
    S = space.new("S", (4, 4), "symmetric").expression()
    D = space.new("D", (4, 4), "diagonal").expression()
    g = space.new("g", ()).expression()
    M = _random_affine(space, rng, (4, 3))
    K, L = rng.normal(size=(5, 4)), rng.normal(size=(3, 2))
    K[1, :] = 0.0
    exprs = {
        "KᵀSK-like": K @ S @ K.T, "K M L": K @ M @ L, "transpose": (K @ M).T, "scalar": g * K,
        "trace": (S + D).trace(), "block": block([[S, M], [M.T, -2.0 * np.eye(3)]]),
        "sum": S - D + 3.0 * S.T, "scaled": (g * 0.5 + 1.0) * np.ones((2, 2)),
    }
    for v in space.variables:
        v.set_value(rng.normal(size=v.shape) if v.shape else rng.normal())
    Sv, Dv, gv = (space.variables[i].value() for i in range(3))
    Sv = (Sv + Sv.T) / 2
    Mv = space.variables[3].value() + (M.const)
    expected = {
        "KᵀSK-like": K @ Sv @ K.T, "K M L": K @ Mv @ L, "transpose": (K @ Mv).T, "scalar": gv * K,
        "trace": np.trace(Sv + Dv), "block": np.block([[Sv, Mv], [Mv.T, -2.0 * np.eye(3)]]),
        "sum": Sv - Dv + 3.0 * Sv.T, "scaled": (gv * 0.5 + 1.0) * np.ones((2, 2)),
    }
    x = space.vector()
    for name, expr in exprs.items():
        np.testing.assert_allclose(expr.value(x), expected[name], rtol=1e-12, atol=1e-12, err_msg=name)


def test_svec_is_an_isometry_on_symmetric_matrices():
    """⟨svec S, svec Z⟩ = tr(S Z), Clarabel's convention for the PSD-triangle cone."""
    rng = np.random.default_rng(1)
    n = 5
    S, Z = rng.normal(size=(n, n)), rng.normal(size=(n, n))
    S, Z = S + S.T, Z + Z.T
    svec = lambda A: Cone.psd(Affine((n, n), A)).const
    assert np.isclose(svec(S) @ svec(Z), np.trace(S @ Z))
    position, _ = svec_map(n)
    assert position[n * 1 + 3] == position[3 * n + 1] == 3 * 4 // 2 + 1   # (1, 3): column 3, row 1


def test_a_product_of_two_variables_is_refused():
    from lmidsl.errors import TheoremDefinitionError
    space = VariableSpace()
    X = space.new("X", (2, 2)).expression()
    with pytest.raises(TheoremDefinitionError, match="not affine"):
        X @ X


@pytest.mark.parametrize("theorem,example", CASES)
def test_same_problem_and_optimum_as_cvxpy(theorem, example):
    """The standard form has cvxpy's sizes (rows of A, cones, variables) and Clarabel gives the
    same optimum on both (scaled as the pipeline scales, so that it solves).

    Not the status word: whether Clarabel stops at "Solved" or "AlmostSolved" on the same
    problem depends on the last bits of its iterates (a fresh machine gave optimal_inaccurate on
    li_delay_dropout.thm2).  What is compared: both return a point or neither does; each point's
    certificate (numpy's largest eigenvalue of every N, margin ε = 1e-7 imposed) holds to within
    Clarabel's feasibility tolerance; the two objectives agree within the sum of the duality gaps
    Clarabel accepts for the status it reported (|p − d| ≤ abs + rel·|p|: 1e-8 + 1e-8 for
    "optimal", 5e-5 + 5e-5 for "optimal_inaccurate", its reduced tolerances), widened to 1e-5
    relative for full accuracy, which covers the 1e-8 primal infeasibility times the dual's size."""
    instance = apply_scaling(make_instance(theorem, example), "auto").scaled
    direct, cvx = get_backend("direct")(instance), get_backend("cvxpy")(instance)
    data, _, _ = cvx.problem.get_problem_data("CLARABEL")
    assert direct.problem.A.shape == data["A"].shape
    assert [c.dim for c in direct.problem.cones if c.kind == "psd"] == list(data["dims"].psd)
    a, b = direct.solve(), cvx.solve()
    assert solved(a.status) == solved(b.status), (a.status, b.status)
    if not solved(a.status):
        return
    for s in (a, b):
        assert s.worst_eig < CLARABEL_FEASIBILITY * max(1.0, max(r.scale for r in s.lmis)), (s.backend, s.worst_eig)
    tolerance = sum(_gap_tolerance(s.status, s.objective) for s in (a, b))
    assert abs(a.objective - b.objective) <= tolerance, (a.status, b.status, a.objective, b.objective)


#: Clarabel's defaults (clarabel.DefaultSettings(): tol_feas; tol_gap_abs/rel, and the reduced
#: ones it accepts for AlmostSolved)
CLARABEL_FEASIBILITY = 1e-8
CLARABEL_GAP = {"optimal": (1e-8, 1e-5), "optimal_inaccurate": (5e-5, 5e-5)}


def _gap_tolerance(status: str, objective: float) -> float:
    absolute, relative = CLARABEL_GAP[status]
    return absolute + relative * abs(objective)


def test_clarabel_tolerances_are_the_ones_the_comparison_assumes():
    """The tolerances above are Clarabel's defaults (a new Clarabel changing them must be seen)."""
    import clarabel
    s = clarabel.DefaultSettings()
    assert (s.tol_feas, s.tol_gap_abs, s.reduced_tol_gap_abs, s.reduced_tol_gap_rel) == \
        (CLARABEL_FEASIBILITY, CLARABEL_GAP["optimal"][0], *CLARABEL_GAP["optimal_inaccurate"])
    assert s.tol_gap_rel <= CLARABEL_GAP["optimal"][1]


def test_solve_defaults_to_direct_and_certifies():
    sol = solve("wang_l2linf.thm3", example="paper-full")
    assert sol.backend == "direct" and sol.solver == "CLARABEL"
    assert sol.certified and sol.analysis.passed
    assert sol.gamma == pytest.approx(0.33674, abs=1e-5)


def test_level_problem_and_margin_sensitivity_match_cvxpy():
    instance = make_instance("wang_l2linf.thm3", "paper-full")
    direct, cvx = get_backend("direct")(instance), get_backend("cvxpy")(instance)
    a, b = direct.solve(), cvx.solve()
    assert direct.margin_sensitivity() == pytest.approx(cvx.margin_sensitivity(), rel=1e-2)
    bound = 1.01 * a.objective
    level = direct.solve(problem=direct.level_problem(bound))
    assert level.ok and level.lmis_hold
    assert direct.expression_value(direct.objective) <= bound * (1 + 1e-7)


def test_update_and_margin_recompile():
    base = make_instance("wang_l2linf.thm3", "paper-full")
    model = get_backend("direct")(base)
    changed = make_instance("wang_l2linf.thm3", "paper-full", overrides={"rbar": 0.6})
    model.update(changed)
    fresh = get_backend("direct")(changed)
    assert model.solve().objective == pytest.approx(fresh.solve().objective, rel=1e-9)
    model.set_margin(1e-5)
    assert model.margin == 1e-5 and model.solve().lmis_hold


def test_feasp_on_the_direct_backend():
    """feasp (t* < 0: strictly feasible) on a feasible instance; the radius bound is a SOC."""
    instance = make_instance("wang_l2linf.thm3", "paper-full")
    report = feasp(instance, backend="direct")
    assert report.verdict == "strictly feasible" and report.tmin < 0


def test_second_opinion_is_another_solver():
    assert second_opinion("direct", "CLARABEL") == Route("picos", "cvxopt")
    assert second_opinion("cvxpy", "CLARABEL") == Route("cvxpy", "CVXOPT")
    assert second_opinion("cvxpy", "CVXOPT") == Route("cvxpy", "CLARABEL")


def test_bad_options_and_solvers_are_one_line():
    instance = make_instance("wang_l2linf.thm3", "paper-full")
    model = get_backend("direct")(instance)
    with pytest.raises(InputError, match="unknown Clarabel setting 'max_iters'"):
        model.solve(max_iters=5)
    with pytest.raises(SolverUnavailableError, match="calls Clarabel only"):
        model.solve("SCS")
    assert model.solve(max_iter=2).status in ("user_limit", "optimal_inaccurate")


@pytest.mark.parametrize("theorem,example,change", [
    ("li_delay_dropout.thm2", "paper", {"xi1": 0.5, "xi2": 0.3}),
    ("wang_l2linf.cor1", "two-vertex", {"rbar": 0.6}),
])
def test_update_keeps_parameter_free_parts_and_equals_a_fresh_compile(theorem, example, change):
    """update() recompiles with the parameter-free sub-expressions of the last compile: the LMI
    matrices at a random point equal those of a model compiled fresh at the new parameters."""
    base = make_instance(theorem, example)
    model = get_backend("direct")(base, reuse=True)
    assert model._static
    changed = base.with_params(**change)
    model.update(changed)
    fresh = get_backend("direct")(changed)
    point = random_point(changed, np.random.default_rng(5))
    model.assign(point)
    fresh.assign(point)
    got, ref = model.lmi_values(), fresh.lmi_values()
    for key in ref:
        np.testing.assert_allclose(got[key], ref[key], rtol=0, atol=1e-12 * max(1.0, np.abs(ref[key]).max()))
    np.testing.assert_allclose(got[next(iter(ref))], numpy_lmis(changed, point)[next(iter(ref))], atol=1e-10)


@pytest.mark.parametrize("theorem,example", [("wang_l2linf.thm3", "paper-full"),
                                             ("pan_impulsive.lemma1", "paper-printed"),
                                             ("wang_l2linf.cor1", "two-vertex")])
def test_feasp_agrees_with_cvxpy(theorem, example):
    """feasp's t* (every strict LMI ⪯ tI, the stacked variables within the radius: a second-order
    cone here, cvxpy's norm atom there) and its verdict agree between the two backends."""
    instance = make_instance(theorem, example)
    a, b = feasp(instance, backend="direct", detail=False), feasp(instance, backend="cvxpy", detail=False)
    assert a.verdict == b.verdict
    assert a.tmin == pytest.approx(b.tmin, rel=1e-3, abs=1e-6)


@pytest.mark.parametrize("backend", ["direct", "picos"])
def test_recompiling_backends_keep_their_conditioning(backend):
    """update() / set_margin() of a backend that compiles again keep the conditioning congruence:
    the LMI matrices equal a fresh conditioned model's (PICOS dropped it before 2026-11-24)."""
    from lmidsl.solver.conditioning import equilibrate
    A = np.array([[-1.0, 2.0, 0.0], [-2.0, -1.0, 0.5], [0.0, 0.0, -3.0]])
    data = {"A": A.tolist(), "B": [[1e-6], [0.0], [1e-6]], "C": [[1e6, 5e5, 0.0]], "D": [[0.0]]}
    instance = make_instance("textbook.brl_ct", data=data)
    proposal = equilibrate(instance)
    assert not proposal.trivial
    model = get_backend(backend)(instance, conditioning=proposal)
    model.set_margin(1e-6)
    fresh = get_backend(backend)(instance, margin=1e-6, conditioning=proposal)
    assert model.conditioning is proposal
    point = random_point(instance, np.random.default_rng(2))
    model.assign(point)
    fresh.assign(point)
    got, ref = model.lmi_values(), fresh.lmi_values()
    for key in ref:
        np.testing.assert_allclose(got[key], ref[key], rtol=1e-12, atol=1e-12 * np.abs(ref[key]).max())


def test_small_problems_run_clarabel_on_one_thread(monkeypatch):
    """One thread below SINGLE_THREAD_ROWS PSD rows (faster there on 2 cores), a fixed number
    above (never 0, "every core": Clarabel's answer depends on its thread count, so it would
    depend on the machine), and LMIDSL_SOLVER_THREADS wins over both."""
    from lmidsl.solver.backends import direct_backend

    small = get_backend("direct")(make_instance("wang_l2linf.thm3", "paper-full")).problem
    rows = sum(c.size for c in small.cones if c.kind == "psd")
    assert rows < direct_backend.SINGLE_THREAD_ROWS
    assert direct_backend.solver_threads(small) == 1
    monkeypatch.setattr(direct_backend, "SINGLE_THREAD_ROWS", rows)
    assert direct_backend.solver_threads(small) == direct_backend.LARGE_PROBLEM_THREADS >= 1
    monkeypatch.setattr(direct_backend, "THREADS", 3)
    assert direct_backend.solver_threads(small) == 3
