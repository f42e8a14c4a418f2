"""Readers for measured (and simulated) vibration records.

Formats, chosen by file extension unless ``fmt`` is given:

=========  ==============  ==========================================================
format     extensions      channels / sampling rate
=========  ==============  ==========================================================
csv        .csv, .txt      columns (header row names them, else ``"0", "1", ...``);
                           fs from a time column (``time``, ``t``, ``time_s``) or a
                           comment line ``# fs = 50000``
wav        .wav            ``"0", "1", ...``; fs from the header; integer PCM scaled
                           to full scale 1.0
mat        .mat            numeric vectors (``"name"``) and matrix columns
                           (``"name:j"``); fs from a scalar ``fs``/``Fs``/``FS``/
                           ``sampling_rate`` or a time vector ``t``/``time``
tdms       .tdms           ``"group/channel"`` or ``"channel"`` if unique; fs from the
                           ``wf_increment`` property
uff        .uff, .unv      type-58 data sets by ``id1`` (or index ``"0", "1", ...``);
                           fs from ``abscissa_inc``
netcdf     .nc, .h5, .nc4  data variables along ``time`` (``"name"``; with more
                           dimensions ``"name[gear=G1,axis=x]"``); fs from attribute
                           ``fs`` or the ``time`` coordinate (s), e.g. gearsim
                           simulator output
=========  ==============  ==========================================================

A sampling rate given by the user is used when the file holds none; when both exist they
must agree within :data:`FS_MATCH_RTOL`. Every problem (missing or unreadable file,
truncated data, missing channel, non-uniform time axis, non-finite samples) raises
:class:`gearsim.errors.InputError` with one line naming the file, the value and the limit.
"""

from __future__ import annotations

import itertools
import logging
import math
import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gearsim.errors import InputError

__all__ = [
    "FORMATS",
    "FS_MATCH_RTOL",
    "TIME_JITTER_RTOL",
    "MeasuredSignal",
    "read_signal",
    "list_channels",
]

#: Relative agreement required between a user-given fs and the file's. UFF stores the
#: abscissa increment with 6 significant digits (``%13.5e``), i.e. fs to ~5e-6 relative;
#: 1e-4 accepts that rounding and still refuses a wrong rate (any real mismatch is >= 1e-3).
FS_MATCH_RTOL = 1e-4

#: A time axis is uniform when every step is within this fraction of the mean step. Text
#: files print times with few decimals (1 us at 48 kHz is a 5 % step error), while a
#: dropped sample is a 100 % error.
TIME_JITTER_RTOL = 0.1

FORMATS: dict[str, tuple[str, ...]] = {
    "csv": (".csv", ".txt"),
    "wav": (".wav",),
    "mat": (".mat",),
    "tdms": (".tdms",),
    "uff": (".uff", ".unv"),
    "netcdf": (".nc", ".nc4", ".h5", ".netcdf"),
}

