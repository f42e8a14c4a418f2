"""Plane linear elasticity with scikit-fem, and frictionless crack-face contact.

Weak form (per unit thickness, displacement u, test field v):

    int_Omega sigma(u) : eps(v) dA = int_Gamma_N t . v ds,
    sigma = lambda tr(eps) I + 2 mu eps,  eps = (grad u + grad u^T) / 2,

with mu = E / (2 (1 + nu)) and lambda = E nu / ((1 + nu)(1 - 2 nu)) for plane strain or
the plane-stress value lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2)
(e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1, 6th ed., ch. 6).
Quadratic Lagrange triangles (P2) by default.

Crack-face contact (frictionless, small displacements): for every pair of coincident
nodes (i on the - face, j on the + face, crack normal n pointing from - to +) the gap
is g = (u_j - u_i) . n; non-penetration g >= 0 is enforced by a penalty spring of
stiffness k_p acting on g only (no tangential coupling) on the active pairs, with a
primal active-set loop: a pair becomes active when g < 0 and inactive when its spring
would pull (g > 0). The spring of a node is ``PENALTY * E * w / h`` with w the node's
share of the face length (Simpson weights for P2) and h the element size: the
interpenetration left is about 1/PENALTY of the local element strain.

References
----------
.. [Gustafsson2020] T. Gustafsson, G. D. McBain, scikit-fem: A Python package for finite
   element assembly, J. Open Source Softw. 5 (2020) 2369.
.. [Wriggers2006] P. Wriggers, Computational Contact Mechanics, 2nd ed., Springer 2006,
   ch. 6 (penalty method) and 7.2 (active-set strategy).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # scipy.sparse is imported where it is used (start-up time)
    import scipy.sparse as sp

from gearsim.errors import InputError, SimulationError

__all__ = ["PENALTY", "ElasticModel", "lame", "plane_lame"]

#: Penalty factor of the crack-face springs (see module docstring).
PENALTY = 1e4
MAX_ACTIVE_SET_ITERATIONS = 60


@dataclass(frozen=True)
class _Factorization:
    """LU factorization of the stiffness matrix on the free dofs, with what it needs to
    solve (:meth:`ElasticModel.solve`, :meth:`ElasticModel.contact_solve`)."""

    fixed: np.ndarray
    free: np.ndarray
    a: sp.csr_matrix
    lu: object


def lame(youngs_modulus: float, poisson_ratio: float) -> tuple[float, float]:
    """Lame constants of the 3D material.

    Parameters
    ----------
    youngs_modulus, poisson_ratio
        E [Pa] and nu [-].

    Returns
    -------
    tuple of float
        (lambda, mu) = (E nu / ((1 + nu)(1 - 2 nu)), E / (2 (1 + nu))) [Pa].

    Examples
    --------
    Steel, E 206 GPa, nu 0.3: lambda = 118.85 GPa, mu = 79.23 GPa.

    >>> [round(v / 1e9, 2) for v in lame(206e9, 0.3)]
    [118.85, 79.23]
    """
    e, nu = youngs_modulus, poisson_ratio
    return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))


def plane_lame(youngs_modulus: float, poisson_ratio: float, plane: str) -> tuple[float, float]:
    """Lame constants of the 2D constitutive law.

    Plane stress: lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2);
    plane strain: the 3D lambda.

    Parameters
    ----------
    youngs_modulus, poisson_ratio
        E [Pa] and nu [-].
    plane
        ``"stress"`` or ``"strain"``.

    Returns
    -------
    tuple of float
        (lambda, mu) [Pa].

    Raises
    ------
    InputError
        If ``plane`` is neither.

    Examples
    --------
    Plane stress, steel: E nu / (1 - nu^2) = 206 x 0.3 / 0.91 = 67.91 GPa.

    >>> round(plane_lame(206e9, 0.3, "stress")[0] / 1e9, 2)
    67.91
    """
    if plane not in ("stress", "strain"):
        raise InputError("stiffness.plane", plane, 'must be "stress" or "strain"')
    lam, mu = lame(youngs_modulus, poisson_ratio)
    if plane == "stress":
        lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    return lam, mu


@dataclass
class ElasticModel:
    """Assembled 2D elasticity problem on a triangle mesh (unit thickness).

    Parameters
    ----------
    p, t
        Nodes (2, n) [m] and triangles (3, m).
    youngs_modulus, poisson_ratio
        Material [Pa], [-].
    plane
        ``"stress"`` or ``"strain"``.
    order
        Polynomial order of the displacement, 1 or 2.

    Raises
    ------
    InputError
        If ``order`` or ``plane`` is invalid.

    References
    ----------
    Gustafsson & McBain (2020) (scikit-fem); Zienkiewicz & Taylor, vol. 1, ch. 6.
    """

    p: np.ndarray
    t: np.ndarray
    youngs_modulus: float
    poisson_ratio: float
    plane: str = "stress"
    order: int = 2
    _facet_index: dict = field(default_factory=dict, repr=False, init=False)

    def __post_init__(self) -> None:
        from skfem import Basis, BilinearForm, ElementTriP1, ElementTriP2, ElementVector, MeshTri
        from skfem.helpers import ddot, div, sym_grad

        if self.order not in (1, 2):
            raise InputError("fem.order", self.order, "must be 1 or 2")
        self.mesh = MeshTri(np.ascontiguousarray(self.p, dtype=float),
                            np.ascontiguousarray(self.t, dtype=np.int64))
        self.element = ElementVector(ElementTriP2() if self.order == 2 else ElementTriP1())
        self.basis = Basis(self.mesh, self.element, intorder=2 * self.order)
        lam, mu = plane_lame(self.youngs_modulus, self.poisson_ratio, self.plane)

        # sigma(u) : eps(v) = 2 mu eps(u) : eps(v) + lam div u div v (isotropic Hooke's
        # law); the same form as skfem.models.elasticity.linear_elasticity, which builds
        # the 4th-order tensor C at every quadrature point: 3x slower, the same matrix
        # to round-off (4e-16 relative, measured on 16k P2 triangles)
        @BilinearForm
        def elasticity(u, v, w):
            eu = sym_grad(u)
            return 2.0 * mu * ddot(eu, sym_grad(v)) + lam * div(u) * div(v)

        self.K = elasticity.assemble(self.basis).tocsr()
        f = self.mesh.facets
        self._facet_index = {(int(a), int(b)): i for i, (a, b) in
                             enumerate(zip(np.minimum(f[0], f[1]), np.maximum(f[0], f[1]),
                                           strict=True))}

    @property
    def ndofs(self) -> int:
        """Number of displacement degrees of freedom."""
        return int(self.basis.N)

    # ----------------------------------------------------------------- dof lookups
    def facets_on_nodes(self, nodes: np.ndarray) -> np.ndarray:
        """Boundary facets whose two vertices are both in ``nodes``.

        Parameters
        ----------
        nodes
            Mesh vertex indices.

        Returns
        -------
        ndarray
            Facet indices.
        """
        bf = self.mesh.boundary_facets()
        inside = np.isin(self.mesh.facets[:, bf], nodes).all(axis=0)
        return bf[inside]

    def facet(self, a: int, b: int) -> int:
        """Index of the facet (edge) between two nodes.

        Parameters
        ----------
        a, b
            Vertex indices (either order).

        Returns
        -------
        int
            Facet index.
        """
        return self._facet_index[(min(a, b), max(a, b))]

    def dofs_on_facets(self, facets: np.ndarray) -> np.ndarray:
        """All displacement dofs (both components, vertices and edges) of facets.

        Parameters
        ----------
        facets
            Facet indices.

        Returns
        -------
        ndarray
            Dof indices.
        """
        return self.basis.get_dofs(facets=facets).flatten()

    def node_dofs(self, node: int) -> np.ndarray:
        """(x, y) dofs of a mesh vertex.

        Parameters
        ----------
        node
            Vertex index.

        Returns
        -------
        ndarray, shape (2,)
            Dof indices.
        """
        return self.basis.nodal_dofs[:, node]

    def edge_dofs(self, facet: int) -> np.ndarray:
        """(x, y) dofs of the midpoint of a P2 edge.

        Parameters
        ----------
        facet
            Facet index.

        Returns
        -------
        ndarray, shape (2,)
            Dof indices.
        """
        return self.basis.facet_dofs[:, facet]

    # ----------------------------------------------------------------- loads
    def traction_load(self, facets: np.ndarray, traction, *, intorder: int | None = None
                      ) -> np.ndarray:
        """Load vector of a traction on boundary ``facets``.

        Parameters
        ----------
        facets
            Facet indices.
        traction
            Constant vector (2,) [Pa x m / m = N/m per unit thickness] or a callable
            ``traction(x, y) -> (tx, ty)`` on quadrature points.
        intorder
            Order of the facet quadrature (default 2 order + 2).
        """
        from skfem import FacetBasis, LinearForm

        fb = FacetBasis(self.mesh, self.element, facets=np.asarray(facets),
                        intorder=intorder or 2 * self.order + 2)

        @LinearForm
        def form(v, w):
            if callable(traction):
                tx, ty = traction(w.x[0], w.x[1])
            else:
                tx, ty = traction
            return tx * v[0] + ty * v[1]

        return form.assemble(fb)

    def probe(self, points: np.ndarray) -> sp.csr_matrix:
        """Interpolation matrix at points.

        Parameters
        ----------
        points
            Coordinates, shape (2, k) [m].

        Returns
        -------
        scipy.sparse.csr_matrix
            P with ``P @ u`` = [u_x at the points, u_y at the points].
        """
        return self.basis.probes(np.asarray(points, dtype=float).reshape(2, -1)).tocsr()

    # ----------------------------------------------------------------- solving
    def solve(self, loads: np.ndarray, fixed: np.ndarray, *, values: np.ndarray | None = None,
              extra: sp.spmatrix | None = None) -> np.ndarray:
        """Solve K u = f for one or several load vectors with Dirichlet dofs ``fixed``.

        Parameters
        ----------
        loads
            Load vectors, shape (ndofs,) or (ndofs, k) [N].
        fixed
            Dirichlet dofs.
        values
            Prescribed values of all dofs (only ``fixed`` entries used) [m]; default 0.
        extra
            Additional stiffness (e.g. contact springs) added to K.

        Returns
        -------
        ndarray
            Displacements, same shape as ``loads`` [m].
        """
        return self._solve_factored(self._factorize(fixed, extra), loads, values)

    def _factorize(self, fixed: np.ndarray, extra: sp.spmatrix | None) -> _Factorization:
        """Factorization of K (+ ``extra``) on the free dofs (``fixed`` eliminated)."""
        n = self.ndofs
        fixed = np.unique(np.asarray(fixed, dtype=np.int64))
        if fixed.size == 0:
            raise InputError("boundary conditions", "none",
                             "at least the bore (or clamped end) must be fixed")
        free = np.setdiff1d(np.arange(n), fixed)
        a = self.K if extra is None else (self.K + extra).tocsr()
        aff = a[free][:, free].tocsc()
        from scipy.sparse.linalg import splu

        try:  # symmetric positive definite: symmetric ordering, no pivoting (as the FE
            # pair's gears): half the fill of the default COLAMD, factor 30 % faster
            # (measured on the level-2 sectors of the 19/48 and Table-1 gears)
            lu = splu(aff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options={"SymmetricMode": True})
        except RuntimeError as exc:  # singular: a part of the model is not held
            raise SimulationError(f"the stiffness matrix is singular ({exc}): some part of "
                                  "the model is not held by the boundary conditions") from None
        return _Factorization(fixed=fixed, free=free, a=a, lu=lu)

    def _solve_factored(self, fac: _Factorization, loads: np.ndarray,
                        values: np.ndarray | None = None) -> np.ndarray:
        """Displacements for ``loads`` (ndofs,) or (ndofs, k) with a factorization [m]."""
        f = np.asarray(loads, dtype=float)
        one = f.ndim == 1
        f2 = f[:, None] if one else f
        n = self.ndofs
        x = np.zeros((n, f2.shape[1]))
        rhs = f2[fac.free]
        if values is not None:  # (zero prescribed values add exactly zero)
            x[fac.fixed] = np.asarray(values, dtype=float).reshape(n, -1)[fac.fixed]
            rhs = rhs - fac.a[fac.free][:, fac.fixed] @ x[fac.fixed]
        x[fac.free] = fac.lu.solve(np.ascontiguousarray(rhs))
        return x[:, 0] if one else x

    def contact_solve(self, load: np.ndarray, fixed: np.ndarray, pairs: np.ndarray,
                      normal: np.ndarray, weights: np.ndarray, *, h: float,
                      active: np.ndarray | None = None, reuse: dict | None = None
                      ) -> tuple[np.ndarray, np.ndarray, int]:
        """Solve with frictionless unilateral contact between node pairs.

        Parameters
        ----------
        load
            Load vector (ndofs,) [N].
        fixed
            Dirichlet dofs (zero).
        pairs
            Dof pairs, shape (k, 2, 2): [pair, (minus, plus), (x, y)].
        normal
            Unit crack normal, from the - face to the + face.
        weights
            Length share of each pair [m].
        h
            Element size at the crack [m].
        active
            Initial active set (bool, k); default all active (closed crack).
        reuse
            A dict the caller keeps across calls (e.g. the load positions of one FE
            tooth): it holds the last factorization and the model, crack problem and
            active set it was made for, and a solve whose model, problem (fixed dofs,
            pairs, normal, weights, h) and active set are the same reuses it instead of factorizing
            again; the matrix is then the same, so the result is the one of a fresh
            factorization. ``None`` (default): factorize for every active set.

        Returns
        -------
        u : ndarray
            Displacements [m].
        active : ndarray of bool
            Final active set (closed pairs).
        iterations : int
            Active-set iterations used.

        Raises
        ------
        SimulationError
            If the active set does not settle.
        """
        k = pairs.shape[0]
        act = np.ones(k, dtype=bool) if active is None else np.asarray(active, bool).copy()
        kp = PENALTY * self.youngs_modulus * np.asarray(weights) / h
        n = self.ndofs
        # constraint rows: g = B u, B[i, plus] = n, B[i, minus] = -n
        rows = np.repeat(np.arange(k), 4)
        cols = np.column_stack([pairs[:, 1, 0], pairs[:, 1, 1], pairs[:, 0, 0],
                                pairs[:, 0, 1]]).ravel()
        vals = np.tile([normal[0], normal[1], -normal[0], -normal[1]], k)
        import scipy.sparse as sp

        b = sp.csr_matrix((vals, (rows, cols)), shape=(k, n))
        # the crack problem a kept factorization must belong to (the active set aside)
        problem = None if reuse is None else hashlib.sha256(b"".join(
            np.ascontiguousarray(v).tobytes() for v in (
                np.unique(np.asarray(fixed, dtype=np.int64)), np.asarray(pairs, np.int64),
                np.asarray(normal, float), kp))).hexdigest()
        for it in range(1, MAX_ACTIVE_SET_ITERATIONS + 1):
            if (reuse is not None and reuse.get("model") is self
                    and reuse.get("problem") == problem
                    and np.array_equal(reuse.get("active"), act)):
                fac = reuse["factorization"]  # the same matrix: no new factorization
            else:
                fac = self._factorize(fixed, b.T @ sp.diags(kp * act) @ b)
                if reuse is not None:
                    reuse.update(model=self, problem=problem, active=act.copy(),
                                 factorization=fac)
            u = self._solve_factored(fac, load)
            g = b @ u
            tol = 1e-9 * max(np.max(np.abs(u)), 1e-300)
            new = np.where(act, g <= tol, g < -tol)
            if np.array_equal(new, act):
                return u, act, it
            act = new
        raise SimulationError(f"crack-face contact did not settle in "
                              f"{MAX_ACTIVE_SET_ITERATIONS} active-set iterations")


def face_dof_pairs(model: ElasticModel, p: np.ndarray, pairs: np.ndarray, edges,
                   dup: dict[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Dof pairs (k, 2, 2), face-length weights (k,) [m] and positions (k, 2) [m] of a crack.

    ``pairs`` (2, n): the vertex on one face and its duplicate on the other; ``edges``:
    (a, b) vertex pairs of the first face's edges, ``dup`` a vertex's duplicate. Weights:
    1/6 per vertex and 4/6 at the midpoint of each edge's length for P2 (then a pair per
    edge midpoint too), 1/2 per vertex for P1.
    """
    index = {int(a): i for i, a in enumerate(pairs[0])}
    dofs = [(model.node_dofs(int(a)), model.node_dofs(int(b))) for a, b in pairs.T]
    weights = [0.0] * len(dofs)
    positions = [p[:, int(a)] for a in pairs[0]]
    share = 1.0 / 6.0 if model.order == 2 else 0.5
    for a, b in edges:
        a, b = int(a), int(b)
        length = float(np.hypot(*(p[:, a] - p[:, b])))
        for nd in (a, b):
            if nd in index:
                weights[index[nd]] += share * length
        if model.order == 2:
            f1 = model.facet(a, b)
            f2 = model.facet(dup.get(a, a), dup.get(b, b))
            dofs.append((model.edge_dofs(f1), model.edge_dofs(f2)))
            weights.append(4.0 / 6.0 * length)
            positions.append(0.5 * (p[:, a] + p[:, b]))
    return (np.array([[d1, d2] for d1, d2 in dofs], dtype=np.int64), np.asarray(weights),
            np.asarray(positions))
