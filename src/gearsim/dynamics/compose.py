r"""A planetary stage followed by a chain of parallel gears, coupled by the output shaft.

The stage's output member (the one neither held nor driven: the sun of a wind-turbine
stage driven by its carrier, the carrier of a helicopter stage driven by its sun) carries
the first gear of a :class:`gearsim.system.GearTrain` on a torsional shaft of stiffness
k_t. The two models keep their own coordinates and springs
(:func:`gearsim.dynamics.stage.build_stage_model`, Lin & Parker 1999 in the stage's model
frame; :func:`gearsim.dynamics.lta.build_lta`, the chain's lateral-torsional-axial model)
and are joined by one more spring row, the shaft:

    tau = k_t (s u_o / r_o - theta_1) + c_t (s u_o' / r_o - theta_1'),

with u_o the output member's rotation coordinate of the stage model (arc length on the
radius r_o: base radius of the sun or ring, planet-centre radius of the carrier),
theta_1 the chain's first gear (positive in its sense of rotation) and s = +-1 the sense
of the output's physical rotation in the stage's model frame (opposite to the load torque
there). The shaft torque replaces the stage's load torque on u_o and the chain's input
torque on theta_1; the chain keeps its loads, on the last gear T_o r_b,N / r_b,1 (on
each output shaft of a chain whose power branches its share, sigma_k T_o omega_o /
omega_k: :func:`gearsim.dynamics.lta.build_lta`), so the static torques balance and the
static shaft torque is the stage's output torque T_o.
Shaft damping c_t = 2 zeta sqrt(k_t J_eq), J_eq = 1 / (1/J_o + 1/J_1) (the bearing
damping ratio; J_o = m_uo r_o^2).

Two mesh frequencies: the stage's f_m and the chain's f_m2 = z_1 |omega_o| / 2 pi. The
kernel reads mesh i's table at c_i = rate_i f_m t + phase_i (``DynamicModel.rate``),
rate 1 for the stage's rows and f_m2 / f_m for the chain's.

The stage may equally be driven by the chain (``side = "input"``: a parallel input
stage ahead of a planetary output stage, as in helicopter main gearboxes and most
industrial planetary reducers). The shaft then joins the chain's last gear theta_N to the
stage's input member u_i, tau = k_t (theta_N - s_i u_i / r_i) + c_t (...)', s_i the sense
of the input's rotation in the model frame (with its driving torque); the shaft replaces
the chain's load torque on theta_N and the stage's input torque on u_i, and the stage runs
at the chain's output speed and torque (:func:`stage_operating`). The gearbox's input,
its speed profile and its inertia load are then the chain's.

Stages in series (:class:`NextStage`, a helicopter's or a wind turbine's planetary stages)
are joined the same way, by one shaft row from stage k's output member u_o to stage
k+1's input member u_i, tau = k_t (s_o u_o / r_o - s_i u_i / r_i) + c_t (...)', with
J_eq from both members (J = m_u r^2); stage k+1 runs at stage k's output speed and
torque (:func:`next_operating`), its rows read their tables at rate f_m,k+1 / f_m,1. One
function, ``_join``, joins a part (a chain's or a stage's model) to the model built so
far through such a shaft; the parts only say which coordinates the shaft turns.

Gears between two stages (``NextStage.input_train``: stage k's output drives a chain whose
last gear drives stage k+1) are two such joins: the chain to stage k's output member as a
chain the stage drives (at :func:`chain_operating` of stage k), then stage k+1 to the
chain's last gear as a stage an input chain drives, tau = k_t (theta_N - s_i u_i / r_i)
(stage k+1 at :func:`stage_operating` of the chain). Default k_t of the two shafts: as
the chains', ten times the torsional stiffness of the chain's first (last) mesh.

The chain runs at the stage's output speed and torque (:func:`chain_operating`); its
other options (layout, bearings, profile modification, runout, cracks and faults of its
gears) are its own. The default shaft is stiff: ten times the torsional stiffness of the
chain's first mesh, k_t = 10 k_mean r_b,1^2.

References
----------
.. [LinParker1999] J. Lin, R. G. Parker, J. Vib. Acoust. 121 (1999) 316-321.
.. [Kahraman1994] A. Kahraman, Dynamic analysis of a multi-mesh helical gear train,
   J. Mech. Des. 116 (1994) 706-712.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from gearsim.dynamics.lta import build_lta
from gearsim.dynamics.model import DynamicModel, nominal_inertia, static_equilibrium
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import check_twist, check_twists
from gearsim.dynamics.stage import StageDynamics, build_stage_model, model_radii, simulate_stage
from gearsim.dynamics.tables import MeshTable, mesh_tables
from gearsim.errors import InputError, require
from gearsim.system import GearTrain
from gearsim.system.graph import MAX_SHAFT_STIFFNESS, MIN_SHAFT_STIFFNESS
from gearsim.system.planetary import MEMBERS, PlanetaryTrain, StageOperating
from gearsim.system.train import Operating

__all__ = ["SHAFT_FACTOR", "SIDES", "STAGE_ONLY", "NextStage", "build_stage_chain_model",
           "chain_of_record", "chain_operating", "next_operating", "output_member", "simulate_stage_chain",
           "stage_of_label", "stage_operating", "stage_prefix", "stage_settings",
           "stage_shaft_names"]

#: Where the chain sits: driven by the stage's output ("output") or driving its input.
SIDES = ("output", "input")

#: Default shaft: this many times the torsional stiffness of the chain's first mesh.
SHAFT_FACTOR = 10.0
#: Dynamics options of the chain that the stage model refuses: reset for the stage.
STAGE_ONLY = {"profile_modification": (0.0,), "crowning": (0.0,),
              "runout": (0.0,), "runout_phase": (0.0,), "assembly_error": (0.0,),
              "contact_mesh": False, "bearing_damping": None, "bearing_axial_stiffness": None,
              "idler_angle": ()}
#: Relative agreement required between the chain's operating point and the stage output.
OPERATING_RTOL = 1e-9


@dataclass(frozen=True)
class NextStage:
    """A planetary stage driven by the previous stage's output member through a shaft.

    Parameters
    ----------
    train : PlanetaryTrain
        The stage, at the previous stage output's speed and torque
        (:func:`next_operating`).
    members : StageDynamics
        Its members' masses, inertias and supports (its sensor is not used: the ring
        sensor of a result is the first stage's).
    shaft_stiffness : float or None
        k_t [N m/rad] of the shaft from the previous stage's output member to this
        stage's input member (to ``input_train``'s first gear when it has one);
        ``None``: ``SHAFT_FACTOR`` N k_sp r_b,s^2 of this stage (ten times the torsional
        stiffness of its sun meshes about the sun; with ``input_train`` as
        :func:`build_stage_chain_model`'s ``chain`` on the output side).
    input_train : GearTrain or None
        Gears between the previous stage and this one: at the previous stage output's
        speed and torque (:func:`chain_operating`), their last gear driving this stage's
        input member (the stage at :func:`stage_operating` of them).
    input_shaft_stiffness : float or None
        k_t [N m/rad] of the shaft from ``input_train``'s last gear to this stage's
        input member; ``None``: as :func:`build_stage_chain_model`'s ``input_chain``.
    """

    train: PlanetaryTrain
    members: StageDynamics = field(default_factory=StageDynamics)
    shaft_stiffness: float | None = None
    input_train: GearTrain | None = None
    input_shaft_stiffness: float | None = None


def output_member(train: PlanetaryTrain) -> str:
    """The stage member neither held nor driven (its output).

    Parameters
    ----------
    train : PlanetaryTrain
        The stage in operation.

    Returns
    -------
    str
        ``"sun"``, ``"ring"`` or ``"carrier"``.
    """
    op = train.operating
    return next(m for m in MEMBERS if m not in (op.fixed, op.input))


def chain_operating(train: PlanetaryTrain) -> Operating:
    """Operating point of a chain driven by the stage's output shaft.

    Parameters
    ----------
    train : PlanetaryTrain
        The stage in operation.

    Returns
    -------
    Operating
        Speed |omega_o| [rad/s] and torque |T_o| [N m] of the output member (Willis and
        the torque balance of :class:`PlanetaryTrain`).
    """
    out = output_member(train)
    return Operating(speed=abs(train.speeds[out]), torque=abs(train.torques[out]))


def stage_operating(chain: GearTrain, fixed: str, driven: str) -> StageOperating:
    """Operating point of a stage driven by a chain's output shaft.

    Parameters
    ----------
    chain : GearTrain
        The chain in operation; its last gear in the power flow drives the stage.
    fixed, driven : str
        The stage's held member and the member the chain drives.

    Returns
    -------
    StageOperating
        Speed [rad/s] and torque [N m] of the chain's last gear (loss-free kinematics and
        statics of :mod:`gearsim.system.graph`).
    """
    last = chain.gear_index(chain.flow.meshes[-1][1])
    return StageOperating(fixed=fixed, input=driven, speed=chain.speed(last),
                          torque=chain.torque(last))


def stage_settings(settings: DynamicsSettings) -> DynamicsSettings:
    """``settings`` with the chain-only options reset, for the stage model.

    Parameters
    ----------
    settings : DynamicsSettings
        Options of the whole system.

    Returns
    -------
    DynamicsSettings
        The same with :data:`STAGE_ONLY` applied (fields the settings do not have are
        skipped).
    """
    names = {f.name for f in dataclasses.fields(settings)}
    return dataclasses.replace(settings, **{k: v for k, v in STAGE_ONLY.items() if k in names})


def _pad(a: np.ndarray | None, rows: int, cols: int) -> np.ndarray:
    """``a`` (rows x <= cols) padded with zero columns; zeros when None."""
    out = np.zeros((rows, cols))
    if a is not None:
        out[:, :a.shape[1]] = a
    return out


def build_stage_chain_model(train: PlanetaryTrain, chain: GearTrain | None,
                            dyn: StageDynamics | None = None,
                            settings: DynamicsSettings | None = None, *,
                            shaft_stiffness: float | None = None,
                            side: str = "output", input_chain: GearTrain | None = None,
                            input_shaft_stiffness: float | None = None,
                            stages: Sequence[NextStage] = ()) -> DynamicModel:
    """Equations of motion of stages, chains of parallel gears and the shafts between.

    Parameters
    ----------
    train
        The (first) stage in operation.
    chain
        A chain; its operating point must be :func:`chain_operating` of the last stage
        (``side = "output"``), or the first stage's that of the chain's last gear
        (:func:`stage_operating`, ``side = "input"``). ``None``: no such chain.
    dyn
        Members, supports and sensor of the first stage.
    settings
        Dynamics options (the chains' own options apply to the chains only).
    shaft_stiffness
        k_t [N m/rad] of ``chain``'s shaft, finite > 0; default ``SHAFT_FACTOR`` k_mean
        r_b^2 of the chain's mesh next to the shaft (its first on the output side, its
        last on the input side).
    side : {"output", "input"}
        ``chain`` is driven by the last stage's output member, or drives the first
        stage's input member.
    input_chain
        Gears driving the first stage's input member as well (with ``chain`` on the
        output side): the stages between two chains.
    input_shaft_stiffness
        k_t [N m/rad] of ``input_chain``'s shaft (default as ``shaft_stiffness``).
    stages
        Further stages in series, each driven by the previous stage's output member
        through its shaft, or through the gears between (:class:`NextStage`). With any,
        the coordinates, gear names and rows of stage k are prefixed ``stage<k>-``
        (:func:`stage_prefix`).

    Returns
    -------
    DynamicModel
        ``kind = "stage+chain"``: the stages' coordinates, then each chain's in the
        order joined; rows: the first stage's springs, per further stage its springs and
        shaft, then per chain its meshes, springs and shaft. ``info`` holds the first
        stage's ``lin_parker``; ``mesh_rows`` and ``row_names`` of all stages;
        ``stages`` (with further stages), one dict per stage (``train``, ``prefix``,
        ``rows`` (its meshes), ``shaft_row`` (from the previous stage; None for the
        first), ``shaft_stiffness``, ``member``, ``dofs``, ``mesh_frequency``);
        ``chains``, one dict per chain in the order joined (``chain``, ``side``
        (``"between"`` for gears between two stages), ``rows`` (its meshes),
        ``shaft_row``, ``shaft_stiffness``, ``member``, ``dofs``, ``bearing_dofs``,
        ``axes``, ``shafts``, ``mesh_frequency``); each shaft's ``twist`` (the names of
        its k_t and of the shaft, for messages); and, of the first chain,
        ``chain_rows``, ``shaft_row``, ``chain_mesh_frequency``, ``shaft_stiffness``,
        ``chain_side``.

    Raises
    ------
    InputError
        If the parts' operating points disagree, the side is unknown, a second chain is
        not on the input side, or a shaft stiffness is not finite > 0.

    References
    ----------
    Lin & Parker (1999); Kahraman (1994); module docstring.
    """
    settings = settings or DynamicsSettings()
    require(side in SIDES, "chain.side", side, 'must be "output" or "input"')
    require(chain is not None or input_chain is not None or stages, "chain", None,
            "a stage alone is gearsim.dynamics.stage.build_stage_model")
    require(input_chain is None or chain is None or side == "output", "chain.side", side,
            "with an input chain the other chain is on the output side")
    trains = (train, *(s.train for s in stages))
    prefix = [stage_prefix(k, len(trains)) for k in range(len(trains))]
    model = _prefixed(build_stage_model(train, dyn, stage_settings(settings)), prefix[0])
    model.info["input_index"] = model.dof_labels.index(f"{prefix[0]}{train.operating.input}.u")
    if stages:
        model.info["stages"] = ({"train": train, "prefix": prefix[0], "shaft_row": None,
                                 "rows": model.info["mesh_rows"], "shaft_stiffness": None,
                                 "member": train.operating.input, "dofs": (0, model.n_dof),
                                 "mesh_frequency": train.mesh_frequency},)
    for k, nxt in enumerate(stages, 1):
        model = _join_stage(model, trains[k - 1], prefix[k - 1], nxt, prefix[k], settings,
                            f"stages[{k}]")
    if chain is not None:
        at = -1 if side == "output" else 0
        model = _join_chain(model, trains[at], prefix[at], chain, side, shaft_stiffness,
                            settings)
    if input_chain is not None:
        model = _join_chain(model, train, prefix[0], input_chain, "input",
                            input_shaft_stiffness, settings, "input_chain.shaft_stiffness")
    return model


def stage_prefix(k: int, n: int) -> str:
    """Prefix of the coordinates, gears and meshes of stage ``k`` (from 0) of ``n``.

    Parameters
    ----------
    k, n : int
        The stage's index in power-flow order and the number of stages.

    Returns
    -------
    str
        ``""`` for a stage alone (its names are unchanged), else ``"stage<k+1>-"``
        (``stage1-sun-planet-1``, ``stage2-sun-planet-1``: as the meshes of several
        chains are numbered through).
    """
    return "" if n == 1 else f"stage{k + 1}-"


def stage_of_label(label: str, n: int) -> int:
    """Index (from 0) of the stage of ``n`` in series that a record labelled ``label``
    belongs to: the last ``stage<k>-`` the label names (a mesh ``stage2-sun-planet-1``,
    a coordinate ``stage2-carrier.x``, the shaft driving stage 2
    ``shaft-stage1-carrier-stage2-sun``); else the first stage (its ring's sensor and
    acceleration, a stage alone).

    Parameters
    ----------
    label : str
        A record's label, or a result channel's (``mesh=stage2-sun-planet-1``).
    n : int
        Number of stages.

    Returns
    -------
    int

    Examples
    --------
    >>> stage_of_label("shaft-stage1-carrier-stage2-sun", 2)
    1
    >>> stage_of_label("sun-planet-1", 1)
    0
    """
    k = re.findall(r"stage(\d+)-", label) if n > 1 else []
    return int(k[-1]) - 1 if k and 1 <= int(k[-1]) <= n else 0


def chain_of_record(variable: str, label: str | None, shafts: list[list[str]],
                    meshes: list[list[str]], between: Sequence[str | bool] = ()) -> int | None:
    """Index of the gear chain beside the stages that a record of a stage result belongs
    to, or None for a record of the stages.

    ``input_shaft_torque`` is the first chain's at an end (the gears driving the
    stages), ``shaft_torque`` the last one's (the shaft between the stages and the gears
    they drive, or those driving them when there is no other); ``stage_shaft_torque``
    of the shaft from a stage to the gears between two stages those gears' (as a shaft
    driving a stage is the stage's); ``chain_acceleration`` the chain holding its shaft,
    ``chain_mesh_force`` the chain holding its mesh, ``q`` (``shaft.axis``) the chain
    holding its shaft (a stage member's coordinate: None).

    Parameters
    ----------
    variable : str
        The record's variable (``chain_mesh_force``).
    label : str or None
        Its label (a mesh ``II`` or a shaft name).
    shafts, meshes : list of list of str
        Each chain's shaft and mesh names, in power-flow order.
    between : sequence of str or bool, optional
        Of each chain sitting between two stages, the name of the shaft from the stage
        driving it (``shaft-stage1-sun-g23``; True: not known), else False (default:
        none sits between).

    Returns
    -------
    int or None

    Examples
    --------
    >>> chain_of_record("chain_mesh_force", "II", [["a", "b"], ["c", "d"]], [["I"], ["II"]])
    1
    >>> chain_of_record("mesh_force", "sun-planet-1", [["a", "b"]], [["I"]]) is None
    True
    >>> chain_of_record("stage_shaft_torque", "shaft-stage1-sun-g23", [["a", "b"]], [["I"]],
    ...                 ["shaft-stage1-sun-g23"])
    0
    """
    ends = [k for k in range(len(shafts)) if not (between and between[k])]
    if variable in ("input_shaft_torque", "shaft_torque"):
        return (ends[0] if variable == "input_shaft_torque" else ends[-1]) if ends else None
    if variable == "stage_shaft_torque":
        return next((k for k, name in enumerate(between) if name == label), None)
    held = {"chain_acceleration": shafts, "chain_mesh_force": meshes, "q": shafts}.get(variable)
    if held is None or label is None:
        return None
    if variable == "q":  # a coordinate, shaft.axis: a chain shaft's, else a stage member's
        label = label.rpartition(".")[0]
    return next((k for k, names in enumerate(held) if label in names), None)


def stage_shaft_names(prev_prefix: str, prev: PlanetaryTrain, prefix: str,
                      nxt: NextStage) -> tuple[str, ...]:
    """Names of the shafts from the stage ``prev``'s output member to ``nxt``'s input.

    Parameters
    ----------
    prev_prefix, prefix : str
        The two stages' name prefixes (:func:`stage_prefix`).
    prev : PlanetaryTrain
        The driving stage.
    nxt : NextStage
        The driven stage (and the gears between, if any).

    Returns
    -------
    tuple of str
        ``shaft-<prev_prefix><output member>-<prefix><input member>``
        (``shaft-stage1-carrier-stage2-sun``); with gears between, the shaft from the
        member to their first gear and the one from their last gear to the member
        (``shaft-stage1-sun-g23``, ``shaft-g57-stage2-sun``).
    """
    up, down, ch = (f"{prev_prefix}{output_member(prev)}",
                    f"{prefix}{nxt.train.operating.input}", nxt.input_train)
    if ch is None:
        return (f"shaft-{up}-{down}",)
    return (f"shaft-{up}-{ch.gears[0].name}",
            f"shaft-{ch.gear(ch.flow.meshes[-1][1]).name}-{down}")


def next_operating(prev: PlanetaryTrain, fixed: str, driven: str) -> StageOperating:
    """Operating point of a stage driven by the output member of the stage ``prev``.

    Parameters
    ----------
    prev : PlanetaryTrain
        The driving stage in operation.
    fixed, driven : str
        The next stage's held member and the member the shaft drives.

    Returns
    -------
    StageOperating
        Speed |omega_o| [rad/s] and torque |T_o| [N m] of ``prev``'s output member
        (:func:`chain_operating`; loss-free).
    """
    op = chain_operating(prev)
    return StageOperating(fixed=fixed, input=driven, speed=op.speed, torque=op.torque)


def _prefixed(model: DynamicModel, prefix: str) -> DynamicModel:
    """``model`` (a stage's) with ``prefix`` before its coordinate, gear and row names."""
    if not prefix:
        return model
    return dataclasses.replace(
        model, dof_labels=tuple(prefix + s for s in model.dof_labels),
        gear_names=tuple(prefix + s for s in model.gear_names),
        info={**model.info, "row_names": tuple(prefix + s for s in model.info["row_names"])})


def _rotation(model: DynamicModel, chain: GearTrain, gear) -> int:
    """Index in ``model`` (a chain's) of the rotation coordinate ``gear`` turns with: its
    shaft's, or its own on a shaft that twists between its gears."""
    shaft = chain.flow.shafts[chain.flow.shaft_of[gear.name]].name
    label = f"{shaft}.theta" if f"{shaft}.theta" in model.dof_labels else f"{gear.name}.theta"
    return model.dof_labels.index(label)


def _member(model: DynamicModel, prefix: str, train: PlanetaryTrain, member: str,
            side: str) -> tuple[int, float, float]:
    """(index, a, J) of a stage member on a shaft: its coordinate u in ``model``, the
    factor a = s / r turning u into the angle in the member's sense of rotation (s as in
    the module docstring: an output turns against its load, an input with its driving
    torque; r from :func:`model_radii`) and its inertia J = m_u r^2 [kg m^2]."""
    i = model.dof_labels.index(f"{prefix}{member}.u")
    r = model_radii(train.stage)[member]
    t_model = train.model_torques[member]
    require(t_model != 0.0, "stage", member, "the member on the shaft carries no torque")
    s = math.copysign(1.0, t_model) * (-1.0 if side == "output" else 1.0)
    return i, s / r, model.mass[i] * r ** 2


def _check_shaft(kt: object, parameter: str) -> float:
    """``kt`` [N m/rad] if finite in the shafts' bounds, else one line naming it."""
    if not (isinstance(kt, (int, float)) and MIN_SHAFT_STIFFNESS <= kt <= MAX_SHAFT_STIFFNESS):
        raise InputError(parameter, kt, f"must be a finite number in "
                         f"[{MIN_SHAFT_STIFFNESS:g}, {MAX_SHAFT_STIFFNESS:g}] N*m/rad")
    return kt


def _check_operating(got_op, want, what: str, hint: str) -> None:
    for name in ("speed", "torque"):
        got, ref = getattr(got_op, name), getattr(want, name)
        require(abs(got - ref) <= OPERATING_RTOL * ref, f"{what}.operating.{name}", got,
                "must be " + hint.format(ref))


def _join_chain(base: DynamicModel, train: PlanetaryTrain, prefix: str, chain: GearTrain,
                side: str, shaft_stiffness: float | None, settings: DynamicsSettings,
                parameter: str = "chain.shaft_stiffness") -> DynamicModel:
    """``base`` and ``chain`` joined by a shaft on the output (``side = "output"``, or
    ``"between"``: gears that drive the next stage, :func:`_join_stage`) or input member
    of the stage ``train`` (names ``prefix``-ed in ``base``; ``parameter``: the shaft's
    k_t)."""
    out = side != "input"
    if out:
        _check_operating(chain.operating, chain_operating(train), "chain",
                         "the stage output's {:.10g} (use chain_operating)")
    else:
        _check_operating(train.operating,
                         stage_operating(chain, train.operating.fixed, train.operating.input),
                         "stage", "the chain output's {:.10g} (use stage_operating)")
    # the gears' meshes as meshes of contacts with ``contact_mesh`` (the stage follows its
    # own ``contacts``), as a gear train's run (gearsim.dynamics.simulate.build_model)
    cm_ = build_lta(chain, settings, tables=mesh_tables(chain, contacts=settings.contact_mesh))
    # the member on the shaft and the chain's gear on it (its first or its last)
    member = output_member(train) if out else train.operating.input
    gear = chain.gears[0] if out else chain.gear(chain.flow.meshes[-1][1])
    next_mesh = 0 if out else len(chain.pairs) - 1
    if shaft_stiffness is None:
        shaft_stiffness = SHAFT_FACTOR * cm_.tables[next_mesh].mean * gear.base_radius ** 2
    kt = _check_shaft(shaft_stiffness, parameter)
    n1, r1 = base.n_dof, base.n_mesh
    rows = r1 + cm_.n_mesh + 1
    chain_rows = tuple(range(r1, r1 + len(chain.pairs)))  # its meshes (then its springs)
    entry = {"chain": chain, "side": side, "rows": chain_rows, "shaft_row": rows - 1,
             "shaft_stiffness": kt, "member": member, "dofs": (n1, n1 + cm_.n_dof),
             "bearing_dofs": cm_.bearing_dofs + n1, "axes": cm_.axes,
             "shafts": cm_.gear_names, "mesh_frequency": chain.mesh_frequency,
             "twist": (parameter, chain.flow.shafts[chain.flow.shaft_of[gear.name]].name)}
    info = {"chains": (*base.info.get("chains", ()), entry),
            "output_member": base.info.get("output_member", output_member(train))}
    if side == "between":  # rows named for the stages joined after it (a shaft by its ends)
        info["row_names"] = (base.info["row_names"] + tuple(
            f"{chain.name}:{i}" for i in range(cm_.n_mesh))
                             + (f"shaft-{prefix}{member}-{gear.name}",))
    elif "chain_rows" not in base.info:  # the first chain at an end, under its own keys
        info.update({"chain_rows": chain_rows, "shaft_row": rows - 1,
                     "chain_mesh_names": tuple(p.name for p in chain.pairs), "chain": chain,
                     "chain_mesh_frequency": chain.mesh_frequency, "shaft_stiffness": kt,
                     "chain_side": side, "chain_dofs": entry["dofs"], "shaft_member": member,
                     "chain_name": chain.name, "chain_bearing_dofs": entry["bearing_dofs"],
                     "chain_axes": cm_.axes, "chain_shafts": cm_.gear_names})
    i_in = None if out else _rotation(cm_, chain, chain.gears[0])
    return _join(base, cm_, _member(base, prefix, train, member, "output" if out else side),
                 (_rotation(cm_, chain, gear), 1.0, gear.polar_inertia), kt,
                 abs(train.torques[member]), settings, downstream=out,
                 part_input=i_in, info=info)


def _join_stage(base: DynamicModel, prev: PlanetaryTrain, prev_prefix: str, nxt: NextStage,
                prefix: str, settings: DynamicsSettings, where: str) -> DynamicModel:
    """``base`` and the stage ``nxt`` joined by a shaft from the output member of the
    stage ``prev`` (the last of ``base``) to ``nxt``'s input member, or from the last
    gear of ``nxt.input_train``, joined to ``prev`` first (:func:`_join_chain`);
    ``where``: ``nxt``'s table (``stages[k]``), naming the shafts' k_t."""
    op, chain = nxt.train.operating, nxt.input_train
    out = output_member(prev)
    if chain is None:
        _check_operating(op, next_operating(prev, op.fixed, op.input), "stages",
                         "the previous stage output's {:.10g} (use next_operating)")
        kt, parameter = nxt.shaft_stiffness, f"{where}.shaft_stiffness"
        at_base, torque = _member(base, prev_prefix, prev, out, "output"), abs(prev.torques[out])
    else:  # the gears between: driven by prev's output, driving nxt
        base = _join_chain(base, prev, prev_prefix, chain, "between", nxt.shaft_stiffness,
                           settings, f"{where}.shaft_stiffness")
        _check_operating(op, stage_operating(chain, op.fixed, op.input), "stages",
                         "the chain output's {:.10g} (use stage_operating)")
        gear = chain.gear(chain.flow.meshes[-1][1])
        kt, parameter = nxt.input_shaft_stiffness, f"{where}.input_chain.shaft_stiffness"
        if kt is None:  # as an input chain's: ten times its last mesh's about its gear
            kt = (SHAFT_FACTOR * base.tables[base.info["chains"][-1]["rows"][-1]].mean
                  * gear.base_radius ** 2)
        at_base, torque = (_rotation(base, chain, gear), 1.0, gear.polar_inertia), op.torque
    part = _prefixed(build_stage_model(nxt.train, nxt.members, stage_settings(settings)),
                     prefix)
    if kt is None:  # ten times the torsional stiffness of its sun meshes about the sun
        lp = part.info["lin_parker"]
        kt = SHAFT_FACTOR * lp.planets * lp.sun_mesh * nxt.train.stage.sun.base_radius ** 2
    kt = _check_shaft(kt, parameter)
    name = stage_shaft_names(prev_prefix, prev, prefix, nxt)[-1]
    r1, n1 = base.n_mesh, base.n_dof
    rows = tuple(r1 + r for r in part.info["mesh_rows"])
    entry = {"train": nxt.train, "prefix": prefix, "rows": rows,
             "shaft_row": r1 + part.n_mesh, "shaft_stiffness": kt, "member": op.input,
             "dofs": (n1, n1 + part.n_dof), "mesh_frequency": nxt.train.mesh_frequency,
             "twist": (parameter, name)}
    info = {"stages": (*base.info["stages"], entry),
            "mesh_rows": base.info["mesh_rows"] + rows,
            "row_names": base.info["row_names"] + part.info["row_names"] + (name,),
            "output_member": output_member(nxt.train)}
    return _join(base, part, at_base, _member(part, prefix, nxt.train, op.input, "input"),
                 kt, torque, settings, downstream=True, part_input=None, info=info)


def _stack(a: np.ndarray | None, b: np.ndarray | None, r1: int, r2: int) -> np.ndarray | None:
    """Rows of ``a`` (r1) then ``b`` (r2) then one zero row, columns padded with zeros;
    None when both are None."""
    if a is None and b is None:
        return None
    nc = max(x.shape[1] for x in (a, b) if x is not None)
    return np.vstack([_pad(a, r1, nc), _pad(b, r2, nc), np.zeros((1, nc))])


def _join(base: DynamicModel, part: DynamicModel, at_base: tuple[int, float, float],
          at_part: tuple[int, float, float], kt: float, torque: float,
          settings: DynamicsSettings, *, downstream: bool, part_input: int | None,
          info: dict) -> DynamicModel:
    """``base`` and ``part`` (a chain's or a stage's model) joined by one shaft.

    ``at_base`` and ``at_part`` are (index, a, J) of the coordinates on the shaft (a the
    factor to the angle in the sense of rotation, J the inertia); the shaft twists by
    a_up q_up - a_down q_down, ``downstream``: ``part`` is driven by ``base``. The shaft
    replaces the load (or drive) of both coordinates and carries ``torque`` [N m]
    statically; damping c_t = 2 zeta sqrt(k_t J_eq) (module docstring). ``part``'s rows
    keep their tables at the rate part.f_m / base.f_m; ``part_input``: the gearbox's
    input coordinate in ``part`` when it drives ``base``. ``info`` is added to
    ``base.info``."""
    n1, n2 = base.n_dof, part.n_dof
    r1, r2 = base.n_mesh, part.n_mesh
    n, rows = n1 + n2, r1 + r2 + 1
    (iu, a_u, j_u), (ip, a_p, j_p) = at_base, at_part
    i_p = n1 + ip
    mass = np.concatenate([base.mass, part.mass])
    kb = np.concatenate([base.kb, part.kb])
    cb = np.concatenate([base.cb, part.cb])
    fext = np.concatenate([base.fext, part.fext])
    fext[iu] = 0.0  # the member's load (or drive) is now the shaft
    fext[i_p] = 0.0  # and so is the part's input torque (or its load)
    V = np.zeros((rows, n))
    V[:r1, :n1] = base.V
    V[r1:r1 + r2, n1:] = part.V
    # tau = k_t (upstream rotation - downstream rotation), each in its sense of rotation
    up, down = (1.0, -1.0) if downstream else (-1.0, 1.0)
    V[-1, iu] = up * a_u
    V[-1, i_p] = down * a_p
    j_eq = 1.0 / (1.0 / j_u + 1.0 / j_p)
    c_t = 2.0 * settings.bearing_damping_ratio * math.sqrt(kt * j_eq)
    kmean = np.concatenate([[t.mean for t in base.tables], [t.mean for t in part.tables],
                            [kt]])
    e0 = np.concatenate([base.e0, part.e0, [0.0]])
    q0 = static_equilibrium(mass, kb, V, kmean, fext, e0)
    # the nominal motion of all parts (each at its operating point, which is the other's
    # on the shaft); the speed profile, its load and the inertia at the gearbox's input
    w = np.concatenate([base.info["nominal_velocity"], part.info["nominal_velocity"]])
    first = base if downstream else part
    i_in = base.info["input_index"] if downstream else n1 + part_input
    inertial = None if first.profile is None else nominal_inertia(mass, w, i_in)
    part_rate = np.ones(r2) if part.rate is None else np.asarray(part.rate)
    base_rate = np.ones(r1) if base.rate is None else np.asarray(base.rate)
    info = {**base.info, "nominal_velocity": w, "input_index": i_in, **info}

    def h(a, b):
        nh = max(a.shape[1], b.shape[1])
        return np.vstack([_pad(a, r1, nh), _pad(b, r2, nh), np.zeros((1, nh))])

    return DynamicModel(
        kind="stage+chain", gear_names=base.gear_names + part.gear_names,
        dof_labels=base.dof_labels + part.dof_labels, mass=mass, kb=kb, cb=cb, fext=fext, V=V,
        kappa=np.concatenate([base.kappa, part.kappa, [1.0]]),
        kscale=np.concatenate([base.kscale, part.kscale, [1.0]]),
        cm=np.concatenate([base.cm, part.cm, [c_t]]),
        clearance=np.concatenate([base.clearance, part.clearance, [np.inf]]),
        tables=base.tables + part.tables + (MeshTable(k=np.array([kt]), positions_per_cycle=1,
                                                      period=1),),
        phase=np.concatenate([base.phase, part.phase, [0.0]]),
        mesh_frequency=base.mesh_frequency, e0=e0,
        h_amp=h(base.h_amp, part.h_amp), h_omega=h(base.h_omega, part.h_omega),
        h_phase=h(base.h_phase, part.h_phase), a_amp=_stack(base.a_amp, part.a_amp, r1, r2),
        a_omega=_stack(base.a_omega, part.a_omega, r1, r2),
        a_phase=_stack(base.a_phase, part.a_phase, r1, r2),
        to_transverse=np.concatenate([base.to_transverse, part.to_transverse, [1.0]]),
        dte_offset=np.concatenate([base.dte_offset, part.dte_offset, [0.0]]),
        static_force=np.concatenate([base.static_force, part.static_force, [torque]]),
        bearing_dofs=base.bearing_dofs, axes=base.axes, q_static=q0,
        rate=np.concatenate([base_rate, part_rate * (part.mesh_frequency / base.mesh_frequency),
                             [1.0]]),
        profile=first.profile, load=first.load, inertial=inertial, info=info)


def simulate_stage_chain(train: PlanetaryTrain, chain: GearTrain | None,
                         dyn: StageDynamics | None = None,
                         settings: DynamicsSettings | None = None, *,
                         shaft_stiffness: float | None = None, side: str = "output",
                         input_chain: GearTrain | None = None,
                         input_shaft_stiffness: float | None = None,
                         stages: Sequence[NextStage] = ()):
    """Time response of stages and their chains (:func:`build_stage_chain_model`).

    Parameters
    ----------
    train
        The stage in operation.
    chain
        The chain at :func:`chain_operating` of ``train`` (``side = "output"``), or
        driving it (``side = "input"``); ``None``: only ``input_chain``.
    dyn
        Members, supports and sensor of the stage.
    settings
        Duration, fs, oversampling, damping, backlash; the chains' own options.
    shaft_stiffness
        k_t [N m/rad]; default ``SHAFT_FACTOR`` k_mean r_b^2 of the chain's mesh next to
        the shaft.
    side : {"output", "input"}
        The chain is driven by the stage, or drives it.
    input_chain, input_shaft_stiffness
        Gears driving the stage besides ``chain`` on its output, and their shaft's k_t.
    stages
        Further stages in series (:class:`NextStage`).

    Returns
    -------
    xarray.Dataset
        As :func:`gearsim.dynamics.stage.simulate_stage` (stage meshes, coordinates of
        all parts, ring sensor) plus ``chain_mesh_force`` (time, chain_mesh) [N],
        ``chain_acceleration`` (time, chain_shaft, chain_axis) [m/s^2] and
        ``shaft_torque`` (time) [N m] (with two chains at the ends also
        ``input_shaft_torque``); attributes ``chain_mesh_frequency``, ``shaft_stiffness``,
        ``output_member``, ``chain_side``, ``shaft_member``, ``static_shaft_torque``; with
        further stages their meshes in ``mesh_force`` and ``stage_shaft_torque`` (time,
        stage_shaft) [N m], gears between two stages in the ``chain_`` records and their
        two shafts in ``stage_shaft_torque`` (:func:`gearsim.dynamics.stage.simulate_stage`).

    Raises
    ------
    InputError
        If fs does not exceed twice the highest mesh frequency, a shaft is twisted past
        ``Q_LIMIT`` by its static torque (:func:`gearsim.dynamics.simulate.check_twist`,
        after the model is built, before the run), or as :func:`build_stage_chain_model`.
    SimulationError
        If the integration diverges.
    """
    settings = settings or DynamicsSettings()
    chains = [c for c in (input_chain, *(s.input_train for s in stages), chain)
              if c is not None]
    f_chain = max((f for c in chains for f in c.mesh_frequencies), default=0.0)
    f_stage = max(t.mesh_frequency for t in (train, *(s.train for s in stages)))
    f_hi = max(f_stage, f_chain)
    if not settings.fs > 2.0 * f_hi:
        raise InputError("dynamics.fs", settings.fs,
                         f"must be > {2 * f_hi:.6g} Hz, twice the highest mesh frequency "
                         f"(stage{'s' if stages else ''} {f_stage:.6g} Hz, gears "
                         f"{f_chain:.6g} Hz), else the record is aliased")
    for c in chains:
        check_twists(c)
    model = build_stage_chain_model(train, chain, dyn, settings,
                                    shaft_stiffness=shaft_stiffness, side=side,
                                    input_chain=input_chain,
                                    input_shaft_stiffness=input_shaft_stiffness,
                                    stages=stages)
    # the shafts between the parts, twisted by their static torques (before the run)
    for e in (*model.info.get("stages", ())[1:], *model.info.get("chains", ())):
        check_twist(model.static_force[e["shaft_row"]], e["shaft_stiffness"], *e["twist"])
    return simulate_stage(train, dyn, settings, model=model)
