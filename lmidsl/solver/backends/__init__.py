"""Backends compile a bound theorem for one modelling layer and solve it.

``get_backend(name)`` returns the model class for ``"cvxpy"`` (default) or ``"picos"``;
``backend_sdp_solvers(name)`` lists the installed solvers of a backend that accept LMIs.
"""
from __future__ import annotations

from ...errors import SolverUnavailableError

BACKENDS = ("cvxpy", "picos")


def get_backend(name: str = "cvxpy"):
    """The :class:`~lmidsl.solver.backends.base.CompiledModel` subclass of a backend."""
    key = (name or "cvxpy").lower()
    if key == "cvxpy":
        from .cvxpy_backend import CvxpyModel
        return CvxpyModel
    if key == "picos":
        try:
            from .picos_backend import PicosModel
        except ImportError:
            raise SolverUnavailableError("backend 'picos' needs the picos package (pip install picos)") from None
        return PicosModel
    raise SolverUnavailableError(f"unknown backend {name!r}; available: {', '.join(BACKENDS)}")


def backend_sdp_solvers(name: str) -> list[str]:
    """Installed SDP-capable solvers of a backend, in that backend's spelling."""
    key = name.lower()
    if key == "cvxpy":
        from .cvxpy_backend import sdp_solvers
        return list(sdp_solvers())
    if key == "picos":
        get_backend("picos")
        from .picos_backend import sdp_solvers
        return list(sdp_solvers())
    raise SolverUnavailableError(f"unknown backend {name!r}; available: {', '.join(BACKENDS)}")


def resolve_solver(backend: str, solver: str | None) -> str:
    """A backend's own name for an installed SDP solver, or a one-line error."""
    key = backend.lower()
    if key == "cvxpy":
        from .cvxpy_backend import resolve_solver as resolve
    elif key == "picos":
        get_backend("picos")
        from .picos_backend import resolve_solver as resolve
    else:
        raise SolverUnavailableError(f"unknown backend {backend!r}; available: {', '.join(BACKENDS)}")
    return resolve(solver)
