"""Lumped-parameter model of a planetary stage after Lin & Parker (1999): modes and their types.

Each of carrier (c), ring (r), sun (s) and the N planets has three degrees of freedom in
the frame rotating with the carrier: two translations and a rotation expressed as the
arc length ``u = r theta`` (base radius for sun, ring and planets, planet-centre radius
for the carrier). Central members translate along the carrier axes x, y; planet n
translates radially (xi_n) and tangentially (eta_n). All coordinates in metres, masses
and ``I / r^2`` in kg, stiffnesses in N/m (torsional stiffnesses as ``k_u / r^2``).

Springs (Lin & Parker 1999, equations of motion): bearings of the central members to the housing
(k_j in x and y, k_ju in rotation), planet bearings on the carrier pins (k_p radially
and tangentially), and the mean mesh stiffnesses k_sp, k_rp along the lines of action
with the deformations

    delta_sn = -x_s sin psi_sn + y_s cos psi_sn - xi_n sin alpha_s - eta_n cos alpha_s + u_s + u_n
    delta_rn = -x_r sin psi_rn + y_r cos psi_rn + xi_n sin alpha_r - eta_n cos alpha_r + u_r - u_n
    delta_cn,radial     = x_c cos psi_n + y_c sin psi_n - xi_n
    delta_cn,tangential = -x_c sin psi_n + y_c cos psi_n + u_c - eta_n

with psi_sn = psi_n - alpha_s and psi_rn = psi_n + alpha_r. The stiffness matrix is
K = sum k b b^T over these springs (b the gradient of delta); it equals the matrices
K_b + K_m printed by Lin & Parker. The gyroscopic matrix and the centripetal softening
(terms in the carrier speed Omega_c) are left out, as in their free-vibration analysis.

References
----------
.. [LinParker1999] J. Lin, R. G. Parker, Analytical characterization of the unique
   properties of planetary gear free vibration, J. Vib. Acoust. 121 (1999) 316-321.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require

__all__ = ["CLUSTER_TOLERANCE", "MOTION_TOLERANCE", "LinParkerModel", "PlanetaryMode", "PlanetaryModes",
           "central_energy_shares"]

#: Relative gap below which neighbouring natural frequencies count as one repeated
#: frequency [-]: eigh resolves exact repeats to ~1e-12 relative; distinct modes of
#: gear systems differ by far more than 1e-6.
CLUSTER_TOLERANCE = 1e-6
#: Share of modal kinetic energy below which a member's motion counts as absent [-].
MOTION_TOLERANCE = 1e-8

_MEMBERS = ("carrier", "ring", "sun")


@dataclass(frozen=True)
class LinParkerModel:
    """Parameters of the Lin & Parker (1999) planetary model.

    Parameters
    ----------
    planets
        Number of planets N (>= 1).
    carrier_mass, ring_mass, sun_mass, planet_mass
        Masses m_c, m_r, m_s, m_p [kg].
    carrier_inertia, ring_inertia, sun_inertia, planet_inertia
        Moments of inertia divided by the squared radius, I_j / r_j^2 [kg] (r: base
        radius, carrier: planet-centre radius).
    carrier_bearing, ring_bearing, sun_bearing
        Translational bearing stiffnesses k_c, k_r, k_s (equal in x and y) [N/m].
    planet_bearing
        Planet bearing stiffness k_p (radial and tangential) [N/m].
    carrier_torsional, ring_torsional, sun_torsional
        Torsional stiffnesses k_cu, k_ru, k_su as k_u / r^2 [N/m] (0: free).
    sun_mesh, ring_mesh
        Mean mesh stiffnesses k_sp, k_rp [N/m].
    sun_pressure_angle, ring_pressure_angle
        Working pressure angles alpha_s, alpha_r [rad].
    planet_angles
        Planet angles psi_n [rad]; ``None``: 2 pi (n - 1)/N.

    Raises
    ------
    InputError
        If N < 1, a mass or inertia is not > 0, a stiffness is negative or not finite, a
        pressure angle is outside (0, 60) deg or the number of angles differs from N.

    References
    ----------
    Lin & Parker (1999): equations of motion and example system.

    Examples
    --------
    >>> m = LinParkerModel.lin_parker_example(planets=4)
    >>> m.stiffness_matrix().shape
    (21, 21)
    """

    planets: int
    carrier_mass: float
    carrier_inertia: float
    ring_mass: float
    ring_inertia: float
    sun_mass: float
    sun_inertia: float
    planet_mass: float
    planet_inertia: float
    carrier_bearing: float
    ring_bearing: float
    sun_bearing: float
    planet_bearing: float
    carrier_torsional: float
    ring_torsional: float
    sun_torsional: float
    sun_mesh: float
    ring_mesh: float
    sun_pressure_angle: float
    ring_pressure_angle: float
    planet_angles: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        require(isinstance(self.planets, int) and not isinstance(self.planets, bool)
                and self.planets >= 1, "model.planets", self.planets, "must be an integer >= 1")
        for name in ("carrier_mass", "carrier_inertia", "ring_mass", "ring_inertia", "sun_mass",
                     "sun_inertia", "planet_mass", "planet_inertia"):
            v = getattr(self, name)
            require(math.isfinite(v) and v > 0.0, f"model.{name}", v, "must be a finite number > 0 kg")
        for name in ("carrier_bearing", "ring_bearing", "sun_bearing", "planet_bearing",
                     "carrier_torsional", "ring_torsional", "sun_torsional", "sun_mesh", "ring_mesh"):
            v = getattr(self, name)
            require(math.isfinite(v) and v >= 0.0, f"model.{name}", v, "must be a finite number >= 0 N/m")
        for name in ("sun_pressure_angle", "ring_pressure_angle"):
            v = getattr(self, name)
            require(0.0 < v < math.radians(60.0), f"model.{name}", f"{math.degrees(v):.4g} deg",
                    "must be in (0, 60) deg")
        if self.planet_angles is not None:
            require(len(self.planet_angles) == self.planets, "model.planet_angles",
                    len(self.planet_angles), f"must give one angle per planet ({self.planets})")

    @classmethod
    def lin_parker_example(cls, planets: int = 4,
                           planet_angles: tuple[float, ...] | None = None) -> LinParkerModel:
        """The example system of Lin & Parker (1999) (parameter values as commonly reproduced).

        m_c 5.43, I_c/r_c^2 6.29, m_r 2.35, I_r/r_r^2 3.00, m_s 0.4, I_s/r_s^2 0.39,
        m_p 0.66, I_p/r_p^2 0.61 kg; k_c = k_r = k_s = k_p = 1e8 N/m; k_ru = 1e9 N/m,
        k_cu = k_su = 0; k_sp = k_rp = 5e8 N/m; alpha_s = alpha_r = 24.6 deg. These are the
        values as commonly reproduced (see docs/planetary.md on their provenance).

        Parameters
        ----------
        planets
            Number of planets N (the paper uses 4).
        planet_angles
            Planet angles [rad]; ``None``: equally spaced.

        Returns
        -------
        LinParkerModel
            The model.
        """
        a = math.radians(24.6)
        return cls(planets=planets, carrier_mass=5.43, carrier_inertia=6.29, ring_mass=2.35,
                   ring_inertia=3.00, sun_mass=0.4, sun_inertia=0.39, planet_mass=0.66,
                   planet_inertia=0.61, carrier_bearing=1e8, ring_bearing=1e8, sun_bearing=1e8,
                   planet_bearing=1e8, carrier_torsional=0.0, ring_torsional=1e9, sun_torsional=0.0,
                   sun_mesh=5e8, ring_mesh=5e8, sun_pressure_angle=a, ring_pressure_angle=a,
                   planet_angles=planet_angles)

    @property
    def angles(self) -> np.ndarray:
        """Planet angles psi_n [rad], shape (N,)."""
        if self.planet_angles is None:
            return 2.0 * math.pi * np.arange(self.planets) / self.planets
        return np.asarray(self.planet_angles, dtype=float)

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom, 3 (N + 3)."""
        return 3 * (self.planets + 3)

    @staticmethod
    def dof_index(member: str, planet: int = 0) -> slice:
        """Slice of the three coordinates of a member in q.

        Order of q: carrier (x, y, u), ring (x, y, u), sun (x, y, u), planet 1
        (xi, eta, u), ..., planet N.

        Parameters
        ----------
        member
            ``"carrier"``, ``"ring"``, ``"sun"`` or ``"planet"``.
        planet
            Planet index 0 ... N-1 (only for ``"planet"``).

        Returns
        -------
        slice
            The three indices.
        """
        i = _MEMBERS.index(member) if member in _MEMBERS else 3 + planet
        return slice(3 * i, 3 * i + 3)

    def mass_matrix(self) -> np.ndarray:
        """Diagonal mass matrix M [kg], shape (n_dof, n_dof) (Lin & Parker 1999).

        Returns
        -------
        ndarray
            diag(m_c, m_c, I_c/r_c^2, m_r, ..., m_p, m_p, I_p/r_p^2, ...).
        """
        d = [self.carrier_mass, self.carrier_mass, self.carrier_inertia,
             self.ring_mass, self.ring_mass, self.ring_inertia,
             self.sun_mass, self.sun_mass, self.sun_inertia]
        d += [self.planet_mass, self.planet_mass, self.planet_inertia] * self.planets
        return np.diag(np.asarray(d, dtype=float))

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """All springs as stiffness k_i and deformation gradient b_i (delta_i = b_i . q).

        Returns
        -------
        k : ndarray, shape (n_springs,)
            Stiffnesses [N/m].
        b : ndarray, shape (n_springs, n_dof)
            Gradients [-] (module docstring: delta_sn, delta_rn, planet bearings, then the
            central members' bearings).
        """
        n = self.n_dof
        ks: list[float] = []
        bs: list[np.ndarray] = []

        def add(k: float, entries: dict[int, float]) -> None:
            b = np.zeros(n)
            for i, v in entries.items():
                b[i] += v
            ks.append(k)
            bs.append(b)

        c, r, s = (self.dof_index(m).start for m in _MEMBERS)
        a_s, a_r = self.sun_pressure_angle, self.ring_pressure_angle
        for j, psi in enumerate(self.angles):
            p = self.dof_index("planet", j).start
            ps, pr = psi - a_s, psi + a_r
            add(self.sun_mesh, {s: -math.sin(ps), s + 1: math.cos(ps), s + 2: 1.0,
                                p: -math.sin(a_s), p + 1: -math.cos(a_s), p + 2: 1.0})
            add(self.ring_mesh, {r: -math.sin(pr), r + 1: math.cos(pr), r + 2: 1.0,
                                 p: math.sin(a_r), p + 1: -math.cos(a_r), p + 2: -1.0})
            add(self.planet_bearing, {c: math.cos(psi), c + 1: math.sin(psi), p: -1.0})
            add(self.planet_bearing, {c: -math.sin(psi), c + 1: math.cos(psi), c + 2: 1.0, p + 1: -1.0})
        for start, kb, ku in ((c, self.carrier_bearing, self.carrier_torsional),
                              (r, self.ring_bearing, self.ring_torsional),
                              (s, self.sun_bearing, self.sun_torsional)):
            add(kb, {start: 1.0})
            add(kb, {start + 1: 1.0})
            add(ku, {start + 2: 1.0})
        return np.asarray(ks), np.vstack(bs)

    def stiffness_matrix(self) -> np.ndarray:
        """Stiffness matrix K = K_b + K_m = sum_i k_i b_i b_i^T [N/m] (Lin & Parker 1999).

        Returns
        -------
        ndarray
            Symmetric, shape (n_dof, n_dof).
        """
        k, b = self.springs()
        return (b.T * k) @ b

    def modes(self) -> PlanetaryModes:
        """Natural frequencies and mode shapes, classified after Lin & Parker (1999).

        Solves K phi = omega^2 M phi (``scipy.linalg.eigh``), groups frequencies that agree
        within ``CLUSTER_TOLERANCE`` (relative) and names each group by its multiplicity
        and the motion of the central members (see :class:`PlanetaryMode`).

        Returns
        -------
        PlanetaryModes
            Frequencies, shapes and the classified groups.
        """
        m, k = self.mass_matrix(), self.stiffness_matrix()
        import scipy.linalg

        w2, phi = scipy.linalg.eigh(k, m)
        w2 = np.where(w2 < 0.0, 0.0, w2)
        f = np.sqrt(w2) / (2.0 * math.pi)
        scale = max(float(f.max()), 1.0)
        groups: list[list[int]] = [[0]]
        for i in range(1, len(f)):
            ref = f[groups[-1][0]]
            if abs(f[i] - ref) <= CLUSTER_TOLERANCE * max(ref, 1e-3 * scale):
                groups[-1].append(i)
            else:
                groups.append([i])
        out = []
        for g in groups:
            shapes = phi[:, g]
            out.append(PlanetaryMode(frequency=float(np.mean(f[g])), multiplicity=len(g),
                                     kind=_classify(shapes, m, self.planets), shapes=shapes))
        return PlanetaryModes(frequencies=f, shapes=phi, groups=tuple(out))


