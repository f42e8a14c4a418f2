"""Simulation results as NetCDF files that say how they were made.

:func:`write_results` writes an :class:`xarray.Dataset` with the h5netcdf engine to a
temporary file in the target's directory and moves it into place with ``os.replace``
(:func:`gearsim.io.atomic.atomic_write`), so a failed run never damages an existing
file. :func:`train_to_toml` writes the complete effective input (gears, operating point,
stiffness options, cracks, dynamics options) as TOML that :func:`gearsim.io.config.loads`
reads back, stored in the file's ``config`` attribute.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

from gearsim.io.atomic import atomic_write
from gearsim.system import GearTrain

__all__ = ["read_results", "train_to_toml", "write_results"]


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


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isinf(v) or math.isnan(v):
            raise ValueError(f"cannot write {v} to TOML")
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _table(lines: list[str], header: str, items: dict[str, Any]) -> None:
    lines.append("")
    lines.append(header)
    for k, v in items.items():
        if v is None:
            continue
        lines.append(f"{k} = {_value(v)}")


def train_to_toml(train: GearTrain, dynamics=None) -> str:
    """The effective configuration of ``train`` (and dynamics options) as TOML, SI units."""
    lines = ["# gearsim effective configuration (SI units: m, rad, rad/s, N m, Pa, s, Hz)",
             f"name = {_value(train.name)}"]
    for g in train.gears:
        _table(lines, "[[gears]]", {
            "name": g.name, "teeth": g.teeth, "normal_module": g.normal_module,
            "normal_pressure_angle": g.normal_pressure_angle,
            "helix_angle": abs(g.helix_angle), "face_width": g.face_width,
            "addendum_coefficient": g.addendum_coefficient,
            "dedendum_coefficient": g.dedendum_coefficient,
            "fillet_radius_coefficient": g.fillet_radius_coefficient,
            "profile_shift": g.profile_shift, "bore_radius": g.bore_radius})
        _table(lines, "[gears.material]", {
            "youngs_modulus": g.material.youngs_modulus,
            "poisson_ratio": g.material.poisson_ratio, "density": g.material.density})
    _table(lines, "[operating]", {"speed": train.operating.speed,
                                  "torque": train.operating.torque})
    st = train.stiffness
    _table(lines, "[stiffness]", {"closure": st.closure, "slices": st.slices,
                                  "positions_per_cycle": st.positions_per_cycle,
                                  "gauss_points": st.gauss_points, "plane": st.plane,
                                  "source": st.source})
    for c in train.cracks:
        _table(lines, "[[cracks]]", {"gear": c.gear, "tooth": c.tooth, "flank": c.flank,
                                     "depth": c.depth, "angle": c.angle, "extent": c.extent,
                                     "profile": c.profile, "start_radius": c.start_radius})
    if dynamics is not None:
        d = dynamics.to_dict()
        _table(lines, "[dynamics]", d)
    return "\n".join(lines) + "\n"
