"""Tiered analysis of one record: what needs nothing never asks for more; skips say why."""

import numpy as np
import pytest
import scipy.stats

from gearsim.signals import timedomain
from gearsim.signals.synthetic import ImpactSpec, gear_signal
from gearsim.signals.tiers import analyze_record

FS = 20_000.0
F_R = 1900.0 / 60.0


def _gear(duration=2.0, seed=2):
    return gear_signal(fs=FS, duration=duration, shaft_frequency=F_R, teeth=39,
                       mesh_amplitudes={1: 1.0, 2: 0.5}, sidebands={(1, -1): 0.05, (1, 1): 0.05},
                       impacts=ImpactSpec(4.0, 3e-4, 4000.0, 0.01), noise=0.01, seed=seed)


def test_statistics_match_numpy_scipy_without_rate_speed_or_teeth():
    x = np.random.default_rng(1).standard_normal(5000) ** 3 + 0.5
    r = analyze_record(x)
    st = r.tiers["statistics"]
    d = x - x.mean()
    rms = np.sqrt(np.mean(d**2))
    assert st["rms"] == pytest.approx(rms, rel=1e-12)
    assert st["peak"] == pytest.approx(np.max(np.abs(d)), rel=1e-12)
    assert st["crest_factor"] == pytest.approx(np.max(np.abs(d)) / rms, rel=1e-12)
    assert st["kurtosis"] == pytest.approx(scipy.stats.kurtosis(x, fisher=False), rel=1e-10)
    assert st["skewness"] == pytest.approx(scipy.stats.skew(x), rel=1e-10)
    assert st["impulse_factor"] == pytest.approx(np.max(np.abs(d)) / np.mean(np.abs(d)))
    assert st["shape_factor"] == pytest.approx(rms / np.mean(np.abs(d)))
    assert st["clearance_factor"] == pytest.approx(np.max(np.abs(d))
                                                   / np.mean(np.sqrt(np.abs(d))) ** 2)
    # the same definitions as gearsim.signals.timedomain
    assert st["skewness"] == pytest.approx(timedomain.skewness(x), rel=1e-10)
    assert st["impulse_factor"] == pytest.approx(timedomain.impulse_factor(d), rel=1e-10)
    assert st["shape_factor"] == pytest.approx(timedomain.shape_factor(d), rel=1e-10)
    assert st["clearance_factor"] == pytest.approx(timedomain.clearance_factor(d), rel=1e-10)
    reasons = {s["tier"]: s["reason"] for s in r.skipped}
    assert "sampling rate" in reasons["shaft"] and "sampling rate" in reasons["gear"]
    assert "cycles/sample" in reasons["spectrum.Hz"]
    assert set(r.tiers) == {"statistics", "spectrum"}


def test_spectrum_without_fs_is_in_cycles_per_sample_and_labelled():
    n = 4096
    x = np.cos(2 * np.pi * 0.125 * np.arange(n))
    r = analyze_record(x)
    sp = r.tiers["spectrum"]
    assert sp["frequency_unit"] == "cycles/sample"
    assert sp["lines"][0]["frequency"] == pytest.approx(0.125)
    assert sp["lines"][0]["amplitude"] == pytest.approx(1.0, rel=1e-6)
    assert "spectrum_peak_frequency_cps" in r.features()
    assert "cycles/sample" in r.text() and r.to_dict()["frequency_unit"] == "cycles/sample"
    r2 = analyze_record(x, 1000.0)
    assert r2.tiers["spectrum"]["lines"][0]["frequency"] == pytest.approx(125.0)
    assert "spectrum_peak_frequency_hz" in r2.features()


def test_every_tier_with_speed_and_teeth_and_provenance():
    r = analyze_record(_gear(), FS, speed=F_R, teeth=(39, 59), fs_provenance="file")
    assert set(r.tiers) == {"statistics", "spectrum", "shaft", "gear"}
    g = r.tiers["gear"]
    assert g["rests_on"] == {"fs": "file", "speed": "given", "teeth": "given"}
    assert abs(g["analysis"]["impacts"]["period_ratio_to_T1"] - 1.0) < 0.01
    assert r.features()["mesh_frequency_hz"][0] == pytest.approx(39 * F_R)
    assert "(given)" in r.text() and "(file)" in r.text()


def test_no_teeth_skips_gear_and_short_record_skips_not_fails():
    # a clear mesh tone: the tooth count is estimated (and labelled); noise: no estimate
    r = analyze_record(_gear(), FS, speed=F_R)
    assert r.teeth == (39,) and r.teeth_provenance == "estimate" and "gear" in r.tiers
    noise = np.random.default_rng(3).normal(size=_gear().size)
    r = analyze_record(noise, FS, speed=F_R)
    assert "shaft" in r.tiers and "gear" not in r.tiers
    assert any(s["tier"] == "gear" and "teeth" in s["reason"] for s in r.skipped)
    short = analyze_record(_gear(duration=0.04), FS, speed=F_R, teeth=(39,))
    assert "shaft" not in short.tiers and "gear" not in short.tiers
    assert any("shorter than 2 revolutions" in s["reason"] for s in short.skipped)
    tiny = analyze_record(np.arange(8.0))
    assert any(s["tier"] == "spectrum" for s in tiny.skipped)


