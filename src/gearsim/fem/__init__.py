"""Finite-element check of the tooth stiffness (gmsh mesh, scikit-fem solver).

Modules: :mod:`~gearsim.fem.geometry` (gear sector / whole gear from the real outline,
crack as a slit), :mod:`~gearsim.fem.solve` (plane elasticity, crack-face contact),
:mod:`~gearsim.fem.tooth` (tooth compliance along the path of contact),
:mod:`~gearsim.fem.check` (FE versus potential energy), :mod:`~gearsim.fem.tables`
(FE compliance as the stiffness table of a simulation, cached) and
:mod:`~gearsim.fem.cantilever` (verification against a closed form). See docs/fem.md.

gmsh and scikit-fem are imported only when a model is built.
"""

__all__ = ["cantilever", "check", "geometry", "solve", "tables", "tooth"]
