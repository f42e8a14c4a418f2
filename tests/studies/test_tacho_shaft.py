"""A gearsim result's tacho must be that of the shaft the record is analysed at.

Every shaft of a result has a tacho. The analysis takes the tacho's speed as the
speed of the record's reference shaft (a gear train's input; the first shaft of the gears
beside a stage; a stage's carrier), whose teeth and stages the file gives. Another
shaft's tacho put every mesh frequency at the wrong speed without a word: the two-stage
reducer's input record with the intermediate shaft's tacho had stage 1 at 384 Hz, not
960 Hz. It is refused in one line naming the tacho to give.
"""

from __future__ import annotations

import math

import pytest
import xarray as xr

import gearsim as gs
from gearsim.io.results import write_results
from gearsim.studies.batch import _read_channels, analyze_file


@pytest.fixture(scope="module")
def reducer(tmp_path_factory):
    path = tmp_path_factory.mktemp("tacho") / "reducer.nc"
    write_results(gs.example("two-stage-reducer").replace(
        dynamics={"duration": 0.6, "fs": 10e3}).simulate(), path)
    return str(path)


@pytest.fixture(scope="module")
def turbine(tmp_path_factory):
    path = tmp_path_factory.mktemp("tacho") / "turbine.nc"
    write_results(gs.example("wind-turbine-grc").replace(
        dynamics={"duration": 3.0}).simulate(), path)
    return str(path)


@pytest.fixture(scope="module")
def stage(tmp_path_factory):
    path = tmp_path_factory.mktemp("tacho") / "stage.nc"
    write_results(gs.example("nrel-grc").replace(dynamics={"duration": 3.0}).simulate(), path)
    return str(path)


def test_the_reference_shafts_tacho_gives_the_mesh_frequency(reducer):
    (row,), problems = analyze_file(reducer, channels=["acceleration[input,y]"],
                                    tacho="tacho[input]")
    assert not problems
    # 32 teeth at 30 Hz, the reducer's input speed measured from its own pulses
    assert row["record"]["speed_hz"] == pytest.approx(30.0, rel=1e-3)
    assert row["features"]["mesh_frequency_hz"][0] == pytest.approx(960.0, rel=1e-3)


@pytest.mark.parametrize(("channel", "tacho", "ref"), [
    ("acceleration[input,y]", "tacho[intermediate]", "tacho[input]"),
    ("acceleration[output,x]", "tacho[shaft=output]", "tacho[input]"),
])
def test_another_shafts_tacho_is_refused(reducer, channel, tacho, ref):
    rows, problems = analyze_file(reducer, channels=[channel], tacho=tacho)
    assert rows == [] and len(problems) == 1
    assert f"--tacho = {tacho}:" in problems[0] or f"tacho = {tacho}:" in problems[0]
    assert f"give --tacho '{ref}'" in problems[0]


@pytest.mark.parametrize(("channel", "tacho", "ok"), [
    ("chain_acceleration[high-speed,y]", "tacho[low-speed]", True),
    ("chain_acceleration[high-speed,y]", "tacho[high-speed]", False),
    ("sensor", "tacho[rotor]", True),
    ("sensor", "tacho[intermediate]", False),
])
def test_a_stage_box_takes_the_tacho_of_the_records_part(turbine, channel, tacho, ok):
    rows, problems = analyze_file(turbine, channels=[channel], tacho=tacho)
    assert (len(rows), len(problems)) == ((1, 0) if ok else (0, 1)), problems


@pytest.mark.parametrize(("tacho", "ok"), [("tacho[carrier]", True), ("tacho[sun]", False)])
def test_a_stage_record_takes_the_carriers_tacho(stage, tacho, ok):
    rows, problems = analyze_file(stage, channels=["sensor"], tacho=tacho)
    assert (len(rows), len(problems)) == ((1, 0) if ok else (0, 1)), problems
    if not ok:
        assert "give --tacho 'tacho[carrier]'" in problems[0]



