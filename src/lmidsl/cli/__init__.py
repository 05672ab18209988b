"""The ``lmidsl`` command line.

Each sub-command lives in its own module ``lmidsl/cli/<name>_cmd.py`` with a ``register``
function that adds its parser and sets ``run``; modules are discovered, so a new command is a
new file.  Only the module of the command being run is imported: the others are listed from
their source (``ORDER`` and the literal ``sub.add_parser(NAME, help=...)``), so that
``lmidsl --help`` and ``lmidsl list`` start without cvxpy, matplotlib or scipy.  Every :class:`~lmidsl.errors.LmidslError` becomes one line ``error: ...`` on stderr
and exit code 2; argument errors too.

Here too, for every command: ``--version``; ``--wide`` (:mod:`lmidsl.render.terminal`);
``--timeout`` (wall time, exit 1); a reader that closes stdout early (``lmidsl list | head -1``)
ends the command quietly with exit 0.
"""
from __future__ import annotations

import _thread
import argparse
import atexit
import ast
import codecs
import contextlib
import errno
import importlib
import json
import os
import signal
import sys
import threading
import unicodedata
import warnings
from pathlib import Path

from ..errors import Interrupted, LmidslError, LmidslWarning, did_you_mean
from ..render.terminal import configure
from ..theorem.index import cache_dir, write_atomically
from ..theorem.registry import load_problems


class OneLineParser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message):
        if message.startswith("unrecognized arguments:"):
            flags = [t for t in message.split(":", 1)[1].split() if t.startswith("-")]
            message += "".join(did_you_mean(f.split("=")[0], self.option_strings_everywhere()) for f in flags)
        self.exit(2, f"error: {self.prog}: {message}\n")

    def option_strings_everywhere(self) -> list:
        """Every option string of this parser and of its sub-commands' parsers."""
        out, parsers = [], [self]
        while parsers:
            parser = parsers.pop()
            for action in parser._actions:
                out += action.option_strings
                if isinstance(action, argparse._SubParsersAction):
                    parsers += list(action.choices.values())
        return sorted(set(out))


class VersionAction(argparse.Action):
    """``--version``: the installed distribution's version (read only when asked)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"lmidsl {package_version()}")
        parser.exit(0)


def package_version() -> str:
    """The version of the installed ``lmidsl`` distribution (importlib.metadata), or the
    package's own ``__version__`` when it runs from a source tree that is not installed."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("lmidsl")
    except PackageNotFoundError:
        return importlib.import_module("lmidsl").__version__


def command_modules():
    """Every command module, imported (each imports what its command needs: slow)."""
    return [importlib.import_module(f"{__name__}.{entry.module}") for entry in command_index()]


class CommandEntry:
    """A command as its module's source states it, read without importing the module."""

    def __init__(self, module: str, name: str | None, help: str | None, order: int):
        self.module, self.name, self.help, self.order = module, name, help, order


def _read_command(path) -> CommandEntry:
    """ORDER and the literal ``sub.add_parser(NAME, help=...)`` of a command module, by ``ast``
    (no import); a module that computes them is imported when the parser is built."""
    name = help_text = None
    order = 50
    try:
        tree = ast.parse(path.read_text())
    except (OSError, SyntaxError, ValueError):
        return CommandEntry(path.stem, None, None, order)
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "ORDER" for t in node.targets) \
                and isinstance(node.value, ast.Constant) and isinstance(node.value.value, int):
            order = node.value.value
        if isinstance(node, ast.FunctionDef) and node.name == "register":
            for call in ast.walk(node):
                if isinstance(call, ast.Call) and getattr(call.func, "attr", None) == "add_parser" \
                        and call.args and isinstance(call.args[0], ast.Constant):
                    name = call.args[0].value
                    keywords = {k.arg: k.value for k in call.keywords}
                    if set(keywords) - {"help"}:
                        name = None           # aliases etc.: import it to be exact
                    elif isinstance(keywords.get("help"), ast.Constant):
                        help_text = keywords["help"].value
                    elif "help" in keywords:
                        name = None
                    break
    return CommandEntry(path.stem, name, help_text, order)


