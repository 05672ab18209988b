"""How a theorem file declares its filtering-error system, in the theorem's own symbols.

A theorem whose data include the filter (the analysis theorem) states the error system once:

    thm1.error_system(
        ErrorSystem(A=A_cl0, B=B_cl, C=C_cl, noise=[{"A": A_cl1}], covariance=[a]),
        figure="energy_to_peak", design=("Af", "Bf", "Cf"), simulate=model_with_filter)

``A, B, C, D`` are the mean matrices; each ``noise`` entry holds the matrices multiplying one
zero-mean random scalar ν_i (keys A, B, C, D, missing = 0); ``covariance`` is Σ = E ννᵀ (a list
= its diagonal, or a nested list), in the theorem's parameters.  Everything is a sympy
expression of the theorem's symbols, evaluated with :class:`~lmidsl.numeric.evaluate.NumericEvaluator`
on an instance (so block matrices are written as the paper writes them).  ``simulate`` is a
numpy function of the *original* model with the filter (see :mod:`.montecarlo`).
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import sympy as sp

from ..numeric.evaluate import NumericEvaluator
from .system import StochasticSystem


class ErrorSystem:
    """Symbolic mean matrices, noise matrices and noise covariance of an error system."""

    def __init__(self, A, B, C, D=None, noise=(), covariance=None):
        self.A, self.B, self.C, self.D = A, B, C, D
        self.noise = [dict(term) for term in noise]
        for i, term in enumerate(self.noise):
            unknown = set(term) - {"A", "B", "C", "D"}
            if unknown:
                raise ValueError(f"noise term {i + 1}: unknown keys {sorted(unknown)} (use A, B, C, D)")
        self.covariance = covariance

    def evaluate(self, instance, vertex: int | None = None) -> StochasticSystem:
        """The numeric :class:`StochasticSystem` of an instance (one vertex of a polytopic one)."""
        ev = NumericEvaluator(instance.dims, instance.data, instance.params, vertex=vertex)

        def num(expr):
            return None if expr is None else np.atleast_2d(ev.visit(expr))

        cov = self.covariance
        if cov is not None:
            cov = np.array([[ev.visit(sp.sympify(c)) for c in row] for row in cov], dtype=float) \
                if isinstance(cov[0], (list, tuple)) else \
                np.array([ev.visit(sp.sympify(c)) for c in cov], dtype=float)
        noise = [{k: num(v) for k, v in term.items()} for term in self.noise]
        return StochasticSystem.build(num(self.A), num(self.B), num(self.C), num(self.D), noise, cov,
                                      time=instance.theorem.time)


def namespace(instance, vertex: int | None = None) -> SimpleNamespace:
    """Dimensions, data (numpy arrays) and parameter values of an instance as attributes: ``d.A``, ``d.rbar``."""
    values = {str(k): v for k, v in instance.dims.items()}
    for name, value in instance.data.items():
        values[name] = np.asarray(value[vertex or 0] if isinstance(value, list) else value, dtype=float)
    values.update(instance.params)
    return SimpleNamespace(**values)
