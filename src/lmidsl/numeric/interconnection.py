"""Designs as python-control systems, and the loops they close.

An independent check of a synthesis result should not reuse the formulas the theorem was
written with.  This module closes the loop of the plant and the design by the generic lower
linear fractional transformation (:func:`lower_lft`, on arrays: the same interconnection as
python-control's ``StateSpace.lft``, against which the tests check it), so the closed loop (or
filtering-error system) whose norm the evidence measures is formed by code independent of
lmidsl's symbolic closed loops (:func:`lmidsl.closed_loop_matrices`).  The loop is a
:class:`Realisation` (arrays and the time base); the public :func:`closed_loop` and
:func:`filtering_error` return it as a python-control ``StateSpace``.  A solve needs no
python-control (its import costs 1–2 s: scipy.signal, matplotlib): the norms are SLICOT's
AB13DD called directly (:mod:`lmidsl.numeric.systems`) and Lyapunov equations (scipy).

Names follow the gallery's convention (``theorems/textbook/plants.py``): a generalized plant
``A, B1, B2, C1, C2, D11, D12, D21, D22`` (x' = A x + B1 w + B2 u, z = C1 x + D11 w + D12 u,
y = C2 x + D21 w + D22 u; missing D blocks are zero); a controller ``AK, BK, CK, DK``, a static
state-feedback gain ``K`` (u = K x), a filter ``Af, Bf, Cf, Df`` (ẑ = filter(y)).

Time base: python-control's ``dt`` — 0 in continuous time, the sampling period (or ``True``,
unspecified) in discrete time.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np
from flint import arb, arb_mat

from ..errors import InputError
from .proof import decimal_ball, object_array
from .systems import hinf_norm

if TYPE_CHECKING:       # python-control is imported where a system is built (1–2 s)
    import control


def timebase(time: str, sample_time: float | None = None):
    """python-control's ``dt``: 0 (continuous) or the sampling period / True (discrete)."""
    if time == "continuous":
        return 0
    if time == "discrete":
        return sample_time or True
    raise InputError(f"unknown time domain {time!r}")


def _m(data: dict, name: str):
    """A matrix of the data or design as floats, or as it is when it is an object array (the balls
    of :func:`ball_loop`)."""
    value = data[name]
    return np.atleast_2d(value if getattr(value, "dtype", None) == object else np.asarray(value, dtype=float))


def _inverse(M: np.ndarray) -> np.ndarray:
    """M⁻¹ in floats, or in ball arithmetic for an object array of python-flint balls."""
    if M.dtype != object:
        return np.linalg.inv(M)
    try:
        inv = arb_mat([[arb(x) for x in row] for row in M.tolist()]).inv()
    except ZeroDivisionError:
        raise np.linalg.LinAlgError("not provably invertible") from None
    return np.array([[inv[i, j] for j in range(inv.ncols())] for i in range(inv.nrows())], dtype=object)


def ball_loop(data: dict, design):
    """:func:`design_loop` in ball arithmetic at the current precision: the data as the proofs read
    them (the decimals as written), the design's doubles exactly.  The loop of a large gain summed
    in doubles is another system (a state-feedback gain of entries 1e10: A + B₂K rounded moves the
    loop's H∞ norm from 75,375.7 to SLICOT's 119,444)."""
    balls = {k: object_array(v, decimal_ball) for k, v in data.items() if not isinstance(v, list)}
    exact = design.with_matrices({k: object_array(v, lambda x: arb(float(x))) for k, v in design.items()})
    return design_loop({**data, **balls}, exact)


def statespace(A, B, C, D, dt) -> control.StateSpace:
    """A ``StateSpace`` from arrays, including the static case (no state: A is 0 × 0)."""
    import control     # 1–2 s to import (scipy.signal, matplotlib): only when a loop is formed
    return control.ss(np.atleast_2d(A) if np.size(A) else np.zeros((0, 0)), B, C, D, dt)