def command_index() -> list[CommandEntry]:
    """The command modules ``<name>_cmd.py`` of this package, in ``ORDER``, read without importing.

    Parsing the eleven modules costs 25 ms a start; the entries are kept in the cache folder
    (``commands.json``) with each file's size and modification time, and read again only when
    one of them changed."""
    folder = Path(__file__).parent
    paths = sorted(folder.glob("*_cmd.py"))
    stamp = [[str(p), st.st_size, st.st_mtime_ns] for p, st in ((p, p.stat()) for p in paths)]
    cache = cache_dir() / "commands.json"
    try:
        data = json.loads(cache.read_text())
        if data["stamp"] == stamp:
            return [CommandEntry(**entry) for entry in data["entries"]]
    except (OSError, ValueError, KeyError, TypeError):
        pass
    entries = sorted((_read_command(path) for path in paths), key=lambda e: e.order)
    write_atomically(cache, json.dumps({"stamp": stamp, "entries": [vars(e) for e in entries]}))
    return entries


def _requested(argv) -> str | None:
    """The sub-command named on the command line (the first word that is not an option)."""
    for word in (sys.argv[1:] if argv is None else argv):
        if not word.startswith("-"):
            return word
    return None


def build_parser(argv=None) -> argparse.ArgumentParser:
    """The parser; only the module of the command being run is imported (``lmidsl --help`` and
    ``lmidsl list`` do not pay for cvxpy, matplotlib or scipy), the others are listed from their
    source (``argv=None``: the process's own arguments)."""
    parser = OneLineParser(prog="lmidsl", description="LMI theorems stated once: solve, recover, certify.")
    parser.add_argument("--version", action=VersionAction, help="print the version of lmidsl and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser,
                                metavar="COMMAND")
    wanted = _requested(argv)
    for entry in command_index():
        if entry.name is None or entry.name == wanted:
            importlib.import_module(f"{__name__}.{entry.module}").register(sub)
        else:
            sub.add_parser(entry.name, help=entry.help)    # listed; never run in this process
    return parser


def _warn_skipped_theorem_files() -> None:
    """One line per user theorem file that failed to load and was skipped (each once)."""
    for problem in load_problems():
        print(f"warning: {problem} (file skipped)", file=sys.stderr)


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    """lmidsl's own warnings as ``warning: <message>`` (one line); a library's (cvxpy's "not
    DPP", "Solution may be inaccurate", Dask's ports) only with ``LMIDSL_DEBUG`` set, as Python
    prints them: what lmidsl reports -- statuses, certificates, its own warnings -- says what
    they would, in the command's words."""
    if issubclass(category, LmidslWarning):
        print(f"warning: {message}", file=sys.stderr)
    elif os.environ.get("LMIDSL_DEBUG"):       # as Python prints it, on stderr as it is now
        print(warnings.formatwarning(message, category, filename, lineno, line),
              file=file or sys.stderr, end="")


class Deadline:
    """``--timeout``: a wall-clock guarantee.  After ``seconds`` the main thread gets SIGALRM,
    whose handler raises KeyboardInterrupt there (so long runs keep what they stored, as after
    Ctrl-C) -- SIGALRM, not SIGINT, whose disposition a caller may have set to "ignore" (a
    command started with ``&`` from a script), which made Ctrl-C's route a no-op.  Should the
    command still run :data:`GRACE` seconds later (the interrupt swallowed by a library, or a
    solver inside C code), the watchdog thread of the ``lmidsl`` process itself ends it: stdout
    flushed, one "timed out" line, exit code 1 (records of ``--out`` stores are on disk as soon
    as they are appended).  A command that finishes after its deadline also exits 1."""

    GRACE = 5.0
    #: end the process from the watchdog (the ``lmidsl`` command; not ``main()`` inside a test)
    hard_exit = False
    #: a deadline of this process has expired (read by :func:`console_main`)
    fired = False

    def __init__(self, seconds: float | None):
        self.seconds, self.expired, self.timer, self.watchdog = seconds, False, None, None
        self._previous = None
        if not seconds:
            return
        self._main = threading.main_thread().ident
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGALRM, self._alarm)
        self.timer = threading.Timer(seconds, self._expire)
        self.timer.daemon = True

    def start(self):
        """Start the clock (inside the ``try`` that handles its interrupt); once."""
        if self.timer is not None and not self.timer.is_alive() and not self.expired:
            self.timer.start()

    @staticmethod
    def _alarm(signum, frame):
        raise KeyboardInterrupt

    def _expire(self):
        self.expired = Deadline.fired = True
        if self.hard_exit:
            self.watchdog = threading.Timer(self.GRACE, self._end_process)
            self.watchdog.daemon = True
            self.watchdog.start()
        if self._previous is not None:
            signal.pthread_kill(self._main, signal.SIGALRM)
        else:
            _thread.interrupt_main()

    def _end_process(self):
        flusher = threading.Thread(target=_flush_quietly, daemon=True)
        flusher.start()
        flusher.join(1.0)           # the main thread may hold stdout's lock: do not wait for ever
        os.write(2, (self.message(f"timed out; still running {self.GRACE:g} s after the deadline, "
                                  "ended") + "\n").encode())
        os._exit(1)

    def cancel(self):
        for timer in (self.timer, self.watchdog):
            if timer is not None:
                timer.cancel()
        if self._previous is not None:
            signal.signal(signal.SIGALRM, self._previous)
            self._previous = None

    def message(self, detail: str = "") -> str:
        return (f"error: --timeout {self.seconds:g}: stopped after {self.seconds:g} s (timed out"
                + (f"; {detail})" if detail else ")"))


