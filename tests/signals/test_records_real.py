"""Real records as they come: the SpectraQuest gearbox fault simulator records of the OpenEI
"Gearbox Fault Diagnosis Data" set (CC BY 4.0; gzip CSV, channels a1..a4, no stored rate),
read from the shared data folder beside the repository and never copied into it."""

import csv
import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from gearsim import cli
from gearsim.errors import InputError
from gearsim.signals.estimate import estimate_fs
from gearsim.signals.tiers import analyze_record

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "spectraquest-gfd"
FOUR = ("h30hz0", "h30hz90", "b30hz0", "b30hz90")

pytestmark = pytest.mark.skipif(
    len(list(DATA.glob("*30hz*.csv.gz"))) != 20,
    reason=f"the 20 SpectraQuest records (OpenEI Gearbox Fault Diagnosis Data) are not in {DATA}")


def _columns(name: str) -> dict[str, np.ndarray]:
    """The file read by the standard library and numpy alone (independent of gearsim)."""
    with gzip.open(DATA / f"{name}.csv.gz", "rt") as fh:
        rows = list(csv.reader(fh))
    values = np.array(rows[1:], dtype=float)
    return {c: values[:, j] for j, c in enumerate(rows[0])}


@pytest.mark.parametrize("name", FOUR)
def test_every_channel_statistics_without_a_rate(name, capsys):
    assert cli.run(["analyze", str(DATA / f"{name}.csv.gz"), "--json"]) == 0
    recs = json.loads(capsys.readouterr().out)["records"]
    ref = _columns(name)
    assert [r["source"]["channel"] for r in recs] == list(ref) == ["a1", "a2", "a3", "a4"]
    for r in recs:
        x = ref[r["source"]["channel"]]
        d = x - x.mean()
        st = r["tiers"]["statistics"]
        assert r["fs_hz"] is None and r["n_samples"] == x.size
        assert st["rms"] == pytest.approx(np.sqrt(np.mean(d * d)), rel=1e-12)
        assert st["kurtosis"] == pytest.approx(np.mean(d**4) / np.mean(d * d) ** 2, rel=1e-9)
        assert st["peak"] == pytest.approx(np.abs(d).max(), rel=1e-12)
        assert r["tiers"]["spectrum"]["frequency_unit"] == "cycles/sample"
        assert 0 < r["tiers"]["spectrum"]["lines"][0]["frequency"] < 0.5
        reasons = {s["tier"]: s["reason"] for s in r["skipped"]}
        assert "needs a sampling rate" in reasons["shaft"]


def test_text_and_report_without_a_rate(tmp_path, capsys):
    files = [str(DATA / f"{n}.csv.gz") for n in FOUR]
    assert cli.run(["analyze", *files, "--channel", "a1", "--label-pattern", "^([hb])30",
                    "--report", str(tmp_path / "rep")]) == 0
    out = capsys.readouterr().out
    assert out.count("fs unknown (frequencies in cycles/sample)") == 4
    rep = json.loads((tmp_path / "rep" / "separability.json").read_text())
    assert rep["counts"] == {"b": 2, "h": 2}
    assert "spectral_centroid_cps" in {r["indicator"] for r in rep["indicators"]}


@pytest.mark.slow
def test_batch_of_all_twenty_files_with_labels_from_names(tmp_path, capsys):
    table, rep = tmp_path / "table.csv", tmp_path / "rep"
    assert cli.run(["analyze", str(DATA / "*30hz*.csv.gz"), "--fs", "12800", "--shaft-rpm",
                    "1800", "--teeth", "32", "--label-pattern", "^([hb])30hz",
                    "--out", str(table), "--report", str(rep)]) == 0
    assert "table:" in capsys.readouterr().out
    with table.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 20 * 4
    assert {(Path(r["file"]).name, r["channel"]) for r in rows} == {
        (f"{c}30hz{load}.csv.gz", f"a{j}") for c in "hb" for load in range(0, 100, 10)
        for j in range(1, 5)}
    assert all(r["label"] == Path(r["file"]).name[0] for r in rows)
    assert {r["fs_provenance"] for r in rows} == {"given"}
    assert all(float(r["mesh_frequency_hz [Hz]"]) == 960.0 for r in rows)
    sep = json.loads((rep / "separability.json").read_text())
    assert sep["counts"] == {"b": 40, "h": 40}


