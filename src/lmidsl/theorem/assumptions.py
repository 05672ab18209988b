"""Assumptions a theorem makes on its data, declared once and checked at bind time.

A theorem's LMIs are a true statement only under its hypotheses: the continuous-time H2 norm is
finite only when the feedthrough D11 is 0 (and a theorem that takes no D11 would otherwise drop
a nonzero one with the routine "unused data" warning, then print a finite h2 for a plant whose
norm is infinite); a Gramian needs A stable; a recovery may need a matrix of full rank.
Declared with :meth:`lmidsl.Theorem.assume`::

    thm.assume(zero("D11", why="the continuous-time H2 norm is infinite when D11 ≠ 0"))
    thm.assume(stable("A"))

and checked by :func:`check_assumptions` when data are bound (:func:`lmidsl.numeric.instance.bind`):
one line naming the theorem, the assumption and the datum, exit code 2.  An assumption reads
the inputs as given, so it sees data the theorem itself does not use (D11 above); a name not
given at all is not checked (a theorem that takes no D11 assumes it 0).  A per-vertex datum is
checked at every vertex.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError


class Assumption:
    """A named hypothesis on the data: ``holds(value)`` for the datum ``name``; ``why`` says what
    fails without it."""

    label = "assumption"

    def __init__(self, name: str, why: str = ""):
        self.name, self.why = name, why

    def holds(self, value: np.ndarray, time: str) -> str | None:
        """None when it holds, else what is wrong (a few words)."""
        raise NotImplementedError

    def describe(self) -> str:
        return self.label.format(name=self.name)


class Zero(Assumption):
    label = "{name} = 0"

    def holds(self, value, time):
        largest = float(np.max(np.abs(value))) if value.size else 0.0
        return None if largest == 0.0 else f"its largest entry is {largest:.3g}"


class Stable(Assumption):
    """Continuous time: every eigenvalue in Re s < 0; discrete time: inside the unit circle."""

    label = "{name} stable"

    def holds(self, value, time):
        if value.ndim != 2 or value.shape[0] != value.shape[1]:
            return "it is not square"
        eigs = np.linalg.eigvals(value)
        worst = float(np.max(eigs.real)) if time == "continuous" else float(np.max(np.abs(eigs)))
        bound = 0.0 if time == "continuous" else 1.0
        what = "largest real part" if time == "continuous" else "spectral radius"
        return None if worst < bound else f"its {what} is {worst:.6g}"


class FullRank(Assumption):
    """Full column (``side="column"``) or row rank, by numpy's SVD rank (its default tolerance)."""

    def __init__(self, name: str, side: str = "column", why: str = ""):
        super().__init__(name, why)
        self.side = side
        self.label = "{name} of full " + side + " rank"

    def holds(self, value, time):
        value = np.atleast_2d(value)
        rank, need = np.linalg.matrix_rank(value), value.shape[1 if self.side == "column" else 0]
        return None if rank == need else f"its rank is {rank}, not {need}"


def zero(name: str, why: str = "") -> Zero:
    return Zero(name, why)


def stable(name: str, why: str = "") -> Stable:
    return Stable(name, why)


def full_rank(name: str, side: str = "column", why: str = "") -> FullRank:
    return FullRank(name, side, why)


def check_assumptions(theorem, inputs: dict, vertices: list | None = None) -> None:
    """Every assumption of ``theorem`` on ``inputs`` (the data as given, before unused names are
    dropped; ``vertices``: the per-vertex inputs), one line for the first that fails."""
    for assumption in getattr(theorem, "assumptions", ()):
        places = [("", inputs)] + [(f" at vertex {k + 1}", v) for k, v in enumerate(vertices or []) if isinstance(v, dict)]
        for where, values in places:
            if assumption.name not in values:
                continue
            try:
                value = np.asarray(values[assumption.name], dtype=float)
            except (TypeError, ValueError):
                continue                   # not numbers: the binding itself says so
            problem = assumption.holds(value, theorem.time)
            if problem is not None:
                why = f": {assumption.why}" if assumption.why else ""
                raise InputError(f"{theorem.id}: assumption {assumption.describe()} does not hold{where} "
                                 f"({problem}){why}")


__all__ = ["Assumption", "Zero", "Stable", "FullRank", "zero", "stable", "full_rank", "check_assumptions"]
