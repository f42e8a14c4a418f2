"""Eigen-analysis of the mean system: natural frequencies, step limit, decay time.

References
----------
.. [Hairer1996] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II,
   Springer 1996, sec. IV.2: the stability region of the classical 4-stage Runge-Kutta
   method reaches |h omega| = 2 sqrt(2) = 2.83 on the imaginary axis; we use 2.78
   (undamped oscillators, small margin).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from gearsim.dynamics.model import DynamicModel, mean_stiffness_matrix

__all__ = ["Modes", "RK4_LIMIT", "decay_time", "modes", "stable_step"]

#: |omega dt| below which classical RK4 is stable for an undamped oscillator (< 2 sqrt 2).
RK4_LIMIT = 2.78


@dataclass(frozen=True)
class Modes:
    """Undamped modes of the mean-stiffness system.

    Attributes
    ----------
    frequencies : natural frequencies f_n [Hz], ascending, rigid-body modes removed
    shapes : (n_dof, n_modes) mass-normalised mode shapes
    mesh_energy : (n_mesh, n_modes) fraction of each mode's strain energy in each mesh
    rigid : number of rigid-body (zero-frequency) modes removed
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    mesh_energy: np.ndarray
    rigid: int


def modes(model: DynamicModel, *, which: str = "mean") -> Modes:
    """Solve K phi = omega^2 M phi for the mean (or maximum) mesh stiffness.

    Uses :func:`scipy.linalg.eigh` on (K, M); modes with omega < 1e-6 of the largest are
    the rigid-body rotation of the chain and are removed.
    """
    K = mean_stiffness_matrix(model, which=which)
    M = np.diag(model.mass)
    w2, phi = scipy.linalg.eigh(K, M)
    w2 = np.clip(w2, 0.0, None)
    keep = w2 > 1e-12 * w2.max()
    w = np.sqrt(w2[keep])
    phi = phi[:, keep]
    k = model.mean_stiffness() if which == "mean" else model.max_stiffness()
    strain = np.einsum("in,i->in", (model.V @ phi) ** 2, k)
    energy = strain / np.maximum(w ** 2, 1e-300)[None, :]  # phi^T K phi = w^2
    return Modes(frequencies=w / (2 * np.pi), shapes=phi, mesh_energy=energy,
                 rigid=int(np.count_nonzero(~keep)))


def stable_step(model: DynamicModel) -> float:
    """Largest RK4 step that is stable for the stiffest state of the system [s].

    ``RK4_LIMIT / omega_max`` with omega_max the highest natural frequency for the
    maximum tabulated mesh stiffness of every mesh (mass-normalised, undamped).
    """
    wmax = 2 * np.pi * float(modes(model, which="max").frequencies.max())
    return RK4_LIMIT / wmax


def decay_time(model: DynamicModel) -> float:
    """1 / (slowest decay rate) of the damped mean linear system [s].

    From the eigenvalues of the first-order system [[0, I], [-M^-1 K, -M^-1 C]] with
    C = C_b + sum c_m,i kappa_i V_i V_i^T; zero eigenvalues (rigid-body mode) skipped.
    """
    n = model.n_dof
    K = mean_stiffness_matrix(model)
    C = np.diag(model.cb).astype(float)
    for i in range(model.n_mesh):
        C += model.kappa[i] * model.cm[i] * np.outer(model.V[i], model.V[i])
    minv = 1.0 / model.mass
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -minv[:, None] * K
    A[n:, n:] = -minv[:, None] * C
    lam = np.linalg.eigvals(A)
    scale = np.abs(lam).max()
    lam = lam[np.abs(lam) > 1e-6 * scale]
    rate = float(np.min(-lam.real))
    return 1.0 / rate
