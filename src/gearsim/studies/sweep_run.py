"""Run a parameter study on Dask, resumably, into one labelled NetCDF store.

Design (see ``docs/studies.md``, "Parameter sweeps"):

* The cases of :func:`gearsim.studies.sweep.expand` are grouped by simulation
  (:meth:`Study.simulation_key`); a *batch* of consecutive groups is one Dask task
  (:func:`batch_bytes`: :func:`gearsim.studies.sweep_case.run_batch`, the rows of
  :func:`~gearsim.studies.sweep_case.run_group` of each group in one table), so that the
  per-task costs (scheduling, transfer, a part file, its decoding) are paid once per
  batch: :func:`plan_batch` gives each worker about
  :data:`BATCH_TASKS_PER_WORKER` tasks of at most :data:`BATCH_MAX` groups, or the
  user's ``batch``.
* The worker encodes a batch's table as bytes (:mod:`gearsim.io.npzset`: ``.npz``, far
  cheaper than NetCDF for such small tables); the client writes them atomically
  (temporary file + rename) as its own part file: ``STORE.parts/<simulation key>.npz``
  for one group, ``STORE.parts/batch-<hash of its keys>.npz`` for several (attribute
  ``groups``: the simulation keys it holds). Keys hash the case parameters and the study
  fingerprint (base config, dynamics overrides, analysed signal, seed), so a restarted
  study skips every group some part holds whole (its rows are found by ``case_key``),
  and a changed study never reuses a stale part.
* When all groups are done the parts are concatenated in case order into ``STORE``
  (atomic write), with the study TOML text, the gearsim version and the case counts as
  attributes. The parts are kept (delete ``STORE.parts`` by hand), so extending a grid
  recomputes only the new cases.
* A worker that dies mid-task is replaced by the nanny and the task (its whole batch)
  rescheduled by the scheduler (``distributed.scheduler.allowed-failures``, set to
  :data:`ALLOWED_FAILURES` for the local cluster); an exception raised by a task is
  retried :data:`RETRIES` times. Errors inside a case are recorded, not raised.
"""

from __future__ import annotations

import logging
import os
import re
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from gearsim._version import __version__
from gearsim.errors import InputError, ModelRangeWarning, SimulationError
from gearsim.io.atomic import atomic_write
from gearsim.io.results import write_results
from gearsim.io.targets import check_output_file

if TYPE_CHECKING:  # the simulation modules load on first use (gearsim analyze needs none)
    from gearsim.studies.sweep import Case, Study

__all__ = ["ALLOWED_FAILURES", "BATCH_MAX", "BATCH_PREFIX", "BATCH_TASKS_PER_WORKER",
           "CONNECT_TIMEOUT", "PART_SUFFIX", "RETRIES", "SweepResult", "batch_bytes",
           "batch_path", "batches", "check_batch", "check_scheduler", "check_workers",
           "cluster_client", "cluster_pays", "combine", "group_runner", "groups",
           "join_tables", "lock_path", "part_bytes", "part_groups", "part_path", "parts_dir",
           "plan_batch", "plan_workers", "read_part", "run_serial", "run_study", "store_lock"]

#: Worker deaths a task may cause before the scheduler gives up on it (local cluster).
ALLOWED_FAILURES = 3
#: Retries of a task that raised (``Client.submit(retries=...)``).
RETRIES = 2
#: Wall-clock cost of a local cluster of two worker processes [s]: its start and its
#: first tasks' imports (gearsim, the numba cache) measured 4.4-5.1 s, its shutdown
#: ~1 s more, on the 2-core machine with another job running. A study whose remaining
#: work a cluster would shorten by less runs in this process (``run_study(adaptive=True)``).
CLUSTER_START_S = 5.0
#: How long to wait for a remote scheduler (``--scheduler``).
CONNECT_TIMEOUT = "10s"
#: Suffix of a part file (:func:`part_path`; :mod:`gearsim.io.npzset` archives).
PART_SUFFIX = ".npz"
#: Name prefix of a part file holding several simulation groups (:func:`batch_path`).
BATCH_PREFIX = "batch-"
#: Most simulation groups a Dask task runs when the batch size is automatic
#: (:func:`plan_batch`): bounds the work a lost worker or a Ctrl-C loses and the idle time
#: of the other workers while the last batch runs (32 Table-1 cases: ~4 s).
BATCH_MAX = 32
#: Tasks per worker the automatic batch size aims at (:func:`plan_batch`).
BATCH_TASKS_PER_WORKER = 10
#: Seconds the local cluster's workers may take to start, and to be spawned.
WORKER_START_TIMEOUT = 120.0
SPAWN_WAIT = 10.0
_ADDRESS = re.compile(r"(?:(?P<scheme>tcp|tls|ucx|ws|wss|inproc)://)?"
                      r"(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):(?P<port>\d{1,5})/?")


@dataclass(frozen=True)
class SweepResult:
    """What :func:`run_study` did.

    Parameters
    ----------
    store : Path
        The combined NetCDF store.
    n_cases : int
        Cases in the study.
    computed : int
        Cases computed in this run.
    skipped : int
        Cases found finished in ``STORE.parts`` and not recomputed.
    failed : int
        Cases whose status is not ``"ok"``.
    """

    store: Path
    n_cases: int
    computed: int
    skipped: int
    failed: int


def groups(study: Study, cases: Sequence[Case] | None = None) -> dict[str, list[Case]]:
    """Cases grouped by simulation key, in order of first appearance.

    Parameters
    ----------
    study : Study
        The study.
    cases : sequence of Case, optional
        Cases to group; default :func:`gearsim.studies.sweep.expand` of ``study``.

    Returns
    -------
    dict of str to list of Case
        :meth:`Study.simulation_key` -> the cases that share that simulation.
    """
    from gearsim.studies.sweep import expand

    out: dict[str, list[Case]] = {}
    for c in expand(study) if cases is None else cases:
        out.setdefault(study.simulation_key(c), []).append(c)
    return out


