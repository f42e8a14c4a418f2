"""The generated transverse tooth outline: involute flank and trochoidal root fillet.

Generation by a basic rack (Litvin & Fuentes 2004, ch. 10): the rack's tip round, a
circle of radius ``rho = rho_f* m_n`` in the normal section, appears in the transverse
plane of a helical gear as an ellipse (semi-axes ``rho / cos(beta)`` across and ``rho``
in depth). A point of the round generates the gear where its normal passes through the
pitch point (the instantaneous centre of the rolling motion); the locus of such points
in the gear frame is the fillet. The rack's straight flank generates the involute.

Coordinates: tooth frame with the origin at the gear centre, ``y`` along the tooth
centre line, ``x`` across it (the outline is symmetric; the ``+x`` half is computed).

References
----------
.. [Litvin] F. L. Litvin, A. Fuentes, Gear Geometry and Applied Theory, 2nd ed., 2004.
.. [ISO6336-3] ISO 6336-3:2019, critical section at the 30 degree tangent of the fillet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from gearsim.errors import InputError
from gearsim.geometry import _kernels as K
from gearsim.geometry.gear import Gear

__all__ = ["OUTLINE_SNAP", "ToothProfile"]

#: Consecutive outline points closer than this fraction of the tip radius are one point
#: (round-off copies of the form point; the outline's own spacing is > 1e-4 of it).
OUTLINE_SNAP = 1e-12


@dataclass(frozen=True)
class ToothProfile:
    """Outline of one tooth of ``gear`` (see module docstring for the frame).

    Parameters
    ----------
    gear
        The gear (:class:`~gearsim.geometry.gear.Gear`).

    References
    ----------
    Litvin & Fuentes (2004), ch. 10 (rack generation); ISO 21771:2007 (involute).

    Examples
    --------
    The chordal thickness at the reference circle of a z 19, m 3.2 mm spur gear is
    2 r sin(s / (2 r)) with s = m pi / 2 = 5.0265 mm, r = 30.4 mm:

    >>> from gearsim.geometry.gear import Gear
    >>> prof = ToothProfile(Gear(teeth=19, normal_module=3.2e-3))
    >>> round(prof.thickness_at_radius(0.0304) * 1e3, 6)
    5.020824
    """

    gear: Gear

    @cached_property
    def packed(self) -> np.ndarray:
        """Profile parameters packed for the compiled kernels (layout ``P_*`` of
        :mod:`gearsim.geometry._kernels`) [SI units]."""
        g = self.gear
        m = g.normal_module
        an = g.normal_pressure_angle
        rho = g.fillet_radius_coefficient * m
        hfp = g.dedendum_coefficient * m
        p = K.empty_profile()
        p[K.P_R] = g.pitch_radius
        p[K.P_RB] = g.base_radius
        p[K.P_PSIB] = g.base_half_thickness_angle
        # rack space centre at u = 0; the straight flank of the rack tooth in the normal
        # section is u = p_n/4 + (x m - v) tan(a_n); the tip round of radius rho is tangent
        # to it and to the tip line v = x m - h_fP.
        p[K.P_UC] = (math.pi * m / 4.0 + (hfp - rho) * math.tan(an) + rho / math.cos(an)
)
        p[K.P_VC] = g.profile_shift * m - hfp + rho
        p[K.P_RHO] = rho
        p[K.P_CB] = math.cos(g.helix_angle)
        p[K.P_AN] = an
        p[K.P_RA] = g.tip_radius
        p[K.P_RROOT] = g.root_radius
        if rho == 0.0:  # sharp rack tip: the fillet degenerates to a point
            p[K.P_RHO] = 1e-9 * m
        xf, yf = K.fillet_point(an, p)
        p[K.P_RF] = math.hypot(xf, yf)
        xr, yr = K.fillet_point(0.5 * math.pi, p)
        p[K.P_YROOT] = yr
        p[K.P_THF] = math.atan2(xr, yr)
        return p

    @property
    def form_radius(self) -> float:
        """Radius where the fillet joins the involute (start of the active flank) [m]."""
        return float(self.packed[K.P_RF])

    @property
    def root_half_angle(self) -> float:
        """Half angle theta_f subtended by the tooth at the root circle [rad]."""
        return float(self.packed[K.P_THF])

    @property
    def root_height(self) -> float:
        """Height on the centre line of the fillet's end at the root circle [m]."""
        return float(self.packed[K.P_YROOT])

    def fillet_point(self, g: float) -> tuple[float, float]:
        """Point of the generated root fillet.

        Parameters
        ----------
        g
            Angle of the rack tip round's normal, in [alpha_n, pi/2] [rad]; pi/2 at the
            root circle, alpha_n at the form circle.

        Returns
        -------
        tuple of float
            (x, y) in the tooth frame [m].
        """
        return K.fillet_point(g, self.packed)

    def involute_point(self, radius: float) -> tuple[float, float]:
        """Point of the involute flank.

        Parameters
        ----------
        radius
            Radius in [r_b, r_a] [m].

        Returns
        -------
        tuple of float
            (x, y) = r (sin psi(r), cos psi(r)) in the tooth frame [m].

        Examples
        --------
        At the base circle psi_b = pi/(2 z) + inv(alpha_t); z 19, m 3.2 mm:
        r_b = 28.5667 mm, x = r_b sin(psi_b) = 2.7831 mm:

        >>> from gearsim.geometry.gear import Gear
        >>> g = Gear(teeth=19, normal_module=3.2e-3)
        >>> x, y = ToothProfile(g).involute_point(g.base_radius)
        >>> round(x * 1e3, 4), round(y * 1e3, 4)
        (2.7831, 28.4308)
        """
        return K.involute_point(radius, self.packed)

    def outline(self, n_fillet: int = 60, n_involute: int = 80) -> np.ndarray:
        """Half outline (``+x`` flank) from the root circle to the tip.

        Parameters
        ----------
        n_fillet
            Number of points on the fillet (uniform in the rack-round angle).
        n_involute
            Number of points on the involute (uniform in radius).

        Returns
        -------
        ndarray, shape (n_fillet + n_involute, 2)
            (x, y) points [m].
        """
        out = K.sample_outline(self.packed, n_fillet, n_involute,
                               np.empty((n_fillet + n_involute, 2)))
        # the fillet ends where the involute starts (the form point, sampled by both):
        # a copy that differs by round-off (1e-17 m measured) is made exact, so that the
        # outline has no edge of round-off length, whose direction is noise (a polygon
        # check then sees a crossing: the 23-tooth pinion of wind-turbine-grc)
        near = np.flatnonzero(np.hypot(*np.diff(out, axis=0).T)
                              <= OUTLINE_SNAP * float(np.hypot(*out[-1])))
        out[near + 1] = out[near]
        return out

    def half_width_at_height(self, y: float) -> float:
        """Half width of the tooth section at a height on the centre line.

        Parameters
        ----------
        y
            Height on the tooth centre line (from the gear centre) [m].

        Returns
        -------
        float
            Half width h(y) [m].

        Raises
        ------
        InputError
            If ``y`` is outside the tooth (below the fillet's root end or above the tip).
        """
        p = self.packed
        xr, yr = K.fillet_point(0.5 * math.pi, p)
        xf, yf = K.fillet_point(p[K.P_AN], p)
        xa, ya = K.involute_point(p[K.P_RA], p)
        if not (yr <= y <= ya):
            raise InputError("height", y, f"must be within the tooth, [{yr:.6g}, {ya:.6g}] m")
        if y <= yf:
            g = K.param_at_coordinate(0, 1, y, 0.5 * math.pi, p[K.P_AN], p)
            return K.fillet_point(g, p)[0]
        r = K.param_at_coordinate(1, 1, y, p[K.P_RF], p[K.P_RA], p)
        return K.involute_point(r, p)[0]

    def thickness_at_radius(self, radius: float) -> float:
        """Transverse chordal tooth thickness at a radius (fillet or involute).

        Parameters
        ----------
        radius
            Radius in [r_f, r_a] [m].

        Returns
        -------
        float
            Chordal thickness [m].

        Raises
        ------
        InputError
            If ``radius`` is outside [root radius, tip radius].
        """
        p = self.packed
        rr = self.gear.root_radius
        if not (rr <= radius <= self.gear.tip_radius * (1 + 1e-12)):
            raise InputError("radius", radius,
                             f"must be within [root {rr:.6g}, tip {self.gear.tip_radius:.6g}] m")
        if radius >= self.form_radius:
            x, y = K.involute_point(radius, p)
        else:
            x, y = K.fillet_point(self._fillet_param(radius), p)
        return 2.0 * x * radius / math.hypot(x, y)

    def tangent_point(self, angle_to_centre_line: float = math.radians(30.0)) -> tuple[float, float]:
        """Fillet point whose tangent makes a given angle with the tooth centre line.

        The default 30 degrees gives the critical section of ISO 6336-3 (method B); it is
        the default start point of a tooth-root crack.

        Parameters
        ----------
        angle_to_centre_line
            Angle between the fillet tangent and the tooth centre line [rad].

        Returns
        -------
        g : float
            Rack-round angle of the point [rad].
        radius : float
            Radius of the point [m].

        References
        ----------
        ISO 6336-3:2019, method B (30 degree tangent).
        """
        p = self.packed
        target = math.tan(angle_to_centre_line)
        lo, hi = p[K.P_AN], 0.5 * math.pi
        # slope |dx/dy| grows from the involute end (steep) towards the root (flat)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            dx, dy = K.profile_dy(0, mid, p)
            slope = abs(dx / dy) if dy != 0.0 else math.inf
            if slope < target:
                lo = mid
            else:
                hi = mid
        g = 0.5 * (lo + hi)
        x, y = K.fillet_point(g, p)
        return g, math.hypot(x, y)

    def fillet_param_at_radius(self, radius: float) -> float:
        """Rack-round angle of the fillet point at a radius.

        Parameters
        ----------
        radius
            Radius between the root and the form radius [m].

        Returns
        -------
        float
            Rack-round angle g in [alpha_n, pi/2] [rad].

        Raises
        ------
        InputError
            If ``radius`` is not on the fillet (reported as ``crack.start_radius``, the
            user input it comes from).
        """
        if not (self.gear.root_radius * (1 - 1e-12) <= radius <= self.form_radius * (1 + 1e-12)):
            raise InputError("crack.start_radius", radius,
                             f"must lie on the root fillet, between the root radius "
                             f"{self.gear.root_radius:.6g} m and the form radius "
                             f"{self.form_radius:.6g} m")
        return self._fillet_param(radius)

    def _fillet_param(self, radius: float) -> float:
        """Bisection on the fillet, whose radius grows monotonically from root to form."""
        p = self.packed
        lo, hi = p[K.P_AN], 0.5 * math.pi
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if math.hypot(*K.fillet_point(mid, p)) > radius:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)
