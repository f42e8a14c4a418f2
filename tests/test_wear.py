"""Archard wear (single-point observation, Flodin & Andersson 1997) against hand numbers.

The reference pair is a spur pair z 20/40, m 4 mm, 20 deg, steel (E 206 GPa, nu 0.3),
standard (x = 0), so its line of action is worked out by hand:

* centre distance a = m (z1 + z2) / 2 = 120 mm, T1T2 = a sin(20 deg) = 41.042417 mm;
* pitch point at l = r_b1 tan 20 deg = r1 sin 20 deg = 40 mm x 0.342020 = 13.680806 mm
  from T1 (r1 = m z1 / 2 = 40 mm the pitch radius of the driver).

Every expected value below comes from Johnson's line-contact formulas and the kinematics
written out in the test, not from the module.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.pair import GearPair
from gearsim.stiffness.wear import archard_wear, hertz_line_contact

T1T2 = 0.120 * math.sin(math.radians(20.0))          # 41.042417 mm
PITCH = 0.040 * math.sin(math.radians(20.0))         # 13.680806 mm from T1
K = 1e-16                                            # m^2/N
W = 1e5                                              # N/m (100 N/mm)


def _pair(z1=20, z2=40, helix=0.0, m2=None):
    kw = dict(normal_module=4e-3, face_width=0.02, helix_angle=helix)
    g2 = Gear(teeth=z2, **kw) if m2 is None else Gear(teeth=z2, material=m2, **kw)
    return GearPair(Gear(teeth=z1, **kw), g2)


@pytest.fixture(scope="module")
def pair():
    return _pair()


def test_reference_geometry(pair):
    """The hand line of action is the library's (guards the numbers used below)."""
    assert pair.line_length == pytest.approx(41.042417e-3, rel=1e-7)
    assert pair.start_of_contact < 10e-3 < PITCH < pair.end_of_contact


def test_hertz_line_contact_steel():
    """Johnson eqs. 4.43/4.45 with the numbers written out.

    E* = 1 / (2 x 0.91 / 206e9) = 113.1868 GPa; R' = 7.5 mm; w = 100 N/mm:
    b = sqrt(4 x 1e5 x 7.5e-3 / (pi x 113.1868e9)) = sqrt(8.43672e-9) = 91.8516 um,
    p0 = 2 x 1e5 / (pi x 91.8516e-6) = 693.094 MPa, also = sqrt(w E* / (pi R')).
    """
    b, p0 = hertz_line_contact(1e5, 7.5e-3, 113.1868e9)
    assert float(b) == pytest.approx(91.8516e-6, rel=1e-5)
    assert float(p0) == pytest.approx(693.094e6, rel=1e-5)
    assert float(p0) == pytest.approx(math.sqrt(1e5 * 113.1868e9 / (math.pi * 7.5e-3)), rel=1e-12)
    # the mean pressure over the band times its width is the load: (pi/4) p0 2b = w
    assert math.pi / 4 * float(p0) * 2 * float(b) == pytest.approx(1e5, rel=1e-12)


def test_hertz_line_contact_mixed_materials():
    """Steel on aluminium (E2 70 GPa, nu2 0.33): 1/E* = 0.91/206e9 + 0.8911/70e9.

    E* = 1 / (4.41748e-12 + 1.27300e-11) = 58.3176 GPa; w = 200 N/mm, R' = 5 mm:
    b = sqrt(4 x 2e5 x 5e-3 / (pi x 58.3176e9)) = 147.759 um, p0 = 861.70 MPa.
    """
    e_star = 1.0 / (0.91 / 206e9 + (1 - 0.33**2) / 70e9)
    assert e_star == pytest.approx(58.3176e9, rel=1e-5)
    b, p0 = hertz_line_contact(2e5, 5e-3, e_star)
    assert float(b) == pytest.approx(147.759e-6, rel=1e-5)
    assert float(p0) == pytest.approx(861.70e6, rel=1e-5)
    zb, zp = hertz_line_contact(np.zeros(3), 5e-3, e_star)
    assert np.all(zb == 0) and np.all(zp == 0)


