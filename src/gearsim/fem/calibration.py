"""The PE tooth calibrated by the FE tooth once per gear (``stiffness.source = "calibrated"``).

The potential-energy tooth (:mod:`gearsim.stiffness.tooth`: beam from the root circle,
Sainsot foundation) is 12-15 % softer than the finite-element tooth
(:mod:`gearsim.fem.tooth`; docs/fem.md, "FE versus potential energy"), and the FE tooth
with the 2D line contact and the FE body coupling is within about 2 % of the FE gear
pair inside the contact zones (docs/stiffness.md, section 4b). The calibrated tooth keeps
the PE computation and multiplies it by the ratio of the two healthy teeth,

    c_cal(r, crack) = c_PE(r, crack) * R(r),   R(r) = c_FE,healthy(r) / c_PE,healthy(r),

R measured once per gear at the :data:`~gearsim.fem.tables.NODES` radii of the FE tables
(:func:`~gearsim.fem.tables.fe_nodes`, equally spaced in roll length from the form circle
to the tip) and interpolated with a cubic spline in roll length. Slicing, helical gears
and a crack profile along the face width stay the PE computation; the four PE
components are scaled alike, so their split is the PE model's.

A crack on the loaded flank (:data:`CORRECTED_SIDES`) is further corrected by its
measured effect: the PE section reduction costs less stiffness than the FE slit (FE
crack factor 1.15-1.19 against PE 1.05-1.08 for the 1 mm crack of the 19/48 pinion,
docs/stiffness.md 4c), so

    c_cal(r, crack) = c_PE(r, crack) * R(r) * Q(r, q),
    Q(r, q) = F_FE(r, q) / F_PE(r, q),   F = c_crack / c_healthy (per tooth model),

F_FE measured with the FE tooth (the one of ``source = "fe"``) once per gear and crack
family (start point, angle, side, closure) at the :data:`CRACK_GRID` depths up to the
centre line (:func:`crack_factor_table`), interpolated with a not-a-knot cubic spline in
depth (F_FE(0) = 1) and a cubic spline in roll length; F_PE is the PE tooth's own at the
contact point. So c_cal,crack = R c_PE,healthy F_FE: the calibrated healthy tooth times
the FE crack factor, at each slice's local depth. Past the deepest grid depth (the FE
tooth takes no crack past the centre line) Q keeps its value there. The closed crack on
the unloaded flank stays the PE section reduction (within 3 % of the FE pair without Q;
docs/stiffness.md 4c).

The same FE solves read the cracked tooth's two neighbours: a crack that Q corrects also
changes the body coupling of the pairs beside the cracked tooth (:meth:`CalibratedCompliance.
cross_factor`; with the loaded-flank crack of the Table-1 input gear, 6 mm, the coupling
to the neighbour behind the cracked tooth grows to 1.16-1.34 times the healthy one, the
crack faces open under both teeth's loads; across the crack, to the neighbour its loaded
flank faces, 0.64-0.81 times with the faces open but 0.96-1.10 when that neighbour's
load closes them, so only the pair away from the crack takes a factor; docs/stiffness.md
4c). The body coupling of the mesh (:class:`gearsim.fem.coupling.FiniteElementCoupling`)
is multiplied there by

    G_load(r_i, r_j, q) = X_crack(tooth -1 at r_i; load on the cracked tooth at r_j)
                          / X_healthy(same),
    G_read(r_i, r_j, q) = X_crack(tooth +1 at r_j; load on the cracked tooth at r_i)
                          / X_healthy(same)   (Maxwell: the cracked tooth read at r_i
                                               under the load on tooth +1 at r_j),

interpolated as F_FE (spline in depth through G(0) = 1, bicubic spline in roll length).

Cache: ``calibration_dir()``, ``$GEARSIM_CACHE/fe/calibration/`` (or
``~/.cache/gearsim/fe/calibration/``), one ``.npz`` per key, the SHA-256 of the gear
geometry and material, plane, FE level, Gauss points of the PE integration, the FE table
and calibration versions and the gearsim version. Each file carries its key document, its
radii and ratio; a file that cannot be read, whose document differs from the expected one,
whose radii are not the gear's nodes or whose ratio is not finite and in
(:data:`RATIO_BOUNDS`) is stale or corrupt: it is recomputed and overwritten, never used.
The FE tooth values come from :func:`gearsim.fem.tables.fe_compliance` solved afresh
(not from the FE-table cache, whose key does not name the gearsim version), once per
calibration entry. The crack factors are cached the same way (``crack-<key>.npz``, key
with the crack family, the depth grid and :data:`CRACK_CORRECTION_VERSION`; a file
whose depths are not the gear's grid or whose factors are not finite and in
:data:`CRACK_FACTOR_BOUNDS` is rebuilt, never used).

The ring tooth of a planetary stage (:class:`CalibratedRingTooth`) is corrected by the
FE ring segment of :mod:`gearsim.fem.ring` (tooth on a 3.5 m_n rim clamped outside,
root fillets), measured once per ring geometry at :data:`~gearsim.fem.tables.NODES`
radii equally spaced in roll length from the ring's tip circle to where its involute meets
the root fillet. The correction is additive, in the foundation column:

    c_cal,ring(r, crack) = c_PE,beam(r, crack) + [c_FE,ring(r) - c_PE,beam,healthy(r)],

c_PE,beam the bending, shear and axial terms of the ring tooth clamped on its root circle
(:class:`gearsim.stiffness.ring.RingToothModel`, ``foundation="none"``): the FE excess is
the deflection of the rim and the root fillet, which the cantilever leaves out
(docs/planetary.md 4.3) and which a crack in the tooth does not scale; a ratio would
multiply a crack's effect by the FE/PE ratio of 1.35-2.65. The same FE solutions give the
cross compliance of neighbouring ring teeth through the rim (the body coupling of the
internal mesh, :func:`gearsim.fem.ring.fe_ring_tooth_result`), cached with it; the
cache rules are those of the external calibration (key with geometry, material, plane,
level, Gauss points, rim, segment and versions; a file that does not load or differs is
rebuilt, never used).

References
----------
.. [ChenShao2013] Z. Chen, Y. Shao, Mesh stiffness of an internal spur gear pair with ring
   gear rim deformation, Mech. Mach. Theory 69 (2013) 1-12 (the ring tooth as a
   cantilever on its root circle, which the FE segment corrects).
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004)
   748-752 (the foundation term of the PE tooth that the ratio corrects, with the beam).
.. [Seed] eqs. 3-8 (the PE tooth).
"""

from __future__ import annotations

import contextlib
import math
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline, RectBivariateSpline

