"""Potential-energy compliance of the ring (internal gear) tooth, against independent numbers.

The reference values here come from constructions that do not use the model's formulas:
the outline's tangent and normal by finite differences of the flank points, the closed
form of the ring's reference tooth thickness (ISO 21771 with the ring's shift sign), the
rack limit of the tooth (a straight tapered beam) integrated with scipy's adaptive
quadrature, and the line of the contact force intersected with the centre line by vector
algebra.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.planetary import PlanetaryStage, RingGear
from gearsim.stiffness.ring import RING_H_F, RingToothModel
from gearsim.stiffness.tooth import ToothModel, sainsot_coefficients

# beta(r) against the closed form s_r / (2 r): the same few operations in another order
# (inv(alpha_t) - inv(alpha_t) cancels exactly), so rounding of ~1e-16 of values ~0.02.
CLOSED_FORM_RTOL = 1e-12
# Involute check by central differences with step DELTA = 1e-6 m: truncation
# (DELTA / rho_curv)^2 ~ 1e-9 of the direction and rounding eps rho / DELTA ~ 1e-11;
# 1e-8 relative is the brief's requirement and leaves a margin of 10.
DELTA = 1e-6
INVOLUTE_RTOL = 1e-8
# Load angle from the finite-difference normal: the same error budget, in radians.
ANGLE_ATOL = 1e-7
# Rack limit: the ring's curvature changes the bending term by about 19 / z (measured
# below: it scales as 1 / z), 2e-7 at z = 1e8; quad converges to 1e-13.
BEAM_LIMIT_TEETH = 10**8
BEAM_LIMIT_RTOL = 1e-6
# Gauss-Legendre rule 8/16/32 nodes per piece: the integrands are smooth (analytic on
# [r_c, r_f], the tooth never thinner than the tip), the brief asks for 1e-6.
CONVERGENCE_RTOL = 1e-6
# Foundation term from an independent u_f (finite-difference normal intersected with the
# centre line): FD error of the load direction ~1e-9 times lever ~1 mm over S_f ~5 mm.
FOUNDATION_RTOL = 1e-7

STEEL = Material(youngs_modulus=206e9, poisson_ratio=0.3)
#: The optional Sainsot-form foundation (the default is none).
SAINSOT = "sainsot-solid"


def _flank(tm: RingToothModel, rho):
    rho = np.asarray(rho, dtype=float)
    b = tm.half_angle(rho)
    return np.stack([rho * np.sin(b), rho * np.cos(b)], axis=-1)


def _unit_tangent(tm: RingToothModel, rho):
    d = _flank(tm, rho + DELTA) - _flank(tm, rho - DELTA)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


RINGS = [
    RingGear(teeth=78, normal_module=2e-3),
    RingGear(teeth=60, normal_module=3e-3, helix_angle=math.radians(17.0), profile_shift=0.3),
    RingGear(teeth=101, normal_module=1.5e-3, normal_pressure_angle=math.radians(25.0),
             profile_shift=-0.2),
]


def _radii(ring: RingGear, n: int = 7) -> np.ndarray:
    return np.linspace(ring.tip_radius, ring.root_radius, n)


# ------------------------------------------------------------------------ 1. geometry
@pytest.mark.parametrize("ring", RINGS)
def test_half_angle_at_reference_radius_is_closed_form(ring):
    """beta(r) = s_r / (2 r), s_r = m_t (pi/2 - 2 x tan alpha_n) (ISO 21771, ring shift)."""
    m_t = ring.normal_module / math.cos(ring.helix_angle)
    s_r = m_t * (math.pi / 2 - 2 * ring.profile_shift * math.tan(ring.normal_pressure_angle))
    r = ring.teeth * m_t / 2
    beta = RingToothModel(ring).half_angle(r)[0]
    assert beta == pytest.approx(s_r / (2 * r), rel=CLOSED_FORM_RTOL)


@pytest.mark.parametrize("ring", RINGS)
def test_flank_is_an_involute_of_the_base_circle(ring):
    """The flank normal (from finite differences of the points) is tangent to the base circle.

    The distance of the normal line through P from the centre is |P x n| = |P . t|.
    """
    tm = RingToothModel(ring)
    rho = _radii(ring)[1:-1]
    dist = np.abs(np.sum(_flank(tm, rho) * _unit_tangent(tm, rho), axis=-1))
    rb = ring.pitch_radius * math.cos(math.atan(math.tan(ring.normal_pressure_angle)
                                                / math.cos(ring.helix_angle)))
    np.testing.assert_allclose(dist, rb, rtol=INVOLUTE_RTOL)


def test_ring_tooth_thickens_outwards():
    """The ring tooth is thicker at its root (outer) circle than at its tip (inner) circle."""
    ring = RINGS[0]
    tm = RingToothModel(ring)
    h = _flank(tm, _radii(ring, 50))[:, 0]
    assert np.all(np.diff(h) > 0)


# ----------------------------------------------------------------- 2. force direction
@pytest.mark.parametrize("ring", RINGS)
def test_load_angle_from_vector_construction(ring):
    """a1 is the angle of the flank normal pointing into the tooth to the X axis.

    The force of the planet on the flank acts along the normal, into the material (-X
    side of the +X flank); its Y component must point to the root (outwards).
    """
    tm = RingToothModel(ring)
    rho = _radii(ring)[1:-1]
    t = _unit_tangent(tm, rho)
    n = np.stack([-t[:, 1], t[:, 0]], axis=-1)  # tangent rotated by +90 deg
    n = np.where(n[:, :1] < 0, n, -n)  # into the tooth: towards -X
    assert np.all(n[:, 1] > 0)  # towards the root
    a1 = np.arctan2(n[:, 1], -n[:, 0])
    np.testing.assert_allclose(tm.load_angle(rho), a1, rtol=0, atol=ANGLE_ATOL)


# ----------------------------------------------------------------- 3. rack beam limit
def _rack_beam(m: float, alpha: float, e: float, g: float) -> np.ndarray:
    """Bending, shear, axial compliance of the rack-limit tooth, contact at the pitch line.

    In the limit z -> infinity the ring tooth is a rack tooth clamped at the root line
    1.25 m beyond the pitch line, half width h(u) = pi m / 4 + u tan(alpha) at the distance
    u from the pitch line towards the root, loaded at u = 0, X_c = pi m / 4, at the angle
    alpha to the normal of its centre line.
    """
    xc = math.pi * m / 4
    ca, sa = math.cos(alpha), math.sin(alpha)

    def h(u):
        return xc + u * math.tan(alpha)

    def integral(f):
        return quad(f, 0.0, 1.25 * m, epsabs=0.0, epsrel=1e-13, limit=200)[0]

    return np.array([
        integral(lambda u: (ca * u - sa * xc) ** 2 * 12.0 / (e * (2 * h(u)) ** 3)),
        integral(lambda u: 1.2 * ca * ca / (g * 2 * h(u))),
        integral(lambda u: sa * sa / (e * 2 * h(u))),
    ])


def _ring_beam(teeth: int, m: float) -> np.ndarray:
    ring = RingGear(teeth=teeth, normal_module=m)
    tm = RingToothModel(ring, material=STEEL, foundation="none")
    return tm.compliance([ring.pitch_radius])[0, :3]


def test_beam_terms_approach_the_rack_limit():
    """With z = 1e8 teeth the bending, shear and axial terms are the rack beam's to 1e-6."""
    m = 2e-3
    ref = _rack_beam(m, math.radians(20.0), STEEL.youngs_modulus, STEEL.shear_modulus)
    np.testing.assert_allclose(_ring_beam(BEAM_LIMIT_TEETH, m), ref, rtol=BEAM_LIMIT_RTOL)


