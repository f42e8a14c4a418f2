"""Finite-element compliance of an internal (ring) gear tooth on its rim (Hertz excluded).

Purpose: an independent 2D reference for the potential-energy model of a ring tooth
with its rim (Chen & Shao 2013), measured like the external tooth of
:mod:`gearsim.fem.tooth`.

Geometry (transverse plane, lengths in m, angles in rad). For a :class:`RingGear` with
z, m_t, alpha_t, base radius r_b, tip (inner) radius r_a, root (outer) radius r_f and
profile shift x, the tooth thickness on the reference circle r is
s_r = m_t (pi/2 - 2 x tan alpha_n) and the half angular thickness at radius rho is

    beta(rho) = s_r / (2 r) - inv(alpha_t) + inv(alpha_rho),  cos(alpha_rho) = r_b / rho,

so that ring teeth thicken outwards. Tooth k of the segment has its centre line at the
polar angle theta = k 2 pi / z measured from ``+y`` towards ``+x`` (a point is
(rho sin theta, rho cos theta)); its flanks are the involutes theta = k 2 pi / z +- beta(rho)
for rho in [r_a, rho_t], its tip the arc r = r_a. At the root each flank joins the root
circle r_f through a circular fillet of radius ``ROOT_FILLET * m_n`` tangent to the
involute (at rho_t slightly below r_f) and to the root circle (a stand-in for the
trochoid a shaper cutter leaves). The rim runs from r_f out to r_o = r_f + rim
thickness (default ``RIM_THICKNESS * m_n``). The model is a segment of ``n_teeth``
(odd) teeth, the loaded tooth k = 0 in the middle, cut by two radial lines
r_f <= rho <= r_o through the middle of the outer tooth spaces.

Support: ``"outer"`` clamps the outer circle r_o (ring pressed into a rigid housing),
the side cuts are free; ``"outer+sides"`` clamps the side cuts too (the difference
shows how much the segment size matters).

Load and measure (the external-tooth conventions of :mod:`gearsim.fem.tooth` mirrored
to an internal tooth): contact at radius r_c on the ``+x`` flank of the middle tooth,
point P = (r_c sin beta_c, r_c cos beta_c), beta_c = beta(r_c). The planet pushes the
ring tooth towards its centre line and towards its root, along the line of action

    d = (-cos a1, +sin a1),  a1 = alpha_c + beta_c,  cos(alpha_c) = r_b / r_c,

which is the inward normal of the involute at P (d = sin(alpha_c) e_r - cos(alpha_c)
e_theta). The unit force (per metre of face width) is spread over the flank as the
smooth bell of :mod:`gearsim.fem.tooth` (half length ``PATCH_HALF_LENGTH * m_n``) and
the compliance is the displacement along d of the point Q where the line of action
crosses the tooth centre line,

    Q = (0, r_c (cos beta_c + sin beta_c tan a1)),   c = u(Q) . d   [m/N, b = 1 m],

away from the contact so that the local (Hertzian) indentation is excluded (Sainsot et
al. 2004). Q lies on the root side of P, inside the tooth or, for contacts near the
root, in the rim.

Mesh: gmsh, linear triangles sized ``h = m_n / (4 2^level)`` on and near the middle
tooth (``level`` as in :func:`gearsim.fem.geometry.element_size`), growing with slope
0.3 away from it; quadratic (P2) displacements (:class:`gearsim.fem.solve.ElasticModel`).
One mesh and one sparse LU factorisation serve all contact radii.

References
----------
.. [ChenShao2013] Z. Chen, Y. Shao, Mesh stiffness of an internal spur gear pair with
   ring gear rim deformation, Mech. Mach. Theory 69 (2013) 1-12 (potential-energy model
   of the ring tooth on a flexible rim).
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004)
   748-752 (deflection measured away from the contact to remove the Hertzian part).
.. [ISO6336-3] ISO 6336-3:2019, Calculation of load capacity of spur and helical gears -
   Part 3: tooth bending strength (rim thickness of internal gears, about 3-3.5 m_n).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.fem.geometry import (
    distance_threshold,
    drop_unused_nodes,
    generate_sized,
    gmsh_nodes_on,
    gmsh_session,
    gmsh_triangles,
    kept_nodes,
)
from gearsim.fem.solve import ElasticModel
from gearsim.fem.tooth import PATCH_HALF_LENGTH, bell_loads, deflection_along_load
from gearsim.geometry.gear import inv
from gearsim.geometry.planetary import RingGear

__all__ = ["RIM_THICKNESS", "ROOT_FILLET", "FERingResult", "RingSegmentMesh",
           "check_ring_fillets", "fe_ring_tooth_compliance", "fe_ring_tooth_result",
           "mesh_ring_segment",
           "ring_involute_limit", "ring_load_geometry", "ring_tooth_half_angle"]

#: Default rim thickness below the root circle, in normal modules [-] (ISO 6336-3's usual
#: minimum rim of internal gears is about 3-3.5 m_n).
RIM_THICKNESS = 3.5
#: Radius of the circular root fillet, in normal modules [-] (a pinion-type shaper
#: cutter's tip radius is typically 0.2-0.4 m_n).
ROOT_FILLET = 0.25
#: Interpolation points of each involute flank spline.
N_FLANK = 40
#: Largest refinement level accepted (level 3: about 3 s per solve for a 2 mm module).
MAX_LEVEL = 5
SUPPORTS = ("outer", "outer+sides")


def ring_tooth_half_angle(ring: RingGear, rho) -> np.ndarray:
    """Half angular thickness beta(rho) of a ring tooth (module docstring).

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    rho : float or array_like
        Radii >= r_b [m].

    Returns
    -------
    ndarray
        beta(rho) = s_r / (2 r) - inv(alpha_t) + inv(alpha_rho) [rad].

    Examples
    --------
    z 78, m 2 mm, x 0: on the reference circle beta = pi / (2 z).

    >>> r = RingGear(teeth=78, normal_module=2e-3)
    >>> bool(abs(ring_tooth_half_angle(r, r.pitch_radius) - math.pi / 156) < 1e-12)
    True
    """
    rho = np.asarray(rho, dtype=float)
    s_r = ring.transverse_module * (0.5 * math.pi - 2.0 * ring.profile_shift
                                    * math.tan(ring.normal_pressure_angle))
    alpha = np.arccos(np.clip(ring.base_radius / rho, -1.0, 1.0))
    return s_r / (2.0 * ring.pitch_radius) - inv(ring.transverse_pressure_angle) \
        + (np.tan(alpha) - alpha)


def ring_load_geometry(ring: RingGear, radius: float
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Contact point, unit force direction and measure point Q on the ring tooth.

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    radius : float
        Contact radius r_c on the ``+x`` involute of the middle tooth [m].

    Returns
    -------
    point, direction, q : ndarray
        P = (r_c sin beta_c, r_c cos beta_c) [m]; d = (-cos a1, sin a1) [-] with
        a1 = alpha_c + beta_c; Q = (0, r_c (cos beta_c + sin beta_c tan a1)) [m].
    """
    b = float(ring_tooth_half_angle(ring, radius))
    alpha = math.acos(min(1.0, ring.base_radius / radius))
    a1 = alpha + b
    p = np.array([radius * math.sin(b), radius * math.cos(b)])
    d = np.array([-math.cos(a1), math.sin(a1)])
    q = np.array([0.0, radius * (math.cos(b) + math.sin(b) * math.tan(a1))])
    return p, d, q


