"""Indicators against hand-computed values: NB4, energy ratio, sideband index, sideband level
factor; and the shape statistics of timedomain (skewness, impulse, shape, clearance factors)
against numpy / scipy.stats and closed forms."""

import numpy as np
import pytest
import scipy.integrate
import scipy.stats
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals import timedomain as td
from gearsim.signals.demodulation import demodulate_tsa
from gearsim.signals.indicators import energy_ratio, nb4, sideband_index, sideband_level_factor
from gearsim.signals.tsa import TSA

M = 256
J = np.arange(M) / M


def _c(order, amp, phase=0.0):
    return amp * np.cos(2 * np.pi * order * J + phase)


def test_nb4_hand_values():
    env = 2.0 + _c(3, 0.4)  # fluctuation 0.4 cos: variance 0.08, 4th moment 0.4^4 * 3/8
    assert_allclose(nb4([env]), 1.5, rtol=1e-12)
    base = 2.0 + _c(3, 0.2)  # variance 0.02 -> average variance 0.05
    assert_allclose(nb4([base, env]), 0.4**4 * 0.375 / 0.05**2, rtol=1e-12)  # = 3.84
    # square wave fluctuation: kurtosis 1
    assert_allclose(nb4([1.0 + np.sign(np.cos(2 * np.pi * J + 0.01))]), 1.0, rtol=1e-12)


def test_nb4_from_demodulated_envelope():
    # mesh order 20 with 10 % amplitude modulation at order 2, demodulated +- 5.5 orders:
    # envelope 1 + 0.1 cos -> NB4 = 1.5
    avg = (1 + _c(2, 0.1)) * np.cos(2 * np.pi * 20 * J)
    env = demodulate_tsa(TSA(avg, 1, 1.0), teeth=20, sidebands=5).amplitude
    assert_allclose(nb4([env]), 1.5, rtol=1e-9)


def test_energy_ratio_hand_value():
    # regular: mesh order 16 (amp 2), sidebands 15/17 (0.4, 0.3), shaft order 1 (0.5),
    # difference: orders 5 (0.2) and 40 (0.1)
    reg = _c(16, 2.0) + _c(15, 0.4, 0.3) + _c(17, 0.3, 1.0) + _c(1, 0.5)
    diff = _c(5, 0.2) + _c(40, 0.1, 0.7)
    t = TSA(3.0 + reg + diff, 1, 1.0)
    expected = np.sqrt((0.2**2 + 0.1**2) / 2) / np.sqrt((4 + 0.16 + 0.09 + 0.25) / 2)
    assert_allclose(energy_ratio(t, teeth=16, shaft_harmonics=2), expected, rtol=1e-12)
    # no sidebands counted as regular: they move to the difference
    expected0 = (np.sqrt((0.04 + 0.01 + 0.16 + 0.09) / 2) / np.sqrt((4 + 0.25) / 2))
    assert_allclose(energy_ratio(t, teeth=16, shaft_harmonics=2, sideband_orders=0),
                    expected0, rtol=1e-12)


def test_sideband_index_and_level_factor_hand_values():
    avg = 0.7 + _c(16, 1.0) + _c(15, 0.25, 1.1) + _c(17, 0.15, -0.4) + _c(32, 0.5) + _c(31, 0.05)
    t = TSA(avg, 1, 1.0)
    assert_allclose(sideband_index(t, teeth=16), 0.2, rtol=1e-12)
    sd = np.sqrt((1 + 0.0625 + 0.0225 + 0.25 + 0.0025) / 2)  # the mean 0.7 is excluded
    assert_allclose(sideband_level_factor(t, teeth=16), 0.4 / sd, rtol=1e-12)
    assert_allclose(sideband_index(t, teeth=16, harmonic=2), 0.025, rtol=1e-12)
    assert_allclose(sideband_level_factor(t, teeth=16) * np.std(avg), 0.4, rtol=1e-12)


def test_refusals():
    t = TSA(_c(16, 1.0), 1, 1.0)
    with pytest.raises(InputError, match="envelopes"):
        nb4([])
    with pytest.raises(InputError, match="length"):
        nb4([np.ones(8) + np.arange(8), np.arange(9.0)])
    with pytest.raises(InputError, match="zero variance"):
        nb4([np.ones(16)])
    with pytest.raises(InputError, match="samples_per_rev"):
        sideband_index(t, teeth=16, harmonic=8)
    with pytest.raises(InputError, match="constant"):
        sideband_level_factor(TSA(np.ones(M), 1, 1.0), teeth=16)
    with pytest.raises(InputError, match="regular"):
        energy_ratio(TSA(_c(5, 1.0), 1, 1.0), teeth=16, shaft_harmonics=0, sideband_orders=0)


# --- shape statistics (appended to timedomain) -------------------------------------------

def _records():
    rng = np.random.default_rng(11)
    return (rng.standard_normal(4000), rng.exponential(size=3000) - 0.3,
            rng.standard_t(3, size=5000))


def test_skewness_equals_scipy():
    for x in _records():
        assert_allclose(td.skewness(x), scipy.stats.skew(x, bias=True), rtol=1e-10)


def test_factors_equal_numpy_expressions():
    for x in _records():
        a = np.abs(x)
        assert_allclose(td.impulse_factor(x), a.max() / a.mean(), rtol=1e-12)
        assert_allclose(td.shape_factor(x), np.sqrt(np.mean(x**2)) / a.mean(), rtol=1e-12)
        assert_allclose(td.clearance_factor(x), a.max() / np.mean(np.sqrt(a)) ** 2, rtol=1e-12)


def test_factors_of_a_sine_closed_forms():
    t = (np.arange(400_000) + 0.5) / 400_000  # one period, midpoint samples
    x = 3.0 * np.sin(2 * np.pi * t)  # the factors do not depend on the amplitude
    assert_allclose(td.impulse_factor(x), np.pi / 2, rtol=1e-9)
    assert_allclose(td.shape_factor(x), np.pi / (2 * np.sqrt(2)), rtol=1e-9)
    # clearance: mean of sqrt|sin| by numerical integration over a quarter period
    quarter, _ = scipy.integrate.quad(lambda th: np.sqrt(np.sin(th)), 0, np.pi / 2)
    mean_sqrt = quarter / (np.pi / 2)
    assert_allclose(mean_sqrt, 0.7627597635, rtol=1e-9)
    assert_allclose(td.clearance_factor(x), 1 / mean_sqrt**2, rtol=1e-6)  # 1.718796
    assert abs(td.skewness(x)) < 1e-9


def test_gaussian_shape_factor_and_impulsive_signal():
    x = np.random.default_rng(5).standard_normal(200_000)
    assert_allclose(td.shape_factor(x), np.sqrt(np.pi / 2), rtol=5e-3)
    y = x.copy()
    y[::1000] += 20.0  # one-sided impacts: positive skew, higher factors
    assert td.skewness(y) > 1.0
    assert td.impulse_factor(y) > td.impulse_factor(x)
    assert td.clearance_factor(y) > td.clearance_factor(x)


def test_shape_statistics_refusals():
    with pytest.raises(InputError, match="variance"):
        td.skewness(np.ones(10))
    for f in (td.impulse_factor, td.shape_factor, td.clearance_factor):
        with pytest.raises(InputError, match="mean"):
            f(np.zeros(10))
