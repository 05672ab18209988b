"""Start-up of the command line: `lmidsl --help` and `lmidsl list` against `python -c pass`.

Each command is a fresh process (what a user waits for); the runs are interleaved (pass, help,
list, pass, help, list, ...) so that load on a shared machine hits all of them alike, and the
medians of wall time are printed with their ratios to `python -c pass` measured in the same run.
`list` is timed with a warm index cache (a private cache folder, filled by one untimed run
first); the cold run, which builds the index by loading every theorem file, is printed once.

    python benchmarks/bench_startup.py [--repeat 5] [--ref PATH]

``--ref PATH`` also times another checkout of lmidsl (e.g. an older commit unpacked with
`git archive COMMIT | tar -x -C PATH`) in the same run, for a before/after comparison.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def timed(argv, env) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, env=env, cwd=env["PYTHONPATH"], stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--ref", type=Path, help="another lmidsl checkout to time in the same run")
    args = parser.parse_args()
    cache = tempfile.mkdtemp(prefix="lmidsl-bench-cache-")
    trees = {"this": ROOT}
    if args.ref:
        trees["ref"] = args.ref.resolve()
    envs = {}
    for label, tree in trees.items():
        env = {k: v for k, v in os.environ.items() if k not in ("LMIDSL_THEOREM_PATH", "LMIDSL_DEBUG")}
        source = tree / "src" if (tree / "src" / "lmidsl").is_dir() else tree
        env.update(PYTHONPATH=str(source), LMIDSL_CACHE_DIR=cache)
        envs[label] = env
    cold = timed([sys.executable, "-m", "lmidsl", "list"], envs["this"])   # builds the index
    py = sys.executable
    cases = {"python -c pass": ([py, "-c", "pass"], envs["this"])}
    for label in trees:
        cases[f"lmidsl --help ({label})"] = ([py, "-m", "lmidsl", "--help"], envs[label])
        cases[f"lmidsl list ({label})"] = ([py, "-m", "lmidsl", "list"], envs[label])
    times = {name: [] for name in cases}
    for _ in range(args.repeat):
        for name, (argv, env) in cases.items():
            times[name].append(timed(argv, env))
    base = statistics.median(times["python -c pass"])
    print(f"medians of {args.repeat} interleaved runs, wall time; {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'command':28s} {'median s':>9s} {'× python -c pass':>17s}")
    for name, values in times.items():
        m = statistics.median(values)
        print(f"{name:28s} {m:9.3f} {m / base:17.1f}")
    print(f"(lmidsl list with a cold index cache, this checkout, once: {cold:.3f} s)")


if __name__ == "__main__":
    main()
