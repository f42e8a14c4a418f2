"""Time-synchronous averaging and FM0 / FM4 / NA4 / M6A / M8A."""

import numpy as np
import pytest
import scipy.stats
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals import tsa as ts

#: Standard error of a standard deviation estimated from M Gaussian samples is
#: 1/sqrt(2M) = 1.1 % for M = 4096; 5 % is more than four standard errors.
RTOL_NOISE = 0.05
#: Kurtosis of N Gaussian samples has standard error sqrt(24/N) = 0.019 for N = 65536;
#: 0.1 is five standard errors. M6A and M8A scale with their own spreads (sqrt(720/N)
#: x ... ~0.5 and ~6); tolerances below are set at about five of those.
ATOL_FM4 = 0.1
ATOL_M6A = 1.5
ATOL_M8A = 25.0
#: Cubic-spline resampling of a component with 20+ samples per period: error < 0.1 %;
#: 1 % is the brief's amplitude tolerance.
RTOL_SYNC = 0.01
#: A square tacho switches within one sample: each edge time is uncertain by up to one
#: sample, i.e. 1/(fs/f_r) = 1/800 of a revolution here; allow two samples.
RTOL_TACHO = 2.5e-3


def test_tsa_reduces_noise_by_sqrt_n():
    m, n_rev = 4096, 64
    f_r = 10.0
    fs = m * f_r  # integer samples per revolution: resampling is exact at the nodes
    rng = np.random.default_rng(5)
    sigma = 1.0
    x = sigma * rng.standard_normal(m * n_rev + 1)
    avg = ts.tsa(x, fs, samples_per_rev=m, shaft_frequency=f_r)
    assert avg.n_averages == n_rev
    assert_allclose(np.std(avg.average), sigma / np.sqrt(n_rev), rtol=RTOL_NOISE,
                    err_msg="non-synchronous noise must fall as 1/sqrt(N)")


def test_tsa_keeps_synchronous_and_removes_other_shaft():
    fs, f_r, teeth = 25_000.0, 1900.0 / 60.0, 39  # fs / f_r is not an integer
    t = np.arange(int(fs * 3.0)) / fs
    sync = 1.0 * np.cos(2 * np.pi * teeth * f_r * t) + 0.3 * np.cos(2 * np.pi * 2 * f_r * t)
    other = 0.8 * np.cos(2 * np.pi * 20.93 * 7.3 * t)  # not a shaft-1 order
    avg = ts.tsa(sync + other, fs, samples_per_rev=1024, shaft_frequency=f_r)
    orders = avg.order_amplitudes()
    assert_allclose(orders[teeth], 1.0, rtol=RTOL_SYNC)
    assert_allclose(orders[2], 0.3, rtol=RTOL_SYNC)
    assert np.delete(orders, [2, teeth]).max() < 0.05


def test_tacho_tsa_matches_known_speed():
    fs, f_r = 20_000.0, 25.0
    t = np.arange(int(fs * 2.0)) / fs
    x = np.cos(2 * np.pi * 20 * f_r * t + 0.4)
    tacho = (np.mod(t * f_r, 1.0) < 0.1).astype(float)  # rising edge at each revolution
    pulses = ts.pulse_times(tacho, fs)
    assert_allclose(np.diff(pulses), 1.0 / f_r, rtol=RTOL_TACHO)
    a = ts.tsa(x, fs, samples_per_rev=512, pulses=pulses)
    b = ts.tsa(x, fs, samples_per_rev=512, shaft_frequency=f_r)
    ao, bo = a.order_amplitudes(), b.order_amplitudes()
    assert_allclose(ao[20], bo[20], rtol=RTOL_SYNC)
    assert_allclose(a.shaft_frequency, f_r, rtol=RTOL_TACHO)


def test_fm4_m6a_m8a_of_gaussian_noise():
    rng = np.random.default_rng(2024)
    d = rng.standard_normal(65536)
    assert_allclose(ts.fm4(d), 3.0, atol=ATOL_FM4)
    assert_allclose(ts.m6a(d), 15.0, atol=ATOL_M6A)
    assert_allclose(ts.m8a(d), 105.0, atol=ATOL_M8A)


