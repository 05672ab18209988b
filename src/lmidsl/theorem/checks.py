"""Extra certificates of a recovered filter, beyond the analysis LMI.

A theorem lists them with ``Theorem.verify_with(check, ...)``; each is a callable taking the
:class:`~lmidsl.solver.solution.Solution` (with its instance, values, recovered filter and analysis
certificate) and returning a :class:`CheckResult`.  ``lmidsl.pipeline.finish_solution`` runs them
after the analysis certificate; the report prints one line per check.
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class CheckResult:
    """Outcome of one independent check: a verdict, a one-line summary, numbers."""

    name: str
    passed: bool
    summary: str
    details: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return {"name": self.name, "passed": self.passed, "summary": self.summary,
                "details": self.details}


def run_checks(solution, designed: bool = True) -> list[CheckResult]:
    """Run the theorem's checks on a solved, recovered solution (or, ``designed=False``, on a
    stand-in for a given filter: checks marked ``needs_synthesis`` are skipped)."""
    return [check(solution) for check in solution.instance.theorem.checks
            if designed or not getattr(check, "needs_synthesis", False)]


def reported_agree(tolerance: float = 1e-3, name: str = "analysis values"):
    """A check: every reported value equals the analysis value within ``tolerance`` (relative).

    For a synthesis theorem whose analysis counterpart reports the same values (e.g. the γ_i of
    each subsystem): the analysis of the recovered filter must give back the synthesis values.
    """

    def check(solution) -> CheckResult:
        analysis = solution.analysis
        if analysis is None or not analysis.reported:
            return CheckResult(name, False, "no analysis values to compare")
        diffs = {}
        for key, value in solution.reported.items():
            if key in analysis.reported:
                other = analysis.reported[key]
                diffs[key] = abs(other - value) / max(abs(value), 1e-12)
        if not diffs:
            return CheckResult(name, False, "the analysis theorem reports none of these values")
        worst = max(diffs, key=diffs.get)
        passed = diffs[worst] <= tolerance
        summary = (f"{len(diffs)} values, largest relative difference {diffs[worst]:.1e} ({worst}); "
                   f"tolerance {tolerance:g}")
        return CheckResult(name, passed, summary, {"relative_differences": diffs})

    check.needs_synthesis = True   # meaningless for a given filter (nothing to compare with)
    return check
