"""Polytopic data: the theorem states an LMI once, the library instantiates it per vertex with
per-vertex or shared variables as declared.  Checked against a hand-written cvxpy model."""
import cvxpy as cp
import numpy as np
import pytest

from lmidsl.pipeline import make_instance, solve
from lmidsl.errors import InputError
from lmidsl.theorem.registry import get_theorem



def _hand_written_theorem1_min(vertices, lam1, lam2, eps, margin=1e-7):
    """(27), (28), P̂ > 0 at every vertex: common R, W, T, S_*, Ψ, g; P̂ per vertex (docs/reproductions/003.md)."""
    n, m, r = 2, 1, 1
    R, W, T, SA, SM = (cp.Variable((n, n)) for _ in range(5))
    SB, SC, SD, Psi = cp.Variable((n, r)), cp.Variable((m, n)), cp.Variable((m, r)), cp.Variable((m, m))
    g = cp.Variable()
    He = lambda X: X + X.T  # noqa: E731
    Im = np.eye(m)
    cons = []
    for v in vertices:
        A, B, M, C, D, L1, L2 = (np.array(v[k], dtype=float) for k in ("A", "B", "M", "C", "D", "L1", "L2"))
        P11, P22 = cp.Variable((n, n), symmetric=True), cp.Variable((n, n), symmetric=True)
        P12 = cp.Variable((n, n))
        Pi1 = -g * Im + eps * He(Psi.T @ L2 - SD @ D)
        Pi2 = P22 + He(T)
        Pi3 = Im - He(Psi)
        o1 = Psi.T @ L1 - SD @ C - SC
        ow = -eps * Psi + Psi.T @ L2 - SD @ D
        for flow in (True, False):
            X = A if flow else M
            S = SA if flow else SM
            SBC = SB @ C if flow else np.zeros((n, n))
            low = [
                [lam1 * He(R.T @ X) - P11],
                [lam1 * W.T @ X + lam2 * (SBC + S) - P12.T, -lam2 * He(S) - P22],
                [eps * o1 + lam1 * B.T @ R if flow else eps * o1,
                 eps * SC + lam1 * B.T @ W + lam2 * D.T @ SB.T if flow else eps * SC, Pi1],
                [-lam1 * R + R.T @ X, -lam1 * W - lam2 * T.T, R.T @ B if flow else np.zeros((n, m)), P11 - He(R)],
                [W.T @ X + SBC + S, lam2 * T.T - S, W.T @ B + SB @ D if flow else np.zeros((n, m)), P12.T - (W.T + T), Pi2],
                [o1, SC, ow, np.zeros((m, n)), np.zeros((m, n)), Pi3],
            ]
            full = [[low[i][j] if j <= i else low[j][i].T for j in range(6)] for i in range(6)]
            N = cp.bmat(full)
            cons.append(N << -margin * np.eye(N.shape[0]))
        cons.append(cp.bmat([[P11, P12], [P12.T, P22]]) >> margin * np.eye(2 * n))
    prob = cp.Problem(cp.Minimize(g), cons)
    prob.solve(solver="CLARABEL")
    return prob.status, float(np.sqrt(g.value))


def test_two_vertex_mechanism_equals_hand_written_shared_variables():
    ex = get_theorem("pan_impulsive.thm1_min").examples["modified-two-vertex"]
    vertices = [{**ex.data, **v} for v in ex.vertices]
    sol = solve("pan_impulsive.thm1_min", "modified-two-vertex", certify=False)
    assert sol.ok and sol.lmis_hold and sol.instance.nvertices == 2
    status, gamma = _hand_written_theorem1_min(vertices, ex.params["lambda1"], ex.params["lambda2"],
                                               ex.params["epsilon"])
    assert status == "optimal"
    assert sol.gamma == pytest.approx(gamma, rel=1e-4)
    # shared variables: one R; per-vertex: one P11 per vertex
    assert np.ndim(sol.values["R"]) == 2 and len(sol.values["P11"]) == 2


def test_identical_vertices_equal_the_single_vertex_theorem():
    """Corollary 1 of seed 000 on two copies of the plant gives Theorem 3's optimum."""
    ex = get_theorem("wang_l2linf.cor1").examples["paper-one-vertex"]
    twice = {**ex.data, **ex.params, "vertices": [dict(ex.vertices[0]), dict(ex.vertices[0])]}
    two = solve("wang_l2linf.cor1", data=twice, certify=False)
    one = solve("wang_l2linf.thm3", "paper-full", certify=False)
    assert two.gamma == pytest.approx(one.gamma, rel=1e-4)   # solver accuracy ~1e-5 here


def test_per_vertex_data_given_once_are_common_to_all_vertices():
    inst = make_instance("pan_impulsive.thm1", "modified-two-vertex")
    assert inst.nvertices == 2
    assert np.array_equal(inst.data["B"][0], inst.data["B"][1])
    assert not np.array_equal(inst.data["A"][0], inst.data["A"][1])
    single = make_instance("pan_impulsive.thm1", "modified")     # no 'vertices': one vertex
    assert single.nvertices == 1
    ex = get_theorem("pan_impulsive.thm1").examples["modified-two-vertex"]
    bad = {**ex.data, **ex.params, "A": ex.vertices[0]["A"], "vertices": ex.vertices}
    with pytest.raises(InputError, match="both in the vertex and once"):
        make_instance("pan_impulsive.thm1", data=bad)