def ring_involute_limit(ring: RingGear) -> float:
    """Radius rho_t where the loaded involute of the FE ring tooth meets its root fillet [m].

    The fillet of radius ``ROOT_FILLET * m_n`` is tangent to the involute at rho_t and
    to the root circle r_f (module docstring); contact radii of the FE ring tooth lie in
    [r_a, rho_t].

    Parameters
    ----------
    ring : RingGear
        The internal gear.

    Returns
    -------
    float
        rho_t, slightly below r_f [m].

    Examples
    --------
    >>> r = RingGear(teeth=78, normal_module=2e-3)
    >>> bool(r.tip_radius < ring_involute_limit(r) < r.root_radius)
    True
    """
    return _root_fillet(ring, ROOT_FILLET * ring.normal_module)[0]


def check_ring_fillets(ring: RingGear) -> tuple[float, float, float]:
    """Refuse a ring whose FE root fillets would overlap; return the fillet's placement.

    Parameters
    ----------
    ring : RingGear
        The internal gear.

    Returns
    -------
    rho_t, theta_centre, theta_root : float
        Where the fillet of radius ``ROOT_FILLET * m_n`` meets the involute [m] and the
        polar angles of its centre and its root-circle tangent point [rad].

    Raises
    ------
    InputError
        If the fillets of neighbouring teeth overlap (theta_root >= pi / z): the segment
        cannot be meshed.
    """
    fr = ROOT_FILLET * ring.normal_module
    rho_t, th_c, th_root = _root_fillet(ring, fr)
    if not th_root < math.pi / ring.teeth:
        raise InputError("ring.root_fillet", f"{fr * 1e3:.4g} mm",
                         f"the root fillets of neighbouring teeth of a {ring.teeth}-tooth ring "
                         "overlap in the FE ring segment (the ring tooth of the default "
                         'stiffness model; [stiffness] model = "seed" takes the '
                         "potential-energy ring tooth)")
    return rho_t, th_c, th_root


