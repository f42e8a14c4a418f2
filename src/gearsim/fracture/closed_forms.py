"""Handbook stress intensity factors (closed forms) for checking the FE values.

Single edge crack, length a, in a strip of width b (Tada, Paris & Irwin, *The Stress
Analysis of Cracks Handbook*, 3rd ed., ASME 2000, pp. 52-53, after Gross & Srawley
and Tada 1973), K_I = sigma sqrt(pi a) F(a/b), with alpha = a / b and
beta = pi alpha / 2:

* uniform tension sigma (ends free to rotate, long strip):
  F = sqrt(tan(beta) / beta) [0.752 + 2.02 alpha + 0.37 (1 - sin beta)^3] / cos(beta),
  "better than 0.5 % for any a/b";
* pure bending, sigma = 6 M / b^2 (per unit thickness), polynomial fit for
  a/b <= 0.6 (Gross & Srawley, quoted by Tada):
  F = 1.122 - 1.40 alpha + 7.33 alpha^2 - 13.08 alpha^3 + 14.0 alpha^4 (0.2 %);
* the polynomial fit of the tension case (a/b <= 0.6, 0.5 %):
  F = 1.12 - 0.231 alpha + 10.55 alpha^2 - 21.72 alpha^3 + 30.39 alpha^4.

The trigonometric bending formula of the handbook is not implemented: the form recalled
for it, sqrt(tan(beta) / beta) [0.923 + 0.199 (1 - sin beta)^4] / cos(beta), is 1.7 %
below the polynomial fit at a/b = 0.2 and 0.4 while the converged FE value is within
0.3 % of the polynomial; it was not checked against the printed page (docs/fracture.md).

Centre crack of half length a in an infinite plate under remote uniaxial tension
sigma, the crack inclined at beta to the plane normal to the load (Anderson 2005,
eq. 2.53 / sec. 2.7; the stresses on the crack plane are sigma cos^2(beta) and
sigma sin(beta) cos(beta), each acting on a Griffith crack):
K_I = sigma sqrt(pi a) cos^2(beta), K_II = sigma sqrt(pi a) sin(beta) cos(beta).

All in SI: sigma [Pa], a, b [m], K [Pa sqrt(m)].

References
----------
.. [Tada2000] H. Tada, P. C. Paris, G. R. Irwin, The Stress Analysis of Cracks
   Handbook, 3rd ed., ASME Press 2000, sec. 2 (edge crack in a strip).
.. [Anderson2005] T. L. Anderson, Fracture Mechanics, 3rd ed., CRC 2005, Table 2.4
   (SENT geometry factor) and sec. 2.7 (mixed mode, inclined crack).
"""

from __future__ import annotations

import math

from gearsim.errors import require

__all__ = ["edge_crack_bending_polynomial", "edge_crack_tension",
           "edge_crack_tension_polynomial", "inclined_centre_crack"]


def _ratio(a: float, b: float, limit: float = 1.0) -> float:
    require(math.isfinite(b) and b > 0.0, "b", b, "must be > 0 m")
    require(math.isfinite(a) and 0.0 < a < limit * b, "a", a,
            f"must be in (0, {limit:g} b = {limit * b:.4g} m)")
    return a / b


def edge_crack_tension(a: float, b: float, stress: float) -> float:
    """K_I of a single edge crack in a strip under uniform tension (Tada 2000).

    Parameters
    ----------
    a
        Crack length [m].
    b
        Strip width [m].
    stress
        Remote tension sigma [Pa].

    Returns
    -------
    float
        K_I = sigma sqrt(pi a) F(a/b) [Pa sqrt(m)], F within 0.5 % for any a/b.

    Examples
    --------
    Short crack: F -> 1.122 (the edge-crack factor).

    >>> round(edge_crack_tension(1e-6, 1.0, 1.0) / math.sqrt(math.pi * 1e-6), 3)
    1.122
    """
    al = _ratio(a, b)
    be = 0.5 * math.pi * al
    f = (math.sqrt(math.tan(be) / be) * (0.752 + 2.02 * al + 0.37 * (1.0 - math.sin(be))**3)
         / math.cos(be))
    return stress * math.sqrt(math.pi * a) * f


def edge_crack_tension_polynomial(a: float, b: float, stress: float) -> float:
    """K_I of the edge crack in tension, polynomial fit (Tada 2000; a/b <= 0.6).

    Parameters
    ----------
    a
        Crack length [m].
    b
        Strip width [m] (a / b <= 0.6).
    stress
        Remote tension [Pa].

    Returns
    -------
    float
        K_I [Pa sqrt(m)], F = 1.12 - 0.231 al + 10.55 al^2 - 21.72 al^3 + 30.39 al^4,
        within 0.5 %.
    """
    al = _ratio(a, b, 0.6 + 1e-12)
    f = 1.12 - 0.231 * al + 10.55 * al**2 - 21.72 * al**3 + 30.39 * al**4
    return stress * math.sqrt(math.pi * a) * f


def edge_crack_bending_polynomial(a: float, b: float, stress: float) -> float:
    """K_I of the edge crack in pure bending, polynomial fit (Tada 2000; a/b <= 0.6).

    Parameters
    ----------
    a
        Crack length [m].
    b
        Strip width [m] (a / b <= 0.6).
    stress
        Outer-fibre bending stress 6 M / b^2 [Pa].

    Returns
    -------
    float
        K_I [Pa sqrt(m)], F = 1.122 - 1.40 al + 7.33 al^2 - 13.08 al^3 + 14.0 al^4,
        within 0.2 %.

    Examples
    --------
    >>> round(edge_crack_bending_polynomial(1e-6, 1.0, 1.0) / math.sqrt(math.pi * 1e-6), 3)
    1.122
    """
    al = _ratio(a, b, 0.6 + 1e-12)
    f = 1.122 - 1.40 * al + 7.33 * al**2 - 13.08 * al**3 + 14.0 * al**4
    return stress * math.sqrt(math.pi * a) * f


def inclined_centre_crack(a: float, beta: float, stress: float) -> tuple[float, float]:
    """K_I, K_II of an inclined centre crack in an infinite plate under tension.

    Parameters
    ----------
    a
        Crack half length [m].
    beta
        Angle between the crack line and the plane normal to the load [rad]
        (0: pure mode I).
    stress
        Remote uniaxial tension sigma [Pa].

    Returns
    -------
    tuple of float
        (K_I, K_II) = sigma sqrt(pi a) (cos^2 beta, sin beta cos beta) [Pa sqrt(m)],
        at either tip in its own frame (x1 pointing out of the crack).

    Examples
    --------
    >>> k1, k2 = inclined_centre_crack(1.0 / math.pi, math.pi / 4, 1.0)
    >>> round(k1, 12), round(k2, 12)
    (0.5, 0.5)
    """
    require(math.isfinite(a) and a > 0.0, "a", a, "must be > 0 m")
    require(math.isfinite(beta) and abs(beta) <= 0.5 * math.pi, "beta", beta,
            "must be in [-pi/2, pi/2] rad")
    require(math.isfinite(stress), "stress", stress, "must be finite Pa")
    k0 = stress * math.sqrt(math.pi * a)
    return k0 * math.cos(beta)**2, k0 * math.sin(beta) * math.cos(beta)
