"""Narrow-band amplitude and phase demodulation (McFadden 1986) on known signals."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.demodulation import analytic_band, demodulate, demodulate_tsa
from gearsim.signals.tsa import TSA, tsa

FS = 5120.0
F_R = 10.0
TEETH = 20
REVS = 64
M = 512  # samples per revolution of the TSA
#: Phase-kurtosis ratio faulty/healthy required (measured: 10.98 / 2.87 = 3.8, seed 0).
MIN_PHASE_KURTOSIS_RATIO = 3.0


def _gear(fault: bool, seed: int = 0) -> np.ndarray:
    """Mesh tone (+ 2nd harmonic) with, once per revolution, one tooth period of
    amplitude (+20 %) and phase (+0.5 rad) modulation (a Hann bump); noise std 0.1."""
    n = int(FS * REVS / F_R)
    t = np.arange(n) / FS
    u = ((F_R * t) % 1.0 - 0.3) * TEETH  # tooth periods since the faulty tooth
    w = np.where((u >= 0) & (u < 1), 0.5 - 0.5 * np.cos(2 * np.pi * u), 0.0) if fault else 0 * t
    x = (1 + 0.2 * w) * np.cos(2 * np.pi * TEETH * F_R * t + 0.5 * w)
    x += 0.3 * np.cos(4 * np.pi * TEETH * F_R * t)
    return x + 0.1 * np.random.default_rng(seed).standard_normal(n)


def test_known_modulations_recovered_exactly():
    t = np.arange(1024) / 1024.0
    m = 2 * np.pi * 3 * t
    x = (1 + 0.3 * np.sin(m)) * np.cos(2 * np.pi * 150 * t + 0.4 * np.cos(m))
    x += 0.5 * np.cos(2 * np.pi * 300 * t)  # next harmonic: outside the band
    d = demodulate(x, 1024.0, center=150.0, bandwidth=60.0, carrier="center")
    assert_allclose(d.amplitude, 1 + 0.3 * np.sin(m), atol=1e-9)
    assert_allclose(d.phase, 0.4 * np.cos(m), atol=1e-9)
    # instantaneous-frequency deviation: d/dt (0.4 cos m) / 2 pi = -0.4 * 3 sin(m)
    assert_allclose(d.frequency_deviation()[5:-5], -1.2 * np.sin(m)[5:-5], atol=2e-3)


def test_fit_carrier_removes_a_carrier_other_than_the_centre():
    t = np.arange(4096) / 4096.0
    pm = 0.2 * np.sin(2 * np.pi * 5 * t)
    x = np.cos(2 * np.pi * 200.0 * t + pm)
    d = demodulate(x, 4096.0, center=199.7, bandwidth=40.0)  # centre 0.3 Hz off
    # the least-squares line also absorbs the trend of the modulation over the record
    slope, icpt = np.polyfit(t, pm, 1)
    line = slope * t + icpt
    assert_allclose(d.carrier_frequency, 200.0 + slope / (2 * np.pi), rtol=1e-9)
    assert_allclose(d.phase, pm - line, atol=1e-4)  # Bessel lines beyond the band: J4(0.2) ~ 4e-6


def test_analytic_band_matches_hilbert_of_the_band():
    import scipy.signal

    rng = np.random.default_rng(1)
    x = rng.standard_normal(2048)
    z = analytic_band(x, 2048.0, low=100.0, high=300.0)
    spec = np.fft.rfft(x)
    f = np.fft.rfftfreq(2048, 1 / 2048.0)
    spec[(f < 100) | (f > 300)] = 0
    assert_allclose(z, scipy.signal.hilbert(np.fft.irfft(spec, 2048)), atol=1e-10)


def test_tooth_fault_raises_phase_kurtosis():
    healthy = tsa(_gear(False), FS, samples_per_rev=M, shaft_frequency=F_R)
    faulty = tsa(_gear(True), FS, samples_per_rev=M, shaft_frequency=F_R)
    dh = demodulate_tsa(healthy, teeth=TEETH, sidebands=9)
    df = demodulate_tsa(faulty, teeth=TEETH, sidebands=9)
    kh, kf = dh.phase_kurtosis(), df.phase_kurtosis()
    assert 2.0 < kh < 4.0  # Gaussian-like phase noise of the average
    assert kf / kh > MIN_PHASE_KURTOSIS_RATIO, (kh, kf)
    # derivative and amplitude react too (measured 2.57 -> 6.89 and 3.85 -> 12.3)
    assert df.phase_kurtosis(derivative=True) > 2 * dh.phase_kurtosis(derivative=True)
    assert df.amplitude_kurtosis() > 2 * dh.amplitude_kurtosis()
    # the phase peak sits on the faulty tooth: 0.3 rev + half a tooth
    j = int(np.argmax(np.abs(df.phase)))
    assert abs(j / M - (0.3 + 0.5 / TEETH)) < 1.0 / TEETH


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_phase_kurtosis_jump_other_seeds(seed):
    kh = demodulate_tsa(tsa(_gear(False, seed), FS, samples_per_rev=M, shaft_frequency=F_R),
                        teeth=TEETH, sidebands=9).phase_kurtosis()
    kf = demodulate_tsa(tsa(_gear(True, seed), FS, samples_per_rev=M, shaft_frequency=F_R),
                        teeth=TEETH, sidebands=9).phase_kurtosis()
    assert kf / kh > 2.5


def test_record_demodulation_sees_the_fault_too():
    kh = demodulate(_gear(False), FS, center=TEETH * F_R, bandwidth=19 * F_R).phase_kurtosis()
    kf = demodulate(_gear(True), FS, center=TEETH * F_R, bandwidth=19 * F_R).phase_kurtosis()
    assert kf > 2 * kh  # measured 2.96 -> 8.15


def test_refusals():
    x = np.cos(2 * np.pi * 100 * np.arange(512) / 512.0)
    with pytest.raises(InputError, match="band"):
        demodulate(x, 512.0, center=250.0, bandwidth=20.0)
    with pytest.raises(InputError, match="carrier"):
        demodulate(x, 512.0, center=100.0, bandwidth=20.0, carrier="mean")
    with pytest.raises(InputError, match="no carrier"):
        demodulate(x, 512.0, center=30.0, bandwidth=10.0)
    t = TSA(np.cos(2 * np.pi * 20 * np.arange(64) / 64), 1, 1.0)
    with pytest.raises(InputError, match="samples_per_rev"):
        demodulate_tsa(t, teeth=20, sidebands=15)
    with pytest.raises(InputError, match="sidebands"):
        demodulate_tsa(t, teeth=20, sidebands=20)
