"""Planar layout of a gear chain: centres, lines of action and the mesh phases.

Conventions
-----------
* Gear 0 (input) turns counter-clockwise (sense s_0 = +1) and sits at the origin; gear
  j turns with the sense s_j = (-1)^j (external gears). Its rotation coordinate is
  positive in its own sense of rotation.
* The centre line of mesh i points from gear i to gear i+1 at the global angle phi_i;
  phi_0 = 0. At an idler j the *idler angle* gamma_j is the angle, measured at the idler
  in its sense of rotation, from the centre line towards the driving gear j-1 to the
  centre line towards the driven gear j+1 (180 deg: the three centres on a line). Hence
  ``phi_j = phi_{j-1} + pi + s_j gamma_j``.
* With e = (cos phi_i, sin phi_i) and e_perp = (-sin phi_i, cos phi_i), the unit vector
  of the transverse line of action of mesh i, pointing in the direction of the force on
  the driven gear (and from the driver's base tangent point T1 to the driven gear's T2),
  is ``n_i = s_i cos(alpha_wt) e_perp + sin(alpha_wt) e`` (alpha_wt: working transverse
  pressure angle). T1 lies on the driver's base circle at the own-sense angle
  ``s_i phi_i - alpha_wt``, T2 on the driven base circle at ``s_{i+1} (phi_i + pi) + alpha_wt``.

Mesh phase
----------
The stiffness tables count mesh cycles c from the instant at which tooth 0 of the driver
enters contact (roll length l = l_A from T1, at the face z = 0); tooth t of the driver
is then at ``l = l_A + (c - t) p_bt``. On the idler j the loaded flank in mesh j-1 is the
rear flank (base point behind the tooth centre line by the base half-thickness angle
psi_b) and in mesh j the front flank (ahead by psi_b). Writing the angular position of
the centre line of one physical idler tooth from both meshes and equating gives the
offset between the cycle coordinates of mesh j and mesh j-1:

    Delta_j = z_j / (2 pi) (2 psi_b + alpha_wt,j-1 + alpha_wt,j - gamma_j)
              - (L_{j-1} - l_A,j-1) / p_bt - l_A,j / p_bt            [mesh cycles]

i.e. ``z_j gamma_j / (2 pi)`` (the number of base pitches between the two centre lines,
whose fractional part is the classical idler mesh phase) plus the contact-position
offsets of the two meshes (pressure angles, the roll lengths to the start of contact of
each mesh, and the tooth thickness between the two flanks). ``c_j = c_{j-1} + Delta_j``;
only ``Delta_j mod 1`` matters for healthy gears, ``Delta_j mod z_j`` for a cracked idler
(which revolution the cracked tooth enters the second mesh).

Where the power branches at a gear (one gear driving meshes i and k, front flank in both,
sense s), the contact of its tooth whose front-flank base point is at the own-sense angle
psi_f lies r_b (psi_f - s phi + alpha_wt) from T1 of each mesh, so

    Delta = c_k - c_i = z / (2 pi) (alpha_wt,k - alpha_wt,i - s (phi_k - phi_i))
            - (l_A,k - l_A,i) / p_bt                                          [mesh cycles]

(the same bookkeeping as the idler's, without the tooth thickness: both meshes load one
flank; for a sun driving planets this is Parker & Lin's sun-planet phasing).

References
----------
.. [Kahraman1994] A. Kahraman, Dynamic analysis of a multi-mesh helical gear train,
   J. Mech. Des. 116 (1994) 706-712 (idler train, mesh phasing by the layout).
.. [Parker2004] R. G. Parker, J. Lin, Mesh phasing relationships in planetary and
   epicyclic gears, J. Mech. Des. 126 (2004) 365-370 (phase = fractional part of
   z times the angle between meshes over 2 pi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.system import GearTrain

__all__ = ["Layout", "idlers", "layout"]


@dataclass(frozen=True)
class Layout:
    """Planar layout of a gearbox (conventions in the module docstring).

    Parameters
    ----------
    centres : ndarray, shape (n_shafts, 2)
        Shaft centres in the global axes [m]; the input shaft at the origin.
    senses : ndarray, shape (n_shafts,)
        Sense of rotation s_j of each shaft (+1: counter-clockwise) [-].
    line_angle : ndarray, shape (n_meshes,)
        Global angle phi_i of centre line i, from the driver's shaft to the driven
        gear's [rad]; phi_0 = 0.
    normal : ndarray, shape (n_meshes, 2)
        Unit vector n_i of the transverse line of action of mesh i, pointing along the
        force on the driven gear [-].
    phase : ndarray, shape (n_meshes,)
        Offset of the cycle coordinate of each mesh [mesh cycles]: through an idler the
        cumulative Delta_j of the module docstring, and from a gear's first mesh to the
        other meshes it drives; 0 for the first mesh of a gear not driven in an earlier
        mesh (tooth 0 of every gear of a shaft enters contact at t = 0).
    """

    centres: np.ndarray
    senses: np.ndarray
    line_angle: np.ndarray
    normal: np.ndarray
    phase: np.ndarray


def idlers(train: GearTrain) -> list[str]:
    """Names of the idlers: gears alone on their shaft, driven in one mesh and driving
    the next (the idler angle places the first mesh they drive).

    Parameters
    ----------
    train : GearTrain
        The gearbox.

    Returns
    -------
    list of str
        In power-flow order (the order of ``dynamics.idler_angle``).
    """
    fl = train.flow
    return [g.name for g in train.gears if len(fl.shafts[fl.shaft_of[g.name]].gears) == 1
            and {role for _, role in fl.meshes_of(g.name)} == {1, 2}]


def _written(train: GearTrain, mesh: int) -> str:
    """``meshes[k]`` of the mesh ``mesh`` (power-flow order) as the file lists it."""
    pair = set(train.flow.meshes[mesh])
    return next(f"meshes[{k}]" for k, m in enumerate(train.meshes) if set(m.gears) == pair)


def _apart(ga, gb, d_vec: np.ndarray, parameter: str, value: object) -> None:
    """Refuse two gears of one plane, not in mesh, whose tip circles overlap."""
    d = float(np.hypot(*d_vec))
    lim = ga.tip_radius + gb.tip_radius
    if d <= lim:
        raise InputError(parameter, value, f"puts {ga.name} and {gb.name} {d:.6g} m apart, "
                         f"closer than their tip radii sum {lim:.6g} m")


def layout(train: GearTrain, idler_angles: tuple[float, ...]) -> Layout:
    """Centres, line-of-action vectors and mesh phases of ``train``.

    Centre line i has the global angle given in ``[[meshes]]``, or through an idler
    ``phi_i = phi_{i-1} + pi + s_i gamma_i``, or else the angle of the line that brought
    power to the driver's shaft (0 on the input shaft: the shafts in a row); the line of
    action ``n_i = s_i cos(alpha_wt) e_perp + sin(alpha_wt) e`` (s_i the driver's
    sense) and, through an idler, the mesh phase ``c_i = c_{i-1} + Delta_i`` with
    Delta_i of the module docstring (derived there; the idler phase is the fractional
    part of z gamma / (2 pi) as in Parker & Lin 2004, applied to an idler train as in
    Kahraman 1994).

    Parameters
    ----------
    train : GearTrain
        The gearbox (its power flow orients the meshes).
    idler_angles : tuple of float
        Idler angle gamma_j for each idler (:func:`idlers`) [rad] (see the module
        docstring); pi puts the three centres on a line. Empty without idlers.

    Returns
    -------
    Layout
        Centres [m], senses of rotation, centre-line angles [rad], line-of-action unit
        vectors and mesh phases [mesh cycles].

    Raises
    ------
    InputError
        (parameter ``dynamics.idler_angle``) if two gears of a chain (one plane) that are
        not in mesh would overlap (centre distance <= sum of their tip radii).

    References
    ----------
    Kahraman (1994); Parker & Lin (2004) (module docstring).

    Examples
    --------
    Table-1 idler train with the centres on a line (gamma = 180 deg): the idler's second
    mesh starts -28.958 cycles after the first (fractional part 0.042; checked by hand
    with the involute formulas for psi_b, l_A and p_bt):

    >>> import math
    >>> import gearsim as gs
    >>> from gearsim.dynamics.layout import layout
    >>> tr = gs.example("idler-table1").train
    >>> lay = layout(tr, (math.pi,))
    >>> lay.centres[:, 0].round(6).tolist()  # a_I = 301.733 mm, a_I + a_II = 868.253 mm
    [0.0, 0.301733, 0.868253]
    >>> lay.normal.round(4).tolist()  # (sin, +-cos) of alpha_wt = 20.483 deg
    [[0.3499, 0.9368], [0.3499, -0.9368]]
    >>> round(float(lay.phase[1]), 3)
    -28.958
    """
    fl, pairs = train.flow, train.pairs
    ns, nm = len(fl.shafts), len(pairs)
    senses = np.array(fl.sense, dtype=float)
    phi = np.zeros(nm)
    centres = np.zeros((ns, 2))
    normal = np.zeros((nm, 2))
    phase = np.zeros(nm)
    gamma_of = dict(zip(idlers(train), idler_angles, strict=False))
    into: dict[int, int] = {}  # shaft -> the mesh that drives it
    drove: dict[str, int] = {}  # gear -> the first mesh it drives
    for i, pair in enumerate(pairs):
        a, b = fl.shaft_of[pair.driver.name], fl.shaft_of[pair.driven.name]
        prev = into.get(a)
        sibling = drove.setdefault(pair.driver.name, i)
        idler = pair.driver.name in gamma_of and sibling == i
        if sibling != i and fl.angles[i] is None:
            raise InputError(f"{_written(train, i)}.angle", "missing",
                             f"{pair.driver.name} drives a second mesh: give the angle of "
                             "its centre line, or the driven gears would sit on one another")
        if fl.angles[i] is not None:
            phi[i] = fl.angles[i]
        elif prev is not None:
            phi[i] = phi[prev] + (math.pi + senses[a] * gamma_of[pair.driver.name]
                                  if idler else 0.0)
        e = np.array([math.cos(phi[i]), math.sin(phi[i])])
        ep = np.array([-e[1], e[0]])
        aw = pair.working_pressure_angle
        normal[i] = senses[a] * math.cos(aw) * ep + math.sin(aw) * e
        centres[b] = centres[a] + pair.centre_distance * e
        if idler:
            pp, g = pairs[prev], pair.driver
            gamma = gamma_of[g.name] if fl.angles[i] is None else \
                senses[a] * (phi[i] - phi[prev] - math.pi)
            delta = g.teeth / (2 * math.pi) * (
                2 * g.base_half_thickness_angle + pp.working_pressure_angle + aw - gamma)
            delta -= (pp.line_length - pp.start_of_contact) / pp.base_pitch
            delta -= pair.start_of_contact / pair.base_pitch
            phase[i] = phase[prev] + delta
        elif sibling != i:
            # a second mesh of the same driver, front flank as in the first (see the
            # module docstring): c = z / (2 pi) (psi_f - s phi + alpha_wt) - l_A / p_bt
            # in each, so the offset follows from the two centre lines
            ps, g = pairs[sibling], pair.driver
            phase[i] = phase[sibling] + g.teeth / (2 * math.pi) * (
                -senses[a] * (phi[i] - phi[sibling]) + aw - ps.working_pressure_angle) \
                - (pair.start_of_contact - ps.start_of_contact) / pair.base_pitch
        into[b] = i
    for i, (drv, dvn) in enumerate(fl.meshes):  # two gears driven by one gear: one plane
        for j in range(i):
            if fl.meshes[j][0] == drv:
                _apart(train.gear(dvn), train.gear(fl.meshes[j][1]),
                       centres[fl.shaft_of[dvn]] - centres[fl.shaft_of[fl.meshes[j][1]]],
                       f"{_written(train, i)}.angle", f"{math.degrees(phi[i]):.6g} deg")
    single = list(train.gears) if train.is_chain else []  # a chain lies in one plane
    meshed = set(fl.meshes)
    for j, ga in enumerate(single):
        for gb in single[j + 1:]:
            if (ga.name, gb.name) in meshed or (gb.name, ga.name) in meshed:
                continue
            _apart(ga, gb, centres[fl.shaft_of[gb.name]] - centres[fl.shaft_of[ga.name]],
                   "dynamics.idler_angle", [math.degrees(g) for g in idler_angles])
    return Layout(centres=centres, senses=senses, line_angle=phi, normal=normal, phase=phase)
