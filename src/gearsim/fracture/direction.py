"""Crack growth direction: maximum tangential stress criterion (Erdogan & Sih 1963).

The crack extends radially from the tip in the direction theta_c (tip frame: x1 along
the crack, theta from x1 towards x2) where the near-tip hoop stress
sigma_tt = (2 pi r)^(-1/2) cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)]
is largest, i.e. where d sigma_tt / d theta = 0:

    K_I sin(theta_c) + K_II (3 cos(theta_c) - 1) = 0,

    theta_c = 2 arctan[ (K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II) ]
            = -2 arctan[ 2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2)) ],

(the second form has no cancellation for K_I >= 0, the first none for K_I < 0),
so theta_c = 0 in pure mode I and -arccos(1/3) = -70.53 deg in pure mode II with
K_II > 0. The equivalent mode-I stress intensity is the hoop stress factor in that
direction:

    K_eq = cos(theta_c / 2) [K_I cos^2(theta_c / 2) - 3/2 K_II sin(theta_c)],

K_eq = K_I in pure mode I and 2 / sqrt(3) |K_II| = 1.155 |K_II| in pure mode II.

References
----------
.. [Erdogan1963] F. Erdogan, G. C. Sih, On the crack extension in plates under plane
   loading and transverse shear, J. Basic Eng. 85 (1963) 519-525.
.. [Anderson2005] T. L. Anderson, Fracture Mechanics, 3rd ed., CRC 2005, sec. 2.11.
"""

from __future__ import annotations

import math

import numpy as np

from gearsim.errors import require

__all__ = ["equivalent_k", "hoop_stress_factor", "kink_angle", "kinked_direction"]


def _finite(name: str, v: float) -> float:
    require(math.isfinite(v), name, v, "must be finite Pa sqrt(m)")
    return float(v)


def kink_angle(k1: float, k2: float) -> float:
    """Kink angle of the maximum tangential stress criterion.

    Parameters
    ----------
    k1, k2
        K_I and K_II [Pa sqrt(m)].

    Returns
    -------
    float
        theta_c [rad], measured in the tip frame from the crack direction towards +x2,
        of sign opposite to K_II; within +-arccos(1/3) = +-70.53 deg when K_I >= 0, up
        to +-180 deg when K_I < 0 (a compressed crack, where the criterion has little
        meaning); 0 when K_II = 0.

    Raises
    ------
    InputError
        Non-finite input.

    Examples
    --------
    >>> round(math.degrees(kink_angle(0.0, 1.0)), 2)
    -70.53
    >>> kink_angle(1.0, 0.0)
    0.0
    """
    k1, k2 = _finite("k1", k1), _finite("k2", k2)
    if k2 == 0.0:
        return 0.0
    root = math.hypot(k1, math.sqrt(8.0) * k2)
    if k1 >= 0.0:  # no cancellation in k1 + root
        return -2.0 * math.atan(2.0 * k2 / (k1 + root))
    return 2.0 * math.atan((k1 - root) / (4.0 * k2))


def hoop_stress_factor(k1: float, k2: float, theta: float) -> float:
    """sqrt(2 pi r) sigma_tt of the near-tip field at angle ``theta``.

    Parameters
    ----------
    k1, k2
        K_I and K_II [Pa sqrt(m)].
    theta
        Angle in the tip frame [rad].

    Returns
    -------
    float
        cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)] [Pa sqrt(m)]
        (Erdogan & Sih 1963).
    """
    c = math.cos(0.5 * theta)
    return c * (k1 * c * c - 1.5 * k2 * math.sin(theta))


def equivalent_k(k1: float, k2: float) -> float:
    """Equivalent mode-I stress intensity of the MTS criterion.

    Parameters
    ----------
    k1, k2
        K_I and K_II [Pa sqrt(m)].

    Returns
    -------
    float
        K_eq = hoop stress factor at the kink angle [Pa sqrt(m)]; K_I in pure mode I,
        2 |K_II| / sqrt(3) in pure mode II.

    Examples
    --------
    >>> round(equivalent_k(0.0, 1.0), 4)
    1.1547
    """
    th = kink_angle(k1, k2)
    return hoop_stress_factor(k1, k2, th)


def kinked_direction(direction, k1: float, k2: float) -> np.ndarray:
    """Unit direction of the next crack increment, the current one turned by theta_c.

    Parameters
    ----------
    direction
        Current crack direction at the tip (2,), the tip frame's x1 axis.
    k1, k2
        K_I and K_II [Pa sqrt(m)].

    Returns
    -------
    ndarray, shape (2,)
        (cos, sin) of the crack angle plus theta_c, in the global frame [-]: x1 rotated
        towards x2 = x1 rotated by +90 deg.
    """
    d = np.asarray(direction, dtype=float)
    n = float(np.hypot(*d))
    require(math.isfinite(n) and n > 0.0, "direction", tuple(d), "must be non-zero")
    th = kink_angle(k1, k2)
    c, s = math.cos(th), math.sin(th)
    d = d / n
    return np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
