"""Time-domain statistics and impact detection on signals with known content."""

import numpy as np
import pytest
import scipy.stats
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals import timedomain as td
from gearsim.signals.synthetic import ImpactSpec, gear_signal

#: Statistics are closed-form sums: agreement with scipy/numpy to float64 round-off.
RTOL_EXACT = 1e-10
#: Brief requirement: impact period within 1 %.
RTOL_PERIOD = 0.01

FS = 20_000.0
F_R = 1900.0 / 60.0
TEETH = 39


def _impact_signal(seed: int = 1) -> np.ndarray:
    return gear_signal(
        fs=FS, duration=2.0, shaft_frequency=F_R, teeth=TEETH, mesh_amplitudes={1: 1.0},
        impacts=ImpactSpec(amplitude=5.0, decay=4e-4, carrier=3000.0, first=0.0123),
        noise=0.05, seed=seed,
    )


def test_rms_peak_crest_of_sine():
    t = np.arange(20_000) / FS
    x = 2.0 * np.sin(2 * np.pi * 50.0 * t)  # whole number of periods
    assert_allclose(td.rms(x), 2.0 / np.sqrt(2.0), rtol=RTOL_EXACT)
    assert_allclose(td.peak(x), 2.0, rtol=1e-6)
    assert_allclose(td.crest_factor(x), np.sqrt(2.0), rtol=1e-6)


def test_kurtosis_equals_scipy_pearson():
    rng = np.random.default_rng(7)
    for x in (rng.standard_normal(5000), rng.exponential(size=3000), _impact_signal()):
        assert_allclose(td.kurtosis(x), scipy.stats.kurtosis(x, fisher=False), rtol=RTOL_EXACT)


def test_time_stats_and_ratios():
    x = _impact_signal() + 10.0
    s = td.time_stats(x, remove_mean=True)
    assert_allclose(s.mean, np.mean(x), rtol=RTOL_EXACT)
    assert_allclose(s.rms, np.std(x), rtol=1e-9)
    b = td.time_stats(0.5 * x, remove_mean=True)
    r = td.ratios_to_baseline(s, b)
    assert_allclose([r["rms"], r["peak"], r["crest_factor"], r["kurtosis"]], [2, 2, 1, 1],
                    rtol=1e-9)
    with pytest.raises(InputError, match="mean_removed"):
        td.ratios_to_baseline(s, td.time_stats(x, remove_mean=False))


def test_impact_period_within_one_percent():
    x = _impact_signal()
    thr = td.impact_threshold(x, FS, window=1.0 / (TEETH * F_R), factor=1.5)
    imp = td.detect_impacts(x, FS, min_separation=0.5 / F_R, threshold=thr)
    assert imp.count >= 60  # 2 s x 31.7 Hz = 63 impacts
    assert_allclose(imp.period, 1.0 / F_R, rtol=RTOL_PERIOD, err_msg="impact period")
    assert_allclose(imp.times[0], 0.0123, atol=2e-3)


def test_impact_period_survives_missed_impacts():
    x = _impact_signal()
    thr = td.impact_threshold(x, FS, window=1.0 / (TEETH * F_R), factor=1.5)
    # Remove every third impact: the period is fitted against cycle numbers, not intervals.
    for i in range(0, 63, 3):
        start = int((0.0123 + i / F_R) * FS) - 5
        x[start : start + 60] = 0.0
    imp = td.detect_impacts(x, FS, min_separation=0.5 / F_R, threshold=thr)
    assert imp.count < 50
    assert_allclose(imp.period, 1.0 / F_R, rtol=RTOL_PERIOD)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_samples_refused(bad):
    x = np.ones(100)
    x[17] = bad
    with pytest.raises(InputError, match=r"signal\[17\]") as err:
        td.rms(x)
    assert "\n" not in str(err.value)


def test_constant_signal_refused_for_kurtosis():
    with pytest.raises(InputError, match="variance"):
        td.kurtosis(np.ones(10))
