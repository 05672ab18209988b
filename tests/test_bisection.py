"""Quasi-convex problems by bisection (GEVP): the decay rate, compiled once, decided by the
certificate, proved at the feasible end; against −max Re λ(A) and against a fine grid."""
from __future__ import annotations

import numpy as np
import pytest

import lmidsl.studies.bisection as bis
from lmidsl import He, I, Source, Theorem
from lmidsl.cli import main
from lmidsl.errors import InputError
from lmidsl.pipeline import make_instance

A_SINGLE = np.array([[-1.0, 2.0], [0.0, -3.0]])


def test_single_system_decay_rate_is_minus_max_real_eigenvalue():
    result = bis.bisect(make_instance("decay_rate.quadratic", "single"))
    exact = -max(np.linalg.eigvals(A_SINGLE).real)                 # = 1
    lo, hi = result.interval
    assert lo <= exact <= hi and hi - lo <= result.tol
    assert result.feasible_end == lo                               # goal max: the feasible end is below
    assert result.holds and all(r.proof == "proved" for r in result.solution.lmis)
    assert len(result.steps) <= int(np.ceil(np.log2(10 / 1e-6))) + 2


def test_compiled_once_on_cvxpy(monkeypatch):
    """On cvxpy the parameter is a cp.Parameter: one compile, every step re-solves (DPP).  The
    direct backend recompiles at each step (cheap) and ends in the same interval."""
    made = []
    real = bis.get_backend

    def counting(name="cvxpy"):
        cls = real(name)

        class Counted(cls):
            def __init__(self, *a, **k):
                made.append(1)
                super().__init__(*a, **k)
        return Counted

    monkeypatch.setattr(bis, "get_backend", counting)
    result = bis.bisect(make_instance("decay_rate.quadratic", "single"), backend="cvxpy")
    assert len(result.steps) > 10 and len(made) == 1
    monkeypatch.undo()
    direct = bis.bisect(make_instance("decay_rate.quadratic", "single"))
    assert direct.interval == pytest.approx(result.interval, abs=2 * result.tol)


def test_polytope_bisection_agrees_with_a_fine_grid():
    instance = make_instance("decay_rate.quadratic", "polytope")
    result = bis.bisect(instance)
    step = 0.005
    values = np.arange(0.0, 1.2 + step / 2, step)
    steps = bis.grid(instance, values)
    best = bis.grid_threshold(steps, "max")
    assert best is not None
    assert best <= result.feasible_end < best + step            # the grid brackets the bisection
    # feasibility is an interval [0, α*): every grid point below the bisection is feasible
    assert all(s["feasible"] == (s["value"] <= result.feasible_end) for s in steps
               if abs(s["value"] - result.feasible_end) > 1e-5)
    # a common Lyapunov function certifies at most the slowest vertex's own rate (1.0 here)
    assert result.feasible_end <= 1.0


def test_goal_min():
    thm = Theorem("test.decay_min", "min beta", Source("test", "(b)"), time="continuous")
    n = thm.dim("n")
    A = thm.data("A", n, n)
    beta = thm.param("beta")
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("(b)", [[He(P * A) - 2 * beta * P]])           # feasible iff beta > max Re λ(A)
    thm.lmi("P >= I", [[P - I]], sense=">=")
    thm.feasibility()
    thm.bisect("beta", lower=-10, upper=0, tol=1e-5, goal="min")
    thm.example("one", {"A": A_SINGLE.tolist()}, params={"beta": 0.0})
    result = bis.bisect(make_instance(thm, "one"))
    lo, hi = result.interval
    assert lo <= -1.0 <= hi and result.feasible_end == hi and result.holds


def test_no_declaration_is_bad_input():
    with pytest.raises(InputError, match="no bisection"):
        bis.bisect(make_instance("wang_l2linf.thm1", "paper-full-printed"))


def test_cli_solve_bisects(capsys):
    assert main(["solve", "decay_rate.quadratic", "--example", "single"]) == 0
    out = capsys.readouterr().out
    assert "bisection on alpha" in out and "CERTIFIED" in out
    assert main(["solve", "decay_rate.quadratic", "--example", "single", "--set", "alpha=0.5"]) == 0
    assert "bisection" not in capsys.readouterr().out


def test_any_parameter_can_be_bisected_without_a_declaration():
    """``parameter=`` bisects a parameter the theorem does not declare for bisection."""
    result = bis.bisect(make_instance("decay_rate.quadratic", "single"), parameter="alpha",
                        lower=0.0, upper=2.0, tol=1e-3)
    lo, hi = result.interval
    assert lo <= 1.0 <= hi and hi - lo <= 1e-3 and result.holds
    assert all(s["solver"] for s in result.steps)
    with pytest.raises(InputError, match="not a parameter"):
        bis.bisect(make_instance("decay_rate.quadratic", "single"), parameter="beta", lower=0, upper=1)


def test_a_bisection_step_ends_at_the_first_route_that_says_infeasible(monkeypatch):
    """``infeasible_ends`` (a bisection step): after the first route fails, the first fallback
    that says "infeasible" ends the road -- the later routes (which would compile and solve the
    step again, SCS included) are not tried; without it every route is tried."""
    from types import SimpleNamespace

    from lmidsl.solver import plan as plan_module
    from lmidsl.solver.plan import Plan
    from lmidsl.solver.solution import Solution

    def answer(backend, solver, status):
        return Solution("t", None, backend, solver, status)

    first = answer("direct", "CLARABEL", "solver_error")
    model = SimpleNamespace(instance=SimpleNamespace(theorem=SimpleNamespace(state_feedback=None,
                                                                             bounded_real=None)))
    for infeasible_ends, expected in ((True, 1), (False, 3)):
        tried = []
        monkeypatch.setattr(plan_module, "route_model", lambda model, route, margin=None: route)

        def solve_route(self, route, solver, **extra):
            tried.append(route)
            return answer(route.backend, route.solver, "infeasible")
        monkeypatch.setattr(Plan, "_solve_model", solve_route)
        monkeypatch.setattr(Plan, "routes", lambda self: [SimpleNamespace(backend=b, solver=s) for b, s in (
            ("direct", "CLARABEL"), ("picos", "cvxopt"), ("cvxpy", "CLARABEL"), ("cvxpy", "CVXOPT"))])
        kept = Plan(None, None, infeasible_ends=infeasible_ends)._other_routes(model, first, plan_module._ClosedForm(None, False))
        assert [(r.backend, r.solver) for r in tried] == [("picos", "cvxopt"), ("cvxpy", "CLARABEL"),
                                                          ("cvxpy", "CVXOPT")][:expected]
        assert kept.status == "solver_error" and not kept.ok        # no point: the step is "no"
