"""Periodicity verdict of impacts from the squared-envelope spectrum."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.periodicity import (
    impact_periodicity,
    line_significance,
    periodogram,
    squared_envelope,
)
from gearsim.signals.synthetic import ImpactSpec, gear_signal

FS = 20_000.0
F_R = 10.0
TEETH = 25
NOISE = 0.5  # noise standard deviation; mesh tone amplitude 1 (SNR of the tone: 3 dB)
#: Impacts: peak 1.5 = 3 x the noise std (9.5 dB), 1 ms decay, 3 kHz resonance.
IMPACT = ImpactSpec(amplitude=1.5, decay=1e-3, carrier=3000.0, first=0.0123)
BAND = (2000.0, 4000.0)


def _record(impacts, seed):
    return gear_signal(fs=FS, duration=10.0, shaft_frequency=F_R, teeth=TEETH,
                       mesh_amplitudes={1: 1.0, 2: 0.3}, impacts=impacts, noise=NOISE, seed=seed)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_impacts_in_noise_are_periodic(seed):
    x = _record(IMPACT, seed)
    r = impact_periodicity(x, FS, frequency=F_R, band=BAND)
    assert r.verdict == "periodic" and r.periodic
    assert r.p_value < 1e-20  # measured 2e-41 .. 4e-55
    assert np.all(r.snr_db > 15.0)  # measured 17.7 .. 22.4 dB
    assert_allclose(r.line_frequencies, F_R * np.arange(1, 4), atol=r.df)
    # the whole band, without demodulating the resonance, still sees it (less strongly)
    assert impact_periodicity(x, FS, frequency=F_R).periodic


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_healthy_gear_in_noise_is_not_periodic(seed):
    x = _record(None, seed)
    for band in (None, BAND):
        r = impact_periodicity(x, FS, frequency=F_R, band=band)
        assert r.verdict == "not periodic"
        assert r.p_value > 0.01  # measured 0.31 .. 0.96


def test_false_alarm_rate_is_at_most_alpha():
    """Pure Gaussian noise, 200 seeds: the fraction with p < 0.05 stays near or below 5 %
    (measured 0.024 over 1000 seeds: Sidak and Fisher on super-uniform p are conservative)."""
    hits = 0
    for seed in range(200):
        x = np.random.default_rng(seed).standard_normal(20_000)
        hits += impact_periodicity(x, 2000.0, frequency=10.0, alpha=0.05).periodic
    assert hits / 200 <= 0.09  # binomial: 0.05 + 2.6 sigma


def test_exponential_floor_law():
    """The p-value of one bin is exp(-SNR) with the floor median / ln 2: check the law on
    exponential samples (the null distribution of a periodogram bin)."""
    rng = np.random.default_rng(3)
    p = rng.exponential(scale=2.0, size=200_001)
    floor = np.median(p) / math.log(2)
    assert_allclose(floor, 2.0, rtol=0.01)
    for kappa in (1.0, 3.0, 6.0):
        assert_allclose(np.mean(p > kappa * floor), math.exp(-kappa), rtol=0.08)


def test_line_significance_hand_value():
    p = np.full(301, 2.0)
    p[100] = 2.0 * 8.0 / math.log(2)  # SNR 8 exactly
    r = line_significance(p, 100.4, search_bins=2)
    assert r.bin == 100 and r.searched == 5
    assert_allclose(r.snr, 8.0, rtol=1e-12)
    n = r.floor_bins  # 50 bins: every second one of 4..53 bins away on each side
    assert n == 50
    t = 8.0 / math.log(2)  # line / median
    p1 = np.prod([(n - i) / (n - i + t) for i in range(25)])
    assert_allclose(r.p_value, 1 - (1 - p1) ** 5, rtol=1e-12)
    assert math.exp(-8.0) < p1 < 4 * math.exp(-8.0)  # 3.2x here; tends to exp(-SNR) for many bins


def test_order_statistic_p_value_is_calibrated():
    """Independent exponential bins (the null of a periodogram): P(p_1 < q) = q."""
    rng = np.random.default_rng(9)
    pv = np.array([line_significance(rng.exponential(size=121), 60, search_bins=0).p_value
                   for _ in range(4000)])
    for q in (0.5, 0.1, 0.01):
        assert abs(np.mean(pv < q) - q) < 4 * np.sqrt(q * (1 - q) / 4000) + 1e-3


def test_squared_envelope_of_am_tone_and_periodogram_of_tone():
    t = np.arange(4000) / 4000.0
    x = (1 + 0.5 * np.cos(2 * np.pi * 7 * t)) * np.cos(2 * np.pi * 500 * t)
    assert_allclose(squared_envelope(x, 4000.0), (1 + 0.5 * np.cos(2 * np.pi * 7 * t)) ** 2,
                    atol=1e-10)
    se = squared_envelope(x, 4000.0, band=(400.0, 600.0))
    assert_allclose(se, (1 + 0.5 * np.cos(2 * np.pi * 7 * t)) ** 2, atol=1e-10)
    assert int(np.argmax(periodogram(se))) == 7


def test_refusals():
    x = _record(None, 0)[:20_000]
    with pytest.raises(InputError, match="harmonics"):
        impact_periodicity(x, FS, frequency=F_R, harmonics=300, band=BAND)
    with pytest.raises(InputError, match="band"):
        impact_periodicity(x, FS, frequency=F_R, band=(3000.0, 2000.0))
    with pytest.raises(InputError, match="alpha"):
        impact_periodicity(x, FS, frequency=F_R, alpha=1.5)
    with pytest.raises(InputError, match="floor"):
        impact_periodicity(x[:4000], FS, frequency=F_R)  # 0.2 s: 2 bins per harmonic
