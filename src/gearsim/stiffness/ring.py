"""Potential-energy compliance of an internal (ring) gear tooth.

The ring tooth is treated as a cantilever clamped on the ring's root circle (Chen & Shao
2013; Liang, Zuo & Pandey 2014), with the bending, shear and axial energies of the
external tooth (Yang & Lin 1987; :mod:`gearsim.stiffness._kernels`) and, optionally, a
fillet-foundation term of the form of Sainsot, Velex & Duverger (2004).

Geometry (transverse plane)
---------------------------
The ring tooth is the space of an external gear. With the ring's profile shift x (positive
moves the flanks radially outwards, :mod:`gearsim.geometry.planetary`), the space width at
the reference radius r = z m_t / 2 is that of an external tooth, m_t (pi/2 + 2 x tan
alpha_n), so the ring's transverse tooth thickness there is

    s_r = m_t (pi/2 - 2 x tan alpha_n)        (= m (pi/2 - 2 x tan alpha) for spur)

and the half angular tooth thickness at radius rho >= r_b is

    beta(rho) = s_r / (2 r) - inv(alpha_t) + inv(alpha_rho),   cos(alpha_rho) = r_b / rho,

which grows outwards: the ring tooth is thicker at its root (outer) circle r_f than at its
tip (inner) circle r_a. In the tooth's axes (X across the tooth, Y along the radial centre
line, outwards, origin at the ring centre) the loaded flank is the involute

    X(rho) = rho sin beta(rho),  Y(rho) = rho cos beta(rho),  h(rho) = X(rho),

with d beta / d rho = tan(alpha_rho) / rho and so dY/drho = cos beta - sin beta tan alpha_rho
(> 0 on the whole flank). The section at height Y has the half width h; its width 2 h L
and second moment (2h)^3 L / 12 are those of the external tooth.

Root. A ring cut by a pinion-type cutter has a short trochoidal fillet between the
involute and the root circle. It is ignored: the involute is extended out to the root
circle r_f, where the tooth is clamped (Chen & Shao 2013 do the same). The fillet adds
material in the corners of the space, so leaving it out makes the tooth slightly more
compliant.

Load. The normal of the involute at rho is tangent to the base circle at polar angle
beta + alpha_rho, so its direction is +-(cos(alpha_rho + beta), -sin(alpha_rho + beta)). The
planet pushes the flank into the tooth (towards the centre line, -X) and so towards the
root: the unit force on the ring tooth is (-cos a1, sin a1) with

    a1 = alpha_rc + beta(r_c),

the angle between the force and the normal of the centre line. F_b = cos a1 bends the
tooth, F_a = sin a1 compresses it (it points to the root). The contact point is X_c = r_c
sin beta_c, Y_c = r_c cos beta_c; at a section at height Y (Y_c <= Y <= Y_root =
r_f cos beta(r_f)) the moment about the section centre is

    M(Y) = F_b (Y - Y_c) - F_a X_c        (the external tooth's form),

and, per unit force (Yang & Lin 1987; Chen & Shao 2013),

    1/k_b = int M^2 / (E I_Y) dY,   1/k_s = int 1.2 F_b^2 / (G A_Y) dY,
    1/k_a = int F_a^2 / (E A_Y) dY,   Y from Y_c to Y_root,

evaluated as integrals over rho in [r_c, r_f] with the Jacobian dY/drho and a
Gauss-Legendre rule of ``gauss_points`` nodes on each of ``PIECES`` equal pieces. E is
replaced by E / (1 - nu^2) in the beam terms in plane strain.

Foundation (``foundation="sainsot-solid"``). Sainsot et al.'s formula

    1/k_f = cos^2(a1) / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a1)]

with the ring's own root geometry: theta_f = beta(r_f), S_f = 2 r_f theta_f (the arc
thickness at the root circle, as the external kernel), and u_f the distance along the
centre line from the root circle to the point where the line of the contact force crosses
the centre line. In the external kernel the force (-cos a1, -sin a1) acts in axes whose y
points to the tip, so it crosses x = 0 at y_c - x_c tan a1 and
u_f = (y_c - x_c tan a1) - y_root. On the ring the force (-cos a1, +sin a1) crosses X = 0
at Y_c + X_c tan a1 (again shifted towards the root) and Y points to the root, so

    u_f = Y_root - (Y_c + X_c tan a1).

Like the external kernel's, u_f is not clipped: it turns negative for contacts within
about X_c tan a1 of the root circle (ring z 78, m 2 mm: above 79.49 mm, r_f = 80.5 mm;
the 30/24/78 stage with ring addendum 0.8 m loads the ring up to 79.74 mm, u_f = -0.32
mm there), where the fitted quadratic is used as it stands (its L* and M* terms are then
below 1 % of the P* term). The coefficients L*, M*, P*, Q* are evaluated at theta_f
and h_f = :data:`RING_H_F` = 7.0, the upper end of Sainsot's fitted range, standing for a
body much larger than the tooth. This is a documented approximation, not Sainsot's own
use: the fit is for external gears on a bore (h_f = r_f / r_int), while a ring's body (its
rim) lies outside the teeth. ``foundation="none"``, the default, gives a zero fourth
column: against the FE ring segment of :mod:`gearsim.fem.ring` (rim 3.5 m_n clamped
outside) the clamped cantilever misses 3-10e-12 m/N per metre of width (rim and fillet),
while the Sainsot-form term adds 8 to 19 times that (docs/planetary.md section 4.3).

Crack (``crack_depth`` q, ``crack_angle`` gamma; Tian 2004 for external teeth, Chen &
Shao 2013 for the ring). A root crack on the loaded flank, the tension side of the ring
tooth under the planet's load, starts at the flank's point on the root circle,
P_0 = (X_0, Y_0) = (r_f sin theta_f, r_f cos theta_f), and runs straight into the tooth
towards its centre line and its tip, at gamma to the centre line, to the tip
P_1 = (X_0 - q sin gamma, Y_0 - q cos gamma); it must end before the centre line
(q sin gamma < X_0). The loaded side of a section at height Y then ends at the crack,
h_c(Y) = X_0 - (Y_0 - Y) tan gamma, for Y_1 <= Y <= Y_0, and tipwards of the crack at
the limiting line X = X_1 (the material beside the crack's shadow carries no bending
stress), h_c = min(h(Y), X_1); the section is h(Y) + h_c(Y) thick, with

    I_Y = (h + h_c)^3 L / 12,   A_Y = (h + h_c) L,

in the bending, shear and axial energies, and the same moment M(Y) (the shift of the
neutral axis is neglected, as in Tian's model). The foundation term is unchanged.

References
----------
.. [Tian2004] X. Tian, Dynamic simulation for system response of gearbox including
   localized gear faults, M.Sc. thesis, University of Alberta, 2004 (cracked-section
   model, limiting line).
.. [ChenShao2013b] Z. Chen, Y. Shao, Dynamic simulation of planetary gear with tooth root
   crack in ring gear, Eng. Fail. Anal. 31 (2013) 8-18.
.. [ChenShao2013] Z. Chen, Y. Shao, Mesh stiffness of an internal spur gear pair with ring
   gear rim deformation, Mech. Mach. Theory 69 (2013) 1-12 (ring tooth as a cantilever on
   the root circle, potential energy method).
.. [Liang2014] X. Liang, M. J. Zuo, M. Pandey, Analytical evaluation of time-varying mesh
   stiffness for planetary gear sets, Mech. Mach. Theory 76 (2014) 20-38.
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004) 748-752.
.. [Yang1987] D. C. H. Yang, J. Y. Lin, Hertzian damping, tooth friction and bending
   elasticity in gear impact dynamics, J. Mech. Trans. Autom. Des. 109 (1987) 189-196.
.. [ISO21771] ISO 21771:2007, Gears - Cylindrical involute gears and gear pairs -
   Concepts and geometry (involute function, tooth thickness).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from gearsim.errors import require
from gearsim.geometry.gear import Material, inv
from gearsim.geometry.planetary import RingGear
from gearsim.stiffness.tooth import (
    beam_moduli,
    gauss_rule,
    sainsot_coefficients,
    sainsot_range_check,
)

__all__ = ["FOUNDATIONS", "PIECES", "RING_H_F", "RingToothModel"]

#: Foundation options of :class:`RingToothModel`.
FOUNDATIONS = ("sainsot-solid", "none")
#: h_f = r_f / r_int used in Sainsot's coefficients for the ring [-]: the upper end of the
#: fitted range [1.4, 7], standing for a body much larger than the tooth (module docstring).
RING_H_F = 7.0
#: Equal pieces of [r_c, r_f] that each get the Gauss-Legendre rule.
PIECES = 2
#: Relative slack on the range [r_a, r_f] of contact radii (rounding of a caller's radii);
#: radii within it are clipped onto the range.
RADIUS_RTOL = 1e-12


@dataclass(frozen=True)
class RingToothModel:
    """Potential-energy compliance of one tooth of an internal (ring) gear.

    The tooth is a cantilever of the involute outline clamped on the root circle, loaded
    along the line of action at the contact radius; columns bending, shear, axial
    compression and fillet foundation (module docstring for the derivation).

    Parameters
    ----------
    ring
        The ring gear (:class:`~gearsim.geometry.planetary.RingGear`); its tip (inner)
        circle must lie outside its base circle.
    material
        Material of the ring (:class:`~gearsim.geometry.gear.Material`).
    plane
        ``"stress"`` (beam terms with E) or ``"strain"`` (beam terms with E / (1 - nu^2));
        shear and foundation use G and E in both.
    foundation
        ``"none"`` (default: zero foundation column, the tooth clamped on its root
        circle as Chen & Shao 2013) or ``"sainsot-solid"`` (Sainsot et al. 2004 with
        the ring's root geometry and h_f = :data:`RING_H_F`; 8 to 19 times what the FE
        ring segment of :mod:`gearsim.fem.ring` shows beyond the beam terms, so not the
        default: docs/planetary.md section 4.3).
    gauss_points
        Gauss-Legendre nodes on each of the :data:`PIECES` pieces of [r_c, r_f] (2 .. 200).

    Raises
    ------
    InputError
        If ``ring`` or ``material`` is of the wrong type, the ring's tip circle is not
        outside its base circle, or ``plane``, ``foundation`` or ``gauss_points`` is
        invalid.

    References
    ----------
    Chen & Shao (2013) (ring tooth as a cantilever on the root circle, PE method); Liang,
    Zuo & Pandey (2014); Yang & Lin (1987) (beam energies); Sainsot, Velex & Duverger
    (2004) (foundation).

    Examples
    --------
    Ring z 78, m 2 mm, steel, unit width: at the reference (pitch) radius the tooth's
    half angle is s_r / (2 r) = (pi/2) / 78 and the load angle alpha + beta =
    20 deg + 90 deg / 78; the columns (bending, shear, axial, foundation) at the tip
    circle and at the pitch circle, in 1e-12 m/N:

    >>> import math
    >>> from gearsim.geometry.planetary import RingGear
    >>> tm = RingToothModel(RingGear(teeth=78, normal_module=2e-3))
    >>> round(float(tm.half_angle(0.078)[0]) * 78 / (math.pi / 2), 12)
    1.0
    >>> round(math.degrees(float(tm.load_angle(0.078)[0])), 4)
    21.1538
    >>> c = tm.compliance([tm.ring.tip_radius, 0.078])
    >>> print(np.array2string(c * 1e12, precision=3, suppress_small=True))
    [[19.972 20.186  0.532  0.   ]
     [ 1.083  7.955  0.382  0.   ]]
    >>> c = RingToothModel(tm.ring, foundation="sainsot-solid").compliance([0.078])
    >>> round(float(c[0, 3]) * 1e12, 3)
    63.738
    """

    ring: RingGear
    material: Material = field(default_factory=Material)
    plane: str = "stress"
    foundation: str = "none"
    gauss_points: int = 16

    def __post_init__(self) -> None:
        require(isinstance(self.ring, RingGear), "ring", type(self.ring).__name__,
                "must be a gearsim.geometry.planetary.RingGear")
        require(isinstance(self.material, Material), "material", type(self.material).__name__,
                "must be a gearsim.geometry.gear.Material")
        require(self.plane in ("stress", "strain"), "stiffness.plane", self.plane,
                'must be "stress" or "strain"')
        require(self.foundation in FOUNDATIONS, "ring_foundation", self.foundation,
                'must be "sainsot-solid" or "none"')
        require(isinstance(self.gauss_points, (int, np.integer))
                and not isinstance(self.gauss_points, bool)
                and 2 <= self.gauss_points <= 200,
                "stiffness.gauss_points", self.gauss_points, "must be an integer in [2, 200]")
        ring = self.ring
        require(ring.tip_radius > ring.base_radius, "ring.tip_radius", ring.tip_radius,
                f"must exceed the base radius {ring.base_radius:.6g} m (no involute inside "
                "the base circle)")

    # ------------------------------------------------------------------ geometry
    @property
    def reference_half_angle(self) -> float:
        """Half angular tooth thickness at the reference radius, s_r / (2 r) [rad].

        s_r = m_t (pi/2 - 2 x tan alpha_n) (module docstring; ISO 21771 with the ring's
        shift convention).
        """
        ring = self.ring
        s_r = ring.transverse_module * (0.5 * math.pi - 2.0 * ring.profile_shift
                                        * math.tan(ring.normal_pressure_angle))
        return s_r / (2.0 * ring.pitch_radius)

    @property
    def root_half_angle(self) -> float:
        """Half angle theta_f = beta(r_f) of the tooth at the root circle [rad]."""
        return float(self._beta(np.array([self.ring.root_radius]))[0])

    @property
    def beam_moduli(self) -> tuple[float, float]:
        """(E_eff, G) of the beam terms [Pa]: E or E / (1 - nu^2), and G."""
        return beam_moduli(self.material, self.plane)

    @cached_property
    def sainsot(self) -> np.ndarray:
        """(L*, M*, P*, Q*) at h_f = :data:`RING_H_F`, theta_f = beta(r_f) [-].

        A :class:`gearsim.errors.ModelRangeWarning` is issued if theta_f lies outside
        Sainsot's fitted range.
        """
        theta_f = self.root_half_angle
        sainsot_range_check("ring", RING_H_F, theta_f)
        return sainsot_coefficients(RING_H_F, theta_f)

    def _alpha(self, rho: np.ndarray) -> np.ndarray:
        return np.arccos(np.minimum(self.ring.base_radius / rho, 1.0))

    def _beta(self, rho: np.ndarray, alpha: np.ndarray | None = None) -> np.ndarray:
        a = self._alpha(rho) if alpha is None else alpha
        return (self.reference_half_angle - inv(self.ring.transverse_pressure_angle)
                + (np.tan(a) - a))

    def _radii(self, radius, name: str, lo: float, hi: float, clip: bool) -> np.ndarray:
        r = np.atleast_1d(np.asarray(radius, dtype=float))
        require(r.ndim == 1, name, f"array of shape {r.shape}", "must be a scalar or 1-D")
        bad = ~np.isfinite(r)
        require(not bad.any(), name, float(r[bad][0]) if bad.any() else None,
                "must be finite")
        slack = RADIUS_RTOL * (hi if math.isfinite(hi) else lo)
        out = (r < lo - slack) | (r > hi + slack)
        if out.any():
            require(False, name, float(r[out][0]),
                    f"must lie in [{lo:.9g}, {hi:.9g}] m")
        return np.clip(r, lo, hi) if clip else r

    def half_angle(self, radius) -> np.ndarray:
        """Half angular tooth thickness beta(rho) of the ring tooth [rad].

        beta(rho) = s_r / (2 r) - inv(alpha_t) + inv(alpha_rho), cos(alpha_rho) = r_b / rho
        (module docstring; ISO 21771).

        Parameters
        ----------
        radius
            Radii rho >= r_b [m], scalar or 1-D.

        Returns
        -------
        ndarray, shape (n,)
            beta [rad].

        Raises
        ------
        InputError
            If a radius is not finite or lies inside the base circle.
        """
        r = self._radii(radius, "radius", self.ring.base_radius, math.inf, clip=False)
        return self._beta(r)

    def load_angle(self, radius) -> np.ndarray:
        """Angle a1 = alpha_rho + beta(rho) of the contact force to the centre line's normal.

        Parameters
        ----------
        radius
            Contact radii rho >= r_b [m], scalar or 1-D.

        Returns
        -------
        ndarray, shape (n,)
            a1 [rad]; the unit force on the tooth is (-cos a1, sin a1) in (X across,
            Y outwards) axes.

        Raises
        ------
        InputError
            If a radius is not finite or lies inside the base circle.

        References
        ----------
        Chen & Shao (2013); derivation in the module docstring.
        """
        r = self._radii(radius, "radius", self.ring.base_radius, math.inf, clip=False)
        a = self._alpha(r)
        return a + self._beta(r, a)

    def centre_line_depth(self, radius) -> np.ndarray:
        """Distance from a contact point to the tooth centre line along the load line [m].

        The contact P = (r_c sin beta_c, r_c cos beta_c) and the point Q where the line of
        the force (-cos a1, sin a1) crosses the centre line X = 0 (where the FE ring
        segment of :mod:`gearsim.fem.ring` reads the tooth's deflection) are
        d = X_c / cos(a1) = r_c sin(beta_c) / cos(alpha_c + beta_c) apart: the depth of the
        ring's side of the line contact (:func:`gearsim.stiffness.tooth.
        line_contact_compliance`), as :func:`gearsim.stiffness.mesh.centre_line_depth`
        for an external tooth.

        Parameters
        ----------
        radius
            Contact radii in [r_a, r_f] [m], scalar or 1-D.

        Returns
        -------
        ndarray, shape (n,)
            d [m].

        Raises
        ------
        InputError
            If a radius is not finite or outside [r_a, r_f].
        """
        r = self._radii(radius, "radius", self.ring.tip_radius, self.ring.root_radius,
                        clip=True)
        a = self._alpha(r)
        b = self._beta(r, a)
        return r * np.sin(b) / np.cos(a + b)

    def _cracked_half(self, y: np.ndarray, h: np.ndarray, q: float, angle: float
                      ) -> np.ndarray:
        """Effective half width h_c of the loaded side at heights Y on a cracked tooth."""
        theta_f = self.root_half_angle
        rf = self.ring.root_radius
        x0, y0 = rf * math.sin(theta_f), rf * math.cos(theta_f)
        x1, y1 = x0 - q * math.sin(angle), y0 - q * math.cos(angle)
        on_crack = y >= y1
        slope = math.tan(angle)
        line = x0 - (y0 - y) * slope
        return np.where(on_crack, np.minimum(line, h), np.minimum(h, x1))

    def max_crack_depth(self, angle: float) -> float:
        """Deepest crack the model takes at ``angle``: its tip on the centre line [m].

        A crack from the loaded flank's root point (X_0 = r_f sin theta_f) at ``angle``
        to the centre line reaches the centre line at depth X_0 / sin(angle).

        Parameters
        ----------
        angle : float
            Angle between the crack and the tooth centre line [rad], in (0, pi/2].

        Returns
        -------
        float
            X_0 / sin(angle) [m].
        """
        rf = self.ring.root_radius
        return rf * math.sin(self.root_half_angle) / math.sin(angle)

    def compliance(self, radii, *, width: float = 1.0, crack_depth: float = 0.0,
                   crack_angle: float = math.radians(45.0)) -> np.ndarray:
        """Tooth compliances at contact radii: columns bending, shear, axial, foundation.

        Parameters
        ----------
        radii
            Contact radii on the ring flank, in [r_a, r_f] [m], scalar or 1-D.
        width
            Face width L carried by the tooth [m] (> 0).
        crack_depth
            Depth q of a root crack on the loaded flank [m] (0: healthy), below
            :meth:`max_crack_depth` (module docstring, "Crack").
        crack_angle
            Angle between the crack and the tooth centre line [rad], in (0, pi/2].

        Returns
        -------
        ndarray, shape (n, 4)
            Compliances 1/k_b, 1/k_s, 1/k_a, 1/k_f for the given width [m/N].

        Raises
        ------
        InputError
            If a radius is not finite or outside [r_a, r_f], or ``width`` is not a
            positive finite number.

        References
        ----------
        Chen & Shao (2013); Liang, Zuo & Pandey (2014); Yang & Lin (1987); Sainsot,
        Velex & Duverger (2004).
        """
        require(isinstance(width, (int, float, np.floating, np.integer))
                and not isinstance(width, bool) and math.isfinite(width) and width > 0.0,
                "width", width, "must be a positive finite number [m]")
        require(math.isfinite(crack_angle) and 0.0 < crack_angle <= 0.5 * math.pi,
                "crack.angle", crack_angle, "must lie in (0, 90] deg")
        q_max = self.max_crack_depth(crack_angle)
        require(math.isfinite(crack_depth) and 0.0 <= crack_depth < q_max, "crack.depth",
                crack_depth, f"must lie in [0, {q_max:.6g}) m: a ring crack ends before the "
                "tooth centre line (its tip on the loaded side)")
        ring = self.ring
        rf = ring.root_radius
        rc = self._radii(radii, "radii", ring.tip_radius, rf, clip=True)
        e_mod, g_mod = self.beam_moduli

        # contact point and load
        a_c = self._alpha(rc)
        b_c = self._beta(rc, a_c)
        a1 = a_c + b_c
        fb = np.cos(a1)
        fa = np.sin(a1)
        xc = rc * np.sin(b_c)

        # Gauss-Legendre nodes over PIECES equal pieces of [r_c, r_f]
        x, w = gauss_rule(self.gauss_points)
        k = np.arange(PIECES)
        t = ((k[:, None] + 0.5 * (x[None, :] + 1.0)) / PIECES).ravel()  # in (0, 1)
        wt = np.tile(w, PIECES) / (2.0 * PIECES)  # sums to 1
        span = rf - rc
        rho = rc[:, None] + span[:, None] * t[None, :]
        a = self._alpha(rho)
        b = self._beta(rho, a)
        sb, cb = np.sin(b), np.cos(b)
        h = rho * sb
        dy = cb - sb * np.tan(a)
        # Y - Y_c without cancellation (large rings)
        y_rel = (rho - rc[:, None]) * cb - 2.0 * rc[:, None] * np.sin(
            0.5 * (b + b_c[:, None])) * np.sin(0.5 * (b - b_c[:, None]))
        jac = (span[:, None] * wt[None, :]) * dy
        mom = fb[:, None] * y_rel - fa[:, None] * xc[:, None]
        # section thickness: 2h, or h + h_c on a cracked tooth (the loaded side ends at
        # the crack line, then at its limiting line; Tian 2004, Chen & Shao 2013)
        thick = 2.0 * h if crack_depth == 0.0 else h + self._cracked_half(
            rho * cb, h, crack_depth, crack_angle)
        inv_w = jac / thick
        out = np.empty((rc.shape[0], 4))
        out[:, 0] = 12.0 * np.sum(mom * mom * inv_w / (thick * thick), axis=1) / e_mod
        out[:, 1] = 1.2 * fb * fb * np.sum(inv_w, axis=1) / g_mod
        out[:, 2] = fa * fa * np.sum(inv_w, axis=1) / e_mod

        if self.foundation == "none":
            out[:, 3] = 0.0
        else:
            ls, ms, ps, qs = self.sainsot
            theta_f = self.root_half_angle
            sf = 2.0 * rf * theta_f
            # Y_root - Y_c, stably
            yr = (rf - rc) * math.cos(theta_f) - 2.0 * rc * np.sin(
                0.5 * (theta_f + b_c)) * np.sin(0.5 * (theta_f - b_c))
            tan1 = np.tan(a1)
            ratio = (yr - xc * tan1) / sf
            out[:, 3] = (fb * fb / self.material.youngs_modulus) * (
                ls * ratio * ratio + ms * ratio + ps * (1.0 + qs * tan1 * tan1))
        return out / width