@pytest.fixture(scope="module")
def run_up(tmp_path_factory):
    path = tmp_path_factory.mktemp("tacho") / "run_up.nc"
    gb = gs.example("two-stage-reducer")
    speed, _ = gb.operating()
    write_results(gb.replace(dynamics={"duration": 1.0, "fs": 10e3, "speed_times": [0.0, 1.5],
                                       "speed_values": [0.5 * speed, 1.5 * speed]}
                             ).simulate(), path)
    return str(path)


def test_a_run_up_is_analysed_with_its_own_tacho(run_up):
    # no --tacho: the file's nominal 30 Hz would smear every line of a 15 -> 40 Hz run;
    # its input shaft's tacho is used, as if given
    (auto,), problems = analyze_file(run_up, channels=["acceleration[input,y]"])
    (given,), _ = analyze_file(run_up, channels=["acceleration[input,y]"],
                               tacho="tacho[input]")
    assert not problems
    assert auto["record"]["source"]["tacho"] == "tacho[shaft=input]"
    assert auto["record"]["speed_hz"] == given["record"]["speed_hz"]
    with xr.open_dataset(run_up) as ds:  # 15 Hz at t = 0, + 20 Hz/s: the record's mean
        mean_speed = 15.0 + 20.0 * float(ds["time"].mean())
    # (the pulses' mean rate, first to last pulse: within 3 %)
    assert auto["record"]["speed_hz"] == pytest.approx(mean_speed, rel=0.03)
    assert auto["features"] == given["features"]


def test_a_run_up_with_a_given_speed_or_a_gearbox(run_up):
    """A speed the user gives is used, not the run-up's own tacho (before: refused as two
    speed sources, although one was given); a gearbox's nominal speed (``--config``)
    gives way to the own tacho, its stages still used."""
    (given,), problems = analyze_file(run_up, channels=["acceleration[input,y]"],
                                      speed=30.0)
    assert not problems and "tacho" not in given["record"]["source"]
    assert given["record"]["speed_hz"] == 30.0
    (auto,), _ = analyze_file(run_up, channels=["acceleration[input,y]"])
    (conf,), problems = analyze_file(
        run_up, channels=["acceleration[input,y]"], speed=30.0, stages=((32, 80), (48, 64)),
        provenance={"speed": "config", "teeth": "config"})
    assert not problems
    assert conf["record"]["source"]["tacho"] == "tacho[shaft=input]"
    assert conf["record"]["speed_hz"] == auto["record"]["speed_hz"]
    assert conf["features"]["mesh_frequency_hz"] == auto["features"]["mesh_frequency_hz"]


def test_a_constant_speed_result_keeps_the_files_speed(reducer):
    (row,), _ = analyze_file(reducer, channels=["acceleration[input,y]"])
    assert "tacho" not in row["record"]["source"]
    assert row["record"]["speed_hz"] == pytest.approx(30.0, rel=1e-12)


@pytest.fixture(scope="module")
def slow_run_up(tmp_path_factory):
    """The NREL GRC stage (carrier = input, 22.1 rpm) run up from 11.05 to 22.1 rpm over
    6 s; its 3 s record (after the transient) holds one carrier pulse."""
    path = tmp_path_factory.mktemp("tacho") / "slow_run_up.nc"
    gb = gs.example("nrel-grc")
    speed, _ = gb.operating()
    write_results(gb.replace(dynamics={"duration": 3.0, "speed_times": [0.0, 6.0],
                                       "speed_values": [0.5 * speed, speed]}).simulate(),
                  path)
    return str(path)


def test_a_slow_members_run_up_is_not_analysed_at_the_nominal_speed(slow_run_up):
    """The carrier's tacho cannot follow the speed (one pulse in the record): the
    record is not analysed at the nominal 22.1 rpm (before: speed 0.3683 Hz, "file",
    and a planetary tier at that constant speed, without a word); the shaft, gear and
    planetary tiers are skipped, saying how the speed changes."""
    (row,), problems = analyze_file(slow_run_up, channels=["sensor"])
    assert not problems
    rec = row["record"]
    assert rec["speed_hz"] is None and "planetary" not in rec["tiers"]
    with xr.open_dataset(slow_run_up) as ds:  # 22.1 rpm x (0.5 + t / 12 s), linear
        t0, t1 = float(ds["time"][0]), float(ds["time"][-1])
    why = {s["tier"]: s["reason"] for s in rec["skipped"]}
    said = (f"the run's input speed goes from {22.1 * (0.5 + t0 / 12):.5g} to "
            f"{22.1 * (0.5 + t1 / 12):.5g} rpm over the record")
    assert why["shaft"].startswith(said) and "nominal 22.1 rpm is not used" in why["shaft"]
    assert said in why["planetary"] and "gear" in why
    # a speed given is used, the planetary tier's carrier too
    (given,), _ = analyze_file(slow_run_up, channels=["sensor"], speed=0.3)
    assert given["record"]["speed_hz"] == 0.3
    assert given["record"]["tiers"]["planetary"]["frequencies"]["carrier"] == 0.3


