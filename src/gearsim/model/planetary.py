"""TOML configuration of a planetary stage, validated into a :class:`~gearsim.model.Gearbox`.

A configuration with a ``[stage]`` section describes one planetary stage (gear trains
have ``[[gears]]`` instead). Values take units as strings like the gear trains'
(``"10 mm"``, ``"7.5 deg"``, ``"22 rpm"``). Layout::

    name = "..."
    [material]        # youngs_modulus, poisson_ratio, density
    [stage]           # sun_teeth, planet_teeth, ring_teeth, planets, normal_module,
                      # normal_pressure_angle, helix_angle, face_width, sun_shift,
                      # planet_shift, ring_shift, planet_angles (list), addendum_coefficient,
                      # dedendum_coefficient, ring_addendum_coefficient,
                      # sun_mesh_stiffness, ring_mesh_stiffness, ring_foundation
    [operating]       # fixed, input, speed, torque
    [members]         # sun_mass, sun_inertia, ..., sun_bearing, planet_bearing, ...,
                      # held_torsional
    [sensor]          # angle, width
    [stiffness]       # as for gear trains (positions_per_cycle, slices, closure, ...)
    [[cracks]]        # gear = "sun" | "planet-1" ..., tooth, flank, depth, angle, ...
    [[faults]]        # as for gear trains (spall, pitting, chip, wear; broken on the sun)
                      # on the sun or a planet's working flank
    [dynamics]        # duration, fs, step, transient, oversample, damping, backlash
    [analysis]        # as for gear trains
    [chain]           # optional: parallel gears on the output shaft (dynamics.compose)
    shaft_stiffness = "2e7 N*m/rad"      # optional; default 10 x the next mesh's
    [chain.common]    # as a gear train's [common]; [[chain.gears]], [[chain.cracks]],
                      # [[chain.faults]], [[chain.modifications]], [chain.stiffness];
                      # [[chain.shafts]] and [[chain.meshes]] for parallel stages
                      # (the first shaft is the one the stage drives)

The chain runs at the stage output's speed and torque (no ``[operating]`` of its own);
it may branch the power to several output shafts, each naming its ``power_share`` (as a
gear train's ``[[shafts]]``); the gears that drive a stage (``[input_chain]``, a later
stage's ``input_chain``) pass the power in one path.
An ``[input_chain]`` (the same keys as ``[chain]``) is a chain whose last gear drives the
stage's ``operating.input`` member: ``[operating]`` ``speed`` and ``torque`` are then its
first gear's (the gearbox input), and the stage runs at its output's speed and torque.
A stage may have both (gears, a planetary stage, gears); gear and shaft names are unique
across the gearbox and differ from the stage's members.

Planetary stages in series are written ``[[stages]]`` instead of ``[stage]``: an array
of tables in power-flow order, each with the keys of ``[stage]``. The first is the
``[stage]`` of the layout above (``[operating]``, ``[members]``, ``[sensor]``,
``[[cracks]]`` and ``[[faults]]`` are its); each later one is driven by the previous
stage's output member through a shaft and may add ``fixed`` and ``input`` (its held and
driven members, default ``"ring"`` and ``"sun"``), ``shaft_stiffness`` (default:
:class:`gearsim.dynamics.compose.NextStage`), ``name``, a ``members`` table and its own
``[[stages.cracks]]`` and ``[[stages.faults]]`` (as ``[[cracks]]`` and ``[[faults]]``, on
its gears), and ``[stages.input_chain]``: gears between the previous stage and this one
(the keys of ``[chain]``; at the previous stage output's speed and torque, their last
gear driving this stage's ``input``; the entry's ``shaft_stiffness`` is then the shaft
from the previous stage to their first gear, theirs the shaft to this stage). A bad
value of entry k is named ``stages[k].<key>`` (k from 0), a refused crack
``stages[k].cracks[i].<key>`` (i from 0, as ``cracks[i]``). ``[input_chain]`` drives the
first stage, ``[chain]`` is driven by the last.

Assembly (coaxiality, (z_s + z_r)/N, planet spacing, tip interference of the internal
pair) and the cracks (a planet the stage does not have) are checked where the stage is
made: a bad value gives one line naming it, the numbers and the condition.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from gearsim.dynamics.compose import NextStage, chain_operating, next_operating, stage_operating
from gearsim.dynamics.settings import parse_dynamics
from gearsim.dynamics.stage import StageDynamics
from gearsim.errors import InputError, require
from gearsim.geometry.gear import Material, check_face_width
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.model.damage import CRACK_KEYS, FAULT_KEYS, parse_cracks, parse_faults
from gearsim.model.gearbox import Gearbox
from gearsim.sections import as_written, convert
from gearsim.signals.settings import parse_analysis
from gearsim.stiffness.settings import StiffnessSettings, model_options
from gearsim.system import GearTrain
from gearsim.system.graph import MAX_SHAFT_STIFFNESS, MIN_SHAFT_STIFFNESS
from gearsim.system.planetary import PlanetaryTrain, StageOperating
from gearsim.system.train import Operating

__all__ = ["PLANETARY_TOP_KEYS", "parse_planetary"]

STAGE_KEYS = {"sun_teeth": "int", "planet_teeth": "int", "ring_teeth": "int",
              "planets": "int", "normal_module": "length", "normal_pressure_angle": "angle",
              "helix_angle": "angle", "face_width": "length", "sun_shift": "dimensionless",
              "planet_shift": "dimensionless", "ring_shift": "dimensionless",
              "planet_angles": "angle", "addendum_coefficient": "dimensionless",
              "dedendum_coefficient": "dimensionless",
              "ring_addendum_coefficient": "dimensionless", "sun_mesh_stiffness": "stiffness",
              "ring_mesh_stiffness": "stiffness", "ring_foundation": "str"}
STAGE_OPERATING_KEYS = {"fixed": "str", "input": "str", "speed": "speed", "torque": "torque"}
MEMBER_KEYS = {f"{m}_{q}": kind for m in ("sun", "planet", "ring", "carrier")
               for q, kind in (("mass", "mass"), ("inertia", "inertia"),
                               ("bearing", "stiffness"))}
MEMBER_KEYS["held_torsional"] = "torsional_stiffness"
SENSOR_KEYS = {"angle": "angle", "width": "angle"}
PLANETARY_TOP_KEYS = ("name", "material", "stage", "stages", "operating", "members",
                      "sensor", "stiffness", "cracks", "faults", "dynamics", "analysis",
                      "chain", "input_chain")
#: Keys of a ``[[stages]]`` entry after the first besides those of ``[stage]``.
NEXT_STAGE_KEYS = ("name", "fixed", "input", "shaft_stiffness", "members", "cracks", "faults",
                   "input_chain")
#: Keys of ``[chain]``: the shaft and a gear train's sections (no operating point).
#: The per-mesh and per-gear dynamics options of a gear train's file
#: (:data:`gearsim.model.config.PER_MESH`, ``PER_GEAR``), refused beside a stage.
PER_ELEMENT = (("backlash", "profile_modification", "crowning", "assembly_error"),
               ("runout", "runout_phase"))
CHAIN_KEYS = ("name", "shaft_stiffness", "common", "shafts", "gears", "meshes", "stiffness",
              "cracks", "faults", "modifications")


def parse_planetary(doc: dict[str, Any], material: Material,
                    parse_train: Callable[[dict[str, Any]], Any]) -> Gearbox:
    """Build the :class:`~gearsim.model.Gearbox` of a parsed TOML document with a ``[stage]``
    (or ``[[stages]]``).

    Parameters
    ----------
    doc : dict
        The document.
    material : Material
        The parsed ``[material]``.
    parse_train : callable
        The gear-train parser (:func:`gearsim.model.config.parse`), for a ``[chain]``.

    Returns
    -------
    Gearbox
        ``stage`` the (first) stage, ``next_stages`` the stages after it, ``train`` the
        ``[chain]`` (or ``None``).

    Raises
    ------
    InputError
        The first problem found (unknown sections or keys, bad values, assembly).
    """
    for key in doc:
        if key not in PLANETARY_TOP_KEYS:
            graph = (" (a gearbox of [[shafts]] writes its stages as [[stages]] naming "
                     "each member's shaft: docs/gearbox.md)"
                     if key in ("shafts", "gears", "meshes") else "")
            raise InputError(key, "...", f"unknown section for a planetary stage{graph}; "
                             "allowed: " + ", ".join(PLANETARY_TOP_KEYS))
    raw, more = _stage_tables(doc)
    first = "stages[0]" if more or "stages" in doc else "stage"
    stage, consts = _stage_geometry(raw, first, material)
    op_raw = doc.get("operating", {})
    with as_written(op_raw, "operating"):
        operating = StageOperating(**convert(op_raw, STAGE_OPERATING_KEYS, "operating"))
    inp, inp_shaft = None, None
    if "input_chain" in doc:  # the gears take [operating]'s speed and torque, the stage theirs
        inp, inp_shaft = _parse_chain(doc["input_chain"], doc.get("material", {}),
                                      Operating(speed=operating.speed,
                                                torque=operating.torque),
                                      parse_train, "input_chain")
        operating = stage_operating(inp, operating.fixed, operating.input)
    stiffness_kw = convert(doc.get("stiffness", {}), {
        "closure": "str", "slices": "int", "positions_per_cycle": "int",
        "gauss_points": "int", "plane": "str", "source": "str", "contact": "str",
        "coupling": "str", "model": "str"}, "stiffness")
    # both meshes of a stage take the gear trains' default model (docs/planetary.md 4.4)
    stiffness = StiffnessSettings(**model_options(stiffness_kw, "stiffness"))
    name = doc.get("name", "planetary stage")
    if not isinstance(name, str):
        raise InputError("name", name, "must be a string")
    with _as_stage(raw, first):
        train = _stage_train(doc, "", stage=stage, operating=operating, settings=stiffness,
                             name=name, **consts)
    sen_raw = doc.get("sensor", {})
    sen = convert(sen_raw, SENSOR_KEYS, "sensor")
    with as_written(sen_raw, "sensor", SENSOR_KEYS):  # its checks, as [sensor] holds them
        members = _members(doc.get("members", {}), "members",
                           sensor_angle=sen.get("angle", 0.0),
                           sensor_width=sen.get("width", math.pi))
    nexts: list[NextStage] = []
    for k, entry in enumerate(more, 1):  # each driven by the previous stage's output
        nexts.append(_next_stage(entry, f"stages[{k}]", material, nexts[-1].train
                                 if nexts else train, stiffness, f"{name}, stage {k + 1}",
                                 lambda raw, op, table: _parse_chain(
                                     raw, doc.get("material", {}), op, parse_train, table)))
    dynamics = parse_dynamics(doc.get("dynamics", {}), "dynamics")
    analysis = parse_analysis(doc.get("analysis", {}), "analysis")
    last = nexts[-1].train if nexts else train
    chain, shaft = (_parse_chain(doc["chain"], doc.get("material", {}),
                                 chain_operating(last), parse_train, "chain")
                    if "chain" in doc else (None, None))
    _unique_names([("input_chain", inp), *((f"stages[{k}].input_chain", ns.input_train)
                                           for k, ns in enumerate(nexts, 1)), ("chain", chain)])
    return Gearbox(train=chain, stage=train, members=members, dynamics=dynamics,
                   analysis=analysis, shaft_stiffness=shaft, input_train=inp,
                   input_shaft_stiffness=inp_shaft, next_stages=tuple(nexts))


def _stage_tables(doc: dict[str, Any]) -> tuple[dict[str, Any], list[Any]]:
    """The first stage's table (``[stage]``, or the first ``[[stages]]``) and those of
    the stages after it (the other ``[[stages]]``)."""
    if "stages" not in doc:
        return doc.get("stage", {}), []
    if "stage" in doc:
        raise InputError("stages", "...", "give [stage] (one stage) or [[stages]] (stages "
                         "in series), not both")
    tables = doc["stages"]
    if not isinstance(tables, list) or not tables or not all(
            isinstance(t, dict) for t in tables):
        raise InputError("stages", "...", "must be one or more [[stages]] tables")
    where = {"fixed": "[operating]", "input": "[operating]", "members": "[members]",
             "name": "the top-level name", "cracks": "[[cracks]]", "faults": "[[faults]]",
             "shaft_stiffness": "no shaft: its input is [operating]'s",
             "input_chain": "[input_chain]"}
    for key in tables[0]:
        if key in where:
            raise InputError(f"stages[0].{key}", tables[0][key] if isinstance(
                tables[0][key], (str, int, float)) else "...", f"the first stage's is {where[key]}"
                             if key != "shaft_stiffness" else f"the first stage has "
                             f"{where[key]}")
    return tables[0], tables[1:]


def _stage_geometry(raw: Any, section: str, material: Material
                    ) -> tuple[PlanetaryStage, dict[str, Any]]:
    """The stage of table ``raw`` (``[stage]`` keys) and its constant-stiffness options."""
    kw = convert(raw, STAGE_KEYS, section, list_keys=("planet_angles",))
    for need in ("sun_teeth", "planet_teeth", "ring_teeth", "normal_module"):
        if need not in kw:
            raise InputError(f"{section}.{need}", "missing", "a planetary stage needs it")
    consts = {k: kw.pop(k) for k in ("sun_mesh_stiffness", "ring_mesh_stiffness",
                                     "ring_foundation") if k in kw}
    if "planet_angles" in kw and not isinstance(kw["planet_angles"], tuple):
        kw["planet_angles"] = (kw["planet_angles"],)
    try:
        with _as_stage(raw, section):
            check_face_width(kw.get("face_width"), "stage.face_width")
            return PlanetaryStage(material=material, **kw), consts
    except InputError as exc:  # a member gear's own check: the stage's key as written
        member, _, key = exc.parameter.partition(".")
        if member not in ("sun", "planet", "ring") or not key:
            raise
        key = {"teeth": f"{member}_teeth", "profile_shift": f"{member}_shift"}.get(key, key)
        if key not in STAGE_KEYS:
            raise
        raise InputError(f"{section}.{key}", raw.get(key, exc.value),
                         f"{exc.limit} (the {member})") from None


@contextmanager
def _as_stage(raw: dict[str, Any], section: str) -> Iterator[None]:
    """A stage's own refusals (``stage.<key>``, ``stage: ring-planet mesh``, ``stage``)
    under its table as written, ``section`` (``stages[1].ring_teeth``, ``stages[1]:
    ring-planet mesh``), a key of ``raw`` with its value as written."""
    try:
        with as_written(raw, "stage", sources=[(section, raw)], default=section):
            yield
    except InputError as exc:
        if exc.parameter != "stage" and not exc.parameter.startswith("stage:"):
            raise
        raise InputError(section + exc.parameter[5:], exc.value, exc.limit) from None


def _members(raw: Any, section: str, **sensor: float) -> StageDynamics:
    """The ``[members]`` table ``raw`` of a stage (and its sensor)."""
    mem = convert(raw, MEMBER_KEYS, section)
    groups: dict[str, dict[str, float]] = {"masses": {}, "inertias": {}, "bearings": {}}
    held = mem.pop("held_torsional", None)
    for key, v in mem.items():
        member, q = key.split("_", 1)
        groups[{"mass": "masses", "inertia": "inertias", "bearing": "bearings"}[q]][member] = v
    with as_written(raw, "members", sources=[(section, raw)]):
        return StageDynamics(held_torsional=held, **sensor, **groups)


def _next_stage(raw: dict[str, Any], section: str, material: Material,
                prev: PlanetaryTrain, stiffness: StiffnessSettings, name: str,
                chain: Callable) -> NextStage:
    """A ``[[stages]]`` entry after the first: a stage driven by ``prev``'s output, or by
    the gears of its ``input_chain`` table (``chain(raw, operating, table)``:
    :func:`_parse_chain`) at that output's speed and torque."""
    for key in raw:
        if key not in STAGE_KEYS and key not in NEXT_STAGE_KEYS:
            raise InputError(f"{section}.{key}", "...", "unknown key; allowed: "
                             + ", ".join((*NEXT_STAGE_KEYS, *STAGE_KEYS)))
    geometry = {k: v for k, v in raw.items() if k not in NEXT_STAGE_KEYS}
    stage, consts = _stage_geometry(geometry, section, material)
    written = {k: raw[k] for k in ("fixed", "input") if k in raw}
    ends = convert(written, STAGE_OPERATING_KEYS, section)
    inp, inp_shaft = (chain(raw["input_chain"], chain_operating(prev), f"{section}.input_chain")
                      if "input_chain" in raw else (None, None))
    with as_written(written, "operating", sources=[(section, written)]):
        ends = (ends.get("fixed", "ring"), ends.get("input", "sun"))
        operating = (next_operating(prev, *ends) if inp is None
                     else stage_operating(inp, *ends))
    own = raw.get("name", name)
    if not isinstance(own, str):
        raise InputError(f"{section}.name", own, "must be a string")
    with _as_stage(raw, section):
        train = _stage_train(raw, f"{section}.", stage=stage, operating=operating,
                             settings=stiffness, name=own, **consts)
    return NextStage(train=train, members=_members(raw.get("members", {}),
                                                   f"{section}.members"),
                     shaft_stiffness=_shaft(raw, section), input_train=inp,
                     input_shaft_stiffness=inp_shaft)


