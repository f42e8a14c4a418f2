"""The typed model of a gearbox: the train and the settings of everything done with it.

:func:`gearsim.load` returns a :class:`Gearbox`: the :class:`~gearsim.system.GearTrain`
(gears, operating point, stiffness options, cracks) and the ``[dynamics]`` and
``[analysis]`` settings, each a frozen, validated dataclass. Variants are made with
:meth:`Gearbox.with_crack` and :meth:`Gearbox.replace`, which check the new value once,
where it is made.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

from gearsim.dynamics.settings import DynamicsSettings
from gearsim.signals.settings import AnalysisSettings
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.toml import train_to_toml
from gearsim.system.train import GearTrain

__all__ = ["Gearbox"]


@dataclass(frozen=True)
class Gearbox:
    """A gear train with its dynamics and analysis settings.

    Parameters
    ----------
    train : GearTrain
        Gears, operating point, stiffness options and cracks.
    dynamics : DynamicsSettings
        Options of the vibration simulation (``[dynamics]``).
    analysis : AnalysisSettings
        Options of the signal analysis (``[analysis]``).

    Examples
    --------
    >>> import gearsim as gs
    >>> gb = gs.example("idler-table1")
    >>> [g.teeth for g in gb.train.gears], gb.dynamics.model, gb.stiffness.closure
    ([39, 59, 125], 'lta', 'contact')
    >>> round(gb.train.mesh_frequency, 3)
    1235.0
    """

    train: GearTrain
    dynamics: DynamicsSettings = field(default_factory=DynamicsSettings)
    analysis: AnalysisSettings = field(default_factory=AnalysisSettings)

    @property
    def name(self) -> str:
        """Name of the train."""
        return self.train.name

    @property
    def stiffness(self) -> StiffnessSettings:
        """Options of the mesh-stiffness computation (the train's)."""
        return self.train.stiffness

    def with_crack(self, flank: str | None, *, depth: float | None = None,
                   closure: str | None = None, source: str | None = None) -> Gearbox:
        """The fault variant: see :meth:`gearsim.system.GearTrain.with_crack`.

        Parameters
        ----------
        flank : {"none", "working", "non-working"} or None
            No crack, the cracks (or the default crack) on that flank, or as configured.
        depth : float, optional
            Crack depth [m] of every crack.
        closure : {"contact", "open"}, optional
            Crack-face model.
        source : {"pe", "fe"}, optional
            Tooth-compliance model.

        Returns
        -------
        Gearbox
        """
        return dataclasses.replace(self, train=self.train.with_crack(
            flank, depth=depth, closure=closure, source=source))

    def replace(self, *, dynamics: dict[str, Any] | None = None,
                analysis: dict[str, Any] | None = None,
                stiffness: dict[str, Any] | None = None) -> Gearbox:
        """A copy with some settings changed (SI values; each checked where it is made).

        Parameters
        ----------
        dynamics, analysis, stiffness : dict, optional
            Field name -> new value of :class:`DynamicsSettings`,
            :class:`AnalysisSettings`, :class:`StiffnessSettings`.

        Returns
        -------
        Gearbox

        Examples
        --------
        >>> import gearsim as gs
        >>> gs.example("spur-19-48").replace(dynamics={"duration": 0.5}).dynamics.duration
        0.5
        """
        gb = self
        if dynamics:
            gb = dataclasses.replace(gb, dynamics=dataclasses.replace(gb.dynamics, **dynamics))
        if analysis:
            gb = dataclasses.replace(gb, analysis=dataclasses.replace(gb.analysis, **analysis))
        if stiffness:
            gb = dataclasses.replace(gb, train=dataclasses.replace(
                gb.train, stiffness=dataclasses.replace(gb.train.stiffness, **stiffness)))
        return gb

    def mesh_stiffness(self, mesh: int = 0, *, revolution_of: int = 1):
        """TVMS of mesh ``mesh`` over one revolution of its gear 1 or 2, as xarray.

        Parameters
        ----------
        mesh : int, optional
            Mesh index (0 = mesh I).
        revolution_of : {1, 2}, optional
            Over one revolution of the driver (1) or of the driven gear (2).

        Returns
        -------
        xarray.Dataset
            ``k`` [N/m] over ``position`` (coordinate ``cycles``), components, pair
            stiffness and load sharing; units in attributes.
        """
        return self.train.mesh_stiffness(mesh, revolution_of=revolution_of).to_dataset()

    def to_toml(self) -> str:
        """The effective configuration as TOML (SI units) that :func:`gearsim.loads` reads.

        Returns
        -------
        str
        """
        return train_to_toml(self.train, self.dynamics.to_dict())
