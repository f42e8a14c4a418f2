"""A chain of gears in mesh (input, idler(s), output) with its operating point and cracks.

Gear i drives gear i+1; power enters at gear 0. Consecutive external helical gears have
opposite hands (gear i has the sign (-1)^i on its helix angle). Which flank a mesh
loads follows from the power flow: the driver's front face (facing the direction of
rotation) and the driven gear's rear face. The *working* flank of a gear is the flank
loaded in the first mesh it takes part in; for an idler the second mesh loads the other
flank (reversed bending).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

from gearsim.errors import require
from gearsim.geometry.gear import Gear
from gearsim.geometry.pair import GearPair
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.mesh import MeshStiffness, StiffnessSettings, ToothCrack, mesh_stiffness

__all__ = ["GearTrain", "Operating"]


@dataclass(frozen=True)
class Operating:
    """Operating point of the input gear.

    Parameters
    ----------
    speed
        Input speed [rad/s] (> 0).
    torque
        Input torque [N m] (> 0).
    """

    speed: float = 1900 * 2 * math.pi / 60
    torque: float = 4876.0

    def __post_init__(self) -> None:
        require(self.speed > 0, "operating.speed", self.speed, "must be > 0 rad/s")
        require(self.torque > 0, "operating.torque", self.torque, "must be > 0 N*m")


@dataclass(frozen=True)
class GearTrain:
    """A chain of gears, its operating point, stiffness options and cracks."""

    gears: tuple[Gear, ...]
    operating: Operating = field(default_factory=Operating)
    stiffness: StiffnessSettings = field(default_factory=StiffnessSettings)
    cracks: tuple[Crack, ...] = ()
    name: str = "gear train"
    extra: dict = field(default_factory=dict)  # further config sections (e.g. dynamics)

    def __post_init__(self) -> None:
        require(len(self.gears) >= 2, "gears", len(self.gears), "need at least 2 gears")
        names = [g.name for g in self.gears]
        require(len(set(names)) == len(names), "gears.name", names, "names must be unique")
        for c in self.cracks:
            require(c.gear in names, "crack.gear", c.gear, f"must be one of {names}")
            z = self.gear(c.gear).teeth
            require(c.tooth < z, "crack.tooth", c.tooth, f"must be < {z} (teeth of {c.gear})")
        _ = self.pairs  # validates every mesh (interference, contact ratio)

    def gear(self, name: str) -> Gear:
        for g in self.gears:
            if g.name == name:
                return g
        raise KeyError(name)

    def gear_index(self, name: str) -> int:
        return [g.name for g in self.gears].index(name)

    @cached_property
    def pairs(self) -> tuple[GearPair, ...]:
        roman = ("I", "II", "III", "IV", "V", "VI", "VII", "VIII")
        return tuple(
            GearPair(self.gears[i], self.gears[i + 1],
                     name=roman[i] if i < len(roman) else str(i + 1))
            for i in range(len(self.gears) - 1)
        )

    # ------------------------------------------------------------------- kinematics
    def speed(self, i: int) -> float:
        """Speed of gear i [rad/s] (magnitude)."""
        return self.operating.speed * self.gears[0].teeth / self.gears[i].teeth

    def torque(self, i: int) -> float:
        """Torque on gear i for loss-free transmission [N m]."""
        return self.operating.torque * self.gears[i].teeth / self.gears[0].teeth

    def shaft_frequency(self, i: int) -> float:
        """f_r of gear i [Hz]."""
        return self.speed(i) / (2 * math.pi)

    @property
    def mesh_frequency(self) -> float:
        """f_m = z_1 f_r1 (common to all meshes of a chain) [Hz]."""
        return self.gears[0].teeth * self.shaft_frequency(0)

    @property
    def power(self) -> float:
        """Transmitted power T_1 omega_1 [W]."""
        return self.operating.torque * self.operating.speed

    def static_mesh_force(self, mesh: int) -> float:
        """Static transverse force along the line of action of mesh ``mesh``, T_i / r_bi [N]."""
        return self.torque(mesh) / self.gears[mesh].base_radius

    # ------------------------------------------------------------------- flanks
    def crack_side(self, crack: Crack, mesh: int) -> int:
        """+1 if mesh ``mesh`` loads the cracked flank, -1 if it loads the other flank."""
        gi = self.gear_index(crack.gear)
        first_mesh = 0 if gi == 0 else gi - 1
        # working flank = loaded in the first mesh; an idler's other mesh loads the other
        loaded_is_working = mesh == first_mesh
        crack_on_working = crack.flank == "working"
        return 1 if crack_on_working == loaded_is_working else -1

    def mesh_cracks(self, mesh: int) -> tuple[ToothCrack, ...]:
        """The cracks of both gears of mesh ``mesh`` with their sides."""
        out = []
        for c in self.cracks:
            gi = self.gear_index(c.gear)
            if gi in (mesh, mesh + 1):
                out.append(ToothCrack(gear=1 if gi == mesh else 2, crack=c,
                                      side=self.crack_side(c, mesh)))
        return tuple(out)

    def mesh_stiffness(self, mesh: int, *, revolution_of: int = 1,
                       settings: StiffnessSettings | None = None) -> MeshStiffness:
        """TVMS of mesh ``mesh`` over one revolution of its gear 1 or 2."""
        return mesh_stiffness(self.pairs[mesh], cracks=self.mesh_cracks(mesh),
                              settings=settings or self.stiffness, revolution_of=revolution_of)

    def with_cracks(self, cracks: tuple[Crack, ...]) -> GearTrain:
        """A copy with other cracks."""
        return replace(self, cracks=tuple(cracks))
