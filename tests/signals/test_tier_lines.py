"""Lines the shaft tier reads: order k of the shaft within the main lobe of k f_r (or the
speed's own spread), never another shaft's line; the envelope blind to a sensor bias."""

import json

import numpy as np
import pytest

from gearsim.signals.tiers import analyze_record

FS = 1000.0


def _tones(n, lines):
    t = np.arange(n) / FS
    return sum(a * np.cos(2 * np.pi * f * t) for f, a in lines)


def test_weak_order_1_beside_a_strong_line_20_percent_below():
    # 10 s at 1 kHz (0.1 Hz bins, every line on a bin: the Hann window reads it exactly):
    # the shaft's 1x of 0.3 at 10 Hz beside a line of 3 at 8 Hz; a carrier of 200 Hz
    # modulated by m1 = 0.05 at 10 Hz and m2 = 0.5 at 8 Hz. The squared envelope
    # |sum A_i e^(i w_i t)|^2 holds 2 A_i A_j at every difference w_i - w_j: at 10 Hz
    # 2 m1 = 0.1 from the carrier and 2 x 0.3 x 0.2 = 0.12 from the 10 and 20 Hz tones
    # (0.22); at 8 Hz 2 m2 = 1
    n = 10_000
    t = np.arange(n) / FS
    am = (1 + 0.05 * np.cos(2 * np.pi * 10 * t) + 0.5 * np.cos(2 * np.pi * 8 * t))
    x = _tones(n, [(10.0, 0.3), (8.0, 3.0), (20.0, 0.2)]) + am * np.cos(2 * np.pi * 200 * t)
    sh = analyze_record(x, FS, speed=10.0).tiers["shaft"]
    o = {r["order"]: r for r in sh["orders"]}
    assert o[1]["frequency_hz"] == pytest.approx(10.0, abs=0.1)
    assert o[1]["amplitude"] == pytest.approx(0.3, rel=1e-6)
    assert o[2]["amplitude"] == pytest.approx(0.2, rel=1e-6)
    e = sh["envelope"]["orders"][0]
    assert (e["order"], e["frequency_hz"]) == (1, pytest.approx(10.0, abs=0.1))
    assert e["amplitude"] == pytest.approx(0.22, rel=1e-6)


def test_order_read_short_of_another_shafts_line():
    # 1.5 s: bins of 2/3 Hz; teeth 20/25 put shaft 2 at 8 Hz, 3 bins below the 1x at
    # 10 Hz: a window of the Hann main lobe (+-2 bins) would reach bin 13 (half the 8 Hz
    # line, 1.5); it ends one main lobe short of 8 Hz and reads 0.3 at 10 Hz
    x = _tones(1500, [(10.0, 0.3), (8.0, 3.0)])
    o = analyze_record(x, FS, speed=10.0, teeth=(20, 25)).tiers["shaft"]["orders"][0]
    assert o["frequency_hz"] == pytest.approx(10.0, abs=1e-9)
    assert o["amplitude"] == pytest.approx(0.3, rel=1e-9)


def test_envelope_orders_blind_to_a_sensor_bias():
    # a bias c adds 2 c x to |x + c + iH|^2: with c = 100 the 30 Hz line of 0.3 (3x)
    # would show as 60 in the envelope; with the mean removed the record and the record
    # + 100 give the same envelope orders (to round-off)
    rng = np.random.default_rng(4)
    n = 10_000
    t = np.arange(n) / FS
    x = _tones(n, [(10.0, 0.3), (30.0, 0.3)]) + (1 + 0.2 * np.cos(2 * np.pi * 10 * t)) * \
        np.cos(2 * np.pi * 200 * t) + 0.05 * rng.standard_normal(n)
    env = [analyze_record(x + c, FS, speed=10.0).tiers["shaft"]["envelope"]["orders"]
           for c in (0.0, 100.0)]
    for r0, r1 in zip(*env, strict=True):
        assert r1["amplitude"] == pytest.approx(r0["amplitude"], rel=1e-9, abs=1e-9)
    # no two lines 30 Hz apart: the 3x is noise, against 2 c 0.3 = 60 with the bias kept
    assert env[0][2]["amplitude"] < 1.0


