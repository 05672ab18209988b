"""Automatic conditioning: an exact congruence and variable scaling of every compiled LMI.

Interior-point solvers see numbers, not systems: a plant with B ≈ 1e6 and C ≈ 1e-6 has the same
H∞ norm as the balanced one, yet its bounded-real LMI has entries from 1e-12 to 1e12 and the
solver stops far from the optimum or fails.  Two changes leave every LMI's feasibility and the
objective's minimiser untouched:

* a congruence of each LMI by T = diag(t₁ I, …, t_q I), one factor per block row:
  N ≺ 0 ⇔ T N T ≺ 0, block (i, j) multiplied by t_i t_j;
* a scaling of each decision variable, X = s_X X̃ (the solver works on X̃; X is reported).

The factors are chosen from the theorem's own terms.  For block (i, j) of an LMI and each
decision variable X in it, m_ijX = max |∂N_ij/∂X · U| for a unit-norm direction U (the size of
X's coefficients), and c_ij = max |N_ij(0)| (the constant part).  Equilibration asks every
nonzero coefficient to become about 1:

    log t_i + log t_j + log s_X = −log m_ijX,       log t_i + log t_j = −log c_ij,

solved in the least-squares sense (with a small pull towards 1 for directions the equations do
not fix) — the geometric scaling of matrix equilibration, on the theorem's block structure.
Factors are rounded to powers of two, so scaling adds no rounding error, and clamped to 2^±60.
The strictness margin then applies to T N T: it is relative to the size of each block.  The
objective is divided by the size of its coefficients in the scaled variables (a power of two),
so that a solver's absolute tolerances mean the same on γ* = 1e-9 as on γ* = 1.

The scaling is proposed only when it narrows the spread of the coefficients (largest over
smallest, log2) by at least :data:`MIN_GAIN` bits.  Even then it is a second opinion, not a
replacement (:meth:`lmidsl.solver.plan.Plan.solve`): a least-squares compromise can make a problem worse for
a particular solver, so the theorem is solved as written *and* conditioned, and of the points
whose LMIs hold the one with the lower objective is kept (both are certificates: the lower bound
is the better one).

Nothing downstream sees the scaling: the model reports X = s_X X̃, and the certificate and the
proofs evaluate the original LMIs at the original point.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..numeric.evaluate import NumericEvaluator
from ..numeric.instance import Instance
from ..symbolic.symbols import DECISION_TYPES, ScalarVariable, StructuredVariable
from ..symbolic.uncertainty import scenarios

MAX_EXPONENT = 60
PULL = 1e-2          # weight of log f = 0 for every factor (fixes the directions left free)
MIN_GAIN = 10.0      # bits of coefficient spread the scaling must remove to be applied


def _spread(log_sizes: np.ndarray) -> float:
    """log2(largest / smallest coefficient)."""
    return float(log_sizes.max() - log_sizes.min()) if log_sizes.size else 0.0


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


def _decision_atoms(expr) -> set:
    found = set()
    for atom in expr.atoms(sp.Symbol, sp.MatrixSymbol):
        if isinstance(atom, StructuredVariable):
            found |= _decision_atoms(atom.expansion)
        elif isinstance(atom, DECISION_TYPES):
            found.add(atom)
    return found


def _unit(symbol, dims, rng):
    """A direction of norm 1 with the variable's structure (symmetric, diagonal, full, scalar)."""
    if isinstance(symbol, ScalarVariable):
        return 1.0
    r = int(sp.sympify(symbol.shape[0]).xreplace(dims))
    c = int(sp.sympify(symbol.shape[1]).xreplace(dims))
    X = rng.standard_normal((r, c))
    if symbol.kind == "symmetric":
        X = X + X.T
    elif symbol.kind == "diagonal":
        X = np.diag(np.diag(X))
    return X / max(np.linalg.norm(X), 1e-300)


def _zero(symbol, dims):
    if isinstance(symbol, ScalarVariable):
        return 0.0
    return np.zeros(tuple(int(sp.sympify(d).xreplace(dims)) for d in symbol.shape))


