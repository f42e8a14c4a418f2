"""Mesh-stiffness tables for the integrator: k against the mesh-cycle coordinate.

For each mesh the table covers one period of its stiffness in mesh cycles:

* no crack on either gear: one mesh cycle (all teeth alike);
* a crack on the driver (driven) gear only: one revolution of that gear, z1 (z2) cycles,
  so the cracked tooth appears once per revolution of its gear;
* cracks on both gears: lcm(z1, z2) cycles, built from the two single-gear tables as
  ``k = k_1(c) + k_2(c) - k_healthy(c)`` (additive stiffness losses; exact while the two
  cracked teeth are never in contact at the same time, an approximation otherwise).

The kernel interpolates linearly and periodically in the cycle coordinate
``c = f_m t + phase``.

A mesh whose contacts have separations (modifications, pitch errors, spalls, broken
teeth, ...; :mod:`gearsim.stiffness.contacts`) carries its mesh of contacts instead: the
table ``k`` is still the sum of every contact's stiffness; ``k_zero`` the sum over the
contacts with zero separation, and the other contacts are listed per position (``ptr``,
``kx``, ``sx``, each position's list sorted by separation). The kernel evaluates
F = k_zero max(0, delta) + sum_j k_j max(0, delta - s_j) at the two tabulated
positions around c and interpolates the forces linearly
(docs/contacts.md). Any crack combination on a contact mesh is exact (its period is
lcm(z1, z2) when both gears differ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.system import GearTrain
from gearsim.system.memo import Memo

__all__ = ["MeshTable", "contact_table", "mesh_tables"]


@dataclass(frozen=True)
class MeshTable:
    """Periodic table of the transverse mesh stiffness of one mesh.

    Sample j is at the mesh-cycle coordinate ``c = j / positions_per_cycle``; the table
    repeats after ``period`` cycles (``k.size == period * positions_per_cycle``).

    Parameters
    ----------
    k : ndarray
        Stiffness samples [N/m] (transverse, along the transverse line of action).
    positions_per_cycle : int
        Samples per mesh cycle.
    period : int
        Table period [mesh cycles]: 1, the teeth z of the cracked gear, or lcm(z1, z2).
    k_zero : ndarray, optional
        Mesh of contacts only: summed stiffness of the contacts with zero separation at
        each sample [N/m].
    ptr : ndarray of int, optional
        Mesh of contacts only: contacts of sample j are ``kx[ptr[j]:ptr[j + 1]]``.
    kx, sx : ndarray, optional
        Stiffness [N/m] and separation [m] of the listed contacts.
    dk_da : ndarray, optional
        Derivative of the stiffness with the operating centre distance [N/m per m], on the
        samples of ``k`` (:func:`centre_distance_derivative`); ``None``: not used.
    """

    k: np.ndarray
    positions_per_cycle: int
    period: int
    k_zero: np.ndarray | None = None
    ptr: np.ndarray | None = None
    kx: np.ndarray | None = None
    sx: np.ndarray | None = None
    dk_da: np.ndarray | None = None

    @property
    def has_contacts(self) -> bool:
        """True when the mesh is a mesh of contacts with separations."""
        return self.k_zero is not None

    @property
    def mean(self) -> float:
        """Mean stiffness over the period [N/m]."""
        return float(np.mean(self.k))

    @property
    def max(self) -> float:
        """Largest tabulated stiffness [N/m] (sets the RK4 step limit)."""
        return float(np.max(self.k))

    def __call__(self, cycles: np.ndarray) -> np.ndarray:
        """Linear periodic interpolation at mesh-cycle coordinates ``cycles`` [N/m]."""
        n = self.k.size
        pos = np.mod(np.asarray(cycles, dtype=float), self.period) * self.positions_per_cycle
        i = np.floor(pos).astype(np.int64)
        w = pos - i
        i %= n
        return self.k[i] * (1.0 - w) + self.k[(i + 1) % n] * w


#: Samples per mesh cycle of the centre-distance derivative before it is averaged onto a
#: table's samples: a 20 um change moves the contact jumps by about 0.005 cycle, far
#: below the 0.025-cycle spacing of a 40-sample table.
FINE_POSITIONS = 2000
#: dk/da results kept in memory (least recently used dropped first): the cases of a study
#: that differ in crack, fault, speed or noise (or torque, under a load-independent
#: contact law) share the healthy derivative instead of recomputing it (two healthy
#: tables at FINE_POSITIONS per cycle, 5-15 s of CPU per mesh).
DERIVATIVE_CACHE_SIZE = 16
_DERIVATIVES = Memo(DERIVATIVE_CACHE_SIZE)


def centre_distance_derivative(train: GearTrain, mesh: int, table: MeshTable,
                               step: float) -> np.ndarray:
    """dk/da of mesh ``mesh`` on the samples of ``table`` [N/m per m].

    Pulling the gears apart by da moves the working pressure angle (cos alpha_wt =
    (r_b1 + r_b2) / a), the start of contact A by da / sin(alpha_wt) along the line of
    action, and, for a fixed rotation, every contact point by r_b1 d alpha_wt: each tooth
    pair enters later and leaves earlier (:class:`gearsim.geometry.pair.GearPair`,
    ``centre_distance_offset``). The healthy TVMS is computed at offsets +-``step`` with
    :data:`FINE_POSITIONS` samples per cycle, brought to the nominal cycle coordinate
    (shifted by ((l_A' - l_A) - r_b1 (alpha_wt' - alpha_wt)) / p_b), differenced, and
    averaged over each sample interval of ``table`` (which keeps the area of the narrow
    peaks at the contact jumps: the change of the mean stiffness). Cracks are left out
    (a second-order interplay).

    Parameters
    ----------
    train : GearTrain
        The train.
    mesh : int
        Mesh index.
    table : MeshTable
        The mesh's table (sampling and period of the result).
    step : float
        Centre-distance step of the central difference [m] (> 0).

    Returns
    -------
    ndarray
        dk/da on the samples of ``table`` [N/m^2].
    """
    import dataclasses

    from gearsim.stiffness.mesh import mesh_stiffness
    from gearsim.system.train import body_coupling, tooth_compliance

    pair = train.pairs[mesh]
    force = train.static_mesh_force(mesh)
    # everything the result depends on (the force only under the line contact law)
    own = train.settings_of(mesh)
    key = (pair, own, force if own.contact == "line" else None,
           float(step), table.positions_per_cycle, table.period)
    hit = _DERIVATIVES.get(key)
    if hit is not None:
        return hit.copy()
    st = dataclasses.replace(own, positions_per_cycle=FINE_POSITIONS)
    fine = np.arange(FINE_POSITIONS) / FINE_POSITIONS  # nominal cycles of one mesh cycle
    ks = []
    for h in (step, -step):
        q = dataclasses.replace(pair, centre_distance_offset=h)
        k = mesh_stiffness(q, settings=st, compliance=tooth_compliance(st.source),
                           force=force, coupling=body_coupling(st)).k
        k = k[:FINE_POSITIONS]
        shift = ((q.start_of_contact - pair.start_of_contact) - pair.driver.base_radius
                 * (q.working_pressure_angle - pair.working_pressure_angle)) / pair.base_pitch
        c = np.mod(fine - shift, 1.0) * FINE_POSITIONS
        i = np.floor(c).astype(int) % FINE_POSITIONS
        w = c - np.floor(c)
        ks.append(k[i] * (1 - w) + k[(i + 1) % FINE_POSITIONS] * w)
    d = (ks[0] - ks[1]) / (2 * step)
    npc = table.positions_per_cycle
    per = FINE_POSITIONS // npc if FINE_POSITIONS % npc == 0 else None
    if per is not None:  # sample interval [j, j + 1) / npc averaged (centred on sample j)
        rolled = np.roll(d, per // 2)
        avg = rolled.reshape(npc, per).mean(axis=1)
    else:
        edges = np.arange(npc + 1) / npc - 0.5 / npc
        avg = np.array([d[(np.mod(fine - a, 1.0) < b - a)].mean()
                        for a, b in zip(edges[:-1], edges[1:], strict=True)])
    out = np.tile(avg, table.period)
    _DERIVATIVES.put(key, out.copy())
    return out


def contact_table(grid) -> MeshTable:
    """The kernel table of a mesh of contacts.

    Parameters
    ----------
    grid : gearsim.stiffness.contacts.ContactGrid
        Contacts of the mesh.

    Returns
    -------
    MeshTable
        ``k`` the summed stiffness, ``k_zero`` that of the zero-separation contacts,
        the others listed per position.
    """
    n = grid.k.shape[0]
    k = grid.k.reshape(n, -1)
    s = grid.s.reshape(n, -1)
    zero = (k > 0) & (s == 0)
    listed = (k > 0) & (s != 0)
    counts = listed.sum(axis=1)
    ptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    # each row sorted by separation: the kernel stops at the first open contact
    key = np.where(listed, s, np.inf)
    order = np.argsort(key, axis=1, kind="stable")
    ks = np.take_along_axis(k, order, axis=1)
    ss = np.take_along_axis(s, order, axis=1)
    first = np.arange(k.shape[1])[None, :] < counts[:, None]
    return MeshTable(k=np.ascontiguousarray(k.sum(axis=1)),
                     positions_per_cycle=grid.positions_per_cycle, period=grid.period,
                     k_zero=np.ascontiguousarray(np.where(zero, k, 0.0).sum(axis=1)),
                     ptr=ptr, kx=np.ascontiguousarray(ks[first]),
                     sx=np.ascontiguousarray(ss[first]))


def mesh_tables(train: GearTrain, *, contacts: bool = False) -> tuple[MeshTable, ...]:
    """Stiffness tables of every mesh of ``train`` (see the module docstring).

    Computed with :meth:`GearTrain.mesh_stiffness` (its stiffness options and cracks):
    one mesh cycle for a healthy mesh, one revolution of the cracked gear, or
    lcm(z1, z2) cycles built as k_1 + k_2 - k_healthy when both gears are cracked.

    A mesh whose contacts are changed by faults, modifications or errors
    (:meth:`GearTrain.has_contact_changes`), or every mesh with ``contacts=True``, gets
    the table of its mesh of contacts (:func:`contact_table`).

    Parameters
    ----------
    train : GearTrain
        Gear chain with its cracks and stiffness options.
    contacts : bool
        Use the mesh of contacts for every mesh (with zero separations it gives the same
        forces as the stiffness table).

    Returns
    -------
    tuple of MeshTable
        One table per mesh, in mesh order [N/m].
    """
    out = []
    for i, pair in enumerate(train.pairs):
        if contacts or train.has_contact_changes(i):
            out.append(contact_table(train.mesh_contacts(i)))
            continue
        cracks = train.mesh_cracks(i)
        on1 = any(c.gear == 1 for c in cracks)
        on2 = any(c.gear == 2 for c in cracks)
        z1, z2 = pair.driver.teeth, pair.driven.teeth
        if on1 and on2:
            ms1 = train.with_cracks(tuple(c.crack for c in cracks if c.gear == 1))
            ms2 = train.with_cracks(tuple(c.crack for c in cracks if c.gear == 2))
            t1 = ms1.mesh_stiffness(i, revolution_of=1)
            t2 = ms2.mesh_stiffness(i, revolution_of=2)
            npc = int(t1.attrs["positions_per_cycle"])
            healthy = train.with_cracks(()).mesh_stiffness(i).k[:npc]
            period = math.lcm(z1, z2)
            idx = np.arange(period * npc)
            k = t1.k[idx % t1.k.size] + t2.k[idx % t2.k.size] - healthy[idx % npc]
        elif on1 or on2:
            ms = train.mesh_stiffness(i, revolution_of=1 if on1 else 2)
            npc = int(ms.attrs["positions_per_cycle"])
            period = z1 if on1 else z2
            k = ms.k
        else:
            ms = train.mesh_stiffness(i, revolution_of=1)
            npc = int(ms.attrs["positions_per_cycle"])
            period = 1
            k = ms.k[:npc]
        out.append(MeshTable(k=np.ascontiguousarray(k, dtype=float),
                             positions_per_cycle=npc, period=period))
    return tuple(out)
