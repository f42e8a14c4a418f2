"""A planetary stage in operation: kinematics, member torques, cracks and phased mesh tables.

Operation (Willis; Mueller 1982): one member is held (``fixed``: ring, carrier or sun),
one is driven (``input``) at ``speed`` with ``torque``, the third is the output. With the
speeds omega and the external torques T of sun, ring and carrier

    omega_s - omega_c = -(z_r / z_s)(omega_r - omega_c),
    T_s + T_r + T_c = 0,  T_s omega_s + T_r omega_r + T_c omega_c = 0 (no losses),
    T_r = (z_r / z_s) T_s                      (planet equilibrium, Lin & Parker 1999).

Mesh frequency f_m = z_s |omega_s - omega_c| / 2 pi = z_r |omega_r - omega_c| / 2 pi.

**Model frame.** The Lin & Parker (1999) model (:mod:`gearsim.dynamics.planetary`)
loads the flanks on which the sun pushes the planets counter-clockwise, i.e. an external
sun torque T_s > 0 (counter-clockwise). A stage whose sun torque is clockwise is looked at
from the other side (``mirrored``: planet angles psi -> -psi, all torques and speeds change
sign), which puts the loads on the model's flanks. The sense in which the contacts then
run along the lines of action is ``direction`` = sign(T_s (omega_s - omega_c)): +1 when
the sun, relative to the carrier, turns the way its torque acts (it drives the planets),
-1 when the planets drive the sun (a wind-turbine stage with the carrier as input, a
star stage driven by the ring): the tables are run backwards.

**Mesh tables.** The table coordinate of planet n's sun mesh, in mesh cycles, is
tau_sn = d c - z_s psi_n / 2 pi (c = f_m t, d = ``direction``; psi_n in the model frame),
which is Parker & Lin's (2004) phase gamma_sn = frac(z_s psi_n / 2 pi) and also places a
cracked sun tooth at each planet in turn. The ring mesh of the same planet has
tau_rn = tau_sn - c_p,sp - Delta + c_p,rp, with c_p the table coordinate of a pitch-point
contact in each table (mid face width) and Delta the mesh cycles a planet tooth turns from
its sun-side to its ring-side pitch-point contact
(:attr:`~gearsim.geometry.planetary.PlanetaryStage.sun_ring_offset`): the planet's tooth
numbers agree in both tables, so a cracked planet tooth loads the sun mesh and then, Delta
cycles later, the ring mesh, each on its own flank.

**Stiffness model.** The sun-planet meshes take the stage's ``[stiffness]`` options as
an external pair of a gear train does (:meth:`gearsim.system.GearTrain.mesh_stiffness`:
the tooth model of ``source``, the body coupling, the line contact at the static mesh
force). The ring-planet mesh takes them too (:func:`gearsim.stiffness.internal.
internal_mesh_stiffness`): under ``source = "calibrated"`` the planet tooth calibrated as
on external gears and the ring tooth corrected by the FE ring segment
(:class:`gearsim.fem.calibration.CalibratedRingTooth`), under ``coupling = "fe"`` the
planet's body and the ring's rim coupling. The static force of every sun-planet and
ring-planet mesh is F = |T_s| / (N r_b,s): the planets share the sun torque equally, and
a planet's moment balance about its centre makes its ring force equal to its sun force
(both lines of action touch its base circle).

**Flanks.** The working flank of the sun and of the ring is the flank the planets load;
the working flank of a planet is the flank the sun loads, so the ring loads its
non-working flank (reversed bending, like an idler). A crack on a planet's working flank
is on the tension side (``side = +1``) in the sun mesh and on the compression side
(``side = -1``) in the ring mesh; a non-working crack the other way round.

References
----------
.. [LinParker1999] J. Lin, R. G. Parker, J. Vib. Acoust. 121 (1999) 316-321.
.. [ParkerLin2004] R. G. Parker, J. Lin, J. Mech. Des. 126 (2004) 365-370.
.. [Muller1982] H. W. Mueller, Epicyclic Drive Trains, Wayne State University Press, 1982.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from gearsim.errors import require
from gearsim.fem.ring import check_ring_fillets
from gearsim.geometry.pair import GearPair
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.contacts import ContactGrid, contact_grid
from gearsim.stiffness.crack import Crack, crack_geometry
from gearsim.stiffness.faults import BrokenTooth, ChippedTip, Pitting, Spall, Wear
from gearsim.stiffness.internal import (
    InternalMesh,
    check_internal_settings,
    internal_mesh_stiffness,
)
from gearsim.stiffness.iso6336 import internal_mean_mesh_stiffness, mean_mesh_stiffness
from gearsim.stiffness.mesh import MeshStiffness, mesh_stiffness
from gearsim.stiffness.ring import RingToothModel
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import ToothCrack
from gearsim.system.faults import mesh_flanks
from gearsim.system.train import (  # the operating point's bounds are the gear trains'
    GearTrain,
    Operating,
    body_coupling,
    tooth_compliance,
)

__all__ = ["MEMBERS", "PhasedTable", "PlanetaryTrain", "StageOperating", "planet_name",
           "stage_stiffness"]

#: Members of a stage that can be held or driven.
MEMBERS = ("sun", "ring", "carrier")
#: Fault classes a stage takes.
FAULT_TYPES = (Spall, Pitting, ChippedTip, BrokenTooth, Wear)


def planet_name(n: int) -> str:
    """Name of planet ``n`` (0-based index) in cracks and results: ``"planet-1"`` ...

    Parameters
    ----------
    n : int
        Planet index 0 .. N-1.

    Returns
    -------
    str
        ``f"planet-{n + 1}"``.
    """
    return f"planet-{n + 1}"


@dataclass(frozen=True)
class StageOperating:
    """Operating point of a planetary stage.

    Parameters
    ----------
    fixed
        Held member: ``"ring"`` (default), ``"carrier"`` or ``"sun"``.
    input
        Driven member (not the held one): ``"sun"`` (default), ``"ring"`` or ``"carrier"``.
    speed
        Speed of the input member [rad/s], finite, in [1e-3, 1e5].
    torque
        Torque on the input member [N m], finite, in [1e-6, 1e9].

    Raises
    ------
    InputError
        Unknown member names, input = fixed, speed or torque outside its range.
    """

    fixed: str = "ring"
    input: str = "sun"
    speed: float = 1000.0 * 2 * math.pi / 60
    torque: float = 100.0

    def __post_init__(self) -> None:
        require(self.fixed in MEMBERS, "operating.fixed", self.fixed,
                'must be "ring", "carrier" or "sun"')
        require(self.input in MEMBERS, "operating.input", self.input,
                'must be "sun", "ring" or "carrier"')
        require(self.input != self.fixed, "operating.input", self.input,
                f"must differ from the held member (operating.fixed = {self.fixed!r})")
        Operating(speed=self.speed, torque=self.torque)  # the gear trains' checks


@dataclass(frozen=True)
class PhasedTable:
    """A mesh-stiffness table with its place in time, ready for the dynamics kernel.

    The stiffness at time t is ``k(f_m t + phase)`` with ``k`` periodic over ``period``
    mesh cycles and sampled at ``positions_per_cycle`` points per cycle (already reversed
    when the contacts run backwards, ``direction = -1``).

    Parameters
    ----------
    mesh : str
        ``"sun-planet-1"``, ``"ring-planet-1"``, ...
    k : ndarray
        Samples [N/m].
    positions_per_cycle, period : int
        Sampling and period [mesh cycles].
    phase : float
        Offset [mesh cycles].
    table : MeshStiffness
        The table as computed (forward sense, with components and teeth).
    grid : ContactGrid, optional
        The mesh of contacts (forward sense) when faults change the contacts of this mesh
        (:mod:`gearsim.stiffness.contacts`); the dynamics reads it in the sense of ``k``.
    reference_mean : float, optional
        With ``grid``: the mean stiffness of the healthy mesh [N/m], which sets the mesh
        damping and the static equilibrium (a local fault does not change them).
    """

    mesh: str
    k: np.ndarray
    positions_per_cycle: int
    period: int
    phase: float
    table: MeshStiffness
    grid: ContactGrid | None = None
    reference_mean: float | None = None

    def __call__(self, t: np.ndarray, mesh_frequency: float) -> np.ndarray:
        """Stiffness at times ``t`` [s] (linear interpolation) [N/m].

        Parameters
        ----------
        t : ndarray
            Times [s].
        mesh_frequency : float
            f_m [Hz].

        Returns
        -------
        ndarray
            k(f_m t + phase) [N/m].
        """
        c = np.asarray(t, dtype=float) * mesh_frequency + self.phase
        pos = np.mod(c, self.period) * self.positions_per_cycle
        i = np.floor(pos).astype(np.int64)
        w = pos - i
        n = self.k.size
        i %= n
        return self.k[i] * (1.0 - w) + self.k[(i + 1) % n] * w


@dataclass(frozen=True)
class PlanetaryTrain:
    """A planetary stage with its operating point, stiffness options and cracks.

    Parameters
    ----------
    stage
        The stage geometry (:class:`~gearsim.geometry.planetary.PlanetaryStage`).
    operating
        Held and driven members, speed and torque.
    settings
        Stiffness options (:class:`~gearsim.stiffness.settings.StiffnessSettings`) of
        both meshes (module docstring, "Stiffness model"); the ring-planet mesh takes
        ``source = "pe"`` or ``"calibrated"``. The Python default is the seed's options; a
        stage file that names no model gets the accurate one
        (:func:`gearsim.model.planetary.parse_planetary`).
    cracks
        Cracks on ``"sun"``, ``"ring"`` (its working flank, the one the planets load) or
        ``"planet-n"`` teeth (``Crack.gear``); flank as in the module docstring. At most
        one cracked member per mesh.
    name
        Name of the configuration.
    sun_mesh_stiffness, ring_mesh_stiffness
        Constant mesh stiffnesses [N/m] replacing the computed tables (e.g. the
        Lin & Parker example, which gives mean values only); ``None``: computed.
    ring_foundation
        Foundation term of the potential-energy ring tooth (``"sainsot-solid"`` or
        ``"none"``); only ``"none"`` with ``source = "calibrated"``, whose ring tooth has
        the FE segment's rim and fillet compliance in that column.
    faults
        Surface faults (:mod:`gearsim.stiffness.faults`: spall, pitting, chipped tip,
        wear; a broken tooth on the sun) on ``"sun"`` or on the working flank of a
        ``"planet-n"`` (the flank the sun loads): the sun-planet meshes become meshes of
        contacts. One damaged member (cracks and faults) at a time.
    contacts
        Use the mesh of contacts for every sun-planet mesh even without faults (as
        ``mesh_tables(..., contacts=True)`` of the gear trains); with faults every
        sun-planet mesh uses it, so that all planets share one mesh model.

    Raises
    ------
    InputError
        A crack on a gear the stage does not have (``planet-5`` of three planets), on
        the ring's non-working flank, on a tooth number the gear does not have, two cracked
        members in one mesh, constant stiffnesses not finite > 0, options the internal
        mesh does not model, ``ring_foundation = "sainsot-solid"`` with the calibrated
        source.

    Examples
    --------
    >>> from gearsim.geometry.planetary import PlanetaryStage
    >>> st = PlanetaryStage(30, 24, 78, 2e-3, planets=4, ring_addendum_coefficient=0.8)
    >>> tr = PlanetaryTrain(st, StageOperating(speed=100.0, torque=50.0))
    >>> round(tr.mesh_frequency, 4), tr.direction
    (344.8357, 1)
    """

    stage: PlanetaryStage
    operating: StageOperating = field(default_factory=StageOperating)
    settings: StiffnessSettings = field(default_factory=StiffnessSettings)
    cracks: tuple[Crack, ...] = ()
    name: str = "planetary stage"
    sun_mesh_stiffness: float | None = None
    ring_mesh_stiffness: float | None = None
    ring_foundation: str = "none"
    faults: tuple = ()
    contacts: bool = False

    def __post_init__(self) -> None:
        st = self.stage
        n = st.planets
        names = ["sun", "ring"] + [planet_name(i) for i in range(n)]
        seen: dict[str, int] = {}
        for c in self.cracks:
            require(isinstance(c, Crack), "cracks", type(c).__name__, "must be Crack objects")
            if c.gear.startswith("planet-") and c.gear not in names:
                require(False, "crack.gear", c.gear,
                        f"no such planet: the stage has {n} planets (planet-1 .. planet-{n})")
            require(c.gear in names, "crack.gear", c.gear,
                    f"must be sun, ring or planet-1 .. planet-{n}")
            if c.gear == "ring":
                require(c.flank == "working", "crack.flank", c.flank,
                        "a ring crack is modelled on the flank the planets load (its "
                        "working flank, the tension side)")
            z = {"sun": st.sun_teeth, "ring": st.ring_teeth}.get(c.gear, st.planet_teeth)
            require(c.tooth < z, "crack.tooth", c.tooth, f"must be < {z} (teeth of {c.gear})")
            # the crack must fit its tooth (refused here, before any table is computed)
            if c.gear == "ring":
                q_max = RingToothModel(st.ring).max_crack_depth(c.angle)
                require(c.depth < q_max, "crack.depth", c.depth,
                        f"must be < {q_max:.6g} m on the ring: a ring crack ends before the "
                        "tooth centre line (its tip on the loaded side)")
            else:
                crack_geometry(ToothProfile(st.sun if c.gear == "sun" else st.planet), c)
            seen[c.gear] = seen.get(c.gear, 0) + 1
            require(seen[c.gear] == 1, "crack.gear", c.gear, "at most one crack per gear")
        planets_cracked = [g for g in seen if g.startswith("planet-")]
        require(not ("sun" in seen and planets_cracked), "cracks", ", ".join(seen),
                "a cracked sun and a cracked planet share a mesh: crack one member at a time")
        require(not ("ring" in seen and planets_cracked), "cracks", ", ".join(seen),
                "a cracked ring and a cracked planet share a mesh: crack one member at a time")
        for nm in ("sun_mesh_stiffness", "ring_mesh_stiffness"):
            v = getattr(self, nm)
            require(v is None or (isinstance(v, (int, float)) and math.isfinite(v) and v > 0),
                    f"stage.{nm}", v, "must be a finite number > 0 N/m (or omitted)")
            require(v is None or not self.cracks, f"stage.{nm}", v,
                    "a constant mesh stiffness cannot carry a crack: leave it out (computed "
                    "tables) or remove the cracks")
        require(self.ring_foundation in ("sainsot-solid", "none"), "stage.ring_foundation",
                self.ring_foundation, 'must be "sainsot-solid" or "none"')
        require(self.ring_foundation == "none" or self.settings.source == "pe",
                "stage.ring_foundation", self.ring_foundation,
                f'belongs to the potential-energy ring tooth (stiffness.source = "pe", model '
                f'"seed"); the {self.settings.source!r} ring tooth has the FE segment\'s rim '
                "and fillet in its place")
        self._check_faults(names)

    def _check_faults(self, names: list[str]) -> None:
        st, n = self.stage, self.stage.planets
        for f in self.faults:
            require(isinstance(f, FAULT_TYPES), "faults", type(f).__name__,
                    "must be fault objects of gearsim.stiffness.faults")
            g = f.gear
            if g.startswith("planet-") and g not in names:
                require(False, "fault.gear", g,
                        f"no such planet: the stage has {n} planets (planet-1 .. planet-{n})")
            require(g != "ring", "fault.gear", "ring", "ring tooth faults are not modelled "
                    "(the internal mesh has no mesh of contacts)")
            require(g in names, "fault.gear", g, f"must be sun or planet-1 .. planet-{n}")
            z = st.sun_teeth if g == "sun" else st.planet_teeth
            require(f.tooth < z, "fault.tooth", f.tooth, f"must be < {z} (teeth of {g})")
            if g == "sun":
                require(getattr(f, "flank", "working") == "working", "fault.flank", f.flank,
                        "the planets load the sun's working flank only: a fault on the other "
                        "flank is never loaded")
            else:
                require(not isinstance(f, BrokenTooth), "fault.kind", "broken",
                        f"a broken tooth of {g} also leaves the ring mesh, which has no mesh "
                        "of contacts: not modelled")
                require(f.flank == "working", "fault.flank", f.flank,
                        f"the non-working flank of {g} meets the ring, whose mesh has no "
                        "mesh of contacts: not modelled (the working flank meets the sun)")
        require(isinstance(self.contacts, bool), "stage.contacts", self.contacts,
                "must be true or false")
        require(not (self.contacts and self.sun_mesh_stiffness is not None),
                "stage.sun_mesh_stiffness", self.sun_mesh_stiffness,
                "a constant mesh stiffness has no mesh of contacts")
        if self.faults:
            damaged = sorted({f.gear for f in self.faults} | {c.gear for c in self.cracks})
            require(len(damaged) == 1, "faults", ", ".join(damaged),
                    "a stage with faults takes damage on one member (the sun or one planet)")
            require(self.sun_mesh_stiffness is None, "stage.sun_mesh_stiffness",
                    self.sun_mesh_stiffness, "a constant mesh stiffness cannot carry faults")
        if self.ring_mesh_stiffness is None:
            check_internal_settings(self.settings)
            InternalMesh(st)  # tip interference of the internal pair
            if self.settings.source == "calibrated" or self.settings.coupling == "fe":
                check_ring_fillets(st.ring)  # the FE ring segment can be meshed

    # ----------------------------------------------------------------- kinematics
    @cached_property
    def speeds(self) -> dict[str, float]:
        """Physical speeds of sun, ring and carrier [rad/s] (input positive)."""
        op, st = self.operating, self.stage
        zs, zr = st.sun_teeth, st.ring_teeth
        w = {op.fixed: 0.0, op.input: op.speed}
        out = next(m for m in MEMBERS if m not in w)
        # omega_s - omega_c = -(z_r/z_s)(omega_r - omega_c): solve for the unknown
        if out == "carrier":
            ws, wr = w["sun"], w["ring"]
            w[out] = (zs * ws + zr * wr) / (zs + zr)
        elif out == "sun":
            w[out] = w["carrier"] - zr / zs * (w["ring"] - w["carrier"])
        else:
            w[out] = w["carrier"] - zs / zr * (w["sun"] - w["carrier"])
        return w

    @cached_property
    def torques(self) -> dict[str, float]:
        """Physical external torques on sun, ring and carrier [N m] (sum zero)."""
        op, st = self.operating, self.stage
        ratio = {"sun": 1.0, "ring": st.ring_teeth / st.sun_teeth}
        ratio["carrier"] = -(ratio["sun"] + ratio["ring"])
        ts = op.torque / ratio[op.input]
        return {m: ts * ratio[m] for m in MEMBERS}

    @property
    def direction(self) -> int:
        """Sense of the contacts along the lines of action in the model frame [-].

        +1: the sun turns, relative to the carrier, the way its torque acts (it drives the
        planets; contacts run from the start to the end of the path), -1 the other way
        (the planets drive the sun; the tables are run backwards): sign(T_s (omega_s -
        omega_c)).
        """
        rel = self.speeds["sun"] - self.speeds["carrier"]
        return 1 if self.torques["sun"] * rel > 0 else -1

    @property
    def mesh_frequency(self) -> float:
        """f_m = z_s |omega_s - omega_c| / 2 pi [Hz]."""
        return self.stage.sun_teeth * abs(self.speeds["sun"] - self.speeds["carrier"]) / (
            2.0 * math.pi)

    def analysis_reference(self) -> tuple[str, float, list[int]]:
        """Reference member of the analysis of this stage's records, its speed and teeth.

        Ring or sun held: the carrier, with ``Z_1 = z_r`` (ring held) or ``z_s`` (sun
        held); carrier held: the ring with ``Z_1 = z_r``; then the other two tooth counts,
        so that ``f_m / Z_j`` are the member rotations relative to the carrier
        (``f_m = Z_1 |f_ref - f_c|``, f_c = 0 for the held carrier).

        Returns
        -------
        member : str
            ``"carrier"`` or ``"ring"``.
        frequency : float
            Its speed [Hz] (absolute value).
        teeth : list of int
            ``Z_1`` first, then the other two.
        """
        st, fixed = self.stage, self.operating.fixed
        zs, zp, zr = st.sun_teeth, st.planet_teeth, st.ring_teeth
        member, teeth = (("ring", [zr, zs, zp]) if fixed == "carrier" else
                         ("carrier", [zs, zr, zp]) if fixed == "sun" else
                         ("carrier", [zr, zs, zp]))
        return member, abs(self.speeds[member]) / (2.0 * math.pi), teeth

    @property
    def mirrored(self) -> bool:
        """True when the model frame is the mirror image (physical sun torque < 0)."""
        return self.torques["sun"] < 0

    @property
    def model_angles(self) -> np.ndarray:
        """Planet angles in the model frame [rad]: psi_n, or (-psi_n) mod 2 pi mirrored."""
        psi = self.stage.planet_angles_value
        return np.mod(-psi, 2.0 * math.pi) if self.mirrored else psi

    @property
    def model_torques(self) -> dict[str, float]:
        """External torques in the model frame [N m] (sun torque > 0)."""
        sgn = -1.0 if self.mirrored else 1.0
        return {m: sgn * t for m, t in self.torques.items()}

    @property
    def sun_torque(self) -> float:
        """|T_s| [N m], the sun torque in the model frame."""
        return abs(self.torques["sun"])

    # --------------------------------------------------------------------- tables
    def _side(self, crack: Crack, mesh: str) -> int:
        working = crack.flank == "working"
        if crack.gear.startswith("planet-") and mesh == "ring":
            working = not working
        return 1 if working else -1

    @property
    def mesh_force(self) -> float:
        """Static transverse line-of-action force of each mesh, |T_s| / (N r_b,s) [N].

        The planets share the sun torque equally; each planet's ring force equals its sun
        force (module docstring, "Stiffness model").
        """
        st = self.stage
        return self.sun_torque / (st.planets * st.sun.base_radius)

    @cached_property
    def _ring_options(self) -> dict:
        """Keyword arguments of the internal mesh for the stage's stiffness options."""
        s = self.settings
        out: dict = {"compliance": tooth_compliance(s.source), "force": self.mesh_force,
                     "coupling": body_coupling(s)}
        if s.source == "calibrated" or s.coupling == "fe":
            from gearsim.fem.calibration import CalibratedRingTooth

            rim = CalibratedRingTooth(self.stage.ring, self.stage.material, plane=s.plane,
                                      gauss_points=s.gauss_points)
            out["ring_coupling"] = rim if s.coupling == "fe" else None
            if s.source == "calibrated":
                out["ring_model"] = rim
        return out

    @cached_property
    def sun_pair(self) -> GearPair:
        """The sun-planet pair (sun drives, model frame)."""
        return GearPair(self.stage.sun, self.stage.planet, name="sun-planet")

    def _pitch_cycle(self, s_pitch: float, la: float) -> float:
        st = self.stage
        tb = math.tan(st.planet.base_helix_angle)
        return (s_pitch - la + 0.5 * st.face_width * tb) / st.base_pitch

    @cached_property
    def ring_offset(self) -> float:
        """tau_rn - tau_sn = c_p,rp - c_p,sp - Delta [mesh cycles] (module docstring)."""
        st, pair = self.stage, self.sun_pair
        c_sp = self._pitch_cycle(st.sun.base_radius * math.tan(st.sun_planet_pressure_angle),
                                 pair.start_of_contact)
        geo = InternalMesh(st)
        c_rp = self._pitch_cycle(geo.pitch_point, geo.start)
        return c_rp - c_sp - st.sun_ring_offset

    def _crack_of(self, gear: str) -> Crack | None:
        return next((c for c in self.cracks if c.gear == gear), None)

    @cached_property
    def _sun_tables(self) -> dict[str, MeshStiffness]:
        """Sun-planet tables: healthy, cracked sun, cracked planet n (keys)."""
        out: dict[str, MeshStiffness] = {}
        if self.sun_mesh_stiffness is not None:
            return out
        pair, s = self.sun_pair, self.settings
        model = {"compliance": tooth_compliance(s.source), "force": self.mesh_force,
                 "coupling": body_coupling(s)}
        out["healthy"] = mesh_stiffness(pair, settings=s, revolution_of=1, **model)
        for c in self.cracks:
            if c.gear == "ring":  # not in the sun meshes
                continue
            gear = 1 if c.gear == "sun" else 2
            out[c.gear] = mesh_stiffness(
                pair, cracks=(ToothCrack(gear, replace(c, gear=pair.driver.name if gear == 1
                                                        else pair.driven.name),
                                         self._side(c, "sun")),),
                settings=s, revolution_of=gear, **model)
        return out

    @cached_property
    def _sun_grids(self) -> dict[str, ContactGrid]:
        """Meshes of contacts of the sun-planet meshes: ``"all"`` healthy, and one for each
        damaged member (``"sun"``, ``"planet-n"``: its faults and cracks), if any."""
        if not (self.faults or self.contacts):
            return {}
        pair, s = self.sun_pair, self.settings
        model = {"compliance": tooth_compliance(s.source), "force": self.mesh_force,
                 "coupling": body_coupling(s)}
        out = {"all": contact_grid(pair, settings=s, corner=s.corner_contact, **model)}
        # the ring's cracks are not in the sun meshes
        damaged = sorted({f.gear for f in self.faults}
                         | {c.gear for c in self.cracks if c.gear != "ring"})
        for member in damaged:
            gear = 1 if member == "sun" else 2
            own = pair.driver.name if gear == 1 else pair.driven.name
            cracks = tuple(replace(c, gear=own) for c in self.cracks if c.gear == member)
            aux = GearTrain(gears=(pair.driver, pair.driven), stiffness=s, cracks=cracks,
                            faults=tuple(replace(f, gear=own) for f in self.faults
                                         if f.gear == member),
                            name=f"{self.name}: sun mesh of {member}")
            f1, f2 = mesh_flanks(aux, 0)
            tc = tuple(ToothCrack(gear, c, self._side(replace(c, gear=member), "sun"))
                       for c in cracks)
            out[member] = contact_grid(pair, cracks=tc, flank1=f1, flank2=f2, settings=s,
                                       corner=s.corner_contact, **model)
        return out

    @cached_property
    def _ring_tables(self) -> dict[str, MeshStiffness]:
        out: dict[str, MeshStiffness] = {}
        if self.ring_mesh_stiffness is not None:
            return out
        st, s = self.stage, self.settings
        kw = dict(self._ring_options, settings=s, ring_foundation=self.ring_foundation)
        out["healthy"] = internal_mesh_stiffness(st, revolution_of=1, **kw)
        for c in self.cracks:
            if c.gear.startswith("planet-"):
                out[c.gear] = internal_mesh_stiffness(
                    st, cracks=(ToothCrack(1, replace(c, gear="planet"), self._side(c, "ring")),),
                    revolution_of=1, **kw)
            elif c.gear == "ring":  # over a ring revolution relative to the carrier
                out["ring"] = internal_mesh_stiffness(
                    st, cracks=(ToothCrack(2, c, 1),), revolution_of=2, **kw)
        return out

    def mesh_table(self, mesh: str, planet: int) -> PhasedTable:
        """Phased stiffness table of one mesh.

        Parameters
        ----------
        mesh : {"sun", "ring"}
            The sun-planet or ring-planet mesh.
        planet : int
            Planet index 0 .. N-1.

        Returns
        -------
        PhasedTable
            k(f_m t + phase) over ``period`` cycles (module docstring).
        """
        require(mesh in ("sun", "ring"), "mesh", mesh, 'must be "sun" or "ring"')
        n = self.stage.planets
        require(isinstance(planet, int) and 0 <= planet < n, "planet", planet,
                f"must be in 0 .. {n - 1} ({n} planets)")
        pname = planet_name(planet)
        const = self.sun_mesh_stiffness if mesh == "sun" else self.ring_mesh_stiffness
        label = f"{mesh}-{pname}"
        if const is not None:
            ms = MeshStiffness.whole_mesh(self.sun_pair, 1, 1, np.array([const]),
                                          {"source": "constant"})
            return PhasedTable(label, np.array([float(const)]), 1, 1, 0.0, ms)
        grids = self._sun_grids if mesh == "sun" else {}
        gkey = next((g for g in (pname, "sun", "all") if g in grids), None)
        grid = grids[gkey] if gkey is not None else None
        if grid is not None:
            npc = grid.positions_per_cycle
            # the stiffness of the contacts that touch without load (those with a
            # separation close under load in the dynamics): equal to the healthy table
            # wherever the fault is out of mesh
            kg = grid.k.reshape(grid.k.shape[0], -1)
            k = np.where(grid.s.reshape(kg.shape) == 0, kg, 0.0).sum(axis=1)
            ms = MeshStiffness.whole_mesh(self.sun_pair, 2 if gkey.startswith("planet") else 1,
                                          npc, k, {"source": "contacts",
                                                   "positions_per_cycle": npc})
            key = gkey
        else:
            tabs = self._sun_tables if mesh == "sun" else self._ring_tables
            key = next(g for g in (pname, mesh, "healthy") if g in tabs)
            ms = tabs[key]
            npc = int(ms.attrs["positions_per_cycle"])
            k = ms.k
        period = k.size // npc
        if key == "healthy":  # one cycle repeats
            k = k[:npc]
            period = 1
        psi = float(self.model_angles[planet])
        tau = -self.stage.sun_teeth * psi / (2.0 * math.pi)
        if mesh == "ring":
            tau += self.ring_offset
        if key == "ring":
            # a ring table counts ring teeth: the planet psi ahead of planet 1 meshes the
            # ring tooth planet 1 meets z_r psi / 2 pi teeth later (the ring turns
            # backwards relative to the carrier); same fraction as -z_s psi / 2 pi for an
            # assemblable stage ((z_s + z_r) psi / 2 pi whole)
            tau = self.stage.ring_teeth * psi / (2.0 * math.pi) + self.ring_offset
        d = self.direction
        if d == -1:  # k_rev(c) = k(-c)
            k = np.roll(k[::-1], 1)
            tau = -tau
        ref = float(np.mean(self._sun_tables["healthy"].k)) if grid is not None else None
        return PhasedTable(label, np.ascontiguousarray(k, dtype=float), npc, period,
                           float(tau), ms, grid, ref)

    def tables(self) -> list[PhasedTable]:
        """All mesh tables: sun mesh then ring mesh of each planet in turn.

        Returns
        -------
        list of PhasedTable
            ``[sun-planet-1, ring-planet-1, sun-planet-2, ...]``.
        """
        return [self.mesh_table(m, j) for j in range(self.stage.planets) for m in ("sun", "ring")]


