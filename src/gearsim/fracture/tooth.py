"""Root crack in a gear tooth: K_I, K_II under a flank load and MTS growth increments.

Model: a sector of ``n_teeth`` (odd, default 3) teeth of the gear with the cracked tooth
in the middle, from the rim down to the bore, radial sides through the middle of the
tooth spaces; the bore and the sides are fixed (the sector model of
:mod:`gearsim.fem.geometry` with ``sides = "fixed"``). The outline is a polygon through
points of :meth:`ToothProfile.outline` (fine on the middle tooth, coarse on the others)
and arcs (tips, tooth spaces, bore); the crack is a polyline from the fillet
(:class:`gearsim.fracture.mesh.CrackPath`), so that a grown, kinked path is meshed as
it is (:func:`gearsim.fracture.mesh.mesh_cracked_polygon`, remeshed at every step).
With ``web=RimWeb(...)`` the sector goes on below the rim down to a fixed hub through a
web whose stiffness is scaled by its thickness / face width (:class:`RimWeb`), so that a
thin rim bends under the tooth load (docs/fracture.md, "Rim thickness").

Load: a force per unit face width on the loaded (+x) flank at a contact radius r,
along the contact normal of :func:`gearsim.fem.tooth.load_geometry` (the PE line of
action, pushing the tooth towards -x, so that the +x fillet is in tension), spread as
the smooth bell traction of :mod:`gearsim.fem.tooth` (half length
``PATCH_HALF_LENGTH m_n``) scaled to the exact resultant. The crack faces are free
(no contact): right for a crack on the loaded (tensile) fillet.

K at the tip by the interaction integral (:func:`gearsim.fracture.sif.interaction_integral`)
on a ring r_out = ``RING_FRACTION`` x min(last segment length, distance from the tip to
the outline), the tip elements r_out / ``TIP_DIVISIONS``.

Growth increment (maximum tangential stress, Erdogan & Sih 1963): the tip moves by
``da`` along the crack direction turned by the kink angle theta_c(K_I, K_II)
(:func:`gearsim.fracture.direction.kinked_direction`), the new point is appended to
the polyline, and the next K is computed on a new mesh (the incremental scheme of
e.g. Lewicki & Ballarini 1997 with FRANC, there with quarter-point elements).

References
----------
.. [Lewicki1997] D. G. Lewicki, R. Ballarini, Effect of rim thickness on gear crack
   propagation path, J. Mech. Des. 119 (1997) 88-95.
.. [Erdogan1963] F. Erdogan, G. C. Sih, J. Basic Eng. 85 (1963) 519-525.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError, require
from gearsim.fem.geometry import point_in_polygon
from gearsim.fem.solve import ElasticModel, plane_lame
from gearsim.fem.tooth import PATCH_HALF_LENGTH, load_geometry
from gearsim.fracture.contact import closed_crack_intensity
from gearsim.fracture.direction import equivalent_k, kink_angle, kinked_direction
from gearsim.fracture.mesh import CrackedMesh, CrackPath, mesh_cracked_polygon, mesh_polygon
from gearsim.fracture.sif import StressIntensity, interaction_integral
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile

__all__ = ["RING_FRACTION", "TIP_DIVISIONS", "CycleIntensity", "RimWeb", "ToothCrackResult",
           "cycle_intensity", "fillet_stress", "grow_crack", "initial_crack",
           "sector_polygon", "tooth_crack_sif"]

#: Outer ring radius of the interaction integral over min(last segment, distance to the
#: outline) [-].
RING_FRACTION = 0.4
#: Outer ring radius over the tip element size [-].
TIP_DIVISIONS = 30.0
#: Points per fillet / involute of the middle tooth and of the other teeth.
FINE_POINTS = (160, 60)
COARSE_POINTS = (8, 10)


@dataclass(frozen=True)
class RimWeb:
    """A web below the rim: the support that lets a thin rim bend.

    The sector then runs from the teeth down to ``hub_radius`` instead of stopping at
    the rim's inner radius (``bore_radius`` of :func:`sector_polygon`): the ring
    between ``hub_radius`` and ``bore_radius`` is the web, modelled in 2D plane stress
    with its own thickness (the element stiffness there scaled by
    ``thickness_ratio`` = web thickness / face width); the hub circle and the sides
    are fixed. The rim above is a ring on an elastic web that bends under the tooth
    load, as in the thin-rim test gears of Lewicki & Ballarini (1997, NASA
    TM-107229), made by machining a web into a solid gear, and in Curà, Mura & Rosso
    (2014), whose thin-rim gears have a web below the rim. The web dimensions of the
    test gears are not given here: ``hub_radius`` and ``thickness_ratio`` are inputs.

    The sector's sides stay fixed, which a whole gear's rim is not: with a web, take
    enough teeth (``n_teeth`` of :func:`sector_polygon` and the K functions) that the
    sides do not hold the bending rim. For the NASA test gear (z = 28) at backup ratio
    0.5 a crack low in the fillet breaks the tooth with 3 teeth and the rim with 5 to
    13 (coarse paths; docs/fracture.md, "Rim thickness"); the tests use 9. With 15
    of 28 teeth (a sector of 193 deg), with or without the web, gmsh did not finish
    meshing (over 60 s, against 0.7 s for a whole K solve with 13).

    Parameters
    ----------
    hub_radius
        Radius where the web meets the (rigid, fixed) hub [m]; > 0 and below the rim's
        inner radius.
    thickness_ratio
        Web thickness over the face width [-], in (0, 1] (1: a solid disc).

    Raises
    ------
    InputError
        ``hub_radius`` not finite and > 0, or ``thickness_ratio`` outside (0, 1].

    References
    ----------
    D. G. Lewicki, R. Ballarini, Effect of rim thickness on gear crack propagation
    path, J. Mech. Des. 119 (1997) 88-95 (NASA TM-107229). F. Curà, A. Mura,
    C. Rosso, Investigation about crack propagation paths in thin rim gears, Frattura
    ed Integrità Strutturale 30 (2014) 446-453.
    """

    hub_radius: float
    thickness_ratio: float

    def __post_init__(self) -> None:
        r = self.hub_radius
        w = self.thickness_ratio
        require(isinstance(r, (int, float)) and math.isfinite(r) and r > 0.0,
                "web.hub_radius", r, "must be > 0 m")
        require(isinstance(w, (int, float)) and math.isfinite(w) and 0.0 < w <= 1.0,
                "web.thickness_ratio", w, "must be in (0, 1] (web thickness / face width)")


@dataclass(frozen=True)
class ToothCrackResult:
    """Stress intensity at the tip of a tooth-root crack under a flank load.

    Parameters
    ----------
    crack
        The crack path the result is for.
    sif
        K_I, K_II at its tip [Pa sqrt(m)] for the given force.
    kink
        MTS kink angle theta_c [rad] (tip frame, towards +x2 = the crack direction
        turned by +90 deg).
    force
        Force per unit face width [N/m].
    radius
        Contact radius [m].
    dofs
        Displacement unknowns of the FE model.
    h_tip
        Element size at the tip [m].
    seconds
        Wall time of meshing, solving and the integral [s].
    """

    crack: CrackPath
    sif: StressIntensity
    kink: float
    force: float
    radius: float
    dofs: int
    h_tip: float
    seconds: float


def _dedupe(pts: np.ndarray) -> np.ndarray:
    keep = np.ones(pts.shape[0], dtype=bool)
    scale = max(1.0, float(np.abs(pts).max()))
    keep[1:] = np.hypot(*np.diff(pts, axis=0).T) > 1e-12 * scale
    return pts[keep]


def _rot(pts: np.ndarray, ang: float) -> np.ndarray:
    c, s = math.cos(ang), math.sin(ang)
    return np.column_stack([c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]])


def _arc(r: float, a0: float, a1: float, n: int) -> np.ndarray:
    """Interior points of the arc of radius r from polar angle a0 to a1 (ends excluded)."""
    ang = np.linspace(a0, a1, n + 2)[1:-1]
    return np.column_stack([r * np.cos(ang), r * np.sin(ang)])


def _tooth(half: np.ndarray, n_tip: int) -> np.ndarray:
    """One tooth, +x root -> tip -> -x root, tip arc through ``n_tip`` interior points."""
    r_tip = float(np.hypot(*half[-1]))
    a_r = math.atan2(half[-1, 1], half[-1, 0])
    tip = _arc(r_tip, a_r, math.pi - a_r, n_tip)
    left = (half[::-1] * [-1.0, 1.0])
    return np.vstack([half, tip, left])


def sector_polygon(gear: Gear, n_teeth: int = 3, *, bore_radius: float | None = None,
                   web: RimWeb | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Outline polygon of a gear sector with the middle tooth on +y.

    Parameters
    ----------
    gear
        The gear (bore radius :attr:`Gear.bore_radius_value`).
    n_teeth
        Odd number of teeth, 3 <= n_teeth < z.
    bore_radius
        Inner radius of the rim [m], below the root radius; default
        :attr:`Gear.bore_radius_value`. Thin rims (backup ratio
        (r_f - r_bore) / (r_a - r_f) below 1, Lewicki & Ballarini 1997) need it: the
        ``Gear`` itself keeps its bore below 0.9 r_f.
    web
        ``None`` (default): the bore is fixed. A :class:`RimWeb`: the outline goes on
        down to ``web.hub_radius`` (the web, below the rim's inner radius
        ``bore_radius``), and the hub circle is fixed instead of the bore.

    Returns
    -------
    polygon : ndarray, shape (n, 2)
        Counter-clockwise along the teeth, then the left side, the bore (or hub) and
        the right side [m].
    fixed : ndarray, shape (k, 2, 2)
        Segments of the fixed boundary (sides and bore, or sides and hub) [m].

    Raises
    ------
    InputError
        Even or out-of-range ``n_teeth``, a bore not below the root circle, or a hub
        not below the bore (``web.hub_radius``).
    """
    z = gear.teeth
    require(isinstance(n_teeth, int) and n_teeth >= 3 and n_teeth % 2 == 1 and n_teeth < z,
            "fracture.n_teeth", n_teeth, f"must be an odd integer in [3, {z - 1}]")
    prof = ToothProfile(gear)
    fine = _dedupe(prof.outline(*FINE_POINTS))
    coarse = _dedupe(prof.outline(*COARSE_POINTS))
    r_root = float(np.hypot(*fine[0]))
    bore = gear.bore_radius_value if bore_radius is None else float(bore_radius)
    require(math.isfinite(bore) and 0.0 < bore < r_root, "fracture.bore_radius", bore,
            f"must be in (0, root radius {r_root:.6g} m)")
    if web is not None:
        require(isinstance(web, RimWeb), "web", type(web).__name__, "must be a RimWeb or None")
        require(web.hub_radius < bore, "web.hub_radius", web.hub_radius,
                f"must be below the rim's inner radius {bore:.6g} m")
        bore = web.hub_radius
    pitch = 2.0 * math.pi / z
    m = n_teeth // 2
    half_side = 0.5 * n_teeth * pitch
    phi_r, phi_l = 0.5 * math.pi - half_side, 0.5 * math.pi + half_side
    pts: list[np.ndarray] = []
    b_r = np.array([[bore * math.cos(phi_r), bore * math.sin(phi_r)]])
    q_r = np.array([[r_root * math.cos(phi_r), r_root * math.sin(phi_r)]])
    pts += [b_r, q_r]
    prev_phi = phi_r
    for k in range(m, -m - 1, -1):
        tooth = _rot(_tooth(fine if k == 0 else coarse, 6 if k == 0 else 3), -k * pitch)
        a_first = math.atan2(tooth[0, 1], tooth[0, 0])
        pts.append(_arc(r_root, prev_phi, a_first, 2))
        pts.append(tooth)
        prev_phi = math.atan2(tooth[-1, 1], tooth[-1, 0])
    q_l = np.array([[r_root * math.cos(phi_l), r_root * math.sin(phi_l)]])
    b_l = np.array([[bore * math.cos(phi_l), bore * math.sin(phi_l)]])
    n_bore = max(8, 4 * n_teeth)
    bore_pts = _arc(bore, phi_l, phi_r, n_bore)
    pts += [_arc(r_root, prev_phi, phi_l, 2), q_l, b_l, bore_pts]
    poly = np.vstack(pts)
    chain = np.vstack([q_l, b_l, bore_pts, b_r, q_r])
    fixed = np.stack([chain[:-1], chain[1:]], axis=1)
    return poly, fixed


