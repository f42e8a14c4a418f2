"""Tooth compliance of the cracked sector of :mod:`gearsim.fracture.tooth` (polyline cracks).

The same 3-tooth sector, flank bell load and gmsh meshes as the stress intensity
factors, solved for the load-point compliance: with the load vector f of a unit force
per unit face width at contact radius r (:func:`gearsim.fracture.tooth._flank_load`),
c(r) = f . u / F^2 [m/N for a face width of 1 m], the work-conjugate displacement of
the load patch along the load. The patch (contact) and the fixed bore make c
differ from a tooth compliance measured away from the contact (:mod:`gearsim.fem.tooth`),
but the *added* compliance of a crack, dc = c(cracked) - c(healthy) on meshes of the
same sizes, is the crack's own: it compares a grown, curved crack (polyline) with a
straight crack (its chord), the crack of the potential-energy model. Crack faces are
free (the loaded fillet opens).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.fracture.mesh import CrackPath, mesh_cracked_polygon, mesh_polygon
from gearsim.fracture.tooth import (
    RING_FRACTION,
    _check_load,
    _flank_load,
    _insert_vertex,
    _sector_model,
    _tip_clearance,
    _with_crack_mouth,
    sector_polygon,
)
from gearsim.geometry.gear import Gear

__all__ = ["SectorCompliance", "sector_compliance"]


@dataclass(frozen=True)
class SectorCompliance:
    """Load-point compliance of the fracture sector at contact radii.

    Parameters
    ----------
    radii
        Contact radii [m].
    compliance
        c(r) for a face width of 1 m [m/N].
    dofs
        FE unknowns.
    seconds
        Wall time [s].
    """

    radii: np.ndarray
    compliance: np.ndarray
    dofs: int
    seconds: float


def sector_compliance(gear: Gear, radii, *, crack: CrackPath | None = None,
                      start: np.ndarray | None = None, n_teeth: int = 3,
                      plane: str = "stress", refinement: float = 1.0) -> SectorCompliance:
    """Load-point compliance of the sector, healthy or with a polyline root crack.

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii on the +x involute [m].
    crack
        The crack (from the +x fillet), or ``None`` for the healthy tooth.
    start
        For a healthy tooth, a fillet point refined like a crack mouth [m] (so that the
        healthy and cracked meshes have the same sizes there); default the crack start.
    n_teeth, plane, refinement
        As :func:`gearsim.fracture.tooth.tooth_crack_sif`.

    Returns
    -------
    SectorCompliance

    Raises
    ------
    InputError
        Radii off the involute, a crack that does not start on the outline, bad mesh
        parameters.
    """
    t0 = time.perf_counter()
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    for ri in r:
        _check_load(gear, float(ri), 1.0, refinement)
    poly, fixed = sector_polygon(gear, n_teeth)
    h = gear.normal_module / (4.0 * refinement)
    if crack is not None:
        poly = _with_crack_mouth(gear, poly, crack)
        r_out = RING_FRACTION * min(crack.last_segment_length(1), _tip_clearance(poly, crack))
        h_tip = r_out / (10.0 * refinement)
        cm = mesh_cracked_polygon(poly, crack, h=h, h_tip=h_tip, growth=0.3)
        p, t = cm.p, cm.t
    else:
        require(start is not None, "start", None, "a healthy sector needs the fillet point")
        pt = np.asarray(start, dtype=float)
        poly = _insert_vertex(poly, pt)
        p, t = mesh_polygon(poly, h=h, focus=pt[None, :], h_focus=h / 8.0, growth=0.3)
    model, fixed_dofs = _sector_model(gear, p, t, fixed, plane)
    loads = np.column_stack([_flank_load(model, gear, float(ri), 1.0, h) for ri in r])
    u = model.solve(loads, fixed_dofs)
    c = np.einsum("ij,ij->j", loads, u)
    return SectorCompliance(radii=r, compliance=c, dofs=model.ndofs,
                            seconds=time.perf_counter() - t0)
