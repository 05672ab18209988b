"""Every figure of docs/figures/, as PNG and PDF, from the current code (CI runs it).

    python scripts/make_figures.py [--out DIR] [--only 001 002 ...]

One function per paper; each draws with :mod:`lmidsl.render.style` (mathtext labels with
units, no internal names) and saves PNG + PDF.  What is solved or simulated is solved or
simulated here, except two stored studies that take minutes and are read back:
``docs/figures/001_fig4/sweep.json`` (``lmidsl sweep``, 361 solves) and
``docs/reproductions/002_results.json`` (``scripts/reproduce_002.py``, about 20 minutes).
Exit code 0 when every figure was written, 1 when one failed (its error is printed).
"""
from __future__ import annotations

import argparse
import json
import sys
import time
import traceback
import warnings
from pathlib import Path

import numpy as np

from lmidsl.render.style import LABELS, WIDE, figure, legend, save

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"


def fig_001(out: Path) -> list:
    """Seed 001, Figs. 2 and 3 (Monte Carlo, 200 runs; also writes 001_mse.json) and Fig. 4
    (γ* over (ξ̄1, ξ̄2), redrawn from the stored sweep)."""
    from lmidsl.render.figures import sweep_figure
    from lmidsl.studies.sweep import SweepResult
    from lmidsl.theorems.li_delay_dropout import simulation

    with warnings.catch_warnings():
        simulation.main(["--out", str(out)])
    result = SweepResult.from_dict(json.loads((FIGURES / "001_fig4" / "sweep.json").read_text()))
    written = sweep_figure(result, out / "001_fig4_gamma")
    return [out / f"{n}.{s}" for n in ("001_fig2_mse_white", "001_fig3_mse_inverse_square")
            for s in ("png", "pdf")] + written


#: readable names of seed 002's synthesis routes and threshold sets
ROUTES_002 = {"exact": "exact LMI (congruence)", "thm2": "Theorem 2, iterated"}
DELTA_002 = {"paper (+β)": r"$\Delta = +\beta$ (paper)", "robust (±β)": r"$\Delta = \pm\beta$"}


def fig_002(out: Path, results: dict | None = None) -> list:
    """Seed 002: Fig. 3 recomputed (best γ against N per synthesis route, from the stored
    results of scripts/reproduce_002.py) and the estimation error of the Table 1 filters."""
    from lmidsl.theorems.zhang_quantized_loss.delta import filter_reading
    from lmidsl.theorems.zhang_quantized_loss.netsim import simulate
    from lmidsl.theorems.zhang_quantized_loss.quantizer import LogQuantizer
    from lmidsl.theorems.zhang_quantized_loss.theorems import H, PLANT, RHO, TABLE1

    if results is None:
        results = json.loads((ROOT / "docs" / "reproductions" / "002_results.json").read_text())
    sets = {"paper (+β)": [1], "robust (±β)": [-1, 1]}
    fig, ax = figure()
    styles = {"exact": "-o", "thm2": "--s"}
    for r_name, route in ROUTES_002.items():
        for label, pts in sets.items():
            rows = [r for r in results["routes"] if r["route"] == r_name and r["points"] == pts
                    and r["alpha_bar"] == 0.5 and r.get("gamma")]
            if rows:
                ax.semilogy([r["N"] for r in rows], [r["gamma"] for r in rows], styles[r_name],
                            ms=4, label=f"{route}, {DELTA_002[label]}")
    printed = sorted((n, row["gamma"]) for n, row in TABLE1.items())
    alphas = ", ".join(f"{TABLE1[n]['alpha_bar']:g}" for n, _ in printed)
    ax.semilogy([n for n, _ in printed], [g for _, g in printed], "k*", ms=10,
                label=rf"printed in the paper (Table 1, $\bar\alpha$ = {alphas})")
    ax.set_title(r"best $\gamma$ per synthesis route, $\bar\alpha = 0.5$")
    ax.set_xlabel(r"maximum number of consecutive losses $N$")
    ax.set_ylabel(LABELS["gamma"])
    ax.set_xticks(range(1, 6))
    ax.grid(True, which="both")
    legend(ax, fontsize=7)
    written = save(fig, out / "002_fig3_gamma_vs_N")

    quantizer = LogQuantizer(RHO, 1.3)
    fig, axs = figure(2, width=WIDE, height=0.36 * WIDE, sharey=True)
    for N, ax in zip(sorted(TABLE1)[:2], axs):
        row = TABLE1[N]
        for reading, name in (("delta", r"$\delta$-operator reading"), ("shift", "shift reading")):
            f = filter_reading(row, reading, H)
            r = simulate(PLANT, f, H, N, row["alpha_bar"], steps=100, x0=[-4, -5],
                         quantizer=quantizer, seed=1)
            ax.plot(r.k, r.e[:, 0], label=f"Table 1 filter, {name}")
        best = [x for x in results["routes"] if x["route"] == "exact" and x["N"] == N
                and x["alpha_bar"] == row["alpha_bar"] and x["points"] == [-1, 1] and x.get("filter")]
        if best:
            f = {k: np.array(v) for k, v in best[0]["filter"].items()}
            r = simulate(PLANT, f, H, N, row["alpha_bar"], steps=100, x0=[-4, -5],
                         quantizer=quantizer, seed=1)
            ax.plot(r.k, r.e[:, 0], label=rf"{ROUTES_002['exact']}, {DELTA_002['robust (±β)']}")
        ax.set_title(rf"$N = {N}$, $\bar\alpha = {row['alpha_bar']}$")
        ax.set_xlabel(LABELS["k"])
        legend(ax, fontsize=7)
    axs[0].set_ylabel(LABELS["error"])
    fig.suptitle(r"logarithmic quantiser, $x(0) = [-4,\,-5]^T$")
    return written + save(fig, out / "002_sim")


