"""Readers for measured (and simulated) vibration records.

Formats, chosen by file extension unless ``fmt`` is given (an unknown extension falls
back to the file's magic bytes for the binary formats):

=========  ==============  ==========================================================
format     extensions      channels / sampling rate
=========  ==============  ==========================================================
csv        .csv, .txt      columns (header row names them, else ``"0", "1", ...``);
                           fs from a time column (``time``, ``t``, ``time_s``,
                           ``time [ms]``) or a comment line ``# fs = 50000`` /
                           ``# fs: 25.6 kHz``; see :mod:`gearsim.io.csvtext` for the
                           delimiters, decimal comma, header and metadata comments
wav        .wav            ``"0", "1", ...``; fs from the header; integer PCM scaled
                           to full scale 1.0
mat        .mat            numeric vectors (``"name"``) and matrix columns
                           (``"name:j"``); fs from a scalar (``fs``, ``SampleRate``,
                           ``dt``, ...), a time vector ``t``/``time`` or header
                           structs: ``Head_1.SampFreq`` (or ``XInc``) for ``Data1``,
                           whose ``Unit``/``Name`` fields give units and name
tdms       .tdms           ``"channel"`` when unique (alias ``"group/channel"``), else
                           ``"group/channel"``; fs from ``wf_increment`` (or a rate
                           property) of the channel, else of its group or the file
uff        .uff, .unv      type-58 data sets by ``id1`` when unique (alias: index
                           ``"0", "1", ...``); fs from ``abscissa_inc``
netcdf     .nc, .h5, .nc4  data variables along ``time`` (``"name"``; with more
                           dimensions ``"name[shaft=input,axis=y]"``); fs from a rate
                           attribute (``fs``, ``sampling_rate``, ``dt``, ...) or the
                           ``time`` coordinate (s), e.g. gearsim simulator output; a
                           file of one dimension needs no ``time`` with a rate
=========  ==============  ==========================================================

Rate names are matched in any case: rates ``fs``, ``SampFreq``, ``SampleRate``,
``sampling_rate``, ...; intervals (rate = 1 / value) ``dt``, ``XInc``, ``Increment``,
``wf_increment``, ... A MAT file that holds a variable more than once (some exporters
write every variable twice, the first copy all zeros) is read using the last copy that
is not all zeros, with one warning; scipy's warnings come out as one line each.

**Compressed files.** Every format is also read gzip-, bz2-, xz-compressed or as the
single member of a zip archive, recognised from the first bytes (not the name), see
:mod:`gearsim.io.compression`: ``rec.csv.gz``, ``rec.uff.xz``, ``rec.zip`` holding
``rec.csv``, and a gzip stream named ``rec.csv`` all read. The inner format comes from
the name without the compression suffix (or the member's name); ``fmt`` overrides it.
Text is parsed in memory; a binary format (or UFF, whose library reads only files) is
written to a private temporary file that is removed at once.

**All channels.** :func:`read_record` returns every channel (or the chosen ones) with
the sampling rate (None when neither the file nor the user gives one), its source,
per-channel units and the file's metadata; :func:`read_signal` returns one channel and
needs a rate. A sampling rate given by the user is used when the file holds none; when
both exist they must agree within :data:`FS_MATCH_RTOL`.

**Problems.** A missing or unreadable file raises :class:`gearsim.errors.InputError` at
once. Otherwise every problem of the call (each missing channel, a missing or
disagreeing fs, a channel of zero samples, non-finite samples, ...) is collected and
raised together as one :class:`ReadProblems` (an ``InputError``) whose one-line message
lists them separated by ``"; "``; a single problem is raised as a plain ``InputError``.
A record of one sample reads: whether it is long enough is for the analysis to decide.

**Non-finite samples** (NaN, inf, empty CSV fields, a row cut short) are refused, naming
the channel and the first index. With ``drop_nonfinite=True`` the leading and trailing
runs of non-finite samples are dropped and reported (:class:`DroppedSamples`); the
channels of one length (one time base) are cut to the same rows, so they stay aligned
and sample ``i`` of the result is sample ``kept[0] + i`` of the file. Interior non-finite
samples are still refused: dropping them would close a gap and break uniform sampling
(every rate, order tracking and TSA result would silently shift), and interpolating
would invent data exactly where fault indicators (kurtosis, crest factor) look for
impulses.
"""

from __future__ import annotations

import itertools
import json
import logging
import math
import re
import tempfile
import tomllib
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gearsim.errors import InputError
from gearsim.io.compression import SUFFIXES, decompress, sniff_compression
from gearsim.io.csvtext import decode_text, parse_table
from gearsim.io.record import (
    MAX_SAMPLING_RATE,
    MIN_SAMPLING_RATE,
    DroppedSamples,
    MeasuredSignal,
    ReadProblems,
    Record,
    raise_all,
)

__all__ = [
    "FORMATS",
    "FS_MATCH_RTOL",
    "TIME_JITTER_RTOL",
    "DroppedSamples",
    "MeasuredSignal",
    "ReadProblems",
    "Record",
    "list_channels",
    "read_record",
    "read_signal",
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
_TIME_UNITS = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6}
#: Names (any case) of a stored sampling rate [Hz], and of a sampling interval [s] whose
#: inverse is the rate, in MAT variables and header structs (``Head_1.SampFreq``,
#: ``XInc``), TDMS properties (``wf_increment``) and NetCDF attributes.
_RATE_KEYS = frozenset({"fs", "sampfreq", "samplerate", "sample_rate", "sampling_rate",
                        "samplingrate", "samplefrequency", "samplingfrequency",
                        "sampling_frequency"})