def test_moment_ratios_of_a_tiny_signal_are_its_moments():
    # a healthy simulated difference signal can be ~1e-40: m2**4 underflows to 0, and the
    # ratio must still be the standardised moment (scipy.stats: kurtosis; for 6 and 8,
    # the moment of the signal scaled to unit variance in double precision)
    rng = np.random.default_rng(7)
    d = rng.standard_normal(4096) ** 3
    z = (d - d.mean()) / d.std()
    for scale in (1.0, 1e-40, 1e20):
        assert_allclose(ts.fm4(scale * d), scipy.stats.kurtosis(d, fisher=False), rtol=1e-12)
        assert_allclose(ts.m6a(scale * d), np.mean(z**6), rtol=1e-12)
        assert_allclose(ts.m8a(scale * d), np.mean(z**8), rtol=1e-12)


def test_fm4_of_difference_signal_of_noisy_tsa_is_gaussian():
    # TSA of noise plus mesh tone: removing the regular orders leaves Gaussian noise.
    m, teeth = 65536, 39
    rng = np.random.default_rng(9)
    avg = np.cos(2 * np.pi * teeth * np.arange(m) / m) + 0.05 * rng.standard_normal(m)
    t = ts.TSA(average=avg, n_averages=1, shaft_frequency=1.0)
    d = ts.difference_signal(t, teeth=teeth, shaft_harmonics=2, sideband_orders=1)
    assert_allclose(ts.fm4(d), 3.0, atol=ATOL_FM4)


def test_regular_difference_residual_partition():
    m, teeth = 1024, 20
    k = np.arange(m)
    comps = {1: 0.5, 20: 1.0, 21: 0.2, 40: 0.4, 7: 0.1}
    avg = sum(a * np.cos(2 * np.pi * o * k / m) for o, a in comps.items())
    t = ts.TSA(average=avg, n_averages=10, shaft_frequency=1.0)
    d = ts.difference_signal(t, teeth=teeth, shaft_harmonics=2, sideband_orders=1)
    r = ts.residual_signal(t, teeth=teeth, shaft_harmonics=2)
    reg = ts.regular_signal(t, teeth=teeth, shaft_harmonics=2, sideband_orders=1)
    assert_allclose(d, 0.1 * np.cos(2 * np.pi * 7 * k / m), atol=1e-12)
    assert_allclose(r, 0.1 * np.cos(2 * np.pi * 7 * k / m) + 0.2 * np.cos(2 * np.pi * 21 * k / m),
                    atol=1e-12)
    assert_allclose(reg + d, avg - avg.mean(), atol=1e-12)


def test_fm0_definition():
    m, teeth = 1024, 16
    k = np.arange(m)
    avg = 1.0 * np.cos(2 * np.pi * teeth * k / m) + 0.5 * np.cos(2 * np.pi * 2 * teeth * k / m)
    t = ts.TSA(average=avg, n_averages=1, shaft_frequency=1.0)
    assert_allclose(ts.fm0(t, teeth=teeth), (avg.max() - avg.min()) / 1.5, rtol=1e-12)


def test_na4_uses_run_average_variance():
    rng = np.random.default_rng(1)
    r1 = rng.standard_normal(4096)
    r2 = 2.0 * rng.standard_normal(4096)
    c = r2 - r2.mean()
    expected = np.mean(c**4) / np.mean([np.var(r1), np.var(r2)]) ** 2
    assert_allclose(ts.na4([r1, r2]), expected, rtol=1e-12)
    assert_allclose(ts.na4([r2]), ts.fm4(r2), rtol=1e-12)
    with pytest.raises(InputError, match="length"):
        ts.na4([r1[:10], r2])


def test_tsa_input_errors():
    with pytest.raises(InputError, match="exactly one"):
        ts.tsa(np.ones(100), 100.0, samples_per_rev=8)
    with pytest.raises(InputError, match="at least one revolution"):
        ts.tsa(np.ones(100), 100.0, samples_per_rev=8, shaft_frequency=0.5)
    with pytest.raises(InputError, match="tacho"):
        ts.pulse_times(np.ones(100), 100.0)