def test_rack_limit_is_approached_as_one_over_z():
    """The deviation from the rack beam falls tenfold per tenfold z (a curvature effect)."""
    m = 2e-3
    ref = _rack_beam(m, math.radians(20.0), STEEL.youngs_modulus, STEEL.shear_modulus)
    d4 = _ring_beam(10**4, m) / ref - 1
    d5 = _ring_beam(10**5, m) / ref - 1
    # first-order in 1/z: the ratio is 10 up to the O(1/z^2) remainder (~1e-3 here)
    np.testing.assert_allclose(d4 / d5, 10.0, rtol=1e-2)


# ------------------------------------------------------------------- 4. convergence
@pytest.mark.parametrize("ring", RINGS)
@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_gauss_points_converged(ring, plane):
    """8, 16 and 32 Gauss points per piece agree to 1e-6 over the whole flank."""
    r = _radii(ring, 9)[:-1]  # r_f itself gives zero beam terms
    c8, c16, c32 = (RingToothModel(ring, plane=plane, gauss_points=n, foundation=SAINSOT).compliance(r)
                    for n in (8, 16, 32))
    np.testing.assert_allclose(c8, c32, rtol=CONVERGENCE_RTOL)
    np.testing.assert_allclose(c16, c32, rtol=CONVERGENCE_RTOL)


