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


def _at(f_r, rel, mesh=1.0, noise=1e-3, seed=0):
    """Z = 32 at f_r, sidebands +-1, +-2 at ``rel`` (n=1) and ``rel / 2`` (n=2) of A_n."""
    sb = {(n, k): mesh * rel / n for n in (1, 2) for k in (-2, -1, 1, 2)}
    return gear_signal(fs=12_800.0, duration=2.0, shaft_frequency=f_r, teeth=32,
                       mesh_amplitudes={1: mesh, 2: 0.5 * mesh}, sidebands=sb, noise=noise,
                       seed=seed)


def test_each_record_read_at_its_own_speed():
    """A simulation at 30 Hz (f_m 960 Hz) against a record at 29.675 Hz (f_m 949.6 Hz,
    10.4 Hz away, beyond the +-7.5 Hz search): relative sidebands 0.10 and 0.12, so every
    error is |0.10 - 0.12| / 0.12 = 16.7 % (before: one speed for both, 99 % or 7e11 %)."""
    sim, meas = _at(30.0, 0.10, seed=1), _at(29.675, 0.12, mesh=0.02, seed=2)
    c = compare_sidebands(sim, 12_800.0, meas, 12_800.0, mesh_frequency=960.0,
                          shaft_frequency=30.0, measured_shaft_frequency=29.675,
                          n_sidebands=2)
    assert_allclose(c.error_percent, 100 * 0.02 / 0.12, atol=ATOL_POINTS)
    assert_allclose(c.measured[0], 0.12, rtol=0.02)
    m = c.to_dict()["mesh"]  # both mesh lines used to normalise, at their own frequencies
    assert_allclose([r["frequency_hz"] for r in m["measured"]], [949.6, 1899.2], atol=0.05)
    assert_allclose([r["amplitude"] for r in m["simulated"]], [1.0, 0.5], rtol=0.01)
    assert_allclose([r["amplitude"] for r in m["measured"]], [0.02, 0.01], rtol=0.01)


def test_a_mesh_line_not_there_is_refused():
    """Read at 30 Hz, the record at 29.675 Hz has no line within 960 +- 7.5 Hz: noise
    (floor 1e-3) is not a mesh line to divide by (before: relative sidebands near 1)."""
    sim, meas = _at(30.0, 0.10, seed=1), _at(29.675, 0.12, mesh=0.02, seed=2)
    with pytest.raises(InputError, match=r"^measured mesh line = 1 f_m = 960 Hz: no line "
                       r"above the noise floor .* is 30 Hz this record's shaft speed\?$"):
        compare_sidebands(sim, 12_800.0, meas, 12_800.0, mesh_frequency=960.0,
                          shaft_frequency=30.0, n_sidebands=2)
    c = compare_sidebands(sim, 12_800.0, meas, 12_800.0, mesh_frequency=960.0,
                          shaft_frequency=30.0, n_sidebands=2, normalize="none")
    assert c.mesh["measured"][0]["p_value"] > 1e-3  # reported, not refused, without "mesh"
