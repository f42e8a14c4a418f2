"""Tier 1: planar layout and mesh phase of the idler, against direct geometry.

The phase formula in :mod:`gearsim.dynamics.layout` is checked against an independent
construction: put the contact point of mesh I at its start of contact, find the idler
tooth there from the polar angle of that point and the involute half-thickness, turn
the idler until that tooth's other flank reaches the start of contact of mesh II, and
read off the cycle offset. Tolerance 1e-9 cycles (round-off).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.dynamics.layout import layout
from gearsim.errors import InputError
from gearsim.model import load


def _angle(v):
    return math.atan2(v[1], v[0])


@pytest.mark.parametrize("gamma_deg", [180.0, 150.0, 215.0, 123.4])
def test_idler_phase_against_geometry(gamma_deg):
    tr = load("idler-table1").train
    lay = layout(tr, (math.radians(gamma_deg),))
    p0, p1 = tr.pairs
    c0, c1, c2 = lay.centres
    s1 = lay.senses[1]
    idler = tr.gears[1]
    for pair, n, ca, cb in ((p0, lay.normal[0], c0, c1), (p1, lay.normal[1], c1, c2)):
        # n is tangent to both base circles and turns both gears the right way
        e = (cb - ca) / np.linalg.norm(cb - ca)
        pitch = ca + pair.driver.base_radius / math.cos(pair.working_pressure_angle) * e
        t1 = pitch - np.dot(pitch - ca, n) * n
        t2 = pitch + np.dot(cb - pitch, n) * n
        assert np.linalg.norm(t1 - ca) == pytest.approx(pair.driver.base_radius, rel=1e-12)
        assert np.linalg.norm(t2 - cb) == pytest.approx(pair.driven.base_radius, rel=1e-12)
    # mesh I start of contact (cycle 0): point A on the idler's tip circle
    n0, n1 = lay.normal
    e0 = (c1 - c0) / np.linalg.norm(c1 - c0)
    pitch0 = c0 + p0.driver.base_radius / math.cos(p0.working_pressure_angle) * e0
    t1_0 = pitch0 - np.dot(pitch0 - c0, n0) * n0
    a_pt = t1_0 + p0.start_of_contact * n0
    ra = np.linalg.norm(a_pt - c1)
    assert ra == pytest.approx(idler.tip_radius, rel=1e-9)
    # tooth 0 of the idler touches with its rear flank: centre line ahead by psi(r)
    centre0 = s1 * _angle(a_pt - c1) + idler.half_thickness_angle(ra)
    # mesh II start of contact: point A'' on the line of action of mesh II
    e1 = (c2 - c1) / np.linalg.norm(c2 - c1)
    pitch1 = c1 + p1.driver.base_radius / math.cos(p1.working_pressure_angle) * e1
    t1_1 = pitch1 - np.dot(pitch1 - c1, n1) * n1
    a2 = t1_1 + p1.start_of_contact * n1
    r2 = np.linalg.norm(a2 - c1)
    # its front flank there: centre line behind by psi(r2); turn the idler (own sense)
    turn = s1 * _angle(a2 - c1) - idler.half_thickness_angle(r2) - centre0
    cycles_in_mesh1 = (turn * idler.teeth / (2 * math.pi)) % idler.teeth
    expected = (-cycles_in_mesh1) % idler.teeth  # c_II = c_I - (that) at tooth 0 entry
    got = lay.phase[1] % idler.teeth
    d = (got - expected + idler.teeth / 2) % idler.teeth - idler.teeth / 2
    assert abs(d) < 1e-9, (got, expected)


def test_phase_moves_one_cycle_per_angular_pitch():
    tr = load("idler-table1").train
    z = tr.gears[1].teeth
    g = math.radians(170.0)
    a = layout(tr, (g,)).phase[1]
    b = layout(tr, (g + 2 * math.pi / z,)).phase[1]
    assert b - a == pytest.approx(-1.0, abs=1e-12)


def test_overlapping_layout_refused():
    tr = load("idler-table1").train
    with pytest.raises(InputError, match="idler_angle"):
        layout(tr, (math.radians(40.0),))
