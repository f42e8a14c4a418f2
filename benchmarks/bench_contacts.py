"""Benchmark: one simulated second of the Table-1 train with a spall, mesh of contacts.

The healthy Table-1 train on the stiffness-table kernel path against the same train
with a spall on tooth 0 of the input gear (3 mm x 20 mm x 0.1 mm at the pitch circle)
run as a mesh of contacts with per-slice contacts (40 slices, tip-corner contacts on),
and a third run with every mesh forced onto the contact path (``contact_mesh``), all
measured in this run with the compiled kernel only (tables built beforehand), default
step 10 us, output 50 kHz. Target: contact path within 3 x the table path.

Run: ``.venv/bin/python benchmarks/bench_contacts.py``
"""

from __future__ import annotations

import time

from gearsim.dynamics import DynamicsSettings, build_model
from gearsim.dynamics.simulate import integration_step, run_kernel
from gearsim.model import load
from gearsim.stiffness.faults import Spall


def _time(model, dt, n, m, repeat=3):
    run_kernel(model, dt=dt, n_steps=100, rec_every=m)  # compile / load the cache
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        run_kernel(model, dt=dt, n_steps=n, rec_every=m)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    train = load("idler-table1").train.with_crack("none")
    g = train.gears[0]
    spall = train.with_faults((Spall(gear=g.name, tooth=0, radius=g.pitch_radius,
                                     length=3e-3, width=20e-3, depth=1e-4),))
    settings = DynamicsSettings(duration=1.0, fs=50_000.0, transient=0.0)
    dt, m = integration_step(settings)
    n = int(round(1.0 / dt))
    t0 = time.perf_counter()
    table_model = build_model(train, settings)
    t_tab_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    spall_model = build_model(spall, settings)
    t_contact_build = time.perf_counter() - t0
    forced = build_model(spall, DynamicsSettings(duration=1.0, fs=50_000.0, transient=0.0,
                                                 contact_mesh=True))
    listed = [int(t.kx.size) if t.has_contacts else 0 for t in spall_model.tables]
    t_table = _time(table_model, dt, n, m)
    t_contact = _time(spall_model, dt, n, m)
    t_forced = _time(forced, dt, n, m)
    print(f"Table-1 train, 1 s simulated, dt = {dt * 1e6:.3g} us ({n} steps), 40 slices")
    print(f"table kernel (healthy):                      {t_table:7.3f} s")
    print(f"mesh of contacts, spall on mesh I:            {t_contact:7.3f} s  "
          f"ratio {t_contact / t_table:5.2f} x  (target <= 3)")
    print(f"every mesh a mesh of contacts:                {t_forced:7.3f} s  "
          f"ratio {t_forced / t_table:5.2f} x")
    print(f"  listed (separated) contacts per mesh: {listed}; tables built in "
          f"{t_tab_build:.2f} s (table) / {t_contact_build:.2f} s (contacts)")


if __name__ == "__main__":
    main()
