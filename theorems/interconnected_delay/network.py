"""Interconnected continuous-time systems with delayed couplings and norm-bounded uncertainty.

Subsystem i (i = 1..N) and its decentralised filter::

    ẋ_i = (A_i + H_i1 F_i(t) E_i) x_i + Σ_j (A_ij + M_i ΔF_ij(t) N_ij) x_j(t − τ_ij) + B_i w_i
    y_i = (C_i + H_i2 F_i(t) E_i) x_i + D_i w_i,          z_i = L_i x_i
    x̂̇_i = A_fi x̂_i + B_fi y_i,                            ẑ_i = L_fi x̂_i,   z̃_i = z_i − ẑ_i

with FᵢᵀFᵢ ≤ I, ΔF_ijᵀΔF_ij ≤ I (``common_coupling=True``: one ΔF_i(t) for every j, the
structure of the S-procedure "Variant A").  The filtering-error state is
X = [x_1; x̂_1; …; x_N; x̂_N]; for frozen uncertainty it is a linear delay system

    Ẋ = A₀ X + Σ_ij A_ij^big X(t − τ_ij) + B w,   z̃ = C X,
    T(s) = C (sI − A₀ − Σ A_ij^big e^{−sτ_ij})⁻¹ B.

A delay-independent certificate ∑‖z̃_i‖² < ∑γ_i²‖w_i‖² (docs/reproductions/004.md) is tested two ways:

* :func:`frequency_sweep`: sup_ω σ̄(T(jω) Γ⁻¹) ≤ 1, Γ = diag(γ_i I), at every uncertainty
  vertex (F = ±I, and random orthogonal F when F is a matrix) and for several delay sets;
* :func:`simulate`: fixed-step RK4 with a history buffer (method of steps; delayed states by
  linear interpolation, zero initial function), time-varying admissible F(t), l2 disturbances;
  the energy ratio ∑‖z̃_i‖² / ∑γ_i²‖w_i‖² must stay below 1 on every horizon.

The names of the data follow :mod:`lmidsl.theorem.family` (``A_1``, ``A_1_2``, ...); ``names`` maps
the roles to the base names a theorem uses.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from lmidsl import CheckResult
from lmidsl import default_grid, is_stable, peak_gain

RK4_SAFE = 1.0  # |λ| dt kept well inside RK4's stability region (|λ| dt < 2.78 on the real axis)

DEFAULT_NAMES = {"A": "A", "Ad": "A", "B": "B", "C": "C", "D": "D", "L": "L", "H1": "HA",
                 "H2": "HC", "E": "E", "M": "M", "Nd": "N", "tau": "tau",
                 "Af": "Af", "Bf": "Bf", "Lf": "Lf", "gamma": "gamma"}


@dataclass
class DelayNetwork:
    """The numeric data of N subsystems (lists indexed 0..N-1, dicts by (i, j))."""

    A: list
    Ad: dict
    B: list
    C: list
    D: list
    L: list
    H1: list
    H2: list
    E: list
    M: list
    Nd: dict
    tau: dict
    common_coupling: bool = True

    @property
    def size(self) -> int:
        return len(self.A)

    @property
    def n(self) -> list[int]:
        return [a.shape[0] for a in self.A]

    @classmethod
    def from_values(cls, values: dict, size: int, names: dict | None = None,
                    common_coupling: bool = True) -> "DelayNetwork":
        """Read ``A_1``, ``A_1_2``, ``tau_1_2``, ... from a dict of data and parameters."""
        nm = dict(DEFAULT_NAMES, **(names or {}))
        idx = range(1, size + 1)

        def one(role, i):
            return np.atleast_2d(np.asarray(values[f"{nm[role]}_{i}"], dtype=float))

        def pair(role, i, j):
            return np.atleast_2d(np.asarray(values[f"{nm[role]}_{i}_{j}"], dtype=float))

        return cls(
            A=[one("A", i) for i in idx], Ad={(i - 1, j - 1): pair("Ad", i, j) for i in idx for j in idx},
            B=[one("B", i) for i in idx], C=[one("C", i) for i in idx], D=[one("D", i) for i in idx],
            L=[one("L", i) for i in idx], H1=[one("H1", i) for i in idx], H2=[one("H2", i) for i in idx],
            E=[one("E", i) for i in idx], M=[one("M", i) for i in idx],
            Nd={(i - 1, j - 1): pair("Nd", i, j) for i in idx for j in idx},
            tau={(i - 1, j - 1): float(values[f"{nm['tau']}_{i}_{j}"]) for i in idx for j in idx},
            common_coupling=common_coupling)


@dataclass
class Filters:
    """Decentralised filters (A_fi, B_fi, L_fi), lists indexed 0..N-1."""

    Af: list
    Bf: list
    Lf: list

    @classmethod
    def from_values(cls, values: dict, size: int, names: dict | None = None) -> "Filters":
        nm = dict(DEFAULT_NAMES, **(names or {}))
        get = lambda role, i: np.atleast_2d(np.asarray(values[f"{nm[role]}_{i}"], dtype=float))  # noqa: E731
        idx = range(1, size + 1)
        return cls([get("Af", i) for i in idx], [get("Bf", i) for i in idx], [get("Lf", i) for i in idx])


@dataclass
class ErrorSystem:
    """Filtering-error system for one frozen uncertainty: A₀, the delayed terms, B, C."""

    A0: np.ndarray
    delayed: list  # [(τ, A_big)]
    B: np.ndarray
    C: np.ndarray
    inputs: list = field(default_factory=list)  # slices of w per subsystem
    outputs: list = field(default_factory=list)  # slices of z̃ per subsystem

    def response(self, s) -> np.ndarray:
        """T(s) for one s (p × m) or a 1-d array of s (stacked, len(s) × p × m)."""
        s_arr = np.atleast_1d(np.asarray(s, dtype=complex))
        n = self.A0.shape[0]
        M = s_arr[:, None, None] * np.eye(n) - self.A0
        for tau, Ab in self.delayed:
            M = M - np.exp(-s_arr * tau)[:, None, None] * Ab
        G = self.C @ np.linalg.solve(M, np.broadcast_to(self.B, (len(s_arr),) + self.B.shape))
        return G if np.ndim(s) else G[0]

    def delay_free(self) -> np.ndarray:
        """A₀ + Σ A_big (all delays set to zero)."""
        return self.A0 + sum((Ab for _, Ab in self.delayed), np.zeros_like(self.A0))


def _offsets(sizes):
    out, k = [], 0
    for s in sizes:
        out.append(slice(k, k + s))
        k += s
    return out


@dataclass
class UncertainErrorSystem:
    """The error system as an affine function of the uncertainty, for simulation and sweeps.

    A₀(F) = A₀ + Σ_i U_i F_i V_i,   A_ij^big(ΔF) = A_ij^big + W_i ΔF_ij Z_ij,
    where U_i injects [H_i1; B_fi H_i2] into (x_i, x̂_i), V_i reads E_i x_i, W_i injects M_i into
    x_i and Z_ij reads N_ij x_j.
    """

    A0: np.ndarray
    Ad: dict
    U: list
    V: list
    W: list
    Z: dict
    B: np.ndarray
    C: np.ndarray
    tau: dict
    inputs: list
    outputs: list

    def frozen(self, F: list, Fd: dict, taus: dict | None = None) -> ErrorSystem:
        taus = self.tau if taus is None else taus
        A0 = self.A0 + sum(self.U[i] @ F[i] @ self.V[i] for i in range(len(F)))
        delayed = [(taus[key], Ab + self.W[key[0]] @ Fd[key] @ self.Z[key]) for key, Ab in self.Ad.items()]
        return ErrorSystem(A0, delayed, self.B, self.C, self.inputs, self.outputs)


def uncertain_error_system(net: DelayNetwork, flt: Filters) -> UncertainErrorSystem:
    """State X = [x_1; x̂_1; …; x_N; x̂_N], input w = [w_1; …], output z̃ = [z̃_1; …]."""
    N, n = net.size, net.n
    starts = np.cumsum([0] + [2 * v for v in n])
    x_sl = [slice(starts[i], starts[i] + n[i]) for i in range(N)]
    xf_sl = [slice(starts[i] + n[i], starts[i + 1]) for i in range(N)]
    total = int(starts[-1])
    w_sl = _offsets([b.shape[1] for b in net.B])
    z_sl = _offsets([l.shape[0] for l in net.L])
    A0 = np.zeros((total, total))
    B = np.zeros((total, w_sl[-1].stop))
    C = np.zeros((z_sl[-1].stop, total))
    U, V, W, Z, Ad = [], [], [], {}, {}
    for i in range(N):
        A0[x_sl[i], x_sl[i]] = net.A[i]
        A0[xf_sl[i], x_sl[i]] = flt.Bf[i] @ net.C[i]
        A0[xf_sl[i], xf_sl[i]] = flt.Af[i]
        B[x_sl[i], w_sl[i]] = net.B[i]
        B[xf_sl[i], w_sl[i]] = flt.Bf[i] @ net.D[i]
        C[z_sl[i], x_sl[i]] = net.L[i]
        C[z_sl[i], xf_sl[i]] = -flt.Lf[i]
        k, r = net.E[i].shape[0], net.M[i].shape[1]
        Ui = np.zeros((total, k))
        Ui[x_sl[i]] = net.H1[i]
        Ui[xf_sl[i]] = flt.Bf[i] @ net.H2[i]
        Vi = np.zeros((k, total))
        Vi[:, x_sl[i]] = net.E[i]
        Wi = np.zeros((total, r))
        Wi[x_sl[i]] = net.M[i]
        U.append(Ui)
        V.append(Vi)
        W.append(Wi)
        for j in range(N):
            Ab = np.zeros((total, total))
            Ab[x_sl[i], x_sl[j]] = net.Ad[i, j]
            Ad[i, j] = Ab
            Zij = np.zeros((r, total))
            Zij[:, x_sl[j]] = net.Nd[i, j]
            Z[i, j] = Zij
    return UncertainErrorSystem(A0, Ad, U, V, W, Z, B, C, dict(net.tau), w_sl, z_sl)


def error_system(net: DelayNetwork, flt: Filters, F: list, Fd: dict, taus: dict | None = None) -> ErrorSystem:
    """Frozen-uncertainty error system: ``F[i]`` (k_i × k_i), ``Fd[(i, j)]`` (r_i × r_i)."""
    return uncertain_error_system(net, flt).frozen(F, Fd, taus)


def uncertainty_vertices(net: DelayNetwork, samples: int = 0, seed: int = 0, max_vertices: int = 256):
    """Frozen admissible uncertainties: the ±I combinations, plus random orthogonal ones.

    For scalar blocks (k_i = r_i = 1) the ±1 combinations are all the extreme points; when
    there are more than ``max_vertices`` of them, a random subset of that size is used.
    With ``common_coupling`` one ΔF_i serves every j.
    """
    N = net.size
    k = [e.shape[0] for e in net.E]
    r = [mm.shape[1] for mm in net.M]
    nd = N if net.common_coupling else N * N
    rng = np.random.default_rng(seed)
    if 2 ** (N + nd) <= max_vertices:
        combos = itertools.product((1.0, -1.0), repeat=N + nd)
    else:
        combos = (rng.choice((1.0, -1.0), size=N + nd) for _ in range(max_vertices))
    for signs in combos:
        F = [signs[i] * np.eye(k[i]) for i in range(N)]
        yield F, _coupling(net, signs[N:], r)
    for _ in range(samples):
        F = [_orthogonal(rng, k[i]) for i in range(N)]
        Fd_list = [_orthogonal(rng, r[i // N if not net.common_coupling else i])
                   for i in range(nd)]
        yield F, _coupling(net, Fd_list, r)


def _orthogonal(rng, k):
    Q, R = np.linalg.qr(rng.standard_normal((k, k)))
    return Q * np.sign(np.diag(R))


def _coupling(net, values, r):
    N = net.size
    out = {}
    for i in range(N):
        for j in range(N):
            v = values[i] if net.common_coupling else values[i * N + j]
            out[i, j] = v * np.eye(r[i]) if np.ndim(v) == 0 else v
    return out


def spectral_radius(net: DelayNetwork, flt: Filters) -> float:
    """Largest |λ| of the nominal error system's A₀ and A₀ + ΣA_big (sets grid and time step)."""
    es = error_system(net, flt, [np.zeros((e.shape[0],) * 2) for e in net.E],
                      {key: np.zeros((net.M[key[0]].shape[1],) * 2) for key in net.Ad})
    return float(max(np.abs(np.linalg.eigvals(es.A0)).max(), np.abs(np.linalg.eigvals(es.delay_free())).max()))


