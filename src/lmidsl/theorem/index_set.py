"""Index sets: modes, rules, vertices, subsystems — declared once, instantiated at bind time.

A theorem declares an index set (``M = thm.index_set("modes", key="modes")``), its indices
(``i, j = M.indices("i j")``), data and variables indexed by it (``A = thm.data("A", n, n,
over=M)`` gives ``A[i]``), coefficient matrices (``Pi = thm.coefficients("Pi", M,
structure="generator")`` gives the scalar ``Pi[i, j]``) and LMIs with free indices, quantified
"for all i" or "for all i < j" (``thm.lmi(label, rows, forall=(i, j), where=i < j)``); sums,
stacks and block diagonals over an index are :func:`~lmidsl.symbolic.indexed.sum_over`,
:func:`~lmidsl.symbolic.indexed.stack_over`, :func:`~lmidsl.symbolic.indexed.diag_over`.

The statement is checked once, symbolically (shapes with the symbolic size N, affinity).  When
the data fix N (the length of the list under the set's ``key``, e.g. ``"modes": [{"A": …,
"B": …}, …]``), :func:`build_member` instantiates it: data ``A_1 … A_N``, variables ``P_1 …
P_N``, one LMI ``(label, i=k)`` per index value in range, one recovery ``K_k`` per member.  The
member is an ordinary :class:`~lmidsl.theorem.theorem.Theorem` (built once per N and cached),
so binding, compiling, certificates, proofs and recovery are those of every theorem; the
template keeps the quantified statement for printing.  Instantiating is one rebuild of each
block per instance (linear in the number of instances); no check is run again.

Coefficient matrices may declare a structure checked when they are bound: ``"generator"`` (a
transition-rate matrix: off-diagonal entries ≥ 0, rows summing to 0), ``"stochastic"`` (entries
≥ 0, rows summing to 1), ``"nonnegative"``; ``diagonal="complete"`` (or the data's
``{"matrix": …, "diagonal": "complete"}``) lets the diagonal complete each row
(:mod:`lmidsl.theorem.structure`).
"""
from __future__ import annotations

import copy
import itertools
import re

import numpy as np
import sympy as sp

from ..errors import InputError, TheoremDefinitionError
from ..symbolic.blocks import BlockMatrixSpec
from ..symbolic.indexed import (Coefficient, Index, IndexedData, IndexedDiagonalVariable,
                                IndexedRecovered, IndexedSymmetricData, IndexedSymmetricVariable,
                                IndexedVariable, _IndexOp, free_indices, holds, instantiate)
from ..symbolic.numbers import finite_matrix
from ..symbolic.symbols import Dim
from .structure import check_declaration, check_structure, split_value
from . import budget
from .members import MemberRule
from .values import LMI



class IndexSet:
    """An index set {1, …, N} of a theorem; N is read off the data (the list under ``key``)."""

    def __init__(self, theorem, name: str, key: str, size: str, latex: str | None, description: str):
        self.theorem = theorem
        self.name = name
        self.key = key
        self.size = Dim(size)
        self.latex = latex or r"\mathcal{I}"
        self.description = description

    def indices(self, names: str):
        """``i, j = M.indices("i j")``: index symbols ranging over this set."""
        made = [Index(n, self.name, self.theorem.id, self.size) for n in names.split()]
        self._first = getattr(self, "_first", None) or made[0]
        return made[0] if len(made) == 1 else tuple(made)

    @property
    def generic_index(self) -> Index:
        """The index a generic member is printed with (the first declared, else i)."""
        return getattr(self, "_first", None) or Index("i", self.name, self.theorem.id, self.size)

    def __repr__(self):
        return f"<IndexSet {self.name} = {{1..{self.size}}} (data key {self.key!r})>"


_CLASSES = {("data", False): IndexedData, ("data", True): IndexedSymmetricData,
            ("full", False): IndexedVariable, ("symmetric", False): IndexedSymmetricVariable,
            ("diagonal", False): IndexedDiagonalVariable, ("recovered", False): IndexedRecovered}


