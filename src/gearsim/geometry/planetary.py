"""Single planetary stage (sun, N planets, ring): geometry, assembly checks, mesh phasing.

All lengths in metres, angles in radians. The sun and the planets are external
:class:`~gearsim.geometry.gear.Gear` objects; the ring is an internal gear whose radii are
computed here (its tip circle is the *smaller* one, its root circle the larger).

Sign convention of the ring's profile shift (DIN 3960 / Niemann-Winter): a positive
``x_r`` moves the ring's flanks radially outwards, like the planet's, so that
``r_a,r = r_r - (h_a* - x_r) m_n`` and ``r_f,r = r_r + (h_f* + x_r) m_n``; planet and ring
with ``x_r = x_p`` mesh at the reference centre distance ``r_r - r_p``.

References
----------
.. [ISO21771] ISO 21771:2007, Gears - Cylindrical involute gears and gear pairs -
   Concepts and geometry (internal gear pairs: working pressure angle, centre distance,
   length of path of contact).
.. [Litvin] F. L. Litvin, A. Fuentes, Gear Geometry and Applied Theory, 2nd ed., Cambridge
   University Press, 2004, ch. 10 (internal involute gears).
.. [ParkerLin2004] R. G. Parker, J. Lin, Mesh phasing relationships in planetary and
   epicyclic gears, J. Mech. Des. 126 (2004) 365-370.
.. [Muller] H. W. Mueller, Epicyclic Drive Trains, Wayne State University Press, 1982
   (assembly condition (z_s + z_r) / N integer for equally spaced planets).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from gearsim.errors import require
from gearsim.geometry.gear import (
    PROFILE_SHIFT_RANGE,
    Gear,
    Material,
    _TransverseGeometry,
    inv,
    inv_inverse,
)

__all__ = ["COAXIAL_TOLERANCE", "PlanetaryStage", "RingGear"]

#: Largest difference of the sun-planet and ring-planet working centre distances,
#: relative to the normal module, accepted as "coaxial" [-]: 1e-3 m_n is far below the
#: backlash allowance of any gear quality grade (ISO 1328: tens of micrometres).
COAXIAL_TOLERANCE = 1e-3
#: Tolerance on "integer" in the assembly condition for given planet angles [-].
ASSEMBLY_TOLERANCE = 1e-6


def _is_int(v: object) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


@dataclass(frozen=True)
class RingGear(_TransverseGeometry):
    """Internal (ring) gear: radii of an involute internal gear.

    Parameters
    ----------
    teeth
        Number of teeth z_r (> 0).
    normal_module
        Normal module m_n [m].
    normal_pressure_angle
        Normal pressure angle alpha_n [rad].
    helix_angle
        Helix angle beta [rad] (same hand as the planet for an internal mesh).
    addendum_coefficient, dedendum_coefficient
        h_a*, h_f* of the basic rack [-].
    profile_shift
        Profile shift x_r [-]; positive moves the flanks outwards (module docstring).

    References
    ----------
    ISO 21771:2007 (internal gears); Litvin & Fuentes (2004), ch. 10.

    Examples
    --------
    z 72, m 2 mm: r 72 mm, tip (inner) 70 mm, root (outer) 74.5 mm:

    >>> r = RingGear(teeth=72, normal_module=2e-3)
    >>> round(r.tip_radius * 1e3, 6), round(r.root_radius * 1e3, 6)
    (70.0, 74.5)
    """

    teeth: int
    normal_module: float
    normal_pressure_angle: float = math.radians(20.0)
    helix_angle: float = 0.0
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    profile_shift: float = 0.0

    @property
    def base_radius(self) -> float:
        """Base radius r_b = r cos(alpha_t) [m]."""
        return self.pitch_radius * math.cos(self.transverse_pressure_angle)

    @property
    def tip_radius(self) -> float:
        """Tip (inner) radius r_a = r - (h_a* - x) m_n [m]."""
        return self.pitch_radius - (self.addendum_coefficient - self.profile_shift) * self.normal_module

    @property
    def root_radius(self) -> float:
        """Root (outer) radius r_f = r + (h_f* + x) m_n [m]."""
        return self.pitch_radius + (self.dedendum_coefficient + self.profile_shift) * self.normal_module


@dataclass(frozen=True)
class PlanetaryStage:
    """A simple planetary stage: sun, ``planets`` identical planets, ring, carrier.

    Parameters
    ----------
    sun_teeth, planet_teeth, ring_teeth
        Tooth counts z_s, z_p, z_r (integers; sun and planet >= 7).
    normal_module
        Normal module m_n [m], common to all gears.
    planets
        Number of planets N (>= 1).
    normal_pressure_angle
        Normal pressure angle alpha_n [rad] (default 20 deg).
    helix_angle
        Helix angle beta [rad] (0 for spur).
    face_width
        Face width b [m], common to all gears.
    sun_shift, planet_shift, ring_shift
        Profile shift coefficients x_s, x_p, x_r [-] (ring convention in the module
        docstring).
    planet_angles
        Angles psi_n of the planet centres, counter-clockwise from planet 1 [rad];
        ``None`` (default) spaces them equally, psi_n = 2 pi (n - 1) / N. Given angles
        must start with 0 and increase within [0, 2 pi).
    material
        :class:`~gearsim.geometry.gear.Material` of all gears.
    addendum_coefficient, dedendum_coefficient
        h_a*, h_f* of the basic rack (defaults 1.0, 1.25).
    ring_addendum_coefficient
        h_a* of the ring [-]; ``None``: ``addendum_coefficient``. Internal gears commonly
        get a shorter addendum (0.8 and less) so that the ring's tip does not reach the
        planet's fillet (checked by :class:`gearsim.stiffness.internal.InternalMesh`).

    Raises
    ------
    InputError
        Tooth counts not integers or N < 1; not coaxial (unshifted: z_r != z_s + 2 z_p;
        shifted: the two working centre distances differ by more than
        ``COAXIAL_TOLERANCE`` m_n); planets not assemblable (equal spacing:
        (z_s + z_r)/N not an integer; given angles: (z_s + z_r) psi_n / 2 pi not an
        integer); neighbouring planets' tip circles overlap; the ring's tip circle inside
        its base circle; a contact ratio below 1; errors of the sun or planet
        :class:`~gearsim.geometry.gear.Gear`.

    References
    ----------
    ISO 21771:2007; Litvin & Fuentes (2004) ch. 10; Mueller (1982) (assembly);
    Parker & Lin (2004) (mesh phasing).

    Examples
    --------
    >>> s = PlanetaryStage(sun_teeth=30, planet_teeth=24, ring_teeth=78, normal_module=2e-3,
    ...                    planets=4)
    >>> round(s.centre_distance * 1e3, 6)
    54.0
    >>> s.phasing, [float(g) for g in s.sun_planet_phases]
    ('sequential', [0.0, 0.5, 0.0, 0.5])
    """

    sun_teeth: int
    planet_teeth: int
    ring_teeth: int
    normal_module: float
    planets: int = 3
    normal_pressure_angle: float = math.radians(20.0)
    helix_angle: float = 0.0
    face_width: float = 0.02
    sun_shift: float = 0.0
    planet_shift: float = 0.0
    ring_shift: float = 0.0
    planet_angles: tuple[float, ...] | None = None
    material: Material = field(default_factory=Material)
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    ring_addendum_coefficient: float | None = None

    def __post_init__(self) -> None:
        ha = self.ring_addendum_coefficient
        require(ha is None or (isinstance(ha, (int, float)) and math.isfinite(ha)
                               and 0.0 < ha <= 1.5), "stage.ring_addendum_coefficient", ha,
                "must be a finite number in (0, 1.5]")
        for name in ("sun_teeth", "planet_teeth", "ring_teeth", "planets"):
            v = getattr(self, name)
            require(_is_int(v), f"stage.{name}", v, "must be an integer")
        require(self.planets >= 1, "stage.planets", self.planets, "must be >= 1")
        require(self.ring_teeth > self.planet_teeth, "stage.ring_teeth", self.ring_teeth,
                f"must be > planet_teeth = {self.planet_teeth} (internal mesh)")
        for name in ("sun_shift", "planet_shift", "ring_shift"):  # before any geometry
            x = getattr(self, name)
            require(isinstance(x, (int, float)) and math.isfinite(x)
                    and PROFILE_SHIFT_RANGE[0] <= x <= PROFILE_SHIFT_RANGE[1],
                    f"stage.{name}", x, f"must be a finite number in "
                    f"[{PROFILE_SHIFT_RANGE[0]:g}, {PROFILE_SHIFT_RANGE[1]:g}]")
        # the Gear constructors check module, angles, face width, undercut, pointed teeth
        _ = self.sun, self.planet
        ring = self.ring
        require(ring.tip_radius > ring.base_radius, "stage.ring_teeth", self.ring_teeth,
                f"ring tip radius {ring.tip_radius:.6g} m must exceed its base radius "
                f"{ring.base_radius:.6g} m (no involute inside the base circle)")
        zs, zp, zr = self.sun_teeth, self.planet_teeth, self.ring_teeth
        shifted = any(x != 0.0 for x in (self.sun_shift, self.planet_shift, self.ring_shift))
        if not shifted:
            require(zr == zs + 2 * zp, "stage.ring_teeth", zr,
                    f"coaxiality of an unshifted stage needs z_r = z_s + 2 z_p = {zs + 2 * zp}")
        for mesh, x_sum, z_sum in (("sun-planet", self.sun_shift + self.planet_shift, zs + zp),
                                   ("ring-planet", self.ring_shift - self.planet_shift, zr - zp)):
            val = inv(self.sun.transverse_pressure_angle) + 2.0 * math.tan(
                self.normal_pressure_angle) * x_sum / z_sum
            require(val > 0.0, "stage", f"{mesh} profile shifts {round(x_sum, 6):g}",
                    "give no real working pressure angle (inv(alpha_w) <= 0): shift less "
                    "negatively")
        a_sp, a_rp = self.sun_planet_centre_distance, self.ring_planet_centre_distance
        require(abs(a_sp - a_rp) <= COAXIAL_TOLERANCE * self.normal_module, "stage",
                f"centre distances sun-planet {a_sp * 1e3:.6g} mm vs ring-planet "
                f"{a_rp * 1e3:.6g} mm",
                f"must agree within {COAXIAL_TOLERANCE:g} m_n (coaxiality; adjust the profile shifts)")
        psi = self.planet_angles_value
        if self.planet_angles is None:
            require((zs + zr) % self.planets == 0, "stage.planets", self.planets,
                    f"equal spacing needs (z_s + z_r)/N integer: ({zs} + {zr})/{self.planets} = "
                    f"{(zs + zr) / self.planets:.6g}")
        else:
            require(len(psi) == self.planets, "stage.planet_angles", len(psi),
                    f"must give one angle per planet ({self.planets})")
            shown = [f"{math.degrees(p):.6g} deg" for p in psi]
            require(psi[0] == 0.0, "stage.planet_angles", shown, "the first (planet 1) must be 0")
            require(bool(np.all(np.diff(psi) > 0.0)) and psi[-1] < 2.0 * math.pi,
                    "stage.planet_angles", tuple(float(p) for p in psi),
                    "must increase strictly within [0, 2 pi)")
            for n, p in enumerate(psi):
                k = (zs + zr) * p / (2.0 * math.pi)
                require(abs(k - round(k)) < ASSEMBLY_TOLERANCE, "stage.planet_angles", shown,
                        f"planet {n + 1} at {math.degrees(p):.10g} deg cannot be assembled: "
                        f"(z_s + z_r) psi / 2 pi = {k:.10g} must be an integer within "
                        f"{ASSEMBLY_TOLERANCE:g} (nearest: {360 * round(k) / (zs + zr):.10g} deg)")
        if self.planets > 1:
            gaps = np.diff(np.append(psi, psi[0] + 2.0 * math.pi))
            gap = float(gaps.min())
            dist = 2.0 * self.centre_distance * math.sin(0.5 * gap)
            require(dist > 2.0 * self.planet.tip_radius, "stage.planets", self.planets,
                    f"neighbouring planets collide: centre spacing 2 a sin(gap/2) = {dist * 1e3:.6g} mm "
                    f"(gap {math.degrees(gap):.4g} deg) must exceed 2 r_a,planet = "
                    f"{2e3 * self.planet.tip_radius:.6g} mm")
        eps_b = self.overlap_ratio
        for mesh, eps in (("sun-planet", self.sun_planet_contact_ratio),
                          ("ring-planet", self.ring_planet_contact_ratio)):
            require(eps > 0.0 and eps + eps_b >= 1.0, "stage",
                    f"{mesh} contact ratio {round(eps, 4):g}",
                    "the total contact ratio eps_alpha + eps_beta must be >= 1")

    # ------------------------------------------------------------------ members
    def _gear(self, teeth: int, shift: float, name: str) -> Gear:
        return Gear(teeth=teeth, normal_module=self.normal_module,
                    normal_pressure_angle=self.normal_pressure_angle, helix_angle=self.helix_angle,
                    face_width=self.face_width, addendum_coefficient=self.addendum_coefficient,
                    dedendum_coefficient=self.dedendum_coefficient, profile_shift=shift,
                    material=self.material, name=name)

    @cached_property
    def sun(self) -> Gear:
        """The sun gear (:class:`~gearsim.geometry.gear.Gear`)."""
        return self._gear(self.sun_teeth, self.sun_shift, "sun")

    @cached_property
    def planet(self) -> Gear:
        """One planet (:class:`~gearsim.geometry.gear.Gear`; all planets are identical)."""
        return self._gear(self.planet_teeth, self.planet_shift, "planet")

    @cached_property
    def ring(self) -> RingGear:
        """The ring gear (:class:`RingGear`)."""
        return RingGear(teeth=self.ring_teeth, normal_module=self.normal_module,
                        normal_pressure_angle=self.normal_pressure_angle, helix_angle=self.helix_angle,
                        addendum_coefficient=(self.addendum_coefficient
                                              if self.ring_addendum_coefficient is None
                                              else self.ring_addendum_coefficient),
                        dedendum_coefficient=self.dedendum_coefficient, profile_shift=self.ring_shift)

    @property
    def planet_angles_value(self) -> np.ndarray:
        """Planet angles psi_n [rad], shape (N,): given, or 2 pi (n - 1)/N."""
        if self.planet_angles is None:
            return 2.0 * math.pi * np.arange(self.planets) / self.planets
        return np.asarray(self.planet_angles, dtype=float)

    # ------------------------------------------------------------- mesh geometry
    @cached_property
    def sun_planet_pressure_angle(self) -> float:
        """Working transverse pressure angle of the sun-planet (external) mesh [rad].

        inv(alpha_w) = inv(alpha_t) + 2 tan(alpha_n)(x_s + x_p)/(z_s + z_p) (ISO 21771).
        """
        return inv_inverse(inv(self.sun.transverse_pressure_angle) + 2.0 * math.tan(
            self.normal_pressure_angle) * (self.sun_shift + self.planet_shift) / (
            self.sun_teeth + self.planet_teeth))

    @cached_property
    def ring_planet_pressure_angle(self) -> float:
        """Working transverse pressure angle of the ring-planet (internal) mesh [rad].

        inv(alpha_w) = inv(alpha_t) + 2 tan(alpha_n)(x_r - x_p)/(z_r - z_p) (ISO 21771,
        internal pair; ring shift convention of the module docstring).
        """
        return inv_inverse(inv(self.sun.transverse_pressure_angle) + 2.0 * math.tan(
            self.normal_pressure_angle) * (self.ring_shift - self.planet_shift) / (
            self.ring_teeth - self.planet_teeth))

    @property
    def sun_planet_centre_distance(self) -> float:
        """a_sp = (r_b,s + r_b,p)/cos(alpha_w,sp) [m]."""
        return (self.sun.base_radius + self.planet.base_radius) / math.cos(self.sun_planet_pressure_angle)

    @property
    def ring_planet_centre_distance(self) -> float:
        """a_rp = (r_b,r - r_b,p)/cos(alpha_w,rp) [m]."""
        return (self.ring.base_radius - self.planet.base_radius) / math.cos(
            self.ring_planet_pressure_angle)

    @property
    def centre_distance(self) -> float:
        """Carrier radius a (planet-centre circle) [m]: the sun-planet working centre distance."""
        return self.sun_planet_centre_distance

    @property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt = 2 pi r_b / z, common to all gears [m]."""
        return self.sun.transverse_base_pitch

    @property
    def sun_planet_line_of_action(self) -> float:
        """Length T_s T_p of the sun-planet line of action, a_sp sin(alpha_w,sp) [m]."""
        return self.sun_planet_centre_distance * math.sin(self.sun_planet_pressure_angle)

    @property
    def ring_planet_line_of_action(self) -> float:
        """Length T_r T_p of the ring-planet line of action, a_rp sin(alpha_w,rp) [m].

        For an internal pair both tangent points lie on the same side of the pitch point:
        r_b,r tan(alpha_w) - r_b,p tan(alpha_w) = a_rp sin(alpha_w).
        """
        return self.ring_planet_centre_distance * math.sin(self.ring_planet_pressure_angle)

    @staticmethod
    def _roll(ra: float, rb: float) -> float:
        return math.sqrt(max(ra * ra - rb * rb, 0.0))

    @property
    def sun_planet_path_of_contact(self) -> float:
        """Length of the sun-planet path of contact g_alpha [m].

        g = sqrt(r_a,s^2 - r_b,s^2) + sqrt(r_a,p^2 - r_b,p^2) - a_sp sin(alpha_w,sp)
        (ISO 21771).
        """
        s, p = self.sun, self.planet
        return (self._roll(s.tip_radius, s.base_radius) + self._roll(p.tip_radius, p.base_radius)
                - self.sun_planet_line_of_action)

    @property
    def ring_planet_path_of_contact(self) -> float:
        """Length of the ring-planet path of contact g_alpha [m].

        g = sqrt(r_a,p^2 - r_b,p^2) - sqrt(r_a,r^2 - r_b,r^2) + a_rp sin(alpha_w,rp),
        r_a,r the ring's (inner) tip radius (ISO 21771; Litvin & Fuentes 2004, ch. 10).
        """
        r, p = self.ring, self.planet
        return (self._roll(p.tip_radius, p.base_radius) - self._roll(r.tip_radius, r.base_radius)
                + self.ring_planet_line_of_action)

    @property
    def sun_planet_contact_ratio(self) -> float:
        """Transverse contact ratio of the sun-planet mesh, g_alpha / p_bt [-]."""
        return self.sun_planet_path_of_contact / self.base_pitch

    @property
    def ring_planet_contact_ratio(self) -> float:
        """Transverse contact ratio of the ring-planet mesh, g_alpha / p_bt [-]."""
        return self.ring_planet_path_of_contact / self.base_pitch

    @property
    def overlap_ratio(self) -> float:
        """Overlap ratio eps_beta = b sin|beta| / (pi m_n) of both meshes [-] (ISO 21771)."""
        return self.face_width * math.sin(abs(self.helix_angle)) / (math.pi * self.normal_module)

    # ------------------------------------------------------------------ phasing
    @property
    def sun_planet_phases(self) -> np.ndarray:
        """Relative phases gamma_sn of the sun-planet meshes, shape (N,), in [0, 1) [-].

        gamma_sn = frac(z_s psi_n / 2 pi) (Parker & Lin 2004). Convention: planets and
        psi_n counted counter-clockwise, the sun turning counter-clockwise relative to the
        carrier; mesh n *lags* mesh 1 by gamma_sn mesh periods T_m,
        k_sn(t) = k_s1(t - gamma_sn T_m). For the opposite sense of rotation replace
        gamma by frac(-gamma) = 1 - gamma (for gamma != 0). gamma_s1 = 0.
        """
        return self._phases(self.sun_teeth)

    @property
    def ring_planet_phases(self) -> np.ndarray:
        """Relative phases gamma_rn of the ring-planet meshes, shape (N,), in [0, 1) [-].

        gamma_rn = frac(-z_r psi_n / 2 pi) (Parker & Lin 2004; the ring turns the other
        way round relative to the carrier than the sun); same lag convention as
        :attr:`sun_planet_phases`, k_rn(t) = k_r1(t - gamma_rn T_m). For assemblable
        planets gamma_rn = gamma_sn.
        """
        return self._phases(-self.ring_teeth)

    def _phases(self, z: int) -> np.ndarray:
        """frac(z psi_n / 2 pi); exact (integer arithmetic) for equally spaced planets."""
        if self.planet_angles is None:
            n = self.planets
            return np.array([(z * j) % n / n for j in range(n)], dtype=float)
        g = np.mod(z * self.planet_angles_value / (2.0 * math.pi), 1.0)
        return np.where(np.isclose(g, 1.0, atol=1e-9) | np.isclose(g, 0.0, atol=1e-9), 0.0, g)

    @property
    def sun_ring_phase(self) -> float:
        """Phase gamma_rs of a planet's ring-planet mesh after its sun-planet mesh [-].

        Reference event of each mesh: a contact at its pitch point. With the sun turning
        counter-clockwise relative to the carrier, the ring-planet contact of the same
        planet reaches its pitch point gamma_rs T_m later than the sun-planet contact:

            gamma_rs = frac( z_p/2 - z_p psi_b/pi + z_p (inv alpha_w,sp + inv alpha_w,rp)/(2 pi) )

        with psi_b the planet's half angular tooth thickness on the base circle
        (:attr:`~gearsim.geometry.gear.Gear.base_half_thickness_angle`). Unshifted
        gears give frac((z_p - 1)/2): 0 for odd, 1/2 for even z_p (Parker & Lin 2004).
        Derivation in docs/planetary.md (the sun mesh loads one flank of the planet, the
        ring mesh the other; the two pitch points are half a planet turn apart).
        """
        g = self.sun_ring_offset % 1.0
        return 0.0 if min(g, 1.0 - g) < 1e-9 else g

    @property
    def sun_ring_offset(self) -> float:
        """Mesh cycles from a planet tooth's sun-side to its ring-side pitch-point contact [-].

        The unwrapped form of :attr:`sun_ring_phase` (same tooth, no frac):
        z_p/2 - z_p psi_b/pi + z_p (inv alpha_w,sp + inv alpha_w,rp)/(2 pi), the angle
        the planet turns between the two events in units of its angular pitch. It ties
        the tooth numbering of a planet's sun and ring meshes together (a cracked planet
        tooth meets the ring this many mesh cycles after it met the sun).
        """
        zp = self.planet_teeth
        return (0.5 * zp - zp * self.planet.base_half_thickness_angle / math.pi
                + zp * (inv(self.sun_planet_pressure_angle) + inv(self.ring_planet_pressure_angle))
                / (2.0 * math.pi))

    @property
    def phasing(self) -> str:
        """``"in-phase"`` if all gamma_sn = 0 (z_s psi_n / 2 pi integers), else ``"sequential"``."""
        return "in-phase" if bool(np.all(self.sun_planet_phases == 0.0)) else "sequential"

    def mesh_frequency(self, sun_speed: float) -> float:
        """Mesh frequency with the ring held, f_m = z_s (n_s - n_c) = z_s n_s z_r/(z_s + z_r).

        Parameters
        ----------
        sun_speed
            Sun speed [rad/s] (ring fixed, carrier output).

        Returns
        -------
        float
            f_m [Hz].
        """
        zs, zr = self.sun_teeth, self.ring_teeth
        return zs * sun_speed * zr / (zs + zr) / (2.0 * math.pi)

