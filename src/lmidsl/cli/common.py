"""Arguments shared by several sub-commands: the instance (example, data file, overrides),
numbers that must be finite (and positive), and strict JSON in and out.

JSON read from the user (``--set``, ``--data``, design files) refuses ``NaN`` and ``Infinity``
(Python's ``json`` accepts them by default); JSON written is strict (``allow_nan=False``): a
non-finite number becomes ``null`` and the output says so under ``"notes"``.
"""
from __future__ import annotations

import argparse
import json
import math

from ..errors import InputError
from ..solver.backends import resolve_solver
from ..studies.store import strict_json


def add_instance_arguments(parser) -> None:
    parser.add_argument("theorem", help="theorem id, e.g. wang_l2linf.thm3 (see `lmidsl list`)")
    parser.add_argument("--example", help="a named example of the theorem")
    parser.add_argument("--data", metavar="FILE.json",
                        help="all data and parameters as one JSON object (matrices as nested lists)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="NAME=VALUE",
                        help="override one parameter or matrix; VALUE is JSON (e.g. rbar=0.6, E=[[1],[0]])")


def parse_overrides(items: list[str]) -> dict:
    out = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or not name:
            raise InputError(f"--set {item!r}: expected NAME=VALUE")
        try:
            out[name.strip()] = strict_loads(text, f"--set {name.strip()}")
        except json.JSONDecodeError:
            raise InputError(f"--set {name}: value {text!r} is not JSON (numbers, or matrices as [[...]])") from None
    return out


def load_data_file(path: str | None) -> dict | None:
    if path is None:
        return None
    try:
        with open(path) as fh:
            data = strict_loads(fh.read(), f"--data {path}")
    except OSError as exc:
        raise InputError(f"--data {path}: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"--data {path}: not a text (UTF-8) file") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"--data {path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(data, dict):
        raise InputError(f"--data {path}: expected a JSON object of names to values")
    return data


def check_solver_argument(args) -> None:
    """An unknown or uninstalled ``--solver`` is a one-line error before any work (saying how to
    install a solver lmidsl knows, e.g. MOSEK)."""
    solver = getattr(args, "solver", None)
    if solver:
        resolve_solver(getattr(args, "backend", None) or "cvxpy", solver)


def instance_spec(args) -> dict:
    """Keyword arguments for :func:`lmidsl.pipeline.make_instance` from parsed arguments (the
    ``--solver`` argument, where the command has one, is checked first)."""
    check_solver_argument(args)
    return {"example": args.example, "data": load_data_file(args.data),
            "overrides": parse_overrides(args.overrides)}


def strict_loads(text: str, what: str):
    """``json.loads`` that refuses NaN and Infinity (one line naming ``what``)."""
    def refuse(constant):
        raise InputError(f"{what}: {constant} is not allowed (finite numbers only)")
    return json.loads(text, parse_constant=refuse)


def _number_argument(text: str, positive: bool, integer: bool, minimum=None):
    kind = ("a positive " if positive else "a finite ") + ("integer" if integer else "number")
    if minimum is not None:
        kind = f"an integer >= {minimum}"
    try:
        value = int(text) if integer else float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}") from None
    if not math.isfinite(value) or (positive and not value > 0) or (minimum is not None and value < minimum):
        raise argparse.ArgumentTypeError(f"expected {kind}, got {text!r}")
    return value


def finite_float(text: str) -> float:
    """argparse type: a finite real number (no nan, inf)."""
    return _number_argument(text, False, False)


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0 (e.g. ``--margin``)."""
    return _number_argument(text, True, False)


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1 (e.g. ``--horizon``, ``--max-points``)."""
    return _number_argument(text, True, True)


def nonnegative_int(text: str) -> int:
    """argparse type: an integer >= 0 (e.g. ``--runs``, ``--seed``)."""
    return _number_argument(text, False, True, minimum=0)


def print_json(obj) -> None:
    print(strict_json(obj))


def probability(text: str) -> float:
    """argparse type: a number strictly between 0 and 1 (e.g. ``--confidence``)."""
    value = _number_argument(text, True, False)
    if not value < 1:
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1), got {text!r}")
    return value


def add_parallel_arguments(parser) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``: run the command's independent points on Dask
    (:mod:`lmidsl.studies.parallel`); read back with :func:`parallel_spec`."""
    group = parser.add_argument_group("parallel runs (Dask)")
    group.add_argument("--workers", type=positive_int, metavar="N",
                       help="solve independent points on a local Dask cluster of N processes "
                            "(default 1: serial, in this process)")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help="solve them on an existing Dask cluster, e.g. tcp://host:8786 "
                            "(started with `dask scheduler` and `dask worker`)")


def parallel_spec(args) -> dict:
    """Keyword arguments ``workers`` and ``scheduler`` from :func:`add_parallel_arguments`."""
    return {"workers": args.workers, "scheduler": args.scheduler}
