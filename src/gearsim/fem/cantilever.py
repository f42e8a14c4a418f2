"""Verification of the elasticity solver on a cantilever with a closed-form deflection.

A rectangle 0 <= x <= L, -c <= y <= c (depth H = 2c, unit thickness, plane stress) is
loaded at the free end x = 0 by a shear force P with the parabolic distribution
tau(y) = P (c^2 - y^2) / (2 I), I = 2 c^3 / 3. The exact 2D elasticity solution is
(Timoshenko & Goodier 1970, sec. 21)

    u = -P x^2 y/(2EI) - nu P y^3/(6EI) + P y^3/(6IG) + d y,
    v =  nu P x y^2/(2EI) + P x^3/(6EI) - e x + f,        e = d + P c^2/(2IG),

with the rigid-body constants d, f fixed here by holding the clamped section x = L
*on average*: zero mean deflection and zero mean rotation (int u y dy = 0), the
clamp a Timoshenko beam assumes. Then the deflection of the loaded end is

    delta = v(0, 0) = P L^3/(3EI) + alpha P L/(G A),  alpha = 1.2 - nu/(10 (1 + nu)),

i.e. the Timoshenko beam formula with the shear coefficient 1.2 of a rectangle and a
small Poisson correction of the 2D solution (alpha = 1.177 for nu = 0.3). The finite
element model prescribes the exact displacement on x = L (the section keeps its exact
warping but is held as above) and the parabolic traction on x = 0; its deflection at
(0, 0) must tend to delta.

References
----------
.. [TG1970] S. P. Timoshenko, J. N. Goodier, Theory of Elasticity, 3rd ed., McGraw-Hill
   1970, sec. 21 (bending of a cantilever loaded at the end).
.. [Cowper1966] G. R. Cowper, The shear coefficient in Timoshenko's beam theory,
   J. Appl. Mech. 33 (1966) 335-340.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gearsim.errors import InputError
from gearsim.fem.geometry import drop_unused_nodes, gmsh_session
from gearsim.fem.solve import ElasticModel

__all__ = ["CantileverResult", "cantilever_exact", "convergence_rate", "solve_cantilever",
           "timoshenko_deflection"]


def timoshenko_deflection(load: float, length: float, depth: float, youngs_modulus: float,
                          poisson_ratio: float, *, alpha: float | None = None) -> float:
    """Tip deflection P L^3/(3EI) + alpha P L/(G A) of a rectangular cantilever [m].

    Parameters
    ----------
    load
        End shear force P per unit thickness [N].
    length, depth
        L and H [m] (unit thickness: A = H, I = H^3/12).
    youngs_modulus, poisson_ratio
        E [Pa], nu [-].
    alpha
        Shear coefficient; default the exact plane-stress value
        1.2 - nu / (10 (1 + nu)) for a clamp holding the section on average (module
        docstring). Pass 1.2 for the Timoshenko beam value.

    Returns
    -------
    float
        Tip deflection [m].

    References
    ----------
    Timoshenko & Goodier (1970), sec. 21; Cowper (1966).

    Examples
    --------
    L 50 mm, H 10 mm, steel, P = 1 N: P L^3/(3EI) = 2.4272e-9 m plus
    1.1769 P L/(G A) = 7.43e-11 m:

    >>> round(timoshenko_deflection(1.0, 0.05, 0.01, 206e9, 0.3) * 1e9, 5)
    2.50146
    >>> round(timoshenko_deflection(1.0, 0.05, 0.01, 206e9, 0.3, alpha=1.2) * 1e9, 5)
    2.50291
    """
    e, nu = youngs_modulus, poisson_ratio
    g = e / (2.0 * (1.0 + nu))
    a = depth
    i = depth**3 / 12.0
    if alpha is None:
        alpha = 1.2 - nu / (10.0 * (1.0 + nu))
    return load * length**3 / (3.0 * e * i) + alpha * load * length / (g * a)


def cantilever_exact(x: np.ndarray, y: np.ndarray, *, load: float, length: float,
                     depth: float, youngs_modulus: float, poisson_ratio: float
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Exact plane-stress displacement (u, v) of the end-loaded cantilever.

    Timoshenko & Goodier (1970), sec. 21, with the clamp constants of the module
    docstring.

    Parameters
    ----------
    x
        Distance from the loaded end [m].
    y
        Distance from the neutral axis [m].
    load
        End shear P per unit thickness [N].
    length, depth
        L and H [m].
    youngs_modulus, poisson_ratio
        E [Pa], nu [-].

    Returns
    -------
    u, v : ndarray
        Displacements [m].

    References
    ----------
    Timoshenko & Goodier (1970), sec. 21.

    Examples
    --------
    At the loaded end on the axis the exact solution equals the beam formula with
    alpha = 1.2 - nu / (10 (1 + nu)) (module docstring):

    >>> import numpy as np
    >>> kw = dict(load=1.0, length=0.05, depth=0.01, youngs_modulus=206e9,
    ...           poisson_ratio=0.3)
    >>> v0 = cantilever_exact(np.array(0.0), np.array(0.0), **kw)[1]
    >>> round(float(v0) * 1e9, 5)
    2.50146
    """
    p, ll, c = load, length, 0.5 * depth
    e, nu = youngs_modulus, poisson_ratio
    g = e / (2.0 * (1.0 + nu))
    i = 2.0 * c**3 / 3.0
    d = p * ll**2 / (2 * e * i) + nu * p * c**2 / (10 * e * i) - p * c**2 / (10 * i * g)
    ee = d + p * c**2 / (2 * i * g)
    f = ee * ll - p * ll**3 / (6 * e * i) - nu * p * ll * c**2 / (6 * e * i)
    u = (-p * x**2 * y / (2 * e * i) - nu * p * y**3 / (6 * e * i) + p * y**3 / (6 * i * g)
         + d * y)
    v = nu * p * x * y**2 / (2 * e * i) + p * x**3 / (6 * e * i) - ee * x + f
    return u, v


