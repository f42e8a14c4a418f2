"""A gearbox of parallel shafts (gears on shafts, meshes between them) in operation.

The gears sit on shafts and mesh in pairs (:mod:`gearsim.system.graph`); power enters at
the first shaft with the operating speed and torque and leaves at the last. Without
``shafts`` and ``meshes`` the gears form a chain: each on its own shaft (named after
it), gear i driving gear i+1 (input, idler(s), output), consecutive external helical
gears of opposite hands. Which flank a mesh loads follows from the power flow: the
driver's front face (facing the direction of rotation) and the driven gear's rear face.
The *working* flank of a gear is the flank loaded in the first mesh it takes part in;
for an idler the second mesh loads the other flank (reversed bending).
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from gearsim.errors import InputError, require
from gearsim.fem.coupling import FiniteElementCoupling
from gearsim.fem.tables import FiniteElementCompliance
from gearsim.geometry.gear import Gear
from gearsim.geometry.pair import GearPair
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.contacts import ContactGrid, contact_grid
from gearsim.stiffness.crack import FLANKS, Crack, crack_geometry
from gearsim.stiffness.faults import Fault
from gearsim.stiffness.mesh import MeshStiffness, StiffnessSettings, ToothCrack, mesh_stiffness
from gearsim.stiffness.modifications import Modification
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCompliance
from gearsim.system.faults import check_faults, flank_side, mesh_flanks
from gearsim.system.fe_pair import fe_pair_train_stiffness
from gearsim.system.graph import MeshSpec, PowerFlow, Shaft, power_flow
from gearsim.system.memo import Memo

__all__ = ["CRACK_CHOICES", "DEFAULT_CRACK", "GearTrain", "Operating", "body_coupling",
           "tooth_compliance"]

#: The one default crack, used when a fault variant is asked for and the configuration
#: names no crack: tooth 0 of the input gear, 2 mm deep at 45 deg to the tooth centre
#: line from the 30 deg tangent point (the crack of the built-in Table-1 example; the
#: 45 deg angle after Chen & Shao 2011). Keys are fields of :class:`Crack` (SI units).
DEFAULT_CRACK: dict[str, float | int] = {"tooth": 0, "depth": 2e-3, "angle": math.radians(45.0)}

#: Mesh stiffness tables kept in memory (least recently used dropped first): the cases of
#: a study that differ in speed, noise, bearings or damping (or in torque, under a
#: load-independent contact law) share their tables instead of recomputing them (0.1-0.5 s
#: a revolution). The key holds everything a table depends on; the arrays are read-only.
TABLE_CACHE_SIZE = 64
_TABLES = Memo(TABLE_CACHE_SIZE)

#: Fault variants :meth:`GearTrain.with_crack` knows.
CRACK_CHOICES = ("none", *FLANKS)


def tooth_compliance(source: str) -> ToothCompliance:
    """The tooth-compliance model named by ``stiffness.source``.

    Parameters
    ----------
    source : {"pe", "fe", "calibrated"}
        ``"pe"``: potential-energy model (:mod:`gearsim.stiffness.source`); ``"fe"``: the
        finite-element tooth (:mod:`gearsim.fem.tables`), the counterpart of the seed's
        rigid-flexible coupling; ``"calibrated"``: the PE tooth times the FE/PE ratio of
        the healthy tooth, measured once per gear and cached, and a crack on the loaded
        flank (``side = +1``; in a stage's ring-planet mesh a planet crack on the flank
        the ring loads) times its measured correction Q = F_FE / F_PE, measured once per
        gear and crack family; a crack on the unloaded flank stays the PE section
        reduction (:mod:`gearsim.fem.calibration`; docs/stiffness.md 4c).

    Returns
    -------
    ToothCompliance
        An object with the :class:`gearsim.stiffness.source.ToothCompliance` interface.
    """
    if source == "fe":
        return FiniteElementCompliance()
    if source == "pe":
        return PotentialEnergyCompliance()
    if source == "calibrated":
        from gearsim.fem.calibration import CalibratedCompliance

        return CalibratedCompliance()
    if source == "fe-pair":
        raise InputError("stiffness.source", source, "gives whole-mesh tables from the FE "
                         "gear pair; the mesh of contacts (faults other than cracks, "
                         "modifications) and eccentricity need a tooth model: "
                         'use "pe", "fe" or "calibrated"')
    raise InputError("stiffness.source", source,
                     'must be "pe", "fe", "fe-pair" or "calibrated"')


def body_coupling(settings: StiffnessSettings):
    """The neighbouring-tooth coupling model named by ``stiffness.coupling``.

    Parameters
    ----------
    settings : StiffnessSettings
        ``coupling`` (``"none"`` or ``"fe"``) and ``plane``.

    Returns
    -------
    FiniteElementCoupling or None
        The FE body coupling (:mod:`gearsim.fem.coupling`), or None without coupling.
    """
    if settings.coupling == "fe":
        return FiniteElementCoupling(plane=settings.plane)
    return None


#: Ceilings of the operating point: about 955 000 rpm, 1e9 N m (the largest gearboxes
#: carry ~1e7 N m); beyond them the value is a unit mistake.
MAX_SPEED = 1e5  # rad/s
MAX_TORQUE = 1e9  # N m
#: Floors: 1e-3 rad/s is one revolution in 1.7 h (slower than any gearbox's input, a
#: wind turbine's rotor turns at ~0.5-2 rad/s), 1e-6 N m a thousandth of a micro gear
#: motor's; below them the value is a unit mistake.
MIN_SPEED = 1e-3  # rad/s
MIN_TORQUE = 1e-6  # N m


@dataclass(frozen=True)
class Operating:
    """Operating point of the input gear.

    Parameters
    ----------
    speed
        Input speed [rad/s] (finite, in [1e-3, 1e5]). In a config file a speed needs a
        unit (``"1900 rpm"``): a bare number would be ambiguous.
    torque
        Input torque [N m] (finite, in [1e-6, 1e9]).

    Raises
    ------
    InputError
        If the speed or the torque is not a finite number > 0 or above its ceiling.
    """

    speed: float = 1900 * 2 * math.pi / 60
    torque: float = 4876.0

    def __post_init__(self) -> None:
        require(_positive(self.speed), "operating.speed", self.speed,
                "must be a finite number > 0 rad/s")
        require(MIN_SPEED <= self.speed <= MAX_SPEED, "operating.speed", self.speed,
                f"must be in [{MIN_SPEED:g}, {MAX_SPEED:g}] rad/s "
                f"([{MIN_SPEED * 30 / math.pi:.3g}, {MAX_SPEED * 30 / math.pi:.0f}] rpm)")
        require(_positive(self.torque), "operating.torque", self.torque,
                "must be a finite number > 0 N*m")
        require(MIN_TORQUE <= self.torque <= MAX_TORQUE, "operating.torque", self.torque,
                f"must be in [{MIN_TORQUE:g}, {MAX_TORQUE:g}] N*m")


def _positive(v: object) -> bool:
    return (isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
            and v > 0)


#: A record's name: variable, a mesh number (mesh_force_2) or a bracketed label.
_RECORD = re.compile(r"\s*(\w+?)(?:_(\d+))?\s*(?:\[([^\]]*)\])?\s*")


@dataclass(frozen=True)
class GearTrain:
    """A gearbox of parallel shafts, its operating point, stiffness options and faults.

    Every check runs where the train is made: at least two gears with unique names, a
    graph whose power flows as a tree from the first shaft to its outputs, each output's
    share of the power given where it branches
    (:func:`gearsim.system.graph.power_flow`), every mesh valid (interference, contact
    ratio; :class:`GearPair`), every crack on an
    existing gear and tooth and fitting its tooth (:func:`crack_geometry`). Variants made
    with :meth:`with_cracks` or :meth:`with_crack` are checked the same way.

    Parameters
    ----------
    gears : tuple of Gear
        The gears; put in the order of the power flow where the train is made (shaft by
        shaft from the input, in each shaft's listed order).
    operating : Operating
        Speed and torque of the input gear.
    stiffness : StiffnessSettings
        Options of the mesh-stiffness computation (closure, slices, source, ...); a mesh
        with its own (:attr:`MeshSpec.stiffness <gearsim.system.graph.MeshSpec>`) takes
        those (:meth:`settings_of`).
    cracks : tuple of Crack
        Tooth-root cracks.
    name : str
        Name of the train.
    faults : tuple of Fault
        Spalls, pitting, chipped and broken teeth, wear
        (:mod:`gearsim.stiffness.faults`); checked by
        :func:`gearsim.system.faults.check_faults`.
    modifications : tuple of Modification
        Profile and lead modifications and pitch errors, at most one per gear
        (:mod:`gearsim.stiffness.modifications`).
    shafts : tuple of Shaft
        The shafts, the input first; empty: one shaft per gear, named after it (a chain).
    meshes : tuple of MeshSpec
        The meshes; empty: gear i with gear i + 1 (a chain).
    """

    gears: tuple[Gear, ...]
    operating: Operating = field(default_factory=Operating)
    stiffness: StiffnessSettings = field(default_factory=StiffnessSettings)
    cracks: tuple[Crack, ...] = ()
    name: str = "gear train"
    faults: tuple[Fault, ...] = ()
    modifications: tuple[Modification, ...] = ()
    shafts: tuple[Shaft, ...] = ()
    meshes: tuple[MeshSpec, ...] = ()

    def __post_init__(self) -> None:
        require(len(self.gears) >= 2, "gears", len(self.gears), "need at least 2 gears")
        names = [g.name for g in self.gears]
        require(len(set(names)) == len(names), "gears.name", names, "names must be unique")
        if not self.shafts and not self.meshes:  # a chain
            object.__setattr__(self, "shafts", tuple(Shaft(n, (n,)) for n in names))
            object.__setattr__(self, "meshes", tuple(MeshSpec((a, b)) for a, b
                                                     in zip(names, names[1:], strict=False)))
        by_name = {g.name: g for g in self.gears}
        flow = power_flow(by_name, tuple(self.shafts), tuple(self.meshes))
        object.__setattr__(self, "gears", tuple(by_name[n] for s in flow.shafts
                                                for n in s.gears))
        self.__dict__["flow"] = flow  # the cached property, solved once
        object.__setattr__(self, "meshes", tuple(  # a mesh's own equal to the train's: none
            replace(m, stiffness=None) if m.stiffness == self.stiffness else m
            for m in self.meshes))
        names = [g.name for g in self.gears]
        for c in self.cracks:
            require(c.gear in names, "crack.gear", c.gear, f"must be one of {names}")
            z = self.gear(c.gear).teeth
            require(c.tooth < z, "crack.tooth", c.tooth, f"must be < {z} (teeth of {c.gear})")
        _ = self.pairs  # validates every mesh (interference, contact ratio)
        for c in self.cracks:  # every crack fits its tooth, checked once, here
            crack_geometry(ToothProfile(self.gear(c.gear)), c)
        check_faults(self)
        fe = [("stiffness.source" if m.stiffness is None else f"meshes[{j}].stiffness.source",
               m.gears) for j, m in enumerate(self.meshes)
              if (m.stiffness or self.stiffness).source == "fe-pair"]  # a mesh's own: its key
        for key, pair in fe:  # the cracks it reads (mesh_cracks)
            for c in (c for c in self.cracks if c.gear in pair):
                require(c.extent == 1.0 and c.profile == "uniform", key, "fe-pair",
                        f"models one transverse section: the crack on {c.gear} must be "
                        f"uniform over the face width (extent {c.extent:g}, profile "
                        f"{c.profile!r})")
        require(not (fe and (self.faults or self.modifications)), fe[0][0] if fe else "",
                "fe-pair", "gives whole-mesh tables: faults other than cracks and "
                'modifications need the mesh of contacts and a tooth model ("pe" or "fe")')

    def gear(self, name: str) -> Gear:
        """The gear called ``name``.

        Parameters
        ----------
        name : str
            Name of a gear of the train.

        Returns
        -------
        Gear
        """
        for g in self.gears:
            if g.name == name:
                return g
        raise KeyError(name)

    def settings_of(self, mesh: int) -> StiffnessSettings:
        """The stiffness options of mesh ``mesh``: its own, else the train's.

        Parameters
        ----------
        mesh : int
            Mesh index in power-flow order (0 = mesh I).

        Returns
        -------
        StiffnessSettings
        """
        pair = set(self.flow.meshes[mesh])
        return next(m.stiffness for m in self.meshes if set(m.gears) == pair) or self.stiffness

    def with_stiffness(self, **changes) -> GearTrain:
        """A copy with ``changes`` to the stiffness options of the train and of every mesh
        with its own (a study's variant switches ``closure`` on every mesh).

        Parameters
        ----------
        **changes
            Fields of :class:`StiffnessSettings` and their values.

        Returns
        -------
        GearTrain
        """
        return replace(self, stiffness=replace(self.stiffness, **changes), meshes=tuple(
            replace(m, stiffness=m.stiffness and replace(m.stiffness, **changes))
            for m in self.meshes))

    def compound_stages(self) -> tuple[tuple[int, int], ...] | None:
        """The stages of a compound train as the signal analysis takes them, or None.

        A train whose meshes form one serial path from the input shaft (the driving gear
        of each mesh on the shaft of the driven gear of the mesh before), at least one
        intermediate shaft carrying two gears, has one mesh frequency per stage
        (:func:`gearsim.signals.analysis.kinematics`, ``stages``).

        Returns
        -------
        tuple of (int, int) or None
            ``(driving teeth, driven teeth)`` of each mesh in power-flow order; None for
            a chain of idlers (one mesh frequency), a single mesh or a branched train.
        """
        fl = self.flow
        if not fl.meshes or len(fl.outputs) != 1:
            return None  # no mesh, or power that branches: no one serial path
        # one output: the path to it is every mesh (:meth:`path_kinematics`' rule)
        return self.path_kinematics(fl.outputs[0]).get("stages")

    def record_shaft(self, signal: str) -> int | None:
        """Shaft (power-flow index) a record of this train's results belongs to, or None.

        Records as :func:`gearsim.simulate` names them or as
        :meth:`gearsim.model.Gearbox.signals` writes them: ``mesh_force_i``, ``dte_i``,
        ``ste_i`` the driven shaft of mesh i; ``shaft_torque[spring=S:a-b]`` shaft S;
        ``acceleration[shaft=S,axis=y]``, ``acceleration[S,y]``, ``bearing_force``,
        ``shaft_angle``, ``tacho`` shaft S; ``angular_acceleration[rotation=R]`` the
        shaft of gear R (or shaft R).

        Parameters
        ----------
        signal : str
            The record's name.

        Returns
        -------
        int or None
            None for a name that says no shaft of this train.
        """
        m = _RECORD.fullmatch(signal)
        if m is None:
            return None
        fl = self.flow
        if m.group(2) is not None:  # mesh_force_i, dte_i, ste_i
            i = int(m.group(2)) - 1
            return fl.shaft_of[fl.meshes[i][1]] if 0 <= i < len(fl.meshes) else None
        label = (m.group(3) or "").split(",")[0].split("=")[-1].split(":")[0].strip()
        names = [sh.name for sh in fl.shafts]
        if label in names:
            return names.index(label)
        return fl.shaft_of.get(label)

    def path_kinematics(self, shaft: int) -> dict[str, tuple]:
        """Tooth counts of the power path from the input to ``shaft``, for the analysis.

        A train whose power branches has no one list of stages: a record of shaft S
        sees the meshes on the path to S. Along that path (meshes in power-flow order;
        for the input shaft, mesh I): ``{"stages": ((z_d, z_n), ...)}`` when a shaft on
        it carries two of its gears (:meth:`compound_stages`' rule), else
        ``{"teeth": (z_1, z_2, ...)}``, the gears in mesh order (one mesh, or idlers).

        Parameters
        ----------
        shaft : int
            Shaft index in the power flow.

        Returns
        -------
        dict
            ``stages`` or ``teeth``, keywords of
            :func:`gearsim.signals.analysis.kinematics`.
        """
        fl = self.flow
        path = fl.path_to(shaft) or [0]
        meshes = [fl.meshes[i] for i in path]
        if all(nxt[0] == prev[1] for prev, nxt in zip(meshes, meshes[1:], strict=False)):
            return {"teeth": tuple(int(self.gear(g).teeth) for g in
                                   [meshes[0][0], *(b for _, b in meshes)])}
        return {"stages": tuple((int(self.gear(a).teeth), int(self.gear(b).teeth))
                                for a, b in meshes)}

    def gear_index(self, name: str) -> int:
        """Position of the gear called ``name`` in the power flow (0 = input).

        Parameters
        ----------
        name : str
            Name of a gear of the train.

        Returns
        -------
        int
        """
        return [g.name for g in self.gears].index(name)

    @cached_property
    def flow(self) -> PowerFlow:
        """The solved graph: meshes oriented, shaft speed ratios and senses."""
        return power_flow({g.name: g for g in self.gears}, tuple(self.shafts),
                          tuple(self.meshes))

    @property
    def is_chain(self) -> bool:
        """True when every shaft carries one gear and gear i drives gear i + 1."""
        names = [g.name for g in self.gears]
        return (all(len(s.gears) == 1 and s.name == s.gears[0] for s in self.shafts)
                and self.flow.meshes == tuple(zip(names, names[1:], strict=False)))

    @cached_property
    def pairs(self) -> tuple[GearPair, ...]:
        """The meshes in power-flow order, named I, II, ... (driver, driven)."""
        roman = ("I", "II", "III", "IV", "V", "VI", "VII", "VIII")
        return tuple(
            GearPair(self.gear(a), self.gear(b), name=roman[i] if i < len(roman) else str(i + 1))
            for i, (a, b) in enumerate(self.flow.meshes)
        )

    # ------------------------------------------------------------------- kinematics
    def speed(self, i: int) -> float:
        """Speed of gear ``i`` [rad/s] (magnitude), from the input speed and tooth counts.

        Parameters
        ----------
        i : int
            Gear index in the power flow.

        Returns
        -------
        float
        """
        r = self.flow.ratio[self.flow.shaft_of[self.gears[i].name]]
        return self.operating.speed * r.numerator / r.denominator

    def torque(self, i: int) -> float:
        """Torque on gear ``i`` for loss-free transmission [N m]: T_in Sigma omega_in /
        omega_shaft, Sigma the share of the input power through the gear (eqs. (1), (2)
        of :mod:`gearsim.system.graph`: 1 without a branch, the shaft's torque; r_b is
        proportional to z within a mesh).

        Parameters
        ----------
        i : int
            Gear index in the power flow.

        Returns
        -------
        float
        """
        name = self.gears[i].name
        return self._loss_free_torque(name, self.flow.gear_share(name))

    def mesh_torque(self, mesh: int) -> float:
        """Torque the driver of mesh ``mesh`` passes through it [N m], T_in Sigma_mesh
        omega_in / omega_driver (eq. (2) of :mod:`gearsim.system.graph`).

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).

        Returns
        -------
        float
        """
        return self._loss_free_torque(self.pairs[mesh].driver.name, self.flow.mesh_share[mesh])

    def _loss_free_torque(self, gear: str, share: float) -> float:
        """T_in Sigma omega_in / omega_shaft on the shaft of ``gear`` for the power share
        ``share`` [N m] (eq. (2) of :mod:`gearsim.system.graph`)."""
        r = self.flow.ratio[self.flow.shaft_of[gear]]
        return self.operating.torque * share * r.denominator / r.numerator

    def shaft_frequency(self, i: int) -> float:
        """Shaft frequency f_r of gear ``i`` [Hz].

        Parameters
        ----------
        i : int
            Gear index in the power flow.

        Returns
        -------
        float
        """
        return self.speed(i) / (2 * math.pi)

    @property
    def mesh_frequency(self) -> float:
        """f_m of mesh I, z_1 f_r1 [Hz] (common to all meshes of a chain)."""
        return self.mesh_frequencies[0]

    @property
    def mesh_frequencies(self) -> tuple[float, ...]:
        """Mesh frequency z_driver f_driver of each mesh [Hz]."""
        f_in = self.operating.speed / (2 * math.pi)
        orders = [p.driver.teeth * self.flow.ratio[self.flow.shaft_of[p.driver.name]]
                  for p in self.pairs]  # mesh orders of the input shaft, exact
        return tuple(o.numerator * f_in / o.denominator for o in orders)

    @property
    def power(self) -> float:
        """Transmitted power T_1 omega_1 [W]."""
        return self.operating.torque * self.operating.speed

    def static_mesh_force(self, mesh: int) -> float:
        """Static transverse force along the line of action of mesh ``mesh`` [N]: the
        torque passed through it over the driver's base radius (:meth:`mesh_torque`).

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).

        Returns
        -------
        float
        """
        return self.mesh_torque(mesh) / self.pairs[mesh].driver.base_radius

    # ------------------------------------------------------------------- flanks
    def crack_side(self, crack: Crack, mesh: int) -> int:
        """+1 if mesh ``mesh`` loads the cracked flank, -1 if it loads the other flank.

        Parameters
        ----------
        crack : Crack
            A crack of this train.
        mesh : int
            Mesh index (0 = mesh I).

        Returns
        -------
        int
        """
        return flank_side(self, crack.gear, crack.flank, mesh)

    def mesh_cracks(self, mesh: int) -> tuple[ToothCrack, ...]:
        """The cracks of both gears of mesh ``mesh`` with their sides.

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).

        Returns
        -------
        tuple of ToothCrack
        """
        pair = self.pairs[mesh]
        return tuple(ToothCrack(gear=1 if c.gear == pair.driver.name else 2, crack=c,
                                side=self.crack_side(c, mesh))
                     for c in self.cracks if c.gear in (pair.driver.name, pair.driven.name))

    def mesh_stiffness(self, mesh: int, *, revolution_of: int = 1,
                       settings: StiffnessSettings | None = None) -> MeshStiffness:
        """TVMS of mesh ``mesh`` over one revolution of its gear 1 or 2.

        The tooth compliance comes from the model named by ``settings.source``
        (:func:`tooth_compliance`).

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).
        revolution_of : {1, 2}
            Over one revolution of the driver (1) or of the driven gear (2).
        settings : StiffnessSettings, optional
            Options; default the mesh's own (:meth:`settings_of`).

        Returns
        -------
        MeshStiffness
            Stiffness [N/m] per position, components and load sharing.
        """
        settings = settings or self.settings_of(mesh)
        if settings.source == "fe-pair":
            return fe_pair_train_stiffness(self, mesh, revolution_of=revolution_of,
                                           settings=settings)
        pair, cracks = self.pairs[mesh], self.mesh_cracks(mesh)
        force = self.static_mesh_force(mesh)
        # everything the table depends on (the force only under the line contact law)
        key = (pair, cracks, settings, revolution_of,
               force if settings.contact == "line" else None)
        hit = _TABLES.get(key)
        if hit is not None:
            return hit
        ms = mesh_stiffness(pair, cracks=cracks, settings=settings,
                            revolution_of=revolution_of,
                            compliance=tooth_compliance(settings.source), force=force,
                            coupling=body_coupling(settings))
        for arr in (ms.cycles, ms.theta1, ms.theta2, ms.k, ms.pair_k, ms.pair_tooth1,
                    ms.pair_tooth2, *ms.components.values()):
            if isinstance(arr, np.ndarray):
                arr.flags.writeable = False  # shared by every caller of the cache
        _TABLES.put(key, ms)
        return ms

    def has_contact_changes(self, mesh: int) -> bool:
        """True when faults, modifications or errors change the contacts of ``mesh``.

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).

        Returns
        -------
        bool
        """
        f1, f2 = mesh_flanks(self, mesh)
        return not (f1.empty and f2.empty)

    def mesh_contacts(self, mesh: int, *, period: int | None = None,
                      settings: StiffnessSettings | None = None) -> ContactGrid:
        """The mesh of contacts of mesh ``mesh``: stiffness and separation of each contact.

        Parameters
        ----------
        mesh : int
            Mesh index (0 = mesh I).
        period : int, optional
            Mesh cycles to cover (a multiple of the contacts' own period).
        settings : StiffnessSettings, optional
            Options; default the mesh's own (:meth:`settings_of`).

        Returns
        -------
        ContactGrid
            See :func:`gearsim.stiffness.contacts.contact_grid`.
        """
        settings = settings or self.settings_of(mesh)
        f1, f2 = mesh_flanks(self, mesh)
        return contact_grid(self.pairs[mesh], cracks=self.mesh_cracks(mesh), flank1=f1,
                            flank2=f2, settings=settings, period=period,
                            compliance=tooth_compliance(settings.source),
                            corner=settings.corner_contact,
                            force=self.static_mesh_force(mesh),
                            coupling=body_coupling(settings))

    def with_faults(self, faults: tuple[Fault, ...] = (),
                    modifications: tuple[Modification, ...] | None = None) -> GearTrain:
        """A copy with other faults (and modifications), checked like the train's own.

        Parameters
        ----------
        faults : tuple of Fault
            The faults of the copy.
        modifications : tuple of Modification, optional
            Its modifications; default the train's own.

        Returns
        -------
        GearTrain
        """
        mods = self.modifications if modifications is None else tuple(modifications)
        return replace(self, faults=tuple(faults), modifications=mods)

    def with_cracks(self, cracks: tuple[Crack, ...]) -> GearTrain:
        """A copy with other cracks (checked like the train's own).

        Parameters
        ----------
        cracks : tuple of Crack
            The cracks of the copy.

        Returns
        -------
        GearTrain
        """
        return replace(self, cracks=tuple(cracks))

    def with_crack(self, flank: str | None, *, depth: float | None = None,
                   closure: str | None = None, source: str | None = None) -> GearTrain:
        """The fault variant of this train: the one place that turns a train into it.

        Parameters
        ----------
        flank : {"none", "working", "non-working"} or None
            ``"none"``: no crack; ``"working"`` / ``"non-working"``: the train's cracks
            (or :data:`DEFAULT_CRACK` on the input gear when it has none) moved to that
            flank; ``None``: the cracks as they are.
        depth : float, optional
            Crack depth q0 [m] of every crack; default: as configured.
        closure : {"contact", "open"}, optional
            Crack-face model of the stiffness computation (of every mesh,
            :meth:`with_stiffness`); default: as configured.
        source : {"pe", "fe"}, optional
            Tooth-compliance model (of every mesh); default: as configured.

        Returns
        -------
        GearTrain
            The variant, checked (a crack that does not fit its tooth is refused here).

        Raises
        ------
        InputError
            For an unknown flank, or a crack deeper than its tooth allows.

        Examples
        --------
        >>> from gearsim import example
        >>> train = example("idler-table1").train.with_crack("non-working", depth=6e-3)
        >>> [(c.gear, c.tooth, c.flank, round(c.depth * 1e3, 3)) for c in train.cracks]
        [('input', 0, 'non-working', 6.0)]
        """
        tr = self
        changes = {k: v for k, v in (("closure", closure), ("source", source)) if v is not None}
        if changes:
            tr = tr.with_stiffness(**changes)
        if flank is None:
            cracks = tr.cracks
        elif flank == "none":
            cracks = ()
        elif flank in FLANKS:
            cracks = tr.cracks or (Crack(gear=tr.gears[0].name, **DEFAULT_CRACK),)
            cracks = tuple(replace(c, flank=flank) for c in cracks)
        else:
            raise InputError("crack", flank, "must be one of " + ", ".join(CRACK_CHOICES))
        if depth is not None:
            cracks = tuple(replace(c, depth=depth) for c in cracks)
        return replace(tr, cracks=cracks)
