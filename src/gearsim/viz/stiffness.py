"""Figures of the time-varying mesh stiffness (TVMS)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from gearsim.errors import InputError
from gearsim.viz.style import figure_and_axes, figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from gearsim.system.stiffness import TrainStiffness

__all__ = ["plot", "plot_train_stiffness", "plot_mesh_tvms", "plot_healthy_vs_cracked"]


def plot(ts: TrainStiffness, mesh: int | None = None, *, ax: Axes | None = None,
         fig: Figure | None = None) -> Figure:
    """The TVMS figure of a train, or one panel of one mesh (what ``TrainStiffness.plot`` calls).

    Parameters
    ----------
    ts : gearsim.system.stiffness.TrainStiffness
        Stiffness of every mesh of a train.
    mesh : int, optional
        Index of one mesh: draw only its TVMS in one panel (:func:`plot_mesh_tvms`);
        default every mesh with its load sharing (:func:`plot_train_stiffness`).
    ax : matplotlib.axes.Axes, optional
        Axes to draw into, with ``mesh``.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into, without ``mesh``.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    gearsim.errors.InputError
        If ``ax`` is given without ``mesh``, or ``fig`` with it.
    """
    if mesh is None:
        if ax is not None:
            raise InputError("ax", "given", "the train figure has several panels: pass fig= "
                             "or choose one mesh")
        return plot_train_stiffness(ts, fig=fig)
    if fig is not None:
        raise InputError("fig", "given", "one mesh draws one panel: pass ax=")
    return plot_mesh_tvms(ts, mesh, ax=ax)


def _tvms_panel(ax: Axes, pair: Any, r: Any, name: str | None = None, **line: Any) -> None:
    """Draw the TVMS ``r`` of mesh ``pair`` (named ``name``, default its own) against its
    driver's rotation, labelled.

    ``line`` goes to ``ax.plot`` (``label``, ``color``).
    """
    ax.plot(np.degrees(r.theta1), r.k / 1e9, lw=1.0, **line)
    ax.set_xlabel(f"rotation of {pair.driver.name} [deg]")
    ax.set_ylabel("mesh stiffness [GN/m]")
    ax.set_title(f"mesh {name or pair.name}: {pair.driver.name} -> {pair.driven.name}")
    ax.legend(loc="lower right")


@styled
def plot_train_stiffness(ts: TrainStiffness, *, fig: Figure | None = None,
                         names: Sequence[str] = ()) -> Figure:
    """TVMS of every mesh over one revolution of its driver, with the load sharing.

    Parameters
    ----------
    ts : gearsim.system.stiffness.TrainStiffness
        Stiffness of every mesh of a train.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one row of two panels per mesh); default a new one.
    names : sequence of str, optional
        The meshes' names (the gearbox's, beside a planetary stage); default their own.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    n = len(ts.train.pairs)
    fig = figure_or_new(fig, 12, 3.6 * n)
    axes = fig.subplots(n, 2, squeeze=False)
    for i, pair in enumerate(ts.train.pairs):
        r = ts.results[(i, 1)]
        name = names[i] if names else pair.name
        _tvms_panel(axes[i, 0], pair, r, name, label="total")
        ax = axes[i, 1]
        npc = r.attrs["positions_per_cycle"]
        sel = slice(0, 3 * npc)
        for m in range(r.pair_k.shape[1]):
            ax.plot(r.cycles[sel], r.load_share[sel, m], lw=1.0, label=f"pair {m}")
        ax.set_xlabel("mesh cycles [-]")
        ax.set_ylabel("load share [-]")
        ax.set_title(f"mesh {name}: load sharing (3 cycles)")
        ax.legend(loc="upper right", fontsize=8, ncol=2)
    return fig


@styled
def plot_mesh_tvms(ts: TrainStiffness, mesh: int = 0, *, label: str | None = None,
                   color: str | None = None, ax: Axes | None = None) -> Figure:
    """TVMS of one mesh over one revolution of its driver, in one panel.

    Draw several trains into the same ``ax`` to compare them (e.g. healthy and cracked).

    Parameters
    ----------
    ts : gearsim.system.stiffness.TrainStiffness
        Stiffness of every mesh of a train.
    mesh : int
        Index of the mesh (0 is the first).
    label : str, optional
        Legend entry; default the train's name.
    color : str, optional
        Line colour; default matplotlib's colour cycle.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    gearsim.errors.InputError
        If ``mesh`` is not a mesh of the train.
    """
    n = len(ts.train.pairs)
    if not (isinstance(mesh, int) and 0 <= mesh < n):
        raise InputError("mesh", mesh, f"must be an integer in 0..{n - 1}")
    fig, ax = figure_and_axes(ax, 10, 4)
    pair = ts.train.pairs[mesh]
    r = ts.results[(mesh, 1)]
    _tvms_panel(ax, pair, r, color=color, label=ts.train.name if label is None else label)
    return fig


@styled
def plot_healthy_vs_cracked(curves: Mapping[str, tuple[np.ndarray, np.ndarray]], *,
                            title: str = "", xlabel: str = "rotation [deg]",
                            colors: Mapping[str, str] | None = None,
                            ax: Axes | None = None) -> Figure:
    """Overlay several mesh stiffness curves, e.g. healthy and cracked.

    Parameters
    ----------
    curves : mapping of str to (x, k)
        Label -> abscissa and mesh stiffness [N/m] (drawn in GN/m), in drawing order.
    title : str
        Axes title.
    xlabel : str
        Label of the abscissa.
    colors : mapping of str to colour, optional
        Colour per label; default matplotlib's colour cycle.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig, ax = figure_and_axes(ax, 10, 4)
    colors = colors or {}
    for label, (x, k) in curves.items():
        ax.plot(x, np.asarray(k) / 1e9, lw=1.1, label=label, color=colors.get(label))
    ax.set_xlabel(xlabel)
    ax.set_ylabel("mesh stiffness [GN/m]")
    ax.set_title(title)
    ax.legend()
    return fig
