"""Evidence for rate-bounded LPV conditions (:meth:`lmidsl.theorem.robust.RobustTheorem.rate`).

A rate-bounded condition claims, for every trajectory α(t) ∈ Λ_N with |α̇ᵢ(t)| ≤ b, that
V(t) = x(t)ᵀ P(α(t)) x(t) decreases along ẋ = A(α(t))x (or along the closed loop with the
scheduled gain K(α(t)) = W(α)Y(α)⁻¹, V = xᵀY(α)⁻¹x).  Three computations, independent of the
coefficient expansion that produced the certificate:

* :func:`scheduled` — a scheduled recovery (K(α) = W(α)Y(α)⁻¹) at a given α, from the solved
  coefficients: M(α) = Σ_k α^k M_k evaluated in numpy;
* :func:`rate_grid_check` — every LMI *as stated* (in α and α̇) evaluated on a dense grid of
  (α, α̇) ∈ Λ_N × b·H_N, with P(α) from its coefficients and ∂P/∂αᵢ = Σ_k kᵢ α^{k−eᵢ} P_k
  computed numerically (not from the symbolic derivative): the largest eigenvalue must be < 0
  (≤ 0 for a non-strict LMI) at every point;
* :func:`rate_simulation_check` — the system simulated (scipy, RK45, tight tolerances) under a
  parameter moving at the largest admitted rate (a triangle wave along the edges of the
  simplex, |α̇ᵢ| = b) and under a sinusoid within the bound: V(t) must not increase and x(t)
  must decay.  A simulation is evidence, not proof.
"""
from __future__ import annotations

import itertools

import numpy as np

from ..numeric.evaluate import NumericEvaluator, eigenvalues, evaluate_block_matrix
from ..symbolic.simplex import rate_vertices
from ..theorem.checks import CheckResult


def _member(solution):
    theorem = solution.instance.theorem
    info = getattr(theorem, "robust", None)
    if info is None:
        raise ValueError(f"{theorem.id} is not a member of a robust theorem")
    return theorem, info


def _monomial(k: tuple, alpha) -> float:
    return float(np.prod([a ** e for p, a_s in zip(k, alpha) for e, a in zip(p, a_s)]))


class AtAlpha:
    """The α-dependent symbols of a solved rate-bounded (or robust) member as numpy functions of
    (α, α̇): vertex data Σᵢ αᵢMᵢ, HPPD variables Σ_k α^k M_k and their derivatives
    Σᵢ α̇ᵢ Σ_k kᵢ α^{k−eᵢ} M_k, computed from the solved coefficients (arrays read once)."""

    def __init__(self, solution):
        theorem, info = _member(solution)
        self.info, self.statement = info, info.statement
        self.base = {k: v for k, v in solution.instance.data.items() if not isinstance(v, list)}
        self.base.update({k: v for k, v in solution.values.items() if not isinstance(v, list)})
        self.vertex = {name: [np.asarray(M, dtype=float) for M in solution.instance.data[name]]
                       for name, d in self.statement.polynomial.items() if d.kind == "vertex"}
        self.coefficients = {name: [(k, np.asarray(solution.values[c.name], dtype=float))
                                    for k, c in info.coefficient_vars[name].items()]
                             for name, d in self.statement.polynomial.items() if d.kind == "variable"}
        self.index = list(itertools.product(*(range(N) for N in info.sizes)))   # first simplex slowest

    def __call__(self, alpha, rate=None) -> dict:
        """Every symbol at α (one sequence per simplex) and α̇ (one per rate; default 0)."""
        alpha = [np.asarray(a, dtype=float) for a in alpha]
        values = dict(self.base)
        weights = [float(np.prod([alpha[s][i] for s, i in enumerate(idx)])) for idx in self.index]
        for name, vertices in self.vertex.items():
            values[name] = sum(w * M for w, M in zip(weights, vertices))
        for name, terms in self.coefficients.items():
            values[name] = sum(_monomial(k, alpha) * M for k, M in terms)
        for name, decl in self.statement.polynomial.items():
            if decl.kind != "derivative":
                continue
            s = decl.rate.simplex.index
            h = np.zeros(self.info.sizes[s]) if rate is None else np.asarray(rate[decl.rate.index], dtype=float)
            total = np.zeros_like(values[decl.of])
            for k, M in self.coefficients[decl.of]:
                for i, ki in enumerate(k[s]):
                    if ki and h[i]:
                        lowered = list(k)
                        lowered[s] = tuple(x - (j == i) for j, x in enumerate(k[s]))
                        total = total + h[i] * ki * _monomial(tuple(lowered), alpha) * M
            values[name] = total
        return values