_STEP_KEYS = frozenset({"dt", "xinc", "x_inc", "increment", "wf_increment", "deltat", "delta_t",
                        "sampleinterval", "sample_interval", "samplinginterval"})
#: Header fields (any case) naming a channel's units and the channel.
_UNIT_KEYS = frozenset({"unit", "units", "unit_string", "engunit", "yunit", "y_unit"})
_NAME_KEYS = frozenset({"name", "channelname", "channel_name", "chname"})
#: Leading bytes of the binary formats, used when the extension is unknown.
_FORMAT_MAGIC = (
    (b"RIFF", "wav"), (b"RIFX", "wav"), (b"MATLAB 5.0 MAT-file", "mat"),
    (b"MATLAB 7.3 MAT-file", "mat"), (b"TDSm", "tdms"), (b"\x89HDF\r\n\x1a\n", "netcdf"),
)


@dataclass
class _Raw:
    channels: dict[str, np.ndarray]
    fs: float | None
    units: dict[str, str] = field(default_factory=dict)
    fs_per_channel: dict[str, float] = field(default_factory=dict)
    aliases: set[str] = field(default_factory=set)  # names that repeat another channel
    metadata: dict = field(default_factory=dict)
    text_rows: bool = False  # samples are rows of a text table (messages name the row)
    problems: list[InputError] = field(default_factory=list)


def _fail(path: Path, fmt: str, reason: object) -> InputError:
    text = str(reason).strip().splitlines()[0] if str(reason).strip() else type(reason).__name__
    return InputError("file", str(path), f"cannot be read as {fmt.upper()}: {text}")


def _rate_of(fields: dict) -> float | None:
    """Sampling rate [Hz] stored in metadata: a rate key, else a step key (rate = 1 / step),
    else the same in a nested mapping (``x_values.increment``); None if none holds one."""
    items = {str(k).lower(): v for k, v in fields.items()}
    for keys, step in ((_RATE_KEYS, False), (_STEP_KEYS, True)):
        for k, v in items.items():
            a = np.asarray(v)
            if k in keys and a.size == 1 and a.dtype.kind in "iuf":
                x = float(a.ravel()[0])
                return (1.0 / x if x else math.inf) if step else x
    return next((r for v in items.values() if isinstance(v, dict)
                 and (r := _rate_of(v)) is not None), None)


def _text_of(fields: dict, keys: frozenset) -> str | None:
    """The first non-empty text field of ``fields`` whose name (any case) is in ``keys``."""
    return next((v.strip() for k, v in fields.items() if str(k).lower() in keys
                 and isinstance(v, str) and v.strip()), None)


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


def _time_scale(name: str, units: dict[str, str]) -> float | None:
    """Seconds per unit of a time column, or None when ``name`` is not a time column."""
    low = name.strip().lower()
    scale = _TIME_UNITS.get(str(units.get(name, "")).strip().lower())  # "t [ms]": in ms
    if scale is not None and re.sub(r"\s*[\[(].*$", "", low) in ("time", "t", "zeit"):
        return scale
    if low in _TIME_NAMES:
        return 1.0
    m = re.match(r"^(time|t|zeit)[ _]?\[?\(?\s*(s|sec|ms|us|µs|μs)\s*\]?\)?$", low)
    return _TIME_UNITS[m.group(2)] if m else None


def _read_csv(text: str, shown: Path) -> _Raw:
    table = parse_table(text, shown.name)
    channels = {n: np.ascontiguousarray(table.columns[:, j])
                for j, n in enumerate(table.names)}
    fs = table.fs
    problems: list[InputError] = []
    time_col = next((n for n in table.names if _time_scale(n, table.units) is not None), None)
    if time_col is not None:
        scale = _time_scale(time_col, table.units)
        t = channels.pop(time_col) * scale
        if t.size >= 2:  # one row gives no rate: the comment or the user must
            fs_t = _fs_from_time(shown, t)
            if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
                problems.append(InputError(f"{shown.name}: fs comment", fs,
                                           f"disagrees with the time column ({fs_t:g} Hz)"))
            fs = fs_t
    units = {n: u for n, u in table.units.items() if n in channels}
    return _Raw(channels=channels, fs=fs, units=units, metadata=dict(table.metadata),
                text_rows=True, problems=problems)


def _read_wav(path: Path, shown: Path) -> _Raw:
    from scipy.io import wavfile

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", wavfile.WavFileWarning)
            rate, data = wavfile.read(path)
    except Exception as exc:
        raise _fail(shown, "wav", exc) from None
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


def _read_mat(path: Path, shown: Path) -> _Raw:
    from scipy.io import loadmat

    twice: list[str] = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            content = loadmat(path, squeeze_me=False)
            if any("Duplicate variable" in str(w.message) for w in caught):
                content, twice = _mat_copies(path)
    except NotImplementedError:
        return _read_mat73(path, shown)
    except Exception as exc:
        raise _fail(shown, "mat", exc) from None
    for w in caught:  # scipy's warnings, each as one line naming the file
        if "Duplicate variable" not in str(w.message):
            warnings.warn(f"{shown.name}: {' '.join(str(w.message).split())}", stacklevel=2)
    if twice:
        warnings.warn(f"{shown.name}: {', '.join(twice)} stored more than once; of each, the "
                      "last copy that is not all zeros is read", stacklevel=2)
    return _mat_channels(shown, {k: v for k, v in content.items() if not k.startswith("__")})


