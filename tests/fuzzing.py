"""Random theorems for the fuzz tests of the builder and the compiler (tests/test_fuzz.py and
benchmarks/fuzz.py).

:func:`random_case` declares a theorem with random dimensions (symbols and integers), data,
variables of every kind (full, symmetric, diagonal, scalar), parameters and derived scalars,
and one or two LMIs of random block structure whose blocks are random conforming expressions
(products, transposes, inverses and powers of data, ``He``, parameters times terms, zero
blocks); now and then something a theorem must refuse (a product of two variables, a bad
shape, a non-finite datum).  :func:`run_case` binds it, compiles it with a backend (cvxpy or direct),
assigns random values to the variables and compares every assembled LMI matrix with numpy's
evaluation of the same block matrix.  The outcome is 'same', 'refused' (an
:class:`~lmidsl.errors.LmidslError` with a one-line message), 'mismatch' or 'crash'.
"""
from __future__ import annotations

import traceback

import numpy as np
import sympy as sp

from lmidsl import He, Source, Theorem
from lmidsl.errors import LmidslError
from lmidsl.numeric.evaluate import NumericEvaluator, evaluate_block_matrix
from lmidsl.numeric.instance import bind, random_point
from lmidsl.solver.backends import get_backend


class Case:
    """A random theorem, its inputs, and how it was built (for the report of a failure)."""

    def __init__(self, seed: int):
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.thm = Theorem(f"fuzz.c{seed}", "fuzz case", Source("fuzz", "(1)"))
        self.inputs: dict = {}
        self.sizes: dict = {}        # token -> int
        self.counter = 0
        self.square_vars: dict = {}  # token -> [symmetric variables]

    # -- tokens of size: dimension symbols or integers ------------------------------------
    def token(self):
        return self.tokens[int(self.rng.integers(len(self.tokens)))]

    def size(self, token) -> int:
        return token if isinstance(token, int) else self.sizes[token]

    def name(self, prefix: str) -> str:
        self.counter += 1
        return f"{prefix}{self.counter}"

    # -- leaves -----------------------------------------------------------------------------
    def data(self, r, c, symmetric=False):
        name = self.name("D")
        D = self.thm.data(name, r, c, symmetric=symmetric and r == c)
        value = self.rng.standard_normal((self.size(r), self.size(c)))
        if symmetric and r == c:
            value = value + value.T
        if r == c:
            value = value + 3 * np.eye(self.size(r))       # comfortably invertible
        u = self.rng.random()
        if u < 0.01:                                          # a datum that must be refused
            value = value.tolist()
            value[0][0] = [float("nan"), True, "1"][int(self.rng.integers(3))]
        elif u < 0.015:                                       # of the wrong shape
            value = self.rng.standard_normal((self.size(r) + 1, self.size(c)))
        elif u < 0.02 and r == c:                             # singular (refused if inverted)
            value = np.zeros((self.size(r), self.size(c)))
        self.inputs[name] = value.tolist() if isinstance(value, np.ndarray) else value
        return D

    def variable(self, r, c):
        kind = "full"
        if r == c:
            kind = ["full", "symmetric", "diagonal"][int(self.rng.integers(3))]
        return self.thm.var(self.name("X"), r, c, kind=kind)

    def symmetric_var(self, r):
        P = self.thm.var(self.name("P"), r, kind=["symmetric", "diagonal"][int(self.rng.integers(2))])
        return P

    def scalar_coefficient(self):
        """A parameter, a derived scalar, a number or a scalar variable (linear) or 1."""
        pick = int(self.rng.integers(5))
        if pick == 0 and self.params:
            return self.params[int(self.rng.integers(len(self.params)))]
        if pick == 1 and self.derived:
            return self.derived[int(self.rng.integers(len(self.derived)))]
        if pick == 2:
            return sp.Rational(int(self.rng.integers(-3, 4)) or 1, int(self.rng.integers(1, 4)))
        return sp.Integer(1)

    # -- terms of a given shape -------------------------------------------------------------
    def term(self, r, c, depth=0, decision=True):
        """A random expression of shape r × c, affine in the variables when ``decision``."""
        choices = ["data", "var", "product", "scaled", "transpose", "sum"]
        if r == c:
            choices += ["inverse", "power", "identity"]
        if depth >= 2:
            choices = ["data", "var"] + (["identity"] if r == c else [])
        pick = choices[int(self.rng.integers(len(choices)))]
        if pick == "data" or (pick == "var" and not decision):
            return self.data(r, c)
        if pick == "var":
            if self.rng.random() < 0.3 and self.scalars:
                s = self.scalars[int(self.rng.integers(len(self.scalars)))]
                return s * self.data(r, c)
            return self.variable(r, c)
        if pick == "product":
            k = self.token()
            if self.rng.random() < 0.02 and decision:             # nonlinear: must be refused
                return self.variable(r, k) * self.variable(k, c)
            left_has = decision and self.rng.random() < 0.5
            return self.term(r, k, depth + 1, left_has) * self.term(k, c, depth + 1, decision and not left_has)
        if pick == "scaled":
            return self.scalar_coefficient() * self.term(r, c, depth + 1, decision)
        if pick == "transpose":
            return self.term(c, r, depth + 1, decision).T
        if pick == "sum":
            return self.term(r, c, depth + 1, decision) + self.term(r, c, depth + 1, decision)
        if pick == "inverse":
            return self.data(r, r).I
        if pick == "power":
            D = self.data(r, r)
            return [D ** 2, D.I * D.I, D * D.I * D][int(self.rng.integers(3))]
        return sp.Identity(r) if not isinstance(r, int) else sp.Identity(r)

    def diagonal_block(self, r):
        pick = int(self.rng.integers(5))
        if pick == 0:
            return -self.symmetric_var(r)
        if pick == 1:
            k = self.token()
            D = self.data(k, r)
            P = self.symmetric_var(k)
            return D.T * P * D - self.symmetric_var(r)
        if pick == 2:
            return He(self.term(r, r))
        if pick == 3:
            return self.scalar_coefficient() * self.symmetric_var(r) + self.data(r, r, symmetric=True)
        t = self.term(r, r)
        return t + t.T

    def off_block(self, r, c):
        if self.rng.random() < 0.2:
            return 0
        return self.term(r, c)


