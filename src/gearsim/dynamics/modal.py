"""Eigen-analysis of the mean system: natural frequencies, step limit, decay time.

References
----------
.. [Hairer1996] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II,
   Springer 1996, sec. IV.2: the stability region of the classical 4-stage Runge-Kutta
   method reaches |h omega| = 2 sqrt(2) = 2.83 on the imaginary axis; we use 2.78
   (undamped oscillators, small margin).

Examples
--------
Two discs (J = 0.5 kg m^2, base radius 0.1 m) coupled by one mesh whose stiffness
alternates between 0.8e8 and 1.2e8 N/m, mesh damping c_m = 500 N s/m, no bearings (so
one rigid-body rotation). By hand: k V V^T with V = (0.1, -0.1) gives K = +-1e6 with the
mean 1e8 N/m (:func:`~gearsim.dynamics.model.mean_stiffness_matrix`);
m_eq = 1 / (2 x 0.1^2 / 0.5) = 25 kg, so f = sqrt(k / m_eq) / (2 pi) = 318.31 Hz with the
mean stiffness and 348.69 Hz with the largest, 1.2e8 N/m (:func:`modes`); then
omega_max = sqrt(1.2e8 / 25) = 2190.89 rad/s and 2.78 / omega_max = 1.2689 ms
(:func:`stable_step`); the decay rate c_m / (2 m_eq) = 10 1/s (damping ratio 0.005) is a
time constant of 0.1 s (:func:`decay_time`):

>>> import numpy as np
>>> from gearsim.dynamics.model import DynamicModel, mean_stiffness_matrix
>>> from gearsim.dynamics.tables import MeshTable
>>> o, z = np.ones(1), np.zeros(2)
>>> pair = DynamicModel(
...     kind="lta", gear_names=("a", "b"), dof_labels=("a.theta", "b.theta"),
...     mass=np.array([0.5, 0.5]), kb=z, cb=z, fext=z, V=np.array([[0.1, -0.1]]),
...     kappa=o, kscale=o, cm=500 * o, clearance=np.inf * o,
...     tables=(MeshTable(k=np.array([0.8e8, 1.2e8]), positions_per_cycle=2, period=1),),
...     phase=0 * o, mesh_frequency=100.0, e0=0 * o, h_amp=np.zeros((1, 1)),
...     h_omega=np.zeros((1, 1)), h_phase=np.zeros((1, 1)), to_transverse=o,
...     dte_offset=0 * o, static_force=0 * o,
...     bearing_dofs=np.zeros((2, 0), dtype=np.int64), axes=(), q_static=z)
>>> mean_stiffness_matrix(pair).round(6).tolist()
[[1000000.0, -1000000.0], [-1000000.0, 1000000.0]]
>>> round(float(mean_stiffness_matrix(pair, which="max")[0, 0]), 6)
1200000.0
>>> from gearsim.dynamics.modal import decay_time, modes, stable_step
>>> md = modes(pair)
>>> md.frequencies.round(2).tolist(), md.rigid, md.mesh_energy.round(6).tolist()
([318.31], 1, [[1.0]])
>>> modes(pair, which="max").frequencies.round(2).tolist()
[348.69]
>>> round(stable_step(pair) * 1e3, 4)  # ms
1.2689
>>> round(decay_time(pair), 6)
0.1
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gearsim.dynamics.model import DynamicModel, mean_stiffness_matrix

__all__ = ["Modes", "RK4_LIMIT", "decay_time", "modes", "stable_step"]

#: |omega dt| below which classical RK4 is stable for an undamped oscillator (< 2 sqrt 2).
RK4_LIMIT = 2.78


@dataclass(frozen=True)
class Modes:
    """Undamped modes of the mean-stiffness system.

    Parameters
    ----------
    frequencies : ndarray, shape (n_modes,)
        Natural frequencies f_n [Hz], ascending, rigid-body modes removed.
    shapes : ndarray, shape (n_dof, n_modes)
        Mass-normalised mode shapes (phi^T M phi = 1) [m or rad per sqrt(kg)].
    mesh_energy : ndarray, shape (n_mesh, n_modes)
        Fraction of each mode's strain energy stored in each mesh,
        k_i (V_i . phi)^2 / omega^2 [-] (the rest is in the bearings).
    rigid : int
        Number of rigid-body (zero-frequency) modes removed.
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    mesh_energy: np.ndarray
    rigid: int


def modes(model: DynamicModel, *, which: str = "mean") -> Modes:
    """Solve K phi = omega^2 M phi for the mean (or maximum) mesh stiffness.

    The generalized symmetric eigenproblem of an undamped linear system with the
    diagonal M is solved in its standard form: with D = M^(-1/2), the eigenpairs
    (omega^2, psi) of the symmetric D K D (:func:`numpy.linalg.eigh`) give the
    mass-normalised shapes phi = D psi (phi^T M phi = I), the same as
    ``scipy.linalg.eigh(K, M)`` to rounding (``scipy.linalg`` is not imported for it:
    0.2 s of start-up). Modes with omega <= 1e-6 of the largest are the rigid-body
    rotation of the chain and are removed. K is :func:`mean_stiffness_matrix`.

    Parameters
    ----------
    model : DynamicModel
        Equations of motion; M = diag(``model.mass``).
    which : {"mean", "max"}
        Mesh stiffness of each mesh: its mean over the table period, or (any other
        value) its largest tabulated value.

    Returns
    -------
    Modes
        Natural frequencies [Hz], mass-normalised shapes and mesh strain-energy fractions.

    Examples
    --------
    The two-disc pair of the module docstring: 318.31 Hz with the mean stiffness,
    348.69 Hz with the largest, one rigid-body mode, the whole strain energy in the mesh.
    """
    K = mean_stiffness_matrix(model, which=which)
    d = 1.0 / np.sqrt(model.mass)
    w2, psi = np.linalg.eigh(d[:, None] * K * d[None, :])
    phi = d[:, None] * psi
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
    maximum tabulated mesh stiffness of every mesh (mass-normalised, undamped). The
    classical RK4 stability region reaches |h omega| = 2 sqrt(2) on the imaginary axis
    (Hairer & Wanner 1996, sec. IV.2); :data:`RK4_LIMIT` = 2.78 keeps a small margin.

    Parameters
    ----------
    model : DynamicModel
        Equations of motion.

    Returns
    -------
    float
        Largest stable step [s].

    References
    ----------
    Hairer & Wanner (1996), module docstring.

    Examples
    --------
    The two-disc pair of the module docstring: 1.2689 ms.
    """
    wmax = 2 * np.pi * float(modes(model, which="max").frequencies.max())
    return RK4_LIMIT / wmax


def decay_time(model: DynamicModel) -> float:
    """1 / (slowest decay rate) of the damped mean linear system [s].

    From the eigenvalues lambda of the first-order (state-space) system
    [[0, I], [-M^-1 K, -M^-1 C]] with K = :func:`mean_stiffness_matrix` and
    C = C_b + sum c_m,i kappa_i V_i V_i^T: the decay rate of a mode is -Re(lambda).
    Eigenvalues with |lambda| <= 1e-6 of the largest (rigid-body mode) are skipped.
    :func:`gearsim.dynamics.simulate` drops 12 such time constants as the transient.

    Parameters
    ----------
    model : DynamicModel
        Equations of motion (mean mesh stiffness, mesh and bearing damping).

    Returns
    -------
    float
        Time constant of the slowest-decaying mode [s].

    Examples
    --------
    The two-disc pair of the module docstring: 0.1 s.
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
