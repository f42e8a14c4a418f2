"""Compound (multi-stage parallel-shaft) trains in the signal analysis (issues 23, 24).

A compound train is given as stages (driving teeth, driven teeth): shaft k + 1 turns at
f_k z_k^d / z_k^n and stage k meshes at f_k z_k^d. The simple-train convention (one mesh
frequency f_r1 Z_1, shaft j at f_m / Z_j) puts the two-stage reducer's intermediate pinion
at 20 Hz and never looks at the second mesh; these tests pin the stage kinematics, the
lines of every stage on a synthetic and a simulated record, the unchanged simple-train
output, the CLI's ``--stages`` refusals and one real SpectraQuest record.
"""

import functools
import hashlib
import json
import math
from pathlib import Path

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import InputError
from gearsim.model.config import example_text
from gearsim.signals.analysis import analyze, kinematics
from gearsim.signals.sidebands import sideband_spacing
from gearsim.studies.sweep_case import features

STAGES = ((32, 80), (48, 64))
#: The SpectraQuest records, read where tests/signals/test_records_real.py reads them.
DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "spectraquest-gfd"


def test_kinematics_of_two_stages_by_hand():
    kin = kinematics(shaft_frequency=30.0, stages=STAGES)
    # shaft2 = 30 x 32/80 = 12 Hz, shaft3 = 12 x 48/64 = 9 Hz; f_m1 = 30 x 32, f_m2 = 12 x 48
    assert kin.shafts == pytest.approx({"shaft1": 30.0, "shaft2": 12.0, "shaft3": 9.0},
                                       rel=1e-15)
    assert [s.mesh_frequency for s in kin.stages] == pytest.approx([960.0, 576.0], rel=1e-15)
    assert [s.shafts for s in kin.stages] == [("shaft1", "shaft2"), ("shaft2", "shaft3")]
    assert kin.mesh_frequency == 960.0 and kin.teeth == (32, 80, 48, 64) and kin.compound
    assert kin.reference_frequency == 30.0
    # the simple-train reading of the same teeth: the old mistake (shaft3 at 960/48 = 20 Hz)
    old = kinematics(shaft_frequency=30.0, teeth=[32, 80, 48, 64])
    assert old.shafts["shaft3"] == pytest.approx(20.0) and not old.compound


@pytest.mark.parametrize("bad", [(), [(32,)], [(32, 0)], [(32, 80), (48, -64)], "32/80",
                                 [(32.5, 80)]])
def test_kinematics_refuses_bad_stages(bad):
    with pytest.raises(InputError, match="stages"):
        kinematics(shaft_frequency=30.0, stages=bad)


def test_kinematics_needs_exactly_one_of_teeth_and_stages():
    with pytest.raises(InputError, match="teeth/stages"):
        kinematics(shaft_frequency=30.0, teeth=[32, 80], stages=STAGES)
    with pytest.raises(InputError, match="teeth/stages"):
        kinematics(shaft_frequency=30.0)


# ----------------------------------------------------------------- synthetic record
FS, T = 12800.0, 4.0  # df = 0.25 Hz: every line below sits on a bin
#: (mesh frequency, mesh amplitude, {shaft frequency: modulation index}) of each stage;
#: additive modulation A (1 + sum m cos 2 pi f t) cos 2 pi f_m t puts A m / 2 at f_m +- f.
TONES = ((960.0, 1.0, {30.0: 0.2, 12.0: 0.1}), (576.0, 0.6, {12.0: 0.3, 9.0: 0.1}))
NOISE = 0.01


def _two_mesh_record():
    t = np.arange(int(FS * T)) / FS
    x = np.zeros_like(t)
    for f_m, amp, mods in TONES:
        env = 1.0 + sum(m * np.cos(2 * np.pi * f * t) for f, m in mods.items())
        x += amp * env * np.cos(2 * np.pi * f_m * t)
    return x + NOISE * np.random.default_rng(7).standard_normal(t.size)


