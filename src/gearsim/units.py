"""Units at the edges: parse user values with pint and return SI floats.

Plain numbers are taken as SI. Strings carry a unit (``"6 mm"``, ``"1900 rpm"``,
``"4876 N*m"``, ``"13 deg"``). Angles are returned in radians, speeds in rad/s.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import pint

from gearsim.errors import InputError

__all__ = ["DIMENSIONS", "to_si", "ureg"]

ureg = pint.UnitRegistry()

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
}


@cache
def _si_unit(kind: str) -> pint.Unit:
    return ureg.Unit(DIMENSIONS[kind])


def to_si(value: Any, kind: str, parameter: str) -> float:
    """Convert ``value`` (number or string with unit) to a float in SI units.

    Parameters
    ----------
    value
        A number (taken as SI) or a string such as ``"6 mm"``.
    kind
        Quantity kind, a key of :data:`DIMENSIONS`.
    parameter
        Name used in the error message.

    Returns
    -------
    float
        The value in SI units (angles in rad, speeds in rad/s).

    Raises
    ------
    InputError
        If the string cannot be parsed or its unit is of the wrong dimension.

    Examples
    --------
    >>> to_si("6 mm", "length", "normal_module")
    0.006
    >>> round(to_si("1900 rpm", "speed", "speed"), 4)  # 1900 x 2 pi / 60
    198.9675
    >>> round(to_si("13 deg", "angle", "helix_angle"), 6)
    0.226893
    """
    if isinstance(value, bool):
        raise InputError(parameter, value, f"must be a number or a quantity in {DIMENSIONS[kind]}")
    if isinstance(value, (int, float)):
        return float(value)
    if not isinstance(value, str):
        raise InputError(parameter, value, f"must be a number or a quantity in {DIMENSIONS[kind]}")
    try:
        q = ureg.Quantity(value)
    except Exception:  # pint raises several parse error types
        raise InputError(parameter, value, "is not a quantity pint can parse") from None
    if not isinstance(q, pint.Quantity):  # a bare number in a string
        return float(q)
    target = _si_unit(kind)
    try:
        return float(q.to(target).magnitude)
    except pint.DimensionalityError:
        raise InputError(
            parameter, value, f"has units of {q.dimensionality}, expected a {kind} in {target:~}"
        ) from None
