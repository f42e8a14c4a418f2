"""Time-varying mesh stiffness (TVMS) of a spur or helical gear pair.

Each tooth pair in contact is a series connection of the Hertzian contact and the
bending, shear, axial and fillet-foundation compliances of both teeth (seed eq. 8);
pairs in contact act in parallel (seed eq. 9). A helical pair is cut into ``slices``
transverse slices of width b/N; the slice at axial position z touches at the point of
the transverse line of action shifted by -z tan(beta_b) (slicing method, e.g. Wan et
al. 2014; docs/references.md, "Helical slicing"). A slice that is only partly inside the path of contact
contributes with its inside fraction, evaluated at the middle of that part; this keeps
the sum smooth in the slice count. A spur pair likewise carries the in-path fraction of
its sampling cell (:func:`in_path_fraction`), so no sample sits on a jump.

Two options go beyond the seed (``StiffnessSettings.contact`` and ``.coupling``; docs/
stiffness.md, "Beyond the seed: contact law and tooth coupling"): the 2D Hertz line
contact up to the tooth centre lines in place of the load-independent k_h, and the
coupling of the two loaded neighbouring teeth of a gear through its body. With coupling,
the pairs of a slice are no longer independent springs in parallel: with C the
compliance matrix of the pairs in contact (per unit face width: contact plus both teeth
on the diagonal, the body cross compliances X of both gears off it) and w their carried
widths, the loads per unit width at a unit approach are q = C^-1 1 and the slice
stiffness is w . q.

Under the line contact law the tables also close the tip corners of the pairs just
outside the path of contact when the loaded transmission error exceeds their separation
(extended contact, as the FE gear pair does under load): :func:`extended_grid`,
:func:`extended_law`, :func:`corner_closing`; the table is then the secant stiffness
F / delta of the loaded mesh at each position. The seed's load-independent law keeps
the path of contact (docs/stiffness.md, section 4c).

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
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numba
import numpy as np

from gearsim.errors import require
from gearsim.geometry.corners import corner_separation, tip_edge_offset
from gearsim.geometry.gear import Gear
from gearsim.geometry.pair import GearPair
from gearsim.geometry.profile import ToothProfile
from gearsim.stiffness import _kernels
from gearsim.stiffness.settings import DEFAULT_SLICES, StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCompliance, ToothCrack
from gearsim.stiffness.tooth import hertz_stiffness, line_contact_compliance

__all__ = ["COMPONENTS", "DEFAULT_SLICES", "MeshStiffness", "StiffnessSettings", "ToothCrack",
           "assemble_revolution", "centre_line_depth", "corner_closing", "crack_cross_factors",
           "extended_grid",
           "extended_law", "in_path_fraction", "mesh_stiffness", "pair_law", "slice_grid",
           "slice_law"]

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

    @classmethod
    def whole_mesh(cls, pair: GearPair, revolution_of: int, npc: int, k: np.ndarray,
                   attrs: dict) -> MeshStiffness:
        """A table of the whole mesh only (no pair or component split): the FE gear pair.

        Parameters
        ----------
        pair : GearPair
            The gear pair.
        revolution_of : {1, 2}
            Gear whose revolution the positions cover.
        npc : int
            Positions per mesh cycle (cycles ``i / npc``).
        k : ndarray
            Mesh stiffness at the positions [N/m].
        attrs : dict
            Options of the table.

        Returns
        -------
        MeshStiffness
            ``components`` empty, ``pair_k`` the mesh as one column, tooth indices 0.
        """
        g1, g2 = pair.driver, pair.driven
        k = np.asarray(k, dtype=float)
        cycles = np.arange(k.size) / npc
        return cls(name=pair.name, revolution_of=(g1.name if revolution_of == 1 else g2.name),
                   cycles=cycles, theta1=2 * math.pi * cycles / g1.teeth,
                   theta2=2 * math.pi * cycles / g2.teeth, k=k, components={},
                   pair_k=k[:, None].copy(), pair_tooth1=np.zeros((k.size, 1), dtype=np.int64),
                   pair_tooth2=np.zeros((k.size, 1), dtype=np.int64), attrs=dict(attrs))

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
    return slice_grid(math.tan(pair.driver.base_helix_angle), pair.face_width,
                      pair.base_pitch, pair.start_of_contact, pair.end_of_contact, settings)


def slice_grid(tb: float, b: float, pb: float, la: float, le: float,
               settings: StiffnessSettings):
    """Contact points and in-contact fractions on the (position, pair age, slice) grid.

    Parameters
    ----------
    tb
        tan of the base helix angle [-] (0: spur, one slice).
    b
        Face width [m].
    pb
        Transverse base pitch [m].
    la, le
        Start and end of the path of contact on the transverse line of action [m].
    settings
        Positions per cycle and slices.

    Returns
    -------
    lmid, frac, dz, n_age, ns, zfrac
        Contact point [m] and in-path fraction [-] of each (position, age, slice), the
        slice width [m], the number of pair ages and slices, and the slice centres over
        the face width [-]. Pair age m at position u of a cycle has its contact at
        la + (u + m) pb - z tan(beta_b) (z the slice centre).
    """
    ns = settings.slices if tb > 0 else 1
    npc = settings.positions_per_cycle
    eps_a = (le - la) / pb
    eps_b = b * tb / pb
    n_age = int(math.ceil(eps_a + eps_b)) + 1
    u = np.arange(npc) / npc
    age = u[:, None] + np.arange(n_age)[None, :]  # (npc, n_age)
    dz = b / ns
    z0 = np.arange(ns) * dz
    base = la + age[:, :, None] * pb  # l at z = 0
    centre = base - (z0 + 0.5 * dz)[None, None, :] * tb
    lmid, frac = in_path_fraction(centre, la, le, pb / npc, dz * tb)
    lmid = np.where(frac > 0, lmid, la)
    return lmid, frac, dz, n_age, ns, (z0 + 0.5 * dz) / b


def _ramp_integral(x: np.ndarray, c: float) -> np.ndarray:
    """Integral of the CDF of the uniform law on [-c, c] from -inf to x."""
    if c <= 0.0:
        return np.maximum(x, 0.0)
    return np.where(x <= -c, 0.0, np.where(x >= c, x, (x + c) ** 2 / (4.0 * c)))


def in_path_fraction(centre: np.ndarray, start: float, end: float, cell: float,
                     width: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Fraction of a contact's sampling cell inside the path of contact.

    A spur tooth pair enters and leaves the path of contact [``start``, ``end``] with a
    jump of the mesh stiffness. A sample that sits on a jump (the first position of a
    cycle sits exactly on the start of contact) would count the whole cell on one side
    and bias the cycle mean by up to one cell (0.96 % at 40 positions per cycle on the
    19/48 pair). Each sample instead carries the in-path fraction of its cell: a contact
    (a face-width slice of length ``width`` on the line of action, 0 for a spur pair)
    whose centre runs over [``centre`` - ``cell`` / 2, ``centre`` + ``cell`` / 2]
    covers ``centre + X`` with X the sum of two uniform laws of half widths ``cell`` / 2
    and ``width`` / 2, so the fraction is
    F(end - centre) - F(start - centre), F(t) = (H(t + cell / 2) - H(t - cell / 2)) / cell,
    H the integral of the uniform CDF of half width ``width`` / 2. The contact point is
    the middle of the in-path part of [lo - cell / 2, hi + cell / 2]. The number of pairs
    in contact then averages exactly the contact ratio over a cycle, and the cycle mean
    of the stiffness converges as (1 / positions)^2
    (``tests/test_stiffness_mesh.py::test_spur_sampling_converges``).

    Parameters
    ----------
    centre
        Contact point of the slice centre at the sample, on the line of action [m].
    start, end
        Start and end of the path of contact on the line of action [m].
    cell
        Length of the sampling cell on the line of action [m] (base pitch over the
        positions per cycle).
    width
        Length of the slice on the line of action [m] (slice width times tan of the
        base helix angle; 0 for a spur pair).

    Returns
    -------
    lmid, frac
        Contact point at the middle of the in-path part [m] and the in-path fraction [-].

    Examples
    --------
    >>> import numpy as np
    >>> lmid, frac = in_path_fraction(np.array([0.0, 1.0, 4.0]), 1.0, 4.0, 1.0)
    >>> frac.tolist(), lmid.tolist()
    ([0.0, 0.5, 0.5], [0.0, 1.25, 3.75])
    """
    half, c = 0.5 * cell, 0.5 * width

    def cdf(t):
        return (_ramp_integral(t + half, c) - _ramp_integral(t - half, c)) / cell

    lo = np.maximum(centre - half - c, start)
    hi = np.minimum(centre + half + c, end)
    # outside the support both CDFs are 0 or 1 up to round-off: exactly 0 there
    frac = np.where(hi > lo, np.clip(cdf(end - centre) - cdf(start - centre), 0.0, 1.0), 0.0)
    return np.where(frac > 0, 0.5 * (lo + hi), centre), frac