def _stage_train(raw: dict[str, Any], where: str, **kw: Any) -> PlanetaryTrain:
    """The stage of keywords ``kw`` with the ``cracks`` and ``faults`` tables of ``raw``
    (``[[cracks]]`` of the first stage, ``where = ""``; ``[[stages.cracks]]`` of entry k,
    ``where = "stages[k]."``). The damage is added one element at a time, so that a
    refused crack or fault (a gear the stage does not have, a tooth too many) is named
    as written, ``<where>cracks[i].<key>``, one line."""
    cracks = parse_cracks(raw.get("cracks", []), f"{where}cracks")
    faults = parse_faults(raw.get("faults", []), f"{where}faults")
    train = PlanetaryTrain(**kw)  # the healthy stage: its own refusals first
    steps = ([("crack", CRACK_KEYS, "cracks", i) for i in range(len(cracks))]
             + [("fault", FAULT_KEYS, "faults", i) for i in range(len(faults))])
    for prefix, spec, key, i in steps:
        table = f"{where}{key}[{i}]"
        tab = raw[key][i]
        part = {"cracks": cracks[:i + 1] if key == "cracks" else cracks,
                "faults": faults[:i + 1] if key == "faults" else ()}
        try:
            with as_written(tab, prefix, spec, sources=[(table, tab)], default=table):
                train = PlanetaryTrain(**kw, **part)
        except InputError as exc:  # two damaged members: the stage's list as a whole
            if exc.parameter not in ("cracks", "faults"):
                raise
            raise InputError(f"{where}{exc.parameter}", exc.value, exc.limit) from None
    return train


