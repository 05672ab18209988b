"""The built-in theorems: one package per paper, each exporting ``THEOREMS``.

Installed as ``lmidsl.theorems``; :mod:`lmidsl.theorem.registry` finds them (and user folders on
``LMIDSL_THEOREM_PATH``).  A paper package holds its theorem file (``theorems.py``) and the
paper's own models and simulators, which the core library never imports.
"""
