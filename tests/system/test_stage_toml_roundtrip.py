"""A gearbox with planetary stages written back as TOML (``Gearbox.to_toml``, the graph
form of ``gearsim.model.graph_toml``) reads back to the same gearbox.

The text written is read by ``gearsim.loads`` (another route: the file reader, not the
object) and compared with the gearbox it was written from element for element (dataclass
equality; what the graph form names otherwise, the members' shafts and the gear chains'
names, set aside), in a short run (every variable bit for bit, ``numpy.array_equal``;
the graph has one tacho a shaft) and against hand numbers (Willis: the NREL stage meshes
at z_r f_c). The stage results carry the text as their ``config``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from two_stage_boxes import TOML, TOML_CHAINS, TOML_CHAINS_GRAPH

import gearsim as gs
from gearsim.errors import InputError
from gearsim.io.measured import read_record
from gearsim.io.results import write_results
from gearsim.model import loads

#: Gears, two stages, gears as a graph, with damage on both stages (a planet's crack,
#: a spall on the sun), on the gears (a crack, a tip relief), members and a sensor.
DAMAGED_GRAPH = TOML_CHAINS_GRAPH.replace("""ring_addendum_coefficient = 0.8
[[stages]]""", """ring_addendum_coefficient = 0.8
[stages.members]
sun_mass = "1.5 kg"
planet_bearing = "5e8 N/m"
held_torsional = "1e7 N*m/rad"
[[stages.cracks]]
gear = "planet-2"
tooth = 1
flank = "working"
depth = "1 mm"
[[stages]]""").replace("[operating]", """[[stages.faults]]
kind = "spall"
gear = "sun"
tooth = 3
radius = "40 mm"
length = "1 mm"
width = "10 mm"
depth = "10 um"
[[cracks]]
gear = "output-pinion"
tooth = 2
flank = "working"
depth = "0.5 mm"
[[modifications]]
gear = "input-pinion"
tip_relief = "10 um"
tip_relief_length = "1 mm"
[sensor]
angle = "30 deg"
width = "60 deg"
[operating]""")

CASES = {"lin-parker-1999": lambda: gs.example("lin-parker-1999"),
         "nrel-grc": lambda: gs.example("nrel-grc"),
         "wind-turbine-grc": lambda: gs.example("wind-turbine-grc"),
         "two-stages": lambda: loads(TOML),
         "gears-stages-gears": lambda: loads(TOML_CHAINS),
         "damaged-graph": lambda: loads(DAMAGED_GRAPH)}
RUN = {"duration": 0.02, "fs": 5000.0}


def _as_read(gb, back):
    """``back`` with what the graph form names its own way taken from ``gb``: the shafts
    of the members (a file of [stage] names none) and the gear chains' names."""
    chains = {k: dataclasses.replace(getattr(back, k), name=getattr(gb, k).name)
              for k in ("train", "input_train") if getattr(gb, k) is not None}
    return dataclasses.replace(back, member_shafts=gb.member_shafts, **chains)


@pytest.mark.parametrize("case", CASES)
def test_written_gearbox_reads_back_to_itself(case):
    gb = CASES[case]().replace(dynamics=RUN)
    text = gb.to_toml()
    back = loads(text)
    assert _as_read(gb, back) == gb
    assert back.to_toml() == text  # what is read back writes the same text
    a, b = gb.simulate(), back.simulate()
    assert list(a.data_vars) == list(b.data_vars)
    for v in a.data_vars:
        if v != "tacho":
            assert np.array_equal(a[v].values, b[v].values), v
    # a tacho a shaft: of a file that named no shafts, that of the first member (or
    # gear) on it, under that one's name
    for shaft in b["shaft"].values:
        assert np.array_equal(a["tacho"].sel(shaft=shaft), b["tacho"].sel(shaft=shaft))
    assert len(b["shaft"]) == len(a["shaft"]) or not gb.member_shafts
    assert a.attrs["config"] == b.attrs["config"] == text
    for key in ("mesh_frequency", "carrier_frequency", "sun_frequency", "ring_frequency",
                "static_mesh_force", "stage_mesh_frequency", "stage_sun_torque",
                "stage_carrier_torque", "chain_mesh_frequencies", "shaft_stiffness"):
        if key in a.attrs:
            assert np.array_equal(a.attrs[key], b.attrs[key]), key
    assert _as_read(gb, back).tvms().summary == gb.tvms().summary


def test_nrel_stage_read_back_meshes_at_ring_teeth_times_carrier_speed():
    """Ring held, carrier in at 22.1 rpm and 324 kN m: f_m = z_r f_c, the sun carries
    T_c z_s / (z_s + z_r), the crack stays on planet 1 (the example's)."""
    back = loads(gs.example("nrel-grc").to_toml())
    assert back.stage.mesh_frequency == pytest.approx(99 * 22.1 / 60, rel=1e-12)
    assert abs(back.stage.torques["sun"]) == pytest.approx(324e3 * 21 / 120, rel=1e-12)
    (crack,) = back.stage.cracks
    assert (crack.gear, crack.tooth, crack.flank, crack.depth) == ("planet-1", 0, "working",
                                                                  0.004)


def test_stage_result_carries_its_configuration(tmp_path):
    """The run's own settings; a reader of results takes a stage result's kinematics
    from its parts, not from the configuration (that of gears written before them)."""
    ds = loads(TOML_CHAINS).simulate(**RUN, model="torsional")
    assert loads(ds.attrs["config"]).dynamics == dataclasses.replace(
        loads(TOML_CHAINS).dynamics, **RUN, model="torsional")
    meta = read_record(write_results(ds, tmp_path / "r.nc")).metadata
    assert "config" not in meta and "parts" in meta and "teeth" in meta


def test_what_the_graph_form_cannot_say_is_refused_in_one_line():
    gb = gs.example("wind-turbine-grc")
    odd = dataclasses.replace(gb, train=dataclasses.replace(
        gb.train, stiffness=dataclasses.replace(gb.train.stiffness, slices=3)))
    with pytest.raises(InputError, match="one .stiffness."):
        odd.to_toml()
    healthy = dataclasses.replace(gb, stage=dataclasses.replace(gb.stage, contacts=True))
    with pytest.raises(InputError) as err:
        healthy.to_toml()
    assert err.value.parameter == "stage.contacts"
    assert "config" not in healthy.simulate(**RUN).attrs  # a run of it: no config
