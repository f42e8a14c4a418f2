"""Options of the train-dynamics simulation (the ``[dynamics]`` config section).

Every default that the seed paper does not give is listed with its source in
``docs/defaults.md`` (section "Dynamics"). Values are SI: metres, seconds, hertz,
newtons per metre, radians.

Example section::

    [dynamics]
    model = "lta"                 # or "torsional", "seed"
    step = "10 us"                # largest integration step (the run uses a divisor)
    duration = "1 s"              # recorded window, after the transient
    fs = "50 kHz"                 # output sampling rate
    bearing_stiffness = "1e9 N/m"
    mesh_damping_ratio = 0.07
    idler_angle = "180 deg"       # angle between the centre lines at each idler
    profile_modification = "2 um" # amplitude of the mesh-harmonic STE, per mesh or one value
    runout = ["5 um", "0 um", "0 um"]   # per gear
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from gearsim.errors import InputError, require
from gearsim.sections import as_written, convert
from gearsim.system.graph import MAX_BEARING_STIFFNESS, MIN_BEARING_STIFFNESS

__all__ = ["DEFAULT_STEP", "KEYS", "LIST_KEYS", "MAX_DURATION", "MAX_FS", "MAX_TRANSIENT",
           "MIN_STEP", "MODELS", "DynamicsSettings", "parse_dynamics"]

#: Default largest integration step [s]. From the step-halving study on the Table-1 train
#: (working-flank crack; ``tests/dynamics/test_dyn_convergence.py``, table in
#: docs/dynamics.md): the RMS of the mesh-force fluctuation changes by 7e-4 (LTA) from
#: 20 to 10 us and by 5e-5 from 10 to 5 us (RK4 order 4: ratio ~16); 10 us keeps the
#: change two orders below the 0.5 % requirement and is 1/80 of a mesh period.
DEFAULT_STEP = 1e-5

MODELS = ("lta", "torsional", "seed")

#: Sane bounds of the time and rate options. They keep a run finite and its arrays in
#: memory; whether a run is affordable is decided by the cost check of
#: :func:`gearsim.dynamics.simulate`.
MIN_STEP = 1e-9  # s
MAX_STEP = 1.0  # s
MAX_DURATION = 1e4  # s
MAX_TRANSIENT = 1e4  # s
MAX_FS = 1e7  # Hz (10 MHz)
#: Ceiling of the bearing damping (the bearing stiffness is bounded by
#: :data:`gearsim.system.graph.MIN_BEARING_STIFFNESS` and ``MAX_BEARING_STIFFNESS``).
MAX_BEARING_DAMPING = 1e12  # N s/m
#: Largest load factor of a load profile: ten times the rated torque (a short-circuit
#: torque of a generator is 5-8 times rated); above, a unit or typing mistake.
MAX_LOAD_FACTOR = 10.0
#: Ceiling of backlash, profile modification, crowning, runout and assembly error [m]:
#: micrometre quantities; 10 mm means a unit mistake.
MAX_ERROR = 1e-2


def _number(v: object) -> bool:
    """A finite real number (not a bool)."""
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def _as_tuple(value: float | tuple | list | None) -> tuple[float, ...] | None:
    if value is None:
        return None
    if isinstance(value, (list, tuple)):
        return tuple(float(v) for v in value)
    return (float(value),)


@dataclass(frozen=True)
class DynamicsSettings:
    """Options of :func:`gearsim.dynamics.simulate`.

    Parameters
    ----------
    model
        ``"lta"`` (lateral-torsional-axial: x, y, z per shaft, rotations), ``"torsional"``
        (the rotations only) or ``"seed"`` (the seed's
        3-DOF translational model, eqs. 1-2, with the static load added).
    step
        Largest integration step [s]. The step used is the largest ``dt <= step`` with
        an integer number of steps per internal sample (``1 / (oversample fs)``).
    duration
        Length of the recorded window [s], after the transient.
    transient
        Simulated time dropped before recording [s]; ``None``: 12 time constants of
        the slowest-decaying mode of the mean linear system (at least one mesh period).
    fs
        Output sampling rate [Hz].
    oversample
        Internal recording rate / ``fs`` (integer >= 1). The internal samples are
        low-pass filtered (FIR) before decimation to ``fs`` (anti-aliasing); 1 gives
        instantaneous samples without filtering.
    bearing_stiffness, bearing_axial_stiffness
        Radial (x, y) and axial (z) stiffness of each gear's bearing support [N/m];
        axial ``None``: equal to the radial one.
    bearing_damping
        Bearing damping [N s/m]; ``None``: ``2 zeta_b sqrt(k_b m)`` per gear.
    bearing_damping_ratio
        zeta_b used when ``bearing_damping`` is ``None`` [-].
    mesh_damping_ratio
        zeta_m, ``c_m = 2 zeta_m sqrt(k_mean m_eq)`` [-].
    backlash
        Clearance 2b along the transverse line of action [m], one value or one per mesh;
        ``None``: the AGMA 2002 minimum normal backlash of each mesh converted to the
        transverse line of action. Set ``nonlinear = false`` for a linear mesh.
    nonlinear
        Backlash non-linearity (tooth separation, back-side contact) on or off. The
        seed model is always linear (as printed).
    idler_angle
        Angle between the centre lines at each idler [rad], measured at the idler in its
        sense of rotation from the line to the driving gear to the line to the driven
        gear; one value or one per idler; empty (default): 180 deg, centres on a straight
        line. Refused on a train without idlers (it would have no effect).
    profile_modification
        Amplitude of the mesh-frequency harmonic of the static transmission error
        caused by profile modification (tip relief) [m], one value or one per mesh.
    crowning
        Lead crowning height C_beta [m] (adds C_beta / 3 to the mean STE), one or per mesh.
    runout
        Eccentricity (runout) of each gear [m], one value or one per gear.
    runout_phase
        Angle of each gear's eccentricity at t = 0 [rad], one value or one per gear.
    assembly_error
        Constant STE of each mesh [m], one value or one per mesh.
    contact_mesh
        Run every mesh as a mesh of contacts (:mod:`gearsim.stiffness.contacts`), also
        those without faults or modifications; a mesh with faults, modifications or pitch
        errors always runs so.
    speed_times, speed_values
        Input speed profile: times [s] (>= 0, increasing, from the start of the run,
        transient included; where the speed changes, at least ``step`` apart) and speeds
        [rad/s] (>= 0, finite), linear between points and held outside (two points: a
        run-up or coast-down); ``None``: the operating speed throughout. The mesh-cycle
        coordinates follow the input shaft's angle.
    load_times, load_values
        Load profile: times [s] and factors on the operating torque (input and load
        torques alike, in [0, 10]), linear between points; ``None``: 1.
    """

    model: str = "lta"
    step: float = DEFAULT_STEP
    duration: float = 1.0
    transient: float | None = None
    fs: float = 50_000.0
    oversample: int = 2
    bearing_stiffness: float = 1.0e9
    bearing_axial_stiffness: float | None = None
    bearing_damping: float | None = None
    bearing_damping_ratio: float = 0.05
    mesh_damping_ratio: float = 0.07
    backlash: tuple[float, ...] | None = None
    nonlinear: bool = True
    idler_angle: tuple[float, ...] = ()
    profile_modification: tuple[float, ...] = (0.0,)
    crowning: tuple[float, ...] = (0.0,)
    runout: tuple[float, ...] = (0.0,)
    runout_phase: tuple[float, ...] = (0.0,)
    assembly_error: tuple[float, ...] = (0.0,)
    contact_mesh: bool = False
    speed_times: tuple[float, ...] | None = None
    speed_values: tuple[float, ...] | None = None
    load_times: tuple[float, ...] | None = None
    load_values: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for name in ("speed_times", "speed_values", "load_times", "load_values"):
            object.__setattr__(self, name, _as_tuple(getattr(self, name)))
        for kind, hi in (("speed", 1e5), ("load", MAX_LOAD_FACTOR)):
            times, vals = getattr(self, f"{kind}_times"), getattr(self, f"{kind}_values")
            p = f"dynamics.{kind}"
            require((times is None) == (vals is None), f"{p}_times", times,
                    f"give {kind}_times and {kind}_values together")
            if times is None:
                continue
            require(len(times) == len(vals) and len(times) >= 1, f"{p}_values", list(vals),
                    f"give one value per time ({len(times)})")
            require(all(_number(t) and 0 <= t <= MAX_DURATION for t in times), f"{p}_times",
                    list(times), f"must be finite times in [0, {MAX_DURATION:g}] s")
            require(all(b > a for a, b in zip(times, times[1:], strict=False)), f"{p}_times",
                    list(times), "must increase")
            require(all(_number(v) and 0 <= v <= hi for v in vals), f"{p}_values", list(vals),
                    f"must be finite and in [0, {hi:g}]" + (" rad/s" if kind == "speed" else ""))
        for name in ("backlash", "idler_angle", "profile_modification", "crowning",
                     "runout", "runout_phase", "assembly_error"):
            object.__setattr__(self, name, _as_tuple(getattr(self, name)))
        p = "dynamics"
        require(self.model in MODELS, f"{p}.model", self.model,
                'must be "lta", "torsional" or "seed"')
        require(self.model != "seed" or self.load_times is None, f"{p}.load_times",
                self.load_times and list(self.load_times),
                'needs model = "lta" or "torsional": the seed\'s 3-DOF model carries its load '
                "as a constant transmission-error offset, not as torques a profile could "
                "scale (docs/dynamics.md section 2)")
        require(_number(self.step) and MIN_STEP <= self.step <= MAX_STEP, f"{p}.step",
                self.step, f"must be a finite number in [{MIN_STEP:g}, {MAX_STEP:g}] s")
        t, w = self.speed_times or (), self.speed_values or ()
        for k in range(1, len(t)):  # a change of speed the integration step can follow
            require(t[k] - t[k - 1] >= self.step or w[k] == w[k - 1], f"{p}.speed_times[{k}]",
                    f"{t[k]:g} s", f"must be >= speed_times[{k - 1}] + dynamics.step = "
                    f"{t[k - 1] + self.step:g} s: the speed changes within less than one "
                    "integration step, an acceleration the run cannot follow (or write a smaller "
                    "[dynamics] step)")
        require(_number(self.duration) and 0 < self.duration <= MAX_DURATION,
                f"{p}.duration", self.duration,
                f"must be a finite number in (0, {MAX_DURATION:g}] s")
        require(self.transient is None
                or (_number(self.transient) and 0 <= self.transient <= MAX_TRANSIENT),
                f"{p}.transient", self.transient,
                f"must be a finite number >= 0 s (0: no transient) and <= {MAX_TRANSIENT:g} s")
        require(_number(self.fs) and 0 < self.fs <= MAX_FS, f"{p}.fs", self.fs,
                f"must be a finite number in (0, {MAX_FS:g}] Hz")
        require(isinstance(self.oversample, int) and not isinstance(self.oversample, bool)
                and 1 <= self.oversample <= 64,
                f"{p}.oversample", self.oversample, "must be an integer in [1, 64]")
        for name in ("bearing_stiffness", "bearing_axial_stiffness"):
            v = getattr(self, name)
            require((v is None and name != "bearing_stiffness")
                    or (_number(v) and MIN_BEARING_STIFFNESS <= v <= MAX_BEARING_STIFFNESS),
                    f"{p}.{name}", v, f"must be a finite number in [{MIN_BEARING_STIFFNESS:g}, "
                    f"{MAX_BEARING_STIFFNESS:g}] N/m")
        require(self.bearing_damping is None
                or (_number(self.bearing_damping)
                    and 0 <= self.bearing_damping <= MAX_BEARING_DAMPING),
                f"{p}.bearing_damping", self.bearing_damping,
                f"must be a finite number in [0, {MAX_BEARING_DAMPING:g}] N*s/m")
        require(isinstance(self.contact_mesh, bool), f"{p}.contact_mesh", self.contact_mesh,
                "must be true or false")
        require(isinstance(self.nonlinear, bool), f"{p}.nonlinear", self.nonlinear,
                "must be true or false")
        require(_number(self.bearing_damping_ratio) and 0 <= self.bearing_damping_ratio < 1,
                f"{p}.bearing_damping_ratio", self.bearing_damping_ratio, "must be in [0, 1)")
        require(_number(self.mesh_damping_ratio) and 0 <= self.mesh_damping_ratio < 1,
                f"{p}.mesh_damping_ratio", self.mesh_damping_ratio, "must be in [0, 1)")
        require(all(_number(a) and 0 < a < 2 * math.pi for a in self.idler_angle),
                f"{p}.idler_angle", self.idler_angle, "must be in (0, 360) deg")
        require(all(_number(a) for a in self.runout_phase), f"{p}.runout_phase",
                self.runout_phase, "must be finite angles (rad)")
        for name in ("backlash", "profile_modification", "crowning", "runout"):
            vals = getattr(self, name)
            if vals is None:
                continue
            require(all(_number(v) and 0 <= v <= MAX_ERROR for v in vals), f"{p}.{name}",
                    vals, f"must be finite, >= 0 m and <= {MAX_ERROR:g} m (plain numbers "
                    "are metres)")
        require(all(_number(v) and abs(v) <= MAX_ERROR for v in self.assembly_error),
                f"{p}.assembly_error", self.assembly_error,
                f"must be finite with |e| <= {MAX_ERROR:g} m (plain numbers are metres)")

    def profiles(self, speed: float) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Segments of the nominal time and the load points for the kernel.

        With the speed omega(t) linear between the given points, tau' = omega / omega_ref
        and tau(t) = integral of tau' (exact, quadratic on each segment); a constant
        segment from t = 0 to the first point and after the last.

        Parameters
        ----------
        speed : float
            Reference (operating) speed omega_ref [rad/s].

        Returns
        -------
        profile : ndarray, shape (n_seg, 4), or None
            (t_k, tau_k, tau'_k, tau''_k) (:attr:`DynamicModel.profile`); None: constant.
        load : ndarray, shape (n, 2), or None
            (t, lambda) points; None: 1.

        Examples
        --------
        A run-up from 0.5 to 1.5 times the reference speed over 2 s: tau(2) = 2 s.

        >>> st = DynamicsSettings(speed_times=(0.0, 2.0), speed_values=(50.0, 150.0))
        >>> prof, _ = st.profiles(100.0)
        >>> prof.tolist()
        [[0.0, 0.0, 0.5, 0.5], [2.0, 2.0, 1.5, 0.0]]
        """
        prof = None
        if self.speed_times is not None:
            t = np.array(self.speed_times)
            w = np.array(self.speed_values) / speed
            rows = [] if t[0] == 0.0 else [[0.0, 0.0, w[0], 0.0]]
            tau = w[0] * t[0]
            for k in range(t.size):
                acc = (w[k + 1] - w[k]) / (t[k + 1] - t[k]) if k + 1 < t.size else 0.0
                rows.append([t[k], tau, w[k], acc])
                if k + 1 < t.size:
                    d = t[k + 1] - t[k]
                    tau += w[k] * d + 0.5 * acc * d * d
            prof = np.array(rows)
        load = None if self.load_times is None else np.stack(
            [np.array(self.load_times), np.array(self.load_values)], axis=1)
        return prof, load

    def per_item(self, name: str, count: int, what: str) -> tuple[float, ...]:
        """The option ``name`` as one value per item (mesh, gear or idler).

        Parameters
        ----------
        name : str
            A tuple-valued option, e.g. ``"runout"`` or ``"idler_angle"``.
        count : int
            Number of items (meshes, gears or idlers of the train).
        what : str
            Item kind for the error message (``"mesh"``, ``"gear"``, ``"idler"``).

        Returns
        -------
        tuple of float
            ``count`` values (SI): a single given value repeated, else the values given.

        Raises
        ------
        InputError
            (parameter ``dynamics.<name>``) if more than one value is given and their
            number is not ``count``, or values are given for no item (``count`` 0).
        """
        vals = getattr(self, name) or ((math.pi,) if name == "idler_angle" else ())
        if count == 0 and getattr(self, name):
            shown = [f"{math.degrees(v):.6g} deg" for v in vals] if what == "idler" else list(vals)
            raise InputError(f"dynamics.{name}", shown, f"the train has no {what}: "
                             "the option would have no effect, leave it out")
        if len(vals) == 1:
            return vals * count
        if len(vals) != count:
            raise InputError(f"dynamics.{name}", list(vals),
                             f"give one value or {count} (one per {what})")
        return vals

    @property
    def output_interval(self) -> float:
        """1 / fs [s]."""
        return 1.0 / self.fs

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of the options (SI numbers), for the results file."""
        out: dict[str, Any] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None or (isinstance(v, tuple) and not v):
                continue
            out[f.name] = list(v) if isinstance(v, tuple) else v
        return out


KEYS = {
    "model": "str", "step": "time", "duration": "time", "transient": "time",
    "fs": "frequency", "oversample": "int", "bearing_stiffness": "stiffness",
    "bearing_axial_stiffness": "stiffness", "bearing_damping": "damping",
    "bearing_damping_ratio": "dimensionless", "mesh_damping_ratio": "dimensionless",
    "backlash": "length", "nonlinear": "bool", "idler_angle": "angle",
    "profile_modification": "length", "crowning": "length", "runout": "length",
    "runout_phase": "angle", "assembly_error": "length", "contact_mesh": "bool",
    "speed_times": "time", "speed_values": "speed", "load_times": "time",
    "load_values": "dimensionless",
}
LIST_KEYS = ("backlash", "idler_angle", "profile_modification", "crowning", "runout",
             "runout_phase", "assembly_error", "speed_times", "speed_values", "load_times",
             "load_values")


def parse_dynamics(table: Any, section: str = "dynamics") -> DynamicsSettings:
    """Parse the ``[dynamics]`` table (values with units) into :class:`DynamicsSettings`.

    Parameters
    ----------
    table : dict
        The TOML table.
    section : str, optional
        Its name, for messages.

    Returns
    -------
    DynamicsSettings

    Raises
    ------
    InputError
        Unknown key, bad value or a value out of range.
    """
    kw = convert(table, KEYS, section, list_keys=LIST_KEYS)
    with as_written(table, "dynamics"):
        return DynamicsSettings(**kw)
