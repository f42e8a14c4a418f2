"""Maximum tangential stress criterion (Erdogan & Sih 1963)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fracture.direction import (
    equivalent_k,
    hoop_stress_factor,
    kink_angle,
    kinked_direction,
)


def test_pure_mode_two_kinks_by_arccos_one_third() -> None:
    assert kink_angle(0.0, 1e6) == pytest.approx(-math.acos(1.0 / 3.0), abs=1e-14)
    assert math.degrees(kink_angle(0.0, 1e6)) == pytest.approx(-70.5288, abs=1e-4)
    assert kink_angle(0.0, -1e6) == pytest.approx(math.acos(1.0 / 3.0), abs=1e-14)
    assert equivalent_k(0.0, 1e6) == pytest.approx(2e6 / math.sqrt(3.0), rel=1e-14)


def test_pure_mode_one_goes_straight() -> None:
    assert kink_angle(1e6, 0.0) == 0.0
    assert equivalent_k(1e6, 0.0) == pytest.approx(1e6, rel=1e-15)


def test_kink_angle_maximises_the_hoop_stress() -> None:
    """The angle solves K_I sin t + K_II (3 cos t - 1) = 0 and is the maximum of
    sigma_tt over a fine scan of (-pi, pi) (independent of the closed form)."""
    rng = np.random.default_rng(27)
    scan = np.linspace(-math.pi + 1e-6, math.pi - 1e-6, 200001)
    for _ in range(20):
        k1 = rng.uniform(0.0, 1.0)
        k2 = rng.uniform(-1.0, 1.0)
        th = kink_angle(k1, k2)
        assert k1 * math.sin(th) + k2 * (3.0 * math.cos(th) - 1.0) == pytest.approx(0.0,
                                                                                      abs=1e-12)
        c = np.cos(0.5 * scan)
        hoop = c * (k1 * c * c - 1.5 * k2 * np.sin(scan))
        assert th == pytest.approx(scan[np.argmax(hoop)], abs=1e-4)
        assert equivalent_k(k1, k2) == pytest.approx(hoop.max(), rel=1e-9)
        assert hoop_stress_factor(k1, k2, th) == pytest.approx(equivalent_k(k1, k2))


def test_compressive_mode_one_branch_is_continuous() -> None:
    """For K_I < 0 the other algebraic form is used; it joins the K_I >= 0 form."""
    a = kink_angle(-1e-12, 1.0)
    b = kink_angle(1e-12, 1.0)
    assert a == pytest.approx(b, abs=1e-11)
    th = kink_angle(-1.0, 0.5)
    assert -1.0 * math.sin(th) + 0.5 * (3.0 * math.cos(th) - 1.0) == pytest.approx(0.0,
                                                                                   abs=1e-12)


def test_kinked_direction_rotates_the_crack() -> None:
    d = kinked_direction((0.0, 2.0), 0.0, 1.0)  # crack along +y, pure mode II
    th = -math.acos(1.0 / 3.0)
    np.testing.assert_allclose(d, [-math.sin(th), math.cos(th)], atol=1e-15)
    assert np.hypot(*d) == pytest.approx(1.0)


def test_refuses_non_finite() -> None:
    with pytest.raises(InputError, match="k2") as err:
        kink_angle(1.0, math.nan)
    assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="direction"):
        kinked_direction((0.0, 0.0), 1.0, 0.0)
