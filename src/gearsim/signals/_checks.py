"""Input validation shared by the signal-analysis modules.

Every check raises :class:`gearsim.errors.InputError` with a one-line message that names
the parameter, the value given and the limit it broke.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from gearsim.errors import InputError

__all__ = [
    "as_signal",
    "check_positive",
    "check_fs",
    "check_below_nyquist",
    "check_resolution",
]


def as_signal(x: object, *, name: str = "signal", min_length: int = 2) -> np.ndarray:
    """Return ``x`` as a 1-D float64 array after checking shape, length and finiteness."""
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


def check_fs(fs: float) -> float:
    """Return the sampling rate ``fs`` (Hz) after checking it is finite and > 0."""
    return check_positive("fs", fs)


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
    ``bins_needed / df_line`` seconds.
    """
    duration = n_samples / fs
    for label, spacing in spacings.items():
        need = bins_needed / spacing
        if duration < need:
            raise InputError(
                "record duration",
                f"{duration:.4g} s",
                f"must be >= {need:.4g} s to separate sidebands spaced {spacing:.4g} Hz "
                f"({label}) with a {window} window ({bins_needed:g} bins per spacing)",
            )