def test_a_steady_speed_off_the_operating_one_is_read_from_the_tacho(tmp_path):
    """A speed table that holds 1.2 times the operating speed (36 Hz, not the reducer's
    30 Hz) over the whole record: the file's speeds are at the operating point, so the
    record is read with its own tacho (36 Hz within 1 %); before, at 30 Hz without a
    word (every line of the analysis 20 % off)."""
    path = tmp_path / "steady.nc"
    w = 2 * math.pi * 36.0
    write_results(gs.example("two-stage-reducer").replace(
        dynamics={"duration": 0.6, "fs": 10e3, "speed_times": [0.0, 1e-3],
                  "speed_values": [w, w]}).simulate(), path)
    (row,), problems = analyze_file(str(path), channels=["acceleration[input,y]"])
    assert not problems
    assert row["record"]["source"]["tacho"] == "tacho[shaft=input]"
    assert row["record"]["speed_hz"] == pytest.approx(36.0, rel=0.01)



def test_default_channels_of_a_result_are_its_vibration_records(turbine):
    """No channel named: the tachos (pulse trains, 0/5 V) and carrier_angle (rad) were
    analysed as vibration (tacho[shaft=rotor]: kurtosis 1107); now one channel per time
    series of every variable of the file but those two, the q[dof=...] displacements kept;
    a named one is still read."""
    with xr.open_dataset(turbine) as ds:
        assert ds["carrier_angle"].attrs.get("units") == "rad"
        expected = sum(ds[v].size // ds.sizes["time"] for v in ds.data_vars
                       if "time" in ds[v].dims and v not in ("tacho", "carrier_angle"))
        n_q = ds["q"].size // ds.sizes["time"]
    names = [c["channel"] for c in _read_channels(turbine, None, None, None, False, None)]
    assert len(names) == expected
    assert not any(n.startswith("tacho") or n == "carrier_angle" for n in names)
    assert sum(n.startswith("q[dof=") for n in names) == n_q
    assert {"sensor", "shaft_torque"} <= set(names)
    (row,) = _read_channels(turbine, ["carrier_angle"], None, None, False, None)
    assert row["channel"] == "carrier_angle"


def test_short_stage_record_skips_in_plain_words(turbine):
    """The 3 s turbine record is too short to check the carrier speed (8 revolutions) and
    holds one passage of the carrier at angle 0 (separation needs two): the reasons were
    'x.length = 18000 samples (3 s)' and 'carrier_pulses = shape (1,)'."""
    (row,), problems = analyze_file(turbine, channels=["sensor"])
    assert not problems
    reasons = {s["tier"]: s["reason"] for s in row["record"]["skipped"]}
    with xr.open_dataset(turbine) as ds:
        fc = float(ds.attrs["carrier_frequency"])  # 22.1 rpm / 60
        angle = ds["carrier_angle"].values
    marks = math.floor(angle[-1] / (2 * math.pi)) - math.ceil(angle[0] / (2 * math.pi)) + 1
    assert marks == 1
    assert reasons["shaft.speed_check"] == (
        f"the file's speed is not checked against the record: the check needs 8 shaft "
        f"revolutions, {8 / fc:.4g} s at {fc:.4g} Hz, and the record lasts 3 s: a longer "
        "record would allow it")
    assert f"({1 / fc:.4g} s apart at {fc:.4g} Hz); the record of 3 s holds 1 passage:" in \
        reasons["planetary.separation"]
    assert not any(w in r for r in reasons.values() for w in ("x.length", "carrier_pulses"))
