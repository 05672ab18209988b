"""The proved lower end of H∞ output-feedback designs (lmidsl.certify.frequency_bound, "Output
feedback"): the full-information and full-control state-feedback certificates inside the
output-feedback LMI, checked against SLICOT's output-feedback syntheses (SB10FD / SB10DD, each
level's closed loop measured by python-control) on a published plant, its transpose and its
discretisation, and refused on theorems that state another LMI.

The plant is COMPleib's AC4 (missile autopilot; B. Fares, P. Apkarian, D. Noll, "An augmented
Lagrangian method for a class of LMI-constrained problems in robust control theory", Int. J.
Control 74(4), 348–360, 2001; F. Leibfritz, COMPleib, 2004).  Before this bound its bracket was
[0.0378, 0.5589]: the dual route's lower end, 93 % wide.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.signal import cont2discrete

import lmidsl
from lmidsl import He, I, Theorem
from lmidsl.certify.frequency_bound import frequency_lower_bound, output_feedback_lmi
from lmidsl.numeric.instance import bind
from lmidsl.numeric.systems import hinf_norm

AC4 = dict(A=[[-0.876, 1, -0.1209, 0], [8.9117, 0, -130.75, 0], [0, 0, -150, 0], [-1, 0, 0, -0.05]],
           B1=[[0, 0], [0, 0], [0, 0], [0, 1]], B2=[[0], [0], [150], [0]],
           C1=[[-0.25, 0, 0, 3.487], [0, 0, -3, 0]], C2=[[-1, 0, 0, 0], [0, -1, 0, 0]],
           D11=[[0, 0.25], [0, 0]], D12=[[0], [3]], D21=[[0, 1], [0.01, 0]])
PLANT = ("A", "B1", "B2", "C1", "C2", "D11", "D12", "D21")


def _arrays(d: dict) -> dict:
    return {k: np.array(v, dtype=float) for k, v in d.items()}


def _with_d22(d: dict) -> dict:
    out = {k: np.asarray(v, dtype=float).tolist() for k, v in d.items()}
    out["D22"] = np.zeros((len(d["C2"]), np.asarray(d["B2"]).shape[1])).tolist()
    return out


def _plain(d: dict) -> dict:
    """The plant's matrices as lists, without D22 (a user theorem's data)."""
    return {k: np.asarray(v, dtype=float).tolist() for k, v in d.items()}


def _transposed(d: dict) -> dict:
    """The dual plant (Aᵀ, C1ᵀ, C2ᵀ, B1ᵀ, B2ᵀ, D11ᵀ, D21ᵀ, D12ᵀ): the same output-feedback optimum."""
    P = _arrays(d)
    return dict(A=P["A"].T, B1=P["C1"].T, B2=P["C2"].T, C1=P["B1"].T, C2=P["B2"].T, D11=P["D11"].T,
                D12=P["D21"].T, D21=P["D12"].T)


def _discretised(d: dict, h: float = 0.05) -> dict:
    """Zero-order hold of (A, [B1 B2]) at step h; C and D unchanged."""
    P = _arrays(d)
    n, m1 = P["A"].shape[0], P["B1"].shape[1]
    B = np.hstack([P["B1"], P["B2"]])
    Ad, Bd, *_ = cont2discrete((P["A"], B, np.eye(n), np.zeros((n, B.shape[1]))), h)
    return dict(P, A=Ad, B1=Bd[:, :m1], B2=Bd[:, m1:])


def _closed_loop(P: dict, K) -> tuple:
    AK, BK, CK, DK = (np.atleast_2d(k) for k in K)
    A = np.block([[P["A"] + P["B2"] @ DK @ P["C2"], P["B2"] @ CK], [BK @ P["C2"], AK]])
    B = np.vstack([P["B1"] + P["B2"] @ DK @ P["D21"], BK @ P["D21"]])
    C = np.hstack([P["C1"] + P["D12"] @ DK @ P["C2"], P["D12"] @ CK])
    D = P["D11"] + P["D12"] @ DK @ P["D21"]
    return A, B, C, D


def _slicot_level(d: dict, time: str) -> float:
    """The least level (bisection to 1e-6) at which SLICOT's H∞ synthesis (SB10FD, SB10DD) returns a
    controller whose closed loop, measured by python-control, meets it: an achieved level, so ≥ the
    output-feedback optimum, and independent of lmidsl."""
    from slycot import sb10dd, sb10fd
    P = _arrays(d)
    n, m2, p2 = P["A"].shape[0], P["B2"].shape[1], P["C2"].shape[0]
    B = np.hstack([P["B1"], P["B2"]])
    C = np.vstack([P["C1"], P["C2"]])
    D = np.block([[P["D11"], P["D12"]], [P["D21"], np.zeros((p2, m2))]])

    def meets(gamma: float) -> bool:
        try:
            if time == "continuous":
                K = sb10fd(n, B.shape[1], C.shape[0], m2, p2, gamma, P["A"], B, C, D)[:4]
            else:
                K = sb10dd(n, B.shape[1], C.shape[0], m2, p2, gamma, P["A"], B, C, D)[1:5]
        except Exception:        # noqa: BLE001 — SLICOT's "no controller at this level"
            return False
        return hinf_norm(*_closed_loop(P, K), time) < gamma * (1 + 1e-9)

    lo, hi = 0.0, 1e4
    assert meets(hi)
    while hi - lo > 1e-6 * hi:
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if meets(mid) else (mid, hi)
    return hi


def _lower_end(d: dict, time: str) -> tuple[float, str]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = lmidsl.solve(f"textbook.hinf_of_{time[0]}t", data=_with_d22(d))
    box = sol.verdict.bracket
    assert box["lower_proved"] and box["upper_proved"], box
    assert box["lower"] <= box["upper"]
    return box["lower"], sol.bounds.how


@pytest.mark.parametrize("time", ["continuous", "discrete"])
def test_a_published_plant_and_its_transpose_get_the_slicot_level(time):
    """AC4 (and its zero-order-hold discretisation at h = 0.05): the proved lower end lies below
    SLICOT's achieved level and within 1e-4 of it (the optimum is set by the full-information
    Riccati equation); the transposed plant, whose optimum is the same, gets the same end from
    the full-control rows.  (In continuous time the coupled certificate, which contains both,
    may come out higher in the last digits and be the one reported.)  The reference is the lower of SLICOT's achieved levels on the plant
    and on its transpose (both are ≥ the optimum; they differ by up to 6e-4: SLICOT's bisection
    is not monotone so close to the optimum)."""
    plant = AC4 if time == "continuous" else _discretised(AC4)
    transposed = _transposed(plant)
    reference = min(_slicot_level(plant, time), _slicot_level(transposed, time))
    lower, how = _lower_end(plant, time)
    assert how.startswith(("full information", "coupled"))
    assert reference * (1 - 1e-4) <= lower <= reference
    lower_t, how_t = _lower_end(transposed, time)
    assert how_t.startswith(("full control", "coupled"))
    assert abs(lower_t - lower) <= 1e-9 * lower


def _of_theorem(name: str, time: str, rows=None, xy: bool = True):
    """textbook.hinf_of_ct's (continuous) LMI as a user states it, or ``rows`` instead; with or
    without [[X, I], [I, Y]] ≻ 0."""
    thm = Theorem(f"adv.{name}", time=time)
    n, m1, m2, p1, p2 = thm.dim("n m1 m2 p1 p2")
    shapes = dict(A=(n, n), B1=(n, m1), B2=(n, m2), C1=(p1, n), C2=(p2, n), D11=(p1, m1), D12=(p1, m2),
                  D21=(p2, m1))
    A, B1, B2, C1, C2, D11, D12, D21 = (thm.data(k, *shapes[k]) for k in PLANT)
    X, Y = thm.var("X", n, kind="symmetric"), thm.var("Y", n, kind="symmetric")
    Ah, Bh, Ch, Dh = thm.var("Ah", n, n), thm.var("Bh", n, p2), thm.var("Ch", m2, n), thm.var("Dh", m2, p2)
    g = thm.scalar("g")
    stated = rows or _stated
    thm.lmi("(OF)", stated(A, B1, B2, C1, C2, D11, D12, D21, X, Y, Ah, Bh, Ch, Dh, g))
    if xy == "apart":
        thm.positive(X)
        thm.positive(Y)
    elif xy:
        thm.lmi("(XY)", [[X], [I, Y]], sense=">")
    thm.minimize(g)
    thm.output_feedback_form(X, Y, Ah, Bh, Ch, Dh, g, (A, B1, B2, C1, C2, D11, D12, D21))
    return thm


def _stated(A, B1, B2, C1, C2, D11, D12, D21, X, Y, Ah, Bh, Ch, Dh, g):
    return [[He(A * X + B2 * Ch)],
            [Ah + (A + B2 * Dh * C2).T, He(Y * A + Bh * C2)],
            [(B1 + B2 * Dh * D21).T, (Y * B1 + Bh * D21).T, -g * I],
            [C1 * X + D12 * Ch, C1 + D12 * Dh * C2, D11 + D12 * Dh * D21, -g * I]]


def test_the_form_as_a_user_states_it_is_recognised_and_bounded():
    thm = _of_theorem("same", "continuous")
    assert output_feedback_lmi(thm) is not None
    lower, how = frequency_lower_bound(bind(thm, _plain(AC4)))
    assert how.startswith(("full information", "coupled")) and "Hamiltonian" in how
    assert lower <= 0.5573


def test_without_xy_the_hamiltonian_certificate_is_not_used():
    """Its X terms are ≥ 0 only for X ⪰ 0: without (XY) the frequency response alone bounds γ."""
    data = _plain(AC4)
    with_xy = frequency_lower_bound(bind(_of_theorem("with_xy", "continuous"), data))
    without = frequency_lower_bound(bind(_of_theorem("without_xy", "continuous", xy=False), data))
    assert "Hamiltonian" in with_xy[1] and "Hamiltonian" not in without[1]
    assert without[0] < with_xy[0]


@pytest.mark.parametrize("name,rows", [
    ("feedthrough_dropped", lambda A, B1, B2, C1, C2, D11, D12, D21, X, Y, Ah, Bh, Ch, Dh, g:
        [[He(A * X + B2 * Ch)], [Ah + (A + B2 * Dh * C2).T, He(Y * A + Bh * C2)],
         [B1.T, (Y * B1 + Bh * D21).T, -g * I],
         [C1 * X + D12 * Ch, C1 + D12 * Dh * C2, D11 + D12 * Dh * D21, -g * I]]),
    ("level_halved", lambda A, B1, B2, C1, C2, D11, D12, D21, X, Y, Ah, Bh, Ch, Dh, g:
        [[He(A * X + B2 * Ch)], [Ah + (A + B2 * Dh * C2).T, He(Y * A + Bh * C2)],
         [(B1 + B2 * Dh * D21).T, (Y * B1 + Bh * D21).T, -0.5 * g * I],
         [C1 * X + D12 * Ch, C1 + D12 * Dh * C2, D11 + D12 * Dh * D21, -g * I]]),
    ("control_doubled", lambda A, B1, B2, C1, C2, D11, D12, D21, X, Y, Ah, Bh, Ch, Dh, g:
        [[He(A * X + 2 * B2 * Ch)], [Ah + (A + B2 * Dh * C2).T, He(Y * A + Bh * C2)],
         [(B1 + B2 * Dh * D21).T, (Y * B1 + Bh * D21).T, -g * I],
         [C1 * X + D12 * Ch, C1 + D12 * Dh * C2, D11 + D12 * Dh * D21, -g * I]]),
])
def test_a_theorem_that_states_another_lmi_gets_no_bound(name, rows):
    """A bound on the declared form would be false for these: each is refused."""
    thm = _of_theorem(name, "continuous", rows)
    assert output_feedback_lmi(thm) is None
    assert frequency_lower_bound(bind(thm, _plain(AC4))) is None


def _filter_as_controller(d: dict) -> dict:
    """The filtering plant as an output-feedback plant: u = ẑ, B2 = 0, D12 = −I."""
    P = _arrays(d)
    n, p1 = P["A"].shape[0], P["C1"].shape[0]
    return dict(P, B2=np.zeros((n, p1)), D12=-np.eye(p1))


@pytest.mark.parametrize("time", ["continuous", "discrete"])
@pytest.mark.parametrize("k", [2, 5])
def test_a_filter_gets_the_slicot_level_from_the_full_control_rows(time, k):
    """The full-order H∞ filter's optimum is the filtering Riccati equation's (no coupling): the
    full-control rows prove it, within 1e-4 below SLICOT's achieved level for the filter as a
    controller (B2 = 0, D12 = −I)."""
    from theorems.textbook.plants import filter_cases
    _, d = filter_cases(time)[k]
    lower, how = frequency_lower_bound(bind(lmidsl.get_theorem(f"textbook.hinf_filter_{time[0]}t"), d))
    assert how.startswith(("full control", "coupled"))
    reference = _slicot_level(_filter_as_controller(d), time)
    assert reference * (1 - 1e-4) <= lower <= reference


def _random_plant(seed: int) -> dict:
    """A random continuous-time plant with D12 = [0; I], D21 = [0, I] (regular), 2–7 states."""
    rng = np.random.default_rng(seed)
    n, m1, m2, p1, p2 = (int(rng.integers(lo, hi)) for lo, hi in ((2, 8), (1, 4), (1, 3), (1, 4), (1, 3)))
    A = rng.standard_normal((n, n)) * rng.choice([0.5, 1, 2])
    B1, B2 = rng.standard_normal((n, m1)), rng.standard_normal((n, m2))
    C1, C2 = rng.standard_normal((p1, n)), rng.standard_normal((p2, n))
    D11 = 0.3 * rng.standard_normal((p1, m1)) * rng.choice([0, 1])
    return dict(A=A, B1=np.hstack([B1, np.zeros((n, p2))]), B2=B2, C1=np.vstack([C1, np.zeros((m2, n))]), C2=C2,
                D11=np.block([[D11, np.zeros((p1, p2))], [np.zeros((m2, m1 + p2))]]),
                D12=np.vstack([np.zeros((p1, m2)), np.eye(m2)]), D21=np.hstack([np.zeros((p2, m1)), np.eye(p2)]))


@pytest.mark.parametrize("seed", [1, 21])
def test_where_the_coupling_sets_the_optimum_the_coupled_certificate_reaches_it(seed):
    """Plants whose optimum is set by ρ(XY) = γ², above both Riccati levels (seed 1: 19.47 against
    a full-control bound of 17.35; seed 21: 477 against 30.4): the coupled certificate
    (lmidsl.certify.coupling_bound) proves a lower end within 1e-4 below SLICOT's achieved level;
    with X ≻ 0 and Y ≻ 0 stated apart instead of [[X, I], [I, Y]] ≻ 0 it is not used, and the bound
    falls back to the two state-feedback ones."""
    plant = _random_plant(seed)
    reference = _slicot_level(plant, "continuous")
    lower, how = frequency_lower_bound(bind(_of_theorem(f"coupled{seed}", "continuous"), _plain(plant)))
    assert how.startswith("coupled")
    assert reference * (1 - 1e-4) <= lower <= reference
    apart = frequency_lower_bound(bind(_of_theorem(f"apart{seed}", "continuous", xy="apart"), _plain(plant)))
    assert not apart[1].startswith("coupled") and apart[0] < 0.95 * lower


def _random_discrete_plant(seed: int) -> dict:
    """:func:`_random_plant` with A scaled to a spectral radius in (0.5, 1.4)."""
    plant = _random_plant(seed)
    radius = np.random.default_rng(seed + 1000).uniform(0.5, 1.4)
    return dict(plant, A=plant["A"] * radius / max(abs(np.linalg.eigvals(plant["A"]))))


@pytest.mark.parametrize("seed", [0, 13])
def test_in_discrete_time_the_coupled_interpolation_certificates_reach_the_slicot_level(seed):
    """Discrete-time plants whose optimum the coupling sets: two interpolation certificates joined
    through the rows (X, Y) of the LMI prove a lower end within 1e-3 below SLICOT's achieved level
    (SB10DD's bisection is coarser than SB10FD's: on AC4 discretised its achieved level is 6e-4
    above the optimum)."""
    plant = _random_discrete_plant(seed)
    reference = _slicot_level(plant, "discrete")
    lower, how = frequency_lower_bound(bind(lmidsl.get_theorem("textbook.hinf_of_dt"), _with_d22(plant)))
    assert how.startswith("coupled") and "interpolation" in how
    assert reference * (1 - 1e-3) <= lower <= reference


#: COMPleib's AC3 (L-1011 aircraft in cruise; C. Edwards, S. K. Spurgeon, "On the development of
#: discontinuous observers", Int. J. Control 59(5), 1211–1229, 1994) with COMPleib's completion
#: B1 = I, C1 = I, D12 = [0; I], D11 = 0, D21 = 0: a singular problem (no measurement noise)
AC3_A = [[0, 0, 1, 0, 0], [0, -0.154, -0.0042, 1.54, 0], [0, 0.249, -1, -5.2, 0],
         [0.0386, -0.996, -0.0003, -0.117, 0], [0, 0.5, 0, 0, -0.5]]
AC3 = dict(A=AC3_A, B1=np.eye(5), B2=[[0, 0], [-0.744, -0.032], [0.337, -1.12], [0.02, 0], [0, 0]],
           C1=np.eye(5), C2=[[0, 1, 0, 0, -1], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [1, 0, 0, 0, 0]],
           D11=np.zeros((5, 5)), D12=np.vstack([np.zeros((3, 2)), np.eye(2)]), D21=np.zeros((4, 5)))


def _regularised(d: dict, eps: float) -> dict:
    """z and w extended by εu and εv (D12 = [D12; εI], D21 = [D21, εI]): a regular plant whose
    closed loops contain the original's, so any controller's level on it bounds the original's."""
    P = _arrays(d)
    n, m1, m2, p1, p2 = P["A"].shape[0], P["B1"].shape[1], P["B2"].shape[1], P["C1"].shape[0], P["C2"].shape[0]
    D11 = np.zeros((p1 + m2, m1 + p2))
    D11[:p1, :m1] = P["D11"]
    return dict(A=P["A"], B1=np.hstack([P["B1"], np.zeros((n, p2))]), B2=P["B2"],
                C1=np.vstack([P["C1"], np.zeros((m2, n))]), C2=P["C2"], D11=D11,
                D12=np.vstack([P["D12"], eps * np.eye(m2)]), D21=np.hstack([P["D21"], eps * np.eye(p2)]))


def test_a_singular_published_plant_gets_a_tight_lower_end_from_interpolation_certificates():
    """AC3 has D21 = 0: no Hamiltonian certificate for its full-control part and no SLICOT
    synthesis.  Two coupled interpolation certificates (their points from a regularised
    Riccati equation, the certificate the plant's own) prove a lower end below SLICOT's achieved
    level on the ε-regularised plant (ε = 1e-4, an upper bound on AC3's optimum) and within 1e-3
    of it.  Before, AC3's lower end was not proved (the dual route: no dual direction with a
    margin)."""
    reference = _slicot_level(_regularised(AC3, 1e-4), "continuous")
    lower, how = _lower_end(AC3, "continuous")
    assert how.startswith("coupled") and "interpolation" in how
    assert reference * (1 - 1e-3) <= lower <= reference
