"""Time-varying mesh stiffness of the internal ring-planet mesh (potential energy method).

The mesh of a planet (gear 1) with the ring (gear 2, an internal gear) is computed like an
external mesh (:func:`gearsim.stiffness.mesh.mesh_stiffness`): the same slicing of a
helical face width, the same in-path sampling, each slice a series of the Hertz contact,
the planet tooth and the ring tooth, slices and tooth pairs in parallel:

    1/k_slice = [1/k_h + sum_(b, s, a, f) 1/k_planet + sum_(b, s, a, f) 1/k_ring] / w_slice

with the planet tooth of :class:`gearsim.stiffness.tooth.ToothModel` (cracks included,
on either flank) and the ring tooth of :class:`gearsim.stiffness.ring.RingToothModel`
(Chen & Shao 2013: the internal tooth as a cantilever on the root circle; Liang, Zuo &
Pandey 2014). The Hertz term is the seed's load-independent line-contact stiffness
(Yang & Sun 1985), which does not depend on the curvatures.

The accurate model (``source = "calibrated"``, ``contact = "line"``, ``coupling = "fe"``;
docs/planetary.md 4.4) takes the law of the external meshes
(:func:`gearsim.stiffness.mesh.slice_law`): the planet tooth calibrated by its FE tooth
(:class:`gearsim.fem.calibration.CalibratedCompliance`; a planet crack on the flank the
ring loads with its measured crack correction), the ring tooth corrected by the
FE ring segment (:class:`gearsim.fem.calibration.CalibratedRingTooth`), both passed in by
the caller (the system layer) since ``stiffness`` does not import ``fem``; the 2D line
contact of :func:`gearsim.stiffness.tooth.line_contact_compliance` with the relative
curvature of a convex-concave pair,

    1/R = 1/rho_planet - 1/rho_ring,  rho_planet = s,  rho_ring = s + a_rp sin alpha_w,rp

(the involutes' radii of curvature are the distances from the contact to the tangent
points; Johnson 1985, section 4.2: the radius of a concave surface counts negative), up
to the tooth centre lines on both sides (planet:
:func:`gearsim.stiffness.mesh.centre_line_depth`; ring:
:meth:`gearsim.stiffness.ring.RingToothModel.centre_line_depth`); and the coupling of the
two loaded neighbouring teeth through the planet's body (:mod:`gearsim.fem.coupling`)
and through the ring's rim (the FE ring segment's cross compliance).

Geometry (ISO 21771, internal pair; :class:`gearsim.geometry.planetary.PlanetaryStage`).
Positions s on the transverse line of action are measured from the tangent point T_p on
the planet's base circle; both tangent points lie on the same side of the pitch point, so
a contact at s has the radii

    r_planet = sqrt(r_b,p^2 + s^2),  r_ring = sqrt(r_b,r^2 + (s + a_rp sin alpha_w,rp)^2)

and the path of contact runs from the ring's (inner) tip circle,
s_a = sqrt(r_a,r^2 - r_b,r^2) - a_rp sin alpha_w,rp, to the planet's tip circle,
s_e = sqrt(r_a,p^2 - r_b,p^2). A contact enters at s_a (near the planet root) and leaves at
s_e when the planet drives the ring, which is the sense of the table: pair age m at
position u of a cycle is at s_a + (u + m) p_bt - z tan(beta_b), with planet tooth
(c - m) mod z_p and ring tooth (c - m) mod z_r in cycle c.

References
----------
.. [ChenShao2013] Z. Chen, Y. Shao, Mesh stiffness of an internal spur gear pair with ring
   gear rim deformation, Mech. Mach. Theory 69 (2013) 1-12.
.. [Liang2014] X. Liang, M. J. Zuo, M. Pandey, Analytical evaluation of time-varying mesh
   stiffness for planetary gear sets, Mech. Mach. Theory 76 (2014) 20-38.
.. [ISO21771] ISO 21771:2007 (internal gear pairs).
.. [Johnson1985] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985,
   sections 4.2 (relative curvature, concave radius negative) and 5.6 (line contact).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.mesh import (
    COMPONENTS,
    MeshStiffness,
    assemble_revolution,
    centre_line_depth,
    slice_grid,
    slice_law,
)
from gearsim.stiffness.ring import RingToothModel
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCompliance, ToothCrack
from gearsim.stiffness.tooth import hertz_stiffness, line_contact_compliance

__all__ = ["InternalMesh", "check_internal_settings", "internal_mesh_stiffness"]


@dataclass(frozen=True)
class InternalMesh:
    """Line-of-action geometry of the ring-planet mesh of a stage.

    Parameters
    ----------
    stage : PlanetaryStage
        The stage.

    Raises
    ------
    InputError
        If the ring's tip circle cuts the planet below its form circle (the contact would
        reach the planet's fillet: tip interference of the internal pair).

    Examples
    --------
    z 30/24/78, m 2 mm, ring addendum 0.8 m: the path of contact over the base pitch is
    the contact ratio of the stage; with the full addendum the ring's tip would reach
    the planet's fillet and the mesh is refused:

    >>> from gearsim.geometry.planetary import PlanetaryStage
    >>> st = PlanetaryStage(30, 24, 78, 2e-3, planets=4, ring_addendum_coefficient=0.8)
    >>> mesh = InternalMesh(st)
    >>> round((mesh.end - mesh.start) / st.base_pitch, 4) == round(st.ring_planet_contact_ratio, 4)
    True
    >>> InternalMesh(PlanetaryStage(30, 24, 78, 2e-3, planets=4))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: stage: ring-planet mesh = ring tip circle 76 mm: reaches ...
    """

    stage: PlanetaryStage

    def __post_init__(self) -> None:
        p = self.stage.planet
        form = ToothProfile(p).form_radius
        s_form = math.sqrt(max(form**2 - p.base_radius**2, 0.0))
        require(self.start >= s_form - 1e-12, "stage: ring-planet mesh", (
            f"ring tip circle {self.stage.ring.tip_radius * 1e3:.6g} mm"),
            f"reaches the planet below its form circle ({form * 1e3:.6g} mm): contact on the "
            f"planet's fillet (start of contact {self.start * 1e3:.4g} mm < "
            f"{s_form * 1e3:.4g} mm from T_p); reduce the ring addendum or shift the gears")

    @property
    def offset(self) -> float:
        """Distance T_p T_r between the tangent points, a_rp sin(alpha_w,rp) [m]."""
        return self.stage.ring_planet_line_of_action

    @property
    def start(self) -> float:
        """Start of contact s_a (ring tip circle), from T_p [m]."""
        r = self.stage.ring
        return math.sqrt(r.tip_radius**2 - r.base_radius**2) - self.offset

    @property
    def end(self) -> float:
        """End of contact s_e (planet tip circle), from T_p [m]."""
        p = self.stage.planet
        return math.sqrt(p.tip_radius**2 - p.base_radius**2)

    @property
    def pitch_point(self) -> float:
        """Pitch point r_b,p tan(alpha_w,rp), from T_p [m]."""
        return self.stage.planet.base_radius * math.tan(self.stage.ring_planet_pressure_angle)

    def radii(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Contact radii on planet and ring at positions ``s`` from T_p [m].

        Parameters
        ----------
        s : ndarray
            Positions on the transverse line of action [m].

        Returns
        -------
        r_planet, r_ring : ndarray
            [m], the shape of ``s``.
        """
        s = np.asarray(s, dtype=float)
        return (np.hypot(self.stage.planet.base_radius, s),
                np.hypot(self.stage.ring.base_radius, s + self.offset))


