"""Simulation of a discrete-time impulsive plant with an impulsive filter (Pan/Sun (1)-(12)).

Plant: x(k+1) = A x + B ω (k ∉ E), x(k+1) = M x (k ∈ E); y = C x + D ω; z = L1 x + L2 ω.
Filter: x̂(k+1) = Â x̂ + B̂ y (k ∉ E), x̂(k+1) = M̂ x̂ (k ∈ E); ẑ = Ĉ x̂ + D̂ y.
Error system, ξ = [x; x̂]: ξ(k+1) = Ā ξ + B̄ ω (k ∉ E), ξ(k+1) = M̄ ξ (k ∈ E),
e = z − ẑ = C̄ ξ + D̄ ω at every k (impulse instants included: docs/reproductions/003.md).

* :func:`impulse_sequence` -- the impulse instants E as a boolean array: none, periodic, random
  (Bernoulli), all (every instant from some k on), or explicit instants;
* :func:`simulate` -- ξ, e for a disturbance ω and impulse sequence;
* :func:`lifted_gain` -- the exact ℓ2 gain over a finite horizon N for one impulse sequence: the
  largest singular value of the lifted map ω(0..N−1) ↦ e(0..N−1), with the disturbance that
  attains it.  It is a lower bound of the robust H∞ level (sup over all sequences and horizons),
  so a filter whose lifted gain exceeds γ is refuted at γ whatever an LMI says.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lmidsl import InputError, SimulationTable

PLANT_NAMES = ("A", "B", "M", "C", "D", "L1", "L2")
FILTER_NAMES = ("Ahat", "Bhat", "Mhat", "Chat", "Dhat")
DEFAULT_SCENARIOS = ("none", "periodic:5", "random:0.2", "all")


@dataclass
class ImpulsiveErrorSystem:
    """The filtering-error system (12): Ā, B̄, M̄, C̄, D̄."""

    Abar: np.ndarray
    Bbar: np.ndarray
    Mbar: np.ndarray
    Cbar: np.ndarray
    Dbar: np.ndarray

    @property
    def nstate(self) -> int:
        return self.Abar.shape[0]

    @property
    def ninput(self) -> int:
        return self.Bbar.shape[1]

    @property
    def noutput(self) -> int:
        return self.Cbar.shape[0]


def error_system(matrices: dict) -> ImpulsiveErrorSystem:
    """(12) from plant matrices A, B, M, C, D, L1, L2 and filter Ahat, Bhat, Mhat, Chat, Dhat."""
    missing = [k for k in PLANT_NAMES + FILTER_NAMES if k not in matrices]
    if missing:
        raise InputError(f"impulsive simulation: missing {', '.join(missing)}")
    m = {k: np.atleast_2d(np.asarray(matrices[k], dtype=float)) for k in PLANT_NAMES + FILTER_NAMES}
    n, nf = m["A"].shape[0], m["Ahat"].shape[0]
    Abar = np.block([[m["A"], np.zeros((n, nf))], [m["Bhat"] @ m["C"], m["Ahat"]]])
    Bbar = np.vstack([m["B"], m["Bhat"] @ m["D"]])
    Mbar = np.block([[m["M"], np.zeros((n, nf))], [np.zeros((nf, n)), m["Mhat"]]])
    Cbar = np.hstack([m["L1"] - m["Dhat"] @ m["C"], -m["Chat"]])
    Dbar = m["L2"] - m["Dhat"] @ m["D"]
    return ImpulsiveErrorSystem(Abar, Bbar, Mbar, Cbar, Dbar)


def impulse_sequence(kind: str, horizon: int, *, period: int = 5, start: int = 1,
                     probability: float = 0.2, seed: int | None = 0, instants=None) -> np.ndarray:
    """Boolean array of length ``horizon``: True at the impulse instants τ_j.

    ``kind``: "none"; "periodic" (k = start, start + period, ...); "random" (each k ≥ start an
    impulse with ``probability``, reproducible with ``seed``); "all" (every k ≥ start: the
    admissible sequence τ_j = start + j); "explicit" (the given ``instants``).
    """
    E = np.zeros(horizon, dtype=bool)
    if kind == "none":
        return E
    if kind == "periodic":
        if period < 1:
            raise InputError("impulse sequence: period must be at least 1")
        E[start::period] = True
    elif kind == "random":
        if not 0.0 <= probability <= 1.0:
            raise InputError("impulse sequence: probability must lie in [0, 1]")
        rng = np.random.default_rng(seed)
        E[start:] = rng.random(max(horizon - start, 0)) < probability
    elif kind == "all":
        E[start:] = True
    elif kind == "explicit":
        idx = np.asarray(list(instants or []), dtype=int)
        E[idx[(idx >= 0) & (idx < horizon)]] = True
    else:
        raise InputError(f"unknown impulse sequence {kind!r}; use none, periodic, random, all, explicit")
    return E


@dataclass
class Trajectory:
    xi: np.ndarray        # (N+1) × 2n states
    e: np.ndarray         # N × p errors z − ẑ
    w: np.ndarray         # N × m disturbances
    impulses: np.ndarray  # N booleans

    @property
    def energy_ratio(self) -> float:
        """‖e‖₂ / ‖ω‖₂ over the horizon."""
        den = float(np.sum(self.w ** 2))
        return float(np.sqrt(np.sum(self.e ** 2) / den)) if den > 0 else float("nan")


def simulate(system: ImpulsiveErrorSystem, w, impulses, xi0=None) -> Trajectory:
    """Run the error system from ξ(0) = ``xi0`` (default 0) under ``w`` (N × m) and ``impulses``."""
    w = np.asarray(w, dtype=float)
    if w.ndim == 1:
        w = w[:, None]
    N = w.shape[0]
    impulses = np.asarray(impulses, dtype=bool)
    if impulses.shape != (N,):
        raise InputError(f"impulsive simulation: {impulses.shape[0]} impulse flags for {N} samples")
    if w.shape[1] != system.ninput:
        raise InputError(f"impulsive simulation: disturbance has {w.shape[1]} channels, the plant {system.ninput}")
    xi = np.zeros((N + 1, system.nstate))
    if xi0 is not None:
        xi[0] = np.asarray(xi0, dtype=float)
    e = np.zeros((N, system.noutput))
    for k in range(N):
        e[k] = system.Cbar @ xi[k] + system.Dbar @ w[k]
        xi[k + 1] = system.Mbar @ xi[k] if impulses[k] else system.Abar @ xi[k] + system.Bbar @ w[k]
    return Trajectory(xi, e, w, impulses)


def lifted_operator(system: ImpulsiveErrorSystem, impulses) -> np.ndarray:
    """The (N p) × (N m) matrix H with e(0..N−1) = H ω(0..N−1) from ξ(0) = 0."""
    impulses = np.asarray(impulses, dtype=bool)
    N, m, p, s = impulses.shape[0], system.ninput, system.noutput, system.nstate
    X = np.zeros((s, N * m))          # state response to every unit input at once
    H = np.zeros((N * p, N * m))
    for k in range(N):
        Wk = np.zeros((m, N * m))
        Wk[:, k * m:(k + 1) * m] = np.eye(m)
        H[k * p:(k + 1) * p] = system.Cbar @ X + system.Dbar @ Wk
        X = system.Mbar @ X if impulses[k] else system.Abar @ X + system.Bbar @ Wk
    return H


def lifted_gain(system: ImpulsiveErrorSystem, impulses) -> tuple[float, np.ndarray]:
    """(ℓ2 gain over the horizon for this impulse sequence, the worst disturbance, N × m)."""
    H = lifted_operator(system, impulses)
    if min(H.shape) > 200:
        from scipy.sparse.linalg import svds
        _, S, Vt = svds(H, k=1, random_state=0)
    else:
        _, S, Vt = np.linalg.svd(H)
    v = Vt[0] if Vt[0].sum() >= 0 else -Vt[0]
    return float(S[0]), v.reshape(-1, system.ninput)


def disturbance(kind: str, horizon: int, ninput: int = 1, *, seed: int | None = 0,
                at: int = 0, frequency: float = 0.05) -> np.ndarray:
    """A test disturbance (N × m): "pulse" (unit at k = ``at``), "noise" (white, seeded),
    "sine" (cos(2π f k)), "step" (ones)."""
    w = np.zeros((horizon, ninput))
    if kind == "pulse":
        w[at] = 1.0
    elif kind == "noise":
        w = np.random.default_rng(seed).standard_normal((horizon, ninput))
    elif kind == "sine":
        w[:] = np.cos(2 * np.pi * frequency * np.arange(horizon))[:, None]
    elif kind == "step":
        w[:] = 1.0
    else:
        raise InputError(f"unknown disturbance {kind!r}; use pulse, noise, sine, step or worst")
    return w


disturbance_signal = disturbance   # the name simulate_design's keyword argument shadows


def parse_impulses(text: str, horizon: int, seed: int | None = 0) -> np.ndarray:
    """'none', 'all', 'all:K', 'periodic:P', 'random:p', 'explicit:k1,k2,...' -> impulse flags."""
    kind, _, arg = text.partition(":")
    try:
        if kind in ("none",):
            return impulse_sequence("none", horizon)
        if kind == "all":
            return impulse_sequence("all", horizon, start=int(arg) if arg else 1)
        if kind == "periodic":
            return impulse_sequence("periodic", horizon, period=int(arg or 5))
        if kind == "random":
            return impulse_sequence("random", horizon, probability=float(arg or 0.2), seed=seed)
        if kind == "explicit":
            return impulse_sequence("explicit", horizon, instants=[int(v) for v in arg.split(",") if v])
    except ValueError:
        raise InputError(f"--impulses {text!r}: bad number") from None
    raise InputError(f"--impulses {text!r}: use none, all[:K], periodic:P, random:p or explicit:k1,k2,...")


def simulate_design(instance, design, *, scenarios=None, horizon: int = 200,
                    disturbance: str = "noise", seed: int | None = 0) -> SimulationTable:
    """The theorems' declared simulation (``lmidsl simulate``): per polytope vertex and impulse
    sequence (``scenarios``: none, all[:K], periodic:P, random:p, explicit:k1,k2,...), the lifted
    ℓ2 gain over the horizon and the energy ratio ‖e‖/‖ω‖ for the test ``disturbance``.  The
    filter is the recovered ``design``, or (analysis theorems) the instance's data."""
    source = design if design is not None else instance.data
    missing = [k for k in FILTER_NAMES if k not in source]
    missing += [k for k in PLANT_NAMES if k not in instance.data]
    if missing:
        raise InputError(f"{instance.theorem.id}: no {', '.join(missing)} to simulate")
    filt = {k: source[k] for k in FILTER_NAMES}
    rows = []
    for v in range(instance.nvertices):
        plant = {k: (instance.data[k][v] if isinstance(instance.data[k], list) else instance.data[k])
                 for k in PLANT_NAMES}
        system = error_system({**plant, **filt})
        w = disturbance_signal(disturbance, horizon, system.ninput, seed=seed)
        for kind in scenarios or DEFAULT_SCENARIOS:
            E = parse_impulses(kind, horizon, seed)
            gain, _ = lifted_gain(system, E)
            rows.append({"vertex": None if instance.nvertices == 1 else v + 1, "impulses": kind,
                         "count": int(E.sum()), "lifted_gain": gain,
                         "energy_ratio": simulate(system, w, E).energy_ratio})
    columns = {"vertex": "vertex", "impulses": "impulses", "count": "#",
               "lifted_gain": "worst gain (lifted)", "energy_ratio": f"‖e‖/‖ω‖ ({disturbance})"}
    notes = ["worst gain: largest singular value of ω(0..N-1) -> e(0..N-1) for that impulse "
             "sequence (a lower bound of the robust H∞ level)."]
    return SimulationTable(columns, rows, notes)
