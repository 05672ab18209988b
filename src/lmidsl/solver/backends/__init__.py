"""The one registry of backends and solvers.

A *backend* compiles a bound theorem for one modelling layer (:class:`BackendInfo`: where its
model class lives, the package it needs, the solvers tried in order when the default one fails
numerically); a *solver* has properties the rest of the library asks about (:class:`SolverInfo`:
first-order methods are less accurate and their 'optimal' is not trusted in a cross-check; how
to install it).  Adding a backend or a solver is one entry here (plus, for a backend, its
module with a ``CompiledModel`` subclass, ``sdp_solvers()`` and ``resolve_solver(name)``).

The backend modules import cvxpy / PICOS, which are heavy: they are imported when first used.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

from ...errors import SolverUnavailableError


@dataclass(frozen=True)
class BackendInfo:
    name: str
    module: str                  # relative module holding the model class
    model_class: str
    package: str                 # the pip package it needs
    default: str = ""            # the solver used when none is named
    fallbacks: tuple = ()        # Routes tried, in order, when the default gives no certified point


@dataclass(frozen=True)
class Route:
    """A backend and one of its solvers (:mod:`lmidsl.solver.fallback`)."""
    backend: str
    solver: str

    def __str__(self) -> str:
        return f"{self.backend}/{self.solver}"


@dataclass(frozen=True)
class SolverInfo:
    name: str
    first_order: bool = False    # ADMM-type: tolerances ~1e-4, 'optimal' is not trustworthy alone
    pip: str | None = None       # how to install it
    cvxpy_options: tuple = ()    # (keyword, value) pairs cvxpy passes unless the user overrides


BACKEND_INFO = {
    # lmidsl's own standard form, handed to Clarabel without a modelling layer; then CVXOPT
    # through PICOS (it certifies where Clarabel is inaccurate: lmidsl.solver.fallback), Clarabel
    # on cvxpy's canonicalisation of the same LMIs, CVXOPT through cvxpy, SCS last
    "direct": BackendInfo("direct", ".direct_backend", "DirectModel", "clarabel", default="CLARABEL",
                          fallbacks=(Route("picos", "cvxopt"), Route("cvxpy", "CLARABEL"),
                                     Route("cvxpy", "CVXOPT"), Route("cvxpy", "SCS"))),
    # CVXOPT behind PICOS before CVXOPT behind cvxpy: on ill-conditioned synthesis LMIs the first
    # certifies where the second fails (lmidsl.solver.fallback); SCS last (first-order, slow)
    "cvxpy": BackendInfo("cvxpy", ".cvxpy_backend", "CvxpyModel", "cvxpy", default="CLARABEL",
                         fallbacks=(Route("picos", "cvxopt"), Route("cvxpy", "CVXOPT"), Route("cvxpy", "SCS"))),
    "picos": BackendInfo("picos", ".picos_backend", "PicosModel", "picos", default="cvxopt",
                         fallbacks=(Route("cvxpy", "CLARABEL"), Route("cvxpy", "SCS"))),
}
BACKENDS = tuple(BACKEND_INFO)
DEFAULT_BACKEND = "direct"
"""The backend a solve uses unless told otherwise: no modelling layer between the LMIs and Clarabel
(compiles 3–6× faster than cvxpy and imports no cvxpy); its fallback routes reach cvxpy and PICOS."""

SOLVER_INFO = {s.name: s for s in (
    SolverInfo("clarabel", pip="clarabel"),
    SolverInfo("cvxopt", pip="cvxopt"),
    # without a cap SCS iterates for minutes on an ill-posed LMI and certifies nothing
    SolverInfo("scs", first_order=True, pip="scs", cvxpy_options=(("max_iters", 20000),)),
    SolverInfo("cosmo", first_order=True),
    SolverInfo("mosek", pip="mosek (and a licence)"),
    SolverInfo("copt", pip="coptpy (and a licence)"),
    SolverInfo("sdpa", pip="sdpa-python"),
    SolverInfo("scip"),
)}


def backend_info(name: str | None) -> BackendInfo:
    key = (name or DEFAULT_BACKEND).lower()
    if key not in BACKEND_INFO:
        raise SolverUnavailableError(f"unknown backend {name!r}; available: {', '.join(BACKENDS)}")
    return BACKEND_INFO[key]


def _module(name: str | None):
    info = backend_info(name)
    try:
        return importlib.import_module(info.module, __name__)
    except ImportError:
        raise SolverUnavailableError(
            f"backend {info.name!r} needs the {info.package} package (pip install {info.package})") from None


def get_backend(name: str = DEFAULT_BACKEND):
    """The :class:`~lmidsl.solver.backends.base.CompiledModel` subclass of a backend."""
    return getattr(_module(name), backend_info(name).model_class)


def backend_sdp_solvers(name: str) -> list[str]:
    """Installed SDP-capable solvers of a backend, in that backend's spelling."""
    return list(_module(name).sdp_solvers())


