"""Simulation results as NetCDF files that say how they were made.

:func:`write_results` writes an :class:`xarray.Dataset` with the h5netcdf engine to a
temporary file in the target's directory and moves it into place with ``os.replace``
(:func:`gearsim.io.atomic.atomic_write`), so a failed run never damages an existing
file. The complete effective input is stored in the file's ``config`` attribute
(:func:`gearsim.system.train_to_toml`).
"""

from __future__ import annotations

import os
from pathlib import Path

from gearsim.io.atomic import atomic_write

__all__ = ["read_results", "write_results"]


def write_results(ds, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` (NetCDF-4, h5netcdf engine) atomically."""
    def write(tmp: Path) -> None:
        ds.to_netcdf(tmp, engine="h5netcdf")
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the usual permissions

    return atomic_write(path, write)


def read_results(path: str | Path):
    """Open a results file written by :func:`write_results` (loaded into memory)."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()
