"""Bad values: inf and NaN everywhere values enter, physical ranges, and messages that
name the right parameter, its value as written and the limit (one line, exit 2)."""

from __future__ import annotations

import copy
import dataclasses
import math
import os
import signal
import subprocess
import sys
import time
import tomllib

import numpy as np
import pytest

from gearsim.dynamics.settings import DynamicsSettings
from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.model import example_text, load, loads
from gearsim.model.config import parse
from gearsim.system.train import Operating
from gearsim.units import to_si

INF, NAN = math.inf, math.nan
SPUR = tomllib.loads(example_text("spur-19-48"))


def _parse_with(section: str, key: str, value, *, gear: int | None = None):
    doc = copy.deepcopy(SPUR)
    if gear is not None:
        doc["gears"][gear][key] = value
    else:
        doc.setdefault(section, {})[key] = value
    return parse(doc)


def _refused(section: str, key: str, value, **kw) -> InputError:
    with pytest.raises(InputError) as info:
        _parse_with(section, key, value, **kw)
    assert "\n" not in str(info.value)
    return info.value


def _cli(args: list[str], capsys) -> tuple[int, str]:
    """Exit status and standard error of the command line ``gearsim <args>``."""
    from gearsim import cli

    if hasattr(cli, "run"):
        code = cli.run(args)
        return code, capsys.readouterr().err
    res = subprocess.run([sys.executable, "-m", "gearsim.cli", *args], capture_output=True,
                         text=True, timeout=300)
    return res.returncode, res.stderr


def _one_line(code: int, err: str) -> str:
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# ------------------------------------------------------------------ units.to_si

@pytest.mark.parametrize("value", [INF, -INF, NAN, "inf mm", "-inf mm", "nan", "nan mm",
                                   "1e400 mm", "1e307 km"])
def test_to_si_refuses_non_finite_values_by_name(value):
    with pytest.raises(InputError, match=r"^gears\[0\]\.face_width = .*must be a finite number"):
        to_si(value, "length", "gears[0].face_width")


def test_to_si_names_the_unit_pint_read():
    with pytest.raises(InputError, match=r"--depths = a: is not a length: pint reads 'a' as "
                                         r"1 year"):
        to_si("a", "length", "--depths")
    with pytest.raises(InputError, match="unit without a number"):
        to_si("mm", "length", "face_width")


# ------------------------------------------------------- config values inf / NaN

MATERIAL_FIELDS = ["youngs_modulus", "poisson_ratio", "density"]
GEAR_FIELDS = ["normal_module", "normal_pressure_angle", "helix_angle", "face_width",
               "addendum_coefficient", "dedendum_coefficient", "fillet_radius_coefficient",
               "profile_shift", "bore_radius"]
DYNAMICS_FIELDS = ["step", "duration", "transient", "fs", "bearing_stiffness",
                   "bearing_axial_stiffness", "bearing_damping", "bearing_damping_ratio",
                   "mesh_damping_ratio", "backlash", "idler_angle", "profile_modification",
                   "crowning", "runout", "runout_phase", "assembly_error"]
CRACK_FIELDS = ["depth", "angle", "extent", "start_radius"]


@pytest.mark.parametrize("bad", [INF, NAN])
@pytest.mark.parametrize("key", MATERIAL_FIELDS)
def test_material_inf_nan_refused(key, bad):
    err = _refused("material", key, bad)
    assert err.parameter == f"material.{key}"
    assert "finite" in err.limit


@pytest.mark.parametrize("bad", [INF, NAN])
@pytest.mark.parametrize("key", GEAR_FIELDS)
def test_gear_inf_nan_refused(key, bad):
    err = _refused("common", key, bad)
    assert err.parameter == f"common.{key}"
    assert "finite" in err.limit


@pytest.mark.parametrize("value", ["inf rpm", "nan rpm", "-inf rpm"])
def test_operating_speed_inf_nan_refused(value):
    err = _refused("operating", "speed", value)
    assert err.parameter == "operating.speed" and "finite" in err.limit


