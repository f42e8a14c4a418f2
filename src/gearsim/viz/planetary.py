"""Figures of a planetary stage: the phased sun-planet and ring-planet mesh stiffnesses
(and those of a gearbox's stages and gears)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from gearsim.errors import require
from gearsim.viz.stiffness import plot_train_stiffness
from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from gearsim.system.planetary import PlanetaryTrain
    from gearsim.system.stiffness import TrainStiffness

__all__ = ["plot_gearbox_meshes", "plot_stage_meshes"]

#: Line styles of the planets, in turn.
LINE_STYLES = ("-", "--", ":", "-.")
#: Samples per mesh cycle of the drawn curves.
SAMPLES_PER_CYCLE = 64


@styled
def plot_stage_meshes(train: PlanetaryTrain, cycles: float | None = None, *,
                      fig: Figure | None = None) -> Figure:
    """Stiffness of every planet's sun and ring mesh against mesh cycles (two panels).

    Each curve is the phased table the dynamics reads (``train.mesh_table``): the planets'
    curves are shifted by their Parker & Lin (2004) phases, and a cracked tooth shows
    where it meets each mesh.

    Parameters
    ----------
    train : gearsim.system.planetary.PlanetaryTrain
        The stage in operation.
    cycles : float, optional
        Mesh cycles drawn from c = 0 (> 0); default the longest table period (a cracked
        member's revolution), at least 3.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        Upper panel sun-planet meshes, lower panel ring-planet meshes [GN/m].
    """
    fm = train.mesh_frequency
    n = train.stage.planets
    if cycles is None:
        cycles = max(3.0, max(train.mesh_table(m, p).period for m in ("sun", "ring")
                              for p in range(n)))
    require(isinstance(cycles, (int, float)) and math.isfinite(cycles) and cycles > 0,
            "cycles", cycles, "must be a finite number of mesh cycles > 0")
    c = np.linspace(0.0, cycles, int(math.ceil(cycles * SAMPLES_PER_CYCLE)) + 1)
    fig = figure_or_new(fig, 7.0, 5.0)
    axes = fig.subplots(2, 1, sharex=True)
    for ax, mesh, title in zip(axes, ("sun", "ring"), ("sun-planet", "ring-planet"),
                               strict=True):
        for p in range(n):
            k = train.mesh_table(mesh, p)(c / fm, fm)
            # planets in phase overlap: line styles keep each visible
            ax.plot(c, k / 1e9, lw=1.0, ls=LINE_STYLES[p % len(LINE_STYLES)],
                    label=f"planet-{p + 1}")
        ax.set_ylabel(f"{title} k [GN/m]")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center",
               ncols=min(n, 6), fontsize="small")
    fig.suptitle(f"{train.name}\nphased mesh stiffness, f_m = {fm:.5g} Hz", fontsize="medium")
    axes[1].set_xlabel("mesh cycles c = f_m t")
    return fig



@styled
def plot_gearbox_meshes(parts: Sequence[PlanetaryTrain | TrainStiffness],
                        names: Sequence[str] = (), *, fig: Figure | None = None) -> Figure:
    """Stiffness of every mesh of a gearbox with planetary stages, one row a part in
    power-flow order: a stage's phased tables (:func:`plot_stage_meshes`), a chain of
    gears' TVMS (:func:`gearsim.viz.stiffness.plot_train_stiffness`).

    Parameters
    ----------
    parts : sequence of PlanetaryTrain or TrainStiffness
        The stages and the stiffness of the gears beside them, in power-flow order.
    names : sequence of str, optional
        The gears' meshes' names, numbered through the chains (default their own).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        A lone stage: the figure of :func:`plot_stage_meshes`.
    """
    gears = [hasattr(p, "results") for p in parts]  # a TrainStiffness (viz imports no system)
    if len(parts) == 1 and not gears[0]:
        return plot_stage_meshes(parts[0], fig=fig)
    heights = [3.6 * len(p.train.pairs) if g else 5.0 for p, g in zip(parts, gears, strict=True)]
    fig = figure_or_new(fig, 12.0, sum(heights))
    subs = fig.subfigures(len(parts), 1, squeeze=False, height_ratios=heights)[:, 0]
    k = 0
    for sub, p, g in zip(subs, parts, gears, strict=True):
        if g:
            plot_train_stiffness(p, fig=sub, names=names[k:k + len(p.train.pairs)])
            k += len(p.train.pairs)
        else:
            plot_stage_meshes(p, fig=sub)
    return fig
