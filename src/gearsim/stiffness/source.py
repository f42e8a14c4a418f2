"""Tooth compliance behind one interface: the potential-energy model and its protocol.

:func:`gearsim.stiffness.mesh.mesh_stiffness` asks a :class:`ToothCompliance` for the
compliance of each tooth at the contact points of its grid; it does not know which model
answers. :class:`PotentialEnergyCompliance` (this module) integrates the bending, shear,
axial and fillet-foundation energies over the tooth (docs/stiffness.md); the
finite-element model implements the same protocol in :mod:`gearsim.fem.tables`. Which one
a train uses is chosen one layer up (:func:`gearsim.system.tooth_compliance`), so
neither ``stiffness`` nor ``fem`` imports the other's implementation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from gearsim.geometry.gear import Gear
from gearsim.stiffness._kernels import C_SIZE
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.tooth import ToothModel

__all__ = ["PotentialEnergyCompliance", "ToothCompliance", "ToothCrack"]


@dataclass(frozen=True)
class ToothCrack:
    """A crack as seen by one mesh: which gear (1 driver, 2 driven), tooth and side.

    Parameters
    ----------
    gear : {1, 2}
        The cracked gear of the pair: 1 driver, 2 driven.
    crack : Crack
        The crack.
    side : {1, -1}
        +1 when the cracked flank is the flank this mesh loads, -1 otherwise.
    """

    gear: int
    crack: Crack
    side: int




@runtime_checkable
class ToothCompliance(Protocol):
    """Compliance of one tooth at contact points: the interface of a stiffness source.

    A structural protocol: any object with a ``name`` and this ``compliance`` method is a
    stiffness source. Implementations: :class:`PotentialEnergyCompliance`,
    :class:`gearsim.fem.tables.FiniteElementCompliance`.
    """

    #: Short name written into results (``"pe"``, ``"fe"``).
    name: str

    def compliance(self, gear: Gear, radii: np.ndarray, crack: ToothCrack | None,
                   zfrac: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """Compliances of the tooth of ``gear`` loaded at ``radii``.

        Parameters
        ----------
        gear : Gear
            The gear whose tooth is loaded.
        radii : ndarray, shape (..., ns)
            Contact radius [m] at each grid point and face-width slice; 0 where the
            point is not in contact.
        crack : ToothCrack or None
            The crack of this tooth as seen by the mesh, or None (healthy tooth).
        zfrac : ndarray, shape (ns,)
            Axial position of each slice centre as a fraction of the face width [-].
        settings : StiffnessSettings
            Closure, plane, quadrature options.

        Returns
        -------
        ndarray, shape (..., ns, 4)
            Bending, shear, axial and foundation compliance times unit face width
            [m/N * m] (0 where not in contact).
        """
        ...


@dataclass(frozen=True)
class PotentialEnergyCompliance:
    """The potential-energy tooth (seed eqs. 3-7, Sainsot foundation; docs/stiffness.md).

    Parameters
    ----------
    name : str
        ``"pe"`` (written into results).

    Notes
    -----
    The tooth section integrals run in the compiled kernel of
    :meth:`gearsim.stiffness.tooth.ToothModel.compliance`; cracked sections follow the
    limiting-line model and the closure option (:mod:`gearsim.stiffness.crack`).
    """

    name: str = "pe"

    def compliance(self, gear: Gear, radii: np.ndarray, crack: ToothCrack | None,
                   zfrac: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """Compliances of the tooth of ``gear`` loaded at ``radii``.

        Parameters
        ----------
        gear, radii, crack, zfrac, settings
            As :meth:`ToothCompliance.compliance` (``zfrac`` gives the local crack depth
            of each slice; ``settings`` the closure, plane and quadrature).

        Returns
        -------
        ndarray, shape (..., ns, 4)
            Bending, shear, axial, foundation compliance times unit width [m/N * m].
        """
        tm = ToothModel(gear, plane=settings.plane, gauss_points=settings.gauss_points,
                        closure=settings.closure)
        shape = radii.shape
        ns = shape[-1]
        records = None
        if crack is not None:  # one record per slice -> per grid point
            depths = crack.crack.depth_at(zfrac) if ns > 1 else np.array([crack.crack.depth])
            recs = np.stack([crack_record(tm.profile, crack.crack, float(q), crack.side)
                             for q in depths])
            records = np.broadcast_to(recs.reshape((1,) * (len(shape) - 1) + recs.shape),
                                      shape + (C_SIZE,)).reshape(-1, C_SIZE)
        c = tm.compliance(radii.ravel(), records)
        return np.nan_to_num(c, nan=0.0).reshape(shape + (4,))
