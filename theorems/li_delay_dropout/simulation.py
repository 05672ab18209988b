"""Monte Carlo simulation of seed 001's network model (2), an H∞ filter and a standard Kalman filter.

The measurement is simulated as the paper defines it, on the original model, not through the
augmented form (5):

    x_{k+1} = A x_k + B w_k,   ỹ_k = C1 x_k + C2 w_k,   z_k = D1 x_k + D2 w_k,
    y_k = ξ1,k ỹ_k + (1−ξ1,k)(1−ξ1,k−1) ξ2,k ỹ_{k−1} + (1−ξ1,k)[1 − (1−ξ1,k−1) ξ2,k] y_{k−1},

with ξ1,k, ξ2,k independent Bernoulli(ξ̄1), Bernoulli(ξ̄2) sequences, x_0 = 0 and
ỹ_{−1} = y_{−1} = 0 (docs/reproductions/001.md); ξ1,−1 is drawn like the others.  A step is "on time"
when ξ1,k = 1, "delayed" when ξ1,k = 0, ξ1,k−1 = 0, ξ2,k = 1 (y_k = ỹ_{k−1}), otherwise "lost"
(y_k = y_{k−1}); Remark 1 gives their probabilities ξ̄1, (1−ξ̄1)²ξ̄2 and the rest.

Filters, both fed the received y_k:

* the H∞ filter (6): X̂_{k+1} = Af X̂_k + Bf y_k, ẑ_k = Cf X̂_k + Df y_k, X̂_0 = 0;
* the standard Kalman filter of the nominal model (no delays, no dropouts: it takes y_k = ỹ_k),
  with w white of variance Q_w, the correlation of process noise B w_k and measurement noise
  C2 w_k taken into account, and the estimate ẑ_k = D1 x̂_{k|k} + D2 ŵ_{k|k} from y_0..y_k.

The error of each is e_k = z_k − ẑ_k; the mean-square error is the average of |e_k|² over runs.
All runs are simulated at once (runs are a batch dimension).
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lmidsl import get_theorem, solve


@dataclass
class Plant:
    A: np.ndarray
    B: np.ndarray
    C1: np.ndarray
    C2: np.ndarray
    D1: np.ndarray
    D2: np.ndarray

    @classmethod
    def from_data(cls, data: dict) -> "Plant":
        return cls(*(np.atleast_2d(np.asarray(data[k], dtype=float)) for k in ("A", "B", "C1", "C2", "D1", "D2")))


@dataclass
class LinearFilter:
    Af: np.ndarray
    Bf: np.ndarray
    Cf: np.ndarray
    Df: np.ndarray

    @classmethod
    def from_data(cls, data: dict) -> "LinearFilter":
        return cls(*(np.atleast_2d(np.asarray(data[k], dtype=float)) for k in ("Af", "Bf", "Cf", "Df")))


def network(steps: int, runs: int, xi1: float, xi2: float, rng) -> tuple[np.ndarray, np.ndarray]:
    """ξ1 (runs × steps+1, column 0 is k = −1) and ξ2 (runs × steps) Bernoulli draws."""
    return ((rng.random((runs, steps + 1)) < xi1).astype(float),
            (rng.random((runs, steps)) < xi2).astype(float))


def simulate_plant(plant: Plant, w: np.ndarray):
    """x (runs × K × n), ỹ (runs × K × r), z (runs × K × m) for w (runs × K × p), x_0 = 0."""
    runs, K, _ = w.shape
    n = plant.A.shape[0]
    x = np.zeros((runs, K, n))
    for k in range(K - 1):
        x[:, k + 1] = x[:, k] @ plant.A.T + w[:, k] @ plant.B.T
    ytil = x @ plant.C1.T + w @ plant.C2.T
    z = x @ plant.D1.T + w @ plant.D2.T
    return x, ytil, z


def received(ytil: np.ndarray, xi1: np.ndarray, xi2: np.ndarray):
    """y_k by (2) and the event of each step (0 on time, 1 one-step delay, 2 lost)."""
    runs, K, r = ytil.shape
    y = np.zeros_like(ytil)
    events = np.zeros((runs, K), dtype=int)
    y_prev = np.zeros((runs, r))
    ytil_prev = np.zeros((runs, r))
    for k in range(K):
        a, a_prev, b = xi1[:, k + 1][:, None], xi1[:, k][:, None], xi2[:, k][:, None]
        delayed = (1 - a) * (1 - a_prev) * b
        held = (1 - a) * (1 - (1 - a_prev) * b)
        y[:, k] = a * ytil[:, k] + delayed * ytil_prev + held * y_prev
        events[:, k] = np.where(a[:, 0] == 1, 0, np.where(delayed[:, 0] == 1, 1, 2))
        y_prev, ytil_prev = y[:, k], ytil[:, k]
    return y, events


def run_filter(f: LinearFilter, y: np.ndarray) -> np.ndarray:
    """ẑ of the linear filter (6) driven by y (runs × K × r), X̂_0 = 0."""
    runs, K, _ = y.shape
    xh = np.zeros((runs, f.Af.shape[0]))
    zh = np.zeros((runs, K, f.Cf.shape[0]))
    for k in range(K):
        zh[:, k] = xh @ f.Cf.T + y[:, k] @ f.Df.T
        xh = xh @ f.Af.T + y[:, k] @ f.Bf.T
    return zh


def measurements(plant: Plant, w: np.ndarray, xi1: float, xi2: float, rng):
    """z, the received y and the events (runs × K) of model (2) driven by w (runs × K × p)."""
    runs, K, _ = w.shape
    _, ytil, z = simulate_plant(plant, w)
    y, events = received(ytil, *network(K, runs, xi1, xi2, rng))
    return z, y, events


def estimation_error(plant: Plant, f: LinearFilter, w: np.ndarray, xi1: float, xi2: float, rng) -> np.ndarray:
    """e_k = z_k − ẑ_k (runs × K × m) of filter ``f`` on model (2) driven by w (runs × K × p)."""
    z, y, _ = measurements(plant, w, xi1, xi2, rng)
    return z - run_filter(f, y)


def model_2_with_filter_6(d, w, runs: int, rng) -> np.ndarray:
    """The certification layer's simulation (:mod:`lmidsl.certify.montecarlo`): plant (1),
    network (2) with ξ1,k, ξ2,k drawn per run and step, filter (6), all from zero state.

    ``d`` holds the analysis instance's data and parameters as attributes (A, B, C1, C2, D1, D2,
    Af, Bf, Cf, Df, xi1, xi2); ``w`` is the deterministic disturbance (K × p), the same in every
    run.  Returns e (runs × K × m).
    """
    values = vars(d)
    w = np.atleast_2d(np.asarray(w, dtype=float))
    w = np.broadcast_to(w[None], (runs,) + w.shape)
    return estimation_error(Plant.from_data(values), LinearFilter.from_data(values), w,
                            float(d.xi1), float(d.xi2), rng)


def kalman(plant: Plant, y: np.ndarray, Qw: float = 1.0, P0: float = 1.0) -> np.ndarray:
    """ẑ_k = D1 x̂_{k|k} + D2 ŵ_{k|k} of the Kalman filter for the nominal model y_k = ỹ_k.

    Joint update of [x_k; w_k] (w_k is correlated with the current measurement through C2):
    S = C1 P C1ᵀ + C2 Q C2ᵀ, [x̂; ŵ]_{k|k} = [x̂_{k|k−1}; 0] + [P C1ᵀ; Q C2ᵀ] S⁻¹ (y_k − C1 x̂_{k|k−1}),
    then x̂_{k+1|k} = A x̂_{k|k} + B ŵ_{k|k} with the joint covariance propagated.  The gains do not
    depend on the data, so they are computed once for all runs.

    The prior is x̂_0 = 0 with covariance P0·I (P0 = 1: the filter does not know the initial
    state).  P0 = 0 would be a trap here: w_k is then read off y_k exactly, the Riccati recursion
    stays at its non-stabilising fixed point P = 0 and the filter is the plant's inverse, whose
    pole −77.3 (a zero of C1(zI − A)⁻¹B + C2) multiplies every mismatch between y_k and ỹ_k.
    From P0 > 0 it converges to the stabilising solution (filter poles 0.883, 0.013, 0).
    """
    A, B, C1, C2, D1, D2 = plant.A, plant.B, plant.C1, plant.C2, plant.D1, plant.D2
    runs, K, _ = y.shape
    n, p = A.shape[0], B.shape[1]
    Q = Qw * np.eye(p)
    P = P0 * np.eye(n)
    xpred = np.zeros((runs, n))
    zh = np.zeros((runs, K, D1.shape[0]))
    for k in range(K):
        S = C1 @ P @ C1.T + C2 @ Q @ C2.T
        Kx = P @ C1.T @ np.linalg.inv(S)
        Kw = Q @ C2.T @ np.linalg.inv(S)
        innov = y[:, k] - xpred @ C1.T
        xf = xpred + innov @ Kx.T
        wf = innov @ Kw.T
        zh[:, k] = xf @ D1.T + wf @ D2.T
        Pxx = P - Kx @ C1 @ P
        Pww = Q - Kw @ C2 @ Q
        Pxw = -Kx @ C2 @ Q
        M = np.hstack([A, B])
        J = np.block([[Pxx, Pxw], [Pxw.T, Pww]])
        P = M @ J @ M.T
        xpred = xf @ A.T + wf @ B.T
    return zh


def disturbance(kind: str, runs: int, steps: int, p: int, rng, Qw: float = 1.0) -> np.ndarray:
    """'white': N(0, Qw) i.i.d.; 'inverse-square': w_k = 1/k² for k = 1..K (the same in every run)."""
    if kind == "white":
        return np.sqrt(Qw) * rng.standard_normal((runs, steps, p))
    if kind == "inverse-square":
        k = np.arange(1, steps + 1, dtype=float)
        return np.broadcast_to((1.0 / k ** 2)[None, :, None], (runs, steps, p)).copy()
    raise ValueError(f"unknown disturbance {kind!r}")


def monte_carlo(plant: Plant, filters: dict, xi1: float, xi2: float, *, runs: int = 200,
                steps: int = 100, kind: str = "white", Qw: float = 1.0, seed: int = 0) -> dict:
    """MSE over ``runs`` of every filter in ``filters`` (name → LinearFilter) and of the Kalman filter."""
    rng = np.random.default_rng(seed)
    w = disturbance(kind, runs, steps, plant.B.shape[1], rng, Qw)
    z, y, events = measurements(plant, w, xi1, xi2, rng)
    estimates = {name: run_filter(f, y) for name, f in filters.items()}
    estimates["Kalman"] = kalman(plant, y, Qw)
    mse = {name: np.mean(np.sum((z - zh) ** 2, axis=2), axis=0) for name, zh in estimates.items()}
    return {
        "kind": kind, "runs": runs, "steps": steps, "xi1": xi1, "xi2": xi2, "seed": seed,
        "event_frequency": {"on_time": float(np.mean(events == 0)), "delayed": float(np.mean(events == 1)),
                            "lost": float(np.mean(events == 2))},
        "event_probability": {"on_time": xi1, "delayed": (1 - xi1) ** 2 * xi2,
                              "lost": (1 - xi1) * xi1 + (1 - xi1) ** 2 * (1 - xi2)},
        "mse": mse,
        "mse_mean": {name: float(np.mean(v)) for name, v in mse.items()},
        "sample": {"z": z[0, :, 0], **{name: zh[0, :, 0] for name, zh in estimates.items()}},
        "z_energy": float(np.mean(np.sum(z ** 2, axis=2))),
    }


def figure(result: dict, path, title: str | None = None) -> list:
    """Left: z_k and the estimates in the first run; right: MSE_k over the runs.  Saved as
    ``path`` in PNG and PDF (:func:`lmidsl.render.style.save`); the paths written."""
    from lmidsl import WIDE_FIGURE as WIDE, figure as new_figure, legend, save_figure as save

    k = np.arange(result["steps"]) + (1 if result["kind"] == "inverse-square" else 0)
    fig, (ax1, ax2) = new_figure(2, width=WIDE, height=0.36 * WIDE)
    ax1.plot(k, result["sample"]["z"], "k-", lw=1.5, label=r"$z_k$ (true)")
    styles = ["r--", "b-.", "g:"]
    names = [n for n in result["mse"] if n != "Kalman"] + ["Kalman"]
    for style, name in zip(styles, names):
        label = {"Kalman": "standard Kalman filter"}.get(name, name.replace("H∞", r"$H_\infty$"))
        ax1.plot(k, result["sample"][name], style, lw=1.1, label=label)
        ax2.semilogy(k, np.maximum(result["mse"][name], 1e-16), style, lw=1.2,
                     label=f"{label} (mean {result['mse_mean'][name]:.3g})")
    ax1.set_xlabel(r"time step $k$")
    ax1.set_ylabel(r"$z_k$ and its estimates $\hat z_k$")
    ax1.set_title("one realisation")
    ax2.set_xlabel(r"time step $k$")
    ax2.set_ylabel(r"$\mathrm{MSE}_k = \mathrm{E}\,|z_k - \hat z_k|^2$")
    ax2.set_title(f"mean-square error over {result['runs']} Monte Carlo runs")
    legend(ax1)
    legend(ax2)
    if title:
        fig.suptitle(title)
    return save(fig, path)


def design_filter(solver: str | None = None, backoff: float | None = 1e-2, xi1=0.7, xi2=0.8):
    """The H∞ filter of Theorem 2 on the paper's example (scaled and backed off by the library)."""
    sol = solve("li_delay_dropout.thm2", example="paper", solver=solver, backoff=backoff,
                overrides={"xi1": xi1, "xi2": xi2}, certify=False)
    return sol, LinearFilter.from_data(sol.recovered)


