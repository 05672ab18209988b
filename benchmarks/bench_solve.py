"""One solve from the command line against the script a user would write:
``python benchmarks/bench_solve.py [--repeat 5]``.

Fresh processes, interleaved, medians of wall time:

* ``lmidsl``: ``lmidsl solve wang_l2linf.thm3 --example paper-full`` — bind, compile, solve,
  recover the filter, prove the LMIs and certify the filter by Theorem 1 (an analysis SDP);
* ``hand``: ``python benchmarks/hand_thm3.py DATA.json`` — the same LMIs typed in cvxpy, Clarabel,
  the recovery (32); no certification.

Prints both, the ratio lmidsl / hand (issue 16's target: ≤ 1.0) and both γ.
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


def example_data(path: Path) -> None:
    import lmidsl

    inputs = lmidsl.get_theorem("wang_l2linf.thm3").examples["paper-full"].inputs()
    path.write_text(json.dumps({k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in inputs.items()}))


def timed(cmd: list[str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return time.perf_counter() - t0, out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "thm3.json"
        example_data(data)
        commands = {"lmidsl": ["lmidsl", "solve", "wang_l2linf.thm3", "--example", "paper-full", "--json"],
                    "hand": [sys.executable, str(HERE / "hand_thm3.py"), str(data)]}
        samples = {k: [] for k in commands}
        outputs = {}
        for _ in range(args.repeat):
            for name, cmd in commands.items():
                seconds, outputs[name] = timed(cmd)
                samples[name].append(seconds)
    med = {k: statistics.median(v) for k, v in samples.items()}
    gamma = {k: json.loads(v)["gamma"] for k, v in outputs.items()}
    print(f"{'command':<10} {'median s':>9} {'gamma':>12}")
    for k in commands:
        print(f"{k:<10} {med[k]:9.3f} {gamma[k]:12.8f}")
    print(f"ratio lmidsl / hand: {med['lmidsl'] / med['hand']:.2f} (target <= 1.0; lmidsl also certifies)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
