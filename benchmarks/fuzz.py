"""The long fuzz run: ≥ 10,000 random theorems through the builder and a backend's compiler (cvxpy
by default, ``--backend direct`` for the direct one), each compared with numpy's evaluation of its
block matrices (see tests/fuzzing.py), then the command line's input parsing properties of
tests/test_fuzz.py with many more examples.

    python benchmarks/fuzz.py [--cases 10000] [--start 0] [--backend cvxpy] [--parse-examples 2000]

Prints the counts (same / refused / mismatch / crash), the kinds of refusal, and every crash or
mismatch with its seed (re-run one with ``python -c "from fuzzing import run_case; print(run_case(SEED))"``
from ``tests/``).  Exit code 1 if any case crashed or mismatched.
"""
from __future__ import annotations

import argparse
import collections
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests")]

from fuzzing import run_case  # noqa: E402


def kind_of(message: str) -> str:
    """A refusal's kind: its message with names and numbers blanked."""
    text = re.sub(r"^fuzz\.c\d+: ", "", message)
    text = re.sub(r"\b[A-Z][a-z]?\d+\b|\b[nps]\d+\b|\ba0\b", "·", text)
    text = re.sub(r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?", "#", text)
    return text[:70]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10000)
    parser.add_argument("--start", type=int, default=0, help="first seed")
    parser.add_argument("--backend", default="cvxpy", help="the compiler under test (cvxpy, direct, picos)")
    parser.add_argument("--parse-examples", type=int, default=2000,
                        help="hypothesis examples for each command-line parsing property (0: skip)")
    args = parser.parse_args()
    counts = collections.Counter()
    refusals = collections.Counter()
    failures = []
    t0 = time.perf_counter()
    for seed in range(args.start, args.start + args.cases):
        outcome, detail = run_case(seed, args.backend)
        counts[outcome] += 1
        if outcome == "refused":
            refusals[kind_of(detail)] += 1
        elif outcome in ("crash", "mismatch"):
            failures.append(detail)
        if (seed - args.start + 1) % 1000 == 0:
            print(f"  {seed - args.start + 1} cases, {dict(counts)}, {time.perf_counter() - t0:.0f} s",
                  file=sys.stderr, flush=True)
    elapsed = time.perf_counter() - t0
    print(f"builder/compiler fuzz ({args.backend}): {args.cases} cases (seeds {args.start}..{args.start + args.cases - 1}) "
          f"in {elapsed:.0f} s")
    for outcome in ("same", "refused", "mismatch", "crash"):
        print(f"  {outcome:9s} {counts[outcome]}")
    print("  refusals by kind:")
    for kind, n in refusals.most_common(12):
        print(f"    {n:6d}  {kind}")
    for detail in failures:
        print("FAILURE", detail)
    parse_failures = 0
    if args.parse_examples:
        from hypothesis import HealthCheck, given, settings
        import test_fuzz
        for name, check, strategies in (("--set values", test_fuzz.check_set_value, test_fuzz.SET_VALUES),
                                        ("--grid texts", test_fuzz.check_grid_text, test_fuzz.GRID_TEXTS)):
            test = settings(max_examples=args.parse_examples, deadline=None, database=None,
                            suppress_health_check=[HealthCheck.too_slow])(given(**strategies)(check))
            try:
                test()
                print(f"{name}: {args.parse_examples} examples, no failure")
            except Exception as exc:      # hypothesis re-raises the failing example
                parse_failures += 1
                print(f"{name}: FAILED: {type(exc).__name__}: {exc}")
    return 1 if failures or parse_failures else 0


if __name__ == "__main__":
    sys.exit(main())
