"""One style for every figure lmidsl and its papers draw: serif text with matching mathtext
(STIX, shipped with matplotlib), labels with units, light grids, legends without frames, and
every figure saved as PNG (for the docs) and PDF (vector, for a paper).

Labels are mathtext (``$\\sigma_{\\max}(T(j\\omega))$``), never internal names: :data:`LABELS`
holds the quantities several figures share.  matplotlib is imported inside the functions, so
importing this module costs nothing.

>>> fig, ax = figure()                      # doctest: +SKIP
>>> ax.set_xlabel(LABELS["omega"])          # doctest: +SKIP
>>> save(fig, "docs/figures/name")          # doctest: +SKIP  (name.png and name.pdf)
"""
from __future__ import annotations

from pathlib import Path

from ..studies.store import atomic_path

#: matplotlib rc parameters of every lmidsl figure
RC = {
    "font.family": "STIXGeneral",
    "mathtext.fontset": "stix",
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 8,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "legend.frameon": False,
    "lines.linewidth": 1.2,
    "figure.dpi": 100,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "savefig.pad_inches": 0.03,
    "pdf.fonttype": 42,          # TrueType in the PDF: text stays text (searchable, editable)
    "axes.unicode_minus": True,
    "axes.formatter.use_mathtext": True,
}

#: width of a figure of one panel and of a full text width (inches)
WIDTH = 4.8
WIDE = 9.6

#: quantities several figures share, as mathtext with their units
LABELS = {
    "k": r"time step $k$",
    "t": r"time $t$ [s]",
    "omega": r"frequency $\omega$ [rad/s]",
    "gamma": r"$\gamma^\star$",
    "gamma_level": r"$\gamma$",
    "error": r"estimation error $e(k) = z(k) - \hat z(k)$",
}

#: formats every figure is saved in
FORMATS = ("png", "pdf")


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update(RC)
    return plt


def figure(ncols: int = 1, nrows: int = 1, *, width: float | None = None,
           height: float | None = None, projection: str | None = None, **kw):
    """A new figure with the lmidsl style: ``(fig, axes)`` like :func:`matplotlib.pyplot.subplots`
    (``axes`` a single Axes for one panel).  ``width`` defaults to one panel per :data:`WIDTH`,
    up to :data:`WIDE`; ``height`` to 0.7 of a panel's width per row."""
    plt = _pyplot()
    width = width or min(WIDE, WIDTH * ncols)
    height = height or 0.7 * width / ncols * nrows
    if projection is not None:
        fig = plt.figure(figsize=(width, height), layout="constrained")
        axes = [fig.add_subplot(nrows, ncols, i + 1, projection=projection if i == 0 else None)
                for i in range(nrows * ncols)]
        return fig, axes[0] if len(axes) == 1 else axes
    fig, axes = plt.subplots(nrows, ncols, figsize=(width, height), layout="constrained",
                             squeeze=True, **kw)
    return fig, axes


def save(fig, path, formats=FORMATS) -> list[Path]:
    """Save ``fig`` as ``path`` with each suffix of ``formats`` (default PNG and PDF), each file
    written atomically (a reader never sees half a figure), then close it; the paths written.
    A suffix of ``path`` is replaced.  The files carry no creation date, so an unchanged figure
    gives unchanged bytes."""
    import matplotlib.pyplot as plt

    base = Path(path)
    base = base.with_suffix("") if base.suffix.lstrip(".") in ("png", "pdf", "svg") else base
    base.parent.mkdir(parents=True, exist_ok=True)
    written = []
    for fmt in formats:
        target = base.parent / f"{base.name}.{fmt}"
        metadata = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None},
                    "svg": {"Date": None}}.get(fmt)
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=fmt, metadata=metadata)
        written.append(target)
    plt.close(fig)
    return written


def legend(ax, **kw):
    """A legend in the style (no frame, small type); nothing if ``ax`` has no labelled artist."""
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        return ax.legend(**kw)
    return None
