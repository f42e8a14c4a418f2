"""The effective configuration of a train as TOML (SI units), for results' provenance."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from gearsim.system.train import GearTrain

__all__ = ["train_to_toml"]


def _value(v: Any) -> str:
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
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _table(lines: list[str], header: str, items: dict[str, Any]) -> None:
    lines.append("")
    lines.append(header)
    for k, v in items.items():
        if v is None:
            continue
        lines.append(f"{k} = {_value(v)}")


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
    lines = ["# gearsim effective configuration (SI units: m, rad, rad/s, N m, Pa, s, Hz)",
             f"name = {_value(train.name)}"]
    chain = train.is_chain
    if not chain:
        for sh in train.flow.shafts:
            _table(lines, "[[shafts]]", {k: v for k, v in dataclasses.asdict(sh).items()
                                         if k != "gears"})
    for g in train.gears:
        where = {} if chain else {"shaft": train.flow.shafts[train.flow.shaft_of[g.name]].name,
                                  "hand": "right" if g.helix_angle >= 0 else "left"}
        _table(lines, "[[gears]]", {
            "name": g.name, **where, "teeth": g.teeth, "normal_module": g.normal_module,
            "normal_pressure_angle": g.normal_pressure_angle,
            "helix_angle": abs(g.helix_angle), "face_width": g.face_width,
            "addendum_coefficient": g.addendum_coefficient,
            "dedendum_coefficient": g.dedendum_coefficient,
            "fillet_radius_coefficient": g.fillet_radius_coefficient,
            "profile_shift": g.profile_shift, "bore_radius": g.bore_radius})
        _table(lines, "[gears.material]", {
            "youngs_modulus": g.material.youngs_modulus,
            "poisson_ratio": g.material.poisson_ratio, "density": g.material.density})
    for (a, b), angle in zip(() if chain else train.flow.meshes, train.flow.angles,
                             strict=False):
        _table(lines, "[[meshes]]", {"gears": [a, b], "angle": angle})
    # the speed with its unit: a bare number would be ambiguous (rpm or rad/s) and is
    # refused when a configuration is read
    _table(lines, "[operating]", {"speed": f"{train.operating.speed!r} rad/s",
                                  "torque": train.operating.torque})
    st = train.stiffness
    _table(lines, "[stiffness]", {"closure": st.closure, "slices": st.slices,
                                  "positions_per_cycle": st.positions_per_cycle,
                                  "gauss_points": st.gauss_points, "plane": st.plane,
                                  "source": st.source, "corner_contact": st.corner_contact,
                                  "contact": st.contact, "coupling": st.coupling,
                                  "fe_pair_positions": st.fe_pair_positions})
    for c in train.cracks:
        _table(lines, "[[cracks]]", {"gear": c.gear, "tooth": c.tooth, "flank": c.flank,
                                     "depth": c.depth, "angle": c.angle, "extent": c.extent,
                                     "profile": c.profile, "start_radius": c.start_radius})
    for f in train.faults:
        _table(lines, "[[faults]]", {"kind": f.kind, **{
            k: v for k, v in dataclasses.asdict(f).items()
            if not (f.kind == "broken" and k == "flank") and v != ()}})
    for m in train.modifications:
        _table(lines, "[[modifications]]", {k: v for k, v in dataclasses.asdict(m).items()
                                            if v != ()})
    if dynamics is not None:
        _table(lines, "[dynamics]", dynamics)
    return "\n".join(lines) + "\n"
