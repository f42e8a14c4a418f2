"""Planetary stage geometry: radii, contact ratios, assembly refusals and mesh phasing.

The contact ratios are checked against a coordinate construction (intersect the line of
action with the tip circles), the mesh phases against explicit involute flanks
intersected numerically with the lines of action in the carrier frame. Neither uses the
closed forms of :mod:`gearsim.geometry.planetary`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from gearsim.errors import InputError
from gearsim.geometry.planetary import PlanetaryStage

#: Lengths from closed forms vs. coordinate constructions: both in double precision.
GEOMETRY_RTOL = 1e-9
#: Mesh phases from root-finding on involute curves (brentq xtol 1e-14 on the roll angle).
PHASE_ATOL = 1e-7

SEQ = dict(sun_teeth=30, planet_teeth=24, ring_teeth=78, normal_module=2e-3, planets=4)
INPHASE = dict(sun_teeth=28, planet_teeth=20, ring_teeth=68, normal_module=2e-3, planets=4)


def _line_circle(p0: np.ndarray, u: np.ndarray, centre: np.ndarray, radius: float) -> np.ndarray:
    """Parameters t of the two points where p0 + t u crosses a circle."""
    d = p0 - centre
    b = float(d @ u)
    c = float(d @ d) - radius**2
    disc = math.sqrt(b * b - c)
    return np.array([-b - disc, -b + disc])


def test_ring_radii_and_centre_distance() -> None:
    s = PlanetaryStage(**SEQ)
    r = s.ring
    # internal gear: tip (inner) circle r - m, root (outer) circle r + 1.25 m
    assert r.tip_radius == pytest.approx(0.076, rel=GEOMETRY_RTOL)
    assert r.root_radius == pytest.approx(0.0805, rel=GEOMETRY_RTOL)
    assert r.tip_radius < r.pitch_radius < r.root_radius
    assert s.centre_distance == pytest.approx(0.5 * (0.030 + 0.024) * 2, rel=GEOMETRY_RTOL)
    assert s.ring_planet_centre_distance == pytest.approx(s.centre_distance, rel=GEOMETRY_RTOL)


@pytest.mark.parametrize("kw", [SEQ, INPHASE, dict(SEQ, helix_angle=math.radians(15.0))])
def test_contact_ratios_by_construction(kw: dict) -> None:
    s = PlanetaryStage(**kw)
    sun, pl, ring = s.sun, s.planet, s.ring
    a = s.centre_distance
    alpha = s.sun_planet_pressure_angle
    o, c = np.zeros(2), np.array([0.0, a])
    # sun-planet: line through the pitch point at alpha to the common tangent
    p = np.array([0.0, sun.base_radius / math.cos(alpha)])
    u = np.array([-math.cos(alpha), math.sin(alpha)])
    t_sun = _line_circle(p, u, o, sun.tip_radius).max()  # sun tip, on the planet side
    t_pl = _line_circle(p, u, c, pl.tip_radius).min()  # planet tip, on the sun side
    assert (t_sun - t_pl) / s.base_pitch == pytest.approx(s.sun_planet_contact_ratio, rel=GEOMETRY_RTOL)
    # ring-planet: pitch point at r_b,r / cos(alpha_w), line at alpha_w (internal pair)
    ar = s.ring_planet_pressure_angle
    p = np.array([0.0, ring.base_radius / math.cos(ar)])
    u = np.array([math.cos(ar), math.sin(ar)])
    t_tr = _line_circle(p, u, o, ring.tip_radius)  # ring tip (inner) circle
    t_tp = _line_circle(p, u, c, pl.tip_radius)
    # the path runs from the ring tip to the planet tip, on the segment beyond T_p
    t_p = float((c - p) @ u)  # T_p, the planet's tangent point
    start = t_tr[t_tr > t_p].min()
    end = t_tp.max()
    assert (end - start) / s.base_pitch == pytest.approx(s.ring_planet_contact_ratio, rel=GEOMETRY_RTOL)
    assert s.ring_planet_line_of_action == pytest.approx(
        (ring.base_radius - pl.base_radius) * math.tan(ar), rel=GEOMETRY_RTOL)


def test_shifted_stage_is_coaxial() -> None:
    # x_s = -x_p and x_r = x_p keep both working pressure angles at alpha_t
    s = PlanetaryStage(**SEQ, sun_shift=-0.2, planet_shift=0.2, ring_shift=0.2)
    assert s.sun_planet_pressure_angle == pytest.approx(s.sun.transverse_pressure_angle, rel=1e-12)
    assert s.ring.tip_radius == pytest.approx(0.078 - 0.8 * 0.002, rel=GEOMETRY_RTOL)
    with pytest.raises(InputError, match="centre distance.*coaxiality"):
        PlanetaryStage(**SEQ, sun_shift=0.3, planet_shift=0.2, ring_shift=0.2)


@pytest.mark.parametrize(("change", "pattern"), [
    (dict(ring_teeth=80), r"z_r = z_s \+ 2 z_p = 78"),
    (dict(planets=5), r"\(30 \+ 78\)/5 = 21\.6"),
    (dict(planets=9), r"planets collide.*2 r_a,planet = 52 mm"),
    (dict(planets=0), "must be >= 1"),
    (dict(sun_teeth=30.0), "must be an integer"),
    (dict(planets=3, planet_angles=(0.0, 2.0, 4.0)), r"cannot be assembled"),
    (dict(planets=3, planet_angles=(0.1, 2.0, 4.0)), r"must be 0"),
    (dict(planets=3, planet_angles=(0.0, 2 * math.pi * 3 / 108, 2 * math.pi * 50 / 108)),
     "planets collide"),
])
def test_refusals(change: dict, pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        PlanetaryStage(**dict(SEQ, **change))


# ---------------------------------------------------------------------------- phasing
def _flank(centre: np.ndarray, rb: float, beta: float, rho: float,
           side: int) -> tuple[np.ndarray, np.ndarray]:
    """Point and unit normal of an involute of base radius rb starting at angle beta.

    side +1: polar angle increasing with radius; -1: decreasing (the mirror flank).
    """
    tau = beta + side * rho
    t = np.array([math.cos(tau), math.sin(tau)])
    n = side * np.array([math.sin(tau), -math.cos(tau)])
    return centre + rb * t + rb * rho * n, n


def _contacts(centre: np.ndarray, rb: float, r_out: float, flanks: list[tuple[float, int]],
              p0: np.ndarray, u: np.ndarray, t_range: tuple[float, float]) -> list[float]:
    """Positions t on the line p0 + t u where a flank crosses it at right angles (contact).

    ``flanks``: (start angle on the base circle, sense) of each involute flank.
    """
    nl = np.array([-u[1], u[0]])
    rho_max = math.sqrt(r_out**2 / rb**2 - 1.0)
    out = []
    for beta, side in flanks:
        def f(rho: float, beta: float = beta, side: int = side) -> float:
            return float((_flank(centre, rb, beta, rho, side)[0] - p0) @ nl)
        grid = np.linspace(0.0, rho_max, 40)
        vals = [f(x) for x in grid]
        for i in range(len(grid) - 1):
            if vals[i] * vals[i + 1] < 0.0:
                rho = brentq(f, grid[i], grid[i + 1], xtol=1e-14)
                pt, n = _flank(centre, rb, beta, rho, side)
                t = float((pt - p0) @ u)
                if abs(abs(float(n @ u)) - 1.0) < 1e-9 and t_range[0] < t < t_range[1]:
                    out.append(t)
    return out


def _rot(v: np.ndarray, ang: float) -> np.ndarray:
    c, s = math.cos(ang), math.sin(ang)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _central_phases(stage: PlanetaryStage, member: str) -> np.ndarray:
    """Lag of mesh n behind mesh 1 from explicit involutes of the sun or ring, in [0, 1).

    Carrier frame, planet 1 on +y, sun turning counter-clockwise, ring clockwise. The
    phase is read from where the central member's flanks cross mesh n's line of action
    and how those crossings move with time.
    """
    pb = stage.base_pitch
    a = stage.centre_distance
    if member == "sun":
        gear, alpha, z, spin = stage.sun, stage.sun_planet_pressure_angle, stage.sun_teeth, +1.0
        p1 = np.array([0.0, gear.base_radius / math.cos(alpha)])
        u1 = np.array([-math.cos(alpha), math.sin(alpha)])
        # between the tangent points T_s and T_p
        t_rng = (-gear.base_radius * math.tan(alpha), stage.planet.base_radius * math.tan(alpha))
    else:
        gear, alpha, z, spin = stage.ring, stage.ring_planet_pressure_angle, stage.ring_teeth, -1.0
        p1 = np.array([0.0, gear.base_radius / math.cos(alpha)])
        u1 = np.array([math.cos(alpha), math.sin(alpha)])
        # beyond the planet's tangent point T_p, away from the ring's T_r
        t_rng = (-stage.planet.base_radius * math.tan(alpha), a)
    rb = gear.base_radius
    r_out = 1.3 * (rb + 2 * a)

    def position(psi: float, theta: float) -> float:
        # both flank senses at an arbitrary common offset: the tooth thickness cancels in
        # the phase of mesh n relative to mesh 1, and t_rng admits only the loaded sense
        betas = theta + 2.0 * math.pi * np.arange(z) / z + 0.123
        flanks = [(float(b), 1) for b in betas] + [(float(b), -1) for b in betas]
        p0, u = _rot(p1, psi), _rot(u1, psi)
        ts = _contacts(np.zeros(2), rb, r_out, flanks, p0, u, t_rng)
        return min(t % pb for t in ts)

    # direction of travel of the contacts with time (member turns by spin * dtheta)
    d0, d1 = position(0.0, 0.0), position(0.0, spin * 1e-5)
    sign = 1.0 if (d1 - d0) % pb < 0.5 * pb else -1.0
    out = []
    for psi in stage.planet_angles_value:
        g = (sign * (position(0.0, 0.0) - position(float(psi), 0.0)) / pb) % 1.0
        out.append(0.0 if min(g, 1.0 - g) < PHASE_ATOL else g)
    return np.array(out)


UNEQUAL = dict(sun_teeth=30, planet_teeth=24, ring_teeth=78, normal_module=2e-3, planets=3,
               planet_angles=(0.0, 2 * math.pi * 35 / 108, 2 * math.pi * 71 / 108))


@pytest.mark.parametrize("kw", [SEQ, INPHASE, UNEQUAL])
def test_mesh_phases_from_involute_geometry(kw: dict) -> None:
    s = PlanetaryStage(**kw)
    np.testing.assert_allclose(s.sun_planet_phases, _central_phases(s, "sun"), atol=PHASE_ATOL)
    np.testing.assert_allclose(s.ring_planet_phases, _central_phases(s, "ring"), atol=PHASE_ATOL)


def test_phasing_kinds() -> None:
    # z_s/N = 30/4 not an integer: sequential, phases 0, 1/2, 0, 1/2 (Parker & Lin 2004:
    # gamma_sn = z_s psi_n / 2 pi); z_s/N = 28/4 = 7: in phase
    seq = PlanetaryStage(**SEQ)
    assert seq.phasing == "sequential"
    np.testing.assert_allclose(seq.sun_planet_phases, [0.0, 0.5, 0.0, 0.5], atol=PHASE_ATOL)
    inph = PlanetaryStage(**INPHASE)
    assert inph.phasing == "in-phase"
    np.testing.assert_allclose(inph.sun_planet_phases, 0.0, atol=PHASE_ATOL)
    # equally spaced, assemblable planets: gamma_rn = gamma_sn
    np.testing.assert_allclose(seq.ring_planet_phases, seq.sun_planet_phases, atol=PHASE_ATOL)


def _planet_pitch_event(stage: PlanetaryStage, mesh: str) -> float:
    """Planet rotation (clockwise positive, fraction of a tooth) at which a planet flank
    contacts the line of action of ``mesh`` at its pitch point; explicit involutes."""
    pl = stage.planet
    a = stage.centre_distance
    c = np.array([0.0, a])
    rb, z = pl.base_radius, pl.teeth
    if mesh == "sun":
        alpha = stage.sun_planet_pressure_angle
        pitch = np.array([0.0, stage.sun.base_radius / math.cos(alpha)])
        u = np.array([-math.cos(alpha), math.sin(alpha)])
    else:
        alpha = stage.ring_planet_pressure_angle
        pitch = np.array([0.0, stage.ring.base_radius / math.cos(alpha)])
        u = np.array([math.cos(alpha), math.sin(alpha)])
    t_tangent = float((c - pitch) @ u)  # planet tangent point on the line

    def offset(phi_cw: float) -> float:
        centres = -phi_cw + 2.0 * math.pi * np.arange(z) / z
        psib = pl.base_half_thickness_angle
        # a tooth's flanks start on the base circle at centre - psi_b (polar angle growing
        # with the radius) and centre + psi_b (shrinking): the tooth narrows to the tip
        flanks = [(float(x - psib), 1) for x in centres] + [(float(x + psib), -1) for x in centres]
        # keep crossings on the planet's half of the line, from its tangent point towards
        # the pitch point (where the mating flank can be)
        ts = [t for t in _contacts(c, rb, pl.tip_radius, flanks, pitch, u, (-a, a))
              if (t - t_tangent) * (0.0 - t_tangent) > 0.0]
        return min(t % pb for t in ts)

    pb = stage.base_pitch
    d0, d1 = offset(0.0), offset(1e-5)
    rate = ((d1 - d0 + 0.5 * pb) % pb - 0.5 * pb) / 1e-5  # signed speed along the line
    # rotation at which the contact nearest behind the pitch point reaches it
    dphi = ((-d0 / rate) % (pb / abs(rate)))
    return dphi * z / (2.0 * math.pi)


@pytest.mark.parametrize("kw", [SEQ, dict(SEQ, planet_teeth=23, ring_teeth=76, sun_teeth=30, planets=2),
                                dict(SEQ, sun_shift=-0.2, planet_shift=0.2, ring_shift=0.2),
                                dict(SEQ, sun_shift=0.1, planet_shift=0.25, ring_shift=0.6)])
def test_sun_ring_phase_from_involute_geometry(kw: dict) -> None:
    s = PlanetaryStage(**kw)
    # the planet turns clockwise; a later event in planet rotation is a later event in time
    geo = (_planet_pitch_event(s, "ring") - _planet_pitch_event(s, "sun")) % 1.0
    geo = 0.0 if min(geo, 1.0 - geo) < PHASE_ATOL else geo
    assert s.sun_ring_phase == pytest.approx(geo, abs=PHASE_ATOL)


def test_sun_ring_phase_parity() -> None:
    # unshifted: gamma_rs = frac((z_p - 1)/2), 1/2 for even and 0 for odd planets
    assert PlanetaryStage(**SEQ).sun_ring_phase == pytest.approx(0.5, abs=PHASE_ATOL)
    odd = PlanetaryStage(sun_teeth=30, planet_teeth=23, ring_teeth=76, normal_module=2e-3, planets=2)
    assert odd.sun_ring_phase == pytest.approx(0.0, abs=PHASE_ATOL)
