"""FE tooth compliance as the stiffness table of a simulation (``stiffness.source = "fe"``).

:func:`FiniteElementCompliance` implements the tooth-compliance protocol of
:mod:`gearsim.stiffness.source` for :func:`gearsim.stiffness.mesh.mesh_stiffness`; each
slice's curve comes from :func:`fe_compliance`.
It runs the finite-element model (:mod:`gearsim.fem.tooth`) at ``NODES`` contact
positions equally spaced in roll length over the whole involute (form circle to tip),
interpolates them with a cubic spline in roll length to the requested radii, and caches
the nodes on disk so that each geometry and crack is computed once.

Cache: ``$GEARSIM_CACHE/fe/`` or ``~/.cache/gearsim/fe/``; one ``.npz`` file per key,
the SHA-256 of the gear geometry and material, crack (angle, start radius), local
depth, side, closure, plane, mesh options and :data:`CACHE_VERSION`; written to a
temporary file and renamed (atomic), so an interrupted run never leaves a half file.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import zipfile
from pathlib import Path

import numpy as np

from gearsim.errors import InputError
from gearsim.fem.geometry import SectorOptions, element_size
from gearsim.fem.tooth import check_crack_resolved, fe_tooth_compliance
from gearsim.geometry.gear import Gear
from gearsim.geometry.profile import ToothProfile
from gearsim.io.atomic import atomic_write
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import ToothCrack

__all__ = ["CACHE_VERSION", "DEFAULT_LEVEL", "NODES", "FiniteElementCompliance", "cache_dir",
           "fe_compliance", "fe_nodes"]

#: Contact positions computed by FE per curve (interpolated in between).
NODES = 13
#: Mesh level of the tables (element size m_n / 16 on the loaded tooth); raised
#: automatically until the element size is <= crack depth / 2.
DEFAULT_LEVEL = 2
#: Bump when the FE model changes so that old cache files are not reused.
CACHE_VERSION = 1


def cache_dir() -> Path:
    """Folder of the FE compliance cache (``$GEARSIM_CACHE/fe`` or ~/.cache/gearsim/fe)."""
    base = os.environ.get("GEARSIM_CACHE")
    root = Path(base) if base else Path.home() / ".cache" / "gearsim"
    return root / "fe"


def _level_for(gear: Gear, depth: float, level: int) -> int:
    while depth > 0 and element_size(gear, level) > 0.5 * depth and level < 6:
        level += 1
    return level


def _gear_key(g: Gear) -> list:
    """Geometry and material of a gear as the FE cache keys hold them."""
    return [g.teeth, g.normal_module, g.normal_pressure_angle, abs(g.helix_angle),
            g.addendum_coefficient, g.dedendum_coefficient, g.fillet_radius_coefficient,
            g.profile_shift, g.bore_radius_value, g.material.youngs_modulus,
            g.material.poisson_ratio]


def _cache_key(doc: dict) -> tuple[str, str]:
    """First 32 hex digits of the SHA-256 of ``doc`` as sorted JSON, and that JSON."""
    text = json.dumps(doc, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:32], text


def _key(gear: Gear, crack, depth: float, side: int, closure: str, plane: str,
         opt: SectorOptions) -> str:
    doc = {
        "v": CACHE_VERSION, "nodes": NODES, "gear": _gear_key(gear),
        "crack": None if crack is None or depth <= 0 or side == 0 else
        [crack.angle, crack.start_radius, depth, side],
        "closure": closure, "plane": plane,
        "mesh": [opt.level, opt.n_teeth, opt.sides, opt.growth, opt.tip_refinement],
    }
    return _cache_key(doc)[0]


def fe_nodes(gear: Gear) -> np.ndarray:
    """Contact radii of the FE table: NODES points equally spaced in roll length [m].

    Parameters
    ----------
    gear : Gear
        The gear.

    Returns
    -------
    ndarray
        :data:`NODES` radii from the form (or base) circle to the tip [m].
    """
    prof = ToothProfile(gear)
    rb = gear.base_radius
    r_lo = max(prof.form_radius, rb)
    l0 = math.sqrt(max(r_lo**2 - rb**2, 0.0))
    l1 = math.sqrt(gear.tip_radius**2 - rb**2)
    # stay a hair inside the involute so that rounding never leaves it
    lengths = np.linspace(l0 + 1e-9 * (l1 - l0), l1 - 1e-9 * (l1 - l0), NODES)
    return np.hypot(rb, lengths)


def _write_npz(path: Path, **arrays) -> None:
    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    atomic_write(path, write)


def _read_npz(path: Path, nodes: np.ndarray, names: tuple[str, ...], doc: str | None = None
              ) -> list[np.ndarray] | None:
    """Arrays ``names`` of a cache file written at the radii ``nodes`` (and for the key
    document ``doc``, where given); None when the file is missing, corrupt, of another key
    or of other radii (the caller computes the entry again and overwrites it)."""
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if doc is not None and str(data["key"]) != doc:
                return None
            radii = np.asarray(data["radii"], dtype=float)
            out = [np.asarray(data[k], dtype=float) for k in names]
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    if radii.shape != nodes.shape or not np.allclose(radii, nodes, rtol=1e-12, atol=0.0):
        return None
    return out


def fe_compliance(gear: Gear, radii, *, crack=None, depth: float = 0.0, side: int = 0,
                  settings=None, options: SectorOptions | None = None,
                  use_cache: bool = True) -> np.ndarray:
    """FE tooth compliance per unit face width at contact radii, shape (n, 4) [m/N].

    Same convention as ``ToothModel.compliance(radii, ..., width=1.0)``: the whole FE
    tooth compliance (bending, shear, axial and foundation together; Hertz excluded) is
    in column 0, the other three columns are zero.

    Parameters
    ----------
    gear
        The gear.
    radii
        Contact radii on the involute [m].
    crack
        :class:`gearsim.stiffness.crack.Crack` or ``None``.
    depth
        Local crack depth of this face slice [m] (0: healthy).
    side
        +1 the cracked flank is loaded in this mesh, -1 it is not, 0 healthy.
    settings
        :class:`gearsim.stiffness.mesh.StiffnessSettings` (``closure``, ``plane``);
        ``None`` = defaults.
    options
        FE mesh options; default level :data:`DEFAULT_LEVEL`, whole gear.
    use_cache
        Read and write the disk cache.

    Returns
    -------
    ndarray, shape (n, 4)
        Compliance [m/N] for a face width of 1 m.
    """
    closure = getattr(settings, "closure", "contact")
    plane = getattr(settings, "plane", "stress")
    if side not in (-1, 0, 1):
        raise InputError("side", side, "must be -1, 0 or +1")
    r = np.atleast_1d(np.asarray(radii, dtype=float))
    cracked = crack is not None and depth > 0.0 and side != 0
    if not cracked:
        crack, depth, side = None, 0.0, 0
    base = options or SectorOptions(level=DEFAULT_LEVEL)
    if cracked:
        check_crack_resolved(gear, depth, crack_depth=getattr(crack, "depth", None))
    lvl = _level_for(gear, depth, base.level)
    opt = SectorOptions(level=lvl, n_teeth=base.n_teeth, sides=base.sides,
                        growth=base.growth, tip_refinement=base.tip_refinement)
    nodes = fe_nodes(gear)
    lo, hi = nodes[0], nodes[-1]
    tol = 1e-6 * hi
    if np.any(r < lo - tol) or np.any(r > hi + tol) or not np.all(np.isfinite(r)):
        bad = r[(r < lo - tol) | (r > hi + tol) | ~np.isfinite(r)][0]
        raise InputError("radii", float(bad), f"FE table of {gear.name} covers the involute "
                         f"[{lo:.6g}, {hi:.6g}] m only")
    key = _key(gear, crack, depth, side, closure, plane, opt)
    path = cache_dir() / f"{key}.npz"
    got = _read_npz(path, nodes, ("compliance",)) if use_cache else None
    if got is None:
        res = fe_tooth_compliance(gear, nodes, crack=crack, depth=depth if cracked else None,
                                  side=side, closure=closure, plane=plane, options=opt)
        got = [res.compliance]
        if use_cache:
            _write_npz(path, radii=nodes, compliance=res.compliance, level=np.array(opt.level))
    rb = gear.base_radius
    from scipy.interpolate import CubicSpline

    spline = CubicSpline(np.sqrt(nodes**2 - rb**2), got[0])
    out = np.zeros((r.size, 4))
    out[:, 0] = spline(np.sqrt(np.maximum(np.clip(r, lo, hi) ** 2 - rb**2, 0.0)))
    return out


class FiniteElementCompliance:
    """The finite-element tooth as a stiffness source (``stiffness.source = "fe"``).

    Implements :class:`gearsim.stiffness.source.ToothCompliance`: per face-width slice
    (local crack depth of a crack profile), the FE compliance curve of
    :func:`fe_compliance` at the contact radii. The whole FE compliance is returned in
    the bending column; shear, axial and foundation are zero (the FE tooth does not
    split them).
    """

    name = "fe"

    def compliance(self, gear: Gear, radii: np.ndarray, crack: ToothCrack | None,
                   zfrac: np.ndarray, settings: StiffnessSettings) -> np.ndarray:
        """Compliances of the FE tooth of ``gear`` loaded at ``radii``.

        Parameters
        ----------
        gear, radii, crack, zfrac, settings
            As :meth:`gearsim.stiffness.source.ToothCompliance.compliance` (``settings``:
            the closure and plane of the FE model).

        Returns
        -------
        ndarray, shape (..., ns, 4)
            Compliance times unit face width [m/N * m] in column 0, zeros elsewhere.
        """
        out = np.zeros(radii.shape + (4,))
        ns = radii.shape[-1]
        for k in range(ns):
            rk = radii[..., k].ravel()
            depth = 0.0
            if crack is not None:
                depth = (float(crack.crack.depth_at(zfrac[k:k + 1])[0]) if ns > 1
                         else crack.crack.depth)
            sel = rk > 0
            vals = np.zeros((rk.size, 4))
            if np.any(sel):
                vals[sel] = fe_compliance(gear, rk[sel], crack=None if crack is None
                                          else crack.crack, depth=depth,
                                          side=0 if crack is None else crack.side,
                                          settings=settings)
            out[..., k, :] = vals.reshape(radii.shape[:-1] + (4,))
        return out
