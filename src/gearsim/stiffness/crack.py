"""Tooth-root crack: geometry on the root fillet and the records the kernels use.

A crack starts at a point of the root fillet of the working or the non-working flank
(default: the 30 degree tangent point of ISO 6336-3, where the root stress peaks) and
runs straight into the tooth, towards the centre line and the root, at ``angle`` to the
tooth centre line, to ``depth``. Along the face width it extends from the face at
``z = 0`` over ``extent`` (fraction of the face width) with a depth profile
``uniform`` (q0), ``linear`` (q0 (1 - z/w)) or ``parabolic`` (q0 sqrt(1 - z/w), the
crack front of Chen & Shao 2011).

**Limiting line** (Tian 2004; seed eqs. 10-11). The part of each section between the
line through the crack tip parallel to the tooth centre line, at signed distance
h_c = x_t from it (positive on the cracked side), and the cracked flank carries no
load, from the tip height (or the root circle, whichever is higher) upwards: the
section of half width h keeps the width h + h_c (A = (h + h_c) L, I = (h + h_c)^3 L / 12).
**Past the centre line** (h_c < 0) the same straight line is kept, on the far side:
the width is h - h_q with h_q = -h_c the tip's distance past the centre line, the case
of a crack through the tooth centre line of Tian (2004) and Wu, Zuo & Parey (2008)
(their A_x = (h_x - h_q) L, I_x = (h_x - h_q)^3 L / 12). The width falls continuously
through h_c = 0 (the same formula on both sides). The section width reaches zero where
the far flank's half width equals h_q: if that happens below the tooth tip (h_q >= the
half width of the top land, the highest load point of any mesh), the model's tooth is
**cut off** (tooth loss) and :func:`crack_geometry` refuses the crack in one line
(:func:`cuts_tooth_off`); the widths of an accepted crack are > 0 everywhere.

**Polyline paths** (:func:`path_limiting_line`): with a vertical limiting line from
every point of the path, the section at height y keeps the part left of the leftmost
path point at or below y, h_c(y) = min {x(s) : y(s) <= y} (Tian's line from the tip for
a straight crack). When the leftmost point of the path lies at or below the root circle
or is its lowest point, h_c(y) is one constant over the sections of the tooth and the
path's record is that of the straight crack to that point; otherwise the path needs
more than one limiting line and is refused.

References
----------
.. [Chen2011] Z. Chen, Y. Shao, Dynamic simulation of spur gear with tooth root crack
   propagating along tooth width and crack depth, Eng. Fail. Anal. 18 (2011) 2149-2164.
.. [Tian2004] X. Tian, Dynamic simulation for system response of gearbox including
   localized gear faults, M.Sc. thesis, University of Alberta, 2004 (limiting line; a
   crack through the centre line).
.. [Wu2008] S. Wu, M. J. Zuo, A. Parey, Simulation of spur gear dynamics and estimation
   of fault growth, J. Sound Vib. 317 (2008) 608-624 (crack through the centre line:
   A_x = (h_x - h_q) L, I_x = (h_x - h_q)^3 L / 12; quoted from memory, the text was not
   reachable here).
.. [Seed] eqs. 10-11.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from gearsim.errors import InputError, require
from gearsim.geometry import _kernels as G
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness import _kernels as K

__all__ = ["Crack", "crack_geometry", "crack_record", "cuts_tooth_off", "path_leftmost",
           "path_limiting_line", "path_record"]

#: Smallest non-zero crack depth [m]: 1 um, a tenth of the finest grain of case-hardened
#: gear steels (ASTM grain size 8-10 is 11-22 um, ISO 643); a smaller depth is a unit
#: mistake (e.g. 2e-9 written for 2 mm), not a crack.
MIN_CRACK_DEPTH = 1e-6

FLANKS = ("working", "non-working")
PROFILES = ("uniform", "linear", "parabolic")


@dataclass(frozen=True)
class Crack:
    """A tooth-root crack.

    Parameters
    ----------
    gear
        Name of the cracked gear.
    tooth
        Index of the cracked tooth (0 .. z-1, counted in the order the teeth enter mesh).
    flank
        ``"working"`` or ``"non-working"``. The working flank of a gear is the flank
        loaded in the first mesh it takes part in along the power flow; an idler's
        other mesh loads the other flank.
    depth
        Crack depth q0 at the face z = 0 [m] (>= 0).
    angle
        Angle between the crack and the tooth centre line [rad] (default 45 deg,
        Chen & Shao 2011), in (0, 90] deg.
    extent
        Fraction of the face width covered, (0, 1].
    profile
        Depth profile along the face width: uniform, linear or parabolic.
    start_radius
        Radius of the start point on the fillet [m]; ``None`` = the 30 deg tangent point.

    Raises
    ------
    InputError
        If the flank or profile name is unknown, the depth < 0 or not finite, the
        start radius not a finite number > 0, the angle outside
        (0, 90] deg, the extent outside (0, 1] or the tooth index not an integer >= 0.

    References
    ----------
    Chen & Shao (2011) (crack angle, depth profile along the face); Tian (2004) and
    seed eqs. 10-11 (limiting line).
    """

    gear: str
    tooth: int = 0
    flank: str = "working"
    depth: float = 0.0
    angle: float = math.radians(45.0)
    extent: float = 1.0
    profile: str = "uniform"
    start_radius: float | None = None

    def __post_init__(self) -> None:
        require(self.flank in FLANKS, "crack.flank", self.flank,
                'must be "working" or "non-working"')
        require(self.profile in PROFILES, "crack.profile", self.profile,
                'must be "uniform", "linear" or "parabolic"')
        require(math.isfinite(self.depth) and (self.depth == 0.0
                                               or self.depth >= MIN_CRACK_DEPTH),
                "crack.depth", self.depth, f"must be 0 (no crack) or a finite number >= "
                f"{MIN_CRACK_DEPTH:g} m (1 um: below the grain size of gear steels a "
                "crack depth can only be a unit mistake)")
        require(0.0 < self.angle <= 0.5 * math.pi + 1e-12, "crack.angle",
                f"{math.degrees(self.angle):.6g} deg", "must be in (0, 90] deg")
        require(0.0 < self.extent <= 1.0, "crack.extent", self.extent, "must be in (0, 1]")
        require(isinstance(self.tooth, int) and not isinstance(self.tooth, bool)
                and self.tooth >= 0, "crack.tooth", self.tooth, "must be an integer >= 0")
        require(self.start_radius is None
                or (math.isfinite(self.start_radius) and self.start_radius > 0.0),
                "crack.start_radius", self.start_radius, "must be a finite number > 0 m")

    def depth_at(self, z_fraction: np.ndarray) -> np.ndarray:
        """Crack depth at axial positions along the face width.

        Parameters
        ----------
        z_fraction
            Axial positions as fractions of the face width, 0 at the cracked face.

        Returns
        -------
        ndarray
            Depth [m]: q0, q0 (1 - z/w) or q0 sqrt(1 - z/w) inside the extent w, 0
            outside.

        Examples
        --------
        Parabolic front (Chen & Shao 2011) over the whole face, q0 = 2 mm: at z/w = 0.75
        the depth is q0 sqrt(0.25) = 1 mm.

        >>> c = Crack(gear="input", depth=2e-3, profile="parabolic")
        >>> [round(float(q) * 1e3, 12) for q in c.depth_at([0.0, 0.75, 1.0])]
        [2.0, 1.0, 0.0]
        """
        z = np.asarray(z_fraction, dtype=float)
        xi = np.clip(1.0 - z / self.extent, 0.0, 1.0)
        inside = z <= self.extent
        if self.profile == "uniform":
            f = np.ones_like(z)
        elif self.profile == "linear":
            f = xi
        else:
            f = np.sqrt(xi)
        return np.where(inside, self.depth * f, 0.0)


@dataclass(frozen=True)
class CrackGeometry:
    """Crack in the tooth frame of the cracked flank (x towards that flank).

    Parameters
    ----------
    start
        Start point (x_s, y_s) on the fillet [m].
    tip
        Tip (x_t, y_t) [m]; x_t is h_c of the limiting line (negative past the centre
        line).
    max_depth
        Depth at which the tip would reach the centre line, x_s / sin(nu) [m] (a deeper
        crack is past it: h_c < 0).
    """

    start: tuple[float, float]
    tip: tuple[float, float]
    max_depth: float


def _top_half_width(profile: ToothProfile) -> float:
    """Half width of the tooth at the top of the involute (the tip circle) [m]."""
    return float(_outline(profile)[-1, 0])


def cuts_tooth_off(profile: ToothProfile, h_c: float) -> bool:
    """Whether a limiting line at ``h_c`` cuts the model's tooth off below its tip.

    The section width is h + h_c (Tian 2004; past the centre line h - h_q, Wu, Zuo &
    Parey 2008). The half width h of the tooth falls from the root to the top land, so
    the width first reaches zero at the top land: the tooth is cut off below its highest
    load point when h_top + h_c <= 0.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    h_c
        Signed distance of the limiting line from the centre line [m] (> 0 on the
        cracked side).

    Returns
    -------
    bool
        True when the section width h + h_c reaches zero at or below the tip circle.

    Examples
    --------
    >>> from gearsim.geometry.gear import Gear
    >>> prof = ToothProfile(Gear(teeth=19, normal_module=3.2e-3, name="pinion"))
    >>> cuts_tooth_off(prof, 0.0), cuts_tooth_off(prof, -1e-2)
    (False, True)
    """
    return _top_half_width(profile) + h_c <= 0.0


def crack_geometry(profile: ToothProfile, crack: Crack, depth: float | None = None
                   ) -> CrackGeometry:
    """Start and tip of the crack, after checking it lies on the fillet and in the tooth.

    Tip ``x_t = x_s - q sin(nu)``, ``y_t = y_s - q cos(nu)`` (seed eqs. 10-11). The tip
    may lie past the tooth centre line (x_t < 0, a crack through the centre line, Tian
    2004, Wu, Zuo & Parey 2008) as long as the limiting line x = x_t leaves a section of
    width h + x_t > 0 up to the tip circle (:func:`cuts_tooth_off`).

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    crack
        The crack (start radius or default 30 deg tangent point, angle nu).
    depth
        Depth q of this section [m]; default ``crack.depth``.

    Returns
    -------
    CrackGeometry
        Start, tip and the depth at which the tip reaches the centre line [m].

    Raises
    ------
    InputError
        If the start radius is not on the fillet or the crack cuts the tooth off (the
        section width h + x_t reaches zero below the tip circle: tooth loss).

    Examples
    --------
    The tip lies at distance q from the start, at 45 deg: equal drops in x and y.

    >>> import math
    >>> from gearsim.geometry.gear import Gear
    >>> from gearsim.geometry.profile import ToothProfile
    >>> prof = ToothProfile(Gear(teeth=19, normal_module=3.2e-3, name="pinion"))
    >>> geo = crack_geometry(prof, Crack(gear="pinion", depth=1e-3))
    >>> round(math.dist(geo.start, geo.tip) * 1e3, 12)
    1.0
    >>> dx, dy = (a - b for a, b in zip(geo.start, geo.tip))
    >>> round(dx / dy, 12)
    1.0
    """
    gear = profile.gear
    if crack.start_radius is None:
        g = _tangent_param(profile)
    else:
        g = profile.fillet_param_at_radius(crack.start_radius)
    xs, ys = profile.fillet_point(g)
    q = crack.depth if depth is None else depth
    q_max = xs / math.sin(crack.angle)
    xt = xs - q * math.sin(crack.angle)
    yt = ys - q * math.cos(crack.angle)
    if cuts_tooth_off(profile, xt):
        q_cut = (xs + _top_half_width(profile)) / math.sin(crack.angle)
        raise InputError("crack.depth", f"{q * 1e3:.6g} mm",
                         f"crack is deeper than the tooth model allows on {gear.name}: it "
                         f"cuts the tooth off (tooth loss: its limiting line meets the far "
                         f"flank below the tip circle), depth < {q_cut * 1e3:.6g} mm at "
                         f"angle {math.degrees(crack.angle):.4g} deg")
    return CrackGeometry(start=(xs, ys), tip=(xt, yt), max_depth=q_max)


@lru_cache(maxsize=64)
def _tangent_param(profile: ToothProfile) -> float:
    """Rack-round angle of the 30 deg tangent point (:meth:`ToothProfile.tangent_point`).

    The default crack start of every crack on this outline, whatever its depth: computed
    once per outline (a frozen value) and process, not once per section and case.
    """
    return profile.tangent_point()[0]


@lru_cache(maxsize=64)
def _outline(profile: ToothProfile) -> np.ndarray:
    """``profile.outline(400, 400)`` (read-only), computed once per outline and process."""
    pts = profile.outline(400, 400)
    pts.flags.writeable = False
    return pts


def _locate(profile: ToothProfile, y: float) -> tuple[int, float]:
    """Outline segment and parameter at height ``y``."""
    p = profile.packed
    _, yf = G.fillet_point(p[G.P_AN], p)
    if y <= yf:
        return 0, G.param_at_coordinate(0, 1, y, 0.5 * math.pi, p[G.P_AN], p)
    return 1, G.param_at_coordinate(1, 1, y, p[G.P_RF], p[G.P_RA], p)


def crack_record(profile: ToothProfile, crack: Crack, depth: float, side: int) -> np.ndarray:
    """Kernel record (``K.C_*`` layout) of a crack of ``depth`` at one axial slice.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    crack
        The crack (angle, start point).
    depth
        Local crack depth at this slice [m]; 0 gives an inactive (healthy) record.
    side
        +1 if the cracked flank is the loaded one in the mesh considered, -1 otherwise.

    Returns
    -------
    ndarray, shape (C_SIZE,)
        Record: active flag, side, h_c = x_t (negative past the centre line), the
        cracked height range from the tip (or the root) up to g_c, where the outline's
        half width first falls to h_c (the tip circle when it does not: always so for
        h_c < 0), and the outline segment and parameter of both ends.

    Raises
    ------
    InputError
        As :func:`crack_geometry` (a crack that cuts the tooth off).

    References
    ----------
    Tian (2004); Wu, Zuo & Parey (2008) (crack through the centre line); seed eqs. 10-11
    (limiting line).
    """
    rec = np.zeros(K.C_SIZE)
    if depth <= 0.0:
        return rec
    geo = crack_geometry(profile, crack, depth)
    return _record(profile, geo.tip[0], geo.tip[1], side)


def _record(profile: ToothProfile, xt: float, yt: float, side: int) -> np.ndarray:
    """Kernel record of a limiting line at h_c = ``xt`` from height ``yt`` upwards."""
    rec = np.zeros(K.C_SIZE)
    p = profile.packed
    y_lo = max(yt, profile.root_height)
    # g_c: first height above the tip where the outline half width falls to h_c
    pts = _outline(profile)
    above = pts[:, 1] > y_lo
    idx = np.nonzero(above & (pts[:, 0] <= xt))[0]
    if idx.size == 0:
        seg_hi, p_hi = 1, p[G.P_RA]
        y_hi = G.involute_point(p[G.P_RA], p)[1]
    else:
        i = int(idx[0])
        # bracket between outline samples i-1 and i, refine on the segment parameter
        seg_hi = 0 if i < 400 else 1
        if seg_hi == 0:
            gs = 0.5 * math.pi - (0.5 * math.pi - p[G.P_AN]) * np.arange(400) / 399
            pa, pb = gs[max(i - 1, 0)], gs[i]
        else:
            rs = p[G.P_RF] + (p[G.P_RA] - p[G.P_RF]) * np.arange(400) / 399
            j = i - 400
            pa, pb = (rs[j - 1], rs[j]) if j > 0 else (rs[0], rs[0])
            if j == 0:  # junction sample: the bracket is the fillet's last interval
                seg_hi = 0
                pa, pb = p[G.P_AN] + 1e-12, p[G.P_AN]
        p_hi = G.param_at_coordinate(seg_hi, 0, xt, pa, pb, p) if pa != pb else pa
        y_hi = G.profile_point(seg_hi, p_hi, p)[1]
    seg_lo, p_lo = _locate(profile, y_lo)
    rec[K.C_ACTIVE] = 1.0
    rec[K.C_SIDE] = float(side)
    rec[K.C_HC] = xt
    rec[K.C_YLO] = y_lo
    rec[K.C_YHI] = y_hi
    rec[K.C_SEGLO] = seg_lo
    rec[K.C_PLO] = p_lo
    rec[K.C_SEGHI] = seg_hi
    rec[K.C_PHI] = p_hi
    return rec


@dataclass(frozen=True)
class PathLine:
    """Limiting line of a polyline crack (:func:`path_limiting_line`).

    Parameters
    ----------
    h_c
        Signed distance of the line from the centre line [m] (the leftmost path point).
    y_low
        Height from which the sections are cracked, max(y of that point, root) [m].
    point
        The path point that sets the line, (x, y) [m].
    """

    h_c: float
    y_low: float
    point: tuple[float, float]


def path_leftmost(profile: ToothProfile, points: np.ndarray) -> tuple[int, bool]:
    """The path point that sets the limiting line, and whether one line represents it.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    points
        Path vertices, shape (n, 2), as :func:`path_limiting_line` [m].

    Returns
    -------
    index : int
        The leftmost vertex (smallest x; the extremes of a polyline are at vertices).
    turns_back : bool
        True when that vertex lies above the root circle with path points below it: the
        path turns back up and needs more than one limiting line (Tian's line of every
        path point, h_c(y) = min {x(s) : y(s) <= y}, is then not one constant).
    """
    i = int(np.argmin(points[:, 0]))
    y = float(points[i, 1])
    return i, bool(y > profile.root_height and float(points[:, 1].min()) < y)


def path_limiting_line(profile: ToothProfile, points) -> PathLine:
    """The one limiting line of a polyline crack path, when one line represents it.

    A vertical limiting line drawn up from every point of the path (Tian's line from
    the tip of a straight crack, Tian 2004) leaves at height y the part of the section
    left of h_c(y) = min {x(s) : y(s) <= y}. Over the sections of the tooth (from the
    root circle up) this is the one constant h_c = x_min, from y_low = max(y(x_min),
    y_root), when the leftmost point of the path lies at or below the root circle or no
    path point lies below it. The path is piecewise linear: the extremes are at
    vertices.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    points
        Path vertices (n >= 2, 2), from the start on the cracked fillet, in the frame of
        :func:`crack_geometry` (x towards the cracked flank) [m].

    Returns
    -------
    PathLine

    Raises
    ------
    InputError
        If the path needs more than one limiting line (its leftmost point lies above
        the root circle with path points below it), or cuts the tooth off
        (:func:`cuts_tooth_off`).

    Examples
    --------
    A straight path has the line of its tip:

    >>> from gearsim.geometry.gear import Gear
    >>> prof = ToothProfile(Gear(teeth=19, normal_module=3.2e-3, name="pinion"))
    >>> geo = crack_geometry(prof, Crack(gear="pinion", depth=1e-3))
    >>> path_limiting_line(prof, [geo.start, geo.tip]).point == geo.tip
    True
    """
    pts = np.asarray(points, dtype=float)
    require(pts.ndim == 2 and pts.shape[0] >= 2 and pts.shape[1] == 2
            and bool(np.all(np.isfinite(pts))), "crack.points", pts.shape,
            "must be >= 2 finite (x, y) points")
    i, turns_back = path_leftmost(profile, pts)
    xm, ym = float(pts[i, 0]), float(pts[i, 1])
    y_root = profile.root_height
    if turns_back:
        raise InputError("crack.points", f"leftmost point at y = {ym * 1e3:.6g} mm",
                         "the path turns back up above the root circle: it needs more "
                         "than one limiting line (the PE crack model takes one)")
    if cuts_tooth_off(profile, xm):
        raise InputError("crack.points", f"h_c = {xm * 1e3:.6g} mm",
                         f"the path cuts the tooth off (tooth loss: the limiting line "
                         f"meets the far flank below the tip circle, h_c <= "
                         f"{-_top_half_width(profile) * 1e3:.6g} mm)")
    return PathLine(h_c=xm, y_low=max(ym, y_root), point=(xm, ym))


def path_record(profile: ToothProfile, points, side: int) -> np.ndarray:
    """Kernel record (``K.C_*`` layout) of a polyline crack path.

    Parameters
    ----------
    profile
        Outline of the cracked gear.
    points
        Path vertices, as :func:`path_limiting_line` [m].
    side
        +1 if the cracked flank is the loaded one, -1 otherwise.

    Returns
    -------
    ndarray, shape (C_SIZE,)
        The record of :func:`crack_record` for the limiting line of the path; for a
        straight path, that of the straight crack.

    Raises
    ------
    InputError
        As :func:`path_limiting_line`.
    """
    line = path_limiting_line(profile, points)
    return _record(profile, line.point[0], line.point[1], side)
