"""Finite-element gear pair in frictionless contact: loaded TE, mesh stiffness, load sharing.

Both gears of a :class:`~gearsim.geometry.pair.GearPair` are meshed whole in 2D
(:func:`gearsim.fem.geometry.mesh_sector`, the real rack-generated outline, plane stress
by default as the potential-energy model), with finer elements on the involutes of the
teeth that can touch (:class:`~gearsim.fem.geometry.FlankRefinement`): at level N the
teeth get h = m_n / (4 2^N), the loaded involutes h_c = h / CONTACT_REFINEMENT, growing
away from them with slope CONTACT_GROWTH 2^(2 - N) (the whole size field halves per
level), and the involutes are splines through 160 points (0.1 um off the involute with
the 32 points of the single-tooth model, about 1 % of the loaded TE). Each bore is tied
to a rigid hub with one rotation: the displacement of gear i is
``u_i = theta_i (z x r) + w_i`` with ``w_i = 0`` on the bore, so ``w_i`` is the
solution of the bore-clamped model (K_i w_i = f_i) and ``theta_i`` the hub rotation.
The driven hub is held (theta_2 = 0, or a prescribed value), the driver hub carries the
torque T (per unit face width in the 2D model, T / b).

Placement: centres O_1 = (0, 0), O_2 = (0, a_w); the transverse line of action is
X(l) = T_1 + l d with T_1 = r_b1 (-sin a_wt, cos a_wt), d = (cos a_wt, sin a_wt), l
measured from T_1 (as in :class:`~gearsim.geometry.pair.GearPair`). At the mesh
position u (fraction of a mesh cycle) the rigid gears are turned so that the ``+x``
involute (tooth frame of :class:`~gearsim.geometry.profile.ToothProfile`) of driver tooth
k touches the ``+x`` involute of driven tooth -k at l_k = l_A + (u + k) p_b, l_A the start
of contact (driven tip circle): driver angle phi_1(u) = phi_1(0) - 2 pi u / z_1 (clockwise),
driven phi_2(u) = phi_2(0) + 2 pi u / z_2. At the zero-backlash centre distance the back
(``-x``) flanks touch as well; a positive torque loads the ``+x`` (drive) flanks, a
negative one the back flanks. Under load, pairs also touch outside the path of contact
A-E (tip corners, "extended contact"); the candidate teeth reach TOOTH_MARGIN base pitches
beyond it.

Contact (frictionless, small displacements, node to segment): every P2 boundary node
(vertices and edge midpoints) of the candidate flanks and tips of one gear ("slave") is
paired with its closest point on the straight P2 edges of the other gear's candidate
flanks and tips ("master"), pass 1 driver -> driven, pass 2 the driven tips -> driver
(so that a tip corner cannot slip between the nodes of the mating flank). With n the
outward master normal at that point and ``q`` the point, the gap is

    g_k = g0_k + n_k . (u_slave - u_master(q)),   g0_k = (x_slave - q) . n_k,

u_master(q) from the quadratic trace of the P2 edge. In matrix form, with the contact
forces lambda_k >= 0 (per unit thickness, along +n on the slave, -n on the master)
loading both gears through the same rows, f_i = B_i^T lambda:

    g = g0 + c_1 theta_1 + c_2 theta_2 + A lambda,   A = sum_i B_i K_i^-1 B_i^T,
    c_i = B_i r_i  (r_i the rigid rotation field (-y, x) of gear i),
    g >= 0, lambda >= 0, lambda . g = 0,   c_1 . lambda = T (hub equilibrium).

This is the optimality system of the convex quadratic programme
min 1/2 lambda^T A lambda + g0^T lambda subject to lambda >= 0, c_1^T lambda = T, whose
multiplier of the equality is theta_1; it is solved exactly (no penalty) by a primal
active-set method (Nocedal & Wright, Numerical Optimization, 2nd ed., alg. 16.3).
Columns of A = B K^-1 B^T come from one sparse LU factorisation per gear (reused over
all mesh positions: only the rigid placement changes), computed only for the
constraints that carry a force at some iteration (A[:, F] lambda_F gives all gaps).
Candidates are the nodes whose initial gap is below a window; after the solve the gap of
every node of the candidate flanks is checked (``g >= -tol``) and the window grown until
none penetrates.

Results: transmission error along the line of action delta = -sign(T) (r_b1 theta_1 +
r_b2 theta_2) (driver lagging the rigid kinematic position), line-of-action force
F = |T| / r_b1 and the mesh stiffness k = F / delta over the face width b (the 2D model
is per unit width: k = b k_2D); load share of each tooth pair as its share of the
driver torque; contact half width from the second moment of the pressure,
b = 2 sqrt(sum lambda s^2 / sum lambda) (exact for the Hertz ellipse); pressure as the
mean over each P2 edge of the driver flank, (f_a / 2 + f_mid + f_b / 2) / L (node-to-
segment forces on P2 edges alternate between vertices and midpoints about the consistent
1 : 2 ratio, the edge mean is smooth); root stress as the largest
principal stress on the tension-side fillet of each loaded tooth (P2 stresses at the
element vertices, averaged over the elements at a node).

References
----------
.. [Johnson1985] K. L. Johnson, Contact Mechanics, Cambridge University Press 1985,
   ch. 4-5 (2D Hertz contact: b = sqrt(4 F R / (pi E*)), p0 = 2 F / (pi b)).
.. [Wriggers2006] P. Wriggers, Computational Contact Mechanics, 2nd ed., Springer 2006,
   ch. 9 (node-to-segment contact discretisation).
.. [Nocedal2006] J. Nocedal, S. J. Wright, Numerical Optimization, 2nd ed., Springer
   2006, sec. 16.5 (active-set methods for convex QP).
.. [Coy1982] J. J. Coy, C. H. Chao, A method of selecting grid size to account for Hertz
   deformation in finite element analysis of spur gears, J. Mech. Des. 104 (1982)
   759-766 (element size in the contact zone of an FE gear pair).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # scipy.sparse is imported where it is used (start-up time)
    import scipy.sparse as sp

from gearsim.errors import InputError, SimulationError
from gearsim.fem.geometry import (
    FlankRefinement,
    SectorOptions,
    crack_line,
    distance_threshold,
    drop_unused_nodes,
    element_size,
    generate_sized,
    gmsh_nodes_on,
    gmsh_session,
    gmsh_triangles,
    kept_nodes,
    mesh_sector,
)
from gearsim.fem.solve import ElasticModel, plane_lame
from gearsim.fem.tooth import _contact_pairs
from gearsim.geometry.gear import Material
from gearsim.geometry.pair import GearPair
from gearsim.geometry.profile import ToothProfile

__all__ = [
    "CONTACT_GROWTH",
    "CRACK_LABEL",
    "CONTACT_REFINEMENT",
    "DEFAULT_LEVEL",
    "FECylinderResult",
    "FEPairModel",
    "FEPairResult",
    "FEPairTVMS",
    "PairCrack",
    "fe_cylinder_contact",
    "fe_pair_solve",
    "fe_pair_tvms",
    "hertz_half_width",
    "pe_slice_stiffness",
]

#: Default mesh level (:class:`gearsim.fem.geometry.SectorOptions`).
DEFAULT_LEVEL = 2
#: Finest mesh level accepted (level 3 has about 0.6 million dofs for the 19/48 pair).
MAX_LEVEL = 4
#: Element size on the contacting involutes relative to the tooth size h = m_n / (4 2^N).
CONTACT_REFINEMENT = 8
#: Slope of the element size away from the contacting involutes at the default level;
#: it halves with every level, so that levels are uniform refinements.
CONTACT_GROWTH = 0.3
#: Teeth refined beyond the path of contact, in base pitches on either side [-].
TOOTH_MARGIN = 0.6
#: Lower bound of the mesh stiffness per unit face width used to size the candidate
#: window of the contact search [N/m per m]; the window is checked after the solve.
STIFFNESS_FLOOR = 4e9
MAX_QP_ITERATIONS = 5000
MAX_WINDOW_GROWTH = 8


# --------------------------------------------------------------------------- bodies
@dataclass
class _Body:
    """One elastic body, clamped on ``fixed`` (its hub), placed rigidly in the plane."""

    model: ElasticModel
    fixed: np.ndarray
    mode: np.ndarray  # rigid field of the hub motion in the local frame (ndofs,)
    centre: np.ndarray
    angle: float = 0.0
    free: np.ndarray = field(default=None, repr=False)
    lu: object = field(default=None, repr=False)
    dofloc: np.ndarray = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.lu is not None:  # factorised before (a shared healthy body)
            return
        n = self.model.ndofs
        self.free = np.setdiff1d(np.arange(n), self.fixed)
        kff = self.model.K[self.free][:, self.free].tocsc()
        from scipy.sparse.linalg import splu

        try:  # symmetric positive definite: symmetric ordering, no pivoting (half the fill)
            self.lu = splu(kff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError as exc:  # pragma: no cover - a held bore is never singular
            # SuperLU reports a failed allocation as a RuntimeError too
            what = ("ran out of memory: a coarser FE level needs less" if "MALLOC" in str(exc)
                    else "found the gear stiffness matrix singular")
            raise SimulationError(f"the sparse LU factorisation of {n} dofs {what} "
                                  f"({exc})") from None

    @property
    def rotation(self) -> np.ndarray:
        """Rotation matrix local -> global."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        return np.array([[c, -s], [s, c]])

    def to_global(self, xy: np.ndarray) -> np.ndarray:
        """Local points (k, 2) -> global (k, 2)."""
        return xy @ self.rotation.T + self.centre

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """Bore-clamped displacements for loads ``rhs`` (ndofs, k) (dense)."""
        rhs = np.asarray(rhs, dtype=float)
        one = rhs.ndim == 1
        r2 = rhs[:, None] if one else rhs
        out = np.zeros((self.model.ndofs, r2.shape[1]))
        out[self.free] = self.lu.solve(np.ascontiguousarray(r2[self.free]))
        return out[:, 0] if one else out


