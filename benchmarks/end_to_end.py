"""One ``lmidsl.solve`` in a fresh process, bounded by a timeout: wall and CPU time, peak memory
(the child's maximum resident set, ``getrusage``), and what the solve said.  Shared by
``bench_mjls.py --end-to-end`` and ``bench_polya.py --end-to-end``.

The child writes one JSON line: status, verdict, the ``times`` record and the number of LMIs;
a child that runs past the timeout is killed and reported as such, one that is refused up
front (exit 2, the estimate) with its message.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time

CHILD = r"""
import json, sys, time, warnings
warnings.simplefilter("ignore")
import lmidsl
from lmidsl.errors import InputError
theorem, path, overrides, limits = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), json.loads(sys.argv[4])
data = json.load(open(path))
t0 = time.perf_counter()
try:
    sol = lmidsl.solve(theorem, data=data, overrides=overrides or None, **limits)
except InputError as exc:
    print(json.dumps({"refused": str(exc), "wall": time.perf_counter() - t0}))
    sys.exit(2)
print(json.dumps({"status": sol.status, "verdict": sol.verdict.word, "gamma": sol.gamma,
                  "lmis": len(sol.instance.theorem.lmis), "times": sol.times,
                  "checks": [c.summary if hasattr(c, "summary") else str(c) for c in sol.checks][:2],
                  "wall": time.perf_counter() - t0}))
"""


def run(theorem: str, data: dict, overrides: dict | None = None, timeout: float = 120.0,
        limits: dict | None = None) -> dict:
    """Solve ``theorem`` on ``data`` in a child process under ``/usr/bin/time`` (its own peak
    resident memory and CPU time); the measures and the child's answer."""
    with tempfile.TemporaryDirectory() as tmp:
        path, measures = os.path.join(tmp, "data.json"), os.path.join(tmp, "time.txt")
        with open(path, "w") as f:
            json.dump(data, f)
        command = ["/usr/bin/time", "-f", "%M %U %S", "-o", measures, sys.executable, "-c", CHILD, theorem,
                   path, json.dumps(overrides or {}), json.dumps(limits or {})]
        t0 = time.perf_counter()
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=True)
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
            text = stdout.strip()
            out = json.loads(text.splitlines()[-1]) if text else \
                {"error": stderr.strip().splitlines()[-1] if stderr.strip() else f"exit {proc.returncode}"}
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)          # the solve and /usr/bin/time
            proc.communicate()
            out = {"timeout": timeout}
        out["wall_total"] = time.perf_counter() - t0
        try:
            rss, user, system = open(measures).read().split()[-3:]
            out["cpu"], out["peak_mib"] = float(user) + float(system), int(rss) / 1024
        except (OSError, ValueError):          # killed: /usr/bin/time wrote nothing
            out["cpu"], out["peak_mib"] = float("nan"), float("nan")
    return out


def line(label: str, out: dict) -> str:
    """One row: label, wall, CPU, peak memory, and the outcome."""
    if "timeout" in out:
        what = f"killed after {out['timeout']:.0f} s"
    elif "refused" in out:
        what = "refused: " + out["refused"]
    elif "error" in out:
        what = "error: " + out["error"]
    else:
        t = out["times"]
        what = (f"{out['status']}, {out['verdict']}, {out['lmis']} LMIs; bind {t.get('bind', 0):.2f} compile "
                f"{t.get('compile', 0):.2f} solver {t.get('solver', 0):.2f} certificate {t.get('certificate', 0):.2f} "
                f"checks {t.get('checks', 0):.2f}")
    return f"{label:28s} wall {out['wall_total']:7.1f} s  cpu {out['cpu']:7.1f} s  peak {out['peak_mib']:7.0f} MiB  {what}"


def load() -> str:
    """The load average, to state with the timings."""
    return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg()) + f" on {os.cpu_count()} cores"
