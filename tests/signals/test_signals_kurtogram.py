"""Spectral kurtosis and the fast kurtogram on signals of known kurtosis.

Known answers: stationary Gaussian noise has spectral kurtosis 0 (the estimate scatters
with standard deviation about ``2/sqrt(M)``, ``M`` independent samples; Antoni 2006), a
pure tone -1, and repetitive impacts ringing a resonance a large value in the band of
the resonance (Antoni 2007).
"""

import math

import numpy as np
import pytest
from matplotlib.figure import Figure

from gearsim.errors import InputError
from gearsim.signals.kurtogram import (
    MIN_BAND_SAMPLES,
    fast_kurtogram,
    kurtogram_levels,
    spectral_kurtosis,
)

FS = 20_000.0
DURATION = 2.0  # s
F_RES = 3000.0  # resonance excited by the impacts [Hz]
ZETA = 0.03  # damping ratio: half-power band 2 zeta f = 180 Hz, decay time 1.8 ms
F_REP = 37.0  # impact repetition frequency [Hz]
SNR_DB = -10.0  # power of the impact train over the power of the white noise
#: Number of standard deviations of a null estimate (Gaussian noise) allowed: the
#: probability of one bin of ~130 beyond 5 sigma is below 1e-4.
N_SIGMA = 5.0
#: Tone of constant envelope: kurtosis -1 exactly; 0.05 covers the noise (amplitude 1 %)
#: and the filters' leakage from neighbouring bands.
ATOL_TONE = 0.05


def impact_signal(snr_db: float = SNR_DB, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Decaying 3 kHz ringing every 1/37 s in white noise at ``snr_db``, plus a mesh tone.

    The mesh tone (800 Hz, amplitude 3 noise standard deviations) has kurtosis -1 and
    dominates the time record; it must not attract the kurtogram.
    """
    n = int(FS * DURATION)
    t = np.arange(n) / FS
    x = np.zeros(n)
    wd = 2 * np.pi * F_RES * math.sqrt(1 - ZETA**2)
    for tk in np.arange(0.0, DURATION, 1 / F_REP) + 0.003:
        tau = t - tk
        m = tau >= 0
        x[m] += np.exp(-ZETA * 2 * np.pi * F_RES * tau[m]) * np.sin(wd * tau[m])
    sigma = math.sqrt(np.mean(x**2) / 10 ** (snr_db / 10))
    rng = np.random.default_rng(seed)
    return t, x + sigma * rng.standard_normal(n) + 3 * sigma * np.cos(2 * np.pi * 800.0 * t)


def test_spectral_kurtosis_of_gaussian_noise_is_zero_within_estimator_spread():
    x = np.random.default_rng(5).standard_normal(2**17)
    sk = spectral_kurtosis(x, FS, nperseg=256)
    assert sk.n_frames == 2**17 // 128 - 1
    # null_std = 2/sqrt(M) with M = 511.5 non-overlapping frames: 0.088
    assert sk.null_std == pytest.approx(2 / math.sqrt(sk.n_frames / 2))
    assert np.all(np.abs(sk.kurtosis) < N_SIGMA * sk.null_std)
    # mean over the ~128 bins (neighbouring Hann bins correlated: 64 independent)
    assert abs(sk.kurtosis.mean()) < N_SIGMA * sk.null_std / math.sqrt(64)


def test_spectral_kurtosis_is_large_at_the_resonance():
    _, x = impact_signal()
    sk = spectral_kurtosis(x, FS, nperseg=128)  # 6.4 ms frames: longer than the ringing
    k_max = int(np.argmax(sk.kurtosis))
    df = FS / 128
    assert abs(sk.frequency[k_max] - F_RES) <= 2 * ZETA * F_RES + df
    assert sk.kurtosis[k_max] > 10 * sk.null_std  # 2.0 here, 18 sigma
    # away from the resonance (below 2 kHz, above 4 kHz) noise and the tone: no large value
    away = (sk.frequency < 2000.0) | (sk.frequency > 4000.0)
    assert np.all(sk.kurtosis[away] < N_SIGMA * sk.null_std)
    # the mesh tone, 19 dB above the noise in its bin, pulls towards -1
    assert sk.kurtosis[np.argmin(np.abs(sk.frequency - 800.0))] < -0.5


def test_kurtogram_chooses_the_resonance_band():
    _, x = impact_signal()
    k = fast_kurtogram(x, FS)
    lo, hi = k.band
    assert lo <= F_RES <= hi
    assert k.best.kurtosis > 1.0
    assert k.n_levels == kurtogram_levels(x.size) == 8
    assert k.kurtosis.shape == (2 * k.n_levels, 3 * 2**k.n_levels)
    assert np.allclose(k.levels[:4], [0.0, 1.0, math.log2(3), 2.0])
    assert k.best.bandwidth == pytest.approx(FS / 2 ** (k.best.level + 1))


@pytest.mark.parametrize("snr_db", [0.0, -5.0])
def test_kurtogram_chooses_the_resonance_band_at_other_snr(snr_db):
    _, x = impact_signal(snr_db, seed=2)
    lo, hi = fast_kurtogram(x, FS).band
    assert lo <= F_RES <= hi


def test_kurtogram_of_a_tone_is_minus_one_in_its_band_and_zero_far_from_it():
    """Each row: the band holding the tone has K = -1; bands two or more away hold noise."""
    n = 2**15
    t = np.arange(n) / FS
    f_tone = 0.29 * FS
    x = np.cos(2 * np.pi * f_tone * t) + 0.01 * np.random.default_rng(7).standard_normal(n)
    k = fast_kurtogram(x, FS, levels=4)
    n_cols = k.kurtosis.shape[1]
    for level, row in zip(k.levels, k.kurtosis, strict=True):
        n_bands = round(2**level)
        values = row[:: n_cols // n_bands]
        i_tone = int(f_tone // (0.5 * FS / n_bands))
        assert values[i_tone] == pytest.approx(-1.0, abs=ATOL_TONE), level
        far = np.abs(np.arange(n_bands) - i_tone) >= 2
        # B*T independent complex samples per band: n / 2^(level+1)
        std = 2 / math.sqrt(n / 2 ** (level + 1))
        assert np.all(np.abs(values[far]) < N_SIGMA * std), level


def test_kurtogram_levels_and_refusals():
    assert kurtogram_levels(2**16) == 9
    assert kurtogram_levels(100) == 0
    x = np.random.default_rng(0).standard_normal(4096)
    with pytest.raises(InputError, match="levels"):
        fast_kurtogram(x, FS, levels=7)
    with pytest.raises(InputError, match="levels"):
        fast_kurtogram(x, FS, levels=0)
    with pytest.raises(InputError, match="length"):
        fast_kurtogram(x[:MIN_BAND_SAMPLES], FS)
    with pytest.raises(InputError, match="constant"):
        fast_kurtogram(np.ones(4096), FS)
    with pytest.raises(InputError, match="nperseg"):
        spectral_kurtosis(x, FS, nperseg=8192)
    with pytest.raises(InputError, match="hop"):
        spectral_kurtosis(x, FS, nperseg=64, hop=65)


def test_kurtogram_plot_returns_figure():
    _, x = impact_signal()
    fig = fast_kurtogram(x, FS).plot()
    assert isinstance(fig, Figure)
    assert len(fig.axes) == 2  # map and colour bar
