"""Figure of a gearbox's layout drawn from its graph: shafts, gears, meshes and a stage."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_layout"]


def _chain(ax, shafts, gears, meshes) -> None:
    """Pitch circles on their shafts, meshes as labelled links, shaft centres (mm)."""
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
    ax.legend(fontsize=7, loc="best")


def _stage(ax, stage: dict) -> None:
    """Sun, planets on the carrier circle and ring of a stage (mm)."""
    mm = 1e3
    phi = np.linspace(0, 2 * np.pi, 241)
    zs, zp, zr = stage["teeth"]
    for r, lab in ((stage["sun"], f"sun (z {zs})"), (stage["ring"], f"ring (z {zr})")):
        ax.plot(r * mm * np.cos(phi), r * mm * np.sin(phi), "-", lw=1.2, label=lab)
    for j, psi in enumerate(stage["angles"]):
        cx, cy = stage["centre"] * mm * np.cos(psi), stage["centre"] * mm * np.sin(psi)
        ax.plot(cx + stage["planet"] * mm * np.cos(phi), cy + stage["planet"] * mm
                * np.sin(phi), "k--", lw=0.8, label=f"planets (z {zp})" if j == 0 else None)
    ax.set_title("planetary stage")
    ax.legend(fontsize=7, loc="lower left")


@styled
def plot_layout(shafts: Sequence[tuple[str, tuple[float, float]]],
                gears: Sequence[tuple[str, int, float, int]],
                meshes: Sequence[tuple[str, str, str]], *, title: str = "",
                stage: dict | None = None, upstream: tuple | None = None,
                fig: Figure | None = None) -> Figure:
    """Plan view of a gearbox: each gear a pitch circle on its shaft, meshes as links.

    Gears on one shaft are concentric circles (they sit at different axial positions);
    each mesh joins its two gears' centres, labelled with its name; a planetary stage is
    drawn in a panel of its own (sun, planets on the carrier circle, ring), in
    power-flow order between the parallel shafts that drive it and those it drives.

    Parameters
    ----------
    shafts : sequence of (str, (float, float))
        Name and centre [m] of each shaft (the layout of the lateral model) of the gears
        (after the stage, when there is one; may be empty).
    gears : sequence of (str, int, float, int)
        Name, shaft index, pitch radius [m] and teeth of each gear.
    meshes : sequence of (str, str, str)
        Driver, driven gear name and the mesh label.
    title : str, optional
        Figure title.
    stage : dict, optional
        ``sun``, ``ring`` and ``planet`` pitch radii [m], ``centre`` (carrier radius,
        [m]), ``angles`` (planet angles [rad]) and ``teeth`` (z_s, z_p, z_r); optional
        ``input`` and ``output`` (the members on the joining shafts).
    upstream : tuple, optional
        ``(shafts, gears, meshes)`` of gears driving the stage, as above.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per part in power-flow order, axes in mm, equal aspect.
    """
    panels: list[tuple[str, object]] = []
    if upstream is not None:
        panels.append(("up", upstream))
    if stage:
        panels.append(("stage", stage))
    if gears or not stage:
        panels.append(("down", (shafts, gears, meshes)))
    fig = figure_or_new(fig, 5.0 * len(panels) + 2.0, 5.5)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    for ax, (kind, part) in zip(axes, panels, strict=True):
        if kind == "stage":
            _stage(ax, part)
            continue
        _chain(ax, *part)
        member = (stage or {}).get("input" if kind == "up" else "output")
        ax.set_title(title if not stage else "parallel shafts" if member is None else
                     f"parallel shafts ({'driving' if kind == 'up' else 'driven by'} the "
                     f"{member})")
    for a in axes:
        a.set_aspect("equal")
        a.set_xlabel("x [mm]")
    axes[0].set_ylabel("y [mm]")
    if stage:
        fig.suptitle(title)
    return fig