def frequency_sweep(net: DelayNetwork, flt: Filters, gammas: list, *, delay_sets=None,
                    omegas=None, samples: int = 0, max_vertices: int = 256, refine: int = 3) -> dict:
    """Weighted peak sup_ω σ̄(T(jω) Γ⁻¹) over the uncertainty vertices and delay sets.

    Every frozen case is evaluated on the grid; the ``refine`` cases with the highest grid peaks
    are refined locally in ω.  Returns the worst weighted peak, where it occurs (frequency,
    delay set, F, ΔF), and whether every frozen error system is stable without delays
    (A₀ + ΣA_big Hurwitz) and with infinitely long ones (A₀ Hurwitz).
    """
    if omegas is None:
        fastest = max(spectral_radius(net, flt), 1.0)
        omegas = default_grid("continuous", points=500, top=max(1e4, 10 * fastest))
    delay_sets = delay_sets or {"given": net.tau, "zero": {key: 0.0 for key in net.tau}}
    m = [b.shape[1] for b in net.B]
    weight = np.diag(np.concatenate([np.full(m[i], 1.0 / gammas[i]) for i in range(net.size)]))
    ues = uncertain_error_system(net, flt)
    cases, stable = [], True
    for F, Fd in uncertainty_vertices(net, samples, max_vertices=max_vertices):
        for label, taus in delay_sets.items():
            es = ues.frozen(F, Fd, taus)
            stable &= is_stable(es.delay_free(), "continuous") and is_stable(es.A0, "continuous")
            gains = np.linalg.svd(es.response(1j * omegas) @ weight, compute_uv=False)[:, 0]
            cases.append((float(gains.max()), label, F, Fd, es))
    cases.sort(key=lambda c: -c[0])
    worst = {"weighted_peak": -np.inf}
    for _, label, F, Fd, es in cases[:refine]:
        peak, where = peak_gain(lambda w: es.response(1j * w) @ weight, omegas)
        if peak > worst["weighted_peak"]:
            worst = {"weighted_peak": peak, "omega": where, "delays": label,
                     "F": [f.tolist() for f in F],
                     "Fd": {f"{i + 1},{j + 1}": v.tolist() for (i, j), v in Fd.items()}}
    worst.update({"stable": bool(stable), "cases": len(cases)})
    return worst


