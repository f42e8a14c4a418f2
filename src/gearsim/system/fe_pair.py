"""The FE gear pair as the stiffness source of a train (``stiffness.source = "fe-pair"``).

The seed's rigid-flexible route: the mesh stiffness of each mesh comes from the
finite-element gear pair in contact (:mod:`gearsim.fem.pair`) at the mesh's static load,
instead of the potential-energy (``"pe"``) or FE single-tooth (``"fe"``) compliance in
the slicing model. The FE pair models the transverse section; the TVMS of that section,
k_2D(u) over one revolution (healthy cycles from one solved cycle, the cycles in which a
cracked tooth is engaged solved with the crack), is computed at
``stiffness.fe_pair_positions`` positions per cycle and cached
(:func:`gearsim.fem.pair_table.fe_pair_mesh_stiffness`, mesh level
:data:`FE_PAIR_LEVEL`). A helical mesh is then sliced as the
potential-energy model is (docs/stiffness.md, section 4): the slice at axial position z
touches a phase z tan(beta_b) / p_b later along the line of action, so

    k(u) = (1 / N) sum_j k_2D(u - z_j tan(beta_b) / p_b),   z_j = (j + 1/2) b / N,

with k_2D interpolated linearly and periodically over the revolution and evaluated at
the ``positions_per_cycle`` positions of the dynamics tables. A spur mesh is the
section itself, interpolated to those positions.

The FE pair's stiffness depends on the load (wider contacts and extended contact at
higher torque), so the table belongs to the train's operating torque. It carries the
whole mesh: the per-pair split and the component split of the slicing model are not
given (``components`` empty, ``pair_k`` one column, the mesh). The mesh of contacts
(faults other than cracks, modifications, eccentricity) needs a tooth model and refuses
this source.
"""

from __future__ import annotations

import math

import numpy as np

from gearsim.fem.pair_table import fe_pair_mesh_stiffness
from gearsim.stiffness.mesh import MeshStiffness
from gearsim.stiffness.settings import StiffnessSettings

__all__ = ["FE_PAIR_LEVEL", "fe_pair_train_stiffness"]

#: FE mesh level of the stiffness tables of this route. Level 1 differs from the default
#: level 2 of the FE pair by 0.06-0.24 % on the 19/48 pair and 0.1 % on Table-1 mesh I at
#: 4876 N m (docs/fem.md, convergence) at a quarter of the cost (0.3 s against 1.5 s per
#: position on mesh I); at a quarter of that torque the Hertz half width (about 100 um) is
#: close to level 1's contact element (94 um), and level 1 is 0.3-0.65 % too soft
#: (docs/stiffness.md, section 4c).
FE_PAIR_LEVEL = 1


def fe_pair_train_stiffness(train, mesh: int, *, revolution_of: int = 1,
                            settings: StiffnessSettings | None = None) -> MeshStiffness:
    """TVMS of mesh ``mesh`` of ``train`` from the FE gear pair (module docstring).

    Parameters
    ----------
    train : GearTrain
        The train (gears, operating torque, cracks).
    mesh : int
        Mesh index (0 = mesh I).
    revolution_of : {1, 2}
        Over one revolution of the driver (1) or of the driven gear (2).
    settings : StiffnessSettings, optional
        ``positions_per_cycle`` of the table, ``slices``, ``plane`` and
        ``fe_pair_positions``; default the mesh's own.

    Returns
    -------
    MeshStiffness
        Stiffness along the transverse line of action [N/m] over one revolution.

    Notes
    -----
    :class:`~gearsim.system.train.GearTrain` refuses, when it is made, a crack that does
    not span the face width uniformly and faults other than cracks with this source.
    """
    settings = settings or train.settings_of(mesh)
    pair = train.pairs[mesh]
    cracks = train.mesh_cracks(mesh)
    section = fe_pair_mesh_stiffness(pair, torque=train.mesh_torque(mesh), cracks=cracks,
                                     positions_per_cycle=settings.fe_pair_positions,
                                     level=FE_PAIR_LEVEL, plane=settings.plane,
                                     revolution_of=revolution_of, closure=settings.closure)
    g1, g2 = pair.driver, pair.driven
    z_rev = g1.teeth if revolution_of == 1 else g2.teeth
    npc = settings.positions_per_cycle
    cycles = np.arange(z_rev * npc) / npc
    tb = math.tan(g1.base_helix_angle)
    ns = settings.slices if tb > 0 else 1
    shifts = (np.arange(ns) + 0.5) / ns * pair.face_width * tb / pair.base_pitch
    xp = np.asarray(section.cycles, dtype=float)
    fp = np.asarray(section.k, dtype=float)
    k = np.zeros(cycles.size)
    for s in shifts:
        k += np.interp(cycles - s, xp, fp, period=float(z_rev))
    k /= ns
    attrs = dict(section.attrs)
    attrs.update({"source": "fe-pair", "positions_per_cycle": npc, "slices": ns,
                  "fe_pair_positions": settings.fe_pair_positions,
                  "torque": train.mesh_torque(mesh), "plane": settings.plane})
    return MeshStiffness.whole_mesh(pair, revolution_of, npc, k, attrs)
