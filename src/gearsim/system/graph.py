"""A gearbox as a graph: shafts carry gears, meshes join gears of two shafts.

Power enters at the input shaft and leaves at the output shaft. Walking the meshes from
the input orients each one (driver -> driven) and gives, for loss-free transmission,

    omega_B = omega_A z_a / z_b,   s_B = -s_A (external mesh),   F = T_a / r_b,a,
    T_b = F r_b,b                                                                 (1)

for a mesh between gear a on shaft A (driver) and gear b on shaft B: speeds from the
kinematics, the static mesh force from the torque the driver carries (equilibrium of the
driver gear), the torque received by the driven gear from the equilibrium of the driven
gear. A shaft that receives power through one gear passes it on through its other gears;
an idler (one gear, two meshes) passes the mesh force on unchanged. Which flank a mesh
loads follows from the power flow: a driver is loaded on its front face, a driven gear on
its rear face; the *working* flank of a gear is the one loaded in its first mesh, so an
idler's second mesh loads its other flank (reversed bending).

The flow is a tree from the input shaft: a shaft (or a gear) may drive several meshes,
each branch ending at an output shaft that takes its load. How the power divides is not
given by the statics of the graph: each output shaft of a branching box names its
``power_share`` sigma_k (> 0, summing to 1; one output takes all), and a mesh carries
the shares of the outputs beyond it,

    P_mesh = P_in sum_{k beyond} sigma_k,   T_gear = P_gear / omega_gear,
    F = T_in Sigma_mesh (omega_in / omega_driver) / r_b,driver,                  (2)

(loss-free; Sigma_mesh the summed share). A loop of meshes is refused (with disagreeing
ratios it cannot turn; with agreeing ratios its torques are statically indeterminate),
and so is power merging (a gear or shaft driven twice).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from fractions import Fraction

from gearsim.errors import InputError, require
from gearsim.stiffness.settings import StiffnessSettings

__all__ = ["MAX_BEARING_STIFFNESS", "MAX_INERTIA", "MAX_MASS", "MAX_SHAFT_STIFFNESS",
           "MIN_BEARING_STIFFNESS", "MIN_INERTIA", "MIN_MASS", "MIN_POWER_SHARE",
           "MIN_SHAFT_STIFFNESS", "SHARE_SUM_TOL",
           "MeshSpec", "PowerFlow", "Shaft", "power_flow"]

#: Bounds of a shaft's own mass [kg] and polar inertia [kg m^2]: the rotor of a 10 MW
#: wind turbine gearbox's largest shaft is below 1e5 kg and 1e5 kg m^2; 0 (the gears'
#: own masses only) is allowed.
MAX_MASS = 1e6
MAX_INERTIA = 1e6
#: Floors of a given member mass [kg] and inertia [kg m^2] (planetary members): a watch
#: wheel weighs ~1 mg, with ~1e-12 kg m^2 at its 1 mm radius; below, a unit mistake.
MIN_MASS = 1e-6
MIN_INERTIA = 1e-12
#: Bounds of a bearing stiffness [N/m]: 1e5 is an elastomer mount, 100 times softer than
#: the softest rolling bearing (~1e7); 1e15 is rigid for every gear train.
MIN_BEARING_STIFFNESS = 1e5
MAX_BEARING_STIFFNESS = 1e15
#: Smallest share of the input power an output shaft may take [-] (one part in a
#: million: a smaller take-off is a unit mistake, not a load).
MIN_POWER_SHARE = 1e-6
#: Tolerance of the sum of the outputs' power shares against 1 [-] (shares written to
#: nine digits, 1/3 as 0.333333333, add up to within 1e-9).
SHARE_SUM_TOL = 1e-8
#: Bounds of a shaft's torsional stiffness between its gears [N m/rad]: a 1 mm steel wire
#: 1 m long is ~1e-2 N m/rad, the stiffest multi-MW shafts ~1e9; outside, a unit mistake.
MIN_SHAFT_STIFFNESS = 1e-3
MAX_SHAFT_STIFFNESS = 1e12


def _number(v: object) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


@dataclass(frozen=True)
class Shaft:
    """A shaft carrying gears, on bearings.

    Parameters
    ----------
    name : str
        Name of the shaft.
    gears : tuple of str
        Names of the gears it carries, in axial order (the torsional springs join
        consecutive gears).
    mass : float
        The shaft's own mass [kg], in [0, 1e6]; the gears add theirs.
    inertia : float
        The shaft's own polar moment of inertia [kg m^2], in [0, 1e6]; the gears add
        theirs.
    torsional_stiffness : float or None
        Torsional stiffness between consecutive gears [N m/rad], in [1e-3, 1e12];
        ``None``: a rigid shaft (its gears turn as one body).
    bearing_stiffness, axial_stiffness : float or None
        Radial and axial stiffness of its bearings [N/m], in [1e5, 1e15] (an elastomer mount
        to a practically rigid support); ``None``: the ``[dynamics]`` defaults.
    power_share : float or None
        Share of the input power this output shaft takes as its load [-], in
        [1e-6, 1]; required on every output of a box whose power branches, ``None``
        otherwise (the one output takes it all).

    Raises
    ------
    InputError
        A value outside its range, no gear, a gear listed twice, or a torsional
        stiffness on a shaft of one gear.
    """

    name: str
    gears: tuple[str, ...]
    mass: float = 0.0
    inertia: float = 0.0
    torsional_stiffness: float | None = None
    bearing_stiffness: float | None = None
    axial_stiffness: float | None = None
    power_share: float | None = None

    def __post_init__(self) -> None:
        p = f"shafts.{self.name}"
        require(isinstance(self.name, str) and self.name != "", "shafts.name", self.name,
                "must be a non-empty string")
        require(len(self.gears) >= 1, f"{p}.gears", list(self.gears), "carries no gear")
        require(len(set(self.gears)) == len(self.gears), f"{p}.gears", list(self.gears),
                "names a gear twice")
        for key, hi in (("mass", MAX_MASS), ("inertia", MAX_INERTIA)):
            v = getattr(self, key)
            require(_number(v) and 0.0 <= v <= hi, f"{p}.{key}", v, f"must be in [0, {hi:g}]")
        kt = self.torsional_stiffness
        require(kt is None or (_number(kt) and MIN_SHAFT_STIFFNESS <= kt <= MAX_SHAFT_STIFFNESS),
                f"{p}.torsional_stiffness", kt,
                f"must be in [{MIN_SHAFT_STIFFNESS:g}, {MAX_SHAFT_STIFFNESS:g}] N*m/rad")
        require(kt is None or len(self.gears) >= 2, f"{p}.torsional_stiffness", kt,
                f"nothing to twist between: the shaft carries one gear ({self.gears[0]}); "
                "the stiffness joins consecutive gears of a shaft")
        for key in ("bearing_stiffness", "axial_stiffness"):
            v = getattr(self, key)
            require(v is None or (_number(v) and MIN_BEARING_STIFFNESS <= v <= MAX_BEARING_STIFFNESS),
                    f"{p}.{key}", v, f"must be in [{MIN_BEARING_STIFFNESS:g}, "
                    f"{MAX_BEARING_STIFFNESS:g}] N/m")
        w = self.power_share
        require(w is None or (_number(w) and MIN_POWER_SHARE <= w <= 1.0), f"{p}.power_share",
                w, f"must be in [{MIN_POWER_SHARE:g}, 1] (a fraction of the input power)")


@dataclass(frozen=True)
class MeshSpec:
    """Two gears in mesh, as written (the power flow decides which one drives).

    Parameters
    ----------
    gears : tuple of str
        The two gears.
    angle : float or None
        Global angle of the centre line from the driver's centre to the driven gear's
        [rad] (the planar layout of the lateral model); ``None``: from the idler angle
        when the driver is an idler, else 0 (the shafts in a row).
    stiffness : StiffnessSettings or None
        The mesh's own stiffness options (a ``[[meshes]]`` table's ``stiffness``);
        ``None``: the train's (:meth:`gearsim.system.GearTrain.settings_of`).
    """

    gears: tuple[str, str]
    angle: float | None = None
    stiffness: StiffnessSettings | None = None

    def __post_init__(self) -> None:
        require(len(self.gears) == 2, "meshes.gears", list(self.gears), "must name two gears")
        require(self.angle is None or (_number(self.angle) and abs(self.angle) <= 2 * math.pi),
                "meshes.angle", self.angle, "must be a finite angle in [-360, 360] deg")
        require(self.stiffness is None or isinstance(self.stiffness, StiffnessSettings),
                "meshes.stiffness", self.stiffness, "must be StiffnessSettings or None")


@dataclass(frozen=True)
class PowerFlow:
    """The solved graph (equations (1) of the module docstring).

    Parameters
    ----------
    shafts : tuple of Shaft
        The shafts, input first, in power-flow order (an output last).
    meshes : tuple of (str, str)
        (driver, driven) gear names of each mesh, in power-flow order.
    angles : tuple of float or None
        Centre-line angle of each mesh as written (:class:`MeshSpec`), same order.
    shaft_of : dict
        Gear name -> index of its shaft in ``shafts``.
    ratio : tuple of Fraction
        omega_shaft / omega_input of each shaft [-], exact (products of tooth ratios;
        the static torque ratio is its inverse).
    sense : tuple of int
        Sense of rotation of each shaft (+1 as the input) [-].
    share : tuple of float
        Share of the input power through each shaft [-] (equation (2): 1 without a
        branch; an output's own ``power_share``).
    mesh_share : tuple of float
        Share of the input power through each mesh [-]: its driven shaft's.
    """

    shafts: tuple[Shaft, ...]
    meshes: tuple[tuple[str, str], ...]
    angles: tuple[float | None, ...]
    shaft_of: dict
    ratio: tuple[Fraction, ...]
    sense: tuple[int, ...]
    share: tuple[float, ...] = ()
    mesh_share: tuple[float, ...] = ()

    @property
    def outputs(self) -> tuple[int, ...]:
        """Indices of the output shafts (those driving no mesh), in power-flow order."""
        driving = {self.shaft_of[d] for d, _ in self.meshes}
        return tuple(i for i in range(len(self.shafts)) if i not in driving)

    def path_to(self, shaft: int) -> list[int]:
        """The meshes carrying the power from the input shaft to ``shaft``.

        Parameters
        ----------
        shaft : int
            Shaft index in power-flow order.

        Returns
        -------
        list of int
            Mesh indices in power-flow order (empty for the input shaft).
        """
        into = {self.shaft_of[b]: i for i, (_, b) in enumerate(self.meshes)}
        path: list[int] = []
        while shaft in into:
            path.insert(0, into[shaft])
            shaft = self.shaft_of[self.meshes[into[shaft]][0]]
        return path

    def gear_share(self, gear: str) -> float:
        """Share of the input power through ``gear`` [-] (equation (2)).

        A gear that drives carries the meshes it drives; a gear that only receives, its
        shaft's share (the power it brings in).

        Parameters
        ----------
        gear : str
            Gear name.

        Returns
        -------
        float
        """
        drives = [i for i, (d, _) in enumerate(self.meshes) if d == gear]
        if not drives:
            return self.share[self.shaft_of[gear]]
        return math.fsum(self.mesh_share[i] for i in drives)

    def meshes_of(self, gear: str) -> list[tuple[int, int]]:
        """(mesh index, 1 driver / 2 driven) of the meshes ``gear`` takes part in.

        Parameters
        ----------
        gear : str
            Gear name.

        Returns
        -------
        list of (int, int)
            In power-flow order.
        """
        return [(i, 1 if m[0] == gear else 2) for i, m in enumerate(self.meshes) if gear in m]

    def flank_side(self, gear: str, flank: str, mesh: int) -> int:
        """+1 if mesh ``mesh`` loads ``flank`` of ``gear``, -1 if it loads the other flank.

        Parameters
        ----------
        gear : str
            Gear name.
        flank : {"working", "non-working"}
            The flank asked about (working: the one loaded in the gear's first mesh).
        mesh : int
            Mesh index.

        Returns
        -------
        int
        """
        roles = dict(self.meshes_of(gear))
        first = self.meshes_of(gear)[0][1]
        return 1 if (flank == "working") == (roles[mesh] == first) else -1


def _refuse_loops(gears: dict, shaft_of: dict, meshes: tuple[MeshSpec, ...]) -> None:
    """Refuse the first mesh that joins two shafts already joined by earlier meshes.

    The speed ratios of the shafts along the earlier meshes (a spanning tree, walked
    breadth first) tell whether the loop could turn at all.
    """
    ratio: dict[int, dict[int, float]] = {}  # component root -> shaft -> speed ratio
    root: dict[int, int] = {}
    for m_i, m in enumerate(meshes):
        (a, b), (za, zb) = ((shaft_of[g] for g in m.gears), (gears[g].teeth for g in m.gears))
        ra, rb = root.setdefault(a, a), root.setdefault(b, b)
        ca, cb = ratio.setdefault(ra, {a: 1.0}), ratio.setdefault(rb, {b: 1.0})
        if ra == rb:
            agree = math.isclose(ca[a] * za / zb, ca[b], rel_tol=1e-9)
            raise InputError(f"meshes[{m_i}].gears", list(m.gears), "closes a loop of meshes ("
                             + ("its torques are statically indeterminate" if agree
                                else "ratios disagree") + "): not supported")
        scale = ca[a] * za / zb / cb[b]  # speed ratios of b's component in a's terms
        for s, r in ratio.pop(rb).items():
            ca[s], root[s] = r * scale, ra


def power_flow(gears: dict, shafts: tuple[Shaft, ...], meshes: tuple[MeshSpec, ...]
               ) -> PowerFlow:
    """Orient the meshes from the input shaft (``shafts[0]``) and check the graph.

    Parameters
    ----------
    gears : dict
        Gear name -> :class:`~gearsim.geometry.gear.Gear` (its ``teeth``).
    shafts : tuple of Shaft
        The shafts; the first is the input.
    meshes : tuple of MeshSpec
        The meshes as written.

    Returns
    -------
    PowerFlow

    Raises
    ------
    InputError
        A gear on no shaft or on two, a shaft naming an unknown gear, a mesh of an
        unknown gear or of two gears on one shaft, a gear meshing nothing, a shaft the
        power does not reach, a loop of meshes, the outputs' power shares missing, out of
        range or not adding up to 1; the message names the element (``gears[3].shaft``,
        ``meshes[1].gears``, ``shafts.out-b.power_share``, ...).

    Examples
    --------
    A two-stage reducer 32/80 then 48/64: the output turns at 32 48 / (80 64) = 0.3 of
    the input, in the input's sense.

    >>> from types import SimpleNamespace as G
    >>> gears = {n: G(teeth=z) for n, z in (("p1", 32), ("g1", 80), ("p2", 48), ("g2", 64))}
    >>> flow = power_flow(gears, (Shaft("in", ("p1",)), Shaft("mid", ("g1", "p2")),
    ...                           Shaft("out", ("g2",))),
    ...                   (MeshSpec(("g1", "p1")), MeshSpec(("p2", "g2"))))
    >>> flow.meshes, [str(r) for r in flow.ratio], flow.sense
    ((('p1', 'g1'), ('p2', 'g2')), ['1', '2/5', '3/10'], (1, -1, 1))
    """
    names = [s.name for s in shafts]
    require(len(set(names)) == len(names), "shafts.name", names, "names must be unique")
    shaft_of: dict[str, int] = {}
    for s_i, s in enumerate(shafts):
        for g in s.gears:
            require(g in gears, f"shafts[{s_i}].gears", g,
                    "no such gear; gears: " + ", ".join(gears))
            if g in shaft_of:
                raise InputError(f"gears.{g}.shaft", f"{shafts[shaft_of[g]].name}, {s.name}",
                                 "a gear sits on one shaft only")
            shaft_of[g] = s_i
    for g in gears:
        require(g in shaft_of, f"gears.{g}.shaft", "missing", "every gear sits on a shaft")
    for m_i, m in enumerate(meshes):
        for g in m.gears:
            require(g in gears, f"meshes[{m_i}].gears", list(m.gears),
                    f"{g!r}: no such gear; gears: " + ", ".join(gears))
        a, b = m.gears
        require(shaft_of[a] != shaft_of[b], f"meshes[{m_i}].gears", list(m.gears),
                f"both sit on shaft {shafts[shaft_of[a]].name!r}")
    meshed = {g for m in meshes for g in m.gears}
    for g in gears:
        require(g in meshed, f"gears.{g}", "meshes nothing", "every gear takes part in a mesh")
    _refuse_loops(gears, shaft_of, meshes)
    ratio: dict[int, Fraction] = {0: Fraction(1)}
    sense: dict[int, int] = {0: 1}
    order, oriented, angles = [0], [], []
    done: set[int] = set()
    k = 0
    while k < len(order):
        s_i = order[k]
        k += 1
        out = [(m_i, m) for m_i, m in enumerate(meshes) if m_i not in done
               and any(shaft_of[g] == s_i for g in m.gears)]
        for m_i, m in out:
            done.add(m_i)
            drv, dvn = m.gears if shaft_of[m.gears[0]] == s_i else m.gears[::-1]
            t_i = shaft_of[dvn]
            ratio[t_i] = ratio[s_i] * Fraction(gears[drv].teeth, gears[dvn].teeth)
            sense[t_i] = -sense[s_i]
            order.append(t_i)
            oriented.append((drv, dvn))
            angles.append(m.angle)
    for s_i, s in enumerate(shafts):
        require(s_i in ratio, f"shafts.{s.name}", "not driven",
                f"no path of meshes from the input shaft {shafts[0].name!r}")
    share = _shares(shafts, order, [(shaft_of[a], shaft_of[b]) for a, b in oriented])
    return PowerFlow(shafts=tuple(shafts[i] for i in order), meshes=tuple(oriented),
                     angles=tuple(angles),
                     shaft_of={g: order.index(i) for g, i in shaft_of.items()},
                     ratio=tuple(ratio[i] for i in order), sense=tuple(sense[i] for i in order),
                     share=tuple(share[i] for i in order),
                     mesh_share=tuple(share[shaft_of[b]] for _, b in oriented))


def _shares(shafts: tuple[Shaft, ...], order: list[int], links: list[tuple[int, int]]
            ) -> dict[int, float]:
    """Share of the input power through each shaft (equation (2)), by shaft index.

    The outputs (shafts driving no mesh) take their ``power_share`` (1 for a single
    output); a shaft passes on the sum of the shafts it drives, summed from the outputs
    back to the input in reverse power-flow order.
    """
    driven = {a: [b for a_, b in links if a_ == a] for a, _ in links}
    outputs = [i for i in order if i not in driven]
    for i in order:
        if i in driven and shafts[i].power_share is not None:
            raise InputError(f"shafts.{shafts[i].name}.power_share", shafts[i].power_share,
                             "only an output shaft (one that drives no mesh) takes a share "
                             "of the power: a take-off on a driving shaft is not read")
    if len(outputs) == 1:
        w = shafts[outputs[0]].power_share
        require(w is None or w == 1.0, f"shafts.{shafts[outputs[0]].name}.power_share", w,
                "the only output takes all the power: 1 or not given")
        share = {outputs[0]: 1.0}
    else:
        for i in outputs:
            require(shafts[i].power_share is not None, f"shafts.{shafts[i].name}.power_share",
                    "missing", "the power branches: every output shaft names its share of "
                    "the input power (" + ", ".join(shafts[j].name for j in outputs) + ")")
        total = math.fsum(shafts[i].power_share for i in outputs)
        require(abs(total - 1.0) <= SHARE_SUM_TOL, "shafts.power_share",
                {shafts[i].name: shafts[i].power_share for i in outputs},
                f"the outputs' shares add up to {total:.12g}, not 1 (within {SHARE_SUM_TOL:g})")
        share = {i: shafts[i].power_share for i in outputs}
    for i in reversed(order):
        if i in driven:
            share[i] = math.fsum(share[j] for j in driven[i])
    return share
