"""Recovery of the design: the theorem's change of variables evaluated at the solved point.

A theorem declares its recovery as ordered steps: sympy formulas (``Theorem.recover``, e.g.
``Af = V2⁻¹ Âf``) and library factorisations producing named intermediate matrices
(``Theorem.factor``, e.g. R, S with R Sᵀ = I − X Z⁻¹, see :mod:`lmidsl.numeric.factorization`),
which later formulas use.  Every matrix that gets inverted is reported with its 2-norm
condition number, because an ill-conditioned inverse makes a recovered design untrustworthy
even when the LMIs are comfortably feasible.
"""
from __future__ import annotations

import numpy as np

from .design import Design
from .instance import Instance
from .evaluate import NumericEvaluator
from .exact import midpoint
from .proof import PRECISION, BallEvaluator, PreciseMatrix, ball_precision
from ..theorem.values import FactorStep


def recover(instance: Instance, values: dict) -> tuple[dict, list]:
    """(recovered matrices by name, [{matrix, cond}] for every inverted/factored matrix)."""
    theorem = instance.theorem
    point = dict(instance.data)
    point.update(values)
    evaluator = NumericEvaluator(instance.dims, point, instance.params)
    reports: list = []
    recovered = {}
    precise = any(getattr(v, "exact", None) is not None for v in values.values())
    steps = theorem.recovery_steps or [("formula", name) for name in theorem.recovery]
    for step in steps:
        if isinstance(step, FactorStep):
            args = [_precise_formula(instance, point, a, exact=True) if precise
                    else np.atleast_2d(evaluator.visit(a)) for a in step.args]
            outputs, report = step.factorization(*args)
            point.update(dict(zip(step.names, outputs)))
            reports += report
        else:
            name = step[1]
            recovered[name] = np.atleast_2d(evaluator.visit(theorem.recovery[name]))
            if precise:
                recovered[name] = _precise_formula(instance, point, theorem.recovery[name])
            point[name] = recovered[name]        # a later formula may use it
    return recovered, reports + evaluator.inverted


def _precise_formula(instance: Instance, point: dict, formula, exact: bool = False) -> np.ndarray:
    """A recovery formula (or a factorisation's argument) at a point holding exact values
    (:class:`~lmidsl.numeric.proof.PreciseMatrix`: the Riccati routes' points), evaluated in
    :data:`PRECISION`-bit ball arithmetic and rounded to doubles.  In doubles, K = W Y⁻¹ at a Y of
    condition number 1e18 (H∞ state feedback, 24 states) is noise; exactly, it is the gain the
    point was built from.  Likewise I − X Y at an output-feedback point whose X Y ≈ I (a singular
    plant near its optimum): in doubles it loses every digit the factors M Nᵀ = I − X Y need, so
    a factorisation's argument is returned with ``exact``: a
    :class:`~lmidsl.numeric.proof.PreciseMatrix` of the balls' midpoints, which the factorisation
    splits in high precision (:func:`lmidsl.numeric.factorization.balanced_split`)."""
    with ball_precision(PRECISION):
        balls = np.atleast_2d(np.asarray(BallEvaluator(instance.dims, point, instance.params).visit(formula),
                                         dtype=object))
        if exact:
            return PreciseMatrix.of(np.vectorize(midpoint, otypes=[object])(balls))
        return np.array([[float(x.mid()) for x in row] for row in balls], dtype=float)


def recover_design(instance: Instance, values: dict, undo=None, **obtained) -> Design:
    """The :class:`Design` recovered at ``values``; ``undo`` maps the matrices of a scaled
    instance back to the original coordinates (:meth:`lmidsl.numeric.scaling.AppliedScaling.undo`)."""
    matrices, inverted = recover(instance, values)
    if undo is not None:
        matrices = undo(matrices)
    theorem = instance.theorem
    return Design(theorem.designs or "unspecified", matrices, theorem.time, theorem.sample_time,
                  tuple(inverted), {"theorem": theorem.id, "example": instance.example, **obtained})