def _flush_quietly():
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass


#: ASCII stand-ins for the characters lmidsl prints, when the output's encoding lacks them
_STAND_INS = {"≤": "<=", "≥": ">=", "≠": "!=", "≈": "~", "×": "x", "·": "*", "−": "-", "–": "-",
              "—": "--", "…": "...", "∞": "inf", "±": "+/-", "⋆": "*", "√": "sqrt", "∈": " in ",
              "→": "->", "←": "<-", "‖": "||", "⪯": "<=", "⪰": ">=", "≺": "<", "≻": ">", "ᵀ": "^T",
              "⁻": "^-", "²": "^2", "³": "^3", "¹": "^1", "✓": "ok", "✗": "x", "│": "|", "─": "-",
              "━": "-", "┃": "|", "•": "*", "‘": "'", "’": "'", "“": '"', "”": '"', "°": "deg"}


def _stand_in(ch: str) -> str:
    """One character in ASCII: a stand-in (≤ → <=), a Greek letter's name (γ → gamma), the
    letters of its decomposition (r̄ → r), else '?'."""
    if ch in _STAND_INS:
        return _STAND_INS[ch]
    name = unicodedata.name(ch, "")
    if name.startswith(("GREEK SMALL LETTER ", "GREEK CAPITAL LETTER ")):
        word = name.rsplit(" ", 1)[-1].lower().replace("lamda", "lambda")
        return word.capitalize() if "CAPITAL" in name else word
    plain = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode()
    return plain if plain or unicodedata.combining(ch) else "?"


def _ascii_fallback(exc):
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    return "".join(_stand_in(c) for c in exc.object[exc.start:exc.end]), exc.end


codecs.register_error("lmidsl-ascii", _ascii_fallback)


def fit_streams_to_encoding() -> None:
    """stdout and stderr in an encoding without lmidsl's characters (``PYTHONIOENCODING=ascii``,
    a C locale) print ASCII stand-ins (γ → gamma, ≤ → <=) instead of failing; JSON is ASCII
    already (``\\u`` escapes)."""
    for stream in (sys.stdout, sys.stderr):
        encoding = getattr(stream, "encoding", None)
        if not encoding or not hasattr(stream, "reconfigure"):
            continue
        try:
            "γ≤ᵀ−r̄‖".encode(encoding)
        except UnicodeEncodeError:
            try:
                stream.reconfigure(errors="lmidsl-ascii")
            except (ValueError, OSError):        # a detached or closed stream: left as it is
                pass
        except LookupError:
            pass


def main(argv=None) -> int:
    fit_streams_to_encoding()
    try:
        return _main(argv)
    except BrokenPipeError:
        # the reader of stdout went away (`lmidsl list | head -1`): not an error of the command;
        # stdout goes to /dev/null so that the interpreter's final flush does not fail again
        _to_devnull(sys.stdout.fileno())
        return 0