from gearsim._version import __version__
from gearsim.errors import InputError, SimulationError, require, warn_model_range
from gearsim.fem.coupling import fe_neighbour_coupling
from gearsim.fem.geometry import SectorOptions, element_size
from gearsim.fem.ring import (
    RIM_THICKNESS,
    ROOT_FILLET,
    fe_ring_tooth_result,
    ring_involute_limit,
)
from gearsim.fem.tables import (
    CACHE_VERSION,
    DEFAULT_LEVEL,
    NODES,
    _cache_key,
    _gear_key,
    _level_for,
    _read_npz,
    _write_npz,
    cache_dir,
    fe_compliance,
)
from gearsim.fem.tables import fe_nodes as _fe_nodes
from gearsim.fem.tooth import check_crack_resolved, fe_tooth_compliance
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.planetary import RingGear
from gearsim.geometry.profile import ToothProfile
from gearsim.io.atomic import exclusive
from gearsim.stiffness.crack import Crack, crack_geometry, crack_record
from gearsim.stiffness.ring import RingToothModel
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCrack
from gearsim.stiffness.tooth import ToothModel

__all__ = ["CALIBRATION_VERSION", "CORRECTED_SIDES", "CRACK_CORRECTION_VERSION",
           "CRACK_FACTOR_BOUNDS", "CRACK_GRID", "CROSS_FACTOR_BOUNDS", "RATIO_BOUNDS",
           "RING_CALIBRATION_VERSION", "RING_RATIO_BOUNDS", "CalibratedCompliance",
           "CalibratedRingTooth", "calibration_dir", "calibration_key", "calibration_ratio",
           "crack_correction_key", "crack_cross_table", "crack_depths", "crack_factor_table",
           "ring_calibration", "ring_calibration_key", "ring_nodes"]

#: Bump when the calibration changes so that old cache files are not reused.
CALIBRATION_VERSION = 1
#: Plausible range of FE / PE tooth compliance [-]: measured 0.85-0.95 on the 19/48 and
#: Table-1 gears (docs/fem.md); a cached ratio outside (0.2, 5) is treated as corrupt.
RATIO_BOUNDS = (0.2, 5.0)

#: Bump when the ring calibration changes so that old cache files are not reused.
RING_CALIBRATION_VERSION = 1
#: Plausible range of the FE ring tooth over the PE beam terms of the ring tooth [-]:
#: measured 1.42-5.04 over the involute of three rings (5 at its root end, where the beam
#: terms vanish and the rim stays); a cached entry outside (0.5, 20) is treated as corrupt.
RING_RATIO_BOUNDS = (0.5, 20.0)
#: Teeth of the FE ring segment of the ring calibration (the loaded one in the middle;
#: 5 -> 7 teeth changes the tooth compliance by < 1.3 %, docs/planetary.md 4.3).
RING_SEGMENT_TEETH = 5

#: Bump when the crack correction changes so that old cache files are not reused.
#: 2: the entry also holds the crack's body-coupling factors (``cross_load``,
#: ``cross_read``).
CRACK_CORRECTION_VERSION = 2
#: Depths of the measured crack correction as fractions of q_c, the depth at which the
#: crack tip reaches the tooth centre line (:func:`crack_depths`; 0.99: the FE tooth
#: refuses a tip on the line); with F_FE(0) = 1 a not-a-knot cubic spline in depth
#: through 5 points. Against FE at 11 depths 0.1-0.999 q_c (19/48 pinion, Table-1 input
#: gear, working flank) it is within 0.29 % of F_FE at 0.2 q_c and 0.41 % at any depth
#: up to 0.95 q_c; 3 depths (0.3, 0.7, top) 1.0 % at 0.1 q_c, 5 depths (0.1, 0.3, 0.6,
#: 0.8, top) 0.27 % (docs/stiffness.md 4c). One FE solve per depth.
CRACK_GRID = (0.1, 0.3, 0.6, 0.99)
#: Plausible range of the FE crack factor c_FE,crack / c_FE,healthy [-]: measured
#: 0.99-2.9 (19/48 pinion and Table-1 input gear, cracks up to the centre line); a cached
#: factor outside (0.5, 20) is treated as corrupt.
CRACK_FACTOR_BOUNDS = (0.5, 20.0)
#: Sides of a crack the correction applies to (+1 loaded flank, -1 the other).
CORRECTED_SIDES = (1,)
#: Plausible range of the crack's body-coupling factor G = X_crack / X_healthy [-]:
#: measured 0.64-1.34 (Table-1 input gear, 6 mm loaded-flank crack, 0.65 q_c); a cached
#: factor outside (0.05, 20) is treated as corrupt.
CROSS_FACTOR_BOUNDS = (0.05, 20.0)

#: Interpolants already read in this process, by cache key (the disk is read once).
_MEMO: dict[str, tuple[CubicSpline, float, float]] = {}
#: Crack-factor interpolants already read in this process, by cache key.
_CRACK_MEMO: dict[str, tuple[CubicSpline, np.ndarray, float] | None] = {}
#: Interpolants in depth of the crack's body-coupling factors, by cache key.
_CROSS_MEMO: dict[str, tuple[CubicSpline, CubicSpline, np.ndarray, float]] = {}
#: Ring calibrations already read in this process, by cache key.
_RING_MEMO: dict[str, tuple] = {}


def calibration_dir() -> Path:
    """Folder of the calibration cache (``<FE cache>/calibration``).

    Returns
    -------
    Path
        ``$GEARSIM_CACHE/fe/calibration`` or ``~/.cache/gearsim/fe/calibration``.
    """
    return cache_dir() / "calibration"


def _key_doc(gear: Gear, plane: str, level: int, gauss_points: int) -> dict:
    return {
        "kind": "calibration", "v": CALIBRATION_VERSION, "fe_tables": CACHE_VERSION,
        "gearsim": __version__, "gear": _gear_key(gear),
        "plane": plane, "level": level, "gauss_points": gauss_points,
    }


def calibration_key(gear: Gear, *, plane: str = "stress", level: int = DEFAULT_LEVEL,
                    gauss_points: int = 16) -> tuple[str, str]:
    """Cache key of a gear's calibration and the document it hashes.

    Parameters
    ----------
    gear : Gear
        The gear.
    plane : {"stress", "strain"}
        Plane assumption of both teeth.
    level : int
        FE mesh level of the FE tooth.
    gauss_points : int
        Gauss-Legendre nodes per piece of the PE integration.

    Returns
    -------
    key, document : str
        The first 32 hex digits of the SHA-256 of ``document``, and ``document``: JSON of
        geometry, material, plane, level, Gauss points, versions (FE tables, calibration,
        gearsim).
    """
    return _cache_key(_key_doc(gear, plane, level, gauss_points))


