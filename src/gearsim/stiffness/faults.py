"""Surface and breakage faults of a tooth: spall, pitting, chipped tip, broken tooth, wear.

Every fault is described on the flank it damages, in two coordinates of that flank:

* along the profile, the **roll length** rho = sqrt(r^2 - r_b^2) of a point at radius r
  (in the transverse plane it is the distance of the contact point from the base-circle
  tangent point along the line of action, so a mesh position maps straight onto it); the
  arc length along the involute from the base circle is s = rho^2 / (2 r_b) (ISO 21771);
* across the face, the axial position z from the face edge z = 0 (the edge where the
  crack of :mod:`gearsim.stiffness.crack` starts) [m].

What a fault does to the mesh (docs/contacts.md):

* **spall, pits** (material recessed by ``depth`` over an area): the part of a contact
  line inside the area carries load only once the deflection exceeds the depth; it is a
  separate contact spring with the separation ``depth``;
* **chipped tip corner, broken tooth** (material gone): the part of the contact line over
  the missing material carries nothing;
* **wear** (material removed over the whole active flank, depth a function of the roll
  length): a separation of the intact contact.

The compliance of what remains follows the slicing model: the slices that keep their
material keep the potential-energy compliance of the healthy section (bending, shear,
axial and foundation terms computed per unit face width); a removed part of the face
width removes its slice stiffness. The section change of a spall (a thinner tooth above
and inside the spall) is not in the potential-energy model; the FE check
(:mod:`gearsim.fem.faults`) measures it.

References
----------
.. [Chaari2008] F. Chaari, W. Baccar, M. S. Abbes, M. Haddar, Effect of spalling or tooth
   breakage on gearmesh stiffness and dynamic response of a one-stage spur gear
   transmission, Eur. J. Mech. A/Solids 27 (2008) 691-705.
.. [Saxena2016] A. Saxena, A. Parey, M. Chouksey, Time varying mesh stiffness calculation
   of spur gear pair considering sliding friction and spalling defects, Eng. Fail. Anal.
   70 (2016) 200-211.
.. [Luo2019] Y. Luo, N. Baddour, M. Liang, A shape-independent approach to modelling
   gear tooth spalls for time varying mesh stiffness evaluation of a spur gear pair,
   Mech. Syst. Signal Process. 120 (2019) 836-852.
.. [ISO21771] ISO 21771:2007, Gears - Cylindrical involute gears and gear pairs -
   Concepts and geometry (roll length, involute arc length).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError, require

__all__ = [
    "FAULT_KINDS",
    "MAX_PITS",
    "MIN_PIT_DIAMETER",
    "SHAPES",
    "BrokenTooth",
    "ChippedTip",
    "Fault",
    "Pitting",
    "Spall",
    "Wear",
    "required_fields",
    "fault_from_kind",
]

#: Faults a ``[[faults]]`` table may name with ``kind``.
FAULT_KINDS = ("spall", "pitting", "chip", "broken", "wear")
#: Outlines of a spall.
SHAPES = ("rectangular", "elliptical")
FLANKS = ("working", "non-working")
EDGES = ("start", "end")
#: Smallest pit diameter [m]: micropits (micropitting, ISO/TR 15144) are 10-50 um across.
MIN_PIT_DIAMETER = 1e-5
#: Most pits of one pitting fault: 10 um pits at half coverage of a 2 x 16 mm band are
#: 2e5 (7 s); the pits are flank patches, each costs memory and time.
MAX_PITS = 500_000


def _num(v: object) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def _pos(name: str, v: object, unit: str = "m") -> None:
    require(_num(v) and v > 0, name, v, f"must be a finite number > 0 {unit}")


def _common(kind: str, gear: object, tooth: object, flank: object) -> None:
    require(isinstance(gear, str) and gear != "", f"{kind}.gear", gear, "name the damaged gear")
    require(isinstance(tooth, numbers.Integral) and not isinstance(tooth, bool) and tooth >= 0,
            f"{kind}.tooth", tooth, "must be an integer >= 0")
    require(flank in FLANKS, f"{kind}.flank", flank, 'must be "working" or "non-working"')


@dataclass(frozen=True, kw_only=True)
class Spall:
    """A spall: flank material recessed by ``depth`` over a patch of the flank.

    Parameters
    ----------
    gear : str
        Name of the damaged gear.
    tooth : int
        Tooth index (0 .. z-1).
    flank : {"working", "non-working"}
        Damaged flank (as for :class:`~gearsim.stiffness.crack.Crack`).
    radius : float
        Radius of the centre of the patch on the flank [m].
    length : float
        Extent along the profile (involute arc length) [m].
    width : float
        Extent across the face [m].
    depth : float
        Depth of the recess, normal to the flank [m].
    z : float, optional
        Axial position of the centre from the face edge z = 0 [m]; default mid-face.
    shape : {"rectangular", "elliptical"}
        Outline of the patch on the flank (ellipse: axes ``length`` and ``width``).

    Raises
    ------
    InputError
        If a size is not a finite number > 0, the shape or flank is unknown, or the
        tooth is not an integer >= 0. Whether the patch lies on the active flank and
        inside the face is checked by the train (:class:`gearsim.system.GearTrain`).

    References
    ----------
    Chaari et al. (2008) (rectangular spall as lost contact width); Saxena et al.
    (2016) and Luo et al. (2019) (spall shapes).
    """

    gear: str
    tooth: int = 0
    flank: str = "working"
    radius: float
    length: float
    width: float
    depth: float
    z: float | None = None
    shape: str = "rectangular"

    kind = "spall"

    def __post_init__(self) -> None:
        _common("spall", self.gear, self.tooth, self.flank)
        for name in ("radius", "length", "width", "depth"):
            _pos(f"spall.{name}", getattr(self, name))
        require(self.z is None or (_num(self.z) and self.z >= 0), "spall.z", self.z,
                "must be a finite number >= 0 m (from the face edge z = 0)")
        require(self.shape in SHAPES, "spall.shape", self.shape,
                'must be "rectangular" or "elliptical"')

    def centre_z(self, face_width: float) -> float:
        """Axial position of the centre [m] (mid-face when not given).

        Parameters
        ----------
        face_width : float
            Face width of the gear [m].

        Returns
        -------
        float
        """
        return 0.5 * face_width if self.z is None else float(self.z)

    def patches(self, face_width: float, base_radius: float, rng=None) -> tuple[Patch, ...]:
        """The recessed area as flank patches.

        Parameters
        ----------
        face_width : float
            Face width [m].
        base_radius : float
            Base radius of the gear [m].
        rng : ignored
            Present for a common signature with :meth:`Pitting.patches`.

        Returns
        -------
        tuple of Patch
        """
        s0 = arc_at_radius(self.radius, base_radius)
        return (Patch(s0, self.length, self.centre_z(face_width), self.width, self.depth,
                      self.shape == "elliptical"),)


@dataclass(frozen=True, kw_only=True)
class Pitting:
    """Pitting: many small round pits spread over a band of the flank (seeded).

    The pits are circles of diameter ``pit_diameter`` and depth ``depth``, centres drawn
    uniformly over the band [``radius_min``, ``radius_max``] x face width with the random
    generator seeded by ``seed``, as many as make ``area_fraction`` of the band area
    (overlaps are allowed, so the pitted fraction is slightly below the target: the
    expected covered fraction is 1 - exp(-area_fraction), Poisson coverage).

    Parameters
    ----------
    gear, tooth, flank
        As :class:`Spall`.
    area_fraction : float
        Total pit area / band area, in (0, 1] [-].
    radius_min, radius_max : float
        Radii bounding the pitted band [m] (pitting starts near the pitch line, in the
        dedendum; Ding & Rieger 2003).
    pit_diameter : float
        Pit diameter [m].
    depth : float
        Pit depth [m].
    seed : int
        Seed of the pit positions.

    Raises
    ------
    InputError
        For a non-positive or non-finite size, an area fraction outside (0, 1], or
        ``radius_min >= radius_max``.
    """

    gear: str
    tooth: int = 0
    flank: str = "working"
    area_fraction: float
    radius_min: float
    radius_max: float
    pit_diameter: float = 1e-3
    depth: float = 1e-4
    seed: int = 0

    kind = "pitting"

    def __post_init__(self) -> None:
        _common("pitting", self.gear, self.tooth, self.flank)
        require(_num(self.area_fraction) and 0 < self.area_fraction <= 1,
                "pitting.area_fraction", self.area_fraction, "must be in (0, 1]")
        for name in ("radius_min", "radius_max", "pit_diameter", "depth"):
            _pos(f"pitting.{name}", getattr(self, name))
        require(self.pit_diameter >= MIN_PIT_DIAMETER, "pitting.pit_diameter", self.pit_diameter,
                f"must be >= {MIN_PIT_DIAMETER:g} m (micropits, the smallest fatigue craters)")
        require(self.radius_max > self.radius_min, "pitting.radius_max", self.radius_max,
                f"must be > radius_min = {self.radius_min:g} m")
        require(isinstance(self.seed, numbers.Integral) and not isinstance(self.seed, bool)
                and self.seed >= 0, "pitting.seed", self.seed, "must be an integer >= 0")

    def count(self, face_width: float, base_radius: float) -> int:
        """Number of pits: ``area_fraction`` x band area / pit area, at least 1.

        Parameters
        ----------
        face_width, base_radius : float
            Face width and base radius of the gear [m].

        Returns
        -------
        int
        """
        area = (arc_at_radius(self.radius_max, base_radius)
                - arc_at_radius(self.radius_min, base_radius)) * face_width
        return max(1, round(self.area_fraction * area / (math.pi * self.pit_diameter ** 2 / 4)))

    def patches(self, face_width: float, base_radius: float, rng=None) -> tuple[Patch, ...]:
        """The pits as round flank patches (positions from ``seed``).

        Parameters
        ----------
        face_width, base_radius : float
            Face width and base radius of the gear [m].
        rng : ignored
            The generator is made from :attr:`seed`.

        Returns
        -------
        tuple of Patch
        """
        n = self.count(face_width, base_radius)
        s_lo = arc_at_radius(self.radius_min, base_radius)
        s_hi = arc_at_radius(self.radius_max, base_radius)
        gen = np.random.default_rng(self.seed)
        s = gen.uniform(s_lo, s_hi, n)
        z = gen.uniform(0.0, face_width, n)
        d = self.pit_diameter
        return tuple(Patch(float(a), d, float(b), d, self.depth, True) for a, b in zip(s, z, strict=True))


@dataclass(frozen=True, kw_only=True)
class ChippedTip:
    """A chipped tip corner: the tooth tip missing over a corner of the face.

    The chip removes the flank above the arc-length position ``length`` below the tip
    (along the profile) over ``width`` of the face from the edge ``edge`` (z = 0:
    ``"start"``, z = b: ``"end"``); a rectangular corner on the developed flank.

    Parameters
    ----------
    gear : str
        Name of the damaged gear.
    tooth : int
        Tooth index.
    flank : {"working", "non-working"}
        The flank whose tip corner is gone.
    length : float
        Extent along the profile from the tip (involute arc length) [m].
    width : float
        Extent across the face from ``edge`` [m].
    edge : {"start", "end"}
        The face edge of the corner.

    Raises
    ------
    InputError
        For a non-positive size or an unknown edge or flank.
    """

    gear: str
    tooth: int = 0
    flank: str = "working"
    length: float
    width: float
    edge: str = "start"

    kind = "chip"

    def __post_init__(self) -> None:
        _common("chip", self.gear, self.tooth, self.flank)
        _pos("chip.length", self.length)
        _pos("chip.width", self.width)
        require(self.edge in EDGES, "chip.edge", self.edge, 'must be "start" or "end"')

    def patches(self, face_width: float, base_radius: float, rng=None,
                tip_radius: float | None = None) -> tuple[Patch, ...]:
        """The missing corner as one patch of infinite depth.

        Parameters
        ----------
        face_width, base_radius, rng
            As :meth:`Spall.patches`.
        tip_radius : float
            Tip radius of the gear [m].

        Returns
        -------
        tuple of Patch
        """
        s_tip = arc_at_radius(tip_radius, base_radius)
        w = min(self.width, face_width)
        zc = 0.5 * w if self.edge == "start" else face_width - 0.5 * w
        # centre a length-2L patch on the tip so that it covers [s_tip - L, s_tip + L]
        return (Patch(s_tip, 2 * self.length, zc, w, math.inf, False),)


@dataclass(frozen=True, kw_only=True)
class BrokenTooth:
    """A broken tooth: the tooth gone over the whole face or part of it.

    Parameters
    ----------
    gear : str
        Name of the damaged gear.
    tooth : int
        Tooth index.
    width : float, optional
        Broken part of the face from ``edge`` [m]; default the whole face.
    edge : {"start", "end"}
        The face edge the break starts from.
    break_radius : float, optional
        Radius where the break line meets the fillet [m] (the FE outline of
        :mod:`gearsim.fem.faults` cuts the tooth there); default the 30 deg tangent
        point of ISO 6336-3. Must lie on the fillet (checked by the train).
    flank : str
        Not used: a broken tooth is gone on both flanks (kept for a common interface).

    Raises
    ------
    InputError
        For a non-positive width or break radius, or an unknown edge.

    References
    ----------
    Chaari et al. (2008) (tooth breakage as lost contact width).
    """

    gear: str
    tooth: int = 0
    width: float | None = None
    edge: str = "start"
    break_radius: float | None = None
    flank: str = field(default="working", repr=False)

    kind = "broken"

    def __post_init__(self) -> None:
        _common("broken", self.gear, self.tooth, self.flank)
        require(self.width is None or (_num(self.width) and self.width > 0), "broken.width",
                self.width, "must be a finite number > 0 m (or left out: the whole face)")
        require(self.break_radius is None or (_num(self.break_radius) and self.break_radius > 0),
                "broken.break_radius", self.break_radius, "must be a finite number > 0 m")
        require(self.edge in EDGES, "broken.edge", self.edge, 'must be "start" or "end"')

    def patches(self, face_width: float, base_radius: float, rng=None) -> tuple[Patch, ...]:
        """The missing tooth as one patch of infinite depth over the whole flank.

        Parameters
        ----------
        face_width, base_radius, rng
            As :meth:`Spall.patches`.

        Returns
        -------
        tuple of Patch
        """
        w = face_width if self.width is None else min(self.width, face_width)
        zc = 0.5 * w if self.edge == "start" else face_width - 0.5 * w
        return (Patch(0.0, math.inf, zc, w, math.inf, False),)


@dataclass(frozen=True, kw_only=True)
class Wear:
    """Wear: flank material removed with a depth that varies along the profile.

    Either a depth profile (``radii``, ``depths``; linear between the points, zero
    outside) or grown by Archard's law (``coefficient``, ``cycles``; computed by
    :func:`gearsim.stiffness.wear.archard_wear` from the sliding distance and the contact
    pressure of the loaded mesh).

    Parameters
    ----------
    gear : str
        Name of the worn gear.
    tooth : int or None
        Tooth index, or None: every tooth (uniform wear).
    flank : {"working", "non-working"}
        Worn flank.
    radii : tuple of float
        Radii of the depth profile points [m], increasing.
    depths : tuple of float
        Wear depth at those radii [m], >= 0.
    coefficient : float, optional
        Archard dimensional wear coefficient k [m^2/N] (Flodin & Andersson 1997).
    cycles : float, optional
        Number of load cycles of the worn tooth for the Archard law [-].

    Raises
    ------
    InputError
        If neither or both of (radii, depths) and (coefficient, cycles) are given, or a
        value is out of range.
    """

    gear: str
    tooth: int | None = None
    flank: str = "working"
    radii: tuple[float, ...] = ()
    depths: tuple[float, ...] = ()
    coefficient: float | None = None
    cycles: float | None = None

    kind = "wear"

    def __post_init__(self) -> None:
        _common("wear", self.gear, 0 if self.tooth is None else self.tooth, self.flank)
        given = bool(self.radii) or bool(self.depths)
        archard = self.coefficient is not None or self.cycles is not None
        require(given != archard, "wear", "radii/depths" if given else "nothing",
                "give either radii and depths or coefficient and cycles (Archard)")
        if given:
            require(len(self.radii) == len(self.depths) and len(self.radii) >= 2,
                    "wear.depths", len(self.depths),
                    f"need one depth per radius and at least 2 points ({len(self.radii)} radii)")
            for r in self.radii:
                _pos("wear.radii", r)
            for d in self.depths:
                require(_num(d) and d >= 0, "wear.depths", d, "must be finite numbers >= 0 m")
            require(all(b > a for a, b in zip(self.radii, self.radii[1:], strict=False)), "wear.radii",
                    list(self.radii), "must increase")
        else:
            _pos("wear.coefficient", self.coefficient, "m^2/N")
            _pos("wear.cycles", self.cycles, "cycles")

    @property
    def grown(self) -> bool:
        """True when the depth is grown by Archard's law."""
        return self.coefficient is not None