class IndexedFamily:
    """A matrix indexed by one or more index sets: ``A[i]``, ``Q[i, j]``; member (3,) is named
    ``A_3`` (``Q_1_2`` for a pair)."""

    def __init__(self, theorem, name: str, kind: str, rows, cols, sets: tuple, latex: str | None,
                 description: str, symmetric: bool = False):
        self.theorem, self.name, self.kind = theorem, name, kind
        self.rows, self.cols = sp.sympify(rows), sp.sympify(cols)
        self.sets = tuple(sets)
        self.latex = latex or name
        self.description = description
        self.symmetric = symmetric
        self.cls = _CLASSES[(kind, symmetric and kind == "data")]

    def __getitem__(self, idx):
        idx = idx if isinstance(idx, tuple) else (idx,)
        if len(idx) != len(self.sets):
            raise TheoremDefinitionError(f"{self.theorem.id}: {self.name} takes {len(self.sets)} "
                                         f"index(es), got {len(idx)}")
        for k, s in zip(idx, self.sets):
            if isinstance(k, Index) and k.set_name != s.name:
                raise TheoremDefinitionError(f"{self.theorem.id}: {self.name} is indexed by {s.name}, "
                                             f"but {k} ranges over {k.set_name}")
        symbol = self.cls(self.name, self.rows, self.cols, self.theorem.id, idx)
        symbol.latex_name = self.latex
        symbol.description = self.description
        return symbol

    def member_names(self, sizes: dict) -> list[tuple]:
        return list(itertools.product(*[range(1, sizes[s.name] + 1) for s in self.sets]))

    def __repr__(self):
        return f"<{self.kind} {self.name}[{', '.join(s.name for s in self.sets)}]>"


class CoefficientFamily:
    """A matrix of scalar coefficients over an index set, ``Pi[i, j]``, bound as one N×N datum."""

    def __init__(self, theorem, name: str, index_set: IndexSet, structure: str | None,
                 latex: str | None, description: str, diagonal: str = "given"):
        check_declaration(f"{theorem.id}: coefficients {name}", structure, diagonal)
        self.theorem, self.name, self.set = theorem, name, index_set
        self.structure, self.diagonal = structure, diagonal
        self.latex = latex or name
        self.description = description
        entry = Coefficient(name, theorem.id, 1, 1)       # the entries' LaTeX name (π_ij)
        entry.latex_name, entry.description = self.latex, description

    def __getitem__(self, idx):
        if not (isinstance(idx, tuple) and len(idx) == 2):
            raise TheoremDefinitionError(f"{self.theorem.id}: {self.name}[i, j] takes two indices")
        return Coefficient(self.name, self.theorem.id, *idx)

    def check(self, value, n: int) -> np.ndarray:
        """The bound matrix, with its shape and declared structure checked (one-line errors); the
        diagonal completed when the theorem or the data declare it (:mod:`lmidsl.theorem.structure`)."""
        where = f"{self.theorem.id}: {self.name}"
        value, option = split_value(value, where)
        M = finite_matrix(value, where)
        if M.shape != (n, n):
            raise InputError(f"{where} is {M.shape[0]}×{M.shape[1]} but there are {n} {self.set.name}")
        diagonal = option or self.diagonal
        if option == "complete" and self.structure not in ("generator", "stochastic"):
            raise InputError(f"{where}: diagonal 'complete' needs a generator or stochastic structure")
        return check_structure(M, self.structure, diagonal, where)


class Quantifier:
    """∀ (indices) with a condition: the instances of a quantified LMI, recovery or positivity."""

    def __init__(self, indices: tuple, where=None):
        self.indices = tuple(indices)
        self.where = where

    def environments(self, sizes: dict) -> list[dict]:
        ranges = [range(1, sizes[k.set_name] + 1) for k in self.indices]
        out = []
        for values in itertools.product(*ranges):
            env = dict(zip(self.indices, values))
            if holds(self.where, env):
                out.append(env)
        return out

    def label(self, label: str, env: dict) -> str:
        """``(9)`` at i=2 → ``(9, i=2)``; any other label gets `` (i=2)``."""
        tag = ", ".join(f"{k}={v}" for k, v in env.items())
        s = label.strip()
        if s.startswith("(") and s.endswith(")"):
            return f"{s[:-1]}, {tag})"
        return f"{label} ({tag})" if tag else label


def quantifier_for(theorem_id: str, where_text: str, exprs, forall, where) -> Quantifier | None:
    """The quantifier of a statement: ``forall`` (an index or a tuple of them), else every free
    index of ``exprs``; every free index must be quantified."""
    free = set()
    for e in exprs:
        free |= free_indices(e)
    if where is not None:
        free |= free_indices(where)
    if forall is None:
        if not free:
            return None
        forall = tuple(sorted(free, key=lambda s: s.name))
    forall = forall if isinstance(forall, (tuple, list)) else (forall,)
    for k in forall:
        if not isinstance(k, Index):
            raise TheoremDefinitionError(f"{theorem_id}: {where_text}: forall={k} is not an index")
    unbound = free - set(forall)
    if unbound:
        raise TheoremDefinitionError(f"{theorem_id}: {where_text}: the index {', '.join(sorted(map(str, unbound)))} "
                                     f"is free but not quantified (forall=...) nor summed over")
    return Quantifier(tuple(forall), where)


