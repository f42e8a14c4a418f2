"""The damage sections of a configuration: ``[[cracks]]`` and ``[[faults]]``.

Shared by the gear trains (:mod:`gearsim.model.config`) and the planetary stages
(:mod:`gearsim.model.planetary`); values take units as strings (``"2 mm"``).
"""

from __future__ import annotations

from typing import Any

from gearsim.errors import InputError
from gearsim.sections import as_written, convert
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.faults import FAULT_KINDS, fault_from_kind, required_fields

__all__ = ["CRACK_KEYS", "FAULT_FIELDS", "FAULT_KEYS", "array_of_tables", "parse_cracks",
           "parse_faults"]

CRACK_KEYS = {"gear": "str", "tooth": "int", "flank": "str", "depth": "length",
              "angle": "angle", "extent": "dimensionless", "profile": "str",
              "start_radius": "length"}

#: Keys of a ``[[faults]]`` table (``kind`` names the fault; the keys each kind takes
#: are :data:`FAULT_FIELDS`).
FAULT_KEYS = {"kind": "str", "gear": "str", "tooth": "int", "flank": "str",
              "radius": "length", "length": "length", "width": "length", "depth": "length",
              "z": "length", "shape": "str", "area_fraction": "dimensionless",
              "radius_min": "length", "radius_max": "length", "pit_diameter": "length",
              "seed": "int", "edge": "str", "break_radius": "length", "radii": "length",
              "depths": "length", "coefficient": "wear_coefficient",
              "cycles": "dimensionless"}
FAULT_FIELDS = {
    "spall": ("gear", "tooth", "flank", "radius", "length", "width", "depth", "z", "shape"),
    "pitting": ("gear", "tooth", "flank", "area_fraction", "radius_min", "radius_max",
                "pit_diameter", "depth", "seed"),
    "chip": ("gear", "tooth", "flank", "length", "width", "edge"),
    "broken": ("gear", "tooth", "width", "edge", "break_radius"),
    "wear": ("gear", "tooth", "flank", "radii", "depths", "coefficient", "cycles"),
}


def array_of_tables(raw: Any, name: str) -> list:
    """``raw`` if it is a TOML array of tables, else one line naming ``name``.

    Parameters
    ----------
    raw : object
        The parsed value.
    name : str
        Its key (``"cracks"``, ``"faults"``, ...).

    Returns
    -------
    list of dict

    Raises
    ------
    InputError
        If ``raw`` is not a list of tables.
    """
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        raise InputError(name, raw, f"must be an array of tables [[{name}]]")
    return raw


def parse_faults(raw: Any, table: str = "faults") -> tuple:
    """Parse the ``[[faults]]`` tables into fault objects (:mod:`gearsim.stiffness.faults`).

    Parameters
    ----------
    raw : list of dict
        The TOML array of tables; each names its ``kind``.
    table : str, optional
        Its name in messages (``"stages[2].faults"`` for a later stage's).

    Returns
    -------
    tuple of Fault

    Raises
    ------
    InputError
        Naming ``<table>[i].<key>``: unknown kind or key, a key the kind does not take,
        a bad value.
    """
    out = []
    for i, tab in enumerate(array_of_tables(raw, table)):
        name = f"{table}[{i}]"
        kw = convert(tab, FAULT_KEYS, name, list_keys=("radii", "depths"))
        kind = kw.pop("kind", None)
        if kind not in FAULT_FIELDS:
            raise InputError(f"{name}.kind", kind if kind is not None else "missing",
                             "must be one of " + ", ".join(FAULT_KINDS))
        for key in kw:
            if key not in FAULT_FIELDS[kind]:
                raise InputError(f"{name}.{key}", tab[key], f"is not a key of a {kind}; "
                                 f"allowed: kind, {', '.join(FAULT_FIELDS[kind])}")
        if "gear" not in kw:
            raise InputError(f"{name}.gear", "missing", "name the damaged gear")
        missing = [k for k in required_fields(kind) if k not in kw]
        if missing:
            raise InputError(f"{name}.{missing[0]}", "missing", f"a {kind} needs "
                             + ", ".join(missing))
        for key in ("radii", "depths"):
            if key in kw and not isinstance(kw[key], tuple):
                kw[key] = (kw[key],)
        with as_written(tab, kind, FAULT_KEYS, sources=[(name, tab)], default=name):
            out.append(fault_from_kind(kind, **kw))
    return tuple(out)


def parse_cracks(raw: Any, table: str = "cracks") -> tuple[Crack, ...]:
    """Parse the ``[[cracks]]`` tables into :class:`~gearsim.stiffness.crack.Crack`.

    Parameters
    ----------
    raw : list of dict
        The TOML array of tables; each names its ``gear``.
    table : str, optional
        Its name in messages (``"stages[2].cracks"`` for a later stage's).

    Returns
    -------
    tuple of Crack

    Raises
    ------
    InputError
        Naming ``<table>[i].<key>``: a missing gear, an unknown key, a bad value.
    """
    out = []
    for i, tab in enumerate(array_of_tables(raw, table)):
        name = f"{table}[{i}]"
        kw = convert(tab, CRACK_KEYS, name)
        if "gear" not in kw:
            raise InputError(f"{name}.gear", "missing", "name the cracked gear")
        with as_written(tab, "crack", CRACK_KEYS, sources=[(name, tab)], default=name):
            out.append(Crack(**kw))
    return tuple(out)
