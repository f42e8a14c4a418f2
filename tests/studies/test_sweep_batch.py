"""Several simulation groups per Dask task (``run_study(batch=...)``, ``gearsim sweep
--batch``): the batch size is checked before any work; a study run in batches of one or
several groups gives the serial loop's store exactly (every variable ``numpy.array_equal``);
a batch whose worker dies is retried whole; a study resumes from batch parts, computing
only the groups no part holds whole."""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

import cloudpickle
import numpy as np
import pytest
import xarray as xr

from gearsim import cli
from gearsim.errors import InputError
from gearsim.io.npzset import from_bytes
from gearsim.studies.sweep import Case, expand, loads_study
from gearsim.studies.sweep_case import run_group
from gearsim.studies.sweep_run import (
    BATCH_MAX,
    BATCH_PREFIX,
    PART_SUFFIX,
    batch_bytes,
    batch_path,
    batches,
    check_batch,
    groups,
    join_tables,
    parts_dir,
    plan_batch,
    run_serial,
    run_study,
)

# the fault-injection hook runs in the workers, which cannot import this module
cloudpickle.register_pickle_by_value(sys.modules[__name__])

#: Twelve cases in six simulation groups (three flanks x two torques; two noise levels
#: share each simulation, so a group's cases are not consecutive), records stored: 0.15 s
#: at 20 kHz, the shortest record resolving the input-shaft sidebands.
STUDY = """
[study]
name = "batched"
config = "idler-table1"
seed = 7
signal = "acceleration[input,y]"
shafts = "reference"
store_signals = true
[study.dynamics]
duration = "0.15 s"
fs = "20 kHz"
transient = "0.02 s"
[parameters]
crack_depth = ["2 mm"]
flank = ["none", "working", "non-working"]
torque = ["2000 N*m", "4876 N*m"]
noise = [0.0, 0.5]
"""


@pytest.fixture(scope="module")
def study():
    return loads_study(STUDY)


@pytest.fixture(scope="module")
def serial(study):
    """The study group by group in a plain loop (no Dask, no files)."""
    return run_serial(study)


def _assert_equal_arrays(ds: xr.Dataset, ref: xr.Dataset) -> None:
    """Every variable and coordinate of ``ref`` in ``ds``, equal element by element
    (floats bit for bit, NaN where NaN), and nothing else."""
    assert sorted(ds.variables) == sorted(ref.variables)
    for name in ref.variables:
        a, b = ds[name].values, ref[name].values
        assert a.shape == b.shape, name
        nan = a.dtype.kind == "f"
        assert np.array_equal(a, b, equal_nan=nan), name
        if nan:  # the same bits, signed zeros included
            assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), name
    xr.testing.assert_identical(ds, ref)


# -- the batch size ---------------------------------------------------------------------

@pytest.mark.parametrize("value", [0, -1, -32, 1.5, 2.0, "3", True, None])
def test_bad_batch_refused_in_one_line(value):
    if value is None:
        assert check_batch(None) is None
        return
    with pytest.raises(InputError) as err:
        check_batch(value)
    assert err.value.parameter == "--batch"
    text = str(err.value)
    assert len(text.splitlines()) == 1 and ">= 1" in text
    assert text.startswith(f"--batch = {value if isinstance(value, str) else repr(value)}:")


@pytest.mark.parametrize("value", [0, -1])
def test_run_study_refuses_a_bad_batch_before_any_work(study, tmp_path, value):
    with pytest.raises(InputError, match=f"--batch = {value}: must be an integer >= 1"):
        run_study(study, tmp_path / "b.nc", workers=1, progress=False, batch=value)
    assert not any(tmp_path.iterdir())  # no store, no parts, no lock


def test_api_sweep_takes_the_batch(tmp_path):
    # gearsim.api.sweep hands its batch to run_study: a bad one is refused there, before
    # any work, as from the CLI
    import gearsim.api as gs

    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    with pytest.raises(InputError, match="--batch = 0: must be an integer >= 1"):
        gs.sweep(path, tmp_path / "A.nc", workers=1, batch=0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]