# -- members ------------------------------------------------------------------------------
def count_members(inputs, key: str, where: str = "") -> int:
    """The N for which ``key_1 .. key_N`` are all present among ``inputs`` (names)."""
    pattern = re.compile(rf"^{re.escape(key)}_(\d+)$")
    found = sorted(int(m.group(1)) for name in inputs for m in [pattern.match(str(name))] if m)
    if not found:
        return 0
    if found != list(range(1, len(found) + 1)):
        raise InputError(f"{where + ': ' if where else ''}the subsystems given as {key}_<i> are {found}; "
                         f"expected {key}_1 .. {key}_{len(found)}")
    return len(found)

def sizes_from_inputs(template, inputs: dict) -> dict:
    """N of each index set: the length of the list under its key, else the number of
    ``<name>_1 … <name>_N`` of its first indexed datum, else the rows of its coefficient matrix."""
    sizes = {}
    for M in template.index_sets.values():
        if M.key in inputs:
            items = inputs[M.key]
            if not isinstance(items, list) or not items or not all(isinstance(v, dict) for v in items):
                raise InputError(f"{template.id}: '{M.key}' must be a non-empty list of objects")
            sizes[M.name] = len(items)
            continue
        found = 0
        for fam in template.indexed_decl.values():
            if fam.kind == "data" and fam.sets == (M,):
                found = count_members(inputs, fam.name, where=template.id)
                if found:
                    break
        if not found:
            for coef in template.coefficient_decl.values():
                if coef.set is M and coef.name in inputs:
                    found = len(split_value(inputs[coef.name], f"{template.id}: {coef.name}")[0])
                    break
        if not found and M.size.name in inputs:
            found = int(inputs[M.size.name])
        if not found:
            raise InputError(f"{template.id}: the {M.name} are not given: give '{M.key}' as a list of "
                             f"objects (one per member)")
        sizes[M.name] = found
    return sizes


class IndexSetRule(MemberRule):
    """Index sets (:mod:`lmidsl.theorem.members`): the key is the sizes of the index sets; a
    member whose LMIs exceed the current limits is refused before it is built
    (:mod:`lmidsl.theorem.budget`: the estimate from the statement and the data shapes)."""

    def key(self, theorem, inputs: dict) -> tuple:
        sizes = sizes_from_inputs(theorem, inputs)
        budget.check(theorem.id, budget.index_set_estimate(theorem, sizes, inputs))
        return tuple(sorted(sizes.items()))

    def build(self, theorem, key: tuple):
        return build_member(theorem, dict(key))


def member_name(base: str, numbers: tuple) -> str:
    return base + "".join(f"_{k}" for k in numbers)


def member_latex(latex: str, numbers: tuple) -> str:
    sub = ",".join(map(str, numbers))
    if "{i}" in latex or "{j}" in latex:
        out = latex.replace("{i}", str(numbers[0]))
        return out.replace("{j}", str(numbers[1])) if len(numbers) > 1 else out
    if latex.endswith("}") and "_{" in latex:
        return latex[:-1] + "," + sub + "}"
    return f"{latex}_{{{sub}}}"


