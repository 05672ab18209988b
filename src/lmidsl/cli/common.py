"""Arguments shared by the sub-commands, parsed here and nowhere else: the instance (theorem,
example, data file, overrides), THE common flags of every command that solves
(:func:`add_solve_arguments`: ``--backend``, ``--solver``, ``--solver-option``, ``--margin``,
``--data``, ``--set``, ``--json``, ``--timeout``), the output flags (``--wide``,
``--no-progress``), numbers that must be finite (and positive), and strict JSON in and out.

A command that cannot honour a common flag in some use refuses it with one line
(:func:`refuse`), never ignores it.

JSON read from the user (``--set``, ``--data``, design files) refuses ``NaN`` and ``Infinity``
(Python's ``json`` accepts them by default); JSON written is strict (``allow_nan=False``): a
non-finite number becomes ``null`` and the output says so under ``"notes"``.
"""
from __future__ import annotations

import argparse
import os
import json
import math
import re

from ..errors import InputError
from ..solver.backends import BACKENDS, DEFAULT_BACKEND, choose_backend, options_for, resolve_solver
from ..solver.backends.options import check_solver_options, finite_value, solver_settings
from ..studies.store import strict_json
from ..theorem.limits import MAX_LMIS, MAX_PSD_ROWS, set_limits

#: the flags every solving command accepts (tests/test_cli_output.py checks each command)
COMMON_FLAGS = ("--backend", "--solver", "--solver-option", "--margin", "--data", "--set", "--json",
                "--timeout")


def add_solve_arguments(parser, *, theorem: bool = True, solver_help: str | None = None) -> None:
    """The common flags of a command that solves; ``theorem``: also the theorem id and
    ``--example`` (commands over many theorems, e.g. ``reproduce``, take neither)."""
    if theorem:
        parser.add_argument("theorem", help="theorem id, e.g. wang_l2linf.thm3 (see `lmidsl list`)")
        parser.add_argument("--example", help="a named example of the theorem")
    add_data_arguments(parser)
    parser.add_argument("--backend", choices=list(BACKENDS),
                        help=f"modelling backend ({', '.join(BACKENDS)}; default {DEFAULT_BACKEND}: "
                             "lmidsl's own standard form for Clarabel)")
    parser.add_argument("--solver", help=solver_help or "solver name (default: clarabel on direct and "
                        "cvxpy, cvxopt on picos); any installed SDP solver of the backend")
    parser.add_argument("--solver-option", dest="solver_options", action="append", default=[],
                        metavar="[[BACKEND:]SOLVER:]KEY=VALUE",
                        help="a solver option, VALUE as JSON (e.g. max_iter=50, or clarabel:max_iter=50 "
                             "for one solver only); repeatable")
    parser.add_argument("--margin", type=positive_float, help="strictness margin ε (N <= -ε I); default 1e-7")
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")
    parser.add_argument("--timeout", type=positive_float, metavar="SECONDS",
                        help="stop after this many seconds of wall time (exit 1; a long run keeps "
                             "what it stored with --out)")
    add_limit_arguments(parser)


def add_limit_arguments(parser) -> None:
    """``--max-lmis`` and ``--max-psd-rows``: the largest expansion (an index set's member, a
    Pólya relaxation) accepted before it is built (:mod:`lmidsl.theorem.limits`, :mod:`lmidsl.theorem.budget`)."""
    parser.add_argument("--max-lmis", type=positive_int, metavar="N",
                        help=f"refuse an expansion into more than N LMIs (default {MAX_LMIS:,})")
    parser.add_argument("--max-psd-rows", type=positive_int, metavar="N",
                        help=f"refuse an SDP whose PSD cones have more than N rows (default {MAX_PSD_ROWS:,})")


def apply_limits(args) -> None:
    """The command's ``--max-lmis`` / ``--max-psd-rows`` for the rest of the run."""
    set_limits(getattr(args, "max_lmis", None), getattr(args, "max_psd_rows", None))