def resolve_solver(backend: str, solver: str | None) -> str:
    """A backend's own name for an installed SDP solver, or a one-line error (saying how to
    install a solver that lmidsl knows but this machine lacks)."""
    module = _module(backend)
    try:
        return module.resolve_solver(solver)
    except SolverUnavailableError as exc:
        info = SOLVER_INFO.get((solver or "").lower())
        if info is None or info.pip is None or not any(
                phrase in str(exc) for phrase in ("unknown solver", "not installed")):
            raise
        listed = ", ".join(module.sdp_solvers()) or "none"
        raise SolverUnavailableError(
            f"solver {solver!r} is not installed (pip install {info.pip}); SDP solvers installed "
            f"for backend {backend_info(backend).name}: {listed}") from None


def choose_backend(backend: str | None, solver: str | None = None) -> str:
    """The backend of a solve: the one named; else the default when it has ``solver`` (or no
    solver is named); else the first other backend that has it, so that ``--solver CVXOPT``
    alone reaches cvxpy's CVXOPT.  A solver no backend has gets the default's one-line error."""
    if backend:
        return backend_info(backend).name
    if solver is None:
        return DEFAULT_BACKEND
    for name in (DEFAULT_BACKEND, *(b for b in BACKENDS if b != DEFAULT_BACKEND)):
        try:
            resolve_solver(name, solver)
            return name
        except SolverUnavailableError as exc:
            if "cannot solve SDPs" in str(exc):      # installed, but not for SDPs (e.g. HiGHS)
                raise
    installed = []
    for name in BACKENDS:
        try:
            installed.append(f"{name}: {', '.join(backend_sdp_solvers(name)) or 'none'}")
        except SolverUnavailableError:
            continue
    info = SOLVER_INFO.get(solver.lower())
    what = f"solver {solver!r} is not installed (pip install {info.pip})" if info and info.pip else \
        f"unknown solver {solver!r}"
    raise SolverUnavailableError(f"{what}; SDP solvers installed here: {'; '.join(installed)}")


def options_for(backend: str, solver: str, options: dict | None) -> dict:
    """Solver options of one row: keys ``solver`` or ``backend:solver`` (case-insensitive); the
    key ``""`` holds options for every row."""
    out: dict = {}
    for target, opts in sorted((options or {}).items(), key=lambda item: item[0].count(":") + bool(item[0])):
        b, sep, s = target.partition(":")
        if not target.strip():
            hit = True
        elif sep:
            hit = b.strip().lower() == backend and s.strip().lower() == solver.lower()
        else:
            hit = target.strip().lower() == solver.lower()
        if hit:
            out.update(opts)
    return out


def fallback_routes(backend: str) -> tuple:
    """Routes to try, in order, after the backend's default solver gave no certified point."""
    return backend_info(backend).fallbacks


def second_opinion(backend: str, solver: str | None) -> Route | None:
    """A route with another solver than ``solver`` (a second opinion, e.g. on "infeasible"): the
    backend's own other solvers first (its default, then its fallbacks on the same backend), then
    its other fallback routes; first-order solvers are not asked.  None when there is none."""
    info = backend_info(backend)
    own = [Route(info.name, info.default)] + [r for r in info.fallbacks if r.backend == info.name]
    candidates = own + [r for r in info.fallbacks if r.backend != info.name]
    for route in candidates:
        if route.solver and route.solver.lower() != (solver or "").lower() and not is_first_order(route.solver):
            return route
    return None


def default_options(solver: str) -> dict:
    """The keyword options a backend passes to ``solver`` unless the user gives them."""
    info = SOLVER_INFO.get((solver or "").lower())
    return dict(info.cvxpy_options) if info else {}


def is_first_order(solver: str) -> bool:
    info = SOLVER_INFO.get((solver or "").lower())
    return bool(info and info.first_order)


__all__ = ["BACKENDS", "DEFAULT_BACKEND", "BACKEND_INFO", "SOLVER_INFO", "BackendInfo", "SolverInfo",
           "Route", "get_backend", "choose_backend", "second_opinion", "backend_sdp_solvers",
           "resolve_solver", "fallback_routes", "is_first_order", "backend_info", "default_options"]