# -- time simulation (method of steps) ---------------------------------------------------

def simulate(net: DelayNetwork, flt: Filters, w, F_of_t, Fd_of_t, T: float, dt: float = 5e-3):
    """RK4 simulation with zero initial state and zero initial function on [−τ, 0].

    ``w(t)`` returns the stacked disturbance, ``F_of_t(t)`` a list of F_i, ``Fd_of_t(t)`` a dict
    of ΔF_ij (any admissible, time-varying values).  Method of steps: every positive delay is
    ≥ dt, so x(s − τ) at every RK stage lies in the stored trajectory (linear interpolation
    between grid points); zero delays use the current stage state.  Returns (t, X, W, Z̃).

    The right-hand side is one matrix-vector product: with c(s) the entries of all F_i(s) and
    ΔF_ij(s), [A₀(s) A_11(s) … A_NN(s)] = G₀ + Σ_t c_t(s) G_t, applied to [x; x(s − τ_11); …].
    """
    taus = sorted({v for v in net.tau.values() if v > 0})
    if taus and taus[0] < dt:
        raise ValueError(f"delay {taus[0]} is shorter than the step {dt}")
    ues = uncertain_error_system(net, flt)
    pairs = list(ues.Ad)
    N, nx = net.size, ues.A0.shape[0]
    width = nx * (1 + len(pairs))
    G0 = np.hstack([ues.A0] + [ues.Ad[key] for key in pairs])
    basis = []
    for i in range(N):                      # entries of F_i: U_i[:, a] V_i[b, :] in the A₀ block
        for a in range(ues.U[i].shape[1]):
            for b in range(ues.V[i].shape[0]):
                g = np.zeros((nx, width))
                g[:, :nx] = np.outer(ues.U[i][:, a], ues.V[i][b])
                basis.append(g)
    for p, key in enumerate(pairs):         # entries of ΔF_ij in the block of x(s − τ_ij)
        Wi, Zij = ues.W[key[0]], ues.Z[key]
        for a in range(Wi.shape[1]):
            for b in range(Zij.shape[0]):
                g = np.zeros((nx, width))
                g[:, nx * (p + 1): nx * (p + 2)] = np.outer(Wi[:, a], Zij[b])
                basis.append(g)
    basis = np.array(basis).reshape(len(basis), -1)

    def coefficients(s):
        F, Fd = F_of_t(s), Fd_of_t(s)
        return np.concatenate([np.ravel(F[i]) for i in range(N)] + [np.ravel(Fd[key]) for key in pairs])

    steps = int(round(T / dt))
    t = np.arange(steps + 1) * dt
    half = np.arange(2 * steps + 1) * (dt / 2)          # every RK stage time
    G = (G0.ravel() + np.array([coefficients(s) for s in half]) @ basis).reshape(len(half), nx, width)
    Bw = np.array([w(s) for s in half]) @ ues.B.T
    # zero delays act on the current state; the others read the stored trajectory
    tau = np.array([ues.tau[key] for key in pairs])
    Gx = G[:, :, :nx].copy()
    for p in np.flatnonzero(tau == 0):
        Gx += G[:, :, nx * (p + 1): nx * (p + 2)]
    live = np.flatnonzero(tau > 0)
    Gd = np.concatenate([G[:, :, nx * (p + 1): nx * (p + 2)] for p in live], axis=2) if len(live) else None
    # x(t_k + θ dt − τ) = (1 − f) X[k + lo] + f X[k + lo + 1], lo = floor(θ − τ/dt), per θ ∈ {0, ½, 1}
    pad = int(np.ceil(tau.max() / dt)) + 2 if len(live) else 0
    X = np.zeros((pad + steps + 1, nx))                 # zero initial function on [−τ, 0]
    interp = []
    for theta in (0.0, 0.5, 1.0):
        u = theta - tau[live] / dt
        lo = np.floor(u + 1e-9).astype(int)
        frac = np.where(np.abs(u - lo) < 1e-9, 0.0, u - lo)
        interp.append((lo + pad, frac[:, None]))

    def delayed(k, which):
        lo, frac = interp[which]
        return ((1 - frac) * X[k + lo] + frac * X[k + lo + 1]).ravel()

    for k in range(steps):
        h, x = 2 * k, X[pad + k]
        if Gd is not None:
            d_a = Gd[h] @ delayed(k, 0) + Bw[h]
            d_b = Gd[h + 1] @ delayed(k, 1) + Bw[h + 1]
            d_c = Gd[h + 2] @ delayed(k, 2) + Bw[h + 2]
        else:
            d_a, d_b, d_c = Bw[h], Bw[h + 1], Bw[h + 2]
        k1 = Gx[h] @ x + d_a
        k2 = Gx[h + 1] @ (x + dt / 2 * k1) + d_b
        k3 = Gx[h + 1] @ (x + dt / 2 * k2) + d_b
        k4 = Gx[h + 2] @ (x + dt * k3) + d_c
        X[pad + k + 1] = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    X = X[pad:]
    W = np.array([w(s) for s in t])
    Z = X @ ues.C.T
    return t, X, W, Z


