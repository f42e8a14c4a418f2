"""FE coupling of neighbouring teeth through the gear body, computed once per gear and cached.

The potential-energy model (:mod:`gearsim.stiffness.tooth`) gives each tooth its own
fillet-foundation compliance (Sainsot et al. 2004) and adds the pairs in contact in
parallel: a load on one tooth does not move its neighbour. In the gear, it does: the
rim and the web under a loaded tooth also turn and bend the tooth next to it. The FE gear
pair (:mod:`gearsim.fem.pair`, docs/fem.md "Gear pair in contact") measures this cross
compliance at 33-46 % of the smaller direct tooth compliance in double contact; summing
independent pairs makes the double-contact stiffness about 16 % too high.

:func:`fe_neighbour_coupling` returns (its ``minus``) the cross compliance of one gear
body, per unit face width,

    X(r_read, r_load) = d_0(r_read) . u_0(Q(r_read))  under a unit load on tooth +1 at r_load,

tooth +1 being the neighbour on the loaded-flank (``+x``) side of tooth 0 (the tooth
frame of :class:`~gearsim.geometry.profile.ToothProfile`), d_0 the load direction and Q
the point where the single-tooth FE model reads its deflection
(:func:`gearsim.fem.tooth.load_geometry`). It is computed by loading tooth 0 at the
:func:`~gearsim.fem.tables.fe_nodes` radii and reading tooth -1 (whose ``+x`` neighbour
tooth 0 is), one factorisation for all loads, and kept on disk next to the FE tooth
tables (:func:`gearsim.fem.tables.cache_dir`). By Maxwell's reciprocity the coupling
to the neighbour on the other side is X(r_load, r_read). The same solve reads tooth +1
too (its ``plus``): the healthy reference of the cracked body's coupling
(:meth:`gearsim.fem.calibration.CalibratedCompliance.cross_factor`), whose loads are on
the cracked tooth.

:class:`FiniteElementCoupling` implements the ``coupling`` protocol that
:func:`gearsim.stiffness.mesh.mesh_stiffness` uses when ``stiffness.coupling = "fe"``.

References
----------
.. [Sainsot2004] P. Sainsot, P. Velex, O. Duverger, Contribution of gear body to tooth
   deflections - a new bidimensional analytical formula, J. Mech. Des. 126 (2004)
   748-752 (the independent-tooth foundation term the coupling complements).
.. [Xie2018] C. Xie et al., Analytical formulas for gear body-induced tooth deflections
   of spur gears considering structure coupling effect, Int. J. Mech. Sci. (2018) (the
   coupling of neighbouring teeth through the body that Sainsot's formula leaves out).
"""

from __future__ import annotations

import numpy as np

from gearsim.errors import require
from gearsim.fem.geometry import SectorOptions, mesh_sector
from gearsim.fem.tables import (
    DEFAULT_LEVEL,
    _cache_key,
    _gear_key,
    _read_npz,
    _write_npz,
    cache_dir,
    fe_nodes,
)
from gearsim.fem.tooth import flank_loads, neighbour_cross
from gearsim.geometry.gear import Gear

__all__ = ["COUPLING_VERSION", "FiniteElementCoupling", "fe_neighbour_coupling"]

#: Bump when the coupling model changes so that old cache files are not reused.
#: 2: the file also holds the reading of tooth +1 (``plus``).
COUPLING_VERSION = 2


def _key(gear: Gear, plane: str, level: int) -> str:
    doc = {
        "kind": "coupling", "v": COUPLING_VERSION, "gear": _gear_key(gear),
        "plane": plane, "level": level, "nodes": fe_nodes(gear).tolist(),
    }
    return _cache_key(doc)[0]


