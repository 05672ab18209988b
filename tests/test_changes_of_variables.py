"""The standard changes of variables (lmidsl.numeric.changes_of_variables), checked numerically.

Each recovery is evaluated through lmidsl's own recovery machinery (a throwaway theorem, bound
to random data, recovered at random values of the transformed variables); the closed loops it
is compared with are formed by python-control (``StateSpace.lft``), not by lmidsl's formulas.
"""
import numpy as np
import pytest

import lmidsl
from lmidsl import I, Theorem, Source
from lmidsl.numeric.changes_of_variables import (closed_loop_matrices, filter_blocks, full_order_filter,
                                                 mn_split, output_feedback, output_feedback_blocks,
                                                 state_feedback_gain)
from lmidsl.numeric.design import Design
from lmidsl.numeric.evaluate import NumericEvaluator
from lmidsl.numeric.instance import bind
from lmidsl.numeric.interconnection import closed_loop, filtering_error, generalized_plant
from lmidsl.numeric.recovery import recover

control = pytest.importorskip("control")

TOL = 1e-9          # relative, on identities that hold exactly in exact arithmetic
PLANT = ("A", "B1", "B2", "C1", "C2", "D11", "D12", "D21", "D22")
SHAPES = dict(A="n n", B1="n m1", B2="n m2", C1="p1 n", C2="p2 n", D11="p1 m1", D12="p1 m2",
              D21="p2 m1", D22="p2 m2")


def _determined(thm, *variables):
    """‖V‖ < 1 for each variable: LMIs that mention them (a recovery may use only variables the
    LMIs determine); never solved here — the tests recover at chosen values."""
    for V in variables:
        thm.lmi(f"(bound {V.name})", [[-I], [V, -I]])


def _theorem(tag: str, with_d22: bool = True):
    thm = Theorem(f"cov_test.{tag}", "change of variables test", Source("test", "-"))
    dims = dict(zip("n m1 m2 p1 p2".split(), thm.dim("n m1 m2 p1 p2")))
    d = {k: thm.data(k, *(dims[s] for s in SHAPES[k].split())) for k in PLANT}
    n, m2, p2 = dims["n"], dims["m2"], dims["p2"]
    v = dict(X=thm.var("X", n, kind="symmetric"), Y=thm.var("Y", n, kind="symmetric"),
             Ah=thm.var("Ah", n, n), Bh=thm.var("Bh", n, p2), Ch=thm.var("Ch", m2, n),
             Dh=thm.var("Dh", m2, p2))
    _determined(thm, *v.values())
    return thm, d, v


def _random(rng, n=3, m1=2, m2=2, p1=3, p2=2, d22=True):
    dims = dict(n=n, m1=m1, m2=m2, p1=p1, p2=p2)
    data = {k: rng.standard_normal(tuple(dims[s] for s in SHAPES[k].split())) for k in PLANT}
    if not d22:
        data["D22"] = np.zeros((p2, m2))
    else:
        data["D22"] *= 0.3
    G = rng.standard_normal((n, n))
    X = G @ G.T + n * np.eye(n)
    H = rng.standard_normal((n, n))
    Y = np.linalg.inv(X) + H @ H.T + 0.1 * np.eye(n)        # [[X, I], [I, Y]] > 0
    values = dict(X=X, Y=Y, Ah=rng.standard_normal((n, n)), Bh=rng.standard_normal((n, p2)),
                  Ch=rng.standard_normal((m2, n)), Dh=0.3 * rng.standard_normal((m2, p2)))
    return data, values


def _recover(thm, data, values):
    instance = bind(thm, {k: v.tolist() for k, v in data.items()})
    return recover(instance, values)[0], instance


def _evaluate(instance, values, exprs: dict) -> dict:
    ev = NumericEvaluator(instance.dims, {**instance.data, **values}, {})
    return {k: np.atleast_2d(ev.visit(e)) for k, e in exprs.items()}


def _close(a, b, tol=TOL):
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    assert a.shape == b.shape
    assert np.max(np.abs(a - b)) <= tol * max(1.0, np.max(np.abs(b))), np.max(np.abs(a - b))


def _pi(X, Y, M, N):
    """Π₁ = [[X, I], [Mᵀ, 0]] and 𝒫 = [[Y, N], [Nᵀ, −NᵀXM⁻ᵀ]] (so 𝒫 Π₁ = [[I, Y], [0, Nᵀ]])."""
    n = X.shape[0]
    Pi1 = np.block([[X, np.eye(n)], [M.T, np.zeros((n, n))]])
    P = np.block([[Y, N], [N.T, -N.T @ X @ np.linalg.inv(M.T)]])
    return Pi1, P


