"""Sympy symbols for the objects a theorem talks about.

* :class:`Dim` - a dimension (``n``, ``k``), a positive integer symbol fixed when data are bound.
* :class:`DataMatrix` - given data (``A``, ``B``); its shape is checked against the data at bind time.
* :class:`Variable` - a full decision matrix; :class:`SymmetricVariable` is its own transpose
  (``P.T is P``); :class:`DiagonalVariable` is symmetric with zero off-diagonal entries.
* :class:`StructuredVariable` - a named matrix built from other variables
  (``Λ = [[X, Z], [Z, Z]]``); it compiles to its expansion and prints as its name.
* :class:`ScalarVariable` - a scalar decision variable (``g = γ²``, a multiplier ``ε``).
* :class:`Param` - a scalar parameter fixed at bind time and swept without recompiling (``r̄``).
* :class:`RecoveredMatrix` - an intermediate matrix of a recovery, computed by a library
  factorisation after the solve (``R``, ``S`` with ``R Sᵀ = I − X Z⁻¹``).
* :class:`DerivedParam` - a named scalar defined by an expression of parameters
  (``a = (1 − r̄) r̄``); LMIs use the name, the value follows from the definition.

Every symbol carries a LaTeX name (``latex``) and a one-line description; the theorem keeps the
declarations, the symbols are what LMIs are written with.
"""
from __future__ import annotations

import numpy as np
import sympy as sp
from sympy import MatrixSymbol
from sympy.core.symbol import Str
from sympy.matrices.exceptions import ShapeError

from ..errors import ShapeMismatchError, TheoremDefinitionError

from ..errors import ShapeMismatchError, TheoremDefinitionError


class Dim(sp.Symbol):
    """A dimension: a positive integer symbol."""

    def __new__(cls, name: str, **kwargs):
        return super().__new__(cls, name, integer=True, positive=True)


_METADATA: dict = {}


def _meta_property(key: str, default=None):
    """A symbol attribute stored in the module's metadata table under (tag, name)."""

    def getter(self):
        return _METADATA.get((self.tag, self.name), {}).get(key, default)

    def setter(self, value):
        _METADATA.setdefault((self.tag, self.name), {})[key] = value

    return property(getter, setter)


def metadata_snapshot(tags=None) -> dict:
    """The symbols' metadata table (a copy; only the entries of ``tags`` if given): it lives in
    this process, not in the symbols, so an expression pickled to another process (a Dask
    worker) or to the theorem build cache needs it sent along."""
    return {key: dict(meta) for key, meta in _METADATA.items() if tags is None or key[0] in tags}


def restore_metadata(snapshot: dict) -> None:
    """Add a :func:`metadata_snapshot` of another process to this process's table."""
    for key, meta in snapshot.items():
        _METADATA.setdefault(key, {}).update(meta)


class _Described:
    """Mixin for symbols declared by a theorem: a theorem tag plus metadata.

    Sympy caches results by structural equality and rebuilds expressions from their ``args``,
    so Python attributes set on a symbol do not survive, and a plain ``Symbol("a")`` is one
    object shared by every theorem.  The ``tag`` (the theorem id) is therefore part of the
    symbol's identity (``args`` for matrices, hashable content for scalars), and the metadata
    (LaTeX name, description, per-vertex flag, definitions) lives in a table keyed by
    (tag, name): two theorems may both declare ``a`` with different definitions.
    """

    latex_name = _meta_property("latex_name")
    description = _meta_property("description", "")
    per_vertex = _meta_property("per_vertex", False)


class _TaggedMatrix(_Described, MatrixSymbol):
    """A MatrixSymbol with a fourth argument, the tag of the declaring theorem."""

    def __new__(cls, name, rows, cols, tag=""):
        rows, cols = sp.sympify(rows), sp.sympify(cols)
        cls._check_dim(rows)
        cls._check_dim(cols)
        return sp.Basic.__new__(cls, Str(str(name)), rows, cols, Str(str(tag)))

    @property
    def tag(self) -> str:
        return self.args[3].name if len(self.args) > 3 else ""


class _TaggedScalar(_Described, sp.Symbol):
    """A real Symbol outside sympy's symbol cache, carrying the tag of the declaring theorem."""

    def __new__(cls, name: str, tag: str = ""):
        obj = sp.Symbol.__xnew__(cls, name, real=True)
        obj._tag = tag
        return obj

    @property
    def tag(self) -> str:
        return getattr(self, "_tag", "")

    def _hashable_content(self):
        return super()._hashable_content() + (self.tag,)

    def __getnewargs_ex__(self):
        return (self.name, self.tag), {}


