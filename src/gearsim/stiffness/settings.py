"""Numerical and modelling options of the mesh-stiffness computation (``[stiffness]``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from gearsim.errors import require

__all__ = ["CLOSURES", "CONTACTS", "COUPLINGS", "DEFAULT_MODEL", "DEFAULT_SLICES", "MODELS",
           "PLANES", "SOURCES", "StiffnessSettings", "model_options"]

#: Tooth-compliance models ``stiffness.source`` may name.
SOURCES = ("pe", "fe", "fe-pair", "calibrated")
#: Crack-face models ``stiffness.closure`` may name.
CLOSURES = ("contact", "open")
#: Plane assumptions ``stiffness.plane`` may name.
PLANES = ("stress", "strain")
#: Contact laws ``stiffness.contact`` may name.
CONTACTS = ("yang-lin", "line")
#: Tooth-coupling models ``stiffness.coupling`` may name.
COUPLINGS = ("none", "fe")

#: Named stiffness models (``[stiffness] model`` of a configuration file) and the options
#: each stands for: ``"seed"``, the source paper's potential-energy method (PE tooth,
#: Yang-Lin contact, independent pairs; +24 % on the cycle mean of the 19/48 pair against
#: the FE gear pair); ``"accurate"``, the calibrated tooth with the 2D line contact and
#: the FE body coupling and the tip-corner contacts under load, the line contact cut off
#: by the tip edge (within 3 % of the FE gear pair at level 2 inside the contact zones,
#: for the cycle mean and at the zone ends, healthy and cracked; docs/stiffness.md,
#: section 4c).
MODELS = {"seed": {"source": "pe", "contact": "yang-lin", "coupling": "none"},
          "accurate": {"source": "calibrated", "contact": "line", "coupling": "fe"}}
#: The model of a gear train, a planetary stage or a stage's chain whose file names none
#: of ``model``, ``source``, ``contact``, ``coupling``: the stage's sun-planet meshes as
#: external pairs, its ring-planet mesh with the ring tooth corrected by the FE ring
#: segment (docs/planetary.md 4.4). The Python default of :class:`StiffnessSettings`
#: stays the seed's options (the library's building block).
DEFAULT_MODEL = "accurate"

#: Default number of slices of a helical face width. From the convergence study in
#: ``tests/test_stiffness_mesh.py::test_slice_convergence`` (Table-1 mesh I, largest
#: pointwise change relative to the mean): 10->20 slices 0.084 %, 20->40 0.021 %,
#: 40->80 0.005 % (second order in 1/N).
DEFAULT_SLICES = 40


@dataclass(frozen=True)
class StiffnessSettings:
    """Numerical and modelling options of the stiffness computation.

    Parameters
    ----------
    closure
        Crack-face model, ``"contact"`` (default) or ``"open"`` (seed as printed).
    slices
        Number of slices of the face width for helical gears and for spur gears with
        crowning or helix slope (else a spur face is one slice).
    positions_per_cycle
        Mesh positions per mesh cycle (base pitch).
    gauss_points
        Gauss-Legendre nodes per integration piece.
    plane
        ``"stress"`` (seed) or ``"strain"``.
    source
        ``"pe"``: potential-energy tooth compliance (default); ``"fe"``: the tooth
        compliance of the finite-element model (:mod:`gearsim.fem.tables`), the
        counterpart of the seed's rigid-flexible coupling; ``"fe-pair"``: the whole mesh
        stiffness from the FE gear pair in contact at the train's torque
        (:mod:`gearsim.system.fe_pair`; cracks only, no mesh of contacts);
        ``"calibrated"``: the PE tooth (cracks included) times the FE/PE compliance ratio
        of the healthy tooth, measured once per gear and cached, and a crack on the
        loaded flank times its measured correction Q = F_FE / F_PE (the FE tooth's crack
        factor over the PE tooth's, measured at a grid of depths once per gear and crack
        family; a crack on the unloaded flank stays the PE section reduction)
        (:mod:`gearsim.fem.calibration`; docs/stiffness.md, section 4c); it requires
        ``contact = "line"`` and ``coupling = "fe"``, the options it was measured with
        against the FE gear pair. The model is chosen one layer up, by
        :func:`gearsim.system.tooth_compliance`.
    corner_contact
        Add the tip-corner contacts of the tooth pairs just outside the path of contact
        to the mesh of contacts (:mod:`gearsim.stiffness.contacts`; default on). They
        close when contact is lost elsewhere (a broken tooth: without them the gears
        would turn freely until the next pair reaches the path of contact) and, near the
        ends of the path, under load (extended contact). Under the line contact law
        (``contact = "line"``, the accurate model) the stiffness tables
        (:func:`gearsim.stiffness.mesh.mesh_stiffness`) close them under load too
        (:func:`gearsim.stiffness.mesh.extended_law`; docs/stiffness.md 4c); the seed's
        load-independent law keeps the path of contact. Off: the path of contact only,
        and a healthy mesh of contacts is exactly the TVMS of the slicing model.
    contact
        Contact law of the mesh stiffness: ``"yang-lin"`` (default, the seed's load-
        independent k_h = pi E b / (4 (1 - nu^2)), :func:`gearsim.stiffness.tooth.
        hertz_stiffness`) or ``"line"``: the 2D Hertz line contact up to the tooth centre
        lines (:func:`gearsim.stiffness.tooth.line_contact_compliance`), which depends on
        the load per unit face width and agrees with the FE gear pair (docs/fem.md).
    fe_pair_positions
        Positions per mesh cycle solved by the FE gear pair (``source = "fe-pair"``),
        interpolated to ``positions_per_cycle``.
    coupling
        ``"none"`` (default, the seed: pairs in contact act in parallel, independently)
        or ``"fe"``: a load on one tooth also deflects its loaded neighbour through the
        gear body, with the cross compliance of the FE gear body computed once per gear
        and cached (:mod:`gearsim.fem.coupling`).
    """

    closure: str = "contact"
    slices: int = DEFAULT_SLICES
    positions_per_cycle: int = 40
    gauss_points: int = 16
    plane: str = "stress"
    source: str = "pe"
    corner_contact: bool = True
    contact: str = "yang-lin"
    coupling: str = "none"
    fe_pair_positions: int = 20

    def __post_init__(self) -> None:
        require(self.closure in CLOSURES, "stiffness.closure", self.closure,
                'must be "open" or "contact"')
        for name, lo, hi in (("slices", 1, 2000), ("positions_per_cycle", 4, 10000),
                             ("gauss_points", 2, 200), ("fe_pair_positions", 4, 200)):
            v = getattr(self, name)
            require(isinstance(v, int) and not isinstance(v, bool) and lo <= v <= hi,
                    f"stiffness.{name}", v, f"must be an integer in [{lo}, {hi}]")
        require(self.plane in PLANES, "stiffness.plane", self.plane,
                'must be "stress" or "strain"')
        require(self.source in SOURCES, "stiffness.source", self.source,
                'must be "pe", "fe", "fe-pair" or "calibrated"')
        require(isinstance(self.corner_contact, bool), "stiffness.corner_contact",
                self.corner_contact, "must be true or false")
        require(self.contact in CONTACTS, "stiffness.contact", self.contact,
                'must be "yang-lin" or "line"')
        require(self.coupling in COUPLINGS, "stiffness.coupling", self.coupling,
                'must be "none" or "fe"')
        if self.source == "calibrated":
            require(self.contact == "line" and self.coupling == "fe", "stiffness.source",
                    self.source, 'needs contact = "line" and coupling = "fe" (the model '
                    "calibrated against the FE gear pair, docs/stiffness.md 4c); got "
                    f"contact = {self.contact!r}, coupling = {self.coupling!r}")


def model_options(kw: dict[str, Any], where: str, default: str = DEFAULT_MODEL
                  ) -> dict[str, Any]:
    """Keyword arguments of :class:`StiffnessSettings` from a ``[stiffness]`` table.

    ``model = "seed"`` or ``"accurate"`` stands for its options (:data:`MODELS`); a
    table that names none of ``model``, ``source``, ``contact`` and ``coupling`` gets
    ``default``'s; a table that names ``source``, ``contact`` or ``coupling`` itself
    keeps the others' class defaults.

    Parameters
    ----------
    kw : dict
        The converted table (:data:`gearsim.model.config.STIFFNESS_KEYS`).
    where : str
        Its name in the file, for messages (``"stiffness"``, ``"chain.stiffness"``).
    default : str
        The model of a table that names none.

    Returns
    -------
    dict

    Raises
    ------
    InputError
        An unknown model, or a model together with ``source``, ``contact`` or
        ``coupling`` (one would override the other).
    """
    kw = dict(kw)
    model = kw.pop("model", None)
    own = [k for k in ("source", "contact", "coupling") if k in kw]
    if model is None:
        return kw if own else {**MODELS[default], **kw}
    require(model in MODELS, f"{where}.model", model,
            "must be " + " or ".join(f'"{m}"' for m in MODELS))
    require(not own, f"{where}.model", model,
            f"names {', '.join(own)} itself: give either model or those keys")
    return {**kw, **MODELS[model]}
