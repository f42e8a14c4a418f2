"""The line contact cut off by a tooth's tip edge (issue 25 item 2, the zone ends).

:func:`gearsim.stiffness.tooth.edge_truncation` is a closed form; here it is checked
against a numerical solution of the same contact problem written out independently (a
panel method: piecewise-constant pressure on the half-plane's logarithmic kernel, an
active set for p >= 0). :func:`gearsim.geometry.corners.tip_edge_offset` is checked
against two independent routes: the arc length of the involute by quadrature, and the
tilt of the outgoing tip corner implied by its closing rate (finite differences of the
corner separations, :func:`gearsim.stiffness.mesh.corner_closing`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import gearsim as gs
from gearsim.geometry.corners import tip_edge_offset
from gearsim.geometry.gear import Material
from gearsim.stiffness.mesh import corner_closing
from gearsim.stiffness.tooth import edge_truncation, line_contact_compliance
from gearsim.system.train import GearTrain

#: Panels of the numerical contact solution (graded towards the edge, where the pressure
#: is square-root singular): its G converged to 1e-5 from 200 to 800 panels.
PANELS = 400
#: Agreement of the closed form with the panel solution [-] (discretisation: 1e-5 at 400
#: panels, measured; G itself is 0 ... 2.6 on the offsets checked).
PANEL_ATOL = 2e-4
#: Agreement of two routes that compute the same geometry with different round-off.
GEOMETRY_RTOL = 1e-9
#: The outgoing corner's tilt from the closing rate: the rate is a central difference
#: (step 1e-3 base pitches) taken at l + delta*, not at l; within 0.02 base pitches of E
#: the two differ by < 0.5 % (measured 1e-4 at 0.01 pitch on Table-1 mesh I).
RATE_RTOL = 1e-2


def _panel_solution(offset: float) -> float:
    """G of the truncated contact by a panel method, in units of the Hertz half width.

    Surface x <= 0 (edge at 0), gap (x - e)^2 (times 2 w / (pi E* a^2)); unknowns: the
    panel pressures p_j >= 0 (sum p_j w_j = 1) and the constant lambda with
    sum_j p_j int_j ln|x_i - s| ds + lambda = h(x_i) on the contact. G = lambda -
    max(e, 0)^2 - (1/2 + ln 2) (the untruncated contact's lambda)."""
    left = min(-3.0, offset - 2.0)
    t = np.linspace(0.0, 1.0, PANELS + 1)
    edges = np.sort(left * (1.0 - t) ** 2)
    s1, s2 = edges[:-1], edges[1:]
    width = s2 - s1
    xm = 0.5 * (s1 + s2)

    def f(z):  # antiderivative of ln|z|
        az = np.abs(z)
        return np.where(az > 0, z * np.log(np.where(az > 0, az, 1.0)) - z, 0.0)

    kernel = f(xm[:, None] - s1[None, :]) - f(xm[:, None] - s2[None, :])
    gap = (xm - offset) ** 2
    active = gap < gap.min() + 1.5
    for _ in range(200):
        idx = np.flatnonzero(active)
        m = idx.size
        a = np.zeros((m + 1, m + 1))
        a[:m, :m] = kernel[np.ix_(idx, idx)]
        a[:m, m] = 1.0
        a[m, :m] = width[idx]
        sol = np.linalg.solve(a, np.r_[gap[idx], 1.0])
        p = np.zeros(PANELS)
        p[idx] = sol[:m]
        lam = sol[m]
        open_gap = gap - kernel @ p - lam
        drop = active & (p < 0)
        add = ~active & (open_gap < -1e-12)
        if not drop.any() and not add.any():
            return lam - max(offset, 0.0) ** 2 - (0.5 + math.log(2.0))
        active = (active & ~drop) | add
    raise AssertionError("active set did not settle")


@pytest.mark.parametrize("offset", [-1.5, -0.9, -0.5, -0.25, 0.0, 0.3, 1.0, 2.0, 4.0])
def test_closed_form_against_a_panel_solution(offset):
    """The closed form of the truncated contact is the contact problem's solution."""
    assert float(edge_truncation(offset)) == pytest.approx(_panel_solution(offset),
                                                            abs=PANEL_ATOL)


def test_closed_form_limits():
    """Whole Hertz strip inside the edge: nothing changes (G = 0 from e = -1, continuous
    there); the centre at the edge: G = ln sqrt(3); a larger offset, a smaller contact."""
    e = np.linspace(-3.0, 6.0, 901)
    g = edge_truncation(e)
    assert np.all(g[e <= -1.0] == 0.0)
    assert float(edge_truncation(-1.0 + 1e-6)) < 1e-9
    assert float(edge_truncation(0.0)) == pytest.approx(math.log(math.sqrt(3.0)), rel=1e-12)
    assert np.all(np.diff(g[e > -1.0]) > 0)


def test_far_edge_is_the_untruncated_contact():
    """An edge beyond the Hertz strip leaves the line contact compliance as it was; one
    at the Hertz centre adds (2 / (pi E*)) ln sqrt(3) (plane stress, steel: E* = E / 2)."""
    st = Material()
    w, r1, r2, d = 2e5, 0.02, 0.03, 2.5e-3  # a = 172 um (the docstring's example)
    plain = float(line_contact_compliance(w, r1, r2, d, d, st, st))
    far = float(line_contact_compliance(w, r1, r2, d, d, st, st, edge=-1e-3))
    at = float(line_contact_compliance(w, r1, r2, d, d, st, st, edge=0.0))
    assert far == plain
    extra = 2.0 / math.pi * (2.0 / st.youngs_modulus) * math.log(math.sqrt(3.0))
    assert at - plain == pytest.approx(extra, rel=1e-12)


def _pair(name: str):
    return gs.example(name).train.pairs[0]


@pytest.mark.parametrize("name", ["spur-19-48", "idler-table1"])
def test_offset_on_the_path_is_the_involute_arc_length(name):
    """On the path the offset is minus the arc length to the nearer tip, here by
    quadrature of the involute r_b (cos t + t sin t, sin t - t cos t)."""
    pair = _pair(name)
    la, le, big_l = pair.start_of_contact, pair.end_of_contact, pair.line_length
    for frac in (0.02, 0.1, 0.3):
        for gear, l, tip in ((pair.driver, le - frac * (le - la), le),
                             (pair.driven, la + frac * (le - la), big_l - la)):
            rho = l if gear is pair.driver else big_l - l
            rb = gear.base_radius
            t = np.linspace(rho / rb, tip / rb, 20001)
            x = rb * (np.cos(t) + t * np.sin(t))
            y = rb * (np.sin(t) - t * np.cos(t))
            arc = np.sum(np.hypot(np.diff(x), np.diff(y)))
            assert float(tip_edge_offset(pair, np.array([l]))[0]) == pytest.approx(
                -arc, rel=1e-6)


@pytest.mark.parametrize("name", ["spur-19-48", "idler-table1"])
def test_outgoing_tilt_matches_the_closing_rate(name):
    """The outgoing tip corner's tilt theta (offset / R) and its closing rate rho, the
    driver's moment arm about the mating flank's normal over r_b1, are tied by
    rho = cos(alpha_a1 + theta) / cos(alpha_a1)."""
    pair = _pair(name)
    le, big_l, pb = pair.end_of_contact, pair.line_length, pair.base_pitch
    r_e = 1.0 / (1.0 / le + 1.0 / (big_l - le))
    alpha_a = math.atan(le / pair.driver.base_radius)
    l = le + np.array([0.005, 0.01, 0.02]) * pb
    theta = tip_edge_offset(pair, l) / r_e
    _, rate = corner_closing(pair, l)
    from_rate = np.arccos(rate * math.cos(alpha_a)) - alpha_a
    np.testing.assert_allclose(theta, from_rate, rtol=RATE_RTOL)
    assert np.all(theta > 0)


def test_incoming_and_outgoing_mirror_on_equal_gears():
    """Two equal gears (the 19/48 example's tooth, 25/25): the incoming corner at
    l_A - x is the outgoing one at l_E + x, and the path offsets are symmetric."""
    base = gs.example("spur-19-48").train
    g0 = base.gears[0]
    gears = tuple(dataclasses.replace(g0, name=n, teeth=25) for n in ("pinion", "gear"))
    pair = GearTrain(gears=gears, operating=base.operating, stiffness=base.stiffness,
                     cracks=()).pairs[0]
    la, le, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
    x = np.array([0.003, 0.01, 0.03, 0.1]) * pb
    np.testing.assert_allclose(tip_edge_offset(pair, la - x), tip_edge_offset(pair, le + x),
                               rtol=GEOMETRY_RTOL)
    np.testing.assert_allclose(tip_edge_offset(pair, la + x), tip_edge_offset(pair, le - x),
                               rtol=GEOMETRY_RTOL)


def test_corner_offset_vanishes_at_the_ends():
    """At l_A and l_E the corner is the end of the involute contact: offset 0 from both
    sides (continuity of the table across the ends)."""
    pair = _pair("idler-table1")
    la, le = pair.start_of_contact, pair.end_of_contact
    h = 1e-9 * pair.base_pitch
    off = tip_edge_offset(pair, np.array([la - h, la, la + h, le - h, le, le + h]))
    assert np.all(np.abs(off) < 1e-6 * pair.base_pitch)