def test_synthetic_two_mesh_record_both_families_found():
    x = _two_mesh_record()
    a = analyze(x, FS, stages=STAGES, shaft_frequency=30.0)
    assert len(a.stages) == 2
    # Tolerance 5 % of each sideband amplitude (the smallest is 0.6 x 0.1 / 2 = 0.03, so
    # 1.5e-3): the white noise of std 0.01 gives a Hann bin of this 51200-sample record an
    # amplitude of about 2 x 0.01 x sqrt(1.5 / 51200) = 1.1e-4 rms, more than ten times
    # smaller; the lines sit on bins, so there is no scalloping or leakage beyond +-1 bin.
    for sl, (f_m, amp, mods) in zip(a.stages, TONES, strict=True):
        assert sl.stage.mesh_frequency == pytest.approx(f_m, rel=1e-12)
        h1 = sl.harmonics[0]
        assert h1.frequency == pytest.approx(f_m, abs=0.125)
        assert h1.amplitude == pytest.approx(amp, rel=0.01)
        fams = {f.shaft_frequency: f for f in sl.families if f.order == 1}
        assert sorted(fams) == pytest.approx(sorted(mods))  # the two shafts of the mesh
        for f_r, m in mods.items():
            fam = next(v for k, v in fams.items() if math.isclose(k, f_r))
            k1 = np.abs(fam.k) == 1
            np.testing.assert_allclose(fam.frequency[k1], [f_m - f_r, f_m + f_r])
            np.testing.assert_allclose(fam.amplitude[k1], amp * m / 2, rtol=0.05)
            assert fam.ser == pytest.approx(amp * m / amp, rel=0.05, abs=6 * 0.002 / amp)
    d = a.to_dict()
    assert [s["mesh_frequency_hz"] for s in d["train"]["stages"]] == pytest.approx([960, 576])
    assert [s["shafts"] for s in d["stages"]] == [["shaft1", "shaft2"], ["shaft2", "shaft3"]]
    json.dumps(d, allow_nan=True)
    # the flat features: stage 1 under the simple names, stage 2 prefixed
    feats = features(d)
    assert "sb_ser_o1_shaft1" in feats and "sb_ser_o1_shaft3" not in feats
    assert feats["stage2_sb_ser_o1_shaft3"] == pytest.approx(
        next(f.ser for f in a.stages[1].families if f.order == 1 and f.shaft == "shaft3"))
    assert feats["stage2_mesh_amplitude_o1"] == pytest.approx(0.6, rel=0.01)
    assert {"stage2_band_energy_o1", "stage2_band_cv_o1", "stage2_band_modulation_o1"} <= set(
        feats)


def test_synthetic_record_with_teeth_misses_the_second_mesh():
    """The old reading (teeth=[32, 80, 48, 64]): one mesh frequency, shafts 30, 12, 20 and
    15 Hz; nothing is measured at 576 Hz or with the 9 Hz spacing of the output shaft."""
    a = analyze(_two_mesh_record(), FS, teeth=[32, 80, 48, 64], shaft_frequency=30.0)
    assert not a.stages and "stages" not in a.to_dict()
    assert a.kinematics.mesh_frequency == 960.0
    assert all(abs(n * 960.0 - 576.0) > 100.0 for n in a.orders)  # no harmonic near f_m2
    assert a.harmonics[0].amplitude == pytest.approx(1.0, rel=0.01)
    assert all(not math.isclose(f.shaft_frequency, 9.0) for f in a.families)
    assert all(np.all(np.abs(f.frequency - 576.0) > 9.0) for f in a.families)


# ----------------------------------------------------------------- simulated reducer
@functools.cache
def _reducer_run(gear: int):
    """1 s of the two-stage reducer at 20 kHz with a 10 um runout on gear ``gear``."""
    runout = [0.0] * 4
    runout[gear] = 10e-6
    return gs.simulate(gs.example("two-stage-reducer"), duration=1.0, fs=20e3,
                       runout=tuple(runout))