def _read(path: Path, doc: str, nodes: np.ndarray) -> np.ndarray | None:
    """The cached ratio, or None when the file is missing, corrupt or stale."""
    got = _read_npz(path, nodes, ("ratio",), doc)
    if got is None or got[0].shape != nodes.shape:
        return None
    ratio = got[0]
    lo, hi = RATIO_BOUNDS
    if not np.all(np.isfinite(ratio)) or np.any(ratio <= lo) or np.any(ratio >= hi):
        return None
    return ratio


def calibration_ratio(gear: Gear, *, plane: str = "stress", level: int = DEFAULT_LEVEL,
                      gauss_points: int = 16, use_cache: bool = True
                      ) -> tuple[np.ndarray, np.ndarray]:
    """FE over PE compliance of the healthy tooth of ``gear`` at the FE-table radii.

    Parameters
    ----------
    gear : Gear
        The gear (whole FE body, bore fixed, as :func:`gearsim.fem.tables.fe_compliance`).
    plane : {"stress", "strain"}
        Plane assumption of both teeth.
    level : int
        FE mesh level of the FE tooth (default that of the FE tables).
    gauss_points : int
        Gauss-Legendre nodes per piece of the PE integration (the ratio is taken against
        the PE tooth of the same rule, so the calibrated healthy tooth is the FE tooth at
        the nodes).
    use_cache : bool
        Read and write the disk cache (:func:`calibration_dir`).

    Returns
    -------
    radii, ratio : ndarray
        The :func:`~gearsim.fem.tables.fe_nodes` radii [m] and c_FE / c_PE there [-],
        c_PE the sum of bending, shear, axial and foundation compliance (Hertz excluded
        from both).
    """
    key, doc = calibration_key(gear, plane=plane, level=level, gauss_points=gauss_points)
    nodes = _fe_nodes(gear)
    path = calibration_dir() / f"{key}.npz"
    ratio = _read(path, doc, nodes) if use_cache else None
    if ratio is not None:
        return nodes, ratio
    # one process computes a gear's ratio at a time (test workers, Dask workers, the
    # install's warm-up): the others wait and read its result
    with exclusive(path.with_suffix(".lock")) if use_cache else contextlib.nullcontext():
        ratio = _read(path, doc, nodes) if use_cache else None
        if ratio is None:
            st = StiffnessSettings(plane=plane, gauss_points=gauss_points)
            # the FE tooth is solved afresh (its table cache does not name the gearsim
            # version): a rebuilt calibration never rests on a stale FE table
            c_fe = fe_compliance(gear, nodes, settings=st, options=SectorOptions(level=level),
                                 use_cache=False)[:, 0]
            c_pe = ToothModel(gear, plane=plane, gauss_points=gauss_points).compliance(nodes)
            ratio = c_fe / c_pe.sum(axis=1)
            if use_cache:
                _write_npz(path, key=np.array(doc), radii=nodes, ratio=ratio)
    return nodes, ratio


# ------------------------------------------------------------------ crack correction
def crack_depths(gear: Gear, crack: Crack, level: int = DEFAULT_LEVEL) -> np.ndarray:
    """Crack depths of the measured crack correction of ``gear`` [m].

    :data:`CRACK_GRID` times q_c = x_s / sin(nu), the depth at which the crack tip
    reaches the tooth centre line (:class:`~gearsim.stiffness.crack.CrackGeometry`
    ``max_depth``; seed eqs. 10-11 with x_t = 0): the deepest crack the FE tooth takes
    (its slit stays on one side of the centre line, :func:`gearsim.fem.geometry.
    crack_line`); none shallower than 2.02 elements of the FE level (the level resolves
    2 h without refining, :func:`gearsim.fem.tooth.check_crack_resolved`; 1 % more as the
    mesher's own check refuses 2 h by rounding).

    Parameters
    ----------
    gear : Gear
        The cracked gear.
    crack : Crack
        The crack (start point and angle; its depth is not used).
    level : int
        FE mesh level of the correction.

    Returns
    -------
    ndarray, shape (len(CRACK_GRID),)
        Depths [m], increasing.
    """
    q_c = crack_geometry(ToothProfile(gear), crack, 0.0).max_depth
    # no shallower than the level resolves (fe_compliance would refine the mesh)
    return np.maximum(q_c * np.asarray(CRACK_GRID, dtype=float),
                      2.02 * element_size(gear, level))


def crack_correction_key(gear: Gear, crack: Crack, side: int, *, closure: str = "contact",
                         plane: str = "stress", level: int = DEFAULT_LEVEL
                         ) -> tuple[str, str]:
    """Cache key of a gear's measured crack factors and the document it hashes.

    Parameters
    ----------
    gear : Gear
        The cracked gear.
    crack : Crack
        The crack: its family (start radius, angle) enters the key, its depth and
        profile along the face width do not (the factors are measured on a grid of
        depths and interpolated to each slice's depth).
    side : {1, -1}
        +1 the cracked flank is the loaded one, -1 the other.
    closure : {"contact", "open"}
        Crack-face model of the FE tooth.
    plane : {"stress", "strain"}
        Plane assumption.
    level : int
        FE mesh level.

    Returns
    -------
    key, document : str
        The first 32 hex digits of the SHA-256 of ``document`` (JSON of the gear
        geometry and material, plane, level, crack family, side, closure, depth grid and
        versions) and ``document``.
    """
    doc = _key_doc(gear, plane, level, 0)
    doc.pop("gauss_points")  # FE only: the PE rule does not enter the factors
    doc.update(kind="crack-correction", v=CRACK_CORRECTION_VERSION,
               crack={"angle": crack.angle, "start_radius": crack.start_radius,
                      "side": int(side), "closure": closure, "grid": list(CRACK_GRID)})
    return _cache_key(doc)


