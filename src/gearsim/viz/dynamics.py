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
        Results of :func:`gearsim.dynamics.simulate` (variables ``mesh_force_*``).
    window : float, optional
        Length of the time view [s]; default two revolutions of the input shaft.
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (one row of two panels per mesh); default a new one.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fs = float(ds.attrs["fs"])
    fm = float(ds.attrs["mesh_frequency"])
    fr1 = float(np.atleast_1d(ds.attrs["shaft_frequency"])[0])
    window = window or 2.0 / fr1
    names = [v for v in ds.data_vars if str(v).startswith("mesh_force_")]
    fig = figure_or_new(fig, 11, 2.8 * len(names) + 0.4)
    axes = fig.subplots(len(names), 2, squeeze=False)
    t = ds["time"].values
    sel = t < t[0] + window
    for row, name in zip(axes, names, strict=True):
        x = ds[name].values
        row[0].plot(t[sel] - t[0], x[sel] / 1e3, lw=0.6, label="mesh force")
        row[0].axhline(ds[name].attrs["static_force"] / 1e3, color="k", lw=0.8, ls="--",
                       label="static force")
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
    fig.suptitle(f"{ds.attrs['model']} model; cracks: {ds.attrs['cracks']}", fontsize=10)
    return fig