def add_output_arguments(parser, *, progress: bool = False) -> None:
    """``--wide`` (tables at full width) and, for long commands, ``--no-progress``."""
    parser.add_argument("--wide", action="store_true",
                        help="print tables at full width (default: fit the terminal, or 100 columns)")
    if progress:
        parser.add_argument("--no-progress", action="store_true",
                            help="no progress (a bar on a terminal, one line per item on stderr off it)")


def show_progress(args) -> bool:
    """Progress unless ``--no-progress`` (it goes to stderr, so ``--json`` keeps it too)."""
    return not getattr(args, "no_progress", False)


def refuse(args, reason: str, *flags: str) -> None:
    """One line for a common flag the command cannot honour here, when it was given."""
    for flag in flags:
        value = getattr(args, flag.lstrip("-").replace("-", "_"), None)
        if flag == "--set":
            value = getattr(args, "overrides", None)
        if flag == "--solver-option":
            value = getattr(args, "solver_options", None)
        if value:
            raise InputError(f"{flag}: {reason}")


def backend_of(args) -> str:
    """``--backend``, else the backend that has ``--solver`` (:func:`~lmidsl.solver.backends.choose_backend`)."""
    return choose_backend(getattr(args, "backend", None), getattr(args, "solver", None))


def add_instance_arguments(parser) -> None:
    """The theorem id, ``--example``, ``--data`` and ``--set`` (commands that bind an instance
    without solving it)."""
    parser.add_argument("theorem", help="theorem id, e.g. wang_l2linf.thm3 (see `lmidsl list`)")
    parser.add_argument("--example", help="a named example of the theorem")
    add_data_arguments(parser)
    add_limit_arguments(parser)


def add_data_arguments(parser) -> None:
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
        resolve_solver(backend_of(args), solver)


def parse_solver_options(items: list[str]) -> dict:
    """``[[backend:]solver:]key=value`` items as ``{"[backend:]solver": {key: value}}``; the
    target ``""`` holds the options for every solver."""
    out: dict = {}
    for item in items:
        left, sep, text = item.partition("=")
        target, _, key = left.rpartition(":")
        if not sep or not key.strip():
            raise InputError(f"--solver-option {item!r}: expected [[BACKEND:]SOLVER:]KEY=VALUE")
        out.setdefault(target.strip().lower(), {})[key.strip()] = option_value(key.strip(), text)
    return out


def option_value(key: str, text: str):
    """An option's VALUE: JSON (finite numbers only), or a bare word (``kktsolver=ldl``) as a string."""
    where = f"--solver-option {key}={text}"
    if BARE_WORD.fullmatch(text) and text not in ("true", "false", "null") and not _is_number(text):
        return text
    try:
        return finite_value(strict_loads(text, where), where)
    except json.JSONDecodeError:
        raise InputError(f"{where}: not JSON (a number, true/false, a quoted string, a list)") from None


def _is_number(text: str) -> bool:
    """Whether Python reads ``text`` as a number (nan, inf, Infinity: never a bare word)."""
    try:
        float(text)
    except ValueError:
        return text.lower() in ("nan", "infinity", "-infinity")
    return True


#: an option value taken as a string without quotes: a word such as ldl or qdldl
BARE_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")



def solver_options(args) -> dict:
    """The ``--solver-option`` values for the one backend and solver this command solves with;
    an option aimed at another solver is a one-line error (it would be silently unused)."""
    parsed = parse_solver_options(getattr(args, "solver_options", []))
    if not parsed:
        return {}
    backend = backend_of(args)
    solver = resolve_solver(backend, getattr(args, "solver", None))
    options = options_for(backend, solver, parsed)
    for target in parsed:
        if target and not options_for(backend, solver, {target: {"hit": True}}):
            raise InputError(f"--solver-option {target}:...: this command solves with {backend}:{solver} only")
    check_solver_options(backend, solver, options)
    return options


