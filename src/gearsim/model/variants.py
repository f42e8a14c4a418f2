"""Fault variants of a gearbox, one per fault class, sized by one severity number.

The multi-class diagnostic study and the reproduction's fault-magnitude section need
every fault type on the same footing: :func:`fault_variant` puts one fault of class
``kind`` on tooth 0 of the input gear (the gear of the seed's crack), with its size set
by ``severity`` in (0, 1] as a fraction of a reference size taken from the gear itself
(module, face width, active flank, ISO 1328-1 tolerances), so that the same call works
for any train:

============== ==========================================================================
class          fault at severity s (input gear, tooth 0, working flank)
============== ==========================================================================
none           healthy
working        root crack on the working flank, depth s x 2 mm x m_n / 6 mm (the
               default crack, 2 mm at the Table-1 module, at s = 1)
non-working    the same crack on the non-working flank
spall          rectangular spall at the pitch circle, mid-face: length s x 0.5 x active
               profile arc, width s x 0.5 b, depth 0.05 m_n
pitting        pits of 0.1 m_n diameter and 0.02 m_n depth over the dedendum half of
               the active flank, area fraction 0.3 s (seed 0)
chip           chipped tip corner at z = 0: length s x 0.4 x active profile arc from
               the tip, width s x 0.5 b
broken         broken tooth over s x b of the face (s = 1: the whole tooth)
pitch          tooth 0 behind its position by s x 4 f_pT (ISO 1328-1 grade 6)
eccentricity   runout of the input gear s x 4 f_pT (grade 6), phase 0
============== ==========================================================================

References
----------
ISO 1328-1:2013 (f_pT); the fault models: :mod:`gearsim.stiffness.faults`,
:mod:`gearsim.stiffness.crack`; runout: :mod:`gearsim.dynamics.lta`.
"""

from __future__ import annotations

import dataclasses
import math

from gearsim.dynamics.compose import stage_prefix
from gearsim.errors import require
from gearsim.model.gearbox import Gearbox
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.faults import BrokenTooth, ChippedTip, Pitting, Spall, arc_at_radius
from gearsim.stiffness.modifications import Modification, single_pitch_tolerance
from gearsim.system.faults import active_roll_range
from gearsim.system.planetary import PlanetaryTrain, planet_name
from gearsim.system.train import DEFAULT_CRACK

__all__ = ["FAULT_CLASSES", "fault_gears", "fault_variant"]

#: Fault classes of :func:`fault_variant` (``none`` = healthy).
FAULT_CLASSES = ("none", "working", "non-working", "spall", "pitting", "chip", "broken",
                 "pitch", "eccentricity")


def fault_gears(gearbox: Gearbox) -> tuple[str, ...]:
    """The gears :func:`fault_variant` can put a fault class on, by name.

    Parameters
    ----------
    gearbox : Gearbox
        The base gearbox.

    Returns
    -------
    tuple of str
        Every gear of the parallel shafts, then every stage member (``sun``, ``ring``,
        ``planet-1``, ...; prefixed ``stage<k>-`` with stages in series).

    Examples
    --------
    >>> import gearsim as gs
    >>> fault_gears(gs.example("nrel-grc"))
    ('sun', 'ring', 'planet-1', 'planet-2', 'planet-3')
    """
    return (*(g.name for t in gearbox.chains for g in t.gears), *_stage_members(gearbox))


