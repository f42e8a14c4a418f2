"""Input validation shared by the signal-analysis modules.

Every check raises :class:`gearsim.errors.InputError` with a one-line message that names
the parameter, the value given and the limit it broke.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from gearsim.errors import InputError
from gearsim.io.record import MAX_SAMPLING_RATE, MIN_SAMPLING_RATE

#: Supported windows and the half width of their main lobe in bins (first zero of the
#: window transform): a line is resolved from its neighbour when they are at least
#: twice this many bins apart.
WINDOWS: dict[str, int] = {"boxcar": 1, "hann": 2, "flattop": 5}

__all__ = [
    "MAX_MAGNITUDE",
    "as_signal",
    "check_positive",
    "check_probability",
    "check_fs",
    "check_below_nyquist",
    "check_resolution",
    "check_int",
    "check_teeth",
    "check_speed_source",
]


#: Largest peak magnitude of a record: the indicators take moments up to the 8th (M8A),
#: and ``max|x|^8`` times the record length must stay below the float range (1e308),
#: else they overflow to null. Any record in physical units lies far inside; rescale
#: (change the unit) otherwise.
MAX_MAGNITUDE = 1e30


def as_signal(x: object, *, name: str = "signal", min_length: int = 2) -> np.ndarray:
    """Return ``x`` as a 1-D float64 array after checking shape, length and values.

    The samples must be finite and of a peak magnitude <= :data:`MAX_MAGNITUDE` (the
    moments of the indicators would overflow otherwise).
    """
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(
            name, type(x).__name__, f"must be a 1-D array of numbers ({exc})"
        ) from None
    if arr.ndim != 1:
        raise InputError(f"{name}.shape", arr.shape, "must be one-dimensional")
    if arr.size < min_length:
        raise InputError(f"{name}.length", arr.size, f"must be >= {min_length} samples")
    finite = np.isfinite(arr)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        kind = "NaN" if math.isnan(arr[bad]) else "infinite"
        raise InputError(
            f"{name}[{bad}]",
            float(arr[bad]),
            f"must be finite ({int((~finite).sum())} {kind}/non-finite samples found)",
        )
    mag = np.abs(arr)
    i = int(np.argmax(mag))
    top = float(mag[i])
    if top > MAX_MAGNITUDE:
        raise InputError(
            f"{name}[{i}]", float(arr[i]),
            f"the peak magnitude must be <= {MAX_MAGNITUDE:g}: the 4th- to 8th-order moments "
            "of the indicators (kurtosis, FM4, NA4, M8A) would overflow; rescale the record "
            "(another unit)",
        )
    return arr


def check_positive(name: str, value: float) -> float:
    """Return ``value`` as float after checking that it is finite and > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, "must be a positive number") from None
    if not (math.isfinite(v) and v > 0.0):
        raise InputError(name, value, "must be a finite number > 0")
    return v


def check_probability(name: str, value: float) -> float:
    """Return ``value`` as float after checking that it lies in (0, 1)."""
    v = check_positive(name, value)
    if v >= 1.0:
        raise InputError(name, v, "must lie in (0, 1)")
    return v


def check_fs(fs: float) -> float:
    """Return the sampling rate ``fs`` (Hz) after checking it is a number in
    [:data:`~gearsim.io.record.MIN_SAMPLING_RATE`,
    :data:`~gearsim.io.record.MAX_SAMPLING_RATE`] (outside: a unit or exponent mistake)."""
    v = check_positive("fs", fs)
    if not MIN_SAMPLING_RATE <= v <= MAX_SAMPLING_RATE:
        raise InputError("fs", fs, f"must be in [{MIN_SAMPLING_RATE:g}, "
                         f"{MAX_SAMPLING_RATE:g}] Hz")
    return v


def check_below_nyquist(fs: float, f_max: float, what: str) -> None:
    """Refuse a sampling rate whose Nyquist frequency ``fs/2`` is not above ``f_max`` (Hz)."""
    if not f_max < 0.5 * fs:
        raise InputError(
            "fs",
            f"{fs:g} Hz",
            f"must exceed 2 x {f_max:g} Hz = {2 * f_max:g} Hz to cover {what} below Nyquist",
        )


