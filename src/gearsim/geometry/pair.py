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

from gearsim.errors import require
from gearsim.geometry.gear import MAX_MODULE, MIN_MODULE, Gear, inv, inv_inverse
from gearsim.geometry.profile import ToothProfile

__all__ = ["GearPair", "require_same_rack"]


def require_same_rack(first: str, module1: float, angle1: float, second: str,
                      module2: float, angle2: float, *, mesh: str | None = None) -> None:
    """Refuse two gears that cannot mesh: unequal normal module or normal pressure angle.

    Parameters
    ----------
    first, second : str
        Names of the two gears (the message blames ``second``).
    module1, module2 : float
        Normal modules [m].
    angle1, angle2 : float
        Normal pressure angles [rad].
    mesh : str, optional
        Name of the mesh, prefixed to the parameter name.

    Raises
    ------
    InputError
        ``<second>.normal_module`` (values in mm) or ``<second>.normal_pressure_angle``
        (values in degrees) when they differ from those of ``first``.

    Examples
    --------
    >>> import math
    >>> require_same_rack("pinion", 3.2e-3, math.radians(20), "gear", 3.2e-3,
    ...                   math.radians(25))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: gear.normal_pressure_angle = 25 deg: must equal pinion...
    """
    if not all(MIN_MODULE <= m < MAX_MODULE for m in (module1, module2)) or not all(
            math.radians(5) <= a <= math.radians(35) for a in (angle1, angle2)):
        return  # a value out of its range: the gear's own check names it
    at = f"{mesh}: " if mesh else ""
    why = "(meshing gears need equal normal module and pressure angle)"
    require(math.isclose(module1, module2, rel_tol=1e-9), f"{at}{second}.normal_module",
            f"{module2 * 1e3:.6g} mm",
            f"must equal {first}.normal_module = {module1 * 1e3:.6g} mm {why}")
    require(math.isclose(angle1, angle2, rel_tol=1e-9), f"{at}{second}.normal_pressure_angle",
            f"{math.degrees(angle2):.6g} deg",
            f"must equal {first}.normal_pressure_angle = {math.degrees(angle1):.6g} deg {why}")


