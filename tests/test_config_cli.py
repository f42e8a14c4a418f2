"""Configuration files with units, bad input, and the CLI verbs of the stiffness issue.

The verbs run in this process (``gearsim_here`` of tests/conftest.py: ``gearsim.cli.run``,
the function behind the installed script)."""

from __future__ import annotations

import json
import math

import pytest

from gearsim.errors import InputError
from gearsim.model import example_text, loads

MINIMAL = """
[common]
normal_module = "{module}"
face_width = "20 mm"
[[gears]]
name = "p"
teeth = 21
[[gears]]
name = "w"
teeth = 40
"""


def test_units_are_converted_to_si():
    t = loads(MINIMAL.format(module="0.25 in") + '[operating]\nspeed = "1900 rpm"\n'
              'torque = "4876 N*m"\n').train
    assert abs(t.gears[0].normal_module - 6.35e-3) < 1e-15
    assert abs(t.operating.speed - 1900 * 2 * math.pi / 60) < 1e-12
    assert t.operating.torque == 4876.0
    plain = loads(MINIMAL.format(module="6 mm").replace('"6 mm"', "0.006")).train
    assert plain.gears[0].normal_module == 0.006


@pytest.mark.parametrize("text,match", [
    (MINIMAL.format(module="6 kg"), r"common.normal_module = 6 kg: has units of \[mass\]"),
    (MINIMAL.format(module="6 mm") + "[stiffness]\nslicez = 3\n",
     r"stiffness.slicez = 3: unknown key"),
    (MINIMAL.format(module="6 mm") + "[extra]\na = 1\n", r"extra = \.\.\.: unknown section"),
    (MINIMAL.format(module="-6 mm"), r"common.normal_module = -6 mm: must be >= 1e-05 m"),
    (MINIMAL.format(module="6 mm") + '[[cracks]]\ngear = "p"\ndepth = "30 mm"\n',
     r"cracks\[0\].depth = 30 mm: crack is deeper than the tooth"),
    (MINIMAL.format(module="6 mm") + '[[cracks]]\ngear = "q"\n', r"cracks\[0\].gear = q"),
    (MINIMAL.format(module="6 mm") + '[stiffness]\nclosure = "glued"\n',
     r"stiffness.closure = glued"),
    (MINIMAL.format(module="6 mm") + '[operating]\nspeed = "-3 rpm"\n', r"operating.speed"),
    ("[[gears]\n", r"config = TOML: is not valid TOML"),
])
def test_bad_config_is_refused_with_one_line(text, match):
    with pytest.raises(InputError, match=match) as info:
        loads(text)
    assert "\n" not in str(info.value)


def test_examples_load():
    for name in ("idler-table1", "spur-19-48"):
        t = loads(example_text(name)).train
        assert len(t.gears) >= 2


def test_cli_example_and_stiffness(tmp_path, gearsim_here):
    run = gearsim_here
    res = run("example", "idler-table1")
    assert res.returncode == 0 and "teeth = 39" in res.stdout
    cfg = tmp_path / "t1.toml"
    cfg.write_text(res.stdout)
    out = tmp_path / "tvms.csv"
    res = run("stiffness", str(cfg), "--out", str(out), "--json", "--crack", "non-working")
    assert res.returncode == 0, res.stderr
    summary = json.loads(res.stdout)
    assert [m["mesh"] for m in summary["meshes"]] == ["I", "II"]
    for m in summary["meshes"]:
        assert m["k_min"] < m["k_mean"] < m["k_max"]
        assert 0.75 < m["ratio_to_iso6336"] < 1.25
    lines = out.read_text().splitlines()
    assert lines[1].startswith("mesh,revolution_of,cycle")
    # 2 meshes x 2 revolutions x teeth x 40 positions
    assert len(lines) - 2 == 40 * (39 + 59 + 59 + 125)


def test_cli_netcdf_and_plot(tmp_path, gearsim_here):
    import xarray as xr

    res = gearsim_here("stiffness", "spur-19-48", "--out", str(tmp_path / "s.nc"), "--plot",
              str(tmp_path / "s.png"))
    assert res.returncode == 0, res.stderr
    ds = xr.open_dataset(tmp_path / "s.nc", engine="h5netcdf")
    assert ds["mesh1_rev1_k"].attrs["units"] == "N/m"
    assert (tmp_path / "s.png").stat().st_size > 10_000


@pytest.mark.parametrize("args,match", [
    (["stiffness", "no-such-file.toml"], "config = no-such-file.toml: file not found"),
    (["stiffness", "spur-19-48", "--crack", "both"], "--crack = both"),
    (["stiffness", "spur-19-48", "--out", "x.txt"], "--out = x.txt: must end in .csv or .nc"),
    (["example", "nope"], "example = nope: unknown"),
])
def test_cli_bad_input_exit_2(args, match, tmp_path, gearsim_here):
    res = gearsim_here(*args, cwd=tmp_path)
    assert res.returncode == 2
    assert match in res.stderr
    assert "Traceback" not in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1


def test_cli_bad_config_file_exit_2(tmp_path, gearsim_here):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(MINIMAL.format(module="6 kg"))
    res = gearsim_here("stiffness", str(cfg))
    assert res.returncode == 2 and "common.normal_module = 6 kg" in res.stderr


def test_existing_output_survives_failure(tmp_path, gearsim_here):
    """A run that fails before writing leaves an earlier result untouched."""
    out = tmp_path / "t.csv"
    out.write_text("old")
    cfg = tmp_path / "bad.toml"
    cfg.write_text(MINIMAL.format(module="6 mm") + '[[cracks]]\ngear = "p"\ndepth = "30 mm"\n')
    res = gearsim_here("stiffness", str(cfg), "--out", str(out))
    assert res.returncode == 2
    assert out.read_text() == "old"
