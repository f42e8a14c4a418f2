"""Squared-envelope spectrum: closed forms, and impacts found in the kurtogram's band.

Known answers: the squared envelope of an AM carrier has lines ``2m`` and ``m^2/2`` at
``f_m`` and ``2 f_m`` (exact on bins); impacts repeating at ``f_r`` that ring a resonance
give lines at ``k f_r`` once the band around the resonance is demodulated (Randall &
Antoni 2011).
"""

import math

import numpy as np
import pytest
from matplotlib.figure import Figure
from scipy.signal import find_peaks

from gearsim.errors import InputError
from gearsim.signals.envelope import band_pass, envelope_spectrum, squared_envelope
from gearsim.signals.kurtogram import fast_kurtogram

FS = 20_000.0
DURATION = 2.0  # s; bins of 0.5 Hz, 37 Hz = 74 bins
F_RES = 3000.0  # resonance [Hz]
ZETA = 0.03  # damping ratio
F_REP = 37.0  # impact repetition frequency [Hz]
SNR_DB = -10.0  # impact-train power over white-noise power
F_MESH = 800.0  # mesh tone, amplitude 3 noise standard deviations
#: Line amplitudes of bin-centred tones through an FFT mask, Hilbert transform and a
#: Hann-windowed spectrum: exact up to round-off.
RTOL_EXACT = 1e-9
#: "Within one bin" of the brief.
BINS = 1


def impact_signal() -> np.ndarray:
    """Decaying 3 kHz ringing every 1/37 s in white noise at -10 dB, plus a mesh tone."""
    n = int(FS * DURATION)
    t = np.arange(n) / FS
    x = np.zeros(n)
    wd = 2 * np.pi * F_RES * math.sqrt(1 - ZETA**2)
    for tk in np.arange(0.0, DURATION, 1 / F_REP) + 0.003:
        tau = t - tk
        m = tau >= 0
        x[m] += np.exp(-ZETA * 2 * np.pi * F_RES * tau[m]) * np.sin(wd * tau[m])
    sigma = math.sqrt(np.mean(x**2) / 10 ** (SNR_DB / 10))
    rng = np.random.default_rng(1)
    return x + sigma * rng.standard_normal(n) + 3 * sigma * np.cos(2 * np.pi * F_MESH * t)


def largest_lines(es, count: int, f_min: float = 5.0) -> np.ndarray:
    """Frequencies of the ``count`` largest local maxima above ``f_min`` (Hz)."""
    peaks, _ = find_peaks(es.amplitude)
    peaks = peaks[es.frequency[peaks] >= f_min]
    return es.frequency[peaks[np.argsort(es.amplitude[peaks])[::-1][:count]]]


def test_am_carrier_lines_are_exact():
    fs, n = 1000.0, 2000
    t = np.arange(n) / fs
    m = 0.4
    x = (1 + m * np.cos(2 * np.pi * 10 * t)) * np.cos(2 * np.pi * 200 * t)
    x += 0.7 * np.cos(2 * np.pi * 400 * t)  # outside the band: must not contribute
    es = envelope_spectrum(x, fs, band=(150.0, 250.0))
    assert es.band == (150.0, 250.0)
    assert es.df == pytest.approx(0.5)
    assert es.amplitude[20] == pytest.approx(2 * m, rel=RTOL_EXACT)
    assert es.amplitude[40] == pytest.approx(m**2 / 2, rel=RTOL_EXACT)
    assert es.amplitude[0] == pytest.approx(0.0, abs=1e-9)  # mean removed
    # squared envelope itself: (1 + m cos)^2
    e = squared_envelope(x, fs, band=(150.0, 250.0))
    assert np.allclose(e, (1 + m * np.cos(2 * np.pi * 10 * t)) ** 2, atol=1e-9)


def test_impacts_show_in_the_kurtogram_band_and_not_in_the_full_band():
    x = impact_signal()
    band = fast_kurtogram(x, FS).band
    assert band[0] <= F_RES <= band[1]
    es = envelope_spectrum(x, FS, band=band)
    expected = F_REP * np.arange(1, 5)  # repetition frequency and its first 3 harmonics
    found = np.sort(largest_lines(es, 4))
    assert np.all(np.abs(found - expected) <= BINS * es.df), found
    # the whole band is dominated by the noise and the tone beating with the ringing:
    # its largest line is elsewhere (3000 - 800 = 2200 Hz region)
    full = envelope_spectrum(x, FS)
    assert np.min(np.abs(largest_lines(full, 1)[0] - expected)) > 10 * es.df


def test_band_pass_keeps_only_the_band():
    fs, n = 1000.0, 1000
    t = np.arange(n) / fs
    lo_tone, hi_tone = np.cos(2 * np.pi * 50 * t), np.cos(2 * np.pi * 300 * t)
    assert np.allclose(band_pass(lo_tone + hi_tone, fs, (250.0, 350.0)), hi_tone, atol=1e-12)


def test_refusals():
    x = np.random.default_rng(0).standard_normal(1000)
    with pytest.raises(InputError, match="band"):
        envelope_spectrum(x, 1000.0, band=(300.0, 200.0))
    with pytest.raises(InputError, match="band"):
        envelope_spectrum(x, 1000.0, band=(100.0, 600.0))
    with pytest.raises(InputError, match="band"):
        envelope_spectrum(x, 1000.0, band=(100.0, 101.0))  # 1 Hz < 2 bins
    with pytest.raises(InputError, match="window"):
        envelope_spectrum(x, 1000.0, window="kaiser")
    with pytest.raises(InputError, match="fs"):
        envelope_spectrum(x, 0.0)


def test_envelope_plot_returns_figure():
    x = impact_signal()
    es = envelope_spectrum(x, FS, band=(2500.0, 3500.0))
    fig = es.plot(f_max=300.0, harmonics_of=F_REP)
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert ax.get_xlim() == (0.0, 300.0)
    assert len(ax.lines) == 1 + 8  # spectrum and the 8 harmonics of 37 Hz below 300 Hz