@pytest.mark.parametrize(("gear", "shaft"), [(2, "shaft2"), (3, "shaft3")])
def test_simulated_two_stage_reducer(gear, shaft):
    """The reducer with a runout (10 um) on the intermediate pinion (gear 2, turning with
    the intermediate shaft) or on the output gear (gear 3): mesh force II."""
    gb = gs.example("two-stage-reducer")
    stages = gb.analysis_stages()
    assert stages == STAGES
    _, f_in, teeth = gb.reference()
    assert teeth == [32, 80, 48, 64]  # reference() as before
    f_int = f_in * stages[0][0] / stages[0][1]
    f_out = f_int * stages[1][0] / stages[1][1]
    f_m2 = f_int * stages[1][0]
    fs = 20e3
    run = _reducer_run(gear)
    a = gs.analyze(run["mesh_force_2"], fs, gearbox=gb, orders=(1, 2, 3, 4, 5, 6))
    assert [s.stage.mesh_frequency for s in a.stages] == pytest.approx([f_in * 32, f_m2])
    assert a.kinematics.shafts == pytest.approx(
        {"shaft1": f_in, "shaft2": f_int, "shaft3": f_out})
    # the stage-2 mesh harmonics are found at n f_m2 and hold the largest lines: of the 5
    # largest spectral peaks above 100 Hz at least 3 are harmonics of f_m2 that are not
    # harmonics of f_m1 (2880 Hz is both), the largest of all a harmonic of f_m2 (6 f_m2
    # on the path-only tables, 5 f_m2 = 2880 Hz with the tip-corner contacts: which
    # harmonic a resonance lifts follows the mesh stiffness model)
    sl = a.stages[1]
    for n, h in zip(a.orders, sl.harmonics, strict=True):
        assert h.frequency == pytest.approx(n * f_m2, abs=0.5 * a.spectrum.df)
    from scipy.signal import find_peaks

    sp = a.spectrum
    pk, _ = find_peaks(sp.amplitude)
    pk = pk[sp.frequency[pk] > 100.0]
    top = sp.frequency[pk[np.argsort(sp.amplitude[pk])[::-1][:5]]]

    def harmonic_of(f, base):
        return abs(f / base - round(f / base)) < 0.5 * sp.df / base

    only2 = [f for f in top if harmonic_of(f, f_m2) and not harmonic_of(f, f_in * 32)]
    assert len(only2) >= 3, top
    assert harmonic_of(top[0], f_m2), top
    # the sidebands of the stage-2 harmonics are spaced at the shaft of the gear with the
    # runout (measured: the most common spacing of the strongest lines)
    f_exp = {"shaft2": f_int, "shaft3": f_out}[shaft]
    for n in (3, 4, 6):
        spacing = sideband_spacing(sp, center=n * f_m2, shaft_frequency=f_int, n_sidebands=3)
        assert spacing == pytest.approx(f_exp, abs=sp.df), (n, spacing)
    # the stage-2 family of that shaft: first sidebands well above the others of the family
    for fam in sl.families:
        if fam.shaft == shaft and fam.order in (3, 4, 6):
            k1 = np.abs(fam.k) == 1
            assert np.min(fam.amplitude[k1]) > 20 * np.median(fam.amplitude[~k1])
    # the simple reading of the same teeth knows no 9 Hz shaft and no line at f_m2
    old = gs.analyze(run["mesh_force_2"], fs, teeth=teeth, shaft_frequency=f_in,
                     settings=gb.analysis)
    assert all(not math.isclose(f, f_out) for f in old.kinematics.shafts.values())
    assert all(abs(h.frequency - f_m2) > 100.0 for h in old.harmonics)


def test_cli_analyses_a_compound_result_by_its_stages(tmp_path, gearsim_here):
    """gearsim analyze of a simulated reducer needs no --stages: its configuration gives
    them (and its input speed the reference shaft's)."""
    from gearsim.io.results import write_results

    nc = write_results(_reducer_run(2), tmp_path / "reducer.nc")
    code, out, err = _cli(gearsim_here, "analyze", nc, "--channel", "mesh_force_2",
                          "--json")
    assert code == 0, err
    rec = json.loads(out)["records"][0]
    assert rec["teeth"] == [32, 80, 48, 64] and rec["teeth_provenance"] == "file"
    g = rec["tiers"]["gear"]["analysis"]
    f_in = gs.example("two-stage-reducer").reference()[1]
    assert [s["mesh_frequency_hz"] for s in g["stages"]] == pytest.approx(
        [f_in * 32, f_in * 32 / 80 * 48])
    assert g["train"]["shaft_frequencies_hz"]["shaft3"] == pytest.approx(f_in * 0.4 * 0.75)


# ----------------------------------------------------------------- simple trains unchanged
def _simple_record():
    fs = 20000.0
    t = np.arange(int(fs * 1.0)) / fs
    rng = np.random.default_rng(3)
    x = ((1 + 0.3 * np.cos(2 * np.pi * 30 * t)) * np.cos(2 * np.pi * 570 * t)
         + 0.2 * np.cos(2 * np.pi * 1140 * t + 0.3) + 0.05 * rng.standard_normal(t.size))
    return x, fs, {"teeth": [19, 48], "shaft_frequency": 30.0}


def _rounded(v):
    if isinstance(v, float):
        return float(f"{v:.9g}") if math.isfinite(v) else str(v)
    if isinstance(v, dict):
        return {k: _rounded(u) for k, u in v.items()}
    if isinstance(v, list):
        return [_rounded(u) for u in v]
    return v