def energy(t: np.ndarray, signal: np.ndarray) -> float:
    """∫ ‖signal(t)‖² dt by the trapezoid rule."""
    trapezoid = getattr(np, "trapezoid", None) or np.trapz
    return float(trapezoid(np.sum(np.atleast_2d(signal.T).T ** 2, axis=1), t))


def energy_ratio(t, W, Z, gammas, net: DelayNetwork) -> float:
    """∑‖z̃_i‖² / ∑γ_i²‖w_i‖²."""
    m = [b.shape[1] for b in net.B]
    sl = _offsets(m)
    denom = sum(gammas[i] ** 2 * energy(t, W[:, sl[i]]) for i in range(net.size))
    return energy(t, Z) / denom


def standard_scenarios(net: DelayNetwork, peak: dict | None = None, T: float = 20.0):
    """Disturbances × admissible time-varying uncertainties used by :class:`SimulationCheck`."""
    N = net.size
    m = [b.shape[1] for b in net.B]
    k = [e.shape[0] for e in net.E]
    r = [mm.shape[1] for mm in net.M]
    mtot = sum(m)
    offs = _offsets(m)

    def w_decay(s):
        out = np.zeros(mtot)
        for i in range(N):
            out[offs[i]] = np.exp(-0.3 * s) * np.sin((1.5 + i) * s + i)
        return out

    def w_pulse(s):
        return np.full(mtot, 1.0) if s < 2.0 else np.zeros(mtot)

    Ik = [np.eye(v) for v in k]
    Ir = [np.eye(v) for v in r]
    shift = [[0 if net.common_coupling else j for j in range(N)] for _ in range(N)]

    def smooth_F(s):
        return [np.cos(1.3 * s + i) * Ik[i] for i in range(N)]

    def smooth_Fd(s):
        return {(i, j): np.sin(0.9 * s + i + 2 * shift[i][j]) * Ir[i] for i in range(N) for j in range(N)}

    def switch_F(s):
        return [(1.0 if np.sin(2.1 * s + i) >= 0 else -1.0) * Ik[i] for i in range(N)]

    def switch_Fd(s):
        return {(i, j): (1.0 if np.cos(1.7 * s + i + shift[i][j]) >= 0 else -1.0) * Ir[i]
                for i in range(N) for j in range(N)}

    scenarios = [("decaying sines, smooth F(t)", w_decay, smooth_F, smooth_Fd),
                 ("unit pulse, switching F(t)", w_pulse, switch_F, switch_Fd)]
    if peak is not None and np.isfinite(peak.get("omega", np.nan)):
        wstar = peak["omega"]
        Fw = [np.array(f) for f in peak["F"]]
        Fdw = {tuple(int(a) - 1 for a in key.split(",")): np.array(v) for key, v in peak["Fd"].items()}
        direction = peak["direction"]
        on = T * 0.8

        def w_peak(s):
            return np.real(direction * np.exp(1j * wstar * s)) if s < on else np.zeros(mtot)

        label = (f"sinusoid at the peak w = {wstar:.3g}" if wstar > 1e-3 else
                 "step in the worst direction (peak at w = 0)")
        scenarios.append((f"{label}, worst frozen F for {on:g} s", w_peak, lambda s: Fw, lambda s: Fdw))
    return scenarios


