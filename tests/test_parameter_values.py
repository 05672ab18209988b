"""Derived parameters evaluated with floats (lmidsl.symbolic.parameter_values): the value is
sympy's substituted value to the last bits, nodes without a float rule are substituted, and a
value that is not real is refused."""
from __future__ import annotations

import math

import pytest
import sympy as sp

from lmidsl.symbolic.parameter_values import NotRealError, parameter_value
from lmidsl.symbolic.symbols import DerivedParam, Param


def _param(name):
    return Param(name)


@pytest.fixture()
def xi():
    return _param("pv_xi1"), _param("pv_xi2")


def test_repeated_evaluations_equal_the_substituted_value(xi):
    x1, x2 = xi
    expressions = [sp.sqrt((1 - x1) ** 2 * (1 - x2) * x2), (1 - x1) / (1 + x1), x1 ** sp.Rational(3, 2),
                   sp.sin(x1) * sp.cos(x2) + sp.Abs(x1 - x2), sp.exp(-x1) * sp.log(1 + x2)]
    for expr in expressions:
        for a, b in [(0.05, 0.95), (0.3, 0.7), (0.5, 0.5), (0.9, 0.1), (1e-12, 1e-8)]:
            exact = float(expr.xreplace({x1: sp.Rational(a), x2: sp.Rational(b)}).evalf(30))
            assert parameter_value(expr, {"pv_xi1": a, "pv_xi2": b}) == pytest.approx(exact, rel=4e-16)


def test_a_value_that_is_not_real_is_refused(xi):
    x1, _ = xi
    for expr in (sp.sqrt(x1 - 1), (x1 - 2) ** sp.Rational(3, 2), 1 / (x1 - sp.Rational(1, 2)),
                 sp.log(x1 - 1), sp.Max(x1, 2) ** sp.Rational(1, 3) * sp.sqrt(x1 - 1)):
        with pytest.raises(NotRealError):
            parameter_value(expr, {"pv_xi1": 0.5})


def test_a_node_without_a_float_rule_is_substituted(xi):
    x1, x2 = xi
    expr = sp.Max(x1, x2) + sp.Piecewise((x1, x1 > 0.4), (x2, True))
    assert parameter_value(expr, {"pv_xi1": 0.3, "pv_xi2": 0.7}) == pytest.approx(1.4, rel=1e-15)


def test_a_derived_parameter_inside_is_expanded(xi):
    x1, x2 = xi
    d = DerivedParam("pv_d")
    d.definition = x1 * (1 - x2)
    for _ in range(2):
        assert parameter_value(2 * d, {"pv_xi1": 0.25, "pv_xi2": 0.5}) == 0.25
    assert math.isclose(parameter_value(sp.sqrt(d), {"pv_xi1": 0.5, "pv_xi2": 0.5}), 0.5)
