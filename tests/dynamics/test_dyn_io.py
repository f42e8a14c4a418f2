"""Results file, config section and CLI: units, provenance, round trips."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import gearsim
from gearsim.cli import app
from gearsim.dynamics import DynamicsSettings
from gearsim.errors import InputError
from gearsim.io.results import read_results
from gearsim.model import example_text, load, loads


def test_dynamics_section_with_units_and_lists():
    text = example_text("idler-table1") + """
[dynamics]
model = "seed"
step = "8 us"
duration = "150 ms"
fs = "20 kHz"
bearing_stiffness = "5e8 N/m"
mesh_damping_ratio = 0.05
idler_angle = "150 deg"
runout = ["5 um", "0 um", "2 um"]
backlash = "0.3 mm"
"""
    d = loads(text).dynamics
    assert isinstance(d, DynamicsSettings)
    assert d.model == "seed"
    assert d.step == pytest.approx(8e-6)
    assert d.duration == pytest.approx(0.15)
    assert d.fs == pytest.approx(2e4)
    assert d.idler_angle == pytest.approx((math.radians(150),))
    assert d.runout == pytest.approx((5e-6, 0.0, 2e-6))
    assert d.backlash == pytest.approx((3e-4,))
    with pytest.raises(InputError, match="unknown key"):
        loads(example_text("idler-table1") + "\n[dynamics]\nstepp = 1e-5\n")
    with pytest.raises(InputError, match="dynamics.step"):
        loads(example_text("idler-table1") + '\n[dynamics]\nstep = "3 mm"\n')


def test_cli_writes_netcdf_with_provenance(tmp_path):
    out = tmp_path / "run.nc"
    res = CliRunner().invoke(app, ["simulate", "idler-table1", "--crack", "non-working",
                                   "--duration", "0.11", "--fs", "20000", "--out", str(out),
                                   "--json", "--plot"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert [m["mesh"] for m in summary["meshes"]] == [1, 2]
    for m in summary["meshes"]:
        assert set(m) >= {"mean", "rms", "peak", "static_force"}
        assert abs(m["mean_error"]) < 5e-3
    assert (tmp_path / "run.png").stat().st_size > 10_000
    ds = read_results(out)
    assert ds.attrs["fs"] == 20000.0
    assert ds.attrs["gearsim_version"] == gearsim.__version__
    assert ds["time"].attrs["units"] == "s"
    for name, unit in (("mesh_force_1", "N"), ("mesh_force_2", "N"), ("dte_1", "m"),
                       ("bearing_force", "N"), ("acceleration", "m/s^2")):
        assert ds[name].attrs["units"] == unit
    assert ds.sizes["time"] == round(0.11 * 20000)
    np.testing.assert_allclose(np.diff(ds["time"].values), 1 / 20000, rtol=1e-9)
    assert "non-working" in ds.attrs["cracks"]
    # the stored config reproduces the run's input
    gb = loads(ds.attrs["config"])
    tr = gb.train
    assert tr.cracks[0].flank == "non-working"
    assert gb.dynamics.duration == pytest.approx(0.11)
    assert tr.pairs[0].centre_distance == pytest.approx(
        load("idler-table1").train.pairs[0].centre_distance, rel=1e-12)
    assert np.all(np.isfinite(ds["acceleration"].values))


def test_default_crack_when_config_has_none(tmp_path):
    tr = load("spur-19-48").train.with_cracks(())
    cracked = tr.with_crack("working")
    (c,) = cracked.cracks
    assert (c.gear, c.tooth, c.flank) == (tr.gears[0].name, 0, "working")
    assert c.depth == pytest.approx(2e-3)
    assert c.angle == pytest.approx(math.radians(45))
    assert load("idler-table1").train.with_crack("none").cracks == ()


def test_bearing_forces_balance_mesh_forces_on_average():
    """Mean bearing force of each gear = vector sum of its mean mesh forces (LTA)."""
    from gearsim.dynamics import build_model, simulate

    tr = load("idler-table1").train.with_cracks(())
    s = DynamicsSettings(duration=0.11, fs=20000.0)
    ds = simulate(tr, s)
    m = build_model(tr, s)
    n = m.info["line_of_action"]
    f = [tr.static_mesh_force(i) for i in range(2)]
    expected = np.array([-f[0] * n[0], f[0] * n[0] - f[1] * n[1], f[1] * n[1]])
    got = ds["bearing_force"].mean("time").values[:, :2]
    np.testing.assert_allclose(got, expected, atol=2e-3 * f[0])  # gear pushes bearing
