"""The factors of an automatic conditioning (:mod:`lmidsl.solver.conditioning` chooses them; every
backend compiles with them): power-of-two row factors of each LMI's congruence, variable
scalings and the objective's divisor."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Equilibration:
    """Power-of-two factors: ``variables[name]`` = s_X, ``rows[k]`` = [t_1, …, t_q] of the k-th LMI."""

    variables: dict = field(default_factory=dict)
    rows: dict = field(default_factory=dict)
    objective: float = 1.0      # the solver minimises objective / this (coefficients about 1)
    spread: tuple = (0.0, 0.0)  # log2 of largest/smallest coefficient, before and after

    def variable(self, name: str) -> float:
        return self.variables.get(name, 1.0)

    def row(self, lmi_index: int, i: int) -> float:
        factors = self.rows.get(lmi_index)
        return factors[i] if factors else 1.0

    @property
    def trivial(self) -> bool:
        return all(f == 1.0 for f in self.variables.values()) and \
            all(f == 1.0 for fs in self.rows.values() for f in fs) and self.objective == 1.0

    def as_dict(self) -> dict:
        return {"objective": self.objective, "spread_bits": list(self.spread),
                "variables": {k: v for k, v in self.variables.items() if v != 1.0},
                "rows": {str(k): v for k, v in self.rows.items() if any(f != 1.0 for f in v)}}


__all__ = ["Equilibration"]
