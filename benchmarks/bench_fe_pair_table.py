"""Cost of the FE-pair stiffness table and of the options beyond the seed (issue 15).

* FE gear pair, 19/48 spur pair at 100 N m: one solve at the default level (meshing and
  factorising included; target < 5 s on one core), the healthy mesh cycle of 20
  positions at the default level and at the table's level 1 (target < 1 min), and the
  cached re-run of the table (target < 1 s).
* The PE table (one revolution, 40 positions per cycle) with the 2D line contact and the
  FE body coupling, against the seed's options in the same run (the coupling's FE body
  table is cached; its first computation is timed separately).

Run: ``.venv/bin/python benchmarks/bench_fe_pair_table.py``. Uses a fresh temporary
cache folder.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
import time

from gearsim.fem.pair import DEFAULT_LEVEL, FEPairModel
from gearsim.model import load
from gearsim.stiffness.settings import MODELS

TARGET_SOLVE = 5.0
TARGET_CYCLE = 60.0
TARGET_CACHED = 1.0


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def main() -> None:
    os.environ["GEARSIM_CACHE"] = tempfile.mkdtemp(prefix="gearsim-bench-")
    train = load("spur-19-48").train.with_cracks(())
    # the seed's options as the reference (the example's own model is the accurate one)
    train = dataclasses.replace(train, stiffness=dataclasses.replace(train.stiffness,
                                                                     **MODELS["seed"]))
    pair = train.pairs[0]
    torque = train.torque(0)

    def one():
        return FEPairModel(pair, torque=torque, level=DEFAULT_LEVEL).solve(0.5)

    _, t_one = timed(one)
    print(f"one FE-pair solve, level {DEFAULT_LEVEL}, set-up included: {t_one:.2f} s "
          f"(target {TARGET_SOLVE:g} s: ratio {t_one / TARGET_SOLVE:.2f})")

    def cycle(level):
        m = FEPairModel(pair, torque=torque, level=level)
        return [m.solve(i / 20).stiffness for i in range(20)]

    for level in (DEFAULT_LEVEL, 1):
        _, t = timed(lambda level=level: cycle(level))
        print(f"20 positions, level {level}: {t:.2f} s (target {TARGET_CYCLE:g} s: ratio "
              f"{t / TARGET_CYCLE:.2f})")

    fe_train = dataclasses.replace(train, stiffness=dataclasses.replace(
        train.stiffness, source="fe-pair"))
    _, t_first = timed(lambda: fe_train.mesh_stiffness(0))
    _, t_cached = timed(lambda: fe_train.mesh_stiffness(0))
    print(f"fe-pair table (level 1, 20 positions, one revolution): first {t_first:.2f} s, "
          f"cached {t_cached * 1e3:.1f} ms (target {TARGET_CACHED:g} s: ratio "
          f"{t_cached / TARGET_CACHED:.4f})")

    seed_st = train.stiffness
    new_st = dataclasses.replace(seed_st, contact="line", coupling="fe")
    _, t_body = timed(lambda: dataclasses.replace(train, stiffness=new_st).mesh_stiffness(0))
    _, t_seed = timed(lambda: train.mesh_stiffness(0))
    _, t_new = timed(lambda: dataclasses.replace(train, stiffness=new_st).mesh_stiffness(0))
    print(f"PE table, one revolution: seed options {t_seed * 1e3:.1f} ms, line contact + "
          f"coupling {t_new * 1e3:.1f} ms (ratio {t_new / t_seed:.2f}); first call with the "
          f"FE body tables {t_body:.2f} s")


if __name__ == "__main__":
    main()
