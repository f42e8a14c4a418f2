"""``gearsim analyze`` and ``gearsim compare``: output, and exit 2 with one line on bad input."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.io import savemat, wavfile

from gearsim import cli
from gearsim.signals.synthetic import ImpactSpec, gear_signal

FS = 20_000.0
RPM = 1900.0
F_R = RPM / 60.0


def _write_nc(path, *, duration=2.0, bad_index=None, fs=FS, impacts=True):
    x = gear_signal(fs=fs, duration=duration, shaft_frequency=F_R, teeth=39,
                    mesh_amplitudes={1: 1.0, 2: 0.5}, sidebands={(1, -1): 0.05, (1, 1): 0.05},
                    impacts=ImpactSpec(4.0, 3e-4, 4000.0, 0.01) if impacts else None,
                    noise=0.01, seed=2)
    if bad_index is not None:
        x[bad_index] = np.inf
    t = np.arange(x.size) / fs
    tacho = (np.mod(t * F_R, 1.0) < 0.2).astype(float)
    xr.Dataset({"mesh_force_1": ("time", x, {"units": "N"}), "tacho": ("time", tacho)},
               coords={"time": t}, attrs={"fs": fs}).to_netcdf(path, engine="h5netcdf")
    return path


def _run(monkeypatch, capsys, *args):
    monkeypatch.setattr(sys, "argv", ["gearsim", *map(str, args)])
    code = 0
    try:
        cli.main()
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_analyze_json_and_plots(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc")
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--shaft-rpm", RPM, "--teeth", 39, "--teeth", 59, "--max-order", 2,
                          "--plot", tmp_path / "figs", "--json", "--baseline", p)
    assert code == 0, err
    (rec,) = json.loads(out)["records"]  # by design: one entry per file x channel, by tier
    d = rec["tiers"]["gear"]["analysis"]
    assert abs(d["impacts"]["period_ratio_to_T1"] - 1.0) < 0.01
    assert rec["units"] == "N"
    assert d["ratios_to_baseline"]["rms"] == pytest.approx(1.0)
    assert len(list((tmp_path / "figs").glob("*.png"))) == 5


def test_analyze_text_with_tacho(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc")
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--tacho", "tacho", "--teeth", 39, "--max-order", 2)
    assert code == 0, err
    assert "TSA" in out and "impacts:" in out


def test_compare_json(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc", impacts=False)
    q = tmp_path / "meas.wav"
    x = gear_signal(fs=FS, duration=2.0, shaft_frequency=F_R, teeth=39,
                    mesh_amplitudes={1: 0.5, 2: 0.25}, sidebands={(1, -1): 0.03, (1, 1): 0.03},
                    noise=0.001, seed=3)
    wavfile.write(q, int(FS), x.astype(np.float32))
    code, out, err = _run(monkeypatch, capsys, "compare", p, q, "--channel-sim", "mesh_force_1",
                          "--shaft-rpm", RPM, "--teeth", 39, "--sidebands", 1, "--json",
                          "--plot", tmp_path / "cmp.png")
    assert code == 0, err
    d = json.loads(out)
    row = d["orders"][0]
    # simulated relative level 0.05, measured 0.06: error 16.7 %
    assert row["mean_error_percent"] == pytest.approx(100 * (0.05 - 0.06) / -0.06, abs=1.0)
    assert (tmp_path / "cmp.png").stat().st_size > 10_000


def _assert_one_line_exit_2(code, err, pattern):
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("gearsim: error: ")
    assert pattern in lines[0], lines[0]
    assert "Traceback" not in err


def test_cli_nonfinite_sample(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "bad.nc", bad_index=321)
    code, _, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                        "--shaft-rpm", RPM, "--teeth", 39)
    _assert_one_line_exit_2(code, err, "mesh_force_1[321] = inf: must be finite")


def test_cli_nyquist(tmp_path, monkeypatch, capsys):
    """By design: harmonics above Nyquist skip the gear tier (with the reason), not the run."""
    p = _write_nc(tmp_path / "slow.nc", fs=8000.0)
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--shaft-rpm", RPM, "--teeth", 39, "--max-order", 4)
    assert code == 0, err
    assert "skipped gear: fs = 8000 Hz: must exceed" in out


def test_cli_record_too_short(tmp_path, monkeypatch, capsys):
    """By design: a record too short for the gear tier skips it; statistics still come."""
    p = _write_nc(tmp_path / "short.nc", duration=0.1)
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--shaft-rpm", RPM, "--teeth", 39, "--teeth", 125, "--max-order", 1)
    assert code == 0, err
    assert "statistics" in out and "skipped gear: record duration = 0.1 s: must be >=" in out


def test_cli_missing_channel(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc")
    code, _, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "acc",
                        "--shaft-rpm", RPM, "--teeth", 39)
    _assert_one_line_exit_2(code, err, "channel = acc: not in sim.nc")


def test_cli_truncated_file(tmp_path, monkeypatch, capsys):
    p = tmp_path / "rec.mat"
    savemat(p, {"acc": np.ones(20000), "fs": FS})
    p.write_bytes(p.read_bytes()[:5000])
    code, _, err = _run(monkeypatch, capsys, "analyze", p, "--shaft-rpm", RPM, "--teeth", 39)
    _assert_one_line_exit_2(code, err, "cannot be read as MAT")


def test_cli_speed_options(tmp_path, monkeypatch, capsys):
    """By design: no speed skips the shaft and gear tiers; two speed sources are refused."""
    p = _write_nc(tmp_path / "sim.nc")
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--teeth", 39)
    assert code == 0, err
    assert "skipped shaft: needs a shaft speed" in out
    code, _, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                        "--teeth", 39, "--shaft-rpm", RPM, "--tacho", "tacho")
    _assert_one_line_exit_2(code, err, "give at most one speed source")


def test_cli_repeated_channel_gives_both(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc")
    code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                          "--channel", "tacho", "--json")
    assert code == 0, err
    assert [r["source"]["channel"] for r in json.loads(out)["records"]] == [
        "mesh_force_1", "tacho"]


def test_cli_teeth_as_several_values(tmp_path, monkeypatch, capsys):
    p = _write_nc(tmp_path / "sim.nc")
    for teeth in (["39", "59"], ["39,59"]):
        code, out, err = _run(monkeypatch, capsys, "analyze", p, "--channel", "mesh_force_1",
                              "--shaft-rpm", RPM, "--teeth", *teeth, "--max-order", 2,
                              "--json")
        assert code == 0, err
        assert json.loads(out)["records"][0]["teeth"] == [39, 59]


def test_entry_point_subprocess(tmp_path):
    """The installed script path: exit status 2, one line, no traceback."""
    p = tmp_path / "rec.wav"  # by design a short record is analysed; a missing file is not
    wavfile.write(p, 8000, np.zeros(80, dtype=np.int16))
    p = tmp_path / "missing.wav"
    r = subprocess.run([sys.executable, "-m", "gearsim.cli", "analyze", str(p),
                        "--shaft-rpm", "1900", "--teeth", "39"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr


@pytest.mark.parametrize("args,option", [
    (["--pulses-per-rev", "0"], "--pulses-per-rev"), (["--sidebands", "0"], "--sidebands"),
    (["--window", "foo"], "--window"), (["--speed-search", "nan,inf"], "--speed-search"),
    (["--fs", "inf"], "--fs"),
])
def test_analysis_options_refused_under_their_own_names(tmp_path, capsys, args, option):
    """A bad analysis option is refused before any work, naming the option typed (not the
    settings field behind it), and nothing is written."""
    from gearsim import cli

    rec = tmp_path / "rec.csv"
    rec.write_text("# fs = 1000\nacc\n" + "".join(f"{np.sin(0.3 * i):.6f}\n"
                                                  for i in range(4000)))
    out = tmp_path / "t.csv"
    assert cli.run(["analyze", str(rec), *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"gearsim: error: {option} = ") and "\n" not in err
    assert not out.exists()


def test_compare_takes_a_gearsim_results_speed_and_teeth(tmp_path, monkeypatch, capsys):
    """Without --shaft-rpm and --teeth, compare takes the simulated gearsim result's
    reference shaft and gear (its shaft_frequency and analysis_teeth attributes), as
    analyze does; a file without them is refused naming compare's own options (before:
    '--shaft-rpm/--tacho = neither', an option compare does not have)."""
    p = _write_nc(tmp_path / "sim.nc", impacts=False)
    with xr.open_dataset(p) as ds:
        ds = ds.load()
    ds.attrs |= {"shaft_frequency": [F_R, F_R * 39 / 59], "analysis_teeth": [39, 59]}
    ds.to_netcdf(tmp_path / "result.nc", engine="h5netcdf")
    args = ["compare", tmp_path / "result.nc", p, "--channel-sim", "mesh_force_1",
            "--channel-meas", "mesh_force_1", "--sidebands", 1, "--json"]
    code, out, err = _run(monkeypatch, capsys, *args)
    assert code == 0, err
    own = json.loads(out)
    assert own["simulated"]["mesh_frequency_hz"] == pytest.approx(1900 / 60 * 39)  # 1235 Hz
    assert own["speed_teeth_provenance"] == "file"
    code, out, err = _run(monkeypatch, capsys, *args, "--shaft-rpm", RPM, "--teeth", 39)
    assert code == 0, err
    assert json.loads(out)["orders"] == own["orders"]
    code, _, err = _run(monkeypatch, capsys, "compare", p, p, "--channel-sim", "mesh_force_1",
                        "--channel-meas", "mesh_force_1")
    _assert_one_line_exit_2(code, err, "--shaft-rpm/--teeth = neither: give both")
    assert "--tacho" not in err
    code, _, err = _run(monkeypatch, capsys, *args, "--teeth", 39)
    _assert_one_line_exit_2(code, err, "--shaft-rpm/--teeth = one of them: give both")


def test_compare_reads_each_record_at_its_own_speed(tmp_path, monkeypatch, capsys):
    """A gearsim result at 30 Hz (Z = 32, f_m 960 Hz, sidebands 0.10 of the mesh line)
    against a record at 29.675 Hz (f_m 949.6 Hz, sidebands 0.12): with MEASURED's speed
    given or searched, every error is |0.10 - 0.12| / 0.12 = 16.7 % and the JSON holds
    both mesh lines; with none, MEASURED's mesh line disagrees with SIMULATED's speed and
    the run is refused in one line (before: read at 30 Hz, errors of about 99 %)."""
    fs, t = 12_800.0, np.arange(25_600) / 12_800.0

    def sig(f_r, mesh, rel, seed):
        sb = {(n, k): mesh * rel / n for n in (1, 2) for k in (-2, -1, 1, 2)}
        return gear_signal(fs=fs, duration=2.0, shaft_frequency=f_r, teeth=32, seed=seed,
                           mesh_amplitudes={1: mesh, 2: 0.5 * mesh}, sidebands=sb,
                           noise=1e-3)

    xr.Dataset({"a": ("time", sig(30.0, 1.0, 0.10, 1))}, coords={"time": t},
               attrs={"fs": fs, "shaft_frequency": [30.0], "analysis_teeth": [32]}
               ).to_netcdf(tmp_path / "sim.nc", engine="h5netcdf")
    wavfile.write(tmp_path / "meas.wav", int(fs), sig(29.675, 0.5, 0.12, 2).astype(np.float32))
    args = ["compare", tmp_path / "sim.nc", tmp_path / "meas.wav", "--channel-sim", "a",
            "--sidebands", 2, "--json"]
    for extra in (["--shaft-rpm-meas", 60 * 29.675], ["--speed-search-meas", "20,40"]):
        code, out, err = _run(monkeypatch, capsys, *args, *extra)
        assert code == 0, err
        d = json.loads(out)
        assert [r["mean_error_percent"] for r in d["orders"]] == pytest.approx(
            [100 * 0.02 / 0.12] * 2, abs=2.0)
        assert d["measured"]["mesh_frequency_hz"] == pytest.approx(32 * 29.675, abs=0.05)
        assert [r["amplitude"] for r in d["mesh"]["measured"]] == pytest.approx(
            [0.5, 0.25], rel=0.01)
        assert [r["amplitude"] for r in d["mesh"]["simulated"]] == pytest.approx(
            [1.0, 0.5], rel=0.01)
    code, _, err = _run(monkeypatch, capsys, *args)
    _assert_one_line_exit_2(code, err, "--shaft-rpm-meas = not given: MEASURED read at "
                            "SIMULATED's speed: given speed 30 Hz disagrees")
    code, _, err = _run(monkeypatch, capsys, *args, "--shaft-rpm", 60 * 29.675, "--teeth", 32)
    _assert_one_line_exit_2(code, err, "simulated mesh line = 1 f_m = 949.6 Hz: no line "
                            "above the noise floor")
    code, _, err = _run(monkeypatch, capsys, *args, "--speed-search-meas", "40,20")
    _assert_one_line_exit_2(code, err, "--speed-search-meas = 40,20: must be")


@pytest.mark.parametrize("value", ["inf", "nan", "0", "-30", "1e300", "1e-300"])
@pytest.mark.parametrize("verb,option", [("analyze", "--shaft-rpm"),
                                         ("compare", "--shaft-rpm"),
                                         ("compare", "--shaft-rpm-meas")])
def test_shaft_speeds_refused_in_one_line_before_the_records_are_read(tmp_path, capsys, verb,
                                                                       option, value):
    """A shaft speed must be finite, > 0 and within a gear train's operating speeds
    ([0.00955, 954930] rpm, 1e-3 to 1e5 rad/s); before, analyze's 1e300 rpm read every
    channel and refused each (33 problems in one 'line'), compare's after both records.
    The records here are not records: the refusal comes before any is read."""
    from gearsim import cli

    recs = [str(tmp_path / "a.csv"), str(tmp_path / "b.csv")]
    for r in recs:
        Path(r).write_text("not a record\n")
    args = ([verb, recs[0], option, value] if verb == "analyze" else
            [verb, *recs, option, value, *(["--teeth", "32"] if option == "--shaft-rpm"
                                           else [])])
    assert cli.run(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"gearsim: error: {option} = ") and "\n" not in err, err
