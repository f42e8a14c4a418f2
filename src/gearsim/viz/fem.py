"""Figures of the finite-element check: FE versus potential-energy tooth stiffness."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from gearsim.viz.style import figure_and_axes, figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from gearsim.fem.check import FECheck

__all__ = ["plot_fe_check", "plot_mesh"]


@styled
def plot_fe_check(check: FECheck, *, fig: Figure | None = None) -> Figure:
    """FE and PE tooth stiffness along the path of contact, and their differences.

    Parameters
    ----------
    check : gearsim.fem.check.FECheck
        Result of :func:`gearsim.fem.check.fe_check`.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 11, 4)
    axes = fig.subplots(1, 2)
    roll = np.degrees(check.roll_angle)
    b = check.gear.face_width
    ax = axes[0]
    ax.plot(roll, check.k_fe * b / 1e9, "o-", label=f"FE (level {check.fe_result.level})")
    ax.plot(roll, check.k_pe * b / 1e9, "s--", label="potential energy")
    ax.set_xlabel("roll angle [deg]")
    ax.set_ylabel(f"tooth stiffness, b = {b * 1e3:.4g} mm [GN/m]")
    ax.set_title(f"{check.gear.name}: crack {check.crack}, {check.closure}")
    ax.legend()
    d = check.differences()
    labels = list(d)
    axes[1].bar(labels, [d[k] for k in labels])
    axes[1].axhline(0.0, color="k", lw=0.8)
    axes[1].set_ylabel("(k_PE - k_FE) / k_FE [%]")
    axes[1].set_title("max / min / mean")
    return fig


@styled
def plot_mesh(p: np.ndarray, t: np.ndarray, *, window: tuple[float, float, float, float]
              | None = None, crack: Any = None, ax: Axes | None = None) -> Figure:
    """The triangulation of a tooth model, optionally zoomed and with the crack drawn.

    Parameters
    ----------
    p : numpy.ndarray
        Node coordinates, shape (2, n_nodes) [m].
    t : numpy.ndarray
        Triangles as node indices, shape (3 or 6, n_elements) (the first three used).
    window : tuple of float, optional
        ``(x0, x1, y0, y1)`` [m] of the view; default the whole mesh.
    crack : object, optional
        Crack with ``start`` and ``tip`` points [m], drawn in red.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig, ax = figure_and_axes(ax, 7, 7)
    ax.triplot(p[0] * 1e3, p[1] * 1e3, t[:3].T, lw=0.3, color="0.3")
    if crack is not None:
        ax.plot([crack.start[0] * 1e3, crack.tip[0] * 1e3],
                [crack.start[1] * 1e3, crack.tip[1] * 1e3], "r-", lw=1.5)
    if window is not None:
        ax.set_xlim(window[0] * 1e3, window[1] * 1e3)
        ax.set_ylim(window[2] * 1e3, window[3] * 1e3)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.grid(False)
    return fig
