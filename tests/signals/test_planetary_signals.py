"""Planetary frequencies and the fixed-sensor sideband rule (McFadden & Smith 1985)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.signals.planetary import planet_pass_signal, planetary_frequencies, sideband_orders

#: Spectral lines of the synthetic signal sit on exact bins (whole carrier revolutions);
#: an absent line is at round-off relative to the largest (1e-9).
ABSENT = 1e-9


def test_willis_and_fault_frequencies():
    """Ring fixed: f_c = f_s z_s / (z_s + z_r); the same stage driven by the carrier with
    the sun fixed gives the Willis ratio; fault frequencies from their definitions."""
    zs, zp, zr, n = 21, 39, 99, 3
    f = planetary_frequencies(zs, zp, zr, n, sun=10.0)
    assert f.carrier == pytest.approx(10.0 * zs / (zs + zr), rel=1e-12)
    assert f.mesh == pytest.approx(zs * (f.sun - f.carrier), rel=1e-12)
    assert f.sun_fault == pytest.approx(n * (f.sun - f.carrier), rel=1e-12)
    assert f.planet_pass == pytest.approx(n * f.carrier, rel=1e-12)
    assert f.ring_fault == f.planet_pass  # ring fixed
    assert f.planet_fault == pytest.approx(f.mesh / zp, rel=1e-12)
    # the planet's relative speed from the sun mesh equals the one from the ring mesh
    assert f.planet_relative == pytest.approx(-zs / zp * (f.sun - f.carrier), rel=1e-12)
    g = planetary_frequencies(zs, zp, zr, n, carrier=1.0, sun=0.0, ring=None)
    assert g.ring == pytest.approx(1.0 + zs / zr, rel=1e-12)  # (z_r + z_s) / z_r
    with pytest.raises(InputError, match="speeds"):
        planetary_frequencies(zs, zp, zr, n, sun=1.0, carrier=1.0)


@pytest.mark.parametrize("z_ring, planets", [(70, 3), (99, 3), (100, 4), (71, 5)])
def test_fixed_sensor_spectrum_has_only_the_predicted_orders(z_ring, planets):
    """FFT of the McFadden-Smith signal over whole carrier revolutions: around f_m the
    lines present are exactly the predicted orders, the strongest the predicted one."""
    fc = 1.0
    revs, per_rev = 8, 4096
    t = np.arange(revs * per_rev) / (per_rev * fc)
    x = planet_pass_signal(t, z_ring, planets, fc, window=0.4)
    spec = np.abs(np.fft.rfft(x)) / x.size
    orders, dominant = sideband_orders(z_ring, planets, 1, 8)
    around = {n: spec[(z_ring + n) * revs] for n in range(-8, 9)}
    peak = max(around.values())
    for n, a in around.items():
        if n in orders:
            assert a > 1e-6 * peak, n
        else:
            assert a < ABSENT * peak, n
    assert max(around, key=around.get) == dominant


def test_unequal_spacing_fills_the_absent_orders():
    """Planets not equally spaced: the orders the rule removes come back."""
    fc, revs, per_rev = 1.0, 8, 4096
    t = np.arange(revs * per_rev) / (per_rev * fc)
    angles = np.radians([0.0, 115.0, 240.0])
    x = planet_pass_signal(t, 70, 3, fc, angles=angles, window=0.4)
    spec = np.abs(np.fft.rfft(x)) / x.size
    assert spec[70 * revs] > 1e-3 * spec.max()  # f_m itself, absent when equally spaced
    assert math.isfinite(float(spec.sum()))
