"""A result's records by the names of ``Gearbox.signals()`` as well as by their keys.

``gearsim analyze RESULT.nc --channel C`` names a record of a multi-dimensional variable
``acceleration[shaft=input,axis=y]``; ``Gearbox.signals()`` and a study's ``signal``
name it ``acceleration[input,y]``. Both are read, and both are analysed with the same
part of the gearbox (a stage box's gear records with the gears' shafts and stages, its
stage records with the carrier).
"""

from __future__ import annotations

import pytest
from test_batch_stages import _without_timings

import gearsim as gs
from gearsim.io.results import write_results
from gearsim.studies.batch import analyze_file


@pytest.mark.parametrize(("name", "dyn", "short", "keyed"), [
    ("two-stage-reducer", {"duration": 0.4, "fs": 10e3},
     "acceleration[intermediate,y]", "acceleration[shaft=intermediate,axis=y]"),
    ("wind-turbine-grc", {"duration": 1.0},
     "chain_acceleration[intermediate,y]",
     "chain_acceleration[chain_shaft=intermediate,chain_axis=y]"),
    ("wind-turbine-grc", {"duration": 1.0},
     "mesh_force[sun-planet-1]", "mesh_force[mesh=sun-planet-1]"),
])
def test_a_record_by_its_labels_is_the_keyed_record(tmp_path, name, dyn, short, keyed):
    gb = gs.example(name).replace(dynamics=dyn)
    assert short in gb.signals()
    path = tmp_path / "r.nc"
    write_results(gb.simulate(), path)
    (a,), _ = analyze_file(str(path), channels=[short])
    (b,), _ = analyze_file(str(path), channels=[keyed])
    assert a["record"]["source"]["channel"] == short
    assert b["record"]["source"]["channel"] == keyed
    a["record"]["source"] = b["record"]["source"] = None
    # the same samples, speed, teeth or stage, and features
    assert _without_timings(a) == _without_timings(b)
