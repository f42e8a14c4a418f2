"""Crack path of a tooth-root crack grown by increments, and its Paris life.

:func:`grow_path` repeats :func:`gearsim.fracture.tooth.grow_crack` (K at the tip, MTS
kink, extension by ``da``, remeshing) and records K_I, K_II, the kink angle and the
equivalent K_eq (:func:`gearsim.fracture.direction.equivalent_k`) against the crack
length (the length of the polyline). It stops after ``steps`` increments or when the
next increment is refused because the crack has (nearly) run through the body: the
tooth or the rim breaks there.

:func:`path_life` integrates the Paris law along the path
(:func:`gearsim.fracture.paris.paris_life`). The model is linear elastic with free crack
faces, so K is proportional to the load: dK(a) = K_eq(a) dF / F_path for a load range
dF (R = 0: dF = F_max), K_eq between the computed lengths by a shape-preserving
piecewise cubic (PCHIP, Fritsch & Carlson 1980) of log K_eq in log a: exact for a
power law K ~ a^p (a short edge crack: p = 1/2), monotone where the data are.

References
----------
.. [Fritsch1980] F. N. Fritsch, R. E. Carlson, Monotone piecewise cubic interpolation,
   SIAM J. Numer. Anal. 17 (1980) 238-246.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator

from gearsim.errors import InputError, require
from gearsim.fem.geometry import point_in_polygon
from gearsim.fracture.direction import equivalent_k, kink_angle, kinked_direction
from gearsim.fracture.mesh import CrackPath
from gearsim.fracture.paris import LifeResult, ParisLaw, paris_life
from gearsim.fracture.tooth import (
    _dist_to_segments,
    _tip_clearance,
    cycle_intensity,
    grow_crack,
    sector_polygon,
)
from gearsim.geometry.gear import Gear

__all__ = ["CyclePath", "GrowthPath", "grow_cycle_path", "grow_path", "largest_increment",
           "path_life"]


@dataclass(frozen=True)
class GrowthPath:
    """A crack grown increment by increment, with K along it.

    Parameters
    ----------
    crack
        The final path (one point more than the K values: the last tip is not analysed).
    lengths
        Crack length (polyline length) at each analysed tip [m], increasing.
    k1, k2
        K_I, K_II at those tips for the force ``force`` [Pa sqrt(m)].
    kink
        MTS kink angle at those tips [rad].
    force
        Force per unit face width the K values are for [N/m].
    status
        ``"steps done"`` or ``"broken"`` (the next increment would leave the body or
        was too large for the ligament left); :func:`grow_cycle_path` also
        ``"no growth"``.
    message
        The refusal that ended the path (empty for ``"steps done"``).
    seconds
        Wall time [s].
    """

    crack: CrackPath
    lengths: np.ndarray
    k1: np.ndarray
    k2: np.ndarray
    kink: np.ndarray
    force: float
    status: str
    message: str
    seconds: float

    @property
    def keq(self) -> np.ndarray:
        """MTS equivalent K at the analysed tips [Pa sqrt(m)]."""
        return np.array([equivalent_k(a, b) for a, b in zip(self.k1, self.k2, strict=True)])


def grow_path(gear: Gear, crack: CrackPath, radius: float, increment: float, *,
              steps: int, **options) -> GrowthPath:
    """Grow a tooth-root crack by ``steps`` MTS increments (or until the tooth breaks).

    Parameters
    ----------
    gear
        The gear.
    crack
        Initial crack (:func:`gearsim.fracture.tooth.initial_crack`).
    radius
        Contact radius of the load [m].
    increment
        Extension per step da [m].
    steps
        Largest number of increments (1 to 500).
    **options
        Passed to :func:`gearsim.fracture.tooth.tooth_crack_sif` (``force``,
        ``n_teeth``, ``plane``, ``refinement``, ``bore_radius``, ``web``: with a
        :class:`gearsim.fracture.tooth.RimWeb` the path also ends, ``"broken"``, when
        the tip reaches the rim's inner radius).

    Returns
    -------
    GrowthPath

    Raises
    ------
    InputError
        Bad ``steps`` or first increment; later refusals end the path instead
        (status ``"broken"``).
    """
    require(isinstance(steps, int) and 1 <= steps <= 500, "steps", steps,
            "must be an integer in [1, 500]")
    t0 = time.perf_counter()
    lengths, k1, k2, kink = [], [], [], []
    status, message = "steps done", ""
    force = float(options.get("force", 1e5))
    for i in range(steps):
        try:
            res, grown = grow_crack(gear, crack, radius, increment, **options)
        except InputError as exc:
            if i == 0 or exc.parameter not in ("crack.increment", "crack.path"):
                raise
            status, message = "broken", str(exc)
            break
        lengths.append(crack.length)
        k1.append(res.sif.k1)
        k2.append(res.sif.k2)
        kink.append(res.kink)
        crack = grown
    return GrowthPath(crack=crack, lengths=np.asarray(lengths), k1=np.asarray(k1),
                      k2=np.asarray(k2), kink=np.asarray(kink), force=force, status=status,
                      message=message, seconds=time.perf_counter() - t0)


def path_life(path: GrowthPath, law: ParisLaw, force_range: float, *,
              force_max: float | None = None, points: int = 50) -> LifeResult:
    """Paris life along a grown path.

    Parameters
    ----------
    path
        The path with K at >= 2 lengths.
    law
        Paris law with threshold and toughness.
    force_range
        Range of the force per unit face width over a load cycle dF [N/m] (> 0).
    force_max
        Largest force of the cycle [N/m], for K_max against K_IC; default
        ``force_range`` (R = 0).
    points
        Output lengths.

    Returns
    -------
    LifeResult
        From the first analysed length; ``"length limit"`` is the end of the path (the
        tooth breaks if ``path.status == "broken"``).

    Raises
    ------
    InputError
        Fewer than 2 lengths, a non-positive force, or a K_eq <= 0 on the path (a closed
        crack, outside this open-face model).
    """
    require(path.lengths.size >= 2, "path.lengths", int(path.lengths.size),
            "needs K at >= 2 crack lengths")
    require(math.isfinite(force_range) and force_range > 0.0, "force_range", force_range,
            "must be > 0 N/m")
    fmax = force_range if force_max is None else float(force_max)
    require(math.isfinite(fmax) and fmax >= force_range, "force_max", force_max,
            f"must be >= force_range = {force_range:g} N/m")
    keq = path.keq
    require(bool(np.all(keq > 0.0)), "path.k1", float(keq.min()),
            "K_eq must be > 0 along the path (open crack)")
    interp = PchipInterpolator(np.log(path.lengths), np.log(keq / path.force))

    def dk(a: float) -> float:
        return math.exp(float(interp(math.log(a)))) * force_range

    def kmax(a: float) -> float:
        return math.exp(float(interp(math.log(a)))) * fmax

    return paris_life(law, dk, float(path.lengths[0]), float(path.lengths[-1]), k_max=kmax,
                      points=points)


@dataclass(frozen=True)
class CyclePath(GrowthPath):
    """A crack grown under the loads of a mesh cycle (:func:`grow_cycle_path`).

    ``k1``, ``k2`` and ``kink`` are those of the contact position with the largest K_eq
    at each tip, ``force`` is 1 (the K values are for the given forces).

    Parameters
    ----------
    crack, lengths, k1, k2, kink, force, status, message, seconds
        As :class:`GrowthPath`.
    delta_k
        Range of K_eq over the cycle at each tip [Pa sqrt(m)]
        (:attr:`gearsim.fracture.tooth.CycleIntensity.delta_k`).
    position
        Index of the contact position with the largest K_eq at each tip.
    dofs
        FE unknowns at each tip.
    seconds_per_step
        Wall time of each increment (mesh, solve for every position, integral) [s].
    """

    delta_k: np.ndarray = field(default_factory=lambda: np.zeros(0))
    position: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    seconds_per_step: np.ndarray = field(default_factory=lambda: np.zeros(0))


def largest_increment(gear: Gear, crack: CrackPath, *, n_teeth: int = 3,
                      bore_radius: float | None = None, web=None) -> float:
    """The largest first increment :func:`grow_cycle_path` accepts [m].

    Half the distance from the crack's tip to the outline of the sector ahead of it
    (:func:`gearsim.fracture.tooth.sector_polygon`): a larger increment is refused at
    the first step. Geometry only, so a caller can check an increment before any work.

    Parameters
    ----------
    gear, crack
        As :func:`grow_path`.
    n_teeth, bore_radius, web
        The sector (:func:`gearsim.fracture.tooth.sector_polygon`).

    Returns
    -------
    float
        0.5 x the tip's clearance ahead [m].
    """
    poly, _ = sector_polygon(gear, n_teeth, bore_radius=bore_radius, web=web)
    return 0.5 * _tip_clearance(poly, crack, ahead=True)


def grow_cycle_path(gear: Gear, crack: CrackPath, radii, forces, increment: float, *,
                    steps: int, min_keq: float = 0.0, **options) -> CyclePath:
    """Grow a root crack under the loads of a mesh cycle, ``steps`` MTS increments.

    At each tip K_I, K_II are computed for every contact position on one mesh
    (:func:`gearsim.fracture.tooth.cycle_intensity`); the crack kinks by the MTS angle of
    the position with the largest K_eq (the load that drives the growth) and extends by
    ``increment``. The checks of :func:`gearsim.fracture.tooth.grow_crack` apply: an
    increment larger than half the ligament ahead ends the path (``"broken"``), as does
    a new tip outside the body or within ``increment / 4`` of the outline.

    Parameters
    ----------
    gear, crack
        As :func:`grow_path`.
    radii
        Contact radii of the cycle [m].
    forces
        Force per unit face width at each radius [N/m].
    increment, steps
        As :func:`grow_path`.
    min_keq
        If the largest K_eq at the initial tip is below this [Pa sqrt(m)] (e.g. the
        Paris threshold over the load factor), the path stops there with status
        ``"no growth"`` (one analysed tip).
    **options
        Passed to :func:`gearsim.fracture.tooth.cycle_intensity` (``n_teeth``,
        ``plane``, ``refinement``, ``bore_radius``, ``web``: with a web the path also
        ends, ``"broken"``, when the tip reaches the rim's inner radius).

    Returns
    -------
    CyclePath

    Raises
    ------
    InputError
        Bad ``steps``, increment or loads; a first increment too large for the ligament.
    """
    require(isinstance(steps, int) and 1 <= steps <= 500, "steps", steps,
            "must be an integer in [1, 500]")
    require(math.isfinite(increment) and increment > 0.0, "crack.increment", increment,
            "must be > 0 m")
    t0 = time.perf_counter()
    web = options.get("web")
    poly, _ = sector_polygon(gear, options.get("n_teeth", 3),
                             bore_radius=options.get("bore_radius"), web=web)
    r_rim = (gear.bore_radius_value if options.get("bore_radius") is None
             else float(options["bore_radius"]))
    edges = (poly, np.roll(poly, -1, axis=0))
    rows: list[tuple] = []
    status, message = "steps done", ""
    for i in range(steps):
        t1 = time.perf_counter()
        clearance = _tip_clearance(poly, crack, ahead=True)
        if increment > 0.5 * clearance:
            msg = (f"crack.increment = {increment:g}: is too large for the local geometry: "
                   f"at most half the distance from the tip to the outline ahead of it, "
                   f"{0.5 * clearance:.4g} m")
            if i == 0:
                raise InputError("crack.increment", increment, msg.split(": ", 2)[-1])
            status, message = "broken", msg
            break
        ci = cycle_intensity(gear, crack, radii, forces, **options)
        j = int(np.argmax(ci.keq))
        k1, k2 = float(ci.k1[j]), float(ci.k2[j])
        tip, d = crack.tip_frame(1)
        new = tip + increment * kinked_direction(d, k1, k2)
        rows.append((crack.length, k1, k2, kink_angle(k1, k2), ci.delta_k, j, ci.dofs,
                     time.perf_counter() - t1))
        if i == 0 and float(ci.keq[j]) < min_keq:
            status = "no growth"
            break
        left = float(_dist_to_segments(new, *edges).min())
        if not (point_in_polygon(poly, new) and left > 0.25 * increment):
            status = "broken"
            message = ("crack.path: the grown crack leaves the body or reaches its outline: "
                       "the tooth (or rim) is broken at this increment")
            break
        if web is not None and float(np.hypot(*new)) < r_rim + 0.25 * increment:
            status = "broken"
            message = ("crack.path: the grown crack reaches the rim's inner radius (the "
                       "web): the rim is broken at this increment")
            break
        crack = CrackPath(points=(*crack.points, (float(new[0]), float(new[1]))),
                          tips=crack.tips)
    cols = list(zip(*rows, strict=True)) if rows else [()] * 8
    return CyclePath(crack=crack, lengths=np.asarray(cols[0], dtype=float),
                     k1=np.asarray(cols[1], dtype=float), k2=np.asarray(cols[2], dtype=float),
                     kink=np.asarray(cols[3], dtype=float), force=1.0, status=status,
                     message=message, seconds=time.perf_counter() - t0,
                     delta_k=np.asarray(cols[4], dtype=float),
                     position=np.asarray(cols[5], dtype=int),
                     dofs=np.asarray(cols[6], dtype=int),
                     seconds_per_step=np.asarray(cols[7], dtype=float))