def fig_003(out: Path) -> list:
    """Seed 003: the printed filter against a certified one, by simulation and lifted gains."""
    from lmidsl.pipeline import solve
    from lmidsl.theorems.pan_impulsive.impulsive import (FILTER_NAMES, disturbance, error_system,
                                                         impulse_sequence, lifted_gain, simulate)
    from lmidsl.theorems.pan_impulsive.theorems import MODIFIED_PLANT, PLANT, PRINTED_FILTER

    sol = solve("pan_impulsive.thm1", "modified")
    designed = {k: sol.recovered[k] for k in FILTER_NAMES}
    lemma1_gamma = sol.analysis.gamma
    printed_paper = error_system({**PLANT, **PRINTED_FILTER})
    designed_mod = error_system({**MODIFIED_PLANT, **designed})
    fig, axes = figure(3, width=1.45 * WIDE, height=0.36 * WIDE)

    # (a) printed filter, paper plant: one disturbance sample, then an impulse at every instant
    N = 8000
    tr = simulate(printed_paper, disturbance("pulse", N), impulse_sequence("all", N, start=1))
    tr_none = simulate(printed_paper, disturbance("pulse", N), impulse_sequence("none", N))
    ax = axes[0]
    ax.semilogy(np.abs(tr.e[:, 0]), label=r"impulse at every $k \geq 1$: no decay")
    ax.semilogy(np.abs(tr_none.e[:, 0]), ls="--", label="no impulses")
    floor = 1 - PRINTED_FILTER["Dhat"][0][0]
    ax.axhline(floor, color="k", ls=":", lw=1, label=rf"$(1 - \hat D)\,x_1(1) = {floor:.4f}$")
    ax.set_ylim(1e-3, 2)
    ax.set_title("(a) paper's plant, printed filter,\n"
                 r"after one disturbance sample $\omega(0) = 1$")
    ax.set_xlabel(LABELS["k"])
    ax.set_ylabel(r"$|e(k)| = |z(k) - \hat z(k)|$")
    legend(ax)

    # (b) lifted ℓ2 gain against the horizon
    horizons = [25, 50, 100, 200, 400, 800]
    ax = axes[1]
    kinds = {"none": "no impulses", "periodic": "every 5 steps", "all": "every step"}
    for system, name, style in ((printed_paper, "printed filter, paper's plant", "-"),
                                (designed_mod, "recovered filter, modified plant", "--")):
        for kind, marker in zip(kinds, "os^"):
            gains = [lifted_gain(system, impulse_sequence(kind, h, period=5))[0] for h in horizons]
            ax.plot(horizons, gains, style, marker=marker, ms=3.5, label=f"{name}, {kinds[kind]}")
    ax.axhline(0.5, color="r", lw=1, label=r"prescribed $\gamma = 0.5$")
    ax.axhline(lemma1_gamma, color="g", lw=1, ls=":",
               label=rf"Lemma 1 certificate $\gamma = {lemma1_gamma:.4f}$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(horizons)
    ax.set_xticklabels([str(h) for h in horizons])
    ax.minorticks_off()
    ax.set_xlabel(r"horizon $N$ [steps]")
    ax.set_ylabel(r"worst $\ell_2$ gain over the horizon")
    ax.set_title("(b) worst-case gain for fixed impulse sequences")
    legend(ax, fontsize=6.5)

    # (c) recovered filter on the modified plant: noise, periodic impulses
    N = 150
    E = impulse_sequence("periodic", N, period=5)
    tr = simulate(designed_mod, disturbance("noise", N, seed=1), E)
    z = (np.array(MODIFIED_PLANT["L1"]) @ tr.xi[:-1, :2].T).ravel()
    ax = axes[2]
    ax.plot(z, lw=1, label=r"$z(k)$, output to estimate")
    ax.plot(z - tr.e[:, 0], lw=1, ls="--", label=r"$\hat z(k)$, recovered filter")
    ax.plot(tr.e[:, 0], lw=1,
            label=rf"$e(k)$, $\|e\|_2 / \|\omega\|_2 = {tr.energy_ratio:.3f}$")
    for k in np.flatnonzero(E):
        ax.axvline(k, color="0.88", lw=0.5, zorder=0)
    ax.set_title("(c) modified example, recovered filter:\n"
                 r"white-noise $\omega$, impulses every 5 steps (grey)")
    ax.set_xlabel(LABELS["k"])
    ax.set_ylabel(r"$z(k)$, $\hat z(k)$, $e(k)$")
    legend(ax)
    return save(fig, out / "003_impulsive")


def fig_004(out: Path) -> list:
    """Seed 004: the Theorem 2 filters, by frequency sweep and simulation; the numbers the
    docs quote (peak, energy ratios) go to 004_numbers.json."""
    from lmidsl.pipeline import solve
    from lmidsl.theorems.interconnected_delay.network import (DelayNetwork, Filters, frequency_sweep,
                                                              peak_direction, simulate, standard_scenarios,
                                                              uncertain_error_system, uncertainty_vertices)

    sol = solve("interconnected_delay.thm2", example="paper", certify=False)
    values = {**sol.instance.data, **sol.instance.params, **sol.recovered}
    net, flt = DelayNetwork.from_values(values, 2), Filters.from_values(values, 2)
    gam = [float(np.sqrt(sol.values[f"rho_{i}"])) for i in (1, 2)]
    weight = np.diag([1 / g for g in gam])
    ues = uncertain_error_system(net, flt)
    w = np.logspace(-3, 3, 600)

    fig, (ax1, ax2) = figure(2, width=WIDE, height=0.38 * WIDE)
    vertices = list(uncertainty_vertices(net))
    for F, Fd in vertices:
        G = ues.frozen(F, Fd).response(1j * w) @ weight
        ax1.semilogx(w, np.linalg.svd(G, compute_uv=False)[:, 0], color="tab:blue", lw=0.7, alpha=0.6)
    ax1.plot([], [], color="tab:blue", lw=0.7, label=f"each of the {len(vertices)} uncertainty vertices")
    ax1.axhline(1.0, color="k", ls="--", lw=1, label="certified level 1")
    ax1.set_xlabel(LABELS["omega"])
    ax1.set_ylabel(r"$\sigma_{\max}\left(T(j\omega)\,\mathrm{diag}(1/\gamma_i)\right)$")
    ax1.set_title("frequency response, given delays")
    ax1.set_ylim(0, 1.1)
    legend(ax1, loc="lower left")

    sweep = frequency_sweep(net, flt, gam, delay_sets={"given": net.tau})
    sweep["direction"] = peak_direction(net, flt, gam, sweep)
    numbers = {"gamma": gam, "weighted_peak": float(sweep["weighted_peak"]), "energy_ratios": []}
    for label, wfun, Ft, Fdt in standard_scenarios(net, sweep, 20.0):
        t, X, W, Z = simulate(net, flt, wfun, Ft, Fdt, 20.0, 5e-3)
        num = np.concatenate([[0], np.cumsum(0.5 * (np.sum(Z[1:] ** 2, 1) + np.sum(Z[:-1] ** 2, 1)) * np.diff(t))])
        wsq = (W * np.array(gam)) ** 2
        den = np.concatenate([[0], np.cumsum(0.5 * (np.sum(wsq[1:], 1) + np.sum(wsq[:-1], 1)) * np.diff(t))])
        ok = den > 1e-12 * den[-1]
        ax2.plot(t[ok], num[ok] / den[ok], label=_mathtext(label))
        numbers["energy_ratios"].append(float(num[-1] / den[-1]))
    ax2.axhline(1.0, color="k", ls="--", lw=1)
    ax2.set_xlabel(LABELS["t"])
    ax2.set_ylabel(r"energy ratio $\int_0^t |z|^2 d\tau \,/\, \int_0^t |\Gamma w|^2 d\tau$")
    ax2.set_title("simulation, time-varying uncertainty")
    ax2.set_ylim(0, 1.1)
    legend(ax2, fontsize=7, loc="lower right")
    fig.suptitle(rf"Theorem 2 filters: $\Gamma = \mathrm{{diag}}(\gamma_1, \gamma_2)$, "
                 rf"$\gamma_1 = {gam[0]:.4f}$, $\gamma_2 = {gam[1]:.4f}$")
    (out / "004_numbers.json").write_text(json.dumps(numbers, indent=2) + "\n")
    return save(fig, out / "004_interconnected_delay") + [out / "004_numbers.json"]


def _mathtext(text: str) -> str:
    """A scenario name of the seed-004 simulation with its symbols as mathtext."""
    for plain, tex in (("F(t)", "$F(t)$"), ("frozen F", "frozen $F$"), ("w = ", r"$\omega$ = ")):
        text = text.replace(plain, tex)
    return text


MAKERS = {"001": fig_001, "002": fig_002, "003": fig_003, "004": fig_004}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(FIGURES), help="folder of the figures (default docs/figures)")
    ap.add_argument("--only", nargs="+", choices=sorted(MAKERS), help="only these papers' figures")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    failed = []
    for name in args.only or MAKERS:
        t0 = time.perf_counter()
        try:
            written = MAKERS[name](out)
        except Exception:  # noqa: BLE001  (report every figure, then fail)
            traceback.print_exc()
            failed.append(name)
            continue
        names = ", ".join(sorted({p.name for p in written}))
        print(f"{name}: {names} ({time.perf_counter() - t0:.0f} s)", flush=True)
    if failed:
        print(f"make_figures: failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
