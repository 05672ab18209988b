"""Shared helpers: run the command line in-process or as a real subprocess."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# lmidsl's caches (theorem index, built theorems) in a folder of the test runs, not the user's:
# the tests' temporary theorem files would leave entries there (subprocesses inherit it)
os.environ.setdefault("LMIDSL_CACHE_DIR", os.path.join(tempfile.gettempdir(), "lmidsl-tests-cache"))


def load_theorem_module(stem: str, alias: str | None = None):
    """The theorem file of the built-in paper package ``<stem>`` (to reach its helper functions)."""
    import importlib
    return importlib.import_module(f"lmidsl.theorems.{stem}.theorems")


#: environment variables :func:`run_cli` may set for a command run in this process (read at each
#: call, never cached by lmidsl)
IN_PROCESS_ENV = frozenset({"COLUMNS"})


def run_cli(*argv, env=None, cwd=None, process=False):
    """``lmidsl ARGV``: (exit code, stdout, stderr).  In this process (:func:`run_cli_here`) unless
    the test is about the process -- ``process=True``, a ``cwd``, or an ``env`` beyond
    :data:`IN_PROCESS_ENV` (a theorem path, a cache folder: read once per process) -- then in a
    subprocess (:func:`run_cli_process`).  A new interpreter costs ~1.5 s of CPU (sympy, the
    solving stack, the theorems read again) for the same exit code and the same two streams."""
    if process or cwd is not None or set(env or ()) - IN_PROCESS_ENV:
        return run_cli_process(*argv, env=env, cwd=cwd)
    return run_cli_here(*argv, env=env)


def run_cli_here(*argv, env=None):
    """``lmidsl.cli.main(ARGV)`` in this process, stdout and stderr captured (argparse's exit
    included): what ``python -m lmidsl ARGV`` prints and returns, less a new interpreter."""
    import contextlib
    import contextvars
    import io
    from unittest import mock

    from lmidsl.cli import main

    import signal

    out, err = io.StringIO(), io.StringIO()
    # a command leaves this process as it found it: its signal dispositions too (a SIGINT left
    # ignored here is inherited by every later subprocess, whose Ctrl-C then does nothing)
    handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGALRM)}
    with mock.patch.dict(os.environ, env or {}), contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        os.environ.pop("LMIDSL_DEBUG", None)        # restored with the environment
        try:
            # in a copy of this context: what a command sets for its process (the expansion
            # limits of --max-lmis, a ContextVar) ends with it
            code = contextvars.copy_context().run(main, list(argv))
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        finally:
            for sig, handler in handlers.items():
                if signal.getsignal(sig) is not handler and handler is not None:
                    signal.signal(sig, handler)
    return code, out.getvalue(), err.getvalue()


def run_cli_process(*argv, env=None, cwd=None):
    """Run ``python -m lmidsl ARGV`` (the installed package) in a subprocess; returns (exit code, stdout, stderr)."""
    full_env = dict(os.environ)
    full_env.pop("LMIDSL_DEBUG", None)
    if env:
        full_env.update(env)
    proc = subprocess.run([sys.executable, "-m", "lmidsl", *argv], capture_output=True, text=True,
                          env=full_env, cwd=cwd or ROOT, timeout=600)
    return proc.returncode, proc.stdout, proc.stderr


def run_cli_json(*argv, **kw):
    code, out, err = run_cli(*argv, "--json", **kw)
    assert code == 0, err
    return json.loads(out)


@pytest.fixture
def cli():
    return run_cli



# -- the slow tests a default run leaves out (pyproject's addopts: -m 'not slow') --------------
# counted where tests are collected (each xdist worker collects them all) and handed to the
# process that prints the summary through xdist's workeroutput
def _markexpr_leaves_out_slow(config) -> bool:
    """Does ``-m`` deselect a test marked slow (and nothing else)?"""
    markexpr = config.getoption("markexpr", "") or ""
    if not markexpr:
        return False
    try:
        from _pytest.mark.expression import Expression
        return not Expression.compile(markexpr).evaluate(lambda name: name == "slow")
    except Exception:  # noqa: BLE001  (another pytest: the plain reading)
        return markexpr.strip() == "not slow"


def pytest_deselected(items):
    if items and _markexpr_leaves_out_slow(items[0].config):
        config = items[0].config
        config._lmidsl_slow_left_out = getattr(config, "_lmidsl_slow_left_out", 0) + sum(
            1 for item in items if item.get_closest_marker("slow") is not None)


def pytest_sessionfinish(session):
    if hasattr(session.config, "workeroutput"):
        session.config.workeroutput["slow_left_out"] = getattr(session.config, "_lmidsl_slow_left_out", 0)


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    count = getattr(node, "workeroutput", {}).get("slow_left_out", 0)
    node.config._lmidsl_slow_left_out = max(getattr(node.config, "_lmidsl_slow_left_out", 0), count)


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """Say how many slow tests the run left out and how to run them."""
    count = getattr(config, "_lmidsl_slow_left_out", 0)
    if count:
        terminalreporter.write_line(
            f"{count} slow test(s) not run (-m 'not slow', pyproject's default); run them with "
            f"`python -m pytest -m slow`, or everything with `python -m pytest -m ''`")
