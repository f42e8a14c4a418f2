"""TOML configuration files with units, validated into the typed gearbox model.

Values may carry units as strings (``"6 mm"``, ``"1900 rpm"``, ``"4876 N*m"``,
``"13 deg"``), parsed with pint; plain numbers are SI (metres, radians, N m, Pa), except
the speed, which needs a unit (rpm or rad/s?). Every value must be finite. Unknown keys
and sections are refused; a refused value is shown as written. A leading UTF-8 byte
order mark is ignored; the effective configuration that results files store (its first
line says "SI units") reads plain numbers as SI throughout. Layout::

    name = "..."
    [material]            # default material of every gear
    [common]              # default gear data (any key of [[gears]])
    [[shafts]]            # optional: name, mass, inertia, torsional/bearing stiffness;
                          # the first is the input shaft (gearsim.system.graph)
    [[gears]]             # one table per gear (with shafts: ``shaft = "..."``, ``hand``);
                          # without [[shafts]]: a chain in the order of the power flow
    [[meshes]]            # with shafts: ``gears = ["a", "b"]``, optional ``angle`` and the
                          # mesh's own backlash, profile_modification, crowning,
                          # assembly_error (PER_MESH; [[gears]] take runout, runout_phase)
                          # and [meshes.stiffness]: any key of [stiffness], its own
    [operating]           # speed and torque of the first gear
    [stiffness]           # closure, slices, positions_per_cycle, gauss_points, plane, source
    [[cracks]]            # gear, tooth, flank, depth, angle, extent, profile, start_radius
    [[faults]]            # kind = spall | pitting | chip | broken | wear, gear, tooth, ...
    [[modifications]]     # gear, tip/root relief, crowning, helix slope, pitch errors
    [dynamics]            # gearsim.dynamics.DynamicsSettings
    [analysis]            # gearsim.signals.AnalysisSettings

Each section is parsed by plain code into its frozen dataclass, whose constructor checks
every value; the result is a :class:`gearsim.model.Gearbox`.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from collections.abc import Callable, Sequence
from contextlib import ExitStack
from pathlib import Path
from types import SimpleNamespace
from typing import Any

from gearsim.data import EXAMPLES, example_text
from gearsim.dynamics.lta import agma_backlash
from gearsim.dynamics.settings import DynamicsSettings, parse_dynamics
from gearsim.errors import InputError, require
from gearsim.geometry.gear import Gear, Material, check_face_width, check_teeth
from gearsim.geometry.pair import require_same_rack
from gearsim.model.damage import CRACK_KEYS, array_of_tables, parse_cracks, parse_faults
from gearsim.model.gearbox import Gearbox
from gearsim.model.graph_form import SHAFT_KEYS, is_graph_with_stages, parse_graph_stages
from gearsim.model.planetary import PER_ELEMENT, parse_planetary
from gearsim.sections import as_written, convert
from gearsim.signals.settings import parse_analysis
from gearsim.stiffness.modifications import Modification
from gearsim.stiffness.settings import (
    CLOSURES,
    CONTACTS,
    COUPLINGS,
    PLANES,
    SOURCES,
    StiffnessSettings,
    model_options,
)
from gearsim.stiffness.settings import MODELS as STIFFNESS_MODELS
from gearsim.system.graph import MeshSpec, Shaft, power_flow
from gearsim.system.toml import EFFECTIVE_HEADER
from gearsim.system.train import GearTrain, Operating
from gearsim.units import plain_numbers_are_si

__all__ = ["EXAMPLES", "example", "example_text", "load", "loads", "parse",
           "read_file_or_builtin"]

#: Built-in examples: the seed's Table-1 helical idler train, Tian's spur pair, the
#: two-stage reducer of the UConn / SpectraQuest test rig, and two planetary stages (the
#: Lin & Parker 1999 example system, the NREL GRC stage) and the whole GRC gearbox.

MATERIAL_KEYS = {"youngs_modulus": "pressure", "poisson_ratio": "dimensionless",
                 "density": "density"}
GEAR_KEYS = {
    "name": "str", "teeth": "int", "normal_module": "length",
    "normal_pressure_angle": "angle", "helix_angle": "angle", "face_width": "length",
    "addendum_coefficient": "dimensionless", "dedendum_coefficient": "dimensionless",
    "fillet_radius_coefficient": "dimensionless", "profile_shift": "dimensionless",
    "bore_radius": "length", "material": "table", "shaft": "str", "hand": "str",
    "runout": "length", "runout_phase": "angle",
}
MESH_KEYS = {"gears": "str", "angle": "angle", "backlash": "length",
             "profile_modification": "length", "crowning": "length",
             "assembly_error": "length", "stiffness": "table"}
#: ``[dynamics]`` options a ``[[meshes]]`` table may give for its own mesh, and a
#: ``[[gears]]`` table (or ``[common]``) for its own gear: the loader puts them into the
#: per-item tuples of :class:`gearsim.dynamics.DynamicsSettings` in power-flow order,
#: the others at their defaults (backlash: the AGMA minimum of each mesh).
PER_MESH, PER_GEAR = PER_ELEMENT
OPERATING_KEYS = {"speed": "speed", "torque": "torque"}
STIFFNESS_KEYS = {"closure": "str:" + "|".join(CLOSURES), "slices": "int",
                  "positions_per_cycle": "int", "gauss_points": "int",
                  "plane": "str:" + "|".join(PLANES), "source": "str:" + "|".join(SOURCES),
                  "corner_contact": "bool", "contact": "str:" + "|".join(CONTACTS),
                  "coupling": "str:" + "|".join(COUPLINGS), "fe_pair_positions": "int",
                  "model": "str:" + "|".join(STIFFNESS_MODELS)}
MODIFICATION_KEYS = {"gear": "str", "tip_relief": "length", "tip_relief_length": "length",
                     "root_relief": "length", "root_relief_length": "length",
                     "relief_shape": "str", "crowning": "length", "helix_slope": "length",
                     "pitch_errors": "length", "pitch_grade": "int", "pitch_seed": "int"}

TOP_KEYS = ("name", "material", "common", "shafts", "gears", "meshes", "operating",
            "stiffness", "cracks", "faults", "modifications", "dynamics", "analysis")


_GEAR_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Gear)}


def _material(data: Any, section: str, base: Material | None = None) -> Material:
    kw = convert(data, MATERIAL_KEYS, section)
    if base is not None:
        kw = {"youngs_modulus": base.youngs_modulus, "poisson_ratio": base.poisson_ratio,
              "density": base.density, **kw}
    try:
        with as_written(data, "material"):
            return Material(**kw)
    except InputError as exc:  # name the table the value came from
        if section != "material" and exc.parameter.startswith("material."):
            raise InputError(section + exc.parameter[len("material"):], exc.value,
                             exc.limit) from None
        raise


def _rack(kw: dict[str, Any]) -> tuple[float, float]:
    return (kw["normal_module"], kw.get("normal_pressure_angle",
                                        _GEAR_DEFAULTS["normal_pressure_angle"]))


def parse(doc: dict[str, Any]) -> Gearbox:
    """Build a :class:`Gearbox` from a parsed TOML document.

    Parameters
    ----------
    doc : dict
        The document (as from :func:`tomllib.loads`).

    Returns
    -------
    Gearbox
        The train and its dynamics and analysis settings, all checked.

    Raises
    ------
    InputError
        The first problem found, naming the parameter, its value and the limit.
    """
    if is_graph_with_stages(doc):  # shafts, gears and stages (gearsim.model.graph_form)
        return parse_graph_stages(doc, _material(doc.get("material", {}), "material"), parse)
    if "stage" in doc or "stages" in doc:  # planetary stages (gearsim.model.planetary)
        return parse_planetary(doc, _material(doc.get("material", {}), "material"), parse)
    for key in doc:
        if key not in TOP_KEYS:
            raise InputError(key, "...", "unknown section; allowed: " + ", ".join(TOP_KEYS))
    material = _material(doc.get("material", {}), "material")
    common = convert(doc.get("common", {}), GEAR_KEYS, "common")
    gear_tables = doc.get("gears")
    if not isinstance(gear_tables, list) or len(gear_tables) < 2:
        raise InputError("gears", gear_tables if gear_tables is not None else "missing",
                         "need at least 2 [[gears]] tables")
    raw_common = doc.get("common", {})
    graph = "shafts" in doc or "meshes" in doc
    kws = []
    for i, table in enumerate(gear_tables):
        kw = {**common, **convert(table, GEAR_KEYS, f"gears[{i}]")}
        kw.setdefault("name", f"gear{i + 1}")
        if not kw["name"]:
            raise InputError(f"gears[{i}].name", kw["name"], "must be a non-empty string")
        if "teeth" not in kw:
            raise InputError(f"gears[{i}].teeth", "missing", "every gear needs a tooth count")
        check_teeth(kw["teeth"], f"gears[{i}].teeth")  # before the power flow divides by it
        if "normal_module" not in kw:
            raise InputError(f"gears[{i}].normal_module", "missing",
                             "give it in [common] or in the gear")
        mat = kw.pop("material", None)
        at = f"gears[{i}].material" if "material" in table else "common.material"
        kw["material"] = material if mat is None else _material(mat, at, material)
        if graph == ("shaft" not in kw) or ("hand" in kw and not graph):
            key = "shaft" if graph or "shaft" in kw else "hand"
            raise InputError(f"gears[{i}].{key}", kw.get(key, "missing"),
                             "every gear names its shaft in a gearbox with [[shafts]] and "
                             "[[meshes]]; a chain has neither")
        kw["helix_angle"] = abs(kw.get("helix_angle", 0.0))
        if not kw["helix_angle"] < math.radians(45):  # its own range before its mates'
            where = f"gears[{i}]" if "helix_angle" in table else "common"
            raise InputError(f"{where}.helix_angle", (table if "helix_angle" in table
                                                      else raw_common)["helix_angle"],
                             "must satisfy |beta| < 45 deg" + ("" if where != "common" else
                                                                f" (for gears[{i}], "
                                                                f"{kw['name']!r})"))
        kws.append(kw)
    _unique([kw["name"] for kw in kws], "gears")
    stiffness = _stiffness(doc.get("stiffness", {}), "stiffness")
    shafts, meshes, own_mesh = _graph(doc, kws, stiffness) if graph else ((), (), {})
    signs = _hands(doc, kws, shafts, meshes)
    gears = []
    own_gear: dict[str, dict[str, Any]] = {}  # gear name -> its dynamics options
    for i, (kw, table) in enumerate(zip(kws, gear_tables, strict=True)):
        own_gear[kw["name"]] = {k: (kw[k], f"gears[{i}]" if k in table else "common")
                                for k in PER_GEAR if k in kw}
        kw = {k: v for k, v in kw.items() if k not in ("shaft", "hand", *PER_GEAR)}
        if kw["helix_angle"]:
            kw["helix_angle"] *= signs[i]
        where = f"gears[{i}]"
        with as_written(None, kw["name"], GEAR_KEYS, default=where,
                        sources=[("common", raw_common), (where, table)],
                        label=f"for {where}, {kw['name']!r}"):
            if not graph and i > 0:  # before the gear's own checks: name the mismatch
                require_same_rack(f"gears[{i - 1}]", *_rack(kws[i - 1]), kw["name"], *_rack(kw))
            check_face_width(kw.get("face_width"), f"{kw['name']}.face_width")
            gears.append(Gear(**kw))
    op_raw = doc.get("operating", {})
    op_kw = convert(op_raw, OPERATING_KEYS, "operating")
    with as_written(op_raw, "operating"):
        operating = Operating(**op_kw)
    cracks_raw = doc.get("cracks", [])
    cracks = parse_cracks(cracks_raw)
    name = doc.get("name", "gear train")
    if not isinstance(name, str):
        raise InputError("name", name, "must be a string")
    kw = {"gears": tuple(gears), "operating": operating, "stiffness": stiffness, "name": name,
          "shafts": shafts, "meshes": meshes,
          "faults": parse_faults(doc.get("faults", [])),
          "modifications": parse_modifications(doc.get("modifications", []))}
    try:
        with ExitStack() as stack:  # a mesh's refusal of a gear's value: as written
            for i, (g, table) in enumerate(zip(kws, gear_tables, strict=True)):
                stack.enter_context(as_written(None, g["name"], GEAR_KEYS, default=f"gears[{i}]",
                                               sources=[("common", raw_common),
                                                        (f"gears[{i}]", table)]))
            train = GearTrain(cracks=tuple(cracks), **kw)
    except InputError as exc:  # a crack that does not fit: name the [[cracks]] table
        if not exc.parameter.startswith("crack.") or not cracks:
            raise
        for i, (crack, table) in enumerate(zip(cracks, cracks_raw, strict=True)):
            with as_written(table, "crack", CRACK_KEYS, sources=[(f"cracks[{i}]", table)],
                            default=f"cracks[{i}]"):
                GearTrain(cracks=(crack,), **kw)
        raise
    dynamics = parse_dynamics(doc.get("dynamics", {}), "dynamics")
    dynamics = _per_element(dynamics, doc.get("dynamics", {}), train, own_mesh, own_gear)
    analysis = parse_analysis(doc.get("analysis", {}), "analysis")
    return Gearbox(train=train, dynamics=dynamics, analysis=analysis)


def _per_element(dynamics: DynamicsSettings, raw: Any, train: GearTrain,
                 own_mesh: dict[frozenset, dict[str, tuple[Any, str]]],
                 own_gear: dict[str, dict[str, tuple[Any, str]]]) -> DynamicsSettings:
    """``dynamics`` with the options the meshes and gears give for themselves
    (:data:`PER_MESH`, :data:`PER_GEAR`) as per-item tuples in power-flow order; each
    value checked and named where it was written (``meshes[1].backlash``), an option
    given both per element and in ``[dynamics]`` refused."""
    items = [("mesh", PER_MESH, [own_mesh.get(frozenset(p), {}) for p in train.flow.meshes]),
             ("gear", PER_GEAR, [own_gear.get(g.name, {}) for g in train.gears])]
    for what, names, given in items:
        for name in names:
            if not any(name in d for d in given):
                continue
            at = next(d[name][1] for d in given if name in d)
            require(not (isinstance(raw, dict) and name in raw), f"{at}.{name}",
                    next(d[name][0] for d in given if name in d), f"is also given in "
                    f"[dynamics] ({name} = {raw.get(name) if isinstance(raw, dict) else ''}):"
                    f" give it per {what} or there, not both")
            values = []
            for k, d in enumerate(given):
                if name not in d:
                    values.append(agma_backlash(train, k) if name == "backlash" else 0.0)
                    continue
                value, where = d[name]
                try:  # the element's value alone, named where it was written
                    dataclasses.replace(dynamics, **{name: (value,)})
                except InputError as exc:
                    raise InputError(f"{where}.{name}", value, exc.limit) from None
                values.append(value)
            dynamics = dataclasses.replace(dynamics, **{name: tuple(values)})
    return dynamics


def _stiffness(raw: Any, where: str, base: StiffnessSettings | None = None
               ) -> StiffnessSettings:
    """The ``[stiffness]`` table ``raw``, or a mesh's own over the file's ``base`` (its
    keys override; ``model`` as in ``[stiffness]``), checked as ``[stiffness]`` is and
    named where written (``meshes[1].stiffness.slices``)."""
    kw = convert(raw, STIFFNESS_KEYS, where)
    kw = model_options(kw, where) if base is None or "model" in kw else kw
    try:
        return StiffnessSettings(**kw) if base is None else dataclasses.replace(base, **kw)
    except InputError as exc:
        raise InputError(where + exc.parameter.removeprefix("stiffness"), exc.value,
                         exc.limit) from None


def _graph(doc: dict[str, Any], kws: list[dict[str, Any]], stiffness: StiffnessSettings
           ) -> tuple[tuple[Shaft, ...], tuple[MeshSpec, ...], dict]:
    """``[[shafts]]`` and ``[[meshes]]`` with each gear's ``shaft``, checked as written;
    each mesh's own stiffness options over ``stiffness``; and its own dynamics options
    (:data:`PER_MESH`), by its pair of gears."""
    shafts_raw = array_of_tables(doc.get("shafts", []), "shafts")
    require_tables = [("shafts", shafts_raw), ("meshes", doc.get("meshes"))]
    for key, raw in require_tables:
        if not raw:
            raise InputError(key, "missing", "a gearbox of shafts needs [[shafts]] and "
                             "[[meshes]] (or neither: a chain)")
    specs = [convert(t, SHAFT_KEYS, f"shafts[{i}]") for i, t in enumerate(shafts_raw)]
    names = [sp.get("name", f"shaft{i + 1}") for i, sp in enumerate(specs)]
    _unique(names, "shafts")
    for i, kw in enumerate(kws):
        if kw["shaft"] not in names:
            raise InputError(f"gears[{i}].shaft", kw["shaft"],
                             "no such shaft; shafts: " + ", ".join(names))
    shafts = []
    for i, (sp, table) in enumerate(zip(specs, shafts_raw, strict=True)):
        sp["name"] = names[i]
        sp["gears"] = tuple(kw["name"] for kw in kws if kw["shaft"] == names[i])
        with as_written(table, f"shafts.{names[i]}", SHAFT_KEYS,
                        sources=[(f"shafts[{i}]", table)], default=f"shafts[{i}]"):
            shafts.append(Shaft(**sp))
    meshes = []
    own: dict[frozenset, dict[str, tuple[Any, str]]] = {}
    gear_names = [kw["name"] for kw in kws]
    for i, table in enumerate(array_of_tables(doc["meshes"], "meshes")):
        at = f"meshes[{i}]"
        pair = table.get("gears") if isinstance(table, dict) else None
        if not (isinstance(pair, list) and len(pair) == 2 and all(g in gear_names for g in pair)):
            raise InputError(f"{at}.gears", pair, "must name two gears of [[gears]]: "
                             + ", ".join(gear_names))
        kw = convert({k: v for k, v in table.items() if k != "gears"}, MESH_KEYS, at)
        first, second = (kws[gear_names.index(g)] for g in pair)
        require(first["shaft"] != second["shaft"], f"{at}.gears", pair,
                f"both sit on shaft {first['shaft']!r}")
        require_same_rack(pair[0], *_rack(first), pair[1], *_rack(second), mesh=at)
        b1, b2 = (abs(kw.get("helix_angle", 0.0)) for kw in (first, second))
        j = gear_names.index(pair[1])
        require(math.isclose(b1, b2, rel_tol=1e-9, abs_tol=1e-12), f"gears[{j}].helix_angle",
                f"{math.degrees(b2):.6g} deg", f"must equal the helix angle of {pair[0]} "
                f"({math.degrees(b1):.6g} deg), its mate in {at}")
        own[frozenset(pair)] = {k: (kw.pop(k), at) for k in PER_MESH if k in kw}
        if "stiffness" in kw:
            kw["stiffness"] = _stiffness(kw["stiffness"], f"{at}.stiffness", stiffness)
        with as_written(table, "meshes", MESH_KEYS, sources=[(at, table)], default=at):
            meshes.append(MeshSpec(gears=tuple(pair), **kw))
    return tuple(shafts), tuple(meshes), own


def _unique(names: list[str], key: str) -> None:
    """Refuse a name that ``[[key]]`` gives twice, naming its second table."""
    for i, n in enumerate(names):
        if n in names[:i]:
            raise InputError(f"{key}[{i}].name", n, f"is also {key}[{names.index(n)}].name: "
                             "names must be unique")


def _hands(doc: dict[str, Any], kws: list[dict[str, Any]], shafts: tuple[Shaft, ...],
           meshes: tuple[MeshSpec, ...]) -> list[int]:
    """Sign of each gear's helix angle: its ``hand`` (right +1, left -1), or from the flow.

    A chain alternates (-1)^i. In a gearbox the input gear is right-handed unless given,
    the driven gear of an external mesh has the driver's opposite hand, and a gear that
    drives from a shaft has the hand of the gear that brought the power to that shaft
    (their thrusts on the shaft oppose). Two given hands that cannot mesh are refused.
    """
    if not shafts:
        return [(-1) ** i for i in range(len(kws))]
    names = [kw["name"] for kw in kws]
    sign: dict[str, int] = {}
    for i, kw in enumerate(kws):
        if "hand" in kw:
            if kw["hand"] not in ("right", "left"):
                raise InputError(f"gears[{i}].hand", kw["hand"], 'must be "right" or "left"')
            sign[kw["name"]] = 1 if kw["hand"] == "right" else -1
    # the power flow needs only the tooth counts of the gears not made yet
    flow = power_flow({kw["name"]: SimpleNamespace(teeth=kw["teeth"]) for kw in kws},
                      shafts, meshes)
    on_shaft: dict[int, int] = {}
    for drv, dvn in flow.meshes:
        s_drv = sign.setdefault(drv, on_shaft.get(flow.shaft_of[drv], 1))
        on_shaft.setdefault(flow.shaft_of[drv], s_drv)
        if sign.setdefault(dvn, -s_drv) == s_drv and kws[names.index(drv)]["helix_angle"]:
            m = next(i for i, m in enumerate(meshes) if set(m.gears) == {drv, dvn})
            raise InputError(f"meshes[{m}].gears", [drv, dvn], "both gears have the same "
                             "hand: external helical gears mesh with opposite hands")
        on_shaft.setdefault(flow.shaft_of[dvn], sign[dvn])
    return [sign[n] for n in names]


def parse_modifications(raw: Any) -> tuple[Modification, ...]:
    """Parse the ``[[modifications]]`` tables (one per gear).

    Parameters
    ----------
    raw : list of dict
        The TOML array of tables.

    Returns
    -------
    tuple of Modification

    Raises
    ------
    InputError
        Naming ``modifications[i].<key>``.
    """
    out = []
    for i, table in enumerate(array_of_tables(raw, "modifications")):
        name = f"modifications[{i}]"
        kw = convert(table, MODIFICATION_KEYS, name, list_keys=("pitch_errors",))
        if "gear" not in kw:
            raise InputError(f"{name}.gear", "missing", "name the modified gear")
        if "pitch_errors" in kw and not isinstance(kw["pitch_errors"], tuple):
            kw["pitch_errors"] = (kw["pitch_errors"],)
        with as_written(table, "modifications", MODIFICATION_KEYS, sources=[(name, table)],
                        default=name):
            out.append(Modification(**kw))
    return tuple(out)


def loads(text: str, *, source: str = "TOML") -> Gearbox:
    """Parse TOML text into a :class:`Gearbox`.

    Parameters
    ----------
    text : str
        A configuration (see module docstring).
    source : str, optional
        Where the text comes from (its path), shown when it is not valid TOML.

    Returns
    -------
    Gearbox

    Raises
    ------
    InputError
        Invalid TOML or any bad value.

    Examples
    --------
    >>> gb = loads(example_text("spur-19-48"))
    >>> [g.teeth for g in gb.train.gears]
    [19, 48]
    """
    text = text.removeprefix("\ufeff")  # a UTF-8 byte order mark (Windows editors)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("config", source, f"is not valid TOML: {exc}") from None
    if text.startswith(EFFECTIVE_HEADER):  # written by gearsim, SI throughout
        with plain_numbers_are_si():
            return parse(doc)
    return parse(doc)


def read_file_or_builtin(path: str | Path, builtins: Sequence[str],
                         builtin_text: Callable[[str], str], *, parameter: str,
                         what: str) -> tuple[str, Path | None]:
    """Text of a file, or of a built-in document when ``path`` is one of ``builtins``.

    Parameters
    ----------
    path : str or Path
        A file, or the name of a built-in document.
    builtins : sequence of str
        Names of the built-in documents.
    builtin_text : callable
        Name -> text of a built-in document.
    parameter : str
        Parameter name for messages (e.g. ``"config"``).
    what : str
        What the built-ins are (e.g. ``"example"``), for messages.

    Returns
    -------
    text : str
        The document.
    folder : Path or None
        The folder of the file (``None`` for a built-in), for relative paths inside it.

    Raises
    ------
    InputError
        A missing or unreadable file or one that is not a regular file (a FIFO, a
        device, a directory), naming ``parameter`` and the built-in names. A leading
        UTF-8 byte order mark is dropped.
    """
    if not str(path).strip():  # Path("") is the current folder
        raise InputError(parameter, repr(str(path)), f"is empty: give a file or a built-in "
                         f"{what}: " + ", ".join(builtins))
    p = Path(path)
    if not p.exists():
        if str(path) in builtins:
            return builtin_text(str(path)), None
        raise InputError(parameter, str(path), f"file not found (or give a built-in {what}: "
                         + ", ".join(builtins) + ")")
    if not p.is_file():  # a FIFO or a device would block or never end
        raise InputError(parameter, str(path), "is not a regular file (a directory, FIFO or "
                         "device cannot be read)")
    try:
        return p.read_text(encoding="utf-8-sig"), p.parent
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(parameter, str(path), f"cannot be read: {exc}") from None


def load(path: str | Path) -> Gearbox:
    """Read a TOML configuration file, or a built-in example by name.

    Parameters
    ----------
    path : str or Path
        A TOML file, or a name of :data:`EXAMPLES`.

    Returns
    -------
    Gearbox

    Raises
    ------
    InputError
        A missing file or any bad value, in one line.
    """
    text, _ = read_file_or_builtin(path, EXAMPLES, example_text, parameter="config",
                                   what="example")
    return loads(text, source=str(path))


def example(name: str) -> Gearbox:
    """A built-in example by name (one of :data:`EXAMPLES`).

    Parameters
    ----------
    name : str
        ``"idler-table1"`` (the seed's Table-1 idler train) or ``"spur-19-48"``.

    Returns
    -------
    Gearbox
    """
    return loads(example_text(name))


