"""Separated synchronous averages of the planets and the sun (McFadden 1991, 1994).

The synthetic signals are built here from the kinematics alone (ring fixed, carrier angle
theta_c = 2 pi f_c t, planet n at the carrier-fixed angle psi_n, sensor at theta_s):

* ring mesh of planet n: cos(z_r (theta_c + psi_n)) (all planets mesh in the same phase
  with a given ring tooth, McFadden & Smith 1985), seen through a transfer path that is a
  Hann bell of width 2 pi / N in carrier angle centred on the planet's pass;
* a planet rolls along the fixed ring by one tooth per 2 pi / z_r of carrier angle, so
  its tooth j (tooth 0 at the sensor at its first pass after theta_c = 0, theta_n0) is
  in the ring mesh at theta_c = theta_n0 + 2 pi (j + q z_p) / z_r;
* the sun turns by (z_r / z_s) theta_c relative to the carrier (Willis); its tooth j
  (numbered in the order the teeth meet a planet; tooth 0 meets planet 0 at theta_00)
  sits at the carrier-frame angle psi_0 + (z_r / z_s)(theta_c - theta_00) - 2 pi j / z_s
  and meshes with planet n when that angle equals psi_n (mod 2 pi).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals.planet_tsa import SeparatedAverage, planet_average, sun_average

#: Stage with gcd(z_r, z_p) = gcd(z_r, z_s) = 1 (every tooth reaches the sensor) and
#: (z_s + z_r) / N = 30 whole (equally spaced planets can be assembled).
ZS, ZP, ZR, N = 19, 26, 71, 3
FC = 5.0  # carrier [Hz]; mesh 355 Hz
FS = 8000.0  # [Hz]: 22.5 samples per mesh period
REVS = 30  # carrier revolutions: > z_p = 26, the planet's tooth cycle
M = 32
PSI = 2 * np.pi * np.arange(N) / N
SENSOR = 0.4  # rad

#: The fault shows within one tooth of its true position.
TOOTH_TOL = 1.0
#: A fault on planet 1 leaks into planet 0's average only through the transfer path while
#: planet 0 passes, which is zero here (planet 1 is 2 pi / 3 away, the bell +-pi / 3 wide):
#: the residue is spline ringing of far impulses, < 1e-6 of the fault peak. 5 % is the
#: separation a diagnosis needs.
RATIO_OTHER = 0.05
#: Over 4 planet cycles (104 carrier revolutions) each tooth of planet 0 is averaged over 4
#: passes, while the damaged sun tooth is at the sensor with planet 0 every 19th pass and
#: then meets a different planet tooth each time (71 x 19 = 23 mod 26): in planet 0's
#: average the sun fault is at most 1/4 of its height in the sun average (where every
#: pass that sees sun tooth 5 carries it); 0.5 leaves a margin for the window edges.
RATIO_SUN_IN_PLANET = 0.5
REVS_LONG = 4 * ZP
#: A pure mesh tone resampled by a cubic spline at 22 samples per period keeps > 99.9 % of
#: its energy in its bin; 0.9 is the brief's criterion.
ENERGY_MIN = 0.9
#: Pulse- and speed-driven averages use the same instants up to round-off of the
#: angle-to-time interpolation (1e-12 relative); 1e-6 is the brief's tolerance.
RTOL_SAME = 1e-6


def _time(revs: float = REVS, fs: float = FS) -> np.ndarray:
    return np.arange(int(round(revs / FC * fs)) + 1) / fs


def _first_pass(n: int, psi=PSI, sensor=SENSOR) -> float:
    """Carrier angle [rad] of planet n's first pass after theta_c = 0."""
    return float(np.mod(sensor - psi[n], 2 * np.pi))


def _gate(theta: np.ndarray, n: int, planets=N, psi=PSI, sensor=SENSOR) -> np.ndarray:
    """Transfer path of planet n: Hann bell of width 2 pi / N about its pass."""
    d = np.angle(np.exp(1j * (theta + psi[n] - sensor)))
    return np.where(np.abs(d) < np.pi / planets, np.cos(planets * d / 2) ** 2, 0.0)


