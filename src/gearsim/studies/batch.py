"""Batches of measured records: one row per file and channel, indicators as columns.

:func:`run_batch` reads every file (all channels by default), runs the tiered analysis
(:func:`gearsim.signals.tiers.analyze_record`) on each channel, and returns the table as
an :class:`xarray.Dataset` along ``record`` (coordinates ``file``, ``channel``, ``label``;
one variable per indicator, its unit in ``attrs["units"]``). Problems of every file are
collected and raised together in one :class:`~gearsim.errors.InputError`.

With labels (a CSV ``file,channel,label`` or ``file,label``, or a regular expression with
one group applied to the file names) :func:`separability` scores each indicator alone
(ROC AUC and its direction, the class against the healthy reference) and all together
(logistic regression cross-validated with every file's channels in one fold,
:func:`gearsim.studies.diagnostic.separability`); the operating point's columns (shaft
and mesh frequencies) are left out of both.

Parallel runs: ``workers > 1`` or a ``scheduler`` address runs one task per file on Dask
(a ``LocalCluster`` as in :mod:`gearsim.studies.sweep_run`: at most one worker per file
to compute and per CPU core, workers that ignore Ctrl-C).

Resume (``out`` given, as ``gearsim analyze --out`` does, serial or on Dask): the rows of
every file analysed without a problem are written atomically to ``OUT.parts/<key>.json``
as soon as the file is done; ``key`` (:func:`part_key`) hashes the file's absolute path,
size and modification time, the analysis options and the gearsim version, so a rerun
skips every finished file and recomputes a file that changed (or all of them under other
options). A file with a problem gets no part. The table is built from the parts, so a
resumed batch writes the same table as an uninterrupted one. ``OUT.lock``
(:func:`gearsim.studies.sweep_run.store_lock`) refuses a second batch on the same
``OUT``; the parts are kept (delete ``OUT.parts`` by hand).
"""

from __future__ import annotations

import csv
import functools
import glob
import hashlib
import io
import json
import math
import os
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gearsim.errors import InputError

if TYPE_CHECKING:  # the model is imported where a stored configuration is read
    from gearsim.model import Gearbox

__all__ = [
    "problems_error",
    "Batch",
    "analyze_file",
    "is_vibration",
    "expand_inputs",
    "labels_from_csv",
    "labels_from_pattern",
    "part_of",
    "part_key",
    "records_table",
    "run_batch",
    "separability",
    "table_csv",
    "write_table",
]

#: Columns of the table that are not indicators.
KEY_COLUMNS = ("file", "channel", "label", "units", "fs_provenance", "speed_provenance",
               "teeth_provenance")


def expand_inputs(items: Sequence[str | Path]) -> tuple[list[str], list[str]]:
    """Files named by paths and glob patterns, in order, without duplicates.

    Parameters
    ----------
    items : sequence of str or Path
        File paths or glob patterns (``*``, ``?``, ``[...]``, ``**``).

    Returns
    -------
    files : list of str
        Matching files, each once.
    problems : list of str
        One line per pattern matching nothing or path that is not a file.
    """
    files: list[str] = []
    problems: list[str] = []
    seen: set[str] = set()
    for item in items:
        text = str(item)
        if any(c in text for c in "*?["):
            hits = sorted(p for p in glob.glob(text, recursive=True) if Path(p).is_file())
            if not hits:
                problems.append(f"{text}: the pattern matches no file")
        elif Path(text).is_file():
            hits = [text]
        else:
            problems.append(f"{text}: does not exist or is not a regular file")
            hits = []
        for h in hits:
            if h not in seen:
                seen.add(h)
                files.append(h)
    return files, problems


