"""Config sections: check a table's keys and convert its values to SI once, at the edge.

Every section of a configuration file (``[operating]``, ``[stiffness]``,
``[dynamics]``, ``[analysis]``, a study file's tables) is a TOML table whose keys are
declared with the kind of their value: ``"str"``, ``"int"``, ``"bool"``, ``"table"``
or a quantity kind of :data:`gearsim.units.DIMENSIONS` (``"length"``, ``"time"``, ...)
converted with pint by :func:`gearsim.units.to_si`. A key may also be a list of
values (``list_keys``): each element is converted and the list becomes a tuple.
Unknown keys are refused with the list of allowed ones.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from gearsim.errors import InputError
from gearsim.units import to_si

__all__ = ["convert", "convert_value"]


def convert_value(value: Any, kind: str, name: str) -> Any:
    """Convert one config value of ``kind`` (see module docstring).

    Parameters
    ----------
    value : Any
        The value as read from TOML.
    kind : str
        ``"str"``, ``"int"``, ``"bool"``, ``"table"`` or a quantity kind.
    name : str
        Dotted parameter name for the error message.

    Returns
    -------
    Any
        The checked value; quantities as SI floats.

    Raises
    ------
    InputError
        Wrong type, unparseable quantity or wrong dimension.

    Examples
    --------
    >>> convert_value("6 mm", "length", "gears[0].normal_module")
    0.006
    >>> convert_value(3, "int", "stiffness.slices")
    3
    """
    if kind == "str":
        if not isinstance(value, str):
            raise InputError(name, value, "must be a string")
        return value
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(name, value, "must be an integer")
        return value
    if kind == "bool":
        if not isinstance(value, bool):
            raise InputError(name, value, "must be true or false")
        return value
    if kind == "table":
        return value
    return to_si(value, kind, name)


def convert(data: Any, spec: Mapping[str, str], section: str, *,
            list_keys: Iterable[str] = ()) -> dict[str, Any]:
    """Check the keys of table ``data`` against ``spec`` and convert its values.

    Parameters
    ----------
    data : Any
        The table (a dict) as read from TOML.
    spec : mapping
        Allowed key -> value kind.
    section : str
        Name of the section, prefixed to every parameter name in messages.
    list_keys : iterable of str, optional
        Keys that also accept a non-empty list of values (returned as a tuple).

    Returns
    -------
    dict
        Key -> converted value.

    Raises
    ------
    InputError
        A table of the wrong type, an unknown key, or a bad value.

    Examples
    --------
    >>> kw = convert({"speed": "1900 rpm"}, {"speed": "speed", "torque": "torque"},
    ...              "operating")
    >>> round(kw["speed"], 6)  # 1900 * 2 pi / 60 rad/s
    198.967535
    """
    if not isinstance(data, dict):
        raise InputError(section, data, "must be a table")
    lists = set(list_keys)
    out: dict[str, Any] = {}
    for key, value in data.items():
        name = f"{section}.{key}"
        if key not in spec:
            raise InputError(name, value, f"unknown key; allowed keys: {', '.join(spec)}")
        if key in lists and isinstance(value, list):
            if not value:
                raise InputError(name, value, "must not be empty")
            out[key] = tuple(convert_value(v, spec[key], f"{name}[{i}]")
                             for i, v in enumerate(value))
        else:
            out[key] = convert_value(value, spec[key], name)
    return out