def test_shaft_orders_of_h30hz0_read_at_the_shaft_not_at_shaft_2():
    # the shaft at 29.754 Hz (speed search); shaft 2 (32/80) at 11.90 Hz has its 2x at
    # 23.80 Hz, inside the former +-25 % window (+-7.4 Hz) where its envelope line
    # (15.5, against 4.2 at 29.7 Hz) was taken for order 1
    x = _columns("h30hz0")["a1"]
    sh = analyze_record(x, 12800.0, speed_search=(20.0, 40.0),
                        stages=[(32, 80), (48, 64)]).tiers["shaft"]
    df = 12800.0 / x.size
    for rows in (sh["orders"], sh["envelope"]["orders"]):
        assert [r["order"] for r in rows] == [1, 2, 3]
        for r in rows:
            assert abs(r["frequency_hz"] - r["order"] * 29.754) < df, rows


#: FM0 / FM4 of the drifting record against the steady one, both in the order domain:
#: the construction's speed steps at the 7 piece boundaries are smoothed over the
#: tracking filter's length (measured: FM0 4.09 / 4.52, FM4 2.65 / 2.71)
STEPPED = 0.15


def test_b30hz50_made_to_drift_read_in_the_order_domain():
    # the tester's construction: b30hz50 a1 cut into 8 pieces, piece i resampled by
    # 100/(100 + i), so that played at 12.8 kHz the shaft steps from 29.68 Hz up by
    # 7 % (x 107/100) to 31.75 Hz; read at the mean speed 30.69 Hz the gear tier gave
    # mesh amplitude 0.137 for 1.77, SER 13.2 for 2.38, FM0 16.1 for 5.75 (then it was
    # skipped); in the order domain its mesh line is the pieces' own
    from scipy.signal import resample_poly

    from gearsim.signals.analysis import analyze

    a1 = _columns("b30hz50")["a1"]
    pieces = np.array_split(a1, 8)
    x = np.concatenate([resample_poly(p, 100, 100 + i) for i, p in enumerate(pieces)])
    kw = dict(speed_search=(20.0, 40.0), stages=[(32, 80), (48, 64)])
    r = analyze_record(x, 12800.0, **kw)
    lo, hi = r.tiers["shaft"]["speed_range_hz"]
    assert lo < 29.68 * 1.01 and hi > 29.68 * 1.07 * 0.99
    g = r.tiers["gear"]
    assert g["order_domain"]["mean_speed_hz"] == pytest.approx(29.68 * 1.035, rel=2e-3)
    # the mesh amplitude of each piece analysed alone at its constant speed (each piece
    # 0.5 s at a steady 29.68 Hz, independent of any tracking): 1.65 to 2.18, mean 1.88
    own = np.mean([analyze(p, 12800.0, stages=[(32, 80), (48, 64)], shaft_frequency=29.6754)
                   .to_dict()["mesh_harmonics"][0]["amplitude"] for p in pieces])
    amp = g["analysis"]["mesh_harmonics"][0]["amplitude"]
    assert amp == pytest.approx(own, rel=0.05)
    # the steady record in the order domain by the public functions (its own tracked
    # speed, 512 samples a revolution: another rate than the tier's resampling)
    from gearsim.signals.ordertrack import order_track
    from gearsim.signals.speed import estimate_speed

    prof = estimate_speed(a1, 12800.0, order=32, search=(25.0, 35.0))
    y, _ = order_track(a1, 12800.0, prof, samples_per_rev=512)
    f = prof.mean_frequency
    ref = analyze(y, 512 * f, stages=[(32, 80), (48, 64)], shaft_frequency=f).to_dict()["tsa"]
    for k in ("fm0", "fm4"):
        assert g["analysis"]["tsa"][k] == pytest.approx(ref[k], rel=STEPPED), k