def fe_neighbour_coupling(gear: Gear, *, plane: str = "stress", level: int = DEFAULT_LEVEL,
                          use_cache: bool = True
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both neighbours' deflections under loads on tooth 0 of the healthy gear [m/(N/m)].

    One factorisation of the whole gear (bore fixed, as the FE tooth tables), unit loads
    per metre of face width on tooth 0 at the :func:`~gearsim.fem.tables.fe_nodes` radii,
    read on teeth -1 and +1 (:func:`gearsim.fem.tooth.neighbour_cross`); cached.

    Parameters
    ----------
    gear
        The gear.
    plane
        ``"stress"`` or ``"strain"``.
    level
        FE mesh level (:class:`gearsim.fem.geometry.SectorOptions`).
    use_cache
        Read and write the disk cache.

    Returns
    -------
    radii, minus, plus
        The :func:`~gearsim.fem.tables.fe_nodes` radii [m]; ``minus[i, j]`` = X[i, j]
        (module docstring), the deflection of tooth 0 at Q(r_i) along its load direction
        under a unit load on tooth +1 at r_j, read as tooth -1 under the load on tooth 0
        at r_j; ``plus[i, j]`` the deflection of tooth +1 at Q(r_i) under the load at r_j
        [m/(N/m)].
    """
    require(plane in ("stress", "strain"), "stiffness.plane", plane,
            'must be "stress" or "strain"')
    nodes = fe_nodes(gear)
    path = cache_dir() / f"{_key(gear, plane, level)}.npz"
    got = _read_npz(path, nodes, ("coupling", "plus")) if use_cache else None
    if got is not None:
        return nodes, *got
    opt = SectorOptions(level=level)
    sector = mesh_sector(gear, options=opt)
    model, fixed, loads, _, _ = flank_loads(gear, sector, nodes, plane, opt)
    u = model.solve(loads, fixed)
    minus, plus = neighbour_cross(model, gear, u, nodes)
    if use_cache:
        _write_npz(path, radii=nodes, coupling=minus, plus=plus, level=np.array(level))
    return nodes, minus, plus


class FiniteElementCoupling:
    """Neighbouring-tooth coupling from the FE gear body (``stiffness.coupling = "fe"``).

    Implements the ``cross`` method that :func:`gearsim.stiffness.mesh.mesh_stiffness`
    asks for when coupling is on; values interpolated from :func:`fe_neighbour_coupling`
    (``minus``) with a bicubic spline in roll length.

    Parameters
    ----------
    plane
        ``"stress"`` or ``"strain"``.
    level
        FE mesh level.
    """

    name = "fe"

    def __init__(self, plane: str = "stress", level: int = DEFAULT_LEVEL) -> None:
        self.plane = plane
        self.level = level
        self._splines: dict[tuple, tuple] = {}

    def cross(self, gear: Gear, r_read: np.ndarray, r_load: np.ndarray) -> np.ndarray:
        """Cross compliance X(r_read, r_load) per unit face width [m/(N/m)].

        Parameters
        ----------
        gear : Gear
            The gear.
        r_read : ndarray
            Contact radius of the tooth whose deflection is read [m].
        r_load : ndarray
            Contact radius on its ``+x``-side neighbour, which carries the load [m]
            (same shape as ``r_read``).

        Returns
        -------
        ndarray
            X at each pair of radii (clipped to the involute of the table) [m/(N/m)].
        """
        key = (id(gear), gear.teeth, gear.normal_module, gear.bore_radius_value)
        if key not in self._splines:
            nodes, x, _ = fe_neighbour_coupling(gear, plane=self.plane, level=self.level)
            rb = gear.base_radius
            ln = np.sqrt(nodes**2 - rb**2)
            from scipy.interpolate import RectBivariateSpline

            self._splines[key] = (RectBivariateSpline(ln, ln, x, kx=3, ky=3), ln[0], ln[-1])
        spl, lo, hi = self._splines[key]
        rb = gear.base_radius

        def roll(r):
            return np.clip(np.sqrt(np.maximum(np.asarray(r, float) ** 2 - rb**2, 0.0)), lo, hi)

        a, b = roll(r_read), roll(r_load)
        return spl.ev(a.ravel(), b.ravel()).reshape(a.shape)
