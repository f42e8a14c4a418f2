"""Parameter studies on a planetary stage: checks, case building and one simulation group.

A study whose ``config`` has a ``[stage]`` section (a
:class:`gearsim.model.planetary.PlanetaryBox`) runs through the same study file, case
list, Dask runner and store as a gear-train study (:mod:`gearsim.studies.sweep`,
:mod:`gearsim.studies.sweep_run`); this module holds what differs.

Parameters of a stage study:

* ``crack_depth``, ``flank``: replace the depth and the flank of the base stage's first
  crack (:func:`dataclasses.replace` on the :class:`~gearsim.stiffness.crack.Crack`; the
  other cracks are kept); ``flank = "none"`` removes every crack. A cracked value needs a
  crack in the base stage (it names the gear and tooth) and computed tables for the
  mesh of the cracked gear (a constant ``stage.sun_mesh_stiffness`` and
  ``stage.ring_mesh_stiffness`` leave a crack without effect and are refused).
* ``speed``, ``torque``: of the input member (``operating.input``).
* ``bearing_stiffness``: :attr:`DynamicsSettings.bearing_stiffness`, which the stage uses
  for the members without a bearing of their own in ``[members]`` (a study where every
  member has its own is refused: the parameter would change nothing).
* ``noise``: as for gear trains.
* ``fault``, ``severity``, ``closure``: refused (the fault variants and the crack-face
  closure switch are gear-train features).

Signals (:func:`stage_signal_choices`): ``sensor`` (the fixed transducer, the default),
``mesh_force[sun-planet-1]``, ``mesh_force[ring-planet-1]``, ... for every mesh, and
``ring_acceleration[x]``, ``ring_acceleration[y]``.

**Analysis.** Each case's record goes through :func:`gearsim.signals.analyze`, as a
gear-train case's does, with the stage's ``[analysis]`` settings. The analysis wants one
reference shaft ``f_r1`` and tooth counts with ``f_m = f_r1 Z_1``
(:func:`gearsim.signals.analysis.kinematics`). For a stage (:func:`stage_reference`):

* ring held (the usual case): the carrier, ``f_r1 = |f_c|``, ``Z_1 = z_r``
  (``f_m = z_r f_c``);
* sun held: the carrier, ``Z_1 = z_s`` (``f_m = z_s f_c``);
* carrier held (a star stage, ``f_c = 0``): the ring, ``f_r1 = |f_r|``, ``Z_1 = z_r``.

With ``shafts = "all"`` the other members follow, ``Z_2, Z_3`` (ring held: ``z_s``,
``z_p``), so that the analysis' "shafts" ``f_m / Z_j`` are the rotations of the sun and
of a planet relative to the carrier (the tooth-fault periods of sun and planet); with
``shafts = "reference"`` only the reference. The time-synchronous average is therefore
over carrier revolutions (a planet-separated average is not made here).

**Checks before any case** (:func:`check_stage_study`): the dynamics overrides (the
stage's settings, which check them; ``model`` is refused), the signal, each speed,
torque and bearing stiffness as the stage checks them, each crack depth on each cracked
flank of the study (it must fit the sun or planet tooth,
:func:`gearsim.stiffness.crack.crack_geometry`), the recorded duration (at least one
revolution of the reference member, the carrier, at the lowest speed, and what the
analysis needs there: two reference revolutions for the time-synchronous average and
the frequency resolution of the sidebands) and the sampling rate (above twice the
highest analysed mesh harmonic and the highest sideband, at the highest speed).
"""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from gearsim.errors import InputError, require

if TYPE_CHECKING:
    from gearsim.dynamics.settings import DynamicsSettings
    from gearsim.dynamics.stage import StageDynamics
    from gearsim.model.planetary import PlanetaryBox
    from gearsim.studies.sweep import Case, Study
    from gearsim.system.planetary import PlanetaryTrain