@dataclass
class RingSegmentMesh:
    """Linear triangulation of a ring segment.

    Parameters
    ----------
    p : ndarray
        Nodes, shape (2, n) [m].
    t : ndarray
        Triangles, shape (3, m).
    outer, sides, flank : ndarray
        Node indices on the outer circle r_o, on the two side cuts, and on the ``+x``
        involute of the middle tooth.
    h : float
        Element size on the middle tooth [m].
    fillet_radius : float
        rho_t, where the involute meets the root fillet [m].
    outer_radius : float
        r_o [m].
    """

    p: np.ndarray
    t: np.ndarray
    outer: np.ndarray
    sides: np.ndarray
    flank: np.ndarray
    h: float
    fillet_radius: float
    outer_radius: float


def _polar(rho, theta) -> np.ndarray:
    """Points (rho sin theta, rho cos theta), shape (n, 2)."""
    rho, theta = np.broadcast_arrays(np.asarray(rho, float), np.asarray(theta, float))
    return np.column_stack([rho * np.sin(theta), rho * np.cos(theta)]).reshape(-1, 2)


def _root_fillet(ring: RingGear, radius: float) -> tuple[float, float, float]:
    """Fillet of the ``+x`` flank of tooth 0: (rho_t, theta_centre, theta_root).

    The fillet circle (radius ``radius``) is tangent to the root circle from inside
    (centre at r_f - radius, polar angle theta_centre; root tangent point at the same
    angle) and to the involute (tangent point at radius rho_t).
    """
    from scipy.optimize import brentq, minimize_scalar

    r_f = ring.root_radius
    rc = r_f - radius

    def closest(theta_c: float) -> tuple[float, float]:
        c = _polar(rc, theta_c)[0]

        def dist(rho: float) -> float:
            return float(np.hypot(*(_polar(rho, ring_tooth_half_angle(ring, rho))[0] - c)))

        lo = max(ring.base_radius * (1 + 1e-12), r_f - 4.0 * radius)
        res = minimize_scalar(dist, bounds=(lo, r_f + radius), method="bounded",
                              options={"xatol": 1e-12 * r_f})
        return float(res.x), float(res.fun)

    b_f = float(ring_tooth_half_angle(ring, r_f))
    theta_c = brentq(lambda th: closest(th)[1] - radius, b_f, b_f + 4.0 * radius / r_f,
                     xtol=1e-14)
    rho_t = closest(theta_c)[0]
    return rho_t, theta_c, theta_c


