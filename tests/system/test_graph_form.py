"""One TOML form for every gearbox: shafts, gears, meshes and planetary stages (issue 23).

A gearbox with stages written as a graph (``[[shafts]]``, ``[[gears]]``, ``[[meshes]]``,
``[[stages]]`` whose members name their shafts, ``gearsim.model.graph_form``) is the same
gearbox as its ``[stage]`` / ``[[stages]]`` + ``[chain]`` / ``[input_chain]`` form: the
same elements (dataclass equality) and the same simulated numbers (numpy.array_equal);
a refusal names the element as written in the graph.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from two_stage_boxes import TOML_CHAINS as CHAINS_STAGE_FORM
from two_stage_boxes import TOML_CHAINS_GRAPH as CHAINS_GRAPH
from two_stage_boxes import refused_in_one_line

import gearsim as gs
from gearsim.cli import run as cli_run
from gearsim.model import loads

#: The wind-turbine-grc example as it was written before the graph form (a [stage]
#: driving a [chain] of two parallel stages).
WIND_TURBINE_STAGE_FORM = """name = "NREL GRC 750 kW gearbox: planetary + two parallel stages"

[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"

[stage]
sun_teeth = 21
planet_teeth = 39
ring_teeth = 99
planets = 3
normal_module = "10 mm"
normal_pressure_angle = "20 deg"
helix_angle = "7.5 deg"
face_width = "227.5 mm"
ring_addendum_coefficient = 0.8

[operating]
fixed = "ring"
input = "carrier"
speed = "22.1 rpm"
torque = "324 kN*m"

[stiffness]
positions_per_cycle = 20
slices = 10


[sensor]
angle = "0 deg"
width = "90 deg"

[dynamics]
duration = 3.0
fs = 6000  # > 2 x 4 x 660 Hz: the fourth harmonic of the high-speed mesh that `gearsim simulate` analyses
oversample = 10

[chain]
name = "parallel stages"

[chain.common]
normal_pressure_angle = "20 deg"
helix_angle = "14 deg"

[[chain.shafts]]
name = "low-speed"          # the sun shaft, driven by the planetary stage

[[chain.shafts]]
name = "intermediate"

[[chain.shafts]]
name = "high-speed"         # to the generator

[[chain.gears]]
name = "low-speed-gear"
shaft = "low-speed"
teeth = 82
normal_module = "8.25 mm"
face_width = "180 mm"

[[chain.gears]]
name = "intermediate-pinion"
shaft = "intermediate"
teeth = 23
normal_module = "8.25 mm"
face_width = "180 mm"

[[chain.gears]]
name = "intermediate-gear"
shaft = "intermediate"
teeth = 88
normal_module = "5 mm"
face_width = "110 mm"

[[chain.gears]]
name = "high-speed-pinion"
shaft = "high-speed"
teeth = 22
normal_module = "5 mm"
face_width = "110 mm"

[[chain.meshes]]
gears = ["low-speed-gear", "intermediate-pinion"]

[[chain.meshes]]
gears = ["intermediate-gear", "high-speed-pinion"]
angle = "180 deg"

[chain.stiffness]
positions_per_cycle = 20
slices = 10
"""




def _same_but_chain_names(a, b) -> bool:
    """Gearbox equality but for the names the forms give their gear chains and the
    members' shafts (which only the graph names)."""
    parts = {k: dataclasses.replace(getattr(a, k), name=getattr(b, k).name)
             for k in ("train", "input_train") if getattr(a, k) is not None}
    return dataclasses.replace(a, member_shafts=(), **parts) == b


def test_wind_turbine_example_is_its_stage_form():
    graph = gs.example("wind-turbine-grc")
    assert _same_but_chain_names(graph, loads(WIND_TURBINE_STAGE_FORM))
    assert [sh.name for sh in graph.train.flow.shafts] == ["low-speed", "intermediate",
                                                           "high-speed"]
    assert dict(graph.member_shafts) == {"carrier": "rotor", "sun": "low-speed"}


@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_gears_stages_gears_graph_gives_the_same_numbers(model):
    graph, staged = loads(CHAINS_GRAPH), loads(CHAINS_STAGE_FORM)
    assert graph.stage == staged.stage and graph.next_stages == staged.next_stages
    assert (graph.shaft_stiffness, graph.input_shaft_stiffness) == (5e7, 2e6)
    assert graph.next_stages[0].shaft_stiffness == 3e6
    a = graph.simulate(duration=0.02, fs=5000.0, model=model)
    b = staged.simulate(duration=0.02, fs=5000.0, model=model)
    assert list(a.data_vars) == list(b.data_vars)
    for v in b.data_vars:
        if v != "tacho":
            assert np.array_equal(a[v].values, b[v].values), v
    # the graph's shaft names label the gears' records and the tachos, one a shaft: the
    # stage form's tacho of the first member (or gear) on each
    assert list(a["chain_shaft"].values) == ["in", "sun-shaft", "out", "output"]
    first = {"between": "stage1-carrier", "sun-shaft": "stage1-sun",
             "out": "stage2-carrier", "in": "input-pinion", "output": "output-pinion"}
    assert sorted(a["shaft"].values) == sorted(first)
    for shaft, member in first.items():
        assert np.array_equal(a["tacho"].sel(shaft=shaft).values,
                              b["tacho"].sel(shaft=member).values), shaft
    assert graph.reference(signal="mesh_force[stage2-sun-planet-1]")[0] == "out"
    assert graph.slowest_shaft()[0] in ("out", "output")


def test_a_crack_on_a_named_gear_reaches_its_chain():
    crack = '\n[[cracks]]\ngear = "output-pinion"\ntooth = 3\nflank = "working"\n' \
            'depth = "1 mm"\n'
    graph = loads(CHAINS_GRAPH + crack)
    staged = loads(CHAINS_STAGE_FORM + crack.replace("[[cracks]]", "[[chain.cracks]]"))
    assert graph.train.cracks == staged.train.cracks and len(graph.train.cracks) == 1
    assert graph.input_train.cracks == () and graph.stage.cracks == ()


PTO = """
[[shafts]]
name = "pto"
[[gears]]
name = "pto-gear"
shaft = "{on}"
teeth = 30
normal_module = "3 mm"
[[gears]]
name = "pto-pinion"
shaft = "pto"
teeth = 20
normal_module = "3 mm"
[[meshes]]
gears = ["pto-gear", "pto-pinion"]
"""
STAGE1_END = 'ring_addendum_coefficient = 0.8\n[[stages]]'


@pytest.mark.parametrize(("edit", "parameter", "value"), [
    (lambda t: t.replace('sun = "between"', 'sun = "nowhere"'), "stages[1].sun", "nowhere"),
    (lambda t: t.replace('carrier = "out"', 'carrier = "housing"'), "stages[1]", None),
    (lambda t: t.replace('sun = "between"', 'sun = "between"\nfixed = "ring"'),
     "stages[1].fixed", "ring"),
    (lambda t: t.replace('torque = "200 N*m"', 'torque = "200 N*m"\ninput = "sun"'),
     "operating.input", "sun"),
    (lambda t: t + '[[shafts]]\nname = "spare"\n', "shafts[5]", "spare"),
    (lambda t: t.replace('shaft = "output"', 'shaft = "outputt"'), "gears[3].shaft",
     "outputt"),
    (lambda t: t + '[[cracks]]\ngear = "sun"\ntooth = 0\nflank = "working"\n'
     'depth = "1 mm"\n', "cracks[0].gear", "sun"),
    (lambda t: t.replace("teeth = 25", "teeth = -5"), "gears[3].teeth", "-5"),
    (lambda t: t.replace('"3e6 N*m/rad"', '"0 N*m/rad"'), "shafts[2].torsional_stiffness",
     "0 N*m/rad"),
    (lambda t: t.replace('"5e7 N*m/rad"', '"-5 N*m/rad"'), "shafts[3].torsional_stiffness",
     "-5 N*m/rad"),
    (lambda t: t.replace('"2e6 N*m/rad"', '"1e300 N*m/rad"'),
     "shafts[1].torsional_stiffness", "1e300 N*m/rad"),
    (lambda t: t.replace("sun_teeth = 20", "sun_teeth = 0"), "stages[1].sun_teeth", "0"),
    (lambda t: t.replace('face_width = "40 mm"', 'face_width = "nan mm"'),
     "stages[1].face_width", "nan mm"),
    (lambda t: t.replace(STAGE1_END, 'ring_addendum_coefficient = 0.8\n[[stages.cracks]]\n'
                         'gear = "planet-9"\ntooth = 0\nflank = "working"\ndepth = "1 mm"\n'
                         '[[stages]]', 1), "stages[0].cracks[0].gear", "planet-9"),
    (lambda t: t.replace("[operating]", '[[stages.cracks]]\ngear = "sun"\ntooth = 0\n'
                         'flank = "working"\ndepth = "inf mm"\n[operating]'),
     "stages[1].cracks[0].depth", "inf mm"),
    (lambda t: t.replace(STAGE1_END, 'ring_addendum_coefficient = 0.8\n[stages.members]\n'
                         'sun_mass = "-1 kg"\n[[stages]]', 1), "stages[0].members.sun_mass",
     "-1 kg"),
    (lambda t: t + PTO.format(on="between"), "shafts[2]", "between"),  # branching power
    (lambda t: t + '[[shafts]]\nname = "x"\n' + PTO.format(on="x"), "gears[4]", "pto-gear"),
    (lambda t: t + '[members]\nsun_mass = "1 kg"\n', "members", None),
    (lambda t: t.replace('speed = "1500 rpm"', 'speed = "1e-300 rpm"'), "operating.speed",
     "1e-300 rpm"),
])
def test_bad_graph_is_one_line_naming_the_element(tmp_path, capsys, edit, parameter, value):
    line = refused_in_one_line(edit(CHAINS_GRAPH), tmp_path, capsys, parameter)
    if value is not None:
        assert line.startswith(f"gearsim: error: {parameter} = {value}:"), line


def test_stage_form_geometry_refusal_names_the_key_as_written():
    staged = CHAINS_STAGE_FORM.replace('normal_module = "4 mm"', 'normal_module = "-4 mm"')
    with pytest.raises(gs.InputError) as err:
        loads(staged)
    assert (err.value.parameter, err.value.value) == ("stages[1].normal_module", "-4 mm")


def test_layout_names_the_shaft_of_each_member(capsys):
    assert cli_run(["layout", "wind-turbine-grc"]) == 0
    out = capsys.readouterr().out
    assert "carrier in, ring held; f_m 36.465 Hz; sun on low-speed, carrier on rotor" in out
    assert "member_shafts" not in gs.example("nrel-grc").layout()["stage"]
