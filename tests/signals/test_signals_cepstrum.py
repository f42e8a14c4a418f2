"""Real cepstrum, cepstral peak and cepstral pre-whitening on signals of known content.

Known answers: an echo of gain ``a`` after ``d`` samples puts ``a/2`` at quefrency ``d``;
sidebands spaced ``f_s`` (once-per-revolution modulation of the mesh) put a rahmonic at
``1/f_s``; pre-whitening leaves a flat amplitude spectrum and the phase, hence impulses
(Sawalhi & Randall 2011; Borghesani et al. 2013).
"""

import math

import numpy as np
import pytest
from matplotlib.figure import Figure
from scipy.signal import welch
from scipy.stats import kurtosis

from gearsim.errors import InputError
from gearsim.signals.cepstrum import cepstral_peak, prewhiten, real_cepstrum
from gearsim.viz.toolbox import plot_cepstrum

FS = 20_000.0
DURATION = 2.0  # s
F_SHAFT = 25.0  # Hz: period 40 ms = 800 samples
TEETH = 32  # mesh 800 Hz
SEARCH = (0.02, 0.06)  # s: holds one revolution, not its half or double
#: Welch PSD (1024-sample Hann segments, 77 averages) of white noise scatters by about
#: 10 log10(e) / sqrt(77) = 0.5 dB; a whitened record must stay within twice that.
FLAT_DB = 1.0
#: Echo amplitude a/2 from a finite series: exact to round-off.
ATOL_ECHO = 1e-9


def gear_signal(modulated: bool, seed: int = 3) -> np.ndarray:
    """Ten mesh harmonics (amplitude 1/h) with a local AM + PM once per revolution.

    The modulation is a Gaussian pulse (sigma 1 ms) of depth 0.5 in amplitude and 0.5 rad
    (times the harmonic number) in phase, as a local tooth fault would cause; white noise
    of standard deviation 0.01.
    """
    n = int(FS * DURATION)
    t = np.arange(n) / FS
    phase = (t * F_SHAFT) % 1.0
    dt = np.minimum(phase, 1 - phase) / F_SHAFT  # time to the nearest revolution start
    pulse = np.exp(-0.5 * (dt / 1e-3) ** 2) if modulated else np.zeros(n)
    fm = TEETH * F_SHAFT
    x = sum(np.cos(2 * np.pi * h * fm * t + h * 0.5 * pulse + 0.7 * h) / h for h in range(1, 11))
    x = (1 + 0.5 * pulse) * x
    return x + 0.01 * np.random.default_rng(seed).standard_normal(n)


def test_echo_rahmonic_closed_form():
    x = np.zeros(512)
    x[0], x[16] = 1.0, 0.4  # impulse and an echo of gain 0.4 after 16 samples
    q, c = real_cepstrum(x, 1000.0)
    assert q.size == 257 and q[16] == pytest.approx(0.016)
    # ln|1 + a z^d| = a cos(w d) - a^2/2 cos(2 w d) + ...: a/2 at d, -a^2/4 at 2d
    assert c[16] == pytest.approx(0.2, abs=ATOL_ECHO)
    assert c[32] == pytest.approx(-0.04, abs=ATOL_ECHO)
    assert c[0] == pytest.approx(0.0, abs=ATOL_ECHO)


def test_cepstrum_finds_the_shaft_period_within_one_sample():
    q, c = real_cepstrum(gear_signal(True), FS)
    peak = cepstral_peak(q, c, search=SEARCH)
    assert abs(peak.quefrency - 1 / F_SHAFT) <= 1 / FS
    assert abs(peak.index - 800) <= 1
    # without the modulation the 40 ms value is small: the peak is the modulation's
    q0, c0 = real_cepstrum(gear_signal(False), FS)
    assert peak.value > 5 * cepstral_peak(q0, c0, search=SEARCH).value


def jittered_impacts(n: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """3 kHz ringing (damping 0.1) every 1/37 s with 1 % random jitter of the times."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    times = np.arange(0.0, DURATION - 0.01, 1 / 37.0) + 0.003
    times += 0.01 / 37.0 * rng.standard_normal(times.size)
    x = np.zeros(n)
    for tk in times:
        tau = t - tk
        m = tau >= 0
        x[m] += np.exp(-0.1 * 2 * np.pi * 3000.0 * tau[m]) * np.sin(2 * np.pi * 3000.0 * tau[m])
    return times, x


def log_psd_std(x: np.ndarray) -> float:
    """Standard deviation over frequency of the Welch PSD in dB (DC and Nyquist left out)."""
    _, p = welch(x, FS, nperseg=1024)
    return float(np.std(10 * np.log10(p[1:-1])))


def test_prewhitening_flattens_the_spectrum_and_keeps_the_impulses():
    n = int(FS * DURATION)
    t = np.arange(n) / FS
    times, impacts = jittered_impacts(n)
    mesh = sum(np.cos(2 * np.pi * h * 800.0 * t + 0.7 * h) / h for h in range(1, 11))
    noise = 0.05 * np.random.default_rng(4).standard_normal(n)
    x = 10 * mesh + impacts + noise  # the mesh tones are 10x the impacts
    y = prewhiten(x)
    assert log_psd_std(x) > 10.0  # 12.4 dB: lines and a resonance
    assert log_psd_std(y) < FLAT_DB  # 0.16 dB
    assert np.sqrt(np.mean(y**2)) == pytest.approx(np.sqrt(np.mean(x**2)))

    def impulses_stand_out(s: np.ndarray) -> bool:
        """Each impact's peak (first ms) exceeds every sample away from the impacts."""
        starts = np.round(times * FS).astype(int)
        at = np.array([np.max(np.abs(s[i : i + 20])) for i in starts])
        away = np.ones(n, dtype=bool)
        for i in starts:
            away[max(i - 2, 0) : i + 40] = False
        return bool(at.min() > np.max(np.abs(s[away])))

    assert not impulses_stand_out(x)  # buried under the mesh tones
    assert impulses_stand_out(y)
    assert kurtosis(y) > kurtosis(x) + 3.0  # 7.3 against 2.8


def test_unit_impulse_is_unchanged_by_prewhitening():
    x = np.zeros(100)
    x[37] = 2.0
    assert np.allclose(prewhiten(x), x, atol=1e-12)


def test_refusals():
    q, c = real_cepstrum(np.random.default_rng(0).standard_normal(100), 1000.0)
    with pytest.raises(InputError, match="search"):
        cepstral_peak(q, c, search=(0.03, 0.01))
    with pytest.raises(InputError, match="search"):
        cepstral_peak(q, c, search=(1.0, 2.0))  # beyond the last quefrency
    with pytest.raises(InputError, match="c"):
        cepstral_peak(q, c[:-1], search=(0.01, 0.03))
    with pytest.raises(InputError, match="zeros"):
        real_cepstrum(np.zeros(16), 1000.0)
    with pytest.raises(InputError, match="zeros"):
        prewhiten(np.zeros(16))


def test_cepstrum_plot_returns_figure():
    q, c = real_cepstrum(gear_signal(True), FS)
    fig = plot_cepstrum(q, c, q_max=0.1, peak=cepstral_peak(q, c, search=SEARCH).quefrency)
    assert isinstance(fig, Figure)
    assert len(fig.axes[0].lines) == 1 + 2  # cepstrum and rahmonics at 40 and 80 ms
    assert math.isclose(fig.axes[0].get_xlim()[1], 100.0)
