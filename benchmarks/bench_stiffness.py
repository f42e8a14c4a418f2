"""Benchmark: TVMS of the cracked Table-1 mesh I over one revolution of the input gear.

Compares gearsim's compiled kernels (fixed Gauss-Legendre rules, numba) with a
straightforward reference that integrates every tooth compliance with
``scipy.integrate.quad`` (``gearsim.stiffness.reference``), measured in the same run.
The reference is timed on a sample of the contact points and scaled to the same number
of tooth evaluations the kernel path performs (stated in the output).

Run: ``.venv/bin/python benchmarks/bench_stiffness.py``; target: < 1 s after
compilation and >= 50 x faster than the reference.
"""

from __future__ import annotations

import time

import numpy as np

from gearsim.model import load
from gearsim.stiffness.crack import crack_record
from gearsim.stiffness.mesh import _slice_grid
from gearsim.stiffness.reference import reference_compliance
from gearsim.stiffness.tooth import ToothModel


def _forget(healthy: bool) -> None:
    """Empty the process's memo of mesh tables, and with ``healthy`` the healthy teeth's
    compliances and the crack's start and outline (a fresh process)."""
    import gearsim.stiffness.crack as cr
    import gearsim.stiffness.tooth as to
    import gearsim.system.train as tm

    tm._TABLES.clear()
    if healthy:
        for cache in (to._healthy_compliance, cr._tangent_param, cr._outline):
            cache.cache_clear()


def main() -> None:
    import warnings

    warnings.simplefilter("ignore")

    import numba

    train = load("idler-table1").train  # working-flank crack, 2 mm, default settings
    s = train.stiffness
    train.mesh_stiffness(0)  # compile / load cache
    reps = 5
    # cold: every tooth's compliances computed (the process's caches emptied each time);
    # in a study: the healthy teeth's compliances cached by value (a case cracks one gear).
    # One numba thread (a study's Dask worker) and all of them (a single run; the
    # tooth-compliance batches run on numba's threads)
    times = {}
    for threads in sorted({1, numba.config.NUMBA_NUM_THREADS}):
        numba.set_num_threads(threads)
        t_fast = t_case = np.inf
        for _ in range(reps):
            _forget(healthy=True)
            t0 = time.perf_counter()
            res = train.mesh_stiffness(0)
            t_fast = min(t_fast, time.perf_counter() - t0)
            _forget(healthy=False)
            t0 = time.perf_counter()
            train.mesh_stiffness(0)
            t_case = min(t_case, time.perf_counter() - t0)
        times[threads] = t_fast, t_case
    pair = train.pairs[0]
    lmid, frac, *_ = _slice_grid(pair, s)
    n_points = int(np.count_nonzero(frac > 0))
    # the kernel path evaluates: healthy driver + healthy driven + cracked driver tables
    n_evals = 3 * n_points
    # reference: quad per point, on a sample, scaled to n_evals
    gear = pair.driver
    tm = ToothModel(gear, closure=s.closure)
    rec = crack_record(tm.profile, train.cracks[0], train.cracks[0].depth, 1)
    radii = np.hypot(gear.base_radius, lmid[frac > 0])
    sample = radii[:: max(1, radii.size // 30)]
    t0 = time.perf_counter()
    for r in sample:
        reference_compliance(tm, float(r), rec, epsrel=1.49e-8)  # quad's default
    t_ref_each = (time.perf_counter() - t0) / sample.size
    t_ref = t_ref_each * n_evals
    print(f"TVMS mesh I, one revolution of the input gear: {res.k.size} positions "
          f"({s.positions_per_cycle}/mesh cycle), {res.attrs['slices']} slices, "
          f"closure {s.closure}")
    for threads, (t_fast, t_case) in times.items():
        print(f"  {threads} numba thread(s), best of {reps}:")
        print(f"  gearsim kernels      : {t_fast:.3f} s   (target < 1 s, issue 26: < 0.04 s; "
              f"every tooth computed: {n_evals} tooth compliances, "
              f"{n_evals / t_fast / 1e3:.0f} k per s, {t_fast / n_evals * 1e6:.1f} us each, "
              f"{s.gauss_points} Gauss nodes per piece)")
        print(f"  in a study           : {t_case:.3f} s   (the healthy teeth's compliances "
              f"cached by value, the cracked tooth's {n_points} computed: "
              f"{t_case / n_points * 1e6:.1f} us each)")
    t_fast = times[1][0]
    print(f"  quad reference       : {t_ref:.1f} s   ({t_ref_each * 1e3:.1f} ms per tooth "
          f"compliance x {n_evals} evaluations, timed on {sample.size})")
    print(f"  speed-up             : {t_ref / t_fast:.0f} x   (one thread; target >= 50 x)")


if __name__ == "__main__":
    main()