def _mat_copies(path: Path) -> tuple[dict, list[str]]:
    """Variables of a MAT file that holds some more than once (as some acquisition exporters
    write it, the first copy all zeros): of each, the last copy that is not all zeros."""
    from scipy.io import loadmat
    from scipy.io.matlab import varmats_from_mat

    copies: dict[str, list] = {}
    with open(path, "rb") as fh:
        for name, stream in varmats_from_mat(fh):
            copies.setdefault(name, []).append(loadmat(stream, squeeze_me=False)[name])

    def filled(v: np.ndarray) -> bool:
        return v.size > 0 and (v.dtype.kind not in "biufc" or bool(np.any(v != 0)))

    content = {n: next((v for v in reversed(vs) if filled(v)), vs[-1]) for n, vs in copies.items()}
    return content, [n for n, vs in copies.items() if len(vs) > 1]


def _struct(arr: np.ndarray) -> dict:
    """A 1x1 MAT struct as a dict of its numbers, texts and nested structs."""
    out: dict = {}
    for k in arr.dtype.names if arr.size == 1 else ():
        v = np.asarray(arr.ravel()[0][k])
        while v.dtype == object and v.size == 1:
            v = np.asarray(v.ravel()[0])
        if v.dtype.names is not None:
            out[k] = _struct(v)
        elif v.dtype.kind in "US" and v.size == 1:
            out[k] = str(v.ravel()[0])
        elif v.dtype.kind in "iuf" and v.size == 1:
            out[k] = v.ravel()[0]
    return out


def _h5_value(obj):
    """A MAT v7.3 (HDF5) variable: a struct (group) as a dict of its fields, a char array
    (uint16 codes, ``MATLAB_class = "char"``) as a string, a number array transposed back
    to MATLAB's column-major shape; ``None`` for what a record cannot use (cells,
    references)."""
    import h5py

    cls = obj.attrs.get("MATLAB_class", b"")
    cls = cls.decode() if isinstance(cls, bytes) else str(cls)
    if isinstance(obj, h5py.Group):
        if cls != "struct":
            return None
        out = {k: _h5_value(obj[k]) for k in obj}
        return {k: v for k, v in out.items() if v is not None}
    if cls == "char":
        return "".join(map(chr, np.asarray(obj).ravel()))
    arr = np.asarray(obj)
    if arr.dtype.kind not in "biuf" or cls in ("cell", "function_handle"):
        return None
    return arr.T


def _scalars(d: dict) -> dict:
    """The numbers and texts of a struct read by :func:`_h5_value` (nested structs kept)."""
    out: dict = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out[k] = _scalars(v)
        elif isinstance(v, str) or (isinstance(v, np.ndarray) and v.size == 1):
            out[k] = v if isinstance(v, str) else v.ravel()[0]
    return out