def mesh_ring_segment(ring: RingGear, *, rim_thickness: float, n_teeth: int, level: int
                      ) -> RingSegmentMesh:
    """Mesh a segment of the ring with gmsh (module docstring).

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    rim_thickness : float
        Rim below the root circle, r_o - r_f [m].
    n_teeth : int
        Teeth in the segment (odd), the loaded one in the middle.
    level : int
        Refinement level: h = m_n / (4 2^level) on the middle tooth.

    Returns
    -------
    RingSegmentMesh
        Triangulation and boundary node sets.

    Raises
    ------
    InputError
        If the root fillets of neighbouring teeth overlap.
    """
    mod = ring.normal_module
    z = ring.teeth
    pitch = 2.0 * math.pi / z
    r_a, r_f = ring.tip_radius, ring.root_radius
    r_o = r_f + rim_thickness
    fr = ROOT_FILLET * mod
    rho_t, th_c, th_root = check_ring_fillets(ring)
    h = mod / (4.0 * 2.0**level)
    h_max = min(16.0 * h, 0.5 * rim_thickness, 2.0 * mod)
    m = n_teeth // 2
    half_side = 0.5 * n_teeth * pitch
    rho_flank = np.linspace(rho_t, r_a, N_FLANK)  # root -> tip
    b_flank = ring_tooth_half_angle(ring, rho_flank)
    b_a = float(ring_tooth_half_angle(ring, r_a))
    with gmsh_session() as gmsh:
        geo = gmsh.model.geo
        centre = geo.addPoint(0.0, 0.0, 0.0)

        def pt(xy) -> int:
            return geo.addPoint(float(xy[0]), float(xy[1]), 0.0)

        def ppt(rho: float, theta: float) -> int:
            return pt(_polar(rho, theta)[0])

        curves: list[int] = []
        middle: list[int] = []
        flank_curve = -1
        # right side cut, outer circle -> root circle
        o_r, q_r = ppt(r_o, half_side), ppt(r_f, half_side)
        side_curves = [geo.addLine(o_r, q_r)]
        curves.append(side_curves[0])
        prev = q_r
        for k in range(m, -m - 1, -1):
            t0 = k * pitch
            tooth: list[int] = []
            # +x flank: root arc -> fillet -> involute (root to tip)
            root_p = ppt(r_f, t0 + th_root)
            curves.append(geo.addCircleArc(prev, centre, root_p))
            fc = ppt(r_f - fr, t0 + th_c)
            flank_pts = _polar(rho_flank, t0 + b_flank)
            start = pt(flank_pts[0])
            tooth.append(geo.addCircleArc(root_p, fc, start))
            tip_p = pt(flank_pts[-1])
            c = geo.addSpline([start, *[pt(xy) for xy in flank_pts[1:-1]], tip_p])
            tooth.append(c)
            if k == 0:
                flank_curve = c
            # tip arc
            tip_m = ppt(r_a, t0 - b_a)
            tooth.append(geo.addCircleArc(tip_p, centre, tip_m))
            # -x flank: involute (tip to root) -> fillet
            flank_m = _polar(rho_flank[::-1], t0 - b_flank[::-1])
            end = pt(flank_m[-1])
            tooth.append(geo.addSpline([tip_m, *[pt(xy) for xy in flank_m[1:-1]], end]))
            fc_m = ppt(r_f - fr, t0 - th_c)
            root_m = ppt(r_f, t0 - th_root)
            tooth.append(geo.addCircleArc(end, fc_m, root_m))
            curves.extend(tooth)
            if k == 0:
                middle = tooth
            prev = root_m
        q_l, o_l = ppt(r_f, -half_side), ppt(r_o, -half_side)
        curves.append(geo.addCircleArc(prev, centre, q_l))
        side_curves.append(geo.addLine(q_l, o_l))
        curves.append(side_curves[1])
        # outer circle from left to right through +y (arcs < pi)
        o_top = ppt(r_o, 0.0)
        outer_curves = [geo.addCircleArc(o_l, centre, o_top), geo.addCircleArc(o_top, centre, o_r)]
        curves += outer_curves
        loop = geo.addCurveLoop(curves)
        surf = geo.addPlaneSurface([loop])
        geo.synchronize()
        thr = distance_threshold(gmsh, curves=middle, sampling=200,
                                 size=(h, h_max),
                                 distance=(0.5 * mod, 0.5 * mod + (h_max - h) / 0.3))
        generate_sized(gmsh, thr)
        xy, index, tri = gmsh_triangles(gmsh, surf, "ring.geometry", "segment")
        outer_nodes = gmsh_nodes_on(gmsh, index, 1, outer_curves)
        side_nodes = gmsh_nodes_on(gmsh, index, 1, side_curves)
        flank_nodes = gmsh_nodes_on(gmsh, index, 1, [flank_curve])
    p, t, renum = drop_unused_nodes(xy, tri)
    return RingSegmentMesh(p=p, t=t, outer=kept_nodes(renum, outer_nodes),
                           sides=kept_nodes(renum, side_nodes),
                           flank=kept_nodes(renum, flank_nodes), h=h,
                           fillet_radius=rho_t, outer_radius=r_o)


