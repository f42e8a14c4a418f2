"""The fault classes on a planetary stage's members (issue 23: faults on any gear).

Independent numbers: the sun's and a planet's active flank in the sun-planet mesh from
the radii alone (line of action a'^2 = L^2 + (r_b,s + r_b,p)^2; the sun's contact from
the planet's tip to its own tip, the planet's the other way round, as roll lengths
sqrt(r^2 - r_b^2)), so a spall's length, 0.5 x the active profile arc
(l_hi^2 - l_lo^2) / (2 r_b), and a chip's, 0.4 x that arc, follow without the pair's code.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import InputError
from gearsim.model.variants import fault_gears, fault_variant
from gearsim.studies.sweep import expand, loads_study
from gearsim.studies.sweep_case import build_case

#: Roll lengths from radii against the pair's contact limits: round-off only.
ARC_RTOL = 1e-12


def _active_arcs(stage) -> dict[str, float]:
    s, p = stage.sun, stage.planet
    rbs, rbp = s.base_radius, p.base_radius
    line = math.sqrt(stage.centre_distance ** 2 - (rbs + rbp) ** 2)
    tip_s = math.sqrt(s.tip_radius ** 2 - rbs ** 2)
    tip_p = math.sqrt(p.tip_radius ** 2 - rbp ** 2)
    return {"sun": (tip_s ** 2 - (line - tip_p) ** 2) / (2 * rbs),
            "planet-2": (tip_p ** 2 - (line - tip_s) ** 2) / (2 * rbp)}


@pytest.mark.parametrize("member", ["sun", "planet-2"])
def test_a_members_spall_and_chip_are_sized_by_its_own_active_flank(member):
    gb = gs.example("nrel-grc")
    arc = _active_arcs(gb.stage.stage)[member]
    spall = fault_variant(gb, "spall", 1.0, gear=member).stage.faults[0]
    chip = fault_variant(gb, "chip", 0.5, gear=member).stage.faults[0]
    assert (spall.gear, spall.tooth, chip.gear) == (member, 0, member)
    assert spall.length == pytest.approx(0.5 * arc, rel=ARC_RTOL)
    assert chip.length == pytest.approx(0.5 * 0.4 * arc, rel=ARC_RTOL)


def test_a_members_crack_scales_with_its_module_and_the_ring_takes_cracks_only():
    gb = gs.example("nrel-grc")
    m = gb.stage.stage.normal_module
    for member in ("sun", "ring", "planet-1"):
        (c,) = fault_variant(gb, "working", 0.5, gear=member).stage.cracks
        assert (c.gear, c.flank) == (member, "working")
        assert c.depth == pytest.approx(0.5 * 2e-3 * m / 6e-3, rel=1e-15)
    with pytest.raises(InputError, match="the ring takes cracks only"):
        fault_variant(gb, "spall", 1.0, gear="ring")
    with pytest.raises(InputError, match="a broken tooth of planet-3 also leaves the ring"):
        fault_variant(gb, "broken", 1.0, gear="planet-3")
    with pytest.raises(InputError, match="pitch error of the stage member sun"):
        fault_variant(gb, "pitch", 1.0, gear="sun")


def test_every_gear_of_the_wind_turbine_box_is_named():
    assert fault_gears(gs.example("wind-turbine-grc")) == (
        "low-speed-gear", "intermediate-pinion", "intermediate-gear", "high-speed-pinion",
        "sun", "ring", "planet-1", "planet-2", "planet-3")


STUDY = """
[study]
config = "wind-turbine-grc"
signal = "sensor"
shafts = "reference"
[study.dynamics]
duration = "11 s"   # two carrier revolutions: parsed and built here, not run
[parameters]
fault = ["none", "spall", "working"]
gear = ["sun", "planet-1", "intermediate-pinion"]
"""


def test_a_study_puts_each_class_on_the_named_member_or_gear():
    study = loads_study(STUDY)
    for c in expand(study):
        gb = build_case(study, c)
        on_stage = [f.gear for f in gb.stage.faults] + [k.gear for k in gb.stage.cracks]
        on_gears = [f.gear for f in gb.train.faults] + [k.gear for k in gb.train.cracks]
        want = [] if c.fault == "none" else [c.gear]
        assert (on_stage + on_gears) == want, c
        assert on_gears == ([] if c.gear != "intermediate-pinion" else want)
    with pytest.raises(InputError) as err:
        loads_study(STUDY.replace('"working"]', '"broken"]'))
    assert err.value.parameter == "parameters.fault[2]"
    assert "planet-1" in str(err.value) and "ring mesh" in str(err.value)


#: A 1e-12 m deep spall changes no contact. What is left: on a gear, round-off (2e-10
#: of the mesh force); on the sun, its mesh of contacts is built from the flank states of
#: the damaged member, the healthy one without (3.6e-5 of the sun mesh force measured).
SAME_FOOTING_RTOL = 1e-4


@pytest.mark.parametrize("gear", ["sun", "intermediate-pinion"])
def test_a_negligible_fault_variant_is_the_healthy_variant(gear):
    """Every variant of a gearbox with stages runs the same mesh models (the stages' sun
    meshes and the gears' meshes as meshes of contacts): a spall 1e-12 m deep on a stage
    member or on a gear beside the stage gives the healthy variant's record. Before, the
    faulty gear's mesh alone ran on contacts and the rest on tables, which moved the
    record by more than the fault (+5.5 % of the sensor's RMS on a 27/35/97 stage)."""
    import dataclasses

    gb = gs.example("wind-turbine-grc").replace(dynamics={"duration": 0.3})
    healthy = fault_variant(gb, "none")
    spalled = fault_variant(gb, "spall", 1.0, gear=gear)
    if gear == "sun":
        (f,) = spalled.stage.faults
        tiny = dataclasses.replace(spalled, stage=dataclasses.replace(
            spalled.stage, faults=(dataclasses.replace(f, depth=1e-12),)))
    else:
        (f,) = spalled.train.faults
        tiny = dataclasses.replace(spalled, train=spalled.train.with_faults(
            (dataclasses.replace(f, depth=1e-12),)))
    for signal in ("mesh_force[sun-planet-1]", "chain_mesh_force[II]"):
        a, b = healthy.record(signal), tiny.record(signal)
        assert np.max(np.abs(a - b)) <= SAME_FOOTING_RTOL * np.max(np.abs(a)), signal
