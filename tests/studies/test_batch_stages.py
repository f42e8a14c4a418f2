"""Batches of compound-train records: ``--stages`` carried to every record, in this
process and on Dask workers alike (each record analysed with its stages in one go), the
further stages' columns in the table and their lines in the text."""

import json
import re

import numpy as np
import pytest

from gearsim.signals.analysis import analyze
from gearsim.signals.tiers import analyze_record, stage_features
from gearsim.studies.batch import run_batch
from gearsim.studies.sweep_case import features

FS = 12800.0
DURATION = 2.0  # s: 18 revolutions of the 9 Hz output shaft, 0.5 Hz bins
STAGES = ((32, 80), (48, 64))  # at 30 Hz: shafts 30, 12, 9 Hz; meshes 960 and 576 Hz
STAGES_TEXT = "32/80,48/64"


def _record(seed: int, stage2: float) -> np.ndarray:
    """Both meshes of the reducer at a 30 Hz input, stage 2's mesh of amplitude
    ``stage2`` modulated by its two shafts (12 and 9 Hz), and some noise."""
    t = np.arange(int(FS * DURATION)) / FS
    x = (1 + 0.2 * np.cos(2 * np.pi * 30 * t)) * np.cos(2 * np.pi * 960 * t)
    x += stage2 * (1 + 0.25 * np.cos(2 * np.pi * 12 * t) + 0.15 * np.cos(2 * np.pi * 9 * t)) \
        * np.cos(2 * np.pi * 576 * t + 0.4)
    return x + 0.02 * np.random.default_rng(seed).standard_normal(t.size)


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    folder = tmp_path_factory.mktemp("compound")
    paths = []
    for i, amp in enumerate((0.5, 0.8)):
        p = folder / f"rec{i}.csv"
        np.savetxt(p, np.column_stack([_record(i, amp), _record(10 + i, 0.3 * amp)]),
                   delimiter=",", header=f"# fs = {FS:g}\na1,a2", comments="", fmt="%.9g")
        paths.append(p)
    return paths


def _cli(gearsim_here, *args):
    """``gearsim *args`` in this process (conftest's ``gearsim_here``): status, out, err."""
    r = gearsim_here(*args)
    return r.returncode, r.stdout, r.stderr


def _without_timings(v):
    """The JSON without wall-clock times (the only values a rerun changes)."""
    if isinstance(v, dict):
        return {k: _without_timings(u) for k, u in v.items() if k != "timings_s"}
    if isinstance(v, list):
        return [_without_timings(u) for u in v]
    return v


def test_serial_and_two_workers_give_the_same_json_and_table(records, tmp_path, gearsim_here):
    """The same two files (two channels each) with --stages: serially and on a local
    cluster of 2 workers, the JSON (but the timings and the run mode) and the CSV table
    are identical, and both hold stage 2."""
    common = ["analyze", *records, "--shaft-rpm", 1800, "--stages", STAGES_TEXT, "--json"]
    code, serial, err = _cli(gearsim_here, *common, "--out", tmp_path / "serial.csv")
    assert code == 0, err
    code, dask, err = _cli(gearsim_here, *common, "--out", tmp_path / "dask.csv",
                           "--workers", 2)
    assert code == 0, err
    a, b = json.loads(serial), json.loads(dask)
    assert a["mode"] == "serial" and b["mode"].startswith("dask local")
    assert _without_timings(a["records"]) == _without_timings(b["records"])
    assert (tmp_path / "serial.csv").read_text() == (tmp_path / "dask.csv").read_text()
    assert len(a["records"]) == 4
    for rec in a["records"]:
        assert rec["stages"] == [[32, 80], [48, 64]] and rec["teeth"] == [32, 80, 48, 64]
        g = rec["tiers"]["gear"]["analysis"]
        assert [s["mesh_frequency_hz"] for s in g["stages"]] == pytest.approx([960.0, 576.0])
        assert [x["shaft"] for x in rec["tiers"]["gear"]["gears"]] == ["shaft2", "shaft3"]
        assert not any(s["tier"].startswith("gear") for s in rec["skipped"]
                       if s["tier"] != "gear.indicators.nb4")
    header = (tmp_path / "serial.csv").read_text().splitlines()[0].split(",")
    assert "stage2_mesh_frequency_hz [Hz]" in header
    assert "stage2_mesh_amplitude_o1 [signal]" in header
    assert "stage2_sb_ser_o1_shaft3 [1]" in header