_TIME_NAMES = ("time", "t", "time_s", "times", "time [s]", "time(s)")
_FS_NAMES = ("fs", "Fs", "FS", "sampling_rate", "samplerate", "sample_rate")


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
        All channels in the file.
    units : str or None, optional
        Units stored with the channel, if any.
    """

    data: np.ndarray
    fs: float
    channel: str
    path: str
    fmt: str
    fs_source: str
    channels: tuple[str, ...] = field(default=())
    units: str | None = None

    @property
    def duration(self) -> float:
        """Record length, samples / fs [s]."""
        return self.data.size / self.fs


@dataclass
class _Raw:
    channels: dict[str, np.ndarray]
    fs: float | None
    units: dict[str, str] = field(default_factory=dict)
    fs_per_channel: dict[str, float] = field(default_factory=dict)


def _fail(path: Path, fmt: str, reason: object) -> InputError:
    text = str(reason).strip().splitlines()[0] if str(reason).strip() else type(reason).__name__
    return InputError("file", str(path), f"cannot be read as {fmt.upper()}: {text}")


def _fs_from_time(path: Path, t: np.ndarray) -> float:
    t = np.asarray(t, dtype=np.float64).ravel()
    if t.size < 2 or not np.all(np.isfinite(t)):
        raise InputError(f"{path.name}: time", f"{t.size} values",
                         "must hold >= 2 finite times to give the sampling rate")
    dt = np.diff(t)
    mean = (t[-1] - t[0]) / (t.size - 1)
    if not mean > 0:
        raise InputError(f"{path.name}: time", f"[{t[0]:g}, {t[-1]:g}] s", "must increase")
    worst = float(np.max(np.abs(dt - mean)) / mean)
    if worst > TIME_JITTER_RTOL:
        i = int(np.argmax(np.abs(dt - mean)))
        raise InputError(
            f"{path.name}: time step {i}", f"{dt[i]:g} s",
            f"must be within {TIME_JITTER_RTOL:g} x mean step {mean:g} s (uniform sampling)",
        )
    return 1.0 / mean


def _read_csv(path: Path) -> _Raw:
    import pandas as pd

    fs = None
    header = None
    with open(path, encoding="utf-8", errors="replace") as fh:
        lines = enumerate(fh, start=1)
        for _, line in lines:
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                m = re.match(r"#\s*(fs|sampling_rate|sample_rate)\s*[:=]\s*([0-9.eE+-]+)", s)
                if m:
                    fs = float(m.group(2))
                continue
            first = [c.strip() for c in s.split(",")]
            try:
                [float(c) for c in first]
                header = None
            except ValueError:
                header = 0
            break
        # a blank line between data rows is a missing sample (pandas would skip it)
        blank = None
        for number, line in lines:
            s = line.strip()
            if not s:
                blank = blank or number
            elif not s.startswith("#") and blank is not None:
                raise InputError(f"{path.name}: line {blank}", "empty",
                                 "every row must hold a finite number (a blank line inside "
                                 "the data is a missing sample)")
    try:
        df = pd.read_csv(path, comment="#", header=header, skip_blank_lines=True)
    except Exception as exc:  # pandas raises many types for malformed text
        raise _fail(path, "csv", exc) from None
    if df.shape[0] < 2 or df.shape[1] < 1:
        raise _fail(path, "csv", f"holds {df.shape[0]} rows x {df.shape[1]} columns")
    cols = [str(c).strip() for c in df.columns]
    df.columns = cols
    channels: dict[str, np.ndarray] = {}
    for c in cols:
        try:
            v = pd.to_numeric(df[c], errors="raise").to_numpy(dtype=np.float64)
        except (ValueError, TypeError) as exc:
            raise _fail(path, "csv", f"column {c!r} is not numeric ({exc})") from None
        bad = ~np.isfinite(v)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            if np.isnan(v[row]):
                shown, why = "missing/NaN", "truncated or damaged file?"
            else:
                shown, why = f"{v[row]:g}", "an overflowed or saturated value?"
            raise InputError(
                f"{path.name}: column {c!r} data row {row + 1}", shown,
                f"every row must hold a finite number ({int(bad.sum())} non-finite in this "
                f"column; {why})",
            )
        channels[c] = v
    time_col = next((c for c in cols if c.lower() in _TIME_NAMES), None)
    if time_col is not None:
        fs_t = _fs_from_time(path, channels.pop(time_col))
        if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
            raise InputError(f"{path.name}: fs comment", fs,
                             f"disagrees with the time column ({fs_t:g} Hz)")
        fs = fs_t
    return _Raw(channels=channels, fs=fs)


def _read_wav(path: Path) -> _Raw:
    from scipy.io import wavfile

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", wavfile.WavFileWarning)
            rate, data = wavfile.read(path)
    except Exception as exc:
        raise _fail(path, "wav", exc) from None
    if np.issubdtype(data.dtype, np.integer):
        info = np.iinfo(data.dtype)
        if data.dtype == np.uint8:  # 8-bit PCM is offset binary
            data = (data.astype(np.float64) - 128.0) / 128.0
        else:
            data = data.astype(np.float64) / float(-info.min)
    else:
        data = data.astype(np.float64)
    data = data.reshape(data.shape[0], -1)
    return _Raw(channels={str(j): data[:, j] for j in range(data.shape[1])}, fs=float(rate))


def _read_mat(path: Path) -> _Raw:
    from scipy.io import loadmat

    try:
        content = loadmat(path, squeeze_me=False)
    except NotImplementedError:
        return _read_mat73(path)
    except Exception as exc:
        raise _fail(path, "mat", exc) from None
    return _mat_channels(path, {k: v for k, v in content.items() if not k.startswith("__")})


def _read_mat73(path: Path) -> _Raw:
    import h5py

    try:
        with h5py.File(path, "r") as f:
            content = {k: np.asarray(f[k]).T for k in f if isinstance(f[k], h5py.Dataset)}
    except Exception as exc:
        raise _fail(path, "mat", exc) from None
    return _mat_channels(path, content)


def _mat_channels(path: Path, content: dict) -> _Raw:
    fs = None
    time = None
    channels: dict[str, np.ndarray] = {}
    for name, val in content.items():
        arr = np.asarray(val)
        if not np.issubdtype(arr.dtype, np.number):
            continue
        if arr.size == 1 and name in _FS_NAMES:
            fs = float(arr.ravel()[0])
            continue
        if arr.ndim > 2 or arr.size < 2:
            continue
        if arr.ndim == 2 and min(arr.shape) == 1:
            arr = arr.ravel()
        if name.lower() in _TIME_NAMES and arr.ndim == 1:
            time = arr
            continue
        if arr.ndim == 1:
            channels[name] = arr.astype(np.float64)
        else:
            cols = arr if arr.shape[0] >= arr.shape[1] else arr.T
            for j in range(cols.shape[1]):
                channels[f"{name}:{j}"] = cols[:, j].astype(np.float64)
    if time is not None:
        fs_t = _fs_from_time(path, time)
        if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
            raise InputError(
                f"{path.name}: fs", fs, f"disagrees with the time vector ({fs_t:g} Hz)"
            )
        fs = fs_t
    return _Raw(channels=channels, fs=fs)


class _LogCatcher(logging.Handler):
    def __init__(self) -> None:
        super().__init__(level=logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _read_tdms(path: Path) -> _Raw:
    from nptdms import TdmsFile

    catcher = _LogCatcher()
    logger = logging.getLogger("nptdms")
    logger.addHandler(catcher)
    try:
        f = TdmsFile.read(path)
        groups = [(g.name, [(c.name, c[:], dict(c.properties)) for c in g.channels()])
                  for g in f.groups()]
    except Exception as exc:
        raise _fail(path, "tdms", exc) from None
    finally:
        logger.removeHandler(catcher)
    trunc = [m for m in catcher.messages if "less data than expected" in m or "not a multiple" in m]
    if trunc:
        raise _fail(path, "tdms", f"truncated ({trunc[0]})")
    names = [c for _, chans in groups for c, _, _ in chans]
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    incs: dict[str, float] = {}
    for gname, chans in groups:
        for cname, data, props in chans:
            keys = [f"{gname}/{cname}"] + ([cname] if names.count(cname) == 1 else [])
            for key in keys:
                channels[key] = np.asarray(data, dtype=np.float64)
                if "unit_string" in props:
                    units[key] = str(props["unit_string"])
                if "wf_increment" in props:
                    incs[key] = float(props["wf_increment"])
    fs_per = {k: 1.0 / v for k, v in incs.items() if v > 0}
    return _Raw(channels=channels, fs=None, units=units, fs_per_channel=fs_per)


def _read_uff(path: Path) -> _Raw:
    import pyuff

    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
        sets = [uff.read_sets(i) for i, t in enumerate(types) if int(t) == 58]
    except Exception as exc:
        raise _fail(path, "uff", exc) from None
    if not sets:
        raise _fail(path, "uff", "no type-58 (function at nodal DOF) data set found")
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    fs_per: dict[str, float] = {}
    ids = [str(s.get("id1", "")).strip() for s in sets]
    for j, s in enumerate(sets):
        data = np.asarray(s["data"])
        if np.iscomplexobj(data):
            raise _fail(path, "uff", f"data set {j} is complex (a spectrum, not a time record)")
        keys = [str(j)] + ([ids[j]] if ids[j] and ids.count(ids[j]) == 1 else [])
        inc = float(s.get("abscissa_inc", 0.0) or 0.0)
        if not inc > 0 and "x" in s:
            inc = 1.0 / _fs_from_time(path, s["x"])
        n_exp = int(s.get("num_pts", data.size) or data.size)
        if data.size != n_exp:
            raise _fail(path, "uff", f"data set {j} holds {data.size} of {n_exp} points")
        for key in keys:
            channels[key] = data.astype(np.float64)
            if inc > 0:
                fs_per[key] = 1.0 / inc
            lab = str(s.get("ordinate_axis_units_lab", "")).strip()
            if lab and lab != "NONE":
                units[key] = lab
    return _Raw(channels=channels, fs=None, units=units, fs_per_channel=fs_per)


def _read_netcdf(path: Path) -> _Raw:
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as exc:
        raise _fail(path, "netcdf", exc) from None
    if "time" not in ds.coords and "time" not in ds.dims:
        raise InputError(
            f"{path.name}: time", "absent", "a NetCDF record needs a 'time' coordinate (s)"
        )
    fs = None
    if "fs" in ds.attrs:
        fs = float(np.asarray(ds.attrs["fs"]).ravel()[0])
    if "time" in ds.coords:
        tvals = ds["time"].values
        if np.issubdtype(tvals.dtype, np.datetime64) or np.issubdtype(tvals.dtype, np.timedelta64):
            tvals = (tvals - tvals[0]) / np.timedelta64(1, "s")
        fs_t = _fs_from_time(path, tvals)
        if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
            raise InputError(f"{path.name}: attrs['fs']", fs,
                             f"disagrees with the time coordinate ({fs_t:g} Hz)")
        fs = fs_t
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for name, var in ds.data_vars.items():
        if "time" not in var.dims or not np.issubdtype(var.dtype, np.number):
            continue
        var = var.transpose("time", ...)
        others = [d for d in var.dims if d != "time"]
        if not others:
            keys = {str(name): var.values}
        else:
            # e.g. acceleration(time, gear, axis) -> "acceleration[gear=G1,axis=x]"
            labels = [[str(v) for v in (ds[d].values if d in ds.coords else range(ds.sizes[d]))]
                      for d in others]
            flat = var.values.reshape(var.shape[0], -1)
            keys = {}
            for j, combo in enumerate(itertools.product(*labels)):
                sel = ",".join(f"{d}={v}" for d, v in zip(others, combo, strict=True))
                keys[f"{name}[{sel}]"] = flat[:, j]
        for key, values in keys.items():
            channels[key] = np.asarray(values, dtype=np.float64)
            if "units" in var.attrs:
                units[key] = str(var.attrs["units"])
    return _Raw(channels=channels, fs=fs, units=units)


_READERS: dict[str, Callable[[Path], _Raw]] = {
    "csv": _read_csv,
    "wav": _read_wav,
    "mat": _read_mat,
    "tdms": _read_tdms,
    "uff": _read_uff,
    "netcdf": _read_netcdf,
}


def _format_of(path: Path, fmt: str | None) -> str:
    if fmt is not None:
        if fmt not in FORMATS:
            raise InputError("fmt", fmt, f"must be one of {sorted(FORMATS)}")
        return fmt
    ext = path.suffix.lower()
    for key, exts in FORMATS.items():
        if ext in exts:
            return key
    known = sorted(e for exts in FORMATS.values() for e in exts)
    raise InputError("file", str(path), f"extension {ext or '(none)'!r} not one of {known}")


def _load(path: str | Path, fmt: str | None) -> tuple[Path, str, _Raw]:
    p = Path(path)
    if not p.is_file():
        raise InputError("file", str(p), "does not exist or is not a regular file")
    if p.stat().st_size == 0:
        raise InputError("file", str(p), "is empty")
    kind = _format_of(p, fmt)
    raw = _READERS[kind](p)
    if not raw.channels:
        raise _fail(p, kind, "holds no numeric 1-D channel")
    return p, kind, raw


def list_channels(path: str | Path, *, fmt: str | None = None) -> tuple[str, ...]:
    """Names of the channels in a file (see the module table for naming).

    Parameters
    ----------
    path : str or Path
        File to read.
    fmt : str, optional
        Format key of :data:`FORMATS`; by default from the extension.

    Returns
    -------
    tuple of str
        Channel names, in file order, as accepted by :func:`read_signal`.

    Raises
    ------
    InputError
        Missing, empty or unreadable file, unknown format or extension, no numeric
        channel.
    """
    _, _, raw = _load(path, fmt)
    return tuple(raw.channels)


def read_signal(
    path: str | Path,
    *,
    channel: str | None = None,
    fs: float | None = None,
    fmt: str | None = None,
) -> MeasuredSignal:
    """Read one channel and its sampling rate from a measured or simulated record.

    Parameters
    ----------
    path : str or Path
        File to read.
    channel : str, optional
        Channel name; may be omitted only when the file holds exactly one channel.
    fs : float, optional
        Sampling rate (Hz); required when the file stores none, checked against the file
        (:data:`FS_MATCH_RTOL`) when it does.
    fmt : str, optional
        Format key of :data:`FORMATS`; by default from the extension.

    Returns
    -------
    MeasuredSignal

    Raises
    ------
    InputError
        Missing, empty or unreadable file; unknown format; channel missing or not
        named when the file has several; fewer than 2 or non-finite samples; no
        sampling rate, or a given ``fs`` that disagrees with the file's.
    """
    p, kind, raw = _load(path, fmt)
    names = tuple(raw.channels)
    if channel is None:
        if len(names) != 1:
            raise InputError("channel", None, f"must be given: {p.name} has channels {list(names)}")
        channel = names[0]
    if channel not in raw.channels:
        raise InputError("channel", channel, f"not in {p.name}; available: {list(names)}")
    data = raw.channels[channel]
    if data.ndim != 1 or data.size < 2:
        raise _fail(p, kind, f"channel {channel!r} holds {data.size} samples (need >= 2)")
    bad = ~np.isfinite(data)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(f"{p.name}: {channel}[{i}]", float(data[i]),
                         f"must be finite ({int(bad.sum())} non-finite samples)")
    fs_file = raw.fs_per_channel.get(channel, raw.fs)
    if fs_file is not None and not (math.isfinite(fs_file) and fs_file > 0):
        raise _fail(p, kind, f"stored sampling rate {fs_file!r} is not a positive number")
    if fs is not None:
        fs_user = float(fs)
        if not (math.isfinite(fs_user) and fs_user > 0):
            raise InputError("fs", fs, "must be a finite number > 0 (Hz)")
        if fs_file is not None and abs(fs_user - fs_file) > FS_MATCH_RTOL * fs_file:
            raise InputError("fs", fs_user,
                             f"disagrees with the {fs_file:g} Hz stored in {p.name}")
        rate, source = (fs_file, "file") if fs_file is not None else (fs_user, "user")
    elif fs_file is not None:
        rate, source = fs_file, "file"
    else:
        raise InputError("fs", None, f"must be given: {p.name} stores no sampling rate")
    return MeasuredSignal(
        data=np.ascontiguousarray(data, dtype=np.float64), fs=float(rate), channel=channel,
        path=str(p), fmt=kind, fs_source=source, channels=names, units=raw.units.get(channel),
    )
