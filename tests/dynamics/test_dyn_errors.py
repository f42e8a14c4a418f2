"""Bad input and failures: refused before running, errors instead of NaN, atomic output."""

from __future__ import annotations

import dataclasses
import re

import pytest
from typer.testing import CliRunner

from gearsim.cli import app
from gearsim.dynamics import DynamicsSettings, build_model, simulate
from gearsim.dynamics.modal import RK4_LIMIT, modes, stable_step
from gearsim.errors import InputError, SimulationError
from gearsim.model import load


def test_unstable_step_refused_with_largest_safe_step():
    tr = load("idler-table1").train
    s = DynamicsSettings(step=2e-4, fs=5000.0, oversample=1, duration=0.11)  # fs > 2 f_m
    m = build_model(tr, s)
    limit = stable_step(m)
    assert limit == pytest.approx(RK4_LIMIT / (2 * 3.141592653589793
                                               * modes(m, which="max").frequencies.max()))
    with pytest.raises(InputError) as exc:
        simulate(tr, s, model=m)
    assert exc.value.parameter == "dynamics.step"
    assert f"{limit:.4g}" in str(exc.value)
    # a step just below the limit runs
    ok = dataclasses.replace(s, step=0.95 * limit, fs=1.0 / (0.95 * limit), duration=0.11)
    simulate(tr, ok, model=m)


def test_divergence_raises_simulation_error_not_nan():
    tr = load("idler-table1").train
    s = DynamicsSettings(step=5e-4, fs=2500.0, oversample=1, duration=0.11, transient=0.0)
    with pytest.raises(SimulationError, match="diverged"):
        simulate(tr, s, check_step=False)


def test_short_duration_refused():
    tr = load("idler-table1").train
    with pytest.raises(InputError) as exc:
        simulate(tr, DynamicsSettings(duration=0.05))
    assert exc.value.parameter == "dynamics.duration"
    t_out = 1.0 / tr.shaft_frequency(2)
    assert re.search(r"must be >= 0\.1012", str(exc.value)), (str(exc.value), t_out)


def test_cli_exit_2_and_existing_file_survives(tmp_path):
    out = tmp_path / "run.nc"
    out.write_bytes(b"previous result")
    runner = CliRunner()
    from gearsim.cli import main  # noqa: F401  (main maps InputError to exit 2)

    res = runner.invoke(app, ["simulate", "idler-table1", "--duration", "0.01", "--out",
                              str(out)])
    assert isinstance(res.exception, InputError)
    assert out.read_bytes() == b"previous result"
    assert list(tmp_path.iterdir()) == [out]


def test_cli_main_exit_status(tmp_path, monkeypatch, capsys):
    import sys

    from gearsim.cli import main

    out = tmp_path / "run.nc"
    monkeypatch.setattr(sys, "argv", ["gearsim", "simulate", "idler-table1", "--duration",
                                      "0.01", "--out", str(out)])
    with pytest.raises(SystemExit) as exc:
        main()
    assert exc.value.code == 2
    assert "--duration = 0.01" in capsys.readouterr().err  # the option the user typed
    assert not out.exists()


def test_failed_write_keeps_existing_file(tmp_path, monkeypatch):
    import xarray as xr

    from gearsim.io.results import write_results

    out = tmp_path / "run.nc"
    out.write_bytes(b"previous result")
    ds = xr.Dataset({"a": ("time", [1.0, 2.0])})

    def broken(self, path, *args, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"partial")
        raise OSError("disk full")

    def broken_store(self, store, **kwargs):  # the temporary file is open, half written
        raise OSError("disk full")

    # write_results writes numpy records through dump_to_store, dask ones by to_netcdf
    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    monkeypatch.setattr(xr.Dataset, "dump_to_store", broken_store)
    with pytest.raises(OSError, match="disk full"):
        write_results(ds, out)
    assert out.read_bytes() == b"previous result"
    assert list(tmp_path.iterdir()) == [out]


def test_bad_settings_refused():
    with pytest.raises(InputError, match="dynamics.model"):
        DynamicsSettings(model="fe")
    with pytest.raises(InputError, match="dynamics.mesh_damping_ratio"):
        DynamicsSettings(mesh_damping_ratio=-0.1)
    tr = load("idler-table1").train
    with pytest.raises(InputError, match="one per gear"):
        simulate(tr, DynamicsSettings(runout=(1e-6, 2e-6), duration=0.11))
