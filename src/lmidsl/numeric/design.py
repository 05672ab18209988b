"""The design a synthesis theorem produces: its matrices, what they are, and how they were got.

A synthesis LMI is solved in transformed variables (Â_f = V₂ A_f, W = K Y, ...); the theorem's
change of variables (:mod:`lmidsl.numeric.recovery`) maps the solved point back to the matrices
of a filter, controller or observer.  A :class:`Design` holds those matrices in the original
coordinates of the data (any signal scaling undone), with

* ``kind``: ``"filter"``, ``"controller"``, ``"observer"`` or ``"gain"`` — what the theorem says it
  designs (``Theorem(..., designs=...)``), ``"unspecified"`` when it does not say;
* ``time`` and ``sample_time``: ``"discrete"`` or ``"continuous"``; the sampling period of a
  discrete design (``None``: unspecified, python-control's ``dt=True``);
* ``inverted``: the 2-norm condition number of every matrix the recovery inverted or factored —
  an ill-conditioned inverse makes a design untrustworthy even when the LMIs hold comfortably;
* ``obtained``: how it was obtained (theorem, example, solver, scaling, back-off).

A Design is a read-only mapping name → matrix, so ``design["Af"]`` works as on a dict.
Certification, LaTeX, JSON and the reports consume it; :meth:`Design.as_statespace` gives it
as a python-control system (and :mod:`lmidsl.numeric.interconnection` closes the loop).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..theorem.values import DESIGN_KINDS
from .interconnection import design_statespace


@dataclass(frozen=True)
class Design(Mapping):
    """Recovered matrices by name, with their kind, time domain and conditioning."""

    kind: str
    matrices: dict
    time: str = "discrete"
    sample_time: float | None = None
    inverted: tuple = ()
    obtained: dict = field(default_factory=dict)

    def __getitem__(self, name):
        return self.matrices[name]

    def __iter__(self):
        return iter(self.matrices)

    def __len__(self):
        return len(self.matrices)

    @property
    def worst_condition(self) -> float | None:
        """The largest condition number among the inverted matrices (None if none inverted)."""
        return max((float(r["cond"]) for r in self.inverted), default=None)

    def with_matrices(self, matrices: dict, **obtained) -> "Design":
        """The same design with other matrices (e.g. mapped back through a scaling)."""
        return Design(self.kind, dict(matrices), self.time, self.sample_time, self.inverted,
                      {**self.obtained, **obtained})

    def as_statespace(self):
        """The design as a python-control ``StateSpace``: a controller (AK, BK, CK, DK) from y to
        u, a filter (Af, Bf, Cf, Df) from y to ẑ, a static gain K as a D-only system; ``dt`` is
        ``sample_time or True`` in discrete time, 0 in continuous time
        (:func:`lmidsl.numeric.interconnection.design_statespace`)."""
        return design_statespace(self)

    def as_dict(self) -> dict:
        return {"kind": self.kind, "time": self.time, "sample_time": self.sample_time,
                "matrices": {k: np.asarray(v, dtype=float).tolist() for k, v in self.matrices.items()},
                "inverted": list(self.inverted), "obtained": self.obtained}

    def __repr__(self):
        shapes = ", ".join(f"{k} {np.shape(v)[0]}x{np.shape(v)[1]}" for k, v in self.matrices.items())
        cond = self.worst_condition
        extra = f", worst cond {cond:.3g}" if cond is not None else ""
        return f"Design({self.kind}, {self.time} time: {shapes}{extra})"


__all__ = ["Design", "DESIGN_KINDS"]