def check_internal_settings(settings: StiffnessSettings) -> None:
    """Refuse the stiffness options a stage's internal mesh does not model.

    Parameters
    ----------
    settings : StiffnessSettings
        The options.

    Raises
    ------
    InputError
        If ``source`` is not ``"pe"`` or ``"calibrated"`` (a stage has no FE tooth
        tables of the ring nor an FE internal gear pair).
    """
    require(settings.source in ("pe", "calibrated"), "stiffness.source", settings.source,
            'the internal (ring-planet) mesh of a stage has the potential-energy ("pe") or '
            'the calibrated tooth ("calibrated") only')


def internal_mesh_stiffness(stage: PlanetaryStage, *, cracks: tuple[ToothCrack, ...] = (),
                            settings: StiffnessSettings | None = None,
                            revolution_of: int = 1, ring_foundation: str = "none",
                            ring_tooth: Callable[[np.ndarray], np.ndarray] | None = None,
                            name: str = "ring-planet",
                            compliance: ToothCompliance | None = None,
                            ring_model=None, force: float | None = None, coupling=None,
                            ring_coupling=None) -> MeshStiffness:
    """TVMS of the ring-planet mesh over one revolution of the planet (1) or ring (2).

    Parameters
    ----------
    stage
        The planetary stage.
    cracks
        Cracks as the mesh sees them: ``gear`` 1 the planet (either flank, ``side``
        +1 when the cracked flank is the one the ring loads), 2 the ring (on the flank
        the planets load, ``side`` +1; :meth:`RingToothModel.compliance` with the
        crack's depth in each face-width slice; needs ``revolution_of = 2``).
    settings
        Options (positions per cycle, slices, closure, plane, Gauss points, ``source``
        of the planet tooth, ``contact``, ``coupling``); default the seed's.
    revolution_of
        1: z_p mesh cycles (a planet revolution relative to the carrier); 2: z_r cycles.
    ring_foundation
        Foundation term of the PE ring tooth (:class:`gearsim.stiffness.ring.
        RingToothModel`): ``"none"`` (default; the tooth clamped on its root circle, Chen
        & Shao 2013) or ``"sainsot-solid"`` (docs/planetary.md section 4.3 for why it is
        not the default). Not with ``ring_model`` or ``ring_tooth``.
    ring_tooth
        Another healthy ring-tooth model: a function of contact radii [m] (1-D array)
        returning the compliances times width [m^2/N], shape (n, 4): bending, shear,
        axial, foundation (for example one interpolated from :mod:`gearsim.fem.ring`).
        Replaces the potential-energy tooth; no ring crack.
    name
        Mesh name written into the table.
    compliance
        The planet's tooth model (:class:`gearsim.stiffness.source.ToothCompliance`),
        whose ``name`` must be ``settings.source``; default the potential-energy tooth.
        The calibrated one is :class:`gearsim.fem.calibration.CalibratedCompliance`.
    ring_model
        Another ring-tooth model with the method ``compliance(radii, *, crack_depth,
        crack_angle)`` of :class:`~gearsim.stiffness.ring.RingToothModel`, used for the
        healthy and a cracked ring tooth (the calibrated ring tooth,
        :class:`gearsim.fem.calibration.CalibratedRingTooth`).
    force
        Transverse line-of-action force of the mesh [N]; needed by ``contact = "line"``.
    coupling
        Body coupling of the planet, ``cross(gear, r_read, r_load)`` [m^2/N]
        (:class:`gearsim.fem.coupling.FiniteElementCoupling`); needed by ``coupling =
        "fe"``.
    ring_coupling
        Rim coupling of the ring teeth, ``cross(r_read, r_load)`` [m^2/N], the load on the
        read tooth's loaded-flank-side neighbour (:class:`gearsim.fem.calibration.
        CalibratedRingTooth`); needed by ``coupling = "fe"``.

    Returns
    -------
    MeshStiffness
        Stiffness along the transverse line of action [N/m] per position; components
        ``hertz`` (the contact law's), ``*_1`` the planet, ``*_2`` the ring; pair
        stiffnesses and teeth (the components leave the coupling out).

    Raises
    ------
    InputError
        If ``source`` is ``"fe-pair"`` or names another model than ``compliance``, the
        line contact has no force, the coupling no model, a crack is on a tooth the gear
        does not have, a ring crack is on the other flank or with a ``ring_tooth``.

    References
    ----------
    Chen & Shao (2013); Liang, Zuo & Pandey (2014); Johnson (1985); docs/planetary.md
    section 4.

    Examples
    --------
    >>> from gearsim.geometry.planetary import PlanetaryStage
    >>> st = PlanetaryStage(30, 24, 78, 2e-3, planets=4, ring_addendum_coefficient=0.8)
    >>> ms = internal_mesh_stiffness(st, settings=StiffnessSettings(positions_per_cycle=20))
    >>> ms.k.size, round(ms.mean / 1e9, 2)
    (480, 0.63)
    """
    settings = settings or StiffnessSettings()
    require(settings.source != "fe-pair", "stiffness.source", settings.source,
            "the FE gear pair is external only: the internal mesh takes a tooth model")
    model = compliance if compliance is not None else PotentialEnergyCompliance()
    require(model.name == settings.source, "stiffness.source", settings.source,
            f"the planet's tooth model passed is {model.name!r}: pass the model the settings "
            "name (gearsim.system.planetary builds it)")
    require(revolution_of in (1, 2), "revolution_of", revolution_of, "must be 1 or 2")
    require(ring_model is None or ring_tooth is None, "ring_model", "given",
            "give either ring_model or ring_tooth")
    planet, ring = stage.planet, stage.ring
    for tc in cracks:
        require(tc.gear in (1, 2), "crack.gear", tc.gear, "must be 1 (planet) or 2 (ring)")
        z = planet.teeth if tc.gear == 1 else ring.teeth
        require(tc.crack.tooth < z, "crack.tooth", tc.crack.tooth,
                f"must be < {z} (teeth of the {'planet' if tc.gear == 1 else 'ring'})")
        if tc.gear == 2:
            require(tc.side == 1, "crack.flank", tc.crack.flank,
                    "a ring crack is modelled on the flank the planets load (the tension "
                    "side); the other flank's root is in compression")
            require(ring_tooth is None, "ring_tooth", "given",
                    "a cracked ring needs a ring-tooth model with cracks (ring_model or the "
                    "potential-energy ring tooth)")
    ring_cracks = [tc for tc in cracks if tc.gear == 2]
    require(len(ring_cracks) <= 1, "cracks", len(ring_cracks), "at most one ring crack")
    require(not ring_cracks or revolution_of == 2, "revolution_of", revolution_of,
            "a cracked ring needs the table over a ring revolution (revolution_of = 2)")
    line = settings.contact == "line"
    if line:
        require(force is not None and math.isfinite(force) and force > 0, "force", force,
                'the line contact law (stiffness.contact = "line") needs the mesh force, '
                "a finite number > 0 N")
    if settings.coupling != "none":
        require(coupling is not None and hasattr(coupling, "cross")
                and ring_coupling is not None and hasattr(ring_coupling, "cross"),
                "stiffness.coupling", settings.coupling,
                "the internal mesh needs the planet's body coupling (coupling=) and the "
                "ring's rim coupling (ring_coupling=): use gearsim.system.planetary")
    geo = InternalMesh(stage)
    tb = math.tan(planet.base_helix_angle)
    lmid, frac, dz, n_age, ns, zfrac = slice_grid(tb, stage.face_width, stage.base_pitch,
                                                  geo.start, geo.end, settings)
    npc = settings.positions_per_cycle
    inside = frac > 0
    rp, rr = geo.radii(lmid)
    rp = np.where(inside, rp, 0.0)
    rr = np.where(inside, np.clip(rr, ring.tip_radius, ring.root_radius), ring.tip_radius)
    healthy1 = model.compliance(planet, rp, None, zfrac, settings)
    cracked1 = {tc.crack.tooth: model.compliance(planet, rp, tc, zfrac, settings)
                for tc in cracks if tc.gear == 1}
    pe_ring = RingToothModel(ring, material=stage.material, plane=settings.plane,
                             foundation=ring_foundation, gauss_points=settings.gauss_points)
    if ring_model is not None or ring_tooth is not None:
        require(ring_foundation == "none", "ring_foundation", ring_foundation,
                "belongs to the potential-energy ring tooth: leave it out with another "
                "ring-tooth model")
    rt = pe_ring if ring_model is None else ring_model
    if ring_tooth is None:
        ring_label = ring_foundation if ring_model is None else getattr(
            ring_model, "name", "user")
        ring_tooth = rt.compliance
    else:
        ring_label = "user"
    c2r = np.asarray(ring_tooth(rr.ravel()), dtype=float)
    require(c2r.shape == (rr.size, 4) and bool(np.all(np.isfinite(c2r))), "ring_tooth",
            c2r.shape, f"must return finite compliances of shape ({rr.size}, 4)")
    c2 = np.where(inside[..., None], c2r.reshape(rr.shape + (4,)), 0.0)
    cracked2: dict[int, np.ndarray] = {}
    for tc in ring_cracks:  # per face-width slice, the crack's depth there
        depth = tc.crack.depth_at(zfrac)
        cc = np.empty(rr.shape + (4,))
        for j in range(ns):
            cc[:, :, j] = rt.compliance(rr[:, :, j].ravel(), crack_depth=float(depth[j]),
                                        crack_angle=tc.crack.angle).reshape(
                rr.shape[:2] + (4,))
        cracked2[tc.crack.tooth] = np.where(inside[..., None], cc, 0.0)
    ch = 1.0 / hertz_stiffness(stage.material, stage.material, 1.0)
    width = frac * dz
    contact = None
    if line:
        # convex planet against the concave ring: 1/R = 1/rho_p - 1/rho_r (Johnson 1985,
        # 4.2), the ring's radius of curvature entered negative
        rho1 = np.where(inside, lmid, 1.0)
        rho2 = np.where(inside, -(lmid + geo.offset), -2.0)
        dep1 = np.where(inside, centre_line_depth(planet, np.where(inside, rp,
                                                                    planet.base_radius)), 1.0)
        dep2 = np.where(inside, pe_ring.centre_line_depth(rr.ravel()).reshape(rr.shape), 1.0)

        def contact(q: np.ndarray) -> np.ndarray:
            return line_contact_compliance(np.maximum(q, 1e-3), rho1, rho2, dep1, dep2,
                                           stage.material, stage.material, settings.plane)
    cross = None
    if settings.coupling != "none":
        # the planet drives: its older pair (age m + 1) is the +x neighbour of the tooth of
        # age m; the ring is driven: its older pair is the -x neighbour, i.e. the tooth of
        # age m is the loaded-flank-side (+x) neighbour of the tooth of age m + 1
        both = inside[:, :-1] & inside[:, 1:]
        x1 = np.where(both, coupling.cross(planet, np.where(both, rp[:, :-1], planet.tip_radius),
                                           np.where(both, rp[:, 1:], planet.tip_radius)), 0.0)
        x2 = np.where(both, ring_coupling.cross(np.where(both, rr[:, 1:], ring.tip_radius),
                                                np.where(both, rr[:, :-1], ring.tip_radius)),
                      0.0)
        cross = x1 + x2
    z_rev = planet.teeth if revolution_of == 1 else ring.teeth
    n_pos = z_rev * npc
    k, comp, pair_k, t1, t2 = assemble_revolution(
        (planet.teeth, ring.teeth), z_rev, npc, (healthy1, c2), (cracked1, cracked2), width,
        slice_law(width, ch, cross, contact, force))
    cycles = np.arange(n_pos) / npc
    return MeshStiffness(
        name=name, revolution_of="planet" if revolution_of == 1 else "ring", cycles=cycles,
        theta1=2 * math.pi * cycles / planet.teeth, theta2=2 * math.pi * cycles / ring.teeth,
        k=k, components={nm: comp[:, q] for q, nm in enumerate(COMPONENTS)}, pair_k=pair_k,
        pair_tooth1=t1, pair_tooth2=t2,
        attrs={"closure": settings.closure, "slices": ns, "positions_per_cycle": npc,
               "plane": settings.plane, "gauss_points": settings.gauss_points,
               "source": model.name, "contact": settings.contact,
               "coupling": settings.coupling, "ring_foundation": ring_label, "internal": 1,
               **({"force": float(force)} if line else {})})
