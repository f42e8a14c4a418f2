"""Train dynamics: the seed's 3-DOF model and a lateral-torsional-axial model.

Entry point: :func:`simulate` (returns an :class:`xarray.Dataset`); the equations are
written down in ``docs/dynamics.md`` and in the docstrings of :mod:`.lta`,
:mod:`.seed3dof`, :mod:`.layout` and :mod:`.model`.
"""

from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import build_model, reference_rhs, simulate, summary

__all__ = ["DynamicsSettings", "build_model", "reference_rhs", "simulate", "summary"]