def _read_mat73(path: Path, shown: Path) -> _Raw:
    """MAT v7.3 (HDF5 with a MATLAB header): its variables, header structs included
    (the HDF5 layout of MATLAB's ``save -v7.3``: one dataset or group per variable)."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            content = {k: _h5_value(f[k]) for k in f if not k.startswith("#")}
    except Exception as exc:
        raise _fail(shown, "mat", exc) from None
    return _mat_channels(shown, {k: (_scalars(v) if isinstance(v, dict) else v)
                                 for k, v in content.items() if v is not None})


def _number(name: str) -> str | None:
    """The last group of digits in a variable name: ``Head_1`` and ``Data1`` share ``1``."""
    digits = re.findall(r"\d+", name)
    return digits[-1] if digits else None


def _mat_channels(shown: Path, content: dict) -> _Raw:
    fs = None
    time = None
    channels: dict[str, np.ndarray] = {}
    heads: dict[str | None, dict] = {}  # header structs by the number in their name
    for name, val in content.items():
        if isinstance(val, dict):  # a header struct of a v7.3 file, already read
            heads.setdefault(_number(name), {}).update(val)
            continue
        arr = np.asarray(val)
        if arr.dtype.names is not None:
            heads.setdefault(_number(name), {}).update(_struct(arr))
            continue
        if not np.issubdtype(arr.dtype, np.number):
            continue
        if arr.size == 1 and (rate := _rate_of({name: arr})) is not None:
            fs = rate
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
        fs_t = _fs_from_time(shown, time)
        if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
            raise InputError(
                f"{shown.name}: fs", fs, f"disagrees with the time vector ({fs_t:g} Hz)"
            )
        fs = fs_t
    rates = {r for h in heads.values() if (r := _rate_of(h)) is not None}
    if fs is None and len(rates) == 1:  # the headers agree: one rate for the file
        fs = rates.pop()
    # a header struct numbered like a variable (Head_1, Data1) gives its rate, units, name
    raw = _Raw(channels={}, fs=fs)
    for key, v in channels.items():
        num = _number(key.split(":")[0])
        head = heads.get(num, {}) if num is not None else {}
        label = _text_of(head, _NAME_KEYS) if ":" not in key else None
        names = [key] if label in (None, key) or label in channels or label in raw.channels \
            else [label, key]
        raw.aliases.update(names[1:])
        rate, unit = _rate_of(head), _text_of(head, _UNIT_KEYS)
        for n in names:
            raw.channels[n] = v
            if rate is not None:
                raw.fs_per_channel[n] = rate
            if unit:
                raw.units[n] = unit
    return raw


class _LogCatcher(logging.Handler):
    def __init__(self) -> None:
        super().__init__(level=logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _read_tdms(path: Path, shown: Path) -> _Raw:
    from nptdms import TdmsFile

    catcher = _LogCatcher()
    logger = logging.getLogger("nptdms")
    logger.addHandler(catcher)
    try:
        f = TdmsFile.read(path)
        # a channel's properties over its group's over the file's (a rate on the group)
        groups = [(g.name, [(c.name, c[:], {**f.properties, **g.properties, **c.properties})
                            for c in g.channels()]) for g in f.groups()]
    except Exception as exc:
        raise _fail(shown, "tdms", exc) from None
    finally:
        logger.removeHandler(catcher)
    trunc = [m for m in catcher.messages if "less data than expected" in m or "not a multiple" in m]
    if trunc:
        raise _fail(shown, "tdms", f"truncated ({trunc[0]})")
    names = [c for _, chans in groups for c, _, _ in chans]
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    fs_per: dict[str, float] = {}
    aliases: set[str] = set()
    for gname, chans in groups:
        for cname, data, props in chans:
            keys = [f"{gname}/{cname}"]
            if names.count(cname) == 1:  # the short name first; "group/channel" an alias
                keys.insert(0, cname)
                aliases.add(keys[1])
            for key in keys:
                channels[key] = np.asarray(data, dtype=np.float64)
                if _text_of(props, _UNIT_KEYS):
                    units[key] = _text_of(props, _UNIT_KEYS)
                rate = _rate_of(props)
                if rate is not None and 0 < rate < math.inf:  # wf_increment 0: no waveform
                    fs_per[key] = rate
    return _Raw(channels=channels, fs=None, units=units, fs_per_channel=fs_per,
                aliases=aliases)


def _read_uff(path: Path, shown: Path) -> _Raw:
    import pyuff

    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
        sets = [uff.read_sets(i) for i, t in enumerate(types) if int(t) == 58]
    except Exception as exc:
        raise _fail(shown, "uff", exc) from None
    if not sets:
        raise _fail(shown, "uff", "no type-58 (function at nodal DOF) data set found")
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    fs_per: dict[str, float] = {}
    aliases: set[str] = set()
    ids = [str(s.get("id1", "")).strip() for s in sets]
    for j, s in enumerate(sets):
        data = np.asarray(s["data"])
        if np.iscomplexobj(data):
            raise _fail(shown, "uff", f"data set {j} is complex (a spectrum, not a time record)")
        keys = [str(j)]
        if ids[j] and ids.count(ids[j]) == 1 and ids[j] != str(j):  # id1 first, index alias
            keys.insert(0, ids[j])
            aliases.add(str(j))
        inc = float(s.get("abscissa_inc", 0.0) or 0.0)
        if not inc > 0 and "x" in s:
            inc = 1.0 / _fs_from_time(shown, s["x"])
        n_exp = int(s.get("num_pts", data.size) or data.size)
        if data.size != n_exp:
            raise _fail(shown, "uff", f"data set {j} holds {data.size} of {n_exp} points")
        for key in keys:
            channels[key] = data.astype(np.float64)
            if inc > 0:
                fs_per[key] = 1.0 / inc
            lab = str(s.get("ordinate_axis_units_lab", "")).strip()
            if lab and lab != "NONE":
                units[key] = lab
    return _Raw(channels=channels, fs=None, units=units, fs_per_channel=fs_per,
                aliases=aliases)


def _read_netcdf(path: Path, shown: Path) -> _Raw:
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as exc:
        raise _fail(shown, "netcdf", exc) from None
    fs = _rate_of(ds.attrs)
    tdim = "time" if "time" in ds.coords or "time" in ds.dims else \
        next(iter(ds.dims)) if len(ds.dims) == 1 and fs is not None else None
    if tdim is None:
        raise InputError(f"{shown.name}: time", "absent", "a NetCDF record needs a 'time' "
                         "coordinate (s), or one dimension and a rate attribute ('fs')")
    if "time" in ds.coords:
        tvals = ds["time"].values
        if np.issubdtype(tvals.dtype, np.datetime64) or np.issubdtype(tvals.dtype, np.timedelta64):
            tvals = (tvals - tvals[0]) / np.timedelta64(1, "s")
        if tvals.size >= 2 or fs is None:  # one time gives no rate; attrs['fs'] may
            fs_t = _fs_from_time(shown, tvals)
            if fs is not None and abs(fs_t - fs) > FS_MATCH_RTOL * fs:
                raise InputError(f"{shown.name}: rate attribute", fs,
                                 f"disagrees with the time coordinate ({fs_t:g} Hz)")
            fs = fs_t
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    fs_per: dict[str, float] = {}
    aliases: set[str] = set()
    for name, var in ds.data_vars.items():
        if tdim not in var.dims or not np.issubdtype(var.dtype, np.number):
            continue
        var = var.transpose(tdim, ...)
        others = [d for d in var.dims if d != tdim]
        if not others:
            keys = {str(name): var.values}
        else:
            # e.g. acceleration(time, shaft, axis) -> "acceleration[shaft=input,axis=y]"
            labels = [[str(v) for v in (ds[d].values if d in ds.coords else range(ds.sizes[d]))]
                      for d in others]
            flat = var.values.reshape(var.shape[0], -1)
            keys = {}
            for j, combo in enumerate(itertools.product(*labels)):
                sel = ",".join(f"{d}={v}" for d, v in zip(others, combo, strict=True))
                keys[f"{name}[{sel}]"] = flat[:, j]
                # also by its labels alone, "acceleration[input,y]": the names of
                # Gearbox.signals() and of a study's signal (an alias, not listed)
                short = f"{name}[{','.join(combo)}]"
                if short not in ds.data_vars:
                    keys[short] = flat[:, j]
                    aliases.add(short)
        for key, values in keys.items():
            channels[key] = np.asarray(values, dtype=np.float64)
            if "units" in var.attrs:
                units[key] = str(var.attrs["units"])
            if "time" not in ds.coords and (rate := _rate_of(var.attrs)) is not None:
                fs_per[key] = rate
    meta: dict = {}
    try:  # a gearsim gear-train result: its input speed and the tooth counts it analyses
        teeth = [int(z) for z in np.atleast_1d(ds.attrs["analysis_teeth"])]
        f_in = float(np.atleast_1d(ds.attrs["shaft_frequency"])[0])
        if teeth and all(z >= 1 for z in teeth) and math.isfinite(f_in) and f_in > 0:
            meta["rpm"], meta["teeth"] = 60.0 * f_in, teeth
            if "tacho" in ds.data_vars and "shaft" in ds.coords:
                # the shaft each simulated tacho pulses once a revolution of, the input
                # (whose speed rpm is) first
                meta["tacho_shafts"] = [str(v) for v in ds["shaft"].values]
    except (KeyError, TypeError, ValueError, IndexError):
        pass
    if "tacho" in ds.data_vars and ds["tacho"].dims == (tdim, "shaft") and "shaft" in ds.coords:
        # a run whose speed changes: the shafts whose tacho period varies
        varying = [str(sh) for sh, x in zip(ds["shaft"].values, ds["tacho"].values.T,
                                            strict=True) if _period_varies(x)]
        if varying:
            meta["varying_tachos"] = varying
    if (change := _speed_change(ds, meta.get("varying_tachos"))) is not None:
        meta["speed_change"] = change
        if "tacho_shafts" in meta and not meta.get("varying_tachos"):
            # a steady speed off the nominal one: every shaft's tacho follows the run
            meta["varying_tachos"] = list(meta["tacho_shafts"])
    if "teeth" in meta:  # a compound train's stages ("32/80,48/64"), else its configuration
        if (stages := _stages_attr(ds.attrs.get("analysis_stages"))) is not None:
            meta["stages"] = stages
        elif isinstance(ds.attrs.get("config"), str) and ds.attrs.get("kind") != "planetary":
            # gears written before the stages (a stage result's parts: analysis_parts)
            meta["config"] = ds.attrs["config"]
    if ds.attrs.get("kind") == "planetary" and (parts := _parts_attr(ds.attrs)) is not None:
        # a gearsim stage result: each stage in series (one alone) and each gear chain
        # beside them; the reader of the channels picks the part a record belongs to
        meta["parts"] = parts
    elif ds.attrs.get("kind") == "planetary" and "carrier_angle" in ds:
        # a result written before the stages' attributes: the first stage, its carrier
        try:
            meta["planetary"] = {
                "z_sun": int(ds.attrs["sun_teeth"]), "z_planet": int(ds.attrs["planet_teeth"]),
                "z_ring": int(ds.attrs["ring_teeth"]), "planets": int(ds.attrs["planets"]),
                "carrier_frequency": float(ds.attrs["carrier_frequency"]),
                "ring_frequency": float(ds.attrs["ring_frequency"]),
                "carrier_phase": float(ds["carrier_angle"].values[0]),
                "sensor_angle": float(ds.attrs["sensor_angle"])}
        except (KeyError, TypeError, ValueError, IndexError):
            pass  # an incomplete stage result is analysed as a plain record
    return _Raw(channels=channels, fs=fs, units=units, metadata=meta, fs_per_channel=fs_per,
                aliases=aliases)


#: A simulated tacho whose pulse intervals differ by more than this fraction of their
#: mean (and by more than two samples, the pulses' quantisation) marks a run with a speed
#: profile: 1 %, where a constant-speed run's intervals agree to a sample.
RUN_UP_TOL = 0.01


def _period_varies(pulses: np.ndarray) -> bool:
    """Whether the once-per-revolution pulse train ``pulses`` has a changing period (at
    least three pulses; :data:`RUN_UP_TOL`)."""
    x = np.asarray(pulses, dtype=float)
    h = 0.5 * float(np.max(x)) if x.size else 0.0
    rises = np.flatnonzero((x[1:] >= h) & (x[:-1] < h)) if h > 0.0 else np.empty(0)
    if rises.size < 3:
        return False
    iv = np.diff(rises)
    return float(iv.max() - iv.min()) > max(2.0, RUN_UP_TOL * float(iv.mean()))


def _speed_change(ds, varying: list[str] | None) -> str | None:
    """How the speed of a gearsim run changes over its record, in words; None when it
    does not (by :data:`RUN_UP_TOL`): from the run's speed profile (the ``dynamics``
    attribute's ``speed_times``, ``speed_values`` [rad/s], linear between its points,
    at the record's times), else from the shafts whose tacho period varies."""
    try:
        dyn = json.loads(ds.attrs["dynamics"])
        t, w = np.asarray(dyn["speed_times"], float), np.asarray(dyn["speed_values"], float)
        if t.ndim != 1 or t.shape != w.shape or t.size == 0:
            raise ValueError("no speed profile")
        t0, t1 = float(ds["time"].values[0]), float(ds["time"].values[-1])
        w = np.interp(np.r_[t0, t[(t > t0) & (t < t1)], t1], t, w) * 30.0 / math.pi
        if np.ptp(w) > RUN_UP_TOL * np.mean(w):
            return (f"the run's input speed goes from {w[0]:.5g} to {w[-1]:.5g} rpm over "
                    "the record")
        # steady over the record, but not at the operating speed the file's speeds are
        nominal = _operating_rpm(ds.attrs.get("config"))
        if nominal is not None and abs(np.mean(w) - nominal) > RUN_UP_TOL * nominal:
            return (f"the run's input speed is {np.mean(w):.5g} rpm over the record, not the "
                    f"operating {nominal:.5g} rpm at which the file gives its speeds")
    except (KeyError, TypeError, ValueError, IndexError):
        pass
    return f"the tacho period of shaft {varying[0]} changes over the record" if varying \
        else None


