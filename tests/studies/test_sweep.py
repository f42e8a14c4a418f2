"""Parameter sweeps on Dask: equal to the serial loop, resumable, robust to a lost worker,
failing cases recorded, bad study files refused."""

from __future__ import annotations

import functools
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import cloudpickle
import numpy as np
import pytest
import xarray as xr

from gearsim.errors import InputError
from gearsim.studies.sweep import expand, loads_study
from gearsim.studies.sweep_case import build_case
from gearsim.studies.sweep_run import PART_SUFFIX, groups, parts_dir, read_part, run_serial, run_study

# The fault-injection hook below runs in Dask worker processes, which cannot import this
# test module: pickle its functions by value.
cloudpickle.register_pickle_by_value(sys.modules[__name__])

GEARSIM = [sys.executable, "-m", "gearsim.cli"]

#: 0.15 s at 20 kHz is the shortest record that resolves the input-shaft sidebands
#: (31.7 Hz spacing, 4 Hann bins) of the Table-1 train; shafts = "reference".
TINY = """
[study]
name = "tiny"
config = "idler-table1"
replicates = 2
seed = 3
signal = "acceleration[input,y]"
shafts = "reference"
[study.dynamics]
duration = "0.15 s"
fs = "20 kHz"
transient = "0.02 s"
[parameters]
crack_depth = ["1 mm", "2 mm"]
flank = ["none", "working", "non-working"]
torque = ["2000 N*m", "4876 N*m"]
noise = [0.0, 0.5]
"""