__all__ = ["STAGE_REFUSED", "build_stage_case", "check_stage_study", "config_kind",
           "run_stage_group", "stage_base_values", "stage_reference", "stage_signal_choices",
           "stage_signal_key"]

#: Study parameters a planetary stage does not take, with the reason given.
STAGE_REFUSED = {
    "fault": "the fault classes are variants of a gear train; a planetary stage is varied "
             "through its first crack (flank, crack_depth)",
    "severity": "sizes the gear-train fault classes, which a planetary stage study does "
                "not vary (its [[faults]] stay as configured; vary crack_depth instead)",
    "closure": "the crack-face closure switch is not varied for a planetary stage (set "
               "[stiffness] closure in the stage configuration)",
}
_SPEC = re.compile(r"\s*(\w+)\s*(?:\[\s*([\w-]+)\s*\])?\s*")


def config_kind(config_text: str) -> str:
    """Kind of a configuration text: ``"planetary"`` with a ``[stage]`` section, else ``"train"``.

    Parameters
    ----------
    config_text : str
        TOML text of a configuration (invalid TOML counts as ``"train"``; reading it
        later names the error).

    Returns
    -------
    str
        ``"planetary"`` or ``"train"``, as :func:`gearsim.model.config.parse` decides.

    Examples
    --------
    >>> from gearsim.model.config import example_text
    >>> config_kind(example_text("nrel-grc")), config_kind(example_text("idler-table1"))
    ('planetary', 'train')
    """
    try:
        doc = tomllib.loads(config_text)
    except tomllib.TOMLDecodeError:
        return "train"
    return "planetary" if "stage" in doc else "train"


def stage_signal_choices(box: PlanetaryBox) -> list[str]:
    """The records a stage study can analyse: what :func:`simulate_stage` produces.

    Parameters
    ----------
    box : gearsim.model.planetary.PlanetaryBox
        The base stage.

    Returns
    -------
    list of str
        ``sensor``, then ``mesh_force[sun-planet-1]``, ``mesh_force[ring-planet-1]``, ...
        for every planet, then ``ring_acceleration[x]`` and ``ring_acceleration[y]``.

    Examples
    --------
    >>> from gearsim.model import load
    >>> names = stage_signal_choices(load("nrel-grc"))
    >>> names[:3], len(names)
    (['sensor', 'mesh_force[sun-planet-1]', 'mesh_force[ring-planet-1]'], 9)
    """
    from gearsim.system.planetary import planet_name

    out = ["sensor"]
    for j in range(box.train.stage.planets):
        out += [f"mesh_force[{m}-{planet_name(j)}]" for m in ("sun", "ring")]
    return out + [f"ring_acceleration[{a}]" for a in ("x", "y")]


def stage_signal_key(spec: str) -> str | None:
    """``spec`` normalised as in :func:`stage_signal_choices` (``None``: not of that form).

    Parameters
    ----------
    spec : str
        Signal as written, e.g. ``" mesh_force[ sun-planet-1 ]"``.

    Returns
    -------
    str or None
        ``variable`` or ``variable[label]`` without blanks.
    """
    m = _SPEC.fullmatch(spec)
    if m is None:
        return None
    return m.group(1) if m.group(2) is None else f"{m.group(1)}[{m.group(2)}]"


