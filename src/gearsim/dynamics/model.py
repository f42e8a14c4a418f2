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

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from gearsim.dynamics.tables import MeshTable
from gearsim.errors import InputError

__all__ = ["DynamicModel", "constrain", "mean_stiffness_matrix"]


@dataclass(frozen=True)
class DynamicModel:
    """Arrays of the equations of motion (SI units; n coordinates, n_mesh meshes).

    Built by :func:`gearsim.dynamics.lta.build_lta` or
    :func:`gearsim.dynamics.seed3dof.build_seed`; the equations are in the module
    docstring.

    Parameters
    ----------
    kind : str
        ``"lta"`` or ``"seed"``.
    gear_names : tuple of str
        Names of the gears in power-flow order.
    dof_labels : tuple of str
        Label of each coordinate, e.g. ``"input.x"``, ``"idler.theta"``.
    mass : ndarray, shape (n,)
        Diagonal of M [kg for translations, kg m^2 for rotations].
    kb, cb : ndarray, shape (n,)
        Bearing stiffness [N/m] and damping [N s/m] on each coordinate (0 on rotations).
    fext : ndarray, shape (n,)
        Constant external generalized forces [N, or N m for rotations].
    V : ndarray, shape (n_mesh, n)
        Projection vectors: mesh deflection = V_i . q [m] (entries [-] on translations,
        base radii [m] on rotations).
    kappa : ndarray, shape (n_mesh,)
        Force projection factor (seed: cos(alpha_n) cos(beta); LTA: 1) [-].
    kscale : ndarray, shape (n_mesh,)
        Factor s_i on the tabulated transverse stiffness (seed: 1/cos^2 beta_b; LTA: 1)
        [-].
    cm : ndarray, shape (n_mesh,)
        Mesh damping c_m [N s/m].
    clearance : ndarray, shape (n_mesh,)
        Backlash 2b [m]; ``inf``: linear mesh (no separation).
    tables : tuple of MeshTable
        Stiffness table of each mesh against the mesh-cycle coordinate.
    phase : ndarray, shape (n_mesh,)
        Mesh-cycle offsets phase_i, c_i = f_m t + phase_i [mesh cycles].
    mesh_frequency : float
        Mesh frequency f_m [Hz].
    e0 : ndarray, shape (n_mesh,)
        Constant part of the static transmission error [m].
    h_amp, h_omega, h_phase : ndarray, shape (n_mesh, n_h)
        STE harmonics ``h_amp sin(h_omega t + h_phase)`` [m], [rad/s], [rad].
    to_transverse : ndarray, shape (n_mesh,)
        Factor from f_i to the reported force along the transverse line of action [-].
    dte_offset : ndarray, shape (n_mesh,)
        Added to V_i . q to give the reported dynamic transmission error [m].
    static_force : ndarray, shape (n_mesh,)
        Static load of each row of ``V``: a mesh's transverse force T_i / r_bi [N], a
        shaft spring's torque [N m], 0 on a bearing row.
    bearing_dofs : ndarray of int, shape (n_gears, n_axes)
        Index of the coordinate of each gear's bearing along each axis.
    axes : tuple of str
        Names of the bearing axes (LTA: x, y, z; seed: y).
    q_static : ndarray, shape (n,)
        Static equilibrium of the mean-stiffness system [m, rad]; the initial state.
    info : dict, optional
        Further descriptive data (mesh damping ratio, equivalent masses, ...).
    rate : ndarray, shape (n_mesh,), optional
        Mesh i reads its table at c_i = rate_i f_m tau + phase_i [-]: a system with
        several mesh frequencies (a gearbox graph, a planetary stage and its chain).
        ``None``: 1 for every mesh.
    profile : ndarray, shape (n_seg, 4), optional
        Speed profile as segments (t_k, tau_k, tau'_k, tau''_k) of the nominal time tau(t)
        (:meth:`nominal`); ``None``: constant speed, tau = t.
    load : ndarray, shape (n_l, 2), optional
        Load factor lambda(t) on ``fext`` as (time [s], factor) points, linear between;
        ``None``: 1.
    inertial : ndarray, shape (n,), optional
        Load g on each coordinate per unit tau'' [N or N m per s/s^2 ...]: the inertia of
        the nominal rotation, -J_j Omega_j, with the input taking the whole train's
        inertia torque so that the rigid rotation stays at rest.
    a_amp, a_omega, a_phase : ndarray, shape (n_mesh, n_h), optional
        Harmonics ``a_amp sin(a_omega t + a_phase)`` of the centre-distance change of each
        mesh by eccentric gears [m], [rad/s], [rad]; the stiffness becomes
        k(c) + Delta a(t) dk/da(c) (``MeshTable.dk_da``). ``None``: none.
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
    a_amp: np.ndarray | None = None
    a_omega: np.ndarray | None = None
    a_phase: np.ndarray | None = None
    rate: np.ndarray | None = None
    profile: np.ndarray | None = None
    load: np.ndarray | None = None
    inertial: np.ndarray | None = None

    def nominal(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Nominal time tau, tau', tau'' [s, -, 1/s] and load factor lambda at times ``t``.

        tau(t) = tau_k + tau'_k (t - t_k) + tau''_k (t - t_k)^2 / 2 on segment k of
        ``profile`` (tau' = omega(t) / omega_ref, the speed relative to the operating
        speed); the mesh-cycle coordinate is c_i = f_i tau + phase_i, so it follows the
        driving shaft's angle. lambda: linear in ``load`` (the same as the kernel's
        :func:`gearsim.dynamics._kernels.nominal`, written with numpy).

        Parameters
        ----------
        t : array_like
            Times [s].

        Returns
        -------
        tau, taud, taudd, lam : ndarray
            Same shape as ``t``.
        """
        t = np.asarray(t, dtype=float)
        lam = (np.ones_like(t) if self.load is None
               else np.interp(t, self.load[:, 0], self.load[:, 1]))
        if self.profile is None and t.ndim > 0 and np.isfinite(t).all():
            # the constant-speed segment (0, 0, 1, 0) below, without its arithmetic: with
            # d = t - 0 = t finite, tau = (0 + 1 d) + ((0.5 0) d) d = t + 0 (the last
            # term is +0, and 0 + -0 is +0), tau' = 1 + 0 d = 1, tau'' = 0 + 0 t = +0:
            # the same numbers, bit for bit (a record of a simulated second: 0.7 ms less)
            return t + 0.0, np.ones(t.shape), np.zeros(t.shape), lam
        prof = np.array([[0.0, 0.0, 1.0, 0.0]]) if self.profile is None else self.profile
        k = np.clip(np.searchsorted(prof[:, 0], t, side="right") - 1, 0, None)
        d = t - prof[k, 0]
        tau = prof[k, 1] + prof[k, 2] * d + 0.5 * prof[k, 3] * d * d
        return tau, prof[k, 2] + prof[k, 3] * d, prof[k, 3] + 0.0 * t, lam

    @property
    def mesh_frequencies(self) -> np.ndarray:
        """Mesh frequency of each mesh, rate_i f_m [Hz], shape (n_mesh,)."""
        rate = np.ones(self.V.shape[0]) if self.rate is None else np.asarray(self.rate)
        return self.mesh_frequency * rate

    @property
    def n_dof(self) -> int:
        """Number of coordinates n (size of ``mass``)."""
        return self.mass.size

    @property
    def n_mesh(self) -> int:
        """Number of meshes (rows of ``V``)."""
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
        """Static transmission error e_i(t) = e0_i + sum_h A_ih sin(w_ih t + p_ih) [m].

        Parameters
        ----------
        t : array_like
            Times [s] (a scalar counts as one time).

        Returns
        -------
        ndarray, shape (len(t), n_mesh)
            e_i at each time [m].
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if (not np.any(self.h_amp) and not np.any(np.signbit(self.e0))
                and np.isfinite(t).all() and np.isfinite(self.h_omega).all()
                and np.isfinite(self.h_phase).all()
                and np.abs(t).max(initial=0.0) * np.abs(self.h_omega).max(initial=0.0)
                + np.abs(self.h_phase).max(initial=0.0) < 1e300):
            # no harmonic (the default): each term is 0 sin(finite arg) = +-0, their sum
            # +-0, and e0 + +-0 = e0 for every e0 but -0 (excluded): e0 itself, without
            # the sines of every time, mesh and harmonic (6 ms for a simulated second);
            # one mesh's column contiguous (filled in one pass each: 0.03 ms instead of
            # 0.3 ms for a simulated second of two meshes, row by row)
            out = np.empty((self.e0.size, t.shape[0])).T
            out[:] = self.e0
            return out
        arg = t[:, None, None] * self.h_omega[None] + self.h_phase[None]
        return self.e0[None, :] + np.sum(self.h_amp[None] * np.sin(arg), axis=-1)


def mean_stiffness_matrix(model: DynamicModel, *, which: str = "mean") -> np.ndarray:
    """K_b + sum_i kappa_i s_i k_i V_i V_i^T with the mean (or maximum) mesh stiffness [N/m].

    The stiffness matrix of the linear mean system: each mesh is a spring of stiffness
    kappa_i s_i k_i acting on the deflection V_i . q, so it adds k V_i V_i^T (projection
    vector of a mesh as in Kahraman 1994 and Velex & Maatar 1996; see
    :mod:`gearsim.dynamics.lta`).

    Parameters
    ----------
    model : DynamicModel
        Equations of motion.
    which : {"mean", "max"}
        Mesh stiffness used: the mean over each table's period
        (:meth:`DynamicModel.mean_stiffness`), or (any other value) the largest
        tabulated value (:meth:`DynamicModel.max_stiffness`).

    Returns
    -------
    ndarray, shape (n_dof, n_dof)
        Symmetric stiffness matrix [N/m, N/rad or N m/rad by coordinate pair].

    Examples
    --------
    The two-disc pair of :mod:`gearsim.dynamics.modal` (module docstring): k V V^T with
    V = (0.1, -0.1) gives K = +-1e6 with the mean stiffness 1e8 N/m, 1.2e6 with the
    largest.
    """
    if which not in ("mean", "max"):
        raise InputError("which", which, 'must be "mean" or "max"')
    k = model.mean_stiffness() if which == "mean" else model.max_stiffness()
    K = np.diag(model.kb).astype(float)
    for i in range(model.n_mesh):
        K += k[i] * np.outer(model.V[i], model.V[i])
    return K


def constrain(model: DynamicModel, follow: dict[str, tuple[str, float]],
              kind: str) -> DynamicModel:
    """The model with coordinates tied to others: q = T q_r (a kinematic reduction).

    Each coordinate is kept, follows one kept coordinate with a factor (``follow[label] =
    (kept label, factor)``) or is held at zero (``factor`` 0). With at most one entry per
    row of T the reduced mass T^T M T, bearings T^T K_b T and T^T C_b T stay diagonal;
    V_r = V T, F_r = T^T F and the inertial loads g_r = T^T g (virtual work); rows of V
    that become zero (springs whose
    ends the constraint ties together) are dropped with their tables.

    Parameters
    ----------
    model : DynamicModel
        The full model.
    follow : dict
        Label of a removed coordinate -> (label of the kept coordinate, factor).
    kind : str
        ``kind`` of the reduced model.

    Returns
    -------
    DynamicModel
        Kept coordinates in their order; ``bearing_dofs`` of the members whose
        translations are all kept, ``q_static`` of the reduced mean system.

    Examples
    --------
    Two discs on a shaft spring, the second tied to the first: one disc with the summed
    inertia, the spring row (now zero) dropped.

    >>> import numpy as np
    >>> from gearsim.dynamics.tables import MeshTable
    >>> o, z = np.ones(1), np.zeros(2)
    >>> m = DynamicModel(
    ...     kind="lta", gear_names=("a", "b"), dof_labels=("a.theta", "b.theta"),
    ...     mass=np.array([0.5, 0.25]), kb=z, cb=z, fext=np.array([2.0, -2.0]),
    ...     V=np.array([[1.0, -1.0]]), kappa=o, kscale=o, cm=o, clearance=np.inf * o,
    ...     tables=(MeshTable(k=np.array([1e6]), positions_per_cycle=1, period=1),),
    ...     phase=0 * o, mesh_frequency=1.0, e0=0 * o, h_amp=np.zeros((1, 1)),
    ...     h_omega=np.zeros((1, 1)), h_phase=np.zeros((1, 1)), to_transverse=o,
    ...     dte_offset=0 * o, static_force=0 * o,
    ...     bearing_dofs=np.zeros((2, 0), dtype=np.int64), axes=(), q_static=z)
    >>> r = constrain(m, {"b.theta": ("a.theta", 1.0)}, "torsional")
    >>> r.dof_labels, r.mass.tolist(), r.fext.tolist(), r.n_mesh
    (('a.theta',), [0.75], [0.0], 0)
    """
    labels = model.dof_labels
    kept = [lab for lab in labels if lab not in follow]
    T = np.zeros((len(labels), len(kept)))
    for i, lab in enumerate(labels):
        target, factor = (lab, 1.0) if lab not in follow else follow[lab]
        if factor != 0.0:
            T[i, kept.index(target)] = factor
    mass, kb, cb = (np.einsum("i,ij->j", x, T * T) for x in (model.mass, model.kb, model.cb))
    V = model.V @ T
    rows = [i for i in range(model.n_mesh) if np.any(V[i] != 0.0)]

    def sub(a):
        return None if a is None else np.asarray(a)[rows]

    fext = T.T @ model.fext
    kmean = np.array([model.tables[i].mean for i in rows]) * model.kappa[rows] * \
        model.kscale[rows]
    index = {lab: j for j, lab in enumerate(kept)}
    bd = [[index[labels[k]] for k in b] for b in model.bearing_dofs
          if all(labels[k] in index for k in b)]
    return dataclasses.replace(
        model, kind=kind, dof_labels=tuple(kept), mass=mass, kb=kb, cb=cb, fext=fext,
        V=V[rows], kappa=model.kappa[rows], kscale=model.kscale[rows], cm=model.cm[rows],
        clearance=model.clearance[rows], tables=tuple(model.tables[i] for i in rows),
        phase=model.phase[rows], e0=model.e0[rows], h_amp=model.h_amp[rows],
        h_omega=model.h_omega[rows], h_phase=model.h_phase[rows],
        to_transverse=model.to_transverse[rows], dte_offset=model.dte_offset[rows],
        static_force=model.static_force[rows],
        bearing_dofs=np.array(bd, dtype=np.int64).reshape(len(bd), len(bd[0]) if bd else 0),
        axes=model.axes if bd and len(bd[0]) else (),
        q_static=static_equilibrium(mass, kb, V[rows], kmean, fext, model.e0[rows]),
        a_amp=sub(model.a_amp), a_omega=sub(model.a_omega), a_phase=sub(model.a_phase),
        rate=sub(model.rate), inertial=None if model.inertial is None else T.T @ model.inertial,
        info={**model.info, "rows_kept": tuple(rows),
              **({"nominal_velocity": np.asarray(model.info["nominal_velocity"])[
                  [labels.index(lab) for lab in kept]]}
                 if "nominal_velocity" in model.info else {})})


def nominal_inertia(mass: np.ndarray, velocity: np.ndarray, input_index: int) -> np.ndarray:
    """Load on each coordinate per unit tau'' of a speed profile (``DynamicModel.inertial``).

    The coordinates are deviations from the nominal motion q_nom = w tau(t) (w: the
    velocity of each coordinate at the operating speed, tau' = 1), whose acceleration
    w tau'' each coordinate's inertia resists: g = -M w. The drive supplies the power
    of that acceleration at the input coordinate, w_in g_in = sum_j M_j w_j^2, so the
    nominal motion itself (V w = 0: no spring is deflected by it) takes no net load,
    w . g = 0, and the rigid rotation stays at rest.

    Parameters
    ----------
    mass : ndarray, shape (n,)
        Diagonal mass matrix [kg or kg m^2, per coordinate].
    velocity : ndarray, shape (n,)
        w [m/s or rad/s per unit tau'].
    input_index : int
        The driven coordinate (w != 0).

    Returns
    -------
    ndarray, shape (n,)
        g [N or N m per unit tau'' (1/s)].

    Examples
    --------
    Two discs 1:2 (inertias 1 and 4, speeds 2 and 1): the input supplies 8 per unit
    tau'', each disc resists with its J w; no net power.

    >>> import numpy as np
    >>> g = nominal_inertia(np.array([1.0, 4.0]), np.array([2.0, 1.0]), 0)
    >>> g.tolist(), float(g @ np.array([2.0, 1.0]))
    ([2.0, -4.0], 0.0)
    """
    g = -mass * velocity
    g[input_index] += np.sum(mass * velocity ** 2) / velocity[input_index]
    return g


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
