"""The tip corners of a gear pair outside and at the ends of the path of contact.

Geometry only (the frame of :func:`corner_separation`; involutes as in Litvin & Fuentes
2004, ch. 10): where the tip corner of the incoming and of the outgoing tooth pair lies
relative to the mating involute (its separation along the line of action), and how far
a contact's Hertz centre lies from the nearer tip edge (:func:`tip_edge_offset`, the
offset of the truncated line contact, :func:`gearsim.stiffness.tooth.edge_truncation`).
Used by the stiffness tables (:mod:`gearsim.stiffness.mesh`) and the mesh of contacts
(:mod:`gearsim.stiffness.contacts`).
"""

from __future__ import annotations

import math

import numpy as np

from gearsim.geometry.pair import GearPair

__all__ = ["corner_separation", "tip_edge_offset"]


def _tip_corners(pair: GearPair, l: np.ndarray):
    """The two tip corners of a pair at line-of-action position ``l``, in the frame of
    :func:`corner_separation`: the driven tip corner C = (cx, cy) of the incoming pair
    with its base-circle angle h, the driver tip corner D relative to the driven centre
    (dx, dy) with its base-circle angle g (Litvin & Fuentes 2004, ch. 10)."""
    rb1, rb2 = pair.driver.base_radius, pair.driven.base_radius
    alpha = pair.working_pressure_angle
    big_l = pair.line_length
    ra2 = big_l - pair.start_of_contact  # roll length of the driven tip
    h = math.pi - alpha + (big_l - l - ra2) / rb2
    cx = pair.centre_distance + rb2 * np.cos(h) + ra2 * np.cos(h + math.pi / 2)
    cy = rb2 * np.sin(h) + ra2 * np.sin(h + math.pi / 2)
    ra1 = pair.end_of_contact  # roll length of the driver tip
    g = l / rb1 - alpha - ra1 / rb1
    dx = rb1 * np.cos(g) + ra1 * np.cos(g + math.pi / 2) - pair.centre_distance
    dy = rb1 * np.sin(g) + ra1 * np.sin(g + math.pi / 2)
    return h, cx, cy, g, dx, dy


def corner_separation(pair: GearPair, l: np.ndarray) -> np.ndarray:
    """Separation of a tooth pair outside the path of contact, at the tip corner [m].

    Frame: driver centre O1 at the origin, driven centre O2 = (a_w, 0), driver turning
    counter-clockwise; the transverse line of action runs from T1 = r_b1 e(-alpha_wt)
    in the direction t = e(pi/2 - alpha_wt). A driver involute whose extension meets the
    line of action at l has the points r_b1 e(g) + rho e(g + pi/2), g = l / r_b1 -
    alpha_wt - rho / r_b1; a driven involute meeting it at l has O2 + r_b2 e(h) + rho
    e(h + pi/2), h = pi - alpha_wt + (T1T2 - l - rho) / r_b2. Before the start of contact
    A (l < l_A) the driven tip corner (rho = rho_a2) lies off the line; the driver must
    turn by Delta = psi_C - phi_1(r_C) (polar angle of the corner minus that of the
    driver involute at the corner's radius) to touch it: separation r_b1 Delta. After the
    end of contact E (l > l_E) the driver's tip corner and the driven involute give
    r_b2 Delta in the same way. Zero at A and E, growing quadratically away from them.

    Parameters
    ----------
    pair : GearPair
        The mesh.
    l : ndarray
        Positions on the (extended) line of action, from T1 [m]; outside [l_A, l_E].

    Returns
    -------
    ndarray
        Separation along the transverse line of action [m] (0 inside [l_A, l_E]).

    References
    ----------
    Involute geometry: Litvin & Fuentes, Gear Geometry and Applied Theory (2004), ch. 10;
    corner (extended) contact: Lin, Liou & Huston (1988) (contact outside the path under
    load).
    """
    l = np.asarray(l, dtype=float)
    rb1, rb2 = pair.driver.base_radius, pair.driven.base_radius
    alpha = pair.working_pressure_angle
    big_l = pair.line_length
    la, le = pair.start_of_contact, pair.end_of_contact
    out = np.zeros(l.shape)
    h, cx, cy, g, dx, dy = _tip_corners(pair, l)
    # incoming pair: driven tip corner against the driver involute
    rc = np.hypot(cx, cy)
    psi = np.arctan2(cy, cx)
    rho = np.sqrt(np.maximum(rc * rc - rb1 * rb1, 0.0))
    phi = l / rb1 - alpha - rho / rb1 + np.arctan2(rho, rb1)
    inc = rb1 * (psi - phi)
    # outgoing pair: driver tip corner against the driven involute
    rd = np.hypot(dx, dy)
    psi2 = np.arctan2(dy, dx)
    rho2 = np.sqrt(np.maximum(rd * rd - rb2 * rb2, 0.0))
    hh = math.pi - alpha + (big_l - l - rho2) / rb2
    phi2 = hh + np.arctan2(rho2, rb2)
    out_ = rb2 * np.mod(psi2 - phi2 + math.pi, 2 * math.pi) - rb2 * math.pi
    out = np.where(l < la, inc, out)
    return np.where(l > le, out_, out)