@dataclass
class FERingResult:
    """FE ring-tooth compliance and how it was obtained.

    Parameters
    ----------
    radii : ndarray
        Contact radii [m].
    compliance : ndarray
        Compliance at each radius for a face width of 1 m [m/N] (Hertz excluded).
    tip_displacement : ndarray
        Shape (2, n): displacement of the tooth centre point (0, r_a + m_n / 4) under
        each unit load [m per N/m] (its x component is negative: the tooth bends
        towards -x).
    level : int
        Mesh refinement level.
    h : float
        Element size on the loaded tooth [m].
    nodes, elements, dofs : int
        Mesh and problem size.
    mesh_seconds, solve_seconds : float
        Wall time of meshing, and of assembly, factorisation and solution [s].
    cross : ndarray or None
        With ``read_radii``: shape (n_read, n), the cross compliance X[i, j] of the
        neighbour tooth -1 read at Q(read_radii[i]) along its load direction under the
        unit load at radii[j] on tooth 0 [m/N, b = 1 m] (:func:`fe_ring_tooth_result`).
    """

    radii: np.ndarray
    compliance: np.ndarray
    tip_displacement: np.ndarray
    level: int
    h: float
    nodes: int
    elements: int
    dofs: int
    mesh_seconds: float
    solve_seconds: float
    cross: np.ndarray | None = None


def _check(ring: RingGear, r: np.ndarray, plane: str, rim: float, n_teeth, support: str,
           level) -> None:
    if not isinstance(ring, RingGear):
        raise InputError("ring", type(ring).__name__, "must be a RingGear")
    if plane not in ("stress", "strain"):
        raise InputError("plane", plane, 'must be "stress" or "strain"')
    if support not in SUPPORTS:
        raise InputError("support", support, 'must be "outer" or "outer+sides"')
    if not (math.isfinite(rim) and rim > 0.0):
        raise InputError("rim_thickness", rim, "must be > 0 m")
    if not (isinstance(n_teeth, (int, np.integer)) and not isinstance(n_teeth, bool)
            and n_teeth >= 3 and n_teeth % 2 == 1):
        raise InputError("n_teeth", n_teeth, "must be an odd integer >= 3")
    if n_teeth > ring.teeth // 2:
        raise InputError("n_teeth", n_teeth, f"must be <= z / 2 = {ring.teeth // 2} (a segment "
                         "of at most half the ring)")
    if not (isinstance(level, (int, np.integer)) and not isinstance(level, bool)
            and 0 <= level <= MAX_LEVEL):
        raise InputError("level", level, f"must be an integer in [0, {MAX_LEVEL}]")
    r_a, r_f = ring.tip_radius, ring.root_radius
    if not r_a > ring.base_radius:
        raise InputError("ring.tip_radius", r_a, f"must exceed the base radius "
                         f"{ring.base_radius:.6g} m (involute flanks from the tip circle)")
    if r.size == 0:
        raise InputError("radii", "[]", "give at least one contact radius")
    bad = ~np.isfinite(r) | (r < r_a * (1 - 1e-12)) | (r > r_f * (1 + 1e-12))
    if np.any(bad):
        raise InputError("radii", float(r[bad][0]),
                         f"must lie in [r_a, r_f] = [{r_a:.6g}, {r_f:.6g}] m")