@pytest.mark.parametrize("bad", [INF, NAN, "inf N*m"])
def test_operating_torque_inf_nan_refused(bad):
    err = _refused("operating", "torque", bad)
    assert err.parameter == "operating.torque" and "finite" in err.limit


@pytest.mark.parametrize("bad", [INF, NAN])
@pytest.mark.parametrize("key", DYNAMICS_FIELDS)
def test_dynamics_inf_nan_refused(key, bad):
    err = _refused("dynamics", key, bad)
    assert err.parameter == f"dynamics.{key}"
    assert "finite" in err.limit


@pytest.mark.parametrize("bad", [INF, NAN])
@pytest.mark.parametrize("key", CRACK_FIELDS)
def test_crack_inf_nan_refused(key, bad):
    doc = copy.deepcopy(SPUR)
    doc["cracks"][0][key] = bad
    with pytest.raises(InputError) as info:
        parse(doc)
    assert info.value.parameter == f"cracks[0].{key}"


@pytest.mark.parametrize("field,value", [
    ("step", INF), ("step", NAN), ("step", 1e-12), ("duration", INF), ("duration", 1e5),
    ("transient", INF), ("transient", 1e5), ("transient", -1.0), ("fs", INF), ("fs", 1e8),
    ("bearing_stiffness", INF), ("bearing_stiffness", 1e20), ("bearing_damping", INF),
    ("bearing_axial_stiffness", NAN), ("runout_phase", (NAN,)), ("assembly_error", (NAN,)),
    ("runout", (5.0,)), ("backlash", (INF,)), ("oversample", True), ("nonlinear", 1),
])
def test_dynamics_settings_bounds(field, value):
    """The physical and sane bounds that prevent hangs, overflows and huge arrays."""
    with pytest.raises(InputError) as info:
        DynamicsSettings(**{field: value})
    assert info.value.parameter == f"dynamics.{field}"


def test_dynamics_settings_limits_are_inclusive_where_said():
    DynamicsSettings(transient=0.0, step=1e-9, duration=1e4, fs=1e7)


@pytest.mark.parametrize("kw,name", [
    ({"youngs_modulus": 1e13}, "youngs_modulus"), ({"youngs_modulus": -1.0}, "youngs_modulus"),
    ({"density": 1e6}, "density"), ({"poisson_ratio": 0.5}, "poisson_ratio"),
    ({"poisson_ratio": -1.0}, "poisson_ratio"),
])
def test_material_ranges(kw, name):
    with pytest.raises(InputError) as info:
        Material(**kw)
    assert info.value.parameter == f"material.{name}"


def test_auxetic_poisson_ratio_accepted():
    assert Material(poisson_ratio=-0.2).shear_modulus > 0


@pytest.mark.parametrize("speed,torque", [(INF, 1.0), (NAN, 1.0), (1.0, INF), (1.0, NAN),
                                          (0.0, 1.0), (1.0, -1.0)])
def test_operating_refuses_non_finite_and_non_positive(speed, torque):
    with pytest.raises(InputError, match="must be a finite number > 0"):
        Operating(speed=speed, torque=torque)


@pytest.mark.parametrize("key,value", [("face_width", 5.0), ("profile_shift", 2.5),
                                        ("addendum_coefficient", 2.5),
                                        ("fillet_radius_coefficient", -0.1)])
def test_gear_ranges_name_the_parameter(key, value):
    with pytest.raises(InputError) as info:
        Gear(teeth=30, normal_module=2e-3, **{key: value})
    assert info.value.parameter == f"gear.{key}"


def test_material_of_one_gear_is_named_by_its_table():
    doc = copy.deepcopy(SPUR)
    doc["gears"][1]["material"] = {"density": "inf kg/m^3"}
    with pytest.raises(InputError, match=r"^gears\[1\]\.material\.density = inf kg/m\^3"):
        parse(doc)
    doc["gears"][1]["material"] = {"youngs_modulus": "20000 GPa"}
    with pytest.raises(InputError, match=r"^gears\[1\]\.material\.youngs_modulus = 20000 GPa: "
                                         r"must be a finite number in \[1e\+08, 1e\+13\) Pa"):
        parse(doc)


