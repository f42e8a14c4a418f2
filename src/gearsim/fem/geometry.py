"""Gear-sector geometry for the finite-element check: outline, crack line, gmsh mesh.

The sector holds ``n_teeth`` (odd) teeth of the gear with the loaded tooth in the
middle, the rim down to the bore and two radial side edges through the middle of the
tooth spaces. Coordinates are those of :class:`gearsim.geometry.profile.ToothProfile`
for the middle tooth: origin at the gear centre, ``+y`` along its centre line, and the
``+x`` flank is the *loaded* flank. Neighbouring teeth are copies rotated by multiples
of ``2 pi / z``.

Each flank is two or three interpolating splines through the outline of
``ToothProfile.outline`` (root fillet, involute; the fillet is split at the crack start
when the crack is on that flank); tips, tooth spaces and the bore are circular arcs.
gmsh meshes the region with linear triangles, sized by a distance field from the middle
tooth; a crack is a straight segment embedded in the mesh, and the triangles on its two
sides are then separated by duplicating the nodes of the segment except its tip
(:func:`split_along_crack`). A tooth may be given another outline (:class:`ToothShape`:
splines, straight lines and tip arcs); :mod:`gearsim.fem.faults` uses this for a spall
notch, a chipped tip and a broken tooth. The solver uses quadratic (P2) displacement fields on that
straight-sided triangulation.

References
----------
.. [Geuzaine2009] C. Geuzaine, J.-F. Remacle, Gmsh: a 3-D finite element mesh generator
   with built-in pre- and post-processing facilities, Int. J. Numer. Meth. Eng. 79 (2009)
   1309-1331.
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004)
   748-752 (gear-body model: tooth with its neighbours on a rim, fixed at the bore).
"""

from __future__ import annotations

import contextlib
import math
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError
from gearsim.fem._kernels import polygon_crosses_itself
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.crack import crack_geometry

__all__ = [
    "CrackLine",
    "distance_threshold",
    "gmsh_session",
    "FlankRefinement",
    "SectorMesh",
    "SectorOptions",
    "ToothShape",
    "crack_line",
    "element_size",
    "gmsh_nodes_on",
    "gmsh_triangles",
    "mesh_sector",
    "sector_outline_check",
    "split_along_crack",
]

#: One gmsh session at a time in a process (:func:`gmsh_session`; re-entrant: a session
#: inside a session uses the open one).
_GMSH_LOCK = threading.RLock()

#: Spline control points per fillet and per involute of each flank.
N_FILLET = 24
N_INVOLUTE = 32


@dataclass(frozen=True)
class SectorOptions:
    """Meshing options of the gear sector.

    Parameters
    ----------
    level
        Refinement level N >= 0: element size on the middle tooth
        ``h = m_n / (4 * 2**N)`` (halved per level).
    n_teeth
        Teeth in the model: ``None`` (default) = the whole gear, all z teeth and the
        full rim (no sector sides, the body model the Sainsot foundation term stands
        for); or an odd number >= 3 for a sector with radial side edges.
    sides
        Condition on the two radial edges of a sector: ``"fixed"`` (default) or
        ``"free"``. The bore is always fixed.
    growth
        Slope of the element size away from the middle tooth [-] (size grows by
        ``growth`` times the distance).
    tip_refinement
        Element size at a crack tip relative to ``h`` [-].
    """

    level: int = 2
    n_teeth: int | None = None
    sides: str = "fixed"
    growth: float = 0.3
    tip_refinement: float = 0.25

    def __post_init__(self) -> None:
        if not (isinstance(self.level, int) and 0 <= self.level <= 6):
            raise InputError("fem.level", self.level, "must be an integer in [0, 6]")
        if self.n_teeth is not None and not (isinstance(self.n_teeth, int)
                                             and self.n_teeth >= 3 and self.n_teeth % 2 == 1):
            raise InputError("fem.n_teeth", self.n_teeth,
                             "must be an odd integer >= 3 or None (whole gear)")
        if self.sides not in ("fixed", "free"):
            raise InputError("fem.sides", self.sides, 'must be "fixed" or "free"')
        if not 0.05 <= self.growth <= 1.0:
            raise InputError("fem.growth", self.growth, "must be in [0.05, 1]")
        if not 0.05 <= self.tip_refinement <= 1.0:
            raise InputError("fem.tip_refinement", self.tip_refinement, "must be in [0.05, 1]")

    def teeth_in(self, z: int) -> int:
        """Teeth of the model for a gear of z teeth.

        Parameters
        ----------
        z
            Tooth count of the gear.

        Returns
        -------
        int
            ``n_teeth``, or z for the whole gear (or a sector as large as the gear).
        """
        return z if self.n_teeth is None or self.n_teeth >= z else self.n_teeth


def element_size(gear: Gear, level: int) -> float:
    """Element size on the middle tooth at a refinement level.

    Parameters
    ----------
    gear
        The gear.
    level
        Refinement level N >= 0.

    Returns
    -------
    float
        h = m_n / (4 2^N) [m].

    Examples
    --------
    >>> from gearsim.geometry.gear import Gear
    >>> element_size(Gear(teeth=39, normal_module=6e-3), 2) * 1e3
    0.375
    """
    return gear.normal_module / (4.0 * 2.0**level)


@dataclass(frozen=True)
class FlankRefinement:
    """Finer elements on the involutes of some teeth (contact of a gear pair).

    Used by :mod:`gearsim.fem.pair`: the teeth that can touch the mating gear get the
    element size ``h`` of the middle tooth, and the involutes of their ``sides``
    flanks the (smaller) ``size``, growing with slope ``growth`` away from them.

    Parameters
    ----------
    teeth
        Tooth indices k (0 = middle tooth, +1 the next one on the ``+x`` side).
    sides
        Flanks to refine: +1 the ``+x`` flank, -1 the ``-x`` flank (tooth frame).
    size
        Element size on those involutes [m] (> 0).
    growth
        Slope of the element size away from the involutes [-].
    involute_points
        Points of the interpolating spline of each involute (all teeth) instead of
        ``N_INVOLUTE``: the spline is off the involute by O(spacing^3); 160 points keep it
        below 1 nm for the 19/48 example (32: 0.1 um).
    """

    teeth: tuple[int, ...]
    sides: tuple[int, ...]
    size: float
    growth: float = 0.3
    involute_points: int = 160