def check_options_for_rows(rows, parsed: dict) -> None:
    """``check``'s options against its rows (backend, solver, error): a target that names no row,
    an option that a row's solver states it does not know, or a value of the wrong type is one
    line (exit 2) before any solve; an option for one solver only is written ``SOLVER:KEY=VALUE``."""
    runnable = [(backend, solver) for backend, solver, error in rows if not error]
    for target, options in parsed.items():
        aimed = [(b, s) for b, s in runnable if options_for(b, s, {target: {"hit": True}})]
        if target and not aimed:
            raise InputError(f"--solver-option {target}:...: no row of this check runs {target} (rows: "
                             + ", ".join(f"{b}:{s}" for b, s in runnable) + ")")
        for backend, solver in aimed:
            try:
                check_solver_options(backend, solver, options)
            except InputError as exc:
                hint = "; aim it at one solver with SOLVER:KEY=VALUE" if not target else ""
                raise InputError(f"{exc}{hint}") from None


def solve_arguments(args) -> dict:
    """``solver``, ``backend``, ``margin`` and the solver options, as keyword arguments of
    :func:`lmidsl.pipeline.solve` and the studies."""
    check_solver_argument(args)
    apply_limits(args)
    return {"solver": getattr(args, "solver", None), "backend": backend_of(args),
            "margin": getattr(args, "margin", None), **solver_options(args)}


def instance_spec(args) -> dict:
    """Keyword arguments for :func:`lmidsl.pipeline.make_instance` from parsed arguments (the
    ``--solver`` argument, where the command has one, is checked first)."""
    check_solver_argument(args)
    apply_limits(args)
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


def add_parallel_arguments(parser, default_workers: int | None = None) -> None:
    """``--workers N`` and ``--scheduler ADDRESS``: run the command's independent points on Dask
    (:mod:`lmidsl.studies.parallel`); read back with :func:`parallel_spec`.  ``default_workers``:
    the N used without ``--workers`` (None: serial)."""
    group = parser.add_argument_group("parallel runs (Dask)")
    default = ("default 1: serial, in this process" if default_workers in (None, 1) else
               f"default {default_workers} on this machine; 1: serial, in this process")
    group.add_argument("--workers", type=positive_int, metavar="N",
                       help=f"solve independent points on a local Dask cluster of N processes ({default})")
    parser.set_defaults(default_workers=default_workers)
    group.add_argument("--dashboard", nargs="?", const=":8787", metavar="ADDRESS",
                       help="show the local cluster's Dask dashboard (default address :8787; none "
                            "without this flag)")
    group.add_argument("--scheduler", metavar="ADDRESS",
                       help="solve them on an existing Dask cluster, e.g. tcp://host:8786 "
                            "(started with `dask scheduler` and `dask worker`)")


def parallel_spec(args) -> dict:
    """Keyword arguments ``workers`` and ``scheduler`` from :func:`add_parallel_arguments`."""
    workers = args.workers
    if getattr(args, "dashboard", None):
        os.environ["LMIDSL_DASK_DASHBOARD"] = args.dashboard      # read by the local cluster
    if workers is None and not args.scheduler:          # the command's default N
        workers = getattr(args, "default_workers", None)
    return {"workers": workers, "scheduler": args.scheduler}


def default_local_workers() -> int:
    """Local Dask workers for a long job: the cores this process may use, at most 2 (reproduce's
    rows take 0.1–8 s each; 2 workers: 50 s -> 38 s on 2 cores, docs/performance.md), 1 on one core."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(2, cores))


def process_age() -> float | None:
    """Seconds since this process started (Linux: /proc), or None where that cannot be read."""
    try:
        with open("/proc/self/stat") as f:
            start_ticks = float(f.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return max(uptime - start_ticks / os.sysconf("SC_CLK_TCK"), 0.0)
    except (OSError, ValueError, IndexError):
        return None
