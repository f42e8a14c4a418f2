"""Output targets checked before any work, folders replaced whole, costs refused up front.

Every refusal is one line on standard error, exit status 2, within seconds (timed
loosely: the run would take minutes to days, or write only after minutes), and leaves
the working folder as it was. The runs are in-process (``gearsim.cli.run``) but for
the ``reproduce`` killed with SIGKILL while it writes.
"""

from __future__ import annotations

import hashlib
import importlib
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from gearsim import cli
from gearsim.dynamics import DynamicsSettings
from gearsim.dynamics.simulate import MAX_STEPS, check_cost, simulate
from gearsim.errors import InputError
from gearsim.io.targets import atomic_folder
from gearsim.model import example_text, load

simulate_module = importlib.import_module("gearsim.dynamics.simulate")

QUICK = 5.0  # s: a refusal of an output target
NO_WORK = 10.0  # s: a refusal of a cost (the run itself would take hours)


@pytest.fixture(scope="module", autouse=True)
def _warm():
    """Import the verbs once, so that the timings measure the checks."""
    if hasattr(cli, "run"):
        cli.app  # noqa: B018  (builds the typer app and imports every verb)


@pytest.fixture
def here(tmp_path, monkeypatch):
    """An empty working folder."""
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    return work


def _gearsim(capsys, monkeypatch, *args) -> tuple[int, str, float]:
    argv = [str(a) for a in args]
    t0 = time.perf_counter()
    if hasattr(cli, "run"):
        code = cli.run(argv)
    else:  # pragma: no cover  (before gearsim.cli.run existed)
        monkeypatch.setattr(sys, "argv", ["gearsim", *argv])
        try:
            cli.main()
            code = 0
        except SystemExit as exc:
            code = exc.code
    return code, capsys.readouterr().err, time.perf_counter() - t0


def _tree(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            if p.is_file() else "/" for p in sorted(folder.rglob("*"))}


def _refused(capsys, monkeypatch, folder: Path, *args, parameter: str,
             within: float = QUICK) -> str:
    before = _tree(folder)
    code, err, seconds = _gearsim(capsys, monkeypatch, *args)
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1, err
    assert lines[0].startswith(f"gearsim: error: {parameter} = "), err
    assert "Traceback" not in err
    assert seconds < within, (seconds, err)
    assert _tree(folder) == before  # nothing written
    return lines[0]


# --- output targets -----------------------------------------------------------------


def test_out_a_directory_is_refused(here, capsys, monkeypatch):
    (here / "d.nc").mkdir()
    (here / "t.csv").mkdir()
    _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--out", "d.nc",
             parameter="--out")
    _refused(capsys, monkeypatch, here, "stiffness", "spur-19-48", "--out", "t.csv",
             parameter="--out")
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--out", ".",
                    parameter="--out")
    assert "is a folder" in line


def test_out_in_read_only_folder_is_refused(here, capsys, monkeypatch):
    ro = here / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as a user who can write into a read-only folder (root)")
        line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--out",
                        ro / "run.nc", parameter="--out")
        assert "not writable" in line
        _refused(capsys, monkeypatch, here, "reproduce", "--no-fe", "--out", ro / "rep",
                 parameter="--out")
        _refused(capsys, monkeypatch, here, "stiffness", "spur-19-48", "--plot",
                 ro / "k.png", parameter="--plot")
    finally:
        ro.chmod(0o755)


def test_empty_out_is_refused(here, capsys, monkeypatch):
    for args in (("simulate", "idler-table1"), ("stiffness", "spur-19-48"),
                 ("reproduce", "--no-fe")):
        line = _refused(capsys, monkeypatch, here, *args, "--out", "", parameter="--out")
        assert line.startswith('gearsim: error: --out = "": must name a')
    _refused(capsys, monkeypatch, here, "compare", "a.nc", "b.nc", "--shaft-rpm", 1900,
             "--teeth", 39, "--plot", "", parameter="--plot")


def test_plot_unknown_suffix_is_refused(here, capsys, monkeypatch):
    for args in (("stiffness", "spur-19-48"),
                 ("compare", "a.nc", "b.nc", "--shaft-rpm", 1900, "--teeth", 39)):
        line = _refused(capsys, monkeypatch, here, *args, "--plot", "out.xyz",
                        parameter="--plot")
        assert line.endswith("must end in .png, .pdf or .svg")
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--out", "r.txt",
                    parameter="--out")
    assert line.endswith("must end in .nc")


def test_plot_existing_folder_for_a_file_target_is_refused(here, capsys, monkeypatch):
    (here / "figs").mkdir()
    (here / "figs" / "keep.txt").write_text("mine")
    (here / "run.png").mkdir()  # where simulate --plot would write
    for args in (("stiffness", "spur-19-48"),
                 ("compare", "a.nc", "b.nc", "--shaft-rpm", 1900, "--teeth", 39)):
        line = _refused(capsys, monkeypatch, here, *args, "--plot", "figs",
                        parameter="--plot")
        assert "is a folder" in line
    _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--out", "run.nc",
             "--plot", parameter="--plot")


