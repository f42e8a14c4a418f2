"""Finite-element tooth compliance along the path of contact (Hertz excluded).

Load: a unit force (per unit face width, plane model of unit thickness) along the line
of action of the potential-energy model, F = (-cos a1, -sin a1) with
a1 = alpha_r - psi, cos(alpha_r) = r_b / r, psi = atan2(x_c, y_c) for the contact
point (x_c, y_c) = ``ToothProfile.involute_point(r)`` on the loaded (+x) flank. It is
spread over the flank as a smooth traction t(s) ~ (1 - (s/a)^2)^2, s the distance from
the contact point, a = ``PATCH_HALF_LENGTH * m_n`` (a stand-in for the Hertzian
contact width), integrated with a high-order facet rule and scaled so that the load
vector carries exactly the unit force: the load does not jump when the mesh changes,
which keeps the mesh-convergence study clean.

Measure (Hertz and local indentation excluded): the displacement along the load
direction of the point Q where the line of action crosses the tooth centre line,
Q = (0, y_c - x_c tan a1). For any rigid motion of the upper tooth the component of
the displacement along a line is the same at every point of that line, so Q moves
like the contact point except for the local (contact-zone) deformation between
them, which the potential-energy model assigns to the Hertzian term. The compliance
is c = u(Q) . F / |F| [m/N] for a face width of 1 m: the same convention as
``ToothModel.compliance(..., width=1.0)``, whose four columns (bending, shear, axial,
foundation) sum to the quantity compared here.

References
----------
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, J. Mech. Des. 126 (2004) 748-752
   (deflection measured away from the contact to remove the Hertzian part).
.. [Chaari2009] F. Chaari, T. Fakhfakh, M. Haddar, Analytical modelling of spur gear tooth
   crack and influence on gearmesh stiffness, Eur. J. Mech. A/Solids 28 (2009) 461-468.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError
from gearsim.fem.geometry import (
    CrackLine,
    SectorMesh,
    SectorOptions,
    crack_line,
    element_size,
    mesh_sector,
)
from gearsim.fem.solve import ElasticModel, face_dof_pairs
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile

__all__ = ["FINEST_LEVEL", "PATCH_HALF_LENGTH", "FEToothResult", "bell_loads",
           "check_crack_resolved",
           "fe_tooth_compliance", "load_geometry", "neighbour_cross"]

#: Finest mesh refinement level (:class:`gearsim.fem.geometry.SectorOptions`).
FINEST_LEVEL = 6

#: Half length of the loaded patch on the flank, in normal modules [-]. Of the order of
#: the Hertzian half width of steel gears at rated load (0.05 m_n); the measure at Q is
#: insensitive to it (docs/fem.md).
PATCH_HALF_LENGTH = 0.05


@dataclass
class FEToothResult:
    """FE tooth compliance at contact radii and how it was obtained.

    Parameters
    ----------
    radii
        Contact radii [m].
    compliance
        Compliance at each radius for a face width of 1 m [m/N] (Hertz excluded).
    level
        Mesh refinement level.
    h
        Element size on the loaded tooth [m].
    nodes, elements, dofs
        Mesh and problem size.
    closure
        ``"open"`` or ``"contact"``.
    plane
        ``"stress"`` or ``"strain"``.
    crack
        The crack segment or ``None``.
    contact_iterations
        Active-set iterations per radius (contact closure).
    closed_fraction
        Share of the crack face length in contact per radius [-].
    neighbours
        Only with ``fe_tooth_compliance(..., neighbours=True)``: shape (2, n, n), the
        deflections of the two neighbouring teeth under the same loads
        (:func:`neighbour_cross`) [m/N for a face width of 1 m]; else shape (0,).
    seconds
        Wall time [s].
    """

    radii: np.ndarray
    compliance: np.ndarray  # [m/N] for a face width of 1 m
    level: int
    h: float
    nodes: int
    elements: int
    dofs: int
    closure: str
    plane: str
    crack: CrackLine | None = None
    contact_iterations: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    closed_fraction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    neighbours: np.ndarray = field(default_factory=lambda: np.zeros(0))
    seconds: float = 0.0


def load_geometry(profile: ToothProfile, radius: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Contact point, unit force direction and measure point Q for a contact radius.

    Parameters
    ----------
    profile
        Tooth outline.
    radius
        Contact radius on the involute [m].

    Returns
    -------
    point, direction, q
        (x_c, y_c) [m], unit force (-cos a1, -sin a1) [-], Q = (0, y_c - x_c tan a1) [m].
    """
    gear = profile.gear
    xc, yc = profile.involute_point(radius)
    alpha_r = math.acos(min(1.0, gear.base_radius / radius))
    a1 = alpha_r - math.atan2(xc, yc)
    d = np.array([-math.cos(a1), -math.sin(a1)])
    return np.array([xc, yc]), d, np.array([0.0, yc - xc * math.tan(a1)])