def fe_ring_tooth_result(ring: RingGear, radii, *, youngs_modulus: float = 2.06e11,
                         poisson_ratio: float = 0.3, plane: str = "stress",
                         rim_thickness: float | None = None, n_teeth: int = 5,
                         support: str = "outer", level: int = 2,
                         read_radii=None) -> FERingResult:
    """FE ring-tooth compliance with mesh data and timings (module docstring).

    With ``read_radii`` the same solutions also give the body coupling of neighbouring
    ring teeth, measured as :mod:`gearsim.fem.coupling` measures it on an external gear:

        X(r_read, r_load) = d_-1(r_read) . u(Q_-1(r_read))  under the unit load at r_load
        on tooth 0,

    d_-1 and Q_-1 the load direction and measure point of tooth -1 (tooth 0's rotated by
    one pitch, 2 pi / z, towards -x), whose ``+x`` (loaded-flank side) neighbour is the
    loaded tooth 0. By the segment's symmetry it stands for a tooth read under a load on
    its ``+x`` neighbour.

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    radii : float or array_like
        Contact radii on the ``+x`` flank of the middle tooth [m], within [r_a, rho_t]
        (rho_t: where the involute meets the root fillet, just below r_f).
    youngs_modulus : float
        E [Pa].
    poisson_ratio : float
        nu [-].
    plane : {"stress", "strain"}
        Plane assumption.
    rim_thickness : float, optional
        r_o - r_f [m]; default ``RIM_THICKNESS * m_n``.
    n_teeth : int
        Teeth in the segment (odd, >= 3, <= z / 2).
    support : {"outer", "outer+sides"}
        Clamped boundary: the outer circle, or the outer circle and the side cuts.
    level : int
        Mesh refinement level (element size m_n / (4 2^level) on the loaded tooth).
    read_radii : float or array_like, optional
        Contact radii at which the neighbour tooth -1 is read for the cross compliance
        (same range as ``radii``) [m]; default none (``cross`` is None).

    Returns
    -------
    FERingResult
        Compliance [m/N] for a face width of 1 m at each radius, the cross compliance
        (with ``read_radii``), and run data.

    Raises
    ------
    InputError
        Radii outside [r_a, r_f] (or on the root fillet), n_teeth even, < 3 or > z / 2,
        unknown plane or support, rim_thickness <= 0, level outside [0, MAX_LEVEL], the
        tip circle inside the base circle.
    """
    t0 = time.perf_counter()
    r = np.atleast_1d(np.asarray(radii, dtype=float)).ravel()
    rim = RIM_THICKNESS * ring.normal_module if rim_thickness is None else float(rim_thickness)
    _check(ring, r, plane, rim, n_teeth, support, level)
    rd = None
    if read_radii is not None:
        rd = np.atleast_1d(np.asarray(read_radii, dtype=float)).ravel()
        _check(ring, rd, plane, rim, n_teeth, support, level)
    seg = mesh_ring_segment(ring, rim_thickness=rim, n_teeth=int(n_teeth), level=int(level))
    for name, rr in (("radii", r), ("read_radii", rd)):
        if rr is not None and np.any(rr > seg.fillet_radius * (1 + 1e-12)):
            raise InputError(name, float(rr[rr > seg.fillet_radius][0]),
                             f"lies on the root fillet: the involute ends at "
                             f"{seg.fillet_radius:.6g} m (root circle {ring.root_radius:.6g} m)")
    t1 = time.perf_counter()
    model = ElasticModel(seg.p, seg.t, youngs_modulus, poisson_ratio, plane=plane, order=2)
    fixed_nodes = seg.outer if support == "outer" else np.union1d(seg.outer, seg.sides)
    fixed = model.dofs_on_facets(model.facets_on_nodes(fixed_nodes))
    flank = model.facets_on_nodes(seg.flank)
    half = PATCH_HALF_LENGTH * ring.normal_module
    loads, dirs, qs = bell_loads(model, flank, [ring_load_geometry(ring, float(rk))
                                                for rk in r], half)
    u = model.solve(loads, fixed)  # one LU factorisation for all radii
    comp = deflection_along_load(model, u, dirs, qs)
    tip = model.probe(np.array([[0.0], [ring.tip_radius + 0.25 * ring.normal_module]])) @ u
    cross = None
    if rd is not None:  # tooth -1: polar angle - 2 pi / z, a counter-clockwise rotation
        pitch = 2.0 * math.pi / ring.teeth
        c, s = math.cos(pitch), math.sin(pitch)
        rot = np.array([[c, -s], [s, c]])
        geo = [ring_load_geometry(ring, float(rk)) for rk in rd]
        d_read = np.array([rot @ g[1] for g in geo])
        q_read = np.array([rot @ g[2] for g in geo]).T
        vals = model.probe(q_read) @ u  # (2 n_read, n): x rows then y rows
        n_read = rd.size
        cross = d_read[:, :1] * vals[:n_read] + d_read[:, 1:] * vals[n_read:]
    t2 = time.perf_counter()
    return FERingResult(radii=r, compliance=comp, tip_displacement=np.asarray(tip),
                        level=int(level), h=seg.h, nodes=int(model.mesh.p.shape[1]),
                        elements=int(model.mesh.t.shape[1]), dofs=model.ndofs,
                        mesh_seconds=t1 - t0, solve_seconds=t2 - t1,
                        cross=None if cross is None else np.asarray(cross))


