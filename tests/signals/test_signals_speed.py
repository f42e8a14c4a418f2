"""Speed from the signal: tacho, tacholess tracking estimate, order tracking, tracked TSA,
given-speed check (the constant-speed estimate of short records: test_speed_short.py).

The synthetic truth: a shaft runs up smoothly from 10 to 30 Hz in 4 s
(``f = 10 + 10 (1 - cos(pi t / T))``) with a 1 % RMS jitter (sum of five sines of
random phase at 0.2-2 Hz); its angle is the integral of ``f``. A 20-tooth gear on it
gives mesh harmonics 1, 0.5, 0.25 at orders 20, 40, 60, amplitude-modulated 10 % at
shaft order 1, plus white noise at 0 dB against the mesh tone (variance 0.5 = the
power of the unit mesh tone), sampled at 20 kHz.
"""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import cumulative_trapezoid

from gearsim.errors import InputError
from gearsim.signals import ordertrack as ot
from gearsim.signals import speed as sp
from gearsim.signals import tsa as ts

FS = 20_000.0
DURATION = 4.0
TEETH = 20
MESH_AMPLITUDES = (1.0, 0.5, 0.25)
SEARCH = (8.0, 35.0)

#: Brief: the estimated instantaneous speed within 0.5 % RMS of the truth.
RTOL_SPEED_RMS = 0.005
#: The estimate's filter edge excluded from that comparison must stay short: at most
#: 0.5 s of each end of the 4 s record (it is half the demodulation FIR, 0.45 s here).
EDGE_MAX = 0.5
#: The mean speed from the mesh phase over ~3 s: the phase noise (0.02 rad at 0 dB
#: in a 20 Hz band) over 2 pi Z f T = 1e4 rad of phase is 2e-6; 1e-4 leaves room for
#: the filter edges (half a filter of 0.4 s at each end).
GIVEN_SPEED_PRECISION = 1e-4
#: Brief: the tracked TSA keeps >= 95 % of the mesh amplitude, the constant-speed TSA
#: < 50 %.
KEPT_TRACKED = 0.95
KEPT_CONSTANT = 0.5
#: Noise left in one order of the TSA: 2 sigma / sqrt(N) = 2 x 0.707 / sqrt(80000)
#: = 0.005 for N samples of noise of std sigma averaged; 0.025 is five of those.
ATOL_TSA_NOISE = 0.025
#: Tacho, sine-shaped pickup (zero crossing at an inflection: the interpolated crossing
#: is exact to third order). One pulse per revolution samples the 0.2-2 Hz jitter at
#: >= 10 pulses/s; the cubic spline's derivative error for a 2 Hz component at 0.1 s
#: spacing is about (2 pi 2 0.1)^3 / 24 = 8 % of the 1 % jitter, so 0.1 % RMS. Four
#: pulses per revolution shrink h^3 by 64: 1e-4.
RTOL_TACHO_1PPR = 1e-3
RTOL_TACHO_4PPR = 1e-4
#: Tacho, square pulses: each edge is quantised to one sample, so one pulse interval
#: at 4 pulses/rev and 30 Hz (167 samples) is off by up to 0.6 % and, for independent
#: uniform errors, 0.25 % RMS; allow twice that. The angle at a pulse is off by up to
#: one sample at the top speed: 30 / 20000 = 1.5e-3 rev.
RTOL_TACHO_SQUARE = 0.005
ATOL_ANGLE_SQUARE = 1.5e-3
#: Cubic-spline resampling of a tone with 54 samples per period: relative error
#: (5/384) (2 pi / 54)^4 = 2.4e-6 (Hall & Meyer 1976); 1e-4 leaves room for the
#: inversion of the angle.
ATOL_RESAMPLE = 1e-4