def _check_radii(gear: Gear, profile: ToothProfile, radii: np.ndarray) -> None:
    lo = max(profile.form_radius, gear.base_radius)
    hi = gear.tip_radius
    bad = (radii < lo * (1 - 1e-9)) | (radii > hi * (1 + 1e-9)) | ~np.isfinite(radii)
    if np.any(bad):
        raise InputError("radii", float(radii[bad][0]),
                         f"contact radii must lie on the involute of {gear.name}, within "
                         f"[{lo:.6g}, {hi:.6g}] m")


def _patch(model: ElasticModel, flank_facets: np.ndarray, point: np.ndarray,
           half: float) -> np.ndarray:
    """Flank facets closer than ``half`` to ``point`` (at least the nearest one)."""
    a = model.mesh.p[:, model.mesh.facets[0, flank_facets]].T
    b = model.mesh.p[:, model.mesh.facets[1, flank_facets]].T
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    dist = np.hypot(*(a + t[:, None] * ab - point).T)
    sel = dist <= half
    sel[np.argmin(dist)] = True
    return flank_facets[sel]


def _contact_pairs(model: ElasticModel, sector: SectorMesh) -> tuple[np.ndarray, np.ndarray]:
    """Dof pairs (k, 2, 2) and length weights (k,) of the crack faces."""
    arr, wts, _ = face_dof_pairs(model, model.mesh.p, sector.crack_pairs,
                                 sector.crack_edges.T, sector.crack_dup)
    return arr, wts


def check_crack_resolved(gear: Gear, depth: float, *, crack_depth: float | None = None) -> None:
    """Refuse a crack shallower than the finest FE mesh can resolve.

    The crack needs elements no larger than half its depth; the finest level
    (:data:`FINEST_LEVEL`) has elements ``m_n / (4 2^6)``, so it resolves depths down to
    ``m_n / 128``.

    Parameters
    ----------
    gear : Gear
        The cracked gear.
    depth : float
        Crack depth of the (transverse) section meshed [m]; 0 for none.
    crack_depth : float, optional
        Depth of the crack at the face [m], when ``depth`` is that of a slice.

    Raises
    ------
    InputError
        ``crack.depth`` when ``0 < depth < 2 h`` at the finest level, naming that
        smallest depth in mm.
    """
    h = element_size(gear, FINEST_LEVEL)
    if 0.0 < depth < 2.0 * h:
        where = "" if crack_depth is None or math.isclose(crack_depth, depth) else \
            f" (depth {depth * 1e3:.4g} mm in a face-width slice)"
        shown = crack_depth if crack_depth is not None else depth
        raise InputError("crack.depth", f"{shown * 1e3:.4g} mm",
                         f"is too small for the FE mesh of {gear.name}{where}: the finest "
                         f"level ({FINEST_LEVEL}, elements {h * 1e3:.3g} mm) resolves depths "
                         f">= {2e3 * h:.4g} mm (2 elements); use stiffness.source = \"pe\" "
                         "for a smaller crack")


def flank_loads(gear: Gear, sector: SectorMesh, r: np.ndarray, plane: str,
                opt: SectorOptions):
    """Elastic model of ``sector`` and a unit load on the loaded flank at each radius.

    The load of radius r_k is a smooth bell of half length ``PATCH_HALF_LENGTH m_n``
    around the involute point, along the contact normal, scaled to a unit resultant
    along that normal; the deflection is read at the point Q of
    :func:`load_geometry`.

    Parameters
    ----------
    gear : Gear
        The gear.
    sector : SectorMesh
        Its meshed sector (:func:`gearsim.fem.geometry.mesh_sector`).
    r : ndarray
        Contact radii [m].
    plane : {"stress", "strain"}
        Plane assumption.
    opt : SectorOptions
        Mesh options (which boundary is fixed).

    Returns
    -------
    model : ElasticModel
        The assembled model.
    fixed : ndarray of int
        Fixed degrees of freedom.
    loads : ndarray, shape (ndofs, n)
        Load vectors, unit resultant [N per m of face width].
    dirs : ndarray, shape (n, 2)
        Load directions (unit vectors).
    qs : ndarray, shape (2, n)
        Points Q where the deflection is read [m].
    """
    prof = ToothProfile(gear)
    mat = gear.material
    model = ElasticModel(sector.p, sector.t, mat.youngs_modulus, mat.poisson_ratio,
                         plane=plane, order=2)
    fixed_nodes = sector.bore if opt.sides == "free" else np.union1d(sector.bore, sector.sides)
    fixed = model.dofs_on_facets(model.facets_on_nodes(fixed_nodes))
    flank = model.facets_on_nodes(sector.flank)
    half = PATCH_HALF_LENGTH * gear.normal_module
    loads, dirs, qs = bell_loads(model, flank, [load_geometry(prof, float(rk)) for rk in r],
                                 half)
    return model, fixed, loads, dirs, qs


