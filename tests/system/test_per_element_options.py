"""Dynamics options written on the element they belong to: a ``[[meshes]]`` table's own
backlash, profile modification, crowning and assembly error, a ``[[gears]]`` table's own
runout (issue 23: each mesh with its own backlash and transmission error).

Independent numbers: the AGMA 2002 minimum backlash of the reducer's spur mesh I by hand,
(2/3)(0.06 + 0.0005 a + 0.03 m_n) mm with a = 84 mm and m_n = 1.5 mm, = 0.098 mm, for the
mesh that gives none; and the same run from the same values written as ``[dynamics]``
lists in power-flow order.
"""

from __future__ import annotations

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import InputError
from gearsim.model.config import example_text

REDUCER = example_text("two-stage-reducer")
MESH_II = 'gears = ["intermediate-pinion", "output-gear"]\nangle = "180 deg"\n'


def _with(text: str, mesh_ii: str = "", dynamics: str = "", gear: str = "") -> str:
    text = text.replace(MESH_II, MESH_II + mesh_ii)
    text = text.replace('name = "output-gear"\nshaft = "output"\nteeth = 64\n',
                        'name = "output-gear"\nshaft = "output"\nteeth = 64\n' + gear)
    return text.replace('[dynamics]\n', "[dynamics]\n" + dynamics)


def test_a_mesh_gives_its_own_and_the_other_takes_its_agma_minimum():
    gb = gs.loads(_with(REDUCER, 'backlash = "0.2 mm"\nassembly_error = "3 um"\n'))
    agma_i = 2 / 3 * (0.06 + 0.0005 * 84 + 0.03 * 1.5) * 1e-3  # spur: cos(beta_b) = 1
    assert gb.dynamics.backlash == pytest.approx((agma_i, 2e-4), rel=1e-12)
    assert gb.dynamics.assembly_error == (0.0, 3e-6)


def test_written_per_element_or_as_lists_the_run_is_the_same():
    per_element = gs.loads(_with(REDUCER, 'backlash = "0.2 mm"\ncrowning = "4 um"\n',
                                 gear='runout = "10 um"\nrunout_phase = "30 deg"\n'))
    agma_i = per_element.dynamics.backlash[0]
    as_lists = gs.loads(_with(REDUCER, dynamics=(
        f'backlash = [{agma_i!r}, "0.2 mm"]\ncrowning = [0.0, "4 um"]\n'
        'runout = [0.0, 0.0, 0.0, "10 um"]\nrunout_phase = [0.0, 0.0, 0.0, "30 deg"]\n')))
    assert per_element.dynamics == as_lists.dynamics
    kw = {"duration": 0.12, "transient": 0.01}
    a, b = (g.record("mesh_force_2", **kw) for g in (per_element, as_lists))
    np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(("mesh_ii", "dynamics", "gear", "parameter", "words"), [
    ('backlash = "2 cm"\n', "", "", "meshes[1].backlash", "<= 0.01 m"),
    ('backlash = "0.2 mm"\n', 'backlash = "0.1 mm"\n', "", "meshes[1].backlash",
     "is also given in [dynamics]"),
    ('assembly_error = "-20 mm"\n', "", "", "meshes[1].assembly_error", "|e| <= 0.01 m"),
    ("", "", 'runout = "-1 um"\n', "gears[3].runout", ">= 0 m"),
    ('backlash = "0.2 kg"\n', "", "", "meshes[1].backlash", "length"),
    ("backlash = inf\n", "", "", "meshes[1].backlash", "finite"),
    ("crowning = nan\n", "", "", "meshes[1].crowning", "finite"),
    ("profile_modification = 1e300\n", "", "", "meshes[1].profile_modification",
     "<= 0.01 m"),
    ("backlash = -1e-300\n", "", "", "meshes[1].backlash", ">= 0 m"),
    ("", "", 'runout_phase = "inf deg"\n', "gears[3].runout_phase", "finite"),
])
def test_bad_element_values_are_named_where_written(mesh_ii, dynamics, gear, parameter,
                                                    words):
    with pytest.raises(InputError) as e:
        gs.loads(_with(REDUCER, mesh_ii, dynamics, gear))
    assert e.value.parameter == parameter and words in str(e.value), str(e.value)


def test_beside_a_stage_they_are_refused():
    text = example_text("wind-turbine-grc").replace(
        'gears = ["intermediate-gear", "high-speed-pinion"]\n',
        'gears = ["intermediate-gear", "high-speed-pinion"]\nbacklash = "0.3 mm"\n')
    with pytest.raises(InputError) as e:
        gs.loads(text)
    assert e.value.parameter == "meshes[1].backlash"
    assert "parallel shafts only" in str(e.value)


def test_a_runout_in_the_common_table_beside_a_stage_is_refused():
    text = example_text("wind-turbine-grc").replace(
        '[common]                    # the parallel stages\' gears\n',
        '[common]                    # the parallel stages\' gears\nrunout = "5 um"\n')
    assert 'runout = "5 um"' in text
    with pytest.raises(InputError) as e:
        gs.loads(text)
    assert e.value.parameter.endswith("common.runout") and "parallel shafts only" in str(e.value)