def check_resolution(
    n_samples: int, fs: float, spacings: Mapping[str, float], *, bins_needed: float, window: str
) -> None:
    """Refuse a record too short to separate spectral lines spaced by ``spacings`` (Hz).

    A line spacing ``df_line`` is resolved when it spans at least ``bins_needed`` frequency
    bins of width ``fs / n_samples``, i.e. when the record lasts at least
    ``bins_needed / df_line`` seconds. The refusal names the smallest spacing, whose
    length is the one that suffices for all (not the first unmet one: a record lengthened
    to that was refused again with a longer need).
    """
    duration = n_samples / fs
    label, spacing = min(spacings.items(), key=lambda kv: kv[1])
    need = bins_needed / spacing
    if duration < need:
        raise InputError(
            "record duration",
            f"{duration:.4g} s",
            f"must be >= {need:.4g} s to separate sidebands spaced {spacing:.4g} Hz "
            f"({label}) with a {window} window ({bins_needed:g} bins per spacing)",
        )


def check_int(name: str, value: object, *, minimum: int, allow: tuple[int, ...] = (),
              maximum: int | None = None) -> int:
    """Return ``value`` as int after checking that it is a whole number >= ``minimum``
    (and <= ``maximum`` when given).

    Values listed in ``allow`` (e.g. ``-1`` for "no limit") are accepted as well. Booleans
    are refused (``True`` is not a count).
    """
    ok = not isinstance(value, bool)
    try:
        v = int(value)  # type: ignore[call-overload]
        ok = ok and v == value
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or (v < minimum and v not in allow):
        extra = "".join(f" or {a}" for a in allow)
        if maximum is not None:
            raise InputError(name, value, f"must be an integer in [{minimum}, {maximum}]{extra}")
        raise InputError(name, value, f"must be an integer >= {minimum}{extra}")
    if maximum is not None and v > maximum and v not in allow:
        raise InputError(name, value, f"must be an integer in [{minimum}, {maximum}]")
    return v


#: Most teeth of a gear in a record's train: the bound of the gears gearsim models
#: (``gearsim.geometry.gear.MAX_TEETH``; the largest ring and bull gears in service have
#: a few hundred). More can only be a mistake (a speed or a ratio typed as teeth).
MAX_TEETH = 1000


def check_teeth(teeth: object, *, name: str = "teeth") -> tuple[int, ...]:
    """Return the tooth counts as a tuple of ints after checking each is in [1, MAX_TEETH].

    ``teeth`` is a sequence (reference gear first, see :mod:`gearsim.signals.analysis`);
    an empty sequence is refused.
    """
    try:
        items = list(teeth)  # type: ignore[call-overload]
    except TypeError:
        raise InputError(name, teeth, "must be a list of tooth counts") from None
    if not items:
        raise InputError(name, items, "must list at least the reference gear's teeth")
    return tuple(check_int(f"{name}[{j}]", z, minimum=1, maximum=MAX_TEETH)
                 for j, z in enumerate(items))


def check_speed_source(
    speed: float | None,
    tacho: object | None,
    *,
    names: tuple[str, str] = ("shaft_frequency", "tacho"),
    unit: str = "Hz",
) -> float | None:
    """Check the rule "give exactly one of a known shaft speed or a tacho".

    Parameters
    ----------
    speed : float or None
        Known speed of the reference shaft [``unit``].
    tacho : object or None
        Tacho channel (signal, pulse times or channel name); only its presence counts.
    names : tuple of str
        Names of the two parameters as the caller spells them (e.g. the CLI flags).
    unit : str
        Unit of ``speed`` for the message (``"Hz"`` in the API, ``"rpm"`` in the CLI).

    Returns
    -------
    float or None
        ``speed`` as a float (finite, > 0), or None when the tacho is given.
    """
    if (speed is None) == (tacho is None):
        raise InputError(
            "/".join(names), "both" if tacho is not None else "neither",
            "give exactly one of a known shaft speed or a tacho",
        )
    if speed is None:
        return None
    try:
        v = float(speed)
    except (TypeError, ValueError):
        raise InputError(names[0], speed, f"must be a finite speed > 0 {unit}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise InputError(names[0], speed, f"must be a finite speed > 0 {unit}")
    return v
