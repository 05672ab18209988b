"""Errors that reach the user as one line.

Every error lmidsl raises on purpose derives from :class:`LmidslError`.  Its message is a
single line that names the theorem, the LMI and the block (i, j) or the argument at fault;
the command line prints it as ``error: <message>`` and exits with its ``exit_code``: 2 for bad
input, 1 for a computation that ran but has no result to give (e.g. an infeasible synthesis has
no design to simulate), 3 for proofs that contradict each other (an internal error).
"""
import difflib


class LmidslError(Exception):
    """A user-facing error whose message is one line."""

    exit_code = 2

    def __init__(self, message: str):
        super().__init__(" ".join(str(message).split()))


class TheoremDefinitionError(LmidslError):
    """A theorem file states something that is not a well-formed LMI problem."""


class ShapeMismatchError(LmidslError):
    """Data or blocks whose shapes do not conform."""


class NonlinearityError(TheoremDefinitionError):
    """An LMI block that is not affine in the decision variables."""


class InputError(LmidslError):
    """Bad user input: unknown names, bad values, malformed files."""


class SolverUnavailableError(LmidslError):
    """The requested backend or solver is not installed or not supported."""


class NoResultError(LmidslError):
    """The computation ran, but its verdict leaves nothing to give (infeasible, not solved)."""

    exit_code = 1


class ProofConflict(LmidslError):
    """Two proofs about the same problem contradict each other (a proved lower end above a proved
    upper end): a bug in lmidsl, never a certificate.  Exit 3, like any internal error."""

    exit_code = 3


class Interrupted(LmidslError):
    """A long run stopped by the user (Ctrl-C); the message says where the finished work is."""

    exit_code = 130


class LmidslWarning(UserWarning):
    """Something the user should know that does not stop the computation; the command line
    prints it as one line ``warning: <message>`` on stderr."""


class UnusedDataWarning(LmidslWarning):
    """A data file has entries the theorem does not use (one plant file serving several
    theorems): they are ignored."""


def did_you_mean(name: str, choices) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``choices`` to a mistyped ``name`` (difflib's
    ratio ≥ 0.6, up to three), else ''."""
    near = difflib.get_close_matches(str(name), [str(c) for c in choices], n=3)
    if not near:
        return ""
    return " (did you mean " + " or ".join(repr(n) for n in near) + "?)"