# --------------------------------------------------------- misleading messages

def test_addendum_3_blames_the_addendum_not_the_profile_shift():
    err = _refused("common", "addendum_coefficient", 3.0)
    assert err.parameter == "common.addendum_coefficient"
    assert "profile_shift" not in str(err)
    err = _refused("", "addendum_coefficient", 3.0, gear=1)
    assert str(err) == "gears[1].addendum_coefficient = 3.0: must be in (0, 2]"


def test_pointed_tooth_from_a_long_addendum_names_the_addendum():
    with pytest.raises(InputError, match="pointed tooth") as info:
        Gear(teeth=20, normal_module=2e-3, addendum_coefficient=1.9, name="g")
    assert info.value.parameter == "g.addendum_coefficient"
    assert "profile_shift 0" in info.value.limit


def test_pointed_tooth_from_a_positive_shift_names_the_shift():
    with pytest.raises(InputError, match="pointed") as info:
        Gear(teeth=12, normal_module=2e-3, face_width=0.01, profile_shift=1.2, name="g")
    assert info.value.parameter == "g.profile_shift"


def test_dedendum_too_deep_names_the_dedendum():
    err = _refused("common", "dedendum_coefficient", 2.5)
    assert err.parameter == "common.dedendum_coefficient"
    assert "20 deg" in err.limit and "'pinion'" in err.limit


def test_pressure_angle_mismatch_names_the_mismatch_in_degrees():
    err = _refused("", "normal_pressure_angle", "25 deg", gear=1)
    assert err.parameter == "gears[1].normal_pressure_angle"
    assert str(err) == ("gears[1].normal_pressure_angle = 25 deg: must equal "
                        "gears[0].normal_pressure_angle = 20 deg (meshing gears need equal "
                        "normal module and pressure angle)")
    assert "fillet" not in str(err)


def test_module_mismatch_names_the_mismatch_in_mm():
    err = _refused("", "normal_module", "4 mm", gear=1)
    assert str(err).startswith("gears[1].normal_module = 4 mm: must equal "
                               "gears[0].normal_module = 3.2 mm (meshing gears need equal "
                               "normal module")


def test_pair_mismatch_outside_a_config_is_in_degrees():
    from gearsim.geometry.pair import GearPair

    with pytest.raises(InputError, match=r"= 25 deg: must equal a\.normal_pressure_angle = "
                                         r"20 deg"):
        GearPair(Gear(teeth=30, normal_module=2e-3, name="a"),
                 Gear(teeth=40, normal_module=2e-3, normal_pressure_angle=math.radians(25),
                      fillet_radius_coefficient=0.25, name="b"))


def test_tip_round_too_large_for_25_deg_names_the_pressure_angle():
    doc = copy.deepcopy(SPUR)
    doc["common"]["normal_pressure_angle"] = "25 deg"
    with pytest.raises(InputError) as info:
        parse(doc)
    assert info.value.parameter == "gears[0].fillet_radius_coefficient"  # the default 0.38
    assert "normal_pressure_angle 25 deg" in info.value.limit


def test_plain_angle_is_shown_as_radians():
    err = _refused("common", "normal_pressure_angle", 20)
    assert str(err).startswith("common.normal_pressure_angle = 20 rad: must be between 5 and "
                               "35 deg")


def test_inf_in_a_csv_is_called_inf_with_row_and_column(tmp_path):
    from gearsim.io.measured import read_signal

    p = tmp_path / "rec.csv"
    p.write_text("time,x\n0,1\n0.001,2\n0.002,inf\n0.003,4\n")
    with pytest.raises(InputError) as info:
        read_signal(p)
    assert info.value.parameter == "rec.csv: column 'x' data row 3"
    assert info.value.value == "inf"
    assert "missing" not in str(info.value)
    p.write_text("time,x\n0,1\n0.001,\n0.002,3\n")
    with pytest.raises(InputError, match="data row 2 = missing/NaN"):
        read_signal(p)