def console_main() -> None:
    """The ``lmidsl`` command: :func:`main`, then leave without tearing the interpreter down.

    Freeing the million objects of sympy's and the theorems' caches one by one at exit took 0.1 s
    of a 1.5 s ``solve``.  The non-daemon threads are waited for, output is flushed and the
    ``atexit`` handlers (logging, temporary directories, Dask) run first, as at a normal exit; the
    normal exit is kept only under a profiler or a tracer (``python -m cProfile``, coverage), which
    write their results there.  ``main(argv)`` itself returns, for tests and embedding."""
    Deadline.hard_exit = True
    try:
        code = main()
    except KeyboardInterrupt:
        # an interrupt after the command handled its own (a late signal during clean-up, a second
        # Ctrl-C): the exit code still says what happened, never death by SIGINT (Python's exit
        # for an unhandled KeyboardInterrupt); a deadline has printed its line already
        if not Deadline.fired:
            print("error: interrupted", file=sys.stderr)
        code = 1 if Deadline.fired else 130
    signal.signal(signal.SIGINT, signal.SIG_IGN)      # the exit code is decided: Ctrl-C ends nothing more
    if not _background_work_ended():
        _leave(code)
    if sys.getprofile() is not None or sys.gettrace() is not None:
        sys.exit(code)
    # never the interpreter's normal exit: `reproduce --timeout 0.5`, its exit code 1 decided and
    # SIGINT ignored, still died of SIGINT (−2) 5 runs in 25 at load 4 when Dask's threads sent it
    # that way — CPython's exit re-raises SIGINT itself (exit_sigint) once it has recorded a
    # KeyboardInterrupt as unhandled, the deadline's, handled long since; 0 in 30 runs through
    # os._exit.  The non-daemon threads are waited for here, as that exit would.
    for thread in threading.enumerate():
        if thread is not threading.current_thread() and not thread.daemon:
            thread.join()
    _leave(code)


def _background_work_ended() -> bool:
    """Cancel the proved bound's workers a command left (an interrupt, a deadline) and wait
    for the shifted solve in flight at most :data:`Deadline.GRACE` seconds; whether they ended.
    (A worker inside Clarabel must not meet the interpreter's exit:
    :class:`lmidsl.certify.dual_bound.PendingBound`.)"""
    dual_bound = sys.modules.get("lmidsl.certify.dual_bound")     # not imported: nothing pending
    if dual_bound is None:
        return True
    try:
        return dual_bound.cancel_pending(wait=Deadline.GRACE)
    except KeyboardInterrupt:          # a second Ctrl-C: leave now
        return False


def _leave(code: int) -> None:
    """Flush, run the ``atexit`` handlers and end the process with ``code`` at once (no thread
    is unwound: one still in native code simply stops)."""
    _flush_quietly()
    atexit._run_exitfuncs()
    os._exit(code)


def _early_timeout(argv) -> float | None:
    """``--timeout SECONDS`` read from the raw arguments, before the parser (and the command's
    imports: cvxpy, Dask) run, so that the clock covers start-up too; None when absent or not a
    positive finite number (the parser then says so)."""
    words = list(sys.argv[1:] if argv is None else argv)
    for i, word in enumerate(words):
        text = word.partition("=")[2] if word.startswith("--timeout=") else \
            (words[i + 1] if word == "--timeout" and i + 1 < len(words) else None)
        if text is not None:
            try:
                value = float(text)
            except ValueError:
                return None
            return value if 0 < value < float("inf") else None
    return None


def _main(argv=None) -> int:
    deadline = Deadline(_early_timeout(argv))
    try:
        deadline.start()
        parser = build_parser(argv)
        args = parser.parse_args(argv)
    except KeyboardInterrupt:              # the deadline during start-up (or Ctrl-C)
        deadline.cancel()
        print(deadline.message("during start-up") if deadline.expired else "error: interrupted", file=sys.stderr)
        return 1 if deadline.expired else 130
    except BaseException:                  # argparse's exit: no clock left running
        deadline.cancel()
        raise
    configure(wide=getattr(args, "wide", False))
    with warnings.catch_warnings():
        warnings.showwarning = _one_line_warning
        return _run(args, deadline)