def _operating_rpm(config: object) -> float | None:
    """The operating (nominal) input speed [rpm] of a gearsim result's configuration
    (``[operating] speed``, ``"... rad/s"`` as results write it); None when absent."""
    try:
        value, unit = str(tomllib.loads(str(config))["operating"]["speed"]).split()
        return float(value) * 30.0 / math.pi if unit == "rad/s" else None
    except (tomllib.TOMLDecodeError, KeyError, TypeError, ValueError):
        return None


def _parts_attr(a: Mapping) -> dict | None:
    """The parts of a gearsim stage result (its ``analysis_parts`` attribute, JSON: each
    stage's and each gear chain's kinematics for the analysis of its records; the
    sensor's angle [rad] added to each stage); None when absent or not of that form
    (the record is then analysed as a plain one)."""
    try:
        parts = json.loads(a["analysis_parts"])
        for st in parts["stages"]:
            st["sensor_angle"] = float(a["sensor_angle"])
            _ = (st["z_sun"], st["z_planet"], st["z_ring"], st["planets"],
                 st["carrier_frequency"], st["ring_frequency"], st["carrier_phase"],
                 st["frequency"], st["teeth"])
        for ch in parts["chains"]:
            _ = (ch["shafts"], ch["meshes"], ch["frequency"], ch["teeth"], ch["stages"])
    except (KeyError, TypeError, ValueError):
        return None
    return parts if parts["stages"] else None


