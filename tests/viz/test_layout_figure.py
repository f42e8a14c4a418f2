"""The layout figure drawn from the graph: gears in their planes, coaxial shafts apart.

Independent numbers: the test rig's reducer (32/80 then 48/64, module 1.5 mm) has its
input and output shafts on one axis (both centre distances (32 + 80) 1.5 / 2 =
(48 + 64) 1.5 / 2 = 84 mm), so a plan view alone puts their labels on one point; the
second stage sits in a plane of its own behind the first.
"""

from __future__ import annotations

import gearsim as gs
from gearsim.viz.layout import axial_stations, plot_layout


def _drawing(name: str) -> dict:
    return gs.example(name).layout()["plan"]


def test_a_compound_shaft_puts_its_second_gear_in_the_next_plane():
    d = _drawing("two-stage-reducer")
    assert axial_stations(d["gears"], d["links"]) == {
        "input-pinion": 0, "intermediate-gear": 0, "intermediate-pinion": 1, "output-gear": 1}


def test_an_idler_train_is_one_plane():
    d = _drawing("idler-table1")
    assert set(axial_stations(d["gears"], d["links"]).values()) == {0}


def test_coaxial_shafts_are_labelled_once_in_plan_and_apart_in_the_side_view():
    d = _drawing("two-stage-reducer")
    centres = dict(d["shafts"])
    assert abs(centres["input"][0] - centres["output"][0]) < 1e-9  # 84 mm both stages
    assert abs(centres["intermediate"][0] - 0.084) < 1e-9
    fig = plot_layout(d["shafts"], d["gears"], d["links"], title="reducer")
    plan, side = fig.axes[:2]
    plan_text = [t.get_text() for t in plan.texts]
    assert "input, output" in plan_text and "I, II" in plan_text
    where = {t.get_text(): t.xy for t in side.texts}
    assert where["input"][0] < where["output"][0]  # one axis, two planes
    assert where["input"][1] == where["output"][1] == 0.0
    assert abs(where["intermediate"][1] - 84.0) < 1e-9


def test_the_stage_panel_names_the_shaft_each_member_sits_on():
    """wind-turbine-grc: the sun on the low-speed shaft, the carrier on the rotor, the
    ring held (the graph's [[stages]] entry)."""
    d = _drawing("wind-turbine-grc")
    fig = plot_layout(d["shafts"], d["gears"], d["links"], title="wt", stage=d["stage"],
                      upstream=d["upstream"])
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["sun (z 21, on low-speed)", "ring (z 99, held)",
                      "carrier (planet centres, on rotor)", "planets (z 39)"]
