"""Text for a bisection (``lmidsl solve`` on a theorem that declares ``Theorem.bisect``)."""
from __future__ import annotations

from .report import format_solution


def format_bisection(result) -> str:
    head = f"{result.theorem}" + (f" [{result.example}]" if result.example else "")
    lines = [head, f"  bisection on {result.parameter} ({result.goal}) in [{result.lower:g}, {result.upper:g}], "
                   f"tol {result.tol:g}: {len(result.steps)} solves of one compiled model "
                   f"({result.total_time:.2f} s)"]
    if result.feasible_end is not None and result.infeasible_end is not None:
        lo, hi = result.interval
        lines.append(f"  {result.parameter} in [{lo:.10g}, {hi:.10g}]: certified at {result.feasible_end:.10g}, "
                     f"no certified point at {result.infeasible_end:.10g}")
    if result.message:
        lines.append(f"  {result.message}")
    if result.solution is not None:
        lines.append(f"  certificate at the feasible end {result.parameter} = {result.feasible_end:.10g}:")
        lines += ["  " + line for line in format_solution(result.solution).splitlines()]
    lines.append("  verdict: " + result.verdict.line())
    return "\n".join(lines)