def test_existing_file_or_foreign_folder_for_a_folder_target_is_refused(here, capsys,
                                                                       monkeypatch):
    (here / "figs").write_text("a file")
    (here / "mixed").mkdir()
    (here / "mixed" / "notes.txt").write_text("not gearsim's")
    # a readable record, so that the output target is the only problem of the call
    (here / "rec.csv").write_text("# fs = 1000\nacc\n"
                                  + "".join(f"{math.sin(0.3 * i):.6f}\n" for i in range(2000)))
    for args in (("analyze", "rec.csv", "--shaft-rpm", 1900, "--teeth", 39),
                 ("fe-check", "spur-19-48")):
        _refused(capsys, monkeypatch, here, *args, "--plot", "figs", parameter="--plot")
        line = _refused(capsys, monkeypatch, here, *args, "--plot", "mixed",
                        parameter="--plot")
        assert "'notes.txt'" in line and "replaced as a whole" in line
    _refused(capsys, monkeypatch, here, "reproduce", "--no-fe", "--out", "figs",
             parameter="--out")
    _refused(capsys, monkeypatch, here, "reproduce", "--no-fe", "--out", "mixed",
             parameter="--out")
    line = _refused(capsys, monkeypatch, here, "reproduce", "--no-fe", "--out", ".",
                    parameter="--out")
    assert "working folder" in line


# --- costs ----------------------------------------------------------------------------


@pytest.mark.parametrize("option,value", [("--fs", "1e9"), ("--step", "1e-12"),
                                          ("--transient", "1e6"), ("--duration", "1e6")])
def test_absurd_simulation_settings_are_refused_before_work(here, capsys, monkeypatch,
                                                            option, value):
    _refused(capsys, monkeypatch, here, "simulate", "idler-table1", option, value,
             parameter=option, within=NO_WORK)


@pytest.mark.parametrize("args,option", [
    (("--duration", "10000"), "--duration"),
    (("--transient", "10000"), "--transient"),
    (("--step", "1e-9"), "--step"),
    (("--fs", "1e7", "--duration", "100"), "--fs"),
])
def test_too_many_steps_refused_naming_the_option_and_the_override(here, capsys, monkeypatch,
                                                                   args, option):
    """Values inside their ranges whose product is more than MAX_STEPS (hours)."""
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", *args,
                    parameter=option, within=NO_WORK)
    assert "integration steps" in line and f"{MAX_STEPS:.0e}" in line
    assert "--force" in line and "GEARSIM_FORCE=1" in line


def test_memory_above_half_the_machine_refused_and_force_overrides(here, capsys,
                                                                   monkeypatch):
    monkeypatch.setattr(simulate_module, "physical_memory", lambda: 2**30)  # 1 GiB
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--duration",
                    "100", parameter="--duration", within=NO_WORK)
    assert "GB of memory" in line and "--force" in line
    # a short run over a tiny "machine" is refused, and runs with --force
    monkeypatch.setattr(simulate_module, "physical_memory", lambda: 2**20)
    args = ("simulate", "idler-table1", "--duration", "0.11", "--fs", "20000", "--out",
            "r.nc")
    _refused(capsys, monkeypatch, here, *args, parameter="--fs", within=NO_WORK)
    code, err, _ = _gearsim(capsys, monkeypatch, *args, "--force")
    assert code == 0, err
    with xr.open_dataset(here / "r.nc", engine="h5netcdf") as ds:
        assert ds.sizes["time"] == 2200


def test_check_cost_override_by_argument_and_environment(monkeypatch):
    train = load("idler-table1").train
    s = DynamicsSettings(duration=10_000.0)
    monkeypatch.delenv("GEARSIM_FORCE", raising=False)
    with pytest.raises(InputError) as exc:
        check_cost(train, s)
    assert exc.value.parameter == "dynamics.duration"
    assert check_cost(train, s, force=True).steps > MAX_STEPS
    monkeypatch.setenv("GEARSIM_FORCE", "1")
    assert check_cost(train, s).steps > MAX_STEPS
    # the estimate follows simulate's own grid: 1 s at 50 kHz, 10 us steps, no transient
    c = check_cost(train, DynamicsSettings(transient=0.0))
    assert c.samples == 50_000 and c.dt == pytest.approx(1e-5)
    assert c.steps == pytest.approx(1e5, rel=1e-3)


def test_reproduce_revolutions_refused_before_work(here, capsys, monkeypatch):
    line = _refused(capsys, monkeypatch, here, "reproduce", "--no-fe", "--revolutions",
                    "100000000", "--out", "rep", parameter="--revolutions", within=NO_WORK)
    assert "per case" in line
    line = _refused(capsys, monkeypatch, here, "reproduce", "--revolutions", "300000",
                    "--out", "rep", parameter="--revolutions", within=NO_WORK)
    # 10 route cases + 18 sensitivity cases + 25 fault-magnitude cases (8 classes x 3
    # severities + the healthy contact-mesh baseline)
    assert "53 simulations" in line and "--force" in line


