"""A study varies the bearings of one named shaft: ``"bearing_stiffness[SHAFT]"``.

Checked against what does not come from the naming code: the stiffness the assembled
equations of motion carry on each coordinate (read by the coordinates' own labels), a
named bearing set to the default value giving the default case's features to the bit,
and the refusals of names and values.
"""

from __future__ import annotations

import numpy as np
import pytest

import gearsim as gs
from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.simulate import build_model
from gearsim.errors import InputError
from gearsim.studies.sweep import expand, loads_study
from gearsim.studies.sweep_case import build_case

STUDY = """
[study]
config = "two-stage-reducer"
[study.dynamics]
duration = "0.5 s"
fs = "20 kHz"
[parameters]
{parameters}
"""


def _kb(model) -> dict[str, float]:
    return dict(zip(model.dof_labels, model.kb, strict=True))


def test_each_case_sets_only_the_named_shafts_bearings_in_the_equations():
    st = loads_study(STUDY.format(parameters='"bearing_stiffness[intermediate]" = '
                                  '["2e8 N/m", "5e8 N/m"]\nbearing_stiffness = ["3e9 N/m"]'))
    cases = expand(st)
    assert [c.bearings for c in cases] == [(("intermediate", 2e8),), (("intermediate", 5e8),)]
    for case, k in zip(cases, (2e8, 5e8), strict=True):
        gb = build_case(st, case)
        kb = _kb(build_model(gb.train, gb.dynamics))
        assert [kb[f"intermediate.{a}"] for a in "xyz"] == [k, k, k]  # axial follows radial
        assert [kb[f"{s}.{a}"] for s in ("input", "output") for a in "xy"] == [3e9] * 4


def test_a_shaft_of_a_stage_member_sets_the_member_and_the_gears_it_carries():
    gb = gs.example("wind-turbine-grc")
    assert gb.bearing_names() == ("low-speed", "intermediate", "high-speed", "planet", "ring",
                                  "rotor")
    gb = gb.with_bearing("low-speed", 3e8).with_bearing("rotor", 4e8)
    kb = _kb(build_stage_chain_model(gb.stage, gb.train, gb.members, gb.dynamics))
    assert [kb["sun.x"], kb["sun.y"], kb["low-speed.x"], kb["low-speed.y"]] == [3e8] * 4
    assert [kb["carrier.x"], kb["carrier.y"]] == [4e8] * 2
    default = gb.dynamics.bearing_stiffness
    assert [kb["ring.x"], kb["intermediate.x"], kb["high-speed.y"]] == [default] * 3


def test_a_named_bearing_at_the_default_stiffness_gives_the_default_case_to_the_bit():
    base = loads_study(STUDY.format(parameters='flank = ["none"]'))
    named = loads_study(STUDY.format(parameters='"bearing_stiffness[output]" = ["1e9 N/m"]'))
    a, b = (build_case(s, expand(s)[0]) for s in (base, named))
    assert b.dynamics.bearing_stiffness == 1e9  # the default every other shaft keeps
    np.testing.assert_array_equal(a.record("acceleration[output,y]"),
                                  b.record("acceleration[output,y]"))
    assert named.case_key(expand(named)[0]) != base.case_key(expand(base)[0])


@pytest.mark.parametrize(("parameters", "where", "says"), [
    ('"bearing_stiffness[intermediat]" = ["1e8 N/m"]', "parameters.bearing_stiffness"
     "[intermediat]", "names no shaft of the gearbox; its bearings: input, intermediate, "
     "output"),
    ('"bearing_stiffness[output]" = ["1e20 N/m"]', "parameters.bearing_stiffness[output][0]",
     "must be in [100000, 1e+15] N/m"),
    ('"bearing_stiffness[output]" = ["-1 N/m"]', "parameters.bearing_stiffness[output][0]",
     "must be > 0 N/m"),
    ('"bearing_stiffness[output]" = [0.0]', "parameters.bearing_stiffness[output][0]",
     "must be > 0 N/m"),
    ('"bearing_stiffness[output]" = ["inf N/m"]', "parameters.bearing_stiffness[output][0]",
     "finite"),
    ('"bearing_stiffness[output]" = [nan]', "parameters.bearing_stiffness[output][0]",
     "finite"),
    ('"bearing_stiffness[output]" = [1e300]', "parameters.bearing_stiffness[output][0]",
     "must be in [100000, 1e+15] N/m"),
    ('"bearing_stiffness[output]" = [1e-300]', "parameters.bearing_stiffness[output][0]",
     "must be in [100000, 1e+15] N/m"),
    ('"bearing_stiffness[output]" = { min = "1e8 N/m", max = "1e30 N/m", num = 2 }',
     "parameters.bearing_stiffness[output].max", "must be in [100000, 1e+15] N/m"),
    ('"bearing_stiffness[output" = ["1e8 N/m"]', "parameters.bearing_stiffness[output",
     "unknown parameter"),
])
def test_a_bad_name_or_value_is_refused_in_one_line(parameters, where, says):
    with pytest.raises(InputError) as e:
        loads_study(STUDY.format(parameters=parameters))
    assert e.value.parameter == where and says in str(e.value)


def test_the_cli_refuses_it_before_writing(tmp_path, gearsim_here):
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(parameters='"bearing_stiffness[idler]" = ["1e8 N/m"]'))
    out = tmp_path / "s.nc"
    r = gearsim_here("sweep", study, "--out", out)
    assert r.returncode == 2 and not out.exists()
    assert r.stderr.count("\n") == 1 and "bearing_stiffness[idler]" in r.stderr