def _insert_vertex(poly: np.ndarray, pt: np.ndarray) -> np.ndarray:
    """The polygon with ``pt`` as a vertex, on (or replacing the vertex nearest to) it."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", pt - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    d = np.hypot(*(a + t[:, None] * ab - pt).T)
    i = int(np.argmin(d))
    seg = float(np.hypot(*ab[i]))
    if t[i] * seg < 1e-3 * seg:
        out = poly.copy()
        out[i] = pt
        return out
    if (1.0 - t[i]) * seg < 1e-3 * seg:
        out = poly.copy()
        out[(i + 1) % poly.shape[0]] = pt
        return out
    return np.vstack([poly[:i + 1], pt, poly[i + 1:]])


def initial_crack(gear: Gear, depth: float, *, angle: float | None = None,
                  start_angle: float = math.radians(30.0), side: int = 1) -> CrackPath:
    """A straight crack from the fillet of the middle tooth.

    Parameters
    ----------
    gear
        The gear.
    depth
        Crack length [m] (> 0, inside the tooth).
    angle
        Angle between the crack and the tooth centre line [rad] (the convention of
        :class:`gearsim.stiffness.crack.Crack`); ``None``: normal to the fillet at the
        start point.
    start_angle
        The start is the fillet point whose tangent makes this angle with the centre
        line [rad] (default 30 deg, ISO 6336-3 critical section).
    side
        +1: crack on the loaded (+x) fillet; -1: on the other one.

    Returns
    -------
    CrackPath
        Two points, start on the fillet, tip inside.

    Raises
    ------
    InputError
        Bad depth, angle or side.
    """
    require(side in (1, -1), "crack.side", side, "must be +1 (loaded flank) or -1")
    require(math.isfinite(depth) and depth > 0.0, "crack.depth", depth, "must be > 0 m")
    prof = ToothProfile(gear)
    g, _ = prof.tangent_point(start_angle)
    xs, ys = prof.fillet_point(g)
    if angle is None:
        dg = 1e-6
        x1, y1 = prof.fillet_point(g - dg)
        x2, y2 = prof.fillet_point(g + dg)
        t = np.array([x2 - x1, y2 - y1])
        n = np.array([-t[1], t[0]]) / np.hypot(*t)
        if n[0] > 0.0:  # inward: towards the centre line (-x for the +x fillet)
            n = -n
        d = n
    else:
        require(math.isfinite(angle) and 0.0 < angle <= 0.5 * math.pi, "crack.angle",
                angle, "must be in (0, pi/2] rad")
        d = np.array([-math.sin(angle), -math.cos(angle)])
    tip = np.array([xs, ys]) + depth * d
    s = float(side)
    return CrackPath(points=((s * xs, ys), (s * float(tip[0]), float(tip[1]))),
                     tips=(False, True))


def _dist_to_segments(pt: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", pt - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * ab - pt).T)


def _tip_clearance(poly: np.ndarray, crack: CrackPath, *, ahead: bool = False) -> float:
    """Distance from the tip to the outline [m]; ``ahead``: only to the outline points
    in front of the tip (the half plane the crack grows into)."""
    tip, d = crack.tip_frame(1)
    a, b = poly, np.roll(poly, -1, axis=0)
    if not ahead:
        return float(_dist_to_segments(tip, a, b).min())
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", tip - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    q = a + t[:, None] * ab
    dist = np.hypot(*(q - tip).T)
    front = (q - tip) @ d > 0.0
    # a segment partly in front: its end points count too
    for end in (a, b):
        f2 = (end - tip) @ d > 0.0
        dist = np.where(front | ~f2, dist, np.hypot(*(end - tip).T))
        front = front | f2
    return float(dist[front].min()) if np.any(front) else math.inf


def _rim_radius(gear: Gear, bore_radius: float | None) -> float:
    """Inner radius of the rim [m] (the bore of :func:`sector_polygon`)."""
    return gear.bore_radius_value if bore_radius is None else float(bore_radius)


def _scale_web(model: ElasticModel, rim_radius: float, web: RimWeb) -> None:
    """Scale the stiffness below ``rim_radius`` by ``web.thickness_ratio`` (in place).

    The thickness is a field over the quadrature points (order 6) of the elements that
    reach below the rim radius: the mesh does not follow the rim/web circle, an
    element across it gets the stiffness of its parts.
    """
    from skfem import Basis, BilinearForm
    from skfem.helpers import ddot, sym_grad, trace

    mesh = model.mesh
    r_nodes = np.hypot(*mesh.p)
    low = np.nonzero(r_nodes[mesh.t].min(axis=0) < rim_radius)[0]
    if low.size == 0:
        return
    lam, mu = plane_lame(model.youngs_modulus, model.poisson_ratio, model.plane)
    ratio = float(web.thickness_ratio)

    @BilinearForm
    def softer(u, v, w):
        r = np.hypot(w.x[0], w.x[1])
        c = np.where(r < rim_radius, ratio - 1.0, 0.0)
        eu, ev = sym_grad(u), sym_grad(v)
        return c * (2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev))

    basis = Basis(mesh, model.element, elements=low, intorder=6)
    model.K = (model.K + softer.assemble(basis)).tocsr()


def _sector_model(gear: Gear, p: np.ndarray, t: np.ndarray, fixed: np.ndarray, plane: str,
                  web: tuple[float, RimWeb] | None = None) -> tuple[ElasticModel, np.ndarray]:
    """P2 model of a sector mesh and its fixed dofs (nodes on the sides and the bore);
    ``web`` = (rim radius, :class:`RimWeb`): the web's stiffness scaled."""
    mat = gear.material
    model = ElasticModel(p, t, mat.youngs_modulus, mat.poisson_ratio, plane=plane, order=2)
    if web is not None:
        _scale_web(model, *web)
    pts = p.T
    dmin = np.full(pts.shape[0], np.inf)
    for a, b in fixed:
        ab = b - a
        tt = np.clip((pts - a) @ ab / (ab @ ab), 0.0, 1.0)
        dmin = np.minimum(dmin, np.hypot(*(a + tt[:, None] * ab - pts).T))
    fixed_nodes = np.nonzero(dmin < 1e-9 * gear.normal_module)[0]
    return model, model.dofs_on_facets(model.facets_on_nodes(fixed_nodes))


