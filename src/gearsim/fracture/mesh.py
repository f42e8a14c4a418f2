"""Triangle meshes of plane bodies with cracks: gmsh meshing and node splitting.

A crack is a polyline embedded in the mesh (:class:`CrackPath`): gmsh meshes the
outline polygon with the crack segments as embedded curves, refined towards each
crack tip by a distance field, and the nodes on the crack except its tips are then
duplicated so that the two crack faces separate (:func:`split_crack_nodes`). The side
of every triangle is decided topologically: around a crack node the fan of triangles
is cut by the crack edges into two groups, and the group on the left of the crack
direction (start -> end of the polyline) gets the copy. This works for kinked
(grown) cracks, where the straight-line test of
:func:`gearsim.fem.geometry.split_along_crack` does not.

References
----------
.. [Geuzaine2009] C. Geuzaine, J.-F. Remacle, Gmsh: a 3-D finite element mesh generator
   with built-in pre- and post-processing facilities, Int. J. Numer. Meth. Eng. 79 (2009)
   1309-1331.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError, require
from gearsim.fem.geometry import (
    distance_threshold,
    drop_unused_nodes,
    generate_sized,
    gmsh_session,
    gmsh_triangles,
)

__all__ = ["CrackPath", "CrackedMesh", "mesh_cracked_polygon", "mesh_polygon",
           "split_crack_nodes"]


@dataclass(frozen=True)
class CrackPath:
    """A crack as a polyline in the plane.

    Parameters
    ----------
    points
        Vertices of the polyline, shape (k, 2), k >= 2 [m]. For an edge crack the first
        point is the mouth (a vertex of the body outline) and the last one the tip.
    tips
        Which ends are crack tips inside the body: ``(start_is_tip, end_is_tip)``.
        An edge crack is ``(False, True)``, an internal crack ``(True, True)``.
    """

    points: tuple[tuple[float, float], ...]
    tips: tuple[bool, bool] = (False, True)

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        require(pts.ndim == 2 and pts.shape[0] >= 2 and pts.shape[1] == 2, "crack.points",
                pts.shape, "must be a polyline of at least 2 points (k, 2)")
        require(bool(np.all(np.isfinite(pts))), "crack.points", "non-finite",
                "must be finite coordinates [m]")
        seg = np.hypot(*np.diff(pts, axis=0).T)
        require(bool(np.all(seg > 0.0)), "crack.points", float(seg.min()),
                "consecutive points must differ (segment length > 0 m)")
        require(any(self.tips), "crack.tips", self.tips, "at least one end must be a tip")

    @property
    def array(self) -> np.ndarray:
        """The points as an array of shape (k, 2) [m]."""
        return np.asarray(self.points, dtype=float)

    @property
    def length(self) -> float:
        """Length of the polyline [m]."""
        return float(np.sum(np.hypot(*np.diff(self.array, axis=0).T)))

    def tip_frame(self, end: int) -> tuple[np.ndarray, np.ndarray]:
        """Position and unit direction of propagation at one end.

        Parameters
        ----------
        end
            1 for the last point, 0 for the first one.

        Returns
        -------
        tip : ndarray, shape (2,)
            Tip position [m].
        direction : ndarray, shape (2,)
            Unit vector along the last segment, pointing out of the crack (the local
            x1 axis of the tip).
        """
        pts = self.array
        if end == 1:
            tip, prev = pts[-1], pts[-2]
        else:
            tip, prev = pts[0], pts[1]
        d = tip - prev
        return tip, d / np.hypot(*d)

    def last_segment_length(self, end: int) -> float:
        """Length of the straight segment at one end.

        Parameters
        ----------
        end
            1 for the last point, 0 for the first one.

        Returns
        -------
        float
            Length of the segment [m] (the ring of the interaction integral must fit
            in it).
        """
        pts = self.array
        d = pts[-1] - pts[-2] if end == 1 else pts[0] - pts[1]
        return float(np.hypot(*d))


@dataclass
class CrackedMesh:
    """Linear triangle mesh with split crack faces.

    Parameters
    ----------
    p
        Nodes, shape (2, n) [m].
    t
        Triangles, shape (3, m).
    crack
        The crack path.
    tip_nodes
        Node index of each tip end, ``{0: i, 1: j}`` for the ends that are tips.
    pairs
        Node pairs of the crack faces, shape (2, k): row 0 the node kept by the
        triangles on the right of the crack direction, row 1 its copy used by the
        triangles on the left.
    h
        Far-field element size [m].
    h_tip
        Element size at the tips [m].
    edges
        Crack edges, shape (e, 2), oriented along the path, as node pairs of the
        right-side face (row 0 of ``pairs`` and the tips); the left-side edge of
        ``(a, b)`` uses the copies of ``a`` and ``b`` (a tip is shared).
    """

    p: np.ndarray
    t: np.ndarray
    crack: CrackPath
    tip_nodes: dict[int, int]
    pairs: np.ndarray
    h: float
    h_tip: float
    edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))


def _point_in_polygon(poly: np.ndarray, pt: np.ndarray) -> bool:
    """Even-odd rule (strictly inside; points on edges are undefined)."""
    x, y = pt
    inside = False
    n = poly.shape[0]
    for i in range(n):
        x1, y1 = poly[i]
        x2, y2 = poly[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def mesh_cracked_polygon(outline: np.ndarray, crack: CrackPath, *, h: float, h_tip: float,
                         growth: float = 0.25, tip_zone: float | None = None) -> CrackedMesh:
    """Mesh a polygon with an embedded crack polyline, refined at the tips.

    Parameters
    ----------
    outline
        Polygon vertices, shape (n, 2), counter-clockwise or clockwise, not closed [m].
        The mouth of an edge crack (a crack start that is not a tip) must be one of them.
    crack
        The crack; its points other than an edge-crack mouth must lie inside the polygon.
    h
        Element size away from the crack [m] (> 0).
    h_tip
        Element size at the tips [m] (0 < h_tip <= h).
    growth
        Slope of the element size away from the tips and the crack [-] (0.05 to 1).
    tip_zone
        Radius around each tip with the size ``h_tip`` [m]; default ``4 h_tip``.

    Returns
    -------
    CrackedMesh

    Raises
    ------
    InputError
        Bad sizes, a mouth that is not an outline vertex, crack points outside the body,
        or a mesh gmsh could not make.
    """
    poly = np.asarray(outline, dtype=float)
    require(poly.ndim == 2 and poly.shape[0] >= 3 and poly.shape[1] == 2, "outline",
            poly.shape, "must be a polygon of at least 3 points (n, 2)")
    require(math.isfinite(h) and h > 0.0, "mesh.h", h, "must be > 0 m")
    require(math.isfinite(h_tip) and 0.0 < h_tip <= h, "mesh.h_tip", h_tip,
            f"must be in (0, h = {h:.4g} m]")
    require(0.05 <= growth <= 1.0, "mesh.growth", growth, "must be in [0.05, 1]")
    zone = 4.0 * h_tip if tip_zone is None else float(tip_zone)
    require(math.isfinite(zone) and zone >= 0.0, "mesh.tip_zone", tip_zone, "must be >= 0 m")
    pts = crack.array
    scale = float(np.abs(poly).max())
    tol = 1e-9 * max(scale, 1e-300)
    mouth = -1
    if not crack.tips[0]:
        d = np.hypot(*(poly - pts[0]).T)
        require(float(d.min()) <= tol, "crack.points[0]", tuple(pts[0]),
                "an edge-crack mouth must be a vertex of the outline")
        mouth = int(np.argmin(d))
    inner = pts[1:] if mouth >= 0 else pts
    if not crack.tips[1]:
        raise InputError("crack.tips", crack.tips, "the end of the polyline must be a tip")
    for q in inner:
        require(_point_in_polygon(poly, q), "crack.points", (float(q[0]), float(q[1])),
                "crack point outside the body (the path leaves the body)")
    try:
        return _mesh(poly, crack, mouth, h, h_tip, growth, zone)
    except InputError:
        raise
    except Exception as exc:  # gmsh raises plain Exception with its log message
        raise InputError("mesh", "cracked body", f"gmsh could not mesh it: {exc}") from None


def _mesh(poly: np.ndarray, crack: CrackPath, mouth: int, h: float, h_tip: float,
          growth: float, zone: float) -> CrackedMesh:
    pts = crack.array
    with gmsh_session("gearsim-fracture") as gmsh:
        geo = gmsh.model.geo
        tags = [geo.addPoint(float(x), float(y), 0.0) for x, y in poly]
        lines = [geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
        loop = geo.addCurveLoop(lines)
        surf = geo.addPlaneSurface([loop])
        ctags = [tags[mouth] if (i == 0 and mouth >= 0) else
                 geo.addPoint(float(x), float(y), 0.0) for i, (x, y) in enumerate(pts)]
        clines = [geo.addLine(ctags[i], ctags[i + 1]) for i in range(len(ctags) - 1)]
        geo.synchronize()
        gmsh.model.mesh.embed(1, clines, 2, surf)
        tip_tags = [ctags[0]] if crack.tips[0] else []
        tip_tags.append(ctags[-1])
        ttip = distance_threshold(gmsh, points=tip_tags,
                                  size=(h_tip, h),
                                  distance=(zone, zone + (h - h_tip) / growth))
        fields = [ttip]
        # the crack faces: at most a few tip sizes, so that the path is well resolved
        h_crack = min(h, 4.0 * h_tip)
        if h_crack < h:
            tcr = distance_threshold(gmsh, curves=clines, sampling=100,
                                     size=(h_crack, h),
                                     distance=(0.0, (h - h_crack) / growth))
            fields.append(tcr)
        generate_sized(gmsh, fields)
        xy, index, tri = gmsh_triangles(gmsh, surf, "mesh", "cracked body")
        edges = []
        for c in clines:
            _, _, en = gmsh.model.mesh.getElements(1, c)
            edges.append(index[np.concatenate(en).astype(np.int64)].reshape(-1, 2))
        crack_edges = np.vstack(edges)
    p, t, renum = drop_unused_nodes(xy, tri)
    crack_edges = renum[crack_edges]
    # orient the edges along the path (start -> end) by the arc parameter of their ends
    s_nodes = _arc_parameter(pts, p.T)
    swap = s_nodes[crack_edges[:, 0]] > s_nodes[crack_edges[:, 1]]
    crack_edges[swap] = crack_edges[swap][:, ::-1]
    tip_nodes: dict[int, int] = {}
    for end, q in ((0, pts[0]), (1, pts[-1])):
        if crack.tips[end]:
            d = np.hypot(*(p.T - q).T)
            tip_nodes[end] = int(np.argmin(d))
    p2, t2, pairs = split_crack_nodes(p, t, crack_edges, list(tip_nodes.values()))
    return CrackedMesh(p=p2, t=t2, crack=crack, tip_nodes=tip_nodes, pairs=pairs, h=h,
                       h_tip=h_tip, edges=crack_edges)


def mesh_polygon(outline: np.ndarray, *, h: float, focus: np.ndarray, h_focus: float,
                 growth: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """Mesh an uncracked polygon, refined around some boundary points.

    Parameters
    ----------
    outline
        Polygon vertices, shape (n, 2) [m]; the focus points must be among them.
    h
        Element size far from the focus points [m].
    focus
        Points (k, 2) to refine around [m], vertices of ``outline``.
    h_focus
        Element size at the focus points [m] (0 < h_focus <= h).
    growth
        Slope of the element size away from them [-] (0.05 to 1).

    Returns
    -------
    p : ndarray, shape (2, n)
        Nodes [m].
    t : ndarray, shape (3, m)
        Triangles.

    Raises
    ------
    InputError
        Bad sizes, focus points that are not vertices, or a gmsh failure.
    """
    poly = np.asarray(outline, dtype=float)
    foc = np.atleast_2d(np.asarray(focus, dtype=float))
    require(math.isfinite(h) and h > 0.0, "mesh.h", h, "must be > 0 m")
    require(math.isfinite(h_focus) and 0.0 < h_focus <= h, "mesh.h_focus", h_focus,
            f"must be in (0, h = {h:.4g} m]")
    require(0.05 <= growth <= 1.0, "mesh.growth", growth, "must be in [0.05, 1]")
    tol = 1e-9 * float(np.abs(poly).max())
    idx = []
    for q in foc:
        d = np.hypot(*(poly - q).T)
        require(float(d.min()) <= tol, "mesh.focus", tuple(q), "must be outline vertices")
        idx.append(int(np.argmin(d)))
    try:
        with gmsh_session("gearsim-fracture") as gmsh:
            geo = gmsh.model.geo
            tags = [geo.addPoint(float(x), float(y), 0.0) for x, y in poly]
            lines = [geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
            surf = geo.addPlaneSurface([geo.addCurveLoop(lines)])
            geo.synchronize()
            thr = distance_threshold(gmsh, points=[tags[i] for i in idx],
                                     size=(h_focus, h),
                                     distance=(4.0 * h_focus, 4.0 * h_focus + (h - h_focus) / growth))
            generate_sized(gmsh, thr)
            xy, _, tri = gmsh_triangles(gmsh, surf, "mesh", "body")
    except InputError:
        raise
    except Exception as exc:  # gmsh raises plain Exception with its log message
        raise InputError("mesh", "body", f"gmsh could not mesh it: {exc}") from None
    p, t, _ = drop_unused_nodes(xy, tri)
    return p, t


def _arc_parameter(path: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Arc-length parameter along ``path`` of the nearest point, for each row of ``xy``."""
    a, b = path[:-1], path[1:]
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    s0 = np.concatenate([[0.0], np.cumsum(np.sqrt(ll))])
    best = np.full(xy.shape[0], np.inf)
    out = np.zeros(xy.shape[0])
    for k in range(a.shape[0]):
        tt = np.clip(((xy - a[k]) @ ab[k]) / ll[k], 0.0, 1.0)
        q = a[k] + tt[:, None] * ab[k]
        d = np.hypot(*(xy - q).T)
        better = d < best
        best[better] = d[better]
        out[better] = s0[k] + tt[better] * math.sqrt(ll[k])
    return out