@dataclass(frozen=True)
class GearPair:
    """External gear pair; ``driver`` drives ``driven``.

    The pair runs at zero backlash at the centre distance given by the profile shifts
    (ISO 21771 eq. for the working pressure angle). Positions on the transverse line of
    action are measured from the tangent point T1 on the driver's base circle.

    Parameters
    ----------
    driver
        Driving gear (:class:`~gearsim.geometry.gear.Gear`).
    driven
        Driven gear; same normal module, pressure angle and helix angle (opposite hand).
    name
        Label used in error messages.
    centre_distance_offset
        Change of the operating centre distance from the zero-backlash one [m] (default
        0): the working pressure angle, the line of action and the path of contact follow
        (cos alpha_wt = (r_b1 + r_b2) / a). Used for the centre-distance modulation of
        an eccentric gear (:mod:`gearsim.dynamics.tables`); must keep |offset| below
        one module.

    Raises
    ------
    InputError
        If the gears cannot mesh (different module, pressure or helix angle), a tip
        reaches below the other gear's form circle (interference) or the total
        contact ratio eps_alpha + eps_beta is below 1.

    References
    ----------
    ISO 21771:2007, sections 5 and 6.

    Examples
    --------
    Mesh I of the Table-1 idler train (z 39/59, m_n 6 mm, beta 13 deg, b 150 mm);
    check values eps_alpha 1.681, eps_beta 1.790 (docs/references.md):

    >>> import math
    >>> from gearsim.geometry.gear import Gear
    >>> kw = dict(normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15)
    >>> pair = GearPair(Gear(teeth=39, **kw), Gear(teeth=59, **kw))
    >>> round(pair.transverse_contact_ratio, 3), round(pair.overlap_ratio, 3)
    (1.681, 1.79)
    >>> round(pair.centre_distance * 1e3, 3)  # x1 = x2 = 0: r1 + r2
    301.733
    """

    driver: Gear
    driven: Gear
    name: str = "mesh"
    centre_distance_offset: float = 0.0

    def __post_init__(self) -> None:
        g1, g2 = self.driver, self.driven
        n = self.name
        off = self.centre_distance_offset
        require(isinstance(off, (int, float)) and math.isfinite(off)
                and abs(off) < g1.normal_module, f"{n}: centre_distance_offset", off,
                f"must be a finite number below one module ({g1.normal_module:g} m) in size")
        require_same_rack(g1.name, g1.normal_module, g1.normal_pressure_angle, g2.name,
                          g2.normal_module, g2.normal_pressure_angle, mesh=n)
        require(math.isclose(abs(g1.helix_angle), abs(g2.helix_angle), rel_tol=1e-9, abs_tol=1e-12),
                f"{n}: {g2.name}.helix_angle", f"{math.degrees(g2.helix_angle):.6g} deg",
                f"must equal {g1.name}.helix_angle = {math.degrees(g1.helix_angle):.6g} deg "
                "(opposite hands) for external helical gears in mesh")
        # interference: the active path must start above each gear's form circle
        lf1 = self.roll_length_at(g1, self.profile1.form_radius)
        lf2 = self.line_length - self.roll_length_at(g2, self.profile2.form_radius)
        for tip, other, r, form, bad in (
                (g2, g1, self.radius_on_driver(self.start_of_contact), self.profile1.form_radius,
                 self.start_of_contact < lf1 - 1e-12),
                (g1, g2, self.radius_on_driven(self.end_of_contact), self.profile2.form_radius,
                 self.end_of_contact > lf2 + 1e-12)):
            # the value written that raised the form circle or the tip: a positive shift
            # of the other gear, else of this one, else this one's addendum
            by, key = ((other, "profile_shift") if other.profile_shift > 0 else
                       (tip, "profile_shift") if tip.profile_shift > 0 else
                       (tip, "addendum_coefficient"))
            require(not bad, f"{by.name}.{key}", getattr(by, key), f"in mesh {n} the tip of "
                    f"{tip.name} (radius {tip.tip_radius * 1e3:.6g} mm) interferes with the "
                    f"fillet of {other.name}: contact would reach radius {r * 1e3:.6g} mm, "
                    f"below its form radius {form * 1e3:.6g} mm (reduce the addendum or the "
                    "profile shift)")
        eps = self.transverse_contact_ratio + self.overlap_ratio
        require(self.transverse_contact_ratio > 0 and eps >= 1.0, f"{n}: contact ratio",
                round(eps, 4), "total contact ratio eps_alpha + eps_beta must be >= 1")

    @cached_property
    def profile1(self) -> ToothProfile:
        """Tooth outline of the driver (:class:`ToothProfile`)."""
        return ToothProfile(self.driver)

    @cached_property
    def profile2(self) -> ToothProfile:
        """Tooth outline of the driven gear (:class:`ToothProfile`)."""
        return ToothProfile(self.driven)

    @cached_property
    def working_pressure_angle(self) -> float:
        """Working transverse pressure angle alpha_wt [rad].

        inv(alpha_wt) = inv(alpha_t) + 2 tan(alpha_n) (x1 + x2) / (z1 + z2) (ISO 21771);
        equal to alpha_t for x1 + x2 = 0.
        """
        g1, g2 = self.driver, self.driven
        v = inv(g1.transverse_pressure_angle) + 2.0 * math.tan(g1.normal_pressure_angle) * (
            g1.profile_shift + g2.profile_shift) / (g1.teeth + g2.teeth)
        alpha = inv_inverse(v)
        if self.centre_distance_offset == 0.0:
            return alpha
        a = (g1.base_radius + g2.base_radius) / math.cos(alpha) + self.centre_distance_offset
        return math.acos((g1.base_radius + g2.base_radius) / a)

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
        """Distance from a gear's base tangent point to the point at ``radius``.

        Parameters
        ----------
        gear
            The gear.
        radius
            Radius of the point on the line of action [m].

        Returns
        -------
        float
            sqrt(r^2 - r_b^2) [m] (0 inside the base circle).
        """
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
        """Transverse contact ratio eps_alpha = g_alpha / p_bt [-].

        g_alpha = sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a_w sin(alpha_wt)
        (ISO 21771).

        Examples
        --------
        Mesh II of the Table-1 train (z 59/125): 1.756 (docs/references.md).

        >>> import math
        >>> from gearsim.geometry.gear import Gear
        >>> kw = dict(normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15)
        >>> round(GearPair(Gear(teeth=59, **kw), Gear(teeth=125, **kw)
        ...                ).transverse_contact_ratio, 3)
        1.756
        """
        return (self.end_of_contact - self.start_of_contact) / self.base_pitch

    @property
    def overlap_ratio(self) -> float:
        """Overlap ratio eps_beta = b sin(|beta|) / (pi m_n) [-], b the common face width.

        References
        ----------
        ISO 21771:2007.
        """
        b = self.face_width
        return b * math.sin(abs(self.driver.helix_angle)) / (math.pi * self.driver.normal_module)

    @property
    def face_width(self) -> float:
        """Common (engaged) face width min(b1, b2) [m]."""
        return min(self.driver.face_width, self.driven.face_width)

    def radius_on_driver(self, l: float) -> float:
        """Radius on the driver of a point of the line of action.

        Parameters
        ----------
        l
            Position on the transverse line of action, from T1 [m].

        Returns
        -------
        float
            sqrt(r_b1^2 + l^2) [m].
        """
        return math.hypot(self.driver.base_radius, l)

    def radius_on_driven(self, l: float) -> float:
        """Radius on the driven gear of a point of the line of action.

        Parameters
        ----------
        l
            Position on the transverse line of action, from T1 [m].

        Returns
        -------
        float
            sqrt(r_b2^2 + (T1T2 - l)^2) [m].
        """
        return math.hypot(self.driven.base_radius, self.line_length - l)

    def mesh_frequency(self, driver_speed: float) -> float:
        """Mesh frequency f_m = z1 n1.

        Parameters
        ----------
        driver_speed
            Driver speed [rad/s].

        Returns
        -------
        float
            f_m [Hz].

        Examples
        --------
        39 teeth at 1900 rpm: 39 x 1900 / 60 = 1235 Hz.

        >>> import math
        >>> from gearsim.geometry.gear import Gear
        >>> kw = dict(normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15)
        >>> pair = GearPair(Gear(teeth=39, **kw), Gear(teeth=59, **kw))
        >>> round(pair.mesh_frequency(1900 * 2 * math.pi / 60), 9)
        1235.0
        """
        return self.driver.teeth * driver_speed / (2.0 * math.pi)
