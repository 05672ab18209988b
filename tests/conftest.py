import warnings

import pytest


@pytest.fixture(autouse=True)
def _quiet_solver_warnings():
    """cvxpy warns 'Solution may be inaccurate' on boundary optima; the tests check certificates."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Solution may be inaccurate")
        yield
