"""Mesh stiffness estimate of ISO 6336-1:2019, method B (section 9).

Single stiffness of a tooth pair (per unit face width, transverse plane):

    q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2
         + C8 x1^2 + C9 x2^2                                   [mm um / N]
    c'_th = 1/q',  c' = c'_th C_M C_R C_B cos(beta),
    c_gamma_alpha = c' (0.75 eps_alpha + 0.25)                 [N / (mm um)]

with z_n = z / (cos^2(beta_b) cos(beta)), C_M = 0.8 (solid discs), C_R = 1 (solid
gear blanks), C_B = 0.975 for the standard basic rack (h_fP = 1.25 m_n, alpha_n = 20
deg) [ISO 6336-1:2019, eqs. 96-103]. The steel reference: E = 206 000 N/mm^2. Below a
line load w = F_t K_A / b of 100 N/mm (F_t the nominal tangential load on the reference
circle, K_A = 1 for the model's static load) ISO 6336-1 lowers the single stiffness by
the factor (w / 100 N/mm)^0.25 (:func:`low_load_factor`): light loads close less of the
flank gap, as measured.
Values and the check numbers: docs/references.md, "ISO 6336-1 mesh stiffness".

References
----------
.. [ISO6336-1] ISO 6336-1:2019, Calculation of load capacity of spur and helical gears -
   Part 1: Basic principles, introduction and general influence factors, clause 9.
"""

from __future__ import annotations

import math

from gearsim.geometry.pair import GearPair

__all__ = ["ISO_C", "internal_mean_mesh_stiffness", "low_load_factor", "mean_mesh_stiffness",
           "single_stiffness"]

#: The line load F_t K_A / b above which ISO 6336-1's single stiffness applies unchanged
#: [N/m] (100 N/mm).
FULL_LOAD = 1e5


def low_load_factor(line_load: float | None) -> float:
    """ISO 6336-1's factor on c' for a line load below 100 N/mm: (w / 100 N/mm)^0.25.

    Parameters
    ----------
    line_load : float or None
        w = F_t K_A / b [N/m], F_t the nominal tangential load on the reference circle;
        None: the load is not known (factor 1, the value at 100 N/mm and above).

    Returns
    -------
    float
        The factor, 1 at and above 100 N/mm [-].

    References
    ----------
    ISO 6336-1:2019, clause 9 (single stiffness c', method B, F_t K_A / b < 100 N/mm).

    Examples
    --------
    F_t = 625 N on a 15 mm face: 41.7 N/mm, factor (0.4167)^0.25 = 0.8034:

    >>> round(low_load_factor(625.0 / 0.015), 4)
    0.8034
    """
    return 1.0 if line_load is None else min(1.0, (line_load / FULL_LOAD) ** 0.25)

ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def single_stiffness(pair: GearPair, *, c_m: float = 0.8, c_r: float = 1.0,
                     c_b: float = 0.975) -> float:
    """Single stiffness c' of ISO 6336-1 method B.

    Parameters
    ----------
    pair
        The gear pair (z, x, beta, beta_b are used).
    c_m
        Correction factor C_M (0.8 for solid discs).
    c_r
        Gear blank factor C_R (1 for solid blanks).
    c_b
        Basic rack factor C_B (0.975 for h_fP = 1.25 m_n, alpha_n = 20 deg).

    Returns
    -------
    float
        c' [N/(mm um) = 1e9 N/m^2].

    References
    ----------
    ISO 6336-1:2019, clause 9.

    Examples
    --------
    Table-1 mesh I: z_n = 41.898 / 63.384, q' = 0.04723 + 0.15551/41.898 +
    0.25791/63.384 = 0.055011, c'_th = 18.178, c' = 18.178 x 0.8 x 0.975 x cos 13 deg
    = 13.816:

    >>> import math
    >>> from gearsim.geometry.gear import Gear
    >>> from gearsim.geometry.pair import GearPair
    >>> kw = dict(normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15)
    >>> pair = GearPair(Gear(teeth=39, **kw), Gear(teeth=59, **kw))
    >>> round(single_stiffness(pair), 3)
    13.816
    """
    g1, g2 = pair.driver, pair.driven
    beta = abs(g1.helix_angle)
    bb = g1.base_helix_angle
    zn1 = g1.teeth / (math.cos(bb) ** 2 * math.cos(beta))
    zn2 = g2.teeth / (math.cos(bb) ** 2 * math.cos(beta))
    x1, x2 = g1.profile_shift, g2.profile_shift
    c = ISO_C
    q = (c[0] + c[1] / zn1 + c[2] / zn2 + c[3] * x1 + c[4] * x1 / zn1 + c[5] * x2
         + c[6] * x2 / zn2 + c[7] * x1**2 + c[8] * x2**2)
    return (1.0 / q) * c_m * c_r * c_b * math.cos(beta)


