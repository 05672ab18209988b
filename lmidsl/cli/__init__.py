"""The ``lmidsl`` command line.

Each sub-command lives in its own module ``lmidsl/cli/<name>_cmd.py`` with a ``register``
function that adds its parser and sets ``run``; modules are discovered, so a new command is a
new file.  Every :class:`~lmidsl.errors.LmidslError` becomes one line ``error: ...`` on stderr
and exit code 2; argument errors too.
"""
from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import sys

from ..errors import LmidslError


class OneLineParser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message):
        self.exit(2, f"error: {self.prog}: {message}\n")


def command_modules():
    package = importlib.import_module(__name__)
    names = sorted(m.name for m in pkgutil.iter_modules(package.__path__) if m.name.endswith("_cmd"))
    return [importlib.import_module(f"{__name__}.{name}") for name in names]


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="lmidsl", description="LMI theorems stated once: solve, recover, certify.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser,
                                metavar="COMMAND")
    for module in sorted(command_modules(), key=lambda m: getattr(m, "ORDER", 50)):
        module.register(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code = args.run(args)
    except LmidslError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug, not bad input: say so in one line unless debugging
        if os.environ.get("LMIDSL_DEBUG"):
            raise
        print(f"internal error: {type(exc).__name__}: {exc} (set LMIDSL_DEBUG=1 for the traceback)",
              file=sys.stderr)
        return 3
    return code or 0


if __name__ == "__main__":
    sys.exit(main())