def _shaft(raw: dict[str, Any], table: str) -> float | None:
    """``shaft_stiffness`` [N m/rad] of table ``raw`` (None: not given), checked."""
    if "shaft_stiffness" not in raw:
        return None
    shaft = convert({"shaft_stiffness": raw["shaft_stiffness"]},
                    {"shaft_stiffness": "torsional_stiffness"}, table)["shaft_stiffness"]
    if not (MIN_SHAFT_STIFFNESS <= shaft <= MAX_SHAFT_STIFFNESS):
        raise InputError(f"{table}.shaft_stiffness", raw["shaft_stiffness"],
                         f"must be a finite stiffness in [{MIN_SHAFT_STIFFNESS:g}, "
                         f"{MAX_SHAFT_STIFFNESS:g}] N*m/rad")
    return shaft


def _unique_names(chains: list[tuple[str, GearTrain | None]]) -> None:
    """Refuse a gear or shaft name used in two chains (``(table, chain)``) or taken by a
    stage member (the results label shafts and tachos by name; a chain's shaft may share
    its own gear's)."""
    seen: dict[str, str] = {m: "the stage's members" for m in ("sun", "ring", "carrier")}
    for table, tr in chains:
        if tr is None:
            continue
        names = {g.name for g in tr.gears} | {sh.name for sh in tr.flow.shafts}
        for name in sorted(names):
            if name in seen:
                raise InputError(f"{table}.gears", name, f"is already a name in "
                                 f"{seen[name]}: names must be unique in the gearbox")
        seen.update(dict.fromkeys(names, f"[{table}]"))


