"""Lateral-torsional-axial (LTA) model of a chain of helical gears.

Coordinates of gear j (4 per gear): x_j, y_j (transverse translation of the centre,
global axes of the layout), z_j (axial), theta_j (rotation, positive in the gear's own
sense of rotation, measured from the nominal rigid rotation Omega_j t) [m, rad].

Mesh i (gear i drives gear i+1) acts along the transverse line of action n_i (see
:mod:`gearsim.dynamics.layout`). Its deflection in transverse-equivalent units is

    delta_i = V_i . q = n_i.(u_i - u_{i+1}) + tan(beta_b) (z_i - z_{i+1})
              + r_b,i theta_i - r_b,i+1 theta_{i+1}                          [m]

(``u = (x, y)``): the normal deflection along the normal line of action divided by
cos(beta_b). The transverse force is f_i = k_i(t) g(delta_i - e_i) + c_m (delta_i' -
e_i') with the tabulated *transverse* stiffness k_i (normal-plane stiffness k_i /
cos^2 beta_b gives the same force, ``F_n = F_t / cos beta_b``), and the mesh acts on
the coordinates with -V_i f_i: the driven gear receives f_i n_i in the plane, the axial
thrust f_i tan(beta_b) and the torque f_i r_b,i+1; the driver the opposite force and
the resisting torque -f_i r_b,i. The sign of the axial coordinate is a convention (the
same for every mesh of a chain of external gears because hands and senses of rotation
alternate together); bearings are symmetric, so it does not change any result.

External loads: the input torque T_1 on gear 0 and, on the driven gear of each output
shaft k, the load torque sigma_k T_1 r_b,k / r_b,1 times r_b,b / r_b,a of each compound
shaft on its path (sigma_k its share of the power, 1 for a single output; eq. (2) of
:mod:`gearsim.system.graph`), scaled by the load profile. Bearings: stiffness and
viscous damping on x, y (radial) and z (axial) of every gear; no torsional support.

Rigid-body rotation: every V_i is orthogonal to the rigid rotation of the chain
(theta_j = c / r_b,j) and the external torques balance, so that mode is neither forced
nor damped. We keep the absolute coordinates and start at the static equilibrium of the
mean system with zero rigid-body velocity, so the mode stays at rest (round-off drift
~1e-12 rad over a second); no torsional spring to ground is added, which would carry
part of the load and bias the mean mesh force. The modal analysis reports the zero
frequency and skips it.

Masses: m_j = ``Gear.mass``, J_j = ``Gear.polar_inertia`` (disc between bore and pitch
radius). Mesh damping: c_m = 2 zeta_m sqrt(k_mean m_eq), m_eq = 1 / (r_b,i^2 / J_i +
r_b,i+1^2 / J_i+1) (Kahraman & Singh 1990, torsional equivalent mass).

References
----------
.. [Kahraman1994] A. Kahraman, Dynamic analysis of a multi-mesh helical gear train,
   J. Mech. Des. 116 (1994) 706-712.
.. [KahramanSingh1990] A. Kahraman, R. Singh, Non-linear dynamics of a spur gear pair,
   J. Sound Vib. 142 (1990) 49-75 (backlash function, equivalent mass, damping ratio).
.. [Velex1996] P. Velex, M. Maatar, A mathematical model for analyzing the influence of
   shape deviations and mounting errors on gear dynamic behaviour, J. Sound Vib. 191
   (1996) 629-660 (projection vector of a helical mesh).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from gearsim.dynamics.layout import idlers, layout
from gearsim.dynamics.model import DynamicModel, nominal_inertia, static_equilibrium
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.tables import MeshTable, centre_distance_derivative, mesh_tables
from gearsim.system import GearTrain

__all__ = ["agma_backlash", "build_lta", "centre_distance_harmonics", "ste_harmonics"]

AXES = ("x", "y", "z")


def agma_backlash(train: GearTrain, mesh: int) -> float:
    """Default clearance 2b of a mesh along the transverse line of action [m].

    AGMA 2002-B88 minimum normal backlash, j_bn = (2/3)(0.06 + 0.0005 a + 0.03 m_n) mm
    (a, m_n in mm), divided by cos(beta_b) to express it along the transverse line of
    action.

    Parameters
    ----------
    train : GearTrain
        The gear chain.
    mesh : int
        Mesh index (0 = mesh I); a = its centre distance, m_n and beta_b of its driver.

    Returns
    -------
    float
        Clearance 2b = j_bn / cos(beta_b) [m].

    References
    ----------
    AGMA 2002-B88, Tooth thickness specification and measurement (minimum backlash).

    Examples
    --------
    Table-1 train (m_n 6 mm, beta_b 12.2035 deg): mesh I, a = 301.733 mm, gives
    (2/3)(0.06 + 0.15087 + 0.18) / cos(beta_b) = 0.2666 mm; mesh II, a = 566.520 mm,
    0.3569 mm:

    >>> import gearsim as gs
    >>> from gearsim.dynamics.lta import agma_backlash
    >>> tr = gs.example("idler-table1").train
    >>> [round(agma_backlash(tr, i) * 1e3, 4) for i in range(2)]  # mm
    [0.2666, 0.3569]
    """
    pair = train.pairs[mesh]
    a_mm = pair.centre_distance * 1e3
    mn_mm = pair.driver.normal_module * 1e3
    jbn = (2.0 / 3.0) * (0.06 + 0.0005 * a_mm + 0.03 * mn_mm) * 1e-3
    return jbn / math.cos(pair.driver.base_helix_angle)


def backlash_values(train: GearTrain, settings: DynamicsSettings) -> np.ndarray:
    """Clearance 2b of every mesh [m]; ``inf`` when the mesh is linear."""
    nm = len(train.pairs)
    if not settings.nonlinear:
        return np.full(nm, np.inf)
    if settings.backlash is None:
        return np.array([agma_backlash(train, i) for i in range(nm)])
    return np.array(settings.per_item("backlash", nm, "mesh"), dtype=float)


def ste_harmonics(train: GearTrain, settings: DynamicsSettings, phase: np.ndarray,
                  normal_angle: np.ndarray, senses: np.ndarray, signs: np.ndarray):
    """Constant part and harmonics of the static transmission error of every mesh.

    e_i(t) = crowning_i / 3 + assembly_i + A_pm,i cos(2 pi (f_m t + phase_i))
             + sum over the two gears j of mesh i of eps_j sin(w_j t + p_ij)

    * profile modification (tip relief): first mesh harmonic of the unloaded STE,
      amplitude A_pm (Oezgueven & Houser 1988 represent the STE by its mesh harmonics);
    * crowning: mean gap of a parabolic lead crown of height C_beta over the face
      width, C_beta / 3 (its load-dependent effect on the stiffness is not modelled);
    * runout: the eccentricity eps_j of gear j, turning with the gear (global angle
      s_j Omega_j t + psi_j), projected on the line of action: a centre offset d changes
      the deflection by sign_ij n_i.d, i.e. e = -sign_ij eps_j cos(s_j Omega_j t + psi_j
      - angle(n_i)), where sign_ij is V_i's sign for gear j (+1 driver, -1 driven);
    * assembly error: a constant per mesh.

    Parameters
    ----------
    train : GearTrain
        The gear chain; gives f_m and the gear speeds Omega_j [rad/s].
    settings : DynamicsSettings
        ``profile_modification``, ``crowning`` and ``assembly_error`` (per mesh) [m],
        ``runout`` [m] and ``runout_phase`` [rad] (per gear), one value or one per item.
    phase : ndarray, shape (n_mesh,)
        Mesh phase phase_i of each mesh (:attr:`Layout.phase`) [mesh cycles].
    normal_angle : ndarray, shape (n_mesh,)
        Global angle of the line-of-action vector n_i [rad].
    senses : ndarray, shape (n_gears,)
        Sense of rotation s_j of each gear (+1 counter-clockwise) [-].
    signs : ndarray, shape (n_mesh, 2)
        sign_ij of V_i for the driver (column 0) and the driven gear (column 1) [-].

    Returns
    -------
    e0 : ndarray, shape (n_mesh,)
        Constant part crowning / 3 + assembly error [m].
    amplitude, omega, phase : ndarray, shape (n_mesh, 3)
        Harmonics ``amplitude sin(omega t + phase)`` [m, rad/s, rad]; column 0: profile
        modification (omega = 2 pi f_m, phase = 2 pi phase_i + pi/2), columns 1 and 2:
        runout of the driver and of the driven gear (omega = s_j Omega_j).

    Raises
    ------
    InputError
        If a per-mesh or per-gear option has neither one value nor one per item.

    References
    ----------
    Oezgueven & Houser (1988), J. Sound Vib. 121, 383-411 (STE by its mesh harmonics);
    Velex & Maatar (1996) (eccentricities projected on the line of action).

    Examples
    --------
    Table-1 train, 2 um tip-relief harmonic and 3 um crowning: e0 = 3 / 3 = 1 um, the
    mesh harmonic turns at 2 pi f_m = 2 pi 39 (1900 / 60) Hz = 7759.7 rad/s:

    >>> import numpy as np
    >>> import gearsim as gs
    >>> from gearsim.dynamics.lta import ste_harmonics
    >>> from gearsim.dynamics.settings import DynamicsSettings
    >>> tr = gs.example("idler-table1").train
    >>> st = DynamicsSettings(profile_modification=2e-6, crowning=3e-6)
    >>> e0, amp, om, ph = ste_harmonics(tr, st, np.zeros(2), np.zeros(2),
    ...                                 np.array([1.0, -1.0, 1.0]), np.tile([1.0, -1.0], (2, 1)))
    >>> e0.tolist(), amp[:, 0].tolist(), round(float(om[0, 0]), 1)
    ([1e-06, 1e-06], [2e-06, 2e-06], 7759.7)
    """
    ng, nm = len(train.gears), len(train.pairs)
    pm = settings.per_item("profile_modification", nm, "mesh")
    crown = settings.per_item("crowning", nm, "mesh")
    asm = settings.per_item("assembly_error", nm, "mesh")
    ro = settings.per_item("runout", ng, "gear")
    rph = settings.per_item("runout_phase", ng, "gear")
    fm = train.mesh_frequency
    e0 = np.array([crown[i] / 3.0 + asm[i] for i in range(nm)])
    amp = np.zeros((nm, 3))
    om = np.zeros((nm, 3))
    ph = np.zeros((nm, 3))
    for i in range(nm):
        amp[i, 0] = pm[i]
        om[i, 0] = 2 * math.pi * fm
        ph[i, 0] = 2 * math.pi * phase[i] + 0.5 * math.pi
        for col, j in ((1, _gi(train, i, 0)), (2, _gi(train, i, 1))):
            sgn = signs[i, col - 1]
            amp[i, col] = ro[j]
            om[i, col] = senses[j] * train.speed(j)
            # -sgn cos(x) = sin(x - sgn pi/2)
            ph[i, col] = rph[j] - normal_angle[i] - sgn * 0.5 * math.pi
    return e0, amp, om, ph


def centre_distance_harmonics(train: GearTrain, settings: DynamicsSettings,
                              centres: np.ndarray, senses: np.ndarray, signs: np.ndarray):
    """Centre-distance change of every mesh by the gears' eccentricities, as harmonics.

    The geometric centre of gear j sits eps_j from its bearing centre, turning with the
    gear (global angle s_j Omega_j t + psi_j). Its component along the centre line of
    mesh i (unit vector c_i from the driver's to the driven gear's centre) changes the
    operating centre distance: Delta a_i(t) = sum_j -sign_ij eps_j cos(s_j Omega_j t +
    psi_j - angle(c_i)) (driver: moving towards the driven gear shortens it), written as
    ``amplitude sin(omega t + phase)``. With :attr:`MeshTable.dk_da` the mesh stiffness
    becomes k(c) + Delta a_i(t) dk/da(c): the contact ratio follows the centre distance,
    the amplitude modulation of the mesh tone by an eccentric gear (the component along
    the line of action is the transmission error of :func:`ste_harmonics`).

    Parameters
    ----------
    train : GearTrain
        The gear chain; gear speeds Omega_j [rad/s].
    settings : DynamicsSettings
        ``runout`` [m] and ``runout_phase`` [rad] per gear.
    centres : ndarray, shape (n_gears, 2)
        Gear centres (their shafts' in the layout) [m].
    senses : ndarray, shape (n_gears,)
        Sense of rotation of each gear [-].
    signs : ndarray, shape (n_mesh, 2)
        sign_ij of V_i for the driver and the driven gear [-].

    Returns
    -------
    amplitude, omega, phase : ndarray, shape (n_mesh, 2)
        One harmonic per gear of the mesh [m, rad/s, rad].

    References
    ----------
    Velex & Maatar (1996) (eccentricities as displacements of the gear centres); the
    path of contact at an operating centre distance: ISO 21771:2007.
    """
    ng, nm = len(train.gears), len(train.pairs)
    ro = settings.per_item("runout", ng, "gear")
    rph = settings.per_item("runout_phase", ng, "gear")
    amp = np.zeros((nm, 2))
    om = np.zeros((nm, 2))
    ph = np.zeros((nm, 2))
    for i in range(nm):
        j1, j2 = _gi(train, i, 0), _gi(train, i, 1)
        d = centres[j2] - centres[j1]
        ang = math.atan2(d[1], d[0])
        for col, j in ((0, j1), (1, j2)):
            amp[i, col] = ro[j]
            om[i, col] = senses[j] * train.speed(j)
            ph[i, col] = rph[j] - ang - signs[i, col] * 0.5 * math.pi
    return amp, om, ph


def _gi(train: GearTrain, mesh: int, which: int) -> int:
    """Index of the driver (``which`` 0) or driven gear (1) of ``mesh`` in ``train.gears``."""
    return train.gear_index(train.flow.meshes[mesh][which])


def dof_map(train: GearTrain, model: str) -> tuple[list[str], dict, np.ndarray]:
    """Coordinates of a gearbox: labels, rotation coordinate of each gear, bearings.

    Each shaft has the translations x, y, z of its centre (``model = "lta"``) and one
    rotation for a rigid shaft, or one per gear when it has a torsional stiffness.

    Parameters
    ----------
    train : GearTrain
        The gearbox.
    model : {"lta", "torsional"}
        Fidelity level.

    Returns
    -------
    labels : list of str
        ``"<shaft>.x"`` ... ``"<shaft>.theta"`` or ``"<gear>.theta"``.
    theta : dict
        Gear name -> index of its rotation coordinate.
    bearing_dofs : ndarray of int, shape (n_shafts, 3 or 0)
        Translations of each shaft.
    """
    labels: list[str] = []
    theta: dict[str, int] = {}
    bearings = []
    for sh in train.flow.shafts:
        if model == "lta":
            bearings.append([len(labels) + a for a in range(3)])
            labels += [f"{sh.name}.{a}" for a in AXES]
        if sh.torsional_stiffness is None or len(sh.gears) == 1:
            theta.update({g: len(labels) for g in sh.gears})
            labels.append(f"{sh.name}.theta")
        else:
            for g in sh.gears:
                theta[g] = len(labels)
                labels.append(f"{g}.theta")
    return labels, theta, np.array(bearings, dtype=np.int64).reshape(len(train.flow.shafts), -1)


def _segment_torque(train: GearTrain, gear: str) -> float:
    """Static torque of the shaft segment after ``gear`` (towards the next gear on its
    shaft) [N m]: T_in omega_in / omega_shaft times the magnitude of the power shares
    entering at the gears up to ``gear`` (the input, the meshes driving them) less those
    leaving (the meshes they drive); eq. (2) of :mod:`gearsim.system.graph`."""
    fl = train.flow
    sh = fl.shafts[fl.shaft_of[gear]]
    net = []
    for g in sh.gears[:sh.gears.index(gear) + 1]:
        net += [1.0] if g == train.gears[0].name else []
        net += [w if b == g else -w for (a, b), w in zip(fl.meshes, fl.mesh_share, strict=True)
                if g in (a, b)]
    r = fl.ratio[fl.shaft_of[gear]]
    return train.operating.torque * abs(math.fsum(net)) * r.denominator / r.numerator


def build_lta(train: GearTrain, settings: DynamicsSettings | None = None, *,
              tables: tuple[MeshTable, ...] | None = None) -> DynamicModel:
    """Assemble the equations of motion of a gearbox from its shafts, gears and meshes.

    With a speed profile the mesh-cycle coordinates follow the input shaft's nominal
    angle (:meth:`DynamicModel.nominal`) and each rotation carries the inertia load of
    the nominal rotation, -J_j Omega_j tau'', the input the whole train's (so the rigid
    rotation is not forced); a load profile scales the input and load torques.
    ``settings.model = "lta"``: lateral-torsional-axial (module docstring);
    ``"torsional"``: the rotations only (the mesh rows keep their base-radius entries,
    the bearings and the lateral coupling go). Each element adds its rows: a shaft its
    mass, inertia and bearings (diagonal), a shaft with a torsional stiffness k_t one
    spring row per pair of consecutive gears, theta_a - theta_b, with a constant table
    and damping 2 zeta_b sqrt(k_t J_eq) (``bearing_damping_ratio``), a mesh its
    projection vector V_i. The axial entry of a mesh is sigma tan(beta_b)(z_drv - z_dvn)
    with sigma = h s the driver's hand (sign of its helix angle) times its sense: the
    thrusts of a mesh are opposite on its two gears, in the direction set by the
    driver's hand and rotation (+1 on every mesh of a chain of external gears).

    Parameters
    ----------
    train
        Gearbox with operating point and cracks.
    settings
        Dynamics options (fidelity, bearings, damping, backlash, layout, STE).
    tables
        Precomputed stiffness tables (default: :func:`mesh_tables`).

    Returns
    -------
    DynamicModel
        Coordinates of :func:`dof_map` [m, rad]; forces [N], torques [N m]; rows: the
        meshes, then the shaft springs (``info["shaft_rows"]``).
    """
    settings = settings or DynamicsSettings()
    tables = tables or mesh_tables(train)
    gears, pairs, fl = train.gears, train.pairs, train.flow
    lateral = settings.model == "lta"
    labels, theta, bearing_dofs = dof_map(train, settings.model)
    n, nm = len(labels), len(pairs)
    n_id = len(idlers(train))
    lay = layout(train, settings.per_item("idler_angle", n_id, "idler"))
    mass = np.zeros(n)
    kb = np.zeros(n)
    cb = np.zeros(n)
    springs = []  # (gear a, gear b, k_t, shaft)
    for s_i, sh in enumerate(fl.shafts):
        gs_ = [train.gear(g) for g in sh.gears]
        rot = sorted({theta[g] for g in sh.gears})
        for g in gs_:
            mass[theta[g.name]] += g.polar_inertia
        mass[rot] += sh.inertia / len(rot)
        springs += [(a, b, sh.torsional_stiffness, sh) for a, b in
                    zip(sh.gears, sh.gears[1:], strict=False) if theta[a] != theta[b]]
        if not lateral:
            continue
        m = sh.mass + sum(g.mass for g in gs_)
        kr = sh.bearing_stiffness or settings.bearing_stiffness
        ka = sh.axial_stiffness or settings.bearing_axial_stiffness or kr
        for a, k in zip(bearing_dofs[s_i], (kr, kr, ka), strict=True):
            mass[a], kb[a] = m, k
            cb[a] = (settings.bearing_damping if settings.bearing_damping is not None
                     else 2 * settings.bearing_damping_ratio * math.sqrt(k * m))
    rows = nm + len(springs)
    V = np.zeros((rows, n))
    for i, pair in enumerate(pairs):
        drv, dvn = pair.driver, pair.driven
        V[i, theta[drv.name]] = drv.base_radius
        V[i, theta[dvn.name]] = -dvn.base_radius
        if lateral:
            a, b = bearing_dofs[fl.shaft_of[drv.name]], bearing_dofs[fl.shaft_of[dvn.name]]
            sigma = math.copysign(1.0, drv.helix_angle) * lay.senses[fl.shaft_of[drv.name]]
            tb = sigma * math.tan(drv.base_helix_angle)
            V[i, a] = (*lay.normal[i], tb)
            V[i, b] = (*(-lay.normal[i]), -tb)
    for r, (a, b, _, _) in enumerate(springs, start=nm):
        V[r, theta[a]], V[r, theta[b]] = 1.0, -1.0
    fext = np.zeros(n)
    t_in = train.operating.torque
    fext[theta[gears[0].name]] = t_in
    for k in fl.outputs:
        # T_out = sigma T_in r_b,out / r_b,in times r_b,b / r_b,a of each compound shaft on
        # the path to the output (gear b receives, gear a passes on; an idler passes the
        # force unchanged)
        path = fl.path_to(k)
        last = fl.meshes[path[-1]][1]
        t_out = t_in * fl.share[k] * train.gear(last).base_radius / train.gear(
            fl.meshes[path[0]][0]).base_radius
        for (_, b), (a, _) in zip((fl.meshes[i] for i in path),
                                  (fl.meshes[i] for i in path[1:]), strict=False):
            if a != b:
                t_out *= train.gear(b).base_radius / train.gear(a).base_radius
        fext[theta[last]] = -t_out
    kmean = np.array([t.mean for t in tables])
    meq = np.array([1.0 / (p.driver.base_radius ** 2 / p.driver.polar_inertia
                           + p.driven.base_radius ** 2 / p.driven.polar_inertia) for p in pairs])
    cm = 2 * settings.mesh_damping_ratio * np.sqrt(kmean * meq)
    kt = np.array([k for _, _, k, _ in springs])
    jeq = np.array([1.0 / (1.0 / mass[theta[a]] + 1.0 / mass[theta[b]]) for a, b, _, _ in springs])
    ct = 2 * settings.bearing_damping_ratio * np.sqrt(kt * jeq)
    g_sense = np.array([lay.senses[fl.shaft_of[g.name]] for g in gears])
    g_centre = np.array([lay.centres[fl.shaft_of[g.name]] for g in gears])
    signs = np.tile([1.0, -1.0], (nm, 1))
    e0, amp, om, ph = ste_harmonics(train, settings, lay.phase,
                                    np.arctan2(lay.normal[:, 1], lay.normal[:, 0]),
                                    g_sense, signs)
    a_amp, a_om, a_ph = centre_distance_harmonics(train, settings, g_centre, g_sense, signs)
    if np.any(a_amp != 0):
        tables = tuple(
            dataclasses.replace(t, dk_da=centre_distance_derivative(
                train, i, t, float(np.sum(a_amp[i])))) if np.any(a_amp[i] != 0) else t
            for i, t in enumerate(tables))
        a_amp, a_om, a_ph = (np.vstack([x, np.zeros((len(springs), 2))])
                             for x in (a_amp, a_om, a_ph))
    else:
        a_amp = a_om = a_ph = None
    pad = np.zeros(len(springs))
    e0 = np.concatenate([e0, pad])
    amp, om, ph = (np.vstack([x, np.zeros((len(springs), x.shape[1]))]) for x in (amp, om, ph))
    tables = tuple(tables) + tuple(MeshTable(k=np.array([k]), positions_per_cycle=1, period=1)
                                   for k in kt)
    q_static = static_equilibrium(mass, kb, V, np.concatenate([kmean, kt]), fext, e0)
    f_m = train.mesh_frequency
    profile, load = settings.profiles(train.operating.speed)
    omega = np.zeros(n)  # the nominal motion: the rotations at their speeds
    for g in gears:
        omega[theta[g.name]] = train.speed(train.gear_index(g.name))
    inertial = None if profile is None else nominal_inertia(mass, omega, theta[gears[0].name])
    rate = np.concatenate([np.array(train.mesh_frequencies) / f_m, pad + 1.0])
    return DynamicModel(
        kind=settings.model, gear_names=tuple(sh.name for sh in fl.shafts),
        dof_labels=tuple(labels), mass=mass, kb=kb, cb=cb, fext=fext, V=V,
        kappa=np.ones(rows), kscale=np.ones(rows), cm=np.concatenate([cm, ct]),
        clearance=np.concatenate([backlash_values(train, settings), pad + np.inf]),
        tables=tables, phase=np.concatenate([lay.phase, pad]), mesh_frequency=f_m, e0=e0,
        h_amp=amp, h_omega=om, h_phase=ph, a_amp=a_amp, a_omega=a_om, a_phase=a_ph,
        to_transverse=np.ones(rows), dte_offset=np.zeros(rows),
        static_force=np.concatenate([[train.static_mesh_force(i) for i in range(nm)],
                                     [_segment_torque(train, a) for a, *_ in springs]]),
        bearing_dofs=bearing_dofs, axes=AXES if lateral else (), q_static=q_static,
        rate=None if np.all(rate == 1.0) else rate, profile=profile, load=load,
        inertial=inertial,
        info={"equivalent_mass": meq, "mesh_damping_ratio": settings.mesh_damping_ratio,
              "nominal_velocity": omega,
              "centres": lay.centres, "line_of_action": lay.normal,
              "rotation_sense": lay.senses, "shaft_rows": tuple(range(nm, rows)),
              "shaft_springs": tuple(f"{sh.name}:{a}-{b}" for a, b, _, sh in springs)},
    )