def _read_crack(path: Path, doc: str, nodes: np.ndarray, depths: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The cached FE crack factors and body-coupling factors, or None when the file is
    missing, corrupt or stale."""
    got = _read_npz(path, nodes, ("depths", "factor", "cross_load", "cross_read"), doc)
    if got is None:
        return None
    d, factor, load, read = got
    if (d.shape != depths.shape or not np.allclose(d, depths, rtol=1e-12, atol=0.0)
            or factor.shape != (depths.size, nodes.size)):
        return None
    lo, hi = CRACK_FACTOR_BOUNDS
    if not np.all(np.isfinite(factor)) or np.any(factor <= lo) or np.any(factor >= hi):
        return None
    lo, hi = CROSS_FACTOR_BOUNDS
    for g in (load, read):
        if (g.shape != (depths.size, nodes.size, nodes.size) or not np.all(np.isfinite(g))
                or np.any(g <= lo) or np.any(g >= hi)):
            return None
    return factor, load, read


def _crack_solve(gear: Gear, nodes: np.ndarray, crack: Crack, depth: float, side: int,
                 closure: str, plane: str, level: int) -> tuple[np.ndarray, np.ndarray]:
    """The cracked FE tooth at ``nodes`` and its neighbours under the same loads.

    :func:`gearsim.fem.tooth.fe_tooth_compliance` with ``neighbours=True`` at level
    ``level`` or finer where the crack needs it (as :func:`gearsim.fem.tables.
    fe_compliance`), solved afresh.

    Returns
    -------
    compliance : ndarray, shape (n,)
        The cracked tooth [m/N for a face width of 1 m].
    neighbours : ndarray, shape (2, n, n)
        Teeth -1 and +1 read under the loads (``FEToothResult.neighbours``).
    """
    check_crack_resolved(gear, depth, crack_depth=crack.depth)
    res = fe_tooth_compliance(gear, nodes, crack=crack, depth=depth, side=side,
                              closure=closure, plane=plane,
                              options=SectorOptions(level=_level_for(gear, depth, level)),
                              neighbours=True)
    return res.compliance, res.neighbours


def _crack_tables(gear: Gear, crack: Crack, side: int, *, closure: str, plane: str,
                  level: int, use_cache: bool
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Radii, depths, F_FE, G_load and G_read of a crack family (cached together)."""
    require(side in (1, -1), "side", side, "must be +1 or -1")
    key, doc = crack_correction_key(gear, crack, side, closure=closure, plane=plane,
                                    level=level)
    nodes = _fe_nodes(gear)
    depths = crack_depths(gear, crack, level)
    path = calibration_dir() / f"crack-{key}.npz"
    got = _read_crack(path, doc, nodes, depths) if use_cache else None
    if got is not None:
        return (nodes, depths, *got)
    with exclusive(path.with_suffix(".lock")) if use_cache else contextlib.nullcontext():
        got = _read_crack(path, doc, nodes, depths) if use_cache else None
        if got is None:
            # the healthy FE tooth of the gear's calibration entry, c_FE = R c_PE (16 Gauss
            # points: any rule, R is taken against the PE tooth of the same rule)
            _, ratio = calibration_ratio(gear, plane=plane, level=level, gauss_points=16,
                                         use_cache=use_cache)
            healthy = ratio * ToothModel(gear, plane=plane, gauss_points=16).compliance(
                nodes).sum(axis=1)
            # the healthy body's neighbours under loads on tooth 0 (the coupling's solve)
            _, minus_h, plus_h = fe_neighbour_coupling(gear, plane=plane, level=level,
                                                       use_cache=use_cache)
            factor, load, read = [], [], []
            for q in depths:
                comp, cross = _crack_solve(gear, nodes, crack, float(q), side, closure, plane,
                                           level)
                factor.append(comp / healthy)
                load.append(cross[0] / minus_h)
                read.append((cross[1] / plus_h).T)  # Maxwell: read <-> load
            factor, load, read = np.stack(factor), np.stack(load), np.stack(read)
            if use_cache:
                _write_npz(path, key=np.array(doc), radii=nodes, depths=depths,
                           factor=factor, cross_load=load, cross_read=read)
            got = factor, load, read
    return (nodes, depths, *got)


def crack_factor_table(gear: Gear, crack: Crack, side: int, *, closure: str = "contact",
                       plane: str = "stress", level: int = DEFAULT_LEVEL,
                       use_cache: bool = True
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """FE crack factors F_FE = c_FE,crack / c_FE,healthy on a grid of depths.

    One FE tooth solve (:func:`gearsim.fem.tooth.fe_tooth_compliance`, solved afresh,
    level ``level`` or finer where the crack needs it, as
    :func:`gearsim.fem.tables.fe_compliance`) per depth of :func:`crack_depths`, loads
    at the :func:`~gearsim.fem.tables.fe_nodes` radii; the healthy FE tooth is that of
    :func:`calibration_ratio`'s entry (solved afresh once per gear), read back as
    R c_PE,healthy. The same solves give the crack's body-coupling factors
    (:func:`crack_cross_table`), cached in the same entry.

    Parameters
    ----------
    gear : Gear
        The cracked gear.
    crack : Crack
        The crack family (start radius, angle; depth and profile not used).
    side : {1, -1}
        +1 crack on the loaded flank, -1 on the other.
    closure : {"contact", "open"}
        Crack-face model of the FE tooth (frictionless contact or free faces).
    plane : {"stress", "strain"}
        Plane assumption.
    level : int
        FE mesh level.
    use_cache : bool
        Read and write the disk cache (:func:`calibration_dir`).

    Returns
    -------
    radii, depths, factor : ndarray
        The FE-table radii [m], the depths [m] and F_FE[i, j] at depth i, radius j [-].
    """
    nodes, depths, factor, _, _ = _crack_tables(gear, crack, side, closure=closure,
                                                plane=plane, level=level,
                                                use_cache=use_cache)
    return nodes, depths, factor


def crack_cross_table(gear: Gear, crack: Crack, side: int, *, closure: str = "contact",
                      plane: str = "stress", level: int = DEFAULT_LEVEL,
                      use_cache: bool = True
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The crack's body-coupling factors G = X_crack / X_healthy on the depth grid.

    From the solves of :func:`crack_factor_table` (the cracked whole gear, bore fixed,
    unit loads on the cracked tooth 0 at the FE-table radii), the two neighbours read at
    their points Q (:func:`gearsim.fem.tooth.neighbour_cross`), over the healthy gear's
    same readings (:func:`gearsim.fem.coupling.fe_neighbour_coupling`).

    Parameters
    ----------
    gear, crack, side, closure, plane, level, use_cache
        As :func:`crack_factor_table`.

    Returns
    -------
    radii, depths : ndarray
        The FE-table radii [m] and the depths [m].
    load : ndarray, shape (depths, n, n)
        G_load[d, i, j]: the tooth behind the cracked one (whose ``+x`` neighbour it is)
        read at r_i, the cracked tooth loaded at r_j [-].
    read : ndarray, shape (depths, n, n)
        G_read[d, i, j]: the cracked tooth read at r_i, its ``+x`` neighbour (the one
        its loaded flank faces) loaded at r_j; by Maxwell's reciprocity the deflection
        of that neighbour at r_j under the load on the cracked tooth at r_i [-].
    """
    nodes, depths, _, load, read = _crack_tables(gear, crack, side, closure=closure,
                                                 plane=plane, level=level,
                                                 use_cache=use_cache)
    return nodes, depths, load, read


class CalibratedCompliance:
    """PE tooth times the FE/PE ratio of the healthy tooth and a measured crack
    correction (``source = "calibrated"``).

    Implements :class:`gearsim.stiffness.source.ToothCompliance`: the PE compliance
    (:class:`~gearsim.stiffness.source.PotentialEnergyCompliance`, cracks included)
    with all four components multiplied by R(r) of :func:`calibration_ratio` (cubic
    spline in roll length, clipped to the involute of the FE table) and, for a crack on
    a side in ``corrected_sides``, by the measured crack correction Q(r, q) of
    :meth:`crack_factor` (module docstring). The source is meant for
    ``contact = "line"`` and ``coupling = "fe"``, which
    :class:`~gearsim.stiffness.settings.StiffnessSettings` requires with it.

    Parameters
    ----------
    level : int
        FE mesh level of the calibration and the crack correction.
    corrected_sides : tuple of int
        Crack sides (+1 loaded flank, -1 the other) that take the measured crack
        correction; default :data:`CORRECTED_SIDES`; an open crack (``closure =
        "open"``) takes it on either side unless this is ``()``, which leaves every crack
        the PE section reduction (the model before the correction).
    """

    name = "calibrated"

    def __init__(self, level: int = DEFAULT_LEVEL,
                 corrected_sides: tuple[int, ...] = CORRECTED_SIDES) -> None:
        self.level = level
        self.corrected_sides = tuple(corrected_sides)
        self._pe = PotentialEnergyCompliance()

    def ratio(self, gear: Gear, radii: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """R(r) = c_FE / c_PE of the healthy tooth at contact radii [-].

        Parameters
        ----------
        gear : Gear
            The gear.
        radii : ndarray
            Contact radii [m] (any shape; values off the involute are clipped to it).
        settings : StiffnessSettings
            ``plane`` and ``gauss_points`` of the calibration.

        Returns
        -------
        ndarray
            The ratio, the shape of ``radii``.
        """
        key, _ = calibration_key(gear, plane=settings.plane, level=self.level,
                                 gauss_points=settings.gauss_points)
        if key not in _MEMO:
            nodes, ratio = calibration_ratio(gear, plane=settings.plane, level=self.level,
                                             gauss_points=settings.gauss_points)
            ln = np.sqrt(nodes**2 - gear.base_radius**2)
            _MEMO[key] = (CubicSpline(ln, ratio), float(ln[0]), float(ln[-1]))
        spline, lo, hi = _MEMO[key]
        r = np.asarray(radii, dtype=float)
        roll = np.sqrt(np.maximum(r**2 - gear.base_radius**2, 0.0))
        return spline(np.clip(roll, lo, hi))

    def compliance(self, gear: Gear, radii: np.ndarray, crack: ToothCrack | None,
                   zfrac: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """Calibrated compliances of the tooth of ``gear`` loaded at ``radii``.

        Parameters
        ----------
        gear, radii, crack, zfrac, settings
            As :meth:`gearsim.stiffness.source.ToothCompliance.compliance`.

        Returns
        -------
        ndarray, shape (..., ns, 4)
            Bending, shear, axial, foundation compliance times unit width [m/N * m], each
            the PE value times R(r) (0 where not in contact).
        """
        c = self._pe.compliance(gear, radii, crack, zfrac, settings)
        r = np.asarray(radii, dtype=float)
        inside = r > 0
        ratio = np.where(inside, self.ratio(gear, np.where(inside, r, gear.tip_radius),
                                            settings), 0.0)
        # an open crack (faces free) is corrected on either flank: the reason the closed
        # crack on the unloaded flank is left without Q (measured worse with it) is its
        # face contact, which an open crack does not have
        if crack is not None and self._corrected(crack, settings):
            ratio = ratio * self.crack_factor(gear, r, crack, zfrac, settings, pe=c)
        return c * ratio[..., None]

    def _crack_spline(self, gear: Gear, crack: ToothCrack, settings: StiffnessSettings
                      ) -> tuple[CubicSpline, np.ndarray, float] | None:
        """Interpolant of F_FE, roll lengths of its radii and deepest depth; None (with a
        :class:`~gearsim.errors.ModelRangeWarning`, once per process) when the FE tooth
        refuses the crack family (e.g. a mesher failure at a grid depth)."""
        key, _ = crack_correction_key(gear, crack.crack, crack.side, closure=settings.closure,
                                      plane=settings.plane, level=self.level)
        if key not in _CRACK_MEMO:
            try:
                nodes, depths, factor = crack_factor_table(
                    gear, crack.crack, crack.side, closure=settings.closure,
                    plane=settings.plane, level=self.level)
            except (InputError, SimulationError) as exc:  # the FE tooth refuses the family
                warn_model_range(
                    f"crack correction of gear {gear.name}: the FE tooth does not take the "
                    f"crack at {math.degrees(crack.crack.angle):.4g} deg ({exc}); the crack "
                    "stays the PE section reduction (Q = 1)")
                _CRACK_MEMO[key] = None
            else:
                q = np.concatenate([[0.0], depths])
                f = np.vstack([np.ones(nodes.size), factor])
                _CRACK_MEMO[key] = (CubicSpline(q, f, axis=0),
                                    np.sqrt(nodes**2 - gear.base_radius**2),
                                    float(depths[-1]))
        return _CRACK_MEMO[key]

    def fe_crack_factor(self, gear: Gear, radii: np.ndarray, crack: ToothCrack,
                        zfrac: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """F_FE(r, q) = c_FE,crack / c_FE,healthy at contact radii, interpolated [-].

        From :func:`crack_factor_table`: a not-a-knot cubic spline in depth through
        F_FE(0) = 1 and the grid of :func:`crack_depths`, then a cubic spline in roll
        length through the FE-table radii (as R). Each face-width slice takes its local
        depth (:meth:`~gearsim.stiffness.crack.Crack.depth_at`), clipped to the deepest
        grid depth.

        Parameters
        ----------
        gear : Gear
            The cracked gear.
        radii : ndarray, shape (..., ns)
            Contact radii [m] (values off the involute are clipped to it).
        crack : ToothCrack
            The crack as seen by the mesh.
        zfrac : ndarray, shape (ns,)
            Axial position of each slice centre / face width [-].
        settings : StiffnessSettings
            ``closure`` and ``plane`` of the FE tooth.

        Returns
        -------
        ndarray
            The factor, the shape of ``radii``.
        """
        r = np.asarray(radii, dtype=float)
        got = self._crack_spline(gear, crack, settings)
        if got is None:
            return np.ones(r.shape)
        spline, roll_nodes, q_top = got
        ns = r.shape[-1]
        depths = crack.crack.depth_at(zfrac) if ns > 1 else np.array([crack.crack.depth])
        q = np.minimum(np.broadcast_to(depths, (ns,)), q_top)
        roll = np.clip(np.sqrt(np.maximum(r**2 - gear.base_radius**2, 0.0)),
                       roll_nodes[0], roll_nodes[-1])
        out = np.empty(r.shape)
        for qk in np.unique(q):  # the slices of one depth share a factor curve
            on = q == qk
            out[..., on] = CubicSpline(roll_nodes, spline(float(qk)))(roll[..., on])
        return out

    def _corrected(self, crack: ToothCrack, settings: StiffnessSettings) -> bool:
        """Whether the crack takes the measured correction (Q and the coupling)."""
        return crack.side in self.corrected_sides or (settings.closure == "open"
                                                       and bool(self.corrected_sides))

    def cross_factor(self, gear: Gear, r_read: np.ndarray, r_load: np.ndarray,
                     crack: ToothCrack, reads_crack: bool, zfrac: np.ndarray,
                     settings: StiffnessSettings) -> np.ndarray | None:
        """The crack's factor G on the body coupling of a pair beside the cracked tooth.

        The mesh's coupling X(r_read, r_load) of a tooth and its loaded ``+x`` neighbour
        (:class:`gearsim.fem.coupling.FiniteElementCoupling`) is measured on the healthy
        gear; a crack that takes the measured correction Q (:meth:`compliance`) also
        changes it, and G = X_crack / X_healthy of :func:`crack_cross_table` (the same FE
        solves as Q) corrects it for the pair of the cracked tooth and its neighbour on
        the side away from the crack: ``reads_crack`` False, the cracked tooth is the
        loaded ``+x`` neighbour of the tooth read (G_load; a crack on the loaded flank,
        ``+x``, is on the far side of the cracked tooth); True, the cracked tooth is read
        and its ``+x`` neighbour is loaded (G_read; for a crack on the ``-x`` flank).
        Across the crack (the other pair) the coupling stays the healthy body's: the
        neighbour's load closes the crack faces there (Table-1 input gear, 6 mm loaded-
        flank crack: closed over their whole length under the neighbour's load alone,
        open under the cracked tooth's), so the factor depends on the two loads' ratio
        (0.64-0.81 with the faces open, 0.96-1.10 closed, measured) and a linear factor
        does not hold; with the open-face value the mesh came out up to 0.15 % *stiffer*
        with a deeper crack where the cracked tooth's tip corner closes beside its loaded
        neighbour (19/48 pinion; a crack cannot stiffen the mesh). Away from the crack
        the faces stay open under both loads (measured) and G_load = 1.16-1.34 > 1.
        A not-a-knot cubic spline in depth through G(0) = 1 and the grid depths, each
        slice at its local depth clipped to the deepest grid depth (as
        :meth:`fe_crack_factor`), then a bicubic spline in the roll lengths of the
        FE-table radii.

        Parameters
        ----------
        gear : Gear
            The cracked gear.
        r_read, r_load : ndarray, shape (..., ns)
            Contact radii of the tooth read and of its loaded ``+x`` neighbour [m]
            (values off the involute are clipped to it).
        crack : ToothCrack
            The crack as seen by the mesh.
        reads_crack : bool
            True: the cracked tooth is the one read; False: the loaded one.
        zfrac : ndarray, shape (ns,)
            Axial position of each slice centre / face width [-].
        settings : StiffnessSettings
            ``closure`` and ``plane`` of the FE tooth.

        Returns
        -------
        ndarray or None
            G [-], the shape of ``r_read``; None when the pair is across the crack
            (above) or the crack takes no correction (a side not corrected, no depth in
            any slice, or a crack family the FE tooth refuses, :meth:`_crack_spline`).
        """
        r_a = np.asarray(r_read, dtype=float)
        r_b = np.asarray(r_load, dtype=float)
        if not self._corrected(crack, settings) or reads_crack != (crack.side < 0):
            return None
        ns = r_a.shape[-1]
        depths = crack.crack.depth_at(zfrac) if ns > 1 else np.array([crack.crack.depth])
        if not np.any(depths > 0.0) or self._crack_spline(gear, crack, settings) is None:
            return None
        key, _ = crack_correction_key(gear, crack.crack, crack.side, closure=settings.closure,
                                      plane=settings.plane, level=self.level)
        if key not in _CROSS_MEMO:
            nodes, grid, load, read = crack_cross_table(
                gear, crack.crack, crack.side, closure=settings.closure, plane=settings.plane,
                level=self.level)
            q = np.concatenate([[0.0], grid])
            one = np.ones((1, nodes.size, nodes.size))
            _CROSS_MEMO[key] = (CubicSpline(q, np.concatenate([one, load]), axis=0),
                                CubicSpline(q, np.concatenate([one, read]), axis=0),
                                np.sqrt(nodes**2 - gear.base_radius**2), float(grid[-1]))
        load_s, read_s, roll_nodes, q_top = _CROSS_MEMO[key]
        spline = read_s if reads_crack else load_s
        rb = gear.base_radius
        a = np.clip(np.sqrt(np.maximum(r_a**2 - rb**2, 0.0)), roll_nodes[0], roll_nodes[-1])
        b = np.clip(np.sqrt(np.maximum(r_b**2 - rb**2, 0.0)), roll_nodes[0], roll_nodes[-1])
        out = np.empty(np.broadcast_shapes(a.shape, b.shape))
        a, b = np.broadcast_to(a, out.shape), np.broadcast_to(b, out.shape)
        q = np.minimum(np.broadcast_to(depths, (ns,)), q_top)
        for qk in np.unique(q):  # the slices of one depth share a surface
            on = q == qk
            surface = RectBivariateSpline(roll_nodes, roll_nodes, spline(float(qk)), kx=3,
                                          ky=3)
            out[..., on] = surface.ev(a[..., on].ravel(), b[..., on].ravel()).reshape(
                out[..., on].shape)
        return out

    def crack_factor(self, gear: Gear, radii: np.ndarray, crack: ToothCrack,
                     zfrac: np.ndarray, settings: StiffnessSettings,
                     pe: np.ndarray | None = None) -> np.ndarray:
        """Measured crack correction Q = F_FE / F_PE at contact radii [-].

        Q(r, q) = [c_FE,crack(r, q) / c_FE,healthy(r)] / [c_PE,crack(r, q) /
        c_PE,healthy(r)], so that c_cal,crack = c_PE,crack R Q = R c_PE,healthy F_FE:
        the calibrated healthy tooth times the FE tooth's crack factor, in the PE
        model's component split. F_FE from :meth:`fe_crack_factor`, F_PE the PE tooth's
        own at the point (sums of the four components). A slice deeper than the deepest
        grid depth q_top (the FE tooth takes no crack past the centre line) keeps
        Q(r, q_top): its compliance grows beyond q_top as the PE crack's.

        Parameters
        ----------
        gear : Gear
            The cracked gear.
        radii : ndarray, shape (..., ns)
            Contact radii [m]; 0 where not in contact (Q = 1 there).
        crack : ToothCrack
            The crack as seen by the mesh.
        zfrac : ndarray, shape (ns,)
            Axial position of each slice centre / face width [-].
        settings : StiffnessSettings
            Closure, plane and quadrature of both teeth.
        pe : ndarray, shape (..., ns, 4), optional
            The PE compliance of the cracked tooth at ``radii`` if already computed.

        Returns
        -------
        ndarray
            Q, the shape of ``radii``.
        """
        r = np.asarray(radii, dtype=float)
        inside = r > 0
        ns = r.shape[-1]
        depths = crack.crack.depth_at(zfrac) if ns > 1 else np.array([crack.crack.depth])
        if not np.any(depths > 0.0):  # no crack in any slice: nothing to measure
            return np.ones(r.shape)
        got = self._crack_spline(gear, crack, settings)
        if got is None:
            return np.ones(r.shape)
        q_top = got[2]
        if pe is None or np.any(depths > q_top):
            pe = _pe_cracked(gear, r, crack, np.minimum(depths, q_top), settings)
        healthy = self._pe.compliance(gear, r, None, zfrac, settings).sum(axis=-1)
        f_pe = np.divide(pe.sum(axis=-1), healthy, out=np.ones(r.shape), where=inside)
        f_fe = self.fe_crack_factor(gear, np.where(inside, r, gear.tip_radius), crack, zfrac,
                                    settings)
        return np.where(inside, f_fe / f_pe, 1.0)


def _pe_cracked(gear: Gear, radii: np.ndarray, crack: ToothCrack, depths: np.ndarray,
                settings: StiffnessSettings) -> np.ndarray:
    """PE compliance (..., ns, 4) of the tooth with the crack at slice depths ``depths``."""
    tm = ToothModel(gear, plane=settings.plane, gauss_points=settings.gauss_points,
                    closure=settings.closure)
    shape = radii.shape
    recs = np.stack([crack_record(tm.profile, crack.crack, float(q), crack.side)
                     for q in depths])
    records = np.broadcast_to(recs.reshape((1,) * (len(shape) - 1) + recs.shape),
                              shape + recs.shape[-1:]).reshape(-1, recs.shape[-1])
    c = tm.compliance(radii.ravel(), records)
    return np.nan_to_num(c, nan=0.0).reshape(shape + (4,))


# ------------------------------------------------------------------------ ring tooth
def ring_nodes(ring: RingGear) -> np.ndarray:
    """Contact radii of the ring calibration: :data:`~gearsim.fem.tables.NODES` radii [m].

    Equally spaced in roll length sqrt(r^2 - r_b^2) from the ring's tip (inner) circle r_a
    to rho_t, where its involute meets the root fillet of the FE segment
    (:func:`gearsim.fem.ring.ring_involute_limit`).

    Parameters
    ----------
    ring : RingGear
        The internal gear.

    Returns
    -------
    ndarray, shape (NODES,)
        Radii [m], increasing.
    """
    rb = ring.base_radius
    lo = math.sqrt(ring.tip_radius**2 - rb**2)
    hi = math.sqrt(ring_involute_limit(ring) ** 2 - rb**2)
    # the top node a hair inside rho_t (the FE refuses radii on the fillet)
    roll = np.linspace(lo, hi * (1.0 - 1e-9), NODES)
    return np.sqrt(roll**2 + rb**2)


def _ring_doc(ring: RingGear, material: Material, plane: str, level: int,
              gauss_points: int) -> dict:
    r = ring
    return {
        "kind": "ring-calibration", "v": RING_CALIBRATION_VERSION, "gearsim": __version__,
        "ring": [r.teeth, r.normal_module, r.normal_pressure_angle, abs(r.helix_angle),
                 r.addendum_coefficient, r.dedendum_coefficient, r.profile_shift],
        "material": [material.youngs_modulus, material.poisson_ratio],
        "plane": plane, "level": level, "gauss_points": gauss_points,
        "segment": {"rim": RIM_THICKNESS, "fillet": ROOT_FILLET, "teeth": RING_SEGMENT_TEETH,
                    "support": "outer"},
    }


def ring_calibration_key(ring: RingGear, material: Material, *, plane: str = "stress",
                         level: int = DEFAULT_LEVEL, gauss_points: int = 16
                         ) -> tuple[str, str]:
    """Cache key of a ring's calibration and the document it hashes.

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    material : Material
        Its material.
    plane : {"stress", "strain"}
        Plane assumption.
    level : int
        FE mesh level of the ring segment.
    gauss_points : int
        Gauss-Legendre nodes per piece of the PE ring tooth.

    Returns
    -------
    key, document : str
        The first 32 hex digits of the SHA-256 of ``document`` (JSON of the ring geometry,
        material, plane, level, Gauss points, FE segment and versions) and ``document``.
    """
    return _cache_key(_ring_doc(ring, material, plane, level, gauss_points))


def _read_ring(path: Path, doc: str, nodes: np.ndarray, beam: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray] | None:
    """The cached FE ring tooth and cross compliance, or None (missing, corrupt, stale)."""
    got = _read_npz(path, nodes, ("fe", "cross"), doc)
    n = nodes.size
    if got is None or got[0].shape != (n,) or got[1].shape != (n, n):
        return None
    fe, cross = got
    lo, hi = RING_RATIO_BOUNDS
    ratio = fe / beam
    if not (np.all(np.isfinite(ratio)) and np.all(ratio > lo) and np.all(ratio < hi)):
        return None
    # a neighbour never deflects more than the loaded tooth itself
    if not (np.all(np.isfinite(cross)) and np.all(np.abs(cross) < fe.max())):
        return None
    return fe, cross


def ring_calibration(ring: RingGear, material: Material | None = None, *,
                     plane: str = "stress", level: int = DEFAULT_LEVEL, gauss_points: int = 16,
                     use_cache: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """FE ring tooth and neighbour cross compliance at the ring's calibration radii.

    One FE solve of the ring segment (:func:`gearsim.fem.ring.fe_ring_tooth_result`: five
    teeth on a 3.5 m_n rim clamped on its outer circle, root fillets 0.25 m_n, P2
    elements, deflection read at Q on the tooth centre line, Hertz excluded), loads at
    the :func:`ring_nodes` radii on the middle tooth, read on it and on its neighbour.

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    material : Material, optional
        Its material (default steel, :class:`~gearsim.geometry.gear.Material`).
    plane : {"stress", "strain"}
        Plane assumption of the FE segment and the PE tooth.
    level : int
        FE mesh level (element size m_n / (4 2^level) on the loaded tooth).
    gauss_points : int
        Gauss-Legendre nodes of the PE ring tooth (the plausibility check of a cached
        entry compares with it).
    use_cache : bool
        Read and write the disk cache (:func:`calibration_dir`).

    Returns
    -------
    radii, fe, cross : ndarray
        The radii [m], the FE tooth compliance there per unit face width [m/(N/m)] and
        X[i, j], the deflection of a tooth at Q(r_i) along its load direction under a
        unit load per unit width on its loaded-flank-side neighbour at r_j [m/(N/m)].
    """
    material = material or Material()
    key, doc = ring_calibration_key(ring, material, plane=plane, level=level,
                                    gauss_points=gauss_points)
    nodes = ring_nodes(ring)
    beam = RingToothModel(ring, material=material, plane=plane,
                          gauss_points=gauss_points).compliance(nodes)[:, :3].sum(axis=1)
    path = calibration_dir() / f"ring-{key}.npz"
    got = _read_ring(path, doc, nodes, beam) if use_cache else None
    if got is not None:
        return nodes, *got
    with exclusive(path.with_suffix(".lock")) if use_cache else contextlib.nullcontext():
        got = _read_ring(path, doc, nodes, beam) if use_cache else None
        if got is None:
            res = fe_ring_tooth_result(ring, nodes, youngs_modulus=material.youngs_modulus,
                                       poisson_ratio=material.poisson_ratio, plane=plane,
                                       n_teeth=RING_SEGMENT_TEETH, level=level,
                                       read_radii=nodes)
            got = (np.asarray(res.compliance, dtype=float), np.asarray(res.cross, dtype=float))
            if use_cache:
                _write_npz(path, key=np.array(doc), radii=nodes, fe=got[0], cross=got[1])
    return nodes, *got


class CalibratedRingTooth:
    """Ring tooth corrected by the FE ring segment, with its rim coupling (module docstring).

    ``compliance`` has the signature of :meth:`gearsim.stiffness.ring.RingToothModel.
    compliance`: the PE beam terms of the tooth clamped on its root circle (cracks
    included) and, in the foundation column, the FE excess of the healthy tooth,
    e(r) = c_FE,ring(r) - c_PE,beam(r), a cubic spline in roll length through the
    :func:`ring_nodes`; ``cross`` the rim coupling of neighbouring teeth, a bicubic spline
    of :func:`ring_calibration`'s X. Used by the internal mesh of a stage under the
    calibrated source (:func:`gearsim.stiffness.internal.internal_mesh_stiffness`).

    Parameters
    ----------
    ring : RingGear
        The internal gear.
    material : Material, optional
        Its material.
    plane : {"stress", "strain"}
        Plane assumption.
    gauss_points : int
        Gauss-Legendre nodes of the PE ring tooth.
    level : int
        FE mesh level of the ring segment.

    Raises
    ------
    InputError
        Bad ring, material, plane or Gauss points (:class:`RingToothModel`).
    """

    name = "calibrated"

    def __init__(self, ring: RingGear, material: Material | None = None, *,
                 plane: str = "stress", gauss_points: int = 16,
                 level: int = DEFAULT_LEVEL) -> None:
        self.pe = RingToothModel(ring, material=material or Material(), plane=plane,
                                 gauss_points=gauss_points)
        self.ring = ring
        self.level = level
        key, _ = ring_calibration_key(ring, self.pe.material, plane=plane, level=level,
                                      gauss_points=gauss_points)
        if key not in _RING_MEMO:
            nodes, fe, cross = ring_calibration(ring, self.pe.material, plane=plane,
                                                level=level, gauss_points=gauss_points)
            ln = np.sqrt(nodes**2 - ring.base_radius**2)
            excess = fe - self.pe.compliance(nodes)[:, :3].sum(axis=1)
            _RING_MEMO[key] = (CubicSpline(ln, excess), RectBivariateSpline(ln, ln, cross),
                               float(ln[0]), float(ln[-1]))
        self._excess, self._cross, self._lo, self._hi = _RING_MEMO[key]

    def _roll(self, radii) -> np.ndarray:
        r = np.asarray(radii, dtype=float)
        roll = np.sqrt(np.maximum(r**2 - self.ring.base_radius**2, 0.0))
        return np.clip(roll, self._lo, self._hi)

    def compliance(self, radii, *, width: float = 1.0, crack_depth: float = 0.0,
                   crack_angle: float = math.radians(45.0)) -> np.ndarray:
        """Calibrated ring-tooth compliances: columns bending, shear, axial, foundation.

        Parameters
        ----------
        radii
            Contact radii on the ring flank, in [r_a, r_f] [m], scalar or 1-D (beyond the
            calibration's rho_t the excess of rho_t is used).
        width
            Face width carried by the tooth [m].
        crack_depth, crack_angle
            A root crack on the loaded flank [m], [rad] (the PE beam terms'; see
            :meth:`RingToothModel.compliance`).

        Returns
        -------
        ndarray, shape (n, 4)
            [m/N] for the given width; the fourth column is the FE rim-and-fillet excess.
        """
        c = self.pe.compliance(radii, width=width, crack_depth=crack_depth,
                               crack_angle=crack_angle)
        c[:, 3] = self._excess(self._roll(np.atleast_1d(radii))) / width
        return c

    def cross(self, r_read: np.ndarray, r_load: np.ndarray) -> np.ndarray:
        """Rim coupling X(r_read, r_load) of neighbouring ring teeth [m/(N/m)].

        Parameters
        ----------
        r_read : ndarray
            Contact radius of the tooth whose deflection is read [m].
        r_load : ndarray
            Contact radius on its loaded-flank-side (``+x``) neighbour, which carries the
            unit load per unit width [m] (same shape).

        Returns
        -------
        ndarray
            X (radii clipped to the calibration's range) [m/(N/m)].
        """
        a, b = self._roll(r_read), self._roll(r_load)
        require(a.shape == b.shape, "r_load", b.shape, f"must have the shape of r_read {a.shape}")
        return self._cross.ev(a.ravel(), b.ravel()).reshape(a.shape)