def _digest(summary: dict) -> str:
    """sha256 of the JSON summary without timings and version, floats to 9 digits."""
    d = {k: v for k, v in summary.items() if k not in ("timings_s", "gearsim_version")}
    return hashlib.sha256(json.dumps(_rounded(d), sort_keys=True).encode()).hexdigest()


#: _digest of the 19/48 record's analysis by the code before compound trains (commit
#: 61dde14, computed once from that version of gearsim/signals/analysis.py).
SIMPLE_DIGEST = "a2f8056bc146c43db0af06c05d09dddb8a5f4a154942f760f89265fe6ebaff6f"


def test_simple_train_summary_as_before():
    x, fs, kw = _simple_record()
    assert _digest(analyze(x, fs, **kw).to_dict()) == SIMPLE_DIGEST


@pytest.mark.parametrize("name", ["idler-table1", "spur-19-48"])
def test_simple_gearboxes_analysed_as_before(name):
    gb = gs.example(name)
    assert gb.analysis_stages() is None
    _, f_r, teeth = gb.reference()
    fs = float(gb.dynamics.fs)
    t = np.arange(int(fs)) / fs
    f_m = f_r * teeth[0]
    x = (1 + 0.2 * np.cos(2 * np.pi * f_r * t)) * np.cos(2 * np.pi * f_m * t)
    x += 0.01 * np.random.default_rng(5).standard_normal(t.size)
    a = gs.analyze(x, fs, gearbox=gb).to_dict()
    b = analyze(x, fs, teeth=teeth, shaft_frequency=f_r, settings=gb.analysis).to_dict()
    a.pop("timings_s"), b.pop("timings_s")
    assert json.dumps(a) == json.dumps(b)
    assert "stages" not in a and "stages" not in a["train"]
    assert not any(k.startswith("stage") for k in features(a))


# ----------------------------------------------------------------- CLI
def _cli(gearsim_here, *args):
    """``gearsim *args`` in this process (conftest's ``gearsim_here``): status, out, err."""
    r = gearsim_here(*args)
    return r.returncode, r.stdout, r.stderr


@pytest.fixture(scope="module")
def record_csv(tmp_path_factory):
    p = tmp_path_factory.mktemp("rec") / "rec.csv"
    np.savetxt(p, _two_mesh_record()[:25600], delimiter=",", header="a1", comments="")
    return p


@pytest.mark.parametrize(("value", "pattern"), [
    ("32/80,48", "--stages = 32/80,48: stage 2 (48) is not DRIVING/DRIVEN"),
    ("32/0,48/64", "--stages = 32/0,48/64: stage 1 (32/0): tooth counts must be integers in "
                   "[1, 1000]"),
    ("32/80,-48/64", "--stages = 32/80,-48/64: stage 2 (-48/64): tooth counts must be "
                     "integers in [1, 1000]"),
    ("32.5/80", "--stages = 32.5/80: stage 1 (32.5/80): tooth counts must be integers in "
                "[1, 1000]"),
    ("32/80,48/5000", "--stages = 32/80,48/5000: stage 2 (48/5000): tooth counts must be "
                      "integers in [1, 1000]"),
    ("32/80,,48/64", "--stages = 32/80,,48/64: stage 2 (empty) is not DRIVING/DRIVEN"),
])
def test_cli_refuses_bad_stages(record_csv, value, pattern, gearsim_here):
    code, _, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS,
                        "--shaft-rpm", 1800, f"--stages={value}")
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gearsim: error: "), err
    assert pattern in lines[0] and "e.g. --stages 32/80,48/64" in lines[0], lines[0]


@pytest.mark.parametrize("value", ["1e300", "0", "-32", "2000", "nan", "32.5"])
def test_cli_refuses_teeth_no_gear_has(record_csv, gearsim_here, value):
    """--teeth out of [1, 1000] or not an integer: one line naming --teeth, before any
    file is read."""
    code, _, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--shaft-rpm", 1800,
                        "--teeth", f"32,{value}")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert lines[0].startswith(f"gearsim: error: --teeth = 32 {value}: must be integers in "
                               "[1, 1000]"), lines[0]


def test_cli_refuses_teeth_with_stages(record_csv, gearsim_here):
    code, _, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS,
                        "--shaft-rpm", 1800, "--teeth", 32, 80, "--stages", "32/80,48/64")
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "--teeth/--stages = 32 80 / 32/80,48/64: give one" in lines[0]


