"""Figure of a run-to-failure store: health indicators over the life and the life fraction
at which each crosses its alarm level (:mod:`gearsim.studies.life`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import new_figure, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_life_alarms"]

_LABELS = {"na4": "NA4 (run history)", "fm4": "FM4", "residual_kurtosis": "residual kurtosis",
           "sideband_energy": "sideband energy ratio, order 1"}


@styled
def plot_life_alarms(fractions: Sequence[float], trends: Mapping[str, np.ndarray],
                     levels: Mapping[str, float], crossings: Mapping[str, float | None], *,
                     title: str = "") -> Figure:
    """Indicators over the life and the life fraction at which each crosses its alarm.

    Parameters
    ----------
    fractions : sequence of float
        Life fractions of the records [-].
    trends : mapping of str to ndarray
        Indicator name -> seed mean at each fraction
        (:func:`gearsim.studies.life.indicator_trends`).
    levels : mapping of str to float
        Indicator name -> alarm level (absolute, same units as the trend).
    crossings : mapping of str to float or None
        Indicator name -> life fraction of the first crossing, ``None`` if never
        (:func:`gearsim.studies.life.alarm_fractions`).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Left: each indicator over its alarm level against the life fraction (log scale,
        alarm at 1); right: the crossing fraction per indicator.
    """
    fig = new_figure(10.0, 4.2)
    ax, bx = fig.subplots(1, 2, width_ratios=(3, 2))
    f = np.asarray(fractions, dtype=float)
    names = list(trends)
    for n in names:
        ax.plot(f, np.asarray(trends[n]) / levels[n], marker="o", label=_LABELS.get(n, n))
    ax.axhline(1.0, color="k", lw=1.0, ls="--", label="alarm level")
    ax.set_yscale("log")
    ax.set_xlabel("life fraction N / N_end [-]")
    ax.set_ylabel("indicator / alarm level [-]")
    ax.legend(fontsize="small")
    y = np.arange(len(names))
    vals = [crossings.get(n) for n in names]
    bx.barh(y, [v if v is not None else 0.0 for v in vals], color="C0")
    for yi, v in zip(y, vals, strict=True):
        bx.text(0.02 if v is None else v + 0.02, yi,
                "not crossed" if v is None else f"{v:.2f}", va="center", fontsize="small")
    bx.set_yticks(y, [f"{_LABELS.get(n, n)}\n(alarm {levels[n]:.3g})" for n in names],
                  fontsize="small")
    bx.set_xlim(0.0, 1.15)
    bx.set_xlabel("life fraction at the alarm [-]")
    if title:
        fig.suptitle(title)
    return fig
