"""Filter recovery: the theorem's change of variables evaluated at the solved point.

The formulas are the symbolic expressions a theorem declares with ``Theorem.recover`` (e.g.
``Af = V2⁻¹ Âf``).  Every matrix that gets inverted is reported with its 2-norm condition
number, because an ill-conditioned inverse makes a recovered filter untrustworthy even when the
LMIs are comfortably feasible.
"""
from __future__ import annotations

import numpy as np

from .instance import Instance
from .numeric import NumericEvaluator


def recover(instance: Instance, values: dict) -> tuple[dict, list]:
    """(recovered matrices by name, [{matrix, cond}] for every inverted matrix)."""
    point = dict(instance.data)
    point.update(values)
    evaluator = NumericEvaluator(instance.dims, point, instance.params)
    recovered = {name: np.atleast_2d(evaluator.visit(expr))
                 for name, expr in instance.theorem.recovery.items()}
    return recovered, evaluator.inverted
