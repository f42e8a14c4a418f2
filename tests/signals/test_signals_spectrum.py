"""Amplitude spectrum, tone interpolation and sideband families on known content."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals import sidebands as sb
from gearsim.signals.spectrum import amplitude_spectrum, tone, zoom
from gearsim.signals.synthetic import gear_signal

#: Brief requirement: tone and sideband amplitudes recovered within 1 %.
RTOL_AMPLITUDE = 0.01
#: A bin-centred tone has no scalloping: only round-off and negative-frequency leakage
#: (Hann sidelobes at > 1000 bins are below 1e-9).
RTOL_ON_BIN = 1e-6

FS = 10_000.0


@pytest.mark.parametrize("window", ["hann", "flattop", "boxcar"])
def test_on_bin_tone_exact(window):
    n = 10_000
    t = np.arange(n) / FS
    x = 3.0 * np.cos(2 * np.pi * 1000.0 * t + 0.3) + 0.5
    s = amplitude_spectrum(x, FS, window=window)
    assert_allclose(s.df, 1.0)
    k = 1000
    assert_allclose(s.amplitude[k], 3.0, rtol=RTOL_ON_BIN)
    if window == "boxcar":
        assert_allclose(s.amplitude[0], 0.5, rtol=RTOL_ON_BIN)


@pytest.mark.parametrize("window", ["hann", "flattop", "boxcar"])
@pytest.mark.parametrize("offset", [0.1, 0.25, 0.5, 0.73])
def test_off_bin_tone_within_one_percent(window, offset):
    n = 10_000
    f0 = 1234.0 + offset
    t = np.arange(n) / FS
    x = 2.0 * np.sin(2 * np.pi * f0 * t)
    s = amplitude_spectrum(x, FS, window=window)
    est = tone(s, f0, search=3.0)
    assert_allclose(est.amplitude, 2.0, rtol=RTOL_AMPLITUDE, err_msg=f"{window} {offset}")
    if window != "flattop":
        assert_allclose(est.frequency, f0, atol=0.05 * s.df)


def test_sideband_family_amplitudes_within_one_percent():
    fs, f_r, teeth = 20_000.0, 1900.0 / 60.0, 39
    amps = {(1, -3): 0.02, (1, -2): 0.05, (1, -1): 0.1, (1, 1): 0.08, (1, 2): 0.04,
            (1, 3): 0.03, (2, -1): 0.06, (2, 1): 0.07}
    x = gear_signal(fs=fs, duration=2.0, shaft_frequency=f_r, teeth=teeth,
                    mesh_amplitudes={1: 1.0, 2: 0.5}, sidebands=amps, noise=0.001, seed=3)
    s = amplitude_spectrum(x, fs, window="hann")
    fams = sb.sideband_families(s, mesh_frequency=teeth * f_r, shafts={"in": f_r},
                                orders=(1, 2), n_sidebands=3)
    assert [f.order for f in fams] == [1, 2]
    assert_allclose(fams[0].mesh.amplitude, 1.0, rtol=RTOL_AMPLITUDE)
    assert_allclose(fams[1].mesh.amplitude, 0.5, rtol=RTOL_AMPLITUDE)
    for fam in fams:
        for k, a in zip(fam.k, fam.amplitude, strict=True):
            expected = amps.get((fam.order, int(k)))
            if expected is not None:
                assert_allclose(a, expected, rtol=RTOL_AMPLITUDE, err_msg=f"{fam.order},{k}")
            else:
                assert a < 0.002
    expected_ser = (0.02 + 0.05 + 0.1 + 0.08 + 0.04 + 0.03) / 1.0
    assert_allclose(fams[0].ser, expected_ser, rtol=RTOL_AMPLITUDE)
    assert fams[0].isolated.all()


def test_uniformity_measures():
    even = np.full(12, 0.3)
    assert_allclose(sb.coefficient_of_variation(even), 0.0, atol=1e-15)
    assert_allclose(sb.spectral_flatness(even), 1.0, rtol=1e-12)
    spiky = np.array([1.0] + [0.01] * 11)
    assert sb.spectral_flatness(spiky) < 0.01
    a = np.array([1.0, 2.0, 3.0])
    assert_allclose(sb.coefficient_of_variation(a), np.std(a) / 2.0, rtol=1e-12)
    assert_allclose(sb.sideband_energy_ratio(2.0, a), 3.0, rtol=1e-12)


def test_overlapping_families_flagged():
    fs, f_r = 20_000.0, 30.0
    x = np.sin(2 * np.pi * 1200.0 * np.arange(int(fs * 2)) / fs)
    s = amplitude_spectrum(x, fs, window="hann")
    # shaft b at 10 Hz: its k=3 line falls on shaft a's k=1 line
    fams = sb.sideband_families(s, mesh_frequency=1200.0, shafts={"a": f_r, "b": 10.0},
                                orders=(1,), n_sidebands=3)
    a = fams[0]
    assert not a.isolated[a.k == 1][0]


def test_nyquist_refused():
    fs = 8000.0
    s = amplitude_spectrum(np.random.default_rng(0).standard_normal(16000), fs)
    with pytest.raises(InputError, match="fs = 8000 Hz") as err:
        sb.sideband_families(s, mesh_frequency=1235.0, shafts={"in": 31.67}, orders=(1, 2, 3, 4),
                             n_sidebands=6)
    assert "Nyquist" in str(err.value) and "\n" not in str(err.value)


def test_short_record_refused():
    fs = 20_000.0
    s = amplitude_spectrum(np.random.default_rng(0).standard_normal(2000), fs)  # 0.1 s
    with pytest.raises(InputError, match="record duration") as err:
        sb.sideband_families(s, mesh_frequency=1235.0, shafts={"in": 31.67}, orders=(1,),
                             n_sidebands=3)
    assert "0.1263 s" in str(err.value)  # 4 Hann bins / 31.67 Hz


def test_zoom_and_unknown_window():
    s = amplitude_spectrum(np.ones(1000), 1000.0, window="boxcar")
    f, a = zoom(s, 100.0, 5.0)
    assert f.min() >= 95.0 and f.max() <= 105.0 and a.size == f.size == 11
    with pytest.raises(InputError, match="window"):
        amplitude_spectrum(np.ones(10), 1.0, window="kaiser")