def bell_loads(model, flank: np.ndarray, geometry: list, half: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit-resultant bell loads on a flank, one column per contact point.

    Each load is the bell ``(1 - s^2)^2`` (s the distance from the contact point over
    ``half``) along the load direction on the flank facets within ``half`` of the point,
    scaled so that its resultant along the direction is 1 N (per metre of face width).

    Parameters
    ----------
    model : ElasticModel
        The assembled model.
    flank : ndarray of int
        Facets of the loaded flank.
    geometry : list of tuple
        ``(point, direction, q)`` per contact: load point [m], unit direction, the point
        where the deflection is read [m].
    half : float
        Half length of the bell [m].

    Returns
    -------
    loads : ndarray, shape (ndofs, n)
        Load vectors [N].
    dirs : ndarray, shape (n, 2)
        Load directions.
    qs : ndarray, shape (2, n)
        Read points [m].
    """
    n = len(geometry)
    loads = np.zeros((model.ndofs, n))
    dirs = np.zeros((n, 2))
    qs = np.zeros((2, n))
    for k, (point, d, q) in enumerate(geometry):
        facets = _patch(model, flank, point, half)

        def bell(x, y, point=point, d=d):
            s2 = ((x - point[0]) ** 2 + (y - point[1]) ** 2) / half**2
            w = np.where(s2 < 1.0, (1.0 - s2) ** 2, 0.0)
            return d[0] * w, d[1] * w

        # Lagrange shape functions sum to one: the dof sums per component are the
        # resultant force (x dofs even, y dofs odd in scikit-fem's vector ordering)
        f = model.traction_load(facets, bell, intorder=12)
        total = float(np.dot(d, [f[0::2].sum(), f[1::2].sum()]))
        if not total > 0.0:  # the bell fell between quadrature points: uniform fallback
            f = model.traction_load(facets[:1], d)
            total = float(np.dot(d, [f[0::2].sum(), f[1::2].sum()]))
        loads[:, k] = f / total
        dirs[k] = d
        qs[:, k] = q
    return loads, dirs, qs


def deflection_along_load(model, u: np.ndarray, dirs: np.ndarray, qs: np.ndarray
                          ) -> np.ndarray:
    """Deflection at Q along each load direction for the solutions ``u`` (one per load).

    Parameters
    ----------
    model : ElasticModel
        The model.
    u : ndarray, shape (ndofs, n)
        Displacements, column k under load k.
    dirs : ndarray, shape (n, 2)
        Load directions.
    qs : ndarray, shape (2, n)
        Points Q.

    Returns
    -------
    ndarray, shape (n,)
        Compliance [m/N per m of face width].
    """
    n = dirs.shape[0]
    vals = model.probe(qs) @ u  # (2 n, n)
    return np.array([dirs[k, 0] * vals[k, k] + dirs[k, 1] * vals[n + k, k] for k in range(n)])


def neighbour_cross(model, gear: Gear, u: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Deflections of the loaded tooth's two neighbours, read as the tooth's own.

    Tooth 0 carries load j (solution ``u[:, j]``, a unit load at ``radii[j]``); the
    neighbours are read at their own points Q(r_i) along their own load directions
    (:func:`load_geometry` turned by one pitch): tooth -1 (turned by +2 pi / z, the
    neighbour whose ``+x`` neighbour the loaded tooth is) and tooth +1 (turned by
    -2 pi / z, the neighbour the loaded flank faces). These are the body cross
    compliances of :mod:`gearsim.fem.coupling` (per unit face width).

    Parameters
    ----------
    model : ElasticModel
        The solved model.
    gear : Gear
        The gear.
    u : ndarray, shape (ndofs, n)
        Displacements, column j under the load at ``radii[j]``.
    radii : ndarray, shape (n,)
        Contact radii of the loads and of the read points [m].

    Returns
    -------
    ndarray, shape (2, n, n)
        ``[0, i, j]``: deflection of tooth -1 at Q(r_i) under the load at r_j;
        ``[1, i, j]``: of tooth +1 [m/N for a face width of 1 m].
    """
    prof = ToothProfile(gear)
    pitch = 2.0 * math.pi / gear.teeth
    out = np.empty((2, radii.size, radii.size))
    for k, ang in enumerate((pitch, -pitch)):
        c, s = math.cos(ang), math.sin(ang)
        rot = np.array([[c, -s], [s, c]])
        dirs, qs = [], []
        for r in radii:
            _, d, q = load_geometry(prof, float(r))
            dirs.append(rot @ d)
            qs.append(rot @ q)
        dirs = np.array(dirs)
        vals = model.probe(np.array(qs).T) @ u  # (2 n, n): rows x then y of each Q
        n = radii.size
        out[k] = dirs[:, :1] * vals[:n] + dirs[:, 1:] * vals[n:]
    return out


def fe_tooth_compliance(gear: Gear, radii, *, crack=None, depth: float | None = None,
                        side: int = 0, closure: str = "contact", plane: str = "stress",
                        options: SectorOptions | None = None,
                        neighbours: bool = False) -> FEToothResult:
    """Finite-element tooth compliance at contact radii (module docstring).

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii on the involute of the loaded flank [m].
    crack
        :class:`gearsim.stiffness.crack.Crack` or ``None``.
    depth
        Crack depth of this (transverse) section [m]; default ``crack.depth``.
    side
        +1: the crack is on the loaded flank; -1: on the unloaded flank; 0: healthy.
    closure
        ``"open"`` (faces free, may overlap, as the seed's equations) or ``"contact"``
        (frictionless unilateral contact of the crack faces).
    plane
        ``"stress"`` or ``"strain"``.
    options
        Mesh options (:class:`SectorOptions`).
    neighbours
        Also read the two neighbouring teeth under the same loads
        (:func:`neighbour_cross`, ``FEToothResult.neighbours``; two more probes of the
        same solutions, no more solves).

    Returns
    -------
    FEToothResult
        Compliance [m/N] for a face width of 1 m at each radius (Hertz excluded).
    """
    t0 = time.perf_counter()
    if closure not in ("open", "contact"):
        raise InputError("stiffness.closure", closure, 'must be "open" or "contact"')
    opt = options or SectorOptions()
    prof = ToothProfile(gear)
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    _check_radii(gear, prof, r)
    cl = None
    if crack is not None and side != 0:
        q = crack.depth if depth is None else float(depth)
        if q > 0.0:
            check_crack_resolved(gear, q, crack_depth=crack.depth)
            cl = crack_line(prof, crack, q, side)
    sector = mesh_sector(gear, crack=cl, options=opt)
    model, fixed, loads, dirs, qs = flank_loads(gear, sector, r, plane, opt)
    n = r.size
    iters = np.zeros(n, dtype=int)
    closed = np.zeros(n)
    if cl is not None and closure == "contact":
        pairs, weights = _contact_pairs(model, sector)
        u = np.zeros_like(loads)
        active = None
        reuse: dict = {}  # one factorization while the closed crack faces do not change
        for k in range(n):
            u[:, k], active, iters[k] = model.contact_solve(
                loads[:, k], fixed, pairs, cl.normal, weights, h=sector.h,
                active=active, reuse=reuse)
            closed[k] = float(np.sum(weights[active]) / np.sum(weights))
    else:
        u = model.solve(loads, fixed)
    comp = deflection_along_load(model, u, dirs, qs)
    cross = neighbour_cross(model, gear, u, r) if neighbours else np.zeros(0)
    return FEToothResult(radii=r, compliance=comp, level=opt.level, h=sector.h,
                         nodes=int(model.mesh.p.shape[1]), elements=int(model.mesh.t.shape[1]),
                         dofs=model.ndofs, closure=closure, plane=plane, crack=cl,
                         contact_iterations=iters, closed_fraction=closed, neighbours=cross,
                         seconds=time.perf_counter() - t0)