class DataMatrix(_TaggedMatrix):
    """A given matrix of the theorem (plant data, a fixed filter, a selector such as ``E``)."""


class SymmetricDataMatrix(DataMatrix):
    """Given data known to be symmetric (checked at bind time); its transpose is itself."""

    is_symmetric = True

    def _eval_transpose(self):
        return self


class Variable(_TaggedMatrix):
    """A full (unstructured) decision matrix."""

    kind = "full"


class SymmetricVariable(Variable):
    """A symmetric decision matrix: ``P.T`` is ``P``."""

    kind = "symmetric"
    is_symmetric = True

    def _eval_transpose(self):
        return self


class DiagonalVariable(SymmetricVariable):
    """A diagonal decision matrix."""

    kind = "diagonal"


class StructuredVariable(_TaggedMatrix):
    """A named matrix whose entries are other decision variables (``expansion``)."""

    kind = "structured"
    expansion = _meta_property("expansion")
    symmetric = _meta_property("symmetric", False)

    def _eval_transpose(self):
        if self.symmetric:
            return self
        return sp.Transpose(self)


class RecoveredMatrix(DataMatrix):
    """An intermediate matrix of a recovery (``R``, ``S`` with ``R Sᵀ = I − X Z⁻¹``), computed
    after the solve by a library factorisation; it may appear in recovery formulas, never in an LMI."""


class ScalarVariable(_TaggedScalar):
    """A scalar decision variable."""

    kind = "scalar"


class Param(_TaggedScalar):
    """A scalar parameter: fixed per solve, may be swept without recompiling."""


class DerivedParam(_TaggedScalar):
    """A named scalar defined from parameters; ``definition`` is a sympy expression."""

    definition = _meta_property("definition")


DECISION_TYPES = (Variable, StructuredVariable, ScalarVariable)


def expand_derived(expr: sp.Expr) -> sp.Expr:
    """Replace every derived parameter by its definition (recursively)."""
    derived = [s for s in expr.free_symbols if isinstance(s, DerivedParam)]
    while derived:
        expr = expr.xreplace({d: d.definition for d in derived})
        derived = [s for s in expr.free_symbols if isinstance(s, DerivedParam)]
    return expr


# -- quick mode: numpy arrays written directly in an LMI --------------------------------------
class ConstantMatrix(DataMatrix):
    """Numeric data written directly in an LMI (a numpy array): a data matrix that carries its
    value (``value``, nested lists), so that a theorem built in Python needs no example.  One
    symbol per distinct array (an array equal to the transpose of a known one is that one's
    transpose), so that ``A.T*P + P*A`` prints as ``M_1^T P + P M_1``."""

    value = _meta_property("value")


CONSTANT_TAG = "lmidsl#constant"
_CONSTANTS: dict = {}


def constant_matrix(array) -> sp.MatrixExpr:
    """The :class:`ConstantMatrix` of a real numpy array (a vector is a column)."""
    a = np.asarray(array, dtype=float)
    a = a.reshape(-1, 1) if a.ndim == 1 else a
    if a.ndim != 2 or not np.all(np.isfinite(a)):
        raise TypeError("a constant in an LMI must be a finite real vector or matrix")
    key = (a.shape, a.tobytes())
    if key in _CONSTANTS:
        return _CONSTANTS[key]
    transposed = (a.T.shape, np.ascontiguousarray(a.T).tobytes())
    if transposed in _CONSTANTS:
        return _CONSTANTS[transposed].T
    symbol = ConstantMatrix(f"M{len(_CONSTANTS) + 1}", a.shape[0], a.shape[1], CONSTANT_TAG)
    symbol.value = a.tolist()
    symbol.latex_name = f"M_{{{len(_CONSTANTS) + 1}}}"
    symbol.description = f"constant {a.shape[0]}×{a.shape[1]} matrix"
    _CONSTANTS[key] = symbol
    return symbol


#: what a numpy array that cannot be an LMI constant holds, by dtype kind
_NOT_REAL = {"c": "complex numbers", "O": "Python objects", "U": "strings", "S": "bytes",
             "M": "dates", "m": "time spans", "V": "records"}


