"""The theorem layer: the statement of a theorem as data (value types, :class:`Theorem`,
families of theorems indexed by an integer) and the registry that finds theorem files.

Imports the symbolic layer; knows nothing of numbers, backends or solvers.
"""
