"""Time simulation of a planetary stage: the Lin & Parker model with phased, time-varying meshes.

Equations of motion (model frame of :mod:`gearsim.system.planetary`; Lin & Parker 1999,
coordinates and spring gradients b_i of :class:`gearsim.dynamics.planetary.LinParkerModel`):

    M q'' + C_b q' + K_b q + sum_i b_i f_i(t, b_i . q, b_i . q') = F

* central members (carrier, ring, sun): bearings k_j in x and y on the diagonal, the held
  member's torsional stiffness k_u on its rotation (``u = r theta``);
* planet bearings (radial and tangential, k_p) and the 2N meshes are springs along b_i;
* a mesh force is f = k_i(t)(delta - 0) + c_m delta' while the flanks touch, zero inside
  the backlash 2b and k_i(t)(delta + 2b) + c_m delta' on the back flanks
  (``nonlinear``), with k_i(t) = k(f_m t + phase_i) the phased table of the mesh
  (:meth:`gearsim.system.planetary.PlanetaryTrain.mesh_table`);
* F: the model-frame torques on the input and output members as forces T / r on their
  ``u`` coordinates (r the base radius; carrier: the planet-centre radius a).

The gyroscopic and centripetal terms of the rotating carrier frame are left out (as in the
paper's free-vibration analysis; they scale with the carrier speed squared over the
natural frequencies squared). The compiled RK4 kernel of the gear trains
(:mod:`gearsim.dynamics._kernels`) integrates the system: its springs are rows of ``V``
with periodic stiffness tables, so the stage reuses it unchanged.

**What a fixed transducer sees** (McFadden & Smith 1985; Inalpolat & Kahraman 2009): the
ring-planet mesh force of each planet reaches a sensor on the ring (housing) through a
path that depends on how far the planet is from it,

    y(t) = sum_n w(phi_n(t)) [f_rn(t) - mean(f_rn)],  phi_n = theta_c(t) + psi_n - theta_s,

with w(phi) = (1 + cos(pi phi / Theta)) / 2 for |phi| < Theta (phi wrapped to
[-pi, pi)) and 0 elsewhere: a Hann window of half width Theta (``sensor_width``) centred on
the sensor angle theta_s. theta_c is the physical carrier angle relative to the housing.

References
----------
.. [LinParker1999] J. Lin, R. G. Parker, J. Vib. Acoust. 121 (1999) 316-321.
.. [McFaddenSmith1985] P. D. McFadden, J. D. Smith, An explanation for the asymmetry of the
   modulation sidebands about the tooth meshing frequency in epicyclic gear vibration,
   Proc. Inst. Mech. Eng. C 199 (1985) 65-70.
.. [Inalpolat2009] M. Inalpolat, A. Kahraman, A theoretical and experimental investigation
   of modulation sidebands of planetary gear sets, J. Sound Vib. 323 (2009) 677-696.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field

import numpy as np

from gearsim._version import __version__
from gearsim.dynamics.modal import modes
from gearsim.dynamics.model import DynamicModel, constrain, nominal_inertia, static_equilibrium
from gearsim.dynamics.planetary import LinParkerModel, PlanetaryMode
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import MAX_STEPS, cost_bounds_lifted, record, tacho_variable
from gearsim.dynamics.tables import MeshTable, contact_table
from gearsim.errors import InputError, require
from gearsim.system import graph as bounds
from gearsim.system.planetary import PlanetaryTrain, planet_name

__all__ = ["StageDynamics", "analysis_parts", "build_stage_model", "chain_mesh_names",
           "chain_record_paths", "lin_parker_of", "model_radii",
           "nominal_velocity", "sensor_window", "check_stage_settings", "simulate_stage",
           "stage_summary"]

_MEMBERS = ("carrier", "ring", "sun")
#: Largest RK4 step as a fraction of 1 / omega_max (RK4's stability limit is 2.78).
STABILITY_FRACTION = 2.0
#: Default backlash 2b in normal modules (of the order of the AGMA minimum backlash).
BACKLASH_MODULES = 0.05
#: Thickness of the estimated carrier (two plates) in face widths.
CARRIER_PLATES = 0.5
#: Rim thickness of the estimated ring in normal modules (as the FE ring tooth).
RING_RIM_MODULES = 3.5


def _positive(v: object) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0


@dataclass(frozen=True)
class StageDynamics:
    """Members, supports and sensor of a simulated stage.

    Parameters
    ----------
    masses
        Mass of ``sun``, ``planet``, ``ring``, ``carrier`` [kg]; a missing member is
        estimated from the geometry (solid steel cylinders of pitch radius and face width;
        ring: annulus from the root circle out by ``RING_RIM_MODULES`` m_n; carrier: two
        plates of the planet-centre radius, ``CARRIER_PLATES`` b thick in all).
    inertias
        Moments of inertia about the axis [kg m^2]; missing: of those cylinders.
    bearings
        Translational bearing stiffness of each member (planet: radial and tangential)
        [N/m]; missing: ``DynamicsSettings.bearing_stiffness``.
    held_torsional
        Torsional stiffness holding the fixed member [N m/rad]; ``None``: 1e3 times the
        mean sun-planet mesh stiffness times r_b,s^2 (a practically rigid hold).
    sensor_angle
        Sensor position on the ring theta_s [rad].
    sensor_width
        Half width Theta of the transfer-path window [rad], in (0, pi].

    Raises
    ------
    InputError
        Unknown member names, masses, inertias, stiffnesses outside the bounds of
        :mod:`gearsim.system.graph` (``MIN_MASS`` .. ``MAX_MASS`` etc.), sensor width
        outside (0, pi].
    """

    masses: dict[str, float] = field(default_factory=dict)
    inertias: dict[str, float] = field(default_factory=dict)
    bearings: dict[str, float] = field(default_factory=dict)
    held_torsional: float | None = None
    sensor_angle: float = 0.0
    sensor_width: float = math.pi

    def __post_init__(self) -> None:
        names = ("sun", "planet", "ring", "carrier")
        b = bounds
        for group, q, lo, hi, unit in (
                ("masses", "mass", b.MIN_MASS, b.MAX_MASS, "kg"),
                ("inertias", "inertia", b.MIN_INERTIA, b.MAX_INERTIA, "kg*m^2"),
                ("bearings", "bearing", b.MIN_BEARING_STIFFNESS, b.MAX_BEARING_STIFFNESS, "N/m")):
            for k, v in getattr(self, group).items():
                require(k in names, f"stage.{group}", k, "must be sun, planet, ring or carrier")
                require(_positive(v) and lo <= v <= hi, f"members.{k}_{q}", v,
                        f"must be a finite number in [{lo:g}, {hi:g}] {unit}")
        kt, lo, hi = self.held_torsional, b.MIN_SHAFT_STIFFNESS, b.MAX_SHAFT_STIFFNESS
        require(kt is None or (_positive(kt) and lo <= kt <= hi), "members.held_torsional", kt,
                f"must be a finite number in [{lo:g}, {hi:g}] N*m/rad")
        require(isinstance(self.sensor_angle, (int, float)) and math.isfinite(self.sensor_angle)
                and abs(self.sensor_angle) <= 2 * math.pi, "sensor.angle", self.sensor_angle,
                "must be a finite angle in [-360, 360] deg")
        require(_positive(self.sensor_width) and self.sensor_width <= math.pi + 1e-12,
                "sensor.width", self.sensor_width, "must be in (0, pi] rad")

    def mass_inertia(self, train: PlanetaryTrain) -> dict[str, tuple[float, float]]:
        """(mass [kg], inertia [kg m^2]) of each member, given or estimated.

        Parameters
        ----------
        train : PlanetaryTrain
            The stage (geometry, material density).

        Returns
        -------
        dict
            ``{"sun": (m, I), "planet": ..., "ring": ..., "carrier": ...}``.
        """
        st = train.stage
        rho, b = st.material.density, st.face_width

        def disc(r_out: float, r_in: float, width: float) -> tuple[float, float]:
            m = rho * math.pi * (r_out**2 - r_in**2) * width
            return m, 0.5 * m * (r_out**2 + r_in**2)

        rf = st.ring.root_radius
        est = {"sun": disc(st.sun.pitch_radius, 0.0, b),
               "planet": disc(st.planet.pitch_radius, 0.0, b),
               "ring": disc(rf + RING_RIM_MODULES * st.normal_module, rf, b),
               "carrier": disc(st.centre_distance, 0.0, CARRIER_PLATES * b)}
        return {k: (self.masses.get(k, m), self.inertias.get(k, i)) for k, (m, i) in est.items()}


def lin_parker_of(train: PlanetaryTrain, dyn: StageDynamics,
                  settings: DynamicsSettings) -> LinParkerModel:
    """The Lin & Parker model of a stage at its mean mesh stiffnesses (model frame).

    Parameters
    ----------
    train
        The stage in operation.
    dyn
        Members and supports.
    settings
        ``bearing_stiffness`` for members without their own.

    Returns
    -------
    LinParkerModel
        Masses as I / r^2 (base radii; carrier: planet-centre radius), the held member's
        torsional stiffness as k_u / r^2, the other two free, the mean of each mesh table.
    """
    st = train.stage
    mi = dyn.mass_inertia(train)
    radius = model_radii(st)
    tabs = train.tables()
    ksp = float(np.mean([np.mean(t.k) for t in tabs[0::2]]))
    krp = float(np.mean([np.mean(t.k) for t in tabs[1::2]]))
    held = dyn.held_torsional
    if held is None:
        held = 1e3 * ksp * st.sun.base_radius**2
    fixed = train.operating.fixed
    tors = {m: (held / radius[m] ** 2 if m == fixed else 0.0) for m in _MEMBERS}
    kb = {m: dyn.bearings.get(m, settings.bearing_stiffness)
          for m in ("sun", "planet", "ring", "carrier")}
    return LinParkerModel(
        planets=st.planets,
        carrier_mass=mi["carrier"][0], carrier_inertia=mi["carrier"][1] / radius["carrier"] ** 2,
        ring_mass=mi["ring"][0], ring_inertia=mi["ring"][1] / radius["ring"] ** 2,
        sun_mass=mi["sun"][0], sun_inertia=mi["sun"][1] / radius["sun"] ** 2,
        planet_mass=mi["planet"][0], planet_inertia=mi["planet"][1] / radius["planet"] ** 2,
        carrier_bearing=kb["carrier"], ring_bearing=kb["ring"], sun_bearing=kb["sun"],
        planet_bearing=kb["planet"], carrier_torsional=tors["carrier"],
        ring_torsional=tors["ring"], sun_torsional=tors["sun"], sun_mesh=ksp, ring_mesh=krp,
        sun_pressure_angle=st.sun_planet_pressure_angle,
        ring_pressure_angle=st.ring_planet_pressure_angle,
        planet_angles=tuple(float(a) for a in train.model_angles))


def _contact_rows(t, direction: int) -> MeshTable:
    """Kernel table of a phased mesh of contacts, read backwards when ``direction`` is -1
    (sample j of the reversed table is sample -j mod n of the forward one, as for ``k``)."""
    tab = contact_table(t.grid)
    if direction == 1:
        return tab
    n = tab.k.size
    perm = (-np.arange(n)) % n
    counts = np.diff(tab.ptr)[perm]
    rows = [np.arange(tab.ptr[j], tab.ptr[j + 1]) for j in perm]
    idx = np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)
    return MeshTable(k=tab.k[perm].copy(), positions_per_cycle=tab.positions_per_cycle,
                     period=tab.period, k_zero=tab.k_zero[perm].copy(),
                     ptr=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
                     kx=np.ascontiguousarray(tab.kx[idx]),
                     sx=np.ascontiguousarray(tab.sx[idx]))


def check_stage_settings(s: DynamicsSettings, *, gears: bool = False) -> None:
    """Refuse the gear-train options a stage does not model (one line each).

    Parameters
    ----------
    s : DynamicsSettings
        The settings of a stage's run.
    gears : bool, optional
        The gearbox has gears beside its stages: the gear-train options (mesh
        modifications, runout, meshes of contacts, bearing damping and axial stiffness,
        idler angles) are theirs (:func:`gearsim.dynamics.compose.stage_settings` resets
        them for the stages), so only the model and the one backlash are checked.

    Raises
    ------
    InputError
        The first option a stage does not model, named ``dynamics.<option>``.
    """
    require(s.model in ("lta", "torsional"), "dynamics.model", s.model,
            'a planetary stage is modelled "lta" (Lin & Parker, planar) or "torsional"')
    for name, default in (() if gears else (
            ("profile_modification", (0.0,)), ("crowning", (0.0,)), ("runout", (0.0,)),
            ("assembly_error", (0.0,)), ("contact_mesh", False), ("bearing_damping", None),
            ("bearing_axial_stiffness", None), ("idler_angle", ()))):
        v = getattr(s, name)
        require(v == default, f"dynamics.{name}", v,
                f"is not modelled for a planetary stage (leave it at {default!r})")
    require(s.backlash is None or len(s.backlash) == 1, "dynamics.backlash", s.backlash,
            "a planetary stage takes one backlash for all its meshes")


def build_stage_model(train: PlanetaryTrain, dyn: StageDynamics | None = None,
                      settings: DynamicsSettings | None = None) -> DynamicModel:
    """Equations of motion of a stage as a :class:`DynamicModel` for the RK4 kernel.

    Parameters
    ----------
    train
        The stage in operation (tables, phases, model-frame torques).
    dyn
        Members, supports and sensor; default :class:`StageDynamics()`.
    settings
        Damping ratios, backlash, non-linearity, bearing stiffness.

    Returns
    -------
    DynamicModel
        ``kind = "planetary"``; rows of ``V``: for each planet its sun mesh, ring mesh,
        radial and tangential bearing; ``info`` holds the Lin & Parker model, the mesh
        rows and the model-frame radii.
    """
    dyn = dyn or StageDynamics()
    settings = settings or DynamicsSettings()
    check_stage_settings(settings)
    st = train.stage
    lp = lin_parker_of(train, dyn, settings)
    k_all, b_all = lp.springs()
    n_planet_rows = 4 * st.planets
    tabs = train.tables()
    mass = np.diag(lp.mass_matrix()).copy()
    n = mass.size
    kb = np.zeros(n)
    # central springs: x, y, u of carrier, ring, sun (diagonal gradients)
    for i in range(n_planet_rows, k_all.size):
        j = int(np.flatnonzero(b_all[i])[0])
        kb[j] += k_all[i]
    zb = settings.bearing_damping_ratio
    cb = 2.0 * zb * np.sqrt(kb * mass)
    V = b_all[:n_planet_rows].copy()
    tables: list[MeshTable] = []
    phase = np.zeros(n_planet_rows)
    cm = np.zeros(n_planet_rows)
    clear = np.full(n_planet_rows, np.inf)
    m_s, m_p, m_r = mass[8], mass[11], mass[5]
    b2 = (settings.backlash[0] if settings.backlash is not None
          else BACKLASH_MODULES * st.normal_module)
    mesh_rows = []
    k_ref_rows: dict[int, float] = {}
    for j in range(st.planets):
        ts, tr = tabs[2 * j], tabs[2 * j + 1]
        for q, (t, m_eq) in enumerate(((ts, 1.0 / (1.0 / m_s + 1.0 / m_p)),
                                       (tr, 1.0 / (1.0 / m_r + 1.0 / m_p)))):
            row = 4 * j + q
            mesh_rows.append(row)
            tables.append(MeshTable(k=t.k, positions_per_cycle=t.positions_per_cycle,
                                    period=t.period) if t.grid is None
                          else _contact_rows(t, train.direction))
            phase[row] = t.phase
            k_ref = t.reference_mean if t.reference_mean is not None else float(np.mean(t.k))
            k_ref_rows[row] = k_ref
            cm[row] = 2.0 * settings.mesh_damping_ratio * math.sqrt(k_ref * m_eq)
            clear[row] = b2 if settings.nonlinear else np.inf
        for q in (2, 3):  # planet bearing, constant
            row = 4 * j + q
            tables.append(MeshTable(k=np.array([k_all[row]]), positions_per_cycle=1, period=1))
            cm[row] = 2.0 * zb * math.sqrt(k_all[row] * m_p)
    radius = model_radii(st)
    tq = train.model_torques
    fext = np.zeros(n)
    for m in _MEMBERS:
        if m != train.operating.fixed:
            fext[3 * _MEMBERS.index(m) + 2] = tq[m] / radius[m]
    kmean = np.array([k_ref_rows.get(i, float(np.mean(t.k))) for i, t in enumerate(tables)])
    q0 = static_equilibrium(mass, kb, V, kmean, fext, np.zeros(n_planet_rows))
    labels = []
    for m in _MEMBERS:
        labels += [f"{m}.x", f"{m}.y", f"{m}.u"]
    for j in range(st.planets):
        p = planet_name(j)
        labels += [f"{p}.xi", f"{p}.eta", f"{p}.u"]
    f_static = train.sun_torque / (st.planets * st.sun.base_radius)
    row_names = []
    for j in range(st.planets):
        p = planet_name(j)
        row_names += [f"sun-{p}", f"ring-{p}", f"bearing-{p}.radial", f"bearing-{p}.tangential"]
    w = nominal_velocity(train, labels)
    profile, load = settings.profiles(train.operating.speed)
    model = DynamicModel(
        kind="planetary", gear_names=_MEMBERS + tuple(planet_name(j) for j in range(st.planets)),
        dof_labels=tuple(labels), mass=mass, kb=kb, cb=cb, fext=fext, V=V,
        kappa=np.ones(n_planet_rows), kscale=np.ones(n_planet_rows), cm=cm, clearance=clear,
        tables=tuple(tables), phase=phase, mesh_frequency=train.mesh_frequency,
        e0=np.zeros(n_planet_rows), h_amp=np.zeros((n_planet_rows, 1)),
        h_omega=np.zeros((n_planet_rows, 1)), h_phase=np.zeros((n_planet_rows, 1)),
        to_transverse=np.ones(n_planet_rows), dte_offset=np.zeros(n_planet_rows),
        static_force=np.where(np.isin(np.arange(n_planet_rows), mesh_rows), f_static, 0.0),
        bearing_dofs=np.arange(3 * len(_MEMBERS)).reshape(len(_MEMBERS), 3)[:, :2],
        axes=("x", "y"), q_static=q0,
        profile=profile, load=load,
        inertial=(None if profile is None
                  else nominal_inertia(mass, w, labels.index(f"{train.operating.input}.u"))),
        info={"lin_parker": lp, "mesh_rows": tuple(mesh_rows), "row_names": tuple(row_names),
              "backlash": b2, "nominal_velocity": w})
    if settings.model != "torsional":
        return model
    # purely torsional: members and planet centres fixed in translation, each planet's
    # centre carried by the carrier (rigid bearings: eta_n = u_c) (Kahraman 1994)
    follow = {f"{m}.{a}": ("", 0.0) for m in _MEMBERS for a in "xy"}
    for j in range(st.planets):
        follow |= {f"{planet_name(j)}.xi": ("", 0.0), f"{planet_name(j)}.eta": ("carrier.u", 1.0)}
    red = constrain(model, follow, "planetary")
    kept = list(red.info["rows_kept"])
    return dataclasses.replace(red, info={**red.info, "mesh_rows": tuple(
        kept.index(r) for r in mesh_rows), "row_names": tuple(row_names[r] for r in kept)})


def chain_mesh_names(chains) -> tuple[str, ...]:
    """Names of the meshes of the chains beside a stage, in power-flow order.

    One chain keeps its meshes' own names (I, II, ...); the meshes of two chains (the
    gears driving the stage, then those it drives) are numbered through, I, II, III, ...

    Parameters
    ----------
    chains : sequence of GearTrain
        The chains in power-flow order.

    Returns
    -------
    tuple of str
    """
    chains = list(chains)
    if len(chains) == 1:
        return tuple(p.name for p in chains[0].pairs)
    roman = ("I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX", "X", "XI", "XII")
    n = sum(len(c.pairs) for c in chains)
    return tuple(roman[i] if i < len(roman) else str(i + 1) for i in range(n))


def model_radii(stage) -> dict[str, float]:
    """Radii of the Lin & Parker rotational coordinates u = r theta [m]: the base radii
    of sun, planet and ring, the planet-centre radius of the carrier.

    Parameters
    ----------
    stage : gearsim.geometry.planetary.PlanetaryStage
        The stage's geometry.

    Returns
    -------
    dict
        ``{"sun", "planet", "ring", "carrier"}`` -> radius [m].
    """
    return {"sun": stage.sun.base_radius, "planet": stage.planet.base_radius,
            "ring": stage.ring.base_radius, "carrier": stage.centre_distance}


def nominal_velocity(train: PlanetaryTrain, labels: list[str] | tuple[str, ...]) -> np.ndarray:
    """Velocity of each coordinate of the stage model in its nominal motion [m/s].

    In the Lin & Parker (1999) coordinates (model frame, mirrored when the sun torque is
    clockwise): u_j = r_j theta_j of sun, ring (base radii) and carrier (planet-centre
    radius r_c) at r_j omega_j; each planet's centre moves tangentially with the carrier,
    eta_n at r_c omega_c, and spins at omega_c + omega_p/c with omega_p/c = -(z_s / z_p)
    (omega_s - omega_c) relative to the carrier, u_n at r_p (omega_c + omega_p/c);
    translations x, y, xi at 0 (centripetal terms are left out, as in the model). The
    nominal motion deflects no spring of the stage, V w = 0 (checked in the tests).

    Parameters
    ----------
    train : PlanetaryTrain
        The stage in operation.
    labels : sequence of str
        Coordinate labels of :func:`build_stage_model` (``"sun.u"``, ``"planet1.eta"`` ...).

    Returns
    -------
    ndarray
        w [m/s] at the operating speed (per unit tau').
    """
    st = train.stage
    sgn = -1.0 if train.mirrored else 1.0
    om = {m: sgn * v for m, v in train.speeds.items()}
    radius = model_radii(st)
    spin = om["carrier"] - st.sun_teeth / st.planet_teeth * (om["sun"] - om["carrier"])
    w = np.zeros(len(labels))
    for i, lab in enumerate(labels):
        body, coord = lab.split(".")
        if coord == "u":
            w[i] = radius[body] * om[body] if body in om else radius["planet"] * spin
        elif coord == "eta":
            w[i] = radius["carrier"] * om["carrier"]
    return w


def sensor_window(phi: np.ndarray, width: float) -> np.ndarray:
    """Transfer-path window w(phi) of a planet at angle ``phi`` from the sensor [-].

    Parameters
    ----------
    phi
        Angle of the planet from the sensor [rad] (any range; wrapped to [-pi, pi)).
    width
        Half width Theta [rad].

    Returns
    -------
    ndarray
        (1 + cos(pi phi / Theta)) / 2 inside |phi| < Theta, 0 outside.

    Examples
    --------
    >>> import numpy as np
    >>> sensor_window(np.array([0.0, np.pi / 4, np.pi / 2, 3.0]), np.pi / 2).round(6).tolist()
    [1.0, 0.5, 0.0, 0.0]
    """
    p = np.mod(np.asarray(phi, dtype=float) + math.pi, 2.0 * math.pi) - math.pi
    return np.where(np.abs(p) < width, 0.5 * (1.0 + np.cos(math.pi * p / width)), 0.0)


def _omega_max(model: DynamicModel) -> float:
    import scipy.linalg

    K = np.diag(model.kb).astype(float)
    for i, t in enumerate(model.tables):
        K += t.max * np.outer(model.V[i], model.V[i])
    w2 = scipy.linalg.eigh(K, np.diag(model.mass), eigvals_only=True)
    return math.sqrt(max(float(w2.max()), 0.0))


def _slowest_decay(model: DynamicModel, zeta: float) -> float:
    import scipy.linalg

    K = np.diag(model.kb).astype(float)
    for i, t in enumerate(model.tables):
        K += t.mean * np.outer(model.V[i], model.V[i])
    w2 = scipy.linalg.eigh(K, np.diag(model.mass), eigvals_only=True)
    w = np.sqrt(w2[w2 > 1e-6 * w2.max()])
    return 1.0 / (max(zeta, 1e-3) * float(w.min()))


def simulate_stage(train: PlanetaryTrain, dyn: StageDynamics | None = None,
                   settings: DynamicsSettings | None = None, *,
                   model: DynamicModel | None = None):
    """Simulate a stage; mesh forces, member motion and the fixed sensor's signal.

    Parameters
    ----------
    train
        The stage in operation.
    dyn
        Members, supports and sensor.
    settings
        ``duration``, ``fs``, ``oversample`` (FIR decimation as the gear trains),
        ``step`` (largest step; the step used is also kept below
        ``STABILITY_FRACTION / omega_max`` of the stiffest mesh state), ``transient``
        (``None``: 12 decay times of the slowest mode at the smaller damping ratio, at
        least one carrier revolution), damping, backlash.
    model
        A prebuilt :func:`build_stage_model` (for benchmarks).

    Returns
    -------
    xarray.Dataset
        ``mesh_force`` (time, mesh) [N] for the 2N meshes, ``q`` (time, dof) [m],
        ``acceleration`` of the ring translation [m/s^2], ``sensor`` [N] (module docstring),
        ``carrier_angle`` [rad] (omega_c tau(t): it follows a speed profile), ``tacho``
        (time, shaft) [V], a once-per-revolution pulse of every turning member and of a
        driven chain's shafts; attributes: f_m, speeds, direction, phases,
        ``gearsim_version`` and ``dynamics`` (the run's options, JSON, SI). A model of
        stages in series (:mod:`gearsim.dynamics.compose`): the meshes of all stages in
        ``mesh_force`` (``stage1-sun-planet-1``, ...), ``stage_shaft_torque`` (time,
        stage_shaft) [N m] and attributes ``stage_mesh_frequency`` [Hz],
        ``stage_sun_torque``, ``stage_carrier_torque`` [N m] (physical, each stage),
        ``stage_static_mesh_force`` [N], ``static_stage_shaft_torque`` [N m] (the shafts
        driving each later stage first, then those from a stage's output member to gears
        between two stages); the sensor, ring acceleration, carrier angle and f_m are the
        first stage's.

    Raises
    ------
    InputError
        If fs does not exceed twice the mesh frequency, options not modelled are set or
        the run needs more than :data:`gearsim.dynamics.simulate.MAX_STEPS` steps.
    SimulationError
        If the integration diverges.
    """
    import xarray as xr

    dyn = dyn or StageDynamics()
    settings = settings or DynamicsSettings()
    f_m = train.mesh_frequency
    if not settings.fs > 2.0 * f_m:
        raise InputError("dynamics.fs", settings.fs,
                         f"must be > {2 * f_m:.6g} Hz, twice the mesh frequency "
                         f"{f_m:.6g} Hz, else the record is aliased")
    model = model or build_stage_model(train, dyn, settings)
    r = settings.oversample
    fs = settings.fs
    t_int = 1.0 / (r * fs)
    w_max = _omega_max(model)
    step = min(settings.step, STABILITY_FRACTION / w_max)
    m = max(1, math.ceil(min(t_int / step * (1 - 1e-12), 1e18)))
    dt = t_int / m
    wc = abs(train.speeds["carrier"])
    transient = settings.transient
    if transient is None:
        zeta = min(settings.bearing_damping_ratio, settings.mesh_damping_ratio)
        transient = max(12.0 * _slowest_decay(model, zeta),
                        (2.0 * math.pi / wc) if wc > 0 else 0.0, 1.0 / f_m)
    steps = (transient + settings.duration) / dt
    if steps > MAX_STEPS and not cost_bounds_lifted():
        name = "transient" if transient > settings.duration else "duration"
        raise InputError(f"dynamics.{name}", getattr(settings, name) or transient,
                         f"the run needs {steps:.3g} integration steps (transient {transient:.4g} "
                         f"s + duration {settings.duration:.4g} s at dt = {dt:.3g} s, set by the "
                         f"highest natural frequency {w_max / (2 * math.pi):.4g} Hz of the "
                         "stage: check the members' masses, inertias and stiffnesses), above the "
                         f"limit of {MAX_STEPS:.0e}; GEARSIM_FORCE=1 runs it anyway")
    t, q, v, f, transient = record(model, settings, dt=dt, m=m, transient=transient)
    n_out = t.size
    rows = list(model.info["mesh_rows"])
    names = [model.info["row_names"][i] for i in rows]
    forces = f[:, rows]
    # stages in series (gearsim.dynamics.compose): the first is this one, named with
    # its prefix; the ring's acceleration and sensor are the first stage's
    series = model.info.get("stages", ())
    pre = series[0]["prefix"] if series else ""
    ring = [model.dof_labels.index(f"{pre}ring.{a}") for a in "xy"
            if f"{pre}ring.{a}" in model.dof_labels]
    acc = (np.gradient(v[:, ring], t, axis=0) if n_out > 2 and ring
           else np.zeros((n_out, 2)))
    tau = model.nominal(t)[0]  # nominal time: the angles follow a speed profile
    theta_c = train.speeds["carrier"] * tau
    psi = train.stage.planet_angles_value
    ring_f = forces[:, 1:2 * train.stage.planets:2]
    dyn_f = ring_f - ring_f.mean(axis=0)
    w = sensor_window(theta_c[:, None] + psi[None, :] - dyn.sensor_angle, dyn.sensor_width)
    sensor = np.sum(w * dyn_f, axis=1)
    if model.axes and model.kind == "planetary":  # a stage alone: Lin & Parker's groups
        groups = model.info["lin_parker"].modes().groups
        modes_of = "the mean-stiffness Lin & Parker model"
    else:  # the whole model's own modes: torsional, or stages and chains joined
        md = modes(model)
        kind = "coupled" if model.axes else "torsional"
        groups = [PlanetaryMode(frequency=float(f), multiplicity=1, kind=kind,
                                shapes=md.shapes[:, [i]]) for i, f in enumerate(md.frequencies)]
        modes_of = f"the whole mean-stiffness {settings.model} model"
    extra: dict = {}
    extra_coords: dict = {}
    extra_attrs: dict = {}
    # the chains beside the stage (gearsim.dynamics.compose), in power-flow order: the
    # gears driving the stages, those between two stages, then those the stages drive
    chains = sorted(model.info.get("chains", ()), key=lambda e: e["side"] != "input")
    ends = [e for e in chains if e["side"] != "between"]
    if chains:
        crow = [r for e in chains for r in e["rows"]]
        extra["chain_mesh_force"] = (("time", "chain_mesh"), f[:, crow], {"units": "N"})
        # the shaft of the gears the stages drive (else of those driving them); stages
        # between two chains also have their input shaft (gears between two stages: in
        # stage_shaft_torque)
        main = (ends or chains)[-1]
        if ends:
            extra["shaft_torque"] = ("time", f[:, main["shaft_row"]], {"units": "N*m"})
        if len(ends) > 1:
            extra["input_shaft_torque"] = ("time", f[:, ends[0]["shaft_row"]],
                                           {"units": "N*m"})
        bd = np.concatenate([e["bearing_dofs"] for e in chains])
        acc_c = (model.fext[bd] - model.kb[bd] * q[:, bd] - model.cb[bd] * v[:, bd]
                 - np.einsum("ti,ijk->tjk", f, model.V[:, bd])) / model.mass[bd]
        extra["chain_acceleration"] = (("time", "chain_shaft", "chain_axis"), acc_c, {
            "units": "m/s^2", "long_name": "acceleration of each chain shaft's centre"})
        extra_coords["chain_shaft"] = [sh for e in chains for sh in e["shafts"]]
        extra_coords["chain_axis"] = list(chains[0]["axes"])
        extra_coords["chain_mesh"] = list(chain_mesh_names([e["chain"] for e in chains]))
        extra_attrs = {"chain_mesh_frequency": main["mesh_frequency"],
                       "chain_mesh_frequencies": [float(x) for e in chains
                                                  for x in e["chain"].mesh_frequencies],
                       "output_member": model.info["output_member"],
                       "input_member": train.operating.input,
                       "chain_name": " + ".join(e["chain"].name for e in chains),
                       "chain_static_mesh_force": [float(model.static_force[i])
                                                   for i in crow]}
        if ends:  # the gears drive the stages ("input"), are driven ("output") or both;
            # shaft_torque is the shaft on shaft_member
            extra_attrs |= {"shaft_stiffness": main["shaft_stiffness"],
                            "chain_side": "both" if len(ends) > 1 else main["side"],
                            "shaft_member": main["member"],
                            "static_shaft_torque": float(model.static_force[main["shaft_row"]])}
        if len(ends) > 1:
            extra_attrs["static_input_shaft_torque"] = float(
                model.static_force[ends[0]["shaft_row"]])
        # what the shaft and gear tiers of the analysis need, under the names of a gear
        # train's result: the gears' speeds [Hz], reference = the first chain's first
        # shaft (the gearbox input, or the stage's output), and their teeth or stages
        ch = chains[0]["chain"]
        extra_attrs["shaft_frequency"] = [float(ch.shaft_frequency(j))
                                          for j in range(len(ch.gears))]
        extra_attrs["analysis_teeth"] = _analysis_teeth(ch)
        if (stages := ch.compound_stages()) is not None:
            extra_attrs["analysis_stages"] = ",".join(f"{d}/{n}" for d, n in stages)
    if len(series) > 1:  # each stage's torques, the shafts between the stages: those
        # driving each later stage, then those driving gears between two stages
        between = [e["shaft_row"] for e in series[1:]] + [
            e["shaft_row"] for e in chains if e["side"] == "between"]
        extra["stage_shaft_torque"] = (("time", "stage_shaft"), f[:, between],
                                       {"units": "N*m"})
        extra_coords["stage_shaft"] = [model.info["row_names"][r] for r in between]
        extra_attrs |= {
            "stage_names": [e["prefix"][:-1] for e in series],
            "stage_mesh_frequency": [e["train"].mesh_frequency for e in series],
            "stage_sun_torque": [e["train"].torques["sun"] for e in series],
            "stage_carrier_torque": [e["train"].torques["carrier"] for e in series],
            "stage_static_mesh_force": [float(model.static_force[i]) for i in rows],
            "static_stage_shaft_torque": [float(model.static_force[r]) for r in between]}
    # once-per-revolution tacho of every turning shaft (the stages' members, then the
    # chains' shafts), each in its own sense, following a speed profile
    parts = series or ({"train": train, "prefix": ""},)  # the stages, named
    extra_attrs["analysis_parts"] = analysis_parts(
        [e["train"] for e in parts], [e["chain"] for e in chains],
        float(tau[0]), prefixes=[e["prefix"] for e in parts],
        between=[e["side"] == "between" and model.info["row_names"][e["shaft_row"]]
                 for e in chains])
    shafts = [(e["prefix"] + m, abs(e["train"].speeds[m]))
              for e in parts
              for m in ("carrier", "sun", "ring") if e["train"].speeds[m] != 0.0]
    for e in chains:
        ch = e["chain"]
        shafts += [(sh.name, abs(ch.speed(ch.gear_index(sh.gears[0]))))
                   for sh in ch.flow.shafts]
    extra["tacho"] = tacho_variable(np.stack([w * tau for _, w in shafts], axis=1))
    extra_coords["shaft"] = [name for name, _ in shafts]
    constant = all(model.tables[i].k.size == 1 for i in list(model.info["mesh_rows"])
                   + [r for e in chains for r in e["rows"]])
    ds = xr.Dataset(
        {"mesh_force": (("time", "mesh"), forces, {"units": "N"}),
         "q": (("time", "dof"), q, {"units": "m"}),
         "ring_acceleration": (("time", "axis"), acc, {"units": "m/s^2"}),
         "sensor": ("time", sensor, {"units": "N", "long_name": "ring-planet forces through "
                                     "the transfer-path window of the fixed sensor"}),
         "carrier_angle": ("time", theta_c, {"units": "rad"}),
         "mode_frequency": ("mode", [g.frequency for g in groups],
                            {"units": "Hz", "long_name": f"natural frequencies of {modes_of}"}),
         "mode_multiplicity": ("mode", [g.multiplicity for g in groups]),
         "mode_kind": ("mode", [g.kind for g in groups]), **extra},
        coords={"time": ("time", t, {"units": "s"}), "mesh": names,
                "dof": list(model.dof_labels), "axis": ["x", "y"], **extra_coords},
        attrs={"kind": "planetary", "name": train.name, "mesh_frequency": f_m, "fs": fs,
               "dt": dt, "transient": transient, "direction": train.direction,
               "mirrored": int(train.mirrored),
               "carrier_frequency": train.speeds["carrier"] / (2 * math.pi),
               "sun_frequency": train.speeds["sun"] / (2 * math.pi),
               "ring_frequency": train.speeds["ring"] / (2 * math.pi),
               "sun_teeth": train.stage.sun_teeth, "planet_teeth": train.stage.planet_teeth,
               "ring_teeth": train.stage.ring_teeth, "planets": train.stage.planets,
               "static_mesh_force": float(model.static_force[rows[0]]),
               "sensor_angle": dyn.sensor_angle, "sensor_width": dyn.sensor_width,
               "cracks": ", ".join(f"{p}{c.gear}:{c.tooth}:{c.flank}:{c.depth:g}" for p, c in (
                   *((e["prefix"], c) for e in parts for c in e["train"].cracks),
                   *(("", c) for e in chains for c in e["chain"].cracks))) or "none",
               "constant_meshes": int(constant), "gearsim_version": __version__,
               "dynamics": json.dumps(settings.to_dict()), **extra_attrs})
    return ds


def _analysis_teeth(chain) -> list[int]:
    """Tooth counts a chain's records are analysed with: every gear of a chain of
    idlers, else the first mesh's driver and driven gear."""
    return [int(g.teeth) for g in (chain.gears if chain.is_chain else
                                   (chain.pairs[0].driver, chain.pairs[0].driven))]


def chain_record_paths(chain, meshes) -> dict[str, dict[str, list]]:
    """Of gears beside a stage whose power branches, the kinematics each record of them
    is analysed with: the power path from their first shaft to the record's shaft.

    Parameters
    ----------
    chain : GearTrain
        The gears.
    meshes : sequence of str
        Their meshes' names in the result (:func:`chain_mesh_names`).

    Returns
    -------
    dict
        Shaft name (``chain_acceleration[shaft,...]``) or mesh name
        (``chain_mesh_force[mesh]``, the shaft of its driven gear) -> ``{"teeth": [...]}``
        or ``{"stages": [[z_d, z_n], ...]}``
        (:meth:`~gearsim.system.GearTrain.path_kinematics`); empty for gears whose power
        does not branch.
    """
    fl = chain.flow
    if len(fl.outputs) < 2:
        return {}
    path = [{k: [list(x) if isinstance(x, tuple) else x for x in v]
             for k, v in chain.path_kinematics(i).items()} for i in range(len(fl.shafts))]
    return {**{sh.name: path[i] for i, sh in enumerate(fl.shafts)},
            **{name: path[fl.shaft_of[b]] for name, (_, b) in zip(meshes, fl.meshes,
                                                                   strict=True)}}


def analysis_parts(stages, chains, tau0: float, prefixes: list[str] | None = None,
                   between: list[str | bool] | None = None) -> str:
    """What the analysis of a stage result's records needs, part by part, as JSON (the
    result's ``analysis_parts`` attribute).

    A record belongs to stage k (:func:`gearsim.dynamics.compose.stage_of_label`) or to
    one of the gear chains beside the stages
    (:func:`gearsim.dynamics.compose.chain_of_record`), and is analysed with that part's
    reference shaft, speed and teeth, as :meth:`gearsim.model.Gearbox.reference` chooses.

    Parameters
    ----------
    stages : sequence of PlanetaryTrain
        The stages, in power-flow order.
    chains : sequence of GearTrain
        The chains beside the stages, in power-flow order.
    tau0 : float
        Nominal time of the first sample [s] (the carrier's angle there is
        omega_c tau0).
    prefixes : sequence of str, optional
        Each stage's prefix of its members' names in the result (``"stage2-"``; default
        none).
    between : sequence of str or bool, optional
        Of each chain sitting between two stages, the name of the shaft from the stage
        driving it (its ``stage_shaft_torque``, analysed with the chain's kinematics),
        else False (default none sits between).

    Returns
    -------
    str
        ``{"stages": [...], "chains": [...]}``: per stage its tooth counts, planets,
        carrier and ring frequencies [Hz], the carrier's angle at the first sample [rad],
        the name of the reference member's tacho (``tacho``: the member with its prefix,
        which :class:`gearsim.model.Gearbox` renames to the member's shaft) and its
        ``frequency`` [Hz] and ``teeth`` of
        :meth:`~gearsim.system.planetary.PlanetaryTrain.analysis_reference`; per chain
        its shafts and meshes (the result's names), the first shaft's frequency [Hz], the
        tooth counts, for a compound train its stages, and ``between`` (``between`` above);
        of gears whose power branches also ``paths``, each record's path
        (:func:`chain_record_paths`).
    """
    import json

    out_stages = []
    prefixes = prefixes or [""] * len(stages)
    for tr, pre in zip(stages, prefixes, strict=True):
        member, freq, teeth = tr.analysis_reference()
        st, w = tr.stage, tr.speeds
        out_stages.append({
            "z_sun": int(st.sun_teeth), "z_planet": int(st.planet_teeth),
            "z_ring": int(st.ring_teeth), "planets": int(st.planets),
            "carrier_frequency": w["carrier"] / (2 * math.pi),
            "ring_frequency": w["ring"] / (2 * math.pi),
            "carrier_phase": float(w["carrier"] * tau0), "tacho": pre + member,
            "frequency": freq, "teeth": [int(z) for z in teeth]})
    names, k, out_chains = chain_mesh_names(chains), 0, []
    for ch, mid in zip(chains, between or [False] * len(chains), strict=True):
        stg, own = ch.compound_stages(), list(names[k:k + len(ch.pairs)])
        paths = chain_record_paths(ch, own)
        out_chains.append({"shafts": [sh.name for sh in ch.flow.shafts], "meshes": own,
                           "frequency": float(ch.shaft_frequency(0)),
                           "teeth": _analysis_teeth(ch),
                           "stages": None if stg is None else [list(p) for p in stg],
                           "between": mid, **({"paths": paths} if paths else {})})
        k += len(ch.pairs)
    return json.dumps({"stages": out_stages, "chains": out_chains})


def stage_summary(ds) -> dict:
    """Summary of a simulated stage: per mesh mean, RMS and peak force; sensor RMS.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`simulate_stage`.

    Returns
    -------
    dict
        ``meshes`` (name, mean, rms, peak, static force), ``sensor_rms``; every ``rms``
        (``*_rms``) is the RMS about the mean, the standard deviation, as in
        :func:`gearsim.dynamics.simulate.summary`;
        ``mesh_frequency``, ``modes`` (frequency [Hz], multiplicity, kind of each group of
        the mean-stiffness Lin & Parker model of a stage alone; each mode of the whole
        model, kind ``"torsional"`` or ``"coupled"``, of the torsional model or of stages
        and chains joined), ``modes_of`` (which model), ``constant_meshes`` (no mesh table
        varies: no parametric excitation, the response stays at the static load); with
        stages in series ``stages`` (per stage ``mesh_frequency`` [Hz], ``sun_torque``,
        ``carrier_torque`` [N m], and the shaft driving it: ``shaft_torque_mean``,
        ``shaft_torque_rms``, ``static_shaft_torque`` [N m]); with a
        chain (:mod:`gearsim.dynamics.compose`) also ``chain_meshes``,
        ``chain_mesh_frequency``, ``output_member``, ``shaft_torque_mean`` and
        ``shaft_torque_rms``.
    """
    f = ds["mesh_force"].values
    static = np.broadcast_to(ds.attrs.get("stage_static_mesh_force",
                                          float(ds.attrs["static_mesh_force"])), f.shape[1])
    meshes = [{"mesh": str(name), "mean": float(np.mean(f[:, i])),
               "rms": float(np.std(f[:, i])), "peak": float(np.max(np.abs(f[:, i]))),
               "static_force": float(static[i])}
              for i, name in enumerate(ds["mesh"].values)]
    return {"kind": "planetary", "meshes": meshes,
            "sensor_rms": float(np.std(ds["sensor"].values)),
            "mesh_frequency": float(ds.attrs["mesh_frequency"]),
            "samples": int(ds.sizes["time"]),
            "modes": [{"frequency": float(f), "multiplicity": int(m), "kind": str(k)}
                      for f, m, k in zip(ds["mode_frequency"].values,
                                         ds["mode_multiplicity"].values,
                                         ds["mode_kind"].values, strict=True)],
            "modes_of": str(ds["mode_frequency"].attrs.get("long_name", "")),
            "constant_meshes": bool(ds.attrs.get("constant_meshes", 0)),
            **_stages_summary(ds), **_chain_summary(ds)}


def _stages_summary(ds) -> dict:
    """Each stage's mesh frequency [Hz], sun and carrier torque [N m] and the torque of
    the shaft driving it [N m] (mean, RMS, static) of a result of stages in series
    (empty for one stage)."""
    if "stage_shaft_torque" not in ds:
        return {}
    a = ds.attrs
    tq = ds["stage_shaft_torque"].values
    out = []
    for k, name in enumerate(np.atleast_1d(a["stage_names"])):
        e = {"stage": str(name), "mesh_frequency": float(np.atleast_1d(
             a["stage_mesh_frequency"])[k]),
             "sun_torque": float(np.atleast_1d(a["stage_sun_torque"])[k]),
             "carrier_torque": float(np.atleast_1d(a["stage_carrier_torque"])[k])}
        if k > 0:
            e |= {"shaft": str(ds["stage_shaft"].values[k - 1]),
                  "shaft_torque_mean": float(np.mean(tq[:, k - 1])),
                  "shaft_torque_rms": float(np.std(tq[:, k - 1])),
                  "static_shaft_torque": float(np.atleast_1d(
                      a["static_stage_shaft_torque"])[k - 1])}
        out.append(e)
    return {"stages": out}


def _chain_summary(ds) -> dict:
    """Chain meshes and shaft torque of a stage+chain result (empty for a stage alone)."""
    if "chain_mesh_force" not in ds:
        return {}
    f = ds["chain_mesh_force"].values
    static = np.atleast_1d(ds.attrs["chain_static_mesh_force"])
    tq = ds["shaft_torque"].values if "shaft_torque" in ds else None  # gears between only
    return {"chain_meshes": [{"mesh": str(name), "mean": float(np.mean(f[:, i])),
                              "rms": float(np.std(f[:, i])), "static_force": float(static[i])}
                             for i, name in enumerate(ds["chain_mesh"].values)],
            "chain_mesh_frequency": float(ds.attrs["chain_mesh_frequency"]),
            "output_member": str(ds.attrs["output_member"]),
            **({} if tq is None else {
                "chain_side": str(ds.attrs.get("chain_side", "output")),
                "shaft_member": str(ds.attrs.get("shaft_member", ds.attrs["output_member"])),
                "shaft_torque_mean": float(np.mean(tq)), "shaft_torque_rms": float(np.std(tq))}),
            **({"input_member": str(ds.attrs["input_member"]),
                "input_shaft_torque_mean": float(np.mean(ds["input_shaft_torque"].values)),
                "input_shaft_torque_rms": float(np.std(ds["input_shaft_torque"].values))}
               if "input_shaft_torque" in ds else {}),
            }
