"""Refusals found while documenting the API (each once returned nonsense or a raw error)."""

from __future__ import annotations

import math

import pytest

import gearsim as gs
from gearsim.dynamics import build_model
from gearsim.dynamics.model import mean_stiffness_matrix
from gearsim.errors import InputError
from gearsim.signals.sidebands import sideband_energy_ratio
from gearsim.system import train_to_toml


@pytest.mark.parametrize("amps", [[math.nan, 0.1], [-1.0, 0.1], [math.inf]])
def test_ser_refuses_non_physical_sideband_amplitudes(amps):
    with pytest.raises(InputError, match="sideband_amplitudes"):
        sideband_energy_ratio(1.0, amps)


def test_ser_refuses_a_non_finite_mesh_amplitude():
    with pytest.raises(InputError, match="mesh_amplitude"):
        sideband_energy_ratio(math.inf, [0.1])


def test_stiffness_matrix_refuses_an_unknown_choice():
    """Any value other than "mean" used to mean "max" without a word."""
    model = build_model(gs.example("spur-19-48").train)
    assert mean_stiffness_matrix(model, which="max").shape == \
        mean_stiffness_matrix(model).shape
    with pytest.raises(InputError, match="which"):
        mean_stiffness_matrix(model, which="min")


def test_effective_configuration_states_the_speed_unit():
    """The stored configuration reads back without the declared-SI header: the speed
    carries its unit (a bare speed is refused on reading) and round-trips exactly."""
    train = gs.example("idler-table1").train
    body = "\n".join(line for line in train_to_toml(train).splitlines()
                     if not line.startswith("#"))
    assert 'speed = "' in body and 'rad/s"' in body
    assert gs.loads(body).train.operating.speed == train.operating.speed


@pytest.mark.parametrize("depth", [1e-9, 1e-300, 5e-7, -1e-3, math.inf, math.nan])
def test_crack_depth_is_zero_or_at_least_a_micrometre(depth):
    """A crack depth below 1 um (a tenth of the finest grain of case-hardened gear
    steel) can only be a unit mistake; 0 is no crack and 1 um the smallest crack."""
    from gearsim.stiffness.crack import Crack

    with pytest.raises(InputError) as err:
        Crack(gear="input", depth=depth)
    assert err.value.parameter == "crack.depth" and "\n" not in str(err.value)
    assert Crack(gear="input", depth=0.0).depth == 0.0
    assert Crack(gear="input", depth=1e-6).depth == 1e-6


