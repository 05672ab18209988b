"""Designs as python-control systems, and the loops they close.

An independent check of a synthesis result should not reuse the formulas the theorem was
written with.  This module builds the plant and the design as python-control ``StateSpace``
objects and closes the loop with python-control's own linear fractional transformation
(``StateSpace.lft``, the Redheffer lower LFT), so the closed loop (or filtering-error system)
whose norm a test measures is formed by code independent of lmidsl's symbolic closed loops
(:func:`lmidsl.closed_loop_matrices`).

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

from ..errors import InputError

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
    return np.atleast_2d(np.asarray(data[name], dtype=float))


def statespace(A, B, C, D, dt) -> control.StateSpace:
    """A ``StateSpace`` from arrays, including the static case (no state: A is 0 × 0)."""
    import control     # 1–2 s to import (scipy.signal, matplotlib): only when a loop is formed
    return control.ss(np.atleast_2d(A) if np.size(A) else np.zeros((0, 0)), B, C, D, dt)


def design_statespace(design) -> control.StateSpace:
    """The design as a system: controller (AK, BK, CK, DK) from y to u, filter (Af, Bf, Cf, Df)
    from y to ẑ, or a static gain K as a D-only system (no state).  A missing DK / Df is 0."""
    dt = timebase(design.time, design.sample_time)
    for a, b, c, d in (("AK", "BK", "CK", "DK"), ("Af", "Bf", "Cf", "Df")):
        if a in design and b in design and c in design:
            C = _m(design, c)
            D = _m(design, d) if d in design else np.zeros((C.shape[0], _m(design, b).shape[1]))
            return statespace(_m(design, a), _m(design, b), C, D, dt)
    if "K" in design:
        K = _m(design, "K")
        return statespace(np.zeros((0, 0)), np.zeros((0, K.shape[1])), np.zeros((K.shape[0], 0)), K, dt)
    raise InputError(f"a {design.kind} design with matrices {', '.join(design)} is not a controller "
                     "(AK, BK, CK[, DK]), a filter (Af, Bf, Cf[, Df]) or a gain (K)")


def generalized_plant(data: dict, time: str, sample_time: float | None = None,
                      state_feedback: bool = False) -> tuple[control.StateSpace, int, int]:
    """(P, number of controls, number of measurements): P from [w; u] to [z; y].

    ``state_feedback``: the measurement is the state (C2 = I, D21 = 0, D22 = 0), as for a gain
    u = K x.  Missing D11, D12, D21, D22 are zero.
    """
    import control     # 1–2 s to import (scipy.signal, matplotlib): only when a loop is formed
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
    P = control.ss(A, np.hstack([B1, B2]), np.vstack([C1, C2]),
                   np.block([[D11, D12], [D21, D22]]), timebase(time, sample_time))
    return P, m2, C2.shape[0]


def closed_loop(data: dict, design) -> control.StateSpace:
    """The closed loop from w to z of the generalized plant ``data`` with the controller or
    state-feedback gain ``design`` (a :class:`~lmidsl.numeric.design.Design`), by python-control's
    lower LFT."""
    K = design_statespace(design)
    P, nu, ny = generalized_plant(data, design.time, design.sample_time,
                                  state_feedback=design.kind == "gain" or (design.kind == "unspecified"
                                                                        and "K" in design and "AK" not in design))
    return P.lft(K, nu, ny)


def filtering_error(data: dict, design) -> control.StateSpace:
    """The filtering-error system from w to e = z − ẑ for the plant x' = A x + B1 w,
    z = C1 x + D11 w, y = C2 x + D21 w and the filter ``design`` (ẑ = F y).

    Formed as the lower LFT of the plant with u = ẑ entering z through −I and nowhere else
    (B2 = 0, D12 = −I, D22 = 0).
    """
    F = design_statespace(design)
    A, B1, C1, C2 = (_m(data, k) for k in ("A", "B1", "C1", "C2"))
    p1 = C1.shape[0]
    plant = dict(data, B2=np.zeros((A.shape[0], p1)), D12=-np.eye(p1),
                 D22=np.zeros((C2.shape[0], p1)))
    P, nu, ny = generalized_plant(plant, design.time, design.sample_time)
    return P.lft(F, nu, ny)


PLANT = ("A", "B1", "B2", "C1")
FILTER_PLANT = ("A", "B1", "C1", "C2")


@dataclass(frozen=True)
class DesignKind:
    """What a kind of design is called, which matrices it has, and the loop it closes.

    ``loop(data, design)`` forms the loop from the plant ``data`` (gallery names, ``needs``) by
    python-control's LFT; ``signal`` names its input and output; ``loop_words`` what it is."""

    name: str
    noun: str
    matrices: tuple
    needs: tuple = ()
    loop: Callable | None = None
    signal: str = "w -> z"
    loop_words: str = "closed loop"


DESIGN_KIND_TABLE = {k.name: k for k in (
    DesignKind("filter", "filter", ("Af", "Bf", "Cf", "Df"), FILTER_PLANT, filtering_error,
               "w -> e", "filtering-error system"),
    DesignKind("controller", "output-feedback controller", ("AK", "BK", "CK", "DK"), PLANT + ("C2",),
               closed_loop, "w -> z", "closed loop"),
    DesignKind("gain", "state-feedback gain", ("K",), PLANT, closed_loop, "w -> z", "closed loop"),
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


def loop_summary(system, signal: str = "w -> z") -> dict:
    """What a user wants to know of a closed loop: stability (all poles in the open left
    half-plane or the open unit disk), the largest pole real part / modulus, and the H∞ and H2
    norms by python-control (SLICOT; ``None`` when the loop is unstable)."""
    import control     # 1–2 s to import (scipy.signal, matplotlib): only when a loop is formed
    poles = np.linalg.eigvals(system.A) if system.nstates else np.zeros(0)
    ct = system.isctime()
    worst = float(np.max(poles.real if ct else np.abs(poles))) if poles.size else None
    stable = worst is None or (worst < 0 if ct else worst < 1)
    out = {"signal": signal, "states": int(system.nstates), "stable": bool(stable),
           "max_pole_real" if ct else "max_pole_modulus": worst, "hinf_norm": None, "h2_norm": None}
    if stable:
        out["hinf_norm"] = float(control.norm(system, "inf", tol=1e-10))
        has_feedthrough = ct and np.any(np.asarray(system.D) != 0)
        out["h2_norm"] = None if has_feedthrough else float(control.norm(system, 2))
    return out


__all__ = ["timebase", "statespace", "design_statespace", "generalized_plant", "closed_loop",
           "filtering_error", "design_loop", "loop_summary", "DesignKind", "DESIGN_KIND_TABLE",
           "design_kind"]
