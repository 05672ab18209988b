"""The symbolic layer: sympy symbols of a theorem, block matrices in the paper's notation, and the
walks over expression trees (shapes, linearity, evaluation share one walker design).

Imports only :mod:`lmidsl.errors` and sympy/numpy.  Uncertainty (interval and norm-bounded) lives
here too: an uncertain quantity is a symbol, and the S-procedure is a rewrite of a block matrix.
"""
