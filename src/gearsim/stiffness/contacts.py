"""A mesh made of contacts: one spring per tooth pair, face-width slice and surface layer.

Each tooth pair in potential contact, and each transverse slice of it (helical gears;
slicing as in :mod:`gearsim.stiffness.mesh`), is a spring j with its own stiffness k_j(c)
and its own no-load separation s_j(c) along the transverse line of action, functions of
the mesh-cycle coordinate c. The mesh force for a deflection delta (driver ahead of
driven, along the transverse line of action) is

    F(c, delta) = sum_j k_j(c) max(0, delta - s_j(c))                         [N]

(docs/contacts.md). The stiffness of a slice is its carried face width times the
series compliance of the contact and both teeth per unit width (the tooth model of
:mod:`gearsim.stiffness.source`; the contact law and body coupling of the tables,
:func:`gearsim.stiffness.mesh.pair_law`, linearised at the static force: seed Hertz by
default, or the 2D line contact and the FE coupling); its separation is the sum over both
flanks of profile and lead modifications, pitch position deviations and wear
(:mod:`gearsim.stiffness.modifications`, :mod:`gearsim.stiffness.faults`). A slice
partly covered by a spall or pits is split into two springs, the intact part at s_j and
the recessed part at s_j + depth ("layer" 1); the part of a slice over missing material
(chipped corner, broken tooth) is dropped. With zero separations and no faults the sum
of the k_j is exactly the TVMS of :func:`gearsim.stiffness.mesh.mesh_stiffness`.

Optionally (``corner=True``) the pair that has not yet entered the path of contact and
the pair that has just left it are springs too: out of the path, the driven tooth's tip
corner (incoming pair) or the driver's tip corner (outgoing pair) touches the mating
involute once the relative rotation, in line-of-action units, exceeds the corner
separation of :func:`gearsim.geometry.corners.corner_separation`. They carry load when contact is lost
elsewhere (a broken tooth) and near the ends of the path under load: the "extended
contact" of loaded gears. Under the seed's contact law a corner spring is the seed's
Hertz contact and the teeth at the path end; under the line contact law it is the
tables' corner law (:func:`gearsim.stiffness.mesh.extended_law`: the line contact and
the teeth of the path end, separation and closing rate in the FE pair's position
convention, :func:`gearsim.stiffness.mesh.corner_closing`), linearised at the
single-pair load per unit width F / b, with the body coupling of its neighbour condensed
into the spring (:func:`_condensed_corners`: the LTCA's springs are independent), and
the path contacts are point samples as the tables'
(:func:`gearsim.stiffness.mesh.extended_grid`: the corner makes the stiffness
continuous across A and E) instead of the in-path cell fractions of
:func:`gearsim.stiffness.mesh.in_path_fraction`, which the seed's law keeps.

References
----------
.. [Velex1996] P. Velex, M. Maatar, J. Sound Vib. 191 (1996) 629-660 (mesh as a set of
   contact springs with initial separations along the contact lines).
.. [Chaari2008] F. Chaari et al., Eur. J. Mech. A/Solids 27 (2008) 691-705 (spall and
   breakage as lost contact width).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import require
from gearsim.geometry.corners import corner_separation, tip_edge_offset
from gearsim.geometry.pair import GearPair
from gearsim.stiffness.faults import Patch
from gearsim.stiffness.mesh import (
    _tridiagonal_solve,
    adjacent_cross,
    centre_line_depth,
    corner_closing,
    crack_cross_factors,
    in_path_fraction,
    pair_law,
)
from gearsim.stiffness.modifications import Modification
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCompliance, ToothCrack
from gearsim.stiffness.tooth import hertz_stiffness, line_contact_compliance

__all__ = ["MAX_GRID", "ContactGrid", "FlankState", "contact_grid", "grid_period"]

#: Largest contact grid (positions x pairs x slices x layers) built in memory; a finer
#: grid is refused naming slices and positions (about 160 MB per array at the limit).
MAX_GRID = 20_000_000


@dataclass(frozen=True)
class FlankState:
    """What one mesh sees of the loaded flanks of one of its gears.

    Parameters
    ----------
    modification : Modification, optional
        Profile and lead modifications and pitch errors of the gear.
    positions : ndarray, optional
        Pitch position deviation of each tooth along the line of action [m]
        (:meth:`Modification.tooth_positions`); None: all zero.
    patches : dict of int to tuple of Patch
        Damaged patches of the loaded flank of each tooth (spall, pits, chip, broken).
    wear : dict of int to (ndarray, ndarray)
        Wear of the loaded flank: tooth -> (roll lengths [m], depths [m]); key -1 applies
        to every tooth.
    """

    modification: Modification | None = None
    positions: np.ndarray | None = None
    patches: dict[int, tuple[Patch, ...]] = field(default_factory=dict)
    wear: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    @property
    def varies(self) -> bool:
        """True when its teeth differ (faults, tooth-specific wear or pitch errors)."""
        pos = self.positions is not None and bool(np.any(self.positions != 0))
        return bool(self.patches) or any(k >= 0 for k in self.wear) or pos

    @property
    def empty(self) -> bool:
        """True when it adds nothing to the healthy, unmodified mesh."""
        m = self.modification
        mod = m is not None and any(getattr(m, a) != 0 for a in (
            "tip_relief", "root_relief", "crowning", "helix_slope"))
        return not (self.varies or mod or self.wear)

    def position(self, tooth: np.ndarray) -> np.ndarray:
        """Pitch position deviation of teeth ``tooth`` [m].

        Parameters
        ----------
        tooth : ndarray of int
            Tooth indices.

        Returns
        -------
        ndarray
        """
        if self.positions is None:
            return np.zeros(np.shape(tooth))
        return self.positions[tooth]

    def wear_depth(self, tooth: int, roll: np.ndarray) -> np.ndarray:
        """Wear depth of tooth ``tooth`` at roll lengths ``roll`` [m].

        Parameters
        ----------
        tooth : int
            Tooth index.
        roll : ndarray
            Roll lengths [m].

        Returns
        -------
        ndarray
        """
        out = np.zeros(np.shape(roll))
        for key in (-1, tooth):
            if key in self.wear:
                r, d = self.wear[key]
                out += np.interp(roll, r, d, left=0.0, right=0.0)
        return out


@dataclass
class ContactGrid:
    """Stiffness and separation of every contact of a mesh over ``period`` mesh cycles.

    Parameters
    ----------
    name : str
        Mesh name.
    positions_per_cycle : int
        Positions per mesh cycle.
    period : int
        Mesh cycles covered (the table repeats after it).
    k : ndarray, shape (n_pos, n_pair, n_slice, n_layer)
        Contact stiffness [N/m] (0: no contact).
    s : ndarray, shape (n_pos, n_pair, n_slice, n_layer)
        No-load separation [m] (meaningful where k > 0).
    tooth1, tooth2 : ndarray of int, shape (n_pos, n_pair)
        Driver and driven tooth of each pair.
    l : ndarray, shape (n_pos, n_pair, n_slice)
        Contact point on the transverse line of action, from T1 [m].
    zfrac : ndarray, shape (n_slice,)
        Slice centres / face width [-].
    slice_width : float
        Face width of one slice [m].
    base_radius2 : float
        Base radius of the driven gear [m] (transmission error as an angle).
    attrs : dict
        Settings it was computed with.
    """

    name: str
    positions_per_cycle: int
    period: int
    k: np.ndarray
    s: np.ndarray
    tooth1: np.ndarray
    tooth2: np.ndarray
    l: np.ndarray
    zfrac: np.ndarray
    slice_width: float
    base_radius2: float
    attrs: dict = field(default_factory=dict)

    @property
    def cycles(self) -> np.ndarray:
        """Mesh-cycle coordinate of each position [-]."""
        return np.arange(self.k.shape[0]) / self.positions_per_cycle

    @property
    def k_total(self) -> np.ndarray:
        """Sum of all contact stiffnesses at each position [N/m] (the TVMS when every
        contact is closed)."""
        return self.k.sum(axis=(1, 2, 3))

    @property
    def has_separations(self) -> bool:
        """True when some contact has a non-zero separation."""
        return bool(np.any((self.k > 0) & (self.s != 0)))


def grid_period(pair: GearPair, varies1: bool, varies2: bool) -> int:
    """Mesh cycles after which the contacts repeat [-].

    1 when the teeth of both gears are alike, z1 (z2) when the driver's (driven gear's)
    teeth differ, lcm(z1, z2) when both do.

    Parameters
    ----------
    pair : GearPair
        The mesh.
    varies1, varies2 : bool
        Whether the teeth of the driver / driven gear differ.

    Returns
    -------
    int

    Examples
    --------
    >>> from gearsim.geometry.gear import Gear
    >>> pair = GearPair(Gear(teeth=19, normal_module=3.2e-3), Gear(teeth=48, normal_module=3.2e-3))
    >>> grid_period(pair, False, False), grid_period(pair, True, False), grid_period(pair, True, True)
    (1, 19, 912)
    """
    z1, z2 = pair.driver.teeth, pair.driven.teeth
    if varies1 and varies2:
        return math.lcm(z1, z2)
    if varies1:
        return z1
    if varies2:
        return z2
    return 1


def _condensed_corners(kpath: np.ndarray, cpath: np.ndarray, width: np.ndarray,
                       inside: np.ndarray, corner: np.ndarray, ccorner: np.ndarray,
                       rate: np.ndarray, sep: np.ndarray, dz: float, before: np.ndarray,
                       cross: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Tip-corner springs of the mesh of contacts, condensed from the tables' law.

    The tables' law (:func:`gearsim.stiffness.mesh.extended_law`) couples a closed corner
    to its neighbouring pair through the gear bodies; the contacts of the LTCA are
    independent springs. With the path contacts closed and linearised (compliances
    ``cpath``, springs ``kpath``) the coupled force is K_0 delta without the corner and
    K_A delta - S_A with it (K_A = w rho . C^-1 rho, S_A = w rho . C^-1 (rho s), one
    corner of a kind per slice), continuous where the corner closes: the corner is the
    spring k = K_A - K_0 with separation S_A / k, exact for one corner at the path
    contacts' linearised compliances.

    Returns
    -------
    k, s : ndarray
        Spring stiffness [N/m] and separation [m] of each corner, shape of ``corner``.
    """
    k0 = kpath.sum(axis=1, where=inside)  # (npc, ns)
    k_out = np.zeros(corner.shape)
    s_out = np.zeros(corner.shape)
    for kind in (corner & before, corner & ~before):
        if not kind.any():
            continue
        act = inside | kind
        diag = np.where(inside, cpath, np.where(kind, ccorner, 1.0))
        rho = np.where(kind, rate, np.where(inside, 1.0, 0.0))
        w = np.where(kind, dz, np.where(inside, width, 0.0))
        off = (np.zeros(diag[:, 1:].shape) if cross is None
               else np.where(act[:, :-1] & act[:, 1:], cross, 0.0))
        a, b = _tridiagonal_solve(diag, off, rho, rho * np.where(kind, sep, 0.0))
        k_a = np.sum(w * rho * a, axis=1)
        s_a = np.sum(w * rho * b, axis=1)
        kc = np.maximum(k_a - k0, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            sc = np.where(kc > 0, s_a / kc, 0.0)
        k_out = np.where(kind, kc[:, None, :], k_out)
        s_out = np.where(kind, sc[:, None, :], s_out)
    return k_out, s_out


def _grid_geometry(pair: GearPair, settings: StiffnessSettings, corner: bool, lead: bool,
                   points: bool = False):
    """Slice contact points, in-path fractions and raw slice-centre positions.

    A spur face is one slice unless a lead modification (``lead``) varies along it. With
    ``points`` (the line contact law with the tip corners, as
    :func:`gearsim.stiffness.mesh.extended_grid`) a slice centre on the closed path
    [l_A, l_E] is a whole contact at its centre and one outside it none (the corner takes
    over there); otherwise each contact carries the in-path fraction of its sampling cell
    (:func:`gearsim.stiffness.mesh.in_path_fraction`).
    """
    tb = math.tan(pair.driver.base_helix_angle)
    b = pair.face_width
    ns = settings.slices if tb > 0 or lead else 1
    npc = settings.positions_per_cycle
    pb = pair.base_pitch
    la, le = pair.start_of_contact, pair.end_of_contact
    eps = pair.transverse_contact_ratio + b * tb / pb
    first = -1 if corner else 0
    n_age = int(math.ceil(eps)) + 1 + (2 if corner else 0)
    u = np.arange(npc) / npc
    age = u[:, None] + (np.arange(n_age) + first)[None, :]
    dz = b / ns
    z0 = np.arange(ns) * dz
    z1 = z0 + dz
    base = la + age[:, :, None] * pb
    hi = base - z0[None, None, :] * tb
    lo = base - z1[None, None, :] * tb
    centre = 0.5 * (hi + lo)
    if points:
        frac = ((centre >= la) & (centre <= le)).astype(float)
        lmid = centre
    else:
        lmid, frac = in_path_fraction(centre, la, le, pb / npc, dz * tb)
    lmid = np.where(frac > 0, lmid, la)
    return lmid, frac, centre, dz, n_age, first, ns, z0, z1


def contact_grid(pair: GearPair, *, cracks: tuple[ToothCrack, ...] = (),
                 flank1: FlankState | None = None, flank2: FlankState | None = None,
                 settings: StiffnessSettings | None = None,
                 compliance: ToothCompliance | None = None, period: int | None = None,
                 corner: bool = False, force: float | None = None,
                 coupling=None) -> ContactGrid:
    """Stiffness and no-load separation of every contact of ``pair``.

    Parameters
    ----------
    pair : GearPair
        The mesh (driver drives driven).
    cracks : tuple of ToothCrack
        Root cracks as seen by this mesh (their compliance enters the tooth terms).
    flank1, flank2 : FlankState, optional
        Modifications, errors and faults of the loaded flanks of driver and driven gear.
    settings : StiffnessSettings, optional
        Slices, positions per cycle, closure, plane, source.
    compliance : ToothCompliance, optional
        Tooth-compliance model (default the potential-energy model); must match
        ``settings.source``.
    period : int, optional
        Mesh cycles to cover; default :func:`grid_period` of the faults, errors and
        cracks (a multiple of it is allowed).
    corner : bool
        Add the tip-corner contacts of the pairs just outside the path of contact
        (:func:`corner_separation`). Under the line contact law the path contacts are
        then point samples, as in the tables' extended contact (module docstring).
    force : float, optional
        Transverse line-of-action force of the mesh [N]: the load at which the line
        contact law (``settings.contact = "line"``) is linearised (required then).
    coupling : optional
        Body coupling of neighbouring teeth (``settings.coupling = "fe"``), as for
        :func:`gearsim.stiffness.mesh.mesh_stiffness`.

    Returns
    -------
    ContactGrid

    Raises
    ------
    InputError
        If ``period`` is not a multiple of the natural period, the model does not match
        ``settings.source``, the grid would exceed :data:`MAX_GRID` entries, or the line
        contact has no force or the coupling no model.

    Notes
    -----
    The contact law and the coupling are those of the TVMS tables
    (:func:`gearsim.stiffness.mesh.pair_law`), evaluated per mesh cycle from the
    contacts' tooth compliances (cracks included): the line contact's compliance at the
    load per unit width each contact carries when all contacts are closed at ``force``,
    and the coupled pairs condensed to one spring each at a common approach
    (q = C^-1 1). A healthy grid without separations therefore sums to the table. The
    contact springs stay linear in the dynamics: a contact that a fault opens or
    overloads keeps the linearised values (the line compliance varies as ln of the load;
    the body coupling of an opened neighbour, a few per cent of a pair's compliance, is
    not removed).
    """
    settings = settings or StiffnessSettings()
    flank1 = flank1 or FlankState()
    flank2 = flank2 or FlankState()
    model = compliance if compliance is not None else PotentialEnergyCompliance()
    require(model.name == settings.source, "stiffness.source", settings.source,
            f"the tooth-compliance model passed is {model.name!r}")
    g1, g2 = pair.driver, pair.driven
    z1, z2 = g1.teeth, g2.teeth
    natural = grid_period(pair, flank1.varies or any(c.gear == 1 for c in cracks),
                          flank2.varies or any(c.gear == 2 for c in cracks))
    period = natural if period is None else period
    require(isinstance(period, int) and period >= 1 and period % natural == 0, "period",
            period, f"must be a multiple of {natural} mesh cycles (the contacts' period)")
    lead = any(f.modification is not None and (f.modification.crowning or f.modification.helix_slope)
               for f in (flank1, flank2))
    # under the line law the tip corners make the stiffness continuous across A and E:
    # point samples, as the tables' extended_grid (the seed's law keeps the cell fractions)
    points = corner and settings.contact == "line"
    lmid, frac, centre, dz, n_age, first, ns, z0, z1_ = _grid_geometry(pair, settings, corner,
                                                                         lead, points)
    npc = settings.positions_per_cycle
    layers = 2
    size = period * npc * n_age * ns * layers
    require(size <= MAX_GRID, "stiffness.slices", settings.slices,
            f"the contact grid would have {size:.3g} entries (> {MAX_GRID:.0e}): "
            f"{period} mesh cycles x {npc} positions x {n_age} pairs x {ns} slices; use "
            "fewer slices or positions_per_cycle")
    big_l = pair.line_length
    la, le = pair.start_of_contact, pair.end_of_contact
    inside = frac > 0
    r1 = np.where(inside, np.hypot(g1.base_radius, lmid), 0.0)
    r2 = np.where(inside, np.hypot(g2.base_radius, big_l - lmid), 0.0)
    zfrac = (z0 + 0.5 * dz) / pair.face_width

    def table(gear, radii, tc):
        return model.compliance(gear, radii, tc, zfrac, settings).sum(-1)

    healthy1 = table(g1, r1, None)
    healthy2 = table(g2, r2, None)
    cr1 = {tc.crack.tooth: table(g1, r1, tc) for tc in cracks if tc.gear == 1}
    cr2 = {tc.crack.tooth: table(g2, r2, tc) for tc in cracks if tc.gear == 2}
    ch = 1.0 / hertz_stiffness(g1.material, g2.material, 1.0)
    width = frac * dz
    law = None
    factors = None
    if settings.contact != "yang-lin" or settings.coupling != "none":
        # with the tip corners (point samples) the line contact is cut off at the tip edges,
        # as the tables' (stiffness.mesh.extended_grid)
        edge = tip_edge_offset(pair, np.where(inside, lmid, la)) if points else None
        law = pair_law(pair, settings, lmid, width, r1, r2, force=force, coupling=coupling,
                       edge=edge)
        # a cracked body's coupling beside the cracked tooth, as the tables'
        factors = crack_cross_factors(pair, model, cracks, settings, r1, r2, inside, zfrac)
    corner_factors = None
    # corner contacts: outside the path, at the whole slice width, with the stiffness
    # of the pair at the nearer end of the path
    corner_mask = np.zeros(frac.shape, dtype=bool)
    s_corner = np.zeros(frac.shape)
    if corner:
        pb = pair.base_pitch
        # within one base pitch of the path and between the base tangents T1, T2 (the
        # involutes exist there)
        corner_mask = (~inside) & (((centre <= la) & (centre > max(la - pb, 0.0)))
                                   | ((centre > le) & (centre < min(le + pb, big_l))))
        s_corner = np.where(corner_mask, corner_separation(pair, centre), 0.0)
        lend = np.where(centre <= la, la + 1e-9 * pb, le - 1e-9 * pb)
        rc1 = np.where(corner_mask, np.hypot(g1.base_radius, lend), 0.0)
        rc2 = np.where(corner_mask, np.hypot(g2.base_radius, big_l - lend), 0.0)
        cc1 = table(g1, rc1, None)
        cc2 = table(g2, rc2, None)
        if settings.contact == "line":
            # the tables' corner law (stiffness.mesh.extended_law): the line contact of
            # the path end, in the FE pair's position convention (driven held), here
            # linearised at the single-pair load per unit width F / b; the coupling is
            # condensed into the spring per cycle (_condensed_corners)
            s_corner, rate = corner_closing(pair, np.where(corner_mask, centre, la))
            s_corner = np.where(corner_mask, s_corner, 0.0)
            ok = corner_mask & (rate > 0)
            cl = line_contact_compliance(
                np.full(centre.shape, force / pair.face_width), np.where(ok, lend, 1.0),
                np.where(ok, big_l - lend, 1.0),
                np.where(ok, centre_line_depth(g1, np.where(ok, rc1, g1.base_radius)), 1.0),
                np.where(ok, centre_line_depth(g2, np.where(ok, rc2, g2.base_radius)), 1.0),
                g1.material, g2.material, settings.plane,
                np.where(ok, tip_edge_offset(pair, np.where(ok, centre, la)), -np.inf))
            kc_unit = np.where(ok, np.maximum(rate, 0.0) ** 2 / (cl + cc1 + cc2), 0.0)
            corner_mask = ok
            c_corner = cl + cc1 + cc2  # normal compliance per unit width [m^2/N]
            cross = None
            if settings.coupling != "none":
                # path or tip-corner contacts, the corner ones at their path end's radii
                rr1, rr2 = np.where(inside, r1, rc1), np.where(inside, r2, rc2)
                x1c, x2c = adjacent_cross(g1, g2, coupling, inside | corner_mask, rr1, rr2)
                cross = x1c + x2c
                corner_factors = crack_cross_factors(pair, model, cracks, settings, rr1, rr2,
                                                     inside | corner_mask, zfrac)
        else:
            kc_unit = np.where(corner_mask, 1.0 / (ch + cc1 + cc2), 0.0)
    roll1 = np.where(corner_mask, np.clip(centre, la, le), lmid)
    roll2 = big_l - roll1
    s1 = roll1 ** 2 / (2 * g1.base_radius)
    s2 = roll2 ** 2 / (2 * g2.base_radius)
    lead = np.zeros(ns)
    prof = np.zeros(frac.shape)
    for fl, roll, tip, start in ((flank1, roll1, le, la), (flank2, roll2, big_l - la, big_l - le)):
        m = fl.modification
        if m is not None:
            lead = lead + m.lead_separation(zfrac)
            prof = prof + m.profile_separation(roll, tip, start)
    base_sep = prof + lead[None, None, :] + s_corner
    n_pos = period * npc
    shape = (n_pos, n_age, ns, layers)
    k = np.zeros(shape)
    s = np.zeros(shape)
    t1 = np.zeros((n_pos, n_age), dtype=np.int64)
    t2 = np.zeros((n_pos, n_age), dtype=np.int64)
    ages = np.arange(n_age) + first
    for c in range(period):
        sl = slice(c * npc, (c + 1) * npc)
        i1 = (c - ages) % z1
        i2 = (c - ages) % z2
        t1[sl] = i1
        t2[sl] = i2
        comp = np.empty(frac.shape)
        sep = base_sep.copy()
        lost = np.zeros(frac.shape)
        cover = np.zeros(frac.shape)
        depth = np.full(frac.shape, np.inf)
        for m in range(n_age):
            comp[:, m] = (cr1.get(int(i1[m]), healthy1)[:, m]
                          + cr2.get(int(i2[m]), healthy2)[:, m])
            for fl, tooth, sarc, roll in ((flank1, int(i1[m]), s1, roll1),
                                          (flank2, int(i2[m]), s2, roll2)):
                sep[:, m] += fl.position(np.array(tooth)) + (
                    fl.wear_depth(tooth, roll[:, m]) if fl.wear else 0.0)
                for p in fl.patches.get(tooth, ()):
                    f = p.covered(sarc[:, m], z0[None, :], z1_[None, :])
                    if math.isinf(p.depth):
                        lost[:, m] = 1.0 - (1.0 - lost[:, m]) * (1.0 - f)
                    else:
                        cover[:, m] = 1.0 - (1.0 - cover[:, m]) * (1.0 - f)
                        depth[:, m] = np.where(f > 0, np.minimum(depth[:, m], p.depth),
                                               depth[:, m])
        if law is None:  # the seed's contact, independent pairs
            with np.errstate(divide="ignore"):
                kunit = np.where(inside, 1.0 / (ch + comp), 0.0)
            kfull = kunit * width
        else:
            f = factors(i1, i2) if factors is not None else None
            kfull, chs = law(comp) if f is None else law(comp, f)
        if corner and settings.contact == "line":
            fc = corner_factors(i1, i2) if corner_factors is not None else None
            kc, sc = _condensed_corners(kfull, np.where(inside, chs + comp, 1.0), width,
                                        inside, corner_mask, c_corner, rate, s_corner, dz,
                                        centre <= la,
                                        cross if fc is None else x1c * fc[0] + x2c * fc[1])
            kfull = np.where(corner_mask, kc, kfull)
            sep = np.where(corner_mask, sep - s_corner + sc, sep)
        elif corner:
            kfull = np.where(corner_mask, kc_unit * dz, kfull)
        keep = 1.0 - lost
        k[sl, ..., 0] = kfull * keep * (1.0 - cover)
        k[sl, ..., 1] = kfull * keep * cover
        s[sl, ..., 0] = sep
        s[sl, ..., 1] = sep + np.where(np.isfinite(depth), depth, 0.0)
    l_grid = np.where(corner_mask, centre, lmid)
    return ContactGrid(
        name=pair.name, positions_per_cycle=npc, period=period, k=k, s=s, tooth1=t1,
        tooth2=t2, l=np.tile(l_grid, (period, 1, 1)), zfrac=zfrac, slice_width=dz,
        base_radius2=g2.base_radius,
        attrs={"closure": settings.closure, "slices": ns, "positions_per_cycle": npc,
               "plane": settings.plane, "source": model.name, "corner_contact": int(corner),
               "contact": settings.contact, "coupling": settings.coupling,
               **({"contact_force": float(force)} if settings.contact == "line" else {})})