def fault_variant(gearbox: Gearbox, kind: str, severity: float = 1.0, *,
                  gear: str | None = None) -> Gearbox:
    """The gearbox with one fault of class ``kind`` on tooth 0 of a gear (the input gear
    unless named).

    Every other crack and fault of ``gearbox`` is removed first (the variant has one
    fault); its modifications are kept. Every variant, the healthy one included, runs its
    meshes as meshes of contacts (``dynamics.contact_mesh``, with the stiffness
    options' tip-corner contacts), so that the classes differ by their fault only and
    not by the mesh model (the tip-corner contacts alone change a spur pair's
    vibration markedly).

    Parameters
    ----------
    gearbox : Gearbox
        The base gearbox.
    kind : str
        One of :data:`FAULT_CLASSES` (module docstring: the size at each severity).
    severity : float
        Fraction of the reference size, in (0, 1].
    gear : str, optional
        Name of the faulty gear (any gear of the train, e.g. ``"intermediate-pinion"``
        of the two-stage reducer); its own module, face width, flank and tolerance set
        the sizes. Default: the input gear. A gearbox with planetary stages takes the
        classes on a named gear (:func:`fault_gears`): a gear of its parallel stages
        (``"intermediate-pinion"`` of wind-turbine-grc) or a stage member (``"sun"``,
        ``"planet-2"``, ``"ring"``; sized by the member's own module, face width and
        active flank in the sun-planet mesh, the flank the sun loads; the ring takes the
        cracks only, a planet no broken tooth, no member a pitch error: refused in one
        line); the stages and the gears keep no other crack or fault, and
        ``eccentricity`` is not among its classes there. Every variant, the healthy one
        included, runs the stages' sun-planet meshes as meshes of contacts (the
        stage's ``contacts``; its tables and contacts differ by 5 % in the ring sensor's
        RMS on a 27/35/97 stage, more than a spall on its sun), so that a member's
        class differs by its fault only; and the gears' meshes too (``contact_mesh``:
        a spall on the input pinion of that box raised the sensor's RMS by 6.5 %
        against a healthy case on tables, 5.5 % of it from the mesh model).

    Returns
    -------
    Gearbox
        The variant (checked where it is made, like any train).

    Raises
    ------
    InputError
        For an unknown class or gear, or a severity outside (0, 1]; on a gearbox with
        planetary stages, no gear, ``eccentricity``, or a class its member does not
        model.

    Examples
    --------
    >>> import gearsim as gs
    >>> gb = fault_variant(gs.example("idler-table1"), "broken", 0.5)
    >>> f = gb.train.faults[0]
    >>> f.kind, f.gear, f.tooth, round(f.width * 1e3, 3)
    ('broken', 'input', 0, 75.0)
    >>> c = fault_variant(gs.example("two-stage-reducer"), "working",
    ...                   gear="intermediate-pinion").train.cracks[0]
    >>> c.gear, c.flank
    ('intermediate-pinion', 'working')
    """
    require(kind in FAULT_CLASSES, "fault", kind, "must be one of " + ", ".join(FAULT_CLASSES))
    require(isinstance(severity, (int, float)) and not isinstance(severity, bool)
            and math.isfinite(severity) and 0 < severity <= 1, "severity", severity,
            "must be a number in (0, 1]")
    if gearbox.stage is not None:  # a gear of the parallel stages beside the planetary ones
        return _beside_stages(gearbox, kind, float(severity), gear, dataclasses.replace(
            gearbox.dynamics, contact_mesh=bool(gearbox.chains)))
    dyn = dataclasses.replace(gearbox.dynamics, runout=(0.0,), contact_mesh=True)
    s = float(severity)
    base = gearbox.train.with_crack("none").with_faults(())
    names = [x.name for x in base.gears]
    require(gear is None or gear in names, "gear", gear,
            "is not a gear of the train; its gears: " + ", ".join(names))
    train, dyn = _with_fault(base, kind, s, gear, dyn)
    return dataclasses.replace(gearbox, train=train, dynamics=dyn)


def _beside_stages(gearbox: Gearbox, kind: str, s: float, gear: str | None,
                   dyn) -> Gearbox:
    """:func:`fault_variant` of a gearbox with planetary stages: every stage and chain
    without cracks and faults, the fault on ``gear``: a gear of the chain holding it, or
    a stage member (:func:`_stage_members`)."""
    names = [g.name for t in gearbox.chains for g in t.gears]
    members = _stage_members(gearbox)
    require(gear in names or gear in members or (kind == "none" and gear is None), "gear",
            gear, "a gearbox with planetary stages takes the fault classes on a named gear: "
            "of its parallel stages (" + (", ".join(names) or "it has none")
            + ") or a stage member (" + ", ".join(members) + ")")
    require(kind != "eccentricity", "fault", kind, "the runout of a gear beside a "
            "planetary stage, or of a stage member, is not among its fault classes")
    require(gear not in members or kind != "pitch", "fault", kind, f"a pitch error of the "
            f"stage member {gear} is not modelled (a stage has no tooth modifications)")
    # every variant, the healthy one included, runs the stages' sun-planet meshes (and,
    # through ``dyn``, the gears' meshes) as meshes of contacts, as a fault's does: the
    # classes differ by their fault only
    stages = [dataclasses.replace(t, cracks=(), faults=(),
                                  contacts=t.contacts or t.sun_mesh_stiffness is None)
              for t in gearbox.stages]
    if gear in members and kind != "none":  # a crack or surface fault of a stage member
        k, m = members[gear]
        stages[k] = _member_fault(stages[k], m, kind, s)
    chains = []
    for t in gearbox.chains:  # the gears before, between and after the stages
        t = t.with_crack("none").with_faults(())
        if gear in [g.name for g in t.gears]:
            t, dyn = _with_fault(t, kind, s, gear, dyn)
        chains.append(t)
    return dataclasses.replace(gearbox._with_stages(tuple(stages))._with_chains(
        tuple(chains)), dynamics=dyn)


