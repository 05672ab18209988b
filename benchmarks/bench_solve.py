"""One solve from the command line against the script a user would write:
``python benchmarks/bench_solve.py [--repeat 5]``.

Fresh processes, interleaved, medians of wall time, for two designs:

* ``wang_l2linf.thm3 --example paper-full``: ``lmidsl solve`` (bind, compile, solve, recover the
  filter, prove the LMIs, certify the filter by Theorem 1: an analysis SDP) against
  ``benchmarks/hand_thm3.py`` (the same LMIs typed in cvxpy, Clarabel, the recovery (32); no
  certification);
* ``li_delay_dropout.thm2 --example paper``: ``lmidsl solve`` (the same, plus the automatic
  back-off: the recovery at the optimum inverts a matrix of condition number 2e8) against
  ``benchmarks/hand_li_thm2.py`` (cvxpy, Clarabel, with the measurement scaling lmidsl finds by
  itself, the recovery; no certification, no back-off).

One untimed warm-up run of each command first: the timed ``lmidsl solve`` is a second solve,
which loads the built theorem from lmidsl's cache (``lmidsl.theorem.build_cache``) instead of
running the theorem file in sympy.

Prints the medians, the ratios lmidsl / hand (issue 16's target: ≤ 1.0) and every γ.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


CASES = {"wang_l2linf.thm3": ("paper-full", "hand_thm3.py"),
         "li_delay_dropout.thm2": ("paper", "hand_li_thm2.py")}


def example_data(theorem: str, example: str, path: Path) -> None:
    import lmidsl

    inputs = lmidsl.get_theorem(theorem).examples[example].inputs()
    path.write_text(json.dumps({k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in inputs.items()}))


def byte_compile_lmidsl() -> None:
    """Write lmidsl's ``.pyc`` files, as ``pip install`` does (cvxpy, the reference's library, has
    them): in a source checkout run with ``PYTHONDONTWRITEBYTECODE=1`` every module would be
    compiled again at every start."""
    import compileall
    import importlib.util

    for package in ("lmidsl", "lmidsl.theorems"):
        for folder in importlib.util.find_spec(package).submodule_search_locations:
            compileall.compile_dir(folder, quiet=1)


def timed(cmd: list[str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return time.perf_counter() - t0, out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--theorem", choices=list(CASES), action="append",
                        help="only these designs (repeatable; default both)")
    args = parser.parse_args(argv)
    byte_compile_lmidsl()
    commands = {}
    with tempfile.TemporaryDirectory() as tmp:
        for theorem in args.theorem or list(CASES):
            example, script = CASES[theorem]
            data = Path(tmp) / f"{theorem}.json"
            example_data(theorem, example, data)
            # the same interpreter as the hand script (``lmidsl`` on PATH may be a pyenv shim: +60 ms)
            commands[(theorem, "lmidsl")] = [sys.executable, "-m", "lmidsl", "solve", theorem,
                                             "--example", example, "--json"]
            commands[(theorem, "hand")] = [sys.executable, str(HERE / script), str(data)]
        samples = {k: [] for k in commands}
        outputs = {}
        for cmd in commands.values():     # warm-up: lmidsl's theorem build cache, the OS file cache
            timed(cmd)
        for _ in range(args.repeat):
            for key, cmd in commands.items():
                seconds, outputs[key] = timed(cmd)
                samples[key].append(seconds)
    med = {k: statistics.median(v) for k, v in samples.items()}
    print(f"{'design':<24} {'command':<8} {'median s':>9} {'gamma':>12}")
    for (theorem, who) in commands:
        print(f"{theorem:<24} {who:<8} {med[(theorem, who)]:9.3f} {json.loads(outputs[(theorem, who)])['gamma']:12.8f}")
    for theorem in dict.fromkeys(t for t, _ in commands):
        print(f"ratio lmidsl / hand, {theorem}: {med[(theorem, 'lmidsl')] / med[(theorem, 'hand')]:.2f} "
              "(target <= 1.0; lmidsl also certifies)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
