"""One record of a run without the dataset (``simulate_record``, ``Gearbox.record``).

A parameter study analyses one record per run; ``Gearbox.record`` forms it from the
channels it needs only. The reference is independent of that code path: the record
selected from the whole result of ``Gearbox.simulate`` (its records formed around the
decimation, the dataset built). The FIR acts on each channel alone and is linear, so the
two differ only by where the channels are combined, before the filter (``simulate``) or
after it (``simulate_record``, the order studies had before, kept so that their
results did not change: tests/studies/test_results_identical_to_before.py): to
round-off, ``ORDER_RTOL``. A record formed alike in both (a mesh force) must be equal.
Any larger difference would mean the fast path integrates, filters or combines
something else (a wrong channel or coefficient moves a record by 1e-6 of its peak or
more).
"""

from __future__ import annotations

import numpy as np
import pytest

import gearsim as gs
from gearsim.dynamics.simulate import simulate_record
from gearsim.errors import InputError
from gearsim.model.variants import fault_variant

#: Records combined from the same filtered channels before or after the filter: sums of
#: two to five terms whose magnitudes exceed the record's (an acceleration is a difference
#: of forces) round differently; measured 1.1e-13 of the record's largest value at most
#: (the reducer's axial bearing force).
ORDER_RTOL = 1e-12


def _box(name: str, **dyn) -> gs.Gearbox:
    return gs.example(name).replace(dynamics={"duration": 0.11, "fs": 20e3, **dyn})


CASES = {
    "table1-lta": lambda: _box("idler-table1"),
    "table1-seed3dof": lambda: _box("idler-table1", model="seed"),
    "spur-torsional": lambda: _box("spur-19-48", model="torsional"),
    "reducer-lta": lambda: _box("two-stage-reducer", duration=0.4),
    "spur-run-up": lambda: _box("spur-19-48").replace(
        dynamics={"speed_times": [0.0, 0.2], "speed_values": [180.0, 200.0]}),
    "spur-spall-contacts": lambda: fault_variant(_box("spur-19-48"), "spall", 1.0),
    "spur-oversample-1": lambda: _box("spur-19-48", oversample=1),
}


@pytest.mark.parametrize("case", list(CASES))
def test_every_record_equals_the_one_selected_from_the_whole_result(case):
    gb = CASES[case]()
    ds = gb.simulate()
    names = gb.signals()
    assert any("acceleration[" in n for n in names)
    for spec in names:
        got, want = gb.record(spec), gb.select(ds, spec)
        scale = np.max(np.abs(want))
        # the same operations in both (ste_i: taken from the whole result), or zero
        if spec.startswith(("mesh_force_", "ste_")) or scale == 0.0:
            np.testing.assert_array_equal(got, want, err_msg=spec)
        else:
            np.testing.assert_allclose(got, want, rtol=0.0, atol=ORDER_RTOL * scale,
                                       err_msg=spec)


def test_names_it_does_not_derive_go_through_the_whole_result():
    gb = _box("spur-19-48")
    train, settings = gb.train, gb.dynamics
    # ste_i (an input, not a response), an unknown shaft or axis, a mesh that is not there
    for spec in ("ste_1", "acceleration[nowhere,y]", "acceleration[pinion,w]", "dte_9",
                 "mesh_force_0", "shaft_angle"):
        assert simulate_record(train, spec, settings) is None, spec
    ds = gb.simulate()
    np.testing.assert_array_equal(gb.record("ste_1"), gb.select(ds, "ste_1"))
    with pytest.raises(InputError, match="study.signal"):
        gb.record("acceleration[nowhere,y]")


def test_a_stage_record_is_the_selected_one():
    gb = gs.example("nrel-grc").replace(dynamics={"duration": 0.6, "fs": 20e3})
    ds = gb.simulate()
    np.testing.assert_array_equal(gb.record("sensor"), gb.select(ds, "sensor"))


def test_refusals_before_the_run_are_the_same():
    gb = _box("idler-table1", duration=0.01)  # shorter than a revolution of the output
    for run in (gb.simulate, lambda: gb.record("acceleration[input,y]")):
        with pytest.raises(InputError, match="dynamics.duration"):
            run()


def test_torsional_model_lists_only_records_it_has():
    """The torsional model has no bearing coordinates: no bearing records are offered
    (they were, and a study of it failed in every case), its default is a rotation."""
    gb = _box("spur-19-48", model="torsional")
    names = gb.signals()
    assert not [n for n in names if n.startswith(("bearing_force[", "acceleration["))]
    assert gb.default_signal == "angular_acceleration[pinion]"
    ds = gb.simulate()
    assert list(ds["rotation"].values) == ["pinion", "gear"]
    assert np.std(gb.record(gb.default_signal)) > 0.0
    lta = _box("spur-19-48")
    assert "acceleration[pinion,z]" in lta.signals()
    assert lta.default_signal == "acceleration[pinion,y]"
