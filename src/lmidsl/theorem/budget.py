"""The size of an expansion, estimated from the declaration before it is built, and the limits
that refuse what would not finish.

A theorem over an index set of N members states each quantified LMI once; its member has one
LMI per environment of the quantifier (N for ∀i, N(N − 1) for ∀i ≠ j, …), each of the size
its blocks have at N.  A robust LMI over Λ_{N₁} × … of degree D_s in simplex s (the largest
block degree, with HPPD variables of degree g) and Pólya's d has

    Π_s C(N_s + D_s + d − 1, D_s + d)

coefficient LMIs, and an HPPD variable Π_s C(N_s + g_s − 1, g_s) coefficient matrices.  The
SDP's size is counted as the solver sees it: the rows of its PSD cones, Σ_k n_k(n_k + 1)/2 for
LMIs of sizes n_k, and the scalar decision variables (free entries).  The dimensions come from
the shapes of the data given (a dimension no datum fixes counts as 1: the estimate is then a
lower bound).

The estimate costs a walk of each statement on a one-vertex domain (degrees) and arithmetic; it
is checked against :class:`Limits` before anything is expanded, and what exceeds a limit is
refused in one line naming the estimate, the limit and the override (``--max-lmis``,
``--max-psd-rows``; ``max_lmis=``, ``max_psd_rows=`` in the Python API).  Defaults, measured on
a loaded 2-core machine (``benchmarks/bench_polya.py --end-to-end``, ``bench_mjls.py
--end-to-end``): HPPD stability of 2×2 matrices over 12 vertices, 1,729 coefficient LMIs, solves
end to end in 8–12 s of CPU (g = 2, d = 1; g = 3, d = 0), while 5,733 (g = 2, d = 2) did not
finish in 280 s (the coefficients' terms grow with g + d), so :data:`MAX_LMIS` = 5,000; the
Markov jump theorem with n = 2 and N = 60 modes (60 LMIs of 120×120, 435,780 rows) solves in
36 s of CPU and 233 MiB, N = 200 (16 million rows) would not fit Clarabel's KKT system, so
:data:`MAX_PSD_ROWS` = 500,000 (N ≤ 62 at n = 2).  The LMI count is a proxy for the symbolic
expansion's work, which also grows with the terms per coefficient.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import comb, prod

import numpy as np
import sympy as sp

from ..errors import InputError
from ..symbolic.symbols import Dim

from .limits import MAX_LMIS, MAX_PSD_ROWS, Limits, _LIMITS, current_limits, expansion_limits, set_limits


@dataclass
class Estimate:
    """What an expansion would build: ``what`` names it (e.g. "12 vertices, degree 4, Pólya 4")."""

    what: str
    lmis: int = 0
    psd_rows: int = 0
    variables: int = 0
    largest: int = 0          # the largest LMI's size

    def add_lmis(self, count: int, size: int) -> None:
        self.lmis += count
        self.psd_rows += count * size * (size + 1) // 2
        self.largest = max(self.largest, size)

    def text(self) -> str:
        return (f"{self.what} expands into {self.lmis:,} LMIs (largest {self.largest}×{self.largest}, "
                f"{self.psd_rows:,} rows of PSD cones, {self.variables:,} scalar variables)")


def check(theorem_id: str, estimate: Estimate) -> None:
    """Refuse (one line, exit 2) an estimate over the current limits."""
    limits = _LIMITS.get()
    if estimate.lmis > limits.max_lmis:
        raise InputError(f"{theorem_id}: {estimate.text()}: over the limit of {limits.max_lmis:,} LMIs; "
                         f"give --max-lmis {estimate.lmis} (max_lmis= in Python) to run it anyway")
    if estimate.psd_rows > limits.max_psd_rows:
        raise InputError(f"{theorem_id}: {estimate.text()}: over the limit of {limits.max_psd_rows:,} rows of "
                         f"PSD cones; give --max-psd-rows {estimate.psd_rows} (max_psd_rows= in Python) to run "
                         f"it anyway")


# -- dimensions from the data, before binding ---------------------------------------------
def _first_shape(inputs: dict, name: str, keys: tuple):
    """The shape of datum ``name`` in the inputs: given directly, or in the first object of one
    of the lists under ``keys`` ("vertices", an index set's key)."""
    candidates = [inputs.get(name)]
    for key in keys:
        items = inputs.get(key)
        if isinstance(items, list) and items and isinstance(items[0], dict):
            candidates.append(items[0].get(name))
    for value in candidates:
        if value is None:
            continue
        try:
            return np.atleast_2d(np.asarray(value, dtype=float)).shape
        except (TypeError, ValueError):
            return None
    return None


def dims_from_inputs(theorem, inputs: dict, keys: tuple = ("vertices",)) -> dict:
    """{Dim: int} read off the data shapes (given dimensions first); a dimension no datum fixes is 1."""
    dims = {}
    for name, d in theorem.dims.items():
        value = inputs.get(name)
        if isinstance(value, int) and not isinstance(value, bool) and value > 0:
            dims[d] = value
    for name, decl in theorem.data_decl.items():
        shape = _first_shape(inputs, name, keys)
        if shape is None or len(shape) != 2:
            continue
        for axis, expected in enumerate(decl.symbol.shape[:2]):
            if isinstance(expected, Dim) and expected not in dims:
                dims[expected] = int(shape[axis])
    for d in theorem.dims.values():
        dims.setdefault(d, 1)
    return dims


def integer(expr, values: dict) -> int:
    """A size expression as an integer under ``values`` (symbols left free count as 1)."""
    e = sp.sympify(sp.sympify(expr).xreplace(values))
    if e.free_symbols:
        e = e.xreplace({s: 1 for s in e.free_symbols})
    return max(int(e), 0)


def free_entries(kind: str, rows: int, cols: int) -> int:
    """Scalar unknowns of a decision matrix of this kind and shape."""
    if kind == "symmetric":
        return rows * (rows + 1) // 2
    if kind == "diagonal":
        return rows
    return rows * cols


# -- index sets ----------------------------------------------------------------------------
ENUMERATE_UP_TO = 1_000_000


def environments_count(quantifier, sizes: dict) -> int:
    """How many instances a quantified statement has: enumerated with its condition when the
    product of the ranges is at most :data:`ENUMERATE_UP_TO`, else that product (an upper bound)."""
    ranges = [sizes[k.set_name] for k in quantifier.indices]
    total = prod(ranges)
    if quantifier.where is None or total > ENUMERATE_UP_TO:
        return total
    return len(quantifier.environments(sizes))


def index_set_estimate(template, sizes: dict, inputs: dict) -> Estimate:
    """The member of ``template`` for the index-set sizes ``sizes``, estimated from the statement."""
    keys = ("vertices",) + tuple(M.key for M in template.index_sets.values())
    dims = dims_from_inputs(template, inputs, keys)
    size_env = {template.index_sets[name].size: n for name, n in sizes.items()}
    values = {**dims, **size_env}
    what = ", ".join(f"{n} {name}" for name, n in sizes.items())
    estimate = Estimate(f"the member for {what}")
    for lmi in template.lmis:
        q = getattr(lmi, "quantifier", None)
        if q is None:
            estimate.add_lmis(1, sum(integer(s, values) for s in lmi.spec.sizes))
            continue
        env = {k: 1 for k in q.indices}          # the size of the instance at i = 1 (j = 1, …)
        estimate.add_lmis(environments_count(q, sizes), sum(integer(s, {**values, **env}) for s in lmi.spec.sizes))
    for name, fam in template.indexed_decl.items():
        if fam.kind in ("data", "recovered"):
            continue
        members = prod(sizes[s.name] for s in fam.sets)
        estimate.variables += members * free_entries(fam.kind, integer(fam.rows, values), integer(fam.cols, values))
    for name, decl in template.var_decl.items():
        if name in template.indexed_decl:
            continue
        shape = getattr(decl.symbol, "shape", ())
        rows, cols = (integer(shape[0], values), integer(shape[1], values)) if len(shape) == 2 else (1, 1)
        estimate.variables += free_entries(getattr(decl.symbol, "kind", "full"), rows, cols)
    return estimate


# -- polytopes: HPPD and Pólya ---------------------------------------------------------------
def robust_estimate(theorem, sizes: tuple, degree: int, polya: int, inputs: dict, lmi_degrees: dict) -> Estimate:
    """The coefficient theorem of a robust theorem for simplices of ``sizes`` vertices, HPPD
    degree ``degree`` and Pólya ``polya``; ``lmi_degrees`` maps an LMI label to its degree per
    simplex (absent: an LMI that does not depend on α)."""
    dims = dims_from_inputs(theorem, inputs)
    domain = " × ".join(f"Λ_{n}" for n in sizes) if len(sizes) > 1 else f"{sizes[0]} vertices"
    estimate = Estimate(f"the relaxation over {domain} at degree {degree}, Pólya {polya}")
    for lmi in theorem.lmis:
        size = sum(integer(s, dims) for s in lmi.spec.sizes)
        D = lmi_degrees.get(lmi.label)
        count = 1 if D is None else prod(comb(N + g + polya - 1, g + polya) for N, g in zip(sizes, D))
        estimate.add_lmis(count, size)
    for name, decl in theorem.var_decl.items():
        symbol = decl.symbol
        shape = getattr(symbol, "shape", ())
        rows, cols = (integer(shape[0], dims), integer(shape[1], dims)) if len(shape) == 2 else (1, 1)
        entries = free_entries(getattr(symbol, "kind", "full"), rows, cols)
        poly = theorem.polynomial.get(name)
        if poly is not None and poly.kind == "variable":
            g = degree if poly.degree == "degree" else poly.degree
            entries *= prod(comb(N + g - 1, g) if s in poly.simplices else 1
                            for N, s in zip(sizes, theorem.simplices))
        estimate.variables += entries
    return estimate


__all__ = ["Limits", "Estimate", "MAX_LMIS", "MAX_PSD_ROWS", "check", "current_limits", "expansion_limits",
           "set_limits", "index_set_estimate", "robust_estimate", "dims_from_inputs", "environments_count"]