@pytest.mark.parametrize("value,expected", [
    ("0", "--batch = 0: must be an integer >= 1 (simulation groups per Dask task)"),
    ("-2", "--batch = -2: must be an integer >= 1 (simulation groups per Dask task)"),
    ("1.5", "'--batch'"),
    ("many", "'--batch'"),
])
def test_cli_refuses_a_bad_batch(capsys, tmp_path, value, expected):
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    store = tmp_path / "S.nc"
    code = cli.run(["sweep", str(path), "--out", str(store), "--no-progress",
                    f"--batch={value}"])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("gearsim: error: "), err
    assert expected in lines[0]
    assert not store.exists() and not parts_dir(store).exists()


def test_automatic_batch_size():
    # a small study: one group a task (as without batches)
    assert plan_batch(12, 2) == 1 and plan_batch(20, 2) == 1 and plan_batch(21, 2) == 2
    # about ten tasks a worker, at most BATCH_MAX groups each
    assert plan_batch(300, 2) == 15 and plan_batch(2000, 2) == BATCH_MAX
    assert plan_batch(2000, 64) == 4
    # the user's size, at most the groups to compute
    assert plan_batch(2000, 2, 5) == 5 and plan_batch(3, 2, 10) == 3
    assert batches(list("abcde"), 2) == [["a", "b"], ["c", "d"], ["e"]]
    assert batches(list("abc"), 5) == [["a", "b", "c"]]
    # the automatic size shrinks at the end (each batch at most 1/(2 workers) of the
    # groups left), every group once, in order
    keys = [f"{i:03d}" for i in range(299)]
    sizes = [len(b) for b in batches(keys, plan_batch(299, 2), workers=2)]
    assert max(sizes) == 15 and sizes[-4:] == [1, 1, 1, 1]
    assert sizes == sorted(sizes, reverse=True)
    assert [k for b in batches(keys, 15, workers=2) for k in b] == keys


def test_batch_part_is_the_join_of_its_group_tables(study):
    """A batch's part holds its groups' tables joined: values as run_group gave them
    (a failed group's features filled with NaN), the groups' keys in ``groups``."""
    grouped = groups(study)
    first = next(iter(grouped.values()))
    case = next(c for c in expand(study) if c.flank == "working")
    bad = [Case(**{**case.params(), "index": 99, "crack_depth": 0.03})]  # does not fit
    part = from_bytes(batch_bytes(study, [first, bad]))
    tables = [run_group(study, first), run_group(study, bad)]
    assert tables[1]["status"].values.tolist() == ["failed"]
    assert part.attrs["groups"] == [study.simulation_key(first[0]), study.simulation_key(bad[0])]
    ref = join_tables(tables)
    part.attrs = {}
    _assert_equal_arrays(part, ref)
    assert np.isnan(part["td_rms"].values[-1]) and part["status"].values[-1] == "failed"


# -- on the cluster ------------------------------------------------------------------------

def _die_once(marker: str, cases) -> None:
    """Kill the worker process the first time any group starts."""
    if not os.path.exists(marker):
        Path(marker).write_text(str(os.getpid()))
        os._exit(1)


@pytest.mark.parametrize("batch", [1, 4])
def test_batched_study_equals_the_serial_loop(study, serial, tmp_path, batch):
    """Batches of one group (six tasks) and of four (a task of four groups and one of
    two): the store is the serial loop's, every variable equal. With 4, the worker running
    the first batch dies at its first group: the batch is retried whole."""
    store = tmp_path / "s.nc"
    marker = tmp_path / "died"
    hook = functools.partial(_die_once, str(marker)) if batch > 1 else None
    res = run_study(study, store, workers=2, progress=False, adaptive=False, batch=batch,
                    hook=hook)
    assert (res.n_cases, res.computed, res.skipped, res.failed) == (12, 12, 0, 0)
    assert marker.exists() == (batch > 1)
    _assert_equal_arrays(xr.load_dataset(store, engine="h5netcdf"), serial)
    names = sorted(p.name for p in parts_dir(store).glob(f"*{PART_SUFFIX}"))
    keys = list(groups(study))
    if batch == 1:
        assert names == sorted(f"{k}{PART_SUFFIX}" for k in keys)
    else:
        assert names == sorted(batch_path(store, b).name for b in batches(keys, batch))
        assert all(n.startswith(BATCH_PREFIX) for n in names)
    # a second run finds every case finished
    again = run_study(study, store, workers=1, progress=False, batch=batch)
    assert (again.computed, again.skipped) == (0, 12)
    _assert_equal_arrays(xr.load_dataset(store, engine="h5netcdf"), serial)