@dataclass(frozen=True)
class CantileverResult:
    """FE and closed-form tip deflection of the cantilever.

    Parameters
    ----------
    h
        Element size [m].
    fe
        FE deflection at the loaded end [m].
    exact
        Exact 2D deflection [m].
    timoshenko_12
        Beam value with the shear coefficient 1.2 [m].
    ndofs
        Degrees of freedom of the FE model.
    """

    h: float
    fe: float
    exact: float
    timoshenko_12: float
    ndofs: int

    @property
    def error(self) -> float:
        """Relative error of the FE deflection against the exact 2D value [-]."""
        return (self.fe - self.exact) / self.exact


def _rectangle(length: float, depth: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Unstructured gmsh triangulation of the rectangle [0, L] x [-H/2, H/2]."""

    with gmsh_session() as gmsh:
        geo = gmsh.model.geo
        c = 0.5 * depth
        pts = [geo.addPoint(x, y, 0.0, h) for x, y in
               ((0.0, -c), (length, -c), (length, c), (0.0, c))]
        lines = [geo.addLine(pts[i], pts[(i + 1) % 4]) for i in range(4)]
        geo.addPlaneSurface([geo.addCurveLoop(lines)])
        geo.synchronize()
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(tags.size)
        et, _, en = gmsh.model.mesh.getElements(2)
        tri = index[en[list(et).index(2)].astype(np.int64)].reshape(-1, 3)
        xy = coords.reshape(-1, 3)[:, :2]
    p, t, _ = drop_unused_nodes(xy, tri)
    return p, t


def solve_cantilever(*, length: float = 0.05, depth: float = 0.01, h: float = 1e-3,
                     load: float = 1.0, youngs_modulus: float = 206e9,
                     poisson_ratio: float = 0.3, order: int = 2) -> CantileverResult:
    """FE tip deflection of the end-loaded cantilever (plane stress, unit thickness).

    Parameters
    ----------
    length, depth
        L, H [m].
    h
        Element size [m].
    load
        End shear P [N].
    youngs_modulus, poisson_ratio
        E [Pa], nu [-].
    order
        Element order (1 or 2).

    Returns
    -------
    CantileverResult
        FE deflection at (0, 0), exact 2D value and the alpha = 1.2 beam value [m].

    Raises
    ------
    InputError
        If L, H <= 0 or ``h`` is not in (0, min(L, H)].
    """
    if not (length > 0 and depth > 0 and 0 < h <= min(length, depth)):
        raise InputError("cantilever.h", h, "must be in (0, min(L, H)] with L, H > 0")
    p, t = _rectangle(length, depth, h)
    model = ElasticModel(p, t, youngs_modulus, poisson_ratio, plane="stress", order=order)
    kw = dict(load=load, length=length, depth=depth, youngs_modulus=youngs_modulus,
              poisson_ratio=poisson_ratio)
    tol = 1e-9 * length
    x_mid = model.mesh.p[:, model.mesh.facets].mean(axis=1)
    bf = model.mesh.boundary_facets()
    clamp = bf[np.abs(x_mid[0, bf] - length) < tol]
    free_end = bf[np.abs(x_mid[0, bf]) < tol]
    fixed = model.dofs_on_facets(clamp)
    # exact values at every dof location (vertices and P2 edge midpoints)
    locs = model.basis.doflocs
    ue, ve = cantilever_exact(locs[0], locs[1], **kw)
    values = np.zeros(model.ndofs)
    values[model.basis.nodal_dofs[0]] = ue[model.basis.nodal_dofs[0]]
    values[model.basis.nodal_dofs[1]] = ve[model.basis.nodal_dofs[1]]
    if order == 2:
        values[model.basis.facet_dofs[0]] = ue[model.basis.facet_dofs[0]]
        values[model.basis.facet_dofs[1]] = ve[model.basis.facet_dofs[1]]
    i2 = 2.0 * (0.5 * depth) ** 3 / 3.0
    f = model.traction_load(free_end, lambda x, y: (0.0 * y, load * ((0.5 * depth) ** 2 - y**2)
                                                    / (2.0 * i2)))
    u = model.solve(f, fixed, values=values)
    tip = float((model.probe(np.array([[0.0], [0.0]])) @ u)[1])
    exact = float(cantilever_exact(np.array(0.0), np.array(0.0), **kw)[1])
    return CantileverResult(h=h, fe=tip, exact=exact,
                            timoshenko_12=timoshenko_deflection(load, length, depth,
                                                                youngs_modulus, poisson_ratio,
                                                                alpha=1.2),
                            ndofs=model.ndofs)


def convergence_rate(h: np.ndarray, err: np.ndarray) -> float:
    """Least-squares slope of log|err| against log h.

    Parameters
    ----------
    h
        Element sizes [m].
    err
        Errors at those sizes (sign ignored).

    Returns
    -------
    float
        Observed order of convergence [-].

    Examples
    --------
    >>> round(convergence_rate([0.1, 0.05, 0.025], [1e-2, 2.5e-3, 6.25e-4]), 12)
    2.0
    """
    h = np.asarray(h, dtype=float)
    e = np.abs(np.asarray(err, dtype=float))
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])

