"""One-line refusals of stage boxes that named the wrong thing (probe-b #12)."""

from __future__ import annotations

import pytest
from two_stage_boxes import TOML, TOML_CHAINS_GRAPH

import gearsim as gs
from gearsim.errors import InputError


def test_planet_angle_off_by_a_little_names_the_stage_and_the_nearest_angle():
    """(24 + 72) x 240.00001 deg / 360 deg = 64.0000027: not an integer within 1e-6, which
    the message showed as "= 64" under stage.planet_angles[2]; the graph form's first
    stage is stages[0], the nearest assemblable angle 64 x 360 / 96 = 240 deg."""
    text = TOML_CHAINS_GRAPH.replace("planets = 3\n", 'planets = 3\nplanet_angles = '
                                     '["0 deg", "120 deg", "240.00001 deg"]\n')
    with pytest.raises(InputError) as err:
        gs.loads(text)
    assert str(err.value) == (
        'stages[0].planet_angles = ["0 deg", "120 deg", "240.00001 deg"]: planet 3 at '
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


def _second_stage_first(text: str) -> str:
    """The graph ``text`` with its two [[stages]] written in the other order (the power
    flow still goes through 24/24/72 first: the file's index is not the flow's)."""
    head, first, second = text.split("[[stages]]\n")
    second, tail = second.split("[operating]")
    return f"{head}[[stages]]\n{second}[[stages]]\n{first}[operating]{tail}"


#: The ring tip circle with ring_addendum_coefficient 1: r_a = m (z_r - 2) / 2, by hand.
TIP_1, TIP_2 = 3 * (72 - 2) / 2, 4 * (100 - 2) / 2  # 105 and 196 mm


@pytest.mark.parametrize(("text", "which", "stage"), [
    (TOML, 1, "stages[0]"), (TOML, 2, "stages[1]"),
    (TOML_CHAINS_GRAPH, 1, "stages[0]"), (TOML_CHAINS_GRAPH, 2, "stages[1]"),
    (_second_stage_first(TOML_CHAINS_GRAPH), 2, "stages[0]"),
    (_second_stage_first(TOML_CHAINS_GRAPH), 1, "stages[1]")],
    ids=["form-1", "form-2", "graph-1", "graph-2", "reordered-2", "reordered-1"])
def test_a_stage_own_refusal_names_its_entry(text, which, stage):
    """The ring-planet mesh of a stage whose ring tip circle reaches the planet's fillet
    (ring addendum 1 instead of 0.8) was refused as "stage: ring-planet mesh" whichever
    of the [[stages]] it was; it names the entry as the file writes it, from 0."""
    tables = text.split("[[stages]]")
    k = next(i for i, t in enumerate(tables) if f"ring_teeth = {(72, 100)[which - 1]}\n" in t)
    tables[k] = tables[k].replace("ring_addendum_coefficient = 0.8\n", "")
    with pytest.raises(InputError) as err:
        gs.loads("[[stages]]".join(tables))
    tip = (TIP_1, TIP_2)[which - 1]
    assert str(err.value).startswith(f"{stage}: ring-planet mesh = ring tip circle {tip:g} mm: "
                                     "reaches the planet below its form circle")


def test_the_first_entry_own_value_is_named_as_written():
    """A first [[stages]] entry's value that the stage itself checks (not its geometry) was
    named stage.ring_foundation; it is the entry's."""
    with pytest.raises(InputError) as err:
        gs.loads(TOML.replace("planets = 3\n", 'planets = 3\nring_foundation = "soft"\n'))
    assert str(err.value) == 'stages[0].ring_foundation = soft: must be "sainsot-solid" or "none"'