def as_symbolic(x):
    """``x``, with a numpy array (of numbers) made a :func:`constant_matrix`; an array of
    anything else (complex, objects, strings) is refused in one line (sympy would say only
    "unsupported operand type(s) for *")."""
    kind = getattr(getattr(x, "dtype", None), "kind", None)
    if type(x).__module__ == "numpy" and kind == "O":
        try:                                   # an object array of real numbers is numbers
            x, kind = x.astype(float), "f"
        except (TypeError, ValueError):
            pass
    if type(x).__module__ == "numpy" and kind in _NOT_REAL:
        hint = (" (a complex system: write the real LMI of [[Re, -Im], [Im, Re]])" if kind == "c" else "")
        raise TheoremDefinitionError(f"a numpy array of {_NOT_REAL[kind]} (dtype {x.dtype}, shape "
                                     f"{x.shape}) in an LMI: a constant must be a real matrix{hint}")
    if type(x).__module__ == "numpy" and getattr(x, "ndim", 0) in (1, 2) and kind in "biuf":
        base = x.base                               # A.T is a view of A: the transpose of A's constant
        if (x.ndim == 2 and type(base).__name__ == "ndarray" and base.ndim == 2 and base.shape == x.shape[::-1]
                and (x == base.T).all() and not (x.shape == base.shape and (x == base).all())):
            return constant_matrix(base).T
        return constant_matrix(x)
    return x


_OPERATORS = {"__add__": ("+", False), "__radd__": ("+", True), "__sub__": ("-", False),
              "__rsub__": ("-", True), "__mul__": ("*", False), "__rmul__": ("*", True),
              "__matmul__": ("@", False), "__rmatmul__": ("@", True)}


def theorem_of(*exprs) -> str:
    """The id of the theorem whose symbols an expression uses ('' for numpy constants alone)."""
    tags = sorted({getattr(s, "tag", "") for e in exprs if isinstance(e, sp.Basic) for s in e.free_symbols}
                  - {"", CONSTANT_TAG})
    return ", ".join(tags)


def shape_slip(op: str, left, right) -> ShapeMismatchError:
    """The one-line error of ``left op right`` with sizes that do not conform (sympy raises its
    ``ShapeError`` when the sizes are numbers): the theorem, both operands and their sizes."""
    product = op in ("*", "@")
    rule = ("a product needs the columns of the left factor to equal the rows of the right"
            if product else "a sum needs equal sizes")
    owner = theorem_of(left, right)
    return ShapeMismatchError(
        f"{owner + ': ' if owner else ''}{'product' if product else 'sum'} {left} {op} {right}: "
        f"{_operand(left)} is {left.shape[0]}×{left.shape[1]} but {_operand(right)} is "
        f"{right.shape[0]}×{right.shape[1]}; {rule} (checked when written, before the LMI is declared)")


def _operand(x) -> str:
    """An operand as the user knows it: a numpy array written in an LMI is 'the numpy constant M1'."""
    base = x.arg if isinstance(x, sp.Transpose) else x
    return f"the numpy constant {x}" if isinstance(base, ConstantMatrix) else str(x)


def _accept_numpy(op: str):
    original = getattr(sp.MatrixExpr, op)
    symbol, reflected = _OPERATORS[op]

    def method(self, other):
        other = as_symbolic(other)
        try:
            return original(self, other)
        except ShapeError:
            left, right = (other, self) if reflected else (self, other)
            raise shape_slip(symbol, left, right) from None
    method.__name__, method.__doc__ = op, original.__doc__
    return method


def _refuse_array(self, *args, **kwargs):
    """numpy converting an lmidsl expression (``A.dot(P)``, ``np.dot(A, P)``): refused in one line."""
    owner = theorem_of(self)
    raise TheoremDefinitionError(
        f"{owner + ': ' if owner else ''}numpy cannot take {self} (an lmidsl matrix expression) as an "
        f"array (A.dot(P), np.dot, np.array): write the product with @, e.g. A.T @ P")


# numpy defers to a matrix expression (``A.T @ P`` with a numpy ``A`` reaches ``P.__rmatmul__``),
# and the expression takes the array as a constant: in sympy such mixed products are errors.
# Sizes that do not conform are one lmidsl error naming the theorem and both operands.
for _op in _OPERATORS:
    setattr(sp.MatrixExpr, _op, _accept_numpy(_op))
sp.MatrixExpr.__array_ufunc__ = None
sp.MatrixExpr.__array__ = _refuse_array
