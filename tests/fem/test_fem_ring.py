"""FE compliance of an internal (ring) gear tooth on its rim (gearsim.fem.ring).

Numbers measured (ring z 78, m 2 mm, spur, x 0, E 206 GPa, nu 0.3, plane stress, rim
3.5 m_n, 5 teeth, outer circle clamped), compliance in 1e-12 m/N for b = 1 m at the
radii r_a + 0.1 h, r (pitch), r_f - 0.3 h (h = r_f - r_a):

=====  ===========================  ==========
level  compliance                   dofs
=====  ===========================  ==========
1      41.288 / 15.083 / 7.5355     5 350
2      41.361 / 15.113 / 7.5487     14 172
3      41.388 / 15.126 / 7.5565     44 928
=====  ===========================  ==========

Rack limit (z 400, rim 42.5 mm, 5 teeth, sides clamped): ring / external-tooth FE of
gearsim.fem.tooth = 1.009, 1.004, 0.998, 0.993, 0.988, 0.984 from tip to root.

Segment size at level 2 (outer support): 5 -> 7 teeth changes the three values by
-0.23 / -0.66 / -1.3 %, 7 -> 9 teeth by -0.04 / -0.10 / -0.24 %; with the sides clamped
too the 5-tooth values are below the converged ones, with the sides free above them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from gearsim.errors import InputError
from gearsim.fem.geometry import SectorOptions
from gearsim.fem.ring import (
    fe_ring_tooth_compliance,
    fe_ring_tooth_result,
    ring_load_geometry,
    ring_tooth_half_angle,
)
from gearsim.fem.tooth import fe_tooth_compliance
from gearsim.geometry.gear import Gear
from gearsim.geometry.planetary import RingGear

E, NU = 2.06e11, 0.3
#: Level 2 vs level 3 at the pitch radius [-]: P2 elements of m_n / 16 on a tooth 2.25 m_n
#: high leave a discretisation error well below 1 % (measured 0.09 %).
TOL_MESH = 0.01
#: 5 vs 7 teeth at the pitch radius [-]: the brief's segment-size target (measured 0.66 %).
TOL_SEGMENT = 0.01
#: 5 vs 7 teeth near the root [-]: the free side cuts are closest to the load there
#: (measured 1.3 %); 2 % bounds it with margin.
TOL_SEGMENT_ROOT = 0.02
#: 7 vs 9 teeth at all radii [-]: the segment effect decays with distance (measured 0.24 %).
TOL_SEGMENT_LARGE = 0.005
#: Upper bound of FE / (Timoshenko cantilever clamped at the root circle) for loads in the
#: outer 40 % of the tooth [-]: the rim (foundation) flexibility the beam leaves out adds a
#: few tens of per cent there (Sainsot et al. 2004 for external teeth); measured 1.45-1.78.
MAX_FOUNDATION_RATIO = 2.0
#: Ring (z 400) vs external gear (z 400) FE, same rack-like tooth, rim and support [-]:
#: they differ only by the root fillet (circle 0.25 m_n vs the rack's trochoid) and by the
#: opposite curvature of order 1/z; measured 0.2-1.7 %.
TOL_RACK = 0.03


@pytest.fixture(scope="module")
def ring():
    return RingGear(teeth=78, normal_module=2e-3)


def _radii(ring):
    ra, rf = ring.tip_radius, ring.root_radius
    return np.array([ra + 0.1 * (rf - ra), ring.pitch_radius, rf - 0.3 * (rf - ra)])


@pytest.fixture(scope="module")
def levels(ring):
    return {lev: fe_ring_tooth_result(ring, _radii(ring), youngs_modulus=E, poisson_ratio=NU,
                                      level=lev) for lev in (1, 2, 3)}


def test_mesh_convergence(levels):
    c = np.array([levels[lev].compliance[1] for lev in (1, 2, 3)])  # pitch radius
    d12, d23 = abs(c[1] - c[0]), abs(c[2] - c[1])
    print(f"pitch radius, levels 1-3: {c * 1e12} e-12 m/N, |c2-c1| = {d12:.3e}, "
          f"|c3-c2| = {d23:.3e}")
    assert d23 < d12
    assert abs(c[1] - c[2]) / c[2] < TOL_MESH
    for lev in (1, 2):  # all three radii converge alike
        rel = np.abs(levels[lev].compliance / levels[3].compliance - 1.0)
        assert np.all(rel < TOL_MESH), (lev, rel)


def test_sign_conventions(ring, levels):
    """d is the inward normal of the involute, Q lies on the centre line and the tooth
    bends towards -x under a positive compliance."""
    for rc in _radii(ring):
        p, d, q = ring_load_geometry(ring, float(rc))
        # flank tangent by finite differences of the flank curve (beta from the brief)
        eps = 1e-7
        pts = []
        for rho in (rc - eps, rc + eps):
            b = float(ring_tooth_half_angle(ring, rho))
            pts.append((rho * math.sin(b), rho * math.cos(b)))
        tangent = np.subtract(pts[1], pts[0])
        tangent /= np.hypot(*tangent)
        assert abs(np.dot(tangent, d)) < 1e-6
        theta = math.atan2(p[0], p[1])
        e_theta = np.array([math.cos(theta), -math.sin(theta)])
        e_r = np.array([math.sin(theta), math.cos(theta)])
        assert np.dot(d, e_theta) < 0.0  # towards the tooth centre line
        assert np.dot(d, e_r) > 0.0  # towards the root (outwards)
        assert q[0] == 0.0
        s = (q - p) / np.hypot(*(q - p))
        assert abs(s[0] * d[1] - s[1] * d[0]) < 1e-12  # Q on the line of action through P
    res = levels[1]
    assert np.all(res.compliance > 0.0)
    assert np.all(res.tip_displacement[0] < 0.0)  # bends towards -x
    assert np.all(np.diff(res.compliance) < 0.0)  # stiffer towards the root


def _beta(ring, rho):
    """Half angular thickness, written out from the formula (independent of the module)."""
    def inv(a):
        return math.tan(a) - a

    at = ring.transverse_pressure_angle
    s_r = ring.transverse_module * (0.5 * math.pi - 2.0 * ring.profile_shift
                                    * math.tan(ring.normal_pressure_angle))
    return s_r / (2.0 * ring.pitch_radius) - inv(at) + inv(math.acos(ring.base_radius / rho))


def _timoshenko(ring, rc):
    """Castigliano compliance along the load of a Timoshenko cantilever of the tooth's
    thickness 2 rho sin(beta), clamped at the root circle, loaded at P along d [m/N]."""
    b = _beta(ring, rc)
    a1 = math.acos(ring.base_radius / rc) + b
    xp, yp = rc * math.sin(b), rc * math.cos(b)
    g = E / (2.0 * (1.0 + NU))

    def f(rho):
        t = 2.0 * rho * math.sin(_beta(ring, rho))
        moment = xp * math.sin(a1) - (rho - yp) * math.cos(a1)
        return (moment**2 / (E * t**3 / 12.0) + 1.2 * math.cos(a1) ** 2 / (g * t)
                + math.sin(a1) ** 2 / (E * t))

    return quad(f, yp, ring.root_radius)[0]


def test_rack_like_tooth_monotonic_and_above_cantilever():
    big = RingGear(teeth=400, normal_module=2e-3)
    ra, rf = big.tip_radius, big.root_radius
    frac = np.array([0.0, 0.2, 0.4, 0.6, 0.8, 0.85])
    radii = ra + frac * (rf - ra)  # the involute ends at the fillet, ~0.87 h above r_a
    res = fe_ring_tooth_result(big, radii, youngs_modulus=E, poisson_ratio=NU,
                               rim_thickness=10 * big.normal_module, support="outer+sides",
                               level=2)
    c = res.compliance
    beam = np.array([_timoshenko(big, float(r)) for r in radii])
    print("z 400: FE", c * 1e12, "beam", beam * 1e12, "ratio", c / beam)
    assert np.all(np.diff(c) < 0.0)  # farther from the root bends more
    assert c[0] > 3.0 * c[-1]
    assert np.all(c > beam)  # the beam leaves out the rim flexibility
    tip = frac <= 0.4
    assert np.all(c[tip] / beam[tip] < MAX_FOUNDATION_RATIO)


def test_rack_limit_matches_external_tooth_fe():
    """At z = 400 a ring tooth and an external tooth are both nearly the rack tooth: the
    ring model must agree with the independent external-tooth FE of gearsim.fem.tooth
    (same measure, same 5-tooth segment with clamped sides, same rim depth)."""
    z, m, rim = 400, 2e-3, 42.5e-3
    gear = Gear(teeth=z, normal_module=m, bore_radius=0.5 * z * m - 1.25 * m - rim)
    big = RingGear(teeth=z, normal_module=m)
    height = np.array([0.9, 0.6, 0.3, 0.0, -0.3, -0.6]) * m  # towards the tip: +ext, -ring
    ext = fe_tooth_compliance(gear, gear.pitch_radius + height, closure="open",
                              options=SectorOptions(level=2, n_teeth=5, sides="fixed"))
    ring_c = fe_ring_tooth_compliance(big, big.pitch_radius - height, rim_thickness=rim,
                                      support="outer+sides", level=2)
    rel = ring_c / ext.compliance - 1.0
    print("rack limit: ring / external - 1 =", rel)
    assert np.all(np.abs(rel) < TOL_RACK)


def test_segment_size(ring):
    radii = _radii(ring)
    c = {n: fe_ring_tooth_compliance(ring, radii, n_teeth=n, level=2) for n in (5, 7, 9)}
    clamped = fe_ring_tooth_compliance(ring, radii, n_teeth=5, support="outer+sides", level=2)
    print({n: v * 1e12 for n, v in c.items()}, "5 teeth, sides clamped", clamped * 1e12)
    assert abs(c[5][1] / c[7][1] - 1.0) < TOL_SEGMENT
    assert np.all(np.abs(c[5] / c[7] - 1.0) < TOL_SEGMENT_ROOT)
    assert np.all(np.abs(c[7] / c[9] - 1.0) < TOL_SEGMENT_LARGE)
    # free sides soften, clamped sides stiffen: the two bracket the larger segment
    assert np.all(clamped < c[9]) and np.all(c[9] < c[5])


@pytest.mark.parametrize("kwargs, name", [
    ({"radii": 0.0755}, "radii"),  # inside the tip circle
    ({"radii": 0.0806}, "radii"),  # outside the root circle
    ({"radii": 0.0804}, "radii"),  # on the root fillet
    ({"radii": float("nan")}, "radii"),
    ({"n_teeth": 4}, "n_teeth"),
    ({"n_teeth": 1}, "n_teeth"),
    ({"n_teeth": 41}, "n_teeth"),
    ({"plane": "membrane"}, "plane"),
    ({"support": "inner"}, "support"),
    ({"rim_thickness": 0.0}, "rim_thickness"),
    ({"rim_thickness": -1e-3}, "rim_thickness"),
    ({"level": -1}, "level"),
])
def test_bad_input_refused(ring, kwargs, name):
    kw = {"radii": ring.pitch_radius, "level": 0} | kwargs
    radii = kw.pop("radii")
    with pytest.raises(InputError) as err:
        fe_ring_tooth_compliance(ring, radii, **kw)
    assert err.value.parameter == name