def labels_from_csv(path: str | Path) -> dict[tuple[str, str | None], str]:
    """Read labels: a CSV with a header ``file,label`` or ``file,channel,label``.

    Parameters
    ----------
    path : str or Path
        The CSV file; ``file`` may be a path or a bare file name.

    Returns
    -------
    dict
        ``(file, channel or None)`` to label.

    Raises
    ------
    InputError
        A missing file, a header without ``file`` and ``label``, or an empty label.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError("--labels", str(p), "does not exist or is not a regular file")
    rows = list(csv.DictReader(io.StringIO(p.read_text(encoding="utf-8-sig"))))
    if not rows or not {"file", "label"} <= set(rows[0]):
        raise InputError("--labels", str(p), "must be a CSV with a header file,label or "
                         "file,channel,label and at least one row")
    out: dict[tuple[str, str | None], str] = {}
    for i, r in enumerate(rows, start=2):
        f, lab = (r.get("file") or "").strip(), (r.get("label") or "").strip()
        if not f or not lab:
            raise InputError(f"--labels line {i}", str(r), "needs a file and a label")
        ch = (r.get("channel") or "").strip() or None
        out[(f, ch)] = lab
    return out


def labels_from_pattern(files: Sequence[str], pattern: str) -> tuple[dict[str, str], list[str]]:
    """Labels from the file names by a regular expression with one group.

    Parameters
    ----------
    files : sequence of str
        File paths; the pattern is searched in the file name (without folder).
    pattern : str
        Regular expression with exactly one capturing group, e.g. ``"^(healthy|faulty)_"``.

    Returns
    -------
    labels : dict
        File to label.
    problems : list of str
        One line per file the pattern does not match.

    Raises
    ------
    InputError
        An invalid expression or one without exactly one group.
    """
    try:
        rx = re.compile(pattern)
    except re.error as exc:
        raise InputError("--label-pattern", pattern, f"is not a regular expression: {exc}") \
            from None
    if rx.groups != 1:
        raise InputError("--label-pattern", pattern, f"must have exactly one group "
                         f"(it has {rx.groups})")
    labels: dict[str, str] = {}
    problems = []
    for f in files:
        m = rx.search(Path(f).name)
        if m is None or not m.group(1):
            problems.append(f"{f}: --label-pattern {pattern} does not match its name")
        else:
            labels[f] = m.group(1)
    return labels, problems


def _label_of(labels: Mapping | None, file: str, channel: str) -> str | None:
    if not labels:
        return None
    name = Path(file).name
    for key in ((file, channel), (name, channel), (file, None), (name, None), file, name):
        if key in labels:
            return labels[key]
    return None


def is_vibration(channel: str, units: str | None) -> bool:
    """Whether a channel is analysed by default: not a tacho pulse train (``tacho``, a
    gearsim result's ``tacho[shaft=...]``) nor an angle (units ``rad``: ``carrier_angle``).

    Parameters
    ----------
    channel : str
        Channel name as in the file.
    units : str or None
        Its units, if the file gives them.

    Returns
    -------
    bool
        True for a vibration record (accelerations, forces, torques, displacements).
    """
    return not (channel == "tacho" or channel.startswith("tacho[") or units == "rad")


def _read_channels(path: str, channels, fs, fmt, drop_nonfinite, tacho,
                   own_tachos: bool = True) -> list[dict]:
    """Channels of one file (one :func:`~gearsim.io.measured.read_record`): per channel
    ``{"channel", "data", "fs", "fs_source", "units", "tacho", "planetary", "rpm",
    "teeth", "stages", "config", "dropped"}`` (``rpm``, ``teeth`` and a compound train's
    ``stages`` from the file: a gearsim result's input speed and tooth counts; ``config``
    the configuration of a result written before results held their stages); ``fs``
    None when neither the file nor the user gives a rate; a run-up's own tachos
    (:func:`_own_tachos`) and how its speed changes (``speed_change``, the reader's)
    only with ``own_tachos`` (no speed given by the user)."""
    from gearsim.io.measured import read_record
    from gearsim.io.record import raise_all

    extra = [tacho] if tacho else []
    want = None if channels is None else list(dict.fromkeys([*channels, *extra]))
    try:  # one message for every problem; a missing tacho named as such
        rec = read_record(path, channels=want, fs=fs, fmt=fmt, drop_nonfinite=drop_nonfinite)
    except InputError as exc:
        raise_all([InputError("tacho", p.value, p.limit) if p.parameter == "channel"
                   and p.value == tacho else p for p in getattr(exc, "problems", None) or (exc,)])
        raise
    data, meta, name = rec.data, rec.metadata, Path(path).name
    if tacho is not None and tacho not in data:
        raise InputError("tacho", tacho, f"not in {name}; available: {list(data)}")
    chosen = list(channels) if channels is not None else \
        [n for n in data if n != tacho and is_vibration(n, rec.units.get(n))]
    if tacho is not None and (tacho in chosen or len(data) == 1):
        raise InputError("tacho", tacho, "is also a channel to analyse: a tacho is not "
                         "analysed as vibration" if chosen else f"is the only channel of "
                         f"{name}: no vibration channel is left to analyse")
    if not chosen:
        raise InputError("channel", "default", f"{name} holds no vibration channel (a tacho "
                         f"or an angle is analysed only when named): give --channel, one of "
                         f"{list(data)}")
    for c in chosen:
        _check_tacho_shaft(tacho, c, meta)
    own = _own_tachos(path, chosen, meta, fs, fmt) if tacho is None and own_tachos else {}
    change = meta.get("speed_change") if tacho is None and own_tachos else None
    return [{"channel": c, "data": data[c], "fs": rec.fs,
             "fs_source": {"file": "file", "user": "given"}.get(rec.fs_source),
             "units": rec.units.get(c),
             "tacho": own[c][1] if c in own else data.get(tacho),
             "own_tacho": own[c][0] if c in own else None, "speed_change": change,
             "shafts": _shafts(c, meta), **part_of(c, meta),
             "dropped": rec.dropped[c].to_dict() if c in rec.dropped else None} for c in chosen]


def _labels(channel: str) -> list[str]:
    """The labels of ``var[dim=label,...]`` or ``var[label,...]`` (none for ``var``)."""
    label = channel.partition("[")[2]
    return [v.partition("=")[2] if "=" in v else v
            for v in label.rstrip("]").split(",")] if label else []


def _part(channel: str, parts: Mapping) -> tuple[str, Mapping]:
    """The part of a stage result (its ``analysis_parts``) a record belongs to:
    ``("chain", chain)`` for the gears beside the stages
    (:func:`~gearsim.dynamics.compose.chain_of_record`), else ``("stage", stage)``
    (:func:`~gearsim.dynamics.compose.stage_of_label`)."""
    from gearsim.dynamics.compose import chain_of_record, stage_of_label

    values = _labels(channel)  # "var[dim=label,...]" or the labels alone
    chains = parts["chains"]
    k = chain_of_record(channel.partition("[")[0], values[0] if values else None,
                        [c["shafts"] for c in chains], [c["meshes"] for c in chains],
                        [c.get("between", False) for c in chains])
    if k is not None:
        return "chain", chains[k]
    return "stage", parts["stages"][stage_of_label(values[0] if values else "",
                                                   len(parts["stages"]))]


def _shafts(channel: str, meta: Mapping) -> list[str]:
    """The shafts of the part of a gearsim result ``channel`` is a record of, by the names
    of their tachos, the reference first: a gear train's in power-flow order, the gears'
    beside a stage, a stage's reference member alone; empty for another file (or a stage
    result written before its stages named their tachos)."""
    if parts := meta.get("parts"):
        kind, part = _part(channel, parts)
        return list(part["shafts"]) if kind == "chain" else [part["tacho"]] \
            if part.get("tacho") else []
    return list(meta.get("tacho_shafts") or ())


def _reference_shaft(channel: str, meta: Mapping) -> str | None:
    """The shaft a record of a gearsim result is analysed at, by the name of its tacho
    (``tacho[shaft=NAME]``): a gear train's input, the first shaft of the gears beside a
    stage, a stage's reference member; ``None`` for another file (:func:`_shafts`)."""
    return next(iter(_shafts(channel, meta)), None)


def _name_shafts(skipped: list[dict], names: Sequence[str]) -> None:
    """The skip reasons with the analysis' shaft labels (``shaft1``, ``shaft shaft3``, in
    :func:`~gearsim.signals.analysis.kinematics`' order) as the result's shaft names
    ``names`` (``shaft mast``), where known."""
    def name(m: re.Match) -> str:
        j = int(m[1]) - 1
        return f"shaft {names[j]}" if j < len(names) else m[0]

    for s in skipped:
        s["reason"] = re.sub(r"\b(?:shaft )?shaft(\d+)\b", name, s["reason"])


def _check_tacho_shaft(tacho: str | None, channel: str, meta: Mapping) -> None:
    """Refuse the tacho of one shaft of a gearsim result for a record whose speed
    reference is another shaft (:func:`_reference_shaft`).

    The analysis takes the tacho's speed as that of the record's reference shaft, whose
    teeth and stages the file gives: another shaft's tacho would put every mesh
    frequency at the wrong speed without a word (the reducer's input record with the
    intermediate shaft's tacho: stage 1 at 384 Hz instead of 960 Hz).

    Raises
    ------
    InputError
        ``tacho``: naming the tacho to give instead.
    """
    if tacho is None or not tacho.startswith("tacho["):
        return
    shaft = (_labels(tacho) or [""])[0]
    ref = _reference_shaft(channel, meta)
    if ref is not None and shaft != ref:
        raise InputError("tacho", tacho, f"pulses once a revolution of shaft {shaft}, but "
                         f"{channel} is analysed at the speed of shaft {ref} (its teeth and "
                         f"stages are counted from there): give --tacho 'tacho[{ref}]'")


def _own_tachos(path: str, chosen: list[str], meta: Mapping, fs, fmt) -> dict[str, tuple]:
    """For a gearsim result of a run whose speed changes, each record's own tacho:
    ``{channel: (tacho name, pulses)}`` for the records whose reference shaft's tacho
    (:func:`_reference_shaft`) has a changing period (the reader's ``varying_tachos``,
    :data:`gearsim.io.measured.RUN_UP_TOL`); empty, without reading anything more, for
    a constant-speed run or another file. The file's nominal speed would smear every
    line of a run-up; the file's own tacho follows it."""
    from gearsim.io.measured import read_record

    varying = set(meta.get("varying_tachos", ()))
    refs = {c: r for c in chosen if not c.startswith("tacho[")
            and (r := _reference_shaft(c, meta)) in varying}
    if not refs:
        return {}
    names = sorted({f"tacho[shaft={r}]" for r in refs.values()})
    rec = read_record(path, channels=names, fs=fs, fmt=fmt)
    return {c: (f"tacho[shaft={r}]", rec.data[f"tacho[shaft={r}]"]) for c, r in refs.items()}


def part_of(channel: str, meta: Mapping) -> dict:
    """What a gearsim result says of the part of the gearbox ``channel`` is a record of:
    ``{"planetary", "rpm", "teeth", "stages", "config"}``. Of a stage result (its
    ``analysis_parts``), a record of stage k
    (:func:`~gearsim.dynamics.compose.stage_of_label`) takes stage k's planetary
    description and reference member's speed and teeth, a record of a gear chain beside
    the stages (:func:`~gearsim.dynamics.compose.chain_of_record`) that chain's first
    shaft, teeth and stages (of gears whose power branches, those of the path to the
    record's shaft, their ``paths``), as :meth:`gearsim.model.Gearbox.reference` chooses; any
    record of another result the file's speed and teeth.

    Parameters
    ----------
    channel : str
        The record's name in the file.
    meta : Mapping
        The file's metadata (:func:`gearsim.io.measured.read_record`).

    Returns
    -------
    dict
        ``planetary``, ``rpm`` [rpm] or None, ``teeth``, ``stages``, ``config``.
    """
    parts = meta.get("parts")
    if not parts:
        rpm = meta.get("rpm")
        return {"planetary": meta.get("planetary"),
                "rpm": float(rpm) if isinstance(rpm, (int, float)) and rpm > 0 else None,
                "teeth": meta.get("teeth"), "stages": meta.get("stages"),
                "config": meta.get("config")}
    kind, part = _part(channel, parts)
    teeth = part["teeth"]
    if kind == "chain":  # of gears whose power branches, the record's path
        planetary = None
        labels = _labels(channel)
        shaft = (labels[0].rpartition(".")[0] if channel.startswith("q[") else labels[0]
                 ) if labels else part["shafts"][0]  # q[dof=shaft.axis]: its shaft's
        path = part.get("paths", {}).get(shaft, {})
        teeth = path.get("teeth", teeth)
        stages = path.get("stages") if path else part["stages"]
        stages = tuple(map(tuple, stages)) if stages else None
    else:
        planetary, stages = part, None
    f = float(part["frequency"])
    return {"planetary": planetary, "rpm": 60.0 * f if f > 0 else None,
            "teeth": list(teeth), "stages": stages, "config": None}


def analyze_file(path: str, *, channels: Sequence[str] | None = None, fs: float | None = None,
                 fmt: str | None = None, speed: float | None = None, tacho: str | None = None,
                 pulses_per_rev: int = 1, speed_search: tuple[float, float] | None = None,
                 teeth: Sequence[int] | None = None, settings: Any = None,
                 drop_nonfinite: bool = False, keep_analysis: bool = False,
                 stage: Sequence[int] | None = None,
                 stages: Sequence[tuple[int, int]] | None = None,
                 provenance: Mapping[str, str] | None = None,
                 ) -> tuple[list[Any], list[str]]:
    """Read one file and analyse each of its channels (a Dask task of :func:`run_batch`).

    Parameters
    ----------
    path : str
        The record file.
    channels : sequence of str, optional
        Channels to analyse; default the vibration channels (:func:`is_vibration`: not
        ``tacho``, the tachos nor the angles).
    fs : float, optional
        Sampling rate [Hz] when the file stores none (checked against it otherwise).
    fmt : str, optional
        Format key of :data:`gearsim.io.measured.FORMATS`.
    speed : float, optional
        Measured-shaft speed [Hz].
    tacho : str, optional
        Tacho channel of the measured shaft.
    pulses_per_rev : int
        Tacho pulses per revolution.
    speed_search : tuple of float, optional
        ``(low, high)`` [Hz] to estimate the speed from each channel.
    teeth : sequence of int, optional
        Tooth counts, gear on the measured shaft first.
    settings : AnalysisSettings, optional
        Options of the gear tier.
    drop_nonfinite : bool
        Drop non-finite samples instead of refusing the file (if the reader supports it).
    keep_analysis : bool
        Return :class:`~gearsim.signals.tiers.RecordAnalysis` objects (with arrays) rather
        than their dicts.
    stage : sequence of int, optional
        ``(z_sun, z_planet, z_ring, planets)`` of a planetary stage with the ring held;
        the measured shaft (``speed``, ``tacho``) is then the carrier. A gearsim stage
        result (NetCDF) brings its own stage and carrier speed, used when this is None.
    stages : sequence of (int, int), optional
        A compound train instead of ``teeth``: ``(driving teeth, driven teeth)`` of each
        stage, stage 1's driving gear on the measured shaft; every stage's mesh is
        analysed in the gear tier (:func:`~gearsim.signals.tiers.analyze_record`). A
        gearsim result of a compound train brings its own (``analysis_stages``), used
        when neither ``teeth`` nor ``stages`` is given.
    provenance : mapping, optional
        Where ``speed`` (key ``"speed"``), ``teeth`` or ``stages`` (``"teeth"``) and
        ``stage`` (``"stage"``) come from when not from the file (``"config"``: a
        gearbox's kinematics, ``gearsim analyze --config``); default: given. Key
        ``"config"``: that gearbox as written, named in the record's ``source`` and in a
        warning when the record disagrees with its speed.

    Returns
    -------
    results : list
        Per channel: ``RecordAnalysis`` (``keep_analysis``) or a dict with
        ``record`` (``to_dict()``) and ``features``.
    problems : list of str
        One line per problem (the file is then left out).
    """
    from gearsim.signals.tiers import analyze_record

    said = provenance or {}
    # a speed the user gives (not a gearbox's nominal one) is used instead of a run-up's
    # own tacho; a configuration's nominal speed gives way to it
    given = speed_search is not None or (speed is not None and said.get("speed") != "config")
    try:
        chans = _read_channels(path, channels, fs, fmt, drop_nonfinite, tacho,
                               own_tachos=not given)
    except InputError as exc:
        return [], [_problem(path, exc)]
    out, problems = [], []
    # a gearsim result brings its tooth counts, and a compound train's its stages
    # (of the part of the gearbox each channel is a record of: part_of)
    own = teeth is None and stages is None and any(ch.get("teeth") for ch in chans)
    for ch in chans:
        # a run whose speed changes over the record, no speed given: never its nominal
        # speed; its reference shaft's own tacho, or no speed (shaft and gear tiers
        # skipped) when that tacho holds too few pulses to follow it
        run = ch.get("speed_change")
        file_rpm = ch.get("rpm") if speed is None and tacho is None and speed_search is None \
            and not run else None
        file_teeth = ch.get("teeth") if own else None
        own_stages = _file_stages(ch) if file_teeth else None
        route = _path_kinematics(ch["config"], ch["channel"]) if file_teeth and isinstance(
            ch.get("config"), str) else None
        if route is not None:  # gears whose power branches: the record's path
            train = {k: list(v) for k, v in route.items()}
        elif file_teeth:
            train = {"stages": own_stages} if own_stages else {"teeth": file_teeth}
        else:
            train = {"stages": stages} if stages is not None else {"teeth": teeth}
        src = {"file": path, "channel": ch["channel"]}
        if said.get("speed") == "config" and said.get("config"):  # whose speed is used
            src["config"] = said["config"]
        if ch.get("own_tacho"):  # a run whose speed changes: the file's own tacho
            src["tacho"] = ch["own_tacho"]
        if ch.get("dropped"):
            src["dropped"] = ch["dropped"]
        try:
            spec = _stage_spec(stage, ch, speed if stage is not None or given else None,
                               said.get("stage"))
            ch_speed = None if run else speed  # the run-up's tacho, or none
            rec = analyze_record(
                ch["data"], ch["fs"], speed=file_rpm / 60.0 if file_rpm else ch_speed,
                speed_provenance="file" if file_rpm else said.get("speed"),
                tacho=ch["tacho"], pulses_per_rev=pulses_per_rev, speed_search=speed_search,
                **train, teeth_provenance="file" if file_teeth else said.get("teeth"),
                settings=settings, fs_provenance=ch["fs_source"],
                source=src, units=ch["units"], stage=None if run else spec,
            )
        except InputError as exc:
            problems.append(_problem(f"{path} [{ch['channel']}]", exc))
            continue
        if run:
            _run_skips(rec, ch, spec)
        elif spec is None and (pl := ch.get("planetary")):  # a ring that turns
            rec.skipped.append({"tier": "planetary", "reason": "reads a sensor on a held ring; "
                                f"this stage's ring turns at {abs(pl['ring_frequency']):.5g} "
                                "Hz" + (" (its carrier held)" if pl["carrier_frequency"] == 0
                                        else "")})
        if file_teeth:  # the result's shaft names: its path's, else the reference's
            n = len(train["stages"]) + 1 if train.get("stages") else len(train["teeth"])
            names = ch["shafts"] if route is None and len(ch["shafts"]) == n else \
                ch["shafts"][:1]
            _name_shafts(rec.skipped, names)
        if not keep_analysis:
            rec = {"record": rec.to_dict(), "features": rec.features()}
        out.append(rec)
    return out, problems


def _run_skips(rec: Any, ch: dict, spec: Any) -> None:
    """The reasons a record of a run whose speed changes (``ch["speed_change"]``) has no
    shaft and gear tiers (its reference shaft's tacho holds too few pulses to follow the
    speed; the file's nominal speed is not used) and no planetary tier (a
    constant-speed analysis; ``spec``, the stage it would have read, not given)."""
    again = "give --shaft-rpm to analyse it at one speed"
    if not ch.get("own_tacho"):
        nominal = f"{ch['rpm']:.6g} rpm" if ch.get("rpm") else "speed"
        why = (f"{ch['speed_change']}, and the tacho of its reference shaft "
               f"{(ch['shafts'] or [''])[0]} holds too few pulses in it (3 needed) to follow "
               f"that: the file's nominal {nominal} is not used; {again}")
        for s in rec.skipped:
            if s["tier"] == "shaft":
                s["reason"] = why
    if spec is not None:
        rec.skipped.append({"tier": "planetary", "reason": f"a constant-speed analysis, and "
                            f"{ch['speed_change']}; {again} (the carrier's)"})


def _file_stages(ch: dict) -> tuple[tuple[int, int], ...] | None:
    """The stages of a gearsim result of a compound gear train (a channel of
    :func:`_read_channels`), else None: its ``analysis_stages`` attribute as the reader
    gave it, or for a result written before that attribute, the stages of its stored
    configuration (:meth:`gearsim.model.Gearbox.analysis_stages`)."""
    if ch.get("stages"):
        return tuple(ch["stages"])
    return _config_stages(ch["config"]) if isinstance(ch.get("config"), str) else None


@functools.lru_cache(maxsize=8)
def _config_gearbox(text: str) -> Gearbox | None:
    """The :class:`gearsim.model.Gearbox` of a stored configuration, read once for every
    channel of its file; None when this version cannot read it."""
    from gearsim.model import loads

    try:
        return loads(text)
    except Exception:  # a configuration this version cannot read: the teeth as they are
        return None


def _config_stages(text: str) -> tuple[tuple[int, int], ...] | None:
    """:meth:`gearsim.model.Gearbox.analysis_stages` of a stored configuration, None when
    this version cannot read it."""
    gb = _config_gearbox(text)
    return None if gb is None else gb.analysis_stages()


def _path_kinematics(text: str, channel: str) -> dict[str, tuple] | None:
    """Of a stored gear train whose power branches, the stages or teeth of the path from
    the input to the shaft of ``channel`` (:meth:`gearsim.system.GearTrain.
    path_kinematics`); None for any other gearbox or a configuration this version cannot
    read."""
    gb = _config_gearbox(text)
    return None if gb is None else gb.record_path(channel)


def _stage_spec(stage: Sequence[int] | None, ch: dict, speed: float | None,
                provenance: str | None = None):
    """The planetary tier's stage: given (``--stage`` or a configuration, ``provenance``;
    the speed is the carrier's) or the file's (a gearsim stage result with the ring
    held; at ``speed`` when given, the carrier's); None when neither applies."""
    from gearsim.signals.planetary_tier import StageSpec

    if stage is not None:
        if speed is None:
            raise InputError("--stage", ",".join(map(str, stage)), "needs the carrier speed "
                             "(--shaft-rpm; the measured shaft is the carrier)")
        zs, zp, zr, n = stage
        return StageSpec(zs, zp, zr, n, carrier_frequency=speed,
                         provenance=provenance or "given")
    meta = ch.get("planetary")
    if not meta or meta["ring_frequency"] != 0.0 or meta["carrier_frequency"] <= 0:
        return None
    return StageSpec(meta["z_sun"], meta["z_planet"], meta["z_ring"], meta["planets"],
                     carrier_frequency=speed or meta["carrier_frequency"],
                     carrier_phase=meta["carrier_phase"], sensor_angle=meta["sensor_angle"],
                     provenance="file")


#: Reader parameters -> the options of ``gearsim analyze`` that set them: a problem found
#: while reading a file names the option the user typed.
READER_OPTIONS = {"channel": "--channel", "fs": "--fs", "fmt": "--format", "teeth": "--teeth",
                  "tacho": "--tacho"}


def _problem(where: str, exc: InputError) -> str:
    parts = getattr(exc, "problems", None) or (exc,)
    text = "; ".join(str(InputError(READER_OPTIONS.get(p.parameter, p.parameter), p.value,
                                    p.limit)) for p in parts)
    return text if where in text or Path(where).name in text else f"{where}: {text}"


@dataclass
class Batch:
    """Records of a batch and the problems met (from :func:`collect`).

    Parameters
    ----------
    records : list
        ``RecordAnalysis`` objects or their dicts (``record``, ``features``).
    labels : list of str or None
        Label of each record (None when unlabelled).
    problems : list of str
        Problems of every file, one line each.
    mode : str
        How the batch ran (``"serial"``, ``"dask local N workers"``, ``"dask scheduler"``).
    resumed : int
        Files read back from finished parts (``OUT.parts``) rather than analysed.
    """

    records: list = field(default_factory=list)
    labels: list = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    mode: str = "serial"
    resumed: int = 0

    def raise_problems(self) -> None:
        """Raise one :class:`InputError` listing every problem, if there is any.

        Raises
        ------
        InputError
            ``input = N problems: first; second; ...``.
        """
        if self.problems:
            raise problems_error(self.problems)


def problems_error(problems: Sequence[str]) -> InputError:
    """One :class:`InputError` for every problem of a call.

    Parameters
    ----------
    problems : sequence of str
        Lines ``PARAMETER = VALUE: LIMIT`` (or free text).

    Returns
    -------
    InputError
        A single problem as itself (``--plot = figs: ...``); several as
        ``input = N problems: first; second; ...``.
    """
    if len(problems) == 1:
        m = re.fullmatch(r"(.+?) = (.*?): (.+)", problems[0])
        if m:
            return InputError(m.group(1), m.group(2), m.group(3))
    n = len(problems)
    return InputError("input", f"{n} problem{'s' if n != 1 else ''}", "; ".join(problems))


def _as_dict(r) -> dict:
    return r if isinstance(r, dict) else {"record": r.to_dict(), "features": r.features()}


def collect(files: Sequence[str], *, labels: Mapping | None = None, workers: int = 1,
            scheduler: str | None = None, keep_analysis: bool = False,
            out: str | Path | None = None, hook: Callable[[str, Path], None] | None = None,
            note: Callable[[str], None] | None = None, **options: Any) -> Batch:
    """Analyse every file; gather records, labels and problems (never raises for a file).

    With ``out`` the batch resumes from ``OUT.parts`` and writes a part per finished file
    (see the module notes); the caller holds ``OUT``'s lock
    (:func:`gearsim.studies.sweep_run.store_lock`) and writes the table.

    Parameters
    ----------
    files : sequence of str
        Record files.
    labels : mapping, optional
        Labels by file, file name, ``(file, channel)`` or ``(file name, channel)``.
    workers : int
        Local Dask worker processes; 1 runs serially in this process.
    scheduler : str, optional
        Address of a running Dask scheduler.
    keep_analysis : bool
        Keep the :class:`~gearsim.signals.tiers.RecordAnalysis` objects (serial, no
        ``out``).
    out : str or Path, optional
        The table to be written: parts go to ``OUT.parts/`` and records are dicts.
    hook : callable, optional
        Called as ``hook(file, part)`` after each part is written (tests interrupt here).
    note : callable, optional
        Called with a one-line note (fewer local workers than asked).
    **options
        Keyword arguments of :func:`analyze_file`.

    Returns
    -------
    Batch
        Records (file order, then channel order), labels, problems, run mode.
    """
    batch = Batch()
    if out is not None:
        results, batch.mode, batch.resumed = _run_parts(files, workers, scheduler, options,
                                                        Path(out), hook, note)
    elif workers == 1 and scheduler is None:
        results = [analyze_file(f, keep_analysis=keep_analysis, **options) for f in files]
    else:
        results: list = [None] * len(files)
        batch.mode = _run_dask(files, list(range(len(files))), workers, scheduler, options,
                               results.__setitem__, note)
    for recs, probs in results:
        batch.problems.extend(probs)
        for r in recs:
            d = _as_dict(r)
            src = d["record"]["source"]
            lab = _label_of(labels, src["file"], src["channel"])
            if labels and lab is None:
                batch.problems.append(f"{src['file']} [{src['channel']}]: no label")
            batch.records.append(r)
            batch.labels.append(lab)
    return batch


def _run_dask(files, todo, workers, scheduler, options, done, note=None) -> str:
    """Analyse ``files[i]`` for ``i`` in ``todo`` on Dask; ``done(i, result)`` as each ends.

    The cluster is shut down quietly however the run ends (Ctrl-C included); returns the
    run mode.
    """
    import dask
    from distributed import as_completed

    from gearsim.studies.sweep_run import (
        ALLOWED_FAILURES,
        _connect,
        _shutdown,
        _start_local,
        check_scheduler,
        plan_workers,
    )

    live: dict = {}
    with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES}):
        try:
            if scheduler is not None:
                _connect(check_scheduler(scheduler), live)
                mode = f"dask scheduler {scheduler}"
            else:
                n, msg = plan_workers(workers, len(todo), "file")
                if msg is not None and note is not None:
                    note(msg)
                _start_local(n, None, live)
                mode = f"dask local {n} worker{'s' if n != 1 else ''}"
            client = live["client"]
            futures = {client.submit(analyze_file, files[i], pure=False, **options): i
                       for i in todo}
            for fut in as_completed(futures):
                done(futures[fut], fut.result())
                fut.release()
            return mode
        finally:
            _shutdown(live.get("client"), live.get("cluster"))


