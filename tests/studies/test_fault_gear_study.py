"""A study varies where the fault sits (issue 23: sweep parameters address elements by
name): ``gear`` names the faulty gear of each fault class, here on the two-stage reducer
(32/80, then 48/64)."""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.model import example_text
from gearsim.studies.sweep import expand, loads_study
from gearsim.studies.sweep_case import build_case, run_group
from gearsim.studies.sweep_run import groups

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

STUDY = """
[study]
name = "where is the spall"
config = "box.toml"
signal = "acceleration[intermediate,y]"
[study.dynamics]
duration = "0.6 s"
[parameters]
fault = ["none", "spall", "working"]
gear = ["input-pinion", "intermediate-pinion"]
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("box")
    (d / "box.toml").write_text(example_text("two-stage-reducer"))
    return d


@pytest.fixture(scope="module")
def study(folder):
    return loads_study(STUDY, base_dir=folder)


def test_cases_place_each_fault_on_its_gear(study):
    cases = expand(study)
    assert [(c.fault, c.gear) for c in cases] == [
        ("none", "input-pinion"), ("none", "intermediate-pinion"),
        ("spall", "input-pinion"), ("spall", "intermediate-pinion"),
        ("working", "input-pinion"), ("working", "intermediate-pinion")]
    assert len(groups(study)) == 5  # the healthy cases share one simulation
    for c in cases[2:]:
        gb = build_case(study, c)
        where = [f.gear for f in gb.train.faults] + [k.gear for k in gb.train.cracks]
        assert where == [c.gear], (c, where)
    assert build_case(study, cases[0]).train.faults == ()


def test_a_study_without_gear_keeps_its_case_keys(folder):
    st = loads_study(STUDY.replace('gear = ["input-pinion", "intermediate-pinion"]\n', ""),
                     base_dir=folder)
    assert all("gear" not in c.params() for c in expand(st))


def test_store_rows_hold_the_gear(study):
    cases = [c for c in expand(study) if c.fault == "spall"]
    ds = run_group(study, cases[:1], None)
    ds2 = run_group(study, cases[1:], None)
    assert list(ds["status"].values) == ["ok"] and list(ds2["status"].values) == ["ok"]
    assert ds["gear"].values.tolist() == ["input-pinion"]
    assert ds2["gear"].values.tolist() == ["intermediate-pinion"]
    # the same spall on another gear is another record
    assert not np.isclose(float(ds["td_rms"][0]), float(ds2["td_rms"][0]), rtol=1e-9)


@pytest.mark.parametrize(("edit", "where"), [
    (('gear = ["input-pinion", "intermediate-pinion"]',
      'gear = ["input-pinion", "idler"]'), "parameters.gear[1]"),
    (('fault = ["none", "spall", "working"]', 'flank = ["working"]'), "parameters.gear"),
    (('gear = ["input-pinion", "intermediate-pinion"]', 'gear = { min = 1, max = 2 }'),
     "parameters.gear"),
    (('gear = ["input-pinion", "intermediate-pinion"]', 'gear = ["input-pinion", ""]'),
     "parameters.gear[1]"),
    (('gear = ["input-pinion", "intermediate-pinion"]', 'gear = [1e300]'),
     "parameters.gear[0]"),
])
def test_bad_gear_is_refused_naming_it(folder, edit, where):
    from gearsim.studies.sweep import check_study

    with pytest.raises(InputError) as e:
        check_study(loads_study(STUDY.replace(*edit), base_dir=folder))
    assert e.value.parameter == where, str(e.value)


STAGE_STUDY = """
[study]
name = "where is the spall, beside a planetary stage"
config = "wind-turbine-grc"
signal = "chain_acceleration[intermediate,y]"
shafts = "reference"
[study.dynamics]
duration = "2.8 s"
[parameters]
fault = ["none", "spall", "working"]
gear = ["intermediate-pinion", "high-speed-pinion"]
"""


def test_a_stage_gearbox_takes_the_classes_on_its_parallel_gears():
    """wind-turbine-grc: each class sits on the named gear of the parallel stages, the
    planetary stage keeps no crack or fault; a gear the gearbox does not have or the
    eccentricity class is refused in one line naming the study's parameter (a stage
    member is a gear too: tests/planetary/test_member_fault_classes.py)."""
    study = loads_study(STAGE_STUDY)
    cases = expand(study)
    for c in cases:
        gb = build_case(study, c)
        where = [f.gear for f in gb.train.faults] + [k.gear for k in gb.train.cracks]
        assert where == ([] if c.fault == "none" else [c.gear]), (c, where)
        assert gb.stage.cracks == () and gb.stage.faults == ()
    with pytest.raises(InputError) as err:
        loads_study(STAGE_STUDY.replace('"high-speed-pinion"]', '"planet-4"]'))
    assert err.value.parameter == "parameters.gear[1]"
    assert "sun, ring, planet-1, planet-2, planet-3" in str(err.value)
    with pytest.raises(InputError) as err:
        loads_study(STAGE_STUDY.replace('"working"]', '"eccentricity"]'))
    assert "not among its fault classes" in str(err.value)
    ds = run_group(study, [c for c in cases if c.fault == "spall"][:1], None)
    assert list(ds["status"].values) == ["ok"]
