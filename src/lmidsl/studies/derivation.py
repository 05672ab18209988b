"""Derivation checks: is a theorem's LMI exactly the congruence (and Schur complement, and
change of variables) of another theorem's LMI, as its paper says?  (``lmidsl derive-check``)

A theorem states the step with :meth:`~lmidsl.theorem.theorem.Theorem.derived_from`
(:class:`~lmidsl.theorem.values.Derivation`).  The claim is a polynomial (rational) identity
in the symbols, so it is checked by Schwartz–Zippel: every symbol that ``substitute`` does not
define (data, parameters, the variables left free, the auxiliary matrices) is drawn as a random
rational matrix of its kind (symmetric, diagonal, full) at the dimensions of the theorem's
examples, both sides are evaluated in exact rational arithmetic (:mod:`lmidsl.numeric.exact`)
and compared block by block.  A false identity survives a random point with probability at
most degree / 61² per entry; several points and every example's dimensions are tried.  The
first block (i, j) that differs is reported with both expressions and one differing entry.

The recovery is checked the same way: each recovery formula of the theorem, evaluated at the
substituted point, must give the declared ``recovers`` expression (default: the source symbol
of the same name), i.e. recover ∘ substitute = identity (or the similarity stated).
"""
from __future__ import annotations

import random
from dataclasses import asdict, dataclass, field

import sympy as sp
from flint import fmpq_mat

from ..errors import InputError, TheoremDefinitionError
from ..numeric.exact import ExactEvaluator, NotRational, random_matrix, random_rational, to_matrix
from ..pipeline import as_theorem, make_instance
from ..symbolic.blocks import SizedIdentity, congruence, schur
from ..symbolic.symbols import Dim
from ..theorem.values import Derivation, FactorStep

EXACT = "exact"
DIFFERS = "differs"
UNDECIDED = "undecided"


@dataclass
class DerivationResult:
    theorem: str
    label: str
    source: str
    source_label: str
    verdict: str                       # exact / differs / undecided
    points: int = 0                    # random rational points where both sides were compared
    dims: list = field(default_factory=list)
    block: tuple | None = None         # first differing block (i, j), 1-based
    target_expr: str = ""
    derived_expr: str = ""
    entry: dict | None = None          # one differing entry: row, col, target, derived
    recovery: list = field(default_factory=list)   # [{name, verdict, expected}]
    message: str = ""
    note: str = ""
    free: list = field(default_factory=list)       # derived scalars with irrational definitions, drawn freely

    @property
    def holds(self) -> bool:
        return self.verdict == EXACT and all(r["verdict"] in (EXACT, "not checked") for r in self.recovery)

    def as_dict(self) -> dict:
        out = asdict(self)
        out["holds"] = self.holds
        return out


def _key(symbol):
    tag = getattr(symbol, "tag", "")
    return ("aux", symbol.name) if tag.endswith("#derivation") else symbol.name


def _kind(symbol) -> str:
    kind = getattr(symbol, "kind", "")
    if kind == "diagonal":
        return "diagonal"
    if kind == "symmetric" or getattr(symbol, "is_symmetric", False) is True:
        return "symmetric"
    return "full"


class _Point:
    """One random rational point: values drawn or defined by the substitution, by key."""

    def __init__(self, dims: dict, definitions: dict, rng: random.Random):
        self.definitions = definitions
        self.rng = rng
        self.values: dict = {}
        self.resolving: set = set()
        self.evaluator = ExactEvaluator(dims, self.lookup, free_irrational=True)

    def lookup(self, symbol):
        key = _key(symbol)
        if key in self.values:
            return self.values[key]
        if key in self.definitions:
            if key in self.resolving:
                raise TheoremDefinitionError(f"derivation: the substitution of {symbol.name} is circular")
            self.resolving.add(key)
            value = self.evaluator.visit(self.definitions[key])
            self.resolving.discard(key)
        elif isinstance(symbol, sp.MatrixSymbol):
            rows, cols = (self.evaluator.size(d) for d in symbol.shape)
            value = random_matrix(self.rng, rows, cols, _kind(symbol))
        else:
            value = random_rational(self.rng)
        self.values[key] = value
        return value


