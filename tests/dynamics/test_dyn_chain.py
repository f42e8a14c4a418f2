"""Any chain of gears: a spur pair (no idler) and a four-gear helical chain with two idlers
at different layout angles. Checks the torque balance (mean force = T_i / r_bi within
0.5 %), the free rigid rotation, and that every mesh is loaded."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearsim.dynamics import DynamicsSettings, build_model, simulate
from gearsim.dynamics.modal import modes
from gearsim.model import example_text, load, loads

FOUR = """
name = "four-gear chain"
[common]
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
helix_angle = "15 deg"
face_width = "60 mm"
[[gears]]
teeth = 23
[[gears]]
teeth = 41
[[gears]]
teeth = 37
[[gears]]
teeth = 67
[operating]
speed = "3000 rpm"
torque = "800 N*m"
[[cracks]]
gear = "gear3"
tooth = 5
flank = "non-working"
depth = "1 mm"
[dynamics]
idler_angle = ["160 deg", "200 deg"]
duration = "0.12 s"
fs = "40 kHz"
"""


@pytest.mark.parametrize("model", ["lta", "seed"])
def test_four_gear_chain(model):
    gb = loads(FOUR)
    tr = gb.train
    s = dataclasses.replace(gb.dynamics, model=model)
    m = build_model(tr, s)
    assert m.n_mesh == 3
    assert modes(m).rigid == (1 if model == "lta" else 0)
    ds = simulate(tr, s)
    for i in range(3):
        f = ds[f"mesh_force_{i + 1}"].values
        assert np.mean(f) == pytest.approx(tr.static_mesh_force(i), rel=5e-3)
        assert np.std(f) > 0
    # the idler crack (gear3 is an idler: meshes 2 and 3) is in both tables
    assert [t.period for t in m.tables] == [1, 37, 37]


def test_spur_pair():
    tr = load("spur-19-48").train
    ds = simulate(tr, DynamicsSettings(duration=0.09, fs=20_000.0))
    assert "mesh_force_2" not in ds
    assert float(ds["mesh_force_1"].mean()) == pytest.approx(tr.static_mesh_force(0), rel=5e-3)
    assert ds.sizes["shaft"] == 2


def test_example_text_unchanged_by_dynamics():
    """The built-in example parses with and without a [dynamics] section."""
    gb = loads(example_text("idler-table1") + "\n[dynamics]\nmodel = \"seed\"\n")
    assert gb.dynamics.model == "seed"
    assert load("idler-table1").dynamics == DynamicsSettings()
