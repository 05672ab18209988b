"""What certification costs: ``python benchmarks/bench_certify.py [--repeat K]``.

For each paper theorem's main example, the wall time of ``lmidsl.solve`` without the independent
certification (bind, compile, solve — as written and, where proposed, conditioned — recover, and
the proofs of the synthesis LMIs, which every solve does) and with it (the analysis counterpart
solved with the design fixed and proved, the theorem's checks), medians of ``--repeat``
interleaved runs in one process.  Prints the ratio (certified − uncertified) / uncertified: the target is
≤ 2 (certification at most twice the synthesis).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings

warnings.filterwarnings("ignore")

import lmidsl  # noqa: E402

CASES = [("wang_l2linf.thm3", "paper-full"), ("wang_l2linf.cor1", "two-vertex"),
         ("li_delay_dropout.thm2", "paper"), ("pan_impulsive.thm1_min", "modified"),
         ("zhang_quantized_loss.thm2", "paper-N2"), ("interconnected_delay.thm2", "paper")]


def timed(theorem, example, certify) -> float:
    t0 = time.perf_counter()
    lmidsl.solve(theorem, example=example, certify=certify)
    return time.perf_counter() - t0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"{'theorem':<28} {'example':<12} {'solve s':>8} {'+certify s':>10} {'ratio':>6}")
    for theorem, example in CASES:
        timed(theorem, example, False)       # warm-up: imports, theorem construction
        plain, full = [], []
        for _ in range(args.repeat):
            plain.append(timed(theorem, example, False))
            full.append(timed(theorem, example, True))
        p, f = statistics.median(plain), statistics.median(full)
        print(f"{theorem:<28} {example:<12} {p:8.3f} {f:10.3f} {(f - p) / p:6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
