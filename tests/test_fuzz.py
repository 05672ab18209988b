"""Property tests (hypothesis) of the builder, the compiler and the command line's input
parsing: every random theorem compiles (cvxpy and direct backends) to the same matrices as numpy's
evaluation of its block matrices, or is refused with a one-line :class:`LmidslError`; every
random ``--set`` value and ``--grid`` text is bound or refused in one line.  The default run is
short; ``python benchmarks/fuzz.py`` runs ≥ 10,000 cases."""
from __future__ import annotations

import json
import math

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

from fuzzing import run_case  # noqa: E402
from lmidsl.cli.common import parse_overrides  # noqa: E402
from lmidsl.errors import LmidslError  # noqa: E402
from lmidsl.pipeline import make_instance  # noqa: E402
from lmidsl.studies.defaults import parse_grid  # noqa: E402

FAST = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.parametrize("backend", ["cvxpy", "direct"])
@FAST
@given(seed=st.integers(min_value=0, max_value=2 ** 32 - 1))
def test_random_theorems_compile_to_the_numpy_matrices_or_are_refused(backend, seed):
    outcome, detail = run_case(seed, backend)
    assert outcome in ("same", "refused"), detail


def _one_line(exc: LmidslError) -> bool:
    return "\n" not in str(exc) and bool(str(exc).strip())


json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10, 10) | st.text(max_size=3)
    | st.floats(allow_nan=True, allow_infinity=True),
    lambda children: st.lists(children, max_size=3), max_leaves=8)


SET_VALUES = {"name": st.sampled_from(["rbar", "E", "A", "D", "L"]), "value": json_values}
GRID_TEXTS = {"text": st.text(alphabet="rbar=0123456789.,:-naiNfe ", max_size=24)}


def check_set_value(name, value):
    text = f"{name}={json.dumps(value)}"        # Python writes NaN / Infinity tokens: refused
    try:
        overrides = parse_overrides([text])
        instance = make_instance("wang_l2linf.thm3", "paper-full", overrides=overrides)
    except LmidslError as exc:
        assert _one_line(exc), str(exc)
        return
    for v in instance.params.values():
        assert math.isfinite(v)


def check_grid_text(text):
    try:
        name, values = parse_grid(text, max_points=1000)
    except LmidslError as exc:
        assert _one_line(exc), str(exc)
        return
    assert name and values and len(values) <= 1000
    assert all(math.isfinite(v) for v in values)


@FAST
@given(**SET_VALUES)
def test_set_values_are_bound_or_refused_in_one_line(name, value):
    check_set_value(name, value)


@FAST
@given(**GRID_TEXTS)
def test_grid_text_is_parsed_or_refused_in_one_line(text):
    check_grid_text(text)
