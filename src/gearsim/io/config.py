"""TOML configuration files with units, validated into frozen dataclasses.

Values may carry units as strings (``"6 mm"``, ``"1900 rpm"``, ``"4876 N*m"``,
``"13 deg"``), parsed with pint; plain numbers are SI (metres, radians, rad/s, N m, Pa).
Unknown keys are refused. Layout::

    name = "..."
    [material]            # default material of every gear
    [common]              # default gear data (any key of [[gears]])
    [[gears]]             # one table per gear, in the order of the power flow
    [operating]           # speed and torque of the first gear
    [stiffness]           # closure, slices, positions_per_cycle, gauss_points, plane
    [[cracks]]            # gear, tooth, flank, depth, angle, extent, profile, start_radius

Further sections (e.g. ``[dynamics]``) are registered in :data:`EXTRA_SECTIONS` by the
modules that use them.
"""

from __future__ import annotations

import importlib
import tomllib
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.crack import Crack, crack_geometry
from gearsim.stiffness.mesh import StiffnessSettings
from gearsim.system import GearTrain, Operating
from gearsim.units import to_si

__all__ = ["EXAMPLES", "EXTRA_SECTIONS", "convert", "example_text", "load", "loads", "parse"]

EXAMPLES = ("idler-table1", "spur-19-48")

MATERIAL_KEYS = {"youngs_modulus": "pressure", "poisson_ratio": "dimensionless",
                 "density": "density"}
GEAR_KEYS = {
    "name": "str", "teeth": "int", "normal_module": "length",
    "normal_pressure_angle": "angle", "helix_angle": "angle", "face_width": "length",
    "addendum_coefficient": "dimensionless", "dedendum_coefficient": "dimensionless",
    "fillet_radius_coefficient": "dimensionless", "profile_shift": "dimensionless",
    "bore_radius": "length", "material": "table",
}
OPERATING_KEYS = {"speed": "speed", "torque": "torque"}
STIFFNESS_KEYS = {"closure": "str", "slices": "int", "positions_per_cycle": "int",
                  "gauss_points": "int", "plane": "str", "source": "str"}
CRACK_KEYS = {"gear": "str", "tooth": "int", "flank": "str", "depth": "length",
              "angle": "angle", "extent": "dimensionless", "profile": "str",
              "start_radius": "length"}

#: name -> parser(dict, section_name) -> object, stored in GearTrain.extra[name].
#: Modules listed in EXTRA_SECTION_MODULES register their sections when imported.
EXTRA_SECTIONS: dict[str, Callable[[dict, str], Any]] = {}
EXTRA_SECTION_MODULES = ("gearsim.dynamics.settings", "gearsim.fem.settings")


def _register_extra_sections() -> None:
    for mod in EXTRA_SECTION_MODULES:
        try:
            importlib.import_module(mod)
        except ModuleNotFoundError as exc:  # that part of gearsim is not present
            if exc.name != mod:
                raise
TOP_KEYS = ("name", "material", "common", "gears", "operating", "stiffness", "cracks")


def convert(data: Any, spec: dict[str, str], section: str) -> dict[str, Any]:
    """Check keys of ``data`` against ``spec`` and convert values to SI / Python types."""
    if not isinstance(data, dict):
        raise InputError(section, data, "must be a table")
    out: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{section}.{key}"
        if key not in spec:
            raise InputError(name, value, f"unknown key; allowed keys: {', '.join(spec)}")
        kind = spec[key]
        if kind == "str":
            if not isinstance(value, str):
                raise InputError(name, value, "must be a string")
            out[key] = value
        elif kind == "int":
            if isinstance(value, bool) or not isinstance(value, int):
                raise InputError(name, value, "must be an integer")
            out[key] = value
        elif kind == "bool":
            if not isinstance(value, bool):
                raise InputError(name, value, "must be true or false")
            out[key] = value
        elif kind == "table":
            out[key] = value
        else:
            out[key] = to_si(value, kind, name)
    return out


def _material(data: Any, section: str, base: Material | None = None) -> Material:
    kw = convert(data, MATERIAL_KEYS, section)
    if base is not None:
        kw = {"youngs_modulus": base.youngs_modulus, "poisson_ratio": base.poisson_ratio,
              "density": base.density, **kw}
    return Material(**kw)