def stage_reference(train: PlanetaryTrain, shafts: str = "all") -> tuple[str, float, list[int]]:
    """Reference member, its frequency and the tooth counts the analysis is given.

    Parameters
    ----------
    train : gearsim.system.planetary.PlanetaryTrain
        The stage at the case's operating point.
    shafts : {"all", "reference"}
        ``"all"``: the reference's tooth count, then those of the other two members;
        ``"reference"``: the reference's only.

    Returns
    -------
    member : str
        ``"carrier"`` (ring or sun held) or ``"ring"`` (carrier held).
    frequency : float
        Its speed [Hz] (absolute value), ``f_r1`` of the analysis.
    teeth : list of int
        ``Z_1`` with ``f_m = f_r1 Z_1`` (ring held: z_r; sun held: z_s; carrier held:
        z_r), then (``shafts = "all"``) the other tooth counts, so that ``f_m / Z_j`` are
        the member rotations relative to the carrier.

    Examples
    --------
    >>> from gearsim.model import load
    >>> tr = load("nrel-grc").train
    >>> member, f, teeth = stage_reference(tr)
    >>> member, round(f * teeth[0], 6) == round(tr.mesh_frequency, 6), teeth
    ('carrier', True, [99, 21, 39])
    """
    st = train.stage
    zs, zp, zr = st.sun_teeth, st.planet_teeth, st.ring_teeth
    fixed = train.operating.fixed
    if fixed == "carrier":
        member, teeth = "ring", [zr, zs, zp]
    elif fixed == "sun":
        member, teeth = "carrier", [zs, zr, zp]
    else:
        member, teeth = "carrier", [zr, zs, zp]
    freq = abs(train.speeds[member]) / (2.0 * math.pi)
    return member, freq, teeth[:1] if shafts == "reference" else teeth


def _box(study: Study) -> PlanetaryBox:
    from gearsim.model import loads

    return loads(study.config_text)


def _settings(box: PlanetaryBox, overrides: dict[str, Any]) -> DynamicsSettings:
    """The stage's dynamics settings with the study's overrides (checked; ``study.`` names)."""
    for key, value in overrides.items():
        if isinstance(value, float):
            require(math.isfinite(value), f"study.dynamics.{key}", value, "must be finite")
    if "model" in overrides:
        raise InputError("study.dynamics.model", overrides["model"],
                         "a planetary stage has one model (Lin & Parker 1999 with "
                         "time-varying meshes): leave it out")
    try:
        return dataclasses.replace(box.dynamics, **overrides)
    except InputError as exc:
        name = exc.parameter
        raise InputError("study." + name if name.startswith("dynamics.") else name,
                         exc.value, exc.limit) from None


def _first_crack(train: PlanetaryTrain, flank: str, depth: float | None):
    """The cracks of ``train`` with the first one moved to ``flank`` and ``depth``."""
    if flank == "none":
        return ()
    first = dataclasses.replace(train.cracks[0], flank=flank,
                                **({} if depth is None else {"depth": depth}))
    return (first, *train.cracks[1:])


def _crack_fits(train: PlanetaryTrain, crack) -> None:
    """Refuse a crack that does not fit its (sun or planet) tooth."""
    from gearsim.geometry.profile import ToothProfile
    from gearsim.stiffness.crack import crack_geometry

    st = train.stage
    gear = st.sun if crack.gear == "sun" else st.planet
    crack_geometry(ToothProfile(gear), crack)


def _operating(train: PlanetaryTrain, speed: float, torque: float) -> PlanetaryTrain:
    from gearsim.system.planetary import StageOperating

    op = train.operating
    return dataclasses.replace(train, operating=StageOperating(
        fixed=op.fixed, input=op.input, speed=speed, torque=torque))