#: Fixed-point passes of the line contact law on the load per unit width.
LINE_ITERATIONS = 3


def centre_line_depth(gear, radii: np.ndarray) -> np.ndarray:
    """Distance from a contact point to the tooth centre line along the load line [m].

    The PE tooth deflects as a beam whose axis is the centre line; the contact approach
    of :func:`gearsim.stiffness.tooth.line_contact_compliance` is taken up to the point
    Q where the load line crosses it: d = x_c / cos(alpha_1), (x_c, y_c) the involute
    point at radius r in the tooth frame and alpha_1 = alpha_r - atan(x_c / y_c) the
    load angle (seed eq. 3). This is the point where the FE tooth reads its deflection
    (:func:`gearsim.fem.tooth.load_geometry`).

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii on the involute [m] (any shape).

    Returns
    -------
    ndarray
        d [m], the shape of ``radii``.
    """
    prof = ToothProfile(gear)
    lo = max(prof.form_radius, gear.base_radius)
    nodes = np.linspace(lo, gear.tip_radius, 64)
    vals = np.empty(nodes.size)
    for i, r in enumerate(nodes):
        xc, yc = prof.involute_point(float(r))
        a1 = math.acos(min(1.0, gear.base_radius / r)) - math.atan2(xc, yc)
        vals[i] = xc / math.cos(a1)
    return np.interp(np.asarray(radii, dtype=float), nodes, vals)


def _slice_stiffness(diag: np.ndarray, width: np.ndarray, cross: np.ndarray | None
                     ) -> np.ndarray:
    """Pair stiffness per slice, (npc, n_age, ns), from per-unit-width compliances."""
    inside = width > 0
    if cross is None:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(inside, width / diag, 0.0)
    n_age = diag.shape[1]
    cmat = np.zeros(diag.shape[:1] + diag.shape[2:] + (n_age, n_age))  # (npc, ns, a, a)
    idx = np.arange(n_age)
    cmat[..., idx, idx] = np.moveaxis(np.where(inside, diag, 1.0), 1, -1)
    off = np.moveaxis(np.where(inside[:, :-1] & inside[:, 1:], cross, 0.0), 1, -1)
    cmat[..., idx[:-1], idx[1:]] = off
    cmat[..., idx[1:], idx[:-1]] = off
    q = np.linalg.solve(cmat, np.ones(cmat.shape[:-1])[..., None])[..., 0]
    return np.where(inside, width * np.moveaxis(q, -1, 1), 0.0)