#: Layout of the part files (part of every :func:`part_key`).
PART_FORMAT = 1


def _option_text(value: Any) -> str:
    if isinstance(value, (list, tuple)):
        return repr(tuple(value))
    return repr(value)


def part_key(path: str | Path, options: Mapping[str, Any]) -> str:
    """Name of a file's part in ``OUT.parts``: a hash of what its rows depend on.

    Parameters
    ----------
    path : str or Path
        The record file (its absolute path, size and modification time enter the key).
    options : mapping
        Keyword arguments of :func:`analyze_file` (their ``repr``; lists as tuples).

    Returns
    -------
    str
        32 hexadecimal characters (SHA-256 prefix), also over the gearsim version and
        :data:`PART_FORMAT`.

    Raises
    ------
    OSError
        The file cannot be examined (``os.stat``).
    """
    from gearsim._version import __version__

    st = os.stat(path)
    doc = {"file": os.path.abspath(path), "size": st.st_size, "mtime_ns": st.st_mtime_ns,
           "options": {k: _option_text(v) for k, v in options.items()},
           "gearsim": __version__, "format": PART_FORMAT}
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:32]


def _jsonable(v: Any) -> Any:
    """``json.dumps`` default: numpy scalars and arrays as Python values (NaN kept)."""
    import numpy as np

    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    raise TypeError(f"{type(v).__name__} is not JSON serialisable")