def test_dropped_samples_reported_as_an_object_and_a_text_line(tmp_path, capsys):
    from gearsim import cli

    # 1000 samples, NaN in the first 3 and the last 2: 5 dropped, file samples 3..997 kept
    x = _tones(1000, [(10.0, 1.0)])
    x[:3] = x[-2:] = np.nan
    p = tmp_path / "nan.csv"
    p.write_text("# fs = 1000\nacc\n" + "\n".join(f"{v:.17g}" for v in x) + "\n")
    assert cli.run(["analyze", str(p), "--drop-nonfinite", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["records"][0]["source"]["dropped"]
    assert d == {"count": 5, "nonfinite": 5, "first": 0, "last": 999, "kept": [3, 998]}
    assert cli.run(["analyze", str(p), "--drop-nonfinite"]) == 0
    out = capsys.readouterr().out
    assert "995 samples" in out
    assert "dropped 5 samples (5 non-finite) at the ends, file samples 0..999: kept 3..997" in out


def test_speed_disagreement_is_a_warning_and_the_given_speed_is_used(tmp_path, capsys):
    from gearsim import cli

    # mesh of 10 teeth at 10 Hz (100 Hz), given 10.2 Hz: 10/10.2 - 1 = -1.96 %, far
    # beyond the check's 0.2 %; every tier still runs at 10.2 Hz, as said, with a warning
    x = _tones(10_000, [(100.0, 1.0), (90.0, 0.1), (110.0, 0.1), (10.0, 0.2)])
    r = analyze_record(x, FS, speed=10.2, teeth=(10, 20))
    assert not any(s["tier"] == "shaft.speed_check" for s in r.skipped)
    (w,) = r.to_dict()["warnings"]
    assert "given speed 10.2 Hz" in w and "-1.96" in w and " 10 Hz" in w
    assert r.tiers["gear"]["analysis"]["train"]["mesh_frequency_hz"] == pytest.approx(102.0)
    p = tmp_path / "r.csv"
    p.write_text("# fs = 1000\nacc\n" + "\n".join(f"{v:.17g}" for v in x) + "\n")
    assert cli.run(["analyze", str(p), "--shaft-rpm", "612", "--teeth", "10", "20"]) == 0
    out = capsys.readouterr().out
    assert "WARNING: given speed 10.2 Hz" in out and "skipped shaft.speed_check" not in out


def test_baseline_shorter_than_two_revolutions_is_not_used():
    # 10 Hz shaft: 2 revolutions are 0.2 s = 200 samples; a baseline of 150 samples
    # (1.5 revolutions) gives no ratios and no NA4 from it, with the reason
    x = _tones(10_000, [(100.0, 1.0), (90.0, 0.1), (110.0, 0.1)])
    x += 0.01 * np.random.default_rng(0).standard_normal(x.size)
    r = analyze_record(x, FS, speed=10.0, teeth=(10, 20), baseline=x[:150])
    assert "ratios_to_baseline" not in r.tiers["gear"]["analysis"]
    (why,) = [s["reason"] for s in r.skipped if s["tier"] == "gear.baseline"]
    assert why == ("baseline 0.15 s is shorter than 2 revolutions of the measured shaft "
                   "(0.2 s)")
    ok = analyze_record(x, FS, speed=10.0, teeth=(10, 20), baseline=x[:200])
    assert "ratios_to_baseline" in ok.tiers["gear"]["analysis"]


@pytest.mark.parametrize("rise", [0.0, 0.1])
def test_gear_tier_in_the_order_domain_when_the_speed_is_tracked(rise):
    # 20 teeth on a shaft at 10 + rise t Hz for 10 s: with rise 0.1 Hz/s the speed goes
    # from 10 to 11 Hz (10 % of its mean 10.5 Hz, beyond the run-up rule's 1 %); at one
    # speed the mesh line would be smeared over 200..220 Hz: the gear tier reads the
    # record resampled at equal angle steps of the mean speed, where the mesh tone of
    # amplitude 1 is at order 20 and its sidebands (0.1) at 19 and 21; at a constant
    # speed it runs on the record itself
    fs = 2000.0
    t = np.arange(int(10 * fs)) / fs
    ph = 2 * np.pi * np.cumsum(10.0 + rise * t) / fs
    x = (np.cos(20 * ph) + 0.3 * np.cos(ph) + 0.1 * np.cos(19 * ph) + 0.1 * np.cos(21 * ph)
         + 0.05 * np.random.default_rng(0).standard_normal(t.size))
    r = analyze_record(x, fs, speed_search=(8.0, 14.0), teeth=(20, 40))
    h = r.tiers["gear"]["analysis"]["mesh_harmonics"][0]
    assert h["amplitude"] == pytest.approx(1.0, rel=0.01)
    # a steady estimated speed is tracked too (STEADY_TRACK_SPAN): its range stays within
    # the noise of the phase, its lines at 20 x 10 Hz
    lo, hi = r.tiers["shaft"]["speed_range_hz"]
    assert (lo, hi) == (pytest.approx(10.0, rel=0.01), pytest.approx(10.0 + 10 * rise,
                                                                      rel=0.01))
    f = r.tiers["gear"]["order_domain"]["mean_speed_hz"]
    assert f"(order domain: resampled at equal angle steps of {f:.6g} Hz)" in r.text()
    assert f == pytest.approx(10.0 + 5 * rise, rel=2e-3)
    assert h["frequency_hz"] == pytest.approx(20 * f, rel=1e-4)
    (sb,) = r.tiers["gear"]["analysis"]["sidebands"][:1]
    assert [sb["amplitude"][sb["k"].index(k)] for k in (-1, 1)] == [
        pytest.approx(0.1, rel=0.05)] * 2
    assert f"mean of {lo:.5g} to {hi:.5g} Hz" in r.text()


def test_a_speed_tracked_without_a_steady_estimate_keeps_the_gears_phase_modulation():
    # a steady 29.7 Hz, mesh (order 32) phase-modulated by 0.3 rad at shaft 2's order 0.4
    # (stages 32/80): its first sidebands are J1(0.3) = 0.1483 by hand. The line family is
    # too sparse for a confident constant estimate, so the given mesh order is tracked over
    # the whole search range with a band that holds the modulation: read in the order
    # domain of that track the sidebands were 0.092 / 0.091; read at its mean speed (the
    # track is steady, within the run-up rule's 1 %) they are the record's own
    from scipy.special import jv

    fs = 12800.0
    th = 29.7 * np.arange(int(8 * fs)) / fs
    x = (np.cos(2 * np.pi * 32 * th + 0.3 * np.sin(2 * np.pi * 0.4 * th))
         + 0.5 * np.cos(2 * np.pi * 19.2 * th) + 0.3 * np.cos(2 * np.pi * th)
         + 0.3 * np.random.default_rng(2).standard_normal(th.size))
    r = analyze_record(x, fs, speed_search=(20.0, 40.0), stages=[(32, 80), (48, 64)])
    st = r.tiers["gear"]["analysis"]["stages"][0]
    (sb,) = [s for s in st["sidebands"] if s["shaft"] == "shaft2" and s["order"] == 1]
    assert [sb["amplitude"][sb["k"].index(k)] for k in (-1, 1)] == [
        pytest.approx(jv(1, 0.3), rel=0.05)] * 2


def test_noise_given_teeth_and_a_search_gets_no_speed():
    # white noise with teeth and a search range: no line family, so no constant estimate;
    # the given mesh order tracked over the range as for a run-up followed the noise (a
    # speed of 28.15 Hz, "mesh line" 0.137 about 7 x the floor). Its ridge stands 7 dB over
    # the band's median (white noise: about 5, 7 dB), under RIDGE_SNR's 12 dB: no speed
    from gearsim.signals.tiers import RIDGE_SNR

    fs = 12800.0
    x = np.random.default_rng(5).standard_normal(int(8 * fs))
    r = analyze_record(x, fs, speed_search=(20.0, 40.0), stages=[(32, 80), (48, 64)])
    assert r.speed is None and "gear" not in r.tiers and "shaft" not in r.tiers
    (why,) = [s["reason"] for s in r.skipped if s["tier"] == "shaft.tracking"]
    assert f"must stand {10 * np.log10(RIDGE_SNR):.3g} dB" in why


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), 0.0, -1.0, 1e300 * 1e10, -1e-300])
def test_min_ridge_snr_refused_before_any_work(bad):
    from gearsim.errors import InputError
    from gearsim.signals.speed import estimate_speed

    x = np.cos(2 * np.pi * 20 * 12.0 * np.arange(10000) / 5000.0)
    with pytest.raises(InputError, match="min_ridge_snr"):
        estimate_speed(x, 5000.0, order=20, search=(10.0, 18.0), min_ridge_snr=bad)
