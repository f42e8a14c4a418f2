"""Crack-face contact and stress intensity of a closed (compressed) crack.

The crack faces of a :class:`gearsim.fracture.mesh.CrackedMesh` are coupled by the
frictionless unilateral penalty contact of :meth:`gearsim.fem.solve.ElasticModel.contact_solve`
(active set, normal gap only) on the node pairs of the two faces: the duplicated
vertices and, for P2, the midpoints of the face edges, with Simpson length weights
(1/6, 4/6, 1/6 of each edge). The contact normal is that of a straight crack, so the
crack must be one segment (the initial crack; a grown, kinked path is not supported).

Stress intensity with closed faces: the faces carry a normal pressure p. In the
interaction integral this adds the face term -int_faces t_i du^a_i/dx1 q ds. For the
mode-II auxiliary field the term vanishes: on the faces (theta = +-pi) the auxiliary
u^a_2 is zero all along them, so du^a_2/dx1 = 0, and a frictionless contact traction has
only the normal component t_2. K_II is therefore given exactly by the plain domain
integral (:func:`gearsim.fracture.sif.interaction_integral`). For mode I the term does
not vanish; instead, when the faces are closed at the tip, the opening mode is
suppressed and K_I = 0 (the crack-tip field of a closed frictionless crack is pure
mode II). When the tip is open but faces inside the ring are closed, K_I from the plain
integral misses the face term: the result says so (``k1_exact = False``).

Check (tests/fracture/test_contact.py): inclined centre crack under remote uniaxial
*compression* sigma < 0: the faces close, the normal stress sigma cos^2(beta) is carried
across them, the shear is not (frictionless), so K_I = 0 and
K_II = sigma sqrt(pi a) sin(beta) cos(beta) (e.g. Anderson 2005, sec. 2.7, with the
normal part removed).

References
----------
.. [Wriggers2006] P. Wriggers, Computational Contact Mechanics, 2nd ed., Springer 2006
   (penalty method, active set).
.. [Anderson2005] T. L. Anderson, Fracture Mechanics, 3rd ed., CRC 2005, sec. 2.7.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.fem.solve import ElasticModel, face_dof_pairs
from gearsim.fracture.mesh import CrackedMesh
from gearsim.fracture.sif import StressIntensity, effective_modulus, interaction_integral

__all__ = ["ContactIntensity", "closed_crack_intensity", "face_pairs"]


@dataclass(frozen=True)
class ContactIntensity:
    """Stress intensity at a crack tip with crack-face contact.

    Parameters
    ----------
    sif
        K_I (0 when the tip is closed), K_II [Pa sqrt(m)].
    tip_closed
        The face pair next to the tip is in contact.
    closed_fraction
        Share of the crack length in contact [-].
    k1_exact
        False when the tip is open but faces inside the integration ring are closed
        (K_I then lacks the face-pressure term).
    iterations
        Active-set iterations.
    u
        Displacement solution [m].
    """

    sif: StressIntensity
    tip_closed: bool
    closed_fraction: float
    k1_exact: bool
    iterations: int
    u: np.ndarray


def face_pairs(model: ElasticModel, cm: CrackedMesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Dof pairs of the two crack faces and their length weights.

    Parameters
    ----------
    model
        Elastic model on ``cm.p``, ``cm.t`` (order 1 or 2).
    cm
        The cracked mesh.

    Returns
    -------
    pairs : ndarray of int, shape (k, 2, 2)
        [pair, (right face, left face), (x, y) dof].
    weights : ndarray, shape (k,)
        Face length carried by each pair [m] (vertex 1/6 and midpoint 4/6 of each edge
        for P2, 1/2 per vertex for P1).
    positions : ndarray, shape (k, 2)
        Location of each pair [m].
    """
    dup = {int(a): int(b) for a, b in cm.pairs.T}
    return face_dof_pairs(model, cm.p, cm.pairs, cm.edges, dup)


def closed_crack_intensity(model: ElasticModel, cm: CrackedMesh, load: np.ndarray,
                           fixed: np.ndarray, *, r_out: float, end: int = 1
                           ) -> ContactIntensity:
    """Solve with frictionless crack-face contact and take K at a tip.

    Parameters
    ----------
    model
        Elastic model on the cracked mesh.
    cm
        The cracked mesh; its crack must be a single straight segment.
    load
        Load vector [N].
    fixed
        Dirichlet dofs (zero).
    r_out
        Outer radius of the interaction-integral ring [m].
    end
        Which tip: 1 the end of the path, 0 its start (internal cracks).

    Returns
    -------
    ContactIntensity

    Raises
    ------
    InputError
        A kinked crack, or ``end`` not a tip.
    """
    pts = cm.crack.array
    require(pts.shape[0] == 2, "crack.points", pts.shape[0],
            "crack-face contact needs a straight crack (2 points)")
    require(end in cm.tip_nodes, "end", end, f"must be a tip end, one of {sorted(cm.tip_nodes)}")
    d = (pts[1] - pts[0]) / math.dist(pts[0], pts[1])
    normal = np.array([-d[1], d[0]])  # right face (minus) -> left face (plus)
    pairs, weights, positions = face_pairs(model, cm)
    u, active, its = model.contact_solve(load, fixed, pairs, normal, weights, h=cm.h_tip)
    tip, direction = cm.crack.tip_frame(end)
    sif = interaction_integral(model, u, tip, direction, r_out=r_out)
    dist = np.hypot(*(positions - tip).T)
    tip_closed = bool(active[int(np.argmin(dist))])
    in_ring = bool(np.any(active & (dist < r_out)))
    closed = float(np.sum(weights[active]) / np.sum(weights)) if weights.size else 0.0
    if tip_closed:
        ep = effective_modulus(model.youngs_modulus, model.poisson_ratio, model.plane)
        sif = StressIntensity(k1=0.0, k2=sif.k2, j=sif.k2**2 / ep, r_in=sif.r_in,
                              r_out=sif.r_out)
    return ContactIntensity(sif=sif, tip_closed=tip_closed, closed_fraction=closed,
                            k1_exact=tip_closed or not in_ring, iterations=its, u=u)