def _flank_load(model: ElasticModel, gear: Gear, radius: float, force: float, h: float
                ) -> np.ndarray:
    """Bell traction on the +x flank around the contact point, exact resultant."""
    point, direction, _ = load_geometry(ToothProfile(gear), radius)
    half = PATCH_HALF_LENGTH * gear.normal_module
    bf = model.mesh.boundary_facets()
    fa, fb = model.mesh.facets[0, bf], model.mesh.facets[1, bf]
    mid = 0.5 * (model.mesh.p[:, fa] + model.mesh.p[:, fb])
    near = bf[np.hypot(mid[0] - point[0], mid[1] - point[1]) < half + h]

    def traction(x, y):
        s = np.hypot(x - point[0], y - point[1]) / half
        w = np.where(s < 1.0, (1.0 - s * s) ** 2, 0.0)
        return w * direction[0], w * direction[1]

    f = model.traction_load(near, traction, intorder=8)
    xdofs = np.concatenate([model.basis.nodal_dofs[0], model.basis.facet_dofs[0]])
    ydofs = np.concatenate([model.basis.nodal_dofs[1], model.basis.facet_dofs[1]])
    resultant = float(f[xdofs].sum() * direction[0] + f[ydofs].sum() * direction[1])
    if not resultant > 0.0:
        raise InputError("radius", radius, "the load patch found no flank facets to load")
    return f * (force / resultant)