def _stages_attr(text: object) -> tuple[tuple[int, int], ...] | None:
    """``"32/80,48/64"`` (a gearsim result's ``analysis_stages``) as ``((32, 80), (48, 64))``;
    None when absent or not of that form (the record is then a simple train's)."""
    if not isinstance(text, str):
        return None
    try:
        pairs = tuple(tuple(int(z) for z in st.split("/")) for st in text.split(","))
    except ValueError:
        return None
    ok = all(len(p) == 2 and min(p) >= 1 for p in pairs)
    return pairs if pairs and ok else None  # type: ignore[return-value]


_READERS: dict[str, Callable[[Path, Path], _Raw]] = {
    "wav": _read_wav,
    "mat": _read_mat,
    "tdms": _read_tdms,
    "uff": _read_uff,
    "netcdf": _read_netcdf,
}


def _format_of(name: str, fmt: str | None, head: bytes, shown: Path,
               compression: str | None) -> str:
    if fmt is not None:
        return fmt
    ext = Path(name).suffix.lower()
    for key, exts in FORMATS.items():
        if ext in exts:
            return key
    for magic, key in _FORMAT_MAGIC:
        if head.startswith(magic):
            return key
    known = sorted(e for exts in FORMATS.values() for e in exts)
    inner = f" (inside the {compression} stream: {name!r})" if compression else ""
    raise InputError("file", str(shown), f"extension {ext or '(none)'!r}{inner} not one of "
                     f"{known} (or give fmt)")


def _load(path: str | Path, fmt: str | None) -> tuple[Path, str, _Raw, str | None]:
    p = Path(path)
    if not p.is_file():
        raise InputError("file", str(p), "does not exist or is not a regular file")
    if p.stat().st_size == 0:
        raise InputError("file", str(p), "is empty")
    compression = sniff_compression(p)
    if compression is None:
        content, name = None, p.name
        with open(p, "rb") as fh:
            head = fh.read(32)
    else:
        dec = decompress(p, compression)
        content, name = dec.data, dec.inner_name
        if not content:
            raise InputError("file", str(p), f"is empty once decompressed ({compression})")
        head = content[:32]
    kind = _format_of(name, fmt, head, p, compression)
    if kind == "csv":
        raw = _read_csv(decode_text(p.read_bytes() if content is None else content), p)
    elif content is None:
        raw = _READERS[kind](p, p)
    else:  # the libraries read files: a private temporary copy, removed at once
        suffix = Path(name).suffix if Path(name).suffix.lower() not in SUFFIXES else ""
        with tempfile.TemporaryDirectory(prefix="gearsim-record-") as tmp:
            inner = Path(tmp) / f"record{suffix or FORMATS[kind][0]}"
            inner.write_bytes(content)
            raw = _READERS[kind](inner, p)
    if not raw.channels:
        raise _fail(p, kind, "holds no numeric 1-D channel")
    return p, kind, raw, compression


def list_channels(path: str | Path, *, fmt: str | None = None) -> tuple[str, ...]:
    """Names of the channels in a file (see the module table for naming).

    Parameters
    ----------
    path : str or Path
        File to read (plain or compressed).
    fmt : str, optional
        Format key of :data:`FORMATS`; by default from the extension.

    Returns
    -------
    tuple of str
        Channel names, in file order, as accepted by :func:`read_signal` and
        :func:`read_record` (aliases included).

    Raises
    ------
    InputError
        Missing, empty or unreadable file, unknown format or extension, no numeric
        channel.
    """
    if fmt is not None and fmt not in FORMATS:
        raise InputError("fmt", fmt, f"must be one of {sorted(FORMATS)}")
    _, _, raw, _ = _load(path, fmt)
    return tuple(raw.channels)