def _parse_chain(raw: Any, material: Any, op: Operating, parse: Callable, table: str
                 ) -> tuple[GearTrain, float | None]:
    """The ``[chain]`` (or ``[input_chain]``) of a stage: a gear train at the operating
    point ``op`` (the stage output's, or the gearbox input's for the input chain)."""
    import dataclasses

    if not isinstance(raw, dict):
        raise InputError(table, raw, f"must be a table [{table}]")
    for key in raw:
        if key not in CHAIN_KEYS:
            raise InputError(f"{table}.{key}", "...", "unknown key; allowed: "
                             + ", ".join(CHAIN_KEYS))
    if "gears" not in raw:
        raise InputError(f"{table}.gears", "missing", f"a chain needs [[{table}.gears]] "
                         "(two or more gears)")
    shaft = _shaft(raw, table)
    tables = [(f"{key}[{i}]", t, per) for key, per in (("meshes", PER_ELEMENT[0]),
                                                       ("gears", PER_ELEMENT[1]))
              for i, t in enumerate(raw.get(key) or [])] + [("common", raw.get("common"),
                                                             PER_ELEMENT[1])]
    for where, t, per in tables:
        for k in per:
            if isinstance(t, dict) and k in t:
                raise InputError(f"{table}.{where}.{k}", t[k], "is read for a gearbox of "
                                 "parallel shafts only: beside a planetary stage the gears "
                                 f"take {k} from [dynamics] (one value for every "
                                 "mesh or gear, the stages' included)")
    sub = {k: v for k, v in raw.items() if k != "shaft_stiffness"}
    sub.setdefault("name", table.replace("_", " "))
    sub["material"] = material
    sub["operating"] = {"speed": f"{op.speed!r} rad/s", "torque": f"{op.torque!r} N*m"}
    try:
        box = parse(sub)
    except InputError as exc:  # name the table the value was written in
        raise InputError(f"{table}.{exc.parameter}", exc.value, exc.limit) from None
    outputs = box.train.flow.outputs  # the gears the last stage drives may branch
    require(len(outputs) == 1 or table == "chain", f"{table}.shafts",
            [box.train.flow.shafts[k].name for k in outputs],
            "the gears driving a planetary stage pass the power in one path: branching "
            "power is read in the gears the last stage drives ([chain]) and in a gearbox "
            "of parallel shafts")
    return dataclasses.replace(box.train, operating=op), shaft
