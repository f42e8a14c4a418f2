"""Figures of the diagnostic parameter study: separability of the fault classes and the
confusion matrices of the cross-validated classifier."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_confusion", "plot_diagnostic", "plot_separability"]

#: Axis label and panel title of the third panel, per level key of the rows.
_LEVELS = {"crack_depth_mm": ("crack depth [mm]", "per depth"),
           "severity": ("fault severity (fraction of the reference size) [-]",
                        "per severity")}


def _level_key(rows: Sequence[dict]) -> str:
    """``"severity"`` for rows of a store of fault classes, else ``"crack_depth_mm"``."""
    return "severity" if any("severity" in r for r in rows) else "crack_depth_mm"


def _snr(noise: float) -> str:
    return "SNR inf" if noise == 0 else f"SNR {-20 * math.log10(noise):.0f} dB"


def _class_text(classes: Sequence[str] | None) -> str:
    if classes is None or list(classes) == ["none", "working", "non-working"]:
        return "healthy, working-flank crack, non-working-flank crack"
    return ", ".join("healthy" if c == "none" else c for c in classes)


@styled
def plot_separability(rows: Sequence[dict], *, title: str = "",
                      classes: Sequence[str] | None = None,
                      method: str = "stratified 5-fold CV",
                      fig: Figure | None = None) -> Figure:
    """Cross-validated accuracy and ROC AUC per feature group against noise and depth.

    Parameters
    ----------
    rows : sequence of dict
        Rows of :func:`gearsim.studies.diagnostic.separability_table` (with
        ``crack_depth_mm`` for a store of flank classes, ``severity`` for a store of
        fault classes).
    title : str
        Figure title.
    classes : sequence of str, optional
        The classes compared (named in the title; chance accuracy 1 / their number);
        default the three flank classes.
    method : str
        The cross-validation, named in the title.
    fig : matplotlib.figure.Figure, optional
        Figure (or sub-figure) to draw into (three panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    groups = list(dict.fromkeys(r["group"] for r in rows))
    noises = sorted({r["noise"] for r in rows})
    key = _level_key(rows)
    n_classes = len(classes) if classes is not None else 3
    chance = f"chance (1/{n_classes})"
    fig = figure_or_new(fig, 15, 4.8)
    axes = fig.subplots(1, 3)
    pooled = [r for r in rows if r.get(key) is None]
    for g in groups:
        rs = sorted((r for r in pooled if r["group"] == g), key=lambda r: r["noise"])
        axes[0].plot([r["noise"] for r in rs], [r["accuracy"] for r in rs], "o-", label=g)
        axes[1].plot([r["noise"] for r in rs], [r["auc"] for r in rs], "o-", label=g)
    axes[0].axhline(1 / n_classes, color="k", ls=":", lw=0.8, label=chance)
    axes[1].axhline(0.5, color="k", ls=":", lw=0.8, label="chance (0.5)")
    pooled_what = ("all crack depths" if key == "crack_depth_mm" else "all severities")
    for ax, what in zip(axes[:2], ("accuracy [-]", "macro one-vs-rest ROC AUC [-]"),
                        strict=True):
        ax.set_xlabel("noise RMS / dynamic signal RMS [-]")
        ax.set_ylabel(f"cross-validated {what}")
        ax.set_title(f"{pooled_what}, loads and speeds pooled", fontsize=9)
        ax.set_ylim(0, 1.02)
        ax.legend(fontsize=8)
    per_level = [r for r in rows if r.get(key) is not None and r["group"] == "all"]
    for noise in noises:
        rs = sorted((r for r in per_level if r["noise"] == noise), key=lambda r: r[key])
        axes[2].plot([r[key] for r in rs], [r["accuracy"] for r in rs], "o-",
                     label=f"noise {noise:g} ({_snr(noise)})")
    axes[2].axhline(1 / n_classes, color="k", ls=":", lw=0.8, label=chance)
    xlabel, what = _LEVELS[key]
    axes[2].set_xlabel(xlabel)
    axes[2].set_ylabel("cross-validated accuracy [-]")
    axes[2].set_title(f"all feature groups together, {what}", fontsize=9)
    axes[2].set_ylim(0, 1.02)
    axes[2].legend(fontsize=8)
    fig.suptitle(f"{title}\nclasses: {_class_text(classes)}; "
                 f"standardised logistic regression, {method}", fontsize=10)
    return fig


@styled
def plot_confusion(rows: Sequence[dict], classes: Sequence[str], *, group: str = "all",
                   title: str = "", fig: Figure | None = None) -> Figure:
    """Confusion matrix of the cross-validated classifier at each noise level.

    One panel per noise level (rows of ``group`` that pool every depth or severity):
    cell (i, j) is coloured by the fraction of the cases of true class i predicted as
    class j (each row sums to 1) and labelled with the count.

    Parameters
    ----------
    rows : sequence of dict
        Rows of :func:`gearsim.studies.diagnostic.separability_table` (with their
        ``confusion`` matrices).
    classes : sequence of str
        Row and column order of the matrices (the classes of the store).
    group : str
        Feature group whose classifier is shown (default all features together).
    title : str
        Figure title.
    fig : matplotlib.figure.Figure, optional
        Figure (or sub-figure) to draw into (one panel per noise level); default a new
        one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    key = _level_key(rows)
    rs = sorted((r for r in rows if r["group"] == group and r.get(key) is None
                 and r.get("confusion") is not None), key=lambda r: r["noise"])
    n = max(len(rs), 1)
    k = len(classes)
    fig = figure_or_new(fig, max(4.0, 3.4 * n), 4.2)
    axes = np.atleast_1d(fig.subplots(1, n, squeeze=False)[0])
    names = ["healthy" if c == "none" else c for c in classes]
    image = None
    for ax, r in zip(axes, rs, strict=False):
        m = np.asarray(r["confusion"], dtype=float)
        total = m.sum(axis=1, keepdims=True)
        frac = np.divide(m, total, out=np.zeros_like(m), where=total > 0)
        image = ax.imshow(frac, cmap="Blues", vmin=0.0, vmax=1.0)
        size = 8 if k <= 5 else 6
        for i in range(k):
            for j in range(k):
                if m[i, j] > 0:
                    ax.text(j, i, f"{m[i, j]:.0f}", ha="center", va="center", fontsize=size,
                            color="white" if frac[i, j] > 0.6 else "black")
        ax.set_xticks(range(k), names, rotation=90)
        ax.set_yticks(range(k), names if ax is axes[0] else [""] * k)
        ax.grid(False)
        ax.set_xlabel("predicted class")
        ax.set_title(f"noise {r['noise']:g} ({_snr(r['noise'])})\naccuracy "
                     f"{r['accuracy']:.2f}", fontsize=9)
    axes[0].set_ylabel("true class")
    if not rs:
        axes[0].text(0.5, 0.5, "no classifier scored", ha="center", va="center",
                     transform=axes[0].transAxes)
    if image is not None:
        fig.colorbar(image, ax=list(axes), shrink=0.8,
                     label="fraction of the true class [-]")
    fig.suptitle(f"{title}\nconfusion matrices of the out-of-fold predictions "
                 f"(features: {group}; rows true class, columns predicted)", fontsize=10)
    return fig


@styled
def plot_diagnostic(rows: Sequence[dict], classes: Sequence[str], *, title: str = "",
                    method: str = "stratified 5-fold CV", fig: Figure | None = None) -> Figure:
    """The diagnostic report's figure: separability (top) and confusion matrices (bottom).

    Parameters
    ----------
    rows : sequence of dict
        Rows of :func:`gearsim.studies.diagnostic.separability_table`.
    classes : sequence of str
        The classes of the store, in the order of the confusion matrices.
    title : str
        Figure title (the study's).
    method : str
        The cross-validation, named in the title.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (two sub-figures); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure: :func:`plot_separability` above :func:`plot_confusion` of all
        feature groups together.
    """
    n = len({r["noise"] for r in rows})
    k = len(classes)
    bottom_h = 3.6 + 0.18 * k
    fig = figure_or_new(fig, max(15.0, 3.4 * n), 4.8 + bottom_h)
    top, bottom = fig.subfigures(2, 1, height_ratios=[4.8, bottom_h])
    plot_separability(rows, title=title, classes=classes, method=method, fig=top)
    plot_confusion(rows, classes, group="all", fig=bottom)
    return fig
