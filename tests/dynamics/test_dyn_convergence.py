"""Tier 1 (convergence): halving the default step changes the RMS of the mesh force
fluctuation by < 0.5 % (docs/references.md, "Dynamics self-checks"); RK4 shows its fourth order.

The measured study (docs/dynamics.md): RMS change 7e-4 from 20 to 10 us, 5e-5 from 10
to 5 us (LTA, working-flank crack).
"""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.dynamics import DynamicsSettings, simulate
from gearsim.dynamics.settings import DEFAULT_STEP
from gearsim.dynamics.tables import mesh_tables
from gearsim.model import load

HALVING_RTOL = 5e-3  # docs/references.md, "Dynamics self-checks"


@pytest.mark.parametrize("model", ["lta", "seed"])
def test_step_halving(model):
    tr = load("idler-table1").train
    tabs = mesh_tables(tr)
    rms = {}
    peak = {}
    for step in (2 * DEFAULT_STEP, DEFAULT_STEP, DEFAULT_STEP / 2):
        # oversample 1 at 50 kHz: the steps 20, 10, 5 us divide the 20 us output period
        s = DynamicsSettings(model=model, step=step, duration=0.11, fs=50_000.0,
                             oversample=1, transient=0.1)
        ds = simulate(tr, s, tables=tabs)
        assert ds.attrs["step"] == pytest.approx(step)
        rms[step] = np.array([float(ds[f"mesh_force_{i}"].std()) for i in (1, 2)])
        peak[step] = np.array([float(ds[f"mesh_force_{i}"].max()) for i in (1, 2)])
    change = np.abs(rms[DEFAULT_STEP / 2] / rms[DEFAULT_STEP] - 1)
    assert np.all(change < HALVING_RTOL), change
    coarse = np.abs(rms[DEFAULT_STEP] / rms[2 * DEFAULT_STEP] - 1)
    # fourth order: the change shrinks when the step is halved (16x in theory), until
    # it reaches the ~1e-5 level where the window's start-up and round-off dominate
    assert np.all(change <= np.maximum(coarse, 1e-5)), (coarse, change)
    assert np.all(np.abs(peak[DEFAULT_STEP / 2] / peak[DEFAULT_STEP] - 1) < HALVING_RTOL)
