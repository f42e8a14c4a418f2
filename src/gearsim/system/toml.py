"""The effective configuration of a train as TOML (SI units), for results' provenance."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from gearsim.system.train import GearTrain

__all__ = ["EFFECTIVE_HEADER", "damage_tables", "gear_tables", "table", "toml_value",
           "train_to_toml"]

#: First line of the text written here: its plain numbers are SI (also a speed).
EFFECTIVE_HEADER = "# gearsim effective configuration (SI units: m, rad, rad/s, N m, Pa, s, Hz)"


def toml_value(v: Any) -> str:
    """``v`` as a TOML value (bool, int, float by ``repr``, str, list).

    Parameters
    ----------
    v : bool, int, float, str, list or tuple
        A finite float.

    Returns
    -------
    str
    """
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isinf(v) or math.isnan(v):
            raise ValueError(f"cannot write {v} to TOML")
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def table(lines: list[str], header: str, items: dict[str, Any]) -> None:
    """Append the TOML table ``header`` (``"[stiffness]"``, ``"[[gears]]"``) to ``lines``.

    Parameters
    ----------
    lines : list of str
        The text so far, one line an item (appended to).
    header : str
        The table's header line.
    items : dict
        Key -> value (bool, int, float via ``repr``: read back bit for bit, str, list);
        ``None`` values are left out.
    """
    lines.append("")
    lines.append(header)
    for k, v in items.items():
        if v is None:
            continue
        lines.append(f"{k} = {toml_value(v)}")


def gear_tables(lines: list[str], train: GearTrain, graph: bool) -> None:
    """Append the ``[[gears]]`` of ``train`` (each with its ``[gears.material]``) and,
    written as a graph, each gear's ``shaft`` and ``hand`` and the ``[[meshes]]`` (a mesh's
    own stiffness options, those that differ from the train's, as ``[meshes.stiffness]``).

    Parameters
    ----------
    lines : list of str
        The text so far (appended to).
    train : GearTrain
        The gears.
    graph : bool
        As a graph of shafts (else a chain: gear i drives gear i + 1).
    """
    for g in train.gears:
        where = {} if not graph else {"shaft": train.flow.shafts[train.flow.shaft_of[g.name]].name,
                                      "hand": "right" if g.helix_angle >= 0 else "left"}
        table(lines, "[[gears]]", {
            "name": g.name, **where, "teeth": g.teeth, "normal_module": g.normal_module,
            "normal_pressure_angle": g.normal_pressure_angle,
            "helix_angle": abs(g.helix_angle), "face_width": g.face_width,
            "addendum_coefficient": g.addendum_coefficient,
            "dedendum_coefficient": g.dedendum_coefficient,
            "fillet_radius_coefficient": g.fillet_radius_coefficient,
            "profile_shift": g.profile_shift, "bore_radius": g.bore_radius})
        table(lines, "[gears.material]", {
            "youngs_modulus": g.material.youngs_modulus,
            "poisson_ratio": g.material.poisson_ratio, "density": g.material.density})
    for i, ((a, b), angle) in enumerate(zip(train.flow.meshes if graph else (),
                                            train.flow.angles, strict=False)):
        table(lines, "[[meshes]]", {"gears": [a, b], "angle": angle})
        own, st = dataclasses.asdict(train.settings_of(i)), dataclasses.asdict(train.stiffness)
        if own != st:
            table(lines, "[meshes.stiffness]", {k: v for k, v in own.items() if v != st[k]})


def damage_tables(lines: list[str], part: Any, prefix: str = "") -> None:
    """Append the ``[[cracks]]``, ``[[faults]]`` and ``[[modifications]]`` of ``part``.

    Parameters
    ----------
    lines : list of str
        The text so far (appended to).
    part : GearTrain or PlanetaryTrain
        Its ``cracks``, ``faults`` and (a train) ``modifications``.
    prefix : str, optional
        Of the headers: ``"stages."`` for a stage's own (``[[stages.cracks]]``).
    """
    for c in part.cracks:
        table(lines, f"[[{prefix}cracks]]", {
            "gear": c.gear, "tooth": c.tooth, "flank": c.flank, "depth": c.depth,
            "angle": c.angle, "extent": c.extent, "profile": c.profile,
            "start_radius": c.start_radius})
    for f in part.faults:
        table(lines, f"[[{prefix}faults]]", {"kind": f.kind, **{
            k: v for k, v in dataclasses.asdict(f).items()
            if not (f.kind == "broken" and k == "flank") and v != ()}})
    for m in getattr(part, "modifications", ()):
        table(lines, f"[[{prefix}modifications]]", {k: v for k, v in dataclasses.asdict(m).items()
                                                    if v != ()})


def train_to_toml(train: GearTrain, dynamics: dict[str, Any] | None = None) -> str:
    """The effective configuration of ``train`` as TOML in SI units.

    The text is a complete configuration that :func:`gearsim.loads` reads back to the
    same train; results files store it as their provenance.

    Parameters
    ----------
    train : GearTrain
        The train (gears, operating point, stiffness options, cracks).
    dynamics : dict, optional
        The ``[dynamics]`` table (``DynamicsSettings.to_dict()``), SI numbers.

    Returns
    -------
    str
        TOML text.
    """
    lines = [EFFECTIVE_HEADER, f"name = {toml_value(train.name)}"]
    graph = not train.is_chain or any(m.stiffness for m in train.meshes)
    for sh in train.flow.shafts if graph else ():
        table(lines, "[[shafts]]", {k: v for k, v in dataclasses.asdict(sh).items()
                                    if k != "gears"})
    gear_tables(lines, train, graph)
    # the speed with its unit: a bare number would be ambiguous (rpm or rad/s) and is
    # refused when a configuration is read
    table(lines, "[operating]", {"speed": f"{train.operating.speed!r} rad/s",
                                 "torque": train.operating.torque})
    table(lines, "[stiffness]", dataclasses.asdict(train.stiffness))
    damage_tables(lines, train)
    if dynamics is not None:
        table(lines, "[dynamics]", dynamics)
    return "\n".join(lines) + "\n"