class _Compliance:
    """Columns of A = sum_i B_i K_i^-1 B_i^T, computed on demand and cached.

    The active-set method only needs the columns of the constraints that ever carry a
    force (A[:, F] gives the gaps of all constraints): one solve per such constraint and
    gear instead of one per candidate.
    """

    def __init__(self, bodies: list[_Body], brows: list[sp.csr_matrix]) -> None:
        self.parts = [(body, b[:, body.free].tocsr(), b[:, body.free].T.tocsc())
                      for body, b in zip(bodies, brows, strict=True)]
        self.k = brows[0].shape[0]
        self.cache: dict[int, np.ndarray] = {}

    def __call__(self, idx) -> np.ndarray:
        """Columns ``idx`` of A, shape (k, len(idx))."""
        idx = [int(j) for j in np.atleast_1d(idx)]
        missing = [j for j in idx if j not in self.cache]
        if missing:
            cols = np.zeros((self.k, len(missing)))
            for body, bf, bt in self.parts:
                rhs = bt[:, missing].toarray()
                if not np.any(rhs):
                    continue
                cols += bf @ body.lu.solve(np.ascontiguousarray(rhs))
            for n, j in enumerate(missing):
                self.cache[j] = cols[:, n]
        if not idx:
            return np.zeros((self.k, 0))
        return np.column_stack([self.cache[j] for j in idx])


#: Healthy gear bodies kept per process (mesh, assembled model, factorisation): the
#: cracked models of an FE pair table mesh the cracked gear anew for each tooth label,
#: the other gear is the same body each time.
HEALTHY_BODIES = 4


@functools.lru_cache(maxsize=HEALTHY_BODIES)
def _healthy_body(gear, level: int, teeth: tuple[int, ...], side: int, size: float,
                  growth: float, plane: str):
    """Mesh, elastic model and bore-clamped factorisation of an uncracked gear body.

    The arguments are those of the mesher and the model (all hashable); the returned
    parts are read-only for their users: a model wraps them in its own :class:`_Body`
    (whose placement angle it sets), so sharing them changes no number.
    """
    mesh = mesh_sector(gear, options=SectorOptions(level=level),
                       refine=FlankRefinement(teeth=teeth, sides=(side,), size=size,
                                              growth=growth))
    mat = gear.material
    model = ElasticModel(mesh.p, mesh.t, mat.youngs_modulus, mat.poisson_ratio,
                         plane=plane, order=2)
    fixed = model.dofs_on_facets(model.facets_on_nodes(mesh.bore))
    body = _Body(model=model, fixed=fixed, mode=_rigid_rotation(model), centre=np.zeros(2))
    return mesh, body


def _rigid_rotation(model: ElasticModel) -> np.ndarray:
    """Dof vector of the rigid rotation (-y, x) about the local origin."""
    basis = model.basis
    loc = basis.doflocs
    ycomp = np.zeros(model.ndofs, dtype=bool)
    ycomp[basis.nodal_dofs[1]] = True
    if basis.facet_dofs.size:
        ycomp[basis.facet_dofs[1]] = True
    return np.where(ycomp, loc[0], -loc[1])


def _translation(model: ElasticModel, direction) -> np.ndarray:
    """Dof vector of a rigid translation along ``direction`` (local frame)."""
    basis = model.basis
    out = np.full(model.ndofs, float(direction[0]))
    out[basis.nodal_dofs[1]] = direction[1]
    if basis.facet_dofs.size:
        out[basis.facet_dofs[1]] = direction[1]
    return out


