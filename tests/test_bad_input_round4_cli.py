"""Bad input, round four (the tester's list on the CLI): ``life``'s increment and noise
bounded on both sides / above before any work, its arrest told as an arrest, options'
numbers echoed as written, ``fe-check``'s cost bound, the mates' helix angles checked
after each gear's own range, the cost refusal of ``simulate`` with the numbers the run
would use.

The refusals run in this process (``gearsim.cli.run``)."""

from __future__ import annotations

import contextlib
import subprocess

import numpy as np
import pytest


def run_here(capsys, *args, cwd=None) -> subprocess.CompletedProcess:
    """``gearsim`` in this process (``cli.run`` in ``cwd``): status, stdout and stderr."""
    from gearsim import cli

    capsys.readouterr()
    with contextlib.chdir(cwd) if cwd is not None else contextlib.nullcontext():
        code = cli.run([str(a) for a in args])
    out = capsys.readouterr()
    return subprocess.CompletedProcess(list(args), code, out.out, out.err)


def _refused(res, start: str) -> str:
    assert res.returncode == 2, res.stderr + res.stdout
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(f"gearsim: error: {start}"), lines[0]
    return lines[0]


# --- 1. life: increment and noise ------------------------------------------------------

@pytest.mark.parametrize("written", ["1e-9", "1e-300", "0.0059", "6"])
def test_life_increment_outside_its_range_is_refused_before_any_work(written, capsys,
                                                                      tmp_path):
    """Table-1 input gear, m_n = 6 mm: at least m_n / 1000 = 0.006 mm; at most half the
    clearance ahead of the 2 mm, 45 deg crack's tip (below half the tooth's whole depth,
    2.25 m_n / 2 = 6.75 mm)."""
    res = run_here(capsys, "life", "idler-table1", "--out", tmp_path / "l.nc", "--torque",
                   "19504 N*m", "--increment", written, "--steps", "2")
    line = _refused(res, f"--increment = {written}: must be in [0.006, ")
    hi = float(line.split("[0.006, ")[1].split("]")[0])
    assert 2.0 < hi < 6.75
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("written", ["1e300", "101"])
def test_life_noise_above_its_limit_is_refused_before_any_work(written, capsys, tmp_path):
    res = run_here(capsys, "life", "idler-table1", "--out", tmp_path / "l.nc", "--noise",
                   written, "--steps", "3")
    line = _refused(res, f"--noise = {written}: must be in [0, 100]")
    assert "SNR -40 dB" in line  # 20 log10(1 / 100)
    assert not any(tmp_path.iterdir())


def test_life_arrest_is_told_as_an_arrest(capsys, tmp_path, monkeypatch):
    """A crack whose dK falls from 9 to 3 MPa sqrt(m) between 2 and 2.5 mm (threshold 6):
    with K_eq linear in a between the two tips (PCHIP of log K in log a, two points: a
    power law K = 9 (a / 2)^p, p = ln(3/9) / ln(2.5/2)), dK = 6 at a = 2 (6/9)^(1/p) mm;
    the line says so and does not call 9 below 6."""
    from gearsim.fracture.mesh import CrackPath
    from gearsim.fracture.paris import MPA_SQRT_M
    from gearsim.fracture.path import CyclePath, path_life
    from gearsim.studies import life as lf

    def fake(gb, gear=None, *, increment=None, steps=20, law=None, **kw):
        k = np.array([9.0, 3.0]) * MPA_SQRT_M
        p = CyclePath(crack=CrackPath(points=((0.0, 0.0), (0.0, 2e-3), (0.0, 2.5e-3),
                                              (0.0, 3e-3))),
                      lengths=np.array([2e-3, 2.5e-3]), k1=k, k2=np.zeros(2),
                      kink=np.zeros(2), force=1.0, status="steps done", message="",
                      seconds=0.0, delta_k=k, position=np.zeros(2, dtype=int),
                      dofs=np.zeros(2, dtype=int), seconds_per_step=np.zeros(2))
        life = path_life(p, law, 1.0, force_max=1.0)
        assert life.status == "arrest"
        return lf.GearLife(gear="input", flank="working", path=p, life=life, end="arrest",
                           law=law, static_force=1.0, dynamic_load_factor=1.0,
                           shaft_frequency=1.0, radii=np.zeros(1), shares=np.zeros(1),
                           seconds=0.0)

    monkeypatch.setattr(lf, "gear_life", fake)
    res = run_here(capsys, "life", "idler-table1", "--out", tmp_path / "l.nc")
    assert res.returncode == 0, res.stderr
    p = np.log(3.0 / 9.0) / np.log(2.5 / 2.0)
    a_arrest = 2.0 * (6.0 / 9.0) ** (1.0 / p)
    assert res.stdout.strip() == (
        f"end: arrest: dK falls from 9 MPa sqrt(m) at the initial crack (2 mm) to the "
        f"threshold 6 MPa sqrt(m) at {a_arrest:.4g} mm (DLF 1.0000); the crack stops "
        "growing, no store written")
    assert not any(tmp_path.iterdir())


