"""Figure of a gearbox's layout drawn from its graph: shafts, gears, meshes and a stage."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.patches import Rectangle

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["axial_stations", "developed_heights", "plot_layout"]


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
    at: dict[tuple, list[str]] = {}  # coaxial shafts and their meshes: one label each
    for a, b, label in meshes:
        p, q = where[a], where[b]
        ax.plot([p[0], q[0]], [p[1], q[1]], "k:", lw=0.8)
        at.setdefault(("mesh", *np.round((p + q) / 2, 6)), []).append(label)
    for name, c in centre.items():
        ax.plot(*c, "k+")
        at.setdefault(("shaft", *np.round(c, 6)), []).append(name)
    for (kind, *c), labels in at.items():
        ax.annotate(", ".join(labels), c, fontsize=8, xytext=(0, 3) if kind == "mesh"
                    else (4, -10), textcoords="offset points",
                    ha="center" if kind == "mesh" else "left")
    ax.legend(fontsize=7, loc="best")


def axial_stations(gears: Sequence[tuple[str, int, float, int]],
                   meshes: Sequence[tuple[str, str, str]]) -> dict[str, int]:
    """Axial station of each gear in a side view: the two gears of a mesh in one plane.

    Walking the meshes in power-flow order, a driver not yet placed (the input gear, or
    the second gear of a compound shaft) opens the next station and its driven gear
    takes the driver's; an idler's two meshes share its station.

    Parameters
    ----------
    gears : sequence of (str, int, float, int)
        Name, shaft index, pitch radius [m] and teeth of each gear.
    meshes : sequence of (str, str, str)
        Driver, driven gear name and mesh label, in power-flow order.

    Returns
    -------
    dict
        Gear name -> station (0, 1, ...); gears in no mesh get stations after the others.

    Examples
    --------
    >>> g = [("a", 0, 0.02, 32), ("b", 1, 0.05, 80), ("c", 1, 0.03, 48), ("d", 2, 0.04, 64)]
    >>> axial_stations(g, [("a", "b", "I"), ("c", "d", "II")])
    {'a': 0, 'b': 0, 'c': 1, 'd': 1}
    """
    where: dict[str, int] = {}
    for a, b, _ in meshes:
        if a not in where:
            where[a] = max(where.values(), default=-1) + 1
        where.setdefault(b, where[a])
    for g, *_ in gears:
        where.setdefault(g, max(where.values(), default=-1) + 1)
    return {g: where[g] for g, *_ in gears}


def developed_heights(shafts: Sequence[tuple[str, tuple[float, float]]],
                      gears: Sequence[tuple[str, int, float, int]],
                      meshes: Sequence[tuple[str, str, str]]) -> list[float]:
    """Height of each shaft in the developed side view [m]: the input at 0, each driven
    shaft its centre distance beyond its driver's, back where the centre line points
    back along the first one (x < 0: a reverted train's output on the input axis).

    Parameters
    ----------
    shafts, gears, meshes
        As :func:`plot_layout` (shaft centres [m] in the plan, meshes in power-flow order).

    Returns
    -------
    list of float
        One height per shaft; a shaft the meshes do not reach keeps its plan x.

    Examples
    --------
    >>> sh = [("a", (0.0, 0.0)), ("b", (0.1, 0.0)), ("c", (0.1, 0.2))]
    >>> g = [("p", 0, 0.02, 20), ("q", 1, 0.08, 80), ("r", 1, 0.05, 30), ("t", 2, 0.15, 90)]
    >>> developed_heights(sh, g, [("p", "q", "I"), ("r", "t", "II")])
    [0.0, 0.1, 0.30000000000000004]
    """
    shaft_of = {g: s_i for g, s_i, _, _ in gears}
    c = [np.asarray(xy, dtype=float) for _, xy in shafts]
    h: dict[int, float] = {shaft_of[meshes[0][0]]: 0.0} if meshes else {}
    for a, b, _ in meshes:
        i, j = shaft_of[a], shaft_of[b]
        d = c[j] - c[i]
        dist = float(np.hypot(*d))
        h.setdefault(j, h.get(i, float(c[i][0])) + (-dist if d[0] < -1e-9 * dist else dist))
    return [h.get(k, float(c[k][0])) for k in range(len(shafts))]


def _side(ax, shafts, gears, meshes) -> None:
    """Side view: shafts as lines at their developed heights (:func:`developed_heights`),
    gears as bars of their pitch diameter at their axial stations, mesh labels at the
    pitch points (mm)."""
    mm = 1e3
    x = {k: v * mm for k, v in enumerate(developed_heights(shafts, gears, meshes))}
    station = axial_stations(gears, meshes)
    shaft_of = {g: s_i for g, s_i, _, _ in gears}
    partner = {a: b for a, b, _ in meshes} | {b: a for a, b, _ in reversed(meshes)}
    span: dict[int, list[int]] = {}
    for k, (g, s_i, r, z) in enumerate(gears):
        z_g = station[g]
        span.setdefault(s_i, []).append(z_g)
        ax.add_patch(Rectangle((z_g - 0.12, x[s_i] - r * mm), 0.24, 2 * r * mm,
                               color=f"C{k % 10}", alpha=0.6))
        away = -1.0 if g in partner and x[shaft_of[partner[g]]] > x[s_i] else 1.0
        ax.annotate(f"{g} (z {z})", (z_g + 0.14, x[s_i] + away * 0.6 * r * mm), fontsize=7,
                    va="center")
    for s_i, zs in span.items():
        ax.plot([min(zs) - 0.35, max(zs) + 0.35], [x[s_i]] * 2, "k-", lw=2.5)
        ax.annotate(shafts[s_i][0], (min(zs) - 0.35, x[s_i]), fontsize=8, ha="right",
                    va="center", xytext=(-3, 0), textcoords="offset points")
    radius = {g: r * mm for g, _, r, _ in gears}
    for a, b, label in meshes:
        up = 1.0 if x[shaft_of[b]] >= x[shaft_of[a]] else -1.0
        ax.annotate(label, (station[a] + 0.14, x[shaft_of[a]] + up * radius[a]), fontsize=8,
                    va="center")
    ax.set_xlim(-1.2, max(station.values(), default=0) + 1.3)
    ax.set_xticks(sorted(set(station.values())))
    ax.set_xlabel("axial station (gear plane)")
    ax.set_ylabel("developed centre distance [mm]")
    ax.grid(alpha=0.3)


def _stage(ax, stage: dict) -> None:
    """Sun, planets on the carrier circle and ring of a stage (mm)."""
    mm = 1e3
    phi = np.linspace(0, 2 * np.pi, 241)
    zs, zp, zr = stage["teeth"]

    def on(member: str) -> str:  # the shaft a turning member sits on, or "held"
        if stage.get("fixed") == member:
            return ", held"
        shaft = (stage.get("shafts") or {}).get(member)
        return f", on {shaft}" if shaft and shaft != member else ""

    for r, m, z in ((stage["sun"], "sun", zs), (stage["ring"], "ring", zr)):
        ax.plot(r * mm * np.cos(phi), r * mm * np.sin(phi), "-", lw=1.2,
                label=f"{m} (z {z}{on(m)})")
    ax.plot(stage["centre"] * mm * np.cos(phi), stage["centre"] * mm * np.sin(phi), ":",
            color="0.5", lw=0.8, label=f"carrier (planet centres{on('carrier')})")
    for j, psi in enumerate(stage["angles"]):
        cx, cy = stage["centre"] * mm * np.cos(psi), stage["centre"] * mm * np.sin(psi)
        ax.plot(cx + stage["planet"] * mm * np.cos(phi), cy + stage["planet"] * mm
                * np.sin(phi), "k--", lw=0.8, label=f"planets (z {zp})" if j == 0 else None)
    ax.set_title(stage.get("title", "planetary stage"))
    ax.legend(fontsize=7, loc="lower left")


@styled
def plot_layout(shafts: Sequence[tuple[str, tuple[float, float]]],
                gears: Sequence[tuple[str, int, float, int]],
                meshes: Sequence[tuple[str, str, str]], *, title: str = "",
                stage: dict | Sequence[dict] | None = None, upstream: tuple | None = None,
                fig: Figure | None = None) -> Figure:
    """Plan and side views of a gearbox: gears on their shafts, meshes labelled.

    Plan view (top): each gear a pitch circle on its shaft, gears on one shaft concentric
    (they sit at different axial positions), each mesh a link between its two gears'
    centres labelled with its name. Side view (below it), developed into one plane: each
    shaft a line at its distance along the power path (:func:`developed_heights`), each
    gear a bar of its pitch diameter in its plane (:func:`axial_stations`), so coaxial
    shafts and the gears of a compound shaft stand apart. A planetary stage is
    drawn in a panel of its own (sun, planets on the carrier circle, ring), stages in
    series one after the other, in power-flow order between the parallel shafts that
    drive them and those they drive.

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
    stage : dict or sequence of dict or tuple, optional
        A stage, or the stages in series: ``sun``, ``ring`` and ``planet`` pitch radii
        [m], ``centre`` (carrier radius, [m]), ``angles`` (planet angles [rad]) and
        ``teeth`` (z_s, z_p, z_r); optional ``input`` and ``output`` (the members on the
        joining shafts), ``fixed`` (the held member), ``shafts`` (member -> the shaft it
        sits on), named in the legend, and ``title`` of its panel; gears between two
        stages as a ``(shafts, gears, meshes)`` tuple between them.
    upstream : tuple, optional
        ``(shafts, gears, meshes)`` of gears driving the stage, as above.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into; default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        One column per part in power-flow order: plan view (mm, equal aspect) above the
        side view of the parallel shafts.
    """
    stages = [stage] if isinstance(stage, dict) else list(stage or ())
    panels: list[tuple[str, object]] = []
    if upstream is not None:
        panels.append(("up", upstream))
    panels += [("stage" if isinstance(st, dict) else "mid", st) for st in stages]
    if gears or not stages:
        panels.append(("down", (shafts, gears, meshes)))
    fig = figure_or_new(fig, 5.0 * len(panels) + 2.0, 10.0)
    axes = fig.subplots(2, len(panels), squeeze=False,
                        gridspec_kw={"height_ratios": [1.2, 1.0]})
    for ax, side, (kind, part) in zip(axes[0], axes[1], panels, strict=True):
        if kind == "stage":
            _stage(ax, part)
            side.set_axis_off()
        else:
            _chain(ax, *part)
            _side(side, *part)
            member = (stages[0] if kind == "up" else stages[-1]).get(
                "input" if kind == "up" else "output") if stages else None
            ax.set_title(title if not stages else "parallel shafts (between two stages)"
                         if kind == "mid" else "parallel shafts" if member is None else
                         f"parallel shafts ({'driving' if kind == 'up' else 'driven by'} the "
                         f"{member})")
            side.set_title("side view: gears in their planes along the shafts", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
    axes[0][0].set_ylabel("y [mm]")
    if stages:
        fig.suptitle(title)
    return fig