def _loaded_model(gear: Gear, p: np.ndarray, t: np.ndarray, fixed: np.ndarray, radius: float,
                  force: float, plane: str, h: float, web: tuple[float, RimWeb] | None = None
                  ) -> tuple[ElasticModel, np.ndarray, np.ndarray]:
    """P2 model of a sector mesh, its flank load vector and its fixed dofs."""
    model, fixed_dofs = _sector_model(gear, p, t, fixed, plane, web)
    return model, _flank_load(model, gear, radius, force, h), fixed_dofs


def _check_load(gear: Gear, radius: float, force: float, refinement: float) -> None:
    prof = ToothProfile(gear)
    lo, hi = max(prof.form_radius, gear.base_radius), gear.tip_radius
    require(math.isfinite(radius) and lo * (1 - 1e-9) <= radius <= hi * (1 + 1e-9), "radius",
            radius, f"must lie on the involute of {gear.name}, within [{lo:.6g}, {hi:.6g}] m")
    require(math.isfinite(force) and force > 0.0, "force", force, "must be > 0 N/m")
    require(0.25 <= refinement <= 8.0, "refinement", refinement, "must be in [0.25, 8]")


def fillet_stress(gear: Gear, radius: float, *, force: float = 1e5,
                  start_angle: float = math.radians(30.0), n_teeth: int = 3,
                  plane: str = "stress", h_focus: float | None = None,
                  bore_radius: float | None = None, web: RimWeb | None = None) -> float:
    """Tangential stress at a fillet point of the uncracked tooth under a flank load.

    At a free surface the stress is uniaxial along the outline:
    sigma_tt = t . sigma . t, from the P2 displacement gradient of the element that
    holds the point. Evaluated at the middle of the outline segment (of the fillet
    polygon, 160 points) that starts at the fillet point, about 10 um from it for
    m_n = 6 mm.

    Parameters
    ----------
    gear
        The gear.
    radius
        Contact radius of the load on the +x involute [m].
    force
        Normal force per unit face width [N/m].
    start_angle
        The fillet point of the +x flank whose tangent makes this angle with the
        centre line [rad] (the crack start of :func:`initial_crack`).
    n_teeth
        Teeth in the sector.
    plane
        ``"stress"`` or ``"strain"``.
    h_focus
        Element size at the point [m]; default 1/20 of the outline segment there.
    bore_radius, web
        Inner rim radius [m] and rim support (:func:`sector_polygon`); default: the
        gear's bore, fixed.

    Returns
    -------
    float
        sigma_tt [Pa] (positive: tension).

    Raises
    ------
    InputError
        Bad load or mesh parameters.
    """
    from skfem import Basis

    _check_load(gear, radius, force, 1.0)
    prof = ToothProfile(gear)
    g, _ = prof.tangent_point(start_angle)
    pt = np.array(prof.fillet_point(g))
    poly, fixed = sector_polygon(gear, n_teeth, bore_radius=bore_radius, web=web)
    web_model = None if web is None else (_rim_radius(gear, bore_radius), web)
    # evaluate in the middle of the outline segment that starts at the fillet point:
    # the polygon vertices are very obtuse corners whose weak singularity must not be
    # sampled (docs/fracture.md)
    poly = _insert_vertex(poly, pt)
    i = int(np.argmin(np.hypot(*(poly - pt).T)))
    nxt = poly[(i + 1) % poly.shape[0]]
    seg = float(np.hypot(*(nxt - pt)))
    mid = 0.5 * (pt + nxt)
    tan = (nxt - pt) / seg
    h = gear.normal_module / 4.0
    hf = seg / 20.0 if h_focus is None else float(h_focus)
    p, t = mesh_polygon(poly, h=h, focus=pt[None, :], h_focus=hf)
    model, f, fixed_dofs = _loaded_model(gear, p, t, fixed, radius, force, plane, h, web_model)
    u = model.solve(f, fixed_dofs)
    inward = np.array([-tan[1], tan[0]])
    if inward[0] > 0.0:
        inward = -inward
    q = mid + 1e-6 * hf * inward
    elem = model.mesh.element_finder()(np.array([q[0]]), np.array([q[1]]))
    xref = model.mesh.mapping().invF(q.reshape(2, 1, 1), tind=elem)
    basis = Basis(model.mesh, model.element, elements=elem,
                  quadrature=(xref[:, 0, :], np.ones(1)))
    grad = np.asarray(basis.interpolate(u).grad)[:, :, 0, 0]
    lam, mu = plane_lame(gear.material.youngs_modulus, gear.material.poisson_ratio, plane)
    eps = 0.5 * (grad + grad.T)
    sig = 2.0 * mu * eps + lam * np.trace(eps) * np.eye(2)
    return float(tan @ sig @ tan)