# ----------------------------------------------------------- other model properties
def test_plane_strain_scales_the_e_terms_only():
    """Plane strain divides E of bending and axial by 1 - nu^2; shear, foundation unchanged."""
    ring = RINGS[0]
    r = _radii(ring)[:-1]
    cs = RingToothModel(ring, plane="stress", foundation=SAINSOT).compliance(r)
    ce = RingToothModel(ring, plane="strain", foundation=SAINSOT).compliance(r)
    np.testing.assert_allclose(ce[:, [0, 2]] / cs[:, [0, 2]], 0.91, rtol=1e-12)
    np.testing.assert_allclose(ce[:, [1, 3]], cs[:, [1, 3]], rtol=1e-14)


def test_compliance_scales_with_one_over_width_and_none_foundation_is_zero():
    """Every column is 1/L; ``foundation="none"`` leaves the beam columns unchanged."""
    ring = RINGS[1]
    r = _radii(ring)
    c1 = RingToothModel(ring, foundation=SAINSOT).compliance(r)
    c2 = RingToothModel(ring, foundation=SAINSOT).compliance(r, width=0.02)
    np.testing.assert_allclose(c2, c1 / 0.02, rtol=1e-14)
    cn = RingToothModel(ring, foundation="none").compliance(r)
    assert np.all(cn[:, 3] == 0.0)
    np.testing.assert_array_equal(cn[:, :3], c1[:, :3])


@pytest.mark.parametrize("ring", RINGS)
def test_foundation_from_independent_force_line(ring):
    """1/k_f with u_f from the force line (FD normal) crossing the centre line.

    u_f is the distance from the root circle (on the centre line, Y_root = r_f
    cos theta_f) to where the line of the contact force crosses X = 0; S_f = 2 r_f
    theta_f; h_f = 7. The coefficients are Sainsot's (checked in tests/test_sainsot.py).
    """
    tm = RingToothModel(ring, material=STEEL, foundation=SAINSOT)
    rho = _radii(ring)[1:-1]
    p = _flank(tm, rho)
    t = _unit_tangent(tm, rho)
    n = np.stack([-t[:, 1], t[:, 0]], axis=-1)
    n = np.where(n[:, :1] < 0, n, -n)  # force direction on the tooth
    y_cross = p[:, 1] - p[:, 0] * n[:, 1] / n[:, 0]
    rf = ring.root_radius
    # theta_f from the closed-form involute at the root circle
    at = math.atan(math.tan(ring.normal_pressure_angle) / math.cos(ring.helix_angle))
    af = math.acos(ring.pitch_radius * math.cos(at) / rf)
    s_r = ring.transverse_module * (math.pi / 2 - 2 * ring.profile_shift
                                    * math.tan(ring.normal_pressure_angle))
    theta_f = s_r / (2 * ring.pitch_radius) - (math.tan(at) - at) + (math.tan(af) - af)
    u_f = rf * math.cos(theta_f) - y_cross
    ratio = u_f / (2 * rf * theta_f)
    cos_a, tan_a = -n[:, 0], -n[:, 1] / n[:, 0]
    ls, ms, ps, qs = sainsot_coefficients(RING_H_F, theta_f)
    ref = cos_a**2 / STEEL.youngs_modulus * (ls * ratio**2 + ms * ratio
                                             + ps * (1 + qs * tan_a**2))
    np.testing.assert_allclose(tm.compliance(rho)[:, 3], ref, rtol=FOUNDATION_RTOL)


