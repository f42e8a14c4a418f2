"""Stiffness of every mesh of a train: tables, summary and file output."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from gearsim._version import __version__
from gearsim.errors import InputError
from gearsim.io.atomic import atomic_write
from gearsim.stiffness.iso6336 import mean_mesh_stiffness
from gearsim.stiffness.mesh import COMPONENTS, MeshStiffness
from gearsim.system.train import GearTrain

__all__ = ["TrainStiffness", "train_stiffness"]


@dataclass
class TrainStiffness:
    """TVMS of each mesh over one revolution of each of its two gears.

    Parameters
    ----------
    train : GearTrain
        The train.
    results : dict
        ``(mesh index, 1 | 2) -> MeshStiffness``: over one revolution of the mesh's
        driver (1) or driven gear (2).
    """

    train: GearTrain
    results: dict[tuple[int, int], MeshStiffness]  # (mesh, 1|2) -> result

    def summary(self) -> dict:
        """Per mesh: max, min, mean stiffness [N/m], contact ratios, ISO 6336-1's
        c_gamma_alpha b at the static line load F_t / b [N/m] and the ratio to it."""
        out = {"name": self.train.name, "gearsim_version": __version__, "meshes": []}
        for i, pair in enumerate(self.train.pairs):
            r = self.results[(i, 1)]
            # ISO's nominal tangential load on the reference circle: F_bt cos(alpha_t)
            f_t = self.train.static_mesh_force(i) * math.cos(pair.driver.transverse_pressure_angle)
            w = f_t / pair.face_width
            iso = mean_mesh_stiffness(pair, w)
            out["meshes"].append({
                "mesh": pair.name,
                "gears": [pair.driver.name, pair.driven.name],
                "k_max": float(r.k.max()), "k_min": float(r.k.min()),
                "k_mean": float(r.k.mean()),
                "eps_alpha": pair.transverse_contact_ratio,
                "eps_beta": pair.overlap_ratio,
                "iso6336_c_gamma_alpha_b": iso, "iso6336_line_load": w,
                "ratio_to_iso6336": float(r.k.mean()) / iso,
                "units": "N/m (transverse plane, along the line of action)",
            })
        return out

    def to_table(self) -> list[dict]:
        """Long-format rows: mesh, revolution_of, position, angles, k and components."""
        rows = []
        for (i, _rev), r in self.results.items():
            for j in range(r.k.size):
                row = {"mesh": self.train.pairs[i].name, "revolution_of": r.revolution_of,
                       "cycle": r.cycles[j], "theta1_deg": math.degrees(r.theta1[j]),
                       "theta2_deg": math.degrees(r.theta2[j]), "k": r.k[j]}
                for c in COMPONENTS:  # the FE pair source has no component split
                    row[f"k_{c}"] = r.components[c][j] if c in r.components else math.nan
                rows.append(row)
        return rows

    def plot(self, mesh: int | None = None, *, ax=None, fig=None):
        """TVMS figure (see :func:`gearsim.viz.stiffness.plot`).

        Parameters
        ----------
        mesh : int, optional
            One mesh in one panel (drawn into ``ax``); default every mesh with its load
            sharing (drawn into ``fig``).
        ax : matplotlib.axes.Axes, optional
            Axes to draw into, with ``mesh``.
        fig : matplotlib.figure.Figure, optional
            Figure to draw into, without ``mesh``.

        Returns
        -------
        matplotlib.figure.Figure
            The figure; write it with :func:`gearsim.viz.save`.
        """
        from gearsim.viz.stiffness import plot

        return plot(self, mesh, ax=ax, fig=fig)

    def write(self, path: str | Path) -> Path:
        """Write CSV (``.csv``) or NetCDF (``.nc``), atomically.

        Parameters
        ----------
        path : str or Path
            Output file; its suffix chooses the format.

        Returns
        -------
        Path

        Raises
        ------
        InputError
            For another suffix.
        """
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".csv":
            rows = self.to_table()
            cols = list(rows[0])

            def w(tmp: Path) -> None:
                with open(tmp, "w", encoding="utf-8") as f:
                    f.write(f"# gearsim {__version__} TVMS of '{self.train.name}'; "
                            "stiffness in N/m (transverse), angles in degrees\n")
                    f.write(",".join(cols) + "\n")
                    for row in rows:
                        f.write(",".join(str(row[c]) if isinstance(row[c], str)
                                         else f"{row[c]:.10g}" for c in cols) + "\n")
            return atomic_write(path, w)
        if suffix in (".nc", ".netcdf"):
            import xarray as xr

            sets = []
            for (i, rev), r in self.results.items():
                ds = r.to_dataset()
                ds = ds.rename({v: f"mesh{i + 1}_rev{rev}_{v}" for v in ds.data_vars})
                ds = ds.rename({"position": f"position_mesh{i + 1}_rev{rev}",
                                "cycles": f"cycles_mesh{i + 1}_rev{rev}",
                                "pair": f"pair_mesh{i + 1}_rev{rev}"})
                ds.attrs = {}
                sets.append(ds)
            out = xr.merge(sets)
            out.attrs.update({"gearsim_version": __version__, "train": self.train.name,
                              "closure": self.train.stiffness.closure})
            from gearsim.io.results import write_results

            return write_results(out, path)
        raise InputError("--out", str(path), "must end in .csv or .nc")


def train_stiffness(train: GearTrain) -> TrainStiffness:
    """TVMS of every mesh over one revolution of each of its gears.

    Parameters
    ----------
    train : GearTrain
        The train; its stiffness options and source apply.

    Returns
    -------
    TrainStiffness
    """
    res = {}
    for i in range(len(train.pairs)):
        for rev in (1, 2):
            res[(i, rev)] = train.mesh_stiffness(i, revolution_of=rev)
    return TrainStiffness(train=train, results=res)

