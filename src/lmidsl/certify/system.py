"""Linear systems with i.i.d. multiplicative noise, and their exact first and second moments.

The filtering-error systems of the Bernoulli papers are all of the form

    x(k+1) = (A + Σ_i ν_i(k) A_i) x(k) + (B + Σ_i ν_i(k) B_i) w(k),
    e(k)   = (C + Σ_i ν_i(k) C_i) x(k) + (D + Σ_i ν_i(k) D_i) w(k),

with ν(k) ∈ R^q independent over k, zero mean, covariance Σ, independent of x(0) = 0, and w a
deterministic disturbance.  (A, B, C, D) are the *mean* matrices.  Seed 000 (error system (5)):
q = 1, ν = r − r̄, Σ = a = r̄(1 − r̄), A = A_cl0, A_1 = A_cl1, B = B_cl, C = C_cl.

With m = E x and X̃ = cov x, and u_i = A_i m + B_i w, c_i = C_i m + D_i w:

    m(k+1) = A m + B w,
    X̃(k+1) = 𝓛(X̃) + Σ_ij Σ_ij u_i u_jᵀ,        𝓛(X) = A X Aᵀ + Σ_ij Σ_ij A_i X A_jᵀ,
    E|e(k)|² = |C m + D w|² + Σ_ij Σ_ij c_iᵀ c_j + tr(Q X̃),   Q = CᵀC + Σ_ij Σ_ij C_iᵀ C_j.

(ν(k) is independent of x(k), so every cross term with one factor ν has zero mean.)  Without
input the second moment E x xᵀ evolves by 𝓛, so the system is mean-square stable iff the
spectral radius of 𝓛 is < 1.  𝓛*(S) = AᵀSA + Σ_ij Σ_ij A_iᵀ S A_j is its adjoint:
tr(S 𝓛(X)) = tr(𝓛*(S) X).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

_PARTS = ("A", "B", "C", "D")


def _mat(value, rows=None, cols=None) -> np.ndarray:
    if value is None:
        return np.zeros((rows, cols))
    return np.atleast_2d(np.asarray(value, dtype=float))


@dataclass
class StochasticSystem:
    """Mean matrices A, B, C, D; ``noise`` = one dict {A, B, C, D} per ν_i; ``covariance`` Σ (q × q)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    noise: list = field(default_factory=list)
    covariance: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    time: str = "discrete"          # "continuous": ẋ = Ax + Bw (deterministic only, see figures)

    @classmethod
    def build(cls, A, B, C, D=None, noise=(), covariance=None, time: str = "discrete") -> "StochasticSystem":
        """Fill missing matrices with zeros; ``covariance`` may be a list of variances (diagonal Σ)."""
        A = _mat(A)
        B = _mat(B)
        C = _mat(C)
        n, m, p = A.shape[0], B.shape[1], C.shape[0]
        D = _mat(D, p, m)
        sizes = {"A": (n, n), "B": (n, m), "C": (p, n), "D": (p, m)}
        full = []
        for term in noise:
            full.append({k: _mat(term.get(k), *sizes[k]) for k in _PARTS})
        q = len(full)
        if covariance is None:
            cov = np.zeros((q, q))
        else:
            cov = np.asarray(covariance, dtype=float)
            cov = np.diag(cov) if cov.ndim == 1 else np.atleast_2d(cov)
        if cov.shape != (q, q):
            raise ValueError(f"covariance must be {q} x {q} (one row per noise term), got {cov.shape}")
        for k, M in (("A", A), ("B", B), ("C", C), ("D", D)):
            if M.shape != sizes[k]:
                raise ValueError(f"{k} must be {sizes[k]}, got {M.shape}")
        for i, term in enumerate(full):
            for k in _PARTS:
                if term[k].shape != sizes[k]:
                    raise ValueError(f"noise term {i + 1}: {k} must be {sizes[k]}, got {term[k].shape}")
        return cls(A, B, C, D, full, cov, time)

    @classmethod
    def bernoulli(cls, A0, A1, B, C, a, D=None) -> "StochasticSystem":
        """x(k+1) = (A0 + (r − r̄) A1) x + B w, e = C x (+ D w); a = var r = r̄(1 − r̄)."""
        return cls.build(A0, B, C, D, noise=[{"A": A1}], covariance=[a])

    # -- sizes ------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return self.A.shape[0]

    @property
    def m(self) -> int:
        return self.B.shape[1]

    @property
    def p(self) -> int:
        return self.C.shape[0]

    @property
    def q(self) -> int:
        return len(self.noise)

    def _pairs(self):
        """(Σ_ij, term_i, term_j) for the nonzero covariance entries."""
        for i in range(self.q):
            for j in range(self.q):
                if self.covariance[i, j] != 0.0:
                    yield self.covariance[i, j], self.noise[i], self.noise[j]

    def noise_in(self, part: str) -> bool:
        return any(np.any(t[part]) for t in self.noise) and np.any(self.covariance)

    # -- the second-moment operator ----------------------------------------------------
    def lyap(self, X: np.ndarray) -> np.ndarray:
        """𝓛(X) = A X Aᵀ + Σ_ij Σ_ij A_i X A_jᵀ."""
        out = self.A @ X @ self.A.T
        for s, ti, tj in self._pairs():
            out = out + s * ti["A"] @ X @ tj["A"].T
        return out

    def lyap_adjoint(self, S: np.ndarray) -> np.ndarray:
        """𝓛*(S) = AᵀSA + Σ_ij Σ_ij A_iᵀ S A_j."""
        out = self.A.T @ S @ self.A
        for s, ti, tj in self._pairs():
            out = out + s * ti["A"].T @ S @ tj["A"]
        return out

    def operator_matrix(self) -> np.ndarray:
        """Matrix of 𝓛 on row-major vec(X): A ⊗ A + Σ_ij Σ_ij A_i ⊗ A_j."""
        L = np.kron(self.A, self.A)
        for s, ti, tj in self._pairs():
            L = L + s * np.kron(ti["A"], tj["A"])
        return L

    def spectral_radius(self) -> float:
        """ρ(𝓛): the system is mean-square (exponentially) stable iff ρ(𝓛) < 1."""
        return float(np.max(np.abs(np.linalg.eigvals(self.operator_matrix()))))

    def mean_square_stable(self) -> bool:
        return self.spectral_radius() < 1.0

    def output_weight(self) -> np.ndarray:
        """Q = CᵀC + Σ_ij Σ_ij C_iᵀC_j: E|e|² = tr(Q E x xᵀ) for w = 0."""
        Q = self.C.T @ self.C
        for s, ti, tj in self._pairs():
            Q = Q + s * ti["C"].T @ tj["C"]
        return (Q + Q.T) / 2

    def observability_gramian(self) -> np.ndarray:
        """W_o = 𝓛*(W_o) + Q: Σ_k E|e(k)|² = x0ᵀ W_o x0 from x(0) = x0, w = 0 (needs ρ(𝓛) < 1)."""
        n = self.n
        L = self.operator_matrix()
        vec = np.linalg.solve(np.eye(n * n) - L.T, self.output_weight().reshape(-1))
        W = vec.reshape(n, n)
        return (W + W.T) / 2

    # -- exact moments for a given disturbance -------------------------------------------
    def mean_square_output(self, w) -> np.ndarray:
        """E|e(k)|² for k = 0..K−1, exactly, for the deterministic w (K × m) from x(0) = 0."""
        w = np.atleast_2d(np.asarray(w, dtype=float))
        if w.shape[1] != self.m and w.shape[0] == self.m:
            w = w.T
        m_ = np.zeros(self.n)
        X = np.zeros((self.n, self.n))
        Q = self.output_weight()
        out = np.empty(len(w))
        for k, wk in enumerate(w):
            mean_e = self.C @ m_ + self.D @ wk
            val = mean_e @ mean_e + np.trace(Q @ X)
            U = np.zeros((self.n, self.n))
            for s, ti, tj in self._pairs():
                val += s * (ti["C"] @ m_ + ti["D"] @ wk) @ (tj["C"] @ m_ + tj["D"] @ wk)
                U += s * np.outer(ti["A"] @ m_ + ti["B"] @ wk, tj["A"] @ m_ + tj["B"] @ wk)
            out[k] = val
            X = self.lyap(X) + U
            m_ = self.A @ m_ + self.B @ wk
        return out

    def is_deterministic(self) -> bool:
        return not np.any(self.covariance)