def _run_up(seed: int = 1):
    rng = np.random.default_rng(seed)
    t = np.arange(int(FS * DURATION)) / FS
    ramp = 10.0 + 10.0 * (1.0 - np.cos(np.pi * t / DURATION))
    fj = rng.uniform(0.2, 2.0, 5)
    ph = rng.uniform(0.0, 2 * np.pi, 5)
    jitter = np.sin(2 * np.pi * fj[:, None] * t + ph[:, None]).sum(axis=0)
    jitter /= np.sqrt(np.mean(jitter**2))
    f = ramp * (1.0 + 0.01 * jitter)
    theta = cumulative_trapezoid(f, t, initial=0.0)
    mesh = sum(a * np.cos(2 * np.pi * (k + 1) * TEETH * theta + 0.3 * k)
               for k, a in enumerate(MESH_AMPLITUDES))
    x = mesh * (1.0 + 0.1 * np.cos(2 * np.pi * theta))
    x = x + np.sqrt(0.5) * rng.standard_normal(t.size)
    return t, f, theta, x


@pytest.fixture(scope="module")
def run_up():
    return _run_up()


@pytest.fixture(scope="module")
def estimated(run_up):
    _, _, _, x = run_up
    return sp.estimate_speed(x, FS, order=TEETH, search=SEARCH)


@pytest.fixture(scope="module")
def constant_speed_record():
    rng = np.random.default_rng(7)
    f_r = 25.0
    t = np.arange(int(FS * 3.0)) / FS
    x = sum(a * np.cos(2 * np.pi * (k + 1) * TEETH * f_r * t)
            for k, a in enumerate(MESH_AMPLITUDES))
    return f_r, x + np.sqrt(0.5) * rng.standard_normal(t.size)


def _rel_rms(est, truth):
    return float(np.sqrt(np.mean(((est - truth) / truth) ** 2)))


# -- tacholess estimate ------------------------------------------------------------


def test_estimated_speed_follows_run_up_within_half_percent(run_up, estimated):
    t, f, _, _ = run_up
    p = estimated
    assert p.source == "estimate"
    assert 0.0 < p.edge <= EDGE_MAX
    inner = (t >= p.edge) & (t <= t[-1] - p.edge)
    err = _rel_rms(p.frequency[inner], f[inner])
    # measured: 1.5e-4 (0.015 %) inside, 2.9e-4 over the whole record
    assert err < RTOL_SPEED_RMS, f"speed RMS error {err:.2e}"
    assert _rel_rms(p.frequency, f) < RTOL_SPEED_RMS


def test_estimated_angle_is_the_shaft_angle(run_up, estimated):
    """The angle from the mesh phase is the shaft angle up to its unknown origin."""
    t, _, theta, _ = run_up
    p = estimated
    inner = (t >= p.edge) & (t <= t[-1] - p.edge)
    d = p.angle[inner] - theta[inner]
    # an angle error of 1/(8 Z) rev turns the mesh phase by 45 deg: keep well below
    assert np.ptp(d) < 1.0 / (8 * TEETH)


def test_estimate_from_rough_speed_and_second_harmonic(constant_speed_record):
    """Rough speed (search f0 / 1.25 .. 1.25 f0) and the mesh's second harmonic."""
    f_r, x = constant_speed_record
    p = sp.estimate_speed(x, FS, order=2 * TEETH, rough=f_r * 1.1)
    inner = (p.time >= p.edge) & (p.time <= p.time[-1] - p.edge)
    assert _rel_rms(p.frequency[inner], f_r) < RTOL_SPEED_RMS
    assert p.mean_frequency == pytest.approx(f_r, rel=GIVEN_SPEED_PRECISION)


@pytest.mark.parametrize(
    ("kwargs", "parameter"),
    [
        ({"order": TEETH}, "rough/search"),
        ({"order": TEETH, "rough": 20.0, "search": SEARCH}, "rough/search"),
        ({"order": TEETH, "search": (30.0, 10.0)}, "search"),
        ({"order": TEETH, "search": (8.0, 600.0)}, "fs"),
        ({"order": 0.0, "rough": 20.0}, "order"),
        ({"order": TEETH, "rough": 20.0, "bandwidth": -1.0}, "bandwidth"),
    ],
)
def test_estimate_refuses_bad_arguments(run_up, kwargs, parameter):
    x = run_up[3][:4000]
    with pytest.raises(InputError) as exc:
        sp.estimate_speed(x, FS, **kwargs)
    assert exc.value.parameter == parameter


