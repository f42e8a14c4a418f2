"""The compiled PE kernel against an oracle that does not share its crack and foundation code.

``gearsim.stiffness.reference`` computes the crack geometry (start point, tip, limiting
line of seed eqs. 10-11), the contact closure and the Sainsot foundation term itself; it
shares only the tooth outline (checked in tests/test_geometry.py) and the published
Sainsot table (checked in tests/test_sainsot.py). Hand-derived closed forms complete
the picture.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.geometry.gear import Gear, Material
from gearsim.stiffness import _kernels as K
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.reference import reference_compliance, reference_crack, root_half_angle
from gearsim.stiffness.tooth import ToothModel

# Kernel (fixed 16-point rules, closed-form closure) against adaptive quad at rtol 1e-10
# (bisection closure): the only differences are quadrature error and the oracle's
# finite-difference Jacobian (step 1e-7, error up to ~3e-7 of dy/dp near the root, up
# to 5e-8 of a compliance; the kernel's is analytic).
ORACLE_RTOL = 1e-6
# Every component, the axial one included, is held to ORACLE_RTOL: the kernel splits its
# rule at each change of the crack closure state (closed / partly closed / open), also
# when two changes fall in one sampling interval (observed: <= 1.4e-7 relative).
# Crack geometry: both sides solve for the same points by root finding to ~1e-15 rad;
# the kernel's tangent-point bisection uses a 1e-7 central difference, the oracle's a
# 1e-6 one, which moves the 30-degree point by ~1e-12 of the radius. 1e-9 m is 1e-6 of a
# 1 mm crack and far above both.
GEOMETRY_ATOL = 1e-9
# theta_f: two exact expressions of the same angle (rack closed form, generated outline).
IDENTITY_RTOL = 1e-12


def _spur_pinion() -> Gear:
    """19-tooth pinion of the classic 19/48 spur pair (Tian 2004), m 3.2 mm, b 16 mm."""
    mat = Material(youngs_modulus=206.8e9, poisson_ratio=0.3, density=7800.0)
    return Gear(teeth=19, normal_module=3.2e-3, face_width=0.016, material=mat, name="pinion")


def _table1_input() -> Gear:
    """Input gear of the Table-1 idler train (z 39, m_n 6 mm, beta 13 deg, b 150 mm)."""
    return Gear(teeth=39, normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15,
                name="input")


def _radii(tm: ToothModel, n: int = 5) -> np.ndarray:
    return np.linspace(tm.profile.form_radius * 1.002, tm.gear.tip_radius * 0.999, n)


@pytest.mark.parametrize("closure,side,depth", [
    ("open", 1, 0.0), ("open", 1, 1.0e-3), ("contact", 1, 1.0e-3), ("contact", -1, 1.0e-3),
    ("contact", -1, 2.5e-3)])
def test_kernel_matches_independent_reference(closure, side, depth):
    """Kernel (crack record from ``crack_record``) = oracle (its own crack geometry)."""
    gear = _spur_pinion()
    tm = ToothModel(gear, closure=closure)
    crack = Crack(gear=gear.name, depth=depth)
    rec = crack_record(tm.profile, crack, depth, side) if depth else None
    radii = _radii(tm)
    got = tm.compliance(radii, rec)
    for r, row in zip(radii, got, strict=True):
        ref = reference_compliance(tm, float(r), crack=crack if depth else None, side=side)
        assert_allclose(row, ref, rtol=ORACLE_RTOL, err_msg=f"r = {r}")
        assert_allclose(row.sum(), ref.sum(), rtol=ORACLE_RTOL, err_msg=f"r = {r}")


@pytest.mark.parametrize("side", [1, -1])
def test_kernel_matches_reference_helical_crack(side):
    """Table-1 input gear (helical rack, root above the base circle), 2 mm crack.

    At the lowest contact point the crack's partly closed band is only 0.08 mm high:
    two closure changes fall in one of the kernel's 24 sampling intervals (before that
    was handled the 16-point bending term was off by 2.3e-5 there).
    """
    gear = _table1_input()
    tm = ToothModel(gear, closure="contact")
    crack = Crack(gear=gear.name, depth=2e-3)
    rec = crack_record(tm.profile, crack, 2e-3, side)
    radii = _radii(tm, 3)
    got = tm.compliance(radii, rec)
    for r, row in zip(radii, got, strict=True):
        ref = reference_compliance(tm, float(r), crack=crack, side=side)
        assert_allclose(row, ref, rtol=ORACLE_RTOL, err_msg=f"r = {r}")


@pytest.mark.parametrize("make", [_spur_pinion, _table1_input])
@pytest.mark.parametrize("depth,angle_deg,start_radius", [
    (1e-3, 45.0, None), (2.5e-3, 45.0, None), (0.8e-3, 70.0, None), (1e-3, 45.0, "root+")])
def test_crack_record_matches_independent_geometry(make, depth, angle_deg, start_radius):
    """h_c, tip height and the top g_c of the cracked range agree with the oracle's own.

    g_c is where the outline's half width falls to h_c above the tip (crack.py finds it
    on a sampled outline then by bisection); the oracle finds it by ``brentq`` on x = h_c.
    """
    gear = make()
    tm = ToothModel(gear)
    prof = tm.profile
    sr = None if start_radius is None else gear.root_radius + 0.3 * (prof.form_radius
                                                                      - gear.root_radius)
    crack = Crack(gear=gear.name, depth=depth, angle=math.radians(angle_deg), start_radius=sr)
    rec = crack_record(prof, crack, depth, 1)
    rc = reference_crack(prof, crack, depth, 1)
    # the crack has length q: independent of both implementations
    assert math.dist(rc.start, rc.tip) == pytest.approx(depth, rel=1e-12)
    assert abs(rec[K.C_HC] - rc.h_c) < GEOMETRY_ATOL
    assert abs(rec[K.C_YLO] - max(rc.tip[1], prof.root_height)) < GEOMETRY_ATOL
    # top of the cracked range: the half width there equals h_c
    x_hi = prof.half_width_at_height(rec[K.C_YHI])
    assert abs(x_hi - rc.h_c) < GEOMETRY_ATOL
    assert rec[K.C_YHI] > rc.start[1]  # the cut strip reaches above the crack mouth


def test_limiting_line_takes_the_first_crossing():
    """The 19-tooth pinion widens again just above its base circle (root below base).

    The half width is not monotone there, so g_c must be the *first* height above the
    tip where the width falls to h_c; check the outline really is non-monotone (else
    this case would not be exercised) and that both implementations agree on a crack
    whose h_c lies in that band.
    """
    gear = _spur_pinion()
    prof = ToothModel(gear).profile
    pts = prof.outline(400, 400)
    widening = np.nonzero(np.diff(pts[:, 0]) > 0)[0]
    assert widening.size > 0
    x_band = 0.5 * (pts[widening[0], 0] + pts[widening[-1] + 1, 0])
    # a horizontal crack (90 deg) from the 30-degree point, deep enough to reach x_band
    rc0 = reference_crack(prof, Crack(gear=gear.name, depth=1e-4), 1e-4, 1)
    depth = rc0.start[0] - x_band
    crack = Crack(gear=gear.name, depth=depth, angle=math.radians(90.0))
    rc = reference_crack(prof, crack, depth, 1)
    assert rc.h_c == pytest.approx(x_band, abs=1e-15)
    rec = crack_record(prof, crack, depth, 1)
    assert abs(rec[K.C_YHI] - rc.top) < GEOMETRY_ATOL
    assert rc.top < pts[widening[-1] + 1, 1]  # stops at the first crossing


@pytest.mark.parametrize("make", [_spur_pinion, _table1_input])
def test_root_half_angle_closed_form(make):
    """theta_f = u_C / (r cos beta) from the rack equals the generated outline's value."""
    tm = ToothModel(make())
    assert root_half_angle(tm) == pytest.approx(tm.profile.root_half_angle, rel=IDENTITY_RTOL)


