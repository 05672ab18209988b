"""The numeric layer: numbers bound to a theorem (an :class:`~lmidsl.numeric.instance.Instance`),
numpy evaluation of its expressions, the factorisations and the recovery of a
:class:`~lmidsl.numeric.design.Design`, exact signal scaling (apply / undo), LTI helpers.

Imports the symbolic and theorem layers; no backend, no solver.
"""
