"""A study on a Dask scheduler and worker started as separate processes (``--scheduler``).

The scheduler and the worker are the ``distributed`` command-line programs, each in a
process of its own, as on a cluster (here on this machine, sharing its file system for
the parts). The study's store must equal the serial loop's; a scheduler that goes away
mid-study leaves the finished parts, one line and exit status 1, and the study resumes
from them.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
import xarray as xr

from gearsim.studies.sweep import loads_study
from gearsim.studies.sweep_run import PART_SUFFIX, groups, parts_dir, read_part, run_serial, run_study

#: Twelve cases of the Table-1 train (0.15 s at 20 kHz: the shortest record resolving
#: the input-shaft sidebands), in groups that share their tables.
STUDY = """
[study]
name = "remote"
config = "idler-table1"
seed = 5
signal = "acceleration[input,y]"
shafts = "reference"
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
#: Seconds to wait for the scheduler's address file and for the worker to join.
START_TIMEOUT = 60.0


def _start(args: list[str], log) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", *args], stdout=log, stderr=log,
                            start_new_session=True)


def _stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


@pytest.fixture
def cluster(tmp_path):
    """``dask scheduler`` and one ``dask worker`` (one thread), each its own process."""
    from distributed import Client

    file = tmp_path / "scheduler.json"
    log = open(tmp_path / "cluster.log", "w")  # noqa: SIM115  closed below
    sched = _start(["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                    "--no-dashboard", "--scheduler-file", str(file)], log)
    procs = [sched]
    try:
        deadline = time.monotonic() + START_TIMEOUT
        address = None
        while address is None and time.monotonic() < deadline:
            assert sched.poll() is None, (tmp_path / "cluster.log").read_text()
            try:  # the scheduler may have created the file and not yet written it
                address = json.loads(file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.05)
        assert address is not None, (tmp_path / "cluster.log").read_text()
        procs.append(_start(["distributed.cli.dask_worker", address, "--nthreads", "1",
                             "--nworkers", "1", "--no-dashboard", "--local-directory",
                             str(tmp_path / "worker")], log))
        with Client(address, timeout=START_TIMEOUT) as client:
            client.wait_for_workers(1, timeout=START_TIMEOUT)
        yield address, sched
    finally:
        for p in reversed(procs):
            _stop(p)
        log.close()


@pytest.fixture(scope="module")
def study():
    return loads_study(STUDY)


@pytest.fixture(scope="module")
def serial(study):
    """The study case by case in a plain loop (no Dask)."""
    return run_serial(study)


def test_remote_scheduler_equals_the_serial_loop(cluster, study, serial, tmp_path):
    address, _ = cluster
    res = run_study(study, tmp_path / "r.nc", scheduler=address, progress=False)
    assert (res.n_cases, res.computed, res.failed) == (12, 12, 0)
    remote = xr.load_dataset(tmp_path / "r.nc", engine="h5netcdf")
    xr.testing.assert_identical(remote, serial)


def test_scheduler_lost_mid_study_keeps_the_parts_and_resumes(cluster, study, serial,
                                                             tmp_path):
    """The scheduler is killed once the first part is written: the sweep ends with one
    ``gearsim: failed:`` line naming the scheduler, exit status 1, the parts stay; a
    second run (local) computes only the rest and gives the serial loop's store."""
    address, sched = cluster
    cfg = tmp_path / "study.toml"
    cfg.write_text(STUDY)
    store = tmp_path / "k.nc"
    parts = parts_dir(store)
    proc = subprocess.Popen([sys.executable, "-m", "gearsim.cli", "sweep", str(cfg), "--out",
                             str(store), "--scheduler", address, "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(parts.glob(f"*{PART_SUFFIX}")) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    _stop(sched)
    out, err = proc.communicate(timeout=120)
    lines = err.strip().splitlines()
    assert proc.returncode == 1, err
    assert len(lines) == 1 and lines[0].startswith(
        f"gearsim: failed: sweep: lost the scheduler {address} mid-study"), err
    assert "resumes" in lines[0]
    done = sorted(parts.glob(f"*{PART_SUFFIX}"))
    assert 1 <= len(done) < len(groups(study)) and not store.exists()
    n_done = 0
    for p in done:
        n_done += read_part(p).sizes["case"]
    again = run_study(study, store, workers=1, progress=False)
    assert (again.skipped, again.computed) == (n_done, 12 - n_done)
    xr.testing.assert_identical(xr.load_dataset(store, engine="h5netcdf"), serial)
