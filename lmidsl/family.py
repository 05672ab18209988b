"""Theorems whose block structure depends on an integer (e.g. the maximum number of losses N).

A paper often states one LMI for every N, with N delay blocks.  The theorem file writes a
function ``build(thm, N)`` that declares everything for one N (building the N blocks in a
Python loop) and declares N itself as a parameter with ``thm.param("N", domain=(N, N))`` so
that it can appear in formulas (``l = sqrt(N)``).  :class:`TheoremFamily` is a
:class:`~lmidsl.theorem.Theorem` (the member for the default N) that binds any other N by
building that member on demand::

    thm1 = TheoremFamily("paper.thm1", "...", Source(...), build, index="N", default=2)
    make_instance(thm1, example="paper-N3")      # the example's N = 3 selects the member

All members share the family's id and examples; the analysis link passes N along with the
other parameters, so a synthesis for N = 3 is certified by the analysis member for N = 3.
"""
from __future__ import annotations

from typing import Callable

from .errors import InputError
from .theorem import Source, Theorem


class TheoremFamily(Theorem):
    """The member for ``default`` of a family ``build(thm, value)``; other members on demand."""

    def __init__(self, id: str, title: str, source: Source, build: Callable[[Theorem, int], None], *,
                 index: str = "N", default: int = 1, domain: tuple[int, int] = (1, 64),
                 description: str = "", time: str = "discrete"):
        super().__init__(id, title, source, description=description, time=time)
        self.build = build
        self.index = index
        self.domain = domain
        self.default = default
        build(self, default)
        if index not in self.param_decl:
            raise InputError(f"{id}: the family index {index} must be declared as a parameter by build()")
        self._members: dict[int, Theorem] = {default: self}

    def member(self, value) -> Theorem:
        """The theorem for ``index = value`` (built once, cached)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
            raise InputError(f"{self.id}: {self.index} must be an integer, got {value!r}")
        value = int(value)
        lo, hi = self.domain
        if not lo <= value <= hi:
            raise InputError(f"{self.id}: {self.index} = {value} is outside [{lo}, {hi}]")
        if value not in self._members:
            thm = Theorem(self.id, self.title, self.source, description=self.description, time=self.time)
            self.build(thm, value)
            thm.examples = self.examples
            thm.family = self
            self._members[value] = thm
        return self._members[value]

    def specialise(self, inputs: dict) -> Theorem:
        """The member selected by ``inputs[index]`` (the default member when absent)."""
        return self.member(inputs.get(self.index, self.default))

    def summary(self) -> dict:
        out = super().summary()
        out["family_index"] = {"name": self.index, "default": self.default, "domain": list(self.domain)}
        return out