def check_stage_study(study: Study, box: PlanetaryBox) -> None:
    """Check every study-wide setting of a stage study once, before any case runs.

    Called by :func:`gearsim.studies.sweep.check_study` for a stage configuration; the
    checks are listed in the module docstring.

    Parameters
    ----------
    study : Study
        The parsed study.
    box : gearsim.model.planetary.PlanetaryBox
        Its base stage.

    Raises
    ------
    InputError
        Naming the study key or parameter value (``parameters.fault``,
        ``study.signal``, ``parameters.crack_depth[1]``, ``study.dynamics.fs``, ...).
    """
    from gearsim.studies.sweep import _points, _raw_parameter

    if box.chain is not None:
        raise InputError("study.config", "[chain]", "a sweep runs a stage alone: remove the "
                         "[chain] of the stage (a stage driving a chain is simulated by "
                         "gearsim simulate)")
    for name, why in STAGE_REFUSED.items():
        if name in study.parameters:
            raise InputError(f"parameters.{name}", _raw_parameter(study, name),
                             f"not a parameter of a planetary stage: {why}")
    settings = _settings(box, study.dynamics)
    choices = stage_signal_choices(box)
    if stage_signal_key(study.signal) not in choices:
        raise InputError("study.signal", study.signal,
                         "not a signal of a planetary stage; give one of " + ", ".join(choices))
    train = box.train
    op = train.operating
    speeds = (_points(study, "speed") if "speed" in study.parameters
              else [("operating.speed", op.speed, op.speed)])
    torques = (_points(study, "torque") if "torque" in study.parameters
               else [("operating.torque", op.torque, op.torque)])
    for points, which in ((speeds, "speed"), (torques, "torque")):
        for where, raw, value in points:
            kw = {"speed": op.speed, "torque": op.torque, which: value}
            try:
                _operating(train, **kw)
            except InputError as exc:
                raise InputError(where, raw, exc.limit) from None
    if "bearing_stiffness" in study.parameters:
        own = box.members.bearings
        if all(m in own for m in ("sun", "planet", "ring", "carrier")):
            raise InputError("parameters.bearing_stiffness",
                             _raw_parameter(study, "bearing_stiffness"),
                             "changes nothing: every member of the stage has its own bearing "
                             "stiffness in [members] (remove some to let the study set them)")
        for where, raw, value in _points(study, "bearing_stiffness"):
            try:
                dataclasses.replace(settings, bearing_stiffness=value)
            except InputError as exc:
                raise InputError(where, raw, exc.limit) from None
    _check_cracks(study, train)
    _check_record(study, box, settings, speeds)


def _check_cracks(study: Study, train: PlanetaryTrain) -> None:
    from gearsim.studies.sweep import _points, _raw_parameter

    flanks = study.parameters.get("flank")
    if flanks is None:
        flanks = (train.cracks[0].flank,) if train.cracks else ("none",)
    cracked = [f for f in dict.fromkeys(flanks) if f != "none"]
    varied = "crack_depth" in study.parameters or "flank" in study.parameters
    if not varied:  # the base cracks in every case: each must fit its tooth
        for i, c in enumerate(train.cracks):
            try:
                _crack_fits(train, c)
            except InputError as exc:
                raise InputError(f"cracks[{i}].depth ({c.gear})", f"{c.depth * 1e3:.6g} mm",
                                 exc.limit) from None
        return
    if not train.cracks:
        if cracked or "crack_depth" in study.parameters:
            name = "flank" if cracked and "flank" in study.parameters else "crack_depth"
            raise InputError(f"parameters.{name}", _raw_parameter(study, name),
                             "the base stage has no crack to vary: give one in [[cracks]] "
                             "(gear = sun or planet-n, tooth, flank, depth)")
        return
    crack = train.cracks[0]
    planet = crack.gear.startswith("planet-")
    const = (train.sun_mesh_stiffness is not None
             and (not planet or train.ring_mesh_stiffness is not None))
    if const:
        name = "crack_depth" if "crack_depth" in study.parameters else "flank"
        raise InputError(f"parameters.{name}", _raw_parameter(study, name),
                         f"changes nothing: the meshes of {crack.gear} have constant "
                         "stiffnesses (stage.sun_mesh_stiffness, stage.ring_mesh_stiffness); "
                         "leave them out to compute the tables, which see the crack")
    depths = (_points(study, "crack_depth") if "crack_depth" in study.parameters
              else [(f"cracks[0].depth ({crack.gear})", crack.depth, crack.depth)])
    for flank in cracked:
        for where, raw, value in depths:
            try:
                (c, *_) = _first_crack(train, flank, value)
                _crack_fits(train, c)
            except InputError as exc:
                raise InputError(where, raw, f"{exc.limit} (crack on {crack.gear} tooth "
                                 f"{crack.tooth}, flank {flank})") from None


