"""Tier 1 checks of the potential-energy tooth compliance: closed forms and convergence.

The comparison with the independent adaptive-quadrature oracle is in
tests/test_reference_independent.py, the Sainsot table in tests/test_sainsot.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.geometry.gear import Material
from gearsim.stiffness import _kernels as K
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.tooth import ToothModel, gauss_rule, hertz_stiffness, sainsot_coefficients

# Hertz is a closed form evaluated twice: agreement to rounding.
HERTZ_RTOL = 1e-12
# A Gauss-Legendre rule with n >= 2 integrates the cubic bending integrand of a constant
# section exactly; 1e-6 is the bound, far above rounding.
TIMOSHENKO_RTOL = 1e-6
# 16 against 64 Gauss points: the integrands are smooth on every piece (the kernel splits
# at the crack range and at every change of the closure state), so the 16-point rule is
# converged far below the 1e-6 the rest of the model needs (observed: 1.6e-8).
CONVERGED_RTOL = 1e-6


def test_hertz_closed_form():
    mat = Material(youngs_modulus=206e9, poisson_ratio=0.3)
    for length in (1e-3, 0.016, 0.15):
        expected = math.pi * 206e9 * length / (4 * (1 - 0.3**2))
        assert abs(hertz_stiffness(mat, mat, length) / expected - 1) < HERTZ_RTOL


@pytest.mark.parametrize("a1_deg", [0.0, 12.0, 25.0])
def test_constant_section_matches_timoshenko(a1_deg):
    """Bending, shear and axial integrals of a rectangular cantilever (unit width).

    Closed forms for a tip load F = 1 at angle a1, eccentricity x_c, length l, width 2h:
    bending (Fb^2 l^3/3 - Fb Fa x_c l^2 + Fa^2 x_c^2 l) / (E I), shear 1.2 Fb^2 l/(G A),
    axial Fa^2 l / (E A) (Timoshenko & Gere, Mechanics of Materials).
    """
    e, g = 206e9, 206e9 / 2.6
    h, length, xc = 4e-3, 11e-3, 1.5e-3
    a1 = math.radians(a1_deg)
    fb, fa = math.cos(a1), math.sin(a1)
    area, inertia = 2 * h, (2 * h) ** 3 / 12
    bend = (fb**2 * length**3 / 3 - fb * fa * xc * length**2 + fa**2 * xc**2 * length) / (
        e * inertia)
    shear = 1.2 * fb**2 * length / (g * area)
    axial = fa**2 * length / (e * area)
    nodes, weights = gauss_rule(8)
    got = K.rectangular_beam_compliance(h, length, a1, xc, e, g, nodes, weights)
    assert_allclose(got[0], bend, rtol=TIMOSHENKO_RTOL)
    assert_allclose(got[1], shear, rtol=TIMOSHENKO_RTOL)
    if a1_deg:
        assert_allclose(got[2], axial, rtol=TIMOSHENKO_RTOL)
    else:
        assert got[2] == 0.0


def _radii(tm, n=5):
    g = tm.gear
    return np.linspace(tm.profile.form_radius * 1.002, g.tip_radius * 0.999, n)


def test_gauss_rule_converged(table1):
    """16-point rules are converged: 64 points change every component < 1e-6."""
    gear = table1.gears[0]
    for closure in ("open", "contact"):
        t16 = ToothModel(gear, gauss_points=16, closure=closure)
        t64 = ToothModel(gear, gauss_points=64, closure=closure)
        rec = crack_record(t16.profile, Crack(gear=gear.name, depth=2e-3), 2e-3, 1)
        r = _radii(t16, 7)
        c16, c64 = t16.compliance(r, rec), t64.compliance(r, rec)
        assert_allclose(c16.sum(1), c64.sum(1), rtol=CONVERGED_RTOL)
        assert_allclose(c16, c64, rtol=CONVERGED_RTOL)


def test_sainsot_coefficients_reference_point():
    """L*, M*, P*, Q* evaluated by hand from Sainsot et al. 2004, Table 1."""
    h, th = 2.0, 0.1
    expected_l = -5.574e-5 / th**2 - 1.9986e-3 * h**2 - 2.3015e-4 * h / th + 4.7702e-3 / th \
        + 0.0271 * h + 6.8045
    got = sainsot_coefficients(h, th)
    assert abs(got[0] - expected_l) < 1e-12
    assert got.shape == (4,)


def test_plane_strain_stiffer_than_plane_stress(table1):
    gear = table1.gears[0]
    r = _radii(ToothModel(gear), 3)
    cs = ToothModel(gear, plane="stress").compliance(r)
    ce = ToothModel(gear, plane="strain").compliance(r)
    # bending and axial scale with 1/E' = (1 - nu^2)/E; shear and foundation unchanged
    assert_allclose(ce[:, 0] / cs[:, 0], 1 - 0.3**2, rtol=1e-12)
    assert_allclose(ce[:, 2] / cs[:, 2], 1 - 0.3**2, rtol=1e-12)
    assert_allclose(ce[:, [1, 3]], cs[:, [1, 3]], rtol=1e-12)