def _part_text(file: str, records: Sequence) -> str:
    return json.dumps({"format": PART_FORMAT, "file": file,
                       "records": [_as_dict(r) for r in records]}, default=_jsonable)


def _part_records(text: str, file: str) -> list | None:
    """Records of a part's text, their ``source.file`` set to ``file`` (None if invalid)."""
    try:
        doc = json.loads(text)
        records = doc["records"]
        if doc.get("format") != PART_FORMAT or not isinstance(records, list):
            return None
        for r in records:
            r["record"]["source"]["file"] = file  # the path as given in this run
    except (ValueError, KeyError, TypeError):
        return None
    return records


def _run_parts(files, workers, scheduler, options, out: Path, hook, note
               ) -> tuple[list, str, int]:
    """Analyse the files not finished in ``OUT.parts``; each new part written as it ends.

    Returns the ``(records, problems)`` of every file in order, the run mode and the
    number of files resumed.
    """
    from gearsim.io.atomic import atomic_write
    from gearsim.studies.sweep_run import parts_dir

    pdir = parts_dir(out)
    results: list = [None] * len(files)
    keys: list = []
    for i, f in enumerate(files):
        try:
            keys.append(part_key(f, options))
        except OSError:  # vanished meanwhile: analyze_file reports it
            keys.append(None)
            continue
        part = pdir / f"{keys[i]}.json"
        if part.is_file():
            try:
                recs = _part_records(part.read_text(encoding="utf-8"), f)
            except OSError:
                recs = None
            if recs is not None:
                results[i] = (recs, [])
    todo = [i for i, r in enumerate(results) if r is None]
    resumed = len(files) - len(todo)

    def done(i: int, result: tuple[list, list[str]]) -> None:
        recs, probs = result
        text = _part_text(files[i], recs)
        # the records as read back from a part: a resumed table equals a fresh one
        results[i] = (_part_records(text, files[i]), probs)
        if not probs and keys[i] is not None:
            part = atomic_write(pdir / f"{keys[i]}.json",
                                lambda t: t.write_text(text, encoding="utf-8"))
            if hook is not None:
                hook(files[i], part)

    mode = "serial"
    if not todo:
        mode = "resumed"
    elif workers == 1 and scheduler is None:
        for i in todo:
            done(i, analyze_file(files[i], **options))
    else:
        mode = _run_dask(files, todo, workers, scheduler, options, done, note)
    return results, mode, resumed