def _mesh(t: np.ndarray, z_ring=ZR, planets=N, psi=PSI, sensor=SENSOR, theta=None
          ) -> np.ndarray:
    theta = 2 * np.pi * FC * t if theta is None else theta
    return sum(_gate(theta, n, planets, psi, sensor) * np.cos(z_ring * (theta + psi[n]))
               for n in range(planets))


def _pulse_train(t: np.ndarray, thetas: np.ndarray, gains: np.ndarray, time_of=None
                 ) -> np.ndarray:
    """Gaussian impacts (sigma 0.1 mesh period, amplitude 0.5 x gain) at the carrier angles
    (converted to time by ``time_of``, constant speed FC by default)."""
    sigma = 0.1 / (ZR * FC)
    x = np.zeros_like(t)
    times = thetas / (2 * np.pi * FC) if time_of is None else time_of(thetas)
    for tq, g in zip(times, gains, strict=True):
        sl = slice(max(0, int((tq - 8 * sigma) * FS)), int((tq + 8 * sigma) * FS) + 2)
        x[sl] += 0.5 * g * np.exp(-0.5 * ((t[sl] - tq) / sigma) ** 2)
    return x


def _planet_fault(t: np.ndarray, planet: int, tooth: int, theta_end=None, time_of=None
                  ) -> np.ndarray:
    theta0 = _first_pass(planet)
    theta_end = 2 * np.pi * FC * t[-1] if theta_end is None else theta_end
    q = np.arange(-1, int(theta_end / (2 * np.pi) * ZR / ZP) + 2)
    thetas = theta0 + 2 * np.pi * (tooth + q * ZP) / ZR
    thetas = thetas[(thetas > 0) & (thetas < theta_end)]
    return _pulse_train(t, thetas, _gate(thetas, planet), time_of)


def _sun_fault(t: np.ndarray, tooth: int) -> np.ndarray:
    theta00 = _first_pass(0)
    xs = np.zeros_like(t)
    revs = t[-1] * FC
    for n in range(N):
        # psi_0 + (z_r/z_s)(theta - theta00) - 2 pi tooth / z_s = psi_n + 2 pi q
        q = np.arange(-2, int(revs * ZR / ZS) + 3)
        thetas = theta00 + ZS / ZR * (PSI[n] - PSI[0] + 2 * np.pi * tooth / ZS + 2 * np.pi * q)
        thetas = thetas[(thetas > 0) & (thetas < 2 * np.pi * FC * t[-1])]
        xs += _pulse_train(t, thetas, _gate(thetas, n))
    return xs


def _tooth_of_peak(avg: SeparatedAverage, diff: np.ndarray) -> float:
    i = int(np.argmax(np.abs(diff)))
    return (i + 0.5) / avg.samples_per_tooth - 0.5  # tooth position of sample i


def _circular(a: float, b: float, z: int) -> float:
    d = (a - b) % z
    return min(d, z - d)


def _kw(**extra):
    return dict(carrier_frequency=FC, z_sun=ZS, z_planet=ZP, z_ring=ZR, planets=N,
                sensor_angle=SENSOR, samples_per_tooth=M, **extra)


def _energy_fraction(y: np.ndarray, k: int) -> float:
    e = np.abs(np.fft.rfft(y)) ** 2
    return float(e[k] / e.sum())


@pytest.mark.parametrize("window, teeth", [("hann", 1), ("rectangular", 1), ("hann", 2),
                                           ("tukey", 3)])
