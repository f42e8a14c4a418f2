"""Archard wear of a gear flank along the path of contact (single-point observation).

Archard's law says the worn volume is proportional to the normal load times the sliding
distance, V = k F s, k the dimensional wear coefficient [m^2/N]. Written for a point of a
surface it gives the wear depth increment dh = k p ds, p the local contact pressure.
Flodin & Andersson (1997) apply it to a point of a spur-gear flank that passes once
through the Hertzian contact band per mesh cycle of its tooth ("single-point
observation"):

    h_i = k p0(l) s_i(l)                                                     (1)

with, at the position l of the contact on the transverse line of action (from the
driver's base tangent point T1, T1T2 the length of that line):

* the Hertz line contact of two cylinders (Johnson 1985, section 4.2, eqs. 4.43-4.45):
  w the load per unit length of contact line, 1/R' = 1/rho1 + 1/rho2 the relative
  curvature, 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 the plane-strain contact modulus,

      b = sqrt(4 w R' / (pi E*)),    p0 = 2 w / (pi b) = sqrt(w E* / (pi R'))       (2)

  b the semi-width of the contact band, p0 the maximum pressure;
* the radii of curvature of the flanks, the roll lengths rho1 = l and rho2 = T1T2 - l in
  the transverse plane, rho_i / cos(beta_b) in the normal plane of a helical gear
  (ISO 6336-2), which is the section the Hertz contact lives in;
* the rolling (surface) speeds of the two flanks relative to the contact point,
  u1 = omega1 rho1 and u2 = omega2 rho2 with omega2 / omega1 = z1 / z2;
* the sliding distance of the observed point of gear i while it crosses the band of
  width 2b at its own speed u_i, during which the other surface slides past it at the
  relative speed |u1 - u2|:

      s_i = 2 b |u1 - u2| / u_i                                               (3)

  Only the speed ratio enters, so the result does not depend on the running speed. At
  the pitch point u1 = u2 (pure rolling) and s_i = 0: no wear.

Two consequences worth knowing (both follow from (1)-(3)):

* p0 times 2b is 4 w / pi, so h_i = (4/pi) k w |u1 - u2| / u_i: the depth does not depend
  on the radii of curvature nor on the elastic moduli, only on the load per unit length,
  the slide-to-roll ratio and k. Integrating the elliptical Hertz pressure across the
  band instead of using its maximum gives k w |u1 - u2| / u_i, a factor pi/4 smaller;
  Flodin & Andersson's form (the maximum pressure) is kept here.
* The law is linear in the number of cycles N: depth = N h_i. The pressure is not
  updated as the profile wears. Flodin & Andersson update the geometry, the load sharing
  and the pressure stepwise (wear is computed in steps of many cycles, the worn profile
  feeds the next step), which lowers the pressure where the profile has worn and spreads
  the wear; the linear law here is the first step of that scheme and overestimates the
  depth where the wear concentrates (near the start of contact on the driver's root).

References
----------
.. [Archard1953] J. F. Archard, Contact and rubbing of flat surfaces, J. Appl. Phys. 24
   (1953) 981-988.
.. [Flodin1997] A. Flodin, S. Andersson, Simulation of mild wear in spur gears, Wear 207
   (1997) 16-23.
.. [Johnson1985] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985,
   chapter 4 (two-dimensional contact of cylinders).
.. [ISO6336-2] ISO 6336-2:2019, Calculation of load capacity of spur and helical gears -
   Part 2: Surface durability (pitting) (normal radius of relative curvature).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from gearsim.errors import InputError, require

__all__ = ["archard_wear", "hertz_line_contact"]


def _finite(v: object) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def hertz_line_contact(load_per_length: np.ndarray, radius: np.ndarray,
                       contact_modulus: float) -> tuple[np.ndarray, np.ndarray]:
    """Semi-width and maximum pressure of a Hertzian line contact (two cylinders).

    b = sqrt(4 w R' / (pi E*)) and p0 = 2 w / (pi b) = sqrt(w E* / (pi R')) (Johnson 1985,
    eqs. 4.43 and 4.45); w = 0 gives b = p0 = 0.

    Parameters
    ----------
    load_per_length : array_like
        Normal load per unit length of the contact line w >= 0 [N/m].
    radius : array_like
        Effective radius R' > 0, 1/R' = 1/R1 + 1/R2 [m].
    contact_modulus : float
        Plane-strain contact modulus E* > 0, 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [Pa].

    Returns
    -------
    b, p0 : ndarray
        Semi-width of the contact band [m] and maximum pressure [Pa], broadcast shape.

    Raises
    ------
    InputError
        If a load is negative or not finite, a radius is not finite and > 0, or E* is
        not finite and > 0.

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, section 4.2.

    Examples
    --------
    Steel on steel (E* = 206 GPa / (2 x 0.91) = 113.19 GPa), w = 100 N/mm, R' = 7.5 mm:
    b = sqrt(4 x 1e5 x 7.5e-3 / (pi x 113.19e9)) = 91.85 um and
    p0 = 2e5 / (pi x 91.85e-6) = 693.1 MPa.

    >>> b, p0 = hertz_line_contact(1e5, 7.5e-3, 206e9 / (2 * 0.91))
    >>> round(float(b) * 1e6, 2), round(float(p0) / 1e6, 1)
    (91.85, 693.1)
    """
    w = np.asarray(load_per_length, dtype=float)
    r = np.asarray(radius, dtype=float)
    require(bool(np.all(np.isfinite(w)) and np.all(w >= 0)), "load_per_length",
            _shown(w), "must be finite numbers >= 0 N/m")
    require(bool(np.all(np.isfinite(r)) and np.all(r > 0)), "radius", _shown(r),
            "must be finite numbers > 0 m")
    require(_finite(contact_modulus) and contact_modulus > 0, "contact_modulus",
            contact_modulus, "must be a finite number > 0 Pa")
    b = np.sqrt(4.0 * w * r / (math.pi * contact_modulus))
    p0 = np.sqrt(w * contact_modulus / (math.pi * r))
    return b, p0


def _shown(a: np.ndarray) -> object:
    """The first offending-looking value of an array for a message (or the scalar)."""
    if a.ndim == 0:
        return float(a)
    bad = ~np.isfinite(a) | (a < 0)
    return float(a[bad][0]) if bad.any() else float(a.flat[0])


def archard_wear(pair, gear: int, l: np.ndarray, load_per_width: np.ndarray, *,
                 coefficient: float, cycles: float) -> np.ndarray:
    """Archard wear depth of a flank at positions of the path of contact.

    Single-point observation of Flodin & Andersson (1997): per passage of the observed
    point through the contact band, h_i = k p0 s_i, and after N cycles
    depth = N k p0 s_i (linear: the pressure is not updated as the profile wears), with

    * p0 = 2 w / (pi b), b = sqrt(4 w R' / (pi E*)) the Hertz maximum pressure [Pa] and
      semi-width [m] of the line contact (Johnson 1985, ch. 4), w = ``load_per_width``,
      1/R' = cos(beta_b) (1/rho1 + 1/rho2), rho1 = l, rho2 = T1T2 - l the transverse
      radii of curvature (beta_b = 0 for spur gears), 1/E* = (1 - nu1^2)/E1 +
      (1 - nu2^2)/E2;
    * s_i = 2 b |u1 - u2| / u_i [m] the sliding distance of the observed point of gear i
      during one passage, u1 = omega1 rho1, u2 = omega2 rho2 the rolling speeds,
      omega2 / omega1 = z1 / z2 (speed-independent: only the ratio enters).

    Since p0 2b = 4 w / pi, depth = N (4/pi) k w |u1 - u2| / u_i: independent of the
    moduli and of the curvature; zero at the pitch point (u1 = u2) and where w = 0. See
    the module docstring for the simplifications.

    Parameters
    ----------
    pair : GearPair
        The gear pair (:class:`~gearsim.geometry.pair.GearPair`).
    gear : {1, 2}
        The observed (worn) gear: 1 the driver, 2 the driven gear.
    l : array_like
        Contact positions on the transverse line of action, from T1 [m]; inside
        (0, T1T2), and inside the path of contact [start_of_contact, end_of_contact]
        wherever the load is > 0.
    load_per_width : array_like
        Transverse load per unit face width at ``l`` [N/m], >= 0, broadcastable with
        ``l``. For a helical pair this equals the normal load per unit length of contact
        line (both differ from the transverse value by the same factor 1/cos(beta_b)).
    coefficient : float
        Dimensional wear coefficient k > 0 [m^2/N].
    cycles : float
        Number N >= 0 of load cycles of the observed tooth (one passage of each point per
        cycle).

    Returns
    -------
    ndarray
        Wear depth normal to the flank of gear ``gear`` at ``l`` [m], broadcast shape of
        ``l`` and ``load_per_width``.

    Raises
    ------
    InputError
        If ``gear`` is not 1 or 2, ``l`` and ``load_per_width`` do not broadcast, a
        position is outside (0, T1T2) or is loaded outside the path of contact, a load is
        negative or not finite, k is not finite and > 0 or N not finite and >= 0.

    References
    ----------
    A. Flodin, S. Andersson, Simulation of mild wear in spur gears, Wear 207 (1997)
    16-23; J. F. Archard, J. Appl. Phys. 24 (1953) 981-988; K. L. Johnson, Contact
    Mechanics (1985), ch. 4; ISO 6336-2:2019 (normal radius of relative curvature).

    Examples
    --------
    Spur pair z 20/40, m 4 mm, 20 deg: T1T2 = a sin(20 deg) = 120 mm x 0.342020 =
    41.0424 mm. At l = 10 mm, rho1 = 10 mm, rho2 = 31.0424 mm; with omega1 = 1,
    u1 = 10 mm/s, u2 = 31.0424 x 20/40 = 15.5212 mm/s, |u1 - u2| / u1 = 0.55212.
    w = 100 N/mm, k = 1e-16 m^2/N, N = 1e6 cycles:
    depth of the driver = 1e6 x (4/pi) x 1e-16 x 1e5 x 0.55212 = 7.0298e-6 m.

    >>> from gearsim.geometry.gear import Gear
    >>> from gearsim.geometry.pair import GearPair
    >>> pair = GearPair(Gear(teeth=20, normal_module=4e-3), Gear(teeth=40, normal_module=4e-3))
    >>> h = archard_wear(pair, 1, 10e-3, 1e5, coefficient=1e-16, cycles=1e6)
    >>> round(float(h) * 1e6, 4)
    7.0298
    """
    require(isinstance(gear, numbers.Integral) and not isinstance(gear, bool) and gear in (1, 2),
            "gear", gear, "must be 1 (driver) or 2 (driven)")
    require(_finite(coefficient) and coefficient > 0, "coefficient", coefficient,
            "must be a finite number > 0 m^2/N")
    require(_finite(cycles) and cycles >= 0, "cycles", cycles, "must be a finite number >= 0")
    try:
        pos, w = np.broadcast_arrays(np.asarray(l, dtype=float),
                                     np.asarray(load_per_width, dtype=float))
    except ValueError:
        raise InputError("load_per_width", f"shape {np.shape(load_per_width)}",
                         f"must broadcast with l of shape {np.shape(l)}") from None
    length = pair.line_length
    inside = np.isfinite(pos) & (pos > 0) & (pos < length)
    require(bool(inside.all()), "l", float(pos[~inside][0]) if (~inside).any() else None,
            f"must be finite positions inside (0, T1T2 = {length:.6g} m) on the line of action")
    require(bool(np.all(np.isfinite(w)) and np.all(w >= 0)), "load_per_width", _shown(w),
            "must be finite numbers >= 0 N/m")
    tol = 1e-9 * length
    off = (w > 0) & ((pos < pair.start_of_contact - tol) | (pos > pair.end_of_contact + tol))
    require(not off.any(), "l", float(pos[off][0]) if off.any() else None,
            f"is loaded outside the path of contact [{pair.start_of_contact:.6g}, "
            f"{pair.end_of_contact:.6g}] m (positions are measured from T1 on the line of action)")

    g1, g2 = pair.driver, pair.driven
    m1, m2 = g1.material, g2.material
    e_star = 1.0 / ((1 - m1.poisson_ratio**2) / m1.youngs_modulus
                    + (1 - m2.poisson_ratio**2) / m2.youngs_modulus)
    rho1 = pos
    rho2 = length - pos
    cos_bb = math.cos(g1.base_helix_angle)
    r_eff = rho1 * rho2 / (rho1 + rho2) / cos_bb     # normal-plane relative radius
    b, p0 = hertz_line_contact(w, r_eff, e_star)
    u1 = rho1                                        # omega1 = 1
    u2 = rho2 * (g1.teeth / g2.teeth)                # omega2 = z1 / z2
    ui = u1 if gear == 1 else u2
    slide = 2.0 * b * np.abs(u1 - u2) / ui
    return cycles * coefficient * p0 * slide