# ------------------------------------------------------------ 5. sanity vs external
def test_ring_tooth_stiffer_than_mating_planet_tooth_at_pitch():
    """Beam terms of the ring tooth at its pitch point are below the planet tooth's.

    Stage 30/24/78, m 2 mm, steel, unit width, at the reference radii [m/N]:

    ==========  ==========  ==========  ==========  ==========
    tooth       bending     shear       axial       foundation
    ==========  ==========  ==========  ==========  ==========
    planet z24  2.753e-12   9.943e-12   2.707e-13   1.931e-11
    ring z78    1.083e-12   7.955e-12   3.817e-13   6.374e-11
    ==========  ==========  ==========  ==========  ==========

    The ring tooth bends 2.5 times less and its beam sum is 0.73 of the planet's, as its
    teeth thicken towards the root. The foundation column is not compared: the ring's
    ``sainsot-solid`` term at h_f = 7 (the most compliant end of Sainsot's fit) is 3.3
    times the planet's on its bore (h_f = 2), which makes the ring's total the larger.
    """
    st = PlanetaryStage(30, 24, 78, 2e-3, planets=4, ring_addendum_coefficient=0.8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the planet's theta_f is just outside Sainsot's range
        cp = ToothModel(st.planet).compliance([st.planet.pitch_radius])[0]
    cr = RingToothModel(st.ring, material=st.material,
                        foundation=SAINSOT).compliance([st.ring.pitch_radius])[0]
    assert cr[0] < 0.5 * cp[0]
    assert cr[:3].sum() < cp[:3].sum()
    assert cr[1] < cp[1]


def test_ring_beam_terms_against_planet_gear_of_same_module():
    """Same check against a stand-alone 24-tooth external gear of the same module."""
    g = Gear(teeth=24, normal_module=2e-3, face_width=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cp = ToothModel(g).compliance([g.pitch_radius])[0]
    ring = RingGear(teeth=78, normal_module=2e-3)
    cr = RingToothModel(ring).compliance([ring.pitch_radius])[0]
    assert cr[0] < cp[0] and cr[:3].sum() < cp[:3].sum()


def test_compliance_falls_towards_the_root():
    """Contacts nearer the clamp are stiffer; on the root circle no beam is left.

    Shear falls monotonically. Bending falls from the tip to past the pitch circle, but
    not all the way: within ~1.3 mm of the root the moment F_b (Y - Y_c) - F_a X_c is
    dominated by the eccentric axial force, as on an external tooth, and the bending term
    has a shallow bump (1.57e-13 to 1.67e-13 m/N between 79.2 and 79.7 mm at z 78,
    m 2 mm, r_f 80.5 mm) before it falls to zero on the root circle.
    """
    ring = RINGS[0]
    r = _radii(ring, 40)
    c = RingToothModel(ring).compliance(r)
    assert np.all(np.diff(c[:, 1]) < 0)
    assert np.all(np.diff(c[r <= ring.pitch_radius + 0.5 * ring.normal_module, 0]) < 0)
    assert np.all(c[-1, :3] == 0.0)


# ------------------------------------------------------------------- 6. bad input
def _param(exc_info) -> str:
    return exc_info.value.parameter


@pytest.mark.parametrize("kwargs, name", [
    ({"plane": "plain"}, "stiffness.plane"),
    ({"foundation": "sainsot"}, "ring_foundation"),
    ({"foundation": None}, "ring_foundation"),
    ({"gauss_points": 1}, "stiffness.gauss_points"),
    ({"gauss_points": 201}, "stiffness.gauss_points"),
    ({"gauss_points": 16.0}, "stiffness.gauss_points"),
    ({"gauss_points": True}, "stiffness.gauss_points"),
    ({"material": 206e9}, "material"),
])
def test_bad_options_refused(kwargs, name):
    """Bad options raise InputError naming the parameter, the value and the limit."""
    with pytest.raises(InputError) as exc:
        RingToothModel(RINGS[0], **kwargs)
    assert _param(exc) == name
    assert str(exc.value).startswith(name + " = ") and "must" in str(exc.value)


def test_bad_ring_refused():
    """Not a RingGear, or a ring whose tip circle lies inside its base circle."""
    with pytest.raises(InputError) as exc:
        RingToothModel(Gear(teeth=24, normal_module=2e-3))
    assert _param(exc) == "ring"
    with pytest.raises(InputError) as exc:
        RingToothModel(RingGear(teeth=20, normal_module=2e-3))  # r_a 18 mm < r_b 18.79 mm
    assert _param(exc) == "ring.tip_radius"


@pytest.mark.parametrize("bad", [0.0759, 0.0806, math.nan, math.inf, -math.inf])
def test_bad_radii_refused(bad):
    """Radii outside [r_a, r_f] = [76, 80.5] mm or not finite are refused, with the value."""
    tm = RingToothModel(RINGS[0])
    with pytest.raises(InputError) as exc:
        tm.compliance([0.078, bad])
    assert _param(exc) == "radii"
    assert "must" in str(exc.value)


@pytest.mark.parametrize("bad", [0.07, math.nan])
def test_bad_geometry_radius_refused(bad):
    """half_angle and load_angle refuse radii inside the base circle or not finite."""
    tm = RingToothModel(RINGS[0])
    for fn in (tm.half_angle, tm.load_angle):
        with pytest.raises(InputError) as exc:
            fn(bad)
        assert _param(exc) == "radius"


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "1"])
def test_bad_width_refused(bad):
    """The face width must be a positive finite number."""
    with pytest.raises(InputError) as exc:
        RingToothModel(RINGS[0]).compliance([0.078], width=bad)
    assert _param(exc) == "width"


def test_radii_on_the_range_ends_accepted():
    """The ends r_a and r_f themselves (and rounding just outside) are valid contacts."""
    ring = RINGS[0]
    tm = RingToothModel(ring)
    ra, rf = ring.tip_radius, ring.root_radius
    c = tm.compliance([ra, rf, ra * (1 - 1e-15), rf * (1 + 1e-15)])
    np.testing.assert_array_equal(c[2], c[0])
    np.testing.assert_array_equal(c[3], c[1])
