"""Bad input, round three (issue 24), verbs and studies: ``analyze --stage`` checked like a
stage file, ``reproduce`` of a planetary config and of ``--depths 1,,2``, a sweep whose
every case must fail, too-small sweep stores; each refused with one line, exit 2, before
any work and with nothing written. Worker warnings of a sweep come out as one
``gearsim: warning:`` line each.

The refusals run in this process (``gearsim.cli.run``, the function behind the installed
script; tests/test_cli_errors.py checks the script in a real process); the checks of
what Dask worker processes and distributed's own logging print run the real script."""

from __future__ import annotations

import contextlib
import socket
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

GEARSIM = [sys.executable, "-m", "gearsim.cli"]


def run(*args, cwd=None):
    """The real script in a new process."""
    return subprocess.run([*GEARSIM, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def run_here(capsys, *args, cwd=None) -> subprocess.CompletedProcess:
    """``gearsim`` in this process (``cli.run`` in ``cwd``): status, stdout and stderr."""
    from gearsim import cli

    capsys.readouterr()
    with contextlib.chdir(cwd) if cwd is not None else contextlib.nullcontext():
        code = cli.run([str(a) for a in args])
    out = capsys.readouterr()
    return subprocess.CompletedProcess(list(args), code, out.out, out.err)


def refused(capsys, *args, cwd=None) -> str:
    """Exit 2 with exactly one stderr line and nothing on stdout; the line."""
    r = run_here(capsys, *args, cwd=cwd)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].startswith("gearsim: error: ") and r.stdout == ""
    return lines[0]


@pytest.mark.parametrize("stage,match", [
    ("21,39,20,3", "--stage = 21,39,20,3: not coaxial: z_r must be z_s + 2 z_p = 99"),
    ("21,39,99,100", "(z_s + z_r)/N integer: (21 + 99)/100 = 1.2"),
    ("21,39,99,120", "neighbouring planets collide: N must be < pi / asin((z_p + 2)/(z_s + z_p))"
                     " = 4.176 (standard addendum)"),
    ("21,39,99,8", "neighbouring planets collide"),
    ("5,10,25,3", "sun and planet need 7 to 1000 teeth"),
    ("21,39,2000,3", "the ring at most 1000"),
])
def test_analyze_stage_checked_before_any_file(tmp_path, capsys, stage, match):
    (tmp_path / "rec.csv").write_text("not a record\n")  # refused before it is read
    line = refused(capsys, "analyze", tmp_path / "rec.csv", "--stage", stage, "--shaft-rpm", "600")
    assert line.startswith(f"gearsim: error: --stage = {stage}: ") and match in line


def test_analyze_valid_stages_pass_the_check(tmp_path, capsys):
    for stage in ("21,39,99,3", "30,24,78,4", "30,24,79,1"):  # 79: shifted, within 2 teeth
        line = refused(capsys, "analyze", tmp_path / "missing.csv", "--stage", stage, "--shaft-rpm", "60")
        assert "--stage" not in line and "missing.csv" in line


def test_reproduce_planetary_config_refused(tmp_path, capsys):
    line = refused(capsys, "reproduce", "--config", "lin-parker-1999", "--out", tmp_path / "r",
                   "--no-fe", "--quiet")
    assert line == ("gearsim: error: --config = lin-parker-1999: has a planetary stage; the "
                    "seed's study (e.g. idler-table1) needs a gearbox of external gears")
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("depths", ["1,,2", "1, 2,", ","])
def test_reproduce_empty_depth_items_refused(tmp_path, capsys, depths):
    # --revolutions 4 is refused too, later: the depths are read first
    line = refused(capsys, "reproduce", "--depths", depths, "--revolutions", "4", "--out",
                   tmp_path / "r")
    assert line == (f"gearsim: error: --depths = {depths}: must list depths without empty "
                    "items, e.g. '2 mm, 6 mm'")
    assert not (tmp_path / "r").exists()


SHORT = """
[study]
name = "short"
config = "idler-table1"
seed = 1
shafts = "all"
[study.dynamics]
duration = "0.3 s"
fs = "20 kHz"
transient = "0.02 s"
[parameters]
flank = ["none", "working"]
crack_depth = ["2 mm"]
noise = [0.0]
"""


def test_sweep_whose_every_case_must_fail_refused(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(SHORT)
    line = refused(capsys, "sweep", "s.toml", "--out", "s.nc", "--workers", "1", "--no-progress",
                   cwd=tmp_path)
    assert line.startswith("gearsim: error: study.dynamics.duration = 0.3 s: must be >= "
                           "0.404858 s for the analysis of every case at the lowest speed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_sweep_report_of_a_too_small_study_refused_before_the_sweep(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(SHORT.replace("0.3 s", "0.6 s"))
    line = refused(capsys, "sweep", "s.toml", "--out", "s.nc", "--report", "rep", cwd=tmp_path)
    assert line == ("gearsim: error: --report = rep: the study is too small to cross-validate: "
                    "the folds are grouped by simulation and every noise level has a class of "
                    "< 2 simulations (at noise 0: none 1, working 1; noise realisations, and a "
                    "healthy case's nominal depths or severities, share one simulation); add "
                    "torques or speeds")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def _store(path, noise=(0.0,), depths=(1e-3,)):
    """A synthetic store: one case per flank, noise level and depth, the depths at their own
    torque (as random sampling draws them: one simulation per depth, the healthy one
    included); features that separate the flanks in every feature group."""
    grid = np.array([(f, z, d) for f in ("none", "working") for z in noise for d in depths])
    flank, nz, depth = grid[:, 0], grid[:, 1].astype(float), grid[:, 2].astype(float)
    x = np.where(flank == "none", 0.0, 5.0) + np.random.default_rng(0).normal(size=flank.size)
    xr.Dataset({"status": ("case", ["ok"] * flank.size), "error": ("case", [""] * flank.size),
                **{f"{g}_x": ("case", x + i) for i, g in enumerate(("td", "sb", "tsa", "band"))}},
               coords={"case": np.arange(flank.size), "flank": ("case", flank),
                       "noise": ("case", nz), "crack_depth": ("case", depth),
                       "torque": ("case", 1e6 * depth)},
               attrs={"title": "synthetic", "study": "[parameters]", "n_cases": flank.size}
               ).to_netcdf(path, engine="h5netcdf")
    return path


def test_sweep_report_too_small_store_says_why(tmp_path, capsys):
    store = _store(tmp_path / "one.nc", noise=(0.0, 0.1))
    line = refused(capsys, "sweep-report", store, "--out", tmp_path / "rep")
    assert line == (f"gearsim: error: store = {store}: too small to cross-validate: the folds "
                    "are grouped by simulation and every noise level has a class of < 2 "
                    "simulations (at noise 0: none 1, working 1; noise realisations, and a "
                    "healthy case's nominal depths or severities, share one simulation); add "
                    "torques or speeds")
    assert not (tmp_path / "rep").exists()
    # rows pooling the two depths can be scored, those of one depth (1 simulation per
    # class) cannot: said in one warning line
    r = run_here(capsys, "sweep-report", _store(tmp_path / "two.nc", depths=(1e-3, 2e-3)), "--out",
            tmp_path / "rep")
    assert r.returncode == 0, r.stderr
    assert r.stderr.strip().splitlines() == [
        "gearsim: warning: 10 of 15 rows of the report are n/a (accuracy and AUC NaN, folds < "
        "2): their subset has < 2 simulations of a class (the folds are grouped by "
        "simulation); add torques or speeds to score them"]


STAGE = """
[stage]
sun_teeth = 30
planet_teeth = 24
ring_teeth = 78
planets = 3
normal_module = "2 mm"
face_width = "20 mm"
ring_addendum_coefficient = 0.8
[operating]
fixed = "ring"
input = "sun"
speed = "6000 rpm"
torque = "100 N*m"
[stiffness]
positions_per_cycle = 12
slices = 4
[dynamics]
duration = 0.2
fs = 20000
"""


def test_sweep_worker_warnings_are_one_gearsim_line_each(tmp_path):
    # the planet (z 24) lies just outside the fitted range of the Sainsot foundation: the
    # workers warn; the client says it once, as one line (was raw Python warning lines)
    (tmp_path / "stage.toml").write_text(STAGE)
    (tmp_path / "s.toml").write_text('[study]\nname = "w"\nconfig = "stage.toml"\n'
                                     '[parameters]\nflank = ["none"]\n')
    r = run("sweep", "s.toml", "--out", "s.nc", "--workers", "1", "--no-progress",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    # and the record's folding (f_m 2.17 kHz at fs 20 kHz, r = 2: its mesh-force spectrum
    # differs by 9.9 % of its largest line from the same run at r = 12), one line too
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith("gearsim: warning: Sainsot foundation of "
                                                   "gear planet: theta_f = "), r.stderr
    assert lines[1].startswith("gearsim: warning: anti-aliasing of the record: "), r.stderr


def test_dask_port_noise_is_not_a_warning_of_ours(tmp_path):
    # another cluster on port 8787: distributed warns that its HTTP server moves; not ours
    with socket.socket() as busy:
        with contextlib.suppress(OSError):  # already taken: as good
            busy.bind(("", 8787))
            busy.listen()
        for name in ("a.csv", "b.csv"):
            (tmp_path / name).write_text("acc\n" + "\n".join(f"{np.sin(i / 3):.6g}"
                                                              for i in range(2000)) + "\n")
        r = run("analyze", "a.csv", "b.csv", "--workers", "2", cwd=tmp_path)
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