#: Standard error of the mean of the 8 pieces' mesh amplitudes below (their spread is
#: 0.1-0.3 of the mean, /sqrt(8)): the whole record agrees with them within it.
PIECES = 0.05


@pytest.mark.parametrize("name", ["b30hz90", "h30hz90"])
def test_steady_record_tracked_reads_the_mesh_line_of_its_pieces(name):
    # a speed estimated as steady (first and last pieces within 0.2 %) still wanders by
    # 0.2 %, which at 950 Hz spreads the mesh line over ~15 bins of the whole record:
    # read in time at one speed, b30hz90 gave 1.333 and h30hz90 0.758. Its 8 pieces (1 s
    # each) read alone at their own constant speeds (independent of any tracking) give
    # 2.13 and 1.22 on average; the record, tracked and read in the order domain, 2.15 and
    # 1.17
    from gearsim.signals.analysis import analyze
    from gearsim.signals.speed import estimate_constant_speed

    a1, fs, kw = _columns(name)["a1"], 12800.0, dict(stages=[(32, 80), (48, 64)])
    own = []
    for p in np.array_split(a1, 8):
        f = estimate_constant_speed(p, fs, search=(29.0, 30.5)).frequency
        own.append(analyze(p, fs, shaft_frequency=f, **kw).to_dict()["mesh_harmonics"][0]
                   ["amplitude"])
    r = analyze_record(a1, fs, speed_search=(20.0, 40.0), **kw)
    g = r.tiers["gear"]
    assert "order_domain" in g and not [s for s in r.skipped if s["tier"] == "shaft.tracking"]
    # its mean over the read revolutions is the line fit's constant estimate
    assert r.speed == pytest.approx(r.tiers["estimates"]["speed"]["frequency"], rel=2e-3)
    amp = g["analysis"]["mesh_harmonics"][0]["amplitude"]
    assert amp == pytest.approx(np.mean(own), rel=PIECES)


def _hand_rate(x: np.ndarray) -> float:
    """The rate 1785 rpm and 32 teeth give if the record was sampled at 12.8 kHz (numpy
    alone): the strongest bin within 2 % of 32 x 29.75 Hz is the mesh line, at f_m Hz
    at 12.8 kHz, so a mesh at 32 x 29.75 Hz means 12.8 kHz x 952 / f_m."""
    n = x.size
    amp = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(n)))
    f = np.fft.rfftfreq(n, 1 / 12_800.0)
    band = np.abs(f / 952.0 - 1) < 0.02
    return 12_800.0 * 952.0 / f[band][np.argmax(amp[band])]


def test_mesh_rate_estimate_of_the_twenty_records_is_their_rate_or_refused():
    """Without --fs the rate from 32 teeth at 1785 rpm was 2, 4, 8 or 10.7 times 12.8 kHz on
    14 of the 20 records (a shaft harmonic taken for the mesh fundamental); the whole comb
    now gives their rate (within 1e-3 of the mesh line: the speed's wander splits
    the mesh lines of b30hz80 and b30hz90 over 0.02 orders) or refuses, naming the
    candidates."""
    kept = 0
    for path in sorted(DATA.glob("*30hz*.csv.gz")):
        x = _columns(path.name.split(".")[0])["a1"]
        try:
            e = estimate_fs(x, shaft_frequency=1785 / 60, teeth=32)
        except InputError as exc:
            assert "kHz (score" in str(exc) and "give the rate (--fs)" in str(exc)
            continue
        kept += 1
        assert e.fs == pytest.approx(_hand_rate(x), rel=1e-3), path.name
        assert e.fs == pytest.approx(12_800.0, rel=0.01)  # the speed is 1785 rpm within 0.6 %
    assert kept >= 15  # 16 of 20; b30hz70 (9.881 kHz), h30hz50, 60, 70 (4.28 kHz) refused


