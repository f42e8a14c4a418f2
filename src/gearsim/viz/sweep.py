"""Figure of the diagnostic parameter study: separability of the crack classes."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_separability"]


@styled
def plot_separability(rows: Sequence[dict], *, title: str = "",
                      fig: Figure | None = None) -> Figure:
    """Cross-validated accuracy and ROC AUC per feature group against noise and depth.

    Parameters
    ----------
    rows : sequence of dict
        Rows of :func:`gearsim.studies.diagnostic.separability_table`.
    title : str
        Figure title.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (three panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    groups = list(dict.fromkeys(r["group"] for r in rows))
    noises = sorted({r["noise"] for r in rows})
    fig = figure_or_new(fig, 15, 4.8)
    axes = fig.subplots(1, 3)
    pooled = [r for r in rows if r["crack_depth_mm"] is None]
    for g in groups:
        rs = sorted((r for r in pooled if r["group"] == g), key=lambda r: r["noise"])
        axes[0].plot([r["noise"] for r in rs], [r["accuracy"] for r in rs], "o-", label=g)
        axes[1].plot([r["noise"] for r in rs], [r["auc"] for r in rs], "o-", label=g)
    axes[0].axhline(1 / 3, color="k", ls=":", lw=0.8, label="chance (1/3)")
    axes[1].axhline(0.5, color="k", ls=":", lw=0.8, label="chance (0.5)")
    for ax, what in zip(axes[:2], ("accuracy [-]", "macro one-vs-rest ROC AUC [-]"),
                        strict=True):
        ax.set_xlabel("noise RMS / dynamic signal RMS [-]")
        ax.set_ylabel(f"cross-validated {what}")
        ax.set_title("all crack depths, loads and speeds pooled", fontsize=9)
        ax.set_ylim(0, 1.02)
        ax.legend(fontsize=8)
    per_depth = [r for r in rows if r["crack_depth_mm"] is not None and r["group"] == "all"]
    for noise in noises:
        rs = sorted((r for r in per_depth if r["noise"] == noise),
                    key=lambda r: r["crack_depth_mm"])
        snr = "SNR inf" if noise == 0 else f"SNR {-20 * math.log10(noise):.0f} dB"
        axes[2].plot([r["crack_depth_mm"] for r in rs], [r["accuracy"] for r in rs], "o-",
                     label=f"noise {noise:g} ({snr})")
    axes[2].axhline(1 / 3, color="k", ls=":", lw=0.8, label="chance (1/3)")
    axes[2].set_xlabel("crack depth [mm]")
    axes[2].set_ylabel("cross-validated accuracy [-]")
    axes[2].set_title("all feature groups together, per depth", fontsize=9)
    axes[2].set_ylim(0, 1.02)
    axes[2].legend(fontsize=8)
    fig.suptitle(f"{title}\nclasses: healthy, working-flank crack, non-working-flank crack; "
                 "standardised logistic regression, stratified 5-fold CV", fontsize=10)
    return fig
