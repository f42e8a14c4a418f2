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
to the tip) and interpolated with a cubic spline in roll length. A crack, a crack
profile along the face width, slicing and helical gears stay the PE computation (the
crack's effect is the PE section reduction, which the FE tooth and pair confirm within
2-3 %, docs/fem.md); the four PE components are scaled by the same R, so their split is
the PE model's.

Cache: ``calibration_dir()``, ``$GEARSIM_CACHE/fe/calibration/`` (or
``~/.cache/gearsim/fe/calibration/``), one ``.npz`` per key, the SHA-256 of the gear
geometry and material, plane, FE level, Gauss points of the PE integration, the FE table
and calibration versions and the gearsim version. Each file carries its key document, its
radii and ratio; a file that cannot be read, whose document differs from the expected one,
whose radii are not the gear's nodes or whose ratio is not finite and in
(:data:`RATIO_BOUNDS`) is stale or corrupt: it is recomputed and overwritten, never used.
The FE tooth values come from :func:`gearsim.fem.tables.fe_compliance` solved afresh
(not from the FE-table cache, whose key does not name the gearsim version), once per
calibration entry.

References
----------
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004)
   748-752 (the foundation term of the PE tooth that the ratio corrects, with the beam).
.. [Seed] eqs. 3-8 (the PE tooth).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import zipfile
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from gearsim._version import __version__
from gearsim.fem.geometry import SectorOptions
from gearsim.fem.tables import CACHE_VERSION, DEFAULT_LEVEL, _write_npz, cache_dir, fe_compliance
from gearsim.fem.tables import fe_nodes as _fe_nodes
from gearsim.geometry.gear import Gear
from gearsim.io.atomic import exclusive
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance, ToothCrack
from gearsim.stiffness.tooth import ToothModel

__all__ = ["CALIBRATION_VERSION", "RATIO_BOUNDS", "CalibratedCompliance", "calibration_dir",
           "calibration_key", "calibration_ratio"]

#: Bump when the calibration changes so that old cache files are not reused.
CALIBRATION_VERSION = 1
#: Plausible range of FE / PE tooth compliance [-]: measured 0.85-0.95 on the 19/48 and
#: Table-1 gears (docs/fem.md); a cached ratio outside (0.2, 5) is treated as corrupt.
RATIO_BOUNDS = (0.2, 5.0)

#: Interpolants already read in this process, by cache key (the disk is read once).
_MEMO: dict[str, tuple[CubicSpline, float, float]] = {}


def calibration_dir() -> Path:
    """Folder of the calibration cache (``<FE cache>/calibration``).

    Returns
    -------
    Path
        ``$GEARSIM_CACHE/fe/calibration`` or ``~/.cache/gearsim/fe/calibration``.
    """
    return cache_dir() / "calibration"


def _key_doc(gear: Gear, plane: str, level: int, gauss_points: int) -> dict:
    g = gear
    return {
        "kind": "calibration", "v": CALIBRATION_VERSION, "fe_tables": CACHE_VERSION,
        "gearsim": __version__,
        "gear": [g.teeth, g.normal_module, g.normal_pressure_angle, abs(g.helix_angle),
                 g.addendum_coefficient, g.dedendum_coefficient, g.fillet_radius_coefficient,
                 g.profile_shift, g.bore_radius_value, g.material.youngs_modulus,
                 g.material.poisson_ratio],
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
    text = json.dumps(_key_doc(gear, plane, level, gauss_points), sort_keys=True,
                      default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:32], text


def _read(path: Path, doc: str, nodes: np.ndarray) -> np.ndarray | None:
    """The cached ratio, or None when the file is missing, corrupt or stale."""
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if str(data["key"]) != doc:
                return None
            radii = np.asarray(data["radii"], dtype=float)
            ratio = np.asarray(data["ratio"], dtype=float)
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    if radii.shape != nodes.shape or ratio.shape != nodes.shape:
        return None
    if not np.allclose(radii, nodes, rtol=1e-12, atol=0.0):
        return None
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


class CalibratedCompliance:
    """PE tooth times the FE/PE ratio of the healthy tooth (``source = "calibrated"``).

    Implements :class:`gearsim.stiffness.source.ToothCompliance`: the PE compliance
    (:class:`~gearsim.stiffness.source.PotentialEnergyCompliance`, cracks included)
    with all four components multiplied by R(r) of :func:`calibration_ratio` (cubic
    spline in roll length, clipped to the involute of the FE table). The source is meant
    for ``contact = "line"`` and ``coupling = "fe"``, which
    :class:`~gearsim.stiffness.settings.StiffnessSettings` requires with it.

    Parameters
    ----------
    level : int
        FE mesh level of the calibration.
    """

    name = "calibrated"

    def __init__(self, level: int = DEFAULT_LEVEL) -> None:
        self.level = level
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
        gear : Gear
            The gear whose tooth is loaded.
        radii : ndarray, shape (..., ns)
            Contact radius [m] per grid point and slice; 0 where not in contact.
        crack : ToothCrack or None
            The crack of this tooth as seen by the mesh, or None.
        zfrac : ndarray, shape (ns,)
            Axial position of each slice centre / face width [-] (crack depth profile).
        settings : StiffnessSettings
            Closure, plane, quadrature options.

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
        return c * ratio[..., None]
