"""Finite-element versus potential-energy tooth compliance along the path of contact.

The two curves are compared as the seed compares them (its Figure 3b: 6.7 / 5.6 /
6.3 %): the maximum of one curve against the maximum of the other, minimum against
minimum, mean against mean, as relative differences of the *tooth stiffness*
k = 1/c (per unit face width) of the potential-energy (PE) model from the
finite-element (FE) reference, 100 (k_PE - k_FE) / k_FE.

Both sides exclude the Hertzian contact compliance: the PE side sums the bending,
shear, axial and foundation columns of :meth:`ToothModel.compliance`; the FE side
measures away from the contact (:mod:`gearsim.fem.tooth`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import FORCE_ENV, InputError, cost_bounds_lifted
from gearsim.fem.geometry import SectorOptions, mesh_sector
from gearsim.fem.tooth import FEToothResult, fe_tooth_compliance
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.tooth import ToothModel

__all__ = ["MAX_DOFS", "MAX_POINTS", "FECheck", "contact_radii", "estimated_dofs", "fe_check",
           "compare_gear"]

CRACK_CHOICES = ("none", "working", "non-working")
#: Most contact positions of one check. Each position is one FE solve of the tooth
#: (about a second at level 2, with contact iterations for a closed crack), and 201
#: positions already space the points at 0.5 % of the path of contact, well below the
#: element size, so more only costs time (100000 points would run for a day).
MAX_POINTS = 201
#: Most FE unknowns of one check without ``force`` (:func:`estimated_dofs`, before any
#: work). The sector's sparse factorization grows faster than its unknowns: level 3 of
#: the two-stage reducer's pinion (68 472 dofs) takes 1.3 s per contact position, level 4
#: (245 126 dofs) 23 s for the default 11 positions and 1.2 GB, and level 5 (about 1.1
#: million) ran for more than 10 minutes. 5e5 admits level 4 of every example and refuses
#: level 5, as ``fe-pair`` caps its pair at level 4.
MAX_DOFS = 5e5


@dataclass
class FECheck:
    """FE and PE tooth compliance of one gear along its path of contact.

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii [m].
    roll_angle
        Involute roll angle tan(alpha_r) at each radius [rad].
    fe, pe
        FE and PE compliance (Hertz excluded) for a face width of 1 m [m/N].
    crack
        Crack case label (``"none"``, ``"working"``, ``"non-working"``).
    closure
        Crack-face model, ``"open"`` or ``"contact"``.
    plane
        ``"stress"`` or ``"strain"``.
    fe_result
        The FE run (mesh size, dofs, contact state).
    depth
        Crack depth [m]; 0 for a healthy tooth.
    pe_components
        PE columns (bending, shear, axial, foundation), shape (n, 4) [m/N].

    References
    ----------
    Seed (Shi, Li & Zhou 2025), Figure 3b (comparison of max, min and mean).
    """

    gear: Gear
    radii: np.ndarray
    roll_angle: np.ndarray
    fe: np.ndarray
    pe: np.ndarray
    crack: str
    closure: str
    plane: str
    fe_result: FEToothResult
    depth: float = 0.0
    pe_components: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    @property
    def k_fe(self) -> np.ndarray:
        """FE tooth stiffness per unit face width [N/m per m]."""
        return 1.0 / self.fe

    @property
    def k_pe(self) -> np.ndarray:
        """PE tooth stiffness per unit face width [N/m per m]."""
        return 1.0 / self.pe

    def differences(self) -> dict[str, float]:
        """100 (k_PE - k_FE) / k_FE for the max, min and mean of the two curves [%]."""
        out = {}
        for name, f in (("max", np.max), ("min", np.min), ("mean", np.mean)):
            out[name] = float(100.0 * (f(self.k_pe) - f(self.k_fe)) / f(self.k_fe))
        return out

    def to_dict(self) -> dict:
        """JSON-ready summary (SI units, stated per key)."""
        r = self.fe_result
        return {
            "gear": self.gear.name,
            "crack": self.crack,
            "crack_depth_m": self.depth,
            "closure": self.closure,
            "plane": self.plane,
            "mesh": {"level": r.level, "element_size_m": r.h, "nodes": r.nodes,
                     "elements": r.elements, "dofs": r.dofs, "order": 2,
                     "seconds": round(r.seconds, 3)},
            "radius_m": self.radii.tolist(),
            "roll_angle_rad": self.roll_angle.tolist(),
            "compliance_fe_m_per_N_per_m": self.fe.tolist(),
            "compliance_pe_m_per_N_per_m": self.pe.tolist(),
            "stiffness_fe_N_per_m_face": (self.k_fe * self.gear.face_width).tolist(),
            "stiffness_pe_N_per_m_face": (self.k_pe * self.gear.face_width).tolist(),
            "crack_closed_fraction": r.closed_fraction.tolist(),
            "difference_percent": self.differences(),
            "difference_definition": "100 (k_PE - k_FE) / k_FE of max, min, mean tooth "
                                     "stiffness (Hertz excluded)",
        }

    def plot(self, *, fig=None):
        """Figure of the two curves and their differences (see :func:`gearsim.viz.fem.plot_fe_check`).

        Parameters
        ----------
        fig : matplotlib.figure.Figure, optional
            Figure to draw into (two panels); default a new one.

        Returns
        -------
        matplotlib.figure.Figure
            The figure; write it with :func:`gearsim.viz.save`.
        """
        from gearsim.viz.fem import plot_fe_check

        return plot_fe_check(self, fig=fig)


def contact_radii(train, gear_name: str, n: int) -> np.ndarray:
    """Contact radii of a gear over its path of contact in its first mesh.

    The first mesh of the power flow the gear takes part in (the one loading its working
    flank, :meth:`gearsim.system.graph.PowerFlow.meshes_of`), as its driver or driven
    gear. Equally spaced in roll length from the start of active profile to the tip.

    Parameters
    ----------
    train
        The gear train.
    gear_name
        Name of the gear.
    n
        Number of radii, 3 to :data:`MAX_POINTS`.

    Returns
    -------
    ndarray, shape (n,)
        Radii [m].

    Raises
    ------
    InputError
        If ``n`` is not an integer in [3, :data:`MAX_POINTS`].
    """
    if not (isinstance(n, int) and not isinstance(n, bool) and n >= 3):
        raise InputError("--points", n, "must be an integer >= 3")
    if n > MAX_POINTS:
        raise InputError("--points", n, f"must be <= {MAX_POINTS}: each point is one FE "
                         f"solve, and {MAX_POINTS} points already resolve the path of "
                         "contact finer than the FE mesh")
    mesh, role = train.flow.meshes_of(gear_name)[0]
    pair = train.pairs[mesh]
    gear = train.gear(gear_name)
    if role == 1:  # driver
        r_lo = pair.radius_on_driver(pair.start_of_contact)
    else:
        r_lo = pair.radius_on_driven(pair.end_of_contact)
    rb = gear.base_radius
    l0, l1 = math.sqrt(max(r_lo**2 - rb**2, 0.0)), math.sqrt(gear.tip_radius**2 - rb**2)
    lengths = np.linspace(l0, l1, n)
    return np.hypot(rb, lengths)


def compare_gear(gear: Gear, radii, *, crack: Crack | None = None, side: int = 0,
                 closure: str = "contact", plane: str = "stress",
                 options: SectorOptions | None = None, label: str = "none",
                 gauss_points: int = 16) -> FECheck:
    """FE and PE compliance of ``gear`` at ``radii`` (see module docstring).

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii [m].
    crack
        The crack or ``None``.
    side
        +1 puts the crack on the loaded flank, -1 on the other, 0 leaves the tooth
        healthy.
    closure, plane
        As :class:`gearsim.stiffness.mesh.StiffnessSettings`.
    options
        FE mesh options.
    label
        Name of the crack case for reports.
    gauss_points
        Gauss-Legendre nodes of the PE integrals.
    """
    r = np.asarray(radii, dtype=float)
    fe = fe_tooth_compliance(gear, r, crack=crack, side=side, closure=closure, plane=plane,
                             options=options)
    prof = ToothProfile(gear)
    rec = None
    depth = 0.0
    if crack is not None and side != 0 and crack.depth > 0:
        rec = crack_record(prof, crack, crack.depth, side)
        depth = crack.depth
    comps = ToothModel(gear, plane=plane, closure=closure,
                       gauss_points=gauss_points).compliance(r, rec, width=1.0)
    rb = gear.base_radius
    roll = np.sqrt(np.maximum(r**2 - rb**2, 0.0)) / rb
    return FECheck(gear=gear, radii=r, roll_angle=roll, fe=fe.compliance, pe=comps.sum(axis=1),
                   crack=label, closure=closure, plane=plane, fe_result=fe, depth=depth,
                   pe_components=comps)


def estimated_dofs(gear: Gear, options: SectorOptions) -> float:
    """FE unknowns of a check of ``gear`` at ``options.level``, before any FE work.

    The sector's linear mesh (:func:`gearsim.fem.geometry.mesh_sector`, gmsh only) at
    level min(level, 3), counted exactly for P2 triangles (two unknowns per vertex and per
    edge), times 4 per further level (each halves the element size). Level 3 to 4 of the
    examples measured x 3.1 to x 3.4, so above level 3 it is an upper estimate.

    Parameters
    ----------
    gear : Gear
        The gear.
    options : SectorOptions
        Mesh options.

    Returns
    -------
    float
        Estimated displacement unknowns.
    """
    ref = min(options.level, 3)
    m = mesh_sector(gear, options=dataclasses.replace(options, level=ref))
    t = np.sort(np.asarray(m.t), axis=0)
    edges = np.unique(np.concatenate([t[[0, 1]], t[[1, 2]], t[[0, 2]]], axis=1), axis=1)
    return 2.0 * (m.p.shape[1] + edges.shape[1]) * 4.0 ** (options.level - ref)


def fe_check(train, gear_name: str | None = None, *, crack: str = "none",
             closure: str | None = None, level: int = 2, points: int = 11,
             options: SectorOptions | None = None, force: bool | None = None) -> FECheck:
    """FE versus PE compliance of one gear of a train (the ``fe-check`` command).

    Parameters
    ----------
    train
        :class:`gearsim.system.GearTrain` (e.g. from :func:`gearsim.load` (its ``train``)).
    gear_name
        Gear to check; default the first cracked gear, else the first gear.
    crack
        ``"none"``, ``"working"`` (crack on the flank loaded in the gear's first mesh)
        or ``"non-working"``; depth, angle and start come from the config's crack on
        that gear.
    closure
        ``"open"`` or ``"contact"``; default the config's ``stiffness.closure`` (the
        gear's first mesh's).
    level
        Mesh level (element size m_n / (4 2^level) on the loaded tooth).
    points
        Contact positions along the path of contact, 3 to :data:`MAX_POINTS`.
    options
        Further mesh options (their ``level`` is replaced by ``level``).
    force
        Lift the cost bound (more than :data:`MAX_DOFS` estimated unknowns); default:
        the environment variable ``GEARSIM_FORCE`` set to 1.

    Returns
    -------
    FECheck

    Raises
    ------
    InputError
        An unknown crack, gear or closure, a level outside [0, 6], too many points, a
        check estimated above :data:`MAX_DOFS` unknowns (``fem.level``, unless
        ``force``), before any FE solve.
    """
    if crack not in CRACK_CHOICES:
        raise InputError("--crack", crack, 'must be "none", "working" or "non-working"')
    names = [g.name for g in train.gears]
    if gear_name is None:
        gear_name = train.cracks[0].gear if train.cracks else names[0]
    if gear_name not in names:
        raise InputError("--gear", gear_name, f"must be one of {names}")
    st = train.settings_of(train.flow.meshes_of(gear_name)[0][0])  # of the gear's first mesh
    closure = st.closure if closure is None else closure
    if closure not in ("open", "contact"):
        raise InputError("--closure", closure, 'must be "open" or "contact"')
    gear = train.gear(gear_name)
    opt = SectorOptions(level=level) if options is None else SectorOptions(
        level=level, n_teeth=options.n_teeth, sides=options.sides, growth=options.growth,
        tip_refinement=options.tip_refinement)
    if not cost_bounds_lifted(force):
        dofs = estimated_dofs(gear, opt)
        if dofs > MAX_DOFS:
            raise InputError("fem.level", level, f"the check needs about {dofs:.3g} FE "
                             f"unknowns (element size m_n / {4 * 2**level}), above the limit "
                             f"of {MAX_DOFS:.0e}: lower the level, or override with --force "
                             f"({FORCE_ENV}=1)")
    c = None
    side = 0
    if crack != "none":
        found = [k for k in train.cracks if k.gear == gear_name]
        if not found:
            raise InputError("--crack", crack, f"the configuration has no [[cracks]] entry on "
                             f"gear {gear_name!r} to take the depth and angle from")
        c = found[0]
        if c.depth <= 0:
            raise InputError("cracks.depth", c.depth, "must be > 0 for a cracked check")
        side = 1 if crack == "working" else -1
    radii = contact_radii(train, gear_name, points)
    return compare_gear(gear, radii, crack=c, side=side, closure=closure,
                        plane=st.plane, options=opt, label=crack,
                        gauss_points=st.gauss_points)
