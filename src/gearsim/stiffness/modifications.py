"""Flank modifications and tooth errors of one gear: the no-load separation they add.

All amounts are measured in the transverse plane along the line of action, i.e. as
the change of the no-load separation of the mating flanks (positive: material removed,
contact later). The profile coordinate is the roll length rho = sqrt(r^2 - r_b^2) of the
contact point on this gear (:mod:`gearsim.stiffness.faults`).

* **Tip relief** C_a over the roll length L_a below the tip, ``linear``:
  C_a (rho - rho_a + L_a) / L_a, ``parabolic``: C_a ((rho - rho_a + L_a) / L_a)^2, for
  rho > rho_a - L_a (rho_a: roll length of the tip circle); **root relief** C_f over L_f
  above the start of the active profile rho_f in the same way (ISO 21771 profile
  modifications; Velex & Maatar 1996).
* **Lead crowning** C_b: C_b (2 z / b - 1)^2, z from the face edge.
* **Helix slope deviation** f_Hb (misalignment of the flank lines): f_Hb (z / b - 1/2).
* **Pitch errors**: the position deviation F_p,i of each tooth's flank (ISO 1328-1
  cumulative pitch deviation of tooth i; the single pitch deviation is
  f_p,i = F_p,i - F_p,i-1), given per tooth or drawn for an ISO 1328-1:2013 accuracy
  grade A from a seed.

References
----------
.. [ISO1328] ISO 1328-1:2013, Cylindrical gears - ISO system of flank tolerance
   classification - Part 1, clause 5.3 (tolerance formulas, grades 1 to 11).
.. [ISO21771] ISO 21771:2007, clause 8 (profile and helix modifications).
.. [Velex1996] P. Velex, M. Maatar, A mathematical model for analyzing the influence of
   shape deviations and mounting errors on gear dynamic behaviour, J. Sound Vib. 191
   (1996) 629-660.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require

__all__ = ["MAX_DEVIATION_MODULES", "RELIEF_SHAPES", "Modification", "single_pitch_tolerance"]

#: Largest relief, crowning, helix slope deviation and pitch deviation, in normal modules
#: (checked with the gear, :func:`gearsim.system.faults.check_faults`): reliefs and
#: crowning are ~0.005-0.02 m_n, ISO 1328-1 grade 11 (the coarsest) allows cumulative
#: pitch deviations of ~0.2 m_n on small modules; a larger value is a unit mistake.
MAX_DEVIATION_MODULES = 0.25

#: Shapes of tip and root relief.
RELIEF_SHAPES = ("linear", "parabolic")
#: Accuracy grades of ISO 1328-1:2013.
GRADES = range(1, 12)


def single_pitch_tolerance(grade: int, diameter: float, module: float) -> float:
    """ISO 1328-1:2013 single pitch tolerance f_pT [m].

    f_pT = (0.001 d + 0.4 m_n + 5) (sqrt 2)^(A - 5) um, with d and m_n in mm.

    Parameters
    ----------
    grade : int
        Flank tolerance class A, 1 .. 11.
    diameter : float
        Reference diameter d [m].
    module : float
        Normal module m_n [m].

    Returns
    -------
    float
        f_pT [m].

    References
    ----------
    ISO 1328-1:2013, 5.3.1.1 (docs/references.md, "ISO 1328-1 tolerances").

    Examples
    --------
    Grade 5, d = 234 mm, m_n = 6 mm: 0.234 + 2.4 + 5 = 7.634 um.

    >>> round(single_pitch_tolerance(5, 0.234, 0.006) * 1e6, 3)
    7.634
    """
    require(isinstance(grade, numbers.Integral) and not isinstance(grade, bool)
            and grade in GRADES, "pitch_grade", grade, "must be an ISO 1328-1 grade 1 .. 11")
    return (0.001 * diameter * 1e3 + 0.4 * module * 1e3 + 5.0) * math.sqrt(2.0) ** (grade - 5) * 1e-6


def _amount(name: str, v: object, *, signed: bool = False) -> None:
    ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
    require(ok and (signed or v >= 0), name, v,
            "must be a finite number" + ("" if signed else " >= 0") + " m")


@dataclass(frozen=True, kw_only=True)
class Modification:
    """Profile and lead modifications and tooth errors of one gear.

    Parameters
    ----------
    gear : str
        Name of the gear.
    tip_relief, root_relief : float
        Amounts C_a, C_f [m] (along the line of action).
    tip_relief_length, root_relief_length : float
        Roll lengths L_a, L_f over which they act [m].
    relief_shape : {"linear", "parabolic"}
        Shape of both reliefs.
    crowning : float
        Lead crowning C_b [m] (separation at each face edge, 0 at mid-face).
    helix_slope : float
        Helix slope deviation f_Hb [m] over the face width (signed).
    pitch_errors : tuple of float
        Position deviation F_p,i of each tooth's flank [m] (one per tooth; positive:
        the flank lies behind its nominal position, contact later). Empty: none, or
        drawn for ``pitch_grade``.
    pitch_grade : int, optional
        ISO 1328-1:2013 grade (1 .. 11) for random single pitch deviations.
    pitch_seed : int
        Seed of the random deviations.

    Raises
    ------
    InputError
        For a negative or non-finite amount, a relief amount without a length, an
        unknown shape, a grade outside 1 .. 11, or both ``pitch_errors`` and
        ``pitch_grade``.
    """

    gear: str
    tip_relief: float = 0.0
    tip_relief_length: float = 0.0
    root_relief: float = 0.0
    root_relief_length: float = 0.0
    relief_shape: str = "linear"
    crowning: float = 0.0
    helix_slope: float = 0.0
    pitch_errors: tuple[float, ...] = ()
    pitch_grade: int | None = None
    pitch_seed: int = 0

    def __post_init__(self) -> None:
        require(isinstance(self.gear, str) and self.gear != "", "modifications.gear",
                self.gear, "name the gear")
        for name in ("tip_relief", "tip_relief_length", "root_relief", "root_relief_length",
                     "crowning"):
            _amount(f"modifications.{name}", getattr(self, name))
        _amount("modifications.helix_slope", self.helix_slope, signed=True)
        for which in ("tip", "root"):
            amt, length = getattr(self, f"{which}_relief"), getattr(self, f"{which}_relief_length")
            require(amt == 0 or length > 0, f"modifications.{which}_relief_length", length,
                    f"must be > 0 m when {which}_relief = {amt:g} m")
        require(self.relief_shape in RELIEF_SHAPES, "modifications.relief_shape",
                self.relief_shape, 'must be "linear" or "parabolic"')
        for e in self.pitch_errors:
            _amount("modifications.pitch_errors", e, signed=True)
        if self.pitch_grade is not None:
            require(not self.pitch_errors, "modifications.pitch_grade", self.pitch_grade,
                    "give pitch_errors or pitch_grade, not both")
            require(isinstance(self.pitch_grade, numbers.Integral)
                    and not isinstance(self.pitch_grade, bool) and self.pitch_grade in GRADES,
                    "modifications.pitch_grade", self.pitch_grade,
                    "must be an ISO 1328-1 grade 1 .. 11")
        require(isinstance(self.pitch_seed, numbers.Integral) and self.pitch_seed >= 0,
                "modifications.pitch_seed", self.pitch_seed, "must be an integer >= 0")

    @property
    def has_pitch_errors(self) -> bool:
        """True when the teeth differ (given or random pitch errors)."""
        return bool(self.pitch_errors) or self.pitch_grade is not None

    def tooth_positions(self, teeth: int, diameter: float, module: float) -> np.ndarray:
        """Position deviation F_p,i of every tooth [m] (zeros without pitch errors).

        Random deviations (``pitch_grade``): single pitch deviations f_p,i drawn from a
        normal law with standard deviation f_pT / 2 clipped to +-f_pT (ISO 1328-1: no
        single pitch deviation may exceed f_pT), their mean removed so that the pitch
        closes over the revolution, then summed: F_p,i = sum_{j <= i} f_p,j.

        Parameters
        ----------
        teeth : int
            Number of teeth z.
        diameter : float
            Reference diameter [m].
        module : float
            Normal module [m].

        Returns
        -------
        ndarray, shape (teeth,)
        """
        if self.pitch_errors:
            require(len(self.pitch_errors) == teeth, "modifications.pitch_errors",
                    len(self.pitch_errors), f"need one value per tooth ({teeth} teeth of "
                    f"{self.gear})")
            return np.asarray(self.pitch_errors, dtype=float)
        if self.pitch_grade is None:
            return np.zeros(teeth)
        fpt = single_pitch_tolerance(self.pitch_grade, diameter, module)
        gen = np.random.default_rng(self.pitch_seed)
        f = np.clip(gen.normal(0.0, 0.5 * fpt, teeth), -fpt, fpt)
        f -= f.mean()
        return np.cumsum(f)

    def profile_separation(self, roll: np.ndarray, roll_tip: float,
                           roll_start: float) -> np.ndarray:
        """Tip and root relief at roll lengths ``roll`` [m].

        Parameters
        ----------
        roll : ndarray
            Roll length of the contact point on this gear [m].
        roll_tip : float
            Roll length of the tip circle rho_a [m].
        roll_start : float
            Roll length of the start of the active profile rho_f in this mesh [m].

        Returns
        -------
        ndarray
            Separation [m].

        Examples
        --------
        Linear tip relief 10 um over 2 mm, tip at rho 20 mm: 5 um at 19 mm, 0 at 17 mm.

        >>> m = Modification(gear="g", tip_relief=10e-6, tip_relief_length=2e-3)
        >>> [round(float(v) * 1e6, 6) for v in m.profile_separation(
        ...     np.array([0.017, 0.019]), 0.020, 0.005)]
        [0.0, 5.0]
        """
        roll = np.asarray(roll, dtype=float)
        p = 1 if self.relief_shape == "linear" else 2
        out = np.zeros(roll.shape)
        if self.tip_relief > 0:
            x = np.clip((roll - roll_tip + self.tip_relief_length) / self.tip_relief_length,
                        0.0, None)
            out += self.tip_relief * x ** p
        if self.root_relief > 0:
            x = np.clip((roll_start + self.root_relief_length - roll) / self.root_relief_length,
                        0.0, None)
            out += self.root_relief * x ** p
        return out

    def lead_separation(self, zfrac: np.ndarray) -> np.ndarray:
        """Crowning and helix slope at axial positions z / b [m].

        Parameters
        ----------
        zfrac : ndarray
            Axial position / face width [-].

        Returns
        -------
        ndarray
            Separation [m].

        Examples
        --------
        Crowning 8 um: 8 um at both edges, 0 mid-face; slope 4 um: -2 .. +2 um.

        >>> m = Modification(gear="g", crowning=8e-6, helix_slope=4e-6)
        >>> [round(float(v) * 1e6, 6) for v in m.lead_separation(np.array([0.0, 0.5, 1.0]))]
        [6.0, 0.0, 10.0]
        """
        zf = np.asarray(zfrac, dtype=float)
        return self.crowning * (2 * zf - 1) ** 2 + self.helix_slope * (zf - 0.5)
