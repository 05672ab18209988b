"""The solver layer: backends (one registry of backends and solvers), the solution with its status
constants and THE certificate (numpy eigenvalues at the returned point), the strictness-margin
policy, back-off, and the feasp diagnosis.
"""