def test_cli_analyses_every_stage(record_csv, gearsim_here):
    code, out, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS,
                          "--shaft-rpm", 1800, "--stages", "32/80,48/64", "--json")
    assert code == 0, err
    rec = json.loads(out)["records"][0]
    assert rec["teeth"] == [32, 80, 48, 64]
    g = rec["tiers"]["gear"]["analysis"]
    assert [s["mesh_frequency_hz"] for s in g["stages"]] == pytest.approx([960.0, 576.0])
    assert g["stages"][1]["mesh_harmonics"][0]["amplitude"] == pytest.approx(0.6, rel=0.02)
    code, out, _ = _cli(gearsim_here, "analyze", record_csv, "--fs", FS,
                        "--shaft-rpm", 1800, "--stages", "32/80,48/64")
    assert code == 0 and "gear stage 2 (48/64): f_m 576 Hz" in out


# ----------------------------------------------------------------- a real record
@pytest.mark.skipif(not (DATA / "h30hz0.csv.gz").exists(),
                    reason=f"the SpectraQuest record h30hz0 (OpenEI Gearbox Fault Diagnosis "
                           f"Data) is not in {DATA}")
def test_spectraquest_record_second_mesh(gearsim_here):
    """A 30 Hz healthy record, rate 12.8 kHz as given (not documented: the source's
    estimate is about 12.9 kHz) and the speed searched: the stage-2 line lies at
    f_r1 x 32/80 x 48 of the estimated speed, within two bins (the tone is interpolated;
    a bin is 12800/88832 = 0.14 Hz), and near 576 Hz within 2 % (the estimated speed
    carries the rate's uncertainty, 12800 Hz against about 12.9 kHz: 0.8 %)."""
    code, out, err = _cli(gearsim_here, "analyze", DATA / "h30hz0.csv.gz", "--channel",
                          "a1", "--fs", 12800, "--speed-search", "25,35", "--stages",
                          "32/80,48/64", "--json")
    assert code == 0, err
    rec = json.loads(out)["records"][0]
    g = rec["tiers"]["gear"]["analysis"]
    f_r = rec["speed_hz"]
    s2 = g["stages"][1]
    assert s2["mesh_frequency_hz"] == pytest.approx(f_r * 32 / 80 * 48, rel=1e-12)
    h1 = s2["mesh_harmonics"][0]
    df = 12800 / rec["n_samples"]
    assert h1["frequency_hz"] == pytest.approx(f_r * 32 / 80 * 48, abs=2 * df)
    assert h1["frequency_hz"] == pytest.approx(30 * 32 / 80 * 48, rel=0.02)
    # a line, not the floor: above 4 x the median amplitude within +-60 Hz
    from gearsim.io.measured import read_signal
    from gearsim.signals.spectrum import amplitude_spectrum

    sp = amplitude_spectrum(read_signal(DATA / "h30hz0.csv.gz", channel="a1", fs=12800).data,
                            12800.0)
    floor = np.median(sp.amplitude[np.abs(sp.frequency - h1["frequency_hz"]) < 60.0])
    assert h1["amplitude"] > 4 * floor


def test_study_case_of_the_reducer_has_stage_features():
    """A study of the two-stage reducer analyses both meshes (sweep_case.run_group): stage
    1's features under the simple names with its two shafts, stage 2's prefixed."""
    from gearsim.studies.sweep import expand, loads_study
    from gearsim.studies.sweep_case import run_group

    study = loads_study("""
[study]
name = "compound"
config = "two-stage-reducer"
replicates = 1
seed = 3
signal = "mesh_force_2"
shafts = "all"
[study.dynamics]
duration = "0.6 s"
fs = "20 kHz"
[parameters]
flank = ["none"]
noise = [0.0]
""")
    ds = run_group(study, expand(study)[:1])
    assert list(ds["status"].values) == ["ok"], ds["error"].values
    names = set(ds.data_vars)
    assert {"sb_ser_o1_shaft1", "sb_ser_o1_shaft2", "stage2_sb_ser_o1_shaft2",
            "stage2_sb_ser_o1_shaft3", "stage2_band_energy_o1"} <= names
    assert "sb_ser_o1_shaft3" not in names and "sb_ser_o1_shaft4" not in names
    # mesh force II: the stage-2 fundamental is larger than stage 1's
    assert float(ds["stage2_mesh_amplitude_o1"][0]) > float(ds["mesh_amplitude_o1"][0])


