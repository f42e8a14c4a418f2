"""Benchmark of ``gearsim.studies.life``: one full life and a 100-record run-to-failure store.

Run: ``.venv/bin/python benchmarks/bench_life.py [--increment MM] [--steps N]
[--torque-factor F] [--seeds S] [--fractions K]``

The Table-1 input gear of ``idler-table1`` (its 2 mm crack at 45 deg on the working
flank as initial crack). At the rated torque a 2 mm crack does not grow (the answer is
"no growth": dK about 2.5 MPa sqrt(m) against a threshold of 6), so the life runs at
``--torque-factor`` (default 4) times the rated torque. Prints: the FE cost of every
increment (mesh, one solve for all contact positions of the mesh cycle, interaction
integral), the life (end reason, cycles, hours), the total (target: < 10 min on 2
cores), then the time of a store of ``--seeds`` x ``--fractions`` records (default
10 x 10 = 100; target < 5 min once the life is computed) and the seed mean of the
indicators at each fraction with the alarm fractions.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import gearsim as gs
from gearsim.fracture.paris import MPA_SQRT_M
from gearsim.studies.life import (
    alarm_fractions,
    gear_life,
    indicator_trends,
    life_records,
    write_store,
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--increment", type=float, default=0.6, help="mm")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--torque-factor", type=float, default=4.0)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--fractions", type=int, default=10)
    args = ap.parse_args()
    gb = gs.example("idler-table1")
    speed, torque = gb.operating()
    gb = gb.at(speed=speed, torque=args.torque_factor * torque)
    t0 = time.perf_counter()
    res = gear_life(gb, increment=args.increment * 1e-3, steps=args.steps)
    t_life = time.perf_counter() - t0
    p = res.path
    print(f"life of {res.gear} at {args.torque_factor:g} x {torque:g} N*m: static "
          f"{res.static_force:.6g} N/m, DLF {res.dynamic_load_factor:.4f}, "
          f"{res.radii.size} contact positions per cycle")
    print(" inc  length[mm]  dK[MPa sqrt(m)]  kink[deg]   dofs  FE[s]")
    for i in range(p.lengths.size):
        print(f"{i:4d}  {p.lengths[i] * 1e3:10.3f}  "
              f"{p.keq[i] * res.dynamic_load_factor / MPA_SQRT_M:15.4f}  "
              f"{np.degrees(p.kink[i]):9.3f}  {p.dofs[i]:5d}  {p.seconds_per_step[i]:5.2f}")
    print(f"path: {p.status} {p.message}")
    print(f"end: {res.end} at a = {res.life.a_end * 1e3:.4g} mm after {res.cycles_end:.6g} "
          f"cycles = {res.hours_end:.6g} h")
    print(f"FE per increment: mean {p.seconds_per_step.mean():.2f} s, max "
          f"{p.seconds_per_step.max():.2f} s; whole life {t_life:.1f} s (target < 600 s)")
    fr = np.round(np.linspace(0.0, 1.0, args.fractions), 6)
    t1 = time.perf_counter()
    ds = life_records(gb, res, fr, args.seeds)
    with tempfile.TemporaryDirectory() as tmp:
        write_store(ds, Path(tmp) / "life.nc")
    t_store = time.perf_counter() - t1
    n = ds.sizes["fraction"] * ds.sizes["seed"]
    print(f"store: {n} records ({ds.sizes['fraction']} rows x {ds.sizes['seed']} seeds, "
          f"{ds.attrs['duration_s']:.4g} s each): {t_store:.1f} s (target < 300 s); "
          f"simulations {float(ds['simulation_seconds'].sum()):.1f} s")
    trends = indicator_trends(ds)
    print("fraction  length[mm]  " + "  ".join(f"{k:>17s}" for k in trends))
    for i, f in enumerate(ds["fraction"].values):
        print(f"{f:8.3f}  {ds['crack_length'].values[i] * 1e3:10.3f}  "
              + "  ".join(f"{trends[k][i]:17.4f}" for k in trends)
              + ("  broken tooth" if ds["broken"].values[i] else ""))
    print("alarm fractions:", {k: None if v is None else round(v, 3)
                               for k, v in alarm_fractions(ds).items()})


if __name__ == "__main__":
    main()