def design_statespace(design) -> control.StateSpace:
    """The design as a system: controller (AK, BK, CK, DK) from y to u, filter (Af, Bf, Cf, Df)
    from y to ẑ, or a static gain K as a D-only system (no state).  A missing DK / Df is 0."""
    return statespace(*_design_arrays(design), timebase(design.time, design.sample_time))


def generalized_plant(data: dict, time: str, sample_time: float | None = None,
                      state_feedback: bool = False) -> tuple[control.StateSpace, int, int]:
    """(P, number of controls, number of measurements): P from [w; u] to [z; y].

    ``state_feedback``: the measurement is the state (C2 = I, D21 = 0, D22 = 0), as for a gain
    u = K x.  Missing D11, D12, D21, D22 are zero.
    """
    import control     # 1–2 s to import (scipy.signal, matplotlib)
    A, B1, B2, C1, C2, D11, D12, D21, D22 = _plant_arrays(data, state_feedback)
    P = control.ss(A, np.hstack([B1, B2]), np.vstack([C1, C2]),
                   np.block([[D11, D12], [D21, D22]]), timebase(time, sample_time))
    return P, B2.shape[1], C2.shape[0]


@dataclass(frozen=True)
class Realisation:
    """A state-space system x' = Ax + Bw, z = Cx + Dw as arrays, with python-control's time
    base ``dt`` (0: continuous)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: object = 0

    @property
    def nstates(self) -> int:
        return int(self.A.shape[0])

    def isctime(self) -> bool:
        return self.dt == 0

    def as_statespace(self) -> control.StateSpace:
        return statespace(self.A, self.B, self.C, self.D, self.dt)


def _design_arrays(design) -> tuple:
    """(AK, BK, CK, DK) of a controller, filter (Af, …) or gain K (no state)."""
    for a, b, c, d in (("AK", "BK", "CK", "DK"), ("Af", "Bf", "Cf", "Df")):
        if a in design and b in design and c in design:
            B, C = _m(design, b), _m(design, c)
            return _m(design, a), B, C, (_m(design, d) if d in design else np.zeros((C.shape[0], B.shape[1])))
    if "K" in design:
        K = _m(design, "K")
        return np.zeros((0, 0)), np.zeros((0, K.shape[1])), np.zeros((K.shape[0], 0)), K
    raise InputError(f"a {design.kind} design with matrices {', '.join(design)} is not a controller "
                     "(AK, BK, CK[, DK]), a filter (Af, Bf, Cf[, Df]) or a gain (K)")


def _plant_arrays(data: dict, state_feedback: bool = False) -> tuple:
    """(A, B1, B2, C1, C2, D11, D12, D21, D22) of the generalized plant ``data`` (missing D blocks
    zero; ``state_feedback``: the measurement is the state)."""
    A, B1, B2, C1 = (_m(data, k) for k in ("A", "B1", "B2", "C1"))
    n, m1, m2, p1 = A.shape[0], B1.shape[1], B2.shape[1], C1.shape[0]
    if state_feedback:
        C2, D21, D22 = np.eye(n), np.zeros((n, m1)), np.zeros((n, m2))
    else:
        C2 = _m(data, "C2")
        D21 = _m(data, "D21") if "D21" in data else np.zeros((C2.shape[0], m1))
        D22 = _m(data, "D22") if "D22" in data else np.zeros((C2.shape[0], m2))
    D11 = _m(data, "D11") if "D11" in data else np.zeros((p1, m1))
    D12 = _m(data, "D12") if "D12" in data else np.zeros((p1, m2))
    return A, B1, B2, C1, C2, D11, D12, D21, D22


def lower_lft(plant: tuple, controller: tuple, dt) -> Realisation:
    """The lower LFT F_l(P, K) of the plant (A, B1, B2, C1, C2, D11, D12, D21, D22) and the
    controller (AK, BK, CK, DK), u = K y.  With E = (I − DK D22)⁻¹ (the loop must be well posed),
    u = E(DK C2 x + CK xK + DK D21 w), y = C2 x + D21 w + D22 u, and the state [x; xK] obeys
    x' = A x + B1 w + B2 u, xK' = AK xK + BK y, z = C1 x + D11 w + D12 u."""
    A, B1, B2, C1, C2, D11, D12, D21, D22 = plant
    AK, BK, CK, DK = controller
    n, nk = A.shape[0], AK.shape[0]
    try:
        E = _inverse(np.eye(DK.shape[0]) - DK @ D22)
    except np.linalg.LinAlgError:
        raise ValueError("the loop is not well posed: I − DK D22 is singular") from None
    # u = Ux [x; xK] + Uw w and y = Yx [x; xK] + Yw w
    Ux, Uw = E @ np.hstack([DK @ C2, CK]), E @ DK @ D21
    Yx, Yw = np.hstack([C2, np.zeros((C2.shape[0], nk))]) + D22 @ Ux, D21 + D22 @ Uw
    Acl = np.block([[A, np.zeros((n, nk))], [np.zeros((nk, n)), AK]]) + np.vstack([B2 @ Ux, BK @ Yx])
    Bcl = np.vstack([B1 + B2 @ Uw, BK @ Yw])
    Ccl = np.hstack([C1, np.zeros((C1.shape[0], nk))]) + D12 @ Ux
    return Realisation(Acl, Bcl, Ccl, D11 + D12 @ Uw, dt)


def closed_loop_realisation(data: dict, design) -> Realisation:
    """The closed loop from w to z of the generalized plant ``data`` with the controller or
    state-feedback gain ``design`` (a :class:`~lmidsl.numeric.design.Design`), by :func:`lower_lft`."""
    gain = design.kind == "gain" or (design.kind == "unspecified" and "K" in design and "AK" not in design)
    return lower_lft(_plant_arrays(data, state_feedback=gain), _design_arrays(design),
                     timebase(design.time, design.sample_time))


def filtering_error_realisation(data: dict, design) -> Realisation:
    """The filtering-error system from w to e = z − ẑ for the plant x' = A x + B1 w,
    z = C1 x + D11 w, y = C2 x + D21 w and the filter ``design`` (ẑ = F y): the lower LFT of the
    plant with u = ẑ entering z through −I and nowhere else (B2 = 0, D12 = −I, D22 = 0)."""
    A, C1, C2 = (_m(data, k) for k in ("A", "C1", "C2"))
    p1 = C1.shape[0]
    plant = dict(data, B2=np.zeros((A.shape[0], p1)), D12=-np.eye(p1), D22=np.zeros((C2.shape[0], p1)))
    return lower_lft(_plant_arrays(plant), _design_arrays(design), timebase(design.time, design.sample_time))


def closed_loop(data: dict, design) -> control.StateSpace:
    """:func:`closed_loop_realisation` as a python-control ``StateSpace``."""
    return closed_loop_realisation(data, design).as_statespace()


def filtering_error(data: dict, design) -> control.StateSpace:
    """:func:`filtering_error_realisation` as a python-control ``StateSpace``."""
    return filtering_error_realisation(data, design).as_statespace()


PLANT = ("A", "B1", "B2", "C1")
FILTER_PLANT = ("A", "B1", "C1", "C2")


@dataclass(frozen=True)
class DesignKind:
    """What a kind of design is called, which matrices it has, and the loop it closes.

    ``loop(data, design)`` forms the loop from the plant ``data`` (gallery names, ``needs``) as a
    :class:`Realisation` (:func:`lower_lft`); ``signal`` names its input and output; ``loop_words`` what it is."""

    name: str
    noun: str
    matrices: tuple
    needs: tuple = ()
    loop: Callable | None = None
    signal: str = "w -> z"
    loop_words: str = "closed loop"


DESIGN_KIND_TABLE = {k.name: k for k in (
    DesignKind("filter", "filter", ("Af", "Bf", "Cf", "Df"), FILTER_PLANT, filtering_error_realisation,
               "w -> e", "filtering-error system"),
    DesignKind("controller", "output-feedback controller", ("AK", "BK", "CK", "DK"), PLANT + ("C2",),
               closed_loop_realisation, "w -> z", "closed loop"),
    DesignKind("gain", "state-feedback gain", ("K",), PLANT, closed_loop_realisation, "w -> z", "closed loop"),
    DesignKind("observer", "observer", ("L",), (), None, "w -> e", "estimation-error system"),
    DesignKind("unspecified", "design", (), (), None, "", ""),
)}
"""One entry per kind (``Theorem(..., designs=KIND)``): its words and its loop."""


def design_kind(name: str | None) -> DesignKind:
    """The table entry of a design kind ('unspecified' for None or an unknown name)."""
    return DESIGN_KIND_TABLE.get(name or "unspecified", DESIGN_KIND_TABLE["unspecified"])


def design_loop(data: dict, design):
    """The loop ``design`` closes with the plant in ``data`` (gallery names), as its kind says
    (:data:`DESIGN_KIND_TABLE`), or None when the kind has no loop or the data are not such a
    plant (other names, or a polytope: per-vertex lists)."""
    if design is None or any(isinstance(v, list) and v and isinstance(v[0], np.ndarray)
                             for v in data.values()):
        return None
    kind = design_kind(design.kind)
    if kind.loop is None or not all(k in data for k in kind.needs):
        return None
    if not all(k in design for k in kind.matrices if k not in ("Df", "DK")):
        return None
    return kind.loop(data, design)


def loop_summary(system: Realisation, signal: str = "w -> z") -> dict:
    """What a user wants to know of a closed loop: stability (all poles in the open left
    half-plane or the open unit disk), the largest pole real part / modulus, and the H∞ norm
    (SLICOT AB13DD, python-control's routine) and H2 norm (:func:`h2_norm`); ``None`` when the
    loop is unstable."""
    poles = np.linalg.eigvals(system.A) if system.nstates else np.zeros(0)
    ct = system.isctime()
    time = "continuous" if ct else "discrete"
    worst = float(np.max(poles.real if ct else np.abs(poles))) if poles.size else None
    stable = worst is None or (worst < 0 if ct else worst < 1)
    out = {"signal": signal, "states": int(system.nstates), "stable": bool(stable),
           "max_pole_real" if ct else "max_pole_modulus": worst, "hinf_norm": None, "h2_norm": None}
    if stable:
        out["hinf_norm"] = float(hinf_norm(system.A, system.B, system.C, system.D, time))
        has_feedthrough = ct and np.any(np.asarray(system.D) != 0)
        out["h2_norm"] = None if has_feedthrough else h2_norm(system, time)
    return out


def h2_norm(system: Realisation, time: str) -> float:
    """‖G‖₂ of a stable system: √tr(C W Cᵀ + [discrete] D Dᵀ), W the controllability Gramian
    (A W + W Aᵀ + B Bᵀ = 0, or A W Aᵀ − W + B Bᵀ = 0); continuous time with D = 0."""
    from scipy.linalg import solve_continuous_lyapunov, solve_discrete_lyapunov
    A, B, C, D = system.A, system.B, system.C, system.D
    value = float(np.sum(D * D)) if time == "discrete" else 0.0
    if system.nstates:
        W = solve_continuous_lyapunov(A, -B @ B.T) if time == "continuous" else solve_discrete_lyapunov(A, B @ B.T)
        value += float(np.trace(C @ W @ C.T))
    return float(np.sqrt(max(value, 0.0)))


__all__ = ["timebase", "statespace", "design_statespace", "generalized_plant", "closed_loop",
           "filtering_error", "closed_loop_realisation", "filtering_error_realisation", "lower_lft",
           "Realisation", "ball_loop", "design_loop", "loop_summary", "h2_norm", "DesignKind", "DESIGN_KIND_TABLE",
           "design_kind"]
