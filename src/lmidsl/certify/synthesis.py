"""The synthesis LMIs re-evaluated in numpy at the point a solver returned.

Independent of the backend and of the solver's status: each LMI ``N ≺ 0`` is assembled from the
solved values at every polytope vertex and uncertainty scenario it is imposed at (the same
certificate :func:`lmidsl.solver.solution.lmi_certificate` gives every solve), with its largest
eigenvalue λ_max(N), the relative margin λ_max(N) / max(1, ‖N‖₂) and the proof in ball
arithmetic (:mod:`lmidsl.numeric.proof`).  The point certifies the strict LMIs iff every one is
proved.
"""
from __future__ import annotations

from ..solver.solution import lmi_certificate


def synthesis_lmis(solution) -> list[dict]:
    """[{label, max_eig, relative, size, vertex?, point?}] for every LMI of the solved theorem."""
    instance = solution.instance
    return [r.as_dict() for r in lmi_certificate(instance, {**instance.data, **solution.values}, prove=True)]