def test_text_has_a_line_per_stage_serial_and_on_workers(records, gearsim_here):
    """The text of records analysed here and of those sent back by workers as dicts (two
    files for two workers: more workers than files is refused)."""
    common = ["analyze", *records, "--channel", "a1", "--shaft-rpm", 1800,
              "--stages", STAGES_TEXT]
    code, serial, err = _cli(gearsim_here, *common)
    assert code == 0, err
    code, dask, err = _cli(gearsim_here, *common, "--workers", 2)
    assert code == 0, err
    assert serial == dask
    assert "rests on: fs 12800 Hz (file); speed 1800 rpm = 30 Hz (given); stages 32/80, " \
           "48/64 (given)" in serial
    assert "f_m 960 Hz (stage 1, 32/80)" in serial
    assert "gear stage 2 (48/64): f_m 576 Hz, shafts shaft2 12 Hz, shaft3 9 Hz" in serial
    amp = re.search(r"\n      1 f_m 576 Hz  A (\S+)  SER shaft2 \S+  shaft3 ", serial)
    assert float(amp.group(1)) == pytest.approx(0.5, rel=0.01)  # stage 2's fundamental


def test_table_columns_are_the_study_features_of_stage_2(records):
    """The batch table's stage-k columns are named and valued as the study features
    (one flattening, gearsim.signals.tiers.stage_features), and the record analysed
    with its stages equals analyze(stages=) of the same samples."""
    ds = run_batch([str(records[1])], channels=["a1"], speed=30.0, stages=STAGES)
    ref = analyze(np.loadtxt(records[1], delimiter=",", skiprows=2)[:, 0], FS,
                  stages=STAGES, shaft_frequency=30.0)
    feats = features(ref.to_dict())
    stage2 = {k: v for k, v in feats.items() if k.startswith("stage2_")}
    assert len(stage2) == 4 * (1 + 2 * 3 + 3)  # 4 orders: amplitude, 2 shafts x 3, 3 bands
    assert set(stage2) <= set(ds.data_vars)
    for k, v in stage2.items():
        assert float(ds[k].values[0]) == pytest.approx(v, rel=1e-12, nan_ok=True), k
    assert ds["stage2_mesh_amplitude_o1"].attrs["units"] == "signal"
    assert ds["stage2_band_energy_o1"].attrs["units"] == "signal^2"
    assert float(ds["stage2_mesh_amplitude_o1"].values[0]) == pytest.approx(0.8, rel=0.02)
    assert float(ds["mesh1_amplitude"].values[0]) == pytest.approx(1.0, rel=0.02)
    assert set(stage_features(ref.to_dict())) == set(stage2)


def test_a_stage_the_record_cannot_resolve_keeps_stage_1(records):
    """A record too short for the sidebands of stage 2's slow output shaft: the gear tier
    is stage 1's pair, with the reason as the skipped tier gear.stages."""
    x = _record(3, 0.5)[:6400]  # 0.5 s; a 48/200 stage 2 turns shaft 3 at 2.88 Hz
    rec = analyze_record(x, FS, speed=30.0, stages=((32, 80), (48, 200)))
    assert "gear" in rec.tiers and rec.stages is None and rec.teeth == (32, 80)
    skip = [s for s in rec.skipped if s["tier"] == "gear.stages"]
    assert len(skip) == 1 and "2.88 Hz (shaft shaft3)" in skip[0]["reason"]
    assert "stages" not in rec.tiers["gear"]["analysis"]
    assert not any(k.startswith("stage2_") for k in rec.features())


def test_teeth_and_stages_together_refused():
    from gearsim.errors import InputError

    with pytest.raises(InputError, match="teeth/stages"):
        analyze_record(_record(0, 0.5), FS, speed=30.0, teeth=(32, 80), stages=STAGES)
