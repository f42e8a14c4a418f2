"""Error types of gearsim.

Every refusal of bad input raises :class:`InputError`, whose message is one line that
names the parameter, the value given and the limit it broke. The command-line interface
prints that line and exits with status 2 instead of showing a traceback.
"""

from __future__ import annotations

import functools
import os
import sys
import warnings
from typing import Any

__all__ = ["FORCE_ENV", "InputError", "ModelRangeWarning", "SimulationError",
           "cost_bounds_lifted", "require", "warn_model_range"]

#: Files whose frames :func:`warn_model_range` skips to reach the caller's line: the
#: package's and functools' (``cached_property``).
_INSIDE = (os.path.dirname(__file__), functools.__file__)


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


def warn_model_range(message: str) -> None:
    """Warn :class:`ModelRangeWarning` at the caller's line: the first frame outside
    gearsim and functools (the cached properties computing a model), not inside them.

    Parameters
    ----------
    message : str
        One line: the model, the item, the quantity, its value and the range.
    """
    level, frame = 1, sys._getframe(0)
    while frame is not None and frame.f_code.co_filename.startswith(_INSIDE):
        level, frame = level + 1, frame.f_back
    warnings.warn(message, ModelRangeWarning, stacklevel=level)


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


#: Environment variable that lifts the cost bounds of the runs (like ``--force``) when set
#: to 1, yes, true or on.
FORCE_ENV = "GEARSIM_FORCE"


def cost_bounds_lifted(force: bool | None = None) -> bool:
    """Whether the cost bounds of a run are lifted (a simulation's steps and memory,
    :func:`gearsim.dynamics.simulate.check_cost`; an FE check's unknowns,
    :func:`gearsim.fem.check.fe_check`).

    Parameters
    ----------
    force : bool, optional
        An explicit choice (``--force``); default: the environment variable
        :data:`FORCE_ENV` set to 1, yes, true or on.

    Returns
    -------
    bool
    """
    if force is not None:
        return bool(force)
    return os.environ.get(FORCE_ENV, "").strip().lower() in ("1", "yes", "true", "on")