def main(argv=None) -> int:
    """``python -m lmidsl.theorems.li_delay_dropout.simulation --out docs/figures``: Figs. 2 and 3 of seed 001."""
    import argparse
    import warnings


    warnings.filterwarnings("ignore", message="Solution may be inaccurate")
    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("--out", default="docs/figures")
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    plant = Plant.from_data(get_theorem("li_delay_dropout.thm2").examples["paper"].data)
    sol, hinf = design_filter()
    numbers = {"filter_gamma": sol.gamma, "filter_backoff": (sol.backoff or {}).get("delta")}
    for kind, fig, title in (("white", "001_fig2_mse_white", r"white noise $w_k$, $Q_w = 1$"),
                             ("inverse-square", "001_fig3_mse_inverse_square", r"$w_k = 1/k^2$")):
        res = monte_carlo(plant, {"H∞ filter": hinf}, 0.7, 0.8, runs=args.runs, steps=args.steps,
                          kind=kind, seed=args.seed)
        figure(res, out / fig, rf"$\bar\xi_1 = 0.7$, $\bar\xi_2 = 0.8$, {title}")
        numbers[kind] = {k: res[k] for k in ("mse_mean", "event_frequency", "event_probability",
                                             "z_energy", "runs", "steps", "seed")}
    (out / "001_mse.json").write_text(json.dumps(numbers, indent=2))
    print(json.dumps(numbers, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