# ----------------------------------------------------------------- results files
@pytest.mark.parametrize("name, stages", [
    ("idler-table1", None),        # 39/59/125 through an idler: one mesh frequency
    ("spur-19-48", None),          # one mesh
    ("two-stage-reducer", ((32, 80), (48, 64))),
])
def test_train_stages_of_the_examples(name, stages):
    """The stages a run stores (GearTrain.compound_stages) and the gearbox's, against the
    examples' layouts."""
    gb = gs.example(name)
    assert gb.train.compound_stages() == gb.analysis_stages() == stages


def _result_without(tmp_path, name: str, *attrs: str) -> Path:
    """The reducer's result written with ``attrs`` removed (e.g. one of before the
    ``analysis_stages`` attribute)."""
    from gearsim.io.results import write_results

    ds = _reducer_run(2).copy()
    ds.attrs = {k: v for k, v in ds.attrs.items() if k not in attrs}
    return write_results(ds, tmp_path / name)


def test_result_stores_its_stages_and_analyze_prefers_them(tmp_path, gearsim_here):
    """A compound train's result carries analysis_stages "32/80,48/64" (beside the first
    pair's analysis_teeth); gearsim analyze reads it without the configuration, and a
    result of before (configuration only) still gives the stages; so does the result
    compressed (the reader passes the attribute on, the file is read once)."""
    import gzip
    import shutil

    from gearsim.io.measured import read_record

    ds = _reducer_run(2)
    assert ds.attrs["analysis_stages"] == "32/80,48/64"
    assert list(ds.attrs["analysis_teeth"]) == [32, 80]
    only_attr = _result_without(tmp_path, "attr.nc", "config")
    only_config = _result_without(tmp_path, "config.nc", "analysis_stages")
    neither = _result_without(tmp_path, "neither.nc", "config", "analysis_stages")
    packed = tmp_path / "attr.nc.gz"
    with open(only_attr, "rb") as src, gzip.open(packed, "wb") as dst:
        shutil.copyfileobj(src, dst)
    assert read_record(only_attr).metadata["stages"] == STAGES
    meta = read_record(only_config).metadata
    assert "stages" not in meta and isinstance(meta["config"], str)
    assert not {"stages", "config"} & set(read_record(neither).metadata)
    f_in = gs.example("two-stage-reducer").reference()[1]
    for nc in (only_attr, only_config, packed):
        code, out, err = _cli(gearsim_here, "analyze", nc, "--channel",
                              "mesh_force_2", "--json")
        assert code == 0, err
        rec = json.loads(out)["records"][0]
        assert rec["stages"] == [[32, 80], [48, 64]] and rec["teeth_provenance"] == "file"
        g = rec["tiers"]["gear"]["analysis"]
        assert [s["mesh_frequency_hz"] for s in g["stages"]] == pytest.approx(
            [f_in * 32, f_in * 32 / 80 * 48])
    code, out, err = _cli(gearsim_here, "analyze", neither, "--channel",
                          "mesh_force_2", "--json")
    assert code == 0, err
    rec = json.loads(out)["records"][0]  # the first pair, as a simple train
    assert rec["teeth"] == [32, 80] and "stages" not in rec


# ----------------------------------------------------------------- a real batch
def _four_records():
    """The four 30 Hz SpectraQuest records where tests/signals/test_records_real.py finds
    them (its path), or None when one is absent."""
    from test_records_real import DATA as SQ
    from test_records_real import FOUR

    paths = [SQ / f"{name}.csv.gz" for name in FOUR]
    return paths if all(p.is_file() for p in paths) else None


@pytest.mark.skipif(_four_records() is None,
                    reason="the SpectraQuest records h30hz0, h30hz90, b30hz0, b30hz90 "
                           "(OpenEI Gearbox Fault Diagnosis Data) are not in the shared "
                           "data folder")
