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
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from gearsim.errors import InputError, require
from gearsim.fracture.direction import equivalent_k
from gearsim.fracture.mesh import CrackPath
from gearsim.fracture.paris import LifeResult, ParisLaw, paris_life
from gearsim.fracture.tooth import grow_crack
from gearsim.geometry.gear import Gear

__all__ = ["GrowthPath", "grow_path", "path_life"]


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
        was too large for the ligament left).
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
        ``n_teeth``, ``plane``, ``refinement``, ``bore_radius``).

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