def adjacent_cross(g1: Gear, g2: Gear, coupling, on: np.ndarray, r1: np.ndarray,
                   r2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Body cross compliance [m^2/N] of adjacent pairs in contact (``on``), driver and
    driven parts, each (npc, n_age - 1, ns); 0 where either pair is out of contact.

    The tooth of age m + 1 (older pair) is the +x neighbour of the driver tooth of age m
    (the drive flank faces the way the driver turns) and the -x neighbour of the driven
    tooth of age m; X is symmetric in the two loaded teeth (Maxwell).
    """
    both = on[:, :-1] & on[:, 1:]
    x1 = np.where(both, coupling.cross(g1, np.where(both, r1[:, :-1], g1.tip_radius),
                                       np.where(both, r1[:, 1:], g1.tip_radius)), 0.0)
    x2 = np.where(both, coupling.cross(g2, np.where(both, r2[:, 1:], g2.tip_radius),
                                       np.where(both, r2[:, :-1], g2.tip_radius)), 0.0)
    return x1, x2


def pair_law(pair: GearPair, settings: StiffnessSettings, lmid: np.ndarray,
             width: np.ndarray, r1: np.ndarray, r2: np.ndarray, *,
             force: float | None = None, coupling=None,
             corner: np.ndarray | None = None, separation: np.ndarray | None = None,
             rate: np.ndarray | None = None, edge: np.ndarray | None = None
             ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """The contact law and coupling of a mesh's slice contacts, as a function of the teeth.

    One law for the TVMS tables (:func:`mesh_stiffness`) and the mesh of contacts
    (:func:`gearsim.stiffness.contacts.contact_grid`): per slice contact the series
    compliance of the contact and both teeth per unit width; under ``settings.contact =
    "line"`` the contact compliance is the 2D Hertz line contact up to the tooth centre
    lines (Johnson 1985, eq. 5.79; :func:`gearsim.stiffness.tooth.line_contact_compliance`)
    at the load per unit width the contact carries, found by :data:`LINE_ITERATIONS`
    fixed-point passes from the mesh ``force`` shared by the contacts' stiffnesses; under
    ``settings.coupling = "fe"`` the pairs of a slice are coupled through both gear bodies
    (module docstring: q = C^-1 1 at a unit approach). Otherwise the load-independent
    Hertz compliance 1/k_h (seed eq. 8) and independent pairs.

    Parameters
    ----------
    pair : GearPair
        The mesh.
    settings : StiffnessSettings
        ``contact``, ``coupling``, ``plane``.
    lmid : ndarray, shape (npc, n_age, ns)
        Contact position of each slice contact along the line of action, from the
        driver's base tangent point T1 [m].
    width : ndarray, shape (npc, n_age, ns)
        Carried width of each slice contact [m] (0: not in the path of contact).
    r1, r2 : ndarray, shape (npc, n_age, ns)
        Contact radii on driver and driven gear [m] (any value where ``width`` is 0).
    force : float, optional
        Transverse line-of-action force of the mesh [N]; needed under the line contact.
    coupling : optional
        Body coupling model with ``cross(gear, r_read, r_load)`` [m^2/N]
        (:class:`gearsim.fem.coupling.FiniteElementCoupling`); needed with coupling.
    corner, separation, rate : ndarray, shape (npc, n_age, ns), optional
        Tip-corner contacts outside the path of contact (:func:`extended_grid`; their
        ``lmid``, ``r1``, ``r2`` at the nearer end of the path), their no-load
        separations [m] and closing rates [-]: the law is then :func:`extended_law`
        (line contact only).
    edge : ndarray, shape (npc, n_age, ns), optional
        Offset of each contact's Hertz centre beyond the nearer tip edge [m]
        (:func:`gearsim.geometry.corners.tip_edge_offset`): the line contact is then
        cut off by the tip corner (:func:`gearsim.stiffness.tooth.edge_truncation`).
        None: the profiles continue past their tips (the path-of-contact law).

    Returns
    -------
    callable
        ``law(teeth) -> (ks, chs)``: from the summed tooth compliances of both gears per
        unit width [m^2/N], shape (npc, n_age, ns), the stiffness of each slice contact
        [N/m] and the contact compliance per unit width used [m^2/N]. With coupling,
        ``law(teeth, factors)`` multiplies the body cross compliance of each gear by
        ``factors = (f1, f2)``, shape (npc, n_age - 1, ns) each (a cracked body's
        coupling, :func:`crack_cross_factors`).

    Raises
    ------
    InputError
        The line contact without a finite force > 0; coupling without a model.
    """
    g1, g2 = pair.driver, pair.driven
    inside = width > 0
    ch = 1.0 / hertz_stiffness(g1.material, g2.material, 1.0)  # per unit width
    line = settings.contact == "line"
    if line:
        require(force is not None and math.isfinite(force) and force > 0, "force", force,
                'the line contact law (stiffness.contact = "line") needs the mesh force, '
                "a finite number > 0 N")
        rho1 = np.where(inside, lmid, 1.0)
        rho2 = np.where(inside, pair.line_length - lmid, 1.0)
        dep1 = np.where(inside, centre_line_depth(g1, np.where(inside, r1, g1.base_radius)),
                        1.0)
        dep2 = np.where(inside, centre_line_depth(g2, np.where(inside, r2, g2.base_radius)),
                        1.0)
    cross = None
    if settings.coupling != "none":
        require(coupling is not None and hasattr(coupling, "cross"), "stiffness.coupling",
                settings.coupling, "needs a body-coupling model: pass coupling= (gearsim."
                "fem.coupling.FiniteElementCoupling) or use GearTrain.mesh_stiffness")
        x1, x2 = adjacent_cross(g1, g2, coupling, inside, r1, r2)
        cross = x1 + x2  # (npc, n_age - 1, ns)

    contact = None
    if line:
        cut = None if edge is None else np.where(inside, edge, -np.inf)

        def contact(q: np.ndarray) -> np.ndarray:
            return line_contact_compliance(np.maximum(q, 1e-3), rho1, rho2, dep1, dep2,
                                           g1.material, g2.material, settings.plane, cut)

    if corner is not None:
        require(line, "stiffness.contact", settings.contact,
                'contact outside the path needs the line contact (stiffness.contact = "line")')
        inner = extended_law(width, corner, separation, rate, ch, cross, contact, force)
    else:
        inner = slice_law(width, ch, cross, contact, force)
    if cross is None:
        return inner

    def law(teeth: np.ndarray, factors: tuple[np.ndarray, np.ndarray] | None = None
            ) -> tuple[np.ndarray, np.ndarray]:
        # factors: a cracked body's coupling, per gear (crack_cross_factors)
        if factors is None:
            return inner(teeth)
        return inner(teeth, x1 * factors[0] + x2 * factors[1])

    return law


def slice_law(width: np.ndarray, ch: float, cross: np.ndarray | None,
              contact: Callable[[np.ndarray], np.ndarray] | None, force: float | None
              ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """The law of :func:`pair_law` from its parts (external and internal meshes).

    Parameters
    ----------
    width : ndarray, shape (npc, n_age, ns)
        Carried width of each slice contact [m] (0: not in the path of contact).
    ch : float
        Load-independent contact compliance per unit width, 1/k_h [m^2/N] (seed eq. 8).
    cross : ndarray, shape (npc, n_age - 1, ns), or None
        Summed body cross compliance of both gears between the pairs of age m and m + 1
        per unit width [m^2/N] (coupled pairs, q = C^-1 1), or None (independent pairs).
    contact : callable or None
        ``contact(q)``: the contact compliance per unit width [m^2/N] at the load per unit
        width q [N/m] of each slice contact (shape of ``width``); None: ``ch``.
    force : float or None
        Line-of-action force of the mesh [N] shared by the contacts (with ``contact``).

    Returns
    -------
    callable
        ``law(teeth) -> (ks, chs)`` as :func:`pair_law`'s; with ``contact``,
        :data:`LINE_ITERATIONS` fixed-point passes on the load per unit width
        q = F k_slice / (k_mesh w) of each contact. ``law(teeth, cross_now)`` takes the
        cross compliance ``cross_now`` (same shape) in place of ``cross``.
    """
    inside = width > 0
    shape = width.shape

    def law(teeth: np.ndarray, cross_now: np.ndarray | None = None
            ) -> tuple[np.ndarray, np.ndarray]:
        cx = cross if cross_now is None else cross_now
        chs = np.full(shape, ch)
        ks = _slice_stiffness(chs + teeth, width, cx)
        if contact is not None:
            # fixed point on the load per unit width of each contact (ln dependence:
            # three passes change k by < 1e-6)
            for _ in range(LINE_ITERATIONS):
                kt = ks.sum(axis=(1, 2))
                with np.errstate(divide="ignore", invalid="ignore"):
                    q = np.where(width > 0, force * ks / (kt[:, None, None] * width), 1.0)
                chs = np.where(inside, contact(q), ch)
                ks = _slice_stiffness(chs + teeth, width, cx)
        return ks, chs

    return law


#: Largest number of active-set passes of :func:`extended_law` on the tip-corner
#: contacts (a slice has at most two candidate corners, so two or three passes settle it;
#: the cap only guards against cycling).
CORNER_PASSES = 8
#: Fixed-point passes on the outgoing corner's separation delta* = s(c + delta*)
#: (:func:`extended_grid`): the contraction factor is s' < 0.1 where a corner can close
#: under load (19/48 at 400 N m), so six passes leave < 1e-6 of it.
SEPARATION_PASSES = 6


def extended_grid(pair: GearPair, settings: StiffnessSettings
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                             int, int, int, np.ndarray]:
    """Slice contacts on and just outside the path of contact (tip corners), point sampled.

    Pair age a = m + first (first = -1) at position u of a cycle has its slice centre
    at c = l_A + (u + a) p_b - z tan(beta_b). On the path (l_A <= c <= l_E) it is an
    involute contact at c; within one base pitch before l_A (incoming pair: the driven
    tip corner against the driver flank) or after l_E (outgoing pair: the driver tip
    corner against the driven flank), and between the base tangent points T1 and T2, it
    is a tip-corner contact with the no-load separation of
    :func:`gearsim.geometry.corners.corner_separation` (Litvin & Fuentes 2004, ch. 10;
    zero at l_A and l_E, quadratic away from them) and the contact law and teeth of the
    nearer path end (``lmid`` = l_A or l_E).

    Position convention: as in the FE gear pair, the driven gear stays at its kinematic
    angle of the position and the driver turns by the deflection (separation and
    closing rate of :func:`corner_closing`). The stiffness is then continuous across
    l_A and l_E (the corner's law at separation 0 is the path end's), so the samples
    are points, not the in-path cell fractions of :func:`in_path_fraction` (those
    average a jump that the tip-corner contact removes).

    Parameters
    ----------
    pair : GearPair
        The mesh.
    settings : StiffnessSettings
        Positions per cycle and slices.

    Returns
    -------
    lmid, width, corner, separation, rate, n_age, first, ns, zfrac, edge
        Contact point for the law (clipped to the path) [m], slice width of each
        existing contact (0: none) [m], tip-corner flags, no-load separations [m] and
        closing rates [-] (1 on the path and before it), all (npc, n_age, ns); number of
        ages, age of the first column (-1), slices, slice centres over the face width
        [-]; the offset of each contact's Hertz centre beyond the nearer tip edge [m]
        (:func:`gearsim.geometry.corners.tip_edge_offset`, (npc, n_age, ns)). The grid
        depends on the geometry alone: it is computed once per pair and grid
        (:data:`EXTENDED_GRID_CACHE_SIZE` kept, about 4.5 ms each for Table-1 mesh I at
        40 x 40) and its arrays are read-only.
    """
    return _extended_grid(pair, settings.positions_per_cycle, settings.slices)


#: Grids of :func:`extended_grid` kept per process (pairs x grids of a study or a run).
EXTENDED_GRID_CACHE_SIZE = 32


@lru_cache(maxsize=EXTENDED_GRID_CACHE_SIZE)
def _extended_grid(pair: GearPair, npc: int, slices: int):
    """:func:`extended_grid` of ``pair`` at ``npc`` positions per cycle and ``slices``."""
    tb = math.tan(pair.driver.base_helix_angle)
    b = pair.face_width
    pb = pair.base_pitch
    la, le, big_l = pair.start_of_contact, pair.end_of_contact, pair.line_length
    ns = slices if tb > 0 else 1
    first = -1
    n_age = int(math.ceil((le - la) / pb + b * tb / pb)) + 3
    u = np.arange(npc) / npc
    age = u[:, None] + (np.arange(n_age) + first)[None, :]
    dz = b / ns
    zc = (np.arange(ns) + 0.5) * dz
    centre = la + age[:, :, None] * pb - zc[None, None, :] * tb
    path = (centre >= la) & (centre <= le)
    corner = ~path & (((centre < la) & (centre > max(la - pb, 0.0)))
                      | ((centre > le) & (centre < min(le + pb, big_l))))
    sep, rate = corner_closing(pair, np.where(corner, centre, la))
    corner = corner & (rate > 0)  # a corner the turning driver cannot close
    width = np.where(path | corner, dz, 0.0)
    edge = np.where(width > 0, tip_edge_offset(pair, np.where(width > 0, centre, la)), 0.0)
    arrays = (np.clip(centre, la, le), width, corner, np.where(corner, sep, 0.0),
              np.where(corner, rate, 1.0), zc / b, edge)
    for arr in arrays:
        arr.flags.writeable = False  # shared by every table of this pair and grid
    return (*arrays[:5], n_age, first, ns, arrays[5], arrays[6])


def corner_closing(pair: GearPair, l: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Separation and closing rate of tip-corner contacts with the driven gear held [m, -].

    As in the FE gear pair (:mod:`gearsim.fem.pair`), the driven gear stays at its
    kinematic angle of the position and the driver turns by the deflection delta
    (line-of-action units). The incoming corner's separation of
    :func:`gearsim.geometry.corners.corner_separation` is that rotation already (rate
    1). The outgoing corner's is given there as a rotation of the driven gear; turning
    the driver instead advances the mesh by delta too, so the corner closes at
    delta* = s(l + delta*) (fixed point, :data:`SEPARATION_PASSES` passes) and beyond it
    its gap closes at the rate rho = 1 - s'(l + delta*) per unit delta: the ratio of the
    driver's moment arm about the corner's contact normal (not the line of action) to
    r_b1 (Litvin & Fuentes 2004, ch. 10, for the involute geometry). The corner's normal
    load f then carries rho f of the line-of-action force, so its stiffness along the
    line of action is rho^2 times its normal stiffness.

    Parameters
    ----------
    pair : GearPair
        The mesh.
    l : ndarray
        Positions on the extended line of action, from T1 [m], outside [l_A, l_E] and
        between T1 and T2.

    Returns
    -------
    separation, rate : ndarray
        Separation along the line of action [m] and closing rate [-] (<= 0: a corner the
        turning driver cannot close), the shape of ``l``.
    """
    l = np.asarray(l, dtype=float)
    le, pb = pair.end_of_contact, pair.base_pitch
    sep = corner_separation(pair, l)
    rate = np.ones(l.shape)
    out = l > le
    if np.any(out):
        c = l[out]
        h = 1e-3 * pb  # central-difference step of s'
        top = min(le + pb, pair.line_length) - 2 * h
        s_out = sep[out]
        for _ in range(SEPARATION_PASSES):
            s_out = corner_separation(pair, np.minimum(c + s_out, top))
        x = np.minimum(c + s_out, top)
        slope = (corner_separation(pair, x + h) - corner_separation(pair, x - h)) / (2 * h)
        sep[out] = s_out
        rate[out] = 1.0 - slope
    return sep, rate


def extended_law(width: np.ndarray, corner: np.ndarray, separation: np.ndarray,
                 rate: np.ndarray, ch: float, cross: np.ndarray | None,
                 contact: Callable[[np.ndarray], np.ndarray], force: float
                 ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """The law of :func:`slice_law` with tip-corner contacts that close under load.

    At each position the mesh deflects by delta along the line of action under the force
    F; a contact j with per-unit-width compliance matrix C (diagonal: contact plus both
    teeth; off-diagonal: body cross compliance of adjacent pairs, as in
    :func:`slice_law`), width w_j, no-load separation s_j and closing rate rho_j (0 and 1
    on the path; the tip corner's outside it, :func:`extended_grid`) carries the normal
    load per unit width q_j >= 0, with

        (C q)_j = rho_j (delta - s_j)  (closed),
        q_j = 0 and rho_j (delta - s_j) < (C q)_j  (open),
        sum_j w_j rho_j q_j = F,

    the static equilibrium of the loaded mesh (the deflection that carries F when the
    loaded transmission error exceeds a corner's separation, as in the FE gear pair).
    For an active set A, with a = C_AA^-1 rho_A and b = C_AA^-1 (rho s)_A:
    q_A = delta a - b and delta = (F + w rho . b) / (w rho . a); a corner opens when its
    q < 0 and closes when its gap is negative (at most :data:`CORNER_PASSES` passes).
    The line contact compliance of every closed contact follows its load per unit width
    by :data:`LINE_ITERATIONS` fixed-point passes (an open corner keeps the
    compliance of the previous pass). The mesh stiffness is the secant F / delta, the
    quantity the FE gear pair computes; contact j's share of it is w_j rho_j q_j / delta.
    The active-set passes of a fixed-point pass are compiled
    (:func:`gearsim.stiffness._kernels.extended_law_solve`, on numba's threads from
    :data:`THREADED_MIN_CONTACTS` slice contacts per cycle when numba has more than one).

    Tip-corner contact law: the 2D line contact of the nearer path end
    (:func:`gearsim.stiffness.tooth.line_contact_compliance`, Johnson 1985 eq. 5.79:
    radii of curvature and centre-line depths at l_A or l_E) at the corner's own load
    per unit width, cut off by the tip edge (:func:`gearsim.stiffness.tooth.
    edge_truncation`, with the offsets of :func:`gearsim.geometry.corners.
    tip_edge_offset` passed in ``contact``): the corner touches the mating flank at the
    end of its involute, its own flank leaving the mating one at a small angle, and
    the path contacts within a Hertz half width of a tip are cut off by it the same
    way. At the path ends both are the involute contact whose centre lies on the edge,
    so the stiffness is continuous across l_A and l_E (docs/stiffness.md, section 4c,
    "The tip edge").

    Parameters
    ----------
    width : ndarray, shape (npc, n_age, ns)
        Width of each slice contact [m] (0: none).
    corner : ndarray of bool, shape (npc, n_age, ns)
        Tip-corner contacts (outside the path).
    separation : ndarray, shape (npc, n_age, ns)
        No-load separation of each contact along the line of action [m].
    rate : ndarray, shape (npc, n_age, ns)
        Closing rate of each contact per unit delta [-] (1 on the path).
    ch : float
        Load-independent contact compliance per unit width, 1/k_h [m^2/N]: the start of
        the fixed point.
    cross : ndarray, shape (npc, n_age - 1, ns), or None
        Body cross compliance between ages m and m + 1 per unit width [m^2/N].
    contact : callable
        ``contact(q)``: line contact compliance per unit width [m^2/N] at the load per
        unit width q [N/m].
    force : float
        Line-of-action force of the mesh [N].

    Returns
    -------
    callable
        ``law(teeth) -> (ks, chs)``: the share of each slice contact in the secant mesh
        stiffness [N/m] (0 for an open corner) and the contact compliance per unit
        width used [m^2/N], both (npc, n_age, ns). ``law(teeth, cross_now)`` takes the
        cross compliance ``cross_now`` (same shape) in place of ``cross``.
    """
    exists = width > 0
    path = exists & ~corner
    cand = exists & corner
    s_pos = np.where(cand, separation, 0.0)
    rho = np.where(cand, rate, 1.0)
    npc = width.shape[0]
    no_cross = np.zeros((npc, 0, 0))

    def law(teeth: np.ndarray, cross_now: np.ndarray | None = None
            ) -> tuple[np.ndarray, np.ndarray]:
        cx = cross if cross_now is None else cross_now
        coupled = cx is not None
        cx = np.ascontiguousarray(cx, dtype=float) if coupled else no_cross
        chs = np.full(width.shape, ch)
        act = path.copy()
        q = np.zeros(width.shape)
        delta = np.empty(npc)
        threads = numba.get_num_threads()
        for it in range(LINE_ITERATIONS + 1):
            if it:
                chs = np.where(exists & (q > 0), contact(np.where(q > 0, q, 1.0)), chs)
            cdiag = chs + teeth
            # the active-set passes of all positions (compiled: the numpy law's operations
            # in its order, so the same tables to the bit)
            args = (cdiag, act, path, cand, width, rho, s_pos, cx, coupled, float(force),
                    CORNER_PASSES, q, delta)
            if threads > 1 and width.size >= THREADED_MIN_CONTACTS:
                _kernels.extended_law_solve_threads(*args, min(threads, npc))
            else:
                _kernels.extended_law_solve(*args)
        ks = np.where(act, width * rho * q / delta[:, None, None], 0.0)
        return ks, chs

    return law


#: Slice contacts of a cycle (positions x pair ages x slices) from which
#: :func:`extended_law` solves on numba's threads, one run of positions per thread: the
#: active-set solve costs about 17 ns a contact (Table-1 mesh I at 40 x 7 x 40: 0.19 ms
#: a fixed-point pass on one thread, 0.10 ms on two); below ~2000 the waking of the
#: other threads costs as much as it saves (measured 2026-11-28, 2-core machine at load 0.5).
THREADED_MIN_CONTACTS = 2048


def _tridiagonal_solve(diag: np.ndarray, off: np.ndarray, *rhs: np.ndarray
                       ) -> tuple[np.ndarray, ...]:
    """Solve symmetric tridiagonal systems along axis 1 (Thomas algorithm).

    The compliance matrix of the pairs of a slice is tridiagonal (the body couples
    adjacent pairs only) and diagonally dominant (a cross compliance is a few per cent of
    a pair's compliance), so elimination without pivoting is stable (Golub & Van Loan,
    Matrix Computations, 4th ed., sec. 4.3). Compiled:
    :func:`gearsim.stiffness._kernels.tridiagonal_solve`.

    Parameters
    ----------
    diag : ndarray, shape (n, m, ...)
        Diagonal [m^2/N].
    off : ndarray, shape (n, m - 1, ...)
        Off-diagonal between rows i and i + 1 [m^2/N].
    *rhs : ndarray, shape of ``diag``
        Right-hand sides.

    Returns
    -------
    tuple of ndarray
        The solutions, shape of ``diag``, one per right-hand side.
    """
    shape = diag.shape
    n, m = shape[:2]
    k = math.prod(shape[2:])
    d3 = np.ascontiguousarray(diag, dtype=float).reshape(n, m, k)
    o3 = np.ascontiguousarray(off, dtype=float).reshape(n, m - 1, k)
    r4 = np.ascontiguousarray(np.stack(rhs, axis=1), dtype=float).reshape(n, len(rhs), m, k)
    out = _kernels.tridiagonal_solve(d3, o3, r4, np.empty(r4.shape))
    return tuple(out[:, j].reshape(shape) for j in range(len(rhs)))


def crack_cross_factors(pair: GearPair, model, cracks: tuple[ToothCrack, ...],
                        settings: StiffnessSettings, r1: np.ndarray, r2: np.ndarray,
                        inside: np.ndarray, zfrac: np.ndarray) -> Callable | None:
    """Factors of a cracked gear body on the coupling of the pairs beside a cracked tooth.

    The body coupling X of adjacent pairs (:func:`pair_law`) is measured on the healthy
    gear; a crack in the fillet of a tooth changes how that tooth and its neighbours
    deflect each other through the rim. A compliance model with a ``cross_factor``
    method (:meth:`gearsim.fem.calibration.CalibratedCompliance.cross_factor`, measured
    with the same FE solves as its crack correction) gives the factor G on X of the
    pair between the cracked tooth and each neighbour: for the cracked tooth at age a
    of the driver, column a - 1 (the younger neighbour read, the cracked tooth its
    loaded ``+x`` neighbour) and column a (the cracked tooth read, its ``+x`` neighbour
    of age a + 1 loaded); of the driven gear, whose older pair is the ``-x`` neighbour,
    columns a and a - 1 the other way round (docs/stiffness.md 4c).

    Parameters
    ----------
    pair : GearPair
        The mesh.
    model
        The tooth-compliance model; without ``cross_factor`` there is no factor.
    cracks : tuple of ToothCrack
        The cracks of the mesh.
    settings : StiffnessSettings
        ``coupling`` (none: no factor), ``closure``, ``plane``.
    r1, r2 : ndarray, shape (npc, n_age, ns)
        Contact radii on driver and driven gear of each slice contact [m].
    inside : ndarray of bool, shape (npc, n_age, ns)
        The slice contacts that exist (elsewhere the radii are not used).
    zfrac : ndarray, shape (ns,)
        Axial position of each slice centre / face width [-].

    Returns
    -------
    callable or None
        ``factors(i1, i2)``: from the tooth index of each age column of both gears in a
        mesh cycle, None (no cracked tooth with a factor) or ``(f1, f2)``, the factors
        on the cross compliance of each gear, shape (npc, n_age - 1, ns) (products when
        several cracked teeth meet, each measured alone). None when no crack of the
        mesh takes a factor.
    """
    if settings.coupling == "none" or not hasattr(model, "cross_factor") or not cracks:
        return None
    g1, g2 = pair.driver, pair.driven
    ra = (np.where(inside, r1, g1.tip_radius), np.where(inside, r2, g2.tip_radius))
    n_col = inside.shape[1] - 1
    memo: dict[tuple[int, int, int], np.ndarray | None] = {}

    def columns(tc: ToothCrack, a: int) -> np.ndarray | None:
        key = (tc.gear, tc.crack.tooth, a)
        if key not in memo:
            gear, rad = (g1, ra[0]) if tc.gear == 1 else (g2, ra[1])
            # (column, age read, age loaded, the cracked tooth is the one read)
            cols = (((a - 1, a - 1, a, False), (a, a, a + 1, True)) if tc.gear == 1 else
                    ((a, a + 1, a, False), (a - 1, a, a - 1, True)))
            f = None
            for col, read, load, reads in cols:
                if not 0 <= col < n_col:
                    continue
                g = model.cross_factor(gear, rad[:, read], rad[:, load], tc, reads, zfrac,
                                       settings)
                if g is None:
                    continue
                if f is None:
                    f = np.ones(inside[:, :-1].shape)
                f[:, col] = g
            memo[key] = f
        return memo[key]

    if all(columns(tc, 0) is None and columns(tc, n_col) is None for tc in cracks):
        return None

    def factors(i1, i2) -> tuple[np.ndarray, np.ndarray] | None:
        out = None
        for tc in cracks:
            for a, tooth in enumerate(i1 if tc.gear == 1 else i2):
                if int(tooth) != tc.crack.tooth:
                    continue
                f = columns(tc, a)
                if f is None:
                    continue
                if out is None:
                    out = [np.ones(inside[:, :-1].shape), np.ones(inside[:, :-1].shape)]
                out[tc.gear - 1] = out[tc.gear - 1] * f
        return None if out is None else (out[0], out[1])

    return factors


def assemble_revolution(teeth: tuple[int, int], z_rev: int, npc: int,
                        healthy: tuple[np.ndarray, np.ndarray],
                        cracked: tuple[dict[int, np.ndarray], dict[int, np.ndarray]],
                        width: np.ndarray, pairs: Callable, first: int = 0,
                        cross_factors: Callable | None = None
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mesh stiffness over ``z_rev`` mesh cycles from the tooth compliances of one cycle.

    In cycle c the pair of age m has tooth (c - m) mod z_i of gear i (its cracked
    compliance when that tooth is cracked); the slices of a pair act in series with the
    contact and in parallel with each other, the pairs in parallel; a component's share
    is that of the compliance-weighted sum (module docstring).

    Parameters
    ----------
    teeth : tuple of int
        Tooth counts (z_1, z_2).
    z_rev : int
        Mesh cycles to cover.
    npc : int
        Positions per cycle.
    healthy : tuple of ndarray
        Per-unit-width compliances of a healthy tooth of each gear, (npc, n_age, ns, 4)
        (bending, shear, axial, foundation) [m^2/N].
    cracked : tuple of dict
        The same for cracked teeth, by tooth index.
    width : ndarray, shape (npc, n_age, ns)
        In-path width of each slice contact [m] (0 outside the path).
    pairs : callable
        ``pairs(teeth_compliance) -> (ks, contact)``: the slice stiffnesses [N/m] and the
        contact compliance per unit width used, both (npc, n_age, ns), from the summed
        tooth compliances of both gears.
    first : int
        Age of the first column (-1 with the tip-corner contacts of
        :func:`extended_grid`: the pair before the path of contact).
    cross_factors : callable, optional
        ``cross_factors(i1, i2)`` of :func:`crack_cross_factors`: the cracked body's
        factors on the coupling of a cycle, passed to ``pairs(teeth, factors)`` when not
        None.

    Returns
    -------
    k, components, pair_k, tooth1, tooth2 : ndarray
        Shapes (n,), (n, 9), (n, n_age), (n, n_age) twice, n = z_rev npc.
    """
    n_age = width.shape[1]
    n_pos = z_rev * npc
    k = np.zeros(n_pos)
    comp = np.zeros((n_pos, len(COMPONENTS)))
    pair_k = np.zeros((n_pos, n_age))
    t1 = np.zeros((n_pos, n_age), dtype=np.int64)
    t2 = np.zeros((n_pos, n_age), dtype=np.int64)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_w = np.where(width > 0, 1.0 / width, 0.0)
    # a cycle's result depends only on which tables its pairs use (healthy or a cracked
    # tooth's): the cycles whose teeth are all healthy are computed once and copied
    done: dict[tuple, slice] = {}
    for c in range(z_rev):
        sl = slice(c * npc, (c + 1) * npc)
        i1 = [(c - m - first) % teeth[0] for m in range(n_age)]
        i2 = [(c - m - first) % teeth[1] for m in range(n_age)]
        t1[sl] = i1
        t2[sl] = i2
        key = (tuple(i if i in cracked[0] else -1 for i in i1),
               tuple(i if i in cracked[1] else -1 for i in i2))
        if key in done:
            src = done[key]
            k[sl], pair_k[sl], comp[sl] = k[src], pair_k[src], comp[src]
            continue
        done[key] = sl
        c1 = np.empty(healthy[0].shape)
        c2 = np.empty(healthy[1].shape)
        for m in range(n_age):
            c1[:, m] = cracked[0].get(i1[m], healthy[0])[:, m]
            c2[:, m] = cracked[1].get(i2[m], healthy[1])[:, m]
        f = cross_factors(i1, i2) if cross_factors is not None else None
        ks, chs = pairs(c1.sum(-1) + c2.sum(-1)) if f is None else pairs(
            c1.sum(-1) + c2.sum(-1), f)
        kt = ks.sum(axis=(1, 2))
        k[sl] = kt
        pair_k[sl] = ks.sum(axis=2)
        share2 = (ks / kt[:, None, None]) ** 2
        parts = [chs] + [c1[..., q] for q in range(4)] + [c2[..., q] for q in range(4)]
        with np.errstate(divide="ignore"):  # a zero component (FE source) -> inf stiffness
            for q, part in enumerate(parts):
                comp[sl, q] = 1.0 / np.sum(share2 * part * inv_w, axis=(1, 2))
    return k, comp, pair_k, t1, t2


def mesh_stiffness(pair: GearPair, *, cracks: tuple[ToothCrack, ...] = (),
                   settings: StiffnessSettings | None = None,
                   revolution_of: int = 1,
                   compliance: ToothCompliance | None = None,
                   force: float | None = None, coupling=None) -> MeshStiffness:
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
    force
        Transverse line-of-action force of the mesh [N]; needed by the line contact
        law (``settings.contact = "line"``), whose compliance depends on the load.
    coupling
        Body coupling of neighbouring teeth, an object with a method
        ``cross(gear, r_read, r_load)`` (:class:`gearsim.fem.coupling.
        FiniteElementCoupling`); needed when ``settings.coupling = "fe"``.

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
    # contact outside the path (tip corners) under the load-dependent line contact law;
    # the seed's load-independent law keeps the path of contact (docs/stiffness.md 4c)
    extended = settings.contact == "line" and settings.corner_contact
    first, corner, sep, rate, edge = 0, None, None, None, None
    if extended:
        lmid, width, corner, sep, rate, n_age, first, ns, zfrac, edge = extended_grid(
            pair, settings)
        inside = width > 0
    else:
        lmid, frac, dz, n_age, ns, zfrac = _slice_grid(pair, settings)
        inside = frac > 0
    npc = settings.positions_per_cycle
    r1 = np.where(inside, np.hypot(g1.base_radius, lmid), 0.0)
    r2 = np.where(inside, np.hypot(g2.base_radius, pair.line_length - lmid), 0.0)

    def table(gear, radii: np.ndarray, tc: ToothCrack | None) -> np.ndarray:
        if corner is None:
            return model.compliance(gear, radii, tc, zfrac, settings)
        # a tip-corner contact takes the teeth at its path end: two radii per slice
        out = model.compliance(gear, np.where(corner, 0.0, radii), tc, zfrac, settings)
        before = corner & (lmid <= pair.start_of_contact)
        ends = np.stack([radii[before].max(initial=0.0), radii[corner & ~before].max(
            initial=0.0)])
        at = model.compliance(gear, np.broadcast_to(ends[:, None], (2, ns)), tc, zfrac,
                              settings)
        return np.where(before[..., None], at[0], np.where((corner & ~before)[..., None],
                                                             at[1], out))

    healthy1 = table(g1, r1, None)
    healthy2 = table(g2, r2, None)
    cracked1: dict[int, np.ndarray] = {}
    cracked2: dict[int, np.ndarray] = {}
    for tc in cracks:
        gear, radii, store = (g1, r1, cracked1) if tc.gear == 1 else (g2, r2, cracked2)
        store[tc.crack.tooth] = table(gear, radii, tc)

    if not extended:
        width = frac * dz  # carried face width of each slice [m]
    pairs = pair_law(pair, settings, lmid, width, r1, r2, force=force, coupling=coupling,
                     corner=corner, separation=sep, rate=rate, edge=edge)

    z_rev = g1.teeth if revolution_of == 1 else g2.teeth
    factors = crack_cross_factors(pair, model, cracks, settings, r1, r2, width > 0, zfrac)
    k, comp, pair_k, t1, t2 = assemble_revolution(
        (g1.teeth, g2.teeth), z_rev, npc, (healthy1, healthy2), (cracked1, cracked2), width,
        pairs, first, factors)
    n_pos = z_rev * npc
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
               "gauss_points": settings.gauss_points, "source": model.name,
               "contact": settings.contact, "coupling": settings.coupling,
               **({"force": float(force), "corner_contact": int(extended)}
                  if settings.contact == "line" else {})},
    )