def test_envelope_rate_estimate_of_the_twenty_records_is_their_rate_or_refused():
    """Without --fs and without teeth the shaft line of the squared envelope gave 0.34 to
    10 times 12.8 kHz on all 20 records (b30hz0 32.0, b30hz90 64.3, h30hz50 127.9,
    h30hz0 21.3, h30hz40 4.31 kHz), then tooth counts of 40 or 160. The pair 32/80 repeats every 5
    revolutions of the shaft: the comb of shaft orders is the denser, but a comb 5 times
    finer (64 kHz) holds the lines it leaves out (shaft 2 at 0.4 orders, shaft 3 at 0.3):
    two readings, so the rate is refused on all 20 (a kept rate would have to be theirs,
    within the estimator's resolution: the rate that puts their order-32 line at 32 x
    29.75 Hz)."""
    for path in sorted(DATA.glob("*30hz*.csv.gz")):
        x = _columns(path.name.split(".")[0])["a1"]
        try:
            e = estimate_fs(x, shaft_frequency=1785 / 60)
        except InputError as exc:
            assert "give the rate (--fs)" in str(exc), path.name
            continue
        assert e.fs == pytest.approx(_hand_rate(x), rel=max(e.relative_resolution, 1e-4))


def test_analyze_with_a_speed_alone_refuses_the_rate_and_so_the_teeth(capsys):
    """b30hz90 with 1785 rpm and nothing else: the rate was estimated at 64.3 kHz and the
    tooth count at 160 from it; the rate is refused with its reason, so no tooth count is
    estimated and the tiers that need a rate say so."""
    assert cli.run(["analyze", str(DATA / "b30hz90.csv.gz"), "--shaft-rpm", "1785",
                    "--channel", "a1", "--json"]) == 0
    (r,) = json.loads(capsys.readouterr().out)["records"]
    reasons = {s["tier"]: s["reason"] for s in r["skipped"]}
    assert r["fs_hz"] is None and r["teeth"] is None
    assert "estimates" not in r["tiers"]
    assert reasons["estimate.fs"].startswith("sampling rate = ")
    assert reasons["estimate.fs"].endswith("give the rate (--fs)")
    assert "needs a sampling rate" in reasons["gear"]


def test_analyze_without_a_rate_gives_their_rate_or_a_reason(capsys):
    files = [str(DATA / f"{n}.csv.gz") for n in FOUR]
    assert cli.run(["analyze", *files, "--shaft-rpm", "1785", "--teeth", "32", "--channel",
                    "a1", "--json"]) == 0
    for r, name in zip(json.loads(capsys.readouterr().out)["records"], FOUR, strict=True):
        if r["fs_hz"] is None:
            reasons = {s["tier"]: s["reason"] for s in r["skipped"]}
            assert "give the rate (--fs)" in reasons["estimate.fs"]
        else:
            assert r["fs_provenance"] == "estimate"
            assert r["fs_hz"] == pytest.approx(_hand_rate(_columns(name)["a1"]), rel=1e-3)


def test_the_config_speed_is_named_as_such_when_the_record_disagrees(capsys):
    """--config two-stage-reducer brings its operating speed, 30 Hz; h30hz0's mesh (32
    teeth) says about 29.75 Hz. The warning called it the 'given speed'; it names the
    configuration and the options that give the speed instead."""
    x = _columns("h30hz0")["a1"]
    amp = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    f = np.fft.rfftfreq(x.size, 1 / 12_800.0)
    band = np.abs(f / 960.0 - 1) < 0.03
    hand = f[band][np.argmax(amp[band])] / 32  # the shaft speed from the mesh line [Hz]
    assert cli.run(["analyze", str(DATA / "h30hz0.csv.gz"), "--fs", "12800", "--config",
                    "two-stage-reducer", "--channel", "a1", "--json"]) == 0
    (rec,) = json.loads(capsys.readouterr().out)["records"]
    (warn,) = rec["warnings"]
    assert warn.startswith("config speed 30 Hz (the operating speed of --config "
                           "two-stage-reducer) disagrees with the speed estimated")
    assert warn.endswith("every tier uses it: give --shaft-rpm or --speed-search")
    pct = float(warn.split("(")[2].split(" %")[0])
    assert pct == pytest.approx(100 * (hand / 30 - 1), abs=0.02)
