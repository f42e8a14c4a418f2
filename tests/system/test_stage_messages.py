"""One-line refusals of stage boxes that named the wrong thing (probe-b #12)."""

from __future__ import annotations

import pytest
from two_stage_boxes import TOML, TOML_CHAINS_GRAPH

import gearsim as gs
from gearsim.errors import InputError


def test_planet_angle_off_by_a_little_names_the_stage_and_the_nearest_angle():
    """(24 + 72) x 240.00001 deg / 360 deg = 64.0000027: not an integer within 1e-6, which
    the message showed as "= 64" under stage.planet_angles[2]; the graph form's first
    stage is stages[1], the nearest assemblable angle 64 x 360 / 96 = 240 deg."""
    text = TOML_CHAINS_GRAPH.replace("planets = 3\n", 'planets = 3\nplanet_angles = '
                                     '["0 deg", "120 deg", "240.00001 deg"]\n')
    with pytest.raises(InputError) as err:
        gs.loads(text)
    assert str(err.value) == (
        'stages[1].planet_angles = ["0 deg", "120 deg", "240.00001 deg"]: planet 3 at '
        "240.00001 deg cannot be assembled: (z_s + z_r) psi / 2 pi = 64.00000267 must be an "
        "integer within 1e-06 (nearest: 240 deg)")


def test_stage_refusals_of_speed_and_crack_member():
    """A negative speed of a stage: refused as a gear train's (> 0), not against a range
    in rad/s; a crack on no member lists the ring, on which cracks are accepted."""
    with pytest.raises(InputError) as err:
        gs.loads(TOML.replace('speed = "3000 rpm"', 'speed = "-3000 rpm"'))
    assert str(err.value) == "operating.speed = -3000 rpm: must be a finite number > 0 rad/s"
    with pytest.raises(InputError, match=r"bull: must be sun, ring or planet-1 \.\. planet-3$"):
        gs.loads(TOML.replace("[operating]", '[[cracks]]\ngear = "bull"\ndepth = "1 mm"\n'
                              "[operating]"))
