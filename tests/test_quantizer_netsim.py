"""The logarithmic quantiser (3) and the loss model (7) of seed 002."""
import numpy as np
import pytest

from lmidsl.theorems.zhang_quantized_loss.netsim import received, simulate
from lmidsl.theorems.zhang_quantized_loss.quantizer import LogQuantizer


@pytest.mark.parametrize("rho,chi0", [(0.75, 1.3), (0.5, 1.0), (0.9, 0.2)])
def test_quantiser_sector_bound(rho, chi0):
    q = LogQuantizer(rho, chi0)
    rng = np.random.default_rng(0)
    v = np.sign(rng.standard_normal(20000)) * 10 ** rng.uniform(-6, 6, 20000)
    err = np.abs(q(v) - v)
    assert np.all(err <= q.beta * np.abs(v) * (1 + 1e-12))
    # the bound is tight: relative errors come close to ±β
    rel = q.relative_error(v)
    assert rel.max() > 0.99 * q.beta and rel.min() < -0.99 * q.beta
    # values are levels ±ρ^i χ0, the quantiser is odd, q(0) = 0
    i = np.log(np.abs(q(v)) / chi0) / np.log(rho)
    assert np.allclose(i, np.round(i), atol=1e-9)
    assert np.array_equal(q(-v), -q(v)) and q(np.array([0.0]))[0] == 0


def test_quantiser_interval_edges():
    q = LogQuantizer(0.75, 1.3)
    b = q.beta
    assert q(np.array([1.3 / (1 - b)]))[0] == pytest.approx(1.3)          # right end belongs to χ0
    assert q(np.array([1.3 / (1 + b) * (1 + 1e-9)]))[0] == pytest.approx(1.3)
    assert q(np.array([1.3 / (1 + b) * (1 - 1e-9)]))[0] == pytest.approx(1.3 * 0.75)


def test_loss_model_is_a_delay_by_the_leading_ones():
    """(7) literally equals ỹ(k − m_k), m_k = number of leading ones of α_1(k), …, α_N(k)."""
    rng = np.random.default_rng(3)
    steps, N = 200, 3
    yq = rng.standard_normal((steps, 1))
    alpha = (rng.random((steps, N)) < 0.5).astype(float)
    yhat, m = received(yq, alpha)
    for k in range(steps):
        lead = 0
        while lead < N and alpha[k, lead] == 1:
            lead += 1
        assert m[k] == lead
        assert yhat[k, 0] == pytest.approx(yq[k - lead, 0] if k - lead >= 0 else 0.0)


def test_loss_frequencies():
    """Pr(m_k = m) = ᾱ^m (1 − ᾱ) for m < N and ᾱ^N for m = N."""
    plant = {"Ad": [[-1.0]], "Bd": [[1.0]], "C": [[1.0]], "D": [[1.0]]}
    filt = {"Af": [[-1.0]], "Bf": [[1.0]], "Cf": [[1.0]]}
    r = simulate(plant, filt, 0.01, 2, 0.5, steps=40000, seed=1)
    freq = np.bincount(r.losses, minlength=3) / 40000
    assert np.allclose(freq, [0.5, 0.25, 0.25], atol=0.01)


def test_simulation_matches_the_difference_equations():
    """No losses, no quantisation: x(k+1) = (I + hA)x + hBw, filter likewise on y."""
    h = 0.1
    plant = {"Ad": [[-1.0, 0.2], [0.0, -0.5]], "Bd": [[1.0], [0.5]], "C": [[1.0, 1.0]], "D": [[1.0, 0.0]]}
    filt = {"Af": [[-2.0]], "Bf": [[1.0]], "Cf": [[0.5]]}
    r = simulate(plant, filt, h, 1, 0.0, steps=5, w=np.ones(5), x0=[1.0, -1.0])
    x = np.array([1.0, -1.0])
    xf = np.zeros(1)
    for k in range(5):
        assert np.allclose(r.x[k], x) and np.allclose(r.xf[k], xf)
        y = np.array(plant["C"]) @ x
        x = x + h * (np.array(plant["Ad"]) @ x + np.array(plant["Bd"])[:, 0])
        xf = xf + h * (np.array(filt["Af"]) @ xf + np.array(filt["Bf"]) @ y)
