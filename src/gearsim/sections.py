"""Config sections: check a table's keys and convert its values to SI once, at the edge.

Every section of a configuration file (``[operating]``, ``[stiffness]``,
``[dynamics]``, ``[analysis]``, a study file's tables) is a TOML table whose keys are
declared with the kind of their value: ``"str"``, ``"int"``, ``"bool"``, ``"table"``
or a quantity kind of :data:`gearsim.units.DIMENSIONS` (``"length"``, ``"time"``, ...)
converted with pint by :func:`gearsim.units.to_si`. A key may also be a list of
values (``list_keys``): each element is converted and the list becomes a tuple.
Unknown keys are refused with the list of allowed ones. Every quantity must be finite.

A refusal raised later, by the dataclass that checks the converted values, shows the
value as the user wrote it (``"-3 rpm"``, not ``-0.314``): wrap the construction in
:func:`as_written`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

from gearsim.errors import InputError
from gearsim.units import to_si

__all__ = ["as_written", "convert", "convert_value", "written", "written_name"]


def convert_value(value: Any, kind: str, name: str) -> Any:
    """Convert one config value of ``kind`` (see module docstring).

    Parameters
    ----------
    value : Any
        The value as read from TOML.
    kind : str
        ``"str"`` (``"str:a|b"``: its choices, named when the value is not a string),
        ``"int"``, ``"bool"``, ``"table"`` or a quantity kind.
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
    if kind.partition(":")[0] == "str":  # "str:a|b": a string, one of a, b
        if not isinstance(value, str):
            choices = kind.partition(":")[2].replace("|", ", ")
            raise InputError(name, value, f"must be one of {choices} (a string)" if choices
                             else "must be a string")
        return value
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(name, repr(value) if isinstance(value, str) else value,
                             "must be an integer" + (" (written as a string: leave out "
                                                     "the quotes)" if isinstance(value, str)
                                                     else ""))
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


def written(raw: Any, kind: str | None = None) -> Any:
    """How a raw config value is shown in a message: strings and lists as written.

    Parameters
    ----------
    raw : Any
        The value as read from TOML.
    kind : str, optional
        Its kind; a plain number of kind ``"angle"`` is shown with the unit it is read
        in (``20 rad``), since the checks show angles in degrees.

    Returns
    -------
    Any
        ``raw`` itself for a string; a list with a string element as TOML-like text
        (``["5 um", "-1 um"]``); a plain angle with ``rad``; ``None`` for anything else
        (show the checked value).

    Examples
    --------
    >>> written("-3 rpm")
    '-3 rpm'
    >>> written(["5 um", 0])
    '["5 um", 0]'
    >>> written(0.3) is None
    True
    >>> written(20, "angle")
    '20 rad'
    """
    if kind == "angle" and isinstance(raw, (int, float)) and not isinstance(raw, bool):
        return f"{raw} rad"
    if isinstance(raw, str):
        return raw
    if isinstance(raw, list) and any(isinstance(v, str) for v in raw):
        return "[" + ", ".join(f'"{v}"' if isinstance(v, str) else repr(v) for v in raw) + "]"
    return None


@contextmanager
def as_written(raw: Any, prefix: str, spec: Mapping[str, str] | None = None, *,
               sources: Sequence[tuple[str, Any]] | None = None,
               default: str | None = None, label: str = "") -> Iterator[None]:
    """Re-raise an :class:`InputError` about ``<prefix>.<key>`` as the user wrote it.

    The dataclasses check SI values under their own names (``operating.speed``, a
    gear's name). When the refused parameter is a key of a raw table, the message names
    the table it was written in (``gears[1].face_width``, ``common.face_width``) and, if
    the value came with a unit, shows the user's text (``operating.speed = -3 rpm: must
    be > 0 rad/s``) instead of the SI number.

    Parameters
    ----------
    raw : Any
        The table (a dict) as read from TOML; its name is ``prefix`` (ignored when
        ``sources`` is given).
    prefix : str
        The name the dataclass gives its parameters before the dot (``"operating"``,
        ``"dynamics"``, a gear's name).
    spec : mapping, optional
        Key -> value kind (as for :func:`convert`), to show plain angles with ``rad``.
    sources : sequence of (str, dict), optional
        ``(section name, raw table)`` in increasing precedence (``[("common", ...),
        ("gears[1]", ...)]``): the last table holding the key names the parameter.
    default : str, optional
        Section name for a key no table holds (a default or derived value); ``None``
        keeps ``prefix``.
    label : str, optional
        Appended to the limit when the parameter is named by a shared table (e.g. the
        gear a ``[common]`` value failed for).

    Yields
    ------
    None
        Run the construction inside the ``with`` block.

    Raises
    ------
    InputError
        The error raised inside the block, renamed and with the value as written.
    """
    tables = list(sources) if sources is not None else [(prefix, raw)]
    try:
        yield
    except InputError as exc:
        if not exc.parameter.startswith(prefix + "."):
            raise
        key = exc.parameter[len(prefix) + 1:]
        section, value = default if default is not None else prefix, None
        for name, table in tables:
            if isinstance(table, dict) and key in table:
                section, value = name, table[key]
        shown = written(value, (spec or {}).get(key)) if value is not None else None
        limit = exc.limit
        if label and default is not None and section != default:
            limit = f"{limit} ({label})"
        parameter = f"{section}.{key}"
        if parameter == exc.parameter and (shown is None or shown == exc.value) \
                and limit == exc.limit:
            raise
        raise InputError(parameter, exc.value if shown is None else shown, limit) from None


def written_name(parameter: str, back: dict[str, str]) -> str:
    """``parameter`` of the translated form (``chain.shaft_stiffness``) as the graph
    wrote it (``shafts[1].torsional_stiffness``), by the longest prefix ``back`` renames;
    unchanged where none does.

    Parameters
    ----------
    parameter : str
        A parameter name of the translated ``[stage]`` / ``[[stages]]`` form.
    back : dict of str to str
        Translated prefix -> the graph's (the graph-form reader keeps it as
        ``gearsim.model.Gearbox.written``).

    Returns
    -------
    str
    """
    for a in sorted(back, key=len, reverse=True):
        rest = parameter[len(a):]  # whole names only: fixed is not a prefix of fixed_x
        whole = a[-1:] in ".[" or not (rest[:1].isalnum() or rest[:1] == "_")
        if parameter.startswith(a) and whole:
            return back[a] + rest
    return parameter
