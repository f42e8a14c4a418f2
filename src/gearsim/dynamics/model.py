"""The assembled equations of motion that the integrator runs.

Both models (:mod:`~gearsim.dynamics.lta` and :mod:`~gearsim.dynamics.seed3dof`) are
written in one form, with a diagonal mass matrix and one projection vector per mesh:

    M q'' + C_b q' + K_b q = F_ext - sum_i V_i f_i(t, q, q')

    f_i = kappa_i [ s_i k_i(c_i) g_i(V_i.q - e_i(t)) + c_mi h_i (V_i.q' - e_i'(t)) ]

with c_i = f_m t + phase_i the mesh-cycle coordinate, k_i the tabulated (transverse)
stiffness scaled by s_i, e_i(t) = e0_i + sum_h A_ih sin(w_ih t + p_ih) the static
transmission error, and the backlash function (clearance 2b_i)

    g(d) = d        for d > 0          (working-flank contact)
    g(d) = 0        for -2b < d <= 0   (teeth separated)
    g(d) = d + 2b   for d <= -2b       (back-side contact)

h_i = 1 while the teeth are in contact on either side, 0 while separated (Kahraman &
Singh 1990, clearance function with the origin moved to the working-flank contact). The
contact force of a flank pair cannot change sign: on the working side f_i is clipped at
0 from below, on the back side at 0 from above (the viscous term would otherwise pull
the separating flanks together, an artefact of Kelvin-Voigt contact damping). A linear
mesh (seed model, ``nonlinear = false``) has ``clearance = inf`` and f_i =
kappa_i (s_i k_i (V_i.q - e_i) + c_mi (V_i.q' - e_i')) for all deflections.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gearsim.dynamics.tables import MeshTable

__all__ = ["DynamicModel", "mean_stiffness_matrix"]


@dataclass(frozen=True)
class DynamicModel:
    """Arrays of the equations of motion (SI units).

    Attributes
    ----------
    kind : "lta" or "seed"
    gear_names : names of the gears in power-flow order
    dof_labels : label of each coordinate, e.g. ``"input.x"``, ``"idler.theta"``
    mass : (n,) diagonal of M [kg or kg m^2]
    kb, cb : (n,) bearing stiffness [N/m] and damping [N s/m] on each coordinate
    fext : (n,) constant external generalized forces [N or N m]
    V : (n_mesh, n) projection vectors: mesh deflection = V_i . q [m]
    kappa : (n_mesh,) force projection factor (seed: cos(alpha_n) cos(beta); LTA: 1)
    kscale : (n_mesh,) factor on the tabulated transverse stiffness (seed: 1/cos^2 beta_b)
    cm : (n_mesh,) mesh damping [N s/m]
    clearance : (n_mesh,) backlash 2b [m]; ``inf``: linear mesh (no separation)
    tables : stiffness tables
    phase : (n_mesh,) mesh-cycle offsets [cycles]
    mesh_frequency : f_m [Hz]
    e0 : (n_mesh,) constant STE [m]
    h_amp, h_omega, h_phase : (n_mesh, n_h) STE harmonics [m], [rad/s], [rad]
    to_transverse : (n_mesh,) factor from f_i to the transverse line-of-action force
    dte_offset : (n_mesh,) added to V.q to give the reported transmission error [m]
    static_force : (n_mesh,) T_i / r_bi [N]
    bearing_dofs : (n_gears, n_axes) index of each bearing coordinate
    axes : names of the bearing axes
    q_static : (n,) static equilibrium of the mean-stiffness system [m, rad]
    info : further descriptive data (mesh damping ratio, equivalent masses, ...)
    """

    kind: str
    gear_names: tuple[str, ...]
    dof_labels: tuple[str, ...]
    mass: np.ndarray
    kb: np.ndarray
    cb: np.ndarray
    fext: np.ndarray
    V: np.ndarray
    kappa: np.ndarray
    kscale: np.ndarray
    cm: np.ndarray
    clearance: np.ndarray
    tables: tuple[MeshTable, ...]
    phase: np.ndarray
    mesh_frequency: float
    e0: np.ndarray
    h_amp: np.ndarray
    h_omega: np.ndarray
    h_phase: np.ndarray
    to_transverse: np.ndarray
    dte_offset: np.ndarray
    static_force: np.ndarray
    bearing_dofs: np.ndarray
    axes: tuple[str, ...]
    q_static: np.ndarray
    info: dict = field(default_factory=dict)

    @property
    def n_dof(self) -> int:
        return self.mass.size

    @property
    def n_mesh(self) -> int:
        return self.V.shape[0]

    def mean_stiffness(self) -> np.ndarray:
        """Mean mesh stiffness of each mesh in the kernel's units, kappa s k_mean [N/m]."""
        return np.array([self.kappa[i] * self.kscale[i] * t.mean
                         for i, t in enumerate(self.tables)])

    def max_stiffness(self) -> np.ndarray:
        """Largest mesh stiffness of each mesh, kappa s k_max [N/m]."""
        return np.array([self.kappa[i] * self.kscale[i] * t.max
                         for i, t in enumerate(self.tables)])

    def ste(self, t: np.ndarray) -> np.ndarray:
        """Static transmission error e_i(t), shape (len(t), n_mesh) [m]."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        arg = t[:, None, None] * self.h_omega[None] + self.h_phase[None]
        return self.e0[None, :] + np.sum(self.h_amp[None] * np.sin(arg), axis=-1)


def mean_stiffness_matrix(model: DynamicModel, *, which: str = "mean") -> np.ndarray:
    """K_b + sum_i kappa_i s_i k_i V_i V_i^T with the mean (or maximum) mesh stiffness [N/m]."""
    k = model.mean_stiffness() if which == "mean" else model.max_stiffness()
    K = np.diag(model.kb).astype(float)
    for i in range(model.n_mesh):
        K += k[i] * np.outer(model.V[i], model.V[i])
    return K


def static_equilibrium(mass: np.ndarray, kb: np.ndarray, V: np.ndarray, kmean: np.ndarray,
                       fext: np.ndarray, e0: np.ndarray) -> np.ndarray:
    """Solve (K_b + sum k_i V_i V_i^T) q = F_ext + sum k_i e0_i V_i (least squares).

    A rigid-body mode (singular K) gets zero amplitude (minimum-norm solution).
    """
    K = np.diag(kb).astype(float)
    rhs = fext.astype(float).copy()
    for i in range(V.shape[0]):
        K += kmean[i] * np.outer(V[i], V[i])
        rhs += kmean[i] * e0[i] * V[i]
    q, *_ = np.linalg.lstsq(K, rhs, rcond=1e-12)
    return q