@dataclass(frozen=True)
class CrackLine:
    """A straight crack in the sector frame.

    Parameters
    ----------
    start
        Start point on the outline (root fillet of the middle tooth) [m].
    tip
        Tip, inside the tooth [m].
    """

    start: tuple[float, float]
    tip: tuple[float, float]

    @property
    def depth(self) -> float:
        """Crack length |tip - start| [m]."""
        return math.dist(self.start, self.tip)

    @property
    def normal(self) -> np.ndarray:
        """Unit normal of the crack line, (t_y, -t_x) rotated from start -> tip."""
        t = (np.asarray(self.tip) - np.asarray(self.start)) / self.depth
        return np.array([-t[1], t[0]])


def crack_line(profile: ToothProfile, crack, depth: float, side: int) -> CrackLine:
    """Crack segment in the sector frame for a crack of ``depth`` on flank ``side``.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    crack
        :class:`gearsim.stiffness.crack.Crack` (start point, angle).
    depth
        Crack depth [m] (> 0).
    side
        +1: crack on the loaded (+x) flank; -1: on the unloaded flank, i.e. the crack of
        :func:`~gearsim.stiffness.crack.crack_geometry` mirrored to ``-x``.
    """

    if side not in (1, -1):
        raise InputError("side", side, "must be +1 (loaded flank) or -1 (unloaded flank)")
    geo = crack_geometry(profile, crack, depth)  # refuses a crack that cuts the tooth off
    s = float(side)
    return CrackLine(start=(s * geo.start[0], geo.start[1]), tip=(s * geo.tip[0], geo.tip[1]))


PIECE_KINDS = ("spline", "line", "arc")


@dataclass(frozen=True)
class ToothShape:
    """Outline of one tooth of the sector that replaces the generated outline.

    Parameters
    ----------
    pieces
        Curves ``(kind, points)`` that run from the ``+x`` root point of the generated
        outline (``ToothProfile.outline(...)[0]``) over the tooth to the ``-x`` root
        point (its mirror), in the tooth frame of :class:`ToothProfile` [m]; each
        ``points`` is an (n, 2) array whose first point is the last point of the piece
        before. ``kind``: ``"spline"`` (interpolating spline through the points),
        ``"line"`` (straight, 2 points) or ``"arc"`` (circular arc about the gear centre
        between 2 points at the same radius). Corners between pieces stay sharp.
    flank
        Indices of the pieces that form the loaded flank (the load patches of
        :mod:`gearsim.fem.tooth` go there); used for the middle tooth only.
    """

    pieces: tuple[tuple[str, np.ndarray], ...]
    flank: tuple[int, ...] = ()

    def polygon(self, n_arc: int = 8) -> np.ndarray:
        """The outline as one polyline (arcs sampled), root ``+x`` to root ``-x``.

        Parameters
        ----------
        n_arc
            Points per arc.

        Returns
        -------
        ndarray, shape (m, 2)
            Points [m], without repeated piece end points.
        """
        out = [np.asarray(self.pieces[0][1][:1], dtype=float)]
        for kind, pts in self.pieces:
            pts = np.asarray(pts, dtype=float)
            if kind == "arc":
                r = float(np.hypot(*pts[0]))
                a0, a1 = (math.atan2(pts[i, 1], pts[i, 0]) for i in (0, -1))
                a = np.linspace(a0, a1, n_arc)[1:]
                out.append(r * np.column_stack([np.cos(a), np.sin(a)]))
            else:
                out.append(pts[1:])
        return np.vstack(out)


