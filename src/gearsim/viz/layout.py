"""Figure of a gearbox's layout drawn from its graph: shafts, gears, meshes and a stage."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_layout"]


@styled
def plot_layout(shafts: Sequence[tuple[str, tuple[float, float]]],
                gears: Sequence[tuple[str, int, float, int]],
                meshes: Sequence[tuple[str, str, str]], *, title: str = "",
                stage: dict | None = None, fig: Figure | None = None) -> Figure:
    """Plan view of a gearbox: each gear a pitch circle on its shaft, meshes as links.

    Gears on one shaft are concentric circles (they sit at different axial positions);
    each mesh joins its two gears' centres, labelled with its name; a planetary stage is
    drawn in a panel of its own (sun, planets on the carrier circle, ring), left of the
    parallel shafts its sun or carrier shaft drives, or right of the parallel shafts that
    drive it.

    Parameters
    ----------
    shafts : sequence of (str, (float, float))
        Name and centre [m] of each shaft (the layout of the lateral model).
    gears : sequence of (str, int, float, int)
        Name, shaft index, pitch radius [m] and teeth of each gear.
    meshes : sequence of (str, str, str)
        Driver, driven gear name and the mesh label.
    title : str, optional
        Figure title.
    stage : dict, optional
        ``sun``, ``ring`` and ``planet`` pitch radii [m], ``centre`` (carrier radius,
        [m]), ``angles`` (planet angles [rad]) and ``teeth`` (z_s, z_p, z_r); optional
        ``side`` (``"output"``: the stage drives the shafts, ``"input"``: they drive it)
        and ``member`` (the stage member on the joining shaft).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The parallel shafts (and the stage, in power-flow order, when given), axes in mm,
        equal aspect.
    """
    fig = figure_or_new(fig, 10.0 if stage else 7.0, 5.0)
    axes = fig.subplots(1, 2 if stage else 1, squeeze=False)[0]
    drives = bool(stage) and stage.get("side") == "input"  # the shafts drive the stage
    ax, sa = (axes[0], axes[-1]) if drives else (axes[-1], axes[0])
    mm = 1e3
    phi = np.linspace(0, 2 * np.pi, 241)
    centre = {name: np.asarray(c) * mm for name, c in shafts}
    names = [s for s, _ in shafts]
    where = {}
    for k, (g, s_i, r, z) in enumerate(gears):
        c = centre[names[s_i]]
        where[g] = c
        ax.plot(c[0] + r * mm * np.cos(phi), c[1] + r * mm * np.sin(phi), color=f"C{k % 10}",
                label=f"{g} (z {z}, on {names[s_i]})")
    for a, b, label in meshes:
        p, q = where[a], where[b]
        ax.plot([p[0], q[0]], [p[1], q[1]], "k:", lw=0.8)
        ax.annotate(label, (p + q) / 2, fontsize=8, ha="center", va="bottom")
    for name, c in centre.items():
        ax.plot(*c, "k+")
        ax.annotate(name, c, fontsize=8, xytext=(4, -10), textcoords="offset points")
    if stage:
        zs, zp, zr = stage["teeth"]
        for r, lab in ((stage["sun"], f"sun (z {zs})"), (stage["ring"], f"ring (z {zr})")):
            sa.plot(r * mm * np.cos(phi), r * mm * np.sin(phi), "-", lw=1.2, label=lab)
        for j, psi in enumerate(stage["angles"]):
            cx, cy = stage["centre"] * mm * np.cos(psi), stage["centre"] * mm * np.sin(psi)
            sa.plot(cx + stage["planet"] * mm * np.cos(phi), cy + stage["planet"] * mm
                    * np.sin(phi), "k--", lw=0.8, label=f"planets (z {zp})" if j == 0 else None)
        sa.set_title("planetary stage")
        sa.legend(fontsize=7, loc="lower left")
    for a in axes:
        a.set_aspect("equal")
        a.set_xlabel("x [mm]")
    axes[0].set_ylabel("y [mm]")
    member = stage.get("member") if stage else None
    ax.set_title(title if not stage else "parallel shafts" if member is None else
                 f"parallel shafts ({'driving' if drives else 'driven by'} the {member})")
    if stage:
        fig.suptitle(title)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig
