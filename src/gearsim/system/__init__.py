"""A gear train: its gears, operating point, stiffness options and faults.

The layer above ``stiffness`` and ``fem``: a :class:`GearTrain` owns its fault variants
(:meth:`GearTrain.with_crack`) and chooses the tooth-compliance model of its meshes
(:func:`tooth_compliance`); :mod:`.stiffness` tabulates the mesh stiffness of every mesh;
:mod:`.toml` writes the effective configuration.
"""

from gearsim.system.stiffness import TrainStiffness, train_stiffness
from gearsim.system.toml import train_to_toml
from gearsim.system.train import DEFAULT_CRACK, GearTrain, Operating, tooth_compliance

__all__ = ["DEFAULT_CRACK", "GearTrain", "Operating", "TrainStiffness", "tooth_compliance",
           "train_stiffness", "train_to_toml"]
