"""Coefficient matrices with a stated tolerance and a declared completion of the diagonal.

Transition rates printed to 4 decimals do not sum to 0 row by row; the error names the row, its
sum and the tolerance, and the declared completion (π_ii = −Σ_{j≠i} π_ij, in the theorem or with
the data) solves them.  The design is judged by the second-moment matrix of the closed loop,
assembled here (as in tests/test_gallery_indexed.py), not by the solver.
"""
from __future__ import annotations

import json

import numpy as np
import pytest
from sympy import Ne, sqrt

import lmidsl
from lmidsl import He, I, Source, Theorem, diag_over, stack_over
from lmidsl.errors import InputError, TheoremDefinitionError
from lmidsl.theorems.textbook import markov
from test_gallery_indexed import second_moment_value

# four modes: two unstable controlled, one stable, one uncontrolled (B = 0) and stable
MODES = [{"A": [[0.0, 1.0], [2.0, -1.0]], "B": [[0.0], [1.0]]},
         {"A": [[0.5, 0.3], [0.0, -0.4]], "B": [[1.0], [0.2]]},
         {"A": [[-1.0, 0.4], [0.1, -2.0]], "B": [[0.5], [1.0]]},
         {"A": [[-1.5, 0.2], [0.3, -1.2]], "B": [[0.0], [0.0]]}]
# rates printed to 4 decimals: the diagonal was rounded separately, rows miss 0 by ≥ 1e-4
RATES = [[-1.2347, 0.3333, 0.6667, 0.2346],
         [0.1429, -0.8572, 0.2857, 0.4285],
         [0.5556, 0.1111, -0.7778, 0.1110],
         [0.4, 0.2, 0.3, -0.9003]]


def _mjls(name, diagonal):
    thm = Theorem(name, "MJLS", Source("test", "test"), time="continuous", designs="gain")
    n, m = thm.dim("n m")
    M = thm.index_set("modes", latex=r"\mathcal{N}")
    i, j = M.indices("i j")
    A = thm.data("A", n, n, over=M)
    B = thm.data("B", n, m, over=M)
    Pi = thm.coefficients("Pi", M, structure="generator", diagonal=diagonal, latex=r"\pi")
    Y = thm.var("Y", n, kind="symmetric", over=M)
    W = thm.var("W", m, n, over=M)
    thm.lmi("(MJ)", [[He(A[i] * Y[i] + B[i] * W[i]) + Pi[i, i] * Y[i]],
                     [stack_over(j, sqrt(Pi[i, j]) * Y[i], Ne(j, i)), -diag_over(j, Y[j], Ne(j, i))]],
            forall=i)
    thm.lmi("Y >= I", [[Y[i] - I]], sense=">=", strict=False, forall=i)
    thm.feasibility()
    thm.recover_each(i, K=W[i] * Y[i].I)
    return thm


def _completed(rates):
    R = np.array(rates, dtype=float)
    np.fill_diagonal(R, 0.0)
    np.fill_diagonal(R, -R.sum(axis=1))
    return R


def _mean_square_stable(sol, Pi):
    closed = [np.array(md["A"]) + np.array(md["B"]) @ sol.design[f"K_{k + 1}"]
              for k, md in enumerate(MODES)]
    return second_moment_value(closed, Pi, "continuous")


def test_rounded_rates_are_refused_naming_the_row_the_sum_and_the_tolerance():
    with pytest.raises(InputError) as err:
        lmidsl.solve(markov.mjls_sf_ct, data={"modes": MODES, "Pi": RATES}, diagnose=False)
    text = str(err.value)
    worst = int(np.abs(np.array(RATES).sum(axis=1)).argmax())
    assert f"row {worst + 1} sums to {np.array(RATES)[worst].sum():.6g}" in text
    assert "tolerance 1e-09" in text and 'diagonal="complete"' in text and "\n" not in text


def test_declared_completion_in_the_data_solves_the_rounded_rates():
    with pytest.warns(lmidsl.LmidslWarning, match=r"diagonal completes each row .*\(4, 4\): -0.9003 -> -0.9"):
        sol = lmidsl.solve(markov.mjls_sf_ct, data={"modes": MODES,
                                                    "Pi": {"matrix": RATES, "diagonal": "complete"}},
                           diagnose=False)
    Pi = _completed(RATES)
    assert sol.certified
    assert np.array_equal(np.array(sol.instance.data["Pi"]), Pi)   # off-diagonal untouched
    assert _mean_square_stable(sol, Pi) < 0
    assert np.allclose(sol.design["K_4"], 0.0)                      # uncontrolled mode


def test_declared_completion_in_the_theorem_solves_the_rounded_rates():
    sol = lmidsl.solve(_mjls("t.complete", "complete"), data={"modes": MODES, "Pi": RATES},
                       diagnose=False)
    assert sol.certified and _mean_square_stable(sol, _completed(RATES)) < 0
    with pytest.raises(InputError, match="row"):
        lmidsl.solve(_mjls("t.given", "given"), data={"modes": MODES, "Pi": RATES}, diagnose=False)


def test_structure_errors_name_the_entry_and_bad_declarations_are_refused():
    bad = [row[:] for row in RATES]
    bad[2][1] = -0.1
    with pytest.raises(InputError, match=r"off-diagonal entry \(3, 2\) is -0.1"):
        lmidsl.solve(markov.mjls_sf_ct, data={"modes": MODES,
                                              "Pi": {"matrix": bad, "diagonal": "complete"}})
    with pytest.raises(InputError, match="diagonal must be one of"):
        lmidsl.solve(markov.mjls_sf_ct, data={"modes": MODES, "Pi": {"matrix": RATES, "diagonal": "yes"}})
    with pytest.raises(TheoremDefinitionError, match="diagonal='complete' needs"):
        thm = Theorem("t.bad", "bad", Source("t", "t"))
        thm.coefficients("Pi", thm.index_set("modes"), structure="nonnegative", diagonal="complete")


def test_cli_names_the_row_in_one_line(tmp_path):
    from conftest import run_cli
    data = tmp_path / "d.json"
    data.write_text(json.dumps({"modes": MODES, "Pi": RATES}))
    code, out, err = run_cli("solve", "textbook.mjls_sf_ct", "--data", str(data))
    err = err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "row 4 sums to -0.0003" in err
