"""Figures (issue 18): one style, mathtext labels, no internal names, PNG and PDF."""
from __future__ import annotations

import numpy as np

from lmidsl.render.figures import parameter_label, sweep_figure
from lmidsl.render.style import FORMATS, LABELS, figure, save
from lmidsl.studies.sweep import SweepPoint, SweepResult


def _result(names, counts=None):
    counts = counts or (3,) * len(names)
    grid = {n: [0.1, 0.5, 0.9][:c] for n, c in zip(names, counts)}
    values = list(np.ndindex(*counts))
    points = [SweepPoint({n: grid[n][i] for n, i in zip(names, idx)}, "optimal", 1.0 + sum(idx),
                         1.0, -1e-8, 0.01, 0.01, 0.02, proved=True) for idx in values]
    return SweepResult("paper.thm2", "paper", "CLARABEL", grid, points,
                       labels={"xi1": r"\bar{\xi}_1", "xi2": r"\bar{\xi}_2"})


def _texts(fig):
    out = []
    for ax in fig.axes:
        out += [ax.get_xlabel(), ax.get_ylabel(), ax.get_title()]
        if hasattr(ax, "get_zlabel"):
            out.append(ax.get_zlabel())
    return [t for t in out if t]


def test_sweep_figure_png_and_pdf_mathtext_labels_no_internal_names(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt
    seen = []
    monkeypatch.setattr(plt, "close", lambda fig: seen.append(_texts(fig)))
    for names in (["xi1"], ["xi1", "xi2"]):
        written = sweep_figure(_result(names), tmp_path / f"s{len(names)}")
        assert [p.suffix for p in written] == [f".{f}" for f in FORMATS] == [".png", ".pdf"]
        assert all(p.stat().st_size > 5000 for p in written)
    one, two = seen
    assert r"$\bar{\xi}_1$" in one and LABELS["gamma"] in one
    assert {r"$\bar{\xi}_1$", r"$\bar{\xi}_2$", LABELS["gamma"]} <= set(two)
    for text in one + two:
        assert not any(bad in text for bad in ("paper.thm2", "CLARABEL", "xi1", "seed"))


def test_a_two_parameter_grid_with_a_single_value_on_an_axis_is_a_line(tmp_path, monkeypatch):
    """A 3 × 1 (or 1 × 1) grid: γ along the axis that varies, the fixed value in the label (a
    contour map needs 2 × 2 points: matplotlib raised, and `sweep` ended in an internal error)."""
    import matplotlib.pyplot as plt
    seen = []
    monkeypatch.setattr(plt, "close", lambda fig: seen.append(_texts(fig)))
    for counts in ((3, 1), (1, 3), (1, 1)):
        written = sweep_figure(_result(["xi1", "xi2"], counts), tmp_path / f"s{counts}")
        assert all(p.stat().st_size > 5000 for p in written)
    assert seen[0][0] == r"$\bar{\xi}_1$ ($\bar{\xi}_2$ = 0.1)"
    assert seen[1][0] == r"$\bar{\xi}_2$ ($\bar{\xi}_1$ = 0.1)"


def test_parameter_label_falls_back_to_the_name():
    r = _result(["xi1"])
    assert parameter_label(r, "xi1") == r"$\bar{\xi}_1$"
    assert parameter_label(r, "other") == "other"


def test_save_replaces_a_suffix_and_writes_reproducible_files(tmp_path):
    def draw():
        fig, ax = figure()
        ax.plot([0, 1], [1, 0])
        ax.set_xlabel(LABELS["omega"])
        return fig
    first = save(draw(), tmp_path / "a.png")
    assert [p.name for p in first] == ["a.png", "a.pdf"]
    before = [p.read_bytes() for p in first]
    save(draw(), tmp_path / "a")
    assert [p.read_bytes() for p in first] == before      # no creation date in the files


def test_every_docs_figure_is_png_and_pdf_and_made_by_the_script():
    """docs/figures/: each figure as PNG and PDF, each named in scripts/make_figures.py."""
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    script = (root / "scripts" / "make_figures.py").read_text()
    pngs = sorted((root / "docs" / "figures").glob("*.png"))
    assert pngs
    for png in pngs:
        assert png.with_suffix(".pdf").exists(), png.name
        assert f'"{png.stem}"' in script, f"{png.name} is not drawn by scripts/make_figures.py"