def central_energy_shares(shapes: np.ndarray, mass: np.ndarray) -> dict[str, float]:
    """Share of kinetic energy in central-member translations and rotations of a mode group.

    Parameters
    ----------
    shapes
        Mode shapes of one group, shape (n_dof, multiplicity).
    mass
        Mass matrix (diagonal), shape (n_dof, n_dof).

    Returns
    -------
    dict
        ``translation`` and ``rotation``: sum over the group of m_i phi_i^2 over the first
        nine coordinates (carrier, ring, sun) divided by the total phi^T M phi [-].
    """
    md = np.diag(mass)
    e = (shapes**2) * md[:, None]
    total = float(e.sum())
    trans = float(sum(e[3 * j + i].sum() for j in range(3) for i in (0, 1)))
    rot = float(sum(e[3 * j + 2].sum() for j in range(3)))
    return {"translation": trans / total, "rotation": rot / total}


def _classify(shapes: np.ndarray, mass: np.ndarray, planets: int) -> str:
    sh = central_energy_shares(shapes, mass)
    mult = shapes.shape[1]
    if sh["translation"] < MOTION_TOLERANCE and sh["rotation"] < MOTION_TOLERANCE:
        return "planet"
    if sh["translation"] < MOTION_TOLERANCE and mult == 1:
        return "rotational"
    if sh["rotation"] < MOTION_TOLERANCE and mult == 2:
        return "translational"
    return "mixed"


