"""Start-up of the command line, per command, against `python -c pass` in the same run.

Each command is a fresh process (what a user waits for); the runs are interleaved (pass, sympy,
help, list, ..., pass, sympy, ...) so that load on a shared machine hits all of them alike, and
the medians of wall time are printed with their ratios to `python -c pass` and to
`python -c "import sympy"` (the floor of any command that builds a theorem: a theorem is sympy
expressions).  The commands:

* ``--help``, ``list`` (the cached index), ``solve nosuch.thm`` (an error: answered from the
  index, before sympy);
* ``latex textbook.brl_ct`` (sympy, the theorem from the build cache, the printer);
* ``solve textbook.brl_ct --no-certify``: the whole command, and its time to first work, the
  ``startup`` the command itself reports (``--json``: interpreter, imports of the solving stack,
  argument parsing, measured from the process's start up to the solve).

Every case runs once untimed first (Python's bytecode and lmidsl's caches are warm, as for a
user's second command); bytecode goes to a private ``PYTHONPYCACHEPREFIX`` so that
``PYTHONDONTWRITEBYTECODE`` in the environment does not make every run recompile lmidsl.

    python benchmarks/bench_startup.py [--repeat 5] [--ref PATH]

``--ref PATH`` also times another checkout of lmidsl (e.g. an older commit unpacked with
`git archive COMMIT | tar -x -C PATH`) in the same run, for a before/after comparison; each tree
has its own cache folder (an entry of one would evict the other's).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
THEOREM = "textbook.brl_ct"


def timed(argv, env) -> tuple[float, float | None]:
    """(wall time, the ``startup`` a ``--json`` solve reports, else None)."""
    t0 = time.perf_counter()
    proc = subprocess.run(argv, env=env, cwd=env["PYTHONPATH"], capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    startup = None
    if "--json" in argv:
        try:
            startup = json.loads(proc.stdout)["times"]["startup"]
        except (ValueError, KeyError, TypeError):
            pass
    return wall, startup


def cases_for(label: str, py: str) -> dict:
    lm = [py, "-m", "lmidsl"]
    return {f"lmidsl --help ({label})": lm + ["--help"],
            f"lmidsl list ({label})": lm + ["list"],
            f"solve nosuch.thm ({label})": lm + ["solve", "nosuch.thm"],
            f"latex {THEOREM} ({label})": lm + ["latex", THEOREM],
            f"solve {THEOREM} --no-certify ({label})": lm + ["solve", THEOREM, "--no-certify", "--json"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--ref", type=Path, help="another lmidsl checkout to time in the same run")
    args = parser.parse_args()
    trees = {"this": ROOT}
    if args.ref:
        trees["ref"] = args.ref.resolve()
    py = sys.executable
    pycache = tempfile.mkdtemp(prefix="lmidsl-bench-pyc-")
    cases = {}
    for label, tree in trees.items():
        env = {k: v for k, v in os.environ.items()
               if k not in ("LMIDSL_THEOREM_PATH", "LMIDSL_DEBUG", "LMIDSL_CACHE", "PYTHONDONTWRITEBYTECODE")}
        source = tree / "src" if (tree / "src" / "lmidsl").is_dir() else tree
        env.update(PYTHONPATH=str(source), LMIDSL_CACHE_DIR=tempfile.mkdtemp(prefix=f"lmidsl-bench-{label}-"),
                   PYTHONPYCACHEPREFIX=pycache)
        if label == "this":
            cases["python -c pass"] = ([py, "-c", "pass"], env)
            cases["python -c 'import sympy'"] = ([py, "-c", "import sympy"], env)
        cases.update({name: (argv, env) for name, argv in cases_for(label, py).items()})
    for argv, env in cases.values():          # bytecode, the index and the build cache written
        timed(argv, env)
    walls = {name: [] for name in cases}
    startups = {name: [] for name, (argv, _) in cases.items() if "--json" in argv}
    for _ in range(args.repeat):
        for name, (argv, env) in cases.items():
            wall, startup = timed(argv, env)
            walls[name].append(wall)
            if startup is not None:
                startups[name].append(startup)
    base = statistics.median(walls["python -c pass"])
    sympy = statistics.median(walls["python -c 'import sympy'"])
    print(f"medians of {args.repeat} interleaved runs, wall time; {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'command':48s} {'median s':>9s} {'× pass':>7s} {'× import sympy':>15s}")
    rows = [(name, statistics.median(values)) for name, values in walls.items()]
    rows += [(f"  time to first work: {name}", statistics.median(values))
             for name, values in startups.items() if values]
    for name, m in rows:
        print(f"{name:48s} {m:9.3f} {m / base:7.1f} {m / sympy:15.2f}")


if __name__ == "__main__":
    main()