def _nonfinite_problem(shown: Path, raw: _Raw, channel: str, data: np.ndarray, i: int,
                       count: int, interior: bool) -> InputError:
    if raw.text_rows:
        param = f"{shown.name}: column {channel!r} data row {i + 1}"
        if np.isnan(data[i]):
            value, why = "missing/NaN", "truncated or damaged file?"
        else:
            value, why = f"{data[i]:g}", "an overflowed or saturated value?"
        where = "in this column"
    else:
        param, value, why = f"{shown.name}: {channel}[{i}]", float(data[i]), ""
        where = "samples"
    if interior:
        return InputError(param, value, f"must be finite: drop_nonfinite drops only leading "
                          f"and trailing runs ({count} non-finite inside the record would "
                          "break uniform sampling)")
    if raw.text_rows:
        return InputError(param, value, f"every row must hold a finite number ({count} "
                          f"non-finite {where}; {why})")
    return InputError(param, value, f"must be finite ({count} non-finite {where})")


def _finite_span(data: np.ndarray) -> tuple[int, int]:
    good = np.flatnonzero(np.isfinite(data))
    return (int(good[0]), int(good[-1]) + 1) if good.size else (0, 0)


def _drop(shown: Path, raw: _Raw, data: dict[str, np.ndarray], problems: list[InputError]
          ) -> tuple[dict[str, np.ndarray], dict[str, DroppedSamples]]:
    """Cut leading/trailing non-finite runs, alike for the channels of one length."""
    spans = {c: _finite_span(v) for c, v in data.items()}
    common: dict[int, tuple[int, int]] = {}
    for c, v in data.items():
        lo, hi = spans[c]
        a, b = common.get(v.size, (0, v.size))
        common[v.size] = (max(a, lo), min(b, hi))
    out: dict[str, np.ndarray] = {}
    dropped: dict[str, DroppedSamples] = {}
    for c, v in data.items():
        start, stop = common[v.size]
        if stop <= start:
            problems.append(InputError(f"{shown.name}: {c}", f"{v.size} samples",
                                       "no finite sample left once the leading and trailing "
                                       "non-finite runs (of this or an aligned channel) are "
                                       "dropped"))
            continue
        kept = v[start:stop]
        bad = np.flatnonzero(~np.isfinite(kept))
        if bad.size:
            problems.append(_nonfinite_problem(shown, raw, c, v, start + int(bad[0]),
                                               int(bad.size), interior=True))
            continue
        out[c] = kept
        if start > 0 or stop < v.size:
            removed = np.r_[np.arange(start), np.arange(stop, v.size)]
            dropped[c] = DroppedSamples(
                count=int(removed.size), nonfinite=int(np.sum(~np.isfinite(v[removed]))),
                first=int(removed[0]), last=int(removed[-1]), kept=(start, stop))
    return out, dropped


def _read(path: str | Path, channels: Sequence[str] | None, fs: float | None,
          fmt: str | None, drop_nonfinite: bool, single: bool) -> Record:
    problems: list[InputError] = []
    fs_user = None
    if fs is not None:
        try:
            fs_user = float(fs)
        except (TypeError, ValueError):
            fs_user = math.nan
        if isinstance(fs, bool) or not (MIN_SAMPLING_RATE <= fs_user <= MAX_SAMPLING_RATE):
            problems.append(InputError("fs", fs, f"must be a number in [{MIN_SAMPLING_RATE:g}, "
                                       f"{MAX_SAMPLING_RATE:g}] Hz"))
            fs_user = None
    if fmt is not None and fmt not in FORMATS:
        problems.append(InputError("fmt", fmt, f"must be one of {sorted(FORMATS)}"))
    wanted: list[str] | None = None
    if channels is not None:
        wanted = [channels] if isinstance(channels, str) else list(dict.fromkeys(channels))
        if not wanted:
            problems.append(InputError("channels", [], "must name at least one channel "
                                       "(or be None for all)"))
        elif not all(isinstance(c, str) for c in wanted):
            problems.append(InputError("channels", wanted, "must be channel names (str)"))
            wanted = [c for c in wanted if isinstance(c, str)]
    try:
        p, kind, raw, compression = _load(path, None if any(
            q.parameter == "fmt" for q in problems) else fmt)
    except InputError as exc:
        raise_all([*problems, exc])
        raise
    problems.extend(raw.problems)
    primary = [c for c in raw.channels if c not in raw.aliases]
    if wanted is None:
        if single and len(primary) != 1:
            problems.append(InputError("channel", None,
                                       f"must be given: {p.name} has channels {primary}"))
        selected = primary if not single else primary if len(primary) == 1 else []
    else:
        missing = [c for c in wanted if c not in raw.channels]
        for j, c in enumerate(missing):
            if len(missing) == 1:
                limit = f"not in {p.name}; available: {primary}"
            else:
                limit = f"not in {p.name}" + (f" (available: {primary})"
                                              if j == len(missing) - 1 else "")
            problems.append(InputError("channel", c, limit))
        selected = [c for c in wanted if c in raw.channels]
    # sampling rate: the file's (one for all selected channels), else the user's
    # (with no channel selected, the file's channels tell whether it stores a rate at all)
    rates: dict[str, float] = {}
    for c in selected or primary:
        r = raw.fs_per_channel.get(c, raw.fs)
        if r is None:
            continue
        if not (MIN_SAMPLING_RATE <= r <= MAX_SAMPLING_RATE):
            problems.append(_fail(p, kind, f"stored sampling rate {r!r} of {c!r} is not a "
                                  f"number in [{MIN_SAMPLING_RATE:g}, {MAX_SAMPLING_RATE:g}] "
                                  "Hz"))
        else:
            rates[c] = r
    fs_file = next(iter(rates.values()), None)
    if selected and rates and any(abs(r - fs_file) > FS_MATCH_RTOL * fs_file
                                  for r in rates.values()):
        shown = ", ".join(f"{c} {r:g} Hz" for c, r in rates.items())
        problems.append(InputError("channels", list(rates), f"have different sampling rates "
                                   f"({shown}): choose channels of one rate"))
    elif selected and rates and len(rates) < len(selected):
        bare = [c for c in selected if c not in rates]
        problems.append(InputError("channels", bare, f"store no sampling rate while "
                                   f"{list(rates)} store {fs_file:g} Hz: choose channels of "
                                   "one rate"))
    rate, source = fs_file, "file"
    if fs_user is not None:
        one_rate = all(abs(r - fs_file) <= FS_MATCH_RTOL * fs_file for r in rates.values())
        if fs_file is not None and (selected or one_rate) and \
                abs(fs_user - fs_file) > FS_MATCH_RTOL * fs_file:
            problems.append(InputError("fs", fs_user,
                                       f"disagrees with the {fs_file:g} Hz stored in {p.name}"))
        if fs_file is None:
            rate, source = fs_user, "user"
    elif fs_file is None and fs is None and single:  # a record may have none
        problems.append(InputError("fs", None, f"must be given: {p.name} stores no "
                                   "sampling rate"))
    # samples
    data: dict[str, np.ndarray] = {}
    for c in selected:
        v = np.ascontiguousarray(raw.channels[c], dtype=np.float64).ravel()
        if v.size == 0:
            problems.append(InputError(f"{p.name}: {c}", "0 samples", "must hold >= 1 sample"))
            continue
        data[c] = v
    dropped: dict[str, DroppedSamples] = {}
    if drop_nonfinite:
        data, dropped = _drop(p, raw, data, problems)
    else:
        for c, v in data.items():
            bad = np.flatnonzero(~np.isfinite(v))
            if bad.size:
                problems.append(_nonfinite_problem(p, raw, c, v, int(bad[0]), int(bad.size),
                                                   interior=False))
    raise_all(problems)
    units = {c: raw.units.get(c) for c in data}
    return Record(data=data, fs=None if rate is None else float(rate), path=str(p), fmt=kind,
                  fs_source=None if rate is None else source,
                  units=units, metadata=dict(raw.metadata), available=tuple(raw.channels),
                  compression=compression, dropped=dropped)


