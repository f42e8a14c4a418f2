"""Time-varying mesh stiffness (TVMS) of a spur or helical gear pair.

Each tooth pair in contact is a series connection of the Hertzian contact and the
bending, shear, axial and fillet-foundation compliances of both teeth (seed eq. 8);
pairs in contact act in parallel (seed eq. 9). A helical pair is cut into ``slices``
transverse slices of width b/N; the slice at axial position z touches at the point of
the transverse line of action shifted by -z tan(beta_b) (slicing method, e.g. Wan et
al. 2014; docs/references.md, "Helical slicing"). A slice that is only partly inside the path of contact
contributes with its inside fraction, evaluated at the middle of that part; this keeps
the sum smooth in the slice count.

All stiffnesses are transverse: force and deflection along the transverse line of
action. The normal-plane stiffness is k / cos^2(beta_b).

References
----------
.. [Wan2014] Z. Wan, H. Cao, Y. Zi, W. He, Z. He, An improved time-varying mesh stiffness
   algorithm and dynamic modeling of gear-rotor system with tooth root crack,
   Eng. Fail. Anal. 42 (2014) 157-177.
.. [Seed] eqs. 8-9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from gearsim.errors import require
from gearsim.geometry.pair import GearPair
from gearsim.stiffness.settings import DEFAULT_SLICES, StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCompliance, ToothCrack
from gearsim.stiffness.tooth import hertz_stiffness

__all__ = ["COMPONENTS", "DEFAULT_SLICES", "MeshStiffness", "StiffnessSettings", "ToothCrack",
           "mesh_stiffness"]

COMPONENTS = ("hertz", "bending_1", "shear_1", "axial_1", "foundation_1",
              "bending_2", "shear_2", "axial_2", "foundation_2")

@dataclass
class MeshStiffness:
    """TVMS of one mesh over one revolution of one of its gears.

    Parameters
    ----------
    name : str
        Name of the mesh (``"I"``, ``"II"``, ...).
    revolution_of : str
        Name of the gear whose revolution the positions cover.
    cycles : ndarray
        Mesh cycles (base pitches of rotation) from the reference position [-].
    theta1, theta2 : ndarray
        Rotation of driver and driven gear [rad].
    k : ndarray
        Total transverse mesh stiffness [N/m].
    components : dict of str to ndarray
        Effective component stiffnesses [N/m], ``sum(1/k_c) = 1/k`` (keys
        :data:`COMPONENTS`).
    pair_k : ndarray, shape (n, pairs)
        Stiffness of each tooth pair in contact [N/m].
    pair_tooth1, pair_tooth2 : ndarray, shape (n, pairs)
        Tooth indices of those pairs (driver, driven).
    attrs : dict
        Settings the table was computed with (closure, slices, source, ...).
    """

    name: str
    revolution_of: str
    cycles: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    k: np.ndarray
    components: dict[str, np.ndarray]
    pair_k: np.ndarray
    pair_tooth1: np.ndarray
    pair_tooth2: np.ndarray
    attrs: dict = field(default_factory=dict)

    @property
    def load_share(self) -> np.ndarray:
        """Load sharing ratio of each pair, k_pair / k [-]."""
        return self.pair_k / self.k[:, None]

    @property
    def mean(self) -> float:
        """Mean mesh stiffness over the revolution [N/m]."""
        return float(np.mean(self.k))

    def to_dataset(self):
        """The result as an :class:`xarray.Dataset` with units in attributes.

        Returns
        -------
        xarray.Dataset
        """
        import xarray as xr

        ds = xr.Dataset(
            {
                "k": ("position", self.k, {"units": "N/m", "long_name": "mesh stiffness"}),
                "theta1": ("position", self.theta1, {"units": "rad"}),
                "theta2": ("position", self.theta2, {"units": "rad"}),
                "pair_k": (("position", "pair"), self.pair_k, {"units": "N/m"}),
                "load_share": (("position", "pair"), self.load_share, {"units": "1"}),
                "pair_tooth1": (("position", "pair"), self.pair_tooth1),
                "pair_tooth2": (("position", "pair"), self.pair_tooth2),
            },
            coords={"cycles": ("position", self.cycles, {"units": "1"})},
            attrs={"mesh": self.name, "revolution_of": self.revolution_of, **self.attrs},
        )
        for name, arr in self.components.items():
            ds[f"k_{name}"] = ("position", arr, {"units": "N/m"})
        return ds


def _slice_grid(pair: GearPair, settings: StiffnessSettings):
    """Contact points and in-contact fractions on the (position, pair age, slice) grid."""
    tb = math.tan(pair.driver.base_helix_angle)
    b = pair.face_width
    ns = settings.slices if tb > 0 else 1
    npc = settings.positions_per_cycle
    pb = pair.base_pitch
    la, le = pair.start_of_contact, pair.end_of_contact
    eps_a = pair.transverse_contact_ratio
    eps_b = b * tb / pb
    n_age = int(math.ceil(eps_a + eps_b)) + 1
    u = np.arange(npc) / npc
    age = u[:, None] + np.arange(n_age)[None, :]  # (npc, n_age)
    dz = b / ns
    z0 = np.arange(ns) * dz
    z1 = z0 + dz
    base = la + age[:, :, None] * pb  # l at z = 0
    if tb > 0:
        hi = base - z0[None, None, :] * tb
        lo = base - z1[None, None, :] * tb
        a = np.maximum(lo, la)
        c = np.minimum(hi, le)
        frac = np.clip((c - a) / (hi - lo), 0.0, 1.0)
        lmid = 0.5 * (a + c)
    else:
        lmid = base
        frac = ((base > la) & (base <= le)).astype(float)  # same side as helical limit
    lmid = np.where(frac > 0, lmid, la)
    return lmid, frac, dz, n_age, ns, (z0 + 0.5 * dz) / b


def mesh_stiffness(pair: GearPair, *, cracks: tuple[ToothCrack, ...] = (),
                   settings: StiffnessSettings | None = None,
                   revolution_of: int = 1,
                   compliance: ToothCompliance | None = None) -> MeshStiffness:
    """TVMS of ``pair`` over one revolution of gear ``revolution_of`` (1 or 2).

    Parameters
    ----------
    pair
        The gear pair (driver drives driven).
    cracks
        Cracks on either gear, with the side this mesh loads.
    settings
        Numerical and modelling options.
    revolution_of
        1: one revolution of the driver (z1 mesh cycles); 2: of the driven gear.
    compliance
        The tooth-compliance model (:class:`gearsim.stiffness.source.ToothCompliance`);
        default the potential-energy model. ``settings.source`` only names the model:
        the caller that owns the choice (:meth:`gearsim.system.GearTrain.mesh_stiffness`)
        passes the matching object.

    Returns
    -------
    MeshStiffness
        Stiffness [N/m] per position, components, pair stiffness and load sharing.
    """
    settings = settings or StiffnessSettings()
    require(revolution_of in (1, 2), "revolution_of", revolution_of, "must be 1 or 2")
    g1, g2 = pair.driver, pair.driven
    for tc in cracks:
        z = g1.teeth if tc.gear == 1 else g2.teeth
        require(tc.crack.tooth < z, "crack.tooth", tc.crack.tooth,
                f"must be < {z} (teeth of {tc.crack.gear})")
    model = compliance if compliance is not None else PotentialEnergyCompliance()
    require(model.name == settings.source, "stiffness.source", settings.source,
            f"the tooth-compliance model passed is {model.name!r}: pass the model the "
            "settings name (gearsim.system.tooth_compliance) or use GearTrain.mesh_stiffness")
    lmid, frac, dz, n_age, ns, zfrac = _slice_grid(pair, settings)
    npc = settings.positions_per_cycle
    inside = frac > 0
    shape = (npc, n_age, ns)
    r1 = np.where(inside, np.hypot(g1.base_radius, lmid), 0.0)
    r2 = np.where(inside, np.hypot(g2.base_radius, pair.line_length - lmid), 0.0)

    def table(gear, radii: np.ndarray, tc: ToothCrack | None) -> np.ndarray:
        return model.compliance(gear, radii, tc, zfrac, settings)

    healthy1 = table(g1, r1, None)
    healthy2 = table(g2, r2, None)
    cracked1: dict[int, np.ndarray] = {}
    cracked2: dict[int, np.ndarray] = {}
    for tc in cracks:
        gear, radii, store = (g1, r1, cracked1) if tc.gear == 1 else (g2, r2, cracked2)
        store[tc.crack.tooth] = table(gear, radii, tc)

    # Hertz compliance per unit width
    ch = 1.0 / hertz_stiffness(g1.material, g2.material, 1.0)
    width = frac * dz  # carried face width of each slice [m]
    z_rev = g1.teeth if revolution_of == 1 else g2.teeth
    n_pos = z_rev * npc
    k = np.zeros(n_pos)
    comp = np.zeros((n_pos, len(COMPONENTS)))
    pair_k = np.zeros((n_pos, n_age))
    t1 = np.zeros((n_pos, n_age), dtype=np.int64)
    t2 = np.zeros((n_pos, n_age), dtype=np.int64)
    for c in range(z_rev):
        sl = slice(c * npc, (c + 1) * npc)
        c1 = np.empty(shape + (4,))
        c2 = np.empty(shape + (4,))
        for m in range(n_age):
            i1 = (c - m) % g1.teeth
            i2 = (c - m) % g2.teeth
            t1[sl, m] = i1
            t2[sl, m] = i2
            c1[:, m] = cracked1.get(i1, healthy1)[:, m]
            c2[:, m] = cracked2.get(i2, healthy2)[:, m]
        # per unit width compliances -> slice compliances
        with np.errstate(divide="ignore", invalid="ignore"):
            cs = ch + c1.sum(-1) + c2.sum(-1)
            ks = np.where(width > 0, width / cs, 0.0)  # (npc, n_age, ns)
        kt = ks.sum(axis=(1, 2))
        k[sl] = kt
        pair_k[sl] = ks.sum(axis=2)
        share2 = (ks / kt[:, None, None]) ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            inv_w = np.where(width > 0, 1.0 / width, 0.0)
        parts = [np.full(shape, ch)] + [c1[..., q] for q in range(4)] + [c2[..., q] for q in range(4)]
        with np.errstate(divide="ignore"):  # a zero component (FE source) -> inf stiffness
            for q, part in enumerate(parts):
                comp[sl, q] = 1.0 / np.sum(share2 * part * inv_w, axis=(1, 2))
    cycles = np.arange(n_pos) / npc
    return MeshStiffness(
        name=pair.name,
        revolution_of=(g1.name if revolution_of == 1 else g2.name),
        cycles=cycles,
        theta1=2 * math.pi * cycles / g1.teeth,
        theta2=2 * math.pi * cycles / g2.teeth,
        k=k,
        components={name: comp[:, q] for q, name in enumerate(COMPONENTS)},
        pair_k=pair_k,
        pair_tooth1=t1,
        pair_tooth2=t2,
        attrs={"closure": settings.closure, "slices": ns,
               "positions_per_cycle": npc, "plane": settings.plane,
               "gauss_points": settings.gauss_points, "source": model.name},
    )
