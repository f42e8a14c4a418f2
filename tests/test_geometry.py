"""Tier 2 (published values) and tier 1 (analytic) checks of the gear geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, inv, inv_inverse
from gearsim.geometry.pair import GearPair
from gearsim.geometry.profile import ToothProfile

# docs/references.md ("Table-1 check values") gives the Table-1 check values to 3
# decimals: compare to half a unit of the last printed digit.
PRINTED_3DP_DEG = 0.0005
PRINTED_3DP_MM = 0.0005e-3
# Contact ratios are printed to 3 decimals.
PRINTED_RATIO = 0.0005
# Numerical identities (junction of fillet and involute): machine precision level.
IDENTITY = 1e-12


def test_table1_derived_values(table1):
    g1, g2, g3 = table1.gears
    assert abs(math.degrees(g1.transverse_pressure_angle) - 20.483) < PRINTED_3DP_DEG
    assert abs(math.degrees(g1.base_helix_angle) - 12.204) < PRINTED_3DP_DEG
    for g, rb in zip((g1, g2, g3), (112.486e-3, 170.171e-3, 360.532e-3), strict=True):
        assert abs(g.base_radius - rb) < PRINTED_3DP_MM, g.name
    p1, p2 = table1.pairs
    assert abs(p1.transverse_contact_ratio - 1.681) < PRINTED_RATIO
    assert abs(p2.transverse_contact_ratio - 1.756) < PRINTED_RATIO
    assert abs(p1.overlap_ratio - 1.790) < PRINTED_RATIO
    assert abs(table1.shaft_frequency(0) - 31.667) < 0.0005
    assert abs(1 / table1.shaft_frequency(0) - 0.0316) < 0.00005
    assert abs(table1.mesh_frequency - 1235.0) < 1e-9
    assert abs(table1.power - 970e3) / 970e3 < 0.001  # "about 970 kW"
    # speeds and torques of the paper's Table 1 (printed to the unit)
    assert_allclose([table1.speed(i) * 60 / (2 * math.pi) for i in range(3)],
                    [1900, 1256, 593], atol=0.5)
    assert_allclose([table1.torque(i) for i in range(3)], [4876, 7376, 15627], atol=1.5)
    # z = 39: root circle only 0.09 mm above the base circle
    assert abs((g1.root_radius - g1.base_radius) - 0.09e-3) < 0.005e-3


def test_involute_function_roundtrip():
    for a in np.radians([5.0, 14.5, 20.0, 25.0, 35.0]):
        assert abs(inv_inverse(inv(a)) - a) < 1e-13


@pytest.mark.parametrize("z,beta", [(39, 13.0), (19, 0.0), (18, 0.0), (125, 13.0)])
def test_fillet_joins_the_involute(z, beta):
    """The rack-generated fillet meets the analytic involute in position and tangent.

    The fillet comes from the rack kinematics, the involute from its closed form: they
    agree at the form circle only if the generation is right.
    """
    g = Gear(teeth=z, normal_module=6e-3, helix_angle=math.radians(beta), face_width=0.05)
    prof = ToothProfile(g)
    an = g.normal_pressure_angle
    xf, yf = prof.fillet_point(an)
    xi, yi = prof.involute_point(prof.form_radius)
    assert abs(xf - xi) < IDENTITY and abs(yf - yi) < IDENTITY
    # tangent continuity: directions of the two curves at the junction
    d = 1e-6
    tf = np.subtract(prof.fillet_point(an + d), prof.fillet_point(an))  # towards the root
    ti = np.subtract(prof.involute_point(prof.form_radius * (1 + d)), (xi, yi))
    cosang = -np.dot(tf, ti) / (np.linalg.norm(tf) * np.linalg.norm(ti))
    assert cosang > 1 - 1e-6
    # the fillet ends on the root circle, tangent to it
    xr, yr = prof.fillet_point(0.5 * math.pi)
    assert abs(math.hypot(xr, yr) - g.root_radius) < 1e-12


def test_root_below_and_above_base_circle(spur, table1):
    """Both orders of root and base circle are handled (19 teeth: root below base)."""
    pinion = spur.gears[0]
    assert pinion.root_radius < pinion.base_radius
    assert table1.gears[0].root_radius > table1.gears[0].base_radius
    for g in (pinion, table1.gears[0]):
        prof = ToothProfile(g)
        assert prof.form_radius >= g.base_radius
        out = prof.outline()
        assert np.all(np.diff(out[:, 1]) >= 0)  # height grows from root to tip


def test_thickness_at_reference_circle():
    """s = m (pi/2 + 2 x tan a) at the reference circle (ISO 21771), chordal to arc."""
    for x in (-0.2, 0.0, 0.4):
        g = Gear(teeth=30, normal_module=4e-3, face_width=0.03, profile_shift=x)
        arc = g.transverse_thickness(g.pitch_radius)
        assert abs(arc - 4e-3 * (math.pi / 2 + 2 * x * math.tan(math.radians(20)))) < 1e-15
        chord = ToothProfile(g).thickness_at_radius(g.pitch_radius)
        assert abs(chord - 2 * g.pitch_radius * math.sin(arc / (2 * g.pitch_radius))) < 1e-12


def test_undercut_refused():
    with pytest.raises(InputError, match=r"profile_shift.*undercut.*>= 0\.\d+"):
        Gear(teeth=10, normal_module=2e-3, face_width=0.01)


def test_pointed_tooth_refused():
    with pytest.raises(InputError, match="pointed"):
        Gear(teeth=12, normal_module=2e-3, face_width=0.01, profile_shift=1.2)


def test_bad_sizes_refused():
    with pytest.raises(InputError, match=r"normal_module = -0.001: must be >= 1e-05 m"):
        Gear(teeth=20, normal_module=-1e-3)
    with pytest.raises(InputError, match=r"normal_module = 1e-300: must be >= 1e-05 m"):
        Gear(teeth=20, normal_module=1e-300)  # 1e-300 mm: a unit mistake, not a gear
    with pytest.raises(InputError, match="face_width"):
        Gear(teeth=20, normal_module=1e-3, face_width=0.0)
    with pytest.raises(InputError, match="teeth"):
        Gear(teeth=5, normal_module=1e-3)


def test_contact_ratio_below_one_refused():
    g1 = Gear(teeth=20, normal_module=2e-3, face_width=0.01, addendum_coefficient=0.3,
              dedendum_coefficient=0.5, fillet_radius_coefficient=0.1)
    g2 = Gear(teeth=20, normal_module=2e-3, face_width=0.01, addendum_coefficient=0.3,
              dedendum_coefficient=0.5, fillet_radius_coefficient=0.1)
    with pytest.raises(InputError, match="contact ratio.*must be >= 1"):
        GearPair(g1, g2)


def test_interference_refused():
    """A long addendum on the wheel reaches below the pinion's form circle."""
    g1 = Gear(teeth=14, normal_module=2e-3, face_width=0.01, profile_shift=0.3)
    g2 = Gear(teeth=60, normal_module=2e-3, face_width=0.01, addendum_coefficient=1.6,
              dedendum_coefficient=1.9, fillet_radius_coefficient=0.1)
    with pytest.raises(InputError, match="interferes"):
        GearPair(g1, g2)


def test_centre_distance_offset_changes_the_path_of_contact():
    """Pulling the gears apart by da lengthens the line of action by da / sin(alpha_wt)
    (d(a sin alpha)/da with cos alpha = const / a), moves the start of contact by that
    amount and leaves the driver's tip point E: d eps_alpha / da = -1 / (p_b sin alpha_wt)
    (first order; 1e-3 relative at 20 um)."""
    import dataclasses
    import math

    import gearsim as gs
    from gearsim.errors import InputError

    p = gs.example("spur-19-48").train.pairs[0]
    da = 20e-6
    q = dataclasses.replace(p, centre_distance_offset=da)
    s = math.sin(p.working_pressure_angle)
    assert q.centre_distance - p.centre_distance == pytest.approx(da, rel=1e-9)
    assert q.start_of_contact - p.start_of_contact == pytest.approx(da / s, rel=1e-3)
    assert q.end_of_contact == p.end_of_contact
    assert q.transverse_contact_ratio - p.transverse_contact_ratio == pytest.approx(
        -da / (p.base_pitch * s), rel=1e-3)
    with pytest.raises(InputError):
        dataclasses.replace(p, centre_distance_offset=0.01)
