"""Figures of lmidsl's studies, in the style of :mod:`lmidsl.render.style`: γ* over a sweep grid."""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from .style import LABELS, WIDE, figure, save


def parameter_label(result, name: str) -> str:
    """Axis label of a sweep parameter: its LaTeX name as mathtext (``$\\bar{\\xi}_1$``), else its name."""
    tex = (getattr(result, "labels", None) or {}).get(name)
    return f"${tex}$" if tex else name


def sweep_figure(result, path, title: str | None = None, formats=None) -> list:
    """γ* of a :class:`~lmidsl.studies.sweep.SweepResult` over its grid: a line for one
    parameter (or for two of which one takes a single value), a surface beside a contour map for
    two.  Saved as ``path`` in every format of
    :data:`lmidsl.render.style.FORMATS` (or ``formats``); the paths written.  The title is
    ``title`` only: the figure names no theorem id or solver."""
    names = list(result.grid)
    gamma = result.gamma_array()
    varying = [n for n in names if len(result.grid[n]) > 1]
    if len(names) == 1 or (len(names) == 2 and len(varying) < 2):
        # one parameter, or two of which one (or none) takes a single value: γ along the other
        along = varying[0] if varying else names[0]
        fixed = [f"{parameter_label(result, n)} = {result.grid[n][0]:g}" for n in names if n != along]
        fig, ax = figure()
        ax.plot(result.grid[along], np.asarray(gamma).reshape(-1), "o-", ms=3)
        ax.set_xlabel(parameter_label(result, along) + (f" ({', '.join(fixed)})" if fixed else ""))
        ax.set_ylabel(LABELS["gamma"])
    elif len(names) == 2:
        x, y = np.meshgrid(result.grid[names[0]], result.grid[names[1]], indexing="ij")
        fig, (ax, ax2) = figure(2, width=WIDE, height=0.45 * WIDE, projection="3d")
        ax.plot_surface(x, y, gamma, cmap="viridis", edgecolor="k", linewidth=0.15)
        ax.set_xlabel(parameter_label(result, names[0]))
        ax.set_ylabel(parameter_label(result, names[1]))
        ax.set_zlabel(LABELS["gamma"])
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            axis.set_rotate_label(False)      # mathtext (ξ̄₁) upright, not turned along the axis
        ax.view_init(elev=28, azim=45)
        ax.set_box_aspect(None, zoom=0.85)
        cs = ax2.contourf(x, y, gamma, levels=20, cmap="viridis")
        lines = ax2.contour(x, y, gamma, levels=10, colors="k", linewidths=0.4)
        ax2.clabel(lines, fontsize=7, fmt="%.2f")
        fig.colorbar(cs, ax=ax2, label=LABELS["gamma"])
        ax2.set_xlabel(parameter_label(result, names[0]))
        ax2.set_ylabel(parameter_label(result, names[1]))
        ax2.set_aspect("equal")
        ax2.grid(False)
    else:
        raise InputError("a figure needs one or two grid parameters")
    if title:
        fig.suptitle(title)
    return save(fig, path, **({"formats": formats} if formats else {}))

