"""Mesh-stiffness table of the FE gear pair over a revolution, cached on disk.

:func:`fe_pair_mesh_stiffness` solves the FE gear pair (:class:`gearsim.fem.pair.
FEPairModel`, transverse section) at ``positions_per_cycle`` positions u = i / N of one
mesh cycle, the same grid as the potential-energy tables
(:func:`gearsim.stiffness.mesh.mesh_stiffness`), and repeats that cycle over the
revolution of gear 1 or 2. With a crack on tooth j of gear g, the cycles c in which that
tooth belongs to one of the model's tooth pairs (pair label k = c - j mod z_g, the
age of its pair as in the PE tables) are solved with the crack on that pair
(:class:`gearsim.fem.pair.PairCrack`; one FE model per label). The result depends on the
load (the contact widths and the extended contact grow with it), so the table belongs
to one torque.

Cache: ``$GEARSIM_CACHE/fe/pair-<key>.npz`` (:func:`gearsim.fem.tables.cache_dir`), the
key the SHA-256 of the pair geometry and materials, the torque, the positions, the mesh
level, the plane and :data:`PAIR_TABLE_VERSION`; written to a temporary file and renamed.
A cached table is returned in well under a second.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from gearsim.errors import require
from gearsim.fem.pair import DEFAULT_LEVEL, FEPairModel, PairCrack
from gearsim.fem.tables import _cache_key, _write_npz, cache_dir
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


def _key(pair: GearPair, torque: float, npc: int, level: int, plane: str,
         crack_doc, revolution_of: int) -> str:
    doc = {"kind": "fe-pair", "v": PAIR_TABLE_VERSION, "driver": _gear_doc(pair.driver),
           "driven": _gear_doc(pair.driven), "offset": pair.centre_distance_offset,
           "torque": torque, "positions": npc, "level": level, "plane": plane,
           "crack": crack_doc, "revolution_of": revolution_of if crack_doc else 0}
    return _cache_key(doc)[0]


def _label(c: int, tooth: int, z: int, teeth: tuple[int, ...]) -> int | None:
    """Pair label of tooth ``tooth`` of a gear with ``z`` teeth in cycle ``c`` (or None)."""
    r = (c - tooth) % z
    for k in (r, r - z):
        if k in teeth:
            return k
    return None


def fe_pair_mesh_stiffness(pair: GearPair, *, torque: float, cracks: tuple = (),
                           positions_per_cycle: int = 20, level: int = DEFAULT_LEVEL,
                           plane: str = "stress", revolution_of: int = 1,
                           closure: str = "contact", use_cache: bool = True) -> MeshStiffness:
    """TVMS of the FE gear pair's transverse section over one revolution [N/m].

    Parameters
    ----------
    pair
        The gear pair (a helical pair: its transverse section, per unit face width times
        the face width).
    torque
        Driver torque [N m] (> 0: drive flanks).
    cracks
        At most one crack (:class:`gearsim.stiffness.source.ToothCrack`: gear 1 or 2,
        the crack with its tooth, side +1 working / -1 non-working flank), uniform over
        the section.
    positions_per_cycle
        Positions u = i / N per mesh cycle solved by FE, 4 to 200.
    level
        FE mesh level (:class:`gearsim.fem.pair.FEPairModel`).
    plane
        ``"stress"`` or ``"strain"``.
    revolution_of
        1: over one revolution of the driver; 2: of the driven gear.
    closure
        Crack faces: ``"contact"`` (they carry compression) or ``"open"``.
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
        Bad positions, revolution, torque, level or plane, more than one crack, or a
        mesh too coarse for the crack (``fem.level``, with the level needed).
    """
    require(isinstance(positions_per_cycle, int) and 4 <= positions_per_cycle <= 200,
            "positions_per_cycle", positions_per_cycle, "must be an integer in [4, 200]")
    require(revolution_of in (1, 2), "revolution_of", revolution_of, "must be 1 or 2")
    require(math.isfinite(torque) and torque > 0, "torque", torque,
            "must be a finite driver torque > 0 N m")
    require(len(cracks) <= 1, "cracks", len(cracks), "the FE pair table takes at most "
            "one cracked tooth per mesh")
    npc = positions_per_cycle
    g1, g2 = pair.driver, pair.driven
    z_rev = g1.teeth if revolution_of == 1 else g2.teeth
    tc = cracks[0] if cracks else None
    crack_doc = None if tc is None else [tc.gear, tc.crack.tooth, tc.crack.depth,
                                         tc.crack.angle, tc.crack.start_radius, tc.side,
                                         closure]
    def table_path(doc) -> Path:
        return cache_dir() / f"pair-{_key(pair, torque, npc, level, plane, doc, revolution_of)}.npz"

    def cached(where: Path, size: int) -> tuple[np.ndarray, float] | None:
        if not (use_cache and where.exists()):
            return None
        try:
            with np.load(where) as data:
                found = np.array(data["k"]), float(data["seconds"])
        except (OSError, ValueError, KeyError):
            return None  # unreadable: recompute and overwrite
        return found if found[0].size == size else None

    path = table_path(crack_doc)
    hit = cached(path, npc if tc is None else z_rev * npc)
    k, seconds = hit if hit is not None else (None, 0.0)
    if k is None:
        t0 = time.perf_counter()
        # a cracked table's healthy cycles are the healthy table's (the same model and
        # solves): read from the cache when a healthy table was computed before, and then
        # the healthy model is not built (its tooth labels come from the geometry alone)
        healthy = cached(table_path(None), npc) if tc is not None else None
        if healthy is not None:
            k = healthy[0]
            labels = FEPairModel.tooth_labels(pair, torque=torque)
        else:
            model = FEPairModel(pair, torque=torque, level=level, plane=plane)
            k = np.array([model.solve(i / npc).stiffness for i in range(npc)])
            labels = model.teeth
        if tc is not None:
            z = g1.teeth if tc.gear == 1 else g2.teeth
            k = np.tile(k, z_rev)
            cracked: dict[int, np.ndarray] = {}
            for c in range(z_rev):
                lab = _label(c, tc.crack.tooth, z, labels)
                if lab is None:
                    continue
                if lab not in cracked:
                    cm = FEPairModel(pair, torque=torque, level=level, plane=plane,
                                     crack=PairCrack(gear=tc.gear, pair=lab, crack=tc.crack,
                                                     side=tc.side, closure=closure))
                    cracked[lab] = np.array([cm.solve(i / npc).stiffness
                                             for i in range(npc)])
                k[c * npc:(c + 1) * npc] = cracked[lab]
        seconds = time.perf_counter() - t0
        if use_cache:
            _write_npz(path, k=k, seconds=np.array(seconds))
    if k.size == npc:
        k = np.tile(k, z_rev)
    return MeshStiffness.whole_mesh(
        pair, revolution_of, npc, k,
        {"source": "fe-pair", "positions_per_cycle": npc, "level": level, "plane": plane,
         "torque": torque, "fe_seconds": seconds,
         "closure": closure if tc is not None else "none"})