def _line_angle(x: np.ndarray) -> np.ndarray:
    """Angle between two lines whose directions differ by ``x`` [rad], in [0, pi/2]."""
    return np.abs(np.mod(x + 0.5 * math.pi, math.pi) - 0.5 * math.pi)


def tip_edge_offset(pair: GearPair, l: np.ndarray) -> np.ndarray:
    """Offset of a contact's Hertz centre beyond the nearer tip edge of its pair [m].

    The signed ``edge`` of :func:`gearsim.stiffness.tooth.line_contact_compliance`
    (:func:`gearsim.stiffness.tooth.edge_truncation`), in the frame of
    :func:`corner_separation`. On the path of contact (l_A <= l <= l_E) the involute
    contact lies the arc length s = (rho_a^2 - rho^2) / (2 r_b) inside the tip edge of
    each profile (Litvin & Fuentes 2004, ch. 10: the involute's arc length between the
    roll lengths rho and rho_a): the driver's tip is at rho_1 = l_E, the driven's at
    rho_2 = L - l_A, and the offset is -min(s_1, s_2). Outside the path the tip corner
    touches the mating flank (the incoming pair's driven corner before l_A, the
    outgoing pair's driver corner after l_E, at the no-load position l): its own flank
    leaves the mating one at the angle theta between the two involutes' normals at the
    corner (the tangents from the corner to the two base circles; 0 at l_A and l_E), a
    gap theta |x| + x^2 / (2 R) at the distance x inside the edge, i.e. the Hertz
    centre theta R beyond it, R the relative radius of curvature at the path end (the
    radii of the corner law, :func:`gearsim.stiffness.mesh.extended_law`).

    Parameters
    ----------
    pair : GearPair
        The mesh.
    l : ndarray
        Positions on the (extended) line of action, from T1 [m], between T1 and T2.

    Returns
    -------
    ndarray
        Offset [m]: <= 0 on the path, >= 0 outside it; the shape of ``l``.

    References
    ----------
    F. L. Litvin, A. Fuentes, Gear Geometry and Applied Theory, Cambridge University
    Press, 2004, ch. 10 (involute geometry); K. L. Johnson, Contact Mechanics, 1985,
    ch. 5 (non-Hertzian contact).
    """
    l = np.asarray(l, dtype=float)
    rb1, rb2 = pair.driver.base_radius, pair.driven.base_radius
    big_l = pair.line_length
    la, le = pair.start_of_contact, pair.end_of_contact
    lc = np.clip(l, la, le)
    s1 = (le * le - lc * lc) / (2.0 * rb1)
    s2 = ((big_l - la) ** 2 - (big_l - lc) ** 2) / (2.0 * rb2)
    on_path = -np.minimum(s1, s2)
    h, cx, cy, g, dx, dy = _tip_corners(pair, l)
    # incoming: the driven tip corner C and the driver involute through it
    rho1 = np.sqrt(np.maximum(cx * cx + cy * cy - rb1 * rb1, 0.0))
    g_in = np.arctan2(cy, cx) - np.arctan2(rho1, rb1)
    theta_in = _line_angle(h - g_in)
    # outgoing: the driver tip corner D and the driven involute through it
    rho2 = np.sqrt(np.maximum(dx * dx + dy * dy - rb2 * rb2, 0.0))
    h_out = np.arctan2(dy, dx) - np.arctan2(rho2, rb2)
    theta_out = _line_angle(h_out - g)
    r_a = 1.0 / (1.0 / la + 1.0 / (big_l - la))
    r_e = 1.0 / (1.0 / le + 1.0 / (big_l - le))
    return np.where(l < la, theta_in * r_a, np.where(l > le, theta_out * r_e, on_path))
