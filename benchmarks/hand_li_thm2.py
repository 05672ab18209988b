"""Theorem 2 of seed 001 ((15), min β = γ²) written by hand in cvxpy: what a user would type
without lmidsl.  No lmidsl import, so that as a script it is a reference of ``bench_solve.py``:

    python benchmarks/hand_li_thm2.py DATA.json     # A, B, C1, C2, D1, D2, xi1, xi2 -> γ and the filter

The user has to know one thing lmidsl does by itself: Clarabel fails (NumericalError) on the
paper's data as printed, and succeeds once the measurement is rescaled, y' = y/32 (C1, C2
divided by 32; the filter's Bf, Df divided by 32 afterwards).  Solves with Clarabel and
recovers the filter with R = I − XZ⁻¹, S = I: Af = R⁻¹ÂfZ⁻¹, Bf = R⁻¹B̂f, Cf = ĈfZ⁻¹, Df = D̂f.
"""
from __future__ import annotations

import json
import sys

import cvxpy as cp
import numpy as np

MARGIN = 1e-7          # lmidsl's default strictness margin: N ⪯ −1e-7 I
Y_SCALE = 32.0


def augmented(d: dict, xi1: float, xi2: float) -> dict:
    """Φ̄, Φ1, Φ2, Γ̄, Γ1, Γ2, H̄, H1, D̄1 of (5) and the weights of Theorem 1."""
    A, B, C1, C2, D1 = (d[k] for k in ("A", "B", "C1", "C2", "D1"))
    n, r, p, m = A.shape[0], C1.shape[0], B.shape[1], D1.shape[0]
    Z, I = np.zeros, np.eye
    Phi0 = np.block([[A, Z((n, r)), Z((n, r))], [Z((r, n)), I(r), Z((r, r))], [Z((r, n)), I(r), Z((r, r))]])
    Phi1 = np.block([[Z((n, n)), Z((n, r)), Z((n, r))], [C1, -I(r), Z((r, r))], [C1, -I(r), Z((r, r))]])
    Phi2 = np.block([[Z((n, n)), Z((n, r)), Z((n, r))], [C1, -I(r), Z((r, r))], [Z((r, n)), Z((r, r)), Z((r, r))]])
    G0 = np.vstack([B, Z((r, p)), Z((r, p))])
    G1 = np.vstack([Z((n, p)), C2, C2])
    G2 = np.vstack([Z((n, p)), C2, Z((r, p))])
    H0 = np.hstack([Z((r, n)), I(r), Z((r, r))])
    H1 = np.hstack([C1, -I(r), Z((r, r))])
    th1, th2 = xi1, (1 - xi1) * xi2
    return dict(Phibar=Phi0 + th1 * Phi1 + th2 * Phi2, Phi1=Phi1, Phi2=Phi2, Gbar=G0 + th1 * G1 + th2 * G2,
                G1=G1, G2=G2, Hbar=H0 + th1 * H1, H1=H1, D1bar=np.hstack([D1, Z((m, r)), Z((m, r))]),
                th1=th1, s1=np.sqrt(xi1 * (1 - xi1) * (1 - xi2)), s2=np.sqrt((1 - xi1) ** 2 * (1 - xi2) * xi2),
                s3=np.sqrt(xi1 * xi2 * (1 - xi1)), s4=np.sqrt(xi1 * (1 - xi1)))


