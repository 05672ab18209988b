"""Simulation of the impulsive filtering-error system (lmidsl.theorems.pan_impulsive.impulsive) and the simulate command."""
import json

import numpy as np
import pytest

from lmidsl.errors import InputError
from lmidsl.theorems.pan_impulsive.impulsive import (disturbance, error_system, impulse_sequence, lifted_gain,
                              lifted_operator, parse_impulses, simulate)

from test_pan_impulsive import PI

DESIGNED = {"Ahat": [[0.04, 0.012], [-0.13, 0.0]], "Bhat": [[0.096], [0.0087]],
            "Mhat": [[0.9, -0.0012], [-0.0028, 0.72]], "Chat": [[7.6, -0.06]], "Dhat": [[0.24]]}


def _system():
    return error_system({**PI.MODIFIED_PLANT, **DESIGNED})


def test_impulse_sequences():
    assert not impulse_sequence("none", 10).any()
    assert np.flatnonzero(impulse_sequence("periodic", 12, period=4)).tolist() == [1, 5, 9]
    assert impulse_sequence("all", 6, start=2).tolist() == [False, False, True, True, True, True]
    r1 = impulse_sequence("random", 500, probability=0.3, seed=3)
    assert np.array_equal(r1, impulse_sequence("random", 500, probability=0.3, seed=3))
    assert 0.2 < r1.mean() < 0.4
    assert np.flatnonzero(parse_impulses("explicit:2,7", 10)).tolist() == [2, 7]
    with pytest.raises(InputError):
        parse_impulses("sometimes", 10)


def test_simulation_is_the_lifted_operator():
    system = _system()
    E = impulse_sequence("random", 60, probability=0.3, seed=1)
    w = disturbance("noise", 60, seed=2)
    H = lifted_operator(system, E)
    assert np.allclose(simulate(system, w, E).e.ravel(), H @ w.ravel(), atol=1e-12)


def test_jump_instants_keep_the_output_error_but_not_the_disturbance():
    system = _system()
    E = impulse_sequence("explicit", 10, instants=[0])
    w = disturbance("pulse", 10, at=0)
    traj = simulate(system, w, E)
    assert np.allclose(traj.xi, 0)                      # ω at an impulse instant does not enter ξ
    assert traj.e[0, 0] == pytest.approx(system.Dbar[0, 0])


def test_lifted_gain_without_impulses_tends_to_the_hinf_norm():
    """A fast plant (poles ≤ 0.6 in modulus), so 300 samples reach the H∞ norm."""
    system = error_system({"A": [[0.5, 0.2], [0.0, -0.4]], "B": [[1.0], [0.5]], "M": [[0.3, 0], [0, 0.2]],
                           "C": [[1.0, 0.0]], "D": [[0.3]], "L1": [[1.0, 1.0]], "L2": [[0.0]],
                           "Ahat": [[0.2, 0.1], [-0.3, 0.6]], "Bhat": [[0.4], [0.2]],
                           "Mhat": [[0.1, 0], [0, 0.1]], "Chat": [[0.5, 0.7]], "Dhat": [[0.2]]})
    w = np.linspace(0, np.pi, 4001)
    hinf = max(np.linalg.norm(system.Cbar @ np.linalg.solve(np.exp(1j * x) * np.eye(4) - system.Abar,
                                                             system.Bbar) + system.Dbar, 2) for x in w)
    gain, worst = lifted_gain(system, impulse_sequence("none", 300))
    assert gain <= hinf * (1 + 1e-6)
    assert gain == pytest.approx(hinf, rel=1e-3)
    # the worst disturbance attains the gain in simulation
    traj = simulate(system, worst, impulse_sequence("none", 300))
    assert traj.energy_ratio == pytest.approx(gain, rel=1e-9)


def test_simulate_cli_on_the_printed_filter(capsys):
    from lmidsl.cli import main
    code = main(["simulate", "pan_impulsive.lemma1", "--example", "paper-printed", "--horizon", "80",
                 "--impulses", "none", "--impulses", "all", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    rows = {r["impulses"]: r for r in out["rows"]}
    assert rows["none"]["lifted_gain"] > 0.5 and rows["all"]["lifted_gain"] > 0.9551
