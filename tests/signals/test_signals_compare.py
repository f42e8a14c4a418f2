"""Simulated-versus-measured sideband comparison (seed Table 2)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.compare import compare_sidebands, percentage_error
from gearsim.signals.synthetic import gear_signal

#: Sideband amplitudes are recovered within 1 % each (test_signals_spectrum); the error of
#: a ratio of two such estimates, in percentage points, then stays within about 2 points.
ATOL_POINTS = 2.0

F_R, TEETH = 1900.0 / 60.0, 39


def _sig(fs, level, gain, seed):
    sb = {(n, k): level * (0.1 if n == 1 else 0.05) for n in (1, 2) for k in (-2, -1, 1, 2)}
    x = gear_signal(fs=fs, duration=2.0, shaft_frequency=F_R, teeth=TEETH,
                    mesh_amplitudes={1: 1.0, 2: 0.5}, sidebands=sb, noise=1e-4, seed=seed)
    return gain * x


def test_percentage_error():
    assert_allclose(percentage_error([1.1, 0.9], [1.0, 1.0]), [10.0, 10.0], rtol=1e-12)
    assert np.isnan(percentage_error([1.0], [0.0])[0])


def test_relative_sideband_errors_match_known_ratio():
    sim = _sig(20_000.0, 1.2, 1000.0, 1)  # N, sidebands 20 % higher, other scale
    meas = _sig(25_000.0, 1.0, 0.01, 2)   # m/s^2, another fs
    c = compare_sidebands(sim, 20_000.0, meas, 25_000.0, mesh_frequency=TEETH * F_R,
                          shaft_frequency=F_R, orders=(1, 2), n_sidebands=2, normalize="mesh")
    assert c.simulated.shape == (2, 4)
    assert_allclose(c.error_percent, 20.0, atol=ATOL_POINTS)
    assert_allclose(c.mean_error_percent, 20.0, atol=ATOL_POINTS)
    d = c.to_dict()
    assert [r["order"] for r in d["orders"]] == [1, 2]


def test_absolute_comparison_and_bad_normalize():
    sim = _sig(20_000.0, 1.0, 1.0, 1)
    c = compare_sidebands(sim, 20_000.0, sim, 20_000.0, mesh_frequency=TEETH * F_R,
                          shaft_frequency=F_R, orders=(1,), n_sidebands=2, normalize="none")
    assert_allclose(c.error_percent, 0.0, atol=1e-9)
    with pytest.raises(InputError, match="normalize"):
        compare_sidebands(sim, 20_000.0, sim, 20_000.0, mesh_frequency=TEETH * F_R,
                          shaft_frequency=F_R, n_sidebands=2, normalize="rms")
