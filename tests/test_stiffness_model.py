"""The stiffness model a configuration gets (issue 25 item 1): the accurate model unless
the file says otherwise, the seed's method by name, and the combinations refused.

The accuracy of the accurate model against the FE gear pair is
tests/stiffness/test_calibrated.py's; here: which options a file stands for."""

from __future__ import annotations

import pytest

from gearsim.errors import InputError
from gearsim.model import example, example_text, loads
from gearsim.stiffness.settings import MODELS, StiffnessSettings

PAIR = """
[common]
normal_module = "3 mm"
face_width = "20 mm"
[[gears]]
name = "p"
teeth = 21
[[gears]]
name = "w"
teeth = 40
"""



def _options(st: StiffnessSettings) -> tuple[str, str, str]:
    return st.source, st.contact, st.coupling


ACCURATE = ("calibrated", "line", "fe")
SEED = ("pe", "yang-lin", "none")


def test_named_models_stand_for_their_options():
    assert tuple(MODELS["accurate"].values()) == ACCURATE
    assert tuple(MODELS["seed"].values()) == SEED
    assert _options(StiffnessSettings()) == SEED  # the Python building block


@pytest.mark.parametrize("table, expected", [
    ("", ACCURATE),                                   # no [stiffness]
    ("[stiffness]\nslices = 10\n", ACCURATE),         # other keys only
    ('[stiffness]\nmodel = "accurate"\n', ACCURATE),
    ('[stiffness]\nmodel = "seed"\n', SEED),
    ('[stiffness]\nsource = "pe"\n', SEED),           # names a key: class defaults
    ('[stiffness]\ncontact = "line"\n', ("pe", "line", "none")),
])
def test_a_gear_train_file_gets_the_accurate_model_unless_it_says(table, expected):
    assert _options(loads(PAIR + table).train.stiffness) == expected


def test_examples():
    assert _options(example("spur-19-48").train.stiffness) == ACCURATE
    assert _options(example("two-stage-reducer").train.stiffness) == ACCURATE
    # the paper's train reproduces the paper's method
    assert _options(example("idler-table1").train.stiffness) == SEED
    wt = example("wind-turbine-grc")
    assert _options(wt.train.stiffness) == ACCURATE  # the chain
    assert _options(wt.stage.settings) == ACCURATE   # the stage's meshes (item 5)
    # the paper's stage reproduces the paper's method
    assert _options(example("lin-parker-1999").stage.settings) == SEED


@pytest.mark.parametrize("table, match", [
    ('[stiffness]\nmodel = "best"\n', r'stiffness.model = best: must be "seed" or "accurate"'),
    ('[stiffness]\nmodel = "seed"\ncontact = "line"\n',
     "stiffness.model = seed: names contact itself"),
    ('[stiffness]\nmodel = 3\n', "stiffness.model"),
])
def test_bad_models_are_refused_in_one_line(table, match):
    with pytest.raises(InputError, match=match) as err:
        loads(PAIR + table)
    assert "\n" not in str(err.value)


def test_a_stage_gets_the_accurate_model_unless_it_says():
    """Issue 25 item 5: a stage's meshes take the default too (docs/planetary.md 4.4)."""
    text = example_text("nrel-grc")
    assert "[stiffness]\n" in text and "model" not in text
    assert _options(loads(text).stage.settings) == ACCURATE
    seed = loads(text.replace("[stiffness]\n", '[stiffness]\nmodel = "seed"\n'))
    assert _options(seed.stage.settings) == SEED
    # the FE source has no ring tooth: refused where the stage is made, in one line
    with pytest.raises(InputError, match="stiffness.source") as err:
        loads(text.replace("[stiffness]\n", '[stiffness]\nsource = "fe"\n'))
    assert "\n" not in str(err.value)


def test_cli_refuses_a_bad_model(gearsim_here, tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(PAIR + '[stiffness]\nmodel = "fast"\n')
    res = gearsim_here("stiffness", str(cfg))
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "stiffness.model = fast" in lines[0], res.stderr
