"""Theorems whose block structure depends on an integer (e.g. the maximum number of losses N,
the number of subsystems), and objects indexed by subsystem.

A paper often states one LMI for every N, with N delay blocks.  The theorem file writes a
function ``build(thm, N)`` that declares everything for one N (building the N blocks in a
Python loop) and declares N itself as a parameter with ``thm.param("N", domain=(N, N))`` so
that it can appear in formulas (``l = sqrt(N)``).  :class:`TheoremFamily` is a
:class:`~lmidsl.theorem.theorem.Theorem` (the member for the default N) that binds any other N by
building that member on demand::

    thm1 = TheoremFamily("paper.thm1", "...", Source(...), build, index="N", default=2)
    make_instance(thm1, example="paper-N3")      # the example's N = 3 selects the member

All members share the family's id and examples; the analysis link passes N along with the
other parameters, so a synthesis for N = 3 is certified by the analysis member for N = 3.
:class:`SubsystemFamily` also reads N off the data (the number of ``A_1, A_2, ...`` given).

Objects indexed by subsystem: an interconnected system with N subsystems has data A_i, B_i, ...
for every i, coupling data A_ij for every pair, and one LMI per subsystem sharing variables
(Q_ij) across the family.  :class:`Family` declares them on a theorem in one call each; they
come back as dictionaries keyed by ``i`` (1-based) or ``(i, j)``, so a build function writes
``A[i]``, ``Q[j, i]`` and ``sum(Q[j, i] for j in fam)`` as the paper does.  Names: member i of
``A`` is ``A_i``, pair (i, j) is ``A_i_j``; LaTeX templates may contain ``{i}`` and ``{j}``
(replaced literally, e.g. ``\\hat{A}_{f{i}}``), otherwise the index is appended as a subscript.
"""
from __future__ import annotations

import re
from typing import Callable

from ..errors import InputError
from . import budget
from .index_set import count_members
from .members import MemberRule, built_member
from .theorem import Source, Theorem


class TheoremFamily(Theorem):
    """The member for ``default`` of a family ``build(thm, value)``; other members on demand."""

    def __init__(self, id: str, title: str, source: Source, build: Callable[[Theorem, int], None], *,
                 index: str = "N", default: int = 1, domain: tuple[int, int] = (1, 64),
                 **options):
        """``options``: the keyword arguments of :class:`Theorem` (description, time, designs,
        provenance, ...), shared by every member."""
        super().__init__(id, title, source, **options)
        self.options = options
        self.build = build
        self.index = index
        self.domain = domain
        self.default = default
        build(self, default)
        if index not in self.param_decl:
            raise InputError(f"{id}: the family index {index} must be declared as a parameter by build()")

    def member_rule(self):
        return IntegerRule()

    def member(self, value) -> Theorem:
        """The theorem for ``index = value`` (built once per declaration,
        :func:`lmidsl.theorem.members.built_member`; the limits are checked by ``specialise``)."""
        rule = IntegerRule()
        return built_member(self, rule, rule.key(self, {self.index: value}))

    def index_value(self, inputs: dict):
        """The family index the inputs give (the default when absent)."""
        return inputs.get(self.index, self.default)

    def summary(self) -> dict:
        out = super().summary()
        out["family_index"] = {"name": self.index, "default": self.default, "domain": list(self.domain)}
        return out


# -- objects indexed by subsystem -------------------------------------------------------

def _latex(template: str | None, base: str, idx: tuple) -> str:
    template = template or base
    if "{i}" in template or "{j}" in template:
        out = template.replace("{i}", str(idx[0]))
        if len(idx) > 1:
            out = out.replace("{j}", str(idx[1]))
        return out
    return f"{template}_{{{''.join(map(str, idx))}}}"


def member_name(base: str, *idx) -> str:
    """``A`` with index (1,) → ``A_1``; ``Ad`` with (1, 2) → ``Ad_1_2``."""
    return base + "".join(f"_{k}" for k in idx)


