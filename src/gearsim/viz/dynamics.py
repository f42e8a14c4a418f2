"""Figure of a dynamics run: mesh forces in time and their amplitude spectra."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gearsim.viz import pyplot

__all__ = ["plot_run"]


def plot_run(ds, path: str | Path, *, window: float | None = None) -> Path:
    """Mesh forces over time (first ``window`` s, default two input revolutions) and
    their amplitude spectra up to 5 f_m; writes a PNG and returns its path."""
    plt = pyplot()
    fs = float(ds.attrs["fs"])
    fm = float(ds.attrs["mesh_frequency"])
    fr1 = float(ds.attrs["shaft_frequency"][0])
    window = window or 2.0 / fr1
    names = [v for v in ds.data_vars if v.startswith("mesh_force_")]
    fig, axes = plt.subplots(len(names), 2, figsize=(11, 2.8 * len(names)), squeeze=False)
    t = ds["time"].values
    sel = t < t[0] + window
    for row, name in zip(axes, names, strict=True):
        x = ds[name].values
        row[0].plot(t[sel] - t[0], x[sel] / 1e3, lw=0.6)
        row[0].axhline(ds[name].attrs["static_force"] / 1e3, color="k", lw=0.8, ls="--")
        row[0].set_xlabel("time after transient [s]")
        row[0].set_ylabel(f"{name} [kN]")
        n = x.size
        spec = 2 * np.abs(np.fft.rfft((x - x.mean()) * np.hanning(n))) / np.sum(np.hanning(n))
        f = np.fft.rfftfreq(n, 1 / fs)
        keep = f < 5 * fm
        row[1].semilogy(f[keep], np.maximum(spec[keep], 1e-3), lw=0.6)
        row[1].set_xlabel("frequency [Hz]")
        row[1].set_ylabel("amplitude [N]")
    fig.suptitle(f"{ds.attrs['model']} model; cracks: {ds.attrs['cracks']}", fontsize=10)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out)
    plt.close(fig)
    return out
