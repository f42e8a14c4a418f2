"""PE mesh stiffness against the FE gear pair on a transverse section (seed Figure 3).

The seed checks its potential-energy (PE) mesh stiffness against a finite-element model
of the gear pair (its Figure 3a: the two TVMS curves; Figure 3b: the differences of their
maximum, minimum and mean). :func:`fe_pair_check` does the same on the transverse section
of a mesh: the FE gear pair in contact (:mod:`gearsim.fem.pair`, through the cached table
of :func:`gearsim.fem.pair_table.fe_pair_mesh_stiffness`) against

* ``pe``: the seed's method (PE tooth, Yang-Lin contact, pairs in parallel; the train's
  other options),
* ``pe_line``: the PE tooth with the 2D line contact and the FE body coupling
  (``stiffness.contact = "line"``, ``stiffness.coupling = "fe"``; docs/stiffness.md 4b),
* ``fe_tooth``: the single-tooth FE compliance with the same two options,
* ``accurate``: gearsim's default model (``[stiffness] model = "accurate"``: the
  calibrated PE tooth with both options; docs/stiffness.md 4c),

all on the section at z = 0 (the FE pair's convention: driver tooth k touches at
l_A + (u + k) p_b), over a window of mesh cycles.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import MODELS
from gearsim.system.fe_pair import FE_PAIR_LEVEL
from gearsim.system.train import GearTrain, body_coupling, tooth_compliance

__all__ = ["CURVES", "FEPairCheck", "fe_pair_check", "section_tvms"]

#: The model curves compared with the FE pair.
CURVES = ("pe", "pe_line", "fe_tooth", "accurate")
#: Positions per cycle of the PE curves (interpolated at the FE positions).
PE_POSITIONS = 400


@dataclass
class FEPairCheck:
    """FE gear pair against the model curves on one transverse section.

    Parameters
    ----------
    mesh
        Mesh name.
    crack
        ``"none"``, ``"working"`` or ``"non-working"`` (faces in contact).
    torque
        Driver torque [N m].
    cycles
        Mesh cycles of the positions [-].
    k_fe
        FE pair stiffness of the section over the face width [N/m].
    curves
        Curve name (:data:`CURVES`) -> stiffness at the same positions [N/m].
    level
        FE mesh level.
    """

    mesh: str
    crack: str
    torque: float
    cycles: np.ndarray
    k_fe: np.ndarray
    curves: dict[str, np.ndarray] = field(default_factory=dict)
    level: int = FE_PAIR_LEVEL

    def differences(self, curve: str = "pe") -> dict[str, float]:
        """100 (k_model - k_FE) / k_FE of the max, min and mean of the curves [%].

        Parameters
        ----------
        curve : str
            One of :data:`CURVES`.

        Returns
        -------
        dict
            ``max``, ``min``, ``mean`` [%] (the seed's Figure 3b quantities).
        """
        k = self.curves[curve]
        return {name: float(100.0 * (f(k) - f(self.k_fe)) / f(self.k_fe))
                for name, f in (("max", np.max), ("min", np.min), ("mean", np.mean))}

    def to_dict(self) -> dict:
        """JSON-ready summary (SI units)."""
        return {"mesh": self.mesh, "crack": self.crack, "torque_N_m": self.torque,
                "level": self.level, "cycles": self.cycles.tolist(),
                "k_fe_pair_N_per_m": self.k_fe.tolist(),
                **{f"k_{c}_N_per_m": v.tolist() for c, v in self.curves.items()},
                "differences_percent": {c: self.differences(c) for c in self.curves}}


#: Face-width scale of the section computation: a slice of width SECTION b has no extent
#: along the line of action (b tan(beta_b) SECTION), so it is the transverse section.
SECTION = 1e-6


def section_tvms(train: GearTrain, mesh: int, settings, npc: int, revolution_of: int = 1
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Slicing-model TVMS of the transverse section over a driver revolution [N/m].

    The slicing model with one slice of the face width spreads a helical slice over
    b tan(beta_b) of the line of action; the section is the same gears with the face
    width scaled by :data:`SECTION` (and the force with it, so the load per unit width
    is the train's), scaled back: the quantity the FE gear pair computes.

    Parameters
    ----------
    train : GearTrain
        The train (its cracks on this mesh are in the section, uniform).
    mesh : int
        Mesh index.
    settings : StiffnessSettings
        Source, contact law, coupling, plane of the curve.
    npc : int
        Positions per mesh cycle.
    revolution_of : {1, 2}
        Over a revolution of the driver (1) or of the driven gear (2).

    Returns
    -------
    cycles, k
        Mesh cycles u = i / npc [-] and the section's stiffness over the face width [N/m]
        over the revolution.
    """
    pair = train.pairs[mesh]
    thin = dataclasses.replace(pair, driver=dataclasses.replace(
        pair.driver, face_width=pair.driver.face_width * SECTION), driven=dataclasses.replace(
        pair.driven, face_width=pair.driven.face_width * SECTION))
    st = dataclasses.replace(settings, slices=1, positions_per_cycle=npc)
    ms = mesh_stiffness(thin, cracks=train.mesh_cracks(mesh), settings=st,
                        compliance=tooth_compliance(st.source),
                        force=train.static_mesh_force(mesh) * SECTION,
                        coupling=body_coupling(st), revolution_of=revolution_of)
    return ms.cycles, ms.k / SECTION


def fe_pair_check(train: GearTrain, mesh: int = 0, *, crack: str = "none",
                  depth: float | None = None, positions_per_cycle: int = 20,
                  cycles: int = 4, level: int = FE_PAIR_LEVEL) -> FEPairCheck:
    """The FE pair's section TVMS against the PE curves (module docstring).

    Parameters
    ----------
    train : GearTrain
        The train (torque from its operating point; its crack gives the cracked tooth,
        angle and default depth).
    mesh : int
        Mesh index.
    crack : {"none", "working", "non-working"}
        Healthy, or the train's crack on the working or the non-working flank of this
        mesh's cracked gear (:meth:`GearTrain.with_crack`), faces in contact.
    depth : float, optional
        Crack depth [m]; default the train's.
    positions_per_cycle : int
        FE positions per mesh cycle (the cached table's).
    cycles : int
        Mesh cycles shown, from the cycle before the cracked tooth enters.
    level : int
        FE mesh level of the FE pair (:class:`gearsim.fem.pair.FEPairModel`); default
        :data:`gearsim.system.fe_pair.FE_PAIR_LEVEL`, the level of the ``fe-pair`` tables.

    Returns
    -------
    FEPairCheck
    """
    from gearsim.fem.pair_table import fe_pair_mesh_stiffness

    if crack == "none":
        tr = train.with_cracks(())
    else:
        kw = {} if depth is None else {"depth": depth}
        tr = train.with_crack(crack, closure="contact", source="pe", **kw)
    pair, own = tr.pairs[mesh], tr.settings_of(mesh)
    torque = tr.mesh_torque(mesh)
    cracks = tr.mesh_cracks(mesh)
    rev = cracks[0].gear if cracks else 1
    # the window starts one cycle before the (train's) cracked tooth enters, healthy too
    ref = cracks[0].crack.tooth if cracks else (
        train.cracks[0].tooth if train.cracks and train.mesh_cracks(mesh) else 1)
    first = ref - 1
    fe = fe_pair_mesh_stiffness(pair, torque=torque, cracks=cracks,
                                positions_per_cycle=positions_per_cycle, level=level,
                                plane=own.plane, revolution_of=rev, closure="contact")
    z_rev = pair.driver.teeth if rev == 1 else pair.driven.teeth
    npc = positions_per_cycle
    idx = (first * npc + np.arange(cycles * npc)) % (z_rev * npc)
    u = first + np.arange(cycles * npc) / npc
    base = dataclasses.replace(own, **MODELS["seed"])  # whatever the file's model
    variants = {
        "pe": base,
        "pe_line": dataclasses.replace(base, contact="line", coupling="fe"),
        "fe_tooth": dataclasses.replace(base, source="fe", contact="line", coupling="fe"),
        "accurate": dataclasses.replace(base, **MODELS["accurate"]),
    }
    curves = {}
    for name, st in variants.items():
        x, k = section_tvms(tr, mesh, st, PE_POSITIONS, revolution_of=rev)
        curves[name] = np.interp(u, x, k, period=float(z_rev))
    return FEPairCheck(mesh=pair.name, crack=crack, torque=torque, cycles=u,
                       k_fe=fe.k[idx].copy(), curves=curves, level=level)