def _check_shapes(shapes: dict[int, ToothShape], half: np.ndarray, teeth: int,
                  n_sector: int, crack: CrackLine | None, name: str) -> None:
    """Refuse tooth shapes that do not join the rim or do not fit the sector."""
    ks = (range(-(n_sector // 2), n_sector // 2 + 1) if n_sector < teeth
          else range(teeth // 2 - teeth + 1, teeth // 2 + 1))
    root_r = half[0]
    root_l = half[0] * [-1.0, 1.0]
    tol = 1e-9 * max(1.0, float(np.hypot(*half[-1])))
    for k, shape in shapes.items():
        if not (isinstance(k, int) and k in ks):
            raise InputError(f"{name}.shapes", k, f"tooth index must be an integer in "
                             f"[{ks[0]}, {ks[-1]}] (0 = the loaded tooth)")
        if k == 0 and crack is not None:
            raise InputError(f"{name}.shapes", 0, "a crack and another outline of the loaded "
                             "tooth cannot be combined")
        if not shape.pieces:
            raise InputError(f"{name}.shapes[{k}]", "no pieces", "needs at least one curve")
        prev = root_r
        for j, (kind, pts) in enumerate(shape.pieces):
            pts = np.asarray(pts, dtype=float)
            if kind not in PIECE_KINDS or pts.ndim != 2 or pts.shape[1] != 2 \
                    or pts.shape[0] < 2 or not np.all(np.isfinite(pts)) \
                    or (kind != "spline" and pts.shape[0] != 2):
                raise InputError(f"{name}.shapes[{k}].pieces[{j}]", kind,
                                 'must be "spline" (n >= 2 points), "line" or "arc" '
                                 "(2 points) with finite (n, 2) coordinates")
            if math.dist(pts[0], prev) > tol:
                raise InputError(f"{name}.shapes[{k}].pieces[{j}]", "start point",
                                 "must continue the piece before (the first piece starts at "
                                 "the +x root point of the generated outline)")
            if kind == "arc" and abs(np.hypot(*pts[0]) - np.hypot(*pts[1])) > tol:
                raise InputError(f"{name}.shapes[{k}].pieces[{j}]", "arc",
                                 "an arc about the gear centre needs 2 points at one radius")
            prev = pts[-1]
        if math.dist(prev, root_l) > tol:
            raise InputError(f"{name}.shapes[{k}]", "end point",
                             "the last piece must end at the -x root point of the generated "
                             "outline")


def _shaped_outer(half: np.ndarray, teeth: int, n_sector: int,
                  shapes: dict[int, ToothShape]) -> np.ndarray:
    """The outer polygon of :func:`sector_outline_check` with the shaped teeth."""
    pitch = 2.0 * math.pi / teeth
    m = n_sector // 2
    ks = range(m, -m - 1, -1) if n_sector < teeth else range(teeth // 2, teeth // 2 - teeth, -1)
    tooth = np.vstack([half, (half[::-1] * [-1.0, 1.0])[1:]])
    parts = [_rot(shapes[k].polygon() if k in shapes else tooth, -k * pitch) for k in ks]
    return np.vstack(parts)


@dataclass
class SectorMesh:
    """Linear triangulation of the sector, after splitting along the crack.

    Parameters
    ----------
    p
        Node coordinates, shape (2, n) [m].
    t
        Triangles, shape (3, m).
    bore, sides
        Node indices on the bore arc and on the two radial edges.
    flank
        Node indices on the involute of the loaded (+x) flank of the middle tooth (on
        the ``flank`` pieces of its :class:`ToothShape` when it has one).
    crack_pairs
        Shape (2, k): (node on the - side, duplicate on the + side) of the crack faces
        (the tip is not duplicated and not listed).
    crack_edges
        Shape (2, e): crack segments as pairs of - side nodes.
    crack_dup
        Map from a - side crack node to its + side duplicate.
    crack
        The crack segment or ``None``.
    h
        Element size on the middle tooth [m].
    level
        Refinement level of the mesh.
    parts
        Only with a :class:`FlankRefinement`: node indices of the outline pieces of the
        refined teeth, keyed ``(k, side, part)`` with ``side`` +1 / -1 for the ``+x`` /
        ``-x`` flank and ``part`` ``"fillet"`` or ``"involute"``, and ``(k, 0, "tip")``
        for the tip arc. Empty otherwise.
    """

    p: np.ndarray
    t: np.ndarray
    bore: np.ndarray
    sides: np.ndarray
    flank: np.ndarray
    crack_pairs: np.ndarray
    crack_edges: np.ndarray
    crack_dup: dict[int, int] = field(default_factory=dict)
    crack: CrackLine | None = None
    h: float = 0.0
    level: int = 0
    parts: dict = field(default_factory=dict)


# --------------------------------------------------------------------------- helpers
def _rot(pts: np.ndarray, ang: float) -> np.ndarray:
    c, s = math.cos(ang), math.sin(ang)
    return np.column_stack([c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]])


def _segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> bool:
    """True if the open segments ab and cd intersect (proper crossing)."""
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    return o1 * o2 < 0 and o3 * o4 < 0


def _polyline_self_intersects(poly: np.ndarray) -> bool:
    """Whether a closed polygon crosses itself (:func:`gearsim.fem._kernels.
    polygon_crosses_itself`, compiled: 0.02 s for 3000 vertices, the row-wise numpy loop
    it replaced took 0.5 s)."""
    return bool(polygon_crosses_itself(np.ascontiguousarray(poly, dtype=float)))


def sector_outline_check(half: np.ndarray, teeth: int, n_teeth: int, bore: float,
                         *, name: str = "gear") -> np.ndarray:
    """Check that the sector outline built from ``half`` is a simple polygon.

    Parameters
    ----------
    half
        Half outline (+x flank) from the root circle to the tip, shape (n, 2) [m].
    teeth
        Tooth count z.
    n_teeth
        Teeth in the sector.
    bore
        Bore radius [m].
    name
        Gear name for error messages.

    Returns
    -------
    ndarray
        The outer outline polygon of the sector (teeth and tooth spaces), (m, 2) [m].

    Raises
    ------
    InputError
        If neighbouring teeth overlap, the bore reaches the root circle, or the outline
        crosses itself (gmsh cannot mesh such a region).
    """
    half = np.asarray(half, dtype=float)
    if half.ndim != 2 or half.shape[1] != 2 or half.shape[0] < 3 or not np.all(np.isfinite(half)):
        raise InputError(f"{name}.outline", f"shape {half.shape}",
                         "must be a finite (n >= 3, 2) array of outline points")
    pitch = 2.0 * math.pi / teeth
    r_root = float(np.hypot(*half[0]))
    theta_root = math.atan2(half[0, 0], half[0, 1])
    gap = pitch - 2.0 * theta_root
    if gap <= 1e-9:
        raise InputError(f"{name}.teeth", teeth,
                         f"neighbouring teeth overlap at the root circle (tooth spans "
                         f"{math.degrees(2 * theta_root):.4g} deg of a {math.degrees(pitch):.4g}"
                         " deg pitch): gmsh cannot mesh this sector")
    if not bore < r_root:
        raise InputError(f"{name}.bore_radius", bore,
                         f"must be below the root radius {r_root:.6g} m for a meshable rim")
    tooth = np.vstack([half, (half[::-1] * [-1.0, 1.0])[1:]])
    m = n_teeth // 2
    ks = range(m, -m - 1, -1) if n_teeth < teeth else range(teeth // 2, teeth // 2 - teeth, -1)
    outer = np.vstack([_rot(tooth, -k * pitch) for k in ks])
    closed = outer if n_teeth >= teeth else np.vstack([outer, [[0.0, 0.0]]])
    if _polyline_self_intersects(closed):
        raise InputError(f"{name}.outline", "self-intersecting",
                         "the tooth outline crosses itself or its neighbour: gmsh cannot "
                         "mesh this sector (check the rack data and profile shift)")
    return outer


def _check_crack(outer: np.ndarray, cl: CrackLine, half: np.ndarray) -> None:
    """Refuse a crack that leaves the tooth, cuts it off or ends on the boundary."""
    s = np.asarray(cl.start)
    tp = np.asarray(cl.tip)
    # the tip must be strictly inside the tooth material: not beyond the centre line
    if cl.start[0] * cl.tip[0] <= 0.0:
        raise InputError("crack.depth", f"{cl.depth * 1e3:.6g} mm",
                         "the crack crosses the tooth centre line, which the FE tooth does "
                         "not model (its crack is a straight slit on one side); reduce the "
                         "depth or the angle, or leave the FE route out (the potential-"
                         "energy model takes the crack up to tooth loss)")
    if not point_in_polygon(np.vstack([outer, [[0.0, 0.0]]]), tp):  # the region below outer
        ang = math.degrees(math.atan2(abs(s[0] - tp[0]), s[1] - tp[1]))
        raise InputError("crack.angle", f"{ang:.4g} deg",
                         "the crack tip lies outside the tooth material; the crack must run "
                         "into the tooth from the fillet")
    a = outer
    b = np.roll(outer, -1, axis=0)
    for i in range(a.shape[0]):
        # ignore the outline segments that touch the start point
        if min(math.dist(a[i], s), math.dist(b[i], s)) < 1e-12:
            continue
        if _segments_cross(s, tp, a[i], b[i]):
            raise InputError("crack.depth", f"{cl.depth * 1e3:.6g} mm",
                             "the crack runs out of the tooth through the outline and would "
                             "cut the tooth off; reduce the depth or change the angle")
    # distance of the tip to the outline: a tip on the boundary would also cut the tooth
    d = _dist_points_segments(tp[None, :], a, b)
    if d < 1e-6 * np.hypot(*half[-1]):
        raise InputError("crack.depth", f"{cl.depth * 1e3:.6g} mm",
                         "the crack tip reaches the tooth outline (tooth cut off)")


def point_in_polygon(poly: np.ndarray, pt: np.ndarray) -> bool:
    """Even-odd point-in-polygon test (ray casting) of ``pt`` in ``poly``, shape (n, 2)."""
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cond = (y > pt[1]) != (yn > pt[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = x + (pt[1] - y) * (xn - x) / (yn - y)
    return bool(np.count_nonzero(cond & (pt[0] < xc)) % 2 == 1)


def _dist_points_segments(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    out = np.inf
    for p in pts:
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(ll > 0, ll, 1.0), 0.0, 1.0)
        q = a + t[:, None] * ab
        out = min(out, float(np.min(np.hypot(*(q - p).T))))
    return out



def gmsh_triangles(gmsh, surf: int, parameter: str, what: str
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes and linear triangles of a surface meshed by gmsh.

    Parameters
    ----------
    gmsh : module
        The gmsh module, inside :func:`gmsh_session`, after ``mesh.generate(2)``.
    surf : int
        Tag of the surface.
    parameter, what : str
        Names for the message when gmsh produced no triangles.

    Returns
    -------
    xy : ndarray, shape (n, 2)
        Every mesh node [m].
    index : ndarray of int
        Map from gmsh node tag to row of ``xy``.
    tri : ndarray of int, shape (m, 3)
        Triangles as rows of ``xy``.

    Raises
    ------
    InputError
        If gmsh produced no triangles.
    """
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = coords.reshape(-1, 3)[:, :2]
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(tags.size)
    etypes, _, enodes = gmsh.model.mesh.getElements(2, surf)
    tri = None
    for et, en in zip(etypes, enodes, strict=True):
        if et == 2:
            tri = index[en.astype(np.int64)].reshape(-1, 3)
    if tri is None or tri.shape[0] == 0:
        raise InputError(parameter, what, "gmsh produced no triangles")
    return xy, index, tri


def distance_threshold(gmsh, *, size: tuple[float, float], distance: tuple[float, float],
                       curves: list[int] | None = None, points: list[int] | None = None,
                       sampling: int | None = None) -> int:
    """A gmsh size field graded with the distance to ``curves`` or ``points``.

    The element size is ``size[0]`` up to ``distance[0]`` [m] from them, ``size[1]``
    beyond ``distance[1]``, linear between (gmsh's ``Distance`` and ``Threshold``
    fields).

    Parameters
    ----------
    gmsh : module
        The gmsh module, inside :func:`gmsh_session`.
    size : tuple of float
        Smallest and largest element size [m].
    distance : tuple of float
        Distances [m] where the size leaves its smallest and reaches its largest value.
    curves, points : list of int, optional
        Tags the distance is measured to (one of them).
    sampling : int, optional
        Points per curve the distance is sampled at (gmsh's default without).

    Returns
    -------
    int
        Tag of the threshold field (combine several with a ``Min`` field).
    """
    fld = gmsh.model.mesh.field
    dist = fld.add("Distance")
    if curves is not None:
        fld.setNumbers(dist, "CurvesList", list(curves))
    if points is not None:
        fld.setNumbers(dist, "PointsList", list(points))
    if sampling is not None:
        fld.setNumber(dist, "Sampling", sampling)
    thr = fld.add("Threshold")
    fld.setNumber(thr, "InField", dist)
    fld.setNumber(thr, "SizeMin", size[0])
    fld.setNumber(thr, "SizeMax", size[1])
    fld.setNumber(thr, "DistMin", distance[0])
    fld.setNumber(thr, "DistMax", distance[1])
    return thr


def generate_sized(gmsh, fields: int | list[int], *, lc_precision: float | None = None
                   ) -> None:
    """Mesh the model in 2D, element sizes from the field ``fields`` (a list: their Min).

    Sizes from points, curvature and boundary off, gmsh algorithm 6; ``lc_precision``
    sets ``Mesh.LcIntegrationPrecision`` for the generation (the 1D size integration is
    slow at the default 1e-9 with a steep field).
    """
    fld = gmsh.model.mesh.field
    if isinstance(fields, list):
        mn = fld.add("Min")
        fld.setNumbers(mn, "FieldsList", fields)
        fields = mn
    fld.setAsBackgroundMesh(fields)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    if lc_precision is None:
        gmsh.model.mesh.generate(2)
        return
    precision = gmsh.option.getNumber("Mesh.LcIntegrationPrecision")
    gmsh.option.setNumber("Mesh.LcIntegrationPrecision", lc_precision)
    try:
        gmsh.model.mesh.generate(2)
    finally:
        gmsh.option.setNumber("Mesh.LcIntegrationPrecision", precision)


def drop_unused_nodes(xy: np.ndarray, tri: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``p`` (2, k), ``t`` (3, m) without the nodes no triangle uses, and ``renum``.

    ``xy`` (n, 2) and ``tri`` (m, 3) as :func:`gmsh_triangles` gives them; ``renum`` is
    the new index of each row of ``xy``, -1 for a dropped node (e.g. an arc centre).
    """
    used = np.unique(tri)
    renum = np.full(xy.shape[0], -1, dtype=np.int64)
    renum[used] = np.arange(used.size)
    return xy[used].T.copy(), renum[tri].T.copy(), renum


def kept_nodes(renum: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """New indices of the node ``rows`` that :func:`drop_unused_nodes` kept."""
    r = renum[rows]
    return r[r >= 0]


def gmsh_nodes_on(gmsh, index: np.ndarray, dim: int, tags: list[int]) -> np.ndarray:
    """Rows (of :func:`gmsh_triangles`' ``xy``) of the nodes on gmsh entities.

    Parameters
    ----------
    gmsh : module
        The gmsh module, after meshing.
    index : ndarray of int
        Tag-to-row map of :func:`gmsh_triangles`.
    dim : int
        Dimension of the entities.
    tags : list of int
        Their tags.

    Returns
    -------
    ndarray of int
        Sorted unique rows, boundaries of the entities included.
    """
    out = [index[gmsh.model.mesh.getNodes(dim, tg, includeBoundary=True)[0].astype(np.int64)]
           for tg in tags]
    return np.unique(np.concatenate(out)) if out else np.zeros(0, dtype=np.int64)

@contextlib.contextmanager
def gmsh_session(model: str = "gearsim-fem") -> Iterator[object]:
    """A quiet gmsh model, always removed (and gmsh finalised if this call started it).

    Parameters
    ----------
    model : str, optional
        Name of the gmsh model.

    Yields
    ------
    module
        The ``gmsh`` module with ``model`` current.
    """
    import gmsh

    # gmsh is one state per process, not thread-safe: one session at a time (a Dask
    # worker's threads); not interruptible, whose SIGINT handler Python allows in the main
    # thread only (before: "signal only works in main thread" in a worker, and the crack
    # correction fell back to Q = 1)
    with _GMSH_LOCK:
        own = not gmsh.isInitialized()
        if own:
            gmsh.initialize(readConfigFiles=False, interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.Verbosity", 0)
        gmsh.model.add(model)
        try:
            yield gmsh
        finally:
            gmsh.model.remove()
            if own:
                gmsh.finalize()


def _distinct(piece: np.ndarray) -> np.ndarray:
    """Drop spline points that repeat their predecessor (keeping both end points).

    The outline repeats the form point (last fillet point = first involute point), so
    the involute piece starts with a doubled point; an interpolating spline through it
    has a cusp of a few micrometres there, which elements of that size (the refined
    flanks of :class:`FlankRefinement`) resolve into a self-intersecting 1D mesh.
    """
    scale = max(1.0, float(np.abs(piece).max()))
    keep = np.ones(piece.shape[0], dtype=bool)
    keep[1:] = np.hypot(*np.diff(piece, axis=0).T) > 1e-9 * scale
    out = piece[keep]
    out[-1] = piece[-1]  # a repeated end point: keep its exact value
    return out


def _flank_pieces(half: np.ndarray, n_fillet: int, split: tuple[float, float] | None
                  ) -> list[np.ndarray]:
    """Fillet (optionally split at a point) and involute pieces of the +x flank."""
    fil = half[:n_fillet]
    inv = half[n_fillet - 1:]
    if split is None:
        return [fil, inv]
    sp = np.asarray(split)
    # insert the split point by height (the fillet rises monotonically root -> form)
    tol = 1e-3 * float(np.max(np.hypot(*np.diff(fil, axis=0).T)))
    k = int(np.searchsorted(fil[:, 1], sp[1]))
    lo = fil[:k]
    hi = fil[k:]
    lo = lo[np.hypot(*(lo - sp).T) > tol]
    hi = hi[np.hypot(*(hi - sp).T) > tol]
    if lo.shape[0] < 1 or hi.shape[0] < 1:
        raise InputError("crack.start_radius", float(np.hypot(*sp)),
                         "the crack must start inside the root fillet, not at its ends")
    return [np.vstack([lo, sp]), np.vstack([sp, hi]), inv]


def mesh_sector(gear: Gear, *, crack: CrackLine | None = None,
                options: SectorOptions | None = None,
                shapes: dict[int, ToothShape] | None = None,
                refine: FlankRefinement | None = None) -> SectorMesh:
    """Mesh the gear sector with gmsh (linear triangles) and split it along the crack.

    Parameters
    ----------
    gear
        The gear; its bore radius is :attr:`Gear.bore_radius_value`, as in the
        potential-energy foundation term.
    crack
        Crack segment in the sector frame (start on the fillet of the middle tooth,
        on ``+x`` for the loaded flank or ``-x`` for the unloaded one), or ``None``.
    options
        :class:`SectorOptions`.
    shapes
        Outlines that replace the generated one for some teeth, keyed by the tooth index
        k relative to the middle tooth (0 = the loaded tooth; +1 = the neighbour on the
        ``+x`` side, which the loaded flank faces; -1 = the one behind the unloaded
        flank): :class:`ToothShape`. ``None`` (default): every tooth as generated. The
        element sizes stay those of the healthy model (refined around the middle tooth).
    refine
        :class:`FlankRefinement`: finer elements on the flanks of several teeth, and
        their node sets in ``SectorMesh.parts``; ``None`` (default) leaves the mesh as
        it was.

    Returns
    -------
    SectorMesh

    Raises
    ------
    InputError
        Unmeshable geometry, a crack that cuts the tooth off, elements too coarse for
        the crack (size > depth / 2), or a tooth shape that does not join the rim, is
        combined with a crack of the same tooth or makes the outline cross itself; a
        refinement of a tooth that is not in the model or has another outline.
    """
    opt = options or SectorOptions()
    prof = ToothProfile(gear)
    z = gear.teeth
    half = prof.outline(N_FILLET, N_INVOLUTE)
    bore = gear.bore_radius_value
    outer = sector_outline_check(half, z, opt.teeth_in(z), bore, name=gear.name)
    shapes = dict(shapes or {})
    if shapes:
        _check_shapes(shapes, half, z, opt.teeth_in(z), crack, gear.name)
        outer = _shaped_outer(half, z, opt.teeth_in(z), shapes)
        closed = outer if opt.teeth_in(z) >= z else np.vstack([outer, [[0.0, 0.0]]])
        if _polyline_self_intersects(closed):
            raise InputError(f"{gear.name}.outline", "self-intersecting",
                             "the changed tooth outline crosses itself or its neighbour: "
                             "gmsh cannot mesh this sector")
    h = element_size(gear, opt.level)
    half_mesh = half
    if refine is not None:
        _check_refine(refine, z, opt.teeth_in(z), shapes, gear.name)
        # a contact model needs the flank far more accurately than a loaded tooth: the
        # spline through 32 points is off the involute by ~0.1 um near the base circle,
        # a profile error of about 1 % of the loaded transmission error
        half_mesh = prof.outline(N_FILLET, max(N_INVOLUTE, refine.involute_points))
    if crack is not None:
        _check_crack(outer, crack, half)
        if h > 0.5 * crack.depth:
            need = math.ceil(math.log2(gear.normal_module / (2.0 * crack.depth)))
            raise InputError("fem.level", opt.level,
                             f"mesh too coarse for the crack: element size {h * 1e3:.4g} mm > "
                             f"crack depth / 2 = {0.5e3 * crack.depth:.4g} mm; use level >= "
                             f"{max(need, opt.level + 1)}")
    try:
        return _mesh(gear, half_mesh, outer, crack, opt, h, shapes, refine)
    except InputError:
        raise
    except Exception as exc:  # gmsh raises plain Exception with its log message
        raise InputError(f"{gear.name}.geometry", "sector",
                         f"gmsh could not mesh the gear sector: {exc}") from None


def _check_refine(refine: FlankRefinement, teeth: int, n_sector: int,
                  shapes: dict[int, ToothShape], name: str) -> None:
    """Refuse a flank refinement of teeth outside the model or with another outline."""
    ks = (range(-(n_sector // 2), n_sector // 2 + 1) if n_sector < teeth
          else range(teeth // 2 - teeth + 1, teeth // 2 + 1))
    for k in refine.teeth:
        if not (isinstance(k, int) and k in ks) or k in shapes:
            raise InputError(f"{name}.refine.teeth", k, f"must be tooth indices in "
                             f"[{ks[0]}, {ks[-1]}] with the generated outline")
    if not refine.sides or any(sd not in (1, -1) for sd in refine.sides):
        raise InputError(f"{name}.refine.sides", refine.sides, "must be +1 and/or -1")
    if not (math.isfinite(refine.size) and refine.size > 0.0):
        raise InputError(f"{name}.refine.size", refine.size, "must be > 0 m")
    if not 0.05 <= refine.growth <= 1.0:
        raise InputError(f"{name}.refine.growth", refine.growth, "must be in [0.05, 1]")
    if not (isinstance(refine.involute_points, int) and 8 <= refine.involute_points <= 2000):
        raise InputError(f"{name}.refine.involute_points", refine.involute_points,
                         "must be an integer in [8, 2000]")


def _mesh(gear: Gear, half: np.ndarray, outer: np.ndarray, crack: CrackLine | None,
          opt: SectorOptions, h: float, shapes: dict[int, ToothShape] | None = None,
          refine: FlankRefinement | None = None) -> SectorMesh:
    shapes = shapes or {}
    # outline curves of the refined teeth: (k, side, part) -> gmsh curve tags
    part_curves: dict[tuple[int, int, str], list[int]] = {}
    refined_curves: list[int] = []
    z = gear.teeth
    pitch = 2.0 * math.pi / z
    n_sector = opt.teeth_in(z)
    m = n_sector // 2
    bore = gear.bore_radius_value
    r_root = float(np.hypot(*half[0]))
    mod = gear.normal_module
    # the whole size field scales with h, so that levels are uniform refinements
    h_max = min(16.0 * h, 0.5 * (r_root - bore))
    with gmsh_session() as gmsh:
        geo = gmsh.model.geo
        centre = geo.addPoint(0.0, 0.0, 0.0)

        def pt(xy) -> int:
            return geo.addPoint(float(xy[0]), float(xy[1]), 0.0)

        curves: list[int] = []
        middle: list[int] = []
        flank_curves: list[int] = []
        side_curves: list[int] = []
        full = n_sector == z
        if full:  # all teeth, no sector sides; the loop closes on the first tooth
            ks = range(z // 2, z // 2 - z, -1)
            prev = -1
        else:
            ks = range(m, -m - 1, -1)
            half_side = 0.5 * n_sector * pitch
            # right side: bore -> root circle at polar angle pi/2 - half_side
            ang_r = 0.5 * math.pi - half_side
            ang_l = 0.5 * math.pi + half_side
            b_r = pt((bore * math.cos(ang_r), bore * math.sin(ang_r)))
            q_r = pt((r_root * math.cos(ang_r), r_root * math.sin(ang_r)))
            b_l = pt((bore * math.cos(ang_l), bore * math.sin(ang_l)))
            q_l = pt((r_root * math.cos(ang_l), r_root * math.sin(ang_l)))
            side_curves.append(geo.addLine(b_r, q_r))
            curves.append(side_curves[0])
            prev = q_r
        first_root = -1
        for k in ks:
            rot = -k * pitch
            if k in shapes:
                start, first, tooth_curves = _shaped_tooth(geo, pt, centre, shapes[k], rot,
                                                           prev, curves)
                if prev < 0:
                    first_root = start
                if k == 0:
                    flank_curves = [tooth_curves[j] for j in shapes[k].flank]
                    middle = list(tooth_curves)
                curves.extend(tooth_curves)
                prev = first
                continue
            split_p = split_m = None
            if k == 0 and crack is not None:
                if crack.start[0] > 0:
                    split_p = crack.start
                else:
                    split_m = (-crack.start[0], crack.start[1])
            right = [_rot(piece, rot) for piece in _flank_pieces(half, N_FILLET, split_p)]
            left_raw = _flank_pieces(half, N_FILLET, split_m)
            if refine is not None:
                right = [_distinct(piece) for piece in right]
                left_raw = [_distinct(piece) for piece in left_raw]
            left = [_rot(piece[::-1] * [-1.0, 1.0], rot) for piece in left_raw[::-1]]
            # root arc from the previous point to this tooth's +x root point
            start = pt(right[0][0])
            if prev >= 0:
                curves.append(geo.addCircleArc(prev, centre, start))
            else:
                first_root = start
            first = start
            tooth_curves = []
            for j, piece in enumerate(right):
                end = pt(piece[-1])
                inner = [pt(xy) for xy in piece[1:-1]]
                c = geo.addSpline([first, *inner, end])
                tooth_curves.append(c)
                if k == 0 and j == len(right) - 1:
                    flank_curves = [c]
                first = end
            tip_l = pt(left[0][0])
            tooth_curves.append(geo.addCircleArc(first, centre, tip_l))
            first = tip_l
            for piece in left:
                end = pt(piece[-1])
                inner = [pt(xy) for xy in piece[1:-1]]
                tooth_curves.append(geo.addSpline([first, *inner, end]))
                first = end
            curves.extend(tooth_curves)
            if refine is not None and k in refine.teeth:
                nr = len(right)
                part_curves[(k, 1, "fillet")] = tooth_curves[:nr - 1]
                part_curves[(k, 1, "involute")] = [tooth_curves[nr - 1]]
                part_curves[(k, 0, "tip")] = [tooth_curves[nr]]
                part_curves[(k, -1, "involute")] = [tooth_curves[nr + 1]]
                part_curves[(k, -1, "fillet")] = tooth_curves[nr + 2:]
                refined_curves.extend(tooth_curves)
            if k == 0:
                middle = list(tooth_curves)
            prev = first
        if full:
            curves.append(geo.addCircleArc(prev, centre, first_root))
            bpts = [pt((bore * math.cos(a), bore * math.sin(a)))
                    for a in (0.5 * math.pi, math.pi, 1.5 * math.pi, 0.0)]
            bore_curves = [geo.addCircleArc(bpts[i], centre, bpts[(i + 1) % 4])
                           for i in range(4)]
            holes = [geo.addCurveLoop(bore_curves)]
        else:
            curves.append(geo.addCircleArc(prev, centre, q_l))
            side_curves.append(geo.addLine(q_l, b_l))
            curves.append(side_curves[1])
            # bore from left to right through +y: split at the top to keep arcs < pi
            b_top = pt((0.0, bore))
            bore_curves = [geo.addCircleArc(b_l, centre, b_top),
                           geo.addCircleArc(b_top, centre, b_r)]
            curves += bore_curves
            holes = []
        loop = geo.addCurveLoop(curves)
        surf = geo.addPlaneSurface([loop, *holes])
        crack_curve = -1
        tip_pt = -1
        if crack is not None:
            # the start point is already a vertex of the outline; find it
            tip_pt = pt(crack.tip)
        geo.synchronize()
        if crack is not None:
            start_tag = _find_point(gmsh, crack.start)
            crack_curve = geo.addLine(start_tag, tip_pt)
            geo.synchronize()
            gmsh.model.mesh.embed(1, [crack_curve], 2, surf)
        # size field: distance from the middle tooth (and the crack)
        near = middle + refined_curves + ([crack_curve] if crack is not None else [])
        thr = distance_threshold(gmsh, curves=near, sampling=200, size=(h, h_max),
                                 distance=(0.5 * mod, 0.5 * mod + (h_max - h) / opt.growth))
        fields = [thr]
        if crack is not None:
            h_tip = opt.tip_refinement * h
            ttip = distance_threshold(gmsh, points=[tip_pt], size=(h_tip, h_max),
                                      distance=(0.5 * h, 0.5 * h + (h_max - h_tip) / 0.3))
            fields.append(ttip)
        if refine is not None:
            inv_curves = [c for (k, sd, part), cs in part_curves.items()
                          if part == "involute" and sd in refine.sides for c in cs]
            tflank = distance_threshold(
                gmsh, curves=inv_curves, sampling=max(200, int(math.ceil(4.0 * mod / refine.size))),
                size=(refine.size, h_max), distance=(0.0, (h_max - refine.size) / refine.growth))
            fields.append(tflank)
        generate_sized(gmsh, fields, lc_precision=None if refine is None else 1e-4)
        xy, index, tri = gmsh_triangles(gmsh, surf, f"{gear.name}.geometry", "sector")

        def nodes_on(dim: int, tags_: list[int]) -> np.ndarray:
            return gmsh_nodes_on(gmsh, index, dim, tags_)

        bore_nodes = nodes_on(1, bore_curves)
        side_nodes = nodes_on(1, side_curves)
        flank_nodes = nodes_on(1, flank_curves)
        part_nodes = {key: nodes_on(1, cs) for key, cs in part_curves.items()}
        crack_edges = np.zeros((0, 2), dtype=np.int64)
        if crack is not None:
            et, _, en = gmsh.model.mesh.getElements(1, crack_curve)
            crack_edges = index[np.concatenate(en).astype(np.int64)].reshape(-1, 2)
    # drop nodes not used by triangles (e.g. the arc centre), renumber
    p, t, renum = drop_unused_nodes(xy, tri)
    out = SectorMesh(p=p, t=t, bore=kept_nodes(renum, bore_nodes),
                     sides=kept_nodes(renum, side_nodes), flank=kept_nodes(renum, flank_nodes),
                     crack_pairs=np.zeros((2, 0), dtype=np.int64),
                     crack_edges=np.zeros((2, 0), dtype=np.int64), crack=crack, h=h,
                     level=opt.level,
                     parts={key: kept_nodes(renum, a) for key, a in part_nodes.items()})
    if crack is not None:
        edges = renum[crack_edges].T
        p2, t2, pairs, dup = split_along_crack(p, t, edges, crack)
        out.p, out.t, out.crack_pairs, out.crack_edges, out.crack_dup = p2, t2, pairs, edges, dup
    return out


def _shaped_tooth(geo, pt, centre: int, shape: ToothShape, rot: float, prev: int,
                  curves: list[int]) -> tuple[int, int, list[int]]:
    """gmsh curves of a :class:`ToothShape` rotated by ``rot``.

    Adds the root arc from ``prev`` (when >= 0) to ``curves``; returns the tags of the
    first and last points and the tooth curves.
    """
    start = pt(_rot(np.asarray(shape.pieces[0][1][:1], dtype=float), rot)[0])
    if prev >= 0:
        curves.append(geo.addCircleArc(prev, centre, start))
    first = start
    out: list[int] = []
    for kind, pts in shape.pieces:
        pr = _rot(np.asarray(pts, dtype=float), rot)
        end = pt(pr[-1])
        if kind == "line":
            c = geo.addLine(first, end)
        elif kind == "arc":
            c = geo.addCircleArc(first, centre, end)
        else:
            inner = [pt(xy) for xy in pr[1:-1]]
            c = geo.addSpline([first, *inner, end])
        out.append(c)
        first = end
    return start, first, out


def _find_point(gmsh, xy: tuple[float, float]) -> int:
    """Tag of the geometry point at ``xy``."""
    best, tag = math.inf, -1
    for _, tg in gmsh.model.getEntities(0):
        x, y, _ = gmsh.model.getValue(0, tg, [])
        d = math.hypot(x - xy[0], y - xy[1])
        if d < best:
            best, tag = d, tg
    if best > 1e-9:
        raise InputError("crack.start_radius", math.hypot(*xy),
                         "the crack start is not a point of the meshed outline")
    return tag


def split_along_crack(p: np.ndarray, t: np.ndarray, edges: np.ndarray, crack: CrackLine
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[int, int]]:
    """Duplicate the nodes of an embedded crack so that its faces separate.

    Every node of the crack segment except its tip gets a copy; triangles with their
    centroid on the ``+normal`` side of the crack line (normal of :class:`CrackLine`)
    that use such a node are renumbered to the copy.

    Parameters
    ----------
    p
        Nodes, shape (2, n) [m].
    t
        Triangles, shape (3, m).
    edges
        Mesh edges on the crack, shape (2, e).
    crack
        The crack segment.

    Returns
    -------
    p, t, pairs, dup
        New nodes and triangles, the node pairs (minus side, plus side) of the crack
        faces, shape (2, k), and the map original -> copy.
    """
    nodes = np.unique(edges)
    tip = np.asarray(crack.tip)
    d_tip = np.hypot(*(p[:, nodes].T - tip).T)
    tip_node = int(nodes[np.argmin(d_tip)])
    if d_tip.min() > 1e-9 * max(1.0, np.abs(tip).max()):
        raise InputError("crack.tip", crack.tip, "is not a node of the mesh")
    dupl = nodes[nodes != tip_node]
    n0 = p.shape[1]
    dup = {int(a): n0 + i for i, a in enumerate(dupl)}
    p2 = np.hstack([p, p[:, dupl]])
    cent = p[:, t].mean(axis=1)  # (2, m)
    s = (cent - np.asarray(crack.start)[:, None]).T @ crack.normal
    t2 = t.copy()
    plus = s > 0.0
    mask = np.isin(t, dupl) & plus[None, :]
    rows, cols = np.nonzero(mask)
    t2[rows, cols] = [dup[int(a)] for a in t[rows, cols]]
    pairs = np.array([dupl, [dup[int(a)] for a in dupl]], dtype=np.int64).reshape(2, -1)
    return p2, t2, pairs, dup
