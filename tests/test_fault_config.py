"""``[[faults]]`` and ``[[modifications]]`` in a configuration: read, written back, and
refused with one line naming the table entry, the value and the limit (exit 2)."""

from __future__ import annotations

import pytest

import gearsim as gs
from gearsim.cli import run
from gearsim.system.toml import train_to_toml

BASE = """
name = "spur with faults"
[common]
normal_module = "3.2 mm"
face_width = "16 mm"
[[gears]]
name = "pinion"
teeth = 19
[[gears]]
name = "gear"
teeth = 48
[operating]
speed = "1800 rpm"
torque = "100 N*m"
"""

GOOD = BASE + """
[[faults]]
kind = "spall"
gear = "pinion"
tooth = 3
radius = "30.4 mm"
length = "2 mm"
width = "6 mm"
depth = "0.1 mm"
shape = "elliptical"
[[faults]]
kind = "broken"
gear = "gear"
tooth = 5
width = "8 mm"
[[faults]]
kind = "chip"
gear = "gear"
tooth = 9
length = "1 mm"
width = "4 mm"
[[faults]]
kind = "pitting"
gear = "pinion"
tooth = 7
area_fraction = 0.2
radius_min = "29 mm"
radius_max = "30.4 mm"
pit_diameter = "0.4 mm"
depth = "50 um"
[[faults]]
kind = "wear"
gear = "pinion"
radii = ["29 mm", "31 mm", "33 mm"]
depths = ["5 um", "0 um", "4 um"]
[[modifications]]
gear = "pinion"
tip_relief = "10 um"
tip_relief_length = "1.5 mm"
relief_shape = "parabolic"
crowning = "5 um"
pitch_grade = 6
"""


def test_faults_round_trip_through_the_effective_configuration():
    gb = gs.loads(GOOD)
    assert [f.kind for f in gb.train.faults] == ["spall", "broken", "chip", "pitting", "wear"]
    assert gb.train.faults[0].depth == pytest.approx(1e-4)
    assert gb.train.modifications[0].tip_relief == pytest.approx(1e-5)
    again = gs.loads(train_to_toml(gb.train))
    assert again.train == gb.train


def _bad(tmp_path, extra: str):
    p = tmp_path / "bad.toml"
    p.write_text(BASE + extra)
    return p


@pytest.mark.parametrize(("extra", "parameter", "words"), [
    # a spall outside the active flank
    ('[[faults]]\nkind = "spall"\ngear = "pinion"\nradius = "27 mm"\nlength = "2 mm"\n'
     'width = "4 mm"\ndepth = "0.1 mm"\n', "faults[0].radius", "active flank"),
    # a spall larger than the tooth (deeper than half its thickness)
    ('[[faults]]\nkind = "spall"\ngear = "pinion"\nradius = "30.4 mm"\nlength = "2 mm"\n'
     'width = "4 mm"\ndepth = "3 mm"\n', "faults[0].depth", "half the tooth thickness"),
    # a spall wider than the face
    ('[[faults]]\nkind = "spall"\ngear = "pinion"\nradius = "30.4 mm"\nlength = "2 mm"\n'
     'width = "20 mm"\ndepth = "0.1 mm"\n', "faults[0].width", "face width"),
    # a chip as long as the profile
    ('[[faults]]\nkind = "chip"\ngear = "pinion"\nlength = "8 mm"\nwidth = "4 mm"\n',
     "faults[0].length", "active profile"),
    # a break line off the fillet
    ('[[faults]]\nkind = "broken"\ngear = "pinion"\nbreak_radius = "31 mm"\n',
     "faults[0].break_radius", "fillet"),
    # wear deeper than the tooth allows
    ('[[faults]]\nkind = "wear"\ngear = "pinion"\nradii = ["29 mm", "33 mm"]\n'
     'depths = ["3 mm", "0 mm"]\n', "faults[0].depths", "half the tooth thickness"),
    # a relief longer than the profile
    ('[[modifications]]\ngear = "pinion"\ntip_relief = "10 um"\n'
     'tip_relief_length = "30 mm"\n', "modifications[0].tip_relief_length",
     "active profile"),
    # an ISO grade outside 1-11
    ('[[modifications]]\ngear = "pinion"\npitch_grade = 12\n',
     "modifications[0].pitch_grade", "1 .. 11"),
    # overlapping faults that leave no tooth
    ('[[faults]]\nkind = "broken"\ngear = "pinion"\ntooth = 2\n'
     '[[faults]]\nkind = "chip"\ngear = "pinion"\ntooth = 2\nlength = "1 mm"\n'
     'width = "4 mm"\n', "faults[1].tooth", "broken over the whole face"),
    # a key the kind does not take, an unknown kind, a tooth that does not exist
    ('[[faults]]\nkind = "chip"\ngear = "pinion"\nlength = "1 mm"\nwidth = "4 mm"\n'
     'depth = "1 mm"\n', "faults[0].depth", "not a key of a chip"),
    ('[[faults]]\nkind = "dent"\ngear = "pinion"\n', "faults[0].kind", "spall"),
    ('[[faults]]\nkind = "broken"\ngear = "pinion"\ntooth = 19\n', "faults[0].tooth",
     "< 19"),
    ('[[faults]]\nkind = "spall"\ngear = "pinion"\nradius = "30.4 mm"\nlength = "-2 mm"\n'
     'width = "4 mm"\ndepth = "0.1 mm"\n', "faults[0].length", "> 0"),
    # a size left out (was an internal TypeError)
    ('[[faults]]\nkind = "spall"\ngear = "pinion"\nlength = "2 mm"\nwidth = "4 mm"\n'
     'depth = "0.1 mm"\n', "faults[0].radius = missing", "a spall needs radius"),
    ('[[faults]]\nkind = "pitting"\ngear = "pinion"\narea_fraction = 0.2\n',
     "faults[0].radius_min = missing", "a pitting needs radius_min, radius_max"),
    ('[[faults]]\nkind = "chip"\ngear = "pinion"\n', "faults[0].length = missing",
     "a chip needs length, width"),
])
def test_bad_faults_exit_2_naming_the_entry(tmp_path, capsys, extra, parameter, words):
    p = _bad(tmp_path, extra)
    assert run(["stiffness", str(p)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert parameter in err[0] and words in err[0], err[0]
