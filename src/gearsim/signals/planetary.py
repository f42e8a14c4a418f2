"""Frequencies and sidebands of a planetary (epicyclic) stage seen from a fixed sensor.

Kinematics (Willis): with z_s, z_p, z_r the tooth counts of sun, planet and ring and
f_s, f_c, f_r the shaft frequencies of sun, carrier and ring (signed, one sense positive),

    f_s - f_c = -(z_r / z_s) (f_r - f_c),

the planets turn about their pins at f_p,rel = (z_r / z_p) (f_r - f_c) relative to the
carrier (absolute f_p = f_c + f_p,rel), and both meshes run at

    f_m = z_s |f_s - f_c| = z_r |f_r - f_c|.

Local-fault frequencies (one damaged tooth; McFadden & Smith 1985; Inalpolat & Kahraman
2009): a sun tooth meets the N planets N times per sun revolution relative to the carrier,
N |f_s - f_c| = N f_m / z_s; a ring tooth N |f_r - f_c| = N f_m / z_r (the planet-pass
frequency when the ring is fixed); one flank of a planet tooth meets the sun (or the ring)
once per planet revolution relative to the carrier, |f_p,rel| = f_m / z_p, both flanks
2 f_m / z_p.

Fixed sensor, fixed ring, N equally spaced identical planets (McFadden & Smith 1985): the
planet at ring angle phi has the ring-mesh phase z_r phi / 2 pi and the transfer path
w(phi - phi_sensor); the sum over planets depends on the carrier angle only through
phi = theta_c + 2 pi i / N, so it repeats every 2 pi / N of carrier rotation and the
spectrum holds only multiples of the planet-pass frequency N f_c. Around the m-th mesh
harmonic m f_m = m z_r f_c the components are at (m z_r + n) f_c with

    m z_r + n = 0 (mod N),

so m f_m itself is absent unless N divides m z_r, and the strongest component is the
allowed order n closest to 0 (the transfer-path window is widest at n = 0): the
asymmetric sidebands McFadden & Smith explained.

References
----------
.. [McFadden1985] P. D. McFadden, J. D. Smith, An explanation for the asymmetry of the
   modulation sidebands about the tooth meshing frequency in epicyclic gear vibration,
   Proc. IMechE C 199 (1985) 65-70.
.. [Inalpolat2009] M. Inalpolat, A. Kahraman, A theoretical and experimental
   investigation of modulation sidebands of planetary gear sets, J. Sound Vib. 323
   (2009) 677-696.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require

__all__ = ["PlanetaryFrequencies", "planet_pass_signal", "planetary_frequencies",
           "sideband_orders"]


@dataclass(frozen=True)
class PlanetaryFrequencies:
    """Shaft, mesh and fault frequencies of a planetary stage [Hz] (module docstring).

    Parameters
    ----------
    sun, carrier, ring
        Shaft frequencies, signed (the sense of the given input positive).
    planet
        Absolute planet frequency f_c + f_p,rel.
    planet_relative
        Planet frequency about its pin relative to the carrier.
    mesh
        Mesh frequency f_m of both meshes.
    planet_pass
        N |f_r - f_c|: planets passing a point of the ring.
    sun_fault, ring_fault
        N f_m / z_s and N f_m / z_r.
    planet_fault
        f_m / z_p: one flank of a planet tooth (2 f_m / z_p for a tooth damaged on both
        flanks).
    """

    sun: float
    carrier: float
    ring: float
    planet: float
    planet_relative: float
    mesh: float
    planet_pass: float
    sun_fault: float
    ring_fault: float
    planet_fault: float


def planetary_frequencies(z_sun: int, z_planet: int, z_ring: int, planets: int, *,
                          sun: float | None = None, carrier: float | None = None,
                          ring: float | None = 0.0) -> PlanetaryFrequencies:
    """Frequencies of a planetary stage from two of the three member speeds (Willis).

    Parameters
    ----------
    z_sun, z_planet, z_ring
        Tooth counts.
    planets
        Number of planets N.
    sun, carrier, ring
        Shaft frequencies [Hz]; exactly two must be given (default: ring fixed, 0).

    Returns
    -------
    PlanetaryFrequencies

    Examples
    --------
    Ring fixed, z_s = 21, z_r = 99, sun at 10 Hz: f_c = 10 x 21 / 120 = 1.75 Hz,
    f_m = 99 x 1.75 = 173.25 Hz, planet pass 3 x 1.75 = 5.25 Hz.

    >>> f = planetary_frequencies(21, 39, 99, 3, sun=10.0)
    >>> round(f.carrier, 6), round(f.mesh, 4), round(f.planet_pass, 4)
    (1.75, 173.25, 5.25)
    """
    for name, z in (("z_sun", z_sun), ("z_planet", z_planet), ("z_ring", z_ring),
                    ("planets", planets)):
        require(isinstance(z, int) and not isinstance(z, bool) and z >= 1, name, z,
                "must be an integer >= 1")
    given = {k: v for k, v in (("sun", sun), ("carrier", carrier), ("ring", ring))
             if v is not None}
    require(len(given) == 2, "speeds", sorted(given), "give exactly two of sun, carrier, "
            "ring")
    for k, v in given.items():
        require(math.isfinite(v), k, v, "must be a finite frequency in Hz")
    r = z_ring / z_sun
    if sun is None:
        fc, fr = carrier, ring
        fs = fc - r * (fr - fc)
    elif carrier is None:
        fs, fr = sun, ring
        fc = (fs + r * fr) / (1.0 + r)
    else:
        fs, fc = sun, carrier
        fr = fc - (fs - fc) / r
    rel = z_ring / z_planet * (fr - fc)
    fm = z_ring * abs(fr - fc)
    return PlanetaryFrequencies(
        sun=fs, carrier=fc, ring=fr, planet=fc + rel, planet_relative=rel, mesh=fm,
        planet_pass=planets * abs(fr - fc), sun_fault=planets * fm / z_sun,
        ring_fault=planets * fm / z_ring, planet_fault=fm / z_planet)


def sideband_orders(z_ring: int, planets: int, harmonic: int = 1, span: int = 10
                    ) -> tuple[np.ndarray, int]:
    """Sideband orders present around m f_m at a fixed sensor (McFadden & Smith 1985).

    Parameters
    ----------
    z_ring
        Ring teeth.
    planets
        Number of equally spaced planets N.
    harmonic
        Mesh harmonic m >= 1.
    span
        Orders n in [-span, span] (carrier orders, n f_c from m f_m).

    Returns
    -------
    orders, dominant
        The orders n with m z_r + n = 0 (mod N), and the one closest to 0 (the lower
        one on a tie).

    Examples
    --------
    z_r = 70, N = 3: 70 = 1 (mod 3), so around f_m only n = -1, 2, -4, ... are present
    and f_m - f_c dominates (f_m itself is absent).

    >>> orders, dominant = sideband_orders(70, 3, 1, 4)
    >>> orders.tolist(), dominant
    ([-4, -1, 2], -1)
    """
    require(isinstance(harmonic, int) and harmonic >= 1, "harmonic", harmonic,
            "must be an integer >= 1")
    n = np.arange(-span, span + 1)
    orders = n[(harmonic * z_ring + n) % planets == 0]
    dominant = int(orders[np.argmin(np.abs(orders) * 2 + (orders > 0))])
    return orders, dominant


def planet_pass_signal(t: np.ndarray, z_ring: int, planets: int, carrier: float, *,
                       angles: np.ndarray | None = None, harmonics: tuple[float, ...] = (1.0,),
                       window: float = 0.5, sensor: float = 0.0) -> np.ndarray:
    """Ring-mesh vibration of N planets seen by a sensor fixed on the ring [-].

    McFadden & Smith (1985): x(t) = sum_i w(theta_c + psi_i - phi_s)
    sum_m A_m cos(m z_r (theta_c + psi_i)), theta_c = 2 pi f_c t, with the transfer path
    w(phi) = cos^2(phi / 2)^p a smooth window centred on the sensor (p set by
    ``window``: the fraction of a revolution over which w > 1/2), ring fixed.

    Parameters
    ----------
    t
        Times [s].
    z_ring, planets
        Ring teeth and number of planets.
    carrier
        Carrier frequency f_c [Hz].
    angles
        Planet angles psi_i [rad]; default equally spaced.
    harmonics
        Amplitudes A_m of the mesh harmonics m = 1, 2, ...
    window
        Fraction of a revolution over which the transfer path is above half its peak.
    sensor
        Sensor angle phi_s [rad].

    Returns
    -------
    ndarray
        The signal at ``t``.
    """
    require(0.0 < window < 1.0, "window", window, "must be in (0, 1)")
    psi = (2 * np.pi * np.arange(planets) / planets if angles is None
           else np.asarray(angles, dtype=float))
    # cos^2(phi/2)^p > 1/2 for |phi| < pi window  ->  p = ln(1/2) / ln(cos^2(pi window / 2))
    p = math.log(0.5) / math.log(math.cos(math.pi * window / 2) ** 2)
    theta = 2 * np.pi * carrier * np.asarray(t, dtype=float)
    x = np.zeros_like(theta)
    for s in psi:
        phi = theta + s
        w = (0.5 * (1.0 + np.cos(phi - sensor))) ** p  # cos^2(phi / 2) >= 0
        mesh = sum(a * np.cos((m + 1) * z_ring * phi) for m, a in enumerate(harmonics))
        x += w * mesh
    return x