def group_runner(study: Study) -> Callable:
    """The function that runs one simulation group of ``study``.

    Parameters
    ----------
    study : Study
        The study.

    Returns
    -------
    callable
        ``(study, cases, hook) -> xarray.Dataset``:
        :func:`gearsim.studies.sweep_case.run_group` (every gearbox).
    """
    from gearsim.studies.sweep_case import run_group

    return run_group


def parts_dir(store: str | Path) -> Path:
    """Folder of the per-group part files of ``store``: ``STORE.parts``.

    Parameters
    ----------
    store : str or Path
        The study store, e.g. ``sweep.nc``.

    Returns
    -------
    Path
        ``sweep.nc.parts`` beside the store (not created here).
    """
    store = Path(store)
    return store.with_name(store.name + ".parts")


def _write_nc(ds, path: str | Path) -> Path:
    return write_results(ds, path)


def part_bytes(study: Study, cases: Sequence[Case], hook: Callable | None = None) -> bytes:
    """Run a group (:func:`gearsim.studies.sweep_case.run_group`'s table) and encode it as
    part bytes.

    The table is encoded by :func:`gearsim.io.npzset.to_bytes` (``.npz``, no HDF5): a
    part is written and read once, by gearsim; as NetCDF a 64-variable part cost ~0.25 s
    to write and ~0.14 s to read, more than the case's analysis (measured,
    ``benchmarks/bench_sweep.py``). The store stays NetCDF (:func:`run_study`). The same
    as :func:`batch_bytes` of one group.

    Parameters
    ----------
    study : Study
        The study.
    cases : sequence of Case
        One simulation group (equal :meth:`Study.simulation_key`).
    hook : callable, optional
        Passed to :func:`run_group` (fault injection in tests).

    Returns
    -------
    bytes
        The group's table; its simulation key in the attribute ``groups`` (a list of one),
        the messages of the warnings the group raised (once each) in ``warnings``.
    """
    return batch_bytes(study, [cases], hook)


def batch_bytes(study: Study, batch: Sequence[Sequence[Case]],
                hook: Callable | None = None) -> bytes:
    """Run several groups and encode their table as one part (the Dask task).

    The groups run one after the other into one table
    (:func:`gearsim.studies.sweep_case.run_batch`: the rows of :func:`run_group` of each
    group, as :func:`join_tables` joins them), encoded once
    (:func:`gearsim.io.npzset.to_bytes`).

    Parameters
    ----------
    study : Study
        The study.
    batch : sequence of sequence of Case
        Simulation groups (each of equal :meth:`Study.simulation_key`), at least one.
    hook : callable, optional
        Called with each group's cases before its work (fault injection in tests).

    Returns
    -------
    bytes
        The table of every case of the batch; attribute ``groups``: the simulation keys of
        the groups, in order; ``warnings``: the messages of the warnings the groups
        raised, once each (absent if none).
    """
    import numba

    from gearsim.io.npzset import to_bytes
    from gearsim.studies.sweep_case import run_batch

    # a task is one core's work: numba's threaded kernels (the tooth-compliance batches)
    # stay on this thread (the setting is this thread's), as the other cores run tasks too
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        with warnings.catch_warnings(record=True) as caught:  # not on the worker's stderr:
            ds = run_batch(study, batch, hook)  # the client says them (run_study)
    finally:
        numba.set_num_threads(threads)
    ds.attrs["groups"] = [study.simulation_key(cases[0]) for cases in batch]
    if caught:
        ds.attrs["warnings"] = "\n".join(dict.fromkeys(
            f"{w.category.__name__}\t{' '.join(str(w.message).split())}" for w in caught))
    return to_bytes(ds)


def check_batch(batch: int | None) -> int | None:
    """The ``--batch`` of ``gearsim sweep`` (simulation groups per Dask task), checked.

    Parameters
    ----------
    batch : int or None
        Groups per task; ``None``: chosen by :func:`plan_batch`.

    Returns
    -------
    int or None
        ``batch`` as an ``int``.

    Raises
    ------
    InputError
        ``--batch``: not an integer >= 1.

    Examples
    --------
    >>> check_batch(8), check_batch(None)
    (8, None)
    >>> try:
    ...     check_batch(0)
    ... except InputError as exc:
    ...     print(exc)
    --batch = 0: must be an integer >= 1 (simulation groups per Dask task)
    """
    if batch is None:
        return None
    if (isinstance(batch, bool) or not isinstance(batch, (int, np.integer))
            or batch < 1):
        raise InputError("--batch", batch,
                         "must be an integer >= 1 (simulation groups per Dask task)")
    return int(batch)


