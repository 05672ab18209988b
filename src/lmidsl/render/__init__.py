"""Rendering: LaTeX of the LMIs and of a whole theorem document, and plain-text tables and reports.

Printing never solves: a document of solved numbers takes a :class:`~lmidsl.solver.solution.Solution`.
"""
