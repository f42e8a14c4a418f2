"""A local cluster only when it pays (``run_study(adaptive=True)``, the default).

The first group runs in this process, timed; the rest runs here too when the cluster's
start-up (``CLUSTER_START_S``) would not be won back by sharing it between the workers.
Either way the store is the serial loop's.
"""

from __future__ import annotations

import pytest
import xarray as xr

import gearsim.studies.sweep_run as sr
from gearsim.studies.sweep import loads_study

#: Four cases of 0.15 s of the Table-1 train in four groups: about 2 s of work, which a
#: cluster of two workers (5 s to start) cannot shorten.
SMALL = """
[study]
name = "adaptive"
config = "idler-table1"
signal = "acceleration[input,y]"
shafts = "reference"
[study.dynamics]
duration = "0.15 s"
fs = "20 kHz"
transient = "0.02 s"
[parameters]
crack_depth = ["2 mm"]
flank = ["none", "working"]
torque = ["2000 N*m", "4876 N*m"]
"""


class Started(Exception):
    """The cluster was asked for."""


@pytest.fixture(scope="module")
def study():
    return loads_study(SMALL)


def test_small_study_stays_in_this_process(study, tmp_path, monkeypatch):
    def refuse(*_a, **_k):
        raise Started

    monkeypatch.setattr(sr, "_run_on_dask", refuse)
    res = sr.run_study(study, tmp_path / "a.nc", workers=2, progress=False)
    assert (res.n_cases, res.computed, res.failed) == (4, 4, 0)
    xr.testing.assert_identical(xr.load_dataset(tmp_path / "a.nc", engine="h5netcdf"),
                                sr.run_serial(study))


def test_the_cluster_when_the_rest_outweighs_its_start(study, tmp_path, monkeypatch):
    """With a start-up cost of zero the rest (three groups) goes to the cluster, on two
    workers; the first group was computed here and is not sent again."""
    seen = {}

    def record(study_, grouped, rest, hook, scheduler, n_workers, kwargs, keep, batch=None):
        seen.update(rest=list(rest), n_workers=n_workers, batch=batch)
        for key in rest:
            keep(key, sr.part_bytes(study_, grouped[key], hook))

    monkeypatch.setattr(sr, "CLUSTER_START_S", 0.0)
    monkeypatch.setattr(sr, "_run_on_dask", record)
    res = sr.run_study(study, tmp_path / "b.nc", workers=2, progress=False)
    assert res.computed == 4
    assert len(seen["rest"]) == len(sr.groups(study)) - 1 and seen["n_workers"] == 2
    with pytest.raises(Started):
        monkeypatch.setattr(sr, "_run_on_dask", lambda *a, **k: (_ for _ in ()).throw(Started))
        sr.run_study(study, tmp_path / "c.nc", workers=2, progress=False, adaptive=False)


def _worker_environ():  # run in a worker: the variables its nanny set
    import os

    return os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OPENBLAS_NUM_THREADS")


def test_local_workers_keep_glibc_memory_between_cases():
    """Dask's nanny sets MALLOC_TRIM_THRESHOLD_=65536 in its workers: every case's freed
    records went back to the system and faulted in again (3x the workers' sys time,
    docs/studies.md). gearsim's local workers start without it and keep Dask's one BLAS
    thread."""
    import dask
    import distributed  # noqa: F401  (its configuration defaults)

    from gearsim.studies.sweep_run import cluster_client, worker_environ

    assert dask.config.get("distributed.nanny.pre-spawn-environ")["MALLOC_TRIM_THRESHOLD_"]
    env = worker_environ()
    assert "MALLOC_TRIM_THRESHOLD_" not in env and env["OPENBLAS_NUM_THREADS"] == 1
    with cluster_client(1) as client:
        assert list(client.run(_worker_environ).values()) == [(None, "1")]
    # Dask's own configuration is left as it was
    assert dask.config.get("distributed.nanny.pre-spawn-environ")["MALLOC_TRIM_THRESHOLD_"]
