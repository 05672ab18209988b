"""The balanced Riccati route (lmidsl.numeric.riccati.balancing_transform, storage_candidates):
square-root balancing checked against SciPy's Gramians, and a stiff closed loop's storage proved
where the coordinates as written give none; λmax reported at the proof's precision."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov, solve_discrete_lyapunov

from lmidsl.numeric.riccati import balancing_transform, hinf_norm, storage_candidates
from lmidsl.pipeline import make_instance
from lmidsl.solver.fallback import riccati_point
from lmidsl.solver.solution import lmi_certificate

pytest.importorskip("slycot")


def _gramians(A, B, C, time):
    if time == "continuous":
        return solve_continuous_lyapunov(A, -B @ B.T), solve_continuous_lyapunov(A.T, -C.T @ C)
    return solve_discrete_lyapunov(A, B @ B.T), solve_discrete_lyapunov(A.T, C.T @ C)


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_balancing_gives_equal_diagonal_gramians(time):
    """T⁻¹AT, T⁻¹B, CT have (by SciPy's Lyapunov solver, not SLICOT's) equal diagonal Gramians,
    and T⁻¹ is T's inverse."""
    rng = np.random.default_rng(3)
    A = rng.standard_normal((5, 5))
    A = A - (np.max(np.linalg.eigvals(A).real) + 0.5) * np.eye(5) if time == "continuous" \
        else 0.8 * A / np.max(np.abs(np.linalg.eigvals(A)))
    B, C = rng.standard_normal((5, 2)), rng.standard_normal((3, 5))
    T, Ti = balancing_transform(A, B, C, time)
    assert np.allclose(Ti @ T, np.eye(5), atol=1e-10)
    Wc, Wo = _gramians(Ti @ A @ T, Ti @ B, C @ T, time)
    scale = np.max(np.abs(Wc))
    assert np.allclose(Wc, Wo, atol=1e-8 * scale)
    assert np.allclose(Wc, np.diag(np.diag(Wc)), atol=1e-8 * scale)


def _stiff_loop(f: float = 5e6):
    """x₁' = −x₁ + w, a fast state x₂' = f(x₁ − x₂) tracking it, z = (1 − 2f)x₁ + 2f x₂ + x₃:
    ‖G‖∞ ≈ 2 by cancellation of entries ~1e7, the bounded-real LMI's entries ~1e14."""
    A = np.array([[-1.0, 0.0, 0.0], [f, -f, 0.0], [0.0, 1.0, -3.0]])
    B = np.array([[1.0], [0.0], [0.0]])
    C = np.array([[1.0 - 2 * f, 2 * f, 1.0]])
    return A, B, C, np.zeros((1, 1))


def test_stiff_storage_is_proved_within_1e4_of_the_norm():
    """As written, every candidate storage violates the LMI (proved); the balanced realisation's
    storage is proved at ‖G‖∞ (1 + 1e-5) by SLICOT's norm, with λmax < 0 as the proof says."""
    A, B, C, D = _stiff_loop()
    norm = hinf_norm(A, B, C, D, "continuous")
    instance = make_instance("textbook.brl_ct", None, {k: v.tolist() for k, v in zip("ABCD", (A, B, C, D))})
    g = (norm * (1 + 1e-5)) ** 2
    written = [P for how, P in storage_candidates(A, B, C, D, g, "continuous", norm) if how.startswith("as written")]
    assert written and all(lmi_certificate(instance, {**instance.data, "P": P, "g": g}, prove=True)[0].proof
                           == "violated" for P in written)
    sol = riccati_point(instance, None, 0.0)
    assert sol is not None and "balanced" in sol.notes[-1]
    assert norm < sol.point_gamma <= norm * (1 + 1e-4)
    proofs = lmi_certificate(instance, {**instance.data, **sol.values}, prove=True)
    assert [r.proof for r in proofs] == ["proved"] * len(proofs)
    assert all(r.max_eig < 0 for r in proofs)
