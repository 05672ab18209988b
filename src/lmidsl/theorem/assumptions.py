"""Assumptions a theorem makes on its data, declared once and checked at bind time.

A theorem's LMIs are a true statement only under its hypotheses: the continuous-time H2 norm is
finite only when the feedthrough D11 is 0 (and a theorem that takes no D11 would otherwise drop
a nonzero one with the routine "unused data" warning, then print a finite h2 for a plant whose
norm is infinite); a Gramian needs A stable; a recovery may need a matrix of full rank.
Declared with :meth:`lmidsl.Theorem.assume`::

    thm.assume(zero("D11", why="the continuous-time H2 norm is infinite when D11 ≠ 0"))
    thm.assume(stable("A"))

and checked by :func:`check_assumptions` when data are bound (:func:`lmidsl.numeric.instance.bind`):
one line naming the theorem, the assumption and the datum, exit code 2.  The name must be a
datum of the theorem (checked at declaration: a typo such as ``zero("Dl1")`` would otherwise
check nothing), or be marked ``external=True``: a datum the theorem does not take, which an
assumption still reads from the inputs as given (``zero("D11", external=True)``: a theorem that
takes no D11 assumes it 0, and a plant file that gives one must give 0); an external name not
given at all is not checked.  The assumption is checked for every member: at every vertex of a
polytope (``vertices``), for every member of an index set (``"modes": [{"A": …}, …]``, e.g.
``stable("A")`` on a per-mode A refuses the unstable mode, naming it), and for a datum given
once for all members.  A value that is not a finite real matrix is an error, never skipped.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError, TheoremDefinitionError, did_you_mean


class Assumption:
    """A named hypothesis on the data: ``holds(value)`` for the datum ``name``; ``why`` says what
    fails without it."""

    label = "assumption"

    def __init__(self, name: str, why: str = "", external: bool = False):
        self.name, self.why, self.external = name, why, external

    def check_declared(self, theorem) -> None:
        """At :meth:`lmidsl.Theorem.assume`: the name is a datum of ``theorem`` (plain, per vertex
        or indexed by an index set), or the assumption is ``external``."""
        names = set(theorem.data_decl) | set(getattr(theorem, "indexed_decl", {}))
        if self.external or self.name in names:
            return
        raise TheoremDefinitionError(
            f"{theorem.id}: assumption {self.describe()}: {self.name!r} is no datum of the theorem"
            f"{did_you_mean(self.name, names)} (declare the datum first, or mark a datum the theorem "
            f"does not take external=True)")

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

    def __init__(self, name: str, side: str = "column", why: str = "", external: bool = False):
        super().__init__(name, why, external)
        self.side = side
        self.label = "{name} of full " + side + " rank"

    def holds(self, value, time):
        value = np.atleast_2d(value)
        rank, need = np.linalg.matrix_rank(value), value.shape[1 if self.side == "column" else 0]
        return None if rank == need else f"its rank is {rank}, not {need}"


def zero(name: str, why: str = "", external: bool = False) -> Zero:
    return Zero(name, why, external)


def stable(name: str, why: str = "", external: bool = False) -> Stable:
    return Stable(name, why, external)


def full_rank(name: str, side: str = "column", why: str = "", external: bool = False) -> FullRank:
    return FullRank(name, side, why, external)


def check_assumptions(theorem, inputs: dict, vertices: list | None = None) -> None:
    """Every assumption of ``theorem`` on ``inputs`` (the data as given, before unused names are
    dropped; ``vertices``: the per-vertex inputs) for every member (:func:`_places`), one line
    for the first that fails."""
    for assumption in getattr(theorem, "assumptions", ()):
        for where, value in _places(theorem, assumption.name, inputs, vertices):
            problem = assumption.holds(_numeric(theorem, assumption, value, where), theorem.time)
            if problem is not None:
                why = f": {assumption.why}" if assumption.why else ""
                raise InputError(f"{theorem.id}: assumption {assumption.describe()} does not hold{where} "
                                 f"({problem}){why}")


def _places(theorem, name: str, inputs: dict, vertices) -> list:
    """(where, value) of every member's ``name``: the datum itself, at each polytope vertex, and
    for a member of an indexed theorem (inputs flattened to ``A_1``, ``A_2``, …:
    :func:`lmidsl.theorem.index_set.flatten_inputs`) at each member, named by its set."""
    found = [("", inputs[name])] if name in inputs else []
    found += [(f" at vertex {k + 1}", v[name]) for k, v in enumerate(vertices or [])
              if isinstance(v, dict) and name in v]
    template = getattr(theorem, "template", None)
    family = getattr(template, "indexed_decl", {}).get(name) if template is not None else None
    if family is not None:
        for numbers in family.member_names(theorem.member_sizes):
            member = name + "".join(f"_{k}" for k in numbers)
            if member in inputs:
                label = ", ".join(f"{s.name} {k}" for s, k in zip(family.sets, numbers))
                found.append((f" for {label} ({member})", inputs[member]))
    return found


def _numeric(theorem, assumption: Assumption, value, where: str) -> np.ndarray:
    """The datum as a finite real array; anything else is an error naming it (an assumption is
    never skipped: an external datum is not bound, so nothing else would say so)."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        array = None
    if array is None or array.dtype.kind not in "iuf" or not np.all(np.isfinite(array)):
        kind = "complex" if array is not None and array.dtype.kind == "c" else "not a finite real matrix"
        raise InputError(f"{theorem.id}: assumption {assumption.describe()} cannot be checked{where}: "
                         f"{assumption.name} is {kind}")
    return array.astype(float)


__all__ = ["Assumption", "Zero", "Stable", "FullRank", "zero", "stable", "full_rank", "check_assumptions"]
