"""Benchmark: the two fidelity levels of a gearbox graph, measured in one run.

The NREL GRC wind-turbine gearbox (planetary stage driving two parallel stages) and the
two-stage reducer, one simulated second each at the default 10 us step: the
lateral-torsional-axial assembly (``dynamics.model = "lta"``; Lin & Parker's planar
stage) against the purely torsional one (``"torsional"``). Prints the kernel time of
each (per simulated second and per RK4 step), the ratio, the sizes (coordinates x spring
rows, and the nonzeros of V: the kernel reads the rows sparse, so its work per step is
about that of the rows' nonzeros, a fixed cost per row and per coordinate) and the
largest stable RK4 step of each model. Target (issue 23): torsional >= 5x faster on the
wind-turbine box.

Run: ``.venv/bin/python benchmarks/bench_gearbox.py``
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.modal import stable_step
from gearsim.dynamics.simulate import build_model, run_kernel
from gearsim.model import example


def _models(name: str, fidelity: str):
    gb = example(name)
    st = dataclasses.replace(gb.dynamics, model=fidelity)
    if gb.stage is not None:
        return build_stage_chain_model(gb.stage, gb.train, gb.members, st,
                                       shaft_stiffness=gb.shaft_stiffness)
    return build_model(gb.train, st)


def _kernel_seconds(model, dt: float = 1e-5, seconds: float = 1.0, repeat: int = 3) -> float:
    run_kernel(model, dt=dt, n_steps=100, rec_every=10)  # compile / load the cache
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        run_kernel(model, dt=dt, n_steps=int(round(seconds / dt)), rec_every=10)
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    for name in ("wind-turbine-grc", "two-stage-reducer"):
        times = {}
        for fidelity in ("lta", "torsional"):
            m = _models(name, fidelity)
            times[fidelity] = _kernel_seconds(m)
            print(f"{name:18s} {fidelity:9s} kernel {times[fidelity]:.3f} s per simulated s "
                  f"({times[fidelity] / 1e5 * 1e9:.0f} ns per step), {m.n_dof} coordinates x "
                  f"{m.n_mesh} rows, {np.count_nonzero(m.V)} nonzeros of V, stable step "
                  f"{stable_step(m) * 1e6:.2f} us")
        ratio = times["lta"] / times["torsional"]
        target = "  (target >= 5: " + ("met" if ratio >= 5 else "NOT met") + ")" \
            if name == "wind-turbine-grc" else ""
        print(f"{name:18s} torsional speed-up {ratio:.2f}x{target}")


if __name__ == "__main__":
    main()