def _run(args, deadline=None) -> int:
    if deadline is None or deadline.seconds != getattr(args, "timeout", None):
        if deadline is not None:
            deadline.cancel()
        deadline = Deadline(getattr(args, "timeout", None))
    try:
        return _run_command(args, deadline)
    finally:                          # whatever ended the command, no clock is left running
        deadline.cancel()


@contextlib.contextmanager
def native_output_to_stderr():
    """File descriptor 1 is stderr for the block, so that what C libraries print (SCS's "KKT
    matrix has < n positive eigenvalues", a solver's banner) cannot mix with lmidsl's output;
    Python's ``sys.stdout`` goes on writing to the real stdout (a stream on a saved copy of
    descriptor 1 when it wrote there).  Used whenever ``--json`` is asked: stdout is one JSON
    object and nothing else."""
    try:
        sys.stdout.flush()
        uses_fd1 = sys.stdout.fileno() == 1
    except (AttributeError, OSError, ValueError):     # a stream with no descriptor (a test's capture)
        uses_fd1 = False
    try:
        saved = os.dup(1)
    except OSError:                                   # no descriptor 1 at all: nothing to keep apart
        yield
        return
    original = sys.stdout
    if uses_fd1:
        sys.stdout = open(saved, "w", encoding=original.encoding, errors=original.errors, closefd=False,
                          buffering=1 if getattr(original, "line_buffering", False) else -1)
    os.dup2(2, 1)
    try:
        yield
    finally:
        try:
            if uses_fd1:
                sys.stdout.flush()
        except OSError:                  # a reader gone: what is left goes nowhere, quietly
            _to_devnull(saved)
            raise
        finally:
            sys.stdout = original
            os.dup2(saved, 1)
            os.close(saved)


def _to_devnull(fd: int) -> None:
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, fd)
    os.close(devnull)


def _run_command(args, deadline) -> int:
    if getattr(args, "json", False):
        with native_output_to_stderr():
            return _run_command_here(args, deadline)
    return _run_command_here(args, deadline)


def _run_command_here(args, deadline) -> int:
    try:
        deadline.start()
        code = args.run(args)
        deadline.cancel()
        sys.stdout.flush()            # a closed pipe shows here, not at the interpreter's exit
        _warn_skipped_theorem_files()
        if deadline.expired:          # finished, but after its deadline (the interrupt came too late)
            print(deadline.message("finished after the deadline"), file=sys.stderr)
            return 1
    except BrokenPipeError:
        raise
    except Interrupted as exc:
        deadline.cancel()
        print(deadline.message(str(exc)) if deadline.expired else f"error: {exc}", file=sys.stderr)
        return 1 if deadline.expired else exc.exit_code
    except LmidslError as exc:
        deadline.cancel()
        _warn_skipped_theorem_files()
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except OSError as exc:
        if exc.errno not in UNWRITABLE:
            return _internal_error(exc)
        deadline.cancel()
        where = f" {exc.filename}" if exc.filename else ""
        print(f"error: cannot write{where}: {exc.strerror} (the command could not finish; files "
              f"already written are kept)", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        deadline.cancel()
        print(deadline.message() if deadline.expired else "error: interrupted", file=sys.stderr)
        return 1 if deadline.expired else 130
    except Exception as exc:  # a bug, not bad input: say so in one line unless debugging
        if deadline.expired:  # the deadline's interrupt, turned into another error by a library
            deadline.cancel()  # (numpy's import makes an ImportError of it): it timed out
            print(deadline.message(), file=sys.stderr)
            return 1
        return _internal_error(exc)
    return code or 0


#: errors of writing an output that are the machine's, not lmidsl's: a full disk or quota, a
#: read-only file system, no permission, an I/O error (exit 1: the command could not finish)
UNWRITABLE = frozenset({errno.ENOSPC, errno.EROFS, errno.EACCES, errno.EPERM, errno.EDQUOT, errno.EIO,
                        errno.EFBIG})


def _internal_error(exc) -> int:
    if os.environ.get("LMIDSL_DEBUG"):
        raise exc
    print(f"internal error: {type(exc).__name__}: {exc} (set LMIDSL_DEBUG=1 for the traceback)",
          file=sys.stderr)
    return 3


if __name__ == "__main__":
    console_main()