def _web_clearance(gear: Gear, poly: np.ndarray, crack: CrackPath,
                   bore_radius: float | None, web: RimWeb | None) -> float:
    """Distance from the tip to the outline and, with a web, to the rim's inner circle."""
    clearance = _tip_clearance(poly, crack)
    if web is None:
        return clearance
    tip, _ = crack.tip_frame(1)
    gap = float(np.hypot(*tip)) - _rim_radius(gear, bore_radius)
    require(gap > 0.0, "crack.points", tuple(tip),
            "the tip must lie in the rim, above its inner radius (the web)")
    return min(clearance, gap)


def _with_crack_mouth(gear: Gear, poly: np.ndarray, crack: CrackPath) -> np.ndarray:
    """``poly`` with the crack's start as a vertex (refused off the outline)."""
    start = crack.array[0]
    on = float(_dist_to_segments(start, poly, np.roll(poly, -1, axis=0)).min())
    require(on <= 1e-3 * gear.normal_module, "crack.points[0]", tuple(start),
            "the crack must start on the tooth outline")
    return _insert_vertex(poly, start)


def _cracked_sector(gear: Gear, crack: CrackPath, closure: str, n_teeth: int,
                    bore_radius: float | None, web: RimWeb | None, refinement: float
                    ) -> tuple[CrackedMesh, np.ndarray, float, float, float]:
    """Mesh of the sector cut by ``crack`` (its start checked on the outline), its fixed
    nodes, the interaction-integral ring r_out and the sizes h_tip and h [m]."""
    require(closure in ("open", "contact"), "closure", closure, 'must be "open" or "contact"')
    poly, fixed = sector_polygon(gear, n_teeth, bore_radius=bore_radius, web=web)
    poly = _with_crack_mouth(gear, poly, crack)
    r_out = RING_FRACTION * min(crack.last_segment_length(1),
                                _web_clearance(gear, poly, crack, bore_radius, web))
    h_tip = r_out / (TIP_DIVISIONS * refinement)
    h = gear.normal_module / (4.0 * refinement)
    cm = mesh_cracked_polygon(poly, crack, h=h, h_tip=h_tip, growth=0.3)
    return cm, fixed, r_out, h_tip, h