def _dimension_sets(theorem, source, given: dict | None) -> list[dict]:
    """The dimensions to check at: ``given``; else every example's; else (no example) two
    generic sets, every dimension 2, and 3, 1, 3, ... in declaration order."""
    if given:
        return [{Dim(n): int(v) for n, v in given.items()}]
    sets = []
    for name in theorem.examples:
        dims = make_instance(theorem, example=name).dims
        if dims not in sets:
            sets.append(dims)
    if not sets:
        names = list(dict.fromkeys([*theorem.dims, *source.dims]))
        sets = [{Dim(n): 2 for n in names}, {Dim(n): (3 if i % 2 == 0 else 1) for i, n in enumerate(names)}]
    return sets


def _derived_spec(d: Derivation):
    source_lmi = next(l for l in d.source.lmis if l.label == d.source_label)
    spec = source_lmi.negative_form()
    for k in sorted(d.schur, reverse=True):
        spec = schur(spec, k - 1)
    if d.congruence is None:
        return spec
    blocks = [t.sized(s) if isinstance(t, SizedIdentity) else t
              for t, s in zip(d.congruence, spec.sizes)]
    return congruence(blocks, spec)


def _expected_recovery(d: Derivation, name: str):
    if name in d.recovers:
        return sp.sympify(d.recovers[name])
    for decls in (d.source.data_decl, d.source.var_decl):
        if name in decls:
            return decls[name].symbol
    for lmi in d.source.lmis:            # a source written with another theorem's symbols
        for symbol in lmi.symbols():
            if getattr(symbol, "name", None) == name:
                return symbol
    return None


def _full(evaluator, spec, sizes) -> fmpq_mat:
    """The whole symmetric matrix from the lower triangle of blocks, exactly."""
    q = spec.nblocks
    lower = [[to_matrix(evaluator.visit(spec.lower[i][j])) for j in range(i + 1)] for i in range(q)]
    return evaluator.block([[lower[i][j] if j <= i else lower[j][i].transpose() for j in range(q)]
                            for i in range(q)])


def _first_difference(a: fmpq_mat, b: fmpq_mat) -> tuple[int, int]:
    """First differing entry in the lower triangle, block row by block row (row-major)."""
    for i in range(a.nrows()):
        for j in range(i + 1):
            if a[i, j] != b[i, j]:
                return i, j
    raise ValueError("no difference")


def _locate(index: int, sizes: list[int]) -> tuple[int, int]:
    """(block, offset inside it) of a scalar row/column index."""
    for block, size in enumerate(sizes):
        if index < size:
            return block, index
        index -= size
    raise IndexError(index)