def parse(doc: dict[str, Any]) -> GearTrain:
    """Build a :class:`GearTrain` from a parsed TOML document."""
    _register_extra_sections()
    for key in doc:
        if key not in TOP_KEYS and key not in EXTRA_SECTIONS:
            raise InputError(key, "...", "unknown section; allowed: "
                             + ", ".join((*TOP_KEYS, *EXTRA_SECTIONS)))
    material = _material(doc.get("material", {}), "material")
    common = convert(doc.get("common", {}), GEAR_KEYS, "common")
    gear_tables = doc.get("gears")
    if not isinstance(gear_tables, list) or len(gear_tables) < 2:
        raise InputError("gears", gear_tables if gear_tables is not None else "missing",
                         "need at least 2 [[gears]] tables")
    gears = []
    for i, table in enumerate(gear_tables):
        kw = {**common, **convert(table, GEAR_KEYS, f"gears[{i}]")}
        kw.setdefault("name", f"gear{i + 1}")
        if "teeth" not in kw:
            raise InputError(f"gears[{i}].teeth", "missing", "every gear needs a tooth count")
        if "normal_module" not in kw:
            raise InputError(f"gears[{i}].normal_module", "missing",
                             "give it in [common] or in the gear")
        mat = kw.pop("material", None)
        kw["material"] = material if mat is None else _material(mat, f"gears[{i}].material",
                                                                material)
        if "helix_angle" in kw:  # consecutive external gears have opposite hands
            kw["helix_angle"] = abs(kw["helix_angle"]) * (-1) ** i
        gears.append(Gear(**kw))
    operating = Operating(**convert(doc.get("operating", {}), OPERATING_KEYS, "operating"))
    stiffness = StiffnessSettings(**convert(doc.get("stiffness", {}), STIFFNESS_KEYS,
                                            "stiffness"))
    cracks_raw = doc.get("cracks", [])
    if not isinstance(cracks_raw, list):
        raise InputError("cracks", cracks_raw, "must be an array of tables [[cracks]]")
    cracks = []
    for i, table in enumerate(cracks_raw):
        kw = convert(table, CRACK_KEYS, f"cracks[{i}]")
        if "gear" not in kw:
            raise InputError(f"cracks[{i}].gear", "missing", "name the cracked gear")
        cracks.append(Crack(**kw))
    extra = {name: parser(doc[name], name) for name, parser in EXTRA_SECTIONS.items()
             if name in doc}
    name = doc.get("name", "gear train")
    if not isinstance(name, str):
        raise InputError("name", name, "must be a string")
    train = GearTrain(gears=tuple(gears), operating=operating, stiffness=stiffness,
                      cracks=tuple(cracks), name=name, extra=extra)
    # check every crack fits its tooth now rather than deep inside a computation
    for c in train.cracks:
        crack_geometry(ToothProfile(train.gear(c.gear)), c)
    return train


def loads(text: str) -> GearTrain:
    """Parse TOML text into a :class:`GearTrain`."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("config", "TOML", f"is not valid TOML: {exc}") from None
    return parse(doc)


def read_file_or_builtin(path: str | Path, builtins, builtin_text, *, parameter: str,
                         what: str) -> tuple[str, Path | None]:
    """Text of a file, or of a built-in document when ``path`` is one of ``builtins``.

    Returns the text and the folder of the file (``None`` for a built-in), for relative
    paths inside it. A missing or unreadable file is an :class:`InputError` naming
    ``parameter`` and listing the built-in ``what`` names.
    """
    p = Path(path)
    if not p.exists():
        if str(path) in builtins:
            return builtin_text(str(path)), None
        raise InputError(parameter, str(path), f"file not found (or give a built-in {what}: "
                         + ", ".join(builtins) + ")")
    try:
        return p.read_text(encoding="utf-8"), p.parent
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(parameter, str(path), f"cannot be read: {exc}") from None


def load(path: str | Path) -> GearTrain:
    """Read a TOML configuration file, or a built-in example by name."""
    text, _ = read_file_or_builtin(path, EXAMPLES, example_text, parameter="config",
                                   what="example")
    return loads(text)


def example_text(name: str) -> str:
    """TOML text of a built-in example."""
    if name not in EXAMPLES:
        raise InputError("example", name, "unknown; built-in examples: " + ", ".join(EXAMPLES))
    return resources.files("gearsim.data").joinpath(f"{name}.toml").read_text(encoding="utf-8")