def test_planet_fault_appears_only_on_its_planet_at_its_tooth(window, teeth):
    t = _time()
    healthy = _mesh(t)
    faulty = healthy + _planet_fault(t, planet=1, tooth=7)
    kw = _kw(window=window, window_teeth=teeth)
    h1, f1 = (planet_average(x, FS, planet=1, **kw) for x in (healthy, faulty))
    h0, f0 = (planet_average(x, FS, planet=0, **kw) for x in (healthy, faulty))
    d1, d0 = f1.signal - h1.signal, f0.signal - h0.signal
    assert f1.teeth == ZP and f1.signal.size == ZP * M
    assert _circular(_tooth_of_peak(f1, d1), 7, ZP) <= TOOTH_TOL
    assert np.abs(d0).max() < RATIO_OTHER * np.abs(d1).max()
    # fault on planet 2's tooth 20 shows on planet 2 only
    f2x = healthy + _planet_fault(t, planet=2, tooth=20)
    d2 = planet_average(f2x, FS, planet=2, **kw).signal - planet_average(
        healthy, FS, planet=2, **kw).signal
    assert _circular(_tooth_of_peak(f1, d2), 20, ZP) <= TOOTH_TOL


def test_sun_fault_appears_at_its_tooth_and_not_in_a_planet():
    t = _time(revs=REVS_LONG)
    healthy = _mesh(t)
    faulty = healthy + _sun_fault(t, tooth=5)
    hs, fs_ = (sun_average(x, FS, **_kw()) for x in (healthy, faulty))
    ds = fs_.signal - hs.signal
    assert fs_.teeth == ZS and fs_.passes >= N * (REVS_LONG - 1)
    assert _circular(_tooth_of_peak(fs_, ds), 5, ZS) <= TOOTH_TOL
    hp, fp = (planet_average(x, FS, planet=0, **_kw()) for x in (healthy, faulty))
    assert np.abs(fp.signal - hp.signal).max() < RATIO_SUN_IN_PLANET * np.abs(ds).max()


def test_mesh_tone_has_one_cycle_per_tooth():
    t = _time()
    tone = np.cos(2 * np.pi * ZR * FC * t + 0.3)
    for n in range(N):
        avg = planet_average(tone, FS, planet=n, **_kw())
        assert _energy_fraction(avg.signal, ZP) > ENERGY_MIN
        assert avg.coverage.min() > 0
    # the sun needs the physical planet phases z_r psi_n (a common phase is not a sun tone)
    sun = sun_average(_mesh(t), FS, **_kw(window="tukey", window_teeth=2))
    assert _energy_fraction(sun.signal, ZS) > ENERGY_MIN


def test_gcd_tooth_counts_need_a_wide_window():
    """z_r = 78, z_p = 24: gcd 6, so each pass advances the tooth at the sensor by
    78 mod 24 = 6 teeth: one-tooth windows see teeth 0, 6, 12, 18 only (refused, the
    message says why and what window is needed); six-tooth windows see all 24 teeth."""
    zs, zp, zr = 30, 24, 78
    t = _time(revs=12)
    kw = dict(carrier_frequency=FC, z_sun=zs, z_planet=zp, z_ring=zr, planets=N,
              samples_per_tooth=M)
    x = np.cos(2 * np.pi * zr * FC * t)
    with pytest.raises(InputError, match=r"only the teeth 0, 6, 12, 18 .*gcd.* = 6.*"
                                         r"window_teeth >= 6"):
        planet_average(x, FS, window_teeth=1, **kw)
    avg = planet_average(x, FS, window="rectangular", window_teeth=6, **kw)
    assert avg.coverage.min() > 0
    # rectangular windows of 6 teeth cover 6 M samples with weight 1 per pass
    assert avg.coverage.sum() == pytest.approx(avg.passes * 6 * M, rel=1e-12)
    assert _energy_fraction(avg.signal, zp) > ENERGY_MIN
    assert planet_average(x, FS, window="hann", window_teeth=6, **kw).coverage.min() > 0


def test_record_too_short_is_refused():
    t = _time(revs=10)  # planet cycle is z_p = 26 carrier revolutions
    with pytest.raises(InputError, match=r"too short to see every tooth of planet 0.*"
                                         r"every 26 carrier revolutions, so 27"):
        planet_average(_mesh(t), FS, **_kw())


