"""A fault class on a named gear of any stage (issue 23: faults anywhere).

The two-stage reducer (32/80 then 48/64): the intermediate pinion (48 teeth) drives mesh
II only, so its fault must change mesh II's stiffness where its tooth 0 meshes and leave
mesh I bit for bit as the healthy one; the sizes follow the named gear's own module.
"""

from __future__ import annotations

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import InputError
from gearsim.model.variants import fault_variant
from gearsim.stiffness.settings import MODELS

GEAR = "intermediate-pinion"


@pytest.fixture(scope="module")
def box():
    return gs.example("two-stage-reducer").replace(stiffness=MODELS["seed"])  # PE speed


def test_crack_on_the_named_gear_is_sized_by_its_module(box):
    v = fault_variant(box, "working", 0.5, gear=GEAR)
    (c,) = v.train.cracks
    m = box.train.gear(GEAR).normal_module
    assert (c.gear, c.tooth, c.flank) == (GEAR, 0, "working")
    assert c.depth == pytest.approx(0.5 * 2e-3 * m / 6e-3, rel=1e-15)


def test_fault_on_the_named_gear_reaches_its_mesh_only(box):
    healthy = box.healthy().train
    v = fault_variant(box, "working", 1.0, gear=GEAR).train
    k1h, k1 = healthy.mesh_stiffness(0).k, v.mesh_stiffness(0).k
    np.testing.assert_array_equal(k1, k1h)  # mesh I does not hold the pinion
    k2h, k2 = healthy.mesh_stiffness(1).k, v.mesh_stiffness(1).k
    assert k2.size == k2h.size
    assert np.min(k2 / k2h) < 0.99  # the cracked tooth softens mesh II
    # over one revolution of the pinion (48 mesh cycles) the crack acts on one tooth's
    # passes: most positions stay healthy
    assert np.mean(np.isclose(k2, k2h, rtol=1e-12, atol=0.0)) > 0.9


def test_runout_on_the_named_gear(box):
    v = fault_variant(box, "eccentricity", 1.0, gear=GEAR)
    names = [g.name for g in box.train.gears]
    ro = np.asarray(v.dynamics.runout)
    assert ro[names.index(GEAR)] > 0 and np.count_nonzero(ro) == 1


def test_unknown_gear_is_refused_naming_it(box):
    with pytest.raises(InputError) as e:
        fault_variant(box, "spall", 0.5, gear="idler2")
    assert e.value.parameter == "gear" and "intermediate-pinion" in str(e.value)