def test_blank_line_inside_csv_data_is_a_missing_sample(tmp_path):
    from gearsim.io.measured import read_signal

    p = tmp_path / "rec.csv"
    p.write_text("acc\n0.1\n\n0.3\n0.4\n")
    with pytest.raises(InputError, match=r"^rec\.csv: line 3 = empty: .*missing sample"):
        read_signal(p, fs=100.0)
    p.write_text("# fs = 100\n\nacc\n0.1\n0.3\n0.4\n\n\n")  # blank lines around: fine
    assert read_signal(p).data.size == 3


def test_material_in_common_is_named_by_common():
    doc = copy.deepcopy(SPUR)
    doc["common"]["material"] = {"youngs_modulus": -1}
    with pytest.raises(InputError, match=r"^common\.material\.youngs_modulus = -1"):
        parse(doc)


def test_tiny_crack_names_the_smallest_depth_the_fe_mesh_resolves(spur):
    from gearsim.fem.tables import fe_compliance
    from gearsim.fem.tooth import fe_tooth_compliance

    gear = spur.gears[0]  # m 3.2 mm: finest elements 3.2 / 256 = 0.0125 mm
    crack = dataclasses.replace(spur.cracks[0], depth=1e-6)
    for call in (lambda: fe_tooth_compliance(gear, [gear.tip_radius], crack=crack, side=1),
                 lambda: fe_compliance(gear, [0.99 * gear.tip_radius], crack=crack,
                                       depth=1e-6, side=1, use_cache=False)):
        with pytest.raises(InputError) as info:
            call()
        msg = str(info.value)
        assert info.value.parameter == "crack.depth"
        assert "too small for the FE mesh" in msg and ">= 0.025 mm" in msg
        assert "level >=" not in msg


def test_transient_minus_one_says_at_least_zero(capsys, tmp_path):
    line = _one_line(*_cli(["simulate", "spur-19-48", "--transient", "-1", "--out",
                            str(tmp_path / "run.nc")], capsys))
    assert "--transient = -1: must be a finite number >= 0 s" in line
    assert DynamicsSettings(transient=0.0).transient == 0.0


@pytest.mark.parametrize("option,value", [("--fs", "inf"), ("--duration", "nan"),
                                          ("--step", "inf"), ("--transient", "inf")])
def test_simulate_options_inf_nan_refused(option, value, capsys, tmp_path):
    out = tmp_path / "run.nc"
    line = _one_line(*_cli(["simulate", "spur-19-48", option, value, "--out", str(out)],
                           capsys))
    assert f"{option} = {value}" in line and "finite" in line
    assert not out.exists()


@pytest.mark.parametrize("depths,expect", [
    ("a", "--depths = a: is not a length: pint reads 'a' as 1 year"),
    ("2, 3 a", "--depths = 3 a: has units of [time] (year), expected a length"),
    ("1, inf", "--depths = inf: must be a finite number"),
    ("nan", "--depths = nan: must be a finite number"),
    ("mm", "--depths = mm: is a unit without a number"),
])
def test_depths_must_be_lengths(depths, expect, capsys, tmp_path):
    out = tmp_path / "rep"
    line = _one_line(*_cli(["reproduce", "--depths", depths, "--out", str(out), "--quiet"],
                           capsys))
    assert expect in line
    assert not out.exists()


def test_depth_plain_numbers_are_millimetres():
    from gearsim.commands.studies import _depths

    assert _depths("1, 2.5, 1e-1, 3 mm") == pytest.approx((1e-3, 2.5e-3, 1e-4, 3e-3))


# ------------------------------------------------------------------ bare speed

