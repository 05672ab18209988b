"""Studies built on the pipeline: verify, sweeps, scalar searches, BMI by successive LMIs,
cross-checks over backends and solvers, and the reproduction of the papers.  They return data
(result objects with ``as_dict``), never formatted text; :mod:`lmidsl.render` and the CLI print.
"""