def test_pulses_and_constant_speed_agree():
    t = _time(revs=REVS + 0.6)
    x = _mesh(t) + _planet_fault(t, 1, 7) + 0.1 * np.random.default_rng(1).standard_normal(
        t.size)
    pulses = np.arange(int(math.floor(t[-1] * FC + 1e-9)) + 1) / FC
    kw = _kw(window="hann", window_teeth=2)
    kw.pop("carrier_frequency")
    for fn, extra in ((planet_average, {"planet": 1}), (sun_average, {})):
        a = fn(x, FS, carrier_frequency=FC, **kw, **extra)
        b = fn(x, FS, carrier_pulses=pulses, **kw, **extra)
        assert a.passes == b.passes
        assert_allclose(b.signal, a.signal, rtol=RTOL_SAME, atol=RTOL_SAME * np.abs(
            a.signal).max())
        assert_allclose(b.coverage, a.coverage, rtol=RTOL_SAME)


def test_varying_speed_with_carrier_pulses():
    """Carrier speed f_c (1 + 0.01 sin 2 pi 0.1 t): with the pulses at theta_c = 2 pi k the
    fault is still found at tooth 7 and the mesh tone stays one cycle per tooth."""
    eps, fv = 0.01, 0.1
    t = _time(revs=REVS + 1)

    def angle(tt):
        return 2 * np.pi * FC * (tt + eps * (1 - np.cos(2 * np.pi * fv * tt)) / (2 * np.pi * fv))

    def time_of(theta):  # Newton on angle(t) = theta
        tt = theta / (2 * np.pi * FC)
        for _ in range(8):
            speed = 2 * np.pi * FC * (1 + eps * np.sin(2 * np.pi * fv * tt))
            tt = tt - (angle(tt) - theta) / speed
        return tt

    theta = angle(t)
    x = _mesh(t, theta=theta)
    xf = x + _planet_fault(t, 1, 7, theta_end=theta[-1], time_of=time_of)
    pulses = time_of(2 * np.pi * np.arange(int(theta[-1] / (2 * np.pi)) + 1))
    kw = {k: v for k, v in _kw().items() if k != "carrier_frequency"}
    h = planet_average(x, FS, carrier_pulses=pulses, planet=1, **kw)
    f = planet_average(xf, FS, carrier_pulses=pulses, planet=1, **kw)
    assert _circular(_tooth_of_peak(f, f.signal - h.signal), 7, ZP) <= TOOTH_TOL
    assert _energy_fraction(h.signal, ZP) > ENERGY_MIN


def test_bad_input_is_refused():
    t = _time()
    x = _mesh(t)
    with pytest.raises(InputError, match=r"planet = 5: is not in 0 \.\. 2 \(3 planets\)"):
        planet_average(x, FS, planet=5, **_kw())
    with pytest.raises(InputError, match="planet = 1.5: must be an integer"):
        planet_average(x, FS, planet=1.5, **_kw())
    with pytest.raises(InputError, match="window = kaiser"):
        planet_average(x, FS, window="kaiser", **_kw())
    with pytest.raises(InputError, match="z_planet"):
        planet_average(x, FS, **{**_kw(), "z_planet": 26.5})
    with pytest.raises(InputError, match="z_ring = 80"):
        sun_average(x, FS, **{**_kw(), "z_ring": 80})
    with pytest.raises(InputError, match="window_teeth = 24"):
        planet_average(x, FS, window_teeth=24, **_kw())  # > z_r // N = 23
    bad = x.copy()
    bad[100] = np.nan
    with pytest.raises(InputError, match=r"signal\[100\]"):
        sun_average(bad, FS, **_kw())
    with pytest.raises(InputError, match="carrier_frequency/carrier_pulses"):
        planet_average(x, FS, carrier_pulses=[0.0, 0.2], **_kw())
    kw = {k: v for k, v in _kw().items() if k != "carrier_frequency"}
    with pytest.raises(InputError, match="carrier_pulses"):
        planet_average(x, FS, carrier_pulses=[0.0, 0.4, 0.2], **kw)
    with pytest.raises(InputError, match="planet_angles"):
        planet_average(x, FS, planet_angles=[0.0, 1.0], **_kw())