def records_table(records: Sequence, labels: Sequence | None = None):
    """The batch table: rows = file x channel, one variable per indicator.

    Parameters
    ----------
    records : sequence
        ``RecordAnalysis`` objects or dicts with ``record`` and ``features``.
    labels : sequence of str, optional
        Label per record.

    Returns
    -------
    xarray.Dataset
        Dimension ``record``; coordinates ``file``, ``channel``, ``label``; variables
        ``units``, provenance columns and every indicator (float, NaN where not computed;
        ``periodicity_verdict`` as text), each with ``attrs["units"]``.
    """
    import numpy as np
    import xarray as xr

    names, cols, units = _columns(records, labels)
    n = len(records)
    ds = xr.Dataset(coords={"record": np.arange(n)})
    for k in ("file", "channel", "label"):
        ds = ds.assign_coords({k: ("record", np.asarray(cols[k], dtype=str))})
    for k in names:
        if k in ("file", "channel", "label"):
            continue
        vals = cols[k]
        if k in KEY_COLUMNS or any(isinstance(v, str) for v in vals):
            arr = np.asarray(["" if v is None else str(v) for v in vals], dtype=str)
        else:
            arr = np.asarray([math.nan if v is None else v for v in vals], dtype=float)
        ds[k] = ("record", arr, {"units": units.get(k, "")} if units.get(k) else {})
    ds.attrs["title"] = "gearsim analyze batch"
    ds.attrs["amplitude_units"] = "signal units: see the units variable of each record"
    return ds