def tooth_crack_sif(gear: Gear, crack: CrackPath, radius: float, *, force: float = 1e5,
                    n_teeth: int = 3, plane: str = "stress", refinement: float = 1.0,
                    bore_radius: float | None = None, closure: str = "open",
                    web: RimWeb | None = None) -> ToothCrackResult:
    """K_I, K_II at the tip of a root crack under a flank load.

    Parameters
    ----------
    gear
        The gear (its material).
    crack
        Crack path from the fillet of the middle tooth (:func:`initial_crack`, or grown
        by :func:`grow_crack`).
    radius
        Contact radius on the loaded (+x) involute [m].
    force
        Normal force per unit face width [N/m] (> 0).
    n_teeth
        Teeth in the sector (odd, >= 3).
    plane
        ``"stress"`` or ``"strain"``.
    refinement
        Divides all element sizes [-] (0.25 to 8).
    bore_radius
        Inner rim radius of the sector [m] (:func:`sector_polygon`).
    closure
        ``"open"``: free crack faces (a crack on the loaded, tensile fillet);
        ``"contact"``: frictionless face contact (:mod:`gearsim.fracture.contact`; a
        straight crack only), needed on the compressed (unloaded-flank) fillet, where
        free faces would overlap; a closed tip has K_I = 0.
    web
        Rim support (:class:`RimWeb`, :func:`sector_polygon`): ``None`` (default) fixes
        the bore. With a web the tip must stay in the rim (above ``bore_radius``), and
        the integral's ring stays inside the rim (homogeneous material).

    Returns
    -------
    ToothCrackResult

    Raises
    ------
    InputError
        Radius off the involute, non-positive force, a crack whose start is not on the
        outline or that leaves the body, bad mesh parameters.
    """
    t0 = time.perf_counter()
    _check_load(gear, radius, force, refinement)
    cm, fixed, r_out, h_tip, h = _cracked_sector(gear, crack, closure, n_teeth, bore_radius,
                                                 web, refinement)
    web_model = None if web is None else (_rim_radius(gear, bore_radius), web)
    model, f, fixed_dofs = _loaded_model(gear, cm.p, cm.t, fixed, radius, force, plane, h,
                                         web_model)
    if closure == "contact":
        sif = closed_crack_intensity(model, cm, f, fixed_dofs, r_out=r_out).sif
    else:
        u = model.solve(f, fixed_dofs)
        tip, d = crack.tip_frame(1)
        sif = interaction_integral(model, u, tip, d, r_out=r_out)
    return ToothCrackResult(crack=crack, sif=sif, kink=kink_angle(sif.k1, sif.k2), force=force,
                            radius=radius, dofs=model.ndofs, h_tip=h_tip,
                            seconds=time.perf_counter() - t0)