def check_derivation(theorem, d: Derivation, *, points: int = 3, seed: int = 0,
                     dims: dict | None = None) -> DerivationResult:
    """Evaluate both sides of ``d`` at ``points`` random rational points per dimension set."""
    theorem = as_theorem(theorem)
    result = DerivationResult(theorem.id, d.label, d.source.id, d.source_label, EXACT, note=d.note)
    target = next(l for l in theorem.lmis if l.label == d.label).negative_form()
    derived = _derived_spec(d)
    definitions = {_key(k): sp.sympify(v) for k, v in d.substitute.items()}
    # factorisation outputs (R, S of rs_split) are checked only when the derivation defines them
    factored = {n for step in theorem.recovery_steps if isinstance(step, FactorStep) for n in step.names
                if n not in definitions}
    rng = random.Random(seed)
    recovery = {}
    for dimset in _dimension_sets(theorem, d.source, dims):
        result.dims.append({str(k): v for k, v in dimset.items()})
        done, attempts = 0, 0
        while done < points:
            attempts += 1
            if attempts > 10 * points:
                result.verdict = UNDECIDED
                result.message = "every random point made a substituted matrix singular"
                return result
            point = _Point(dimset, definitions, rng)
            try:
                t_sizes = [point.evaluator.size(x) for x in target.sizes]
                g_sizes = [point.evaluator.size(x) for x in derived.sizes]
                T = _full(point.evaluator, target, t_sizes)
                D = _full(point.evaluator, derived, g_sizes)
                if (T.nrows(), T.ncols()) != (D.nrows(), D.ncols()):
                    result.verdict = DIFFERS
                    result.message = (f"{d.label} is {T.nrows()}x{T.ncols()}, the derivation gives "
                                      f"{D.nrows()}x{D.ncols()}")
                    return result
                if T != D:
                    r, c = _first_difference(T, D)
                    i, ri = _locate(r, t_sizes)
                    j, cj = _locate(c, t_sizes)
                    if j > i:
                        i, j, ri, cj, r, c = j, i, cj, ri, c, r
                    gi, gr = _locate(r, g_sizes)
                    gj, gc = _locate(c, g_sizes)
                    result.verdict = DIFFERS
                    result.block = (i + 1, j + 1)
                    result.target_expr = str(target.block(i, j))
                    result.derived_expr = str(derived.block(gi, gj)) if gj <= gi else \
                        f"({derived.block(gj, gi)}).T"
                    if (t_sizes[i], t_sizes[j]) != (g_sizes[gi], g_sizes[gj]):
                        result.derived_expr = (f"entry ({gr + 1},{gc + 1}) of derived block "
                                               f"({gi + 1},{gj + 1}) = {result.derived_expr}")
                    result.target_expr = " ".join(result.target_expr.split())
                    result.derived_expr = " ".join(result.derived_expr.split())
                    result.entry = {"row": ri + 1, "col": cj + 1, "target": str(T[r, c]),
                                    "derived": str(D[r, c])}
                    result.points = done + 1
                    return result
                for name, formula in theorem.recovery.items():
                    expected = _expected_recovery(d, name)
                    if expected is None or any(getattr(s, "name", None) in factored for s in formula.atoms(sp.MatrixSymbol)):
                        recovery.setdefault(name, {"name": name, "verdict": "not checked",
                                                   "expected": "" if expected is None else str(expected)})
                        continue
                    got = to_matrix(point.evaluator.visit(formula))
                    want = to_matrix(point.evaluator.visit(expected))
                    same = (got.nrows(), got.ncols()) == (want.nrows(), want.ncols()) and got == want
                    previous = recovery.get(name, {}).get("verdict", EXACT)
                    recovery[name] = {"name": name, "formula": str(formula), "expected": str(expected),
                                      "verdict": EXACT if same and previous == EXACT else DIFFERS}
            except ZeroDivisionError:
                continue                      # a substituted matrix singular here: draw again
            except NotRational as exc:
                result.verdict = UNDECIDED
                result.message = f"not exactly evaluable: {exc}"
                return result
            except (TypeError, ValueError, KeyError) as exc:   # e.g. a dimension no example fixes
                result.verdict = UNDECIDED
                result.message = f"cannot evaluate at {result.dims[-1]}: {type(exc).__name__}: {exc}"
                return result
            done += 1
            result.points += 1
            result.free = sorted(set(result.free) | point.evaluator.freed)
    result.recovery = list(recovery.values())
    return result


def check_theorem(theorem, *, points: int = 3, seed: int = 0, dims: dict | None = None) -> list[DerivationResult]:
    """Every derivation the theorem declares (a one-line error if it declares none)."""
    theorem = as_theorem(theorem)
    if not getattr(theorem, "derivations", ()):            # a family of theorems has none
        raise InputError(f"{theorem.id} declares no derivation (Theorem.derived_from)")
    return [check_derivation(theorem, d, points=points, seed=seed, dims=dims) for d in theorem.derivations]


__all__ = ["DerivationResult", "check_derivation", "check_theorem", "EXACT", "DIFFERS", "UNDECIDED"]