def test_fe_check_points_bounded(here, capsys, monkeypatch):
    line = _refused(capsys, monkeypatch, here, "fe-check", "spur-19-48", "--points",
                    "100000", parameter="--points", within=NO_WORK)
    assert "<= 201" in line and "FE solve" in line


# --- aliasing and short records -------------------------------------------------------


def _fast_config(folder: Path, speed: str) -> Path:
    text = example_text("idler-table1")
    assert 'speed = "1900 rpm"' in text
    path = folder / f"fast-{speed.split()[0]}.toml"
    path.write_text(text.replace('speed = "1900 rpm"', f'speed = "{speed}"'))
    return path


@pytest.mark.parametrize("speed", ["12000 rpm", "900000 rpm"])
def test_aliasing_output_rate_refused(tmp_path, here, capsys, monkeypatch, speed):
    """fs = 50 kHz: 8 f_m (4 analysed harmonics) is 62.4 kHz at 12000 rpm."""
    cfg = _fast_config(tmp_path, speed)
    line = _refused(capsys, monkeypatch, here, "simulate", cfg, "--out", "r.nc",
                    parameter="dynamics.fs", within=NO_WORK)
    assert "aliased" in line
    train = load(cfg).train
    if speed == "12000 rpm":  # the API's default asks for f_m itself only
        check_cost(train, DynamicsSettings(), harmonics=1)
    with pytest.raises(InputError, match="aliased"):
        simulate(train, DynamicsSettings(), harmonics=4)


def test_one_sample_record_refused(here, capsys, monkeypatch):
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--fs", "10",
                    parameter="--fs", within=NO_WORK)
    assert "aliased" in line
    line = _refused(capsys, monkeypatch, here, "simulate", "idler-table1", "--duration",
                    "0.05", parameter="--duration", within=NO_WORK)
    assert "one revolution of the slowest gear" in line


# --- folders replaced whole -------------------------------------------------------------


def test_atomic_folder_keeps_the_old_folder_on_failure(tmp_path):
    d = tmp_path / "d"
    d.mkdir()
    (d / "a.png").write_text("old")
    with pytest.raises(RuntimeError), atomic_folder(d) as tmp:
        (tmp / "b.png").write_text("new")
        raise RuntimeError("killed")
    assert _tree(d) == {"a.png": hashlib.sha256(b"old").hexdigest()}
    with atomic_folder(d, keep=lambda n: n == "a.png") as tmp:
        (tmp / "b.png").write_text("new")
    assert sorted(p.name for p in d.iterdir()) == ["a.png", "b.png"]
    assert [p.name for p in tmp_path.iterdir()] == ["d"]  # no temporary folder left


def test_fe_check_plot_folder_keeps_other_figures(here, capsys, monkeypatch):
    figs = here / "figs"
    figs.mkdir()
    (figs / "fe_check_other.png").write_bytes(b"earlier figure")
    code, err, _ = _gearsim(capsys, monkeypatch, "fe-check", "spur-19-48", "--level", "1",
                            "--points", "3", "--plot", figs)
    assert code == 0, err
    names = sorted(p.name for p in figs.iterdir())
    assert "fe_check_other.png" in names and len(names) == 2
    assert (figs / "fe_check_other.png").read_bytes() == b"earlier figure"
    assert [p.name for p in here.iterdir()] == ["figs"]


def test_reproduce_killed_while_writing_leaves_the_earlier_report_whole(tmp_path,
                                                                        small_reproduction):
    """An earlier report (a copy of the session's small reproduction, tests/conftest.py)
    and a second ``reproduce`` into the same folder, killed while it writes its files."""
    out = tmp_path / "D"
    shutil.copytree(small_reproduction, out)
    env = dict(os.environ, GEARSIM_CACHE=str(tmp_path / "cache"))
    args = [sys.executable, "-m", "gearsim.cli", "reproduce", "--no-fe", "--revolutions",
            "13", "--depths", "2mm", "--fault-severities", "none", "--out", str(out),
            "--quiet"]
    before = _tree(out)
    assert {"report.html", "claims.json", "dynamic_load.nc", "figures"} <= set(before)

    proc = subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    killed = False
    deadline = time.monotonic() + 240
    try:
        while proc.poll() is None and time.monotonic() < deadline:
            tmp = [p for p in tmp_path.glob(".D.*.tmp") if p.is_dir()]
            if tmp and any(tmp[0].iterdir()):  # the new report is being written
                os.kill(proc.pid, signal.SIGKILL)
                killed = True
                break
            time.sleep(0.005)
    finally:
        if proc.poll() is None and not killed:
            proc.kill()
        proc.wait()
    assert killed, "the run ended before it could be killed while writing"
    assert _tree(out) == before  # exactly the earlier files, unchanged
    assert not [p for p in out.rglob("*") if p.name.endswith(".tmp")]
    leftovers = [p.name for p in tmp_path.iterdir() if p.name.startswith(".D.")]
    assert all(n.endswith(".tmp") for n in leftovers)  # only the killed run's own folder
    # and the earlier report is intact: its NetCDF still reads
    with xr.open_dataset(out / "dynamic_load.nc", engine="h5netcdf") as ds:
        assert np.isfinite(ds["mesh_force_1"].values).all()