def hand_written(d: dict, xi1: float, xi2: float, variables: dict) -> cp.Problem:
    """(15) and min β written directly in cvxpy."""
    a = augmented(d, xi1, xi2)
    C2, D2 = d["C2"], d["D2"]
    na, r, p, m = a["Phibar"].shape[0], C2.shape[0], C2.shape[1], D2.shape[0]
    X = cp.Variable((na, na), symmetric=True)
    Z = cp.Variable((na, na), symmetric=True)
    Ah, Bh = cp.Variable((na, na)), cp.Variable((na, r))
    Ch, Dh = cp.Variable((m, na)), cp.Variable((m, r))
    beta = cp.Variable()
    Lam = cp.bmat([[X, Z], [Z, Z]])

    def theta_A(top, bottom, extra=None):
        return cp.bmat([[top, top + extra if extra is not None else top], [bottom, bottom]])

    s1, s2, s3, s4, th1 = a["s1"], a["s2"], a["s3"], a["s4"], a["th1"]
    TA = [theta_A(X @ a["Phibar"] + Bh @ a["Hbar"], Z @ a["Phibar"], Ah),
          s1 * theta_A(X @ a["Phi1"] + Bh @ a["H1"], Z @ a["Phi1"]),
          s2 * theta_A(X @ a["Phi2"], Z @ a["Phi2"]),
          s3 * theta_A(X @ (a["Phi1"] - a["Phi2"]) + Bh @ a["H1"], Z @ (a["Phi1"] - a["Phi2"]))]
    TB = [cp.vstack([X @ a["Gbar"] + th1 * Bh @ C2, Z @ a["Gbar"]]),
          s1 * cp.vstack([X @ a["G1"] + Bh @ C2, Z @ a["G1"]]),
          s2 * cp.vstack([X @ a["G2"], Z @ a["G2"]]),
          s3 * cp.vstack([X @ (a["G1"] - a["G2"]) + Bh @ C2, Z @ (a["G1"] - a["G2"])])]
    Gbar = a["D1bar"] - Dh @ a["Hbar"]
    TG = [cp.hstack([Gbar, Gbar - Ch]), s4 * cp.hstack([-Dh @ a["H1"], -Dh @ a["H1"]])]
    TF = [D2 - th1 * Dh @ C2, -s4 * Dh @ C2]
    k = 2 * na
    O = np.zeros
    rows = [[-Lam, O((k, p))] + [TA[i].T for i in range(4)] + [TG[0].T, TG[1].T],
            [O((p, k)), -beta * np.eye(p)] + [TB[i].T for i in range(4)] + [TF[0].T, TF[1].T]]
    for i in range(4):
        rows.append([TA[i], TB[i]] + [-Lam if j == i else O((k, k)) for j in range(4)] + [O((k, m)), O((k, m))])
    for i in range(2):
        rows.append([TG[i], TF[i]] + [O((m, k))] * 4 + [-np.eye(m) if j == i else O((m, m)) for j in range(2)])
    N = cp.bmat(rows)
    size = N.shape[0]
    variables.update(X=X, Z=Z, Ah=Ah, Bh=Bh, Ch=Ch, Dh=Dh, beta=beta)
    return cp.Problem(cp.Minimize(beta), [N << -MARGIN * np.eye(size)])


def main(path: str) -> None:
    with open(path) as fh:
        raw = json.load(fh)
    d = {k: np.array(raw[k], dtype=float) for k in ("A", "B", "C1", "C2", "D1", "D2")}
    d["C1"], d["C2"] = d["C1"] / Y_SCALE, d["C2"] / Y_SCALE        # y' = y / 32
    v: dict = {}
    problem = hand_written(d, float(raw["xi1"]), float(raw["xi2"]), v)
    problem.solve(solver=cp.CLARABEL)
    X, Z = v["X"].value, v["Z"].value
    Zinv = np.linalg.inv(Z)
    Rinv = np.linalg.inv(np.eye(len(X)) - X @ Zinv)
    Af, Bf = Rinv @ v["Ah"].value @ Zinv, Rinv @ v["Bh"].value / Y_SCALE
    Cf, Df = v["Ch"].value @ Zinv, v["Dh"].value / Y_SCALE
    print(json.dumps({"status": problem.status, "gamma": float(np.sqrt(v["beta"].value)),
                      "Af": Af.tolist(), "Bf": Bf.tolist(), "Cf": Cf.tolist(), "Df": Df.tolist()}))


if __name__ == "__main__":
    main(sys.argv[1])
