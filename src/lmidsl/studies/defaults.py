"""What the command line shows of the studies before a study is imported: the defaults and
choices of their flags, and the parameter grid of sweeps and searches (numpy only).  A command
checks its theorem id and its grid with these, so an unknown theorem or a bad grid is answered
without the solving stack; the studies read the same values from here."""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

DEFAULT_TOLERANCE = 1e-3
"""``check``: the relative tolerance on the compared value among trusted rows."""
FIRST_ORDER_CAP = 3.0
"""``check``: a first-order row's default time limit, as a multiple of the interior-point rows' median time."""
OBJECTIVES = ("gamma", "tmin")
"""``search``: what is minimised over the scalars (the level, or the feasp t*)."""
FORMATS = ("sdpa", "cbf", "json")
"""``export``: the file formats."""
#: ``export --check``: the file's optimum and lmidsl's (the same SDP, the same margin) agree within
#: this (relative): Clarabel's reduced duality-gap tolerance 5e-5 on each side of a solve that ends
#: "inaccurate", and primal residuals of 1e-8 times duals of ~1e3–1e4 on the random H∞ filter
#: plants (textbook.hinf_filter_dt: 5.703912 from the file, 5.703574 from the direct backend,
#: both "optimal")
OPTIMUM_RTOL = 1e-4

#: the largest grid a sweep runs unless told otherwise (``--max-points``)
MAX_POINTS = 100_000


def parse_grid(text: str, max_points: int = MAX_POINTS) -> tuple[str, list[float]]:
    """'xi1=0.05:0.95:19' (start:stop:count, inclusive) or 'xi1=0.1,0.5,0.9' → (name, values);
    finite numbers only, at most ``max_points`` values."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name or not spec:
        raise InputError(f"--grid {text!r}: expected NAME=START:STOP:COUNT or NAME=V1,V2,...")
    try:
        if ":" in spec:
            start, stop, count = spec.split(":")
            count = int(count)
            if count < 1:
                raise ValueError
            ends = [float(start), float(stop)]
            if not all(math.isfinite(v) for v in ends):
                raise InputError(f"--grid {text!r}: START and STOP must be finite numbers")
            if count > max_points:
                raise InputError(f"--grid {text!r}: {count} points exceed the maximum of {max_points} "
                                 f"(raise it with --max-points)")
            values = np.linspace(ends[0], ends[1], count).tolist()
        else:
            values = [float(v) for v in spec.split(",")]
            if not all(math.isfinite(v) for v in values):
                raise InputError(f"--grid {text!r}: values must be finite numbers (no nan, inf)")
    except ValueError:
        raise InputError(f"--grid {text!r}: expected NAME=START:STOP:COUNT (COUNT ≥ 1) or NAME=V1,V2,...") from None
    return name, [round(v, 12) for v in values]
