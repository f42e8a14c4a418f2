"""Figure of a dynamics run: mesh forces in time and their amplitude spectra."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gearsim.viz.style import figure_or_new, styled

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["plot_run"]


@styled
def plot_run(ds: xr.Dataset, *, window: float | None = None, fig: Figure | None = None) -> Figure:
    """Mesh forces over time and their amplitude spectra up to 5 f_m.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :meth:`gearsim.model.Gearbox.simulate`: gears (``mesh_force_*``) or a
        stage (``mesh_force`` over ``mesh``, ``chain_mesh_force`` over ``chain_mesh``).
    window : float, optional
        Length of the time view [s]; default two revolutions of the input shaft (of
        the carrier for a stage).
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one row of two panels per mesh); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fs = float(ds.attrs["fs"])
    fm = float(ds.attrs["mesh_frequency"])
    fr1 = float(np.atleast_1d(ds.attrs.get("shaft_frequency", ds.attrs.get(
        "carrier_frequency", 0.0)))[0]) or fm
    window = window or 2.0 / fr1
    forces = [(v, ds[v].values, ds[v].attrs["static_force"]) for v in ds.data_vars
              if str(v).startswith("mesh_force_")]
    for var, dim, static in (("mesh_force", "mesh", "static_mesh_force"),
                             ("chain_mesh_force", "chain_mesh", "chain_static_mesh_force")):
        if var in ds:
            forces += [(str(m), ds[var].values[:, i], np.atleast_1d(ds.attrs[static])[
                min(i, np.size(ds.attrs[static]) - 1)]) for i, m in enumerate(ds[dim].values)]
    fig = figure_or_new(fig, 11, 2.8 * len(forces) + 0.4)
    axes = fig.subplots(len(forces), 2, squeeze=False)
    t = ds["time"].values
    sel = t < t[0] + window
    for row, (name, x, static) in zip(axes, forces, strict=True):
        row[0].plot(t[sel] - t[0], x[sel] / 1e3, lw=0.6, label="mesh force")
        row[0].axhline(static / 1e3, color="k", lw=0.8, ls="--", label="static force")
        row[0].set_xlabel("time after transient [s]")
        row[0].set_ylabel(f"{name} [kN]")
        row[0].legend(loc="upper right", fontsize=8)
        n = x.size
        spec = 2 * np.abs(np.fft.rfft((x - x.mean()) * np.hanning(n))) / np.sum(np.hanning(n))
        f = np.fft.rfftfreq(n, 1 / fs)
        keep = f < 5 * fm
        row[1].semilogy(f[keep], np.maximum(spec[keep], 1e-3), lw=0.6)
        row[1].set_xlabel("frequency [Hz]")
        row[1].set_ylabel("amplitude [N]")
    fig.suptitle(f"{ds.attrs.get('model', 'lta')} model; cracks: {ds.attrs['cracks']}",
                 fontsize=10)
    return fig