def test_spectraquest_batch_of_four_has_stage_2(tmp_path, gearsim_here):
    """A batch of the four 30 Hz records (healthy and broken tooth, loads 0 and 90 %),
    rate 12.8 kHz, speed searched in 20-40 Hz, stages 32/80,48/64: the table has stage-2
    columns, and in every file and channel the stage-2 fundamental lies within 1 % of
    the speed estimate x 32/80 x 48 (measured: within 0.35 %; read in the order domain of
    the tracked speed). Stage-2 / stage-1 fundamental amplitude over the 8 channels of
    each: healthy 0.05-0.42 (median 0.21), broken 0.05-0.27 (median 0.13); the broken
    tooth's records have the larger stage-1 fundamental (mean 1.35 against 1.04) and the
    smaller stage-2 one (0.175 against 0.195)."""
    paths = _four_records()
    table = tmp_path / "table.csv"
    code, out, err = _cli(gearsim_here, "analyze", *paths, "--fs", 12800,
                          "--speed-search", "20,40", "--stages", "32/80,48/64",
                          "--out", table, "--json")
    assert code == 0, err
    records = json.loads(out)["records"]
    assert {Path(r["source"]["file"]).name for r in records} == {p.name for p in paths}
    with table.open() as fh:
        import csv

        rows = list(csv.DictReader(fh))
    assert len(rows) == len(records) == 16
    for r, row in zip(records, rows, strict=True):
        assert r["speed_provenance"] == "estimate" and r["stages"] == [[32, 80], [48, 64]]
        predicted = r["speed_hz"] * 32 / 80 * 48
        s2 = r["tiers"]["gear"]["analysis"]["stages"][1]
        h1 = s2["mesh_harmonics"][0]
        assert h1["frequency_hz"] == pytest.approx(predicted, rel=0.01), r["source"]
        assert float(row["stage2_mesh_frequency_hz [Hz]"]) == pytest.approx(predicted,
                                                                           rel=1e-9)
        assert float(row["stage2_mesh_amplitude_o1 [signal]"]) == pytest.approx(
            h1["amplitude"], rel=1e-9)
        assert row["stage2_sb_ser_o1_shaft3 [1]"] != ""


# ------------------------------------------------------- the gearbox measured: --config
def _without(rec: dict) -> dict:
    """A record's JSON without what differs between two spellings of one analysis: its
    timings and the provenance labels."""
    text = json.dumps({k: v for k, v in rec.items() if k != "timings_s"})
    out = json.loads(text.replace('"config"', '"given"'))
    out["tiers"].get("gear", {}).get("analysis", {}).pop("timings_s", None)
    return out


def test_config_brings_the_reducers_stages_and_speed(record_csv, gearsim_here):
    """The synthetic record is the reducer at its configured 1800 rpm (960 and 576 Hz):
    --config two-stage-reducer analyses it at that speed and with its stages, labelled
    (config), and with the speed given it is the analysis of --stages 32/80,48/64."""
    code, out, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--config",
                          "two-stage-reducer", "--json")
    assert code == 0, err
    mine = json.loads(out)["records"][0]
    assert (mine["speed_provenance"], mine["teeth_provenance"]) == ("config", "config")
    assert mine["speed_hz"] == pytest.approx(30.0, rel=1e-15)  # 1800 rpm through rad/s
    assert mine["stages"] == [[32, 80], [48, 64]]
    assert [s["mesh_frequency_hz"] for s in mine["tiers"]["gear"]["analysis"]["stages"]] \
        == pytest.approx([960.0, 576.0], rel=1e-12)
    runs = [_cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--shaft-rpm", 1800, *how,
                 "--json") for how in (("--config", "two-stage-reducer"),
                                       ("--stages", "32/80,48/64"))]
    assert [r[0] for r in runs] == [0, 0], runs[0][2] + runs[1][2]
    a, b = (json.loads(r[1])["records"][0] for r in runs)
    assert a["teeth_provenance"] == "config" and a["speed_provenance"] == "given"
    assert _without(a) == _without(b)


def test_config_of_a_lone_stage_brings_its_stage_and_carrier_speed(record_csv, gearsim_here):
    """nrel-grc (21/39/99 x 3, ring held, carrier 22.1 rpm): the planetary tier of
    --stage 21,39,99,3 at the carrier speed."""
    code, out, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--config",
                          "nrel-grc", "--json")
    assert code == 0, err
    mine = json.loads(out)["records"][0]
    assert mine["tiers"]["planetary"]["rests_on"]["stage"] == "config"
    assert mine["speed_hz"] == pytest.approx(22.1 / 60, rel=1e-14)
    runs = [_cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--shaft-rpm", 22.1, *how,
                 "--json") for how in (("--config", "nrel-grc"), ("--stage", "21,39,99,3"))]
    assert [r[0] for r in runs] == [0, 0], runs[0][2] + runs[1][2]
    a, b = (json.loads(r[1])["records"][0] for r in runs)
    assert _without(a) == _without(b)