def _columns(records, labels) -> tuple[list[str], dict[str, list], dict[str, str]]:
    dicts = [_as_dict(r) for r in records]
    labels = list(labels) if labels is not None else [None] * len(dicts)
    names = list(KEY_COLUMNS)
    units: dict[str, str] = {}
    for d in dicts:
        for k, (_, u) in d["features"].items():
            if k not in units:
                units[k] = u
                names.append(k)
    cols: dict[str, list] = {k: [] for k in names}
    for d, lab in zip(dicts, labels, strict=True):
        rec = d["record"]
        key = {"file": rec["source"]["file"], "channel": rec["source"]["channel"],
               "label": lab or "", "units": rec.get("units") or "",
               "fs_provenance": rec.get("fs_provenance") or "",
               "speed_provenance": rec.get("speed_provenance") or "",
               "teeth_provenance": rec.get("teeth_provenance") or ""}
        for k in names:
            cols[k].append(key[k] if k in key else d["features"].get(k, (None, ""))[0])
    return names, cols, units


def table_csv(records: Sequence, labels: Sequence | None = None) -> str:
    """The batch table as CSV text; indicator headers carry their unit, ``rms [signal]``.

    Parameters
    ----------
    records : sequence
        ``RecordAnalysis`` objects or dicts with ``record`` and ``features``.
    labels : sequence of str, optional
        Label per record.

    Returns
    -------
    str
        Header and one line per record; empty cells where a tier was skipped.
    """
    names, cols, units = _columns(records, labels)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([f"{k} [{units[k]}]" if units.get(k) else k for k in names])
    for i in range(len(records)):
        row = []
        for k in names:
            v = cols[k][i]
            row.append("" if v is None else (f"{v:.10g}" if isinstance(v, float) else v))
        w.writerow(row)
    return buf.getvalue()


