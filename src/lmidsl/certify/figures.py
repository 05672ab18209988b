"""Exact performance figures of a :class:`StochasticSystem`, computed without any LMI.

All figures are for a **deterministic** disturbance w (the papers' index; the expectation is
over the Bernoulli variables only) and zero initial state; they are gains in the units of γ
(``value``), with ``squared`` = value² in the units of γ² = g.

**Mean-square energy-to-peak** (seed 000, index (6) as proved, docs/reproductions/000.md):

    γ_ep² = sup_{K ≥ 0} sup_{‖w‖₂ ≤ 1} E|e(K)|².

For fixed K, E|e(K)|² = wᵀ M_K w is a quadratic form in the stacked w(0..K); ``M_K`` is
built from the moment recursion of :mod:`.system`:

    E|e(K)|² = |C m_K + D w_K|² + Σ_ij Σ_ij c_iᵀc_j + Σ_{j<K} Σ_il Σ_il u_i(j)ᵀ 𝓛*^{K−1−j}(Q) u_l(j),

with m_j, u_i(j) = A_i m_j + B_i w_j, c_i = C_i m_K + D_i w_K linear in w.  Hence
sup_{‖w‖≤1} E|e(K)|² = λ_max(M_K).  λ_max(M_K) is non-decreasing in K (delay w by one step)
and converges geometrically when ρ(𝓛) < 1, so γ_ep² = lim λ_max(M_K); the top eigenvector
is the worst-case disturbance.  Note: λ_max(C W Cᵀ) with W = 𝓛(W) + BBᵀ (the deterministic
formula with the generalised Gramian) is *not* this figure when the system is random: it is
λ_max(E[H Hᵀ]) for the random map H: w ↦ e(K), while the figure is λ_max(E[HᵀH]).

Also reported (``feedback``) for systems without output noise: the same index when w may be
any causal function of the state, from the Riccati recursion Π ← 𝓛*(Π) + Fᵀ(gI − R)⁻¹F
(F = BᵀΠA + ΣΣ B_iᵀΠA_j, R = BᵀΠB + ΣΣ B_iᵀΠB_j), Π₀ = Q: the least g with gI − R(Π_l) ≻ 0 for
every l.  The LMI analysis (a quadratic storage, valid for any such w) can certify nothing below it.

**Mean-square H∞** (energy to energy, seed 001):  γ_∞² = sup_{‖w‖₂ ≤ 1} Σ_k E|e(k)|².
Summing the moment recursion over k, the covariance injected at step k+1 contributes
tr(X̃ W_o) with W_o = 𝓛*(W_o) + Q, so

    Σ_k E|e(k)|² = Σ_k |z(k)|²,  z = [C m + D w;  (Σ⊗I)^½ [c_i];  (Σ⊗W_o)^½ [u_i]],

the output energy of a *deterministic* LTI system (A, B, C_eq, D_eq) driven by w: γ_∞ is its
H∞ norm (:func:`lti_hinf_norm`, python-control's ``linfnorm`` with slycot's AB13DD).  For a
deterministic system this is the ordinary H∞ norm.

**Continuous time** (a theorem with ``time="continuous"``): only deterministic systems
ẋ = Ax + Bw, e = Cx + Dw are covered (multiplicative noise in continuous time is an Itô system,
not implemented: refused).  Stability is max Re λ(A) < 0 (``spectral_radius`` then holds the
spectral abscissa); γ_∞ is the H∞ norm (python-control); the energy-to-peak (generalised H2)
figure is √λ_max(C W Cᵀ) with A W + W Aᵀ + B Bᵀ = 0 when D = 0 (infinite otherwise).  No
worst-case disturbance is computed (the Monte Carlo check is discrete-time only).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import eigh, solve_continuous_lyapunov

from ..errors import InputError
from .system import StochasticSystem

ENERGY_TO_PEAK = "energy_to_peak"
H_INFINITY = "h_infinity"
FIGURES = {ENERGY_TO_PEAK: "mean-square energy-to-peak gain sup_k E|e(k)|² / ‖w‖²",
           H_INFINITY: "mean-square H∞ gain Σ_k E|e(k)|² / ‖w‖²"}


@dataclass
class Figure:
    """An exact figure: ``value`` (γ units; None = infinite), worst-case disturbance, details."""

    kind: str
    value: float | None
    spectral_radius: float
    worst_disturbance: np.ndarray | None = None
    peak_step: int | None = None
    details: dict = field(default_factory=dict)

    @property
    def squared(self) -> float | None:
        return None if self.value is None else self.value ** 2

    time: str = "discrete"

    @property
    def mean_square_stable(self) -> bool:
        """ρ(𝓛) < 1 in discrete time; in continuous time ``spectral_radius`` is the spectral
        abscissa max Re λ(A), and stability is abscissa < 0."""
        if self.time == "continuous":
            return self.spectral_radius < 0.0
        return self.spectral_radius < 1.0

    def as_dict(self) -> dict:
        return {"kind": self.kind, "description": FIGURES.get(self.kind, self.kind), "time": self.time,
                "value": self.value, "squared": self.squared,
                "mean_square_stable": self.mean_square_stable,
                "spectral_radius": self.spectral_radius, **self.details}


def _sym_sqrt(M: np.ndarray) -> np.ndarray:
    vals, vecs = np.linalg.eigh((M + M.T) / 2)
    return (vecs * np.sqrt(np.clip(vals, 0.0, None))) @ vecs.T


# -- energy to peak ------------------------------------------------------------------------
def peak_form(sys: StochasticSystem, K: int) -> np.ndarray:
    """M_K with E|e(K)|² = wᵀ M_K w, w = (w(0), ..., w(K)) stacked (size (K+1)m)."""
    n, m = sys.n, sys.m
    N = (K + 1) * m
    Q = sys.output_weight()
    S = [Q]
    for _ in range(K - 1):
        S.append(sys.lyap_adjoint(S[-1]))
    pairs = list(sys._pairs())
    T = np.zeros((n, N))  # m_j = T w
    M = np.zeros((N, N))
    for j in range(K):
        cols = slice(j * m, (j + 1) * m)
        St = S[K - 1 - j]
        for s, ti, tl in pairs:
            Ui = ti["A"] @ T
            Ui[:, cols] += ti["B"]
            Ul = tl["A"] @ T if tl is not ti else Ui
            if tl is not ti:
                Ul[:, cols] += tl["B"]
            M += s * Ui.T @ St @ Ul
        T = sys.A @ T
        T[:, cols] += sys.B
    last = slice(K * m, (K + 1) * m)
    E0 = sys.C @ T
    E0[:, last] += sys.D
    M += E0.T @ E0
    for s, ti, tl in pairs:
        Ci = ti["C"] @ T
        Ci[:, last] += ti["D"]
        Cl = tl["C"] @ T
        Cl[:, last] += tl["D"]
        M += s * Ci.T @ Cl
    return (M + M.T) / 2


def energy_to_peak(sys: StochasticSystem, rtol: float = 1e-12, max_size: int = 1024,
                   feedback: bool = True) -> Figure:
    """γ_ep = √(lim_K λ_max(M_K)) with the worst-case disturbance (K doubled until converged)."""
    rho = sys.spectral_radius()
    if rho >= 1.0:
        return Figure(ENERGY_TO_PEAK, None, rho, details={"reason": "not mean-square stable"})
    K, prev, converged = 16, None, False
    while True:
        M = peak_form(sys, K)
        vals, vecs = eigh(M, subset_by_index=[M.shape[0] - 1, M.shape[0] - 1])
        lam = float(max(vals[-1], 0.0))
        if prev is not None and abs(lam - prev) <= rtol * max(lam, 1e-300):
            converged = True
            break
        if 2 * (K + 1) * sys.m > max_size:
            break
        prev, K = lam, 2 * K
    w = vecs[:, -1].reshape(K + 1, sys.m)
    energy = np.cumsum(np.sum(w ** 2, axis=1))
    first = int(np.searchsorted(energy, 1e-16 * energy[-1]))  # drop the negligible early steps
    w = w[first:]
    w = w / np.linalg.norm(w)
    details = {"horizon": K, "converged": converged}
    if feedback:
        details["feedback_value"] = feedback_energy_to_peak(sys, lower=lam)
    return Figure(ENERGY_TO_PEAK, float(np.sqrt(lam)), rho, w, len(w) - 1, details)


def _riccati_holds(sys: StochasticSystem, g: float, adapted: bool, max_iter: int = 20000,
                   rtol: float = 1e-13) -> bool:
    """gI − R(Π_l) ≻ 0 for every l of the backward recursion (see the module docstring).

    ``adapted=False`` is the deterministic-disturbance variant, an independent check of M_K: the
    covariance weights S_l = 𝓛*^l(Q) propagate without the disturbance's help,
    Π_{l+1} = AᵀΠ_lA + (𝓛*(S_l) − AᵀS_lA) + Fᵀ(gI − R)⁻¹F with S_l in place of Π_l in the noise
    parts of F and R.
    """
    pairs = list(sys._pairs())
    Pi = sys.output_weight()
    S = Pi.copy()
    for _ in range(max_iter):
        R = sys.B.T @ Pi @ sys.B
        F = sys.B.T @ Pi @ sys.A
        Z = Pi if adapted else S
        for s, ti, tj in pairs:
            R = R + s * ti["B"].T @ Z @ tj["B"]
            F = F + s * ti["B"].T @ Z @ tj["A"]
        G = g * np.eye(sys.m) - (R + R.T) / 2
        try:
            np.linalg.cholesky(G)
        except np.linalg.LinAlgError:
            return False
        base = sys.lyap_adjoint(Pi) if adapted else (
            sys.A.T @ Pi @ sys.A + sys.lyap_adjoint(S) - sys.A.T @ S @ sys.A)
        new = base + F.T @ np.linalg.solve(G, F)
        new = (new + new.T) / 2
        if not adapted:
            S = sys.lyap_adjoint(S)
        if np.max(np.abs(new - Pi)) <= rtol * max(1.0, np.max(np.abs(new))):
            return True
        Pi = new
    return False


def riccati_energy_to_peak(sys: StochasticSystem, adapted: bool, lower: float = 0.0,
                           rtol: float = 1e-9) -> float | None:
    """Least g (squared units) passing :func:`_riccati_holds`, by bisection (None with output noise or feedthrough)."""
    if sys.noise_in("C") or sys.noise_in("D") or np.any(sys.D):
        return None
    lo = max(lower * (1 - 1e-9), 0.0)
    hi = max(2 * lower, 1e-12)
    while not _riccati_holds(sys, hi, adapted):
        lo, hi = hi, 2 * hi
        if hi > 1e12:
            return None
    while hi - lo > rtol * hi:
        mid = (lo + hi) / 2
        if _riccati_holds(sys, mid, adapted):
            hi = mid
        else:
            lo = mid
    return hi


def feedback_energy_to_peak(sys: StochasticSystem, lower: float = 0.0) -> float | None:
    """√g for disturbances that may depend causally on the state (≥ the deterministic figure)."""
    g = riccati_energy_to_peak(sys, adapted=True, lower=lower)
    return None if g is None else float(np.sqrt(g))


# -- H∞ ------------------------------------------------------------------------------------
def equivalent_lti(sys: StochasticSystem):
    """(A, B, C_eq, D_eq) whose output energy equals Σ_k E|e(k)|² for every deterministic w."""
    Cs, Ds = [sys.C], [sys.D]
    if sys.q and np.any(sys.covariance):
        Wo = sys.observability_gramian()
        Rc = _sym_sqrt(np.kron(sys.covariance, np.eye(sys.p)))
        Ry = _sym_sqrt(np.kron(sys.covariance, Wo))
        Cs += [Rc @ np.vstack([t["C"] for t in sys.noise]), Ry @ np.vstack([t["A"] for t in sys.noise])]
        Ds += [Rc @ np.vstack([t["D"] for t in sys.noise]), Ry @ np.vstack([t["B"] for t in sys.noise])]
    return sys.A, sys.B, np.vstack(Cs), np.vstack(Ds)


def lti_hinf_norm(A, B, C, D, dt=True) -> tuple[float, float]:
    """(‖G‖∞, frequency of the peak) of a stable LTI system, by python-control (slycot AB13DD);
    ``dt=True`` discrete time (frequency in rad/sample), ``dt=0`` continuous."""
    A, B, C, D = (np.atleast_2d(np.asarray(M, dtype=float)) for M in (A, B, C, D))
    if A.size == 0:
        return float(np.linalg.norm(D, 2)), 0.0
    import control     # 1–2 s to import: only when a norm is computed
    peak, frequency = control.linfnorm(control.ss(A, B, C, D, dt))
    return float(peak), float(frequency)


def h_infinity(sys: StochasticSystem, horizon: int = 200) -> Figure:
    """γ_∞ = ‖(A, B, C_eq, D_eq)‖∞, and a finite-horizon worst-case disturbance for simulation."""
    rho = sys.spectral_radius()
    if rho >= 1.0:
        return Figure(H_INFINITY, None, rho, details={"reason": "not mean-square stable"})
    A, B, Ceq, Deq = equivalent_lti(sys)
    value, theta = lti_hinf_norm(A, B, Ceq, Deq)
    # worst w of length `horizon`: top right singular vector of the (horizon + tail) x horizon
    # block-Toeplitz map of the equivalent system (its energy ratio tends to value² as horizon grows)
    decay = max(float(np.max(np.abs(np.linalg.eigvals(A)))) if A.size else 0.0, 1e-3)
    tail = int(np.ceil(np.log(1e-10) / np.log(decay))) if decay < 1 else horizon
    L = horizon + max(tail, 1)
    markov = [Deq]
    P = B
    for _ in range(L - 1):
        markov.append(Ceq @ P)
        P = A @ P
    pz, m = Deq.shape
    T = np.zeros((L * pz, horizon * m))
    for i in range(L):
        for j in range(min(i + 1, horizon)):
            T[i * pz:(i + 1) * pz, j * m:(j + 1) * m] = markov[i - j]
    vals, vecs = np.linalg.eigh(T.T @ T)
    w = np.concatenate([vecs[:, -1].reshape(horizon, m), np.zeros((L - horizon, m))])
    return Figure(H_INFINITY, value, rho, w, None,
                  {"frequency": theta, "finite_horizon_value": float(np.sqrt(max(vals[-1], 0.0))),
                   "horizon": horizon})


def continuous_figure(kind: str, sys: StochasticSystem) -> Figure:
    """The figures of a deterministic continuous-time system (see the module docstring)."""
    if sys.q:
        raise InputError("exact figures of continuous-time systems with multiplicative noise are "
                         "not implemented (an Itô system); only deterministic error systems")
    abscissa = float(np.max(np.linalg.eigvals(sys.A).real)) if sys.A.size else -np.inf
    if abscissa >= 0.0:
        return Figure(kind, None, abscissa, details={"reason": "not stable (max Re λ(A) ≥ 0)"},
                      time="continuous")
    if kind == H_INFINITY:
        value, frequency = lti_hinf_norm(sys.A, sys.B, sys.C, sys.D, dt=0)
        return Figure(H_INFINITY, value, abscissa, details={"frequency": frequency}, time="continuous")
    if kind == ENERGY_TO_PEAK:
        if np.any(sys.D):
            return Figure(kind, None, abscissa, details={"reason": "D ≠ 0: the peak is unbounded"},
                          time="continuous")
        W = solve_continuous_lyapunov(sys.A, -sys.B @ sys.B.T)
        lam = float(np.max(np.linalg.eigvalsh(sys.C @ W @ sys.C.T)))
        return Figure(kind, float(np.sqrt(max(lam, 0.0))), abscissa, time="continuous")
    raise ValueError(f"unknown figure {kind!r}; known: {', '.join(FIGURES)}")


def exact_figure(kind: str, sys: StochasticSystem) -> Figure:
    if sys.time == "continuous":
        return continuous_figure(kind, sys)
    if kind == ENERGY_TO_PEAK:
        return energy_to_peak(sys)
    if kind == H_INFINITY:
        return h_infinity(sys)
    raise ValueError(f"unknown figure {kind!r}; known: {', '.join(FIGURES)}")