def build_member(template, sizes: dict):
    """The ordinary theorem the template states for the index-set sizes ``sizes``."""
    m = copy.copy(template)
    m.index_sets = {}
    m.template = template
    m.member_sizes = dict(sizes)
    m._members = {}
    for attr in ("dims", "data_decl", "var_decl", "recovered_decl", "recovery", "reported", "notation",
                 "intermediate_decl"):
        setattr(m, attr, {k: v for k, v in getattr(template, attr).items()
                          if k not in template.indexed_decl and k not in template.coefficient_decl})
    m.indexed_decl, m.coefficient_decl, m.indexed_statements = {}, {}, []
    m.recovery_steps = list(template.recovery_steps)
    m.checks = list(template.checks)
    size_env = {template.index_sets[name].size: n for name, n in sizes.items()}
    members: dict = {}
    for fam in template.indexed_decl.values():
        for numbers in fam.member_names(sizes):
            name = member_name(fam.name, numbers)
            rows, cols = fam.rows.xreplace(size_env), fam.cols.xreplace(size_env)
            latex = member_latex(fam.latex, numbers)
            if fam.kind == "data":
                symbol = m.data(name, rows, cols, latex=latex, description=fam.description,
                                symmetric=fam.symmetric)
            elif fam.kind == "recovered":
                continue     # made by the recovery below
            else:
                symbol = m.var(name, rows, cols, kind=fam.kind, latex=latex, description=fam.description)
            members[(fam.name, numbers)] = symbol
    coefficients = {}
    for coef in template.coefficient_decl.values():
        n = sizes[coef.set.name]
        coefficients[coef.name] = m.data(coef.name, n, n, latex=coef.latex, description=coef.description)

    def resolve(symbol, numbers):
        try:
            return members[(symbol.name, numbers)]
        except KeyError:
            raise TheoremDefinitionError(f"{template.id}: {symbol.name}{list(numbers)} is not a member "
                                         f"of {symbol.name}") from None

    def coefficient(entry, numbers):
        return coefficients[entry.name][numbers[0] - 1, numbers[1] - 1]

    def inst(expr, env=None):
        return instantiate(expr, {**size_env, **(env or {})}, resolve, coefficient)

    lmis = []
    for lmi in template.lmis:
        q = getattr(lmi, "quantifier", None)
        if q is None:
            lmis.append(_instantiate_lmi(lmi, lmi.label, {}, inst) if _has_indexed(lmi) else lmi)
            continue
        for env in q.environments(sizes):
            lmis.append(_instantiate_lmi(lmi, q.label(lmi.label, env), env, inst))
    m.lmis = lmis
    if template.objective is not None:
        m.objective = inst(template.objective)
    if template.performance is not None:
        m.performance = (template.performance[0], inst(template.performance[1]))
    m.reported = {k: inst(v) for k, v in template.reported.items()}
    steps = []
    for step in template.recovery_steps:
        indexed = step[1] in template.indexed_recovery if isinstance(step, tuple) else False
        if not indexed:
            if isinstance(step, tuple):
                m.recovery[step[1]] = inst(template.recovery[step[1]])
            steps.append(step)
            continue
        formula, fam, q = template.indexed_recovery[step[1]]
        for env in q.environments(sizes):
            numbers = tuple(env[k] for k in q.indices)
            name = member_name(fam.name, numbers)
            symbol = m.recover(**{name: inst(formula, env)})
            symbol.latex_name = member_latex(fam.latex, numbers)
            members[(fam.name, numbers)] = symbol
        steps.extend(("formula", member_name(fam.name, tuple(env[k] for k in q.indices)))
                     for env in q.environments(sizes))
    m.recovery_steps = steps
    m.conditioned = [inst(e, env) for e in template.conditioned
                     for env in (quantifier_for(template.id, "well_conditioned", [e], None, None)
                                 or Quantifier(())).environments(sizes)]
    if template.analysis is not None:
        link = copy.copy(template.analysis)
        link.design = tuple(n for d in link.design for n in _expand_name(template, d, sizes))
        m.analysis = link
    return m


def _expand_name(template, name: str, sizes: dict) -> list[str]:
    fam = template.indexed_decl.get(name)
    if fam is None:
        return [name]
    return [member_name(name, numbers) for numbers in fam.member_names(sizes)]


def _has_indexed(lmi) -> bool:
    return any(b.has(Coefficient, _IndexOp) or free_indices(b) for row in lmi.spec.lower for b in row)


def _instantiate_lmi(lmi, label: str, env: dict, inst) -> LMI:
    """One instance of a quantified LMI: blocks instantiated, block rows of size 0 (an empty
    range: j ≠ i with one member) dropped."""
    spec = lmi.spec
    sizes = [sp.expand(inst(s, env)) for s in spec.sizes]
    keep = [k for k, s in enumerate(sizes) if s != 0]
    lower = [[inst(spec.lower[i][j], env) for j in keep if j <= i] for i in keep]
    out = LMI(label, BlockMatrixSpec(lower, [sizes[k] for k in keep], spec.given_as), lmi.sense,
              lmi.strict, lmi.description)
    out.template = lmi
    return out


def flatten_inputs(template, inputs: dict, sizes: dict) -> dict:
    """The inputs of a member: ``"modes": [{"A": …}, …]`` → ``A_1, …``; an indexed datum given
    once (outside the list) is common to every member; coefficient matrices checked."""
    inputs = dict(inputs)
    for M in template.index_sets.values():
        if M.key not in inputs:
            continue
        items = inputs.pop(M.key)
        for k, item in enumerate(items, 1):
            for name, value in item.items():
                fam = template.indexed_decl.get(name)
                if fam is None or fam.kind != "data" or fam.sets != (M,):
                    raise InputError(f"{template.id}: {M.key}[{k}]: {name!r} is not data indexed by "
                                     f"the {M.name}")
                inputs[member_name(name, (k,))] = value
    for fam in template.indexed_decl.values():
        if fam.kind == "data" and fam.name in inputs:
            value = inputs.pop(fam.name)
            for numbers in fam.member_names(sizes):
                key = member_name(fam.name, numbers)
                if key in inputs:
                    raise InputError(f"{template.id}: {fam.name} is given both for every member and "
                                     f"for member {numbers}")
                inputs[key] = value
    for coef in template.coefficient_decl.values():
        if coef.name in inputs:
            inputs[coef.name] = coef.check(inputs[coef.name], sizes[coef.set.name]).tolist()
    return inputs


__all__ = ["IndexSet", "IndexedFamily", "CoefficientFamily", "Quantifier", "build_member",
           "flatten_inputs", "sizes_from_inputs", "quantifier_for", "IndexSetRule"]