def write_table(records: Sequence, labels: Sequence | None, path: str | Path) -> Path:
    """Write the table atomically as CSV (``.csv``) or NetCDF (``.nc``).

    Parameters
    ----------
    records : sequence
        ``RecordAnalysis`` objects or dicts with ``record`` and ``features``.
    labels : sequence of str or None
        Label per record.
    path : str or Path
        Target, checked beforehand with :func:`gearsim.io.targets.check_output_file`.

    Returns
    -------
    Path
        The file written.
    """
    from gearsim.io.atomic import atomic_write

    p = Path(path)
    if p.suffix.lower() == ".nc":
        ds = records_table(records, labels)
        from gearsim.io.results import write_results

        return write_results(ds, p)
    text = table_csv(records, labels)
    return atomic_write(p, lambda t: t.write_text(text))


def separability(records: Sequence, labels: Sequence[str], *, folds: int | None = None,
                 seed: int = 0, healthy: str | None = None) -> dict[str, Any]:
    """How well the indicators separate the labelled classes.

    The classifier's folds are grouped by file when a file gives several rows (its
    channels): no record is predicted by a model trained on another channel of it.

    Parameters
    ----------
    records : sequence
        ``RecordAnalysis`` objects or dicts with ``record`` and ``features``.
    labels : sequence of str
        Class of each record (at least two classes).
    folds : int, optional
        Folds of the stratified cross-validation (default
        :data:`gearsim.studies.diagnostic.FOLDS`).
    seed : int
        Seed of the fold shuffle.
    healthy : str, optional
        The reference class (``--healthy``; default: the label that names a healthy
        state, :func:`gearsim.studies.diagnostic.reference_class`).

    Returns
    -------
    dict
        See :func:`gearsim.studies.diagnostic.separability_report`.

    Raises
    ------
    InputError
        Fewer than two classes, or a ``healthy`` that is not among the labels.
    """
    from threadpoolctl import threadpool_limits

    from gearsim.studies.diagnostic import FOLDS, separability_report

    names, cols, _ = _columns(records, labels)
    feats = {k: cols[k] for k in names if k not in KEY_COLUMNS
             and not any(isinstance(v, str) for v in cols[k])}
    # one BLAS thread: the L-BFGS fits of a few hundred rows make only small BLAS calls,
    # where OpenBLAS's other threads spin (0.78 s of CPU against 0.13 s for the 80 rows of
    # the 20 SpectraQuest records; the report is the same to the last digit)
    with threadpool_limits(limits=1, user_api="blas"):
        return separability_report(feats, list(labels), folds=folds or FOLDS, seed=seed,
                                   healthy=healthy, groups=cols["file"], group_name="file")