def values_at(solution, alpha, rate=None) -> dict:
    """Every α-dependent symbol of the statement at α and α̇ (:class:`AtAlpha`)."""
    return AtAlpha(solution)(alpha, rate)


def scheduled(solution, name: str, alpha, at: AtAlpha | None = None) -> np.ndarray:
    """The scheduled recovery ``name`` (:meth:`RobustTheorem.recover_scheduled`) at α: its formula
    evaluated with every α-dependent symbol replaced by its value at α."""
    at = at or AtAlpha(solution)
    inst = solution.instance
    ev = NumericEvaluator(inst.dims, at(alpha), inst.params)
    return np.asarray(ev.visit(at.statement.scheduled[name]), dtype=float)


def rate_grid(sizes: tuple, bound: float, resolution: int, rate_steps: int):
    """(α, α̇) points: α on the regular grid {kᵢ/r} of Λ_N (one simplex), α̇ = b·h for h on the
    segments between consecutive vertices of H_N (``rate_steps`` points each)."""
    N = sizes[0]
    alphas = [np.array(k, dtype=float) / resolution
              for k in itertools.product(range(resolution + 1), repeat=N) if sum(k) == resolution]
    H = [np.array(h, dtype=float) for h in rate_vertices(N)]
    rates = []
    for a, b in zip(H, H[1:] + H[:1]):
        rates += [bound * ((1 - t) * a + t * b) for t in np.linspace(0, 1, rate_steps, endpoint=False)]
    return alphas, rates


def rate_grid_check(resolution: int = 20, rate_steps: int = 11, name: str = "rate grid"):
    """A check: the stated LMIs hold on a dense (α, α̇) grid (see the module docstring)."""

    def check(solution) -> CheckResult:
        theorem, info = _member(solution)
        statement = info.statement
        if len(info.sizes) != 1 or len(statement.rates) != 1:
            return CheckResult(name, False, "the grid covers one simplex with one rate bound")
        bound = float(solution.instance.params[statement.rates[0].bound])
        alphas, rates = rate_grid(info.sizes, bound, resolution, rate_steps)
        worst, where, count = -np.inf, None, 0
        inst = solution.instance
        at = AtAlpha(solution)
        for alpha in alphas:
            for h in rates:
                values = at([alpha], [h])
                ev = NumericEvaluator(inst.dims, values, inst.params)
                for lmi in statement.lmis:
                    top = eigenvalues(evaluate_block_matrix(ev, lmi.negative_form()))[-1]
                    count += 1
                    if top > worst:
                        worst, where = float(top), (alpha.tolist(), h.tolist(), lmi.label)
        passed = worst < 0
        summary = (f"largest eigenvalue of the stated LMIs {worst:.3e} over {len(alphas)} α × {len(rates)} α̇ "
                   f"points (at α = {np.round(where[0], 4).tolist()}, α̇ = {np.round(where[1], 4).tolist()}, "
                   f"{where[2]})")
        return CheckResult(name, passed, summary, {"worst": worst, "alpha": where[0], "rate": where[1],
                                                   "lmi": where[2], "evaluations": count})

    return check