@pytest.mark.parametrize(("args", "words"), [
    (("--config", "wind-turbine-grc"), "--config = wind-turbine-grc: the records of a "
     "gearbox with a planetary stage and other parts"),
    (("--config", "two-stage-reducer", "--teeth", "32"), "--config/--teeth = "
     "two-stage-reducer / ...: give one"),
    (("--config", "no-such-box"), "no-such-box"),
])
def test_config_refusals(record_csv, gearsim_here, args, words):
    code, _, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS, *args)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert words in lines[0], lines[0]


@pytest.mark.skipif(not (DATA / "b30hz90.csv.gz").exists(),
                    reason=f"the SpectraQuest record b30hz90 (OpenEI Gearbox Fault Diagnosis "
                           f"Data) is not in {DATA}")
def test_a_real_record_of_the_rig_analysed_with_its_gearbox(gearsim_here):
    """The rig's broken-tooth record at 90 % load, 12.8 kHz, speed searched: --config
    two-stage-reducer gives every feature of --stages 32/80,48/64."""
    base = ("analyze", DATA / "b30hz90.csv.gz", "--channel", "a1", "--fs", 12800,
            "--speed-search", "20,40", "--json")
    code, out, err = _cli(gearsim_here, *base, "--config", "two-stage-reducer")
    assert code == 0, err
    mine = json.loads(out)["records"][0]
    code, out, err = _cli(gearsim_here, *base, "--stages", "32/80,48/64")
    assert code == 0, err
    assert _without(mine) == _without(json.loads(out)["records"][0])
    assert mine["stages"] == [[32, 80], [48, 64]]


#: The stage's speeds reach the two analyses through different products of tooth ratios
#: (25 x 23/71 here, the kinematics' own there): a last-bit difference in f_m moves the
#: band edges by that much.
ROUTE_RTOL = 1e-9


def test_a_slow_further_stage_is_banded_as_its_own_pair():
    """Three stages 23/71, 19/67, 17/59 at 25 Hz: mesh II at 153.9 Hz, mesh III at 39 Hz.
    Frames sized by the input shaft (4 a revolution: 100 Hz bins) held under two bins
    around 2 x 153.9 Hz and the whole analysis was refused; each further stage's band
    energy, widths and modulation are now those of the stage analysed alone as a pair at
    its own driving shaft's speed (to ROUTE_RTOL)."""
    fs, f1 = 20_000.0, 25.0
    stages = ((23, 71), (19, 67), (17, 59))
    t = np.arange(int(6.2 * fs)) / fs  # 4 Hann bins per 0.66 Hz: the output's sidebands
    f_shaft, x = f1, np.zeros_like(t)
    for zd, zn in stages:  # each mesh modulated by its driving shaft
        x += (1 + 0.3 * np.cos(2 * np.pi * f_shaft * t)) * np.cos(2 * np.pi * zd * f_shaft * t)
        f_shaft *= zd / zn
    x += 0.01 * np.random.default_rng(3).standard_normal(t.size)
    whole = analyze(x, fs, stages=stages, shaft_frequency=f1)
    f_shaft = f1
    for k, (zd, zn) in enumerate(stages):
        alone = analyze(x, fs, stages=((zd, zn),), shaft_frequency=f_shaft).stages[0]
        mine = whole.stages[k]
        for name in ("band_energy", "band_width_spectrum", "band_width_stft",
                     "band_modulation"):
            got, want = getattr(mine, name), getattr(alone, name)
            assert got.keys() == want.keys()
            for n in got:
                np.testing.assert_allclose(got[n], want[n], rtol=ROUTE_RTOL,
                                           err_msg=f"{k} {name} {n}")
        f_shaft *= zd / zn
    assert whole.stages[1].band_modulation[1] > 0.3  # the 0.3 AM of stage 2's shaft


@pytest.mark.parametrize("teeth", ["1e300", "inf", "0", "-32", "nan"])
def test_a_bad_config_is_refused_before_any_record_is_read(record_csv, gearsim_here,
                                                           tmp_path, teeth):
    """--config of a file with an impossible tooth count: one line naming the file's
    key, exit 2, no table written."""
    text = example_text("two-stage-reducer").replace("teeth = 32\n", f"teeth = {teeth}\n", 1)
    assert f"teeth = {teeth}\n" in text
    box = tmp_path / "box.toml"
    box.write_text(text)
    out = tmp_path / "t.csv"
    code, _, err = _cli(gearsim_here, "analyze", record_csv, "--fs", FS, "--config", box,
                        "--out", out)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "gears[0].teeth" in lines[0], err
    assert not out.exists()