def test_contact_section_triangular_stress_block():
    """Partly closed crack: the kernel's section energy equals a hand-derived triangle.

    With axial force N < 0 and moment M_s (about the centre line, positive opening the
    crack side s > 0), the load-carrying section is [-h, c] with zero stress at s = c:
    a triangular stress block of base w = c + h and peak 2 N / w at s = -h. Its moment
    about s = 0 is N (-h + w/3) = M_s, so w = 3 (M_s / N + h). The normal-stress energy
    per unit length (the kernel's M_e^2/(E I_e) + N^2/(E A_e), i.e. int sigma^2 / E ds)
    is (2N/w)^2 w / 3 / E = 4 N^2 / (3 w E); shear acts on h_c + h.
    Numbers: h 2 mm, h_c 0.5 mm, N -0.5 N, c 1.5 mm -> w 3.5 mm, M_s = N (w/3 - h)
    = 4.1667e-4 N m.
    """
    e, g = 206e9, 206e9 / 2.6
    h, hc = 2e-3, 0.5e-3
    fa = 0.5  # N = -F_a
    fb = math.sqrt(1 - fa**2)
    n = -fa
    w = 3.5e-3
    ms = n * (w / 3 - h)
    assert ms == pytest.approx(4.1666666e-4, rel=1e-6)
    # place the section so that the kernel's moment F_b (y_c - y) - F_a x_c equals M_s
    xc, yc, y = 0.0, 0.05, 0.05 - ms / fb
    cr = np.zeros(K.C_SIZE)
    cr[K.C_ACTIVE], cr[K.C_SIDE], cr[K.C_HC] = 1.0, 1.0, hc
    eb, es, ea = K._section_energy(h, y, True, cr, K.MODEL_CONTACT, fb, fa, xc, yc, e, g)
    assert eb + ea == pytest.approx(4 * n**2 / (3 * w * e), rel=1e-12)
    assert es == pytest.approx(1.2 * fb**2 / (g * (hc + h)), rel=1e-12)
    # the oracle's bisection finds the same block
    ref = reference_compliance.__globals__["_contact_extent"](h, hc, n, ms)
    assert ref + h == pytest.approx(w, rel=1e-12)


def test_open_crack_on_either_flank_is_the_same():
    """The open model as printed (section about the centre line) ignores the flank."""
    gear = _spur_pinion()
    tm = ToothModel(gear, closure="open")
    crack = Crack(gear=gear.name, depth=1e-3)
    r = _radii(tm, 3)
    a = tm.compliance(r, crack_record(tm.profile, crack, 1e-3, 1))
    b = tm.compliance(r, crack_record(tm.profile, crack, 1e-3, -1))
    assert_allclose(a, b, rtol=1e-14)