@pytest.fixture(scope="module", autouse=True)
def _one_blas_thread():
    """One BLAS thread in this process for the logistic regressions of the report and
    separability tests: their L-BFGS fits make small BLAS calls, where OpenBLAS's second
    thread only spins on ``make test``'s two busy cores. No number checked here depends
    on it (the cluster's workers and the serial loop simulate as before)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


@pytest.fixture(scope="module")
def study():
    return loads_study(TINY)


@pytest.fixture(scope="module")
def serial(study):
    """The study run case by case in a plain loop (no Dask)."""
    return run_serial(study)


def test_expansion_and_serial_numbers(study, serial):
    cases = expand(study)
    assert len(cases) == 2 * 3 * 2 * 2 * 2 == serial.sizes["case"]
    # healthy cases share one simulation per torque whatever the nominal depth
    assert len(groups(study)) == 2 + 2 * 2 * 2
    # a depth that does not fit the tooth is refused with the study (check_study); a
    # case that fails at run time is recorded: tests/studies/test_sweep_bad_input.py
    ok = serial["status"].values == "ok"
    assert ok.all()
    # td_rms of a noise-free case is the RMS of the simulated record minus its mean
    case = cases[0]
    assert case.noise == 0.0 and case.flank == "none"
    from gearsim.dynamics import simulate

    gb = build_case(study, case)
    x = simulate(gb.train, gb.dynamics)["acceleration"].sel(shaft="input", axis="y").values
    np.testing.assert_allclose(serial["td_rms"].values[0], np.std(x), rtol=1e-12)
    # noise of RMS 0.5 std(x): RMS grows by sqrt(1 + 0.5^2) (sampling error ~ 1/sqrt(3000))
    sel = ok & (serial["noise"].values == 0.5)
    base = ok & (serial["noise"].values == 0.0)
    ratio = serial["td_rms"].values[sel] / serial["td_rms"].values[base]
    np.testing.assert_allclose(ratio, np.sqrt(1.25), rtol=0.05)
    # noise-free replicates are equal, noisy ones are not (seeded per case)
    r0 = serial.where(serial.replicate == 0, drop=True)
    r1 = serial.where(serial.replicate == 1, drop=True)
    z = (r0.noise.values == 0) & (r0.status.values == "ok")
    np.testing.assert_array_equal(r0.tsa_fm4.values[z], r1.tsa_fm4.values[z])
    assert np.all(r0.tsa_fm4.values[~z & (r0.status.values == "ok")]
                  != r1.tsa_fm4.values[~z & (r0.status.values == "ok")])
    # a crack adds once-per-revolution sidebands: SER of mesh order 1 of the noise-free
    # record grows from healthy to non-working to working flank (the working flank sees
    # the larger stiffness loss), at each torque
    for torque in (2000.0, 4876.0):
        ser = {f: serial.sb_ser_o1_shaft1.values[ok & (serial.flank.values == f)
                                                 & (serial.noise.values == 0)
                                                 & (serial.torque.values == torque)].mean()
               for f in ("none", "working", "non-working")}
        assert ser["working"] > 1.05 * ser["non-working"] > 1.05 * 1.01 * ser["none"], ser


def test_two_worker_cluster_equals_serial(study, serial, tmp_path):
    # adaptive=False: the cluster, which a study this small would not start by itself
    res = run_study(study, tmp_path / "s.nc", workers=2, progress=False, adaptive=False)
    assert (res.n_cases, res.computed, res.skipped, res.failed) == (48, 48, 0, 0)
    ds = xr.load_dataset(tmp_path / "s.nc", engine="h5netcdf")
    xr.testing.assert_identical(ds, serial)
    assert ds.attrs["study"] == TINY and ds.attrs["gearsim_version"]
    # a second run finds every case finished
    again = run_study(study, tmp_path / "s.nc", workers=1, progress=False)
    assert (again.computed, again.skipped) == (0, 48)


def test_killed_study_resumes_without_recomputing(study, serial, tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(TINY)
    store = tmp_path / "k.nc"
    parts = parts_dir(store)
    proc = subprocess.Popen([*GEARSIM, "sweep", str(path), "--out", str(store), "--workers",
                             "1", "--no-progress"], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while len(list(parts.glob(f"*{PART_SUFFIX}"))) < 2 and time.monotonic() < deadline:
            assert proc.poll() is None, "the study finished or failed before the kill"
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the client and its cluster, like a power cut
        proc.wait()
    finished = {p: p.stat().st_mtime_ns for p in parts.glob(f"*{PART_SUFFIX}")}
    assert 2 <= len(finished) < len(groups(study))
    assert not store.exists()
    n_done = sum(read_part(p).sizes["case"] for p in finished)
    # resumed in this process (workers=1: no cluster): which parts are finished is decided
    # before the groups are run, the same for the serial and the Dask path; the Dask path
    # writing a store equal to the serial one is test_two_worker_cluster_equals_serial's
    res = run_study(study, store, workers=1, progress=False)
    assert res.skipped == n_done and res.computed == 48 - n_done > 0
    assert {p: p.stat().st_mtime_ns for p in finished} == finished  # not rewritten
    xr.testing.assert_identical(xr.load_dataset(store, engine="h5netcdf"), serial)


def _die_once(marker: str, cases) -> None:
    """Kill the worker process the first time any case group starts."""
    if not os.path.exists(marker):
        Path(marker).write_text(str(os.getpid()))
        os._exit(1)


#: :data:`TINY` at the rated torque alone: 5 of its 10 simulation groups, 24 of its 48
#: cases. Case keys (and so the noise seeds) hash the parameters and the study's settings,
#: not its parameter lists: each case equals the serial run's case of the same parameters.
RATED = TINY.replace('torque = ["2000 N*m", "4876 N*m"]', 'torque = ["4876 N*m"]')


def test_lost_worker_task_is_retried(serial, tmp_path):
    """A worker dies at the start of its first group; the group is retried on the
    restarted worker and the store is the serial one. Run on :data:`RATED` (a lost worker
    and its retry do not depend on the number of groups; 5 groups still give both
    workers work) against the serial run's cases at 4876 N*m."""
    assert RATED != TINY
    marker = tmp_path / "died"
    res = run_study(loads_study(RATED), tmp_path / "w.nc", workers=2, progress=False,
                    hook=functools.partial(_die_once, str(marker)))
    assert marker.exists()  # a worker did die
    assert res.computed == 24
    ds = xr.load_dataset(tmp_path / "w.nc", engine="h5netcdf")
    ref = serial.isel(case=np.flatnonzero(serial["torque"].values == 4876.0))
    ref = ref.assign_coords(case=np.arange(ref.sizes["case"]))
    assert ds.attrs["study"] == RATED and ds.attrs["n_cases"] == ds.attrs["n_ok"] == 24

    def other(attrs):
        return {k: str(v) for k, v in attrs.items() if k not in ("study", "n_cases", "n_ok")}

    assert other(ds.attrs) == other(serial.attrs)
    ref.attrs = ds.attrs  # compared above; every coordinate and value below
    xr.testing.assert_identical(ds, ref)


