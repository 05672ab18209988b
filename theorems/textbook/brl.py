"""The bounded real lemma, continuous and discrete time: the H∞ norm as an LMI optimum.

References: Boyd, El Ghaoui, Feron, Balakrishnan, *Linear Matrix Inequalities in System and
Control Theory*, SIAM 1994, §2.7.3 (bounded-real lemma); Scherer & Weiland, *Linear Matrix
Inequalities in Control*, lecture notes (the bounded real lemma in its LMI form); Gahinet &
Apkarian, "A linear matrix inequality approach to H∞ control", Int. J. Robust Nonlinear
Control 4, 1994 (both time domains, as used for synthesis).

For a system x' = A x + B w, z = C x + D w (x' = ẋ or x(k+1)) with A stable, ‖G‖∞ < γ iff
there is P ≻ 0 with

* continuous time:  [[AᵀP + PA, PB, Cᵀ], [BᵀP, −γ²I, Dᵀ], [C, D, −I]] ≺ 0;
* discrete time:    [[−P, 0, AᵀP, Cᵀ], [0, −γ²I, BᵀP, Dᵀ], [PA, PB, −P, 0], [C, D, 0, −I]] ≺ 0
  (the Schur complement of AᵀPA − P + ... with respect to P and I).

With g = γ² the LMIs are linear in (P, g); min g gives ‖G‖∞² (the infimum is not attained:
the strictness margin of lmidsl puts the optimum a hair above the norm).

:func:`bounded_real` states these LMIs for any expressions A, B, C, D, so the closed-loop
analyses of the synthesis theorems (:mod:`.hinf_sf`, :mod:`.hinf_of`) are the same lemma.
"""
from lmidsl import He, I, Source, Theorem
from sympy import sqrt

from .plants import first_order_dt, random_system, second_order

BOYD = ("Boyd, El Ghaoui, Feron, Balakrishnan, Linear Matrix Inequalities in System and "
        "Control Theory, SIAM 1994")
SOURCE_CT = Source("Boyd et al. 1994", "Sec. 2.7.3, bounded-real lemma", BOYD)
SOURCE_DT = Source("Gahinet & Apkarian 1994", "discrete-time bounded real lemma",
                   "Gahinet, Apkarian, A linear matrix inequality approach to H∞ control, "
                   "Int. J. Robust Nonlinear Control 4:421-448, 1994")


def bounded_real(thm: Theorem, label: str, A, B, C, D, n, *, P_name: str = "P"):
    """Declare P ≻ 0, g = γ² and the bounded-real LMI of (A, B, C, D) in ``thm.time``;
    objective min g with performance γ = √g.  ``n``: the state dimension of A."""
    P = thm.var(P_name, n, kind="symmetric", latex=P_name, description="Lyapunov (storage) matrix")
    g = thm.scalar("g", latex=r"\gamma^2", description="squared H∞ level")
    if thm.time == "continuous":
        thm.lmi(label, [
            [He(P * A)],
            [B.T * P, -g * I],
            [C, D, -I],
        ])
    else:
        thm.lmi(label, [
            [-P],
            [0, -g * I],
            [P * A, P * B, -P],
            [C, D, 0, -I],
        ])
    thm.positive(P)
    thm.minimize(g, performance=("gamma", sqrt(g)))
    thm.bounded_real_form(P, g, (A, B, C, D))
    return P, g


def scale_state(thm: Theorem, rows: tuple, cols: tuple, recovered_cols: tuple = ()):
    """Declare the plant state's exact similarity x = S x' (``rows``: data whose rows are ẋ's,
    ``cols``: data acting on x, ``recovered_cols``: recovered gains acting on x): the library
    balances A with it, and the transfer functions, hence the theorem's level, are unchanged."""
    thm.scale_signal("x", rows=rows, cols=cols, recovered_cols=recovered_cols,
                     description="plant state x = s·x' (a similarity: the transfer functions are unchanged)")


def system_data(thm: Theorem):
    """The system A, B, C, D of the gallery's convention: n states, m inputs w, p outputs z."""
    n, m, p = thm.dim("n m p")
    A = thm.data("A", n, n, description="state matrix")
    B = thm.data("B", n, m, description="input matrix (w)")
    C = thm.data("C", p, n, description="output matrix (z)")
    D = thm.data("D", p, m, description="feedthrough")
    return (n, m, p), (A, B, C, D)


def _brl(name: str, time: str, source: Source) -> Theorem:
    thm = Theorem(f"textbook.{name}", f"Bounded real lemma ({time} time): H∞ norm", source,
                  time=time, description="min γ² over P ≻ 0 such that the bounded-real LMI holds; "
                                         "γ is the H∞ norm of (A, B, C, D).")
    (n, _, _), (A, B, C, D) = system_data(thm)
    bounded_real(thm, "(BRL)", A, B, C, D, n)
    scale_state(thm, ("A", "B"), ("A", "C"))
    return thm


brl_ct = _brl("brl_ct", "continuous", SOURCE_CT)
_resonant, _resonant_norm = second_order(zeta=0.05)
brl_ct.example("resonant", _resonant, printed={"gamma": _resonant_norm},
               printed_note="the resonant peak 1/(2ζ√(1-ζ²)) of wn²/(s²+2ζwn s+wn²), ζ = 0.05",
               provenance="illustration",
               provenance_note="a closed-form example (second-order resonance), not from the book")
brl_ct.example("random-3x2x2", random_system(7, 3, 2, 2, "continuous"), provenance="illustration",
               provenance_note="a random stable system, numpy seed 7 (theorems/textbook/plants.py)")

brl_dt = _brl("brl_dt", "discrete", SOURCE_DT)
_first, _first_norm = first_order_dt(a=0.8)
brl_dt.example("first-order", _first, printed={"gamma": _first_norm},
               printed_note="|b|/(1-|a|) for b/(z-a), a = 0.8", provenance="illustration",
               provenance_note="a closed-form example (first-order low-pass), not from the book")
brl_dt.example("random-3x2x2", random_system(7, 3, 2, 2, "discrete"), provenance="illustration",
               provenance_note="a random Schur-stable system, numpy seed 7 (theorems/textbook/plants.py)")

THEOREMS = [brl_ct, brl_dt]