# --------------------------------------------------------------------------- surfaces
@dataclass
class _Surface:
    """P2 boundary nodes (slave role) and edges (master role) of some boundary parts."""

    # slave points
    xy: np.ndarray  # (p, 2) local
    dofs: np.ndarray  # (p, 2)
    weight: np.ndarray  # (p,) Simpson length share [m]
    label: np.ndarray  # (p,) tooth index
    # master edges
    ea: np.ndarray  # (e, 2) local end a
    eb: np.ndarray  # (e, 2) local end b
    edofs: np.ndarray  # (e, 3, 2) dofs of a, midpoint, b
    enormal: np.ndarray  # (e, 2) outward unit normal (local)
    elabel: np.ndarray  # (e,)
    conn: np.ndarray  # (e, 3) slave-point indices of each edge's a, midpoint, b

    def edge_pressure(self, forces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mean pressure of each edge, (f_a / 2 + f_mid + f_b / 2) / L.

        The nodal forces of node-to-segment contact on P2 edges alternate between
        vertices and midpoints about the consistent values (Simpson ratio 1 : 2); the
        edge mean, which shares each vertex force between its two edges, is smooth.

        Parameters
        ----------
        forces
            Force of every slave point [N/m].

        Returns
        -------
        xy, pressure
            Local midpoints of the edges (e, 2) [m] and their mean pressure [Pa].
        """
        ln = np.hypot(*(self.eb - self.ea).T)
        f = forces[self.conn]
        return 0.5 * (self.ea + self.eb), (0.5 * f[:, 0] + f[:, 1] + 0.5 * f[:, 2]) / ln


def _surface(model: ElasticModel, parts: dict[int, np.ndarray]) -> _Surface:
    """Slave points and master edges of the boundary node sets ``parts`` (label -> nodes)."""
    mesh = model.mesh
    p = mesh.p
    xy, dofs, weight, label = [], [], [], []
    ea, eb, edofs, en, el, conn = [], [], [], [], [], []
    for lab, nodes in parts.items():
        vidx: dict[int, int] = {}
        econn: list[tuple[int, int, int]] = []
        facets = model.facets_on_nodes(np.asarray(nodes))
        wv: dict[int, float] = {}
        for f in facets:
            a, b = (int(v) for v in mesh.facets[:, f])
            xa, xb = p[:, a], p[:, b]
            length = float(np.hypot(*(xb - xa)))
            wv[a] = wv.get(a, 0.0) + length / 6.0
            wv[b] = wv.get(b, 0.0) + length / 6.0
            mdofs = model.edge_dofs(int(f))
            econn.append((a, len(xy), b))
            xy.append(0.5 * (xa + xb))
            dofs.append(mdofs)
            weight.append(4.0 * length / 6.0)
            label.append(lab)
            # outward normal: away from the third vertex of the adjacent triangle
            tri = mesh.t[:, mesh.f2t[0, f]]
            third = p[:, [v for v in tri if v not in (a, b)][0]]
            t = (xb - xa) / length
            nrm = np.array([t[1], -t[0]])
            if np.dot(third - xa, nrm) > 0.0:
                nrm = -nrm
            ea.append(xa)
            eb.append(xb)
            edofs.append([model.node_dofs(a), mdofs, model.node_dofs(b)])
            en.append(nrm)
            el.append(lab)
        for v, w in wv.items():
            vidx[v] = len(xy)
            xy.append(p[:, v])
            dofs.append(model.node_dofs(v))
            weight.append(w)
            label.append(lab)
        conn += [(vidx[a], m, vidx[b]) for a, m, b in econn]
    return _Surface(xy=np.array(xy).reshape(-1, 2), dofs=np.array(dofs, dtype=np.int64).reshape(-1, 2),
                    weight=np.array(weight), label=np.array(label, dtype=np.int64),
                    ea=np.array(ea).reshape(-1, 2), eb=np.array(eb).reshape(-1, 2),
                    edofs=np.array(edofs, dtype=np.int64).reshape(-1, 3, 2),
                    enormal=np.array(en).reshape(-1, 2), elabel=np.array(el, dtype=np.int64),
                    conn=np.array(conn, dtype=np.int64).reshape(-1, 3))


@dataclass
class _Pairs:
    """Node-to-segment contact constraints of one pass (global normals)."""

    g0: np.ndarray
    normal: np.ndarray
    slave_body: int
    slave_dofs: np.ndarray  # (k, 2)
    master_dofs: np.ndarray  # (k, 3, 2)
    shape: np.ndarray  # (k, 3) P2 edge shape functions at the projection
    xy: np.ndarray  # (k, 2) global slave position
    weight: np.ndarray
    label: np.ndarray  # tooth index of the driver-side (body 0) surface


def _project(slave: _Surface, sbody: _Body, master: _Surface, mbody: _Body, sidx: int,
             driver_label_from_slave: bool) -> _Pairs:
    """Closest-point projection of every slave point onto the master edges."""
    xs = sbody.to_global(slave.xy)  # (p, 2)
    a = mbody.to_global(master.ea)
    b = mbody.to_global(master.eb)
    nf = master.enormal @ mbody.rotation.T
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    # (p, e) parameter and distance, in blocks to bound memory
    npnt = xs.shape[0]
    best = np.zeros(npnt, dtype=np.int64)
    tbest = np.zeros(npnt)
    for i0 in range(0, npnt, 512):
        xp = xs[i0:i0 + 512]
        t = np.einsum("pij,ij->pi", xp[:, None, :] - a[None], ab) / ll[None]
        t = np.clip(t, 0.0, 1.0)
        q = a[None] + t[..., None] * ab[None]
        d2 = np.sum((xp[:, None, :] - q) ** 2, axis=-1)
        j = np.argmin(d2, axis=1)
        best[i0:i0 + 512] = j
        tbest[i0:i0 + 512] = t[np.arange(xp.shape[0]), j]
    q = a[best] + tbest[:, None] * ab[best]
    diff = xs - q
    dist = np.hypot(diff[:, 0], diff[:, 1])
    n = nf[best].copy()
    # closest point at an edge end: the normal is along the connecting line, its sign
    # from the mean normal of the edges meeting there
    atend = (tbest <= 0.0) | (tbest >= 1.0)
    if np.any(atend):
        ends = np.where(tbest <= 0.0, 0, 1)
        endpt = np.where(ends[:, None] == 0, a[best], b[best])
        vn = np.zeros_like(n)
        degree = np.zeros(npnt)
        for pts in (a, b):
            close = np.hypot(*(pts[None, :, :] - endpt[atend][:, None, :]).transpose(2, 0, 1)) \
                < 1e-12 * max(1.0, float(np.abs(pts).max()))
            vn[atend] += close.astype(float) @ nf
            degree[atend] += close.sum(axis=1)
        vn[atend] /= np.maximum(np.hypot(vn[atend, 0], vn[atend, 1]), 1e-300)[:, None]
        sgn = np.sign(np.einsum("ij,ij->i", diff, vn))
        sgn[sgn == 0.0] = 1.0
        far = atend & (dist > 1e-14)
        n[far] = sgn[far, None] * diff[far] / dist[far, None]
        n[atend & ~far] = vn[atend & ~far]
    g0 = np.einsum("ij,ij->i", diff, n)
    if np.any(atend):
        # beyond a free end of the master surface: no contact partner (never a candidate)
        g0[atend & (degree < 2)] = np.inf
    t = tbest
    shape = np.column_stack([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)])
    label = slave.label if driver_label_from_slave else master.elabel[best]
    return _Pairs(g0=g0, normal=n, slave_body=sidx, slave_dofs=slave.dofs,
                  master_dofs=master.edofs[best], shape=shape, xy=xs, weight=slave.weight,
                  label=label)


def _rows(pairs: list[_Pairs], bodies: list[_Body], keep: list[np.ndarray]
          ) -> tuple[list[sp.csr_matrix], dict[str, np.ndarray]]:
    """Constraint rows B_i (k, ndofs_i) of the kept pairs, and their data."""
    rows = [[], []]
    cols = [[], []]
    vals = [[], []]
    info = {"g0": [], "normal": [], "xy": [], "weight": [], "label": [], "pass": []}
    r0 = 0
    for ip, (pr, kp) in enumerate(zip(pairs, keep, strict=True)):
        idx = np.flatnonzero(kp)
        k = idx.size
        if k == 0:
            continue
        s, m = pr.slave_body, 1 - pr.slave_body
        ns = pr.normal[idx] @ bodies[s].rotation  # global -> local: R^T n  (row form)
        nm = pr.normal[idx] @ bodies[m].rotation
        rr = r0 + np.arange(k)
        # slave: + n . u_s
        rows[s] += [rr, rr]
        cols[s] += [pr.slave_dofs[idx, 0], pr.slave_dofs[idx, 1]]
        vals[s] += [ns[:, 0], ns[:, 1]]
        # master: - n . sum N_j u_j
        for j in range(3):
            rows[m] += [rr, rr]
            cols[m] += [pr.master_dofs[idx, j, 0], pr.master_dofs[idx, j, 1]]
            vals[m] += [-pr.shape[idx, j] * nm[:, 0], -pr.shape[idx, j] * nm[:, 1]]
        for key, arr in (("g0", pr.g0), ("normal", pr.normal), ("xy", pr.xy),
                         ("weight", pr.weight), ("label", pr.label)):
            info[key].append(arr[idx])
        info["pass"].append(np.full(k, ip))
        r0 += k
    import scipy.sparse as sp

    out = []
    for i, body in enumerate(bodies):
        if rows[i]:
            out.append(sp.csr_matrix((np.concatenate(vals[i]), (np.concatenate(rows[i]),
                                                                 np.concatenate(cols[i]))),
                                     shape=(r0, body.model.ndofs)))
        else:
            out.append(sp.csr_matrix((r0, body.model.ndofs)))
    data = {key: (np.concatenate(v) if v else np.zeros((0,))) for key, v in info.items()}
    return out, data


# --------------------------------------------------------------------------- QP
def _contact_qp(acol, g0: np.ndarray, c: np.ndarray | None, load: float,
                tol: float) -> tuple[np.ndarray, float, int]:
    """min 1/2 x^T A x + g0^T x, x >= 0 [, c^T x = load]: primal active set.

    ``acol(idx)`` returns columns of the symmetric positive definite A. Returns the forces
    x, the multiplier theta of the equality (0 without it) and the iterations; the gap
    g = g0 + A x + c theta is >= -tol at the solution (Nocedal & Wright, alg. 16.3).
    """
    k = g0.size
    x = np.zeros(k)
    free = np.zeros(k, dtype=bool)
    if c is not None:
        ok = (c * load > 0.0) & np.isfinite(g0)
        if not np.any(ok):
            raise SimulationError("no contact candidate can carry the load in its sense")
        i0 = np.flatnonzero(ok)[np.argmin(g0[ok])]
        x[i0] = load / c[i0]
        free[i0] = True
    theta = 0.0
    for it in range(1, MAX_QP_ITERATIONS + 1):
        f = np.flatnonzero(free)
        nf = f.size
        af = acol(f)  # (k, nf)
        if c is None:
            sol = np.linalg.solve(af[f], -g0[f]) if nf else np.zeros(0)
            th = 0.0
        else:
            kkt = np.zeros((nf + 1, nf + 1))
            kkt[:nf, :nf] = af[f]
            kkt[:nf, nf] = c[f]
            kkt[nf, :nf] = c[f]
            rhs = np.concatenate([-g0[f], [load]])
            try:
                z = np.linalg.solve(kkt, rhs)
            except np.linalg.LinAlgError:
                z = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
            sol, th = z[:nf], float(z[nf])
        p = sol - x[f]
        scale = max(float(np.max(np.abs(sol))) if nf else 0.0, 1e-300)
        if np.all(np.abs(p) <= 1e-12 * scale):
            x[f] = sol
            theta = th
            gap = g0 + af @ sol + (c * theta if c is not None else 0.0)
            gap_w = np.where(free, np.inf, gap)
            j = int(np.argmin(gap_w))
            if gap_w[j] >= -tol:
                return x, theta, it
            free[j] = True
            continue
        neg = p < 0.0
        alpha = 1.0
        block = -1
        if np.any(neg):
            ratios = -x[f][neg] / p[neg]
            m = int(np.argmin(ratios))
            if ratios[m] < 1.0:
                alpha = float(ratios[m])
                block = int(f[neg][m])
        x[f] += alpha * p
        if block >= 0:
            x[block] = 0.0
            free[block] = False
        x[x < 0.0] = 0.0
    raise SimulationError(f"the contact problem did not converge in {MAX_QP_ITERATIONS} "
                          "active-set iterations")


# --------------------------------------------------------------------------- stresses
def _vertex_stress(model: ElasticModel, u: np.ndarray) -> np.ndarray:
    """Stress (sxx, syy, sxy) at every mesh vertex, averaged over its elements [Pa]."""
    from skfem import Basis

    x = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    w = np.full(3, 1.0 / 6.0)
    vb = Basis(model.mesh, model.element, quadrature=(x, w))
    grad = vb.interpolate(u).grad  # (2, 2, nel, 3): d u_i / d x_j
    exx, eyy = grad[0, 0], grad[1, 1]
    exy = 0.5 * (grad[0, 1] + grad[1, 0])
    lam, mu = plane_lame(model.youngs_modulus, model.poisson_ratio, model.plane)
    tr = exx + eyy
    sig = np.stack([lam * tr + 2 * mu * exx, lam * tr + 2 * mu * eyy, 2 * mu * exy])
    n = model.mesh.p.shape[1]
    acc = np.zeros((3, n))
    cnt = np.zeros(n)
    t = model.mesh.t
    for i in range(3):
        for comp in range(3):
            np.add.at(acc[comp], t[i], sig[comp][:, i])
        np.add.at(cnt, t[i], 1.0)
    return acc / np.maximum(cnt, 1.0)


def _max_principal(s: np.ndarray) -> np.ndarray:
    """Largest principal stress of (sxx, syy, sxy) columns."""
    c = 0.5 * (s[0] + s[1])
    r = np.hypot(0.5 * (s[0] - s[1]), s[2])
    return c + r


# --------------------------------------------------------------------------- Hertz
def hertz_half_width(load: float, radius: float, youngs_modulus: float, poisson_ratio: float,
                     plane: str = "strain") -> float:
    """Half width of the 2D Hertz contact of two equal-material cylinders.

    b = sqrt(4 F R / (pi E*)) per unit length (Johnson 1985, eq. 4.43), with
    1/E* = 2 (1 - nu^2) / E in plane strain and 2 / E in plane stress.

    Parameters
    ----------
    load
        Normal load per unit length F [N/m].
    radius
        Relative radius of curvature R = R1 R2 / (R1 + R2) [m].
    youngs_modulus, poisson_ratio
        Material of both bodies [Pa], [-].
    plane
        ``"strain"`` (default) or ``"stress"``.

    Returns
    -------
    float
        b [m].

    Examples
    --------
    Steel rollers R1 = R2 = 20 mm (R = 10 mm), 100 kN/m, plane strain:

    >>> round(hertz_half_width(1e5, 0.01, 206e9, 0.3) * 1e6, 2)
    106.06
    """
    if plane not in ("stress", "strain"):
        raise InputError("plane", plane, 'must be "stress" or "strain"')
    e_star = youngs_modulus / (2.0 * ((1.0 - poisson_ratio**2) if plane == "strain" else 1.0))
    return math.sqrt(4.0 * load * radius / (math.pi * e_star))


# --------------------------------------------------------------------------- results
@dataclass
class FEPairResult:
    """FE gear pair at one mesh position.

    Parameters
    ----------
    position
        Mesh-cycle fraction u in [0, 1).
    torque
        Driver torque T over the face width [N m] (> 0 drives the ``+x`` flanks).
    force
        Line-of-action force F = |T| / r_b1 [N].
    transmission_error
        Loaded transmission error delta along the line of action [m] (> 0: the driver
        lags its rigid kinematic position).
    stiffness
        Mesh stiffness k = F / delta over the face width [N/m].
    theta1, theta2
        Hub rotations of driver and driven gear [rad] (counter-clockwise positive).
    driven_torque
        Reaction torque on the driven hub [N m].
    pair_teeth
        Driver tooth index k of each tooth pair (the driven tooth is -k).
    pair_force
        Normal contact force of each pair over the face width [N].
    load_share
        Share of the driver torque carried by each pair [-].
    contact_half_width
        Half width of each pair's contact, 2 sqrt(second moment of the pressure) [m].
    contact_extent
        Length of flank in contact (first to last node with a force) [m].
    hertz_half_width
        2D Hertz half width for the pair's force and curvature radii at its contact
        point (plane of the model) [m]; NaN for a pair touching outside the path of
        contact (tip corner).
    peak_pressure
        Largest edge-mean pressure on the pair's driver flank [Pa]
        (``(f_a / 2 + f_mid + f_b / 2) / L`` over each P2 edge, f the nodal forces); NaN
        when only the driven tip corner touches (pass 2).
    root_stress_driver, root_stress_driven
        Largest principal stress on the tension-side root fillet of the pair's driver and
        driven tooth [Pa].
    contact_xy
        Midpoints of the loaded driver-flank edges, global coordinates (k, 2) [m].
    contact_pressure
        Their edge-mean pressure [Pa].
    contact_pair
        Their pair (driver tooth index).
    candidates
        Contact constraints in the final problem.
    iterations
        Active-set iterations (summed over window growths).
    level
        Mesh level.
    h, h_contact
        Element size on the teeth and on the contacting involutes [m].
    dofs
        Degrees of freedom of driver and driven model.
    plane
        ``"stress"`` or ``"strain"``.
    seconds
        Wall time of this position [s] (without the shared set-up).
    crack_closed
        Length fraction of the crack faces in contact (closed crack model), NaN without.
    """

    position: float
    torque: float
    force: float
    transmission_error: float
    stiffness: float
    theta1: float
    theta2: float
    driven_torque: float
    pair_teeth: np.ndarray
    pair_force: np.ndarray
    load_share: np.ndarray
    contact_half_width: np.ndarray
    contact_extent: np.ndarray
    hertz_half_width: np.ndarray
    peak_pressure: np.ndarray
    root_stress_driver: np.ndarray
    root_stress_driven: np.ndarray
    contact_xy: np.ndarray
    contact_pressure: np.ndarray
    contact_pair: np.ndarray
    candidates: int
    iterations: int
    level: int
    h: float
    h_contact: float
    dofs: tuple[int, int]
    plane: str
    seconds: float = 0.0
    crack_closed: float = float("nan")


@dataclass
class FEPairTVMS:
    """FE gear pair over a mesh cycle.

    Parameters
    ----------
    positions
        Mesh-cycle fractions u [-].
    stiffness
        Mesh stiffness k(u) over the face width [N/m].
    transmission_error
        Loaded transmission error along the line of action [m].
    load_share
        Torque share of pairs k = -1, 0, 1, 2, ... (columns, driver tooth index
        ``pair_teeth``) at each position [-].
    pair_teeth
        Driver tooth indices of the ``load_share`` columns.
    results
        The :class:`FEPairResult` of every position.
    setup_seconds
        Wall time of meshing and factorising (shared by all positions) [s].
    """

    positions: np.ndarray
    stiffness: np.ndarray
    transmission_error: np.ndarray
    load_share: np.ndarray
    pair_teeth: np.ndarray
    results: list
    setup_seconds: float = 0.0

    @property
    def mean(self) -> float:
        """Mean mesh stiffness over the positions [N/m]."""
        return float(np.mean(self.stiffness))


# --------------------------------------------------------------------------- the model
def _check_torque(torque, name: str = "torque") -> float:
    if isinstance(torque, bool) or not isinstance(torque, (int, float, np.floating)) \
            or not math.isfinite(float(torque)) or float(torque) == 0.0:
        raise InputError(name, torque, "must be a finite, nonzero driver torque [N m] "
                         "(> 0 loads the drive flanks, < 0 the back flanks)")
    return float(torque)


def _check_position(position) -> float:
    if isinstance(position, bool) or not isinstance(position, (int, float, np.floating)) \
            or not (0.0 <= float(position) < 1.0):
        raise InputError("position", position, "must be a mesh-cycle fraction in [0, 1)")
    return float(position)


def _check_level(level) -> int:
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) \
            or not 0 <= int(level) <= MAX_LEVEL:
        raise InputError("fem.level", level, f"must be an integer in [0, {MAX_LEVEL}]")
    return int(level)


@dataclass(frozen=True)
class PairCrack:
    """A tooth-root crack on one tooth of the FE gear pair.

    Parameters
    ----------
    gear
        1: the driver, 2: the driven gear.
    pair
        Label of the tooth pair the cracked tooth belongs to: the driver tooth index k
        of :class:`FEPairModel` (driver tooth k touches at l_A + (u + k) p_b; the driven
        tooth of that pair is the one meeting it).
    crack
        :class:`gearsim.stiffness.crack.Crack` (start on the fillet, angle, depth).
    side
        +1: the crack is on the flank this model loads (working flank); -1: on the
        other flank (non-working).
    closure
        ``"contact"`` (default): the crack faces touch without friction and carry
        compression (unilateral constraints in the same contact problem as the flanks);
        ``"open"``: free faces (they may overlap, as the seed's PE model).
    """

    gear: int
    pair: int
    crack: object
    side: int
    closure: str = "contact"

    def __post_init__(self) -> None:
        if self.gear not in (1, 2):
            raise InputError("crack.gear", self.gear, "must be 1 (driver) or 2 (driven)")
        if self.side not in (1, -1):
            raise InputError("crack.side", self.side, "must be +1 (working) or -1")
        if self.closure not in ("contact", "open"):
            raise InputError("stiffness.closure", self.closure, 'must be "open" or "contact"')


#: Label of the crack-face constraints in the contact problem (not a tooth pair).
CRACK_LABEL = -(10**6)


class FEPairModel:
    """Meshed, factorised FE model of a gear pair for one loaded flank side.

    Building it meshes both gears (whole bodies, flanks of the teeth that can touch
    refined) and factorises both bore-clamped stiffness matrices once; :meth:`solve`
    then places the gears at a mesh position and solves the contact problem.

    Parameters
    ----------
    pair
        The gear pair (2D transverse section; a helical pair is modelled by its
        transverse slice).
    torque
        Driver torque over the face width [N m]; its sign chooses the loaded flanks
        (> 0 the drive flanks, < 0 the back flanks) and its size the check that the
        mesh resolves the contact.
    level
        Mesh level N: element size m_n / (4 2^N) on the teeth and
        m_n / (4 2^N CONTACT_REFINEMENT) on their involutes.
    plane
        ``"stress"`` (default, as the potential-energy model) or ``"strain"``.
    flanks
        ``"auto"`` (default, from the sign of ``torque``), ``"drive"`` or ``"back"``;
        a torque that would separate the chosen flanks is refused.
    crack
        A :class:`PairCrack` on one tooth of the model (its pair label must be one of
        the model's teeth, :attr:`teeth`), or ``None``.

    Raises
    ------
    InputError
        A zero or non-finite torque, one whose sign separates the chosen flanks, an
        unknown plane or flank choice, a level outside [0, MAX_LEVEL], a mesh too coarse
        for the contact (element size on the involutes above the Hertz half width at the
        pitch point under the full load), or back flanks loaded at a centre distance
        with backlash.
    """

    def __init__(self, pair: GearPair, *, torque: float, level: int = DEFAULT_LEVEL,
                 plane: str = "stress", flanks: str = "auto",
                 crack: PairCrack | None = None) -> None:
        t0 = time.perf_counter()
        torque = _check_torque(torque)
        level = _check_level(level)
        if plane not in ("stress", "strain"):
            raise InputError("plane", plane, 'must be "stress" or "strain"')
        if flanks not in ("auto", "drive", "back"):
            raise InputError("flanks", flanks, 'must be "auto", "drive" or "back"')
        side = 1 if torque > 0 else -1
        if (flanks == "drive" and side < 0) or (flanks == "back" and side > 0):
            raise InputError("torque", torque, f"would separate the {flanks} flanks: use a "
                             f"{'positive' if flanks == 'drive' else 'negative'} torque or "
                             'flanks="auto"')
        self.pair = pair
        self.side = side
        self.level = level
        self.plane = plane
        self.torque_scale = abs(torque)
        g1, g2 = pair.driver, pair.driven
        self.h = element_size(g1, level)
        self.h_contact = self.h / CONTACT_REFINEMENT
        # slope of the element size away from the flanks, halved per level with h: the
        # whole size field scales with 2^-N (uniform refinement for the convergence study)
        self.growth = min(1.0, CONTACT_GROWTH * 2.0 ** (DEFAULT_LEVEL - level))
        self.hertz_pitch = self._check_resolution(torque)
        self._place()
        self.teeth = self._teeth()
        # driver tooth k meets driven tooth n - k (n = 0 on the drive flanks)
        n = self.driven_offset
        z2 = g2.teeth
        lo2 = z2 // 2 - z2 + 1  # tooth indices of the whole-gear mesh: [lo2, z2 // 2]

        def wrap(i: int) -> int:
            return lo2 + (i - lo2) % z2

        if crack is not None and crack.pair not in self.teeth:
            raise InputError("crack.pair", crack.pair, f"must be one of the model's tooth "
                             f"pairs {self.teeth}")
        self.crack = crack
        self.crack_rows: np.ndarray | None = None  # (k, 2, 2) dof pairs, body crack.gear-1
        bodies, surfaces, fillets = [], [], []
        for gi, (gear, ks) in enumerate(((g1, self.teeth),
                                         (g2, tuple(wrap(n - k) for k in self.teeth)))):
            cracked = crack is not None and crack.gear == gi + 1
            centre = np.array([0.0, 0.0]) if gi == 0 else np.array([0.0, pair.centre_distance])
            if cracked:
                z = gear.teeth
                kc = crack.pair if gi == 0 else wrap(n - crack.pair)
                lo = z // 2 - z + 1  # tooth indices of the whole-gear mesh: [lo, z // 2]
                mesh = self._cracked_mesh(gear, ks, kc, side * crack.side, level,
                                          crack.crack, lambda i, z=z, lo=lo: lo + (i - lo) % z)
                mat = gear.material
                model = ElasticModel(mesh.p, mesh.t, mat.youngs_modulus, mat.poisson_ratio,
                                     plane=plane, order=2)
                fixed = model.dofs_on_facets(model.facets_on_nodes(mesh.bore))
                bodies.append(_Body(model=model, fixed=fixed, mode=_rigid_rotation(model),
                                    centre=centre))
            else:  # the same body for every model of the process (a copy placed here)
                mesh, shared = _healthy_body(gear, level, tuple(sorted(ks)), side,
                                             self.h_contact, self.growth, plane)
                model = shared.model
                bodies.append(dataclasses.replace(shared, centre=centre))
            if cracked and crack.closure == "contact":
                dofs, weights = _contact_pairs(model, mesh)
                self.crack_rows = dofs
                self.crack_weights = weights
                self.crack_normal = mesh.crack_normal
            # surfaces labelled with the driver tooth index of the pair
            def lab(k, gi=gi):
                return k if gi == 0 else self.teeth[[wrap(n - j) for j in self.teeth].index(k)]

            flank = {lab(k): np.union1d(mesh.parts[(k, side, "involute")],
                                        mesh.parts[(k, 0, "tip")]) for k in ks}
            tips = {lab(k): mesh.parts[(k, 0, "tip")] for k in ks}
            surfaces.append((_surface(model, flank), _surface(model, tips)))
            fillets.append({lab(k): mesh.parts[(k, side, "fillet")] for k in ks})
        self.bodies = bodies
        self.surfaces = surfaces
        self.fillets = fillets
        self.setup_seconds = time.perf_counter() - t0

    # ---------------------------------------------------------------- geometry
    def _cracked_mesh(self, gear, ks, kc: int, flank: int, level: int, crack, wrap):
        """Mesh of ``gear`` with the crack on its tooth ``kc``.

        The mesher cracks the middle tooth (index 0): the gear is meshed with the teeth
        renumbered so that ``kc`` is tooth 0, then turned by -kc pitches and the parts
        relabelled, which is the same gear with the crack on tooth ``kc``.
        """
        z = gear.teeth
        pitch = 2.0 * math.pi / z
        cl = crack_line(ToothProfile(gear), crack, crack.depth, flank)
        shifted = tuple(sorted(wrap(k - kc) for k in ks))
        mesh = mesh_sector(gear, crack=cl, options=SectorOptions(level=level),
                           refine=FlankRefinement(teeth=shifted, sides=(self.side,),
                                                  size=self.h_contact, growth=self.growth))
        c, s_ = math.cos(-kc * pitch), math.sin(-kc * pitch)
        rot = np.array([[c, -s_], [s_, c]])
        mesh.p = rot @ mesh.p
        mesh.parts = {(wrap(k + kc), sd, part): nodes
                      for (k, sd, part), nodes in mesh.parts.items()}
        mesh.crack_normal = rot @ cl.normal
        return mesh

    def _check_resolution(self, torque: float) -> float:
        """Hertz half width at the pitch point under ``torque``; refuse a coarser mesh."""
        pair = self.pair
        g1 = pair.driver
        w = abs(torque) / (g1.base_radius * pair.face_width)  # force per unit width
        b = self._hertz_at(self._pitch_l(), w)
        if self.h_contact > b:
            need = math.ceil(math.log2(g1.normal_module / (4.0 * CONTACT_REFINEMENT * b)))
            hint = (f"use level >= {max(need, self.level + 1)} or a larger torque"
                    if need <= MAX_LEVEL else "use a larger torque")
            raise InputError("fem.level", self.level,
                             f"mesh too coarse for the contact: element size on the flanks "
                             f"{self.h_contact * 1e3:.4g} mm > Hertz half width "
                             f"{b * 1e3:.4g} mm at the pitch point under {abs(torque):g} N m; "
                             f"{hint}")
        return b

    def _pitch_l(self) -> float:
        pair = self.pair
        return pair.driver.base_radius * math.tan(pair.working_pressure_angle)

    def _hertz_at(self, l: float, w: float) -> float:
        """2D Hertz half width for a line load w [N/m] at roll length l."""
        pair = self.pair
        r1, r2 = l, pair.line_length - l
        rel = r1 * r2 / (r1 + r2) if r1 > 0 and r2 > 0 else 0.0
        m1, m2 = pair.driver.material, pair.driven.material
        f = (lambda m: 1.0) if self.plane == "stress" else (lambda m: 1.0 - m.poisson_ratio**2)
        e_star = 1.0 / (f(m1) / m1.youngs_modulus + f(m2) / m2.youngs_modulus)
        return math.sqrt(4.0 * w * rel / (math.pi * e_star))

    def _place(self) -> None:
        """Rotations phi_1(0), phi_2(0) of the middle teeth touching at l_A."""
        pair = self.pair
        g1, g2 = pair.driver, pair.driven
        alpha = pair.working_pressure_angle
        self.direction = np.array([math.cos(alpha), math.sin(alpha)])
        self.t1 = g1.base_radius * np.array([-math.sin(alpha), math.cos(alpha)])
        la = pair.start_of_contact
        x = self.t1 + la * self.direction
        xl, yl = ToothProfile(g1).involute_point(math.hypot(g1.base_radius, la))
        self.phi1 = math.atan2(x[1], x[0]) - math.atan2(yl, xl)
        o2 = np.array([0.0, pair.centre_distance])
        xl, yl = ToothProfile(g2).involute_point(math.hypot(g2.base_radius,
                                                            pair.line_length - la))
        self.phi2 = math.atan2(x[1] - o2[1], x[0] - o2[0]) - math.atan2(yl, xl)
        self.pitch1 = 2.0 * math.pi / g1.teeth
        self.pitch2 = 2.0 * math.pi / g2.teeth
        # back flanks (mirror image x -> -x): driver tooth k touches at
        # l_A + (q - u - k) p_b, q = 2 phi_1(0) / pitch_1, driven tooth i at
        # l_A + (q_2 - u + i) p_b, q_2 = -2 phi_2(0) / pitch_2: they meet for i = q - q_2 - k,
        # an integer at zero backlash
        self.back_offset = 2.0 * self.phi1 / self.pitch1
        self.driven_offset = 0
        if self.side < 0:
            shift = self.back_offset + 2.0 * self.phi2 / self.pitch2
            self.driven_offset = int(round(shift))
            if abs(shift - self.driven_offset) > 1e-6:
                raise InputError("torque", -self.torque_scale,
                                 f"loads the back flanks, which do not touch: the pair has "
                                 f"backlash ({abs(shift - self.driven_offset) * pair.base_pitch * 1e6:.4g}"
                                 f" um along the line of action) at centre_distance_offset = "
                                 f"{pair.centre_distance_offset:g} m; back-flank contact "
                                 "needs the zero-backlash centre distance")

    def roll_position(self, position: float, tooth: int) -> float:
        """Roll length l on the line of action where driver tooth ``tooth`` touches.

        Parameters
        ----------
        position
            Mesh-cycle fraction u.
        tooth
            Driver tooth index k.

        Returns
        -------
        float
            l [m] from T_1 (on the mirrored line of action for the back flanks).
        """
        pair = self.pair
        if self.side > 0:
            return pair.start_of_contact + (position + tooth) * pair.base_pitch
        return pair.start_of_contact + (self.back_offset - position - tooth) * pair.base_pitch

    @classmethod
    def tooth_labels(cls, pair: GearPair, *, torque: float) -> tuple[int, ...]:
        """Driver tooth labels k of the model of ``pair`` at ``torque``, without meshing.

        The labels depend on the pair's geometry and the loaded flanks only (the teeth
        whose contact reaches the path within ``TOOTH_MARGIN`` base pitches over a
        cycle); they equal :attr:`teeth` of ``FEPairModel(pair, torque=torque)`` at any
        level.

        Parameters
        ----------
        pair
            The gear pair.
        torque
            Driver torque [N m] (its sign selects the flanks).

        Returns
        -------
        tuple of int
            The labels, ascending.

        Raises
        ------
        InputError
            A zero or non-finite torque, or back flanks that do not touch.
        """
        self = cls.__new__(cls)
        torque = _check_torque(torque)
        self.pair = pair
        self.side = 1 if torque > 0 else -1
        self.torque_scale = abs(torque)
        self._place()
        return self._teeth()

    def _teeth(self) -> tuple[int, ...]:
        pair = self.pair
        eps = pair.transverse_contact_ratio
        lo, hi = -TOOTH_MARGIN, eps + TOOTH_MARGIN
        out = []
        for k in range(-6, 8):
            ends = [(self.roll_position(u, k) - pair.start_of_contact) / pair.base_pitch
                    for u in (0.0, 1.0)]
            if max(ends) > lo and min(ends) < hi:
                out.append(k)
        return tuple(out)

    # ---------------------------------------------------------------- solving
    def mirror_position(self, position: float) -> float:
        """Mesh position whose drive-flank contact mirrors the back-flank one at ``position``.

        Parameters
        ----------
        position
            Mesh-cycle fraction u.

        Returns
        -------
        float
            u' = (2 phi_1(0) z_1 / (2 pi) - u) mod 1: the configuration at u' is the
            mirror image (x -> -x) of the one at u.
        """
        return float((self.back_offset - position) % 1.0)

    def _add_crack_rows(self, brows: list, info: dict) -> tuple[list, dict]:
        """Append the crack-face constraints g = n . (u_+ - u_-) >= 0 (closed crack)."""
        if self.crack_rows is None:
            return brows, info
        bi = self.crack.gear - 1
        dofs = self.crack_rows
        k = dofs.shape[0]
        nrm = self.crack_normal
        rows = np.repeat(np.arange(k), 4)
        cols = np.column_stack([dofs[:, 1, 0], dofs[:, 1, 1], dofs[:, 0, 0],
                                dofs[:, 0, 1]]).ravel()
        vals = np.tile([nrm[0], nrm[1], -nrm[0], -nrm[1]], k)
        import scipy.sparse as sp

        out = []
        for i, (b, body) in enumerate(zip(brows, self.bodies, strict=True)):
            extra = (sp.csr_matrix((vals, (rows, cols)), shape=(k, body.model.ndofs))
                     if i == bi else sp.csr_matrix((k, body.model.ndofs)))
            out.append(sp.vstack([b, extra]).tocsr())
        gn = self.bodies[bi].rotation @ nrm
        add = {"g0": np.zeros(k), "normal": np.tile(gn, (k, 1)), "xy": np.zeros((k, 2)),
               "weight": np.asarray(self.crack_weights, dtype=float),
               "label": np.full(k, CRACK_LABEL), "pass": np.full(k, 2)}
        info = {key: np.concatenate([np.asarray(v).reshape((-1,) + add[key].shape[1:]),
                                     add[key]]) for key, v in info.items()}
        return out, info

    def solve(self, position: float, *, torque: float | None = None,
              rotation: float | None = None, driven_rotation: float = 0.0) -> FEPairResult:
        """Solve the contact problem at one mesh position.

        Parameters
        ----------
        position
            Mesh-cycle fraction u in [0, 1).
        torque
            Driver torque over the face width [N m]; default the model's. Its sign must be
            that of the model.
        rotation
            Instead of a torque (which is then ignored): prescribed driver hub rotation
            (counter-clockwise) [rad]; the torque is the reaction.
        driven_rotation
            Prescribed driven hub rotation (counter-clockwise) [rad]; default 0 (held).

        Returns
        -------
        FEPairResult

        Raises
        ------
        InputError
            A position outside [0, 1), a torque of the other sign (it would separate the
            flanks of this model) or too small for the mesh.
        SimulationError
            If the contact zone does not settle.
        """
        t0 = time.perf_counter()
        u = _check_position(position)
        pair = self.pair
        g1, g2 = pair.driver, pair.driven
        width = pair.face_width
        if rotation is None:
            tq = _check_torque(self.torque_scale * self.side if torque is None else torque)
            if (tq > 0) != (self.side > 0):
                raise InputError("torque", tq, "would separate the flanks this model "
                                 "loads: its sign must be that of the model's torque")
            self._check_resolution(tq)
            load = tq / width  # per unit thickness, c1 . lambda = T
            scale_force = abs(load) / g1.base_radius
        else:
            if not math.isfinite(rotation):
                raise InputError("rotation", rotation, "must be finite")
            tq = 0.0
            load = None
            scale_force = None
        b1, b2 = self.bodies
        b1.angle = self.phi1 - u * self.pitch1
        b2.angle = self.phi2 + u * self.pitch2
        (s1, tip1), (s2, tip2) = self.surfaces
        passes = [_project(s1, b1, s2, b2, 0, True), _project(tip2, b2, s1, b1, 1, False)]
        allg0 = np.concatenate([p.g0 for p in passes])
        full, _ = _rows(passes, self.bodies, [np.ones(p.g0.size, dtype=bool) for p in passes])
        if scale_force is None:
            # rigid approach of the prescribed rotations at the candidates
            est = abs(rotation) * g1.base_radius + abs(driven_rotation) * g2.base_radius
            window = 2.0 * est + 1e-3 * self.h_contact
        else:
            window = 1.5 * scale_force / STIFFNESS_FLOOR
        iters = 0
        for _grow in range(MAX_WINDOW_GROWTH):
            keep = [p.g0 < window for p in passes]
            brows, info = _rows(passes, self.bodies, keep)
            brows, info = self._add_crack_rows(brows, info)
            kc = brows[0].shape[0]
            if kc == 0:
                window *= 2.0
                continue
            amat = _Compliance(self.bodies, brows)
            c1 = brows[0] @ b1.mode
            c2 = brows[1] @ b2.mode
            g0 = info["g0"] + c2 * driven_rotation
            gscale = max(window, 1e-12)
            tol = 1e-7 * gscale
            if load is None:
                lam, _, it = _contact_qp(amat, g0 + c1 * rotation, None, 0.0, tol)
                th1 = float(rotation)
            else:
                lam, th1, it = _contact_qp(amat, g0, c1, load, tol)
            iters += it
            # displacements and the gap of every candidate node (kept or not)
            w1 = b1.solve(brows[0].T @ lam)
            w2 = b2.solve(brows[1].T @ lam)
            gall = allg0 + full[0] @ (w1 + th1 * b1.mode) + full[1] @ (w2 + driven_rotation
                                                                        * b2.mode)
            outside = ~np.concatenate(keep)
            if not np.any(outside & (gall < -tol)):
                break
            window *= 2.0
        else:
            raise SimulationError("the contact zone kept growing: the candidate window did not "
                                  "settle (is the load far beyond the elastic range?)")
        th2 = float(driven_rotation)
        torque_on_driver = float(c1 @ lam) * width
        driven_torque = float(c2 @ lam) * width
        if load is None:
            tq = torque_on_driver
        sgn = 1.0 if self.side > 0 else -1.0
        delta = -sgn * (g1.base_radius * th1 + g2.base_radius * th2)
        force = abs(tq) / g1.base_radius
        k = force / delta if delta > 0 else float("nan")
        # pairs
        labels = info["label"]
        on_crack = labels == CRACK_LABEL
        closed = (float(np.sum(info["weight"][on_crack & (lam > 0)])
                        / np.sum(info["weight"][on_crack])) if np.any(on_crack)
                  else float("nan"))
        teeth = np.array(sorted(set(int(v) for v in labels[(lam > 0) & ~on_crack])),
                         dtype=np.int64)
        pforce = np.zeros(teeth.size)
        share = np.zeros(teeth.size)
        halfw = np.zeros(teeth.size)
        extent = np.zeros(teeth.size)
        hertz = np.zeros(teeth.size)
        peak = np.zeros(teeth.size)
        # pressure: mean over the driver-flank edges (pass 1 forces)
        on_s1 = np.flatnonzero(keep[0])
        f_s1 = np.zeros(s1.xy.shape[0])
        f_s1[on_s1] = lam[:on_s1.size]
        exy, epress = s1.edge_pressure(f_s1)
        ctot = float(c1 @ lam)
        for i, kk in enumerate(teeth):
            sel = (labels == kk) & (lam > 0)
            lk = lam[sel]
            pforce[i] = float(lk.sum()) * width
            share[i] = float(c1[sel] @ lk) / ctot if ctot != 0 else float("nan")
            xy = info["xy"][sel]
            nbar = np.sum(info["normal"][sel] * lk[:, None], axis=0)
            nbar /= np.hypot(*nbar)
            tang = np.array([-nbar[1], nbar[0]])
            s = (xy - np.sum(xy * lk[:, None], axis=0) / lk.sum()) @ tang
            halfw[i] = 2.0 * math.sqrt(max(float(lk @ s**2) / float(lk.sum()), 0.0))
            extent[i] = float(s.max() - s.min())
            on_pair = (s1.elabel == kk) & (epress > 0)
            peak[i] = float(epress[on_pair].max()) if np.any(on_pair) else float("nan")
            lr = self.roll_position(u, int(kk))
            # involute contact inside the path; a tip corner outside it has no Hertz width
            inside = pair.start_of_contact <= lr <= pair.end_of_contact
            hertz[i] = self._hertz_at(lr, float(lk.sum())) if inside else float("nan")
        # root stresses on the tension fillets
        rs = []
        for bi, (body, w_) in enumerate(((b1, w1), (b2, w2))):
            sig = _vertex_stress(body.model, w_)
            smax = _max_principal(sig)
            rs.append(np.array([float(smax[self.fillets[bi][int(kk)]].max())
                                if int(kk) in self.fillets[bi] else float("nan")
                                for kk in teeth]))
        loaded = epress > 0
        return FEPairResult(
            position=u, torque=tq, force=force, transmission_error=delta, stiffness=k,
            theta1=th1, theta2=th2, driven_torque=driven_torque, pair_teeth=teeth,
            pair_force=pforce, load_share=share, contact_half_width=halfw,
            contact_extent=extent, hertz_half_width=hertz, peak_pressure=peak,
            root_stress_driver=rs[0], root_stress_driven=rs[1],
            contact_xy=b1.to_global(exy[loaded]), contact_pressure=epress[loaded],
            contact_pair=s1.elabel[loaded], candidates=int(kc), iterations=iters,
            level=self.level, h=self.h, h_contact=self.h_contact,
            dofs=(b1.model.ndofs, b2.model.ndofs), plane=self.plane,
            seconds=time.perf_counter() - t0, crack_closed=closed)


# --------------------------------------------------------------------------- public API
def fe_pair_solve(pair: GearPair, position: float, *, torque: float, level: int = DEFAULT_LEVEL,
                  plane: str = "stress") -> FEPairResult:
    """FE gear pair in contact at one mesh position (module docstring).

    Parameters
    ----------
    pair
        The gear pair (its transverse section).
    position
        Mesh-cycle fraction u in [0, 1): driver tooth k touches at
        l = l_A + (u + k) p_b on the line of action.
    torque
        Driver torque over the face width [N m]; > 0 loads the drive flanks, < 0 the
        back flanks.
    level
        Mesh level (:class:`FEPairModel`).
    plane
        ``"stress"`` or ``"strain"``.

    Returns
    -------
    FEPairResult
        Transmission error, mesh stiffness k = F / delta, load sharing, contact widths,
        pressures and root stresses.

    Raises
    ------
    InputError
        A position outside [0, 1), a zero or non-finite torque, a level outside
        [0, MAX_LEVEL] or too coarse for the contact.
    """
    _check_position(position)
    torque = _check_torque(torque)
    model = FEPairModel(pair, torque=torque, level=level, plane=plane)
    res = model.solve(position)
    res.seconds += model.setup_seconds
    return res


def fe_pair_tvms(pair: GearPair, positions=8, *, torque: float, level: int = DEFAULT_LEVEL,
                 plane: str = "stress") -> FEPairTVMS:
    """FE mesh stiffness, transmission error and load sharing over a mesh cycle.

    Parameters
    ----------
    pair
        The gear pair.
    positions
        Number N of positions u = (i + 1/2) / N, i = 0 .. N-1, or the mesh-cycle
        fractions themselves (each in [0, 1)).
    torque
        Driver torque over the face width [N m] (sign: the loaded flanks).
    level
        Mesh level.
    plane
        ``"stress"`` or ``"strain"``.

    Returns
    -------
    FEPairTVMS

    Raises
    ------
    InputError
        Bad positions (a count outside [1, 1000] or fractions outside [0, 1)), torque or
        level.
    """
    if isinstance(positions, (int, np.integer)) and not isinstance(positions, bool):
        if not 1 <= int(positions) <= 1000:
            raise InputError("positions", positions, "must be a count in [1, 1000] or "
                             "mesh-cycle fractions in [0, 1)")
        u = (np.arange(int(positions)) + 0.5) / int(positions)
    else:
        u = np.atleast_1d(np.asarray(positions, dtype=float))
        if u.ndim != 1 or u.size == 0:
            raise InputError("positions", positions, "must be a count or a 1D list of "
                             "mesh-cycle fractions in [0, 1)")
        for v in u:
            _check_position(float(v))
    torque = _check_torque(torque)
    model = FEPairModel(pair, torque=torque, level=level, plane=plane)
    results = [model.solve(float(v)) for v in u]
    teeth = np.array(sorted({int(k) for r in results for k in r.pair_teeth}), dtype=np.int64)
    share = np.zeros((u.size, teeth.size))
    for i, r in enumerate(results):
        for k, s in zip(r.pair_teeth, r.load_share, strict=True):
            share[i, int(np.searchsorted(teeth, k))] = s
    return FEPairTVMS(positions=u, stiffness=np.array([r.stiffness for r in results]),
                      transmission_error=np.array([r.transmission_error for r in results]),
                      load_share=share, pair_teeth=teeth, results=results,
                      setup_seconds=model.setup_seconds)


def pe_slice_stiffness(pair: GearPair, positions, *, plane: str = "stress") -> np.ndarray:
    """Potential-energy mesh stiffness of the transverse section at mesh positions.

    The spur formula of :func:`gearsim.stiffness.mesh.mesh_stiffness` (pairs in contact
    at l = l_A + (u + k) p_b, l_A < l <= l_E, each a series of Hertz and the four tooth
    compliances of both gears, pairs in parallel) over the face width b, for the 2D
    section the FE pair models; for a spur pair it is ``mesh_stiffness`` itself.

    Parameters
    ----------
    pair
        The gear pair.
    positions
        Mesh-cycle fractions u.
    plane
        ``"stress"`` or ``"strain"`` (tooth compliance; the Hertz term is the PE one).

    Returns
    -------
    ndarray
        k(u) over the face width [N/m].
    """
    from gearsim.stiffness.settings import StiffnessSettings
    from gearsim.stiffness.source import PotentialEnergyCompliance
    from gearsim.stiffness.tooth import hertz_stiffness

    u = np.atleast_1d(np.asarray(positions, dtype=float))
    g1, g2 = pair.driver, pair.driven
    la, le, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
    n_age = int(math.ceil(pair.transverse_contact_ratio)) + 1
    lpos = la + (u[:, None] + np.arange(n_age)[None, :]) * pb
    inside = (lpos > la) & (lpos <= le)
    lsafe = np.where(inside, lpos, 0.5 * (la + le))
    r1 = np.hypot(g1.base_radius, lsafe)[..., None]
    r2 = np.hypot(g2.base_radius, pair.line_length - lsafe)[..., None]
    settings = StiffnessSettings(plane=plane)
    model = PotentialEnergyCompliance()
    zfrac = np.array([0.5])
    c1 = model.compliance(g1, r1, None, zfrac, settings).sum(-1)[..., 0]
    c2 = model.compliance(g2, r2, None, zfrac, settings).sum(-1)[..., 0]
    ch = 1.0 / hertz_stiffness(g1.material, g2.material, 1.0)
    return pair.face_width * np.sum(np.where(inside, 1.0 / (ch + c1 + c2), 0.0), axis=1)


# --------------------------------------------------------------------------- cylinders
@dataclass
class FECylinderResult:
    """FE line contact of two elastic discs against the 2D Hertz solution.

    Parameters
    ----------
    load
        Normal load per unit length F [N/m].
    half_width
        FE half width from the second moment of the contact forces [m].
    extent
        Half the distance between the outermost nodes with a force [m].
    peak_pressure
        Largest nodal pressure [Pa].
    hertz_half_width
        b = sqrt(4 F R / (pi E*)) [m].
    hertz_peak_pressure
        p0 = 2 F / (pi b) [Pa].
    approach
        Approach of the two hubs (bores) [m].
    x, pressure
        Positions across the contact (tangential coordinate) [m] and edge-mean pressures
        ``(f_a / 2 + f_mid + f_b / 2) / L`` [Pa] of the loaded edges of disc 1.
    h_contact
        Element size at the contact [m].
    candidates, iterations
        Contact constraints and active-set iterations.
    """

    load: float
    half_width: float
    extent: float
    peak_pressure: float
    hertz_half_width: float
    hertz_peak_pressure: float
    approach: float
    x: np.ndarray
    pressure: np.ndarray
    h_contact: float
    candidates: int
    iterations: int


def _mesh_disc(radius: float, bore: float, contact_y: float, h_contact: float,
               h_max: float, growth: float = 0.3):
    """gmsh mesh of an annulus with a refinement at (0, contact_y); returns p, t, bore, rim."""
    with gmsh_session() as gmsh:
        geo = gmsh.model.geo
        c = geo.addPoint(0.0, 0.0, 0.0)
        rim_pts = [geo.addPoint(radius * math.cos(a), radius * math.sin(a), 0.0)
                   for a in (0.5 * math.pi, math.pi, 1.5 * math.pi, 0.0)]
        bore_pts = [geo.addPoint(bore * math.cos(a), bore * math.sin(a), 0.0)
                    for a in (0.5 * math.pi, math.pi, 1.5 * math.pi, 0.0)]
        rim = [geo.addCircleArc(rim_pts[i], c, rim_pts[(i + 1) % 4]) for i in range(4)]
        bcs = [geo.addCircleArc(bore_pts[i], c, bore_pts[(i + 1) % 4]) for i in range(4)]
        surf = geo.addPlaneSurface([geo.addCurveLoop(rim), geo.addCurveLoop(bcs)])
        geo.synchronize()
        target = rim_pts[0] if contact_y > 0 else rim_pts[2]
        thr = distance_threshold(gmsh, points=[target], size=(h_contact, h_max),
                                 distance=(20.0 * h_contact,
                                           20.0 * h_contact + (h_max - h_contact) / growth))
        generate_sized(gmsh, thr, lc_precision=1e-4)
        xy, index, tri = gmsh_triangles(gmsh, surf, "mesh", "disc")
        bore_nodes = gmsh_nodes_on(gmsh, index, 1, bcs)
        rim_nodes = gmsh_nodes_on(gmsh, index, 1, rim)
    p, t, renum = drop_unused_nodes(xy, tri)
    return p, t, kept_nodes(renum, bore_nodes), kept_nodes(renum, rim_nodes)


def fe_cylinder_contact(radius1: float, radius2: float, load: float, *,
                        material: Material | None = None, plane: str = "strain",
                        h_contact: float | None = None, bore_ratio: float = 0.3
                        ) -> FECylinderResult:
    """Two elastic discs pressed together, solved with the gear-pair contact machinery.

    Disc 1 (centre (0, 0)) and disc 2 (centre (0, R1 + R2)) touch at (0, R1); each bore
    (radius ``bore_ratio`` R) is tied to a rigid hub, hub 2 held and hub 1 pushed
    towards disc 2 by the load. The contact is the node-to-segment, exact active-set
    contact of :class:`FEPairModel`.

    Parameters
    ----------
    radius1, radius2
        Disc radii [m].
    load
        Normal load per unit length [N/m] (> 0).
    material
        Both discs' material (default steel, :class:`~gearsim.geometry.gear.Material`).
    plane
        ``"strain"`` (default) or ``"stress"``.
    h_contact
        Element size at the contact [m]; default b / 16 with b the Hertz half width.
    bore_ratio
        Bore radius / disc radius [-].

    Returns
    -------
    FECylinderResult

    Raises
    ------
    InputError
        Non-positive radii, load or element size.
    """
    mat = material or Material()
    for name, v in (("radius1", radius1), ("radius2", radius2), ("load", load)):
        if not (math.isfinite(v) and v > 0.0):
            raise InputError(name, v, "must be a finite number > 0")
    rel = radius1 * radius2 / (radius1 + radius2)
    bh = hertz_half_width(load, rel, mat.youngs_modulus, mat.poisson_ratio, plane)
    hc = bh / 16.0 if h_contact is None else float(h_contact)
    if not (math.isfinite(hc) and hc > 0.0):
        raise InputError("h_contact", h_contact, "must be > 0 m")
    bodies, surfs = [], []
    for i, (r, cy) in enumerate(((radius1, 1.0), (radius2, -1.0))):
        p, t, bore, rim = _mesh_disc(r, bore_ratio * r, cy, hc, r / 8.0)
        model = ElasticModel(p, t, mat.youngs_modulus, mat.poisson_ratio, plane=plane, order=2)
        fixed = model.dofs_on_facets(model.facets_on_nodes(bore))
        centre = np.array([0.0, 0.0 if i == 0 else radius1 + radius2])
        bodies.append(_Body(model=model, fixed=fixed, mode=_translation(model, (0.0, 1.0)),
                            centre=centre))
        near = rim[(np.abs(p[0, rim]) < 6.0 * bh) & (p[1, rim] * cy > 0)]
        surfs.append(_surface(model, {0: near}))
    pr = _project(surfs[0], bodies[0], surfs[1], bodies[1], 0, True)
    window = 8.0 * bh**2 / (2.0 * rel)
    keep = [pr.g0 < window]
    brows, info = _rows([pr], bodies, keep)
    amat = _Compliance(bodies, brows)
    c1 = brows[0] @ bodies[0].mode
    lam, th, it = _contact_qp(amat, info["g0"], c1, -load, 1e-9 * window)
    act = lam > 0
    full = np.zeros(surfs[0].xy.shape[0])
    full[np.flatnonzero(keep[0])] = lam
    exy, epress = surfs[0].edge_pressure(full)
    x = info["xy"][:, 0]
    xc = float(x[act] @ lam[act] / lam[act].sum())
    half = 2.0 * math.sqrt(float(lam[act] @ (x[act] - xc) ** 2) / float(lam[act].sum()))
    extent = 0.5 * float(x[act].max() - x[act].min())
    loaded = epress > 0
    ex = bodies[0].to_global(exy)[loaded, 0]
    order = np.argsort(ex)
    return FECylinderResult(load=load, half_width=half, extent=extent,
                            peak_pressure=float(epress.max()), hertz_half_width=bh,
                            hertz_peak_pressure=2.0 * load / (math.pi * bh), approach=float(th),
                            x=ex[order], pressure=epress[loaded][order], h_contact=hc,
                            candidates=int(lam.size), iterations=it)