@pytest.mark.parametrize("edit,parameter", [
    (("torque = [", "gear_ratio = [2, 3]\ntorque = ["), "parameters.gear_ratio"),
    (('torque = ["2000 N*m", "4876 N*m"]', "torque = []"), "parameters.torque"),
    (('torque = ["2000 N*m", "4876 N*m"]', 'torque = {min = "3 kN*m", max = "2 kN*m", num = 3}'),
     "parameters.torque"),
    (('torque = ["2000 N*m", "4876 N*m"]', 'torque = {min = "1 kN*m", max = "2 kN*m", num = 0}'),
     "parameters.torque.num"),
    (('flank = ["none"', 'flank = ["both"'), "parameters.flank[0]"),
    (('duration = "0.15 s"', 'duration = "0.15 kg"'), "study.dynamics.duration"),
])
def test_bad_study_refused(edit, parameter, tmp_path, capsys):
    """The study file refused by ``gearsim sweep`` (in-process ``cli.run``: the exit status
    and the one stderr line, as tests/test_cli_errors.py checks them in a real process)."""
    from gearsim import cli

    text = TINY.replace(*edit)
    assert text != TINY
    with pytest.raises(InputError) as err:
        loads_study(text)
    assert err.value.parameter == parameter
    path = tmp_path / "bad.toml"
    path.write_text(text)
    code = cli.run(["sweep", str(path), "--out", str(tmp_path / "b.nc")])
    res = capsys.readouterr()
    assert code == 2
    assert res.err.strip().splitlines() == [f"gearsim: error: {err.value}"]
    assert not (tmp_path / "b.nc").exists()


def test_separability_scores():
    from gearsim.studies.diagnostic import separability

    rng = np.random.default_rng(0)
    y = np.repeat(np.array(["none", "working", "non-working"]), 30)
    centres = {"none": 0.0, "working": 10.0, "non-working": -10.0}
    x = np.array([[centres[c]] for c in y]) + rng.normal(size=(y.size, 1))
    r = separability(np.column_stack([x, rng.normal(size=(y.size, 2))]), y)
    assert r["accuracy"] == 1.0 and r["auc"] == 1.0 and r["n"] == 90
    # features unrelated to the labels: near chance (1/3, 0.5), 90 samples -> +-0.15
    r = separability(rng.normal(size=(y.size, 3)), y)
    assert abs(r["accuracy"] - 1 / 3) < 0.15 and abs(r["auc"] - 0.5) < 0.15, r


def test_sweep_report(serial, tmp_path):
    import json

    from gearsim.studies.diagnostic import diagnostic_report

    store = tmp_path / "s.nc"
    serial.to_netcdf(store, engine="h5netcdf")
    csv, js, png = diagnostic_report(store, tmp_path / "rep")
    doc = json.loads(js.read_text())
    assert png.stat().st_size > 10_000 and csv.read_text().startswith("group,noise,snr_db")
    rows = {(r["group"], r["noise"], r["crack_depth_mm"]): r for r in doc["rows"]}
    # noise-free sideband features separate the three classes of the tiny study perfectly
    assert rows[("sideband", 0.0, 1.0)]["accuracy"] == 1.0
    assert rows[("sideband", 0.0, 1.0)]["n"] == 12  # 3 classes x 2 torques x 2 replicates
