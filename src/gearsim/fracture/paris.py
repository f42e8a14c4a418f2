"""Fatigue crack growth: Paris law with threshold and fracture toughness, life N(a).

Growth rate per load cycle (Paris & Erdogan 1963), with the threshold as a cut-off:

    da/dN = C (dK)^m   for dK >= dK_th,   0 below,          [m/cycle]

dK = K_max - K_min the range of the (equivalent) stress intensity over a load cycle
[Pa sqrt(m)], C in (m/cycle) / (Pa sqrt(m))^m. Life from a_0 to a:

    N(a) = int_{a_0}^{a} da' / (C dK(a')^m)                                  [cycles]

by adaptive quadrature (``scipy.integrate.quad``) between output points. The life
ends at the first of: K_max(a) >= K_IC (fracture), dK(a) < dK_th (arrest: growth
stops), or the length limit given by the caller (e.g. the tooth is lost). If
dK(a_0) < dK_th the crack does not grow at all: status ``"no growth"``, N = inf --
an answer, not an error.

For a constant geometry factor, dK = Y dsigma sqrt(pi a), the integral is closed:
N = [a^(1 - m/2) - a_0^(1 - m/2)] / ((1 - m/2) C (Y dsigma sqrt(pi))^m) for m != 2 and
ln(a / a_0) / (C (Y dsigma sqrt(pi))^2) for m = 2 (Anderson 2005, sec. 10.2; the test).

Material constants: :data:`STEEL_CLASSES` holds the Paris constants of Barsom & Rolfe
for steel classes (upper bounds of many tests, R about 0): they set C and m only;
the threshold and the toughness depend on the grade, its heat treatment, the case
and the load ratio, and are given by the caller (:func:`steel_class_law`).

References
----------
.. [Paris1963] P. Paris, F. Erdogan, A critical analysis of crack propagation laws,
   J. Basic Eng. 85 (1963) 528-533.
.. [Barsom1999] J. M. Barsom, S. T. Rolfe, Fracture and Fatigue Control in Structures,
   3rd ed., ASTM 1999, ch. 9 (da/dN = 1.36e-10 dK^2.25 martensitic, 6.89e-12 dK^3.0
   ferrite-pearlite, 5.60e-12 dK^3.25 austenitic steels; m/cycle, MPa sqrt(m)).
.. [Anderson2005] T. L. Anderson, Fracture Mechanics, 3rd ed., CRC 2005, ch. 10.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from gearsim.errors import InputError, require

__all__ = ["STEEL_CLASSES", "LifeResult", "ParisLaw", "paris_life", "steel_class_law"]

MPA_SQRT_M = 1e6  # Pa sqrt(m) per MPa sqrt(m)

#: Bounds of the physical range of the constants (steels and other structural metals).
EXPONENT_RANGE = (1.0, 8.0)
#: da/dN at dK = 10 MPa sqrt(m) must lie in this range [m/cycle]: it catches C given in
#: other units (mm/cycle, MPa sqrt(m)) by mistake.
RATE_AT_10MPA_RANGE = (1e-13, 1e-5)
THRESHOLD_RANGE = (0.5e6, 30e6)  # [Pa sqrt(m)]
TOUGHNESS_RANGE = (5e6, 400e6)  # [Pa sqrt(m)]

#: Paris constants (C [m/cycle/(MPa sqrt(m))^m], m) of steel classes, Barsom & Rolfe
#: (1999, ch. 9): upper bounds of the scatter bands of many steels at R ~ 0.
STEEL_CLASSES: dict[str, tuple[float, float, str]] = {
    "martensitic": (1.36e-10, 2.25, "Barsom & Rolfe 1999, ch. 9 (martensitic steels)"),
    "ferrite-pearlite": (6.89e-12, 3.0, "Barsom & Rolfe 1999, ch. 9 (ferrite-pearlite "
                                        "steels)"),
    "austenitic": (5.60e-12, 3.25, "Barsom & Rolfe 1999, ch. 9 (austenitic stainless "
                                   "steels)"),
}


@dataclass(frozen=True)
class ParisLaw:
    """Paris law with threshold and fracture toughness (SI units).

    Parameters
    ----------
    c
        C [(m/cycle) / (Pa sqrt(m))^m].
    m
        Exponent m [-], in [1, 8].
    threshold
        dK_th [Pa sqrt(m)], in [0.5, 30] MPa sqrt(m).
    toughness
        K_IC [Pa sqrt(m)], in [5, 400] MPa sqrt(m), above the threshold.
    name
        Label.
    source
        Where the constants come from.

    Raises
    ------
    InputError
        A constant outside its range (one line naming it), or C such that da/dN at
        10 MPa sqrt(m) is outside [1e-13, 1e-5] m/cycle (C in other units).
    """

    c: float
    m: float
    threshold: float
    toughness: float
    name: str = "custom"
    source: str = ""

    def __post_init__(self) -> None:
        require(math.isfinite(self.m) and EXPONENT_RANGE[0] <= self.m <= EXPONENT_RANGE[1],
                f"{self.name}.m", self.m,
                f"must be in [{EXPONENT_RANGE[0]:g}, {EXPONENT_RANGE[1]:g}]")
        require(math.isfinite(self.c) and self.c > 0.0, f"{self.name}.c", self.c,
                "must be > 0 (m/cycle)/(Pa sqrt(m))^m")
        rate = self.c * (10.0 * MPA_SQRT_M) ** self.m
        lo, hi = RATE_AT_10MPA_RANGE
        require(lo <= rate <= hi, f"{self.name}.c", self.c,
                f"gives da/dN = {rate:.3g} m/cycle at dK = 10 MPa sqrt(m), outside "
                f"[{lo:g}, {hi:g}]: C must be in SI units (m/cycle)/(Pa sqrt(m))^m")
        lo, hi = THRESHOLD_RANGE
        require(math.isfinite(self.threshold) and lo <= self.threshold <= hi,
                f"{self.name}.threshold", self.threshold,
                f"must be in [{lo:g}, {hi:g}] Pa sqrt(m)")
        lo, hi = TOUGHNESS_RANGE
        require(math.isfinite(self.toughness) and lo <= self.toughness <= hi,
                f"{self.name}.toughness", self.toughness,
                f"must be in [{lo:g}, {hi:g}] Pa sqrt(m)")
        require(self.toughness > self.threshold, f"{self.name}.toughness", self.toughness,
                f"must exceed the threshold {self.threshold:g} Pa sqrt(m)")

    @classmethod
    def from_mpa(cls, c_mpa: float, m: float, threshold_mpa: float, toughness_mpa: float,
                 name: str = "custom", source: str = "") -> ParisLaw:
        """Build from constants in the usual units (m/cycle and MPa sqrt(m)).

        Parameters
        ----------
        c_mpa
            C [(m/cycle) / (MPa sqrt(m))^m].
        m
            Exponent [-].
        threshold_mpa
            dK_th [MPa sqrt(m)].
        toughness_mpa
            K_IC [MPa sqrt(m)].
        name, source
            Label and provenance.

        Returns
        -------
        ParisLaw
            With C_SI = C_MPa (1e6)^(-m).
        """
        require(math.isfinite(m) and EXPONENT_RANGE[0] <= m <= EXPONENT_RANGE[1],
                f"{name}.m", m, f"must be in [{EXPONENT_RANGE[0]:g}, {EXPONENT_RANGE[1]:g}]")
        return cls(c=c_mpa * MPA_SQRT_M ** (-m), m=m, threshold=threshold_mpa * MPA_SQRT_M,
                   toughness=toughness_mpa * MPA_SQRT_M, name=name, source=source)

    def rate(self, delta_k: float) -> float:
        """Growth per cycle da/dN [m/cycle] at the range ``delta_k`` [Pa sqrt(m)].

        Parameters
        ----------
        delta_k
            dK [Pa sqrt(m)].

        Returns
        -------
        float
            C dK^m, or 0 below the threshold.
        """
        if not delta_k >= self.threshold:
            return 0.0
        return self.c * delta_k**self.m


def steel_class_law(steel_class: str, *, threshold: float, toughness: float) -> ParisLaw:
    """Paris law of a steel class (Barsom & Rolfe C, m) with a given threshold and K_IC.

    Parameters
    ----------
    steel_class
        A key of :data:`STEEL_CLASSES`: ``"martensitic"`` (quenched and tempered and
        carburised gear steels), ``"ferrite-pearlite"`` or ``"austenitic"``.
    threshold
        dK_th [Pa sqrt(m)].
    toughness
        K_IC [Pa sqrt(m)].

    Returns
    -------
    ParisLaw

    Raises
    ------
    InputError
        Unknown class or constants out of range.

    Examples
    --------
    >>> law = steel_class_law("martensitic", threshold=5e6, toughness=80e6)
    >>> f"{law.rate(10e6):.3e}"
    '2.418e-08'
    """
    require(steel_class in STEEL_CLASSES, "steel_class", steel_class,
            f"must be one of {', '.join(STEEL_CLASSES)}")
    c, m, src = STEEL_CLASSES[steel_class]
    return ParisLaw.from_mpa(c, m, threshold / MPA_SQRT_M, toughness / MPA_SQRT_M,
                             name=steel_class, source=src)


@dataclass(frozen=True)
class LifeResult:
    """Crack growth life from a_0.

    Parameters
    ----------
    a
        Crack lengths, increasing from a_0 to ``a_end`` [m].
    cycles
        Load cycles to reach each length, from 0 [cycles].
    status
        ``"fracture"`` (K_max reached K_IC at a_end), ``"arrest"`` (dK fell to the
        threshold at a_end), ``"length limit"`` (a_end is the caller's limit) or
        ``"no growth"`` (dK(a_0) below the threshold: ``cycles_end`` is inf).
    a_end
        Crack length at the end [m].
    cycles_end
        Cycles to ``a_end`` [cycles] (inf for ``"no growth"`` and ``"arrest"``: the
        crack never gets further).
    """

    a: np.ndarray
    cycles: np.ndarray
    status: str
    a_end: float
    cycles_end: float


def _checked(fn: Callable[[float], float], a: float, name: str) -> float:
    v = float(fn(a))
    if not math.isfinite(v) or v < 0.0:
        raise InputError(name, v, f"must be finite and >= 0 Pa sqrt(m) (at a = {a:.6g} m)")
    return v


def paris_life(law: ParisLaw, delta_k: Callable[[float], float], a0: float,
               a_limit: float, *, k_max: Callable[[float], float] | None = None,
               points: int = 50, scan: int = 400, rtol: float = 1e-11) -> LifeResult:
    """Integrate the Paris law from a_0 to the end of life.

    Parameters
    ----------
    law
        Paris law with threshold and toughness.
    delta_k
        dK(a), the stress intensity range over a load cycle at crack length a
        [m -> Pa sqrt(m)].
    a0
        Initial crack length [m] (> 0).
    a_limit
        Largest length the caller's K(a) is valid for (tooth lost, rim reached) [m].
    k_max
        K_max(a) [m -> Pa sqrt(m)] compared with K_IC; default ``delta_k`` (load ratio
        R = 0, the usual for a gear tooth loaded once per revolution).
    points
        Number of output lengths (>= 2).
    scan
        Number of lengths at which dK and K_max are sampled to find the end of life
        (the first crossing is then solved by Brent's method): an excursion narrower
        than (a_limit - a_0) / scan can be missed.
    rtol
        Relative tolerance of the quadrature and the end-of-life root.

    Returns
    -------
    LifeResult

    Raises
    ------
    InputError
        a_0 <= 0, a_limit <= a_0, or dK / K_max not finite and >= 0.
    """
    require(math.isfinite(a0) and a0 > 0.0, "a0", a0, "must be > 0 m")
    require(math.isfinite(a_limit) and a_limit > a0, "a_limit", a_limit,
            f"must be > a0 = {a0:.6g} m")
    require(isinstance(points, int) and points >= 2, "points", points, "must be an int >= 2")
    require(isinstance(scan, int) and scan >= 2, "scan", scan, "must be an int >= 2")
    kmax = delta_k if k_max is None else k_max
    kname = "delta_k" if k_max is None else "k_max"
    one = np.array([a0])
    if _checked(kmax, a0, kname) >= law.toughness:
        return LifeResult(a=one, cycles=np.zeros(1), status="fracture", a_end=a0,
                          cycles_end=0.0)
    if _checked(delta_k, a0, "delta_k") < law.threshold:
        return LifeResult(a=one, cycles=np.zeros(1), status="no growth", a_end=a0,
                          cycles_end=math.inf)
    # end of life: first crossing of K_max = K_IC or dK = dK_th
    grid = np.linspace(a0, a_limit, scan + 1)
    status, a_end = "length limit", a_limit
    prev = a0
    for a in grid[1:]:
        if _checked(kmax, a, kname) >= law.toughness:
            status = "fracture"
            a_end = brentq(lambda x: kmax(x) - law.toughness, prev, a,
                           xtol=1e-15 * a_limit, rtol=4.0 * np.finfo(float).eps)
            break
        if _checked(delta_k, a, "delta_k") < law.threshold:
            status = "arrest"
            a_end = brentq(lambda x: delta_k(x) - law.threshold, prev, a,
                           xtol=1e-15 * a_limit, rtol=4.0 * np.finfo(float).eps)
            break
        prev = a
    a_out = np.linspace(a0, a_end, points)

    def inv_rate(a: float) -> float:
        return 1.0 / (law.c * max(float(delta_k(a)), law.threshold) ** law.m)

    steps = [quad(inv_rate, lo, hi, epsabs=0.0, epsrel=rtol, limit=200)[0]
             for lo, hi in zip(a_out[:-1], a_out[1:], strict=True)]
    cycles = np.concatenate([[0.0], np.cumsum(steps)])
    end = math.inf if status == "arrest" else float(cycles[-1])
    return LifeResult(a=a_out, cycles=cycles, status=status, a_end=float(a_end),
                      cycles_end=end)