@pytest.mark.parametrize("speed", [1900, 1900.0, "1900"])
def test_bare_speed_is_refused_with_the_assumed_unit(speed):
    err = _refused("operating", "speed", speed)
    assert str(err) == (f'operating.speed = {speed}: give a unit, e.g. "1900 rpm" (a bare '
                        "number would be read as rad/s)")


def test_speed_with_units_and_examples_parse():
    assert _parse_with("operating", "speed", "200 rad/s").train.operating.speed == 200.0
    for name in ("idler-table1", "spur-19-48"):
        assert load(name).train.operating.speed > 0


@pytest.mark.parametrize("text,rad_s", [
    ("30 Hz", 30 * 2 * math.pi),        # a shaft at 30 rev/s, as records are labelled
    ("0.03 kHz", 30 * 2 * math.pi),
    ("1800 1/min", 1800 * 2 * math.pi / 60),
    ("1800 rpm", 1800 * 2 * math.pi / 60),
    ("188.5 rad/s", 188.5),
    ("360 deg/s", 2 * math.pi),
])
def test_speed_in_a_frequency_unit_is_revolutions_per_time(text, rad_s):
    """pint reads Hz as 1/s, the same dimension as rad/s (the radian is a number): a
    shaft speed in Hz would be 2 pi too slow without the revolutions."""
    speed = _parse_with("operating", "speed", text).train.operating.speed
    assert speed == pytest.approx(rad_s, rel=1e-12)


def test_effective_config_with_si_speed_reads_back():
    """Results files store the effective configuration (plain SI numbers, declared)."""
    gb = load("spur-19-48")
    again = loads(gb.to_toml())
    assert again.train.operating.speed == gb.train.operating.speed


def test_refused_value_is_shown_as_written():
    err = _refused("operating", "speed", "-3 rpm")
    assert str(err) == "operating.speed = -3 rpm: must be a finite number > 0 rad/s"
    err = _refused("dynamics", "duration", "5 h")
    assert str(err).startswith("dynamics.duration = 5 h: must be a finite number in (0, ")


# --------------------------------------------------------------- config files

def test_utf8_bom_is_accepted(tmp_path):
    text = "\ufeff" + example_text("spur-19-48")
    assert [g.teeth for g in loads(text).train.gears] == [19, 48]
    p = tmp_path / "bom.toml"
    p.write_bytes(text.encode("utf-8"))
    assert [g.teeth for g in load(p).train.gears] == [19, 48]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs a POSIX FIFO")
def test_fifo_as_config_is_refused_quickly(tmp_path):
    fifo = tmp_path / "config.toml"
    os.mkfifo(fifo)

    def hung(signum, frame):  # pragma: no cover - only on a regression
        raise TimeoutError("reading the FIFO blocked")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(30)
    try:
        t0 = time.perf_counter()
        with pytest.raises(InputError, match="is not a regular file") as info:
            load(fifo)
        assert info.value.parameter == "config"
        assert time.perf_counter() - t0 < 5.0
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def test_directory_as_config_is_refused(tmp_path):
    with pytest.raises(InputError, match="is not a regular file"):
        load(tmp_path)


# -------------------------------------------------------------------- signals

def test_analyze_refuses_records_that_would_overflow_the_moments():
    from gearsim.signals import analyze
    from gearsim.signals.timedomain import time_stats

    t = np.arange(20_000) / 20_000.0
    x = 1e300 * np.sin(2 * np.pi * 1235.0 * t)
    with pytest.raises(InputError, match=r"peak magnitude must be <= 1e\+30") as info:
        analyze(x, 20_000.0, teeth=(39, 59), shaft_frequency=1900 / 60)
    assert info.value.parameter.startswith("signal[")
    with pytest.raises(InputError, match="overflow"):
        time_stats(x, remove_mean=True)
    # a large but representable record is analysed without overflow warnings
    with np.errstate(over="raise", invalid="raise"):
        time_stats(1e29 * np.sin(2 * np.pi * 5 * t), remove_mean=True)