def _size(value) -> float:
    a = np.abs(np.asarray(value, dtype=float))
    return float(a.max()) if a.size else 0.0


def equilibrate(instance: Instance) -> Equilibration:
    """The factors for ``instance`` (see the module docstring)."""
    theorem = instance.theorem
    rng = np.random.default_rng(0)
    variables = {n: d.symbol for n, d in theorem.var_decl.items()
                 if getattr(d.symbol, "kind", None) != "structured"}
    zero = dict(instance.data)
    for name, symbol in variables.items():
        value = _zero(symbol, instance.dims)
        zero[name] = [value] * instance.nvertices if getattr(symbol, "per_vertex", False) else value
    units = {name: _unit(symbol, instance.dims, rng) for name, symbol in variables.items()}

    columns: dict = {}                       # unknown -> column index

    def col(key):
        return columns.setdefault(key, len(columns))

    equations = []                           # ([(column, coefficient)], right-hand side)
    for index, lmi in enumerate(theorem.lmis):
        scenario = scenarios(instance, lmi)[0]
        negative = lmi.negative_form()
        for i, row in enumerate(negative.lower):
            for j, block in enumerate(row):
                expr = scenario.apply(block)
                at_zero = NumericEvaluator(instance.dims, zero, instance.params, scenario.vertex).visit(expr)
                rows = [(col(("row", index, i)), 1.0), (col(("row", index, j)), 1.0)]
                c = _size(at_zero)
                if c > 0:
                    equations.append((rows, -np.log2(c)))
                for symbol in _decision_atoms(expr):
                    point = dict(zero)
                    unit = units[symbol.name]
                    point[symbol.name] = ([unit] * instance.nvertices
                                          if getattr(symbol, "per_vertex", False) else unit)
                    value = NumericEvaluator(instance.dims, point, instance.params, scenario.vertex).visit(expr)
                    m = _size(np.asarray(value, dtype=float) - np.asarray(at_zero, dtype=float))
                    if m > 0:
                        equations.append((rows + [(col(("var", symbol.name)), 1.0)], -np.log2(m)))
    if not equations:
        return Equilibration()
    M = np.zeros((len(equations) + len(columns), len(columns)))
    rhs = np.zeros(M.shape[0])
    for k, (terms, b) in enumerate(equations):
        for c, a in terms:
            M[k, c] += a
        rhs[k] = b
    M[len(equations):, :] = PULL * np.eye(len(columns))
    logs, *_ = np.linalg.lstsq(M, rhs, rcond=None)
    exponents = np.clip(np.round(logs), -MAX_EXPONENT, MAX_EXPONENT)
    terms = M[:len(equations)]
    before = _spread(-rhs[:len(equations)])
    after = _spread(terms @ exponents - rhs[:len(equations)])
    if before - after < MIN_GAIN:
        return Equilibration(spread=(before, before))      # already balanced: leave it alone
    result = Equilibration(spread=(before, after))
    for key, c in columns.items():
        factor = float(2.0 ** exponents[c])
        if key[0] == "var":
            result.variables[key[1]] = factor
        else:
            _, index, i = key
            q = theorem.lmis[index].negative_form().nblocks
            result.rows.setdefault(index, [1.0] * q)[i] = factor
    if theorem.objective is not None:
        at_zero = float(NumericEvaluator(instance.dims, zero, instance.params).visit(theorem.objective))
        sizes = []
        for symbol in _decision_atoms(theorem.objective):
            point = dict(zero)
            unit = units[symbol.name]
            point[symbol.name] = [unit] * instance.nvertices if getattr(symbol, "per_vertex", False) else unit
            value = float(NumericEvaluator(instance.dims, point, instance.params).visit(theorem.objective))
            sizes.append(abs(value - at_zero) * result.variable(symbol.name))
        if sizes and max(sizes) > 0:
            result.objective = float(2.0 ** np.clip(np.round(np.log2(max(sizes))), -MAX_EXPONENT, MAX_EXPONENT))
    return result


__all__ = ["Equilibration", "equilibrate"]