class Family:
    """Members 1..N of a theorem (subsystems), with indexed declarations."""

    def __init__(self, theorem, size: int, index: str = "i"):
        if size < 1:
            raise InputError(f"{theorem.id}: a family needs at least one member, got {size}")
        self.theorem = theorem
        self.size = int(size)
        self.index = index

    def __iter__(self):
        return iter(range(1, self.size + 1))

    def __len__(self):
        return self.size

    @property
    def pairs(self) -> list[tuple[int, int]]:
        return [(i, j) for i in self for j in self]

    def _keys(self, pairs: bool):
        return self.pairs if pairs else [(i,) for i in self]

    @staticmethod
    def _shape(value, idx):
        if callable(value):
            return value(*idx)
        return value

    # -- declarations -------------------------------------------------------------------
    def dims(self, names: str) -> tuple[dict, ...] | dict:
        """Per-member dimensions: ``n, m = fam.dims("n m")`` gives ``n[i]`` = Dim ``n_i``."""
        made = []
        for base in names.split():
            made.append({i: self.theorem.dim(member_name(base, i)) for i in self})
        return made[0] if len(made) == 1 else tuple(made)

    def data(self, base: str, rows, cols, *, pairs: bool = False, latex: str | None = None,
             description: str = "", **kwargs) -> dict:
        """Indexed data; ``rows``/``cols`` are dimensions or functions of the index."""
        out = {}
        for idx in self._keys(pairs):
            symbol = self.theorem.data(member_name(base, *idx), self._shape(rows, idx),
                                       self._shape(cols, idx), latex=_latex(latex, base, idx),
                                       description=description, **kwargs)
            out[idx if pairs else idx[0]] = symbol
        return out

    def var(self, base: str, rows, cols=None, *, pairs: bool = False, latex: str | None = None,
            description: str = "", **kwargs) -> dict:
        """Indexed decision matrices (``kind`` as in ``Theorem.var``)."""
        out = {}
        for idx in self._keys(pairs):
            c = None if cols is None else self._shape(cols, idx)
            symbol = self.theorem.var(member_name(base, *idx), self._shape(rows, idx), c,
                                      latex=_latex(latex, base, idx), description=description,
                                      **kwargs)
            out[idx if pairs else idx[0]] = symbol
        return out

    def scalar(self, base: str, *, pairs: bool = False, latex: str | None = None,
               description: str = "", **kwargs) -> dict:
        """Indexed scalar decision variables (multipliers ε_i, levels ρ_i = γ_i²)."""
        out = {}
        for idx in self._keys(pairs):
            out[idx if pairs else idx[0]] = self.theorem.scalar(
                member_name(base, *idx), latex=_latex(latex, base, idx), description=description,
                **kwargs)
        return out

    def param(self, base: str, *, pairs: bool = False, latex: str | None = None,
              description: str = "", **kwargs) -> dict:
        """Indexed scalar parameters (e.g. delays τ_ij)."""
        out = {}
        for idx in self._keys(pairs):
            out[idx if pairs else idx[0]] = self.theorem.param(
                member_name(base, *idx), latex=_latex(latex, base, idx), description=description,
                **kwargs)
        return out

    def lmis(self, label: str, build, **kwargs) -> list:
        """One LMI per member: ``build(i)`` returns its rows (or a BlockMatrixSpec).

        ``label`` may contain ``{i}``; a paper label ``"(18)"`` becomes ``"(18, i=1)"``
        (still an equation tag); any other label gets ``" (i=1)"`` appended.
        """
        made = []
        for i in self:
            made.append(self.theorem.lmi(member_label(label, i), build(i), **kwargs))
        return made


def member_label(label: str, i: int) -> str:
    """The label of member i's LMI: ``"(18)"`` → ``"(18, i=1)"``, ``"{i}"`` replaced."""
    if "{i}" in label:
        return label.replace("{i}", str(i))
    m = re.fullmatch(r"\((.+)\)", label.strip())
    return f"({m.group(1)}, i={i})" if m else f"{label} (i={i})"




class SubsystemFamily(TheoremFamily):
    """A :class:`TheoremFamily` indexed by the number of subsystems N, which the data also tell:
    when ``N`` is not given, it is the number of ``<key>_1, <key>_2, ...`` among the inputs."""

    def __init__(self, id: str, title: str, source: Source, build, *, key: str, index: str = "N",
                 default: int = 2, **kwargs):
        self.key = key
        super().__init__(id, title, source, build, index=index, default=default, **kwargs)

    def index_value(self, inputs: dict):
        """N as given, else the number of ``<key>_1, <key>_2, ...`` among the inputs."""
        return inputs[self.index] if self.index in inputs else \
            count_members(inputs, self.key, where=self.id) or self.default


class IntegerRule(MemberRule):
    """A :class:`TheoremFamily` (:mod:`lmidsl.theorem.members`): the key is the integer its
    ``build`` loop takes, within the family's domain; the member is built by the theorem file's
    own loop, so its LMIs (sizes from the data shapes) are checked against the current limits
    once built, before the compile."""

    def key(self, family, inputs: dict) -> tuple:
        value = family.index_value(inputs)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
            raise InputError(f"{family.id}: {family.index} must be an integer, got {value!r}")
        lo, hi = family.domain
        if not lo <= int(value) <= hi:
            raise InputError(f"{family.id}: {family.index} = {int(value)} is outside [{lo}, {hi}]")
        return (int(value),)

    def build(self, family, key: tuple) -> Theorem:
        (value,) = key
        if value == family.default:
            return family
        member = Theorem(family.id, family.title, family.source, **family.options)
        family.build(member, value)
        member.examples = family.examples
        member.family = family
        return member

    def admit(self, family, member, inputs: dict) -> Theorem:
        value = member.param_decl[family.index].extra.get("default") if family.index in member.param_decl else "?"
        estimate = budget.Estimate(f"the member for {family.index} = {value}")
        dims = budget.dims_from_inputs(member, inputs)
        for lmi in member.lmis:
            estimate.add_lmis(1, sum(budget.integer(s, dims) for s in lmi.spec.sizes))
        budget.check(family.id, estimate)
        return member


__all__ = ["TheoremFamily", "SubsystemFamily", "Family", "member_name", "member_label", "count_members",
           "IntegerRule"]
