"""Benchmark: one simulated second of the Table-1 train (LTA, working-flank crack).

Default converged step (10 us), output at 50 kHz. Prints the compiled-kernel time (with
the arithmetic of a step counted from the kernel's loops and the rate achieved), the
full ``simulate`` time (tables and model given: checks, modal analysis, kernel,
decimation, dataset) and its ratio to the kernel (issue 26: <= 1.3), the anti-aliasing
decimation alone (``_kernels.decimate_linear`` with the maps of
:func:`gearsim.dynamics.simulate.linear_records`: the signals filtered, the records
formed) and its share of ``simulate``, the rest by difference, and the time of
the same equations (numpy right-hand side, :func:`gearsim.dynamics.reference_rhs`) with
``scipy.integrate.solve_ivp`` (RK45, rtol 1e-6), measured in the same run on a shorter
window and scaled linearly to one second (the solve_ivp cost per simulated second is
constant once past the start). Target: kernel < 1 s, ratio >= 50. The kernel,
``simulate`` and the decimation are timed in turns in one loop, best of ``--repeat``
(default 5), so that a load on the machine weighs on all three alike.

Run: ``.venv/bin/python benchmarks/bench_dynamics.py [--ivp-window 0.02]``
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from gearsim.dynamics import DynamicsSettings, _kernels, build_model, reference_rhs, simulate
from gearsim.dynamics.simulate import (
    FIR_HALF_PER_R,
    anti_alias_taps,
    integration_step,
    linear_records,
    run_kernel,
)
from gearsim.dynamics.tables import mesh_tables
from gearsim.model import load


def flops_per_step(model) -> int:
    """Arithmetic of one RK4 step of the kernel, counted from its loops
    (:mod:`gearsim.dynamics._kernels`): four right-hand sides and the stage updates.

    Per right-hand side: each mesh row 4 operations per nonzero of V (V q and V q'), 2 per
    nonzero back (V^T f), about 20 for the table read (cycle, floor, two samples, weight),
    the force law and the damping, and 6 per STE harmonic with a nonzero amplitude (sin
    and cos counted once each); each coordinate 7 (bearing spring, damper, load, 1/M).
    Per step: 4 right-hand sides and 22 operations per coordinate for the RK4 stages.
    """
    nnz = int(np.count_nonzero(model.V))
    rows = model.V.shape[0]
    harmonics = int(np.count_nonzero(model.h_amp))
    rhs = 6 * nnz + 20 * rows + 6 * harmonics + 7 * model.n_dof
    return 4 * rhs + 22 * model.n_dof


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ivp-window", type=float, default=0.02, help="solve_ivp window [s]")
    ap.add_argument("--repeat", type=int, default=5, help="best of this many runs")
    args = ap.parse_args()
    train = load("idler-table1").train  # working-flank crack on the input gear
    settings = DynamicsSettings(model="lta", duration=1.0, fs=50_000.0, transient=0.0)
    tables = mesh_tables(train)
    model = build_model(train, settings, tables=tables)
    dt, m = integration_step(settings)
    n_steps = int(round(1.0 / dt))
    run_kernel(model, dt=dt, n_steps=100, rec_every=m)  # compile / load the cache
    simulate(train, DynamicsSettings(model="lta", duration=0.11, fs=50_000.0, transient=0.0),
             tables=tables, model=model)  # first-call imports (xarray, scipy.special)

    # the anti-aliasing decimation alone, as simulate() runs it: the channels the kernel
    # records for the records (rows of ones), r fs to fs, the records formed
    r = settings.oversample
    half = FIR_HALF_PER_R * r
    n_out = int(round(settings.duration * settings.fs))
    lin = linear_records(model, train)
    rows = sum(c.size for c in lin.channels)
    signals = lin.pre[0].size - 1
    x = np.ones((rows, (n_out - 1) * r + 1 + 2 * half))
    taps = anti_alias_taps(r, settings.fs)
    extra = np.ones((len(lin.extra), n_out))

    def decimate(n: int) -> np.ndarray:
        z = np.empty((len(lin.names), n))  # a new output, as in simulate()
        return _kernels.decimate_linear(taps, x, r, 2 * half // r, n, *lin.pre, extra[:, :n],
                                        *lin.post, z)

    decimate(1)  # cache load

    t_kernel = t_sim = t_fir = math.inf
    for _ in range(args.repeat):  # best of --repeat, in turns
        t0 = time.perf_counter()
        run_kernel(model, dt=dt, n_steps=n_steps, rec_every=m)
        t_kernel = min(t_kernel, time.perf_counter() - t0)
        t0 = time.perf_counter()
        simulate(train, settings, tables=tables, model=model)
        t_sim = min(t_sim, time.perf_counter() - t0)
        t0 = time.perf_counter()
        decimate(n_out)
        t_fir = min(t_fir, time.perf_counter() - t0)

    fun = reference_rhs(model)
    y0 = np.concatenate([model.q_static, np.zeros(model.n_dof)])
    t0 = time.perf_counter()
    sol = solve_ivp(fun, (0.0, args.ivp_window), y0, method="RK45", rtol=1e-6)
    t_ivp = (time.perf_counter() - t0) / args.ivp_window
    assert sol.success

    # same-window cost of the kernel for an apples-to-apples ratio
    t0 = time.perf_counter()
    run_kernel(model, dt=dt, n_steps=int(round(args.ivp_window / dt)), rec_every=m)
    t_kernel_win = (time.perf_counter() - t0) / args.ivp_window

    print(f"LTA Table-1 train, working-flank crack, dt = {dt * 1e6:.3g} us, "
          f"{n_steps} steps, output {settings.fs / 1e3:g} kHz")
    t_rest = t_sim - t_kernel - t_fir
    print(f"numba RK4 kernel, 1 s simulated:          {t_kernel:8.4f} s  (target < 1 s)")
    print(f"simulate() incl. checks and decimation:   {t_sim:8.4f} s  = {t_sim / t_kernel:4.2f} x "
          "the kernel (issue 26 target <= 1.3)")
    print(f"  of which the decimation, {signals} signals:  {t_fir:8.4f} s  = {t_fir / t_sim:4.0%} of "
          f"simulate() ({signals} x {n_out} outputs x {taps.size} taps = "
          f"{signals * n_out * taps.size / 1e6:.0f} M multiply-adds; from {rows} channels, "
          f"{len(lin.names)} records)")
    print(f"  the rest (STE, tacho, dataset, modes, checks; by difference): "
          f"{t_rest:6.4f} s  = {t_rest / t_sim:4.0%} of simulate()")
    print(f"  (best of {args.repeat} each, in turns; the 2-core machine may have been loaded)")
    print(f"solve_ivp RK45 rtol 1e-6, per simulated s: {t_ivp:8.2f} s  "
          f"(measured on {args.ivp_window:g} s, {sol.nfev} evaluations, scaled)")
    ops = flops_per_step(model)
    print(f"arithmetic: ~{ops} operations per step ({model.n_dof} coordinates, "
          f"{model.V.shape[0]} rows, {np.count_nonzero(model.V)} nonzeros of V): "
          f"{ops * n_steps / t_kernel / 1e9:.2f} Gop/s achieved, "
          f"{t_kernel / n_steps * 1e9:.0f} ns per step")
    print(f"speed-up kernel vs solve_ivp:             {t_ivp / t_kernel:8.0f} x  (target >= 50)")
    print(f"  (same {args.ivp_window:g} s window for both: {t_ivp / t_kernel_win:.0f} x)")


if __name__ == "__main__":
    main()
