"""Lines the shaft tier reads: order k of the shaft within the main lobe of k f_r (or the
speed's own spread), never another shaft's line; the envelope blind to a sensor bias."""

import numpy as np
import pytest

from gearsim.signals.tiers import analyze_record

FS = 1000.0


def _tones(n, lines):
    t = np.arange(n) / FS
    return sum(a * np.cos(2 * np.pi * f * t) for f, a in lines)


def test_envelope_orders_blind_to_a_sensor_bias():
    # a bias c adds 2 c x to |x + c + iH|^2: with c = 100 the 30 Hz line of 0.3 (3x)
    # would show as 60 in the envelope; with the mean removed the record and the record
    # + 100 give the same envelope orders (to round-off)
    rng = np.random.default_rng(4)
    n = 10_000
    t = np.arange(n) / FS
    x = _tones(n, [(10.0, 0.3), (30.0, 0.3)]) + (1 + 0.2 * np.cos(2 * np.pi * 10 * t)) * \
        np.cos(2 * np.pi * 200 * t) + 0.05 * rng.standard_normal(n)
    env = [analyze_record(x + c, FS, speed=10.0).tiers["shaft"]["envelope"]["orders"]
           for c in (0.0, 100.0)]
    for r0, r1 in zip(*env, strict=True):
        assert r1["amplitude"] == pytest.approx(r0["amplitude"], rel=1e-9, abs=1e-9)
    # no two lines 30 Hz apart: the 3x is noise, against 2 c 0.3 = 60 with the bias kept
    assert env[0][2]["amplitude"] < 1.0
