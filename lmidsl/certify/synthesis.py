"""The synthesis LMIs re-evaluated in numpy at the point a solver returned.

Independent of the backend and of the solver's status: each LMI ``N ≺ 0`` is assembled block by
block from the solved values with :class:`~lmidsl.numeric.evaluate.NumericEvaluator` and its largest
eigenvalue λ_max(N) is reported with the relative margin λ_max(N) / max(1, ‖N‖₂).  The point
certifies the strict LMIs iff every λ_max(N) < 0.
"""
from __future__ import annotations

import numpy as np

from ..numeric.evaluate import NumericEvaluator, evaluate_block_matrix


def synthesis_lmis(solution) -> list[dict]:
    """[{label, max_eig, relative, size, vertex?}] for every LMI of the solved theorem."""
    instance = solution.instance
    point = dict(instance.data)
    point.update(solution.values)
    out = []
    for lmi in instance.theorem.lmis:
        vertices = range(instance.nvertices) if lmi.per_vertex else [None]
        for v in vertices:
            N = evaluate_block_matrix(NumericEvaluator(instance.dims, point, instance.params, vertex=v),
                                      lmi.negative_form())
            N = (N + N.T) / 2
            eigs = np.linalg.eigvalsh(N)
            row = {"label": lmi.label, "max_eig": float(eigs[-1]),
                   "relative": float(eigs[-1] / max(1.0, float(np.max(np.abs(eigs))))),
                   "size": int(N.shape[0])}
            if v is not None:
                row["vertex"] = v + 1
            out.append(row)
    return out