@pytest.mark.parametrize("seed", range(5))
def test_output_feedback_congruence_identities(seed):
    """Π₁ᵀ𝒫Π₁ = [[X, I], [I, Y]], Π₁ᵀ𝒫𝒜Π₁, Π₁ᵀ𝒫ℬ, 𝒞Π₁, 𝒟 equal the affine blocks, for the
    controller recovered by output_feedback and the closed loop formed by python-control."""
    rng = np.random.default_rng(seed)
    data, values = _random(rng, d22=False)
    thm, d, v = _theorem(f"of{seed}")
    thm.recover(**output_feedback(thm, v["X"], v["Y"], v["Ah"], v["Bh"], v["Ch"], v["Dh"],
                                  d["A"], d["B2"], d["C2"]))
    K, instance = _recover(thm, data, values)
    design = Design("controller", K, time="continuous")
    cl = closed_loop(data, design)                          # python-control's LFT
    (M, N), _ = mn_split(np.eye(3) - values["X"] @ values["Y"])
    Pi1, P = _pi(values["X"], values["Y"], M, N)
    _close(M @ N.T, np.eye(3) - values["X"] @ values["Y"])
    _close(P, P.T)
    b = _evaluate(instance, values, output_feedback_blocks(
        v["X"], v["Y"], v["Ah"], v["Bh"], v["Ch"], v["Dh"], *(d[k] for k in PLANT[:-1])))
    _close(Pi1.T @ P @ Pi1, np.block([[b["P11"], np.eye(3)], [np.eye(3), b["P22"]]]))
    _close(Pi1.T @ P @ cl.A @ Pi1, np.block([[b["A11"], b["A12"]], [b["A21"], b["A22"]]]))
    _close(Pi1.T @ P @ cl.B, np.vstack([b["B1"], b["B2"]]))
    _close(cl.C @ Pi1, np.hstack([b["C1"], b["C2"]]))
    _close(cl.D, b["D"])


@pytest.mark.parametrize("seed", range(3))
def test_loop_shift_for_d22(seed):
    """The controller recovered with D22 closes, around the plant with D22, exactly the loop the
    controller recovered without it closes around the plant with D22 = 0."""
    rng = np.random.default_rng(10 + seed)
    data, values = _random(rng, d22=True)
    thm1, d1, v1 = _theorem(f"ls_with{seed}")
    thm1.recover(**output_feedback(thm1, v1["X"], v1["Y"], v1["Ah"], v1["Bh"], v1["Ch"], v1["Dh"],
                                   d1["A"], d1["B2"], d1["C2"], d1["D22"]))
    thm0, d0, v0 = _theorem(f"ls_without{seed}")
    thm0.recover(**output_feedback(thm0, v0["X"], v0["Y"], v0["Ah"], v0["Bh"], v0["Ch"], v0["Dh"],
                                   d0["A"], d0["B2"], d0["C2"]))
    K1, _ = _recover(thm1, data, values)
    K0, _ = _recover(thm0, data, values)
    cl1 = closed_loop(data, Design("controller", K1, time="continuous"))
    cl0 = closed_loop(dict(data, D22=np.zeros_like(data["D22"])), Design("controller", K0, time="continuous"))
    for a, b in ((cl1.A, cl0.A), (cl1.B, cl0.B), (cl1.C, cl0.C), (cl1.D, cl0.D)):
        _close(a, b)


def test_state_feedback_gain():
    """K = W Y⁻¹ makes (A + B2 K) Y = A Y + B2 W."""
    rng = np.random.default_rng(3)
    thm = Theorem("cov_test.sf", "sf", Source("test", "-"))
    n, m2 = thm.dim("n m2")
    thm.data("A", n, n)
    thm.data("B2", n, m2)
    Y, W = thm.var("Y", n, kind="symmetric"), thm.var("W", m2, n)
    _determined(thm, Y, W)
    thm.recover(K=state_feedback_gain(W, Y))
    G = rng.standard_normal((3, 3))
    vals = dict(Y=G @ G.T + np.eye(3), W=rng.standard_normal((2, 3)))
    data = dict(A=rng.standard_normal((3, 3)), B2=rng.standard_normal((3, 2)))
    K, _ = _recover(thm, data, vals)
    _close((data["A"] + data["B2"] @ K["K"]) @ vals["Y"], data["A"] @ vals["Y"] + data["B2"] @ vals["W"])


