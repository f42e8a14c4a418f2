"""Mesh-stiffness table of the FE gear pair over a revolution, cached on disk.

:func:`fe_pair_mesh_stiffness` solves the FE gear pair (:class:`gearsim.fem.pair.
FEPairModel`, transverse section) at ``positions_per_cycle`` positions u = i / N of one
mesh cycle, the same grid as the potential-energy tables
(:func:`gearsim.stiffness.mesh.mesh_stiffness`), and repeats that cycle over the
revolution of gear 1 or 2. The result depends on the load (the contact widths and the
extended contact grow with it), so the table belongs to one torque.

Cache: ``$GEARSIM_CACHE/fe/pair-<key>.npz`` (:func:`gearsim.fem.tables.cache_dir`), the
key the SHA-256 of the pair geometry and materials, the torque, the positions, the mesh
level, the plane and :data:`PAIR_TABLE_VERSION`; written to a temporary file and renamed.
A cached table is returned in well under a second.
"""

from __future__ import annotations

import hashlib
import json
import math
import time

import numpy as np

from gearsim.errors import InputError, require
from gearsim.fem.pair import DEFAULT_LEVEL, FEPairModel
from gearsim.fem.tables import _write_npz, cache_dir
from gearsim.geometry.pair import GearPair
from gearsim.stiffness.mesh import MeshStiffness

__all__ = ["PAIR_TABLE_VERSION", "fe_pair_mesh_stiffness"]

#: Bump when the FE pair model changes so that old cache files are not reused.
PAIR_TABLE_VERSION = 1


def _gear_doc(g) -> list:
    return [g.teeth, g.normal_module, g.normal_pressure_angle, g.helix_angle,
            g.addendum_coefficient, g.dedendum_coefficient, g.fillet_radius_coefficient,
            g.profile_shift, g.bore_radius_value, g.face_width, g.material.youngs_modulus,
            g.material.poisson_ratio]


def _key(pair: GearPair, torque: float, npc: int, level: int, plane: str) -> str:
    doc = {"kind": "fe-pair", "v": PAIR_TABLE_VERSION, "driver": _gear_doc(pair.driver),
           "driven": _gear_doc(pair.driven), "offset": pair.centre_distance_offset,
           "torque": torque, "positions": npc, "level": level, "plane": plane}
    text = json.dumps(doc, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def fe_pair_mesh_stiffness(pair: GearPair, *, torque: float, cracks: tuple = (),
                           positions_per_cycle: int = 20, level: int = DEFAULT_LEVEL,
                           plane: str = "stress", revolution_of: int = 1,
                           use_cache: bool = True) -> MeshStiffness:
    """TVMS of the FE gear pair's transverse section over one revolution [N/m].

    Parameters
    ----------
    pair
        The gear pair (a helical pair: its transverse section, per unit face width times
        the face width).
    torque
        Driver torque [N m] (> 0: drive flanks).
    cracks
        Cracks of the pair (:class:`gearsim.stiffness.source.ToothCrack`); the FE pair
        table is for healthy gears (a crack is refused, naming ``cracks``).
    positions_per_cycle
        Positions u = i / N per mesh cycle solved by FE, 4 to 200.
    level
        FE mesh level (:class:`gearsim.fem.pair.FEPairModel`).
    plane
        ``"stress"`` or ``"strain"``.
    revolution_of
        1: over one revolution of the driver; 2: of the driven gear.
    use_cache
        Read and write the disk cache.

    Returns
    -------
    MeshStiffness
        ``k`` over z_1 (or z_2) cycles, ``cycles = i / N``; ``components`` empty (the FE
        pair does not split the compliance), ``pair_k`` the mesh (one column), ``attrs``
        with the FE options and the set-up and solve times.

    Raises
    ------
    InputError
        Bad positions, revolution, torque, level or plane, or a crack.
    """
    require(isinstance(positions_per_cycle, int) and 4 <= positions_per_cycle <= 200,
            "positions_per_cycle", positions_per_cycle, "must be an integer in [4, 200]")
    require(revolution_of in (1, 2), "revolution_of", revolution_of, "must be 1 or 2")
    require(math.isfinite(torque) and torque > 0, "torque", torque,
            "must be a finite driver torque > 0 N m")
    if cracks:
        raise InputError("cracks", len(cracks), "the FE pair table is for healthy gears")
    npc = positions_per_cycle
    path = cache_dir() / f"pair-{_key(pair, torque, npc, level, plane)}.npz"
    k_cycle = None
    if use_cache and path.exists():
        try:
            with np.load(path) as data:
                k_cycle = np.array(data["k"])
                seconds = float(data["seconds"])
        except (OSError, ValueError, KeyError):
            k_cycle = None  # unreadable: recompute and overwrite
    if k_cycle is None or k_cycle.size != npc:
        t0 = time.perf_counter()
        model = FEPairModel(pair, torque=torque, level=level, plane=plane)
        k_cycle = np.array([model.solve(i / npc).stiffness for i in range(npc)])
        seconds = time.perf_counter() - t0
        if use_cache:
            _write_npz(path, k=k_cycle, seconds=np.array(seconds))
    g1, g2 = pair.driver, pair.driven
    z_rev = g1.teeth if revolution_of == 1 else g2.teeth
    k = np.tile(k_cycle, z_rev)
    cycles = np.arange(k.size) / npc
    return MeshStiffness(
        name=pair.name, revolution_of=(g1.name if revolution_of == 1 else g2.name),
        cycles=cycles, theta1=2 * math.pi * cycles / g1.teeth,
        theta2=2 * math.pi * cycles / g2.teeth, k=k, components={},
        pair_k=k[:, None].copy(), pair_tooth1=np.zeros((k.size, 1), dtype=np.int64),
        pair_tooth2=np.zeros((k.size, 1), dtype=np.int64),
        attrs={"source": "fe-pair", "positions_per_cycle": npc, "level": level,
               "plane": plane, "torque": torque, "fe_seconds": seconds})
