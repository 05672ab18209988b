"""Backends compile a bound theorem for one modelling layer and solve it.

``get_backend(name)`` returns the model class for ``"cvxpy"`` (default).
"""
from __future__ import annotations

from ..errors import SolverUnavailableError

BACKENDS = ("cvxpy",)


def get_backend(name: str = "cvxpy"):
    """The :class:`~lmidsl.backends.base.CompiledModel` subclass of a backend."""
    if name == "cvxpy":
        from .cvxpy_backend import CvxpyModel
        return CvxpyModel
    raise SolverUnavailableError(f"unknown backend {name!r}; available: {', '.join(BACKENDS)}")