def test_estimate_refuses_a_record_shorter_than_its_filter(run_up):
    with pytest.raises(InputError) as exc:
        sp.estimate_speed(run_up[3][:4000], FS, order=TEETH, rough=10.0)
    assert exc.value.parameter == "x.length"


# -- tacho ---------------------------------------------------------------------------


@pytest.mark.parametrize(("ppr", "rtol"), [(1, RTOL_TACHO_1PPR), (4, RTOL_TACHO_4PPR)])
def test_sine_tacho_recovers_profile(run_up, ppr, rtol):
    t, f, theta, _ = run_up
    tacho = -np.cos(2 * np.pi * ppr * theta)  # rising zero crossing at angle (i + 1/4) / ppr
    p = sp.speed_from_tacho(tacho, FS, pulses_per_rev=ppr)
    assert p.source == "tacho"
    assert p.time.size == pytest.approx(ppr * theta[-1], abs=1)
    assert _rel_rms(p.frequency, np.interp(p.time, t, f)) < rtol
    assert_allclose(np.diff(p.angle), 1.0 / ppr)


def test_square_tacho_four_per_rev_recovers_profile(run_up):
    t, f, theta, x = run_up
    tacho = (np.mod(4 * theta, 1.0) < 0.5).astype(float)
    p = sp.speed_from_tacho(tacho, FS, pulses_per_rev=4)
    assert _rel_rms(p.frequency, np.interp(p.time, t, f)) < RTOL_TACHO_SQUARE
    true_angle = np.interp(p.time, t, theta)  # pulse i at (i + k0) / 4 rev
    d = p.angle - true_angle
    assert np.ptp(d) < ATOL_ANGLE_SQUARE
    avg, quality = ot.tracked_tsa(x, FS, p, teeth=TEETH)
    assert quality >= KEPT_TRACKED
    assert avg.order_amplitudes()[TEETH] == pytest.approx(MESH_AMPLITUDES[0], abs=ATOL_TSA_NOISE)


def _tacho_error(make):
    with pytest.raises(InputError) as exc:
        sp.speed_from_tacho(make(), FS, pulses_per_rev=1)
    return exc.value


