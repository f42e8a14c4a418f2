"""Figures of gearsim results: one plotting convention for the whole package.

* Every plot function takes the result as its first argument and a keyword-only
  ``ax=None`` (single-panel plots: draw into the given Axes, else make a figure) or
  ``fig=None`` (multi-panel plots: add the panels to the given figure, else make one),
  and returns the :class:`matplotlib.figure.Figure`. No plot function writes a file.
* The house style (:data:`gearsim.viz.style.STYLE`) is applied with
  :func:`matplotlib.rc_context` around each plot function and around saving; the global
  ``matplotlib.rcParams`` are never changed.
* New figures are :class:`matplotlib.figure.Figure` objects with an Agg canvas (no
  pyplot, no GUI).
* Files are written only by :func:`save` (one figure) and :func:`save_all` (several):
  format from the suffix, atomically, at one resolution (:data:`DPI`).
* Result objects hand off in one line, e.g. ``Analysis.plot(kind="spectrum")``,
  ``TrainStiffness.plot()``, ``FECheck.plot()``; the core imports this package only
  inside those methods, never at module level.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

from gearsim.errors import InputError
from gearsim.io.atomic import atomic_write
from gearsim.io.targets import check_output_file
from gearsim.viz.style import DPI, STYLE

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["DPI", "FORMATS", "STYLE", "check_plot_file", "save", "save_all"]

#: File formats :func:`save` writes, by suffix (without the dot).
FORMATS = ("png", "pdf", "svg")


def _format(path: Path, parameter: str) -> str:
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise InputError(parameter, str(path), "must end in .png, .pdf or .svg")
    return fmt


def check_plot_file(path: str | Path, parameter: str = "path") -> Path:
    """Check, before any work, that :func:`save` can write a figure to ``path``.

    Parameters
    ----------
    path : str or Path
        Output file ending in ``.png``, ``.pdf`` or ``.svg``.
    parameter : str
        Name of the option that gave ``path``, for the message (e.g. ``"--plot"``).

    Returns
    -------
    Path

    Raises
    ------
    gearsim.errors.InputError
        An empty path, an existing folder, another suffix, or a folder that cannot be
        written (nothing is created).

    Examples
    --------
    >>> check_plot_file("fig.svg", "--plot").name
    'fig.svg'
    """
    return check_output_file(path, parameter, tuple(f".{f}" for f in FORMATS))


def save(fig: Figure, path: str | Path, *, dpi: float = DPI, parameter: str = "path") -> Path:
    """Write ``fig`` to ``path`` atomically; the format follows the suffix.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Figure to write (e.g. returned by a plot function).
    path : str or Path
        Output file ending in ``.png``, ``.pdf`` or ``.svg``; its folder is created.
    dpi : float
        Resolution of raster output [dots per inch].
    parameter : str
        Name of the option that gave ``path``, used in the error message (a CLI verb
        passes ``"--plot"``).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    gearsim.errors.InputError
        If the suffix is not one of :data:`FORMATS`, or the path is a folder or cannot
        be written (:func:`check_plot_file`; nothing is written).
    """
    path = check_plot_file(path, parameter)
    fmt = _format(path, parameter)

    def write(tmp: Path) -> None:
        with matplotlib.rc_context(STYLE):
            fig.savefig(tmp, format=fmt, dpi=dpi)

    return atomic_write(path, write)


def save_all(figs: Mapping[str, Figure], folder: str | Path, fmt: str = "png", *,
             dpi: float = DPI) -> list[Path]:
    """Write each figure of ``figs`` to ``folder / f"{name}.{fmt}"`` with :func:`save`.

    Parameters
    ----------
    figs : mapping of str to matplotlib.figure.Figure
        Figures by file stem, in the order they are written.
    folder : str or Path
        Output folder (created if needed).
    fmt : {"png", "pdf", "svg"}
        File format of all figures.
    dpi : float
        Resolution of raster output [dots per inch].

    Returns
    -------
    list of Path
        The files written, in the order of ``figs``.

    Raises
    ------
    gearsim.errors.InputError
        If ``fmt`` is not one of :data:`FORMATS` (nothing is written).
    """
    if fmt not in FORMATS:
        raise InputError("fmt", fmt, "must be png, pdf or svg")
    folder = Path(folder)
    return [save(fig, folder / f"{name}.{fmt}", dpi=dpi) for name, fig in figs.items()]
