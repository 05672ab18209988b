"""Declared structure of a coefficient matrix (``Pi[i, j]``): the check, its tolerance, and the
declared completion of the diagonal.

* ``"generator"`` — a transition-rate matrix: π_ij ≥ 0 for j ≠ i and every row sums to 0;
* ``"stochastic"`` — a transition-probability matrix: p_ij ≥ 0 and every row sums to 1;
* ``"nonnegative"`` — every entry ≥ 0.

A row sum is accepted within :func:`row_tolerance` = 1e-9·max(1, max|M_ij|) (the rounding of
numbers typed in full); an error names the row, its sum and that tolerance.  Most Markov jump
papers print only the off-diagonal rates and let the diagonal complete the row,
π_ii = −Σ_{j≠i} π_ij (p_ii = 1 − Σ_{j≠i} p_ij): declared in the theorem
(``thm.coefficients(..., structure="generator", diagonal="complete")``) or given with the data
(``"Pi": {"matrix": [[...]], "diagonal": "complete"}``), the diagonal entries given are replaced by
the completion (the off-diagonal entries are never changed, no number is changed without that
declaration, and a diagonal entry that changes is reported: an :class:`~lmidsl.errors.LmidslWarning`,
one line on the command line).
"""
from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError, LmidslWarning, TheoremDefinitionError

STRUCTURES = ("generator", "stochastic", "nonnegative", None)
DIAGONALS = ("given", "complete")
_ROW_SUM = {"generator": 0.0, "stochastic": 1.0}
_NAMES = {"generator": "a transition-rate generator", "stochastic": "a stochastic matrix"}


def check_declaration(where: str, structure, diagonal) -> None:
    """Refuse an unknown structure, or a completed diagonal without row sums to complete."""
    if structure not in STRUCTURES:
        raise TheoremDefinitionError(f"{where}: structure must be one of {', '.join(map(str, STRUCTURES))}")
    if diagonal not in DIAGONALS:
        raise TheoremDefinitionError(f"{where}: diagonal must be one of {', '.join(DIAGONALS)}")
    if diagonal == "complete" and structure not in _ROW_SUM:
        raise TheoremDefinitionError(f"{where}: diagonal='complete' needs structure 'generator' or "
                                     f"'stochastic' (rows with a prescribed sum)")


def split_value(value, where: str):
    """``(matrix, diagonal option or None)`` from a datum given as a matrix or as
    ``{"matrix": [[...]], "diagonal": "complete"}``."""
    if not isinstance(value, dict):
        return value, None
    extra = set(value) - {"matrix", "diagonal"}
    if "matrix" not in value or extra:
        raise InputError(f"{where}: give a matrix, or {{\"matrix\": [[...]], \"diagonal\": \"complete\"}}")
    option = value.get("diagonal", "given")
    if option not in DIAGONALS:
        raise InputError(f"{where}: diagonal must be one of {', '.join(DIAGONALS)}, not {option!r}")
    return value["matrix"], option


def row_tolerance(M: np.ndarray) -> float:
    """The accepted deviation of a row sum: 1e-9·max(1, max|M_ij|)."""
    return 1e-9 * max(1.0, float(np.abs(M).max()) if M.size else 1.0)


def complete_diagonal(M: np.ndarray, structure: str) -> np.ndarray:
    """M with M_ii = s − Σ_{j≠i} M_ij (s = 0 for a generator, 1 for a stochastic matrix)."""
    out = np.array(M, dtype=float)
    off = out.sum(axis=1) - np.diag(out)
    np.fill_diagonal(out, _ROW_SUM[structure] - off)
    return out


def check_structure(M: np.ndarray, structure, diagonal: str, where: str) -> np.ndarray:
    """The matrix to use: completed when declared, then checked; errors name the entry or the
    row (1-based), the value and the tolerance, and the fix when a row sum is off."""
    if diagonal == "complete":
        given, M = M, complete_diagonal(M, structure)
        change = np.abs(np.diag(M) - np.diag(given))
        if change.max(initial=0.0) > row_tolerance(M):      # said, never silent
            i = int(change.argmax())
            warnings.warn(LmidslWarning(
                f"{where}: the diagonal completes each row (declared): {int((change > 0).sum())} diagonal "
                f"entries replaced, the largest change at ({i + 1}, {i + 1}): {given[i, i]:.6g} -> {M[i, i]:.6g}"),
                stacklevel=2)
    if structure is None:
        return M
    n = M.shape[0]
    if structure == "nonnegative" or structure == "stochastic":
        bad = np.argwhere(M < 0)
        if len(bad):
            i, j = bad[0]
            raise InputError(f"{where} must be {_NAMES.get(structure, 'nonnegative')}: entry ({i + 1}, {j + 1}) "
                             f"is {M[i, j]:g} < 0")
    if structure == "generator":
        off = ~np.eye(n, dtype=bool)
        bad = np.argwhere((M < 0) & off)
        if len(bad):
            i, j = bad[0]
            raise InputError(f"{where} must be a transition-rate generator: the off-diagonal entry "
                             f"({i + 1}, {j + 1}) is {M[i, j]:g} < 0")
    if structure in _ROW_SUM:
        target = _ROW_SUM[structure]
        deviation = M.sum(axis=1) - target
        tol = row_tolerance(M)
        row = int(np.abs(deviation).argmax())
        if abs(deviation[row]) > tol:
            raise InputError(f"{where} must be {_NAMES[structure]}: row {row + 1} sums to "
                             f"{M[row].sum():.6g}, not {target:g} (tolerance {tol:.1g}); if the diagonal "
                             f"completes each row, declare diagonal=\"complete\" in the theorem or give "
                             f"the data as {{\"matrix\": [[...]], \"diagonal\": \"complete\"}}")
    return M


__all__ = ["STRUCTURES", "DIAGONALS", "check_declaration", "split_value", "row_tolerance",
           "complete_diagonal", "check_structure"]
