"""The main job of ``make run`` on the built-in Table-1 idler train.

Until the full reproduction of the seed study is available it computes the TVMS of
both meshes, healthy and with the example crack on the working and on the non-working
flank of the input gear (closure models ``open`` and ``contact``), writes the tables and
figures, and returns the path of the summary.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

from gearsim.io.atomic import atomic_write
from gearsim.io.config import load
from gearsim.stiffness.report import train_stiffness

__all__ = ["run_default_job"]


def run_default_job(out: str | Path) -> Path:
    """Compute and plot the Table-1 TVMS cases into folder ``out``; return the summary path."""
    from gearsim.viz.stiffness import plot_healthy_vs_cracked, plot_train_stiffness

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    base = load("idler-table1")
    healthy = train_stiffness(base.with_cracks(()))
    healthy.write(out / "tvms_healthy.nc")
    healthy.write(out / "tvms_healthy.csv")
    plot_train_stiffness(healthy, out / "tvms_healthy.png")
    summary = {"healthy": healthy.summary(), "cracked": {}}
    curves = {"healthy": (math.degrees(1) * healthy.results[(0, 1)].theta1,
                          healthy.results[(0, 1)].k)}
    for closure in ("open", "contact"):
        for flank in ("working", "non-working"):
            tr = dataclasses.replace(
                base, stiffness=dataclasses.replace(base.stiffness, closure=closure),
                cracks=tuple(dataclasses.replace(c, flank=flank) for c in base.cracks))
            r = tr.mesh_stiffness(0, revolution_of=1)
            label = f"{flank} flank, {closure}"
            curves[label] = (math.degrees(1) * r.theta1, r.k)
            summary["cracked"][label] = {"k_min": float(r.k.min()), "k_mean": float(r.k.mean())}
    crack = base.cracks[0]
    plot_healthy_vs_cracked(
        curves, out / "tvms_cracked_mesh1.png",
        title=f"mesh I, crack on input tooth 0: depth {crack.depth * 1e3:.3g} mm, "
              f"{math.degrees(crack.angle):.0f} deg",
        xlabel="rotation of the input gear [deg]")
    path = out / "summary.json"
    atomic_write(path, lambda p: p.write_text(json.dumps(summary, indent=2)))
    return path