def _check_record(study: Study, box: PlanetaryBox, settings: DynamicsSettings,
                  speeds: list) -> None:
    """Duration at the lowest speed, sampling rate at the highest (module docstring)."""
    from gearsim.signals._checks import WINDOWS
    from gearsim.signals.analysis import kinematics

    train, opt = box.train, box.analysis
    op = train.operating
    lo = min(v for _, _, v in speeds)
    hi = max(v for _, _, v in speeds)
    rpm = 30.0 / math.pi
    slow = _operating(train, lo, op.torque)
    member, f_ref, teeth = stage_reference(slow, study.shafts)
    t_rev = 1.0 / f_ref
    duration = settings.duration
    if duration < t_rev * (1 - 1e-9):
        raise InputError("study.dynamics.duration", f"{duration:g} s",
                         f"must be >= {t_rev:.6g} s (one revolution of the {member} at the "
                         f"lowest speed of the study, {lo * rpm:.6g} rpm of the {op.input})")
    kin = kinematics(shaft_frequency=f_ref, teeth=teeth)
    need = max(2.0 / f_ref, 2 * WINDOWS[opt.window] / min(kin.shafts.values()))
    if duration < need * (1 - 1e-9):
        raise InputError("study.dynamics.duration", f"{duration:g} s",
                         f"must be >= {need:.6g} s for the analysis at the lowest speed of the "
                         f"study ({lo * rpm:.6g} rpm of the {op.input}): the longer of two "
                         f"revolutions of the {member} (time-synchronous average) and "
                         f"{2 * WINDOWS[opt.window]} {opt.window} bins per sideband spacing "
                         "(frequency resolution)")
    fast = _operating(train, hi, op.torque)
    f_m = fast.mesh_frequency
    n = max(opt.orders)
    which = "the mesh frequency f_m" if n == 1 else f"the highest analysed mesh harmonic {n} f_m"
    if not settings.fs > 2.0 * n * f_m:
        raise InputError("study.dynamics.fs", settings.fs,
                         f"must be > {2 * n * f_m:.6g} Hz, twice {which} = {n * f_m:.6g} Hz at "
                         f"the highest speed of the study ({hi * rpm:.6g} rpm of the "
                         f"{op.input}), else the record is aliased")
    _, f_fast, teeth = stage_reference(fast, study.shafts)
    kin = kinematics(shaft_frequency=f_fast, teeth=teeth)
    f_top = n * f_m + opt.n_sidebands * max(kin.shafts.values())
    if not settings.fs > 2.0 * f_top:
        raise InputError("study.dynamics.fs", settings.fs,
                         f"must be > {2 * f_top:.6g} Hz, twice the highest line the analysis "
                         f"reads ({n} f_m with {opt.n_sidebands} sidebands, {f_top:.6g} Hz) at "
                         f"the highest speed of the study ({hi * rpm:.6g} rpm of the "
                         f"{op.input})")


def stage_base_values(study: Study) -> dict[str, tuple]:
    """Value of each study parameter a stage study does not vary (the base stage's).

    Parameters
    ----------
    study : Study
        A study whose configuration is a planetary stage.

    Returns
    -------
    dict of str to tuple
        Parameter -> one-value tuple: the first crack's depth and flank (``0``,
        ``"none"`` without cracks), the stiffness closure, the input member's speed and
        torque, the dynamics bearing stiffness, noise 0; ``fault`` and ``severity``
        ``None``.
    """
    box = _box(study)
    train = box.train
    depth = train.cracks[0].depth if train.cracks else 0.0
    flank = train.cracks[0].flank if train.cracks else "none"
    return {"crack_depth": (depth,), "flank": (flank,), "fault": (None,),
            "severity": (None,), "closure": (train.settings.closure,),
            "speed": (train.operating.speed,), "torque": (train.operating.torque,),
            "bearing_stiffness": (box.dynamics.bearing_stiffness,), "noise": (0.0,)}


