"""Figure for docs/reproductions/003.md: the printed filter vs a certified one, by simulation.

Run from the repository root: ``PYTHONPATH=. python docs/figures/make_003_impulsive.py``.
"""
import importlib.util
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from lmidsl.pipeline import solve  # noqa: E402
from lmidsl.theorems.pan_impulsive.impulsive import disturbance, error_system, impulse_sequence, lifted_gain, simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("pan", ROOT / "theorems" / "pan_impulsive.py")
PI = importlib.util.module_from_spec(spec)
spec.loader.exec_module(PI)

sol = solve("pan_impulsive.thm1", "modified")
designed = {k: sol.recovered[k] for k in PI.FILTER}
lemma1_gamma = sol.analysis.gamma
printed_paper = error_system({**PI.PLANT, **PI.PRINTED_FILTER})
designed_mod = error_system({**PI.MODIFIED_PLANT, **designed})

fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))

# (a) printed filter, paper plant: one disturbance sample, then an impulse at every instant
N = 8000
E_all = impulse_sequence("all", N, start=1)
tr = simulate(printed_paper, disturbance("pulse", N), E_all)
tr_none = simulate(printed_paper, disturbance("pulse", N), impulse_sequence("none", N))
ax = axes[0]
ax.semilogy(np.abs(tr.e[:, 0]), lw=1.5, label="impulse at every k ≥ 1 (τ_j = j): no decay")
ax.semilogy(np.abs(tr_none.e[:, 0]), lw=1.5, ls="--", label="no impulses: decays like 0.9995^k")
ax.axhline(1 - PI.PRINTED_FILTER["Dhat"][0][0], color="k", ls=":", lw=1, label="(1 − D̂)·x₁(1) = 0.0449")
ax.set_ylim(1e-3, 2)
ax.set_title("paper's plant, printed filter:\n|e(k)| after one disturbance sample ω(0) = 1")
ax.set_xlabel("k")
ax.set_ylabel("|e(k)| = |z − ẑ|")
ax.legend(fontsize=8)

# (b) lifted ℓ2 gain vs horizon
horizons = [25, 50, 100, 200, 400, 800]
ax = axes[1]
for system, name, style in ((printed_paper, "printed filter, paper plant", "-"),
                            (designed_mod, "recovered filter, modified plant", "--")):
    for kind, marker in (("none", "o"), ("periodic", "s"), ("all", "^")):
        gains = [lifted_gain(system, impulse_sequence(kind, h, period=5))[0] for h in horizons]
        ax.plot(horizons, gains, style, marker=marker, ms=4, label=f"{name}, {kind}")
ax.axhline(0.5, color="r", lw=1, label="γ = 0.5 (prescribed)")
ax.axhline(lemma1_gamma, color="g", lw=1, ls=":", label=f"Lemma 1 certificate {lemma1_gamma:.4f}")
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xticks(horizons)
ax.set_xticklabels([str(h) for h in horizons])
ax.minorticks_off()
ax.set_xlabel("horizon N")
ax.set_ylabel("worst ℓ2 gain over the horizon (lifted)")
ax.set_title("worst-case gain for fixed impulse sequences")
ax.legend(fontsize=6.5, ncol=1)

# (c) recovered filter on the modified plant: noise, periodic impulses
N = 150
w = disturbance("noise", N, seed=1)
E = impulse_sequence("periodic", N, period=5)
tr = simulate(designed_mod, w, E)
z = (np.array(PI.MODIFIED_PLANT["L1"]) @ tr.xi[:-1, :2].T).ravel()
ax = axes[2]
ax.plot(z, lw=1, label="z (plant output to estimate)")
ax.plot(z - tr.e[:, 0], lw=1, ls="--", label="ẑ (recovered filter)")
ax.plot(tr.e[:, 0], lw=1, label=f"e = z − ẑ  (‖e‖/‖ω‖ = {tr.energy_ratio:.3f})")
for k in np.flatnonzero(E):
    ax.axvline(k, color="0.85", lw=0.5, zorder=0)
ax.set_title("modified example, recovered filter (γ = 0.5):\n"
             "white-noise ω, impulses every 5 steps (grey)")
ax.set_xlabel("k")
ax.legend(fontsize=8)

fig.tight_layout()
out = ROOT / "docs" / "figures" / "003_impulsive.png"
fig.savefig(out, dpi=110)
print(out)