Fault = Spall | Pitting | ChippedTip | BrokenTooth | Wear

_CLASSES = {"spall": Spall, "pitting": Pitting, "chip": ChippedTip, "broken": BrokenTooth,
            "wear": Wear}


def required_fields(kind: str) -> tuple[str, ...]:
    """The fields a fault of ``kind`` must be given (those without a default).

    Parameters
    ----------
    kind : str
        One of :data:`FAULT_KINDS`.

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> required_fields("spall")
    ('gear', 'radius', 'length', 'width', 'depth')
    """
    return tuple(f.name for f in dataclasses.fields(_CLASSES[kind])
                 if f.default is dataclasses.MISSING
                 and f.default_factory is dataclasses.MISSING)


def fault_from_kind(kind: str, **kw) -> Fault:
    """Make the fault named by ``kind`` from its keyword fields.

    Parameters
    ----------
    kind : str
        One of :data:`FAULT_KINDS`.
    **kw
        Fields of that fault class (SI units).

    Returns
    -------
    Fault

    Raises
    ------
    InputError
        For an unknown kind.
    """
    if kind not in _CLASSES:
        raise InputError("faults.kind", kind, "must be one of " + ", ".join(FAULT_KINDS))
    return _CLASSES[kind](**kw)


@dataclass(frozen=True)
class Patch:
    """A damaged patch of a flank in developed coordinates.

    Parameters
    ----------
    s : float
        Centre along the profile, involute arc length from the base circle [m].
    length : float
        Extent along the profile [m] (inf: the whole profile).
    z : float
        Centre across the face [m].
    width : float
        Extent across the face [m].
    depth : float
        Depth of the recess [m]; inf: material gone (no contact).
    elliptical : bool
        Ellipse with axes (length, width) instead of a rectangle.
    """

    s: float
    length: float
    z: float
    width: float
    depth: float
    elliptical: bool

    def covered(self, s: np.ndarray, z0: np.ndarray, z1: np.ndarray) -> np.ndarray:
        """Fraction of the face interval [z0, z1] covered at profile positions ``s`` [-].

        Parameters
        ----------
        s : ndarray
            Arc-length positions of the contact line [m].
        z0, z1 : ndarray
            Ends of the face interval of each slice [m] (broadcast with ``s``).

        Returns
        -------
        ndarray
            Covered fraction in [0, 1].
        """
        ds = np.abs(np.asarray(s, dtype=float) - self.s)
        half_l = 0.5 * self.length
        inside = ds <= half_l
        if self.elliptical:
            with np.errstate(invalid="ignore"):
                half_w = 0.5 * self.width * np.sqrt(np.clip(1.0 - (ds / half_l) ** 2, 0.0, 1.0))
        else:
            half_w = np.full(np.shape(ds), 0.5 * self.width)
        lo = np.maximum(z0, self.z - half_w)
        hi = np.minimum(z1, self.z + half_w)
        frac = np.clip((hi - lo) / (z1 - z0), 0.0, 1.0)
        return np.where(inside, frac, 0.0)


def arc_at_radius(radius: float, base_radius: float) -> float:
    """Involute arc length from the base circle to ``radius``, rho^2 / (2 r_b) [m].

    Parameters
    ----------
    radius : float
        Radius on the involute [m] (>= r_b).
    base_radius : float
        Base radius r_b [m].

    Returns
    -------
    float
        s = (r^2 - r_b^2) / (2 r_b) [m].

    References
    ----------
    ISO 21771:2007 (involute: the arc length grows with the square of the roll length).

    Examples
    --------
    r_b = 1, r = sqrt(2): rho = 1, s = 0.5.

    >>> round(arc_at_radius(2 ** 0.5, 1.0), 12)
    0.5
    """
    return max(radius * radius - base_radius * base_radius, 0.0) / (2.0 * base_radius)