def run_batch(files: Sequence[str | Path], *, channels: Sequence[str] | None = None,
              fs: float | None = None, fmt: str | None = None, speed: float | None = None,
              tacho: str | None = None, pulses_per_rev: int = 1,
              speed_search: tuple[float, float] | None = None,
              teeth: Sequence[int] | None = None,
              stages: Sequence[tuple[int, int]] | None = None, settings: Any = None,
              drop_nonfinite: bool = False, labels: Mapping | str | Path | None = None,
              label_pattern: str | None = None, healthy: str | None = None,
              workers: int = 1,
              scheduler: str | None = None,
              progress: Callable[[str], None] | None = None, out: str | Path | None = None,
              hook: Callable[[str, Path], None] | None = None):
    """Analyse many records; the table of indicators (rows = file x channel).

    With ``out`` the batch is resumable (``OUT.parts``, see the module notes) and the
    table is written to ``out`` under its lock.

    Parameters
    ----------
    files : sequence of str or Path
        Files or glob patterns.
    channels : sequence of str, optional
        Channels to analyse in every file; default the vibration channels
        (:func:`is_vibration`: not ``tacho``, the tachos nor the angles).
    fs : float, optional
        Sampling rate [Hz] for files that store none.
    fmt : str, optional
        Format key, default from each extension.
    speed : float, optional
        Speed of the measured shaft [Hz].
    tacho : str, optional
        Tacho channel name.
    pulses_per_rev : int
        Tacho pulses per revolution.
    speed_search : tuple of float, optional
        ``(low, high)`` [Hz]: estimate the speed from each record.
    teeth : sequence of int, optional
        Tooth counts, gear on the measured shaft first.
    stages : sequence of (int, int), optional
        A compound train instead of ``teeth``: ``(driving teeth, driven teeth)`` of each
        stage (:func:`analyze_file`); the records are analysed with them in this process
        and on Dask workers alike.
    settings : AnalysisSettings, optional
        Options of the gear tier.
    drop_nonfinite : bool
        Drop non-finite samples instead of refusing the file.
    labels : mapping or path, optional
        Labels (mapping, or CSV path for :func:`labels_from_csv`).
    label_pattern : str, optional
        Regular expression with one group on the file names (instead of ``labels``).
    healthy : str, optional
        The reference class of the separability report (:func:`separability`).
    workers : int
        Local Dask workers; 1 runs serially in this process.
    scheduler : str, optional
        Address of a Dask scheduler.
    progress : callable, optional
        Called with one-line notes (fewer local workers than asked).
    out : str or Path, optional
        Table to write (``.csv`` or ``.nc``, :func:`write_table`); parts in
        ``OUT.parts/``, lock ``OUT.lock``.
    hook : callable, optional
        ``hook(file, part)`` after each part is written (see :func:`collect`).

    Returns
    -------
    xarray.Dataset
        :func:`records_table` of the batch; ``attrs["separability"]`` holds the JSON of
        :func:`separability` when labels were given; ``attrs["resumed"]`` the files read
        back from parts.

    Raises
    ------
    InputError
        Every problem of every file (and of the labels), in one message; an ``out``
        being written by another batch.
    """
    from contextlib import nullcontext

    if out is not None:
        from gearsim.io.targets import check_output_file
        from gearsim.studies.sweep_run import store_lock

        out = check_output_file(out, "--out", (".csv", ".nc"))
    names, problems = expand_inputs(files)
    lab: Mapping | None = None
    if label_pattern is not None:
        lab, more = labels_from_pattern(names, label_pattern)
        problems += more
    elif labels is not None:
        lab = labels if isinstance(labels, Mapping) else labels_from_csv(labels)
    if healthy is not None and lab:  # before any file is read
        from gearsim.studies.diagnostic import reference_class

        reference_class(sorted(set(lab.values())), healthy, "healthy")
    with store_lock(out, owner="batch") if out is not None else nullcontext():
        batch = collect(names, labels=lab, workers=workers, scheduler=scheduler, out=out,
                        hook=hook, note=progress, channels=channels, fs=fs, fmt=fmt,
                        speed=speed, tacho=tacho, pulses_per_rev=pulses_per_rev,
                        speed_search=speed_search, teeth=teeth, settings=settings,
                        drop_nonfinite=drop_nonfinite,
                        # only when given: the part keys of simple batches stay as they were
                        **({"stages": stages} if stages is not None else {}))
        batch.problems[:0] = problems
        batch.raise_problems()
        ds = records_table(batch.records, batch.labels if lab else None)
        ds.attrs["mode"] = batch.mode
        ds.attrs["resumed"] = batch.resumed
        if lab:
            ds.attrs["separability"] = json.dumps(separability(batch.records, batch.labels,
                                                               healthy=healthy))
        if out is not None:
            write_table(batch.records, batch.labels if lab else None, out)
    return ds
