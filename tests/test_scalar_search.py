"""Scalar search (lmidsl.studies.search) on problems whose optimum over the scalars is known."""
import math

import numpy as np
import pytest
from sympy import Identity, sqrt

from lmidsl import Source, Theorem
from lmidsl.errors import InputError
from lmidsl.numeric.instance import bind
from lmidsl.studies.search import scalar_search
from lmidsl.studies.defaults import parse_grid


def _brl_theorem():
    """Two scalar systems x⁺ = a_i x + ω, z_i = x + λ_i ω, bounded real lemma each, min g1 + g2.

    ‖1/(z − a) + λ‖∞ = |λ + a/(1 − a²)| + 1/(1 − a²): the optimum is λ_i* = −a_i/(1 − a_i²) with
    g_i* = 1/(1 − a_i²)², so γ* = sqrt(Σ g_i*) (the image of the unit circle is a circle centred
    at a/(1 − a²) with radius 1/(1 − a²)).
    """
    thm = Theorem("test_search.brl", "two BRLs", Source("none", "none"))
    k = thm.dim("k")
    lams, gs = [], []
    for i in (1, 2):
        a = thm.data(f"a{i}", k, k)
        one = thm.data(f"one{i}", k, k)
        lam = thm.param(f"lambda{i}")
        P = thm.var(f"P{i}", k, kind="symmetric")
        g = thm.scalar(f"g{i}")
        thm.lmi(f"BRL{i}", [
            [a.T * P * a - P],
            [one.T * P * a, one.T * P * one - g * Identity(k)],
            [one, lam * one, -Identity(k)],
        ])
        thm.positive(P)
        lams.append(lam)
        gs.append(g)
    thm.minimize(gs[0] + gs[1], performance=("gamma", sqrt(gs[0] + gs[1])))
    return thm


A1, A2 = 0.5, -0.3


def _instance():
    return bind(_brl_theorem(), {"a1": [[A1]], "a2": [[A2]], "one1": [[1.0]], "one2": [[1.0]],
                                 "lambda1": 0.0, "lambda2": 0.0})


@pytest.mark.slow
def test_grid_then_nelder_mead_finds_the_known_optimum_in_parallel():
    lam_star = [-A1 / (1 - A1 ** 2), -A2 / (1 - A2 ** 2)]
    gamma_star = math.sqrt(sum(1 / (1 - a ** 2) ** 2 for a in (A1, A2)))
    axes = {"lambda1": list(np.linspace(-1.5, 0.5, 5)), "lambda2": list(np.linspace(-0.5, 1.0, 4))}
    result = scalar_search(_instance(), axes, refine_best=True, workers=2, progress=False, maxfev=120)
    assert len(result.grid) == 20 and all(math.isfinite(p.value) for p in result.grid)
    # the grid values are the closed form at the grid points
    for p in result.grid:
        expected = math.sqrt(sum((abs(p.params[f"lambda{i}"] + a / (1 - a ** 2)) + 1 / (1 - a ** 2)) ** 2
                                 for i, a in ((1, A1), (2, A2))))
        assert p.value == pytest.approx(expected, rel=1e-5)
    best = result.best
    assert best.value == pytest.approx(gamma_star, rel=1e-5)
    assert best.params["lambda1"] == pytest.approx(lam_star[0], abs=2e-3)
    assert best.params["lambda2"] == pytest.approx(lam_star[1], abs=2e-3)
    assert result.best_proved is not None
    assert result.best_grid.value > best.value          # the refinement improved on the grid


@pytest.mark.slow
def test_serial_and_parallel_grids_agree():
    axes = {"lambda1": [-0.5, 0.0], "lambda2": [0.0, 0.5]}
    serial = scalar_search(_instance(), axes, workers=1, progress=False)
    parallel = scalar_search(_instance(), axes, workers=2, progress=False)
    assert [p.params for p in serial.grid] == [p.params for p in parallel.grid]
    assert np.allclose([p.value for p in serial.grid], [p.value for p in parallel.grid], rtol=1e-6)


def _tmin_theorem():
    """X < 1 and X > (λ − 0.3)² + 0.5: feasp t*(λ) = ((λ − 0.3)² − 0.5)/2, least −0.25 at λ = 0.3."""
    thm = Theorem("test_search.tmin", "tmin", Source("none", "none"))
    k = thm.dim("k")
    one = thm.data("one", k, k)
    lam = thm.param("lam")
    X = thm.var("X", k, kind="symmetric")
    thm.lmi("upper", [[X - one]])
    thm.lmi("lower", [[((lam - 0.3) ** 2 + 0.5) * one - X]])
    return thm


def test_tmin_objective_finds_the_known_optimum():
    inst = bind(_tmin_theorem(), {"one": [[1.0]], "lam": 0.0})
    result = scalar_search(inst, {"lam": [-1.0, 0.0, 1.0]}, refine_best=True, workers=1,
                           progress=False)
    assert result.objective == "tmin"
    assert result.best.value == pytest.approx(-0.25, abs=1e-6)
    assert result.best.params["lam"] == pytest.approx(0.3, abs=2e-3)


def test_parse_grid_and_errors():
    assert parse_grid("lambda1=0:1:3") == ("lambda1", [0.0, 0.5, 1.0])
    assert parse_grid("eps=0.1,0.2") == ("eps", [0.1, 0.2])
    for bad in ("lambda1", "lambda1=0:1", "lambda1=a:b:3", "x=0:1:0"):
        with pytest.raises(InputError):
            parse_grid(bad)
    with pytest.raises(InputError, match="not a scalar parameter"):
        scalar_search(_instance(), {"g1": [0.0]}, progress=False)


def test_search_cli_json(capsys):
    import json
    from lmidsl.cli import main
    code = main(["search", "pan_impulsive.thm1", "--example", "modified", "--grid", "lambda1=0.3",
                 "--grid", "lambda2=-0.3,0.3", "--grid", "epsilon=0", "--workers", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["objective"] == "tmin"
    values = {p["params"]["lambda2"]: p["value"] for p in out["grid"]}
    assert values[0.3] < 0 < values[-0.3]     # λ1 = λ2 feasible at γ = 0.5, λ1 ≠ λ2 not
