"""Helpers of tests/test_dual_bound.py and tests/test_infeasibility.py: a theorem solved on the
direct backend with its compiled model kept (as :func:`lmidsl.pipeline.solve_instance` does,
without recovery and certification), and the stress plants."""
from __future__ import annotations

import warnings

import numpy as np

from lmidsl.numeric.scaling import apply_scaling
from lmidsl.pipeline import make_instance
from lmidsl.solver.backends.direct_backend import DirectModel
from lmidsl.solver.conditioning import equilibrate
from lmidsl.solver.margin import solve_model


def solved_model(theorem, example=None, data=None, conditioning=False, scaling="auto"):
    """(model, solution): the theorem bound to an example or data, its declared signal scalings
    applied (``scaling``), compiled (with :func:`equilibrate`'s conditioning when asked) and solved."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        instance = make_instance(theorem, example, data)
    scaled = apply_scaling(instance, scaling).scaled
    model = DirectModel(scaled, conditioning=equilibrate(scaled) if conditioning else None)
    return model, solve_model(model)


def lists(**matrices) -> dict:
    return {k: np.atleast_2d(np.asarray(v, dtype=float)).tolist() for k, v in matrices.items()}


def stable_system(rng, n, m, p, time, zeta=None):
    """A random stable (A, B, C, D); ``zeta``: add a lightly damped pair (continuous) or a pole
    pair at radius 1 − zeta (discrete)."""
    A = rng.standard_normal((n, n))
    eig = np.linalg.eigvals(A)
    A = A - (max(eig.real) + 0.2 + rng.random()) * np.eye(n) if time == "continuous" else 0.9 * A / max(abs(eig))
    if zeta is not None:
        if time == "continuous":
            w = 1 + rng.random()
            block = np.array([[0.0, w], [-w, -2 * zeta * w]])
        else:
            th = 0.3 + rng.random()
            block = (1 - zeta) * np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])
        A = np.block([[A, np.zeros((n, 2))], [np.zeros((2, n)), block]])
        n += 2
    return A, rng.standard_normal((n, m)), rng.standard_normal((p, n)), 0.3 * rng.standard_normal((p, m))


REFERENCE: dict = {}


def brl_stress(time: str) -> list[tuple[str, dict]]:
    """Bounded-real stress plants: generic, lightly damped, badly scaled (B × 1e3, C × 1e-3: the
    same norm through entries 1e6 apart), large gain (C × 1e3), a zero on the stability boundary
    (s² + 1, or z² + 1), and a diagonal similarity spreading the entries over 1e-3..1e3.

    :data:`REFERENCE` maps the scaled cases to a well-scaled realization of the same transfer
    function: python-control's ``linfnorm`` on the discrete similarity-1e6 system itself returns
    6.055531, below the norm 6.055881 it gives for the same transfer function well scaled (a
    200,001-point frequency grid already reaches 6.055868)."""
    rng = np.random.default_rng(2025 if time == "continuous" else 2026)
    cases = []
    for k in range(4):
        A, B, C, D = stable_system(rng, 2 + k, 1 + k % 2, 1 + (k + 1) % 2, time)
        cases.append((f"generic-{k}", lists(A=A, B=B, C=C, D=D)))
    for k, zeta in enumerate((1e-2, 1e-3)):
        A, B, C, D = stable_system(rng, 2, 1, 1, time, zeta)
        cases.append((f"light-{zeta:g}", lists(A=A, B=B, C=C, D=D)))
    A, B, C, D = stable_system(rng, 3, 2, 2, time)
    REFERENCE[(time, "badly-scaled")] = REFERENCE[(time, "similarity-1e6")] = lists(A=A, B=B, C=C, D=D)
    cases.append(("badly-scaled", lists(A=A, B=1e3 * B, C=1e-3 * C, D=D)))
    cases.append(("large-gain", lists(A=A, B=B, C=1e3 * C, D=1e3 * D)))
    T = np.diag(10.0 ** np.linspace(-3, 3, 3))
    cases.append(("similarity-1e6", lists(A=T @ A @ np.linalg.inv(T), B=T @ B, C=C @ np.linalg.inv(T), D=D)))
    if time == "continuous":      # (s² + 1) / (s + 1)(s + 2)(s + 3): zeros at ±j
        import control
        G = control.tf2ss(control.tf([1.0, 0.0, 1.0], np.polymul([1.0, 1.0], np.polymul([1.0, 2.0], [1.0, 3.0]))))
    else:                         # (z² + 1) / (z − 0.5)(z + 0.3)(z − 0.1): zeros at ±j on the unit circle
        import control
        G = control.tf2ss(control.tf([1.0, 0.0, 1.0], np.polymul([1.0, -0.5], np.polymul([1.0, 0.3], [1.0, -0.1])), True))
    cases.append(("boundary-zero", lists(A=G.A, B=G.B, C=G.C, D=G.D)))
    return cases


def unstabilisable_plant(rng, n: int, time: str, mode: float, m2: int = 1, hidden: int = 1) -> dict:
    """A generalized plant (A, B1, B2, C1, D11, D12) whose last ``hidden`` states form a block
    that B2 does not reach (A block upper triangular, B2's last rows exactly 0), every eigenvalue
    of that block at least ``mode`` (continuous: real parts; discrete: moduli); the rest random."""
    A = rng.standard_normal((n, n))
    A[n - hidden:, : n - hidden] = 0.0
    block = rng.standard_normal((hidden, hidden))
    if hidden == 1:
        block = np.array([[mode]])
    elif time == "continuous":
        block = block - (min(np.linalg.eigvals(block).real) - mode) * np.eye(hidden)
    else:
        block = mode * block / min(abs(np.linalg.eigvals(block)))
    A[n - hidden:, n - hidden:] = block
    B2 = rng.standard_normal((n, m2))
    B2[n - hidden:] = 0.0
    B1 = rng.standard_normal((n, 2))
    C1 = np.vstack([rng.standard_normal((1, n)), np.zeros((m2, n))])
    D12 = np.vstack([np.zeros((1, m2)), np.eye(m2)])
    D11 = np.zeros((1 + m2, 2))
    return lists(A=A, B1=B1, B2=B2, C1=C1, D11=D11, D12=D12)


def pbh_unstabilisable(A, B, time: str) -> bool:
    """PBH: some eigenvalue λ with Re λ ≥ 0 (|λ| ≥ 1) has rank [A − λI, B] < n."""
    A, B = np.asarray(A), np.asarray(B)
    n = A.shape[0]
    for lam in np.linalg.eigvals(A):
        unstable = lam.real >= -1e-12 if time == "continuous" else abs(lam) >= 1 - 1e-12
        if unstable and np.linalg.matrix_rank(np.hstack([A - lam * np.eye(n), B]), tol=1e-9) < n:
            return True
    return False