def random_case(seed: int) -> Case:
    case = Case(seed)
    rng = case.rng
    thm = case.thm
    ndims = int(rng.integers(1, 4))
    dims = [thm.dim(f"n{i}") for i in range(ndims)]
    for d in dims:
        case.sizes[d] = int(rng.integers(1, 4))
        case.inputs[str(d)] = case.sizes[d]        # given, so that no datum must fix it
    case.tokens = dims + [int(v) for v in rng.integers(1, 4, size=int(rng.integers(0, 2)))]
    case.params = [thm.param(f"p{i}", domain=(0.0, 1.0)) for i in range(int(rng.integers(0, 3)))]
    for p in case.params:
        case.inputs[str(p)] = float(rng.uniform(0.1, 0.9))
    case.derived = []
    if case.params and rng.random() < 0.5:
        p = case.params[0]
        case.derived.append(thm.derived("a0", (1 - p) * p))
    case.scalars = [thm.scalar(f"s{i}") for i in range(int(rng.integers(0, 2)))]
    for label in ["(1)", "(2)"][: int(rng.integers(1, 3))]:
        sizes = [case.token() for _ in range(int(rng.integers(1, 4)))]
        rows = [[case.off_block(sizes[i], sizes[j]) for j in range(i)] + [case.diagonal_block(sizes[i])]
                for i in range(len(sizes))]
        sense = "<" if rng.random() < 0.7 else ">"
        thm.lmi(label, rows, sense=sense, sizes=sizes if rng.random() < 0.3 else None)
    return case


def run_case(seed: int, backend: str = "cvxpy") -> tuple[str, str]:
    """('same' | 'refused' | 'mismatch' | 'crash', detail) of one random theorem compiled by ``backend``."""
    try:
        case = random_case(seed)
        instance = bind(case.thm, case.inputs)
        model = get_backend(backend)(instance)
        values = random_point(instance, np.random.default_rng(seed + 1))
        model.assign(values)
        compiled = model.lmi_values()
        for lmi in instance.theorem.lmis:
            keys = [k for k in compiled if k[0] == lmi.label]
            assert len(keys) == 1, keys
            expected = evaluate_block_matrix(NumericEvaluator(instance.dims, values, instance.params),
                                             lmi.negative_form())
            got = compiled[keys[0]]
            scale = max(1.0, float(np.max(np.abs(expected))))
            if got.shape != expected.shape or not np.allclose(got, expected, rtol=1e-9, atol=1e-9 * scale):
                diff = float(np.max(np.abs(got - expected))) if got.shape == expected.shape else "shape"
                return "mismatch", f"seed {seed}: LMI {lmi.label} differs by {diff}"
        return "same", ""
    except LmidslError as exc:
        message = str(exc)
        if "\n" in message or not message.strip():
            return "crash", f"seed {seed}: LmidslError message not one line: {message!r}"
        return "refused", message
    except Exception as exc:       # anything else is a crash of the library
        return "crash", f"seed {seed}: {type(exc).__name__}: {exc}\n{traceback.format_exc()}"
