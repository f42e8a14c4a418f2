"""STFT spectrogram, band energy, band width and modulation index."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.signal import ShortTimeFFT, get_window

from gearsim.errors import InputError
from gearsim.signals.timefreq import band_energy, band_width, modulation_index, spectrogram

#: Same library call on the same data: identical up to round-off.
RTOL_SAME = 1e-12
#: Band power of a stationary tone from a Hann-windowed PSD: exact for bin-centred tones
#: (Parseval over the band that holds the whole main lobe); 1e-6 covers round-off.
RTOL_BAND = 1e-6

FS = 8000.0


def test_spectrogram_equals_shorttimefft():
    rng = np.random.default_rng(11)
    x = rng.standard_normal(8000)
    sg = spectrogram(x, FS, nperseg=256, hop=64, window="hann")
    ref = ShortTimeFFT(get_window("hann", 256, fftbins=True), 64, FS, fft_mode="onesided2X",
                       scale_to="psd")
    p0, p1 = ref.lower_border_end[1], ref.upper_border_begin(x.size)[1]
    z = ref.stft(x, p0=p0, p1=p1)
    assert_allclose(sg.psd, np.abs(z) ** 2, rtol=RTOL_SAME)
    assert_allclose(sg.time, ref.t(x.size, p0=p0, p1=p1), rtol=RTOL_SAME)
    assert_allclose(sg.frequency, ref.f, rtol=RTOL_SAME)
    # Only whole frames: the first frame starts at sample 0, the last ends inside the record.
    assert sg.time[0] - 128 / FS >= -1e-12
    assert sg.time[-1] + 128 / FS <= x.size / FS + 1e-12


def test_band_energy_of_tone_is_mean_square():
    t = np.arange(16000) / FS
    x = 2.0 * np.cos(2 * np.pi * 1000.0 * t)  # bin-centred for nperseg=400 (20 Hz bins)
    sg = spectrogram(x, FS, nperseg=400, hop=200)
    e = band_energy(sg, center=1000.0, half_width=200.0)
    assert_allclose(e, 2.0**2 / 2, rtol=RTOL_BAND)


def test_band_width_of_known_power_distribution():
    f = np.arange(0.0, 200.0, 1.0)
    p = np.zeros_like(f)
    p[100] = 0.5
    p[[90, 110]] = 0.2
    p[[80, 120]] = 0.05
    assert_allclose(band_width(f, p, center=100.0, half_window=50.0, fraction=0.5), 0.0)
    assert_allclose(band_width(f, p, center=100.0, half_window=50.0, fraction=0.85), 20.0)
    assert_allclose(band_width(f, p, center=100.0, half_window=50.0, fraction=0.95), 40.0)
    with pytest.raises(InputError, match="fraction"):
        band_width(f, p, center=100.0, half_window=50.0, fraction=1.0)


def test_modulation_index_of_am_envelope():
    t = np.arange(200) / 100.0
    e = 1.0 + 0.4 * np.cos(2 * np.pi * 5.0 * t)
    assert_allclose(modulation_index(e, t, frequency=5.0), 0.4, rtol=1e-9)
    assert modulation_index(np.ones(200), t, frequency=5.0) < 1e-12


def test_bad_frame_refused():
    with pytest.raises(InputError, match="nperseg"):
        spectrogram(np.ones(100), FS, nperseg=200, hop=10)
    with pytest.raises(InputError, match="hop"):
        spectrogram(np.ones(100), FS, nperseg=50, hop=0)
