"""The design stress set (benchmarks/stress/designs.py): the delivered designs against
python-control/slycot, the back-off's cost in words, and lower ends that say nothing."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import lmidsl
from lmidsl.solver.verdict import useless_lower_end

pytest.importorskip("control")
pytest.importorskip("slycot")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks" / "stress"))


def test_a_lower_end_at_or_below_zero_is_no_useful_lower_bound():
    """−1.2e-271 under an optimum of ~1e-7 is true and useless; [6.237, 6.497] is a bracket."""
    assert "no useful lower bound" in useless_lower_end(-1.2e-271, 1.3e-7)
    assert "no useful lower bound" in useless_lower_end(0.0, 1e-7)
    assert "no useful lower bound" in useless_lower_end(0.4, 1.0)       # wider than its lower end
    assert useless_lower_end(6.237, 6.497) == ""


def _case(name):
    from designs import cases
    return next(c for c in cases() if c["name"] == name)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["hinf_of_ct/random-21", "hinf_of_dt/light-32"])
def test_output_feedback_within_one_percent_of_slicot(name):
    """The delivered controller's certified level is ≤ 1.01 × the best level SLICOT achieves
    (SB10FD / SB10DD bisection, each closed loop measured), and python-control measures its
    closed loop at or below the certified level; a back-off point's verdict states its cost."""
    from bench_designs import judge

    case = _case(name)
    row = judge(case)
    assert row["certified"], row
    assert row["judged"] <= row["level"] * (1 + 1e-6), row
    assert row["level"] <= case["truth"]["optimum"] * 1.01, row
    if row["backoff_delta"] is not None:
        assert "back-off" in row["verdict"] and "over the SDP optimum" in row["verdict"], row["verdict"]