def read_record(
    path: str | Path,
    *,
    channels: Sequence[str] | None = None,
    fs: float | None = None,
    fmt: str | None = None,
    drop_nonfinite: bool = False,
) -> Record:
    """Read every channel (or the chosen ones) of a measured or simulated record.

    Parameters
    ----------
    path : str or Path
        File to read; plain, or gzip/bz2/xz/single-member zip compressed (recognised
        from the content, see the module notes).
    channels : sequence of str, optional
        Channels to read, in this order (a single name is accepted); by default every
        channel of the file, in file order, without aliases (e.g. the TDMS
        ``"group/channel"`` of a unique ``"channel"``).
    fs : float, optional
        Sampling rate (Hz), used when the file stores none (else the record's ``fs`` is
        None), checked against the file (:data:`FS_MATCH_RTOL`) when it does.
    fmt : str, optional
        Format key of :data:`FORMATS`; by default from the extension of the (inner)
        file name.
    drop_nonfinite : bool, optional
        Drop leading and trailing runs of non-finite samples and report them in
        :attr:`Record.dropped` instead of refusing the record (interior ones are still
        refused; see the module notes).

    Returns
    -------
    Record

    Raises
    ------
    InputError
        Missing, empty, corrupt or unreadable file; a zip of several members; unknown
        format. :class:`ReadProblems` (an ``InputError``) when several of these are
        found together: missing channels, a disagreeing sampling rate, channels of
        different rates, a channel of zero samples, non-finite samples.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "rec.csv").write_text("# fs: 25.6 kHz\\n# rpm = 1480\\nacc;tacho\\n"
    ...                                "0,5;1\\n-0,25;0\\n")
    >>> r = read_record(d / "rec.csv")
    >>> r.channels, r.fs, r.metadata["rpm"], r.data["acc"].tolist()
    (('acc', 'tacho'), 25600.0, 1480.0, [0.5, -0.25])
    """
    return _read(path, channels, fs, fmt, drop_nonfinite, single=False)


def read_signal(
    path: str | Path,
    *,
    channel: str | None = None,
    fs: float | None = None,
    fmt: str | None = None,
    drop_nonfinite: bool = False,
) -> MeasuredSignal:
    """Read one channel and its sampling rate from a measured or simulated record.

    Parameters
    ----------
    path : str or Path
        File to read (plain or compressed, see :func:`read_record`).
    channel : str, optional
        Channel name; may be omitted only when the file holds exactly one channel.
    fs : float, optional
        Sampling rate (Hz); required when the file stores none, checked against the file
        (:data:`FS_MATCH_RTOL`) when it does.
    fmt : str, optional
        Format key of :data:`FORMATS`; by default from the extension.
    drop_nonfinite : bool, optional
        Drop leading and trailing non-finite runs (see :func:`read_record`).

    Returns
    -------
    MeasuredSignal

    Raises
    ------
    InputError
        Missing, empty or unreadable file; unknown format; channel missing or not
        named when the file has several; no or non-finite samples; no sampling rate, or
        a given ``fs`` that disagrees with the file's. Several problems are reported
        together (:class:`ReadProblems`).
    """
    rec = _read(path, None if channel is None else [channel], fs, fmt, drop_nonfinite,
                single=True)
    return rec.signal(rec.channels[0])
