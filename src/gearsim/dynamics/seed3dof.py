"""The seed's translational model (Shi, Li & Zhou 2025, eqs. 1-2) with the load path added.

As printed (three gears, y_j the displacement of gear j along the line of action):

    F_y1 = cos(a) cos(b) [k_m1 (y2 - y1 - e1) + c_m1 (y2' - y1' - e1')]
    F_y2 = cos(a) cos(b) [k_m2 (y2 - y3 - e2) + c_m2 (y2' - y3' - e2')]
    m1 y1'' + c1 y1' + k1 y1 = F_y1
    m3 y3'' + c3 y3' + k3 y3 = F_y2
    m2 y2'' + c2 y2' + k2 y2 = -F_y1 - F_y2

(the printed eq. 1 puts the damping term inside the stiffness bracket; we read it as
the sum above).

What the printed equations lack
-------------------------------
No term carries the transmitted torque: there are no rotations and no external force,
so the only static equilibrium is y = 0 with zero mesh force. With e = 0 the response
stays identically zero; with an STE the mesh forces only oscillate about zero (their
mean is zero up to small correlation terms), whereas the real mesh carries the static
load W_i = T_i / r_b,i (transverse) at all times.

What we add
-----------
In a model with rotations the relative rotation of the gears supplies the mean mesh
deflection that carries the load, and the bearings carry the static mesh force. We
represent that missing rotation by a constant static-transmission-error offset: the
printed equations are integrated in total coordinates with e_i replaced by
``e_i - delta_off,i``, where

    delta_off,i = W_n,i / k_n,mean,i - V_i . y_s + (constant part of e_i),
    K_b y_s = -sum_i V_i kappa W_n,i      (bearings carrying the static mesh forces),

W_n,i = T_i / (r_b,i cos beta_b) the normal static load, kappa = cos(alpha_n) cos(beta)
the seed's projection, k_n = k / cos^2(beta_b) the normal mesh stiffness (from the
transverse table) and V_i the seed's deflection vector (``y2 - y1``, ``y2 - y3``;
for a longer chain ``delta_i = (-1)^i (y_{i+1} - y_i)``). Then the mean-stiffness static
state has exactly F_y,i = kappa W_n,i, the bearings carry it, and the dynamic response
(parametric excitation by k_m(t), STE harmonics) is that of the printed equations. The
time-averaged force of the time-varying system equals the static force up to the
correlation of k_m(t) with the vibration (checked < 0.5 % in the tests).

Reported mesh force: the transverse line-of-action force F_y / kappa * cos(beta_b) =
F_n cos(beta_b) (mean T_i / r_b,i), the same quantity as the LTA model reports.
Masses: m_j = ``Gear.mass``. Mesh damping c_m = 2 zeta_m sqrt(k_n,mean m_eq),
m_eq = m_i m_i+1 / (m_i + m_i+1). No backlash (the printed force is linear).

References
----------
.. [Seed] X. Shi, Y. Li, J. Zhou, Actuators 14 (2025) 292, eqs. 1-2.
"""

from __future__ import annotations

import math

import numpy as np

from gearsim.dynamics.layout import layout
from gearsim.dynamics.lta import ste_harmonics
from gearsim.dynamics.model import DynamicModel, static_equilibrium
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.tables import MeshTable, mesh_tables
from gearsim.system import GearTrain

__all__ = ["build_seed"]


def build_seed(train: GearTrain, settings: DynamicsSettings | None = None, *,
               tables: tuple[MeshTable, ...] | None = None) -> DynamicModel:
    """Assemble the seed's 3-DOF (one DOF per gear) equations with the static load.

    Parameters
    ----------
    train
        Gear chain (any length; three gears reproduce the seed).
    settings
        Dynamics options (bearing stiffness/damping, mesh damping ratio, STE).
    tables
        Precomputed stiffness tables (default: :func:`mesh_tables`).

    Returns
    -------
    DynamicModel
        Coordinates y_j [m]; mesh force f_i = F_y,i [N].
    """

    settings = settings or DynamicsSettings()
    tables = tables or mesh_tables(train)
    gears, pairs = train.gears, train.pairs
    ng, nm = len(gears), len(pairs)
    mass = np.array([g.mass for g in gears])
    kb = np.full(ng, settings.bearing_stiffness)
    if settings.bearing_damping is not None:
        cb = np.full(ng, settings.bearing_damping)
    else:
        cb = 2 * settings.bearing_damping_ratio * np.sqrt(kb * mass)
    V = np.zeros((nm, ng))
    for i in range(nm):
        s = (-1.0) ** i
        V[i, i] = -s
        V[i, i + 1] = s
    beta_b = np.array([p.driver.base_helix_angle for p in pairs])
    kappa = np.array([math.cos(p.driver.normal_pressure_angle) * math.cos(p.driver.helix_angle)
                      for p in pairs])
    kscale = 1.0 / np.cos(beta_b) ** 2
    kn_mean = np.array([t.mean for t in tables]) * kscale
    static = np.array([train.static_mesh_force(i) for i in range(nm)])
    wn = static / np.cos(beta_b)
    ys = np.linalg.solve(np.diag(kb), -(V.T @ (kappa * wn)))
    signs = np.array([[V[i, i], V[i, i + 1]] for i in range(nm)])
    e_const, amp, om, ph = ste_harmonics(train, settings, np.zeros(nm), np.zeros(nm),
                                         np.ones(ng), signs)
    # mesh phase of a straight chain in the seed model: the LTA layout phases

    lay = layout(train, settings.per_item("idler_angle", ng - 2, "idler"))
    amp_pm_phase = 2 * math.pi * lay.phase + 0.5 * math.pi
    ph[:, 0] = amp_pm_phase
    offset = wn / kn_mean - V @ ys + e_const
    e0 = e_const - offset
    meq = np.array([p.driver.mass * p.driven.mass / (p.driver.mass + p.driven.mass)
                    for p in pairs])
    cm = 2 * settings.mesh_damping_ratio * np.sqrt(kn_mean * meq)
    q_static = static_equilibrium(mass, kb, V, kappa * kn_mean, np.zeros(ng), e0)
    # a speed profile: the tables are read at f_i tau(t); the coordinates are
    # translations, which the nominal rotation does not load (no inertial term); a load
    # profile is refused by DynamicsSettings (the load is the offset e0)
    profile, _ = settings.profiles(train.operating.speed)
    return DynamicModel(
        kind="seed", gear_names=tuple(g.name for g in gears),
        dof_labels=tuple(f"{g.name}.y" for g in gears), mass=mass, kb=kb, cb=cb,
        fext=np.zeros(ng), V=V, kappa=kappa, kscale=kscale, cm=cm,
        clearance=np.full(nm, np.inf), tables=tables, phase=lay.phase.copy(),
        mesh_frequency=train.mesh_frequency, e0=e0, h_amp=amp, h_omega=om, h_phase=ph,
        to_transverse=np.cos(beta_b) / kappa, dte_offset=offset, static_force=static,
        bearing_dofs=np.arange(ng, dtype=np.int64)[:, None], axes=("y",), q_static=q_static,
        profile=profile,
        info={"equivalent_mass": meq, "mesh_damping_ratio": settings.mesh_damping_ratio,
              "static_offset": offset, "kappa": kappa},
    )