@dataclass(frozen=True)
class PlanetaryMode:
    """One natural frequency (possibly repeated) and its mode type.

    Parameters
    ----------
    frequency
        Natural frequency [Hz] (mean over the group).
    multiplicity
        Number of modes at this frequency.
    kind
        ``"rotational"`` (multiplicity 1, central members only rotate),
        ``"translational"`` (multiplicity 2, central members only translate),
        ``"planet"`` (central members stationary; multiplicity N - 3 for equally spaced
        planets) or ``"mixed"`` (none of these, e.g. unequally spaced planets).
    shapes
        Mass-normalised shapes of the group, shape (n_dof, multiplicity).
    """

    frequency: float
    multiplicity: int
    kind: str
    shapes: np.ndarray


@dataclass(frozen=True)
class PlanetaryModes:
    """Result of :meth:`LinParkerModel.modes`.

    Parameters
    ----------
    frequencies
        All natural frequencies [Hz], ascending, shape (n_dof,).
    shapes
        Mass-normalised shapes, shape (n_dof, n_dof) (phi^T M phi = I).
    groups
        The frequencies grouped by multiplicity and classified (:class:`PlanetaryMode`).
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    groups: tuple[PlanetaryMode, ...]

    def of_kind(self, kind: str) -> list[PlanetaryMode]:
        """The groups of one type.

        Parameters
        ----------
        kind
            ``"rotational"``, ``"translational"``, ``"planet"`` or ``"mixed"``.

        Returns
        -------
        list of PlanetaryMode
            In ascending frequency.
        """
        return [g for g in self.groups if g.kind == kind]