def stage_stiffness(train: PlanetaryTrain) -> tuple[dict, object]:
    """Stiffness tables of every mesh of a stage: JSON summary and an xarray Dataset.

    Parameters
    ----------
    train : PlanetaryTrain
        The stage.

    Returns
    -------
    summary : dict
        Per mesh (``sun-planet-1`` ...): mean, min, max [N/m], table period [cycles],
        phase [cycles] and the ISO 6336-1 estimate c_gamma_alpha b at the line load
        |T_s| / (N r_s b) with the ratio mean / ISO; ``mesh_frequency`` [Hz], ``direction``, contact ratios.
    dataset : xarray.Dataset
        ``k_<mesh>`` over ``cycles_<mesh>`` (the forward tables, one period each).
    """
    import xarray as xr

    st = train.stage
    # ISO's tangential load per planet on the reference circles (equal for both meshes)
    w = abs(train.torques["sun"]) / (st.planets * st.sun.pitch_radius * st.face_width)
    iso = {"sun": mean_mesh_stiffness(train.sun_pair, w),
           "ring": internal_mean_mesh_stiffness(st, w)}
    meshes, data = [], {}
    tables = train.tables()
    for t in tables:
        kind = t.mesh.split("-")[0]
        k = t.table.k
        meshes.append({"mesh": t.mesh, "k_mean": float(np.mean(t.k)), "k_min": float(t.k.min()),
                       "k_max": float(t.k.max()), "period_cycles": int(t.period),
                       "phase_cycles": float(t.phase), "iso6336": iso[kind],
                       "ratio_to_iso6336": float(np.mean(t.k)) / iso[kind]})
        data[f"k_{t.mesh}"] = (f"cycles_{t.mesh}", k, {"units": "N/m"})
    coords = {f"cycles_{t.mesh}": (f"cycles_{t.mesh}", t.table.cycles, {"units": "1"})
              for t in tables}
    ds = xr.Dataset(data, coords=coords, attrs={"kind": "planetary", "name": train.name,
                                                "mesh_frequency": train.mesh_frequency})
    summary = {"kind": "planetary", "name": train.name, "meshes": meshes,
               "mesh_frequency": train.mesh_frequency, "direction": train.direction,
               "eps_alpha_sun": st.sun_planet_contact_ratio,
               "eps_alpha_ring": st.ring_planet_contact_ratio, "eps_beta": st.overlap_ratio,
               "phasing": st.phasing}
    return summary, ds
