"""Finite-element tooth compliance with a spall notch, a chipped tip or a broken neighbour.

The FE model of :mod:`gearsim.fem.tooth` (whole gear, plane elasticity, P2 triangles,
Hertz excluded by measuring at the point Q on the tooth centre line) with a changed
outline of one tooth (:class:`gearsim.fem.geometry.ToothShape`). The model is 2D: **a
fault covers the whole face width** in it (the ``width``, ``z`` and ``edge`` of the
fault are not used), so the FE numbers are those of a fault through the face; the
potential-energy slices of a partly damaged face are made of such slices and healthy
ones.

Outlines, in the frame of :class:`gearsim.geometry.profile.ToothProfile` (the ``+x``
flank is the working, loaded flank; a fault on the non-working flank is mirrored to
``-x``). Arc lengths s along the involute are measured from the base circle,
s = (r^2 - r_b^2) / (2 r_b) (:func:`gearsim.stiffness.faults.arc_at_radius`).

* **Spall** (:class:`~gearsim.stiffness.faults.Spall`): a rectangular notch of
  ``depth``, measured along the flank normal, over the arc-length range
  [s_c - length/2, s_c + length/2], s_c = s(``radius``). Its walls are normal to the
  flank at the two ends and its bottom is the involute offset by ``depth`` (parallel to
  the flank: a flat bottom). The ``shape`` (elliptical or rectangular outline on the
  flank) does not enter a 2D section; both are the rectangular notch.
* **Chipped tip** (:class:`~gearsim.stiffness.faults.ChippedTip`): the flank above
  s_tip - ``length`` is gone, cut off by a straight chord from that flank point towards
  the tooth centre line at :data:`CHIP_ANGLE` (45 deg) to the centre line, up to the tip
  circle. A chip whose chord would reach the centre line before the tip circle is
  refused.
* **Broken tooth** (:class:`~gearsim.stiffness.faults.BrokenTooth`): the tooth cut off
  along a straight line perpendicular to its centre line through the fillet point at
  ``break_radius`` (default: the 30 deg tangent point of ISO 6336-3), across to the
  same point of the other fillet. A broken tooth carries no load, so the FE check is
  the one on a *neighbour* (:func:`fe_neighbour_compliance`): the healthy loaded tooth
  with the next or previous tooth broken (the foundation of the loaded tooth loses the
  neighbour's material).

The load never goes onto the damaged part of the loaded flank: a contact radius whose
load patch (half length :data:`~gearsim.fem.tooth.PATCH_HALF_LENGTH` m_n) reaches the
spall or the chip is refused (in the potential-energy model that part of the contact
line is lost or only touches after a separation, :mod:`gearsim.stiffness.faults`). The
element sizes are those of the healthy model, so the faulted and healthy runs differ
only where the outline does, up to the remeshing noise (about 1e-3 relative,
docs/fem.md).

References
----------
Chaari et al. (2008), Saxena et al. (2016), Luo et al. (2019): the full entries are in
:mod:`gearsim.stiffness.faults`.

.. [ISO6336-3] ISO 6336-3:2019, 30 degree tangent of the root fillet (break line).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.fem.geometry import (
    N_FILLET,
    N_INVOLUTE,
    SectorMesh,
    SectorOptions,
    ToothShape,
    element_size,
    mesh_sector,
)
from gearsim.fem.solve import ElasticModel
from gearsim.fem.tooth import (
    FINEST_LEVEL,
    PATCH_HALF_LENGTH,
    _check_radii,
    deflection_along_load,
    flank_loads,
    load_geometry,
)
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.faults import BrokenTooth, ChippedTip, Spall, arc_at_radius

__all__ = [
    "CHIP_ANGLE",
    "NEIGHBOURS",
    "FEFaultResult",
    "broken_shape",
    "chip_shape",
    "fe_fault_compliance",
    "fe_neighbour_compliance",
    "generated_shape",
    "spall_span",
    "spall_shape",
]

#: Angle of the chip's cut to the tooth centre line [rad] (45 deg).
CHIP_ANGLE = math.radians(45.0)
#: Neighbours of the loaded tooth that :func:`fe_neighbour_compliance` can remove, with
#: their tooth indices (:func:`gearsim.fem.geometry.mesh_sector`).
NEIGHBOURS = {"next": (1,), "previous": (-1,), "both": (1, -1)}
#: Sample points on a spall bottom.
N_BOTTOM = 16


@dataclass
class FEFaultResult:
    """FE tooth compliance of the loaded tooth with a fault outline.

    Parameters
    ----------
    radii, compliance, level, h, nodes, elements, dofs, plane
        As :class:`gearsim.fem.tooth.FEToothResult`.
    fault
        The fault (``None``: healthy).
    teeth
        Indices of the teeth with a changed outline (0 = the loaded tooth, +1 the next
        tooth, on the side of the loaded flank, -1 the previous one).
    seconds
        Wall time [s].
    """

    radii: np.ndarray
    compliance: np.ndarray
    level: int
    h: float
    nodes: int
    elements: int
    dofs: int
    plane: str
    fault: object = None
    teeth: tuple[int, ...] = ()
    seconds: float = 0.0


# --------------------------------------------------------------------------- outlines
def _radius_at_arc(s: float, rb: float) -> float:
    return math.sqrt(rb * rb + 2.0 * rb * s)


def _half(gear: Gear) -> np.ndarray:
    return ToothProfile(gear).outline(N_FILLET, N_INVOLUTE)


def _assemble(right: list, left: list, flank_right: tuple[int, ...] = ()) -> ToothShape:
    """Tooth from the pieces of its two halves, each given root -> top in ``+x`` coordinates.

    The top joins the two upper ends: a tip arc when both lie on one circle about the
    gear centre, otherwise a straight line.
    """
    mirror = np.array([-1.0, 1.0])
    top_r = np.asarray(right[-1][1][-1], dtype=float)
    top_l = np.asarray(left[-1][1][-1], dtype=float) * mirror
    same_circle = abs(np.hypot(*top_r) - np.hypot(*top_l)) <= 1e-12 * np.hypot(*top_r)
    top = ("arc" if same_circle else "line", np.vstack([top_r, top_l]))
    left_pieces = [(kind, np.asarray(pts, dtype=float)[::-1] * mirror)
                   for kind, pts in left[::-1]]
    return ToothShape(pieces=(*right, top, *left_pieces), flank=flank_right)


def _healthy_half(half: np.ndarray) -> list:
    return [("spline", half[:N_FILLET]), ("spline", half[N_FILLET - 1:])]


def _oriented(gear: Gear, flank: str, damaged: list, flank_idx: tuple[int, ...]) -> ToothShape:
    """Damaged half on the working (+x) or non-working (-x) side, the other half healthy."""
    healthy = _healthy_half(_half(gear))
    if flank == "working":
        return _assemble(damaged, healthy, flank_idx)
    return _assemble(healthy, damaged, (1,))


def generated_shape(gear: Gear) -> ToothShape:
    """The generated (healthy) tooth outline as a :class:`ToothShape`.

    Meshing the gear with this shape for the loaded tooth gives the same mesh as the
    generated outline (a check of the outline hook of
    :func:`gearsim.fem.geometry.mesh_sector`).

    Parameters
    ----------
    gear
        The gear.

    Returns
    -------
    ToothShape
        Fillet and involute splines of both flanks and the tip arc; the loaded flank is
        the ``+x`` involute.
    """
    healthy = _healthy_half(_half(gear))
    return _assemble(healthy, healthy, (1,))


def spall_span(gear: Gear, spall: Spall) -> tuple[float, float]:
    """Radii of the two ends of a spall along the involute.

    Parameters
    ----------
    gear
        The damaged gear.
    spall
        The spall (centre ``radius``, ``length`` along the involute arc).

    Returns
    -------
    r1, r2 : float
        Radii of arc lengths s_c -/+ length / 2 [m], s_c = arc_at_radius(radius, r_b).

    Raises
    ------
    InputError
        ``spall.radius`` when the centre is off the involute [form radius, tip radius];
        ``spall.length`` when an end of the notch leaves the involute.

    References
    ----------
    ISO 21771:2007 (involute arc length s = (r^2 - r_b^2) / (2 r_b)).
    """
    prof = ToothProfile(gear)
    rb = gear.base_radius
    lo = max(prof.form_radius, rb)
    hi = gear.tip_radius
    if not lo < spall.radius < hi:
        raise InputError("spall.radius", spall.radius,
                         f"must lie on the involute of {gear.name}, in ({lo:.6g}, {hi:.6g}) m")
    s_c = arc_at_radius(spall.radius, rb)
    s_lo, s_hi = arc_at_radius(lo, rb), arc_at_radius(hi, rb)
    margin = 0.01 * gear.normal_module
    room = 2.0 * (min(s_c - s_lo, s_hi - s_c) - margin)
    if spall.length > room:
        raise InputError("spall.length", f"{spall.length * 1e3:.4g} mm",
                         f"the notch leaves the involute of {gear.name} (form circle to tip); "
                         f"centred at r = {spall.radius * 1e3:.5g} mm it may be at most "
                         f"{max(room, 0.0) * 1e3:.4g} mm long")
    s1 = s_c - 0.5 * spall.length
    s2 = s_c + 0.5 * spall.length
    return _radius_at_arc(s1, rb), _radius_at_arc(s2, rb)


def spall_shape(gear: Gear, spall: Spall) -> ToothShape:
    """Outline of a tooth with a spall notch (module docstring).

    Parameters
    ----------
    gear
        The damaged gear.
    spall
        The spall; its ``flank`` chooses the ``+x`` (working) or ``-x`` side.

    Returns
    -------
    ToothShape
        The notched tooth; its loaded-flank pieces are the involute below and above the
        notch (no load goes onto the notch).

    Raises
    ------
    InputError
        ``spall.radius`` / ``spall.length`` (notch off the involute, :func:`spall_span`),
        ``spall.depth`` when the notch bottom would reach the tooth centre line
        (depth >= the tooth half thickness along the flank normal).
    """
    prof = ToothProfile(gear)
    half = _half(gear)
    r1, r2 = spall_span(gear, spall)
    inv = half[N_FILLET - 1:]
    below = _involute_part(prof, inv, r1, "below")
    above = _involute_part(prof, inv, r2, "above")
    radii = np.linspace(r1, r2, N_BOTTOM)
    flank_pts = np.array([prof.involute_point(float(r)) for r in radii])
    normals = np.array([load_geometry(prof, float(r))[1] for r in radii])  # inward normals
    # distance along the inward normal from the flank to the centre line x = 0
    to_centre = flank_pts[:, 0] / -normals[:, 0]
    if spall.depth >= float(np.min(to_centre)):
        raise InputError("spall.depth", f"{spall.depth * 1e3:.4g} mm",
                         f"must be less than the tooth half thickness along the flank normal "
                         f"over the spall, {np.min(to_centre) * 1e3:.4g} mm: a deeper notch "
                         "would cut through the tooth")
    bottom = flank_pts + spall.depth * normals
    damaged = [("spline", half[:N_FILLET]), _piece(below),
               ("line", np.vstack([below[-1], bottom[0]])), ("spline", bottom),
               ("line", np.vstack([bottom[-1], above[0]])), _piece(above)]
    return _oriented(gear, spall.flank, damaged, (1, 5))


def _piece(pts: np.ndarray) -> tuple[str, np.ndarray]:
    return ("line" if pts.shape[0] == 2 else "spline", pts)


def _involute_part(prof: ToothProfile, inv: np.ndarray, r_cut: float, keep: str
                   ) -> np.ndarray:
    """Points of the sampled involute below or above ``r_cut``, with the point at r_cut."""
    rr = np.hypot(*inv.T)
    tol = 1e-3 * float(np.max(np.hypot(*np.diff(inv, axis=0).T)))
    p_cut = np.asarray(prof.involute_point(r_cut))
    far = np.hypot(*(inv - p_cut).T) > tol
    if keep == "below":
        return np.vstack([inv[(rr < r_cut) & far], p_cut])
    return np.vstack([p_cut, inv[(rr > r_cut) & far]])


def chip_shape(gear: Gear, chip: ChippedTip) -> ToothShape:
    """Outline of a tooth with a chipped tip corner (module docstring).

    Parameters
    ----------
    gear
        The damaged gear.
    chip
        The chip: the flank above the arc length s_tip - ``length`` is gone; its
        ``flank`` chooses the side.

    Returns
    -------
    ToothShape
        The tooth cut by the chord at :data:`CHIP_ANGLE` to the centre line from the
        flank point at s_tip - ``length`` to the tip circle.

    Raises
    ------
    InputError
        ``chip.length`` when the chip reaches below the form circle, or its chord
        reaches the tooth centre line before the tip circle (more than the tip land of
        one half would be gone).
    """
    prof = ToothProfile(gear)
    half = _half(gear)
    rb = gear.base_radius
    ra = gear.tip_radius
    lo = max(prof.form_radius, rb)
    s_tip = arc_at_radius(ra, rb)
    s_cut = s_tip - chip.length
    if s_cut <= arc_at_radius(lo, rb) + 0.01 * gear.normal_module:
        raise InputError("chip.length", f"{chip.length * 1e3:.4g} mm",
                         f"reaches below the form circle of {gear.name}: at most "
                         f"{(s_tip - arc_at_radius(lo, rb)) * 1e3:.4g} mm of involute arc")
    r_cut = _radius_at_arc(s_cut, rb)
    p = np.asarray(prof.involute_point(r_cut))
    u = np.array([-math.sin(CHIP_ANGLE), math.cos(CHIP_ANGLE)])
    # |p + t u| = r_a, t > 0
    b = float(p @ u)
    t = -b + math.sqrt(b * b - (float(p @ p) - ra * ra))
    tip = p + t * u
    x_tip = prof.involute_point(ra)[0]
    if not 0.0 < tip[0] < x_tip:
        longest = _longest_chip(prof, s_tip, u)
        raise InputError("chip.length", f"{chip.length * 1e3:.4g} mm",
                         f"the {math.degrees(CHIP_ANGLE):.0f} deg cut of the chip reaches the "
                         "tooth centre line before the tip circle; at most "
                         f"{longest * 1e3:.4g} mm")
    tip = ra * tip / np.hypot(*tip)  # exactly on the tip circle (arc end)
    below = _involute_part(prof, half[N_FILLET - 1:], r_cut, "below")
    damaged = [("spline", half[:N_FILLET]), _piece(below), ("line", np.vstack([p, tip]))]
    return _oriented(gear, chip.flank, damaged, (1,))


def _longest_chip(prof: ToothProfile, s_tip: float, u: np.ndarray) -> float:
    """Chip length whose chord ends on the centre line at the tip circle (bisection)."""
    gear = prof.gear
    rb, ra = gear.base_radius, gear.tip_radius
    lo, hi = 0.0, s_tip - arc_at_radius(max(prof.form_radius, rb), rb)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        p = np.asarray(prof.involute_point(_radius_at_arc(s_tip - mid, rb)))
        b = float(p @ u)
        x = (p + (-b + math.sqrt(b * b - (float(p @ p) - ra * ra))) * u)[0]
        lo, hi = (mid, hi) if x > 0.0 else (lo, mid)
    return lo


def broken_shape(gear: Gear, broken: BrokenTooth | None = None) -> ToothShape:
    """Outline of a tooth broken off at its root (module docstring).

    Parameters
    ----------
    gear
        The gear.
    broken
        The fault, for its ``break_radius``; ``None`` or no radius: the 30 deg tangent
        point of the fillet (ISO 6336-3).

    Returns
    -------
    ToothShape
        The two fillets up to the break height, joined by a straight line perpendicular
        to the tooth centre line; no loaded flank.

    Raises
    ------
    InputError
        ``broken.break_radius`` when the radius is not on the root fillet.

    References
    ----------
    ISO 6336-3:2019 (30 deg tangent, the critical section of tooth-root breakage).
    """
    prof = ToothProfile(gear)
    radius = None if broken is None else broken.break_radius
    if radius is None:
        g = prof.tangent_point()[0]
    else:
        lo, hi = gear.root_radius, prof.form_radius
        if not lo < radius < hi:
            raise InputError("broken.break_radius", radius,
                             f"must lie on the root fillet of {gear.name}, in ({lo:.6g}, "
                             f"{hi:.6g}) m")
        g = prof.fillet_param_at_radius(radius)
    b = np.asarray(prof.fillet_point(g))
    fil = _half(gear)[:N_FILLET]
    tol = 1e-3 * float(np.max(np.hypot(*np.diff(fil, axis=0).T)))
    keep = (fil[:, 1] < b[1]) & (np.hypot(*(fil - b).T) > tol)
    stump = np.vstack([fil[keep], b])
    half_pieces = [_piece(stump)]
    return ToothShape(pieces=(*half_pieces, ("line", np.vstack([b, b * [-1.0, 1.0]])),
                              _piece(stump[::-1] * [-1.0, 1.0])))


# --------------------------------------------------------------------------- solving
def _solve(gear: Gear, sector: SectorMesh, r: np.ndarray, plane: str,
           opt: SectorOptions) -> tuple[np.ndarray, ElasticModel]:
    """Compliance at Q along the load for each radius (as :mod:`gearsim.fem.tooth`)."""
    model, fixed, loads, dirs, qs = flank_loads(gear, sector, r, plane, opt)
    u = model.solve(loads, fixed)
    return deflection_along_load(model, u, dirs, qs), model


def _result(gear, sector, r, plane, opt, fault, teeth, t0) -> FEFaultResult:
    comp, model = _solve(gear, sector, r, plane, opt)
    return FEFaultResult(radii=r, compliance=comp, level=opt.level, h=sector.h,
                         nodes=int(model.mesh.p.shape[1]), elements=int(model.mesh.t.shape[1]),
                         dofs=model.ndofs, plane=plane, fault=fault, teeth=teeth,
                         seconds=time.perf_counter() - t0)


def _check_plane(plane: str) -> None:
    if plane not in ("stress", "strain"):
        raise InputError("stiffness.plane", plane, 'must be "stress" or "strain"')


def _check_spall_resolved(gear: Gear, spall: Spall, level: int) -> None:
    """Elements no larger than half the notch depth and half its length."""
    size = min(spall.depth, spall.length)
    name = "spall.depth" if spall.depth <= spall.length else "spall.length"
    finest = element_size(gear, FINEST_LEVEL)
    if size < 2.0 * finest:
        raise InputError(name, f"{size * 1e3:.4g} mm",
                         f"is too small for the FE mesh of {gear.name}: the finest level "
                         f"({FINEST_LEVEL}, elements {finest * 1e3:.3g} mm) resolves notches "
                         f">= {2e3 * finest:.4g} mm (2 elements)")
    h = element_size(gear, level)
    if h > 0.5 * size:
        need = math.ceil(math.log2(gear.normal_module / (2.0 * size)))
        raise InputError("fem.level", level,
                         f"mesh too coarse for the spall: element size {h * 1e3:.4g} mm > "
                         f"{name.split('.')[1]} / 2 = {0.5e3 * size:.4g} mm; use level >= "
                         f"{max(need, level + 1)}")


def _refuse_damaged_radii(gear: Gear, r: np.ndarray, lo_s: float, hi_s: float,
                          what: str) -> None:
    """Refuse contact radii whose load patch reaches the arc-length range [lo_s, hi_s]."""
    rb = gear.base_radius
    a = PATCH_HALF_LENGTH * gear.normal_module
    s = np.array([arc_at_radius(float(x), rb) for x in r])
    bad = (s > lo_s - a) & (s < hi_s + a)
    if np.any(bad):
        lo_r = _radius_at_arc(max(lo_s - a, 0.0), rb)
        hi_r = _radius_at_arc(hi_s + a, rb)
        raise InputError("radii", float(r[bad][0]),
                         f"the load patch reaches the {what} (load radii must be outside "
                         f"[{lo_r:.6g}, {hi_r:.6g}] m): the damaged flank carries no load here")


def fe_fault_compliance(gear: Gear, radii, *, fault: Spall | ChippedTip | None,
                        plane: str = "stress", options: SectorOptions | None = None
                        ) -> FEFaultResult:
    """FE compliance of a tooth with a spall notch or a chipped tip at contact radii.

    The loaded tooth gets the fault outline (module docstring) over the whole face
    width; the load and the measure are those of
    :func:`gearsim.fem.tooth.fe_tooth_compliance` (Hertz excluded).

    Parameters
    ----------
    gear
        The damaged gear.
    radii
        Contact radii on the involute of the loaded (working) flank [m]; for a fault on
        the working flank, outside the damaged part (with the load patch).
    fault
        :class:`~gearsim.stiffness.faults.Spall` or
        :class:`~gearsim.stiffness.faults.ChippedTip` (working or non-working flank), or
        ``None`` for the healthy tooth (the same mesh as ``fe_tooth_compliance``).
    plane
        ``"stress"`` or ``"strain"``.
    options
        Mesh options (:class:`~gearsim.fem.geometry.SectorOptions`).

    Returns
    -------
    FEFaultResult
        Compliance [m/N] for a face width of 1 m at each radius.

    Raises
    ------
    InputError
        A broken tooth (no load on it: use :func:`fe_neighbour_compliance`) or another
        fault kind (``fault``); a notch off the involute, deeper than the tooth half
        thickness or finer than the mesh (``spall.*``, ``fem.level`` naming the level
        needed); a chip too long (``chip.length``); radii off the involute or on the
        damaged flank (``radii``).

    References
    ----------
    Chaari et al. (2008); Saxena et al. (2016); Luo et al. (2019).
    """
    t0 = time.perf_counter()
    _check_plane(plane)
    opt = options or SectorOptions()
    prof = ToothProfile(gear)
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    _check_radii(gear, prof, r)
    rb = gear.base_radius
    if fault is None:
        shapes = {}
    elif isinstance(fault, Spall):
        shape = spall_shape(gear, fault)
        _check_spall_resolved(gear, fault, opt.level)
        if fault.flank == "working":
            r1, r2 = spall_span(gear, fault)
            _refuse_damaged_radii(gear, r, arc_at_radius(r1, rb), arc_at_radius(r2, rb),
                                  "spall")
        shapes = {0: shape}
    elif isinstance(fault, ChippedTip):
        shape = chip_shape(gear, fault)
        if fault.flank == "working":
            s_tip = arc_at_radius(gear.tip_radius, rb)
            _refuse_damaged_radii(gear, r, s_tip - fault.length, s_tip, "chip")
        shapes = {0: shape}
    elif isinstance(fault, BrokenTooth):
        raise InputError("fault", "broken", "a broken tooth carries no load; use "
                         "fe_neighbour_compliance for its effect on the neighbouring teeth")
    else:
        raise InputError("fault", type(fault).__name__,
                         "must be a Spall or a ChippedTip (or None: healthy)")
    sector = mesh_sector(gear, options=opt, shapes=shapes)
    return _result(gear, sector, r, plane, opt, fault, tuple(shapes), t0)


def fe_neighbour_compliance(gear: Gear, radii, *, missing: str = "next",
                            fault: BrokenTooth | None = None, plane: str = "stress",
                            options: SectorOptions | None = None) -> FEFaultResult:
    """FE compliance of a healthy tooth whose neighbour is broken off.

    The loaded (middle) tooth is healthy and loaded as in
    :func:`gearsim.fem.tooth.fe_tooth_compliance`; the neighbour named by ``missing``
    has the outline of :func:`broken_shape` (a stump up to the break line). The change
    from the healthy gear is the foundation effect of the missing tooth, which the
    potential-energy model (Sainsot foundation term of each tooth on its own) leaves
    out.

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii on the involute of the loaded flank [m].
    missing
        ``"next"``: the neighbour on the ``+x`` side, which the loaded flank faces
        (tooth index +1); ``"previous"``: the one behind the unloaded flank (-1);
        ``"both"``.
    fault
        The broken tooth (its ``break_radius``), or ``None`` for a break at the 30 deg
        tangent point. Its ``tooth``, ``width`` and ``edge`` are not used (2D model, the
        break through the whole face).
    plane
        ``"stress"`` or ``"strain"``.
    options
        Mesh options (:class:`~gearsim.fem.geometry.SectorOptions`); a sector needs
        ``n_teeth >= 3`` (always true).

    Returns
    -------
    FEFaultResult
        Compliance [m/N] of the loaded tooth for a face width of 1 m.

    Raises
    ------
    InputError
        ``missing`` not one of :data:`NEIGHBOURS`; ``broken.break_radius`` off the
        fillet; radii off the involute.

    References
    ----------
    Chaari et al. (2008) (tooth breakage); Sainsot et al. (2004) (gear body).
    """
    t0 = time.perf_counter()
    _check_plane(plane)
    if missing not in NEIGHBOURS:
        raise InputError("missing", missing, "must be " + ", ".join(f'"{k}"' for k in NEIGHBOURS))
    if fault is not None and not isinstance(fault, BrokenTooth):
        raise InputError("fault", type(fault).__name__, "must be a BrokenTooth or None")
    opt = options or SectorOptions()
    prof = ToothProfile(gear)
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    _check_radii(gear, prof, r)
    shape = broken_shape(gear, fault)
    shapes = {k: shape for k in NEIGHBOURS[missing]}
    sector = mesh_sector(gear, options=opt, shapes=shapes)
    return _result(gear, sector, r, plane, opt, fault, tuple(shapes), t0)
