"""Simulation of a delta-operator plant and filter over a quantising, lossy network.

Mechanism of Zhang/Liu/Du (seed 002), for any plant and filter:

* plant (2):  x(k+1) = x(k) + h(A_δ x(k) + B_δ w(k)),  y = C x,  z = D x;
* quantiser (3): ỹ(k) = q(y(k)) componentwise (:class:`.quantizer.LogQuantizer`), or the
  sector model ỹ = (1 + Δ)y with a fixed Δ;
* losses (7): α_j(k) i.i.d. Bernoulli(ᾱ), π_i(k) = ∏_{j≤i} α_j(k),
  ŷ(k) = ỹ(k) − Σ_{i=1..N} π_i(k) [ỹ(k+1−i) − ỹ(k−i)]  (= ỹ(k − m_k), m_k the number of
  leading ones among α_1(k) … α_N(k)); samples before k = 0 are 0;
* filter (8): x_f(k+1) = x_f + h(A_f x_f + B_f ŷ),  z_f = C_f x_f,  e = z − z_f.

:func:`empirical_gain` gives sqrt(E Σ‖e‖² / Σ‖w‖²) from zero initial state, averaged over
loss realisations: a lower bound on the expected l2 gain that a certified γ must exceed
(when the certificate covers the quantiser, i.e. the whole sector |Δ| ≤ β).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def paper_disturbance(k):
    """w(k) = 0.5 exp(−0.1k) sin(0.01πk) (Section 3 of the paper)."""
    k = np.asarray(k, dtype=float)
    return 0.5 * np.exp(-0.1 * k) * np.sin(0.01 * np.pi * k)


def loss_variables(steps: int, N: int, alpha_bar: float, rng) -> np.ndarray:
    """α_j(k), shape (steps, N), i.i.d. Bernoulli(ᾱ)."""
    return (rng.random((steps, N)) < alpha_bar).astype(float)


@dataclass
class SimResult:
    k: np.ndarray
    x: np.ndarray
    xf: np.ndarray
    y: np.ndarray
    y_quantised: np.ndarray
    y_received: np.ndarray
    losses: np.ndarray          # m_k
    z: np.ndarray
    zf: np.ndarray
    e: np.ndarray
    w: np.ndarray

    @property
    def energy_ratio(self) -> float:
        """sqrt(Σ‖e‖² / Σ‖w‖²) over the run."""
        return float(np.sqrt(np.sum(self.e ** 2) / np.sum(self.w ** 2)))


def _shift_state(A, B, x0, u):
    """x(k+1) = A x(k) + B u(k), x(0) = x0; returns x(0 … steps−1) (rows)."""
    steps = u.shape[0]
    x = np.empty((steps, A.shape[0]))
    xk = np.asarray(x0, dtype=float).copy()
    Bu = u @ B.T
    At = A.T
    for t in range(steps):
        x[t] = xk
        xk = xk @ At + Bu[t]
    return x


def received(yq: np.ndarray, alpha: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Model (7) literally, for all k at once: (ŷ, m_k) from ỹ (steps × n_y) and α (steps × N)."""
    steps, N = alpha.shape
    pad = np.vstack([np.zeros((N + 1, yq.shape[1])), yq])   # pad[j + N + 1] = ỹ(j), zeros before 0
    pi = np.cumprod(alpha, axis=1)
    yhat = yq.copy()
    ks = np.arange(steps)
    for i in range(1, N + 1):
        yhat -= pi[:, i - 1:i] * (pad[ks + 1 - i + N + 1] - pad[ks - i + N + 1])
    return yhat, pi.sum(axis=1).astype(int)


def simulate(plant: dict, filt: dict, h: float, N: int, alpha_bar: float, *, steps: int = 100,
             w=paper_disturbance, x0=None, xf0=None, quantizer=None, delta: float | None = None,
             rng=None, seed: int = 0) -> SimResult:
    """One run.  ``plant``: Ad, Bd, C, D; ``filt``: Af, Bf, Cf (delta form).

    ``quantizer`` (callable) quantises y; otherwise ỹ = (1 + delta) y (delta = 0 by default).
    ``w`` is a callable of k or an array of length ``steps``.  The plant does not depend on the
    filter, so the plant, the quantiser and the channel are evaluated first, then the filter.
    """
    Ad, Bd, C, D = (np.atleast_2d(np.asarray(plant[k], dtype=float)) for k in ("Ad", "Bd", "C", "D"))
    Af, Bf, Cf = (np.atleast_2d(np.asarray(filt[k], dtype=float)) for k in ("Af", "Bf", "Cf"))
    rng = np.random.default_rng(seed) if rng is None else rng
    n, nf = Ad.shape[0], Af.shape[0]
    k = np.arange(steps)
    wk = np.asarray(w(k) if callable(w) else w, dtype=float).reshape(steps, -1)
    x = _shift_state(np.eye(n) + h * Ad, h * Bd, np.zeros(n) if x0 is None else np.ravel(x0), wk)
    y = x @ C.T
    yq = quantizer(y) if quantizer is not None else (1 + (delta or 0.0)) * y
    alpha = loss_variables(steps, N, alpha_bar, rng)
    yr, m = received(yq, alpha)
    xf = _shift_state(np.eye(nf) + h * Af, h * Bf, np.zeros(nf) if xf0 is None else np.ravel(xf0), yr)
    z = x @ D.T
    zf = xf @ Cf.T
    return SimResult(k, x, xf, y, yq, yr, m, z, zf, z - zf, wk)


def empirical_gain(plant: dict, filt: dict, h: float, N: int, alpha_bar: float, *, steps: int,
                   runs: int = 20, w=paper_disturbance, quantizer=None, delta: float | None = None,
                   seed: int = 0) -> float:
    """sqrt(mean over runs of Σ‖e‖² / Σ‖w‖²), zero initial state."""
    rng = np.random.default_rng(seed)
    ratios = [simulate(plant, filt, h, N, alpha_bar, steps=steps, w=w, quantizer=quantizer,
                       delta=delta, rng=rng).energy_ratio ** 2 for _ in range(runs)]
    return float(np.sqrt(np.mean(ratios)))
