"""Theorem 3 of seed 000 ((30), (31), P1 > 0, P3 > 0, min γ²; E = I) written by hand in cvxpy:
what a user would type without lmidsl.  No lmidsl import, so that as a script it is the reference
of ``bench_solve.py``:

    python benchmarks/hand_thm3.py DATA.json     # A, B, C, D, L, E, rbar -> γ and the filter

solves with Clarabel and recovers the filter by (32): Af = V2⁻¹Âf, Bf = V2⁻¹B̂f, Cf = Ĉf.
``bench_compile.py`` imports the model builder.
"""
from __future__ import annotations

import json
import sys

import cvxpy as cp
import numpy as np

MARGIN = 1e-7          # lmidsl's default strictness margin: N ⪯ −1e-7 I
M_IN, NY, P_OUT = 2, 2, 1
RBAR = 0.8


def random_plant(n: int, rng: np.random.Generator) -> dict:
    A = rng.standard_normal((n, n))
    A *= 0.9 / max(abs(np.linalg.eigvals(A)))
    return {"A": A, "B": rng.standard_normal((n, M_IN)), "C": rng.standard_normal((NY, n)),
            "D": rng.standard_normal((NY, M_IN)), "L": rng.standard_normal((P_OUT, n)),
            "E": np.eye(n)}


def hand_written(d: dict, use_parameters: bool, rbar: float = RBAR, variables: dict | None = None) -> cp.Problem:
    """(30), (31), P1 > 0, P3 > 0 and min γ² written directly in cvxpy (E = I, k = n)."""
    A, B, C, D, L, E = (d[k] for k in "ABCDLE")
    n, k, m, p = A.shape[0], E.shape[1], B.shape[1], L.shape[0]
    if use_parameters:
        r = cp.Parameter(value=rbar)
        a = cp.Parameter(value=(1 - rbar) * rbar)
    else:
        r, a = rbar, (1 - rbar) * rbar
    eps = MARGIN
    P1 = cp.Variable((n, n), symmetric=True)
    P2 = cp.Variable((n, k))
    P3 = cp.Variable((k, k), symmetric=True)
    V1, V2, V3 = cp.Variable((n, n)), cp.Variable((k, k)), cp.Variable((n, k))
    Ah, Bh, Ch = cp.Variable((k, k)), cp.Variable((k, C.shape[0])), cp.Variable((p, k))
    g = cp.Variable()
    W11 = P1 - V1 - V1.T
    W21 = P2.T - V3.T - V2.T @ E.T
    W22 = P3 - V2 - V2.T
    Z = np.zeros
    r41 = V1.T @ A + r * (E @ Bh @ C)
    r42 = E @ Ah
    r43 = V1.T @ B + E @ Bh @ D
    r51 = V3.T @ A + r * (Bh @ C)
    r53 = V3.T @ B + Bh @ D
    r61 = a * (E @ Bh @ C)
    r71 = a * (Bh @ C)
    M30 = cp.bmat([
        [-P1, -P2, Z((n, m)), r41.T, r51.T, r61.T, r71.T],
        [-P2.T, -P3, Z((k, m)), r42.T, Ah.T, Z((k, n)), Z((k, k))],
        [Z((m, n)), Z((m, k)), -np.eye(m), r43.T, r53.T, Z((m, n)), Z((m, k))],
        [r41, r42, r43, W11, W21.T, Z((n, n)), Z((n, k))],
        [r51, Ah, r53, W21, W22, Z((k, n)), Z((k, k))],
        [r61, Z((n, k)), Z((n, m)), Z((n, n)), Z((n, k)), a * W11, a * W21.T],
        [r71, Z((k, k)), Z((k, m)), Z((k, n)), Z((k, k)), a * W21, a * W22],
    ])
    M31 = cp.bmat([[-P1, -P2, L.T], [-P2.T, -P3, -Ch.T], [L, -Ch, -g * np.eye(p)]])
    size30 = 3 * n + 3 * k + m
    cons = [M30 << -eps * np.eye(size30), M31 << -eps * np.eye(n + k + p),
            P1 >> eps * np.eye(n), P3 >> eps * np.eye(k)]
    if variables is not None:
        variables.update(V2=V2, Ah=Ah, Bh=Bh, Ch=Ch, g=g)
    return cp.Problem(cp.Minimize(g), cons)


def main(path: str) -> None:
    with open(path) as fh:
        raw = json.load(fh)
    d = {k: np.array(raw[k], dtype=float) for k in "ABCDLE"}
    v: dict = {}
    problem = hand_written(d, False, rbar=float(raw["rbar"]), variables=v)
    problem.solve(solver=cp.CLARABEL)
    V2inv = np.linalg.inv(v["V2"].value)
    Af, Bf, Cf = V2inv @ v["Ah"].value, V2inv @ v["Bh"].value, v["Ch"].value
    print(json.dumps({"status": problem.status, "gamma": float(np.sqrt(v["g"].value)),
                      "Af": Af.tolist(), "Bf": Bf.tolist(), "Cf": Cf.tolist()}))


if __name__ == "__main__":
    main(sys.argv[1])