def test_speed_estimate_is_labelled_estimate():
    r = analyze_record(_gear(), FS, speed_search=(25.0, 40.0), teeth=(39,))
    if "shaft" in r.tiers:
        assert r.speed_provenance == "estimate"
        assert r.speed == pytest.approx(F_R, rel=0.02)
        assert "(estimate; mean of" in r.text()  # tracked (tiers.STEADY_TRACK_SPAN)
    else:  # the estimator refused: skipped with its reason, never an error
        assert any(s["tier"] == "shaft" for s in r.skipped)


def test_estimates_fill_a_missing_rate_or_tooth_count_and_are_labelled():
    """fs from the known shaft speed and the mesh comb; teeth from the dominant tone; both
    labelled "estimate" (fs 12345 Hz, f_r 17 Hz, Z 29: values recovered within the
    estimator's resolution, 1e-5 relative for fs). Without sidebands the two mesh lines fit
    fs (harmonics 1 and 2) and fs / 2 (harmonic 1) alike: the rate is skipped, not
    guessed."""
    fs, f_r, z = 12345.0, 17.0, 29
    t = np.arange(int(4 * fs)) / fs
    x = (np.cos(2 * np.pi * z * f_r * t) + 0.4 * np.cos(4 * np.pi * z * f_r * t)
         + 0.3 * np.random.default_rng(0).normal(size=t.size))
    d = analyze_record(x, None, speed=f_r, teeth=[z]).to_dict()
    assert d["fs_hz"] is None
    reason = {s["tier"]: s["reason"] for s in d["skipped"]}["estimate.fs"]
    assert "12.3" in reason and "6.17" in reason and "(--fs)" in reason  # fs, fs / 2 in kHz
    sidebands = sum(a * np.cos(2 * np.pi * (z + m) * f_r * t) for m, a in ((-1, 0.2), (1, 0.15)))
    d = analyze_record(x + sidebands, None, speed=f_r, teeth=[z]).to_dict()
    assert d["fs_provenance"] == "estimate"
    assert d["fs_hz"] == pytest.approx(fs, rel=1e-5)
    assert d["tiers"]["estimates"]["fs"]["estimate"] is True
    assert "gear" in d["tiers"]
    d = analyze_record(x, fs, speed=f_r).to_dict()
    assert d["teeth"] == [z] and d["teeth_provenance"] == "estimate"
    assert "gear" in d["tiers"]
    assert not any(s["tier"] == "shaft.speed_check" for s in d["skipped"])


def test_mesh_frequency_above_nyquist_is_refused(tmp_path):
    """80 teeth x 10 Hz = 800 Hz above the 500 Hz Nyquist frequency of fs = 1 kHz: the
    inputs contradict each other, so the call is refused (exit 2, nothing written),
    while 20 teeth (200 Hz) is not refused."""
    from gearsim import cli
    from gearsim.errors import InputError

    x = np.sin(2 * np.pi * 37 * np.arange(20_000) / 1000.0)
    with pytest.raises(InputError, match="Nyquist"):
        analyze_record(x, 1000.0, speed=10.0, teeth=(80,))
    # 20 teeth: the mesh tone is below Nyquist; the tier needing 4 harmonics and their
    # sidebands is skipped with its reason, the call is not refused
    r = analyze_record(x, 1000.0, speed=10.0, teeth=(20,))
    assert "gear" in r.tiers or any(s["tier"] == "gear" for s in r.skipped)
    rec = tmp_path / "rec.csv"
    np.savetxt(rec, x, header="acc", comments="")
    out = tmp_path / "t.csv"
    assert cli.run(["analyze", str(rec), "--fs", "1000", "--shaft-rpm", "600", "--teeth", "80",
                    "--out", str(out)]) == 2
    assert not out.exists()


def test_the_squared_envelope_lines_are_in_squared_units_and_match_the_hand_values():
    """x = A (1 + m cos w_r t) cos w_c t: the squared envelope A^2 (1 + m cos)^2 has the
    line 2 m A^2 at the shaft order and m^2 A^2 / 2 at twice it (4 and 0.5 (m/s^2)^2 for
    A = 2 m/s^2, m = 0.5); they were labelled in m/s^2."""
    fs, fr, amp, m = 20_000.0, 25.0, 2.0, 0.5
    t = np.arange(int(2 * fs)) / fs
    x = amp * (1 + m * np.cos(2 * np.pi * fr * t)) * np.cos(2 * np.pi * 40 * fr * t)
    r = analyze_record(x, fs, speed=fr, teeth=[40], units="m/s^2")
    f = r.features()
    assert f["envelope_order1_amplitude"][1] == "signal^2"
    assert f["envelope_order1_amplitude"][0] == pytest.approx(2 * m * amp**2, rel=1e-9)
    assert f["envelope_order2_amplitude"][0] == pytest.approx(m**2 * amp**2 / 2, rel=1e-9)
    line = next(s for s in r.text().splitlines() if "envelope at shaft orders" in s)
    assert line.strip().startswith("squared envelope") and "1x 4 (m/s^2)^2" in line
