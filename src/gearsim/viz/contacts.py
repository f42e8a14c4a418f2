"""Figures of the loaded tooth contact analysis (mesh of contacts)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from gearsim.stiffness.ltca import LoadedContact

__all__ = ["plot_loaded_contact"]


@styled
def plot_loaded_contact(lc: LoadedContact, *, cycles: float | None = None,
                        fig: Figure | None = None) -> Figure:
    """Loaded transmission error, load sharing and contact pattern of one mesh.

    Panels: (a) loaded and unloaded transmission error along the line of action [um]
    against the mesh cycle, positions without contact marked; (b) load share of each
    tooth pair; (c) contact pattern: the largest load per unit face width seen at each
    point of the flank (line of action x face width) [N/mm].

    Parameters
    ----------
    lc : gearsim.stiffness.ltca.LoadedContact
        Result of :func:`gearsim.stiffness.ltca.loaded_contact`.
    cycles : float, optional
        Mesh cycles shown in (a) and (b); default all (the contacts' period).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (three panels); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig = figure_or_new(fig, 13, 4.2)
    ax_te, ax_share, ax_pat = fig.subplots(1, 3)
    c = lc.grid.cycles
    sel = c <= cycles if cycles is not None else np.ones(c.size, dtype=bool)
    ax_te.plot(c[sel], lc.delta[sel] * 1e6, lw=1.0, label="loaded")
    ax_te.plot(c[sel], lc.unloaded[sel] * 1e6, lw=0.8, ls="--", label="unloaded")
    lost = sel & ~lc.contact
    if lost.any():
        ax_te.plot(c[lost], np.zeros(lost.sum()), "x", color="C3", label="no contact")
    ax_te.set_xlabel("mesh cycles [-]")
    ax_te.set_ylabel("transmission error, line of action [um]")
    ax_te.set_title(f"(a) mesh {lc.grid.name}, F = {lc.force / 1e3:.4g} kN")
    ax_te.legend(fontsize=8)
    share = lc.pair_share
    for m in range(share.shape[1]):
        if np.any(share[sel, m] > 0):
            ax_share.plot(c[sel], share[sel, m], lw=1.0)
    ax_share.set_xlabel("mesh cycles [-]")
    ax_share.set_ylabel("load share of each tooth pair [-]")
    ax_share.set_title("(b) load sharing")
    edges, zfrac, peak = lc.pattern()
    im = ax_pat.imshow(peak.T / 1e3, origin="lower", aspect="auto", cmap="viridis",
                       extent=(edges[0] * 1e3, edges[-1] * 1e3, 0.0, 1.0))
    fig.colorbar(im, ax=ax_pat, label="peak load per unit width [N/mm]")
    ax_pat.set_xlabel("position on the line of action from T1 [mm]")
    ax_pat.set_ylabel("face width z / b [-]")
    ax_pat.set_title("(c) contact pattern")
    return fig
