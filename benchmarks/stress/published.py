"""Published benchmark plants (COMPleib) for H∞ output- and state-feedback synthesis, continuous
time: does lmidsl prove a lower end of the optimum's bracket, and is every number right?

    python benchmarks/stress/published.py [--only NAME[,NAME...]] [--problems of,sf]
                                          [--timeout 120] [--out FILE] [--json FILE] [--label TEXT]

Runs against whichever ``lmidsl`` is importable.  For another checkout (e.g. ``git archive REV src
theorems`` into DIR): ``PYTHONPATH=DIR/src`` with ``DIR/src/lmidsl/theorems`` a link to
``DIR/theorems`` — without the link the editable install maps ``lmidsl.theorems`` to this
working tree's ``theorems/`` (published_before.txt: DIR = main at cfb2f57).

Data: F. Leibfritz, "COMPleib: COnstrained Matrix-optimization Problem library — a collection of
test examples for nonlinear semidefinite programs, control system design and related problems",
Tech. Report, Universität Trier, 2004 (the MATLAB file COMPleib.m, version 1.1 of 09.03.2005; with
F. Leibfritz and W. Lipinski, "COMPleib 1.0 — user manual and quick reference", 2004).  Only the
numeric matrices of plants given inline with n ≤ 12 are transcribed (:data:`RAW`); where the
file leaves B1 empty its closing lines complete the plant, and so does :func:`complete`:
B1 = I, C1 = I (nz = nx), D12 = [0_{(nz−nu)×nu}; I_nu], D11 = 0, D21 = 0.  D22 = 0 throughout.
Each plant's original source, as the comment above it in COMPleib.m names it:

  AC1, AC2, REA1, REA2, TG1, AGS  Hung & MacFarlane, Multivariable feedback: a quasi-classical
                       approach, LNCIS, Springer 1982 (TG1 p. 117/167, AGS p. 27/163)
  AC3    Edwards & Spurgeon, On the development of discontinuous observers, IJC 59(5), 1994
  AC4    Fares, Apkarian & Noll, An augmented Lagrangian method for a class of LMI-constrained
         problems in robust control theory, IJC 74(4), 2001 (missile autopilot)
  AC6    "the aircraft L-1011 model" (COMPleib names no source)
  AC7, AC8  Gangsaas, Bruce, Blight & Ly, Application of modern synthesis to aircraft control:
         three case studies, IEEE TAC 31(11), 1986 (case studies III 2 and II)
  AC11   Alexandridis & Paraskevopoulos, A new approach to eigenstructure assignment by output
         feedback, IEEE TAC 41(7), 1996, Ex. 2
  AC12   Tøffner-Clausen, System identification and robust control, Springer 1996, p. 274
  AC15, AC16  "Computation of optimal output feedback gains for linear multivariable systems",
         IEEE TAC 19, 1974 (Mach 2.7 supersonic transport)
  AC17   Galimidi & Barmish, The constrained Lyapunov problem and its application to robust
         output feedback stabilization, IEEE TAC 31(5), 1986
  HE1    Singh & Coelho, Nonlinear control of mismatched uncertain linear systems and application
         to control of aircraft, J. Dyn. Sys. Meas. Control 106, 1984
  HE2    Fitzsimons, Reducing the computation required to solve a standard minimax problem,
         Automatica 31, 1995
  HE3, NN13, NN14  Gu, Petkov & Konstantinov, H∞ and H2 optimization toolbox in SLICOT, SLICOT
         Working Note 1999-12 (NN13 p. 15, NN14 p. 19)
  HE5    Skogestad & Postlethwaite, Multivariable feedback control, Wiley 1996, Sec. 12.2
  DIS1   Singh, Brown & Naidu, Unified approach to linear quadratic regulator with time-scale
         property, OCAM 22, 2001
  DIS2   Liu & Sreeram, New algorithm for computing LQ suboptimal output feedback gains of
         decentralized control systems, JOTA 93
  DIS3   Saif & Guan, Decentralized state estimation in large-scale interconnected dynamical
         systems, Automatica 28(1), 1992
  DIS4   Toivonen & Mäkilä, A descent Anderson–Moore algorithm for optimal decentralized
         control, Automatica 21(6), 1985
  BDT1, UWV  Davison (ed.), Benchmark problems for control system design, IFAC Theory Committee
         report, 1990 (UWV p. 32)
  MFP    Scherer, Gahinet & Chilali, Multiobjective output-feedback control via LMI optimization,
         IEEE TAC 42(7), 1997
  EB1, EB2  Geromel & Gapski, Synthesis of positive real H2 controllers, IEEE TAC 42(7), 1997
  PSM    Varga, Model reduction routines for SLICOT, NICONET Report 1999-8; Fosha & Elgerd,
         IEEE Trans. Power Apparatus and Systems 89, 1970
  TF1    Gershon, Shaked & Yaesh, Static output feedback of state multiplicative systems with
         application to terrain following, Tech. Report, Tel-Aviv University, 2003
  NN1, NN4, NN5  Miller, Cochran & Howze, Output feedback stabilization of a spectral radius
         functional, IJC 27, 1978 (NN5: Saturn V booster)
  NN2    Levine & Athans, On the determination of the optimal constant output feedback gains for
         linear multivariable systems, IEEE TAC 15, 1970
  NN3    Scherer, An efficient solution to multi-objective control problems with LMI objectives,
         TU Delft, 2000
  NN8    (COMPleib names no source)
  NN9    Chen, H∞ control and its applications, LNCIS 235, Springer 1998, p. 110
  NN15   Peres & Geromel, An alternate numerical solution to the linear quadratic problem, IEEE
         TAC 39(1), 1994 (space backpack)
  NN16   Calise & Moerder, Optimal output feedback design of systems with ill-conditioned
         dynamics, Automatica 21(3), 1985
  NN17   Gahinet & Laub, Numerically reliable computation of optimal performance in singular H∞
         control, SIAM J. Control Optim. 35(5), 1997
  DLR1   Bals, Aktive Schwingungsdämpfung flexibler Strukturen, Universität Karlsruhe, 1989

Skipped: discrete-time models (AC5, REA4, DIS5), plants loaded from .mat files, plants built by
code (EB3–EB6, CSE, TMD, FS, WEC, HF1), n > 12 (NN11) and the ROC plants (COMPleib augments them
for a reduced-order controller: full-order synthesis on them only repeats the plant).

References (independent of lmidsl; python-control 0.10.2 / slycot / scipy, helpers of ``designs.py``):

* output feedback, only where SB10FD applies (D12 full column rank, D21 full row rank, no zeros of
  P12 = (A, B2, C1, D12) or P21 = (A, B1, C2, D21) on the imaginary axis, (A, B2) stabilisable,
  (C2, A) detectable; otherwise "no reference"): ``ref hi`` = SLICOT SB10FD bisected on the level
  (:func:`sb10fd_bracket`), the least closed-loop norm (``linfnorm``) of a controller that met its
  level — an achieved level, so the optimum is ≤ it; ``ref lo`` = the largest level at which the
  Riccati conditions of Glover & Doyle definitely fail (:func:`dgkf_state`, scipy: an eigenvalue
  of a Hamiltonian on the imaginary axis, X∞ or Y∞ indefinite, or ρ(X∞Y∞) > γ²; bisected to
  1e-8) — the optimum is ≥ it.  (SB10FD's own failures give no floor: below the optimum it
  returns controllers that destabilise the loop.)
* state feedback (C2 = I, D21 = 0), where D12 has full column rank, P12 has no imaginary-axis
  zero and (A, B2) is stabilisable: ``ref hi`` = :func:`designs.sf_hinf_optimum` (the
  full-information Riccati bisection, each level's gain measured in closed loop: an achieved
  level); ``ref lo`` = the full-information Riccati floor (:func:`fi_state`), ≤ the state-feedback
  optimum (loose where D11 ≠ 0: NN13).
  The full-information floor is also a floor under the output-feedback optimum: an
  output-feedback upper end below it is wrong too.

Flags: FALSE — a proved lower end above ``ref hi`` by more than 1e-6 relative, or a proved upper
end / certified design level below ``ref lo`` (for OF also below the full-information floor) by
more than 1e-6 relative; a floor that the delivered design's own closed loop goes below is
reported as refuted instead (REF-REFUTED) and not used.  BADDESIGN — a certified design whose
closed loop (python-control, recomputed from the recovered controller as
``bench_designs.measured`` does) is unstable or has an H∞ norm above the certified level ×
(1 + 1e-6), the norm above the level confirmed by the loop's gain evaluated at 50 digits
(``witnessed_gain``: ``linfnorm`` is wrong on stiff loops).  Each case runs in its own process, killed after ``--timeout`` seconds.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from designs import CT, linf, of_closed_loop, pbh_gap, sb10fd_level, sf_hinf_optimum, stable  # noqa: E402

TOL = 1e-6
R2 = 1 / math.sqrt(2)


# -- transcription helpers (shapes only; every number below is COMPleib's) ---------------------
def _z(r, c):
    return [[0.0] * c for _ in range(r)]


def _eye(n):
    return [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]


def _e(n, *cols):
    """Rows of I_n: row k has its 1 in column cols[k] (1-based, as in the MATLAB file)."""
    return [[1.0 if j == c - 1 else 0.0 for j in range(n)] for c in cols]


def _s(k, M):
    return [[k * x for x in row] for row in M]


def _vstack(*Ms):
    return [list(r) for M in Ms for r in M]


def _hstack(*Ms):
    return [sum((list(M[i]) for M in Ms), []) for i in range(len(Ms[0]))]


def _col(*v):
    return [[x] for x in v]


# -- the plants as COMPleib.m writes them: A, B (= B2), C (= C2), and B1, C1, D11, D12, D21 where
#    given; "0" = zeros of the right shape, as the file's own D11=zeros(nz,nw) / D21=zeros(ny,nw)
_AC1_A = [[0, 0, 1.132, 0, -1], [0, -0.0538, -0.1712, 0, 0.0705], [0, 0, 0, 1, 0],
          [0, 0.0485, 0, -0.8556, -1.013], [0, -0.2909, 0, 1.0532, -0.6859]]
_AC1_B = [[0, 0, 0], [-0.12, 1, 0], [0, 0, 0], [4.419, 0, -1.665], [1.575, 0, -0.0732]]
_AC1_C = [[1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0]]
_AC1_B1 = [[3.593e-2, 0, 1.672e-2], [0, 9.89e-3, 0], [0, -7.548e-2, 0], [0, 0, 5.635e-2],
           [1.45e-3, 0, 6.743e-2]]

_AC15_A = [[-.037, .0123, .00055, -1], [0, 0, 1, 0], [-6.37, 0, -.23, .0618], [1.25, 0, .016, -.0457]]
_AC15_B = [[.00084, .000236], [0, 0], [.08, .804], [-.0862, -.0665]]
_AC15_C1 = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0], [0, 0, 0, 0]]
_AC15_D12 = [[0, 0], [0, 0], [0, 0], [0, 0], [1, 0], [0, 1]]

_HE_a01 = [[0, 0, 0, 0.99857378005981],
           [0, 0, 1.00000000000000, -0.00318221934140],
           [0, 0, -11.57049560546880, -2.54463768005371],
           [0, 0, 0.43935656547546, -1.99818229675293],
           [0, 0, -2.04089546203613, -0.45899915695190],
           [-32.10360717773440, 0, -0.50335502624512, 2.29785919189453],
           [0.10216116905212, 32.05783081054690, -2.34721755981445, -0.50361156463623],
           [-1.91097259521484, 1.71382904052734, -0.00400543212891, -0.05741119384766]]
_HE_a02 = [[0.05338427424431, 0, 0, 0],
           [0.05952465534210, 0, 0, 0],
           [-0.06360262632370, 0.10678052902222, -0.09491866827011, 0.00710757449269],
           [0, 0.01665188372135, 0.01846204698086, -0.00118747074157],
           [-0.73502779006958, 0.01925575733185, -0.00459562242031, 0.00212036073208],
           [0, -0.02121581137180, -0.02116791903973, 0.01581159234047],
           [0.83494758605957, 0.02122657001019, -0.03787973523140, 0.00035400385968],
           [0, 0.01398963481188, -0.00090675335377, -0.29051351547241]]
_HE_B = [[0, 0, 0, 0],
         [0, 0, 0, 0],
         [0.12433505058289, 0.08278584480286, -2.75247764587402, -0.01788876950741],
         [-0.03635892271996, 0.47509527206421, 0.01429074257612, 0],
         [0.30449151992798, 0.01495801657438, -0.49651837348938, -0.20674192905426],
         [0.28773546218872, -0.54450607299805, -0.01637935638428, 0],
         [-0.01907348632812, 0.01636743545532, -0.54453611373901, 0.23484230041504],
         [-4.82063293457031, -0.00038146972656, 0, 0]]

_DIS1_A11 = [[0.144, -0.058, 0.056, 0.042], [-0.506, -0.236, -0.020, -0.012], [0, 0, -0.278, 0.291],
             [0, 0, 0, -0.330]]
_DIS1_A12 = [[0.120, 2.1454, 0, 0.080], [-0.06, -0.909, 1.093, -0.040], [0, 0, 0, 0.580], [0, 0, 0, 0]]
_DIS1_A21 = [[0, 0, 0.303, 0.029], [-0.154, 0.133, -0.006, -0.004], [-0.345, 0.304, -0.018, -0.014],
             [0, 0, 0, 0.247]]
_DIS1_A22 = [[-1.67, 0, 0, 0.092], [-0.014, -1.688, 0.236, 0.013], [-0.032, -0.611, -1.824, -0.024],
             [0, 0, 0, -1.978]]
_DIS1_Bb1 = [[-0.076, 0.02], [0.588, -0.006], [0, 0.152], [0, 1.45]]
_DIS1_Bb2 = [[0, 0.012], [0.162, -0.002], [0.414, -0.008], [0, 0.248]]

# EB1/EB2: A = blkdiag([0 1; -w² -2ξw]) for s = 1..5, w = s², ξ = 0.01 (the file's own numbers)
_EB_A = [[0.0] * 10 for _ in range(10)]
for _s_ in range(1, 6):
    _w = _s_ ** 2
    _i = 2 * (_s_ - 1)
    _EB_A[_i][_i + 1] = 1.0
    _EB_A[_i + 1][_i] = -_w ** 2
    _EB_A[_i + 1][_i + 1] = -2 * 0.01 * _w
_EB_B = _col(0, 0.9877, 0, -0.309, 0, -0.891, 0, 0.5878, 0, 0.7071)
_EB_B1 = [[0, 0], [0.9877, 0], [0, 0], [-0.309, 0], [0, 0], [-0.891, 0], [0, 0], [0.5878, 0], [0, 0],
          [0.7071, 0]]

_NN13_A = [[-1, 0, 4, 5, -3, -2], [-2, 4, -7, -2, 0, 3], [-6, 9, -5, 0, 2, -1], [-8, 4, 7, -1, -3, 0],
           [2, 5, 8, -9, 1, -4], [3, -5, 8, 0, 2, -6]]
_NN13_B = [[1, 0], [-5, 2], [7, -2], [1, -2], [0, 5], [-6, -2]]
_NN13_C = [[9, -3, 4, 0, 3, 7], [0, 1, -2, 1, -6, -2]]
_NN13_B1 = [[-3, -4, -2], [2, 0, 1], [-5, -7, 0], [4, -6, 1], [-3, 9, -8], [1, -2, 3]]
_NN13_C1 = [[1, -1, 2, -4, 0, -3], [-3, 0, 5, -1, 1, 1], [-7, 5, 0, -8, 2, -2]]

_TF1_beta, _TF1_eps2 = 1 / 20, -1e-5

RAW: dict[str, dict] = {
    "AC1": dict(A=_AC1_A, B=_AC1_B, C=_AC1_C, B1=_AC1_B1,
                C1=_s(R2, [[0, 1, 0, 0, 0], [0, 0, 1, 0, 0]]),          # (1/√2) C(2:3,:)
                D12=_s(R2, [[1, 0, 0], [0, 1, 0]]), D11="0", D21="0"),
    "AC2": dict(A=_AC1_A, B=_AC1_B, C=_AC1_C, B1=_AC1_B1,
                C1=_s(R2, [[0, 1, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0]]),
                D12=_s(R2, [[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]), D11="0", D21="0"),
    "AC3": dict(A=[[0, 0, 1, 0, 0], [0, -0.154, -0.0042, 1.54, 0], [0, 0.249, -1, -5.2, 0],
                   [0.0386, -0.996, -0.0003, -0.117, 0], [0, 0.5, 0, 0, -0.5]],
                B=[[0, 0], [-0.744, -0.032], [0.337, -1.12], [0.02, 0], [0, 0]],
                C=[[0, 1, 0, 0, -1], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [1, 0, 0, 0, 0]]),
    "AC4": dict(A=[[-0.876, 1, -0.1209, 0], [8.9117, 0, -130.75, 0], [0, 0, -150, 0], [-1, 0, 0, -0.05]],
                B=_col(0, 0, 150, 0), C=[[-1, 0, 0, 0], [0, -1, 0, 0]],
                B1=[[0, 0], [0, 0], [0, 0], [0, 1]], C1=[[-0.25, 0, 0, 3.487], [0, 0, -3, 0]],
                D12=_col(0, 3), D11=[[0, 0.25], [0, 0]], D21=[[0, 1], [0.01, 0]]),
    "AC6": dict(A=[[0, 0, 1, 0, 0, 0, 0],
                   [0, -0.154, -0.0042, 1.54, 0, -0.744, -0.032],
                   [0, 0.249, -1, -5.2, 0, 0.337, -1.12],
                   [0.0386, -0.996, -0.0003, -2.117, 0, 0.02, 0],
                   [0, 0.5, 0, 0, -4, 0, 0],
                   [0, 0, 0, 0, 0, -20, 0],
                   [0, 0, 0, 0, 0, 0, -25]],
                B=[[0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [20, 0], [0, 25]],
                C=[[0, -0.154, -0.0042, 1.54, 0, -0.744, -0.032],
                   [0, 0.249, -1, -5.2, 0, 0.337, -1.12],
                   [1, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 1, 0, 0]]),
    "AC7": dict(A=[[-0.06254, 0.01888, 0, -0.56141, -0.02751, 0, 0.06254, -0.00123, 0],
                   [0.01089, -0.99280, 0.99795, 0.00097, -0.07057, 0, -0.01089, 0.06449, 0],
                   [0.07743, 1.67540, -1.31111, -0.00030, -4.25030, 0, -0.07743, -0.10883, 0],
                   [0, 0, 1, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, -20.0000, 20, 0, 0, 0],
                   [0, 0, 0, 0, 0, -30, 0, 0, 0],
                   [0, 0, 0, 0, 0, 0, -0.88206, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, -0.88206, 0.00882],
                   [0, 0, 0, 0, 0, 0, 0, -0.00882, -0.88206]],
                B=_col(0, 0, 0, 0, 0, 30, 0, 0, 0),
                C=[[-0.00519, 0.47604, 0.00098, -0.00031, 0.03378, 0, 0.00519, -0.03086, 0],
                   [0, 0, 1, 0, 0, 0, 0, 0, 0]],
                B1=[[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0],
                    [1.3282, 0, 0, 0], [0, 1.62671, 0, 0], [0, -68.75283, 0, 0]],
                C1=_s(R2, [[-0.00519, 0.47604, 0.00098, -0.00031, 0.03378, 0, 0.00519, -0.03086, 0]]),
                D12=[[R2]], D21=[[0, 0, 0, 0], [0, 0, 0, 1]], D11="0"),
    "AC8": dict(A=[[-0.01365, 0.17800, 0.00017, -0.56100, -0.03726, 0, 0.01365, -0.01311, 0],
                   [-0.01516, -0.75200, 1.00100, 0.00127, -0.06311, 0, 0.01516, 0.05536, 0],
                   [0.00107, 0.07896, -0.87250, 0, -3.39900, 0, -0.00107, -0.00581, 0],
                   [0, 0, 1, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, -20.0000, 10.72, 0, 0, 0],
                   [0, 0, 0, 0, 0, -50, 0, 0, 0],
                   [0, 0, 0, 0, 0, 0, -0.44470, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, -0.44470, 0.00440],
                   [0, 0, 0, 0, 0, 0, 0, -0.00440, -0.44470]],
                B=_col(0, 0, 0, 0, 0, 50, 0, 0, 0),
                C=[[0.00646, 0.3203, -0.03358, 0, -0.10320, 0, -0.00646, -0.02358, 0],
                   [1, 0, 0, 0, 0, 0, -1, 0, 0],
                   [-0.01365, 0.1780, 0.00017, -0.561, -0.03726, 0, 0.01365, -0.01311, 0],
                   [0, -13.58, 0, 13.58, 0, 0, 0, 0, 0],
                   [0, 0, 1, 0, 0, 0, 0, 0, 0]],
                C1=_s(0.5, [[0.00646, 0.3203, -0.03358, 0, -0.10320, 0, -0.00646, -0.02358, 0],
                            [1, 0, 0, 0, 0, 0, -1, 0, 0]]),                   # (1/2) C(1:2,:)
                B1=[[0, 0, 0, 1, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 50, 0, 0, 0, 0, 0],
                    [0.9431, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 1.155, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0, -48.82, 0, 0, 0, 0, 0, 0, 0, 0]],
                D12=_col(0.5, 0.5), D21=_e(10, 8, 6, 7, 10, 9), D11="0"),
    "AC11": dict(A=[[-1.3410, 0.9933, 0, -0.1689, -0.2518],
                    [43.2230, -0.8693, 0, -17.251, -1.5766],
                    [1.34100, 0.0067, 0, 0.1689, 0.2518],
                    [0, 0, 0, -20, 0], [0, 0, 0, 0, -20]],
                 B=[[0, 0], [0, 0], [0, 0], [20, 0], [0, 20]],
                 C=[[0, 0, 1, 0, 0], [47.76, -0.268, 0, -4.56, 4.45], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]),
    "AC12": dict(A=[[-0.0017, 0.0413, -5.3257, -9.7565], [-0.0721, -0.3393, 49.5146, -1.0097],
                    [-0.0008, 0.0138, -0.2032, 0.0009], [0, 0, 1, 0]],
                 B=[[0.2086, -0.0005, -0.0271], [-0.0005, 0.2046, 0.0139], [-0.0047, 0.0023, 0.1226], [0, 0, 0]],
                 C=[[0, 0, 57.2958, 0], [0, 0, 0, 57.2958], [0.1045, -0.9945, 0.1375, 51.5791],
                    [-0.0002, 0.0045, 0, 0]],
                 B1=[[0.033, 0, 0], [0, 0.048, -0.002], [-0.064, 0, 0.340], [0, 0, 0.006]],
                 C1=_s(R2, [[1, 0, 0, 0]]), D12=_s(R2, [[0, 0, 1]]),
                 D21=[[0, 0, 0], [0, 0, 0], [0, 0, 0], [0.0212, 0, 0]], D11="0"),
    "AC15": dict(A=_AC15_A, B=_AC15_B, C=[[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], B1=_eye(4),
                 C1=_AC15_C1, D12=_AC15_D12, D11="0", D21="0"),
    "AC16": dict(A=_AC15_A, B=_AC15_B, C=_eye(4), B1=_eye(4), C1=_AC15_C1, D12=_AC15_D12, D11="0", D21="0"),
    "AC17": dict(A=[[-2.98, 0.93, 0, -0.034], [-0.99, -0.21, 0.035, -0.0011], [0, 0, 0, 1],
                    [0.39, -5.555, 0, -1.89]],
                 B=_col(-0.032, 0, 0, -1.6), C=[[0, 0, 1, 0], [0, 0, 0, 1]]),
    "HE1": dict(A=[[-0.0366, 0.0271, 0.0188, -0.4555], [0.0482, -1.01, 0.0024, -4.0208],
                   [0.1002, 0.3681, -0.7070, 1.42], [0, 0, 1, 0]],
                B=[[0.4422, 0.1761], [3.5446, -7.5922], [-5.52, 4.49], [0, 0]], C=[[0, 1, 0, 0]],
                B1=[[4.678e-2, 0], [4.572e-2, 9.88e-3], [4.369e-2, 1.11e-3], [-2.179e-2, 0]],
                C1=_s(R2, [[2, 0, 0, 0], [0, 1, 0, 0]]), D12=_s(R2, [[1, 0], [0, 1]]), D11="0", D21="0"),
    "HE2": dict(A=[[-0.0649, 0.0787, 0.1705, -0.5616], [0.0386, -0.939, 4.2277, 0.0198],
                   [0.1121, -0.4254, -0.7968, 0], [0, 0, 1, 0]],
                B=[[-0.9454, 0.5313], [-8.6476, -10.769], [19.0824, -2.8959], [0, 0]],
                C=[[1, 0, 0, 0], [0, 0, 0, 1]]),
    "HE3": dict(A=[[-0.0046, 0.038, 0.3259, -0.0045, -0.402, -0.073, -9.81, 0],
                   [-0.1978, -0.5667, 0.357, -0.0378, -0.2149, 0.5683, 0, 0],
                   [0.0039, -0.0029, -0.2947, 0.007, 0.2266, 0.0148, 0, 0],
                   [0.0133, -0.0014, -0.4076, -0.0654, -0.4093, 0.2674, 0, 9.81],
                   [0.0127, -0.01, -0.8152, -0.0397, -0.821, 0.1442, 0, 0],
                   [-0.0285, -0.0232, 0.1064, 0.0709, -0.2786, -0.7396, 0, 0],
                   [0, 0, 1, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 1, 0, 0, 0]],
                B=[[0.0676, 0.1221, -0.0001, -0.0016],
                   [-1.1151, 0.1055, 0.0039, 0.0035],
                   [0.0062, -0.0682, 0.001, -0.0035],
                   [-0.017, 0.0049, 0.1067, 0.1692],
                   [-0.0129, 0.0106, 0.2227, 0.143],
                   [0.139, 0.0059, 0.0326, -0.407],
                   [0, 0, 0, 0],
                   [0, 0, 0, 0]],
                C=_e(8, 2, 7, 8, 6, 3, 5),
                C1=_vstack(_e(8, 2, 7, 8, 6, 3, 5), _z(4, 8)), D12=_vstack(_z(6, 4), _eye(4)),
                B1=_col(0.0676, -1.1151, 0.0062, -0.017, -0.0129, 0.139, 0, 0),      # B(:,1)
                D21=_s(0.1, _col(0, 1, 0, 0, 0.5, 0)), D11="0"),
    "HE5": dict(A=_hstack(_HE_a01, _HE_a02), B=_HE_B,
                B1=[[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0], [0, 0, 0], [0, 0, 0]],
                C1=[[0, 0, 0, 0, 0, 0.0595, 0.05329, -0.9968],
                    [1.0, 0, 0, 0, 0, 0, 0, 0],
                    [0, 1.0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, -0.05348, 1.0, 0, 0, 0]],
                D11="0", D12=_eye(4), C=[[0, 0, 1.0, 0, 0, 0, 0, 0], [0, 0, 0, 1.0, 0, 0, 0, 0]],
                D21=[[0.01, 0, 0], [0, 0.01, 0]]),
    "REA1": dict(A=[[1.38, -0.2077, 6.715, -5.676], [-0.5814, -4.29, 0, 0.675], [1.067, 4.273, -6.654, 5.893],
                    [0.048, 4.273, 1.343, -2.104]],
                 B=[[0, 0], [5.679, 0], [1.136, -3.146], [1.136, 0]],
                 C=[[1, 0, 1, -1], [0, 1, 0, 0], [0, 0, 1, -1]]),
    "REA2": dict(A=[[1.4, -0.208, 6.715, -5.676], [-0.581, -4.29, 0, .675], [1.067, 4.273, -6.654, 5.893],
                    [.048, 4.273, 1.343, -2.104]],
                 B=[[0, 0], [5.679, 0], [1.136, -3.146], [1.136, 0]],
                 C=[[1, 0, 1, -1], [0, 1, 0, 0]]),
    "DIS1": dict(A=_vstack(_hstack(_DIS1_A11, _DIS1_A12), _hstack(_DIS1_A21, _DIS1_A22)),
                 B=_vstack(_hstack(_DIS1_Bb1, _z(4, 2)), _hstack(_z(4, 2), _DIS1_Bb2)),
                 C=_e(8, 1, 2, 3, 4), C1=_vstack(_e(8, 1, 2, 3, 4), _z(4, 8)),
                 B1=_col(1, 0, 1, 0, 1, 0, 1, 0), D11="0", D12=_vstack(_z(4, 4), _eye(4)), D21="0"),
    "DIS2": dict(A=[[-4, 2, 1], [3, -2, 5], [-7, 0, 3]], B=[[1, 0], [1, 0], [0, 1]],
                 C=[[0, 1, 0], [0, 0, 1]]),
    "DIS3": dict(A=[[-1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [-1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
                    [1.0, -2.0, -1.0, -1.0, 1.0, 1.0], [0.0, 0.0, 0.0, -1.0, 0.0, 0.0],
                    [-8.0, 1.0, -1.0, -1.0, -2.0, 0.0], [4.0, -0.5, 0.5, 0.0, 0.0, -4.0]],
                 B=[[0, 1, 0, 0], [1, 0, 0, 0], [1, 1, 0, 0], [0, 0, 0, -1], [0, 0, 1, 0], [0, 0, 0, 1]],
                 C=[[0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]),
    "DIS4": dict(A=[[0, 1, 0.5, 1, 0.6, 0], [-2, -3, 1, 0, 0, 1], [0, 2, 0.5, 1, 1, 0.5],
                    [1, 3, 0, 0.5, 0, -0.5], [0, 1, 1, 0, 1, 0], [-3, -4, 0, 0.5, 0.5, 0]],
                 B=[[1, 0, 0, 0], [1, 0, 0, 0], [0, 3, 0, 0], [0, 0, 4, 0], [0, 0, 0, 2], [0, 0, 0, 3]],
                 C=_eye(6)),
    "TG1": dict(A=[[0, 1, 0, 0, 0, 0, 0, 0, 0, 0],
                   [0, -0.11323, -.98109, -11.847, -11.847, -63.08, -34.339, -34.339, -27.645, 0],
                   [324.121, -1.1755, -29.101, .12722, 2.83448, -967.73, -678.14, -678.14, 0, -129.29],
                   [-127.3, 0.46167, 11.4294, -1.0379, 13.1237, 380.079, 266.341, 266.341, 0, 1054.85],
                   [-186.05, .67475, 16.7045, 0.86092, -17.068, 555.502, 389.268, 389.268, 0, -874.92],
                   [341.917, 1.09173, 1052.75, 756.465, 756.465, -29.774, 0.16507, 3.27626, 0, 0],
                   [-30.748, -.09817, -94.674, -68.029, -68.029, 2.67753, -2.6558, 4.88497, 0, 0],
                   [-302.36, -.96543, -930.96, -668.95, -668.95, 26.3292, 2.42028, -9.5603, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, 0, -1.6667, 0],
                   [0, 0, 0, 0, 0, 0, 0, 0, 0, -10]],
                B=_vstack(_z(8, 2), [[1.6667, 0], [0, 10]]),
                C=[[1, 0, 0, 0, 0, 0, 0, 0, 0, 0], [-.49134, 0, -.63203, 0, 0, -.20743, 0, 0, 0, 0]]),
    "AGS": dict(A=[[0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                   [-0.202, -1.15, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0],
                   [0, 0, -2.36, -13.6, -12.8, 0, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0],
                   [0, 0, 0, 0, 0, -1.62, -9.4, -9.15, 0, 0, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0],
                   [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0],
                   [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1],
                   [0, 0, 0, 0, 0, 0, 0, 0, -188, -111.6, -116.4, -20.8]],
                B=[[0, 0], [1.0439, 4.1486], [0, 0], [0, 0], [-1.794, 2.6775], [0, 0], [0, 0], [1.0439, 4.1486],
                   [0, 0], [0, 0], [0, 0], [-1.794, 2.6775]],
                C=[[0.264, 0.806, -1.42, -15, 0, 0, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 0, 0, 4.9, 2.12, 1.95, 9.35, 25.8, 7.14, 0]]),
    "BDT1": dict(A=[[-0.014, 0.0043, 0, 0, 0, 0, 0, 0, 0, 0, 0],
                    [0.0095, -0.0138, 0.0046, 0, 0, 0, 0, 0, 0, 0, 0.0005],
                    [0, 0.0095, -0.0141, 0.0063, 0, 0, 0, 0, 0, 0, 0.0002],
                    [0, 0, 0.0095, -0.0158, 0.011, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0.0095, -0.0312, 0.015, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0.0202, -0.0352, 0.022, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0.0202, -0.0422, 0.028, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0.0202, -0.0482, 0.037, 0, 0.0002],
                    [0, 0, 0, 0, 0, 0, 0, 0.0202, -0.0572, 0.042, 0.0005],
                    [0, 0, 0, 0, 0, 0, 0, 0, 0.0202, -0.0483, 0.0005],
                    [0.0255, 0, 0, 0, 0, 0, 0, 0, 0, 0.0255, -0.0185]],
                 B=[[0, 0, 0], [0.000005, -0.00004, 0.0025], [0.000002, -0.00002, 0.005],
                    [0.000001, -0.00001, 0.005], [0, 0, 0.005], [0, 0, 0.005], [-0.000005, 0.00001, 0.005],
                    [-0.00001, 0.00003, 0.005], [-0.00004, 0.000005, 0.0025], [-0.00002, 0.000002, 0.0025],
                    [0.00046, 0.00046, 0]],
                 C=_e(11, 10, 1, 11),
                 B1=_col(0, 0, 0, 0, 1.0e-2, 0, 0, 0, 0, 0, 0), C1=_vstack(_e(11, 10, 1, 11), _z(3, 11)),
                 D12=_vstack(_z(3, 3), _eye(3)), D11="0", D21="0"),
    "MFP": dict(A=[[0, 0, 1, 0], [0, 0, 0, 1], [-0.101, -0.1681, -0.04564, -0.01075],
                   [0.06082, -2.1407, -0.05578, -0.1273]],
                B=[[0, 0, 0], [0, 0, 0], [0.1179, 0.1441, 0.1476], [0.1441, 1.7057, -0.7557]],
                C=[[1, 0, 0, 0], [0, 1, 0, 0]]),
    "UWV": dict(A=[[0, 850, 0, 0, 0, 0, 0, 0],
                   [-850, -120, -4100, 0, 0, 0, 0, 0],
                   [33, 0, -33, 0, -700, 0, 0, 0],
                   [0, 0, 0, 0, 1400, 0, 0, 0],
                   [0, 0, 1600, -450, -110, 0, 0, 0],
                   [0, 0, 0, 81, 0, -1, 0, -900],
                   [0, 0, 0, 0, 0, 0, 0, 110],
                   [0, 0, 0, 0, 0, 12, -1.1, -22]],
                B=[[0, 0], [4.6, 99000], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0]],
                C=_e(8, 6, 7),
                B1=[[0, 0], [9900, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 99]],
                C1=[[0, 0, 0, 0, 0, 0, 1, 0]], D12=[[1, 0]], D11="0", D21="0"),
    "EB1": dict(A=_EB_A, B=_EB_B, C=[[r[0] for r in _EB_B]], B1=_EB_B1,
                C1=[[0, 0.809, 0, -0.9511, 0, 0.309, 0, 0.5878, 0, -1], [0] * 10],
                D12=_col(0, 1.9), D21=[[0, 1.9]], D11="0"),
    "EB2": dict(A=_EB_A, B=_EB_B, C=[[r[0] for r in _EB_B]], B1=_EB_B1,
                C1=[[0.809, 0, -0.9511, 0, 0.309, 0, 0.5878, 0, -1, 0], [0] * 10],
                D12=_col(0, 0.5), D21=[[0, 1.9]], D11="0"),
    "PSM": dict(A=[[-0.04165, 0, 4.92, -4.92, 0, 0, 0],
                   [-5.21, -12.5, 0, 0, 0, 0, 0],
                   [0, 3.33, -3.33, 0, 0, 0, 0],
                   [0.545, 0, 0, 0, -0.545, 0, 0],
                   [0, 0, 0, 4.92, -0.04165, 0, 4.92],
                   [0, 0, 0, 0, -5.21, -12.5, 0],
                   [0, 0, 0, 0, 0, 3.33, -3.33]],
                B=[[-4.92, 0], [0, 0], [0, 0], [0, 0], [0, -4.92], [0, 0], [0, 0]],
                C=_e(7, 1, 4, 5),
                B1=[[0, 0], [12.5, 0], [0, 0], [0, 0], [0, 0], [0, 12.5], [0, 0]],
                C1=_vstack(_e(7, 1, 4, 5), _z(2, 7)), D12=_vstack(_z(3, 2), _eye(2)), D11="0", D21="0"),
    "TF1": dict(A=[[-1, 0, 0, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0],
                   [0, 0, 0, 1, -1, 0, 0], [-0.088, 0.0345, 0, 0, 1, -0.0032, 0],
                   [0, 0, _TF1_beta, 0, 0, 0, _TF1_eps2]],
                B=[[1, 0], [0, 0], [0, 0], [0, 0.09], [0, 0], [0, 0], [0, 0]],
                C=_e(7, 3, 2, 7, 6),
                B1=_col(0, 0, 0, 0, 0, 0, -_TF1_beta),
                C1=[[0, 0, 0, 0, 0, 0, 1.0], [0, 0, 0, 0, 0, 2.23, 0], [0] * 7, [0] * 7],
                D11="0", D12=[[0, 0], [0, 0], [math.sqrt(3), 0], [0, math.sqrt(0.3)]],
                D21=_col(0.04, 0, 0, 0)),
    "NN1": dict(A=[[0, 1, 0], [0, 0, 1], [0, 13, 0]], B=_col(0, 0, 1), C=[[0, 5, -1], [-1, -1, 0]]),
    "NN2": dict(A=[[0, 1], [-1, 0]], B1=[[1, 0], [0, 1]], B=_col(0, 1), C1=[[1, 0], [0, 0]], C=[[0, 1]],
                D11="0", D21="0", D12=_col(0, 1)),
    "NN3": dict(A=[[0.5, 1, 1.5, 1], [-1, 3, 2.1, 2], [1, -1, -0.6, 1], [-2, 2, -1, 1]],
                B1=_col(0, 0, 1, 0), B=_col(0, 0, 0, 1), C1=[[1, 0, 0, 0]], C=[[0, 0, 0, 1]],
                D12=[[0]], D11="0", D21="0"),
    "NN4": dict(A=[[0, 1, 0, 0], [0, -2.93, -4.75, -0.78], [0.086, 0, -0.11, -1], [0, -0.042, 2.59, -0.39]],
                B=[[0, 0], [0, -3.91], [0.035, 0], [-2.53, 0.31]],
                C=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]),
    "NN5": dict(A=[[0, 1, 0, 0, 0, 0, 0], [0, 0, .2, -.65, -.002, 2.6, 0], [-.014, 1, -.041, .0002, -.015, -.033, 0],
                   [0, 0, 0, 0, 1, 0, 0], [0, 0, 0, -45, -.13, 255, 0], [0, 0, 0, 0, 0, 0, 1],
                   [0, 0, 0, 0, 0, -50, -10]],
                B=_col(0, 0, 0, 0, 0, 0, 1), C=[[1, 0, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0, 0]]),
    "NN8": dict(A=[[-0.2, 0.1, 1], [-0.05, 0, 0], [0, 0, -1]], B=[[0, 1], [0, 0.7], [1, 0]],
                C=[[1, 0, 0], [0, 1, 0]]),
    "NN9": dict(A=[[1, 1, 1, 0, 1], [0, 1, 0, 0, 1], [0, 1, 1, 0, 1], [1, 1, 1, 1, 1], [1, 1, 1, 1, 0]],
                B=[[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 1], [0, 1, 0]],
                C=[[0, -2, -3, -2, -1], [1, 2, 3, 2, 1]],
                B1=[[5, 1], [0, 0], [0, 0], [2, 3], [1, 4]],
                C1=[[0, 0, 1, 0, 0], [0, 0, 0, 0, 1], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0]],
                D12=[[1, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]], D21=[[1, 0], [0, 0]], D11="0"),
    "NN13": dict(A=_NN13_A, B=_NN13_B, C=_NN13_C, B1=_NN13_B1, C1=_NN13_C1,
                 D11=[[1, -2, -3], [0, 4, 0], [5, -3, -4]], D12=[[0, 0], [1, 0], [0, 1]],
                 D21=[[0, 1, 0], [0, 0, 1]]),
    "NN14": dict(A=_NN13_A, B=_NN13_B, C=_NN13_C, B1=_NN13_B1, C1=_NN13_C1, D11="0",
                 D12=[[-4, -1], [1, 0], [0, 1]], D21=[[3, 1, 0], [-2, 0, 1]]),
    "NN15": dict(A=[[0, 1, 0], [-79.285, -0.113, 0], [28.564, 0.041, 0]], B1=_col(0, 0.041, -0.03),
                 B=[[0, 0], [0.041, -0.0047], [-0.03, -0.0016]], C1=[[0, 0, 1], [1, 0, 0], [0, 0, 0], [0, 0, 0]],
                 C=[[0, 0, 1], [1, 0, 0]], D11="0", D21="0", D12=[[0, 0], [0, 0], [0.1, 0], [0, 0.1]]),
    "NN16": dict(A=[[0, 1, 0, 0, 0, 0, 0, 0],
                    [-0.42, 0, 0, 0, 0, 0, 0, 0],
                    [0, 0, 0, 1, 0, 0, 0, 0],
                    [0, 0, -0.1849, 0, 0, 0, 0, 0],
                    [0, 0, 0, 0, 0, 1, 0, 0],
                    [0, 0, 0, 0, -4.41, 0, 0, 0],
                    [0, 0, 0, 0, 0, 0, 0, 1],
                    [0, 0, 0, 0, 0, 0, -4.84, 0]],
                 B=[[0, 0, 0, 0], [-0.92, -1.4, 0.92, -1.4], [0, 0, 0, 0], [0.65, 1.6, 0.65, -1.6],
                    [0, 0, 0, 0], [1.4, -1, 1.4, 1], [0, 0, 0, 0], [2, -0.8, -2, -0.8]],
                 C=[[0, -1.8, 0, 1.3, 0, 2.9, 0, 4.1], [0, -2.7, 0, 3.2, 0, -2.1, 0, -1.6],
                    [0, 1.8, 0, 1.3, 0, 2.9, 0, -4.1], [0, -2.7, 0, -3.2, 0, 2.1, 0, -1.6]],
                 C1=[[0.065, 0, 0, 0, 0, 0, 0, 0], [0, 0.065, 0, 0, 0, 0, 0, 0], [0] * 8, [0] * 8],
                 D12=_eye(4), B1=_eye(8), D11="0", D21="0"),
    "NN17": dict(A=[[0, -1, 2], [1, -2, 3], [0, 1, 0]], B1=_col(1, -1, 0), B=[[1, 0], [0, 0], [0, -1]],
                 C1=[[1, 0, 1], [1, 0, 1]], C=[[1, 0, 0]], D11="0", D21="0", D12=[[0, 1], [0, 0]]),
    "DLR1": dict(A=_vstack(_hstack(_z(5, 5), _eye(5)),
                           [[-8.4268, 0, 9.6557, 0, -5.083, -0.0253, 0, 0.0155, 0, -0.0112],
                            [0, -20.2022, 0, 20.0736, 0, 0, -0.0244, 0, 0.0151, 0],
                            [-23.9425, 0, -10.7354, 0, -147.0685, -0.0049, 0, -0.0359, 0, -0.0849],
                            [0, 126.1547, 0, -132.8028, 0, 0, 0.0947, 0, -0.1089, 0],
                            [-39.905, 0, 6.607, 0, -188.4411, -0.0247, 0, 0.0016, 0, -0.1368]]),
                 B=_vstack(_z(5, 2), [[-0.001, -0.001], [-0.0133, 0.0133], [0.048, 0.048], [-0.0516, 0.0516],
                                      [0.0213, 0.0213]]),
                 C=[[0, 0, 0, 0, 0, 0.0115, -0.0536, 0.9713, -0.2009, -0.5746],
                    [0, 0, 0, 0, 0, 0.0115, 0.0536, 0.9713, 0.2009, -0.5746]],
                 B1=_vstack(_z(5, 2), [[-0.0076, -0.0076], [-0.0351, 0.0351], [0.0972, 0.0972], [-0.1824, 0.1824],
                                       [0.0748, 0.0748]]),
                 C1=[[0, 1, 0, 0, 0, 0, 0, 0, 0, 0], [-0.8084, 0, 0.7509, 0, -0.9501, 0, 0, 0, 0, 0]],
                 D12=_eye(2), D11="0", D21=[[0, 0], [0.0972, 0.7509]]),
}


def complete(raw: dict) -> dict:
    """The generalized plant (lists of floats) of one RAW entry, as COMPleib.m's closing lines
    complete it: with B1 empty, B1 = I, C1 = I, D12 = [0; I], D11 = 0, D21 = 0."""
    A = np.asarray(raw["A"], dtype=float)
    B2 = np.asarray(raw["B"], dtype=float)
    C2 = np.asarray(raw["C"], dtype=float)
    n, nu, ny = A.shape[0], B2.shape[1], C2.shape[0]
    if "B1" not in raw:
        B1, C1 = np.eye(n), np.eye(n)
        D12 = np.vstack([np.zeros((n - nu, nu)), np.eye(nu)])
        D11, D21 = np.zeros((n, n)), np.zeros((ny, n))
    else:
        B1 = np.asarray(raw["B1"], dtype=float)
        C1 = np.asarray(raw["C1"], dtype=float)
        nw, nz = B1.shape[1], C1.shape[0]
        D12 = np.asarray(raw["D12"], dtype=float)
        D11 = np.zeros((nz, nw)) if isinstance(raw["D11"], str) else np.asarray(raw["D11"], dtype=float)
        D21 = np.zeros((ny, nw)) if isinstance(raw["D21"], str) else np.asarray(raw["D21"], dtype=float)
    P = dict(A=A, B1=B1, B2=B2, C1=C1, C2=C2, D11=D11, D12=D12, D21=D21)
    nw, nz = B1.shape[1], C1.shape[0]
    want = dict(A=(n, n), B1=(n, nw), B2=(n, nu), C1=(nz, n), C2=(ny, n), D11=(nz, nw), D12=(nz, nu),
                D21=(ny, nw))
    for k, shape in want.items():
        if P[k].shape != shape:
            raise ValueError(f"{k}: shape {P[k].shape}, expected {shape}")
    return {k: v.tolist() for k, v in P.items()}


PLANTS: dict[str, dict] = {name: complete(raw) for name, raw in RAW.items()}
"""name -> {A, B1, B2, C1, C2, D11, D12, D21} (lists of lists); D22 = 0."""


# -- structure and the independent references (python-control / slycot / scipy only) ----------
JW_TOL = 1e-7          # a zero z is on the imaginary axis when |Re z| ≤ JW_TOL · max(1, |z|)


def arrays(name: str) -> dict:
    """The plant as float arrays, with D22 = 0."""
    P = {k: np.asarray(v, dtype=float) for k, v in PLANTS[name].items()}
    P["D22"] = np.zeros((P["C2"].shape[0], P["B2"].shape[1]))
    return P


def invariant_zeros(A, B, C, D) -> np.ndarray:
    """The invariant zeros of (A, B, C, D) (SLICOT AB08ND through python-control)."""
    import control
    return np.asarray(control.ss(A, B, C, D).zeros(), dtype=complex)


def on_axis(zeros) -> list:
    return [complex(z) for z in zeros if abs(z.real) <= JW_TOL * max(1.0, abs(z))]


def structure(P: dict) -> dict:
    """What decides whether the regular H∞ theory (and SB10FD / the Riccati bisection) applies."""
    nu, ny = P["B2"].shape[1], P["C2"].shape[0]
    z12 = invariant_zeros(P["A"], P["B2"], P["C1"], P["D12"])
    z21 = invariant_zeros(P["A"], P["B1"], P["C2"], P["D21"])
    s = dict(n=P["A"].shape[0], nu=nu, ny=ny, nw=P["B1"].shape[1], nz=P["C1"].shape[0],
             rank_D12=int(np.linalg.matrix_rank(P["D12"])), rank_D21=int(np.linalg.matrix_rank(P["D21"])),
             jw_P12=on_axis(z12), jw_P21=on_axis(z21),
             stabilisable=bool(pbh_gap(P["A"], P["B2"], CT) > 1e-9),
             detectable=bool(pbh_gap(P["A"].T, P["C2"].T, CT) > 1e-9),
             D11_zero=bool(not np.any(P["D11"])))
    s["of_regular"] = (s["rank_D12"] == nu and s["rank_D21"] == ny and not s["jw_P12"] and not s["jw_P21"])
    s["sf_regular"] = s["rank_D12"] == nu and not s["jw_P12"]
    return s


def singular_words(s: dict, problem: str) -> str:
    """Why the regular theory does not apply, in words ("" when it does)."""
    out = []
    if s["rank_D12"] < s["nu"]:
        out.append(f"rank D12 = {s['rank_D12']} < nu = {s['nu']}")
    if problem == "of" and s["rank_D21"] < s["ny"]:
        out.append(f"rank D21 = {s['rank_D21']} < ny = {s['ny']}")
    if s["jw_P12"]:
        out.append("P12 zeros on jR: " + ", ".join(f"{z:.3g}" for z in s["jw_P12"]))
    if problem == "of" and s["jw_P21"]:
        out.append("P21 zeros on jR: " + ", ".join(f"{z:.3g}" for z in s["jw_P21"]))
    if not s["stabilisable"]:
        out.append("(A, B2) not stabilisable")
    if problem == "of" and not s["detectable"]:
        out.append("(C2, A) not detectable")
    return "; ".join(out)


def _sb10fd_try(P: dict, g: float):
    """('none', None): SB10FD reports no controller at level g; ('met', norm) / ('unmet', norm):
    it returns one, whose closed loop (linfnorm) meets / does not meet g (1 + 1e-6)."""
    try:
        K = sb10fd_level(P, g)
    except Exception:        # noqa: BLE001 — SLICOT's "no controller at this level"
        return "none", None
    norm = linf(*of_closed_loop(P, K), CT)
    return ("met" if norm < g * (1 + TOL) else "unmet"), norm


def sb10fd_bracket(P: dict, rtol: float = 1e-8) -> dict | None:
    """The output-feedback reference by SB10FD, bisected geometrically to ``rtol``: ``hi`` the
    least measured closed-loop norm of a controller that met its level (an achieved level: the
    optimum is ≤ it), ``lo`` the largest level at which SB10FD reported that no controller exists
    (None if it never did), ``unmet`` the levels at which its controller missed the level.  None
    when no level up to 1e12 is met."""
    g, hi, best = 1.0, None, np.inf
    while g <= 1e12:
        state, norm = _sb10fd_try(P, g)
        if state == "met":
            hi, best = g, norm
            break
        g *= 4
    if hi is None:
        return None
    lo, lo_none, unmet = 0.0, None, 0
    g = hi
    while g > 1e-9:
        g /= 4
        state, norm = _sb10fd_try(P, g)
        if state == "met":
            hi, best = g, min(best, norm)
            continue
        lo = g
        unmet += state == "unmet"
        lo_none = g if state == "none" else lo_none
        break
    while lo > 0 and hi / lo - 1 > rtol:
        mid = math.sqrt(lo * hi)
        state, norm = _sb10fd_try(P, mid)
        if state == "met":
            hi, best = mid, min(best, norm)
        else:
            lo = mid
            unmet += state == "unmet"
            if state == "none":
                lo_none = mid if lo_none is None else max(lo_none, mid)
    return {"hi": float(best), "lo": lo_none, "unmet": unmet}


OK, FAIL, UNKNOWN = "ok", "fail", "unknown"


def _care(A, B, Q, R, S):
    """(state, X) for AᵀX + XA − (XB + S)R⁻¹(BᵀX + Sᵀ) + Q = 0 (scipy): OK with the stabilising
    solution X ⪰ 0; FAIL only where the failure is definite — the Hamiltonian has an eigenvalue
    within 1e-9 · (its largest modulus) of the imaginary axis (no stabilising solution; there
    scipy returns one that is not: EB1's Y∞ below its optimum 3.10408, whose central controllers at
    3.101 … 3.104 all close the loop at 3.10408), or X has an eigenvalue below −1e-6 · max|X|
    (indefinite); UNKNOWN otherwise (scipy fails, X not finite, A − BF not Hurwitz at a PSD X:
    near an optimum where X grows without bound the computed X is not accurate, TF1's at 0.2463639)."""
    from scipy.linalg import solve_continuous_are
    Ri = np.linalg.inv(R)
    Ah = A - B @ Ri @ S.T
    H = np.block([[Ah, -B @ Ri @ B.T], [-(Q - S @ Ri @ S.T), -Ah.T]])
    ev = np.linalg.eigvals(H)
    if min(abs(ev.real)) <= 1e-9 * max(abs(ev)):
        return FAIL, None
    try:
        with np.errstate(all="ignore"):
            X = solve_continuous_are(A, B, Q, R, s=S)
    except (np.linalg.LinAlgError, ValueError):
        return UNKNOWN, None
    if not np.all(np.isfinite(X)):
        return UNKNOWN, None
    X = (X + X.T) / 2
    low = np.linalg.eigvalsh(X)[0]
    if low < -1e-6 * max(1.0, abs(X).max()):
        return FAIL, None
    if low < -1e-9 * max(1.0, abs(X).max()) or not stable(A - B @ np.linalg.solve(R, B.T @ X + S.T), CT):
        return UNKNOWN, None
    return OK, X


def _d11_bound(P: dict) -> float:
    """max(‖D12⊥ᵀD11‖, ‖D11 D21⊥‖): no controller reaches a level at or below it."""
    from scipy.linalg import null_space
    U, V = null_space(P["D12"].T), null_space(P["D21"])
    return max(np.linalg.norm(U.T @ P["D11"], 2) if U.size else 0.0,
               np.linalg.norm(P["D11"] @ V, 2) if V.size else 0.0)


def _x_riccati(P: dict, g: float):
    """X∞ of the full-information problem at level g (the J-factor Riccati equation with
    R = [D11 D12]ᵀ[D11 D12] − diag(g²I, 0)): (state, X)."""
    B1, C1, D11, D12 = P["B1"], P["C1"], P["D11"], P["D12"]
    D1 = np.hstack([D11, D12])
    R = D1.T @ D1
    R[:B1.shape[1], :B1.shape[1]] -= g ** 2 * np.eye(B1.shape[1])
    return _care(P["A"], np.hstack([B1, P["B2"]]), C1.T @ C1, R, C1.T @ D1)


def fi_state(P: dict, g: float) -> str:
    """Whether the full-information H∞ problem has a solution of level < g (OK / FAIL / UNKNOWN):
    g > ‖D12⊥ᵀD11‖ and a stabilising X∞ ⪰ 0.  The full-information optimum is ≤ the state-feedback
    and the output-feedback optima, so a level where this definitely fails is a floor under both."""
    from scipy.linalg import null_space
    U = null_space(P["D12"].T)
    if U.size and g <= np.linalg.norm(U.T @ P["D11"], 2):
        return FAIL
    return _x_riccati(P, g)[0]


def dgkf_state(P: dict, g: float) -> str:
    """Whether a controller of level < g exists (OK / FAIL / UNKNOWN) by the Riccati conditions of
    Glover & Doyle (Systems & Control Letters 11, 1988; Doyle, Glover, Khargonekar & Francis, IEEE
    TAC 34, 1989) for a regular plant with general D11: g > max(‖D12⊥ᵀD11‖, ‖D11 D21⊥‖),
    stabilising X∞ ⪰ 0 and Y∞ ⪰ 0 of the J-factor Riccati equations, ρ(X∞Y∞) < g² (FAIL when
    ρ ≥ g²(1 + 1e-6)); scipy, no SLICOT."""
    if g <= _d11_bound(P):
        return FAIL
    sx, X = _x_riccati(P, g)
    B1, C1, C2, D11, D21 = P["B1"], P["C1"], P["C2"], P["D11"], P["D21"]
    Dt = np.vstack([D11, D21])
    Rt = Dt @ Dt.T
    Rt[:C1.shape[0], :C1.shape[0]] -= g ** 2 * np.eye(C1.shape[0])
    sy, Y = _care(P["A"].T, np.hstack([C1.T, C2.T]), B1 @ B1.T, Rt, B1 @ Dt.T)
    if FAIL in (sx, sy):
        return FAIL
    if UNKNOWN in (sx, sy):
        return UNKNOWN
    rho = max(abs(np.linalg.eigvals(X @ Y)))
    return OK if rho < g ** 2 else (FAIL if rho >= g ** 2 * (1 + 1e-6) else UNKNOWN)


def riccati_floor(state, start: float, rtol: float = 1e-8):
    """The largest level (to ``rtol``) at which ``state`` definitely fails, searched below
    ``start`` (an achieved level): a floor under the optimum.  Where the test fails at ``start``
    (within its margin of the optimum) the search starts up to 1e-3 above it; a floor above
    ``start`` (1 + 1e-7) contradicts the achieved level and is dropped (None).  0.0 when the test
    does not fail down to 1e-13."""
    hi, k = start, 0
    while state(hi) == FAIL:          # within the test's margin of the optimum: step up a little
        k += 1
        if k > 6:
            return None
        hi = start * (1 + 1e-9 * 10 ** k)
    lo = hi / 2
    while state(lo) != FAIL:
        hi, lo = lo, lo / 2
        if lo < 1e-13:
            return 0.0
    while hi / lo - 1 > rtol:
        mid = math.sqrt(lo * hi)
        hi, lo = (hi, mid) if state(mid) == FAIL else (mid, lo)
    return lo if lo <= start * (1 + 1e-7) else None


def references(name: str) -> dict:
    """The structure of plant ``name`` and its references (see the module docstring)."""
    P = arrays(name)
    s = structure(P)
    ref = {"structure": s}
    if s["of_regular"] and s["stabilisable"] and s["detectable"]:
        b = sb10fd_bracket(P)
        if b is None:
            ref["of"] = {"none": "SB10FD met no level up to 1e12"}
        else:
            ref["of"] = {"hi": b["hi"], "lo": riccati_floor(lambda g: dgkf_state(P, g), b["hi"]),
                         "sb10fd_lo": b["lo"], "sb10fd_unmet": b["unmet"]}
    else:
        ref["of"] = {"none": "SB10FD does not apply: " + singular_words(s, "of")}
    if s["sf_regular"] and s["stabilisable"]:
        g = sf_hinf_optimum(P, CT)
        if np.isfinite(g):
            ref["sf"] = {"hi": float(g), "lo": riccati_floor(lambda x: fi_state(P, x), float(g))}
        else:
            ref["sf"] = {"none": "the full-information Riccati bisection found no level"}
    else:
        ref["sf"] = {"none": "the Riccati bisection does not apply: " + singular_words(s, "sf")}
    return ref


# -- one case as a user solves it (run in its own process) ---------------------------------------
THEOREMS = {"of": "textbook.hinf_of_ct", "sf": "textbook.hinf_sf_ct"}
SF_KEYS = ("A", "B1", "B2", "C1", "D11", "D12")


def case_data(name: str, problem: str) -> dict:
    P = arrays(name)
    keys = SF_KEYS if problem == "sf" else ("A", "B1", "B2", "C1", "C2", "D11", "D12", "D21", "D22")
    return {k: P[k].tolist() for k in keys}


def solve_case(name: str, problem: str) -> dict:
    """``lmidsl.solve`` on the plant as a user calls it; what the verdict says, and the design."""
    import warnings
    import lmidsl
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = lmidsl.solve(THEOREMS[problem], data=case_data(name, problem))
    v = sol.verdict
    box = v.bracket or {}
    method = getattr(sol.bounds, "method", "") or ""
    design = None
    if sol.design is not None:
        keys = ("K",) if problem == "sf" else ("AK", "BK", "CK", "DK")
        if all(k in sol.design for k in keys):
            design = {k: np.atleast_2d(np.asarray(sol.design[k], dtype=float)).tolist() for k in keys}
    return {"word": v.word, "certified": bool(v.certified), "gamma": v.gamma, "status": sol.status,
            "bracket": {k: box.get(k) for k in ("lower", "upper", "lower_proved", "upper_proved", "why")},
            "method": method, "line": v.line()[:400], "design": design,
            "seconds": time.perf_counter() - t0, "lmidsl": os.path.dirname(lmidsl.__file__)}


def run_child(name: str, problem: str, timeout: float) -> dict:
    """:func:`solve_case` in a fresh process (same interpreter and environment), killed (its
    process group) after ``timeout`` seconds."""
    import signal
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, os.path.abspath(__file__), "--child", name, problem],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return {"error": f"timeout ({timeout:.0f} s)", "seconds": time.perf_counter() - t0}
    lines = [ln for ln in out.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = (err.strip().splitlines() or ["?"])[-1]
        return {"error": f"exit {proc.returncode}: {tail[:200]}", "seconds": time.perf_counter() - t0}
    row = json.loads(lines[-1])
    row["wall"] = time.perf_counter() - t0
    return row


# -- judging -------------------------------------------------------------------------------------
def _loop(name: str, problem: str, design: dict) -> tuple:
    """(A, B, C, D) of the plant's closed loop with the delivered design, in doubles."""
    P = arrays(name)
    if problem == "sf":
        K = np.asarray(design["K"], dtype=float)
        return P["A"] + P["B2"] @ K, P["B1"], P["C1"] + P["D12"] @ K, P["D11"]
    K = tuple(np.asarray(design[k], dtype=float) for k in ("AK", "BK", "CK", "DK"))
    return of_closed_loop(P, K)


def closed_loop_norm(name: str, problem: str, design: dict) -> float:
    """The H∞ norm of the closed loop of the delivered design (inf when unstable), python-control."""
    return linf(*_loop(name, problem, design), CT)


WITNESS_DIGITS = 50


def witnessed_gain(name: str, problem: str, design: dict) -> float:
    """max σ(G(jω)) of the delivered design's closed loop (its doubles taken exactly) evaluated at
    50 digits (mpmath) at the frequency where python-control's ``linfnorm`` puts the peak and on a
    grid of 61 frequencies (0 and 1e-6 … 1e6): a lower bound on the closed loop's norm that no
    rounding can raise.  A design "misses its level" only where this exceeds it: on TF1's stiff
    output-feedback loop (controller poles to −2.6e5, a closed-loop pole at −1.2e-4) ``linfnorm``
    said 6.8359 at ω = 0 where the loop's gain at ω = 0 is 6.7689366 (50 digits; the balanced
    realisation's AB13DD agrees)."""
    import control
    import mpmath
    A, B, C, D = _loop(name, problem, design)
    if not stable(A, CT):
        return float("inf")
    peak = float(control.linfnorm(control.ss(A, B, C, D), tol=1e-10)[1])
    with mpmath.workdps(WITNESS_DIGITS):
        Am, Bm, Cm, Dm = (mpmath.matrix(np.atleast_2d(M).tolist()) for M in (A, B, C, D))
        n = A.shape[0]

        def gain(omega: float):
            X = mpmath.lu_solve(mpmath.mpc(0, omega) * mpmath.eye(n) - Am, Bm)
            return max(mpmath.svd_c(Cm * X + Dm, compute_uv=False))

        omegas = [peak if np.isfinite(peak) else 0.0, 0.0, *np.logspace(-6, 6, 61)]
        return float(max(gain(float(w)) for w in omegas))


def judge(name: str, problem: str, row: dict, ref: dict) -> dict:
    """Flags of one solved case: FALSE (a proved end on the wrong side of a reference), BADDESIGN
    (a certified design whose recomputed closed loop misses its level).  A floor that the delivered
    design's own closed loop (python-control) goes below is refuted, not used: the Riccati floors
    fail at tiny levels (DLR1's state-feedback optimum is 0: u = −C1x, D12 = I, A − B2C1 stable;
    the Riccati equation fails below 3.7e-7)."""
    out = {"false": [], "baddesign": False, "closed_loop": None, "witnessed": None, "refuted": []}
    if "error" in row:
        return out
    box = row["bracket"]
    lower = box["lower"] if box["lower_proved"] else None
    upper = box["upper"] if box["upper_proved"] else None
    level = row["gamma"] if row["certified"] else None
    if row.get("design") is not None:
        out["closed_loop"] = closed_loop_norm(name, problem, row["design"])
        if level is not None and not out["closed_loop"] <= level * (1 + TOL):
            out["witnessed"] = witnessed_gain(name, problem, row["design"])
            out["baddesign"] = not out["witnessed"] <= level * (1 + TOL)
    achieved = out["closed_loop"] if out["closed_loop"] is not None and np.isfinite(out["closed_loop"]) else None
    own = ref[problem]
    floors = []                                     # (value, what): the optimum is ≥ value
    if own.get("lo") is not None:
        floors.append((own["lo"], "ref lo"))
    if problem == "of" and ref["sf"].get("lo") is not None:
        floors.append((ref["sf"]["lo"], "SF floor"))
    if lower is not None and own.get("hi") is not None and lower > own["hi"] * (1 + TOL):
        out["false"].append(f"proved lower {lower:.9g} > reference {own['hi']:.9g}")
    for value, what in floors:
        if achieved is not None and achieved < value * (1 - TOL):
            out["refuted"].append(f"{what} {value:.3g} refuted by the design's closed loop {achieved:.3g}")
            continue
        for v, w in ((upper, "proved upper"), (level, "certified level")):
            if v is not None and v < value * (1 - TOL):
                out["false"].append(f"{w} {v:.9g} < {what} {value:.9g}")
    return out


# -- the run -------------------------------------------------------------------------------------
def _f(x, fmt=".7g"):
    return "-" if x is None else format(x, fmt)


def run_case(name: str, problem: str, ref: dict, timeout: float) -> dict:
    row = run_child(name, problem, timeout)
    flags = judge(name, problem, row, ref)
    own = ref[problem]
    box = row.get("bracket") or {}
    lower = box.get("lower") if box.get("lower_proved") else None
    upper = box.get("upper") if box.get("upper_proved") else None
    top = upper if upper is not None else (row.get("gamma") if row.get("certified") else None)
    width = (top - lower) / top if lower is not None and top else None
    return {"plant": name, "problem": problem, "n": ref["structure"]["n"], "word": row.get("word"),
            "error": row.get("error"), "certified": bool(row.get("certified")),
            "design_level": row.get("gamma") if row.get("certified") else None, "lower": lower, "upper": upper,
            "width": width, "why": None if lower is not None else
            ((box.get("why") or "") + (f" [{row['method']}]" if row.get("method") else "")) or row.get("error")
            or row.get("line"),
            "seconds": row.get("seconds"), "wall": row.get("wall", row.get("seconds")),
            "ref_hi": own.get("hi"), "ref_lo": own.get("lo"), "ref_none": own.get("none"),
            "closed_loop": flags["closed_loop"], "witnessed": flags["witnessed"], "false": flags["false"], "baddesign": flags["baddesign"],
            "refuted": flags["refuted"],
            "line": row.get("line"), "lmidsl": row.get("lmidsl")}


def table(rows: list[dict], refs: dict) -> str:
    out = [f"{'plant':6s} {'pb':2s} {'n':>2s} {'word':16s} {'design γ':>11s} {'lower':>11s} {'upper':>11s} "
           f"{'width':>8s} {'ref lo':>11s} {'ref hi':>11s} {'closed':>11s} {'s':>6s}  flags / why (no lower end)"]
    for r in rows:
        flags = ((["FALSE: " + "; ".join(r["false"])] if r["false"] else []) + (["BADDESIGN"] if r["baddesign"] else [])
                 + (["REF-REFUTED: " + "; ".join(r["refuted"])] if r.get("refuted") else []))
        note = " ".join(flags) or ("" if r["lower"] is not None else (r["why"] or "")[:300])
        out.append(f"{r['plant']:6s} {r['problem']:2s} {r['n']:2d} {(r['word'] or r['error'] or '?')[:16]:16s} "
                   f"{_f(r['design_level'], '.9g'):>11s} {_f(r['lower'], '.9g'):>11s} {_f(r['upper'], '.9g'):>11s} "
                   f"{_f(r['width'], '.2e'):>8s} {_f(r['ref_lo'], '.9g'):>11s} {_f(r['ref_hi'], '.9g'):>11s} "
                   f"{_f(r['closed_loop'], '.9g'):>11s} {_f(r['wall'], '.1f'):>6s}  {note}")
    return "\n".join(out)


def summary(rows: list[dict]) -> str:
    lines = []
    for problem in ("of", "sf"):
        group = [r for r in rows if r["problem"] == problem]
        if not group:
            continue
        cert = [r for r in group if r["certified"]]
        proved = [r for r in cert if r["lower"] is not None]
        widths = sorted(r["width"] for r in proved if r["width"] is not None)
        with_ref = [r for r in group if r["ref_hi"] is not None]
        lines.append(
            f"{problem.upper()}: {len(group)} plants, {len(cert)} certified, lower end proved on "
            f"{len(proved)}/{len(cert)} certified ({100 * len(proved) / max(1, len(cert)):.0f} %); width median "
            f"{_f(widths[len(widths) // 2] if widths else None, '.2e')}, "
            f"worst {_f(widths[-1] if widths else None, '.2e')}; "
            f"reference on {len(with_ref)}; FALSE {sum(bool(r['false']) for r in group)}, "
            f"BADDESIGN {sum(r['baddesign'] for r in group)}, "
            f"reference refuted {sum(bool(r.get('refuted')) for r in group)}, "
            f"errors/timeouts {sum(bool(r['error']) for r in group)}; "
            f"median {_f(float(np.median([r['wall'] for r in group if r['wall'] is not None])), '.1f')} s")
    return "\n".join(lines)


def structure_table(names: list[str], refs: dict) -> str:
    out = ["plant   n nw nz nu ny rkD12 rkD21 D11  jω-zeros P12 / P21  OF reference [lo, hi]"
           "            SF reference [lo, hi]"]
    for name in names:
        s, r = refs[name]["structure"], refs[name]
        of = (f"[{_f(r['of'].get('lo'), '.9g')}, {_f(r['of']['hi'], '.9g')}]" if "hi" in r["of"] else "none")
        sf = (f"[{_f(r['sf'].get('lo'), '.9g')}, {_f(r['sf']['hi'], '.9g')}]" if "hi" in r["sf"] else "none")
        jw = f"{len(s['jw_P12'])} / {len(s['jw_P21'])}"
        out.append(f"{name:6s} {s['n']:2d} {s['nw']:2d} {s['nz']:2d} {s['nu']:2d} {s['ny']:2d} {s['rank_D12']:5d} "
                   f"{s['rank_D21']:5d} {'0' if s['D11_zero'] else '≠0':3s}  {jw:19s} {of:31s} {sf}")
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", help="comma-separated plant names")
    parser.add_argument("--problems", default="of,sf", help="of, sf or of,sf")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per case")
    parser.add_argument("--out", help="write the table and summary to this file")
    parser.add_argument("--json", help="write the rows as JSON")
    parser.add_argument("--label", default="", help="a line for the header (which lmidsl)")
    parser.add_argument("--child", nargs=2, metavar=("NAME", "PROBLEM"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        print(json.dumps(solve_case(*args.child)), flush=True)
        return 0
    names = list(PLANTS) if not args.only else [s.strip() for s in args.only.split(",")]
    unknown = [n for n in names if n not in PLANTS]
    if unknown:
        parser.error(f"unknown plant(s) {unknown}; known: {', '.join(PLANTS)}")
    problems = [p.strip() for p in args.problems.split(",")]
    if any(p not in THEOREMS for p in problems):
        parser.error("--problems: of, sf")
    refs = {}
    for name in names:
        refs[name] = references(name)
    rows = []
    for name in names:
        for problem in problems:
            r = run_case(name, problem, refs[name], args.timeout)
            rows.append(r)
            print(table([r], refs).splitlines()[1], flush=True)
    lmidsl_at = sorted({r["lmidsl"] for r in rows if r.get("lmidsl")})
    text = "\n".join([f"COMPleib H∞ stress set, continuous time ({len(names)} plants; {args.label or ''}"
                      f" lmidsl from {', '.join(lmidsl_at) or '?'}; per-case limit {args.timeout:.0f} s)", "",
                      "Structure and references (OF: [Glover–Doyle Riccati floor, SB10FD achieved level]; SF: "
                      "[full-information Riccati floor, Riccati bisection achieved level]):", structure_table(names, refs), "",
                      table(rows, refs), "", summary(rows)])
    print("\n" + summary(rows))
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"rows": rows, "refs": refs}, fh, indent=1, default=lambda o: str(o))
    return 1 if any(r["false"] or r["baddesign"] for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
