"""Run-to-failure records at several loads and speeds, on Dask (issue 27, item 5).

The life of tests/studies/test_life.py made shorter (Table-1 input gear at four times
its rated torque, 3 increments of 2 mm, 3 contact positions, coarse FE): its crack
states are recorded at two input torques and two input speeds.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import InputError

#: Torque factor of the life (at the rated torque a 2 mm crack does not grow).
TORQUE_FACTOR = 4.0
#: Second load and speed of the records, over the life's (not powers of two: a linear
#: model scaled by 2 is bit-exact in floating point and would hide rounding).
LOAD_FACTOR = 1.5
SPEED_FACTOR = 1.5
FRACTIONS = [0.0, 0.5, 1.0]
SEEDS = 2
#: Relative tolerance of the load scaling of a linear model (rounding only) [-].
LINEAR_TOL = 1e-9
#: Dask against the serial run [-] (the issue's 1e-12; measured bit-identical).
DASK_TOL = 1e-12


@pytest.fixture(scope="module")
def box():
    gb = gs.example("idler-table1")
    speed, torque = gb.operating()
    return gb.at(speed=speed, torque=TORQUE_FACTOR * torque)


@pytest.fixture(scope="module")
def life(box):
    from gearsim.studies.life import gear_life

    return gear_life(box, steps=3, increment=2e-3, positions=3, refinement=0.5)


@pytest.fixture(scope="module")
def records(box, life):
    from gearsim.studies.life import life_records

    speed, torque = box.operating()
    return life_records(box, life, FRACTIONS, SEEDS, loads=[LOAD_FACTOR * torque, torque],
                        speeds=[SPEED_FACTOR * speed, speed])


def _serial_reference(box, life, fractions, seeds):
    """The records of one operating point as the single-point code computed them: one
    simulation per fraction, each seed's noise and analysis, NA4 with the history of
    that seed's records (written out here from the library's parts, independently of
    ``life_records``)."""
    from gearsim.signals import analyze
    from gearsim.signals.tsa import na4
    from gearsim.studies.life import equivalent_crack, life_fractions, record_duration
    from gearsim.studies.sweep_case import add_noise, features

    (crack,) = box.train.cracks
    _, f_ref, teeth = box.reference()
    history: list[list[np.ndarray]] = [[] for _ in range(seeds)]
    rows = []
    for s in life_fractions(life, fractions):
        eq, _ = equivalent_crack(crack, s.crack)
        b = dataclasses.replace(box, train=box.train.with_cracks((eq,)))
        x = b.select(b.simulate(duration=record_duration(box)), box.default_signal)
        row = []
        for k in range(seeds):
            a = analyze(add_noise(x, 0.1, k), float(box.dynamics.fs), teeth=teeth,
                        shaft_frequency=f_ref, settings=box.analysis)
            f = features(a.to_dict())
            history[k].append(a.residual)
            f["na4_history"] = na4(history[k])
            f["residual_kurtosis"] = na4([a.residual])
            row.append(f)
        rows.append(row)
    return rows


def test_one_condition_is_the_single_point_records(box, life, records):
    """The default (the gearbox's own load and speed) and that condition inside a grid
    of loads and speeds give exactly the single-point numbers."""
    from gearsim.studies.life import life_records

    assert life.end == "path end"  # no broken tooth: the records stay on the tables
    ref = _serial_reference(box, life, FRACTIONS, SEEDS)
    speed, torque = box.operating()
    one = life_records(box, life, FRACTIONS, SEEDS)
    assert (one.sizes["load"], one.sizes["speed"]) == (1, 1)
    assert one["load"].item() == torque and one["speed"].item() == speed
    grid = records.sel(load=torque, speed=speed)
    names = sorted(ref[0][0])
    assert set(names) == {str(n) for n in one.data_vars
                          if one[n].dims == ("fraction", "load", "speed", "seed")}
    for n in names:
        want = np.array([[f[n] for f in row] for row in ref])
        np.testing.assert_array_equal(one[n].isel(load=0, speed=0).values, want, err_msg=n)
        np.testing.assert_array_equal(grid[n].values, want, err_msg=n)
    assert one.attrs["duration_s"] == pytest.approx(4.2 / box.slowest_shaft()[1], rel=1e-12)
    assert one.attrs["dask_workers"] == 0


def test_features_over_fraction_load_speed_seed(box, records):
    ds = records
    speed, torque = box.operating()
    assert ds.sizes["fraction"] == 3 and ds.sizes["seed"] == SEEDS
    np.testing.assert_array_equal(ds["load"].values, [torque, LOAD_FACTOR * torque])
    np.testing.assert_array_equal(ds["speed"].values, [speed, SPEED_FACTOR * speed])
    assert ds["load"].attrs["units"] == "N*m" and ds["speed"].attrs["units"] == "rad/s"
    for n in ("td_rms", "tsa_fm4", "na4_history", "residual_kurtosis"):
        assert ds[n].dims == ("fraction", "load", "speed", "seed")
    assert ds["simulation_seconds"].dims == ("fraction", "load", "speed")
    # the crack states are the life's, whatever the load and speed
    assert ds["crack_length"].dims == ("fraction",)
    assert ds.attrs["torque_n_m"] == torque and ds.attrs["speed_rad_s"] == speed
    # NA4 with history starts at NA4 alone for every load, speed and seed
    np.testing.assert_allclose(ds["na4_history"].isel(fraction=0),
                               ds["residual_kurtosis"].isel(fraction=0), rtol=1e-9)


def test_frequencies_and_durations_follow_the_speed(box, records):
    """Per speed: the analysis' reference shaft runs at speed / 2 pi, the cracked gear's
    mesh at z_1 speed / 2 pi, and every record holds 4.2 revolutions of the slowest
    shaft (the output, z_1 / z_3 of the input speed, idler train)."""
    ds = records
    w = ds["speed"].values
    z = [g.teeth for g in box.train.gears]
    np.testing.assert_allclose(ds["reference_shaft_frequency"].values, w / (2 * math.pi),
                               rtol=1e-12)
    np.testing.assert_allclose(ds["mesh_frequency"].values, z[0] * w / (2 * math.pi),
                               rtol=1e-12)
    f_slow = w / (2 * math.pi) * z[0] / max(z)
    np.testing.assert_allclose(ds["duration"].values, 4.2 / f_slow, rtol=1e-12)
    # the analysis finds the mesh line at each speed's mesh frequency: its amplitude is
    # a large part of the record (a sinusoid of amplitude A has RMS A / sqrt 2)
    amp, rms = ds["mesh_amplitude_o1"], ds["td_rms"]
    assert bool((amp < math.sqrt(2.0) * rms).all()) and bool((amp > 0.3 * rms).all())
    assert float(abs(rms.isel(speed=1) / rms.isel(speed=0) - 1.0).min()) > 0.05


def test_features_scale_with_the_load(records):
    """The tables' mesh model is linear in the load (no contact loss at these loads) and
    the noise is relative to the record: at each crack state, speed and seed the
    amplitudes scale with the load, energies with its square, shape indicators not."""
    ds = records
    lo, hi = ds.isel(load=0), ds.isel(load=1)
    ratio = float(ds["load"][1] / ds["load"][0])
    assert ratio == pytest.approx(LOAD_FACTOR, rel=1e-15)
    for n, power in (("td_rms", 1), ("td_peak", 1), ("mesh_amplitude_o1", 1),
                     ("mesh_amplitude_o2", 1), ("band_energy_o1", 2), ("band_energy_o2", 2),
                     ("tsa_fm4", 0), ("na4_history", 0), ("residual_kurtosis", 0),
                     ("td_kurtosis", 0), ("td_crest_factor", 0)):
        np.testing.assert_allclose(hi[n].values, ratio**power * lo[n].values,
                                   rtol=LINEAR_TOL, err_msg=n)
    # and the crack shows: FM4 grows along the life at every load and speed
    fm4 = ds["tsa_fm4"].mean("seed")
    assert bool((fm4.isel(fraction=-1) > 2.0 * fm4.isel(fraction=0)).all())


def test_trends_and_alarms_per_condition(box, records):
    from gearsim.studies.life import alarm_fractions, indicator_trends, record_condition

    speed, torque = box.operating()
    own = indicator_trends(records)  # default: the life's operating point
    np.testing.assert_array_equal(
        own["fm4"], records["tsa_fm4"].sel(load=torque, speed=speed).mean("seed").values)
    other = indicator_trends(records, load=LOAD_FACTOR * torque, speed=SPEED_FACTOR * speed)
    np.testing.assert_array_equal(
        other["na4"], records["na4_history"].isel(load=1, speed=1).mean("seed").values)
    assert set(alarm_fractions(records, load=torque, speed=speed)) == set(own)
    with pytest.raises(InputError, match=r"load = 1.0: is not recorded: give one of "
                                         r"19504, 29256 N\*m"):
        record_condition(records, load=1.0)
    one = records.isel(load=[1], speed=[1]).copy()
    one.attrs.update(torque_n_m=1.0, speed_rad_s=1.0)  # not the recorded ones: the only
    assert record_condition(one)["td_rms"].dims == ("fraction", "seed")


@pytest.mark.parametrize("kw, match", [
    ({"loads": [0.0]}, "loads = 0.0: must be a finite number > 0 N"),
    ({"loads": [-5.0]}, "loads = -5.0: must be a finite number > 0"),
    ({"loads": [math.inf]}, "loads = inf"),
    ({"loads": [2e9]}, r"loads = 2000000000.0: must be in \[1e-06, 1e\+09\] N\*m"),
    ({"loads": [1e-300]}, r"loads = 1e-300: must be in \[1e-06, 1e\+09\] N\*m"),
    ({"loads": [1e3, 1e3]}, "must not repeat"),
    ({"loads": []}, "must list at least one"),
    ({"speeds": [math.nan]}, "speeds = nan"),
    ({"speeds": [2e5]}, r"speeds = 200000.0: must be in \[0.001, 100000\] rad/s"),
    ({"speeds": [1e-300]}, r"speeds = 1e-300: must be in \[0.001, 100000\] rad/s"),
    ({"speeds": [1e5]}, "speeds = 100000.0: its record is refused: dynamics.fs"),
    ({"duration": 0.01}, r"^duration = 0.01: must be >= 0.101215 s"),  # 60 / (1900 * 39/125)
])
def test_operating_conditions_refused(box, kw, match):
    from gearsim.studies.life import operating_conditions

    with pytest.raises(InputError, match=match):
        operating_conditions(box, **kw)


def test_records_on_dask_equal_the_serial_ones(box, life, records):
    """A LocalCluster of 2 worker processes: the same numbers as the serial run (the
    fractions are a prefix of the serial run's: the same NA4 history)."""
    from gearsim.studies.life import life_records

    speed, torque = box.operating()
    ds = life_records(box, life, FRACTIONS[:2], 1, loads=[torque],
                      speeds=[speed, SPEED_FACTOR * speed], workers=2, adaptive=False)
    assert ds.attrs["dask_workers"] == 2
    ref = records.isel(fraction=[0, 1], seed=[0]).sel(load=[torque])
    n = 0
    for name in ref.data_vars:
        if ref[name].dims == ("fraction", "load", "speed", "seed"):
            np.testing.assert_allclose(ds[name].values, ref[name].values, rtol=DASK_TOL,
                                       atol=0.0, err_msg=str(name))
            n += 1
    assert n > 50
    for c in ("reference_shaft_frequency", "mesh_frequency", "duration", "crack_length"):
        np.testing.assert_array_equal(ds[c].values, ref[c].values)


def _cli(capsys, *args):
    from gearsim import cli

    code = cli.run([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def no_life(monkeypatch):
    """The life's FE must not start: the refusals come before it."""
    from gearsim.studies import life as lf

    def refuse(*args, **kwargs):
        raise AssertionError("the life started")

    monkeypatch.setattr(lf, "gear_life", refuse)


@pytest.mark.parametrize("args, expected", [
    (("--loads", "0,100 N*m"), "--loads = 0,100 N*m: 0 N*m: must be a finite number > 0"),
    (("--loads", "-100 N*m"), "--loads = -100 N*m: -100 N*m: must be a finite number > 0"),
    (("--loads", "100,inf N*m"), "--loads = 100,inf N*m: inf N*m: must be a finite number"),
    (("--loads", "100,2e10 N*m"), "--loads = 100,2e10 N*m: 2e10 N*m: must be in [1e-06, 1e+09] N*m"),
    (("--loads", "1e-12 N*m"), "--loads = 1e-12 N*m: 1e-12 N*m: must be >= 1e-09 N*m"),
    (("--loads", "40,60"), "--loads = 40,60: 40: give a unit after the last value, e.g. "
                           "'40,60 N*m'"),  # not the hint of a bare TOML number
    (("--loads", "100,,200 N*m"), "--loads = 100,,200 N*m: must list values without empty"),
    (("--loads", "2000 N*m,2 kN*m"), "--loads = 2000 N*m,2 kN*m: must not repeat a value"),
    (("--loads", "5 m"), "--loads = 5 m: 5 m: has units of [length]"),
    (("--speeds", "1900"), "--speeds = 1900: 1900: give a unit after the last value, e.g. "
                           "'1900 rpm'"),
    (("--speeds", "1500,nan rpm"), "--speeds = 1500,nan rpm: nan rpm: must be a finite"),
    (("--speeds", "-5 rpm"), "--speeds = -5 rpm: -5 rpm: must be a finite number > 0 rad/s"),
    (("--speeds", "2e5 rad/s"), "--speeds = 2e5 rad/s: 2e5 rad/s: must be in [0.001, 100000] rad/s"),
    (("--speeds", "1e5 rad/s"), "--speeds = 1e5 rad/s: 1e5 rad/s: its record is refused: "
                                "dynamics.fs"),
    # one revolution of the 125-tooth output: 60 s / (1900 rpm * 39 / 125), twice at 950 rpm
    (("--duration", "0.01"), "--duration = 0.01: must be >= 0.101215 s (one revolution"),
    (("--duration", "0.15", "--speeds", "950,1900 rpm"),
     "--duration = 0.15: must be >= 0.202429 s (one revolution of the slowest gear, output) "
     "at 950 rpm"),
    (("--workers", "0"), "--workers = 0: must be an integer >= 1"),
    (("--scheduler", "not a url"), "--scheduler = not a url: must be a scheduler address"),
    (("--scheduler", "localhost:99999"), "--scheduler = localhost:99999: port must be in 1-65535"),
])
def test_cli_refuses_bad_conditions_in_one_line(capsys, tmp_path, no_life, args, expected):
    code, out, err = _cli(capsys, "life", "idler-table1", "--out", tmp_path / "s.nc", *args)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith(f"gearsim: error: {expected}"), lines[0]
    assert not (tmp_path / "s.nc").exists()


def test_cli_unreachable_scheduler_before_the_life(capsys, tmp_path, no_life, monkeypatch):
    import socket

    monkeypatch.setattr("gearsim.studies.sweep_run.CONNECT_TIMEOUT", "1s")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    code, _, err = _cli(capsys, "life", "idler-table1", "--out", tmp_path / "s.nc",
                        "--scheduler", address)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1
    assert lines[0].startswith(f"gearsim: error: --scheduler = {address}: cannot connect")


@pytest.fixture
def same_life(monkeypatch, life):
    """The CLI's life is the module's (the same gearbox and settings would recompute it
    with the default FE mesh): the CLI's own part is parsing, records and output."""
    from gearsim.studies import life as lf

    monkeypatch.setattr(lf, "gear_life", lambda *args, **kwargs: life)


def test_cli_loads_and_speeds(capsys, tmp_path, box, same_life):
    import json

    import xarray as xr

    speed, torque = box.operating()
    rpm = speed * 30 / math.pi
    code, out, err = _cli(capsys, "life", "idler-table1", "--out", tmp_path / "s.nc",
                          "--torque", f"{torque} N*m", "--fractions", "0,1", "--seeds", "1",
                          "--loads", f"{torque / 1e3},{LOAD_FACTOR * torque / 1e3} kN*m",
                          "--speeds", f"{rpm} rpm, {SPEED_FACTOR * speed} rad/s", "--json")
    assert code == 0, err
    s = json.loads(out)
    ds = xr.load_dataset(tmp_path / "s.nc", engine="h5netcdf")
    assert dict(ds.sizes) == {"fraction": 2, "load": 2, "speed": 2, "seed": 1,
                              "vertex": ds.sizes["vertex"], "life_point": 50}
    np.testing.assert_allclose(ds["load"].values, [torque, LOAD_FACTOR * torque], rtol=1e-12)
    np.testing.assert_allclose(ds["speed"].values, [speed, SPEED_FACTOR * speed], rtol=1e-12)
    assert s["alarm_condition"] == {"load_n_m": torque, "speed_rad_s": speed}
    assert len(s["alarm_fractions_by_condition"]) == 4
    assert set(s["alarm_fractions"]) == {"na4", "fm4", "residual_kurtosis", "sideband_energy"}


def test_cli_more_workers_than_simulations(capsys, tmp_path, box):
    """--workers 5 for at most 2 simulations (one fraction, and the broken tooth after a
    fracture, at one load and speed): one line, exit 2, before the life's FE and with
    nothing written."""
    _, torque = box.operating()
    code, out, err = _cli(capsys, "life", "idler-table1", "--out", tmp_path / "s.nc",
                          "--torque", f"{torque} N*m", "--fractions", "0.5", "--seeds", "1",
                          "--workers", "5")
    assert code == 2, err
    assert err.strip() == ("gearsim: error: --workers = 5: must be <= 2, the simulations "
                           "to compute (a worker more would have nothing to do)")
    assert not list(tmp_path.iterdir())


def test_few_short_simulations_stay_in_this_process(box, life, records):
    """workers=2 for three simulations of well under a second: a local cluster would not
    win back its start-up (CLUSTER_START_S), so they run here, as gearsim sweep decides;
    the numbers are those of the serial run."""
    from gearsim.studies.life import life_records

    speed, torque = box.operating()
    ds = life_records(box, life, FRACTIONS, 1, loads=[torque], speeds=[speed], workers=2)
    assert ds.attrs["dask_workers"] == 0
    ref = records.isel(seed=[0]).sel(load=[torque], speed=[speed])
    assert ref.sizes == ds.sizes
    for name in ref.data_vars:
        if name in ds.data_vars and ref[name].dims == ds[name].dims \
                and "seconds" not in str(name):
            np.testing.assert_array_equal(ds[name].values, ref[name].values, err_msg=name)