def fe_ring_tooth_compliance(ring: RingGear, radii, *, youngs_modulus: float = 2.06e11,
                             poisson_ratio: float = 0.3, plane: str = "stress",
                             rim_thickness: float | None = None, n_teeth: int = 5,
                             support: str = "outer", level: int = 2) -> np.ndarray:
    """FE compliance of a ring tooth on its rim at contact radii (Hertz excluded).

    See the module docstring for geometry, load and measure; the potential-energy model
    it checks is that of Chen & Shao (2013), the measure point away from the contact
    that of Sainsot et al. (2004).

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    radii : float or array_like
        Contact radii on the loaded flank [m], within [r_a, r_f] and below the root
        fillet.
    youngs_modulus : float
        E [Pa].
    poisson_ratio : float
        nu [-].
    plane : {"stress", "strain"}
        Plane assumption.
    rim_thickness : float, optional
        Rim thickness r_o - r_f [m]; default ``RIM_THICKNESS * m_n`` = 3.5 m_n.
    n_teeth : int
        Teeth in the segment (odd, >= 3), the loaded one in the middle.
    support : {"outer", "outer+sides"}
        ``"outer"``: outer circle clamped, side cuts free; ``"outer+sides"``: both
        clamped.
    level : int
        Mesh refinement level: element size m_n / (4 2^level) on the loaded tooth.

    Returns
    -------
    ndarray, shape (n,)
        Compliance u(Q) . d per unit force for a face width of 1 m [m/N].

    Raises
    ------
    InputError
        Bad input (see :func:`fe_ring_tooth_result`).

    Examples
    --------
    >>> ring = RingGear(teeth=78, normal_module=2e-3)
    >>> c = fe_ring_tooth_compliance(ring, ring.pitch_radius, level=0)
    >>> bool(1e-11 < c[0] < 1e-10)
    True
    """
    return fe_ring_tooth_result(ring, radii, youngs_modulus=youngs_modulus,
                                poisson_ratio=poisson_ratio, plane=plane,
                                rim_thickness=rim_thickness, n_teeth=n_teeth,
                                support=support, level=level).compliance