# --- 5. numbers as written --------------------------------------------------------------

@pytest.mark.parametrize("args, start", [
    (("simulate", "two-stage-reducer", "--fs", "1e300"), "--fs = 1e300: "),
    (("simulate", "two-stage-reducer", "--fs=1e300"), "--fs = 1e300: "),
    (("simulate", "two-stage-reducer", "--duration", "-1"), "--duration = -1: "),
])
def test_an_options_number_is_echoed_as_written(args, start, capsys, tmp_path):
    _refused(run_here(capsys, *args, "--out", tmp_path / "r.nc"), start)
    assert not any(tmp_path.iterdir())


# --- 2. fe-check's cost bound -----------------------------------------------------------

def test_fe_check_above_its_cost_bound_is_refused_with_the_estimate(capsys, tmp_path,
                                                                    monkeypatch):
    """Level 5 of the two-stage reducer's pinion: level 3 has 68 472 P2 unknowns (a
    measured FE run), so level 5 about 16 times that, above 5e5; --force lifts it (the
    estimate alone is checked here: the FE solve is replaced)."""
    from gearsim.fem import check

    monkeypatch.delenv("GEARSIM_FORCE", raising=False)
    line = _refused(run_here(capsys, "fe-check", "two-stage-reducer", "--level", "5",
                             "--plot", tmp_path / "figs"), "--level = 5: the check needs about ")
    est = float(line.split("about ")[1].split(" FE unknowns")[0])
    assert 0.8 * 16 * 68472 < est < 1.3 * 16 * 68472
    assert "above the limit of 5e+05" in line and "--force" in line
    assert not any(tmp_path.iterdir())

    def solved(*args, **kw):
        raise RuntimeError("FE started")

    monkeypatch.setattr(check, "compare_gear", solved)
    res = run_here(capsys, "fe-check", "two-stage-reducer", "--level", "5", "--force")
    assert res.returncode == 1 and "FE started" in res.stderr


# --- 3. one RMS: about the mean -----------------------------------------------------------

@pytest.mark.parametrize("config, extra", [("two-stage-reducer", ()),
                                           ("lin-parker-1999", ("--duration", "0.2"))])
def test_simulate_rms_is_about_the_mean_for_every_kind(config, extra, capsys, tmp_path):
    """The summary's ``rms`` beside the mean is the standard deviation of the written mesh
    force (numpy on the file), for a gear train as for a planetary stage, and the text
    says "RMS about the mean"."""
    import json

    import xarray as xr

    out = tmp_path / "r.nc"
    res = run_here(capsys, "simulate", config, "--out", out, "--json", *extra)
    assert res.returncode == 0, res.stderr
    meshes = json.loads(res.stdout)["meshes"]
    with xr.open_dataset(out) as ds:
        f = (np.stack([ds[f"mesh_force_{m['mesh']}"].values for m in meshes], axis=1)
             if "mesh_force_1" in ds else ds["mesh_force"].values)
    for i, m in enumerate(meshes):
        x = f[:, i]
        dev = np.sqrt(np.mean((x - x.mean()) ** 2))
        assert m["rms"] == pytest.approx(dev, rel=1e-9, abs=1e-9 * abs(x.mean()))
    res = run_here(capsys, "simulate", config, "--out", out, *extra)
    first = res.stdout.splitlines()[0]
    assert "RMS about the mean" in first and ", RMS " not in first.replace(
        ", RMS about the mean", "")


