"""Stress intensity factors K_I, K_II at a crack tip of a 2D elastic FE solution.

Method: the **interaction integral** in its equivalent domain form (Yau, Wang & Corten
1980; Shih & Asaro 1988; domain form of Shih, Moran & Nakamura 1986 / Moran & Shih 1987;
Anderson, *Fracture Mechanics*, 3rd ed., 2005, sec. 7.4.2 / 12.1.3). With the actual
field (u, sigma, eps) and an auxiliary field (u^a, sigma^a, eps^a) -- the Williams
near-tip field of pure mode I or pure mode II with unit K --, in the tip frame
(x1 along the crack extension, x2 normal to it):

    I = int_A [ sigma_ij du^a_i/dx1 + sigma^a_ij du_i/dx1 - sigma_ik eps^a_ik delta_1j ]
              dq/dx_j dA,                                                    [N/m]

    K_I = E' I(mode I aux) / 2,   K_II = E' I(mode II aux) / 2,            [Pa sqrt(m)]

with E' = E (plane stress) or E / (1 - nu^2) (plane strain), and the weight q(r) = 1
for r <= r_in falling smoothly (3 rho^2 - 2 rho^3) to 0 at r = r_out, so that only the
ring r_in < r < r_out is integrated: the elements at the tip, where the FE field is
least accurate, do not enter. The crack faces in the ring must be straight and
traction-free (no face contact), and the ring must not reach any other boundary.

Auxiliary fields (Anderson, Table 2.1/2.2; Williams 1957), r, theta in the tip frame,
kappa = 3 - 4 nu (plane strain) or (3 - nu) / (1 + nu) (plane stress),
u = K / (2 mu) sqrt(r / (2 pi)) f(theta):

    mode I:  f1 = cos(t/2) (kappa - 1 + 2 sin^2(t/2)),  f2 = sin(t/2) (kappa + 1 - 2 cos^2(t/2))
    mode II: f1 = sin(t/2) (kappa + 1 + 2 cos^2(t/2)),  f2 = -cos(t/2) (kappa - 1 - 2 sin^2(t/2))

Their gradients are differentiated analytically; the auxiliary stress follows from
the auxiliary strain by the same Hooke law as the FE model (it equals the Williams
stress, e.g. sigma_22 = K / sqrt(2 pi r) ahead of a mode-I tip; tested).

The FE field is the quadratic (P2) displacement of :class:`gearsim.fem.solve.ElasticModel`
on a mesh refined at the tip (:mod:`gearsim.fracture.mesh`); no singular elements are
needed because the domain integral is taken away from the tip.

References
----------
.. [Yau1980] J. F. Yau, S. S. Wang, H. T. Corten, A mixed-mode crack analysis of
   isotropic solids using conservation laws of elasticity, J. Appl. Mech. 47 (1980)
   335-341.
.. [Shih1986] C. F. Shih, B. Moran, T. Nakamura, Energy release rate along a
   three-dimensional crack front in a thermally stressed body, Int. J. Fract. 30 (1986)
   79-102 (equivalent domain integral).
.. [Anderson2005] T. L. Anderson, Fracture Mechanics: Fundamentals and Applications,
   3rd ed., CRC Press 2005, ch. 2 (near-tip fields) and ch. 7/12 (J and interaction
   integrals, domain form).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gearsim.errors import require
from gearsim.fem.solve import ElasticModel, plane_lame

__all__ = ["StressIntensity", "effective_modulus", "interaction_integral",
           "kolosov_constant", "williams_displacement_gradient", "williams_stress"]

#: Order of the triangle quadrature of the domain integral (polynomial degree exact).
QUADRATURE_ORDER = 8


@dataclass(frozen=True)
class StressIntensity:
    """Mixed-mode stress intensity factors at a crack tip.

    Parameters
    ----------
    k1
        Mode-I stress intensity factor K_I [Pa sqrt(m)].
    k2
        Mode-II stress intensity factor K_II [Pa sqrt(m)] (positive: the face on the
        +x2 side slides forward along x1, the Williams sign convention).
    j
        Energy release rate (K_I^2 + K_II^2) / E' [N/m = J/m^2].
    r_in, r_out
        Inner and outer radius of the integration ring [m].
    """

    k1: float
    k2: float
    j: float
    r_in: float
    r_out: float


def kolosov_constant(poisson_ratio: float, plane: str) -> float:
    """Kolosov constant kappa.

    Parameters
    ----------
    poisson_ratio
        nu [-].
    plane
        ``"stress"`` ((3 - nu) / (1 + nu)) or ``"strain"`` (3 - 4 nu).

    Returns
    -------
    float
        kappa [-] (Anderson 2005, Table 2.1).

    Examples
    --------
    >>> round(kolosov_constant(0.3, "strain"), 3), round(kolosov_constant(0.3, "stress"), 4)
    (1.8, 2.0769)
    """
    plane_lame(1.0, poisson_ratio, plane)  # refuses an unknown plane
    nu = poisson_ratio
    return 3.0 - 4.0 * nu if plane == "strain" else (3.0 - nu) / (1.0 + nu)


def effective_modulus(youngs_modulus: float, poisson_ratio: float, plane: str) -> float:
    """E' of the relation J = (K_I^2 + K_II^2) / E'.

    Parameters
    ----------
    youngs_modulus, poisson_ratio
        E [Pa] and nu [-].
    plane
        ``"stress"`` (E' = E) or ``"strain"`` (E' = E / (1 - nu^2)).

    Returns
    -------
    float
        E' [Pa] (Anderson 2005, eq. 2.58).
    """
    plane_lame(youngs_modulus, poisson_ratio, plane)
    e = youngs_modulus
    return e if plane == "stress" else e / (1.0 - poisson_ratio**2)


def _angular(theta: np.ndarray, kappa: float, mode: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """f1, f2 and their theta derivatives of the Williams displacement (see module)."""
    s, c = np.sin(0.5 * theta), np.cos(0.5 * theta)
    if mode == 1:
        f1 = c * (kappa - 1.0 + 2.0 * s**2)
        f2 = s * (kappa + 1.0 - 2.0 * c**2)
        d1 = -0.5 * s * (kappa - 1.0 + 2.0 * s**2) + 2.0 * s * c**2
        d2 = 0.5 * c * (kappa + 1.0 - 2.0 * c**2) + 2.0 * s**2 * c
    else:
        f1 = s * (kappa + 1.0 + 2.0 * c**2)
        f2 = -c * (kappa - 1.0 - 2.0 * s**2)
        d1 = 0.5 * c * (kappa + 1.0 + 2.0 * c**2) - 2.0 * s**2 * c
        d2 = 0.5 * s * (kappa - 1.0 - 2.0 * s**2) + 2.0 * s * c**2
    return f1, f2, d1, d2


def williams_displacement_gradient(x1: np.ndarray, x2: np.ndarray, mode: int,
                                   shear_modulus: float, kappa: float) -> np.ndarray:
    """Gradient of the Williams near-tip displacement for a unit K.

    Parameters
    ----------
    x1, x2
        Points in the tip frame (x1 ahead of the tip, x2 normal), same shape [m]; not
        at the tip.
    mode
        1 or 2.
    shear_modulus
        mu [Pa].
    kappa
        Kolosov constant [-].

    Returns
    -------
    ndarray, shape (2, 2, *x1.shape)
        G[i, j] = du_i / dx_j for K = 1 Pa sqrt(m) [-/ (Pa sqrt(m))], from
        u = sqrt(r / (2 pi)) f(theta) / (2 mu):
        du/dx1 = (cos t f / 2 - sin t f') / (2 mu sqrt(2 pi r)),
        du/dx2 = (sin t f / 2 + cos t f') / (2 mu sqrt(2 pi r)).
    """
    require(mode in (1, 2), "mode", mode, "must be 1 or 2")
    r = np.hypot(x1, x2)
    th = np.arctan2(x2, x1)
    f1, f2, d1, d2 = _angular(th, kappa, mode)
    a = 1.0 / (2.0 * shear_modulus * np.sqrt(2.0 * math.pi * r))
    ct, st = np.cos(th), np.sin(th)
    g = np.empty((2, 2, *np.shape(x1)))
    g[0, 0] = a * (0.5 * ct * f1 - st * d1)
    g[0, 1] = a * (0.5 * st * f1 + ct * d1)
    g[1, 0] = a * (0.5 * ct * f2 - st * d2)
    g[1, 1] = a * (0.5 * st * f2 + ct * d2)
    return g


def williams_stress(x1: np.ndarray, x2: np.ndarray, mode: int) -> np.ndarray:
    """Williams near-tip stress for a unit K (closed form, for checks).

    Parameters
    ----------
    x1, x2
        Points in the tip frame [m].
    mode
        1 or 2.

    Returns
    -------
    ndarray, shape (3, *x1.shape)
        (sigma_11, sigma_22, sigma_12) for K = 1 Pa sqrt(m) [1/sqrt(m)]
        (Anderson 2005, Table 2.1 and 2.2).
    """
    require(mode in (1, 2), "mode", mode, "must be 1 or 2")
    r = np.hypot(x1, x2)
    th = np.arctan2(x2, x1)
    s, c = np.sin(0.5 * th), np.cos(0.5 * th)
    s3, c3 = np.sin(1.5 * th), np.cos(1.5 * th)
    a = 1.0 / np.sqrt(2.0 * math.pi * r)
    if mode == 1:
        return np.stack([a * c * (1.0 - s * s3), a * c * (1.0 + s * s3), a * c * s * c3])
    return np.stack([-a * s * (2.0 + c * c3), a * s * c * c3, a * c * (1.0 - s * s3)])


def interaction_integral(model: ElasticModel, u: np.ndarray, tip, direction, *,
                         r_out: float, r_in: float | None = None) -> StressIntensity:
    """K_I and K_II at a crack tip by the domain interaction integral.

    Parameters
    ----------
    model
        The assembled elastic model (P2 or P1, plane stress or strain).
    u
        Its displacement vector [m].
    tip
        Tip position (2,) [m].
    direction
        Direction of crack extension (2,): the tip frame's x1 axis (normalised here).
    r_out
        Outer radius of the ring [m]: smaller than the distance from the tip to any
        other boundary than the crack faces, and than the straight last crack segment.
    r_in
        Inner radius of the ring [m] (default ``r_out / 4``).

    Returns
    -------
    StressIntensity

    Raises
    ------
    InputError
        Non-positive radii, ``r_in >= r_out`` or a zero direction.
    """
    require(math.isfinite(r_out) and r_out > 0.0, "sif.r_out", r_out, "must be > 0 m")
    rin = 0.25 * r_out if r_in is None else float(r_in)
    require(math.isfinite(rin) and 0.0 <= rin < r_out, "sif.r_in", r_in,
            f"must be in [0, r_out = {r_out:.4g} m)")
    from skfem import Basis

    e1 = np.asarray(direction, dtype=float)
    n1 = float(np.hypot(*e1))
    require(n1 > 0.0 and math.isfinite(n1), "sif.direction", tuple(e1), "must be non-zero")
    e1 = e1 / n1
    rot = np.array([e1, [-e1[1], e1[0]]])  # rows: local axes in global components
    x0 = np.asarray(tip, dtype=float)
    mesh = model.mesh
    # elements that can touch the ring
    vx = mesh.p[:, mesh.t] - x0[:, None, None]  # (2, 3, m)
    rv = np.hypot(vx[0], vx[1])
    diam = np.max(np.hypot(*(mesh.p[:, mesh.t] - mesh.p[:, np.roll(mesh.t, 1, axis=0)])),
                  axis=0)
    near = np.nonzero((rv.min(axis=0) < r_out + diam) & (rv.max(axis=0) > rin - diam))[0]
    basis = Basis(mesh, model.element, elements=near, intorder=QUADRATURE_ORDER)
    grad = basis.interpolate(u).grad  # (2, 2, ne, nq): du_i/dx_j, global frame
    xg = np.asarray(basis.global_coordinates()) - x0[:, None, None]
    dx = basis.dx
    gl = np.einsum("ai,ijeq,bj->abeq", rot, grad, rot)  # local gradient
    xl = np.einsum("ai,ieq->aeq", rot, xg)
    r = np.hypot(xl[0], xl[1])
    rho = np.clip((r - rin) / (r_out - rin), 0.0, 1.0)
    ring = (rho > 0.0) & (rho < 1.0)
    dq_dr = np.where(ring, -6.0 * rho * (1.0 - rho) / (r_out - rin), 0.0)
    rs = np.where(r > 0.0, r, 1.0)
    dq = np.stack([dq_dr * xl[0] / rs, dq_dr * xl[1] / rs])
    lam, mu = plane_lame(model.youngs_modulus, model.poisson_ratio, model.plane)
    kappa = kolosov_constant(model.poisson_ratio, model.plane)

    def stress(g: np.ndarray) -> np.ndarray:
        eps = 0.5 * (g + np.swapaxes(g, 0, 1))
        tr = eps[0, 0] + eps[1, 1]
        sig = 2.0 * mu * eps
        sig[0, 0] += lam * tr
        sig[1, 1] += lam * tr
        return sig

    sig = stress(gl)
    eps = 0.5 * (gl + np.swapaxes(gl, 0, 1))
    ints = []
    x1 = np.where(ring, xl[0], 1.0)
    x2 = np.where(ring, xl[1], 0.0)
    for mode in (1, 2):
        ga = williams_displacement_gradient(x1, x2, mode, mu, kappa)
        ga = np.where(ring, ga, 0.0)
        sa = stress(ga)
        w12 = np.einsum("ijeq,ijeq->eq", sa, eps)
        integrand = (np.einsum("ijeq,ieq,jeq->eq", sig, ga[:, 0], dq)
                     + np.einsum("ijeq,ieq,jeq->eq", sa, gl[:, 0], dq)
                     - w12 * dq[0])
        ints.append(float(np.sum(integrand * dx)))
    ep = effective_modulus(model.youngs_modulus, model.poisson_ratio, model.plane)
    k1, k2 = 0.5 * ep * ints[0], 0.5 * ep * ints[1]
    return StressIntensity(k1=k1, k2=k2, j=(k1**2 + k2**2) / ep, r_in=rin, r_out=r_out)