def test_hand_point_driver_and_driven(pair):
    """l = 10 mm: the whole chain of Flodin & Andersson's single-point form by hand.

    rho1 = 10 mm, rho2 = 41.042417 - 10 = 31.042417 mm,
    R' = 10 x 31.042417 / 41.042417 = 7.563496 mm, E* = 113.1868 GPa, w = 100 N/mm:
    b = sqrt(4 x 1e5 x 7.563496e-3 / (pi x 113.1868e9)) = 92.2398 um,
    p0 = 2e5 / (pi x 92.2398e-6) = 690.179 MPa.
    omega1 = 1 rad/s, omega2 = 20/40: u1 = 10 mm/s, u2 = 15.521209 mm/s,
    s1 = 2b |u1 - u2| / u1 = 2 x 92.2398 um x 0.5521209 = 101.855 um,
    s2 = 2b |u1 - u2| / u2 = 65.6231 um.
    Per cycle h1 = 1e-16 x 690.179e6 x 101.855e-6 = 7.02982e-12 m, h2 = 4.52917e-12 m.
    """
    rho2 = 31.042417e-3
    r_eff = 10e-3 * rho2 / 41.042417e-3
    assert r_eff == pytest.approx(7.563496e-3, rel=1e-6)
    b = math.sqrt(4 * 1e5 * r_eff / (math.pi * 113.1868e9))
    p0 = 2e5 / (math.pi * b)
    assert b == pytest.approx(92.2398e-6, rel=1e-5)
    assert p0 == pytest.approx(690.179e6, rel=1e-5)
    u1, u2 = 10e-3, rho2 * 20 / 40
    s1, s2 = 2 * b * abs(u1 - u2) / u1, 2 * b * abs(u1 - u2) / u2
    assert s1 == pytest.approx(101.855e-6, rel=1e-5)
    assert s2 == pytest.approx(65.6231e-6, rel=1e-5)

    n = 2.5e6
    h1 = archard_wear(pair, 1, 10e-3, W, coefficient=K, cycles=n)
    h2 = archard_wear(pair, 2, 10e-3, W, coefficient=K, cycles=n)
    assert float(h1) == pytest.approx(n * 7.02982e-12, rel=1e-5)
    assert float(h2) == pytest.approx(n * 4.52917e-12, rel=1e-5)
    assert float(h1) == pytest.approx(n * K * p0 * s1, rel=1e-6)
    assert float(h2) == pytest.approx(n * K * p0 * s2, rel=1e-6)


def test_short_form_four_over_pi(pair):
    """p0 2b = 4 w / pi, so depth = N (4/pi) k w |u1 - u2| / u_i (hand, l = 20 mm).

    rho1 = 20 mm, rho2 = 21.042417 mm, u2 = 10.521209 mm/s with omega1 = 1:
    |u1 - u2| / u1 = 9.478791 / 20 = 0.4739396, / u2 = 0.9009224.
    """
    n = 1e6
    h1 = float(archard_wear(pair, 1, 20e-3, W, coefficient=K, cycles=n))
    h2 = float(archard_wear(pair, 2, 20e-3, W, coefficient=K, cycles=n))
    assert h1 == pytest.approx(n * 4 / math.pi * K * W * 0.4739396, rel=1e-6)
    assert h2 == pytest.approx(n * 4 / math.pi * K * W * 0.9009224, rel=1e-6)


def test_no_wear_at_the_pitch_point(pair):
    """Pure rolling at the pitch point (u1 = u2): no sliding, no wear on either flank."""
    near = float(archard_wear(pair, 1, 10e-3, W, coefficient=K, cycles=1e6))
    for gear in (1, 2):
        h = float(archard_wear(pair, gear, PITCH, W, coefficient=K, cycles=1e6))
        assert abs(h) < 1e-12 * near
    # either side of the pitch point there is wear, growing away from it
    l = np.linspace(pair.start_of_contact, pair.end_of_contact, 201)
    h = archard_wear(pair, 1, l, np.full_like(l, W), coefficient=K, cycles=1e6)
    below, above = l < PITCH - 1e-4, l > PITCH + 1e-4
    assert np.all(h[below] > 0) and np.all(h[above] > 0)
    assert np.all(np.diff(h[below]) < 0) and np.all(np.diff(h[above]) > 0)
    assert abs(l[np.argmin(h)] - PITCH) < (l[1] - l[0])


def test_proportional_to_cycles_and_coefficient(pair):
    l = np.array([5e-3, 10e-3, 18e-3, 22e-3])
    w = np.array([5e4, 1e5, 1.5e5, 8e4])
    base = archard_wear(pair, 2, l, w, coefficient=K, cycles=1e5)
    assert np.all(base > 0)
    np.testing.assert_allclose(archard_wear(pair, 2, l, w, coefficient=K, cycles=3e5), 3 * base,
                               rtol=1e-12)
    np.testing.assert_allclose(archard_wear(pair, 2, l, w, coefficient=2.5 * K, cycles=1e5),
                               2.5 * base, rtol=1e-12)
    np.testing.assert_allclose(archard_wear(pair, 2, l, 2 * w, coefficient=K, cycles=1e5),
                               2 * base, rtol=1e-12)
    assert np.all(archard_wear(pair, 2, l, w, coefficient=K, cycles=0) == 0)


def test_zero_load_zero_wear(pair):
    """Unloaded points wear nothing, also outside the path of contact."""
    l = np.array([1e-3, 10e-3, 15e-3, 40e-3])
    w = np.array([0.0, 0.0, W, 0.0])
    h = archard_wear(pair, 1, l, w, coefficient=K, cycles=1e6)
    assert h[0] == 0 and h[1] == 0 and h[3] == 0 and h[2] > 0