def _sized(kind: str, s: float, g, name: str, lo: float, hi: float):
    """The crack or surface fault of class ``kind`` (a crack, spall, pitting, chip or
    broken tooth) at severity ``s`` on tooth 0 of gear ``g`` (named ``name``), whose
    working flank is in contact between the roll lengths ``lo`` and ``hi`` [m]; sizes of
    the module docstring."""
    m = g.normal_module
    if kind in ("working", "non-working"):
        return Crack(gear=name, flank=kind, **{**DEFAULT_CRACK, "depth": s * 2e-3 * m / 6e-3})
    b, rb = g.face_width, g.base_radius
    arc = (hi * hi - lo * lo) / (2 * rb)
    if kind == "spall":
        # centred on the pitch circle, kept inside the active flank
        sc = min(max(arc_at_radius(g.pitch_radius, rb), lo * lo / (2 * rb) + 0.25 * arc),
                 hi * hi / (2 * rb) - 0.25 * arc)
        r = math.sqrt(2 * rb * sc + rb * rb)
        return Spall(gear=name, tooth=0, radius=r, length=s * 0.5 * arc, width=s * 0.5 * b,
                     depth=0.05 * m)
    if kind == "pitting":
        r_lo = math.hypot(rb, lo)
        r_hi = max(min(g.pitch_radius, math.hypot(rb, hi)), r_lo + 0.25 * (math.hypot(rb, hi) - r_lo))
        return Pitting(gear=name, tooth=0, area_fraction=0.3 * s, radius_min=r_lo,
                       radius_max=r_hi, pit_diameter=0.1 * m, depth=0.02 * m)
    if kind == "chip":
        return ChippedTip(gear=name, tooth=0, length=s * 0.4 * arc, width=s * 0.5 * b)
    require(kind == "broken", "fault", kind, "is not a tooth fault of a gear's flank")
    return BrokenTooth(gear=name, tooth=0, width=None if s == 1 else s * b)


def _stage_members(gearbox: Gearbox) -> dict[str, tuple[int, str]]:
    """Name (``sun``, ``ring``, ``planet-1``, ...; ``stage<k>-`` before them with stages in
    series) -> (stage index, member) of every stage member a fault class can sit on."""
    n = len(gearbox.stages)
    return {stage_prefix(k, n) + m: (k, m) for k, st in enumerate(gearbox.stages)
            for m in ("sun", "ring", *(planet_name(j) for j in range(st.stage.planets)))}


def _member_fault(stage: PlanetaryTrain, member: str, kind: str, s: float) -> PlanetaryTrain:
    """``stage`` (no crack, no fault) with the class ``kind`` at severity ``s`` on tooth 0 of
    ``member``; the working flank is the one in the sun-planet mesh (the sun drives in
    the model frame: the sun's roll lengths from its start of contact, a planet's from
    the other end of the line; the ring takes cracks only, on the flank the planets
    load). What a stage does not model is refused where the stage is made."""
    require(member != "ring" or kind in ("working", "non-working"), "fault", kind,
            "the ring takes cracks only (working, on the flank the planets load): its "
            "mesh has no mesh of contacts for surface faults")
    st, pair = stage.stage, stage.sun_pair
    g = {"sun": st.sun, "ring": st.ring}.get(member, st.planet)
    lo, hi = ((pair.start_of_contact, pair.end_of_contact) if member == "sun" else
              (pair.line_length - pair.end_of_contact, pair.line_length - pair.start_of_contact))
    fault = _sized(kind, s, g, member, lo, hi)
    if isinstance(fault, Crack):
        return dataclasses.replace(stage, cracks=(fault,))
    return dataclasses.replace(stage, faults=(fault,))


def _with_fault(base, kind: str, s: float, gear: str | None, dyn):
    """The train ``base`` (no crack, no fault) with one fault of class ``kind`` at
    severity ``s`` on tooth 0 of ``gear`` (its first gear if None), and the dynamics
    settings (the eccentricity's runout)."""
    names = [x.name for x in base.gears]
    g = base.gears[0] if gear is None else base.gear(gear)
    m = g.normal_module
    fpt = single_pitch_tolerance(6, 2 * g.pitch_radius, m)
    train = base
    if kind in ("working", "non-working"):
        train = base.with_cracks((_sized(kind, s, g, g.name, 0.0, 0.0),))
    elif kind in ("spall", "pitting", "chip", "broken"):
        lo, hi = active_roll_range(base, g.name, "working")
        train = base.with_faults((_sized(kind, s, g, g.name, lo, hi),))
    elif kind == "pitch":
        errors = [0.0] * g.teeth
        errors[0] = s * 4 * fpt
        mods = tuple(x for x in base.modifications if x.gear != g.name)
        old = next((x for x in base.modifications if x.gear == g.name), None)
        new = (dataclasses.replace(old, pitch_errors=tuple(errors), pitch_grade=None)
               if old is not None else Modification(gear=g.name, pitch_errors=tuple(errors)))
        train = base.with_faults((), (*mods, new))
    elif kind == "eccentricity":
        ro = [0.0] * len(base.gears)
        ro[names.index(g.name)] = s * 4 * fpt
        dyn = dataclasses.replace(dyn, runout=tuple(ro))
    return train, dyn