def build_stage_case(study: Study, case: Case
                     ) -> tuple[PlanetaryTrain, StageDynamics, DynamicsSettings, PlanetaryBox]:
    """Stage, members, dynamics settings and base box of a case.

    Parameters
    ----------
    study : Study
        The study (base stage and dynamics overrides).
    case : Case
        The case (first crack's flank and depth, input speed and torque, bearing
        stiffness).

    Returns
    -------
    train : gearsim.system.planetary.PlanetaryTrain
        The base stage at the case's operating point, its first crack moved to the case's
        flank and depth (``"none"``: no cracks), checked to fit its tooth.
    members : gearsim.dynamics.stage.StageDynamics
        The base stage's members (their own bearings kept).
    settings : gearsim.dynamics.settings.DynamicsSettings
        The stage's settings with the study's overrides and the case's bearing stiffness.
    box : gearsim.model.planetary.PlanetaryBox
        The base stage as read (its analysis settings).

    Raises
    ------
    InputError
        A crack that does not fit, a setting out of range.
    """
    box = _box(study)
    train = _operating(box.train, case.speed, case.torque)
    if train.cracks or case.flank != "none":
        if not train.cracks:
            raise InputError("flank", case.flank, "the base stage has no crack to move")
        depth = None if case.flank == "none" else case.crack_depth
        cracks = _first_crack(train, case.flank, depth)
        for c in cracks:
            _crack_fits(train, c)
        train = dataclasses.replace(train, cracks=cracks)
    settings = dataclasses.replace(_settings(box, study.dynamics),
                                   bearing_stiffness=case.bearing_stiffness)
    return train, box.members, settings, box


def _select(ds, spec: str) -> np.ndarray:
    m = _SPEC.fullmatch(spec)
    if m is None or m.group(1) not in ("sensor", "mesh_force", "ring_acceleration"):
        raise InputError("study.signal", spec, "must name a signal of a planetary stage")
    da = ds[m.group(1)]
    dim = {"mesh_force": "mesh", "ring_acceleration": "axis"}.get(m.group(1))
    try:
        da = da.sel({dim: m.group(2)}) if dim and m.group(2) else da
    except (KeyError, ValueError):
        raise InputError("study.signal", spec, "mesh or axis not in the simulation") from None
    if da.ndim != 1:
        raise InputError("study.signal", spec, "select one mesh or axis: variable[label]")
    return np.asarray(da.values, dtype=float)


def run_stage_group(study: Study, cases: Sequence[Case],
                    hook: Callable[[Sequence[Case]], None] | None = None):
    """Simulate a stage once and analyse every case of a simulation group.

    The counterpart of :func:`gearsim.studies.sweep_case.run_group` (same table: one
    row per case, parameters as coordinates, ``status``, ``error``, one variable per
    feature of :func:`gearsim.studies.sweep_case.features`).

    Parameters
    ----------
    study : Study
        A study whose configuration is a planetary stage.
    cases : sequence of Case
        Cases with equal :meth:`Study.simulation_key` (they differ in noise/replicate).
    hook : callable, optional
        Called with ``cases`` before the work (tests use it to inject faults).

    Returns
    -------
    xarray.Dataset
        One row per case along ``case``; refused input and failed simulations are
        recorded (status, message), not raised.
    """
    from gearsim.dynamics.stage import simulate_stage
    from gearsim.studies.sweep_case import analyse_group

    def record() -> tuple[np.ndarray, float, dict]:
        train, members, settings, box = build_stage_case(study, cases[0])
        ds = simulate_stage(train, members, settings)
        _, f_ref, teeth = stage_reference(train, study.shafts)
        return (_select(ds, study.signal), float(settings.fs),
                {"teeth": teeth, "shaft_frequency": f_ref, "settings": box.analysis})

    return analyse_group(study, cases, record, hook)