def peak_direction(net, flt, gammas, peak) -> np.ndarray:
    """The input direction Γ⁻¹v (v the top right singular vector of T(jω*)Γ⁻¹) at the peak."""
    Fw = [np.array(f) for f in peak["F"]]
    Fdw = {tuple(int(a) - 1 for a in key.split(",")): np.array(v) for key, v in peak["Fd"].items()}
    taus = net.tau if peak["delays"] == "given" else {key: 0.0 for key in net.tau}
    es = error_system(net, flt, Fw, Fdw, taus)
    m = [b.shape[1] for b in net.B]
    gw = np.concatenate([np.full(m[i], 1.0 / gammas[i]) for i in range(net.size)])
    _, _, Vh = np.linalg.svd(es.response(1j * peak["omega"]) @ np.diag(gw))
    v = Vh[0].conj()
    v = v * np.exp(-1j * np.angle(v[np.argmax(np.abs(v))]))   # real at ω = 0, whatever the phase
    return gw * v


# -- checks for Theorem.verify_with ----------------------------------------------------------

def _network_and_filters(solution, size, names, common_coupling):
    scaling = getattr(solution, "scaling", None)
    inst = scaling.original if scaling is not None else solution.instance   # unscaled data
    values = {**inst.data, **inst.params, **solution.recovered}
    net = DelayNetwork.from_values(values, size, names, common_coupling)
    flt = Filters.from_values(values, size, names)
    nm = dict(DEFAULT_NAMES, **(names or {}))
    gammas = [solution.reported[f"{nm['gamma']}_{i}"] for i in range(1, size + 1)]
    return net, flt, gammas


