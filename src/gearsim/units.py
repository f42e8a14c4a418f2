"""Units at the edges: parse user values with pint and return SI floats.

Plain numbers are taken as SI, except where a bare number is ambiguous for the quantity
(a speed: rpm or rad/s?), which needs a unit. Strings carry a unit (``"6 mm"``,
``"1900 rpm"``, ``"4876 N*m"``, ``"13 deg"``). Angles are returned in radians, speeds in
rad/s. Every value must be finite: ``inf``, ``nan`` and strings such as ``"inf mm"`` are
refused by name.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gearsim.errors import InputError

if TYPE_CHECKING:  # pint is imported with the registry, on first use (start-up time)
    import pint

__all__ = ["DIMENSIONS", "EXAMPLES", "UNIT_REQUIRED", "plain_numbers_are_si", "registry", "to_si"]



@cache
def registry() -> pint.UnitRegistry:
    """The unit registry, made on first use.

    Parsing pint's definition files takes about 0.15 s; the parsed definitions are kept
    in pint's disk cache under ``$GEARSIM_CACHE/pint-<version>`` (or
    ``~/.cache/gearsim/pint-<version>``), which makes it about 0.03 s. A cache folder
    that cannot be made or read (read-only home, a file half written by a parallel
    process) gives the registry parsed afresh: the cache only saves time.

    Returns
    -------
    pint.UnitRegistry
    """
    import pint

    base = os.environ.get("GEARSIM_CACHE")
    root = Path(base) if base else Path.home() / ".cache" / "gearsim"
    try:
        return pint.UnitRegistry(cache_folder=root / f"pint-{pint.__version__}")
    except Exception:  # noqa: BLE001 - any failure of the cache: parse afresh
        return pint.UnitRegistry()


def __getattr__(name: str) -> Any:
    if name == "ureg":  # the registry under its usual name, made on first access
        return registry()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

# name of a quantity kind -> (SI unit string, pint dimensionality)
DIMENSIONS: dict[str, str] = {
    "length": "m",
    "angle": "rad",
    "speed": "rad/s",
    "torque": "N*m",
    "pressure": "Pa",
    "density": "kg/m**3",
    "time": "s",
    "frequency": "Hz",
    "stiffness": "N/m",
    "damping": "N*s/m",
    "torsional_stiffness": "N*m/rad",
    "mass": "kg",
    "inertia": "kg*m**2",
    "dimensionless": "dimensionless",
    "force": "N",
    "acceleration": "m/s**2",
    "wear_coefficient": "m**2/N",
}

#: A typical value with a unit for each kind, shown in messages.
EXAMPLES: dict[str, str] = {
    "length": "6 mm", "angle": "20 deg", "speed": "1900 rpm", "torque": "4876 N*m",
    "pressure": "206 GPa", "density": "7850 kg/m^3", "time": "0.5 s",
    "frequency": "50 kHz", "stiffness": "1e9 N/m", "damping": "1e3 N*s/m",
    "torsional_stiffness": "1e6 N*m/rad", "mass": "40 kg", "inertia": "1.2 kg*m^2",
    "dimensionless": "0.3", "force": "1 kN", "acceleration": "9.81 m/s^2",
    "wear_coefficient": "1e-17 m^2/N",
}

#: Kinds whose bare numbers are ambiguous (a speed in rpm or rad/s?): a unit is required.
UNIT_REQUIRED = frozenset({"speed"})

_PLAIN_SI: ContextVar[bool] = ContextVar("gearsim_plain_numbers_are_si", default=False)


@contextmanager
def plain_numbers_are_si() -> Iterator[None]:
    """Accept bare numbers as SI for every kind, also those in :data:`UNIT_REQUIRED`.

    For documents that declare their units, such as the effective configuration
    written into results files (SI throughout).

    Yields
    ------
    None
        Inside the ``with`` block a bare speed is read as rad/s.
    """
    token = _PLAIN_SI.set(True)
    try:
        yield
    finally:
        _PLAIN_SI.reset(token)


@cache
def _si_unit(kind: str) -> pint.Unit:
    return registry().Unit(DIMENSIONS[kind])


def _finite(si: float, value: Any, kind: str, parameter: str) -> float:
    if not math.isfinite(si):
        unit = DIMENSIONS[kind]
        where = "" if unit == "dimensionless" else f" in {unit}"
        raise InputError(parameter, value, f"must be a finite number{where}")
    return si


def _bare(number: float, value: Any, kind: str, parameter: str) -> float:
    _finite(number, value, kind, parameter)
    if kind in UNIT_REQUIRED and not _PLAIN_SI.get():
        raise InputError(parameter, value, f'give a unit, e.g. "{EXAMPLES[kind]}" (a bare '
                         f"number would be read as {DIMENSIONS[kind]})")
    return number


def to_si(value: Any, kind: str, parameter: str) -> float:
    """Convert ``value`` (number or string with unit) to a finite float in SI units.

    Parameters
    ----------
    value
        A number (taken as SI) or a string such as ``"6 mm"``. A speed needs a unit
        (:data:`UNIT_REQUIRED`).
    kind
        Quantity kind, a key of :data:`DIMENSIONS`.
    parameter
        Name used in the error message.

    Returns
    -------
    float
        The value in SI units (angles in rad, speeds in rad/s; a speed in a frequency
        unit without an angle, such as Hz or 1/min, is read as revolutions per unit
        time).

    Raises
    ------
    InputError
        If the value is not finite (``inf``, ``nan``, ``"inf mm"``), the string cannot
        be parsed, its unit is of the wrong dimension, or a bare number is given where
        a unit is required.

    Examples
    --------
    >>> to_si("6 mm", "length", "normal_module")
    0.006
    >>> round(to_si("1900 rpm", "speed", "speed"), 4)  # 1900 x 2 pi / 60
    198.9675
    >>> round(to_si("30 Hz", "speed", "speed"), 4)  # a shaft at 30 rev/s: 30 x 2 pi
    188.4956
    >>> round(to_si("13 deg", "angle", "helix_angle"), 6)
    0.226893
    >>> to_si("inf mm", "length", "face_width")
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: face_width = inf mm: must be a finite number in m
    """
    if isinstance(value, bool):
        raise InputError(parameter, value, f"must be a number or a quantity in {DIMENSIONS[kind]}")
    if isinstance(value, (int, float)):
        try:
            number = float(value)
        except OverflowError:  # an int too large for a float
            number = math.inf
        return _bare(number, value, kind, parameter)
    if not isinstance(value, str):
        raise InputError(parameter, value, f"must be a number or a quantity in {DIMENSIONS[kind]}")
    ureg = registry()
    import pint  # imported by registry()

    try:
        q = ureg.Quantity(value)
    except Exception:  # pint raises several parse error types
        raise InputError(parameter, value, "is not a quantity pint can parse") from None
    if not isinstance(q, pint.Quantity):  # a bare number in a string (older pint)
        return _bare(float(q), value, kind, parameter)
    try:
        magnitude = float(q.magnitude)
    except (TypeError, ValueError):
        raise InputError(parameter, value, "must be one number with a unit") from None
    if q.units == registry().dimensionless:  # "0.3", "nan", "inf": a number in a string
        # (pint calls "80 %" unitless too: it falls through to the conversion below)
        _finite(magnitude, value, kind, parameter)
        if kind == "angle":  # radians are dimensionless in pint
            return magnitude
        if kind == "dimensionless" or kind in UNIT_REQUIRED:
            return _bare(magnitude, value, kind, parameter)
        raise InputError(parameter, value, f'give a unit, e.g. "{EXAMPLES[kind]}" (or a '
                         f"number without quotes, read as {DIMENSIONS[kind]})")
    _finite(magnitude, value, kind, parameter)
    target = _si_unit(kind)
    if not any(c.isdigit() for c in value) and q.dimensionality == target.dimensionality:
        raise InputError(parameter, value, f'is a unit without a number; write e.g. '
                         f'"{EXAMPLES[kind]}"')
    if kind == "dimensionless" and "radian" in q.to_base_units().units._units:
        # pint counts angles as dimensionless ("90 deg" would read 1.5708)
        raise InputError(parameter, value, "is an angle; give a plain number (or a "
                         'percentage, "80 %")')
    if kind == "speed" and q.dimensionality == target.dimensionality \
            and "radian" not in q.to_base_units().units._units:
        # a frequency without an angle (Hz, kHz, 1/s, 1/min) is a shaft's rotation
        # frequency in revolutions per unit time, as shaft speeds are quoted in Hz:
        # pint reads Hz as 1/s = rad/s (the radian is dimensionless), 2 pi too small
        q = q * registry().Quantity(1.0, "turn")
    try:
        si = float(q.to(target).magnitude)
    except pint.DimensionalityError:
        if not any(c.isdigit() for c in value):  # a unit alone, e.g. "a" (year)
            raise InputError(parameter, value, f"is not a {kind}: pint reads {value.strip()!r} "
                             f"as 1 {q.units}, a {q.dimensionality}; expected a {kind} in "
                             f'{target:~}, e.g. "{EXAMPLES[kind]}"') from None
        raise InputError(
            parameter, value, f"has units of {q.dimensionality} ({q.units}), expected a {kind} "
            f'in {target:~}, e.g. "{EXAMPLES[kind]}"'
        ) from None
    return _finite(si, value, kind, parameter)
