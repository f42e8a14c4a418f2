"""House style of every gearsim figure, in one place.

The style is a dictionary of matplotlib rc settings applied with
:func:`matplotlib.rc_context` around each plot function (decorator :func:`styled`) and
around saving (:func:`gearsim.viz.save`). Nothing here, nor anywhere in gearsim, changes
the global :data:`matplotlib.rcParams`: a user's own settings are untouched after a
gearsim figure is drawn.

Figures are :class:`matplotlib.figure.Figure` objects with an Agg canvas: no pyplot
state, no GUI, safe in worker processes. A user who wants a figure inside a pyplot
window passes their own ``ax=`` or ``fig=``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import matplotlib
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["DPI", "STYLE", "styled", "new_figure", "figure_and_axes", "figure_or_new", "figure_of"]

#: Resolution of saved raster figures [dots per inch].
DPI = 130

#: rc settings of the house style: fonts of at least 9 pt at the saved size, light grid.
STYLE: dict[str, Any] = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "figure.dpi": DPI,
    "savefig.dpi": DPI,
}

F = TypeVar("F", bound=Callable[..., Any])


def styled(func: F) -> F:
    """Decorate a plot function so that it draws inside ``rc_context(STYLE)``.

    Parameters
    ----------
    func : callable
        Plot function; its signature and docstring are kept.

    Returns
    -------
    callable
        The wrapped function.
    """

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with matplotlib.rc_context(STYLE):
            return func(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def new_figure(width: float, height: float) -> Figure:
    """A new figure with an Agg canvas and constrained layout (no pyplot, no GUI).

    Parameters
    ----------
    width, height : float
        Size [inch].

    Returns
    -------
    matplotlib.figure.Figure
        The empty figure, at :data:`DPI`.
    """
    fig = Figure(figsize=(width, height), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def figure_of(ax: Axes) -> Figure:
    """The top-level figure that holds ``ax`` (also when ``ax`` is in a sub-figure).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes of the figure.

    Returns
    -------
    matplotlib.figure.Figure
        Its root figure.
    """
    return ax.get_figure(root=True)


def figure_and_axes(ax: Axes | None, width: float, height: float) -> tuple[Figure, Axes]:
    """The figure and axes a single-panel plot draws into.

    Parameters
    ----------
    ax : matplotlib.axes.Axes or None
        Axes given by the caller; ``None`` makes a new figure of one panel.
    width, height : float
        Size of the new figure [inch] (unused when ``ax`` is given).

    Returns
    -------
    fig : matplotlib.figure.Figure
        Root figure of the axes.
    ax : matplotlib.axes.Axes
        Axes to draw into.
    """
    if ax is None:
        fig = new_figure(width, height)
        return fig, fig.add_subplot(1, 1, 1)
    return figure_of(ax), ax


def figure_or_new(fig: Figure | None, width: float, height: float) -> Figure:
    """The figure a multi-panel plot draws into: ``fig`` or a new one of the given size.

    Parameters
    ----------
    fig : matplotlib.figure.Figure or None
        Figure given by the caller (panels are added to it); ``None`` makes a new one.
    width, height : float
        Size of the new figure [inch] (unused when ``fig`` is given).

    Returns
    -------
    matplotlib.figure.Figure
        The figure to draw into.
    """
    return new_figure(width, height) if fig is None else fig