def edge_path(N: int, bound: float, period_edges: int = 1):
    """α(t) moving at the largest admitted rate: along the edges e₁ → e₂ → … → e_N → e₁ of the
    simplex (|α̇ᵢ| = b on the moving pair), a triangle wave on each edge; returns α(t)."""
    edge_time = 1.0 / bound                       # from one vertex to the next at rate b

    def alpha(t):
        k = int(t // edge_time)
        s = (t - k * edge_time) / edge_time
        i, j = k % N, (k + 1) % N
        a = np.zeros(N)
        a[i] += 1 - s
        a[j] += s
        return a

    return alpha


def sinusoid_path(N: int, bound: float):
    """α(t) = ½(e₁ + e₂) + ½ sin(2b t)(e₂ − e₁): |α̇ᵢ| ≤ b, reaching it at the midpoint."""

    def alpha(t):
        a = np.zeros(N)
        s = 0.5 + 0.5 * np.sin(2 * bound * t)
        a[0], a[1] = 1 - s, s
        return a

    return alpha


def simulate(solution, path, *, A: str = "A", B: str | None = None, K: str | None = None,
             lyapunov: str = "P", inverse: bool = False, horizon: float = 20.0, x0=None,
             samples: int = 400):
    """ẋ = (A(α(t)) + B(α(t))K(α(t)))x from x0 (default: ones); returns (t, x, V) with
    V = xᵀP(α)x (``inverse``: xᵀP(α)⁻¹x, for a Y = P⁻¹ parametrisation)."""
    from scipy.integrate import solve_ivp

    at = AtAlpha(solution)

    def matrices(t):
        a = path(t)
        values = at([a])
        M = np.asarray(values[A], dtype=float)
        if B is not None and K is not None:
            M = M + np.asarray(values[B], dtype=float) @ scheduled(solution, K, [a], at)
        L = np.asarray(values[lyapunov], dtype=float)
        return M, (np.linalg.inv(L) if inverse else L)

    n = matrices(0.0)[0].shape[0]
    x0 = np.ones(n) if x0 is None else np.asarray(x0, dtype=float)
    sol = solve_ivp(lambda t, x: matrices(t)[0] @ x, (0.0, horizon), x0, rtol=1e-9, atol=1e-12,
                    dense_output=True, max_step=0.05)
    ts = np.linspace(0.0, horizon, samples)
    xs = sol.sol(ts).T
    V = np.array([x @ matrices(t)[1] @ x for t, x in zip(ts, xs)])
    return ts, xs, V


def rate_simulation_check(*, A: str = "A", B: str | None = None, K: str | None = None,
                          lyapunov: str = "P", inverse: bool = False, horizon: float = 20.0,
                          name: str = "rate-bounded simulation"):
    """A check: under the fastest admitted parameter (edge path) and a sinusoid, V(t) does not
    increase (relative tolerance 1e-7) and ‖x(T)‖ < ‖x(0)‖."""

    def check(solution) -> CheckResult:
        theorem, info = _member(solution)
        statement = info.statement
        bound = float(solution.instance.params[statement.rates[0].bound])
        N = info.sizes[0]
        results = []
        for label, path in (("edges at the rate bound", edge_path(N, bound)),
                            ("sinusoid", sinusoid_path(N, bound))):
            ts, xs, V = simulate(solution, path, A=A, B=B, K=K, lyapunov=lyapunov, inverse=inverse,
                                 horizon=horizon)
            rise = float(np.max(np.diff(V) / np.maximum(V[:-1], 1e-300)))
            decay = float(np.linalg.norm(xs[-1]) / np.linalg.norm(xs[0]))
            results.append((label, rise, decay))
        passed = all(r <= 1e-7 and d < 1 for _, r, d in results)
        summary = "; ".join(f"{label}: largest relative step of V {rise:+.1e}, ‖x(T)‖/‖x(0)‖ {decay:.2e}"
                            for label, rise, decay in results)
        return CheckResult(name, passed, summary, {"runs": [{"path": l, "rise": r, "decay": d}
                                                            for l, r, d in results]})

    check.needs_synthesis = False
    return check


__all__ = ["AtAlpha", "values_at", "scheduled", "rate_grid", "rate_grid_check", "edge_path", "sinusoid_path",
           "simulate", "rate_simulation_check"]