@dataclass(frozen=True)
class CycleIntensity:
    """K at a crack tip for a sequence of loads (the contact positions of a mesh cycle).

    Parameters
    ----------
    radii
        Contact radii [m].
    forces
        Normal force per unit face width at each radius [N/m] (0: the tooth is unloaded
        there).
    k1, k2
        K_I, K_II at each position [Pa sqrt(m)].
    keq
        MTS equivalent K at each position [Pa sqrt(m)].
    delta_k
        Range of K_eq over the cycle, max(K_eq) - min(0, min K_eq) [Pa sqrt(m)]: the
        tooth is unloaded for most of a revolution, so the cycle includes K = 0.
    k_max
        max(K_eq) [Pa sqrt(m)].
    dofs
        Displacement unknowns.
    seconds
        Wall time [s].
    """

    radii: np.ndarray
    forces: np.ndarray
    k1: np.ndarray
    k2: np.ndarray
    keq: np.ndarray
    delta_k: float
    k_max: float
    dofs: int
    seconds: float


def cycle_intensity(gear: Gear, crack: CrackPath, radii, forces, *, n_teeth: int = 3,
                    plane: str = "stress", refinement: float = 1.0,
                    bore_radius: float | None = None, closure: str = "open",
                    web: RimWeb | None = None) -> CycleIntensity:
    """K at the crack tip for the loads of a mesh cycle, on one mesh and one factorisation.

    Parameters
    ----------
    gear
        The gear.
    crack
        The crack path (faces free: a crack on the loaded, tensile fillet).
    radii
        Contact radii on the +x involute [m], e.g. the positions of the path of contact.
    forces
        Normal force per unit face width at each radius [N/m] (>= 0; the share of the
        mesh force this tooth carries, from a load-sharing or dynamic analysis).
    n_teeth, plane, refinement, bore_radius, closure, web
        As :func:`tooth_crack_sif` (with ``"contact"`` each position is a separate
        active-set solve).

    Returns
    -------
    CycleIntensity

    Raises
    ------
    InputError
        Radii off the involute, negative or all-zero forces, mismatched lengths, or the
        errors of :func:`tooth_crack_sif`.
    """
    t0 = time.perf_counter()
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    fz = np.atleast_1d(np.asarray(forces, dtype=float))
    require(r.shape == fz.shape and r.ndim == 1 and r.size >= 1, "forces", fz.shape,
            f"must match the radii, shape {r.shape}")
    require(bool(np.all(np.isfinite(fz)) and np.all(fz >= 0.0) and np.any(fz > 0.0)),
            "forces", "negative, non-finite or all zero", "must be >= 0 N/m, one > 0")
    for ri in r:
        _check_load(gear, float(ri), 1.0, refinement)
    cm, fixed, r_out, h_tip, h = _cracked_sector(gear, crack, closure, n_teeth, bore_radius,
                                                 web, refinement)
    model, fixed_dofs = _sector_model(gear, cm.p, cm.t, fixed, plane,
                                      None if web is None else
                                      (_rim_radius(gear, bore_radius), web))
    loads = np.column_stack([_flank_load(model, gear, float(ri), 1.0, h) * fi
                             for ri, fi in zip(r, fz, strict=True)])
    tip, d = crack.tip_frame(1)
    k1, k2 = [], []
    if closure == "contact":
        for j in range(r.size):
            if fz[j] == 0.0:  # unloaded position: no field
                k1.append(0.0)
                k2.append(0.0)
                continue
            sif = closed_crack_intensity(model, cm, loads[:, j], fixed_dofs, r_out=r_out).sif
            k1.append(sif.k1)
            k2.append(sif.k2)
    else:
        u = model.solve(loads, fixed_dofs)
        for j in range(r.size):
            sif = interaction_integral(model, u[:, j], tip, d, r_out=r_out)
            k1.append(sif.k1)
            k2.append(sif.k2)
    k1a, k2a = np.asarray(k1), np.asarray(k2)
    keq = np.array([equivalent_k(a, b) if f > 0.0 else 0.0
                    for a, b, f in zip(k1a, k2a, fz, strict=True)])
    kmax = float(keq.max())
    return CycleIntensity(radii=r, forces=fz, k1=k1a, k2=k2a, keq=keq,
                          delta_k=kmax - min(0.0, float(keq.min())), k_max=kmax,
                          dofs=model.ndofs, seconds=time.perf_counter() - t0)


