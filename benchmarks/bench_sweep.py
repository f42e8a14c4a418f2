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

Batches: the 2-worker study runs twice in the same process, once with one simulation
group per Dask task (``batch=1``, as before batches) and once with ``--batch`` groups a
task (default: :func:`gearsim.studies.sweep_run.plan_batch`'s automatic size), alternated
``--repeat`` times (the machine is shared: compare the pairs), and the ratios of the two
and of each to the serial loops are printed. ``--no-one-worker`` skips the 1-worker run
(a larger study: ``--cases 300 --no-one-worker``), ``--no-serial`` the serial loops (the
2000-case study: ``--cases 2000 --no-one-worker --no-serial``).

The issue's reference, measured in the same run (:func:`physics_floor`, one thread, up
to 16 cases): the bare kernel-plus-analysis time of two cores, n (t_kernel +
t_analysis) / 2, and the same with each case's mesh-stiffness tables (a new crack depth
each case); the 2-worker study's time over each is printed.

Run: ``.venv/bin/python benchmarks/bench_sweep.py [--cases 8] [--batch N] [--repeat R]
[--grid depths|factorial]``
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time
from pathlib import Path

from gearsim.studies.sweep import loads_study
from gearsim.studies.sweep_case import run_group
from gearsim.studies.sweep_run import groups, plan_batch, run_serial, run_study

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

