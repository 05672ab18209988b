"""Binding numbers to a theorem: shape-checked data, parameter values, dimensions.

``bind(theorem, inputs)`` turns a dictionary of data matrices (nested lists), dimension
values and scalar parameters into an :class:`Instance`.  Dimensions are read off the data in
declaration order; a datum whose shape contradicts them is reported with the LMI block where
it enters.  Parameters are checked against their declared domains; derived parameters are
evaluated.  The diagonal blocks of every LMI are checked to be symmetric at random points.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from ..errors import InputError, ShapeMismatchError, TheoremDefinitionError, UnusedDataWarning
from .evaluate import NumericEvaluator, asymmetry
from ..symbolic.numbers import finite_matrix, finite_number, positive_integer
from ..symbolic.shapes import fmt_shape
from ..symbolic.parameter_values import NotRealError, parameter_value
from ..symbolic.symbols import Dim, ScalarVariable
from ..theorem.assumptions import check_assumptions
from ..theorem.theorem import Theorem
from ..symbolic.uncertainty import bind_points
from ..symbolic.uncertainty import scenarios


@dataclass
class Instance:
    """A theorem with numbers: dims, data (per-vertex data as lists), parameter values."""

    theorem: Theorem
    dims: dict
    data: dict
    params: dict
    nvertices: int = 1
    example: str | None = None
    notes: list = field(default_factory=list)
    uncertain: dict = field(default_factory=dict)  # name -> points (units of the bound)

    def dim_values(self) -> dict:
        return {str(k): v for k, v in self.dims.items()}

    def with_params(self, **values) -> "Instance":
        """The same instance with some base parameters changed (derived ones recomputed)."""
        base = {n: self.params[n] for n in self.theorem.param_decl}
        for name, value in values.items():
            if name not in self.theorem.param_decl:
                raise InputError(f"{self.theorem.id}: unknown parameter {name!r}")
            base[name] = value
        return replace(self, params=_evaluate_params(self.theorem, base))


def _as_matrix(theorem: Theorem, name: str, value) -> np.ndarray:
    return finite_matrix(value, f"{theorem.id}: data {name}")


def _evaluate_params(theorem: Theorem, base: dict) -> dict:
    values = {}
    for name, decl in theorem.param_decl.items():
        value = base.get(name, decl.extra.get("default"))
        if value is None:
            raise InputError(f"{theorem.id}: missing parameter {name}")
        value = finite_number(value, f"{theorem.id}: parameter {name}")
        domain = decl.extra.get("domain")
        if domain is not None:
            is_open = decl.extra.get("open", False)
            inside = domain[0] < value < domain[1] if is_open else domain[0] <= value <= domain[1]
            if not inside:
                interval = f"({domain[0]}, {domain[1]})" if is_open else f"[{domain[0]}, {domain[1]}]"
                note = decl.extra.get("note")
                raise InputError(f"{theorem.id}: parameter {name} = {value} is outside its domain "
                                 f"{interval}" + (f": {note}" if note else ""))
        values[name] = float(value)
    for name, decl in theorem.derived_decl.items():
        try:
            values[name] = parameter_value(decl.symbol.definition, values)
        except NotRealError as exc:
            raise InputError(f"{theorem.id}: derived parameter {name} = {exc} is not a real number") from None
        if not np.isfinite(values[name]):
            raise InputError(f"{theorem.id}: derived parameter {name} is not finite at these parameters")
    return values


def _infer_dims(theorem: Theorem, matrices: dict, given_dims: dict) -> dict:
    """Assign every dimension symbol from the data shapes: the size most data agree on (one vote
    per datum; a tie goes to the first declared), so that the one datum of a wrong shape (a
    ``--set A=...`` of the wrong size) is the one blamed, not its neighbours."""
    dims = {theorem.dims[k]: v for k, v in given_dims.items()}
    origin = {theorem.dims[k]: "given" for k in given_dims}
    votes: dict = {}                        # dim -> size -> [(datum, axis), ...]
    for name, (symbol, arrays) in matrices.items():
        for axis, expected in enumerate(symbol.shape):
            if isinstance(expected, Dim) and expected not in dims:
                sources = votes.setdefault(expected, {}).setdefault(arrays[0].shape[axis], [])
                if name not in (n for n, _ in sources):
                    sources.append((name, axis))
    for d, sizes in votes.items():
        size, sources = max(sizes.items(), key=lambda item: len(item[1]))   # max keeps the first of a tie
        dims[d] = size
        origin[d] = f"{sources[0][0]} {'rows' if sources[0][1] == 0 else 'columns'}"
    for d in theorem.dims.values():
        if d not in dims:
            raise InputError(f"{theorem.id}: dimension {d} is not fixed by any datum; give it as {d}=<int>")
    for name, (symbol, arrays) in matrices.items():
        for v, arr in enumerate(arrays):
            expected = tuple(int(sp.sympify(e).xreplace(dims)) for e in symbol.shape)
            if expected != arr.shape:
                used = [f"{d} = {dims[d]} from {origin[d]}" for d in
                        sorted(sp.Tuple(*symbol.shape).free_symbols, key=str)]
                vtxt = f" (vertex {v + 1})" if len(arrays) > 1 else ""
                raise ShapeMismatchError(
                    f"{theorem.id}: data {name}{vtxt} is {fmt_shape(arr.shape)} but must be "
                    f"{fmt_shape(symbol.shape)} = {fmt_shape(expected)} ({', '.join(used)}); "
                    f"{name}{vtxt} enters {_first_use(theorem, symbol, v)}")
    return dims


def _first_use(theorem: Theorem, symbol, vertex: int) -> str:
    """Where ``symbol`` (at ``vertex``) first enters the theorem's LMIs: in a member of a robust
    theorem (:mod:`lmidsl.theorem.robust`) a vertex datum enters through its vertex copy
    (A at vertex 2 is ``A_2`` in the coefficient LMIs)."""
    for alias, (name, v) in getattr(theorem, "vertex_data", {}).items():
        if name == symbol.name and v == vertex:
            copy = next((a for lmi in theorem.lmis for a in lmi.symbols() if getattr(a, "name", None) == alias), None)
            if copy is not None:
                return f"{theorem.first_use(copy)} (as {alias})"
    return theorem.first_use(symbol)


def bind(theorem: Theorem, inputs: dict, example: str | None = None, *,
         optional: frozenset | set = frozenset()) -> Instance:
    """Check and bind ``inputs`` (data, dims, parameters, optional 'vertices') to ``theorem``.

    Per-vertex data go under ``vertices`` (a list of objects, one per polytope vertex); a
    per-vertex datum given once, outside ``vertices``, is common to every vertex, and without
    ``vertices`` the polytope is the single vertex of the data given.
    A theorem whose block structure depends on an input (``theorem.specialise``, see
    :mod:`lmidsl.theorem.family`) is first replaced by the member that input selects.  Inputs named
    after an uncertain symbol choose its points (:mod:`lmidsl.symbolic.uncertainty`).
    Names in ``optional`` (the entries of a data file) that the theorem does not know are
    ignored with an :class:`~lmidsl.errors.UnusedDataWarning`, so that one plant file serves
    several theorems; any other unknown name is an error (a typo in ``--set``).
    """
    if hasattr(theorem, "specialise"):
        theorem = theorem.specialise(inputs)
    inputs = dict(theorem.inputs_for(inputs) if hasattr(theorem, "inputs_for") else inputs)
    check_assumptions(theorem, inputs, inputs.get("vertices") if isinstance(inputs.get("vertices"), list) else None)
    uncertain = bind_points(theorem, inputs)
    vertices = inputs.pop("vertices", None)
    per_vertex = theorem.per_vertex_names
    known = set(theorem.data_decl) | set(theorem.param_decl) | set(theorem.dims)
    unused = sorted(n for n in inputs if n in optional and n not in known
                    and n not in theorem.derived_decl and n != "vertices")
    if unused:
        warnings.warn(UnusedDataWarning(f"{theorem.id}: ignoring data the theorem does not use: "
                                        f"{', '.join(unused)}"), stacklevel=2)
        for name in unused:
            inputs.pop(name)
    for name in inputs:
        if name in theorem.derived_decl:
            defn = theorem.derived_decl[name].symbol.definition
            raise InputError(f"{theorem.id}: {name} is derived ({name} = {defn}); set the parameters it "
                             f"depends on instead")
        if name not in known:
            raise InputError(
                f"{theorem.id}: unknown data or parameter {name!r} (known: {', '.join(sorted(known))})")
    if vertices is not None and not per_vertex:
        raise InputError(f"{theorem.id}: this theorem has no per-vertex data, but 'vertices' was given")
    if per_vertex and vertices is None:
        vertices = [{}]          # one vertex: the per-vertex data are all given once
    if vertices is not None:
        if not isinstance(vertices, list) or not vertices or not all(isinstance(v, dict) for v in vertices):
            raise InputError(f"{theorem.id}: 'vertices' must be a non-empty list of objects")
        # a per-vertex datum given once, outside 'vertices', is common to every vertex
        common = per_vertex & set(inputs)
        for k, v in enumerate(vertices):
            extra = set(v) - per_vertex
            twice = set(v) & common
            missing = per_vertex - set(v) - common
            if extra:
                raise InputError(f"{theorem.id}: vertex {k + 1}: {', '.join(sorted(extra))} are not per-vertex data")
            if twice:
                raise InputError(f"{theorem.id}: vertex {k + 1}: {', '.join(sorted(twice))} given both in "
                                 f"the vertex and once for all vertices")
            if missing:
                raise InputError(f"{theorem.id}: vertex {k + 1}: missing {', '.join(sorted(missing))}")
        vertices = [{**{c: inputs[c] for c in common}, **v} for v in vertices]
        for c in common:
            inputs.pop(c)
    nvertices = len(vertices) if vertices else 1

    given_dims = {}
    for name in theorem.dims:
        if name in inputs:
            value = inputs[name]
            given_dims[name] = positive_integer(value, f"{theorem.id}: dimension {name}")
    data, matrices = {}, {}
    for name, decl in theorem.data_decl.items():
        if name in per_vertex:
            arrays = [_as_matrix(theorem, name, v[name]) for v in vertices]
            data[name] = arrays
        else:
            if name not in inputs:
                raise InputError(f"{theorem.id}: missing data {name}")
            arrays = [_as_matrix(theorem, name, inputs[name])]
            data[name] = arrays[0]
        matrices[name] = (decl.symbol, arrays)
        if getattr(decl.symbol, "is_symmetric", False):
            for arr in arrays:
                if arr.shape[0] == arr.shape[1] and asymmetry(arr) > 1e-12:
                    raise InputError(f"{theorem.id}: data {name} must be symmetric")
    dims = _infer_dims(theorem, matrices, given_dims)
    _refuse_empty_dimensions(theorem, dims, data)
    for alias, (name, v) in getattr(theorem, "vertex_data", {}).items():   # A_i of A(α): theorem/robust.py
        data[alias] = data[name][v]
    params = _evaluate_params(theorem, {k: inputs[k] for k in theorem.param_decl if k in inputs})
    instance = Instance(theorem, dims, data, params, nvertices, example, uncertain=uncertain)
    check_symmetric_blocks(instance)
    return instance


def _refuse_empty_dimensions(theorem: Theorem, dims: dict, data: dict) -> None:
    """A dimension 0 (a 2×0 matrix in the data) is bad input, in one line naming the datum: an
    empty variable or block has no meaning in an LMI, and solvers and modelling layers fail on it
    each in their own way."""
    zero = sorted(str(d) for d, v in dims.items() if int(v) == 0)
    if not zero:
        return
    for name, value in data.items():
        for array in (value if isinstance(value, list) else [value]):
            if 0 in np.shape(array):
                shape = "×".join(str(n) for n in np.shape(array))
                raise InputError(f"{theorem.id}: data {name} is {shape}, so dimension {zero[0]} = 0; "
                                 f"dimensions must be at least 1")
    raise InputError(f"{theorem.id}: dimension {zero[0]} = 0; dimensions must be at least 1")


def random_point(instance: Instance, rng: np.random.Generator) -> dict:
    """Random values for every decision variable, respecting symmetric/diagonal kinds."""
    values = dict(instance.data)
    for name, decl in instance.theorem.var_decl.items():
        symbol = decl.symbol
        copies = instance.nvertices if getattr(symbol, "per_vertex", False) else 1
        draws = []
        for _ in range(copies):
            if isinstance(symbol, ScalarVariable):
                draws.append(float(rng.standard_normal()))
                continue
            if not hasattr(symbol, "kind") or symbol.kind == "structured":
                continue
            r = int(sp.sympify(symbol.shape[0]).xreplace(instance.dims))
            c = int(sp.sympify(symbol.shape[1]).xreplace(instance.dims))
            X = rng.standard_normal((r, c))
            if symbol.kind == "symmetric":
                X = X + X.T
            elif symbol.kind == "diagonal":
                X = np.diag(np.diag(X))
            draws.append(X)
        if draws:
            values[name] = draws if copies > 1 or getattr(symbol, "per_vertex", False) else draws[0]
    return values


def check_symmetric_blocks(instance: Instance) -> None:
    """Refuse an LMI whose diagonal block is not symmetric (never symmetrise silently): each
    diagonal block is evaluated at a random point of the variables *and of the data* (of their
    declared kinds: symmetric data symmetric; constants written in the LMI and parameters as
    given), at every polytope vertex and uncertainty scenario the LMI is imposed at.  A block
    symmetric at random data is symmetric for all data (its asymmetry is a polynomial in them);
    one that is symmetric only for the data given (``2·D₁·X₂ᵀ`` with a diagonal D₁ and X₂) is
    refused too, saying so: other data break it, and a datum that must be symmetric is declared
    so (``symmetric=True``)."""
    rng = np.random.default_rng(0)
    values = _random_data(instance, random_point(instance, rng), rng)
    theorem = instance.theorem
    for lmi in theorem.lmis:
        for scenario in scenarios(instance, lmi):
            for i, row in enumerate(lmi.spec.lower):
                value = _diagonal_value(instance, values, lmi, scenario, i)
                if value.shape[0] == value.shape[1] and asymmetry(value) <= 1e-9:
                    continue
                where = ("" if scenario.vertex is None else f" at vertex {scenario.vertex + 1}") + \
                        (f" at {scenario.label}" if scenario.label else "")
                given = _diagonal_value(instance, random_point(instance, rng), lmi, scenario, i)
                only = given.shape[0] == given.shape[1] and asymmetry(given) <= 1e-9
                text = (" for these data only: its symmetry rests on the data's values, not on their "
                        "declared kinds (a datum that must be symmetric is declared symmetric=True)"
                        if only else "")
                raise TheoremDefinitionError(
                    f"{theorem.id}: LMI {lmi.label} diagonal block ({i + 1},{i + 1}) {scenario.apply(row[i])} "
                    f"is {'symmetric' if only else 'not symmetric'}{where}{text} (relative asymmetry "
                    f"{asymmetry(value) if value.shape[0] == value.shape[1] else 'n/a'})")


def _diagonal_value(instance: Instance, values: dict, lmi, scenario, i: int) -> np.ndarray:
    """The diagonal block (i, i) of ``lmi`` at ``values`` (a definition error if it cannot be
    evaluated)."""
    blk = scenario.apply(lmi.spec.lower[i][i])
    ev = NumericEvaluator(instance.dims, values, instance.params, vertex=scenario.vertex)
    try:
        return np.atleast_2d(ev.visit(blk))
    except Exception as exc:  # a theorem that cannot be evaluated is a definition error
        raise TheoremDefinitionError(
            f"{instance.theorem.id}: LMI {lmi.label} block ({i + 1},{i + 1}) cannot be evaluated: {exc}") from None


def _random_data(instance: Instance, values: dict, rng: np.random.Generator) -> dict:
    """``values`` with every declared datum replaced by a random matrix of its shape and kind
    (symmetric data symmetric), per vertex; constants written in an LMI (quick mode) are kept,
    and the vertex copies of a robust theorem's data follow the data they are."""
    values = dict(values)
    for name, decl in instance.theorem.data_decl.items():
        if name not in values or type(decl.symbol).__name__ == "ConstantMatrix":
            continue
        symmetric = getattr(decl.symbol, "is_symmetric", False)

        def draw(a):
            r = rng.standard_normal(np.shape(a))
            return r + r.T if symmetric and r.ndim == 2 and r.shape[0] == r.shape[1] else r
        given = values[name]
        values[name] = [draw(a) for a in given] if isinstance(given, list) else draw(given)
    for alias, (name, v) in getattr(instance.theorem, "vertex_data", {}).items():
        values[alias] = values[name][v]
    return values