# --- 4. a gear's own helix range before its mates' equality --------------------------------

def test_helix_angle_out_of_range_names_its_own_gear(capsys, tmp_path):
    """89 deg on input-pinion alone: the mesh's equality check would blame its mate
    (gears[1] = 0 deg); the gear's own range |beta| < 45 deg comes first."""
    res = run_here(capsys, "example", "two-stage-reducer")
    text = res.stdout.replace('name = "input-pinion"\n',
                              'name = "input-pinion"\nhelix_angle = "89 deg"\n', 1)
    assert text != res.stdout
    (tmp_path / "x.toml").write_text(text)
    line = _refused(run_here(capsys, "layout", tmp_path / "x.toml"), "")
    assert line == "gearsim: error: gears[0].helix_angle = 89 deg: must satisfy |beta| < 45 deg"


# --- 6. the cost refusal states the run's numbers ----------------------------------------

def test_simulate_cost_refusal_states_the_transient_and_step_the_run_uses(capsys, tmp_path,
                                                                          monkeypatch):
    """The refusal of 1e4 s names the default transient and the step a real (short) run of
    the same config records in its file, not 0 s."""
    import xarray as xr

    monkeypatch.delenv("GEARSIM_FORCE", raising=False)
    out = tmp_path / "r.nc"
    assert run_here(capsys, "simulate", "two-stage-reducer", "--duration", "0.2", "--out",
                    out).returncode == 0
    with xr.open_dataset(out) as ds:
        transient, dt = float(ds.attrs["transient"]), float(ds.attrs["step"])
    assert transient > 0.0
    line = _refused(run_here(capsys, "simulate", "two-stage-reducer", "--duration", "10000",
                             "--out", tmp_path / "big.nc"), "--duration = 10000: the run needs ")
    assert f"(transient {transient:.4g} s + duration 1e+04 s at dt = {dt:.4g} s" in line
    assert "the largest step 1e-05 s" in line
    assert not (tmp_path / "big.nc").exists()


# --- 5. messages: the path, the empty name, a quoted number, a count's limit, all problems -

def test_invalid_toml_names_the_file_and_the_line(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[common\n')
    line = _refused(run_here(capsys, "layout", bad), f"config = {bad}: is not valid TOML")
    assert "line 2" in line
    study = tmp_path / "s.toml"
    study.write_text("[study\n")
    line = _refused(run_here(capsys, "sweep", study, "--out", tmp_path / "s.nc"),
                    f"study = {study}: is not valid TOML")
    assert "line 1" in line


def test_an_empty_config_path_is_called_empty(capsys):
    _refused(run_here(capsys, "stiffness", ""), "config = '': is empty: give a file or a "
             "built-in example: idler-table1")


def test_a_quoted_number_in_a_study_is_called_a_string(capsys, tmp_path):
    study = tmp_path / "s.toml"
    study.write_text('[study]\nconfig = "spur-19-48"\nreplicates = "3"\n[parameters]\n'
                     "crack_depth = [0.0, 1e-3]\n")
    line = _refused(run_here(capsys, "sweep", study, "--out", tmp_path / "s.nc"),
                    'study.replicates = "3": must be an integer >= 1')
    assert "not a string" in line


def test_fe_pair_position_count_states_its_limit(capsys):
    _refused(run_here(capsys, "fe-pair", "spur-19-48", "--positions", "100000"),
             "--positions = 100000: a count must be in [1, 200]")


def test_reproduce_reports_every_problem(capsys, tmp_path):
    line = _refused(run_here(capsys, "reproduce", "--out", tmp_path / "rep", "--revolutions",
                             "2", "--model", "xyz"), "input = 2 problems: ")
    assert "--revolutions = 2: " in line and "--model = xyz: " in line
    assert not any(tmp_path.iterdir())
