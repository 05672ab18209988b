"""The loop lmidsl's evidence measures (lmidsl.numeric.interconnection.lower_lft, numpy) against
python-control's own LFT (``StateSpace.lft``) and norms, on random plants and designs of every
kind, both time domains, with non-zero D blocks (D22 and DK included)."""
from __future__ import annotations

import numpy as np
import pytest

from lmidsl.numeric.design import Design
from lmidsl.numeric.interconnection import (closed_loop_realisation, filtering_error_realisation,
                                            generalized_plant, h2_norm, loop_summary)

control = pytest.importorskip("control")


def _plant(rng, n, m1, m2, p1, p2, feedthrough=True):
    d = {"A": rng.standard_normal((n, n)), "B1": rng.standard_normal((n, m1)), "B2": rng.standard_normal((n, m2)),
         "C1": rng.standard_normal((p1, n)), "C2": rng.standard_normal((p2, n))}
    if feedthrough:
        d.update(D11=rng.standard_normal((p1, m1)), D12=rng.standard_normal((p1, m2)),
                 D21=rng.standard_normal((p2, m1)), D22=0.3 * rng.standard_normal((p2, m2)))
    return d


def _same(a, b):
    """Two realisations of one transfer function: the same frequency response at a few points."""
    for s in (0.3j, 1.7j, 0.2 + 5j) if a.isctime() else (np.exp(0.3j), np.exp(2.1j), 0.5 + 0.1j):
        Ga = a.C @ np.linalg.solve(s * np.eye(a.nstates) - a.A, a.B) + a.D if a.nstates else a.D
        Gb = b.C @ np.linalg.solve(s * np.eye(b.nstates) - b.A, b.B) + b.D if b.nstates else b.D
        assert np.allclose(Ga, Gb, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("time", ["continuous", "discrete"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_controller_loop_is_python_controls(time, seed):
    rng = np.random.default_rng(seed)
    d = _plant(rng, 4, 2, 2, 3, 2)
    nk = 3
    design = Design("controller", {"AK": rng.standard_normal((nk, nk)), "BK": rng.standard_normal((nk, 2)),
                                   "CK": rng.standard_normal((2, nk)), "DK": 0.4 * rng.standard_normal((2, 2))},
                    time=time)
    ours = closed_loop_realisation(d, design)
    P, nu, ny = generalized_plant(d, time)
    theirs = P.lft(design.as_statespace(), nu, ny)
    assert ours.nstates == theirs.nstates
    _same(ours, theirs)


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_gain_and_filter_loops_are_python_controls(time):
    rng = np.random.default_rng(7)
    d = _plant(rng, 5, 2, 1, 2, 2)
    gain = Design("gain", {"K": rng.standard_normal((1, 5))}, time=time)
    P, nu, ny = generalized_plant(d, time, state_feedback=True)
    _same(closed_loop_realisation(d, gain), P.lft(gain.as_statespace(), nu, ny))
    filt = Design("filter", {"Af": rng.standard_normal((3, 3)), "Bf": rng.standard_normal((3, 2)),
                             "Cf": rng.standard_normal((2, 3)), "Df": rng.standard_normal((2, 2))}, time=time)
    plant = dict(d, B2=np.zeros((5, 2)), D12=-np.eye(2), D22=np.zeros((2, 2)))
    P, nu, ny = generalized_plant(plant, time)
    _same(filtering_error_realisation(d, filt), P.lft(filt.as_statespace(), nu, ny))


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_summary_norms_are_python_controls(time):
    rng = np.random.default_rng(11)
    d = _plant(rng, 4, 2, 1, 2, 2, feedthrough=(time == "discrete"))
    A = d["A"]
    d["A"] = A - (max(np.linalg.eigvals(A).real) + 0.5) * np.eye(4) if time == "continuous" \
        else 0.8 * A / max(abs(np.linalg.eigvals(A)))
    gain = Design("gain", {"K": np.zeros((1, 4))}, time=time)
    loop = closed_loop_realisation(d, gain)
    summary = loop_summary(loop)
    system = loop.as_statespace()
    assert summary["stable"]
    assert summary["hinf_norm"] == pytest.approx(float(control.norm(system, "inf", tol=1e-10)), rel=1e-9)
    assert h2_norm(loop, time) == pytest.approx(float(control.norm(system, 2)), rel=1e-9)
    assert summary["h2_norm"] == pytest.approx(float(control.norm(system, 2)), rel=1e-9)


def test_an_ill_posed_loop_is_refused():
    rng = np.random.default_rng(5)
    d = _plant(rng, 3, 1, 1, 1, 1)
    d["D22"] = np.array([[2.0]])
    design = Design("controller", {"AK": np.zeros((1, 1)), "BK": np.ones((1, 1)), "CK": np.ones((1, 1)),
                                   "DK": np.array([[0.5]])}, time="continuous")
    with pytest.raises(ValueError, match="well posed"):
        closed_loop_realisation(d, design)
