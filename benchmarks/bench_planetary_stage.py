"""Benchmark: one simulated second of a 3-planet helical stage with a cracked planet, 50 kHz.

Stage z 30/24/78, m_n 2 mm, beta 15 deg, b 20 mm, three planets, a 1 mm root crack on a
tooth of planet 1 (working flank), ring held, sun input 1500 rpm, 100 N m; potential-energy
tables of both meshes (internal mesh with the ring tooth model), output 50 kHz
(oversampling 2, FIR decimation), no transient. Prints the time of the tables, of the
compiled-kernel run and of the whole ``simulate_stage`` (after compilation), and the same
equations (numpy right-hand side :func:`gearsim.dynamics.simulate.reference_rhs`) with
``scipy.integrate.solve_ivp`` (RK45, rtol 1e-6) over a short window, scaled to one second,
measured in the same run. Target: ``simulate_stage`` < 1 s on one core.

Run: ``.venv/bin/python benchmarks/bench_planetary_stage.py [--ivp-window 0.01]``
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import reference_rhs
from gearsim.dynamics.stage import StageDynamics, build_stage_model, simulate_stage
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.stiffness.crack import Crack
from gearsim.system.planetary import PlanetaryTrain, StageOperating


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ivp-window", type=float, default=0.01, help="solve_ivp window [s]")
    args = ap.parse_args()
    st = PlanetaryStage(30, 24, 78, 2e-3, planets=3, helix_angle=math.radians(15.0),
                        face_width=0.02, ring_addendum_coefficient=0.8)
    train = PlanetaryTrain(st, StageOperating(speed=1500 * 2 * math.pi / 60, torque=100.0),
                           cracks=(Crack(gear="planet-1", tooth=0, depth=1e-3),))
    settings = DynamicsSettings(duration=1.0, fs=50_000.0, transient=0.0)
    t0 = time.perf_counter()
    model = build_stage_model(train, StageDynamics(), settings)
    t_tables = time.perf_counter() - t0
    # compile (or load the numba cache) and first-call imports
    simulate_stage(train, StageDynamics(), DynamicsSettings(duration=0.01, fs=50_000.0,
                                                             transient=0.0), model=model)
    t0 = time.perf_counter()
    ds = simulate_stage(train, StageDynamics(), settings, model=model)
    t_sim = time.perf_counter() - t0
    dt = float(ds.attrs["dt"])

    fun = reference_rhs(model)
    y0 = np.concatenate([model.q_static, np.zeros(model.n_dof)])
    t0 = time.perf_counter()
    sol = solve_ivp(fun, (0.0, args.ivp_window), y0, method="RK45", rtol=1e-6)
    t_ivp = (time.perf_counter() - t0) / args.ivp_window
    assert sol.success
    print(f"planetary stage (3 planets, helical, cracked planet): {model.n_dof} DOF, "
          f"{model.n_mesh} springs, dt = {dt * 1e6:.3g} us")
    print(f"  tables + model build:           {t_tables:8.3f} s (first time, not cached)")
    print(f"  simulate_stage, 1 s at 50 kHz:  {t_sim:8.3f} s   (target < 1 s: "
          f"{'met' if t_sim < 1.0 else 'NOT met'})")
    print(f"  solve_ivp RK45 (numpy rhs):     {t_ivp:8.3f} s per simulated second "
          f"(window {args.ivp_window} s)")
    print(f"  ratio solve_ivp / simulate:     {t_ivp / t_sim:8.1f}")


if __name__ == "__main__":
    main()