def test_cli_refuses_a_nanometre_crack_before_any_work(tmp_path, capsys):
    from gearsim import cli

    out = tmp_path / "rep"
    code = cli.run(["reproduce", "--depth", "1e-6 mm", "--no-fe", "--out", str(out),
                    "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "1e-06 m" in err[0] and "--depth" in err[0]
    assert not out.exists()


@pytest.mark.parametrize("kw,parameter", [
    ({"teeth": [32, 1_000_000]}, "teeth[1]"),
    ({"teeth": [0]}, "teeth[0]"),
    ({"stages": [(32, 80), (48, 100_000)]}, "stages[1][1]"),
])
def test_analysis_refuses_tooth_counts_no_gear_has(kw, parameter):
    """A million teeth (a speed or a ratio typed where teeth go) used to be analysed:
    mesh lines far above any record's band, every tier empty, no word."""
    from gearsim.signals._checks import MAX_TEETH
    from gearsim.signals.analysis import kinematics

    with pytest.raises(InputError, match=parameter.replace("[", r"\[")) as err:
        kinematics(shaft_frequency=30.0, **kw)
    assert f"[1, {MAX_TEETH}]" in err.value.limit



def _reducer(old: str, new: str) -> str:
    from gearsim.model import example_text

    text = example_text("two-stage-reducer")
    assert old in text
    return text.replace(old, new)


PINION = 'name = "intermediate-pinion"\nshaft = "intermediate"\nteeth = 48'
OUTPUT = 'name = "output-gear"\nshaft = "output"\nteeth = 64'


@pytest.mark.parametrize("text,line", [
    # the gear's own range, not the mesh's equality with a sign-flipped module
    (_reducer(PINION, PINION + '\nnormal_module = "-1.5 mm"'),
     "gears[2].normal_module = -1.5 mm: must be >= 1e-05 m"),
    # two gears of one shaft: that, whatever their modules
    (_reducer(PINION, PINION + '\nnormal_module = "2 mm"').replace(
        'gears = ["intermediate-pinion", "output-gear"]',
        'gears = ["intermediate-gear", "intermediate-pinion"]'),
     "meshes[1].gears = ['intermediate-gear', 'intermediate-pinion']: both sit on shaft "
     "'intermediate'"),
    (_reducer('name = "output"', 'name = "intermediate"').replace(
        'shaft = "output"', 'shaft = "intermediate"'),
     "shafts[2].name = intermediate: is also shafts[1].name: names must be unique"),
    (_reducer('"output-gear"', '"intermediate-pinion"').replace(
        'gears = ["intermediate-pinion", "output-gear"]',
        'gears = ["intermediate-pinion", "intermediate-pinion"]'),
     "gears[3].name = intermediate-pinion: is also gears[2].name: names must be unique"),
])
def test_graph_refusals_name_what_is_wrong(text, line, tmp_path, capsys):
    """probe-a #10: each was refused in one line naming something else (the mesh's module
    equality, a gear on two shafts, a mesh of unknown gears)."""
    from gearsim import cli

    path = tmp_path / "box.toml"
    path.write_text(text)
    assert cli.run(["layout", str(path)]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"gearsim: error: {line}"]


def test_interference_names_the_shift_as_written():
    """A shift of 1.9 on the 64-tooth gear raises its form circle above the reach of the
    48-tooth pinion's tip, 1.5 mm x 48 / 2 + 1.5 mm = 37.5 mm (before: "II:
    intermediate-pinion.tip_radius = 0.0375: interferes ...", a float in metres naming a
    key no file has)."""
    with pytest.raises(InputError) as err:
        gs.loads(_reducer(OUTPUT, OUTPUT + "\nprofile_shift = 1.9"))
    assert str(err.value).startswith(
        "gears[3].profile_shift = 1.9: in mesh II the tip of intermediate-pinion (radius "
        "37.5 mm) interferes with the fillet of output-gear: contact would reach radius ")
    assert "below its form radius" in str(err.value) and "\n" not in str(err.value)


def test_model_range_warning_points_at_the_callers_line():
    """The Sainsot range warning of a 21-tooth 10 deg helical pinion (theta_f 0.14 rad)
    is shown at the line that asked for the stiffness, not inside functools."""
    import warnings

    text = _reducer("teeth = 32", 'teeth = 21\nface_width = "13.7 mm"').replace(
        "teeth = 80", 'teeth = 80\nface_width = "13.7 mm"')
    train = gs.loads(text).train
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        train.mesh_stiffness(0)
    ours = [w for w in caught if issubclass(w.category, gs.errors.ModelRangeWarning)]
    assert ours and all(w.filename == __file__ for w in ours), [
        (w.filename, w.lineno) for w in caught]


def test_an_integer_written_as_a_string_keeps_its_quotes():
    """``teeth = "32"`` was refused as ``teeth = 32: must be an integer``, which reads as
    a contradiction; the value is shown as written, with the reason."""
    from gearsim.model import example_text

    text = example_text("two-stage-reducer").replace("teeth = 32\n", 'teeth = "32"\n', 1)
    with pytest.raises(InputError) as exc:
        gs.loads(text)
    assert str(exc.value) == ("gears[0].teeth = '32': must be an integer (written as a "
                              "string: leave out the quotes)")


def test_written_name_renames_whole_names_only():
    # a refusal of the translated form is named as the graph wrote it, by whole names:
    # "fixed" is not the start of "fixed_x", "stages[1]" not of "stages[10]"
    from gearsim.sections import written_name

    back = {"stages[1]": "stages[3]", "stage.": "stages[0].", "fixed": "stages[0].sun"}
    assert [written_name(p, back) for p in ("stages[1].ring_teeth", "stages[10].x",
                                            "stage.ring_teeth", "fixed_x", "fixed")] == [
        "stages[3].ring_teeth", "stages[10].x", "stages[0].ring_teeth", "fixed_x",
        "stages[0].sun"]