def plan_batch(tasks: int, workers: int, batch: int | None = None) -> int:
    """Simulation groups per Dask task.

    Automatic (``batch`` ``None``): each worker gets about :data:`BATCH_TASKS_PER_WORKER`
    tasks, none of more than :data:`BATCH_MAX` groups (a study of up to
    ``workers * BATCH_TASKS_PER_WORKER`` groups: one group a task, as without batches).
    A given ``batch`` is kept (at most ``tasks``).

    Parameters
    ----------
    tasks : int
        Simulation groups to compute.
    workers : int
        Worker threads that run them (>= 1).
    batch : int, optional
        Groups per task asked for (:func:`check_batch`).

    Returns
    -------
    int
        Groups per task, >= 1.

    Examples
    --------
    >>> plan_batch(2000, 2), plan_batch(300, 2), plan_batch(12, 2), plan_batch(12, 2, 5)
    (32, 15, 1, 5)
    """
    if batch is not None:
        return max(1, min(check_batch(batch), tasks))
    per_task = -(-max(tasks, 1) // (max(workers, 1) * BATCH_TASKS_PER_WORKER))
    return max(1, min(BATCH_MAX, per_task))


def batches(keys: Sequence[str], size: int, workers: int = 0) -> list[list[str]]:
    """``keys`` in consecutive runs of at most ``size``, smaller at the end with ``workers``.

    With ``workers`` > 0 (the automatic batch size), no batch holds more than
    ``1 / (2 workers)`` of the groups not yet handed out, so the last batches shrink to
    one group and the workers finish together (guided self-scheduling) instead of one
    worker running a whole last batch while the others wait.

    Parameters
    ----------
    keys : sequence of str
        Simulation keys, in study order.
    size : int
        Groups per batch (>= 1).
    workers : int
        Worker threads; 0: every batch ``size`` groups (the last one what is left).

    Returns
    -------
    list of list of str

    Examples
    --------
    >>> batches(list("abcde"), 2)
    [['a', 'b'], ['c', 'd'], ['e']]
    >>> [len(b) for b in batches([str(i) for i in range(40)], 8, workers=2)]
    [8, 8, 6, 5, 4, 3, 2, 1, 1, 1, 1]
    """
    out: list[list[str]] = []
    i = 0
    while i < len(keys):
        n = size if workers <= 0 else max(1, min(size, -(-(len(keys) - i) // (2 * workers))))
        out.append(list(keys[i:i + n]))
        i += n
    return out


def part_path(store: str | Path, key: str) -> Path:
    """The part file of simulation group ``key`` of ``store``.

    Parameters
    ----------
    store : str or Path
        The study store.
    key : str
        :meth:`Study.simulation_key` of the group.

    Returns
    -------
    Path
        ``STORE.parts/<key>.npz``.
    """
    return parts_dir(store) / f"{key}{PART_SUFFIX}"


def batch_path(store: str | Path, keys: Sequence[str]) -> Path:
    """The part file of a batch of simulation groups of ``store``.

    Parameters
    ----------
    store : str or Path
        The study store.
    keys : sequence of str
        :meth:`Study.simulation_key` of its groups, in order.

    Returns
    -------
    Path
        :func:`part_path` for one group; ``STORE.parts/batch-<hash of the keys>.npz`` for
        several.
    """
    return parts_dir(store) / f"{_batch_name(keys)}{PART_SUFFIX}"


def _batch_name(keys: Sequence[str]) -> str:
    """The name of a batch's part file without its suffix: the key of a single group."""
    import hashlib

    keys = list(keys)
    if len(keys) == 1:
        return keys[0]
    return BATCH_PREFIX + hashlib.sha256("\n".join(keys).encode()).hexdigest()[:16]


def read_part(path: str | Path):
    """Read a part file written from :func:`part_bytes` or :func:`batch_bytes` bytes.

    Parameters
    ----------
    path : str or Path
        A part file (:func:`part_path`, :func:`batch_path`).

    Returns
    -------
    xarray.Dataset or None
        The table of its groups; ``None`` if the file cannot be read or is not a part (its
        groups are then recomputed).
    """
    from gearsim.io.npzset import from_bytes

    try:
        return from_bytes(Path(path).read_bytes())
    except (OSError, ValueError):  # unreadable part: recompute it (atomic writes: never)
        return None


def part_groups(part, path: str | Path) -> list[str]:
    """The simulation keys of the groups a part holds.

    Parameters
    ----------
    part : xarray.Dataset
        A part (:func:`read_part`).
    path : str or Path
        Its file: a part written before batches (no attribute ``groups``) holds the group
        its name says.

    Returns
    -------
    list of str
        The attribute ``groups``, else the file name without :data:`PART_SUFFIX`.
    """
    held = part.attrs.get("groups")
    if held is None:
        name = Path(path).name
        return [name[:-len(PART_SUFFIX)] if name.endswith(PART_SUFFIX) else name]
    return [held] if isinstance(held, str) else [str(k) for k in held]


def combine(study: Study, parts: Sequence, keys: Sequence[str] | None = None):
    """Concatenate group tables in case order into the study store (an ``xr.Dataset``).

    Variables missing from a part (features of a failed group, its record) are filled
    with NaN or an empty string. The tables are joined array by array (each variable's
    parts concatenated along ``case`` once and put in case order): the same dataset as
    ``xarray.concat`` along ``case`` followed by ``sortby("case")`` (tested), which
    cost ~6 ms a part (12 s for a 2000-case study) where this costs ~0.2 ms.

    Parameters
    ----------
    study : Study
        The study (its text, config and name go into the attributes).
    parts : sequence of xarray.Dataset
        Group tables of :func:`run_group` (features one variable each), any order; a part
        may hold several groups (:func:`batch_bytes`).
    keys : sequence of str, optional
        The ``case_key`` of every case of the study, in case order: the rows are then
        taken by key (the first row of each key; rows of other keys are left out, as
        the groups of a part resumed from another grid) and ``case`` numbered 0, 1, ...
        in that order. Default: every row, sorted by ``case``.

    Returns
    -------
    xarray.Dataset
        All cases sorted by ``case``; attributes ``title``, ``study``, ``config``,
        ``gearsim_version``, ``n_cases``, ``n_ok``, ``n_failed``, ``signal``,
        ``features``.

    Raises
    ------
    ValueError
        Parts that differ in their coordinates or in the shape of a record (the groups
        of one study share both); a key of ``keys`` that no part holds.
    """
    ds = join_tables(parts, keys)
    status = ds["status"].values
    ds.attrs = {
        "title": f"gearsim parameter study: {study.name}",
        "study": study.text,
        "config": study.config_text,
        "gearsim_version": __version__,
        "n_cases": int(ds.sizes["case"]),
        "n_ok": int(np.sum(status == "ok")),
        "n_failed": int(np.sum(status != "ok")),
        "signal": study.signal,
        "features": "see gearsim.studies.sweep_case.features",
    }
    return ds


def join_tables(parts: Sequence, keys: Sequence[str] | None = None):
    """Group tables joined along ``case`` (:func:`combine` without the study's attributes).

    Parameters
    ----------
    parts : sequence of xarray.Dataset
        Tables of :func:`run_group` or parts of :func:`batch_bytes`, at least one.
    keys : sequence of str, optional
        As in :func:`combine`.

    Returns
    -------
    xarray.Dataset
        The rows sorted by ``case`` (or in the order of ``keys``); no attributes.

    Raises
    ------
    ValueError
        As :func:`combine`.
    """
    parts = list(parts)
    names: dict[str, tuple] = {}
    sample_time = None
    for p in parts:
        table = p.variables  # Variables: no DataArray made per access
        for k in p.data_vars:
            if k not in names:
                v = table[k]
                names[k] = (v.dims, v.dtype, v.shape[1:], v.attrs)
        if "sample_time" in p.coords and sample_time is None:
            sample_time = p["sample_time"]
    ds = _join_arrays(parts, names, keys)
    if sample_time is not None:
        ds = ds.assign_coords(sample_time=sample_time)
    return ds


def _fill(dims_dtype_tail: tuple, n: int) -> np.ndarray:
    """The values of a variable a part of ``n`` cases lacks: NaN, or empty text."""
    _, dtype, tail, _ = dims_dtype_tail
    return np.full((n, *tail), np.nan if dtype.kind == "f" else "", dtype=dtype)


def _join_arrays(parts: list, names: dict, keys: Sequence[str] | None = None):
    """:func:`combine`'s join, array by array.

    Raises ``ValueError`` when the parts differ in their coordinates or in the shape of
    a record: the groups of one study share both (xarray's join refuses them too); or
    when a key of ``keys`` is in no part.
    """
    import xarray as xr

    first = parts[0]
    coords = sorted(c for c in first.coords if c != "sample_time")
    tables = [p.variables for p in parts]  # Variables: no DataArray made per access
    for p, v in zip(parts, tables, strict=True):
        own = sorted(c for c in p.coords if c != "sample_time")
        if own != coords or any(v[c].dims != ("case",) for c in coords):
            raise ValueError(f"study parts differ in their coordinates: {own} against "
                             f"{coords} (each along case)")
    for k, spec in names.items():
        for v in tables:
            if k in v and (v[k].dims != spec[0] or v[k].shape[1:] != spec[2]):
                raise ValueError(f"study parts differ in the shape of {k!r}: "
                                 f"{v[k].dims} {v[k].shape[1:]} against {spec[0]} {spec[2]}")
    sizes = [p.sizes["case"] for p in parts]
    if keys is None:
        order = np.argsort(np.concatenate([v["case"].values for v in tables]), kind="stable")
    else:  # the first row of each key, in the order of the keys
        row_of: dict[str, int] = {}
        for i, k in enumerate(np.concatenate([v["case_key"].values for v in tables]).tolist()):
            row_of.setdefault(k, i)
        missing = [k for k in keys if k not in row_of]
        if missing:
            raise ValueError(f"study parts lack {len(missing)} case(s), e.g. case_key "
                             f"{missing[0]!r}")
        order = np.array([row_of[k] for k in keys], dtype=np.intp)

    def joined(name: str, spec: tuple | None) -> np.ndarray:
        arrays = [v[name].values if name in v else _fill(spec, n)
                  for v, n in zip(tables, sizes, strict=True)]
        return np.concatenate(arrays)[order]

    # the first part's variables in its order, then those only later parts have
    variables = list(first.data_vars) + [k for k in names if k not in first.data_vars]
    # attributes of the first part's variable (xarray.concat's rule): none if it lacks it
    data = {k: xr.Variable(names[k][0], joined(k, names[k]),
                           first.variables[k].attrs if k in first.data_vars else {})
            for k in variables}
    coord_vars = {c: xr.Variable(("case",), joined(c, None), first.variables[c].attrs)
                  for c in first.coords if c != "sample_time"}
    if keys is not None:  # numbered as the study numbers its cases now
        case = coord_vars["case"]
        coord_vars["case"] = xr.Variable(("case",), np.arange(len(keys), dtype=case.dtype),
                                         case.attrs)
    return xr.Dataset(data, coords=coord_vars)


def run_serial(study: Study, *, hook: Callable | None = None):
    """Run every group in a plain loop (no Dask, no files); return the combined Dataset.

    Parameters
    ----------
    study : Study
        The study.
    hook : callable, optional
        Passed to :func:`run_group` (fault injection in tests).

    Returns
    -------
    xarray.Dataset
        As :func:`combine`; not written to disk.
    """
    run = group_runner(study)
    return combine(study, [run(study, cs, hook) for cs in groups(study).values()])


def _progress(total: int, done: int, enabled: bool):
    """A rich progress bar on standard error (or a no-op)."""
    if not enabled:
        return None
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    prog = Progress(TextColumn("sweep"), BarColumn(), MofNCompleteColumn(),
                    TextColumn("cases"), TimeElapsedColumn(), TimeRemainingColumn(),
                    console=Console(file=sys.stderr))
    task = prog.add_task("cases", total=total, completed=done)
    prog.start()
    return prog, task


def check_scheduler(address: str) -> str:
    """Check the form of a Dask scheduler address before connecting to it.

    Parameters
    ----------
    address : str
        ``tcp://host:port`` (or ``tls://``, ``ucx://``, ``ws://``, ``wss://``, ``inproc://``)
        or ``host:port``; the host a name, an IPv4 address or a bracketed IPv6 address.

    Returns
    -------
    str
        The address, stripped of surrounding blanks.

    Raises
    ------
    InputError
        Any other form, or a port outside 1-65535.

    Examples
    --------
    >>> check_scheduler("tcp://10.0.0.5:8786")
    'tcp://10.0.0.5:8786'
    """
    text = address.strip() if isinstance(address, str) else ""
    m = _ADDRESS.fullmatch(text)
    if m is None:
        raise InputError("--scheduler", address, "must be a scheduler address, "
                         "tcp://host:port or host:port (e.g. tcp://127.0.0.1:8786)")
    if m.group("scheme") != "inproc" and not 1 <= int(m.group("port")) <= 65535:
        raise InputError("--scheduler", address, "port must be in 1-65535")
    return text


def plan_workers(requested: int, tasks: int, what: str = "simulation group",
                 ) -> tuple[int, str | None]:
    """Local worker processes for ``tasks`` simulation groups: at most one per group or core.

    Parameters
    ----------
    requested : int
        Workers asked for (``--workers``), >= 1.
    tasks : int
        Simulation groups (or other tasks) still to compute.
    what : str
        Name of one task in the note, e.g. ``"file"`` for ``gearsim analyze``.

    Returns
    -------
    n : int
        ``min(requested, tasks, os.cpu_count())``, at least 1.
    note : str or None
        A one-line note when ``n < requested``, else ``None``.

    Raises
    ------
    InputError
        ``requested`` is not an integer >= 1.
    """
    if isinstance(requested, bool) or not isinstance(requested, int) or requested < 1:
        raise InputError("--workers", requested, "must be an integer >= 1")
    cores = os.cpu_count() or 1
    n = max(1, min(requested, tasks, cores))
    if n >= requested:
        return n, None
    why = (f"{tasks} {what}{'s' if tasks != 1 else ''} to compute"
           if n == max(1, tasks) and tasks < cores else f"{cores} CPU core{'s' if cores != 1 else ''}")
    return n, f"gearsim: note: --workers {requested} reduced to {n} ({why})"


def check_workers(requested: int | None, tasks: int, what: str) -> int:
    """The ``--workers`` of a verb, refused in one line when it cannot work.

    More workers than the work has tasks (simulations of a study, files of a batch)
    would wait with nothing to do: refused, with the number that would work. ``None``
    (the option not given) is one worker per task and CPU core. More workers than CPU
    cores can run (they share the cores) and are reduced later by :func:`plan_workers`,
    with a note.

    Parameters
    ----------
    requested : int or None
        ``--workers`` as given; ``None``: not given.
    tasks : int
        Tasks of the whole work (a resumed study's finished parts included), >= 1.
    what : str
        Name of one task, e.g. ``"simulation"``, ``"file"``.

    Returns
    -------
    int
        The workers to ask :func:`plan_workers` for.

    Raises
    ------
    InputError
        ``--workers``: not an integer >= 1, or more than ``tasks``.

    Examples
    --------
    >>> check_workers(2, 5, "simulation")
    2
    >>> try:
    ...     check_workers(8, 3, "simulation")
    ... except InputError as exc:
    ...     print(str(exc)[:52])
    --workers = 8: must be <= 3, the simulations to comp
    """
    if requested is None:
        return max(1, min(tasks, os.cpu_count() or 1))
    plan_workers(requested, 1)  # an integer >= 1
    if requested > tasks:
        raise InputError("--workers", requested,
                         f"must be <= {tasks}, the {what}{'s' if tasks != 1 else ''} to "
                         "compute (a worker more would have nothing to do)")
    return requested


def cluster_pays(seconds_left: float, tasks_left: int, workers: int) -> bool:
    """Whether a local cluster shortens the remaining work by more than its start-up.

    ``n`` workers (at most one per remaining task) save ``seconds_left (1 - 1/n)`` of
    the serial time; a cluster costs :data:`CLUSTER_START_S`.

    Parameters
    ----------
    seconds_left : float
        The remaining tasks' time in this process [s] (measured on a first task).
    tasks_left : int
        Remaining tasks.
    workers : int
        Local workers that would run them.

    Returns
    -------
    bool

    Examples
    --------
    >>> cluster_pays(4.0, 10, 2), cluster_pays(40.0, 10, 2)
    (False, True)
    """
    n = min(workers, max(tasks_left, 1))
    return seconds_left * (1.0 - 1.0 / n) > CLUSTER_START_S


def lock_path(store: str | Path) -> Path:
    """Lock file of ``store`` while a sweep writes it: ``STORE.lock`` (holds the pid).

    Parameters
    ----------
    store : str or Path
        The study store.

    Returns
    -------
    Path
    """
    store = Path(store)
    return store.with_name(store.name + ".lock")


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's live process
        return True
    except OSError:
        return False
    return True


@contextmanager
def store_lock(store: str | Path, owner: str = "sweep") -> Iterator[Path]:
    """Hold ``STORE.lock`` (created with ``O_CREAT | O_EXCL``) while writing ``store``.

    The lock file holds the pid of its owner and is removed on exit. A lock whose pid no
    longer runs (a killed sweep) is taken over.

    Parameters
    ----------
    store : str or Path
        The study store (or any output file, e.g. the table of ``gearsim analyze``).
    owner : str
        What writes it, named in the refusal (``"sweep"``, ``"batch"``).

    Yields
    ------
    Path
        The lock file.

    Raises
    ------
    InputError
        Another live process holds the lock.
    """
    lock = lock_path(store)
    lock.parent.mkdir(parents=True, exist_ok=True)
    for _attempt in range(3):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            try:
                text = lock.read_text().strip()
                age = time.time() - lock.stat().st_mtime
            except FileNotFoundError:
                continue  # released meanwhile: try again
            pid = int(text) if text.isdigit() else 0
            if _pid_alive(pid) or (not text and age < 10.0):  # empty: being written now
                raise InputError("--out", str(store), f"is being written by another {owner} "
                                 f"(pid {pid or '?'}; lock file {lock})") from None
            lock.unlink(missing_ok=True)  # stale: its sweep was killed
            continue
        with os.fdopen(fd, "w") as f:
            f.write(f"{os.getpid()}\n")
        break
    else:
        raise InputError("--out", str(store), f"cannot take the lock file {lock}")
    try:
        yield lock
    finally:
        try:
            if lock.read_text().strip() == str(os.getpid()):
                lock.unlink()
        except OSError:
            pass


@contextmanager
def _quiet_distributed() -> Iterator[None]:
    """Silence distributed's loggers (shutdown chatter, interrupted comms)."""
    names = ["distributed", *(n for n in logging.root.manager.loggerDict
                              if n.startswith("distributed."))]
    saved = {n: logging.getLogger(n).level for n in names}
    for n in names:
        logging.getLogger(n).setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for n, level in saved.items():
            logging.getLogger(n).setLevel(level)


def _shutdown(client, cluster) -> None:
    """Close the client and the local cluster quietly (also after Ctrl-C)."""
    with _quiet_distributed(), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for thing in (client, cluster):
            if thing is None:
                continue
            try:
                thing.close()
            except Exception:  # noqa: BLE001  (best effort; the run's outcome is decided)
                pass


def worker_environ() -> dict:
    """Environment of the local worker processes: Dask's, without its malloc trim.

    Dask's nanny starts each worker with ``MALLOC_TRIM_THRESHOLD_=65536`` (config
    ``distributed.nanny.pre-spawn-environ``), so that glibc hands freed memory back to
    the system at once. A case allocates and frees tens of MB of records, which then
    fault their pages in again at every case: on the 2-core machine the workers of a
    300-case Table-1 study spent 9.9 s in the kernel (sys) against 3.2 s with glibc's
    default threshold, and the study took 27.4 s against 24.0 s (docs/studies.md). The
    workers keep the rest of Dask's environment (one BLAS/OpenMP thread).

    Returns
    -------
    dict
        ``distributed.nanny.pre-spawn-environ`` without ``MALLOC_TRIM_THRESHOLD_``.
    """
    import dask

    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {})
    env.pop("MALLOC_TRIM_THRESHOLD_", None)
    return env


def _start_local(workers: int, cluster_kwargs: dict | None, live: dict) -> None:
    """A LocalCluster whose worker processes ignore Ctrl-C (only the client handles it).

    A Ctrl-C in a terminal reaches every process of its process group, the workers too,
    which would die with tracebacks of their own. The cluster starts without workers;
    SIGINT is ignored only while the worker processes are spawned (an ignored signal
    stays ignored across exec, so the workers keep ignoring it), then restored: the
    client is interrupted, and shuts the cluster down. The cluster and client go into
    ``live`` as soon as they exist, so the caller shuts them down wherever an interrupt
    lands.
    """
    import dask
    from distributed import Client, LocalCluster

    # silence_logs: the level of distributed's loggers here and in the workers; their
    # messages at shutdown (tasks cancelled, heartbeats to a closed scheduler) are no news
    # to the user, and a task's own failure reaches the client as its exception
    kw = {"threads_per_worker": 1, "processes": True, "dashboard_address": None,
          "silence_logs": logging.CRITICAL, **(cluster_kwargs or {}), "n_workers": 0}
    with _quiet_distributed(), warnings.catch_warnings():  # the scheduler's HTTP server
        # moves off a busy port 8787 (another cluster) with a warning: no concern of ours
        warnings.filterwarnings("ignore", message=r"Port \d+ is already in use")
        live["cluster"] = cluster = LocalCluster(**kw)
        live["client"] = client = Client(cluster)
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        with dask.config.set({"distributed.nanny.pre-spawn-environ": worker_environ()}):
            cluster.scale(workers)
            deadline = time.monotonic() + SPAWN_WAIT
            while time.monotonic() < deadline:  # until every worker process exists
                nannies = list(cluster.workers.values())
                if len(nannies) >= workers and all(getattr(n, "pid", None) for n in nannies):
                    break
                time.sleep(0.005)
    finally:
        if main:
            signal.signal(signal.SIGINT, previous if previous is not None
                          else signal.default_int_handler)
    try:
        client.wait_for_workers(workers, timeout=WORKER_START_TIMEOUT)
    except TimeoutError:
        raise SimulationError(f"sweep: the local cluster did not start {workers} worker"
                              f"{'s' if workers != 1 else ''} within "
                              f"{WORKER_START_TIMEOUT:g} s") from None


def _connect(address: str, live: dict) -> None:
    from distributed import Client

    try:
        with _quiet_distributed():
            live["client"] = Client(address, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError("--scheduler", address,
                         f"cannot connect within {CONNECT_TIMEOUT}: {_first_line(exc)}") from None


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _scheduler_lost(exc: BaseException, client) -> bool:
    """True when a task's error is the client losing its scheduler (not the case's own
    failure): distributed cancels every future with "scheduler-connection-lost"."""
    from concurrent.futures import CancelledError

    return (isinstance(exc, CancelledError) and "connection-lost" in str(exc)) or \
        getattr(client, "status", "running") in ("closing", "closed", "connecting")


@contextmanager
def cluster_client(workers: int, scheduler: str | None = None,
                   cluster_kwargs: dict | None = None) -> Iterator:
    """A Dask client on a new local cluster or a running scheduler, shut down on exit.

    The machinery of :func:`run_study`: a ``LocalCluster`` of ``workers`` processes
    with one thread each whose workers ignore Ctrl-C (only this process handles it), or
    a client of ``scheduler``; ``distributed.scheduler.allowed-failures`` set to
    :data:`ALLOWED_FAILURES` meanwhile; client and cluster closed quietly whatever
    happens (also after Ctrl-C).

    Parameters
    ----------
    workers : int
        Local worker processes (>= 1; give :func:`plan_workers`' number); ignored with
        ``scheduler``.
    scheduler : str, optional
        Address of a running Dask scheduler (checked by :func:`check_scheduler` first).
    cluster_kwargs : dict, optional
        Extra keyword arguments of ``LocalCluster``.

    Yields
    ------
    distributed.Client

    Raises
    ------
    InputError
        ``--scheduler``: the scheduler cannot be reached within :data:`CONNECT_TIMEOUT`.
    SimulationError
        The local workers did not start within ``WORKER_START_TIMEOUT``.
    """
    import dask
    import distributed  # noqa: F401  (its config defaults before the set below: a
    # section that did not exist when it was set is dropped whole when it is restored)

    live: dict = {}
    with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES}):
        try:
            if scheduler is None:
                _start_local(workers, cluster_kwargs, live)
            else:
                _connect(scheduler, live)
            yield live["client"]
        finally:
            _shutdown(live.get("client"), live.get("cluster"))


def _cases_text(study_cases: list[Case]) -> str:
    """The case numbers of a failed task, for its message (a range for a long batch)."""
    idx = [c.index for c in study_cases]
    if len(idx) <= 8:
        return f"cases {idx}"
    return f"{len(idx)} cases ({idx[0]} ... {idx[-1]})"


def _run_on_dask(study: Study, grouped: dict, todo: list[str], hook: Callable | None,
                 scheduler: str | None, n_workers: int, cluster_kwargs: dict | None,
                 keep: Callable[[list[str], bytes], None], batch: int | None = None) -> None:
    """Run the groups ``todo`` as Dask tasks of :func:`plan_batch` groups each (local
    cluster or ``scheduler``); ``keep`` each batch's part as it arrives; the cluster is
    shut down whatever happens."""
    from distributed import as_completed

    with cluster_client(n_workers, scheduler, cluster_kwargs) as client:
        threads = n_workers if scheduler is None else max(1, sum(client.nthreads().values()))
        size = plan_batch(len(todo), threads, batch)
        futures = {}
        # the automatic size shrinks towards the end (the workers finish together)
        for keys in batches(todo, size, threads if batch is None else 0):
            name = _batch_name(keys)
            futures[client.submit(batch_bytes, study, [grouped[k] for k in keys], hook,
                                  key=f"case-{name}", pure=False, retries=RETRIES)] = keys
        kept = 0
        for fut in as_completed(futures):
            keys = futures[fut]
            try:
                data = fut.result()
            except Exception as exc:
                if _scheduler_lost(exc, client):
                    where = scheduler or "of the local cluster"
                    raise SimulationError(
                        f"sweep: lost the scheduler {where} mid-study: {kept} of the "
                        f"{len(todo)} groups to compute are written; the same command "
                        "resumes from them") from exc
                raise SimulationError(
                    f"sweep: {_cases_text([c for k in keys for c in grouped[k]])} failed "
                    f"after retries: {_first_line(exc)}") from exc
            keep(keys, data)
            kept += len(keys)
            fut.release()


def _finished_parts(store: Path, grouped: dict, case_keys: dict,
                    ) -> tuple[set[str], list[tuple[int, object]]]:
    """The groups of ``grouped`` some part file in ``STORE.parts`` holds whole, and the
    parts that hold them (each group counted in the first such part, by file name), each
    with the position of its first such group in ``grouped``."""
    done: set[str] = set()
    found: list[tuple[int, object]] = []
    position = {k: i for i, k in enumerate(grouped)}
    folder = parts_dir(store)
    if not folder.is_dir():
        return done, found
    for path in sorted(folder.glob(f"*{PART_SUFFIX}")):
        stem = path.name[:-len(PART_SUFFIX)]
        if stem not in grouped and not stem.startswith(BATCH_PREFIX):
            continue  # another study's group (another fingerprint or grid): not read
        part = read_part(path)
        if part is None or "case_key" not in part.coords:
            continue
        have = set(part["case_key"].values.tolist())
        new = [g for g in part_groups(part, path) if g in grouped and g not in done
               and all(k in have for k in case_keys[g])]
        if new:
            done.update(new)
            found.append((min(position[g] for g in new), part))
    return done, found


def run_study(study: Study, store: str | Path, *, scheduler: str | None = None,
              workers: int = 2, progress: bool = True, hook: Callable | None = None,
              cluster_kwargs: dict | None = None,
              note: Callable[[str], None] | None = None, adaptive: bool = True,
              batch: int | None = None) -> SweepResult:
    """Run a study on Dask and write its store; resume from ``STORE.parts`` if present.

    Checks come first (the study's settings were checked when it was read,
    :func:`gearsim.studies.sweep.check_study`): ``workers``, ``batch``, the scheduler
    address, the store path; then the store's lock (``STORE.lock``: a second sweep on the
    same store is refused). The local cluster has at most one worker per group to compute
    and per CPU core. On Ctrl-C (``KeyboardInterrupt``) the client and cluster are shut
    down quietly and the finished parts are kept: the next run resumes from them.

    Parameters
    ----------
    study : Study
        Parsed study (:func:`gearsim.studies.sweep.load_study`).
    store : path
        Final NetCDF store (``.nc``); parts go to ``STORE.parts/``.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``); ``None``: start a
        ``LocalCluster`` of ``workers`` processes with one thread each.
    workers : int
        Number of local worker processes (>= 1; reduced to the groups to compute and
        the CPU cores, see :func:`plan_workers`). One worker runs the groups in this
        process, without a cluster (same parts, same store; no start-up cost).
    progress : bool
        Show a progress bar on standard error.
    hook : callable, optional
        Passed to :func:`run_group` (fault injection in tests).
    cluster_kwargs : dict, optional
        Extra keyword arguments of ``LocalCluster``.
    note : callable, optional
        Called with a one-line note (e.g. fewer workers than asked); default: none.
    adaptive : bool
        With a local cluster of several workers (no ``scheduler``, no ``hook``): run the
        first group here, timed, and start the cluster only if the rest, shared by the
        workers, saves more than its start-up (:data:`CLUSTER_START_S`); else the rest
        runs here too. The parts and the store are the same either way. ``False``:
        always the cluster.
    batch : int, optional
        Simulation groups per Dask task (one part file each, :func:`batch_bytes`);
        default: :func:`plan_batch` (about :data:`BATCH_TASKS_PER_WORKER` tasks per
        worker, at most :data:`BATCH_MAX` groups each). Groups run in this process are
        written one part each. The store is the same whatever the batch.

    Returns
    -------
    SweepResult

    Raises
    ------
    InputError
        Bad ``workers``, ``batch``, scheduler address or store path; a store being
        written by another sweep; a scheduler that cannot be reached.
    SimulationError
        A group failed after its retries.

    Warns
    -----
    UserWarning
        Each distinct warning the groups raised in the workers, once, here in the client
        (a :class:`~gearsim.errors.ModelRangeWarning` as itself).
    """
    from gearsim.io.npzset import from_bytes
    from gearsim.studies.sweep import expand

    plan_workers(workers, 1)  # the type and sign of workers, before anything else
    batch = check_batch(batch)
    if scheduler is not None:
        scheduler = check_scheduler(scheduler)
    store = check_output_file(store, "--out", (".nc",))
    cases = expand(study)
    grouped = groups(study, cases)
    all_keys = [study.case_key(c) for c in cases]  # in case order (Case.index)
    case_keys = {g: [all_keys[c.index] for c in cs] for g, cs in grouped.items()}
    position = {k: i for i, k in enumerate(grouped)}
    with store_lock(store):
        done, parts = _finished_parts(store, grouped, case_keys)
        todo = [k for k in grouped if k not in done]
        skipped = sum(len(grouped[k]) for k in done)
        computed = 0
        if todo:
            n_workers, msg = plan_workers(workers, len(todo))
            if msg is not None and scheduler is None and note is not None:
                note(msg)
            bar = _progress(len(cases), skipped, progress)

            def keep(keys: str | Sequence[str], data: bytes) -> None:
                # written, then decoded here while the workers go on (the store is made
                # from the decoded parts, not read back once the cluster is gone)
                nonlocal computed
                keys = [keys] if isinstance(keys, str) else list(keys)
                atomic_write(batch_path(store, keys), lambda p, d=data: p.write_bytes(d))
                n = sum(len(grouped[k]) for k in keys)
                computed += n
                parts.append((min(position[k] for k in keys), from_bytes(data)))
                if bar is not None:
                    bar[0].advance(bar[1], n)

            def here(keys: list[str]) -> None:
                # a Ctrl-C is remembered as well as raised: where it lands, library code
                # may turn it into a case's failure; a part computed while it arrived is
                # not kept, and the interrupt goes on (the next run computes that group)
                hit = threading.Event()

                def interrupt(signum, frame):
                    hit.set()
                    raise KeyboardInterrupt

                # in the main thread, unless Ctrl-C is ignored (a job in the background)
                main = (threading.current_thread() is threading.main_thread()
                        and signal.getsignal(signal.SIGINT) is not signal.SIG_IGN)
                previous = signal.signal(signal.SIGINT, interrupt) if main else None
                try:
                    for key in keys:
                        try:
                            data = part_bytes(study, grouped[key], hook)
                        except Exception as exc:
                            if hit.is_set():
                                raise KeyboardInterrupt from exc
                            raise SimulationError(
                                f"sweep: cases {[c.index for c in grouped[key]]} failed: "
                                f"{_first_line(exc)}") from exc
                        if hit.is_set():
                            raise KeyboardInterrupt
                        keep(key, data)
                finally:
                    if main:
                        signal.signal(signal.SIGINT, previous)

            try:
                rest = todo
                if scheduler is None and n_workers > 1 and adaptive and hook is None:
                    # the cluster only when it pays: the first group here, timed; the
                    # rest here too when a local cluster's start-up would not be won back
                    t0 = time.perf_counter()
                    here(rest[:1])
                    per_case = (time.perf_counter() - t0) / len(grouped[rest[0]])
                    rest = rest[1:]
                    left = per_case * sum(len(grouped[k]) for k in rest)
                    if not cluster_pays(left, len(rest), n_workers):
                        n_workers = 1
                if scheduler is None and n_workers == 1:
                    # one local worker: a cluster would only add its start-up (seconds)
                    # and the transfers; the groups run here, each part as it finishes
                    here(rest)
                elif rest:
                    _run_on_dask(study, grouped, rest, hook, scheduler,
                                 min(n_workers, len(rest)), cluster_kwargs, keep, batch=batch)
            finally:
                if bar is not None:
                    bar[0].stop()
        parts.sort(key=lambda item: item[0])  # in the order of their groups
        for line in dict.fromkeys(w for _, p in parts for w in
                                  str(p.attrs.get("warnings", "")).splitlines()):
            kind, _, text = line.partition("\t")  # the workers' warnings, once each
            warnings.warn(text, ModelRangeWarning if kind == "ModelRangeWarning" else UserWarning,
                          stacklevel=2)
        ds = combine(study, [p for _, p in parts], keys=all_keys)
        _write_nc(ds, store)
    failed = int(ds.attrs["n_failed"])
    return SweepResult(store=store, n_cases=len(cases), computed=computed, skipped=skipped,
                       failed=failed)
