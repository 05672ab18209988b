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

import numpy as np
import sympy as sp
from scipy import sparse
from scipy.sparse.linalg import spsolve

from ..numeric.instance import Instance
from .backends.direct_backend import DirectModel
from .equilibration import Equilibration
from ..symbolic.symbols import ScalarVariable

MAX_EXPONENT = 60
PULL = 1e-2          # weight of log f = 0 for every factor (fixes the directions left free)
MIN_GAIN = 10.0      # bits of coefficient spread the scaling must remove to be applied


def _spread(log_sizes: np.ndarray) -> float:
    """log2(largest / smallest coefficient)."""
    return float(log_sizes.max() - log_sizes.min()) if log_sizes.size else 0.0


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


def _affine_model(instance: Instance, model):
    """``model`` when it is a direct-backend model compiled as written, else one compiled now:
    the LMIs in the affine algebra, vec N(x) = vec N₀ + C x (:mod:`.backends.affine`)."""
    if isinstance(model, DirectModel) and model.equilibration.trivial and model.instance is instance:
        return model
    return DirectModel(instance)


def _directions(model, units: dict, names: list) -> tuple:
    """(u, owner) over the decision vector x: u holds each variable's unit direction in its free
    entries (the same direction at every vertex copy), owner[k] the index in ``names`` of the
    variable that entry k belongs to (−1: none)."""
    index = {name: k for k, name in enumerate(names)}
    u, owner = np.zeros(model.space.size), np.full(model.space.size, -1, dtype=np.int64)
    for (name, _), expression in model._variables.items():
        k = index.get(name)
        variable = getattr(expression, "variable", None)
        if k is None or variable is None:
            continue
        span = slice(variable.offset, variable.offset + variable.size)
        u[span], owner[span] = variable.free_entries(units[name]), k
    return u, owner


def _block_sizes(N, sizes: list, u: np.ndarray, owner: np.ndarray, nvars: int) -> tuple:
    """For the lower blocks (i ≥ j) of the assembled affine N: c_ij = max |N₀ block| and, per
    variable X, m_ijX = max |(C u_X) block| (C u_X = ∂N/∂X · U_X, one entry per triplet
    summed by (entry, X)).  Returns (c[q, q], m[q, q, nvars])."""
    q = len(sizes)
    edges = np.concatenate([[0], np.cumsum(sizes)])
    total = int(edges[-1])
    const = np.abs(np.atleast_2d(np.asarray(N.const, dtype=float)))
    c = np.zeros((q, q))
    for i in range(q):
        for j in range(i + 1):
            part = const[edges[i]:edges[i + 1], edges[j]:edges[j + 1]]
            c[i, j] = part.max() if part.size else 0.0
    m = np.zeros((q, q, nvars))
    if not len(N.vals) or not nvars:
        return c, m
    x = owner[N.cols]
    keep = x >= 0
    rows, x, w = N.rows[keep], x[keep], N.vals[keep] * u[N.cols[keep]]
    key, inverse = np.unique(rows * nvars + x, return_inverse=True)
    summed = np.abs(np.bincount(inverse, weights=w, minlength=len(key)))
    entry, var = np.divmod(key, nvars)
    r, col = np.divmod(entry, total)
    bi = np.searchsorted(edges, r, side="right") - 1
    bj = np.searchsorted(edges, col, side="right") - 1
    lower = bi >= bj
    np.maximum.at(m, (bi[lower], bj[lower], var[lower]), summed[lower])
    return c, m


def _least_squares(equations: list, ncols: int) -> tuple:
    """argmin ‖M x − b‖² + PULL²‖x‖² for the equations' sparse rows M (each equation touches two
    or three unknowns): the normal equations (MᵀM + PULL² I) x = Mᵀb, symmetric positive
    definite and sparse, by a sparse LU — not a dense least-squares solve, whose cost grows as
    (equations × unknowns²) (a Pólya relaxation of 1,729 LMIs: 41 s).  Returns (x, M, b)."""
    rows = [k for k, (terms, _) in enumerate(equations) for _ in terms]
    cols = [c for terms, _ in equations for c, _ in terms]
    vals = [a for terms, _ in equations for _, a in terms]
    M = sparse.csr_matrix((vals, (rows, cols)), shape=(len(equations), ncols))      # duplicates add up
    b = np.array([rhs for _, rhs in equations])
    normal = (M.T @ M + PULL ** 2 * sparse.identity(ncols)).tocsc()
    return np.atleast_1d(spsolve(normal, M.T @ b)), M, b


def equilibrate(instance: Instance, model=None) -> Equilibration:
    """The factors for ``instance`` (see the module docstring), from the LMIs compiled as written
    in the direct backend's affine algebra (``model``, or a model compiled here): c_ij and
    m_ijX are read off N₀ and the coefficient triplets C with numpy, at the first scenario
    (vertex) of each LMI — no symbolic walk per variable."""
    theorem = instance.theorem
    rng = np.random.default_rng(0)
    variables = {n: d.symbol for n, d in theorem.var_decl.items()
                 if getattr(d.symbol, "kind", None) != "structured"}
    units = {name: _unit(symbol, instance.dims, rng) for name, symbol in variables.items()}
    names = list(variables)
    model = _affine_model(instance, model)
    u, owner = _directions(model, units, names)
    first = {}
    for (label, _, _), N in model.lmi_matrices:
        first.setdefault(label, N)

    columns: dict = {}                       # unknown -> column index

    def col(key):
        return columns.setdefault(key, len(columns))

    equations = []                           # ([(column, coefficient)], right-hand side)
    for index, lmi in enumerate(theorem.lmis):
        negative = lmi.negative_form()
        sizes = [int(sp.sympify(s).xreplace(instance.dims)) for s in negative.sizes]
        c, m = _block_sizes(first[lmi.label], sizes, u, owner, len(names))
        for i in range(len(sizes)):
            for j in range(i + 1):
                rows = [(col(("row", index, i)), 1.0), (col(("row", index, j)), 1.0)]
                if c[i, j] > 0:
                    equations.append((rows, -np.log2(c[i, j])))
                for k in np.flatnonzero(m[i, j]):
                    equations.append((rows + [(col(("var", names[k])), 1.0)], -np.log2(m[i, j, k])))
    if not equations:
        return Equilibration()
    logs, terms, rhs = _least_squares(equations, len(columns))
    exponents = np.clip(np.round(logs), -MAX_EXPONENT, MAX_EXPONENT)
    before = _spread(-rhs)
    after = _spread(terms @ exponents - rhs)
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
    objective = model.objective
    if theorem.objective is not None and getattr(objective, "vals", None) is not None and len(objective.vals):
        x = owner[objective.cols]
        keep = x >= 0
        per_variable = np.abs(np.bincount(x[keep], weights=objective.vals[keep] * u[objective.cols[keep]],
                                          minlength=len(names)))
        sizes = [per_variable[k] * result.variable(names[k]) for k in np.unique(x[keep])]
        if sizes and max(sizes) > 0:
            result.objective = float(2.0 ** np.clip(np.round(np.log2(max(sizes))), -MAX_EXPONENT, MAX_EXPONENT))
    return result


__all__ = ["Equilibration", "equilibrate"]