# -- resume --------------------------------------------------------------------------------

def test_resume_from_batch_parts(study, serial, tmp_path):
    """Parts of an interrupted batched run (two batches finished of three) and a part of
    another grid: the resumed run computes only the group no part holds whole, leaves
    the parts as they are and writes the serial loop's store."""
    store = tmp_path / "r.nc"
    grouped = groups(study)
    keys = list(grouped)
    folder = parts_dir(store)
    folder.mkdir()
    # two finished batches of two groups; the third batch was lost with its worker
    for b in batches(keys, 2)[:2]:
        batch_path(store, b).write_bytes(batch_bytes(study, [grouped[k] for k in b]))
    # a batch of another grid (the rated torque alone, two replicates; the same
    # simulations): it holds the study's cases of its groups (replicate 0, numbered
    # differently there) and cases the study does not have (replicate 1). Of its two
    # groups one is held by a finished batch already, the other by no part: that one is
    # taken from it, its rows by case key, renumbered.
    other = loads_study(STUDY.replace('torque = ["2000 N*m", "4876 N*m"]',
                                      'torque = ["4876 N*m"]')
                        .replace("seed = 7", "seed = 7\nreplicates = 2"))
    og = groups(other)
    taken = list(og)[1:]
    assert taken == [keys[3], keys[5]] and len(og[keys[5]]) == 2 * len(grouped[keys[5]])
    assert [c.index for c in og[keys[5]]] != [c.index for c in grouped[keys[5]]]
    batch_path(store, taken).write_bytes(batch_bytes(other, [og[k] for k in taken]))
    # a half-written part (a leftover temporary file) and an unreadable part are ignored
    (folder / f".{keys[5]}{PART_SUFFIX}.abc.tmp").write_bytes(b"PK")
    (folder / f"{BATCH_PREFIX}0000000000000000{PART_SUFFIX}").write_bytes(b"not a part")
    before = {p: p.stat().st_mtime_ns for p in folder.iterdir()}
    res = run_study(study, store, workers=1, progress=False, batch=2)
    held = {*keys[:4], keys[5]}
    n_held = sum(len(grouped[k]) for k in held)
    assert (res.skipped, res.computed) == (n_held, 12 - n_held) == (10, 2)
    assert {p: p.stat().st_mtime_ns for p in before} == before  # none rewritten
    # the groups left ran in this process (one worker), one part each
    new = sorted(set(folder.iterdir()) - set(before))
    assert sorted(p.name for p in new) == sorted(f"{k}{PART_SUFFIX}" for k in keys
                                                 if k not in held)
    _assert_equal_arrays(xr.load_dataset(store, engine="h5netcdf"), serial)


def test_a_part_missing_cases_of_its_group_is_recomputed(study, serial, tmp_path):
    """A group counts as finished only when a part holds every one of its cases (by
    ``case_key``): a part of the same simulation with one case fewer (a study of fewer
    noise levels) is not enough."""
    store = tmp_path / "m.nc"
    grouped = groups(study)
    key = next(iter(grouped))
    fewer = loads_study(STUDY.replace("noise = [0.0, 0.5]", "noise = [0.5]"))
    part = groups(fewer)[key]
    assert len(part) == len(grouped[key]) - 1
    parts_dir(store).mkdir()
    batch_path(store, [key]).write_bytes(batch_bytes(fewer, [part]))
    res = run_study(study, store, workers=1, progress=False)
    assert (res.skipped, res.computed) == (0, 12)
    _assert_equal_arrays(xr.load_dataset(store, engine="h5netcdf"), serial)
