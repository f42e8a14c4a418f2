"""A gear pair in mesh: centre distance, line of action, contact ratios, interference.

References
----------
.. [ISO21771] ISO 21771:2007, sections 5 and 6 (working pressure angle, centre distance,
   length of path of contact, transverse and overlap ratios).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from gearsim.errors import InputError, require
from gearsim.geometry.gear import Gear, inv, inv_inverse
from gearsim.geometry.profile import ToothProfile

__all__ = ["GearPair"]


@dataclass(frozen=True)
class GearPair:
    """External gear pair; ``driver`` drives ``driven``.

    The pair runs at zero backlash at the centre distance given by the profile shifts
    (ISO 21771 eq. for the working pressure angle). Positions on the transverse line of
    action are measured from the tangent point T1 on the driver's base circle.
    """

    driver: Gear
    driven: Gear
    name: str = "mesh"

    def __post_init__(self) -> None:
        g1, g2 = self.driver, self.driven
        n = self.name
        for attr in ("normal_module", "normal_pressure_angle"):
            require(math.isclose(getattr(g1, attr), getattr(g2, attr), rel_tol=1e-9),
                    f"{n}: {g2.name}.{attr}", getattr(g2, attr),
                    f"must equal {g1.name}.{attr} = {getattr(g1, attr)!r} for gears in mesh")
        require(math.isclose(abs(g1.helix_angle), abs(g2.helix_angle), rel_tol=1e-9, abs_tol=1e-12),
                f"{n}: {g2.name}.helix_angle", f"{math.degrees(g2.helix_angle):.6g} deg",
                f"must equal {g1.name}.helix_angle = {math.degrees(g1.helix_angle):.6g} deg "
                "(opposite hands) for external helical gears in mesh")
        # interference: the active path must start above each gear's form circle
        lf1 = self.roll_length_at(g1, self.profile1.form_radius)
        if self.start_of_contact < lf1 - 1e-12:
            raise InputError(
                f"{n}: {g2.name}.tip_radius", g2.tip_radius,
                f"interferes with the fillet of {g1.name}: contact would start at radius "
                f"{self.radius_on_driver(self.start_of_contact):.6g} m, below its form radius "
                f"{self.profile1.form_radius:.6g} m (reduce the addendum or shift the profile)")
        lf2 = self.line_length - self.roll_length_at(g2, self.profile2.form_radius)
        if self.end_of_contact > lf2 + 1e-12:
            raise InputError(
                f"{n}: {g1.name}.tip_radius", g1.tip_radius,
                f"interferes with the fillet of {g2.name}: contact would end at radius "
                f"{self.radius_on_driven(self.end_of_contact):.6g} m, below its form radius "
                f"{self.profile2.form_radius:.6g} m (reduce the addendum or shift the profile)")
        eps = self.transverse_contact_ratio + self.overlap_ratio
        require(self.transverse_contact_ratio > 0 and eps >= 1.0, f"{n}: contact ratio",
                round(eps, 4), "total contact ratio eps_alpha + eps_beta must be >= 1")

    @cached_property
    def profile1(self) -> ToothProfile:
        return ToothProfile(self.driver)

    @cached_property
    def profile2(self) -> ToothProfile:
        return ToothProfile(self.driven)

    @property
    def gear_ratio(self) -> float:
        """u = z2 / z1."""
        return self.driven.teeth / self.driver.teeth

    @cached_property
    def working_pressure_angle(self) -> float:
        """alpha_wt from inv(a_wt) = inv(a_t) + 2 tan(a_n) (x1 + x2)/(z1 + z2) [rad]."""
        g1, g2 = self.driver, self.driven
        v = inv(g1.transverse_pressure_angle) + 2.0 * math.tan(g1.normal_pressure_angle) * (
            g1.profile_shift + g2.profile_shift) / (g1.teeth + g2.teeth)
        return inv_inverse(v)

    @property
    def centre_distance(self) -> float:
        """a_w = (r_b1 + r_b2) / cos(alpha_wt) [m]."""
        return (self.driver.base_radius + self.driven.base_radius) / math.cos(
            self.working_pressure_angle)

    @property
    def line_length(self) -> float:
        """Length T1T2 of the transverse line of action between the base tangents [m]."""
        return self.centre_distance * math.sin(self.working_pressure_angle)

    @staticmethod
    def roll_length_at(gear: Gear, radius: float) -> float:
        """Distance from a gear's base tangent point to the point at ``radius`` [m]."""
        return math.sqrt(max(radius**2 - gear.base_radius**2, 0.0))

    @property
    def start_of_contact(self) -> float:
        """Point A (driven tip circle) on the line of action, from T1 [m]."""
        return self.line_length - self.roll_length_at(self.driven, self.driven.tip_radius)

    @property
    def end_of_contact(self) -> float:
        """Point E (driver tip circle) on the line of action, from T1 [m]."""
        return self.roll_length_at(self.driver, self.driver.tip_radius)

    @property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt [m]."""
        return self.driver.transverse_base_pitch

    @property
    def transverse_contact_ratio(self) -> float:
        """eps_alpha = g_alpha / p_bt."""
        return (self.end_of_contact - self.start_of_contact) / self.base_pitch

    @property
    def overlap_ratio(self) -> float:
        """eps_beta = b sin(|beta|) / (pi m_n), with b the common face width."""
        b = self.face_width
        return b * math.sin(abs(self.driver.helix_angle)) / (math.pi * self.driver.normal_module)

    @property
    def face_width(self) -> float:
        """Common (engaged) face width min(b1, b2) [m]."""
        return min(self.driver.face_width, self.driven.face_width)

    def radius_on_driver(self, l: float) -> float:
        """Radius on the driver of the line-of-action point at ``l`` from T1 [m]."""
        return math.hypot(self.driver.base_radius, l)

    def radius_on_driven(self, l: float) -> float:
        """Radius on the driven gear of the line-of-action point at ``l`` from T1 [m]."""
        return math.hypot(self.driven.base_radius, self.line_length - l)

    def mesh_frequency(self, driver_speed: float) -> float:
        """f_m = z1 n1 for a driver speed in rad/s [Hz]."""
        return self.driver.teeth * driver_speed / (2.0 * math.pi)
