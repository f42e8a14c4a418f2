"""TOML configuration files with units, validated into the typed gearbox model.

Values may carry units as strings (``"6 mm"``, ``"1900 rpm"``, ``"4876 N*m"``,
``"13 deg"``), parsed with pint; plain numbers are SI (metres, radians, rad/s, N m, Pa).
Unknown keys and sections are refused. Layout::

    name = "..."
    [material]            # default material of every gear
    [common]              # default gear data (any key of [[gears]])
    [[gears]]             # one table per gear, in the order of the power flow
    [operating]           # speed and torque of the first gear
    [stiffness]           # closure, slices, positions_per_cycle, gauss_points, plane, source
    [[cracks]]            # gear, tooth, flank, depth, angle, extent, profile, start_radius
    [dynamics]            # gearsim.dynamics.DynamicsSettings
    [analysis]            # gearsim.signals.AnalysisSettings

Each section is parsed by plain code into its frozen dataclass, whose constructor checks
every value; the result is a :class:`gearsim.model.Gearbox`.
"""

from __future__ import annotations

import tomllib
from collections.abc import Callable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

from gearsim.dynamics.settings import parse_dynamics
from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.model.gearbox import Gearbox
from gearsim.sections import convert
from gearsim.signals.settings import parse_analysis
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.train import GearTrain, Operating

__all__ = ["EXAMPLES", "example", "example_text", "load", "loads", "parse",
           "read_file_or_builtin"]

#: Built-in examples: the seed's Table-1 helical idler train and Tian's spur pair.
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

TOP_KEYS = ("name", "material", "common", "gears", "operating", "stiffness", "cracks",
            "dynamics", "analysis")


def _material(data: Any, section: str, base: Material | None = None) -> Material:
    kw = convert(data, MATERIAL_KEYS, section)
    if base is not None:
        kw = {"youngs_modulus": base.youngs_modulus, "poisson_ratio": base.poisson_ratio,
              "density": base.density, **kw}
    return Material(**kw)


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
    for key in doc:
        if key not in TOP_KEYS:
            raise InputError(key, "...", "unknown section; allowed: " + ", ".join(TOP_KEYS))
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
    name = doc.get("name", "gear train")
    if not isinstance(name, str):
        raise InputError("name", name, "must be a string")
    train = GearTrain(gears=tuple(gears), operating=operating, stiffness=stiffness,
                      cracks=tuple(cracks), name=name)
    dynamics = parse_dynamics(doc.get("dynamics", {}), "dynamics")
    analysis = parse_analysis(doc.get("analysis", {}), "analysis")
    return Gearbox(train=train, dynamics=dynamics, analysis=analysis)


def loads(text: str) -> Gearbox:
    """Parse TOML text into a :class:`Gearbox`.

    Parameters
    ----------
    text : str
        A configuration (see module docstring).

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
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("config", "TOML", f"is not valid TOML: {exc}") from None
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
        A missing or unreadable file, naming ``parameter`` and the built-in names.
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
    return loads(text)


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


def example_text(name: str) -> str:
    """TOML text of a built-in example.

    Parameters
    ----------
    name : str
        One of :data:`EXAMPLES`.

    Returns
    -------
    str
    """
    if name not in EXAMPLES:
        raise InputError("example", name, "unknown; built-in examples: " + ", ".join(EXAMPLES))
    return resources.files("gearsim.data").joinpath(f"{name}.toml").read_text(encoding="utf-8")