def _find(parent: dict[int, int], x: int) -> int:
    """Root of ``x`` in a union-find forest (with path halving)."""
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


def split_crack_nodes(p: np.ndarray, t: np.ndarray, edges: np.ndarray,
                      tips: Sequence[int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Duplicate the crack nodes (all but the tips) so that the crack faces separate.

    Around each crack node the triangles sharing it form a fan; the crack edges at the
    node cut the fan into two groups of triangles connected through non-crack edges.
    The group on the left of the crack direction (the oriented edges) is renumbered
    to a new copy of the node.

    Parameters
    ----------
    p
        Nodes, shape (2, n) [m].
    t
        Triangles, shape (3, m).
    edges
        Crack edges, shape (e, 2), each oriented along the crack (start -> end).
    tips
        Node indices of the crack tips (not duplicated).

    Returns
    -------
    p, t : ndarray
        Nodes with the copies appended, and renumbered triangles.
    pairs : ndarray of int, shape (2, k)
        (right-side node, left-side copy) for every duplicated node.

    Raises
    ------
    InputError
        If the crack edges do not cut the fan of a crack node into exactly two groups
        (a crack that touches itself or a degenerate mesh).
    """
    edges = np.asarray(edges, dtype=np.int64)
    crack_set = {(min(a, b), max(a, b)) for a, b in edges}
    nodes = np.setdiff1d(np.unique(edges), np.asarray(tips, dtype=np.int64))
    require(t.shape[1] > 0, "mesh", "empty", "has no triangles")
    # vertex -> triangles
    order = np.argsort(t.ravel(order="F"), kind="stable")
    flat = t.ravel(order="F")[order]
    tri_of = order // 3
    starts = np.searchsorted(flat, nodes)
    ends = np.searchsorted(flat, nodes, side="right")
    cent = p[:, t].mean(axis=1)  # (2, m)
    n0 = p.shape[1]
    t2 = t.copy()
    copies = []
    for k, node in enumerate(nodes):
        tris = tri_of[starts[k]:ends[k]]
        # union-find over the fan through edges (node, other) that are not crack edges
        parent = {int(tr): int(tr) for tr in tris}
        by_edge: dict[int, list[int]] = {}
        for tr in tris:
            for other in t[:, tr]:
                if other != node and (min(node, other), max(node, other)) not in crack_set:
                    by_edge.setdefault(int(other), []).append(int(tr))
        for trs in by_edge.values():
            for a in trs[1:]:
                ra, rb = _find(parent, a), _find(parent, trs[0])
                if ra != rb:
                    parent[ra] = rb
        groups: dict[int, list[int]] = {}
        for tr in tris:
            groups.setdefault(_find(parent, int(tr)), []).append(int(tr))
        if len(groups) != 2:
            raise InputError("crack", f"node at {tuple(np.round(p[:, node], 9))}",
                             f"the crack cuts the triangles around it into {len(groups)} "
                             "groups instead of 2 (crack touching itself or the outline)")
        inc = edges[(edges[:, 0] == node) | (edges[:, 1] == node)]
        d = np.zeros(2)
        for a, b in inc:
            v = p[:, b] - p[:, a]
            d += v / np.hypot(*v)
        side = []
        for trs in groups.values():
            c = cent[:, trs] - p[:, [node]]
            side.append(float(np.mean(d[0] * c[1] - d[1] * c[0])))
        left = list(groups.values())[int(np.argmax(side))]
        new = n0 + len(copies)
        copies.append(int(node))
        for tr in left:
            col = t2[:, tr]
            col[col == node] = new
    p2 = np.hstack([p, p[:, copies]]) if copies else p.copy()
    pairs = np.array([copies, list(range(n0, n0 + len(copies)))], dtype=np.int64)
    return p2, t2, pairs.reshape(2, -1)