#: ``--grid factorial``: a labelled data set as users build them, crack depth x speed x
#: torque (10 speeds x 10 torques per depth): every case is its own simulation, and the
#: cases of one depth share its mesh-stiffness table (the seed model's contact law does
#: not depend on the load).
FACTORIAL = STUDY.replace('name = "bench"', 'name = "bench-factorial"') + """\
speed = {{ min = "1500 rpm", max = "1900 rpm", num = 10 }}
torque = {{ min = "2000 N*m", max = "4876 N*m", num = 10 }}
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


def _cpu() -> float:
    """CPU time [s] of this process (client, and a local cluster's scheduler) and of its
    finished children (the nannies and, reaped by them, the workers)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(
        resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def _timed_study(study, store: Path, cases: int, workers: int, batch: int | None,
                 ) -> tuple[float, float]:
    """Wall time and CPU time (:func:`_cpu`: every process of the study, once its
    cluster is closed) of ``run_study`` of ``study`` (fresh caches), checked complete [s].
    The CPU time hardly depends on other jobs sharing the machine, the wall time does."""
    forget_tables()
    c0, t0 = _cpu(), time.perf_counter()
    res = run_study(study, store, workers=workers, progress=False, batch=batch)
    dt, cpu = time.perf_counter() - t0, _cpu() - c0
    assert res.computed == cases and res.failed == 0, res
    return dt, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8, help="cases per configuration")
    ap.add_argument("--batch", type=int, default=None,
                    help="groups per Dask task of the batched runs (default: automatic)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="alternating pairs of unbatched and batched 2-worker runs")
    ap.add_argument("--no-one-worker", action="store_true",
                    help="skip the 1-worker run (in-process for a small study)")
    ap.add_argument("--no-serial", action="store_true",
                    help="skip the serial loops (a large study: the 2-worker pairs only)")
    ap.add_argument("--grid", choices=("depths", "factorial"), default="depths",
                    help="depths: a new crack depth each case (default); factorial: crack "
                         "depth x 10 speeds x 10 torques (--cases a multiple of 100)")
    args = ap.parse_args()
    if args.grid == "factorial":
        if args.cases % 100:
            ap.error(f"--cases = {args.cases}: must be a multiple of 100 with --grid factorial")
        study = loads_study(FACTORIAL.format(n=args.cases // 100))
    else:
        study = loads_study(STUDY.format(n=args.cases))
    n_groups = len(groups(study))
    auto = plan_batch(n_groups - 1, 2, args.batch)  # the first group runs in-process
    rate = {}
    warm_up()  # this process warm, as for the serial loop (a cluster's workers start cold)
    with tempfile.TemporaryDirectory() as tmp:
        if not args.no_one_worker:
            dt, _ = _timed_study(study, Path(tmp) / "w1.nc", args.cases, 1, None)
            rate[1] = 60 * args.cases / dt
            print(f"Dask, 1 worker(s): {args.cases} cases in {dt:7.2f} s = {rate[1]:6.1f} "
                  "cases/min (in-process: no cluster)", flush=True)
        pairs = []
        cpus: dict = {}
        for r in range(args.repeat):
            pair = {}
            for b in (1, args.batch):  # None: automatic
                dt, cpu = _timed_study(study, Path(tmp) / f"w2-{r}-{b}.nc", args.cases, 2, b)
                pair[b] = dt
                cpus.setdefault(b, []).append(cpu)
                what = ("batch=1" if b == 1 else f"batch={b}" if b is not None
                        else f"batch<={auto} (auto, smaller at the end)")
                print(f"Dask, 2 workers, {what}: {args.cases} cases in {dt:7.2f} s = "
                      f"{60 * args.cases / dt:6.1f} cases/min (incl. any cluster start and "
                      f"worker warm-up); CPU {cpu:7.2f} s = {cpu / args.cases:6.4f} s a case "
                      "(all processes)", flush=True)
            pairs.append(pair)
        rate[2] = 60 * args.cases / min(p[args.batch] for p in pairs)
        rate["2u"] = 60 * args.cases / min(p[1] for p in pairs)
        serial = {} if args.no_serial else _serial_runs(study, args.cases, Path(tmp), cpus)
    for i, p in enumerate(pairs):
        print(f"pair {i + 1}: 2 workers batch={args.batch or auto} / batch=1 throughput: "
              f"{p[1] / p[args.batch]:6.3f}, CPU a case {cpus[args.batch][i] / cpus[1][i]:6.3f}")
    # the reference: the bare kernel-plus-analysis time of two cores
    fl = physics_floor(study, min(args.cases, 16) if args.grid == "depths" else 100)
    study_s = min(p[args.batch] for p in pairs)
    bare = args.cases * (fl["kernel"] + fl["analysis"]) / 2
    with_tables = args.cases * (fl["kernel"] + fl["analysis"] + fl["tables"]) / 2
    shared = ("a new crack depth each" if args.grid == "depths"
              else "a depth's table shared by its 100 cases")
    print(f"a case, 1 thread, on {fl['cases']} cases: kernel {fl['kernel']:6.4f} s, "
          f"analysis {fl['analysis']:6.4f} s, mesh tables {fl['tables']:6.4f} s ({shared}), "
          f"whole run_group {fl['case']:6.4f} s")
    print(f"2-worker study / bare kernel+analysis of two cores ({bare:7.2f} s): "
          f"{study_s / bare:5.2f} (target <= 1.3)")
    print(f"2-worker study / kernel+analysis+tables of two cores ({with_tables:7.2f} s): "
          f"{study_s / with_tables:5.2f}")
    if not serial:
        return
    import numba

    one = cpus["serial1"] / args.cases
    for b in (1, args.batch):
        c = min(cpus[b]) / args.cases
        print(f"CPU a case, 2 workers batch={b or auto}: {c:6.4f} s (best of "
              f"{len(cpus[b])}) = {c / one:5.3f} x the 1-thread loop's {one:6.4f} s")
    per_case = 1.0 / (serial[1] / 60)
    for b, r in (("1", rate["2u"]), (str(args.batch or auto), rate[2])):
        # a worker's time per case (2 workers x wall / cases) against the 1-thread loop's
        print(f"2 workers, batch={b}: best {r:6.1f} cases/min; a worker's time per case "
              f"{120 / r:6.3f} s = {120 / r / per_case:5.2f} x the 1-thread loop's")
    if 1 in rate:
        print(f"scaling 2 / 1 workers:          {rate[2] / rate[1]:6.2f} (ideal 2)")
        print(f"1 worker / serial loop, 1 thread: {rate[1] / serial[1]:6.2f} (in-process "
              "run_study: parts and store)")
    best = max(serial[numba.config.NUMBA_NUM_THREADS], serial[1])
    print(f"2 workers / serial loop, all threads: {rate[2] / best:6.2f}")
    print(f"2 workers / serial loop, 1 thread: {rate[2] / serial[1]:6.2f} (the loop writes "
          "no file; ideal 2)")
    print(f"2 workers / serial loop writing the store: {rate[2] / serial['store']:6.2f} "
          "(target >= 1 for a small study: the cluster only when it pays)")


def physics_floor(study, sample: int) -> dict[str, float]:
    """Seconds a case of the physics alone, one numba thread, on the first ``sample``
    simulation groups (fresh caches, as a worker): the compiled RK4 kernel
    (``dynamics.simulate.run_kernel``), the analysis of the record
    (``signals.analyze``) and the mesh-stiffness tables (``dynamics.tables.mesh_tables``:
    every case of this study cracks the input gear to its own depth, so its table is
    new). Measured by timing those three functions inside ``run_group``."""
    import importlib

    import numba

    ds = importlib.import_module("gearsim.dynamics.simulate")  # the module, not the function
    sc = importlib.import_module("gearsim.studies.sweep_case")

    spent = {"kernel": 0.0, "analysis": 0.0, "tables": 0.0}

    def timed(fn, key):
        def wrapper(*a, **k):
            t0 = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                spent[key] += time.perf_counter() - t0
        return wrapper

    saved = ds.run_kernel, sc.analyze, ds.mesh_tables
    ds.run_kernel, sc.analyze = timed(ds.run_kernel, "kernel"), timed(sc.analyze, "analysis")
    ds.mesh_tables = timed(ds.mesh_tables, "tables")
    numba.set_num_threads(1)
    forget_tables()
    n = 0
    try:
        t0 = time.perf_counter()
        for cases in list(groups(study).values())[:sample]:
            run_group(study, cases)
            n += len(cases)
        spent["case"] = time.perf_counter() - t0
    finally:
        ds.run_kernel, sc.analyze, ds.mesh_tables = saved
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return {**{k: v / n for k, v in spent.items()}, "cases": n}


def _serial_runs(study, n_cases: int, tmp: Path, cpus: dict) -> dict:
    """The serial loops (numba's threads, one thread, one thread writing the store):
    cases/min of each; their CPU times go into ``cpus`` (``serial<threads>``)."""
    import numba

    serial = {}
    for threads in (numba.config.NUMBA_NUM_THREADS, 1):
        numba.set_num_threads(threads)
        forget_tables()
        c0, t0 = _cpu(), time.perf_counter()
        for cases in groups(study).values():
            run_group(study, cases)
        dt, cpu = time.perf_counter() - t0, _cpu() - c0
        serial[threads] = 60 * n_cases / dt
        cpus[f"serial{threads}"] = cpu
        print(f"serial loop, no Dask, {threads} numba thread(s): {n_cases} cases in "
              f"{dt:7.2f} s = {serial[threads]:6.1f} cases/min; CPU "
              f"{cpu / n_cases:6.4f} s a case", flush=True)
    # the loop that makes what a study makes: the same cases and the same store file
    # (run_serial + the NetCDF write), one numba thread as a worker has
    numba.set_num_threads(1)
    forget_tables()
    t0 = time.perf_counter()
    run_serial(study).to_netcdf(tmp / "serial.nc", engine="h5netcdf")
    dt = time.perf_counter() - t0
    serial["store"] = 60 * n_cases / dt
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    print(f"serial loop writing the store, 1 numba thread: {n_cases} cases in "
          f"{dt:7.2f} s = {serial['store']:6.1f} cases/min", flush=True)
    return serial


if __name__ == "__main__":
    main()
