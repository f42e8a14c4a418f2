"""Bad input, round three (issue 24): extreme but finite physical values and options that
would have no effect are refused by the CLI before any work: exit 2, one line naming the
parameter, its value as written and the limit, no output file (before: numba overflows,
divergence, eigen-solver failures, hours of steps, or exit 0 with the value ignored).

The verbs run in this process (``gearsim_here`` of tests/conftest.py)."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from gearsim.errors import InputError
from gearsim.model import example_text

SPUR = example_text("spur-19-48")
STAGE = example_text("lin-parker-1999")
PITS = ('[[faults]]\nkind = "pitting"\ngear = "pinion"\ntooth = 7\narea_fraction = 0.2\n'
        'radius_min = "29 mm"\nradius_max = "30.4 mm"\npit_diameter = "1 nm"\n')
MOD = '[[modifications]]\ngear = "pinion"\n'


def _sub(text: str, key: str, value: str) -> str:
    out, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
    assert n == 1
    return out


CASES = [
    ("simulate", SPUR + "[dynamics]\nbearing_stiffness = 1e-300\n",
     r"dynamics\.bearing_stiffness = 1e-300: .*\[100000, 1e\+15\] N/m"),
    ("simulate", SPUR + '[dynamics]\nbearing_stiffness = "10 N/m"\n',
     r"dynamics\.bearing_stiffness = 10 N/m: .*\[100000"),
    ("simulate", _sub(SPUR, "density", "1e-300"), r"material\.density = 1e-300: .*\[100, "),
    ("simulate", _sub(SPUR, "youngs_modulus", "206"),
     r"material\.youngs_modulus = 206(\.0)?: .*\[1e\+08, "),
    ("simulate", _sub(STAGE, "sun_mass", "1e-300"), r"members\.sun_mass = 1e-300: .*\[1e-06, "),
    ("simulate", _sub(STAGE, "carrier_mass", '"1e30 kg"'),
     r"members\.carrier_mass = 1e30 kg: .*1e\+06\] kg"),
    ("simulate", _sub(STAGE, "sun_inertia", "1e-300"), r"members\.sun_inertia = 1e-300: .*1e-12"),
    ("simulate", _sub(STAGE, "ring_bearing", '"1e-3 N/m"'), r"members\.ring_bearing = 1e-3 N/m"),
    ("simulate", _sub(STAGE, "held_torsional", "1e300"),
     r"members\.held_torsional = 1e\+300: .*1e\+12\] N\*m/rad"),
    # within every bound, but stiff and light together: 6e11 steps, refused before the run
    ("simulate", _sub(_sub(_sub(STAGE, "held_torsional", "1e12"), "carrier_inertia", "1e-12"),
                      "ring_inertia", "1e-12"),
     r"dynamics\.duration = 1\.0: the run needs 6\.\d+e\+11 integration steps .* limit of 1e\+09"),
    ("simulate", example_text("wind-turbine-grc").replace(
        'name = "low-speed"', 'name = "low-speed"\ntorsional_stiffness = 1e300'),
     r"shafts\[1\]\.torsional_stiffness = 1e\+300: .*1e\+12\] N\*m/rad"),
    ("simulate", SPUR + '[dynamics]\nidler_angle = "150 deg"\n',
     r"dynamics\.idler_angle = \['150 deg'\]: the train has no idler"),
    ("simulate", STAGE + 'idler_angle = "150 deg"\n', r"dynamics\.idler_angle = .*planetary"),
    ("stiffness", SPUR + PITS, r"faults\[0\]\.pit_diameter = 1 nm: must be >= 1e-05 m"),
    ("stiffness", SPUR + PITS.replace('"1 nm"', '"0.01 mm"').replace("0.2", "1.0").replace(
        '"29 mm"', '"28.7 mm"').replace('"30.4 mm"', '"33.5 mm"').replace("16 mm", "160 mm"),
     r"faults\[0\]\.pit_diameter = 0\.01 mm: makes 1\.\d+e\+06 pits"),
    ("stiffness", SPUR + MOD + 'tip_relief = "1 m"\ntip_relief_length = "1 mm"\n',
     r"modifications\[0\]\.tip_relief = 1000 mm: must be <= 0\.25 x the module of pinion = 0\.8 mm"),
    ("stiffness", SPUR + MOD + 'crowning = "2 m"\n', r"modifications\[0\]\.crowning = 2000 mm"),
    ("stiffness", SPUR + MOD + 'helix_slope = "-1 m"\n', r"modifications\[0\]\.helix_slope = -1000 mm"),
    ("stiffness", SPUR + MOD + "pitch_errors = [" + "0.0, " * 18 + '"1 m"]\n',
     r"modifications\[0\]\.pitch_errors = 1000 mm"),
]


@pytest.mark.parametrize("verb,text,match", CASES, ids=[c[2][:40] for c in CASES])
def test_extreme_values_and_idle_options_refused_before_work(tmp_path, gearsim_here, verb,
                                                             text, match):
    cfg = tmp_path / "c.toml"
    cfg.write_text(text)
    out = tmp_path / ("o.nc" if verb == "simulate" else "o.csv")
    res = gearsim_here(verb, cfg, "--out", out)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2, res.stderr
    assert len(lines) == 1 and "Traceback" not in res.stderr, res.stderr
    assert re.match(r"gearsim: error: " + match, lines[0]), lines[0]
    assert not out.exists()


def _bounded():
    from gearsim.dynamics.settings import DynamicsSettings
    from gearsim.dynamics.stage import StageDynamics
    from gearsim.geometry import gear
    from gearsim.stiffness.faults import MIN_PIT_DIAMETER, Pitting
    from gearsim.system import graph as g

    pits = {"gear": "p", "area_fraction": 0.2, "radius_min": 0.03, "radius_max": 0.031}
    return [  # (make, lower, upper, parameter)
        (lambda v: gear.Material(youngs_modulus=v), gear.MIN_YOUNGS_MODULUS,
         gear.MAX_YOUNGS_MODULUS, "material.youngs_modulus"),
        (lambda v: gear.Material(density=v), gear.MIN_DENSITY, gear.MAX_DENSITY, "material.density"),
        (lambda v: StageDynamics(masses={"sun": v}), g.MIN_MASS, g.MAX_MASS, "members.sun_mass"),
        (lambda v: StageDynamics(inertias={"ring": v}), g.MIN_INERTIA, g.MAX_INERTIA,
         "members.ring_inertia"),
        (lambda v: StageDynamics(bearings={"planet": v}), g.MIN_BEARING_STIFFNESS,
         g.MAX_BEARING_STIFFNESS, "members.planet_bearing"),
        (lambda v: StageDynamics(held_torsional=v), g.MIN_SHAFT_STIFFNESS, g.MAX_SHAFT_STIFFNESS,
         "members.held_torsional"),
        (lambda v: DynamicsSettings(bearing_stiffness=v), g.MIN_BEARING_STIFFNESS,
         g.MAX_BEARING_STIFFNESS, "dynamics.bearing_stiffness"),
        (lambda v: g.Shaft(name="s", gears=("a",), bearing_stiffness=v), g.MIN_BEARING_STIFFNESS,
         g.MAX_BEARING_STIFFNESS, "shafts.s.bearing_stiffness"),
        (lambda v: Pitting(pit_diameter=v, **pits), MIN_PIT_DIAMETER, math.inf,
         "pitting.pit_diameter"),
    ]


@settings(max_examples=300, deadline=None)
@given(case=st.integers(0, 8), v=st.one_of(st.floats(), st.sampled_from(
    [1e-300, -1.0, 0.0, 1e300, 1e-7, 1e3, 1.0, 1e14])))
def test_every_physical_bound_holds_on_both_sides(case, v):
    make, lo, hi, name = _bounded()[case]
    assume(v not in (lo, hi))
    if lo < v < hi:
        make(v)
    else:
        with pytest.raises(InputError) as info:
            make(v)
        assert info.value.parameter == name
