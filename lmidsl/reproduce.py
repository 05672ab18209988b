"""The main job: every theorem × example, printed value against computed value, with evidence.

For each example that prints a γ, the theorem is solved; the row holds the printed γ, the
computed γ, their relative difference, the certificate (largest LMI eigenvalue at the returned
point), and for synthesis theorems the γ that the analysis counterpart certifies for the
recovered filter.  ``tolerance`` is the relative difference under which a value counts as
reproduced.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

from .api import solve
from .errors import LmidslError
from .registry import all_theorems

REPRODUCED_TOLERANCE = 5e-3


@dataclass
class ReproductionRow:
    theorem: str
    example: str
    printed_kind: str
    printed_gamma: float | None
    computed_gamma: float | None
    rel_diff: float | None
    status: str
    worst_eig: float | None
    certified_gamma: float | None
    certified: bool
    verdict: str

    def as_dict(self) -> dict:
        return asdict(self)


def _verdict(kind, printed, computed, rel, certified, status):
    if status not in ("optimal", "optimal_inaccurate"):
        return status
    if printed is None:
        verdict = "computed (no printed value)"
    elif kind == "gamma_bound":
        holds = computed <= printed * (1 + REPRODUCED_TOLERANCE)
        verdict = "printed bound holds" if holds else "printed bound NOT certified"
    else:
        verdict = "reproduced" if rel <= REPRODUCED_TOLERANCE else "differs from print"
    return verdict + ("" if certified else ", NOT certified")


def reproduce_one(theorem_id: str, example: str, solver: str | None = None) -> ReproductionRow:
    theorem = all_theorems()[theorem_id]
    printed_values = theorem.examples[example].printed
    kind = "gamma_bound" if "gamma_bound" in printed_values else "gamma"
    printed = printed_values.get(kind)
    try:
        sol = solve(theorem, example=example, solver=solver, backoff="auto")
    except LmidslError as exc:
        return ReproductionRow(theorem_id, example, kind, printed, None, None, f"error: {exc}", None,
                               None, False, "error")
    # after an automatic back-off the optimum is what compares with the printed value
    computed = (sol.backoff or {}).get("gamma_opt", sol.gamma) if sol.backoff else sol.gamma
    rel = None
    if printed is not None and computed is not None:
        rel = abs(computed - printed) / abs(printed)
    analysis = getattr(sol, "analysis", None)
    certified = sol.certified and (analysis.passed if analysis is not None else True)
    verdict = _verdict(kind, printed, computed, rel, certified, sol.status)
    if sol.backoff and "gamma" in sol.backoff:
        verdict += f" (filter from the back-off at γ {sol.backoff['gamma']:.6g})"
    return ReproductionRow(theorem_id, example, kind, printed, computed, rel, sol.status,
                           sol.worst_eig, analysis.gamma if analysis is not None else None, certified,
                           verdict)


def reproduce_all(solver: str | None = None, theorems: list[str] | None = None, progress=None):
    """Rows for every theorem × example (optionally only the listed theorem ids)."""
    jobs = [(tid, ex) for tid, thm in sorted(all_theorems().items())
            if theorems is None or tid in theorems for ex in thm.examples]
    rows = []
    for tid, ex in (progress(jobs) if progress else jobs):
        rows.append(reproduce_one(tid, ex, solver))
    return rows
