"""Benchmark: parameter-study throughput on Dask, 1 and 2 local workers vs a serial loop.

Table-1 train (``idler-table1``), working-flank crack of ``--cases`` different depths
(each case a different mesh-stiffness table and simulation), 1 s simulated at 50 kHz,
analysed with every shaft's sidebands. Each worker configuration is the default path of
``gearsim sweep``: ``run_study(..., workers=N)`` runs the first group in this process,
timed, and starts a ``LocalCluster`` (processes, 1 thread each, whose fresh workers import
gearsim and load the numba cache) for the rest only when that pays for its start-up
(``CLUSTER_START_S``; else the rest runs here too), and writes the part files and the
final store; all of that is timed. The serial reference runs the same
cases in a plain loop in this process (warmed up first, no Dask, no files), once with
numba's default thread count and once with one thread (a Dask worker has one thread, so
that is the per-core reference), and once more writing the same store (``run_serial``
and the NetCDF write: what a study produces, made by a loop). Prints cases per minute and the scaling ratio
(2-worker / 1-worker throughput).

Run: ``.venv/bin/python benchmarks/bench_sweep.py [--cases 8]``
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from gearsim.studies.sweep import loads_study
from gearsim.studies.sweep_case import run_group
from gearsim.studies.sweep_run import groups, run_serial, run_study

STUDY = """
[study]
name = "bench"
config = "idler-table1"
signal = "acceleration[input,y]"
[study.dynamics]
duration = "1 s"
fs = "50 kHz"
[parameters]
flank = ["working"]
crack_depth = {{ min = "1 mm", max = "2.5 mm", num = {n} }}
"""

WARM = """
[study]
[study.dynamics]
duration = "0.15 s"
fs = "20 kHz"
[parameters]
flank = ["working"]
"""


def warm_up() -> None:
    """Imports and numba kernels (cache load) of one short case, and the imports of a
    store's write (h5netcdf; xarray's writer imports distributed), which every
    configuration below pays, the serial loop writing the store included."""
    st = loads_study(WARM.replace("[study]\n", "[study]\nshafts = \"reference\"\n", 1))
    with tempfile.TemporaryDirectory() as tmp:
        run_study(st, Path(tmp) / "warm.nc", workers=1, progress=False)


def forget_tables() -> None:
    """Empty this process's in-memory caches of what the cases share (mesh tables, the
    healthy teeth's compliances, the crack start and outline, the parsed base gearbox,
    the spectrum's window), so that every configuration computes them (as a fresh worker
    would), not the serial loop alone."""
    import gearsim.dynamics.tables as dt
    import gearsim.signals.spectrum as sp
    import gearsim.stiffness.crack as cr
    import gearsim.stiffness.tooth as to
    import gearsim.studies.sweep_case as sc
    import gearsim.system.train as tm

    tm._TABLES.clear()
    dt._DERIVATIVES.clear()
    for cache in (to._healthy_compliance, cr._tangent_param, cr._outline, sc._base,
                  sp._cached_window):
        cache.cache_clear()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8, help="cases per configuration")
    args = ap.parse_args()
    study = loads_study(STUDY.format(n=args.cases))
    rate = {}
    warm_up()  # this process warm, as for the serial loop (a cluster's workers start cold)
    with tempfile.TemporaryDirectory() as tmp:
        for n in (1, 2):
            forget_tables()
            t0 = time.perf_counter()
            res = run_study(study, Path(tmp) / f"w{n}.nc", workers=n, progress=False)
            dt = time.perf_counter() - t0
            assert res.computed == args.cases and res.failed == 0, res
            rate[n] = 60 * args.cases / dt
            print(f"Dask, {n} worker(s): {args.cases} cases in {dt:7.2f} s = {rate[n]:6.1f} "
                  "cases/min (incl. any cluster start and worker warm-up)", flush=True)
        import numba

        serial = {}
        for threads in (numba.config.NUMBA_NUM_THREADS, 1):
            numba.set_num_threads(threads)
            forget_tables()
            t0 = time.perf_counter()
            for cases in groups(study).values():
                run_group(study, cases)
            dt = time.perf_counter() - t0
            serial[threads] = 60 * args.cases / dt
            print(f"serial loop, no Dask, {threads} numba thread(s): {args.cases} cases in "
                  f"{dt:7.2f} s = {serial[threads]:6.1f} cases/min", flush=True)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        # the loop that makes what a study makes: the same cases and the same store file
        # (run_serial + the NetCDF write), one numba thread as a worker has
        numba.set_num_threads(1)
        forget_tables()
        t0 = time.perf_counter()
        run_serial(study).to_netcdf(Path(tmp) / "serial.nc", engine="h5netcdf")
        dt = time.perf_counter() - t0
        serial["store"] = 60 * args.cases / dt
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        print(f"serial loop writing the store, 1 numba thread: {args.cases} cases in "
              f"{dt:7.2f} s = {serial['store']:6.1f} cases/min", flush=True)
    print(f"scaling 2 / 1 workers:          {rate[2] / rate[1]:6.2f} (ideal 2)")
    print(f"1 worker / serial loop, 1 thread: {rate[1] / serial[1]:6.2f} (Dask overhead; a "
          "Dask worker runs numba on 1 thread)")
    best = max(serial[numba.config.NUMBA_NUM_THREADS], serial[1])
    print(f"2 workers / serial loop, all threads: {rate[2] / best:6.2f}")
    print(f"2 workers / serial loop, 1 thread: {rate[2] / serial[1]:6.2f} (the loop writes "
          "no file)")
    print(f"2 workers / serial loop writing the store: {rate[2] / serial['store']:6.2f} "
          "(target >= 1 for a small study: the cluster only when it pays)")


if __name__ == "__main__":
    main()