@pytest.mark.parametrize("seed", range(3))
def test_full_order_filter_congruence_identities(seed):
    """The filter recovered by full_order_filter: the filtering-error system formed by
    python-control satisfies the congruence identities with filter_blocks."""
    rng = np.random.default_rng(20 + seed)
    data, values = _random(rng, m2=3, p1=3, d22=False)       # u = ẑ has the size of z
    thm, d, v = _theorem(f"f{seed}")
    thm.recover(**full_order_filter(thm, v["X"], v["Y"], v["Ah"], v["Bh"], v["Ch"], v["Dh"],
                                    d["A"], d["C2"]))
    values["Ch"] = rng.standard_normal((3, 3))
    values["Dh"] = rng.standard_normal((3, 2))
    F, instance = _recover(thm, data, values)
    err = filtering_error(data, Design("filter", F, time="discrete"))
    (M, N), _ = mn_split(np.eye(3) - values["X"] @ values["Y"])
    Pi1, P = _pi(values["X"], values["Y"], M, N)
    b = _evaluate(instance, values, filter_blocks(v["X"], v["Y"], v["Ah"], v["Bh"], v["Ch"], v["Dh"],
                                                  d["A"], d["B1"], d["C1"], d["C2"], d["D11"], d["D21"]))
    _close(Pi1.T @ P @ err.A @ Pi1, np.block([[b["A11"], b["A12"]], [b["A21"], b["A22"]]]))
    _close(Pi1.T @ P @ err.B, np.vstack([b["B1"], b["B2"]]))
    _close(err.C @ Pi1, np.hstack([b["C1"], b["C2"]]))
    _close(err.D, b["D"])


def test_symbolic_closed_loop_matches_python_control():
    """closed_loop_matrices (the analysis theorems' closed loop, general D22) = python-control's LFT."""
    rng = np.random.default_rng(5)
    data, _ = _random(rng, d22=True)
    thm = Theorem("cov_test.cl", "cl", Source("test", "-"))
    dims = dict(zip("n m1 m2 p1 p2 nk".split(), thm.dim("n m1 m2 p1 p2 nk")))
    d = {k: thm.data(k, *(dims[s] for s in SHAPES[k].split())) for k in PLANT}
    K = dict(AK=thm.data("AK", dims["nk"], dims["nk"]), BK=thm.data("BK", dims["nk"], dims["p2"]),
             CK=thm.data("CK", dims["m2"], dims["nk"]), DK=thm.data("DK", dims["m2"], dims["p2"]))
    Kv = dict(AK=rng.standard_normal((2, 2)), BK=rng.standard_normal((2, 2)),
              CK=rng.standard_normal((2, 2)), DK=0.3 * rng.standard_normal((2, 2)))
    instance = bind(thm, {k: np.asarray(x).tolist() for k, x in {**data, **Kv}.items()})
    ours = _evaluate(instance, {}, closed_loop_matrices(*(d[k] for k in PLANT), *(K[k] for k in K)))
    theirs = closed_loop(data, Design("controller", Kv, time="continuous"))
    for k in "ABCD":
        _close(ours[k], getattr(theirs, k))


def test_design_as_statespace():
    """Controller, filter and static gain as python-control systems, with the right time base."""
    rng = np.random.default_rng(0)
    K = Design("controller", dict(AK=rng.standard_normal((2, 2)), BK=np.ones((2, 1)),
                                  CK=np.ones((1, 2)), DK=[[0.5]]), time="continuous")
    s = K.as_statespace()
    assert (s.nstates, s.ninputs, s.noutputs, s.dt) == (2, 1, 1, 0)
    F = Design("filter", dict(Af=[[0.5]], Bf=[[1.0]], Cf=[[2.0]]), time="discrete", sample_time=0.1)
    s = F.as_statespace()
    assert s.dt == 0.1 and np.allclose(s.D, 0)
    G = Design("gain", dict(K=[[1.0, 2.0, 3.0]]), time="discrete")
    s = G.as_statespace()
    assert (s.nstates, s.ninputs, s.noutputs, s.dt) == (0, 3, 1, True)
    assert np.allclose(s.D, [[1, 2, 3]])
    P, nu, ny = generalized_plant(dict(A=[[1.0]], B1=[[1.0]], B2=[[1.0]], C1=[[1.0]], C2=[[1.0]]),
                                  "continuous")
    assert (P.ninputs, P.noutputs, nu, ny) == (2, 2, 1, 1)
    assert lmidsl.closed_loop is closed_loop
