"""The feasp diagnosis (lmidsl.solver.feasibility) on problems whose t* is known in closed form."""
import pytest

from lmidsl import Source, Theorem
from lmidsl.pipeline import solve_instance
from lmidsl.solver.feasibility import feasp
from lmidsl.numeric.instance import bind


def _interval_theorem():
    """X > c and X < d for a 1×1 symmetric X: feasp t* = (c − d)/2 (X = (c + d)/2)."""
    thm = Theorem("test_feasp.interval", "interval", Source("none", "none"))
    k = thm.dim("k")
    c = thm.data("c", k, k)
    d = thm.data("d", k, k)
    X = thm.var("X", k, kind="symmetric")
    thm.lmi("X > c", [[c - X]])
    thm.lmi("X < d", [[X - d]])
    return thm


def _lyapunov_theorem():
    """AᵀPA − P < 0, P > 0 for A = a I: for |a| ≥ 1, t* = 0 (P → 0); for |a| < 1, t* < 0."""
    thm = Theorem("test_feasp.lyap", "lyapunov", Source("none", "none"))
    n = thm.dim("n")
    A = thm.data("A", n, n)
    P = thm.var("P", n, kind="symmetric")
    thm.lmi("Lyapunov", [[A.T * P * A - P]])
    thm.positive(P)
    return thm


@pytest.mark.parametrize("c, d", [(1.0, 0.0), (0.0, 1.0), (3.0, 2.5)])
def test_interval_tmin_closed_form(c, d):
    inst = bind(_interval_theorem(), {"c": [[c]], "d": [[d]]})
    report = feasp(inst)
    assert report.tmin == pytest.approx((c - d) / 2, abs=1e-6)
    assert report.verdict == ("strictly feasible" if c < d else "infeasible")
    if c > d:
        # each alone is feasible, dropping either restores feasibility: both are responsible
        assert sorted(report.responsible) == ["X < d", "X > c"]
        for m in report.lmis:
            assert m.value == pytest.approx((c - d) / 2, abs=1e-5)
            assert m.binding


@pytest.mark.parametrize("backend", ["cvxpy", "picos"])
def test_unstable_lyapunov_infeasible_on_every_backend(backend):
    inst = bind(_lyapunov_theorem(), {"A": [[1.1, 0.0], [0.0, 0.5]]})
    report = feasp(inst, backend=backend)
    assert report.verdict == "infeasible"
    assert abs(report.tmin) < 1e-6
    # AᵀPA − P < 0 alone holds with an indefinite P, P > 0 alone holds: the pair is responsible
    assert sorted(report.responsible) == ["Lyapunov", "P > 0"]


def test_stable_lyapunov_strictly_feasible():
    inst = bind(_lyapunov_theorem(), {"A": [[0.5, 0.2], [0.0, -0.3]]})
    report = feasp(inst)
    assert report.feasible and report.tmin < -1.0
    assert report.responsible == []


def test_solve_reports_infeasible_as_a_result_with_margins():
    sol = solve_instance(bind(_interval_theorem(), {"c": [[1.0]], "d": [[0.0]]}))
    assert sol.feasp.verdict == "infeasible" and not sol.ok   # feasp's word; status is the solver's
    assert sol.feasp.tmin == pytest.approx(0.5, abs=1e-6)
    d = sol.as_dict()
    assert d["feasp"]["verdict"] == "infeasible" and d["verdict"]["word"] == "infeasible"   # proved: X > 1, X < 0
    assert {m["label"] for m in d["feasp"]["lmis"]} == {"X > c", "X < d"}


def test_thin_problem_is_marginal_not_infeasible():
    """Feasible by less than the margin: t* ∈ [−margin, 0) is 'marginal'."""
    inst = bind(_interval_theorem(), {"c": [[0.0]], "d": [[2e-8]]})
    report = feasp(inst, margin=1e-7)
    assert report.tmin == pytest.approx(-1e-8, abs=2e-9)
    assert report.verdict == "marginal"