@dataclass
class FrequencySweepCheck:
    """sup_ω σ̄(T(jω)Γ⁻¹) ≤ 1 at every uncertainty vertex, for the given and for zero delays."""

    size: int
    names: dict | None = None
    common_coupling: bool = True
    samples: int = 4
    name: str = "frequency sweep"

    def __call__(self, solution) -> CheckResult:
        net, flt, gammas = _network_and_filters(solution, self.size, self.names, self.common_coupling)
        res = frequency_sweep(net, flt, gammas, samples=self.samples)
        passed = res["stable"] and res["weighted_peak"] <= 1.0 + 1e-6
        summary = (f"max over {res['cases']} frozen uncertainties x delay sets of sup_w "
                   f"sigma(T(jw) diag(1/gamma_i)) = {res['weighted_peak']:.4f} (<= 1 required) at "
                   f"w = {res['omega']:.3g} ({res['delays']} delays); error systems "
                   f"{'stable' if res['stable'] else 'NOT stable'}")
        return CheckResult(self.name, bool(passed), summary, res)


@dataclass
class SimulationCheck:
    """Energy ratio ∑‖z̃_i‖² / ∑γ_i²‖w_i‖² < 1 in time simulations of the delayed network."""

    size: int
    names: dict | None = None
    common_coupling: bool = True
    T: float = 20.0
    dt: float = 5e-3
    name: str = "simulation"

    def __call__(self, solution) -> CheckResult:
        net, flt, gammas = _network_and_filters(solution, self.size, self.names, self.common_coupling)
        fastest = spectral_radius(net, flt)
        if fastest * self.dt > RK4_SAFE:
            return CheckResult(self.name, False,
                               f"not simulated: the error system is stiff (|lambda| up to {fastest:.3g}); "
                               f"RK4 would need dt < {RK4_SAFE / fastest:.3g} (recovered filter ill-conditioned?)",
                               {"spectral_radius": fastest})
        sweep = frequency_sweep(net, flt, gammas, delay_sets={"given": net.tau},
                                omegas=default_grid("continuous", points=200), refine=1)
        sweep["direction"] = peak_direction(net, flt, gammas, sweep)
        ratios = {}
        for label, w, Ft, Fdt in standard_scenarios(net, sweep, self.T):
            t, X, W, Z = simulate(net, flt, w, Ft, Fdt, self.T, self.dt)
            ratios[label] = energy_ratio(t, W, Z, gammas, net)
        worst = max(ratios, key=ratios.get)
        passed = all(r < 1.0 for r in ratios.values())
        summary = (f"energy ratio sum||z_i||^2 / sum gamma_i^2||w_i||^2 over {len(ratios)} scenarios "
                   f"(T = {self.T:g} s, dt = {self.dt:g}): max {ratios[worst]:.4f} ({worst}); "
                   + ", ".join(f"{v:.4f}" for v in ratios.values()))
        return CheckResult(self.name, bool(passed), summary, {"ratios": ratios})