def mean_mesh_stiffness(pair: GearPair, line_load: float | None = None) -> float:
    """ISO 6336-1 mesh stiffness c_gamma_alpha times the face width [N/m].

    The material correction E/E_steel of ISO 6336-1 (9.3) is applied for equal
    materials other than steel, and :func:`low_load_factor` of ``line_load``.

    Parameters
    ----------
    pair
        The gear pair.
    line_load : float, optional
        F_t K_A / b [N/m]; None: 100 N/mm or more (no low-load factor).

    Returns
    -------
    float
        c_gamma_alpha b = c' (0.75 eps_alpha + 0.25) b [N/m].

    References
    ----------
    ISO 6336-1:2019, clause 9.

    Examples
    --------
    Table-1 mesh I: 13.816 x (0.75 x 1.6806 + 0.25) = 20.868 N/(mm um), times
    b = 150 mm: 3.130e9 N/m.

    >>> import math
    >>> from gearsim.geometry.gear import Gear
    >>> from gearsim.geometry.pair import GearPair
    >>> kw = dict(normal_module=6e-3, helix_angle=math.radians(13.0), face_width=0.15)
    >>> pair = GearPair(Gear(teeth=39, **kw), Gear(teeth=59, **kw))
    >>> round(mean_mesh_stiffness(pair) / 1e9, 3)
    3.13
    """
    c1 = (single_stiffness(pair) * low_load_factor(line_load)
          * (0.75 * pair.transverse_contact_ratio + 0.25))
    e_ratio = pair.driver.material.youngs_modulus / 206e9
    return c1 * 1e9 * pair.face_width * e_ratio


def internal_mean_mesh_stiffness(stage, line_load: float | None = None) -> float:
    """ISO 6336-1 mesh stiffness c_gamma_alpha b of the ring-planet (internal) mesh [N/m].

    ISO 6336-1:2019, 9.3: for internal gears the virtual number of teeth of the ring is
    taken as infinite, z_n2 = inf, so C3/z_n2 and C7 x2/z_n2 vanish; the shift terms
    C6 x2 + C9 x2^2 keep the ring's shift (the built-in stages are unshifted). C_M = 0.8,
    C_R = 1, C_B = 0.975 as for the external meshes, c' = c'_th C_M C_R C_B cos(beta),
    c_gamma_alpha = c' (0.75 eps_alpha + 0.25) with the ring-planet contact ratio.

    Parameters
    ----------
    stage : gearsim.geometry.planetary.PlanetaryStage
        The stage (planet z, x; ring shift; helix angle; face width; material).
    line_load : float, optional
        F_t K_A / b [N/m] (:func:`low_load_factor`); None: 100 N/mm or more.

    Returns
    -------
    float
        c_gamma_alpha b [N/m].

    References
    ----------
    ISO 6336-1:2019, clause 9 (eqs. 96-103 and the note on internal gears).

    Examples
    --------
    z_p 24 spur, unshifted: q' = 0.04723 + 0.15551/24 = 0.053710, c'_th = 18.618,
    c' = 18.618 x 0.8 x 0.975 = 14.522 N/(mm um); eps_alpha 1.9163:
    c_gamma_alpha = 14.522 x (0.75 x 1.9163 + 0.25) = 24.502; b = 20 mm: 4.900e8 N/m.

    >>> from gearsim.geometry.planetary import PlanetaryStage
    >>> st = PlanetaryStage(30, 24, 78, 2e-3, planets=4, face_width=0.02)
    >>> round(internal_mean_mesh_stiffness(st) / 1e8, 3)
    4.901
    """
    p = stage.planet
    beta = abs(p.helix_angle)
    zn1 = p.teeth / (math.cos(p.base_helix_angle) ** 2 * math.cos(beta))
    x1, x2 = p.profile_shift, stage.ring_shift
    c = ISO_C
    q = (c[0] + c[1] / zn1 + c[3] * x1 + c[4] * x1 / zn1 + c[5] * x2 + c[7] * x1**2
         + c[8] * x2**2)
    c_single = (1.0 / q) * 0.8 * 1.0 * 0.975 * math.cos(beta) * low_load_factor(line_load)
    c_ga = c_single * (0.75 * stage.ring_planet_contact_ratio + 0.25)
    e_ratio = stage.material.youngs_modulus / 206e9
    return c_ga * 1e9 * stage.face_width * e_ratio