def test_flank_ratio_is_speed_ratio(pair):
    """Same contact, same band: h1 / h2 = s1 / s2 = u2 / u1 = (T1T2 - l) z1 / (z2 l)."""
    l = np.array([4e-3, 8e-3, 17e-3, 22e-3])
    h1 = archard_wear(pair, 1, l, W, coefficient=K, cycles=1e6)
    h2 = archard_wear(pair, 2, l, W, coefficient=K, cycles=1e6)
    np.testing.assert_allclose(h1 / h2, (T1T2 - l) * 20 / (40 * l), rtol=1e-9)
    # the driver's root (start of contact, l < pitch) wears more than the mating tip
    assert h1[0] > h2[0] and h1[-1] < h2[-1]


def test_swapping_driver_and_driven(pair):
    """The 40-tooth gear driving the 20-tooth one sees the same contact at T1T2 - l."""
    rev = _pair(40, 20)
    l = np.array([5e-3, 10e-3, 20e-3])
    np.testing.assert_allclose(
        archard_wear(pair, 1, l, W, coefficient=K, cycles=1e6),
        archard_wear(rev, 2, T1T2 - l, W, coefficient=K, cycles=1e6), rtol=1e-9)
    np.testing.assert_allclose(
        archard_wear(pair, 2, l, W, coefficient=K, cycles=1e6),
        archard_wear(rev, 1, T1T2 - l, W, coefficient=K, cycles=1e6), rtol=1e-9)


def test_equal_gears_mirror_about_the_pitch_point():
    """z 30/30: the pitch point is mid-line; gear 1 at l wears like gear 2 at T1T2 - l."""
    p = _pair(30, 30)
    mid = 0.5 * p.line_length
    l = mid + np.array([-4e-3, -1e-3, 2e-3, 3.5e-3])
    h1 = archard_wear(p, 1, l, W, coefficient=K, cycles=1e6)
    h2 = archard_wear(p, 2, 2 * mid - l, W, coefficient=K, cycles=1e6)
    np.testing.assert_allclose(h1, h2, rtol=1e-9)
    assert float(archard_wear(p, 1, mid, W, coefficient=K, cycles=1e6)) < 1e-15


def test_depth_does_not_depend_on_the_moduli():
    """p0 x 2b = 4 w / pi for any E*: a softer mating gear leaves the depth unchanged."""
    alu = Material(youngs_modulus=70e9, poisson_ratio=0.33, density=2700.0)
    l = np.array([6e-3, 12e-3, 20e-3])
    np.testing.assert_allclose(archard_wear(_pair(), 1, l, W, coefficient=K, cycles=1e6),
                               archard_wear(_pair(m2=alu), 1, l, W, coefficient=K, cycles=1e6),
                               rtol=1e-12)


@pytest.mark.parametrize(("args", "kw", "name"), [
    ((0, 10e-3, W), {}, "gear"),
    ((3, 10e-3, W), {}, "gear"),
    ((True, 10e-3, W), {}, "gear"),
    (("1", 10e-3, W), {}, "gear"),
    ((1, 10e-3, W), {"coefficient": 0.0}, "coefficient"),
    ((1, 10e-3, W), {"coefficient": -1e-16}, "coefficient"),
    ((1, 10e-3, W), {"coefficient": math.nan}, "coefficient"),
    ((1, 10e-3, W), {"cycles": -1.0}, "cycles"),
    ((1, 10e-3, W), {"cycles": math.inf}, "cycles"),
    ((1, 0.0, W), {}, "l"),
    ((1, T1T2, W), {}, "l"),
    ((1, math.nan, W), {}, "l"),
    ((1, 1e-3, W), {}, "l"),             # loaded before the start of contact
    ((1, 30e-3, W), {}, "l"),            # loaded after the end of contact
    ((1, 10e-3, -1.0), {}, "load_per_width"),
    ((1, 10e-3, math.inf), {}, "load_per_width"),
    ((1, np.array([10e-3, 12e-3]), np.array([W, W, W])), {}, "load_per_width"),
])
def test_bad_input_refused(pair, args, kw, name):
    opts = {"coefficient": K, "cycles": 1e6} | kw
    with pytest.raises(InputError) as err:
        archard_wear(pair, *args, **opts)
    assert err.value.parameter == name


def test_hertz_bad_input_refused():
    with pytest.raises(InputError):
        hertz_line_contact(-1.0, 5e-3, 1e11)
    with pytest.raises(InputError):
        hertz_line_contact(1e5, 0.0, 1e11)
    with pytest.raises(InputError):
        hertz_line_contact(1e5, 5e-3, math.nan)
