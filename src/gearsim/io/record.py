"""What a read returns: :class:`Record` (all channels), :class:`MeasuredSignal` (one),
:class:`DroppedSamples` and the combined refusal :class:`ReadProblems`.

Made by the readers of :mod:`gearsim.io.measured`, which re-exports them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import InputError

__all__ = ["MAX_SAMPLING_RATE", "MIN_SAMPLING_RATE", "DroppedSamples", "MeasuredSignal",
           "ReadProblems", "Record", "raise_all"]

#: Sampling rates a record can have [Hz]. Vibration, speed and acoustic-emission
#: acquisition runs from slow trend logging (a sample every few minutes, ~1e-2 Hz) to AE
#: digitisers of tens of MHz: a rate below 1e-3 Hz or above 1 GHz, stored in a file or
#: given, can only be a mistake (a unit or an exponent wrong), and is refused.
MIN_SAMPLING_RATE = 1e-3
MAX_SAMPLING_RATE = 1e9


class ReadProblems(InputError):
    """Several problems of one read, reported together in one line.

    The message is the problems' ``"parameter = value: limit"`` joined by ``"; "``.
    ``parameter`` and ``limit`` join those of the problems the same way and ``value``
    is the tuple of their values.

    Parameters
    ----------
    problems : sequence of InputError
        The problems, in the order found (at least two).
    """

    def __init__(self, problems: Sequence[InputError]) -> None:
        self.problems = tuple(problems)
        self.parameter = "; ".join(p.parameter for p in self.problems)
        self.value = tuple(p.value for p in self.problems)
        self.limit = "; ".join(p.limit for p in self.problems)
        ValueError.__init__(self, "; ".join(str(p) for p in self.problems))


def raise_all(problems: list[InputError]) -> None:
    """Raise the problems found: none, one as itself, several as one :class:`ReadProblems`.

    Parameters
    ----------
    problems : list of InputError
        Problems in the order found.

    Raises
    ------
    InputError
        The single problem, or :class:`ReadProblems` for several.
    """
    if len(problems) == 1:
        raise problems[0]
    if problems:
        raise ReadProblems(problems)


@dataclass(frozen=True)
class DroppedSamples:
    """Samples dropped from one channel by ``drop_nonfinite=True``.

    Parameters
    ----------
    count : int
        Samples removed from the channel (leading plus trailing).
    nonfinite : int
        How many of them were non-finite in this channel (the others were cut to keep
        the channel aligned with channels of the same time base).
    first : int
        File index of the first removed sample.
    last : int
        File index of the last removed sample.
    kept : tuple of int
        File indices ``(start, stop)`` of the samples kept: sample ``i`` of the result
        is sample ``start + i`` of the file (time origin shifted by ``start / fs``).
    """

    count: int
    nonfinite: int
    first: int
    last: int
    kept: tuple[int, int]

    def to_dict(self) -> dict:
        """Plain-type form for JSON reports.

        Returns
        -------
        dict
            The fields, ``kept`` as a list.
        """
        return {"count": self.count, "nonfinite": self.nonfinite, "first": self.first,
                "last": self.last, "kept": list(self.kept)}


@dataclass(frozen=True)
class MeasuredSignal:
    """One channel read from a file (returned by :func:`read_signal`).

    Parameters
    ----------
    data : ndarray
        Samples (float64, units of the file).
    fs : float
        Sampling rate [Hz].
    channel : str
        Channel name as used to select it.
    path : str
        File path.
    fmt : str
        Format key of :data:`FORMATS`.
    fs_source : str
        ``"file"`` or ``"user"``.
    channels : tuple of str, optional
        All channel names the file accepts (aliases included).
    units : str or None, optional
        Units stored with the channel, if any.
    metadata : dict, optional
        Metadata of the file (CSV comment lines ``# key = value``).
    dropped : DroppedSamples or None, optional
        Non-finite samples dropped (``drop_nonfinite=True``), None if none were.
    compression : str or None, optional
        Compression the file was read through (``"gzip"``, ``"bz2"``, ``"xz"``,
        ``"zip"``), None if plain.
    """

    data: np.ndarray
    fs: float
    channel: str
    path: str
    fmt: str
    fs_source: str
    channels: tuple[str, ...] = field(default=())
    units: str | None = None
    metadata: dict = field(default_factory=dict)
    dropped: DroppedSamples | None = None
    compression: str | None = None

    @property
    def duration(self) -> float:
        """Record length, samples / fs [s]."""
        return self.data.size / self.fs


@dataclass(frozen=True)
class Record:
    """The channels read from one file on one sampling rate (returned by :func:`read_record`).

    Parameters
    ----------
    data : dict
        Channel name -> samples (float64 ndarray, units of the file), in the order
        asked for (file order by default). Channels may differ in length (TDMS, UFF).
    fs : float or None
        Sampling rate of every channel [Hz]; None when neither the file nor the user
        gives one.
    path : str
        File path.
    fmt : str
        Format key of :data:`FORMATS` (of the inner record when compressed).
    fs_source : str or None
        ``"file"`` or ``"user"``; None without a rate.
    units : dict
        Channel name -> units stored with it, or None.
    metadata : dict, optional
        Metadata of the file (CSV comment lines ``# key = value``: numbers as float,
        else the text; e.g. ``{"fs": "25.6 kHz", "rpm": 1480.0, "units": "m/s^2"}``).
    available : tuple of str, optional
        Every channel name the file accepts (aliases included).
    compression : str or None, optional
        ``"gzip"``, ``"bz2"``, ``"xz"`` or ``"zip"`` when read through one, else None.
    dropped : dict, optional
        Channel name -> :class:`DroppedSamples`, for the channels that lost samples
        (``drop_nonfinite=True``); empty otherwise.
    """

    data: dict[str, np.ndarray]
    fs: float | None
    path: str
    fmt: str
    fs_source: str | None
    units: dict[str, str | None]
    metadata: dict = field(default_factory=dict)
    available: tuple[str, ...] = field(default=())
    compression: str | None = None
    dropped: dict[str, DroppedSamples] = field(default_factory=dict)

    @property
    def channels(self) -> tuple[str, ...]:
        """Names of the channels read, in order."""
        return tuple(self.data)

    def signal(self, channel: str) -> MeasuredSignal:
        """One channel of the record as a :class:`MeasuredSignal`.

        Parameters
        ----------
        channel : str
            One of :attr:`channels`.

        Returns
        -------
        MeasuredSignal

        Raises
        ------
        InputError
            If the channel was not read, or the record has no sampling rate.
        """
        if channel not in self.data:
            raise InputError("channel", channel, f"not read; the record holds {list(self.data)}")
        if self.fs is None:
            raise InputError("fs", None, f"must be given: {self.path} stores no sampling rate")
        return MeasuredSignal(
            data=self.data[channel], fs=self.fs, channel=channel, path=self.path,
            fmt=self.fmt, fs_source=self.fs_source, channels=self.available,
            units=self.units.get(channel), metadata=self.metadata,
            dropped=self.dropped.get(channel), compression=self.compression,
        )

    def to_dict(self) -> dict:
        """Plain-type description (no samples) for JSON reports.

        Returns
        -------
        dict
            File, format, compression, fs and its source, per channel the sample count,
            units and dropped samples, and the metadata.
        """
        return {
            "file": self.path, "format": self.fmt, "compression": self.compression,
            "fs_hz": self.fs, "fs_source": self.fs_source, "metadata": dict(self.metadata),
            "channels": {c: {"samples": int(v.size), "units": self.units.get(c),
                             "dropped": (self.dropped[c].to_dict() if c in self.dropped
                                         else None)}
                         for c, v in self.data.items()},
        }