@pytest.mark.parametrize(
    "make",
    [
        lambda: np.array([]),  # empty
        lambda: np.ones(1000),  # constant: no pulses
        lambda: np.sin(2 * np.pi * 5.0 * np.arange(6000) / FS),  # 1 pulse: too sparse
        lambda: np.where(np.isin(np.arange(20_000) // 1000, [6]), 0.0,  # a missing pulse
                         (np.arange(20_000) % 1000 < 500).astype(float)),
        lambda: (np.isin(np.arange(20_000) % 1000, np.r_[0:100, 300:400])).astype(float),
    ],
    ids=["empty", "constant", "too-sparse", "missing-pulse", "extra-pulse"],
)
def test_bad_tacho_refused(make):
    err = _tacho_error(make)
    assert err.parameter.split(".")[0] == "tacho"


def test_tacho_with_too_few_pulses_for_one_revolution():
    tacho = np.sin(2 * np.pi * 40.0 * np.arange(4000) / FS)  # 8 pulses, 16 per rev
    with pytest.raises(InputError) as exc:
        sp.speed_from_tacho(tacho, FS, pulses_per_rev=16)
    assert exc.value.parameter == "tacho"


# -- profile -------------------------------------------------------------------------


def test_constant_profile_revolution_times_and_inverse():
    p = sp.SpeedProfile.constant(12.5, 2.0)
    assert p.source == "given"
    assert_allclose(p.revolution_times(), np.arange(26) / 12.5, atol=1e-12)
    assert_allclose(p.angle_at(p.times_at([0.3, 7.7])), [0.3, 7.7], atol=1e-12)
    assert_allclose(p.frequency_at([0.0, 1.0]), 12.5)
    assert p.mean_frequency == pytest.approx(12.5)


def test_profile_refuses_bad_arrays():
    with pytest.raises(InputError):
        sp.SpeedProfile(np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.array([1.0, 0.5]),
                        "given")
    with pytest.raises(InputError):
        sp.SpeedProfile(np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.array([0.0, 1.0]),
                        "guess")
    with pytest.raises(InputError):
        sp.SpeedProfile.constant(10.0, 1.0).times_at([20.0])


# -- order tracking and tracked TSA ---------------------------------------------------


def test_order_track_of_a_tone_is_the_tone_in_angle():
    fs, f_r, order = 5000.0, 13.3, 7  # 5000 / 93.1 = 54 samples per period
    t = np.arange(int(fs * 2.0)) / fs
    x = np.cos(2 * np.pi * order * f_r * t)
    y, angle = ot.order_track(x, fs, sp.SpeedProfile.constant(f_r, t[-1]), samples_per_rev=64)
    assert angle.size == 26 * 64
    assert_allclose(y, np.cos(2 * np.pi * order * angle), atol=ATOL_RESAMPLE)


def test_order_spectrum_has_sharp_mesh_lines(run_up, estimated):
    x = run_up[3]
    orders, amp = ot.order_spectrum(x, FS, estimated, samples_per_rev=2048)
    for k, a in enumerate(MESH_AMPLITUDES, start=1):
        i = int(np.argmin(abs(orders - k * TEETH)))
        assert orders[i] == pytest.approx(k * TEETH)
        assert amp[i] == pytest.approx(a, abs=ATOL_TSA_NOISE)
    assert orders[int(np.argmax(amp))] == pytest.approx(TEETH)


def test_tracked_tsa_keeps_mesh_where_constant_speed_tsa_loses_it(run_up, estimated):
    t, _, _, x = run_up
    avg, quality = ot.tracked_tsa(x, FS, estimated, teeth=TEETH)
    kept = avg.order_amplitudes()[[TEETH, 2 * TEETH, 3 * TEETH]]
    # measured: quality 0.999, orders 20/40/60 at 1.009/0.503/0.243
    assert quality >= KEPT_TRACKED
    assert kept[0] / MESH_AMPLITUDES[0] >= KEPT_TRACKED
    assert_allclose(kept, MESH_AMPLITUDES, atol=ATOL_TSA_NOISE)
    assert avg.shaft_frequency == pytest.approx(estimated.mean_frequency, rel=0.02)

    m = avg.samples_per_rev
    const = ts.tsa(x, FS, samples_per_rev=m, shaft_frequency=estimated.mean_frequency)
    const_kept = const.order_amplitudes()[TEETH] / MESH_AMPLITUDES[0]
    _, const_quality = ot.tracked_tsa(
        x, FS, sp.SpeedProfile.constant(estimated.mean_frequency, t[-1]), teeth=TEETH,
        samples_per_rev=m)
    # measured: 0.011 kept, quality 0.043
    assert const_kept < KEPT_CONSTANT
    assert const_quality < KEPT_CONSTANT


# -- given speed check -----------------------------------------------------------------


def test_given_speed_checked_on_half_a_second(constant_speed_record):
    """Eight periods suffice (the demodulation filter of the tracking estimate would need
    0.7 s); fewer are refused."""
    f_r, x = constant_speed_record
    half = x[: int(0.5 * FS)]
    assert sp.check_given_speed(half, FS, f_r, order=TEETH) is None
    assert "disagrees" in sp.check_given_speed(half, FS, f_r * 1.005, order=TEETH)
    with pytest.raises(InputError) as exc:
        sp.check_given_speed(x[: int(7 * FS / f_r)], FS, f_r, order=TEETH)
    assert exc.value.parameter == "x.length"


def test_given_speed_warning(constant_speed_record):
    f_r, x = constant_speed_record
    assert sp.check_given_speed(x, FS, f_r, order=TEETH) is None
    for wrong in (f_r * 1.005, f_r * 0.995):
        msg = sp.check_given_speed(x, FS, wrong, order=TEETH)
        assert msg is not None and "disagrees" in msg and f"{wrong:g} Hz" in msg