def grow_crack(gear: Gear, crack: CrackPath, radius: float, increment: float,
               **options) -> tuple[ToothCrackResult, CrackPath]:
    """One growth increment by the maximum tangential stress criterion.

    Parameters
    ----------
    gear
        The gear.
    crack
        Current crack path.
    radius
        Contact radius of the load [m].
    increment
        Crack extension da [m]: > 0 and at most half the distance from the tip to the
        outline ahead of it (a larger step could leave the body or jump over the
        ligament before the direction is updated).
    **options
        Passed to :func:`tooth_crack_sif` (``force``, ``n_teeth``, ``plane``,
        ``refinement``, ``bore_radius``, ``closure``, ``web``).

    Returns
    -------
    result : ToothCrackResult
        K and kink angle at the current tip.
    grown : CrackPath
        The path with the new tip ``tip + da (cos, sin)`` of the kinked direction.

    Raises
    ------
    InputError
        Bad increment (one line naming ``crack.increment``), a new tip outside the body
        or closer to the outline than da / 4 (``crack.path``: the tooth breaks), with a
        ``web`` a new tip below the rim's inner radius (``crack.path``: the rim
        breaks), or the errors of :func:`tooth_crack_sif`.
    """
    require(math.isfinite(increment) and increment > 0.0, "crack.increment", increment,
            "must be > 0 m")
    web = options.get("web")
    poly, _ = sector_polygon(gear, options.get("n_teeth", 3),
                             bore_radius=options.get("bore_radius"), web=web)
    clearance = _tip_clearance(poly, crack, ahead=True)
    require(increment <= 0.5 * clearance, "crack.increment", increment,
            f"is too large for the local geometry: at most half the distance from the tip "
            f"to the outline ahead of it, {0.5 * clearance:.4g} m")
    res = tooth_crack_sif(gear, crack, radius, **options)
    tip, d = crack.tip_frame(1)
    new = tip + increment * kinked_direction(d, res.sif.k1, res.sif.k2)
    grown = CrackPath(points=(*crack.points, (float(new[0]), float(new[1]))), tips=crack.tips)
    left = float(_dist_to_segments(new, poly, np.roll(poly, -1, axis=0)).min())
    if not (point_in_polygon(poly, new) and left > 0.25 * increment):
        raise InputError("crack.path", f"tip at {tuple(np.round(new * 1e3, 4))} mm",
                         "the grown crack leaves the body or reaches its outline: the tooth "
                         "(or rim) is broken at this increment")
    if web is not None:
        r_rim = _rim_radius(gear, options.get("bore_radius"))
        if float(np.hypot(*new)) < r_rim + 0.25 * increment:
            raise InputError("crack.path", f"tip at {tuple(np.round(new * 1e3, 4))} mm",
                             f"the grown crack reaches the rim's inner radius "
                             f"{r_rim * 1e3:.4g} mm (the web): the rim is broken at this "
                             "increment")
    return res, grown
