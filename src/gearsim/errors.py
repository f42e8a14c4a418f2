"""Error types of gearsim.

Every refusal of bad input raises :class:`InputError`, whose message is one line that
names the parameter, the value given and the limit it broke. The command-line interface
prints that line and exits with status 2 instead of showing a traceback.
"""

from __future__ import annotations

from typing import Any

__all__ = ["InputError", "ModelRangeWarning", "SimulationError", "require"]


class InputError(ValueError):
    """Bad input: a parameter value outside its valid range or of the wrong kind.

    Parameters
    ----------
    parameter
        Dotted name of the parameter as the user wrote it, e.g. ``gears[0].teeth``.
    value
        The offending value (printed with ``repr`` unless it is a string).
    limit
        What the value must satisfy, e.g. ``"must be >= 7"``.
    """

    def __init__(self, parameter: str, value: Any, limit: str) -> None:
        self.parameter = parameter
        self.value = value
        self.limit = limit
        shown = value if isinstance(value, str) else repr(value)
        super().__init__(f"{parameter} = {shown}: {limit}")


class ModelRangeWarning(UserWarning):
    """A model used outside the range it was fitted or validated on (the result is kept).

    The message names the model, the gear or item, the quantity, its value and the range,
    e.g. ``Sainsot foundation of gear pinion: theta_f = 0.159 rad outside the fitted
    range [0.01, 0.12] rad``. The command-line interface prints it as one line
    ``gearsim: warning: ...`` on standard error.
    """


class SimulationError(RuntimeError):
    """A computation that started with valid input but could not finish (e.g. diverged)."""


def require(ok: bool, parameter: str, value: Any, limit: str) -> None:
    """Raise :class:`InputError` unless ``ok``.

    Parameters
    ----------
    ok
        The condition that must hold.
    parameter
        Dotted name of the parameter.
    value
        The value given.
    limit
        What the value must satisfy.

    Raises
    ------
    InputError
        If ``ok`` is false.

    Examples
    --------
    >>> require(True, "gear.teeth", 39, "must be >= 7")
    >>> require(False, "gear.teeth", 5, "must be >= 7")
    Traceback (most recent call last):
    ...
    gearsim.errors.InputError: gear.teeth = 5: must be >= 7
    """
    if not ok:
        raise InputError(parameter, value, limit)
