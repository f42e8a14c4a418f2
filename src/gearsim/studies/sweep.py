"""Parameter-study definitions: the study TOML file, parsed and expanded into cases.

A study varies the crack (depth, flank) or the fault (class, severity), the closure model
of the crack faces, the operating point (speed, torque), the bearing stiffness and the
measurement noise of one base gear train, on a full grid or by seeded random sampling.
Layout::

    [study]
    name = "my study"
    config = "idler-table1"     # base train: built-in example name or TOML path
    sampling = "grid"           # or "random" (then give samples = N)
    seed = 1                    # random sampling and measurement noise
    replicates = 2              # noise realisations per case
    signal = "acceleration[input,y]"   # analysed record: variable[shaft,axis] or e.g. mesh_force_1
    shafts = "all"              # sidebands of every shaft, or "reference" (input shaft only)
    store_signals = false       # also keep the noisy analysed records in the store

    [study.dynamics]            # overrides of the base train's [dynamics] section
    duration = "0.5 s"
    fs = "20 kHz"

    [parameters]                # each: a list of values, or a range table
    crack_depth = ["0.5 mm", "1 mm", "2 mm"]
    flank = ["none", "working", "non-working"]
    # or, instead of crack_depth and flank, the fault classes of gearsim.model.variants:
    # fault = ["none", "spall", "broken"]   # FAULT_CLASSES
    # severity = [0.5, 1.0]                 # fraction of each class's reference size
    # gear = ["input-pinion", "intermediate-pinion"]   # the faulty gear (default: input)
    closure = ["contact"]
    speed = { min = "1200 rpm", max = "1900 rpm", num = 3 }   # grid: linspace
    torque = ["2000 N*m", "4876 N*m"]
    bearing_stiffness = ["1e9 N/m"]
    "bearing_stiffness[idler]" = ["2e8 N/m"]   # one shaft's bearings only (a quoted key)
    noise = [0.0, 0.5, 1.0]     # noise RMS / RMS of the noise-free dynamic record

Parameters not given take the base train's value (noise: 0; severity: 1). Plain numbers
are SI. A study with ``fault`` builds each case's train with
:func:`gearsim.model.variants.fault_variant` (one fault on tooth 0 of the input gear, the
base train's cracks and faults removed, every class on the contact-mesh path); it may not
also give ``flank`` or ``crack_depth`` (its cases have ``flank = "none"`` and
``crack_depth = 0``), and ``severity`` and ``gear`` (the faulty gear, any gear of the
train by name; default the input gear) need ``fault``. With
``sampling = "random"`` a list is sampled uniformly and a range ``{min, max}`` uniformly
in value (``log = true``: in logarithm). Unknown keys, empty lists and empty ranges are
refused with :class:`gearsim.errors.InputError`.

Every study-wide setting is checked once, when the file is read (:func:`check_study`),
so that a bad one is refused before any case runs rather than failing every case: the
dynamics overrides (applied to the base train's settings, which check them), the
analysed signal (a variable the simulation produces), every parameter value (noise
>= 0, speed, torque and bearing stiffness > 0, severity in (0, 1], all finite; each crack
depth fits the tooth on each cracked flank of the study; each fault class at each
severity end makes a valid train), the recorded duration (at least one
revolution of the slowest shaft at the lowest speed), a study that varies nothing, and
the number of cases (at most :data:`MAX_CASES`, or ``study.max_cases``).

Every gearbox runs through the same study: the parameters address it through
:class:`gearsim.model.Gearbox` (:meth:`~gearsim.model.Gearbox.with_crack` moves its
cracks, :meth:`~gearsim.model.Gearbox.at` sets the input's speed and torque, the
signals are :meth:`~gearsim.model.Gearbox.signals`, the default
:attr:`~gearsim.model.Gearbox.default_signal`: the input bearing's y acceleration of a
gear train, the ring sensor of a planetary stage; the
analysis' reference shaft and tooth counts are :meth:`~gearsim.model.Gearbox.reference`:
the carrier of a stage with its ring held). The fault classes are refused for a stage
(:func:`gearsim.model.variants.fault_variant`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import itertools
import json
import math
import re
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from gearsim.errors import InputError, require
from gearsim.model import Gearbox, loads
from gearsim.model.config import EXAMPLES, example_text, read_file_or_builtin
from gearsim.model.variants import FAULT_CLASSES, fault_gears, fault_variant
from gearsim.sections import convert
from gearsim.stiffness.settings import CLOSURES
from gearsim.system.train import CRACK_CHOICES
from gearsim.units import to_si

__all__ = ["BUILTIN_STUDIES", "MAX_CASES", "PARAMETERS", "Case", "Study", "builtin_study_text",
           "case_count", "check_study", "expand", "load_study", "loads_study",
           "simulation_params"]

#: Built-in studies in ``gearsim/data/studies``.
BUILTIN_STUDIES = ("diagnostic", "faults")

#: Study parameter -> quantity kind (see :data:`gearsim.units.DIMENSIONS`) or choices.
PARAMETERS: dict[str, str | tuple[str, ...]] = {
    "crack_depth": "length",
    "flank": CRACK_CHOICES,
    "fault": FAULT_CLASSES,
    "severity": "dimensionless",
    "gear": "name",
    "closure": CLOSURES,
    "speed": "speed",
    "torque": "torque",
    "bearing_stiffness": "stiffness",
    "noise": "dimensionless",
}
#: A parameter of one shaft's bearings, ``bearing_stiffness[SHAFT]`` (a name of
#: :meth:`gearsim.model.Gearbox.bearing_names`): the radial stiffness [N/m] of that shaft's
#: bearings only, a quoted key of ``[parameters]``.
NAMED_BEARING = re.compile(r"bearing_stiffness\[([\w.-]+)\]")
STUDY_KEYS = ("name", "config", "sampling", "samples", "seed", "replicates", "signal",
              "shafts", "store_signals", "max_cases", "dynamics")
#: Largest number of cases a study may have unless its ``study.max_cases`` allows more.
MAX_CASES = 100_000
#: Parameter -> (lowest value, whether the lowest value itself is allowed, unit shown).
LOWER_BOUNDS = {"crack_depth": (0.0, True, "m"), "speed": (0.0, False, "rad/s"),
                "torque": (0.0, False, "N*m"), "bearing_stiffness": (0.0, False, "N/m"),
                "noise": (0.0, True, ""), "severity": (0.0, False, "")}
#: Parameter -> highest value (allowed itself).
UPPER_BOUNDS = {"severity": 1.0}
#: Parameters of the crack route that a study with ``fault`` may not give.
CRACK_ONLY = ("flank", "crack_depth")
DYNAMICS_OVERRIDES = {"duration": "time", "fs": "frequency", "transient": "time",
                      "step": "time", "model": "str"}


@dataclass(frozen=True)
class Case:
    """One analysed record of a study (SI units).

    Parameters
    ----------
    index : int
        Position in the study's case list.
    crack_depth : float
        Crack depth [m]; for ``flank == "none"`` the nominal depth of the grid cell (no
        crack is modelled).
    flank : str
        ``"none"``, ``"working"`` or ``"non-working"``.
    closure : str
        ``"open"`` or ``"contact"``.
    speed, torque, bearing_stiffness : float
        Input speed [rad/s], input torque [N m], radial bearing stiffness [N/m].
    noise : float
        RMS of the added Gaussian noise / RMS of the noise-free dynamic record [-].
    replicate : int
        Noise realisation number.
    fault : str or None
        Fault class (:data:`gearsim.model.variants.FAULT_CLASSES`) of a study that
        varies ``fault``; ``None`` otherwise (then the crack route: ``flank``,
        ``crack_depth``).
    severity : float or None
        Fault size as a fraction of the class's reference size, in (0, 1]
        (:func:`gearsim.model.variants.fault_variant`); for ``fault == "none"`` the
        nominal severity of the grid cell (no fault is modelled); ``None`` without
        ``fault``.
    gear : str or None
        The faulty gear of a study that varies ``gear`` (a name of the train's gears);
        ``None``: the input gear.
    bearings : tuple of (str, float)
        Shaft name and radial stiffness [N/m] of each shaft's bearings the study varies
        (``bearing_stiffness[SHAFT]``, :meth:`gearsim.model.Gearbox.with_bearing`); set
        after ``bearing_stiffness``, which the other bearings keep.
    """

    index: int
    crack_depth: float
    flank: str
    closure: str
    speed: float
    torque: float
    bearing_stiffness: float
    noise: float
    replicate: int
    fault: str | None = None
    severity: float | None = None
    gear: str | None = None
    bearings: tuple[tuple[str, float], ...] = ()

    def params(self) -> dict[str, Any]:
        """Parameters without the index (the case's identity).

        ``fault`` and ``severity`` are left out when ``fault`` is ``None``, and ``gear``
        when it is ``None``, so that the keys of a study without them are those it had
        before they existed; each shaft's bearing stiffness is
        ``bearing_stiffness[SHAFT]``.
        """
        d = dataclasses.asdict(self)
        d.pop("index")
        d.pop("bearings")
        d.update({f"bearing_stiffness[{n}]": k for n, k in self.bearings})
        if self.fault is None:
            d.pop("fault")
            d.pop("severity")
        if self.gear is None:
            d.pop("gear")
        return d

    def simulation_params(self) -> dict[str, Any]:
        """Parameters that change the simulation (not noise or replicate).

        The crack depth of an uncracked case (``flank == "none"``) and the severity and
        gear of a healthy case (``fault == "none"``) count as 0 and none: such cases share
        one simulation whatever their nominal depth, severity or gear.
        """
        return simulation_params(self.params())


def simulation_params(params: dict[str, Any]) -> dict[str, Any]:
    """The parameters of one case (:meth:`Case.params`, or a row of a store's coordinates)
    that change its simulation: cases with equal results share one simulated record.

    Parameters
    ----------
    params : dict
        Parameter name -> value of one case; ``noise`` and ``replicate`` (either may be
        missing) are dropped, the crack depth of an uncracked case (``flank == "none"``)
        and the severity of a healthy case (``fault == "none"``) count as 0, the gear of
        a healthy case is dropped.

    Returns
    -------
    dict
        A new dict.

    Examples
    --------
    >>> simulation_params({"flank": "none", "crack_depth": 2e-3, "noise": 0.1,
    ...                    "replicate": 2, "torque": 2000.0})
    {'flank': 'none', 'crack_depth': 0.0, 'torque': 2000.0}
    """
    d = {k: v for k, v in params.items() if k not in ("noise", "replicate")}
    if d.get("flank") == "none":
        d["crack_depth"] = 0.0
    if d.get("fault") == "none":
        d["severity"] = 0.0
        d.pop("gear", None)
    return d


@dataclass(frozen=True)
class Study:
    """A parsed study file (made by :func:`loads_study`; see the module docstring).

    Parameters
    ----------
    name : str
        Study name.
    text : str
        The TOML text as given (stored with the results).
    config : str
        Base train: built-in example name or path of a TOML file.
    config_text : str
        TOML text of the base train (hashed, so a changed config invalidates old parts).
    sampling : str
        ``"grid"`` or ``"random"``.
    samples : int
        Number of random samples (random sampling only).
    seed : int
        Seed of random sampling and of the measurement noise.
    replicates : int
        Noise realisations per parameter combination.
    signal : str
        Analysed record, ``variable`` or ``variable[shaft,axis]`` of the simulated dataset.
    shafts : str
        ``"all"``: sidebands of every shaft; ``"reference"``: the input shaft only.
    store_signals : bool
        Keep the analysed (noisy) records in the store.
    dynamics : dict
        Overrides of the dynamics settings (SI).
    parameters : dict
        Parameter name -> tuple of values, or a dict ``{min, max, num, log}`` (SI).
    """

    name: str
    text: str
    config: str
    config_text: str
    sampling: str
    samples: int
    seed: int
    replicates: int
    signal: str
    shafts: str
    store_signals: bool
    dynamics: dict[str, Any]
    parameters: dict[str, Any]

    def fingerprint(self) -> str:
        """Hash of everything but the parameter lists that changes a case's result."""
        doc = {"config": self.config_text, "dynamics": self.dynamics, "signal": self.signal,
               "shafts": self.shafts, "seed": self.seed, "store_signals": self.store_signals}
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()

    def case_key(self, case: Case) -> str:
        """Hash of a case's parameters and the study fingerprint (hex, 16 characters).

        Parameters
        ----------
        case : Case
            A case of this study (its index is not hashed).

        Returns
        -------
        str
            First 16 hex digits of the SHA-256 of the parameters and
            :meth:`fingerprint`; also seeds the case's measurement noise.
        """
        doc = json.dumps({"study": self.fingerprint(), **case.params()}, sort_keys=True)
        return hashlib.sha256(doc.encode()).hexdigest()[:16]

    def simulation_key(self, case: Case) -> str:
        """Hash of the simulation parameters: cases with equal keys share one simulation.

        Parameters
        ----------
        case : Case
            A case of this study; noise and replicate are not hashed, the crack
            depth counts as 0 when ``flank == "none"`` and the severity as 0 when
            ``fault == "none"``.

        Returns
        -------
        str
            First 16 hex digits of the SHA-256 of :meth:`Case.simulation_params` and
            :meth:`fingerprint`; names the part file of the group.
        """
        doc = json.dumps({"study": self.fingerprint(), **case.simulation_params()},
                         sort_keys=True)
        return hashlib.sha256(doc.encode()).hexdigest()[:16]


def builtin_study_text(name: str) -> str:
    """TOML text of a built-in study (see :data:`BUILTIN_STUDIES`).

    Parameters
    ----------
    name : str
        Name of a built-in study, e.g. ``"diagnostic"``.

    Returns
    -------
    str
        The study TOML text (``gearsim/data/studies/<name>.toml``).

    Raises
    ------
    InputError
        If ``name`` is not a built-in study.
    """
    if name not in BUILTIN_STUDIES:
        raise InputError("study", name, "unknown; built-in studies: " + ", ".join(BUILTIN_STUDIES))
    return (resources.files("gearsim.data").joinpath("studies", f"{name}.toml")
            .read_text(encoding="utf-8"))


def load_study(path: str | Path) -> Study:
    """Read a study file, or a built-in study by name (:data:`BUILTIN_STUDIES`).

    Parameters
    ----------
    path : str or Path
        Study TOML file, or a built-in study name. A relative ``config`` in the file is
        taken relative to the file's folder.

    Returns
    -------
    Study

    Raises
    ------
    InputError
        A missing or unreadable file, or any refused content (see :func:`loads_study`).
    """
    text, folder = read_file_or_builtin(path, BUILTIN_STUDIES, builtin_study_text,
                                        parameter="study", what="study")
    return loads_study(text, base_dir=folder, source=str(path))


def _toml(value: Any) -> Any:
    """A TOML value as written: a string in its quotes (``"3"``, not 3)."""
    return f'"{value}"' if isinstance(value, str) else value


def _quoted(value: Any) -> str:
    """The hint for a number given as a string."""
    return " (a number, not a string: drop the quotes)" if isinstance(value, str) else ""


def _kind_of(name: str) -> str:
    """The parameter whose kind and bounds ``name`` takes: ``bearing_stiffness`` for a
    shaft's own (:data:`NAMED_BEARING`), else ``name``."""
    return "bearing_stiffness" if NAMED_BEARING.fullmatch(name) else name


def _checked(name: str, value: float, where: str, raw: Any) -> float:
    """``value`` (SI) if finite and within the parameter's bounds, else refused."""
    low, inclusive, unit = LOWER_BOUNDS[_kind_of(name)]
    unit = f" {unit}" if unit else ""
    limit = f"must be >= {low:g}{unit}" if inclusive else f"must be > {low:g}{unit}"
    ok = math.isfinite(value) and (value >= low if inclusive else value > low)
    high = UPPER_BOUNDS.get(_kind_of(name))
    if high is not None:
        limit += f" and <= {high:g}{unit}"
        ok = ok and value <= high
    require(ok, where, raw, limit + " and finite")
    return value


def _values(name: str, raw: Any) -> tuple | dict:
    kind = PARAMETERS[_kind_of(name)]
    where = f"parameters.{name}"
    if isinstance(raw, dict):
        if isinstance(kind, tuple) or kind == "name":
            raise InputError(where, raw, "give a list of choices" + (
                ": " + ", ".join(kind) if isinstance(kind, tuple) else " (gear names)"))
        for key in raw:
            if key not in ("min", "max", "num", "log"):
                raise InputError(f"{where}.{key}", raw[key], "unknown key; allowed: min, max, "
                                 "num, log")
        if "min" not in raw or "max" not in raw:
            raise InputError(where, raw, "a range needs min and max")
        lo = _checked(name, to_si(raw["min"], kind, f"{where}.min"), f"{where}.min", raw["min"])
        hi = _checked(name, to_si(raw["max"], kind, f"{where}.max"), f"{where}.max", raw["max"])
        require(lo <= hi, where, f"min {raw['min']} > max {raw['max']}",
                "empty range: need min <= max")
        num = raw.get("num")
        if num is not None:
            require(isinstance(num, int) and not isinstance(num, bool) and num >= 1,
                    f"{where}.num", num, "empty range: must be an integer >= 1")
        log = raw.get("log", False)
        require(isinstance(log, bool), f"{where}.log", log, "must be true or false")
        if log:
            require(lo > 0, f"{where}.min", raw["min"], "must be > 0 with log = true")
        return {"min": lo, "max": hi, "num": num, "log": log}
    if not isinstance(raw, list):
        raw = [raw]
    require(len(raw) > 0, where, raw, "empty list: give at least one value")
    out = []
    for i, v in enumerate(raw):
        if isinstance(kind, tuple):
            require(v in kind, f"{where}[{i}]", v, "must be one of " + ", ".join(kind))
            out.append(v)
        elif kind == "name":  # checked against the gearbox in check_study
            require(isinstance(v, str) and v != "", f"{where}[{i}]", v,
                    "must be a gear's name (a non-empty string)")
            out.append(v)
        else:
            out.append(_checked(name, to_si(v, kind, f"{where}[{i}]"), f"{where}[{i}]", v))
    return tuple(out)


def loads_study(text: str, *, base_dir: str | Path | None = None,
                source: str = "TOML") -> Study:
    """Parse study TOML text into a :class:`Study` (``base_dir``: for a relative config).

    Values with units are converted to SI (:func:`gearsim.units.to_si`); plain numbers
    are SI. The base train is read here (its text is part of the study fingerprint).

    Parameters
    ----------
    text : str
        Study TOML (layout in the module docstring).
    base_dir : str or Path, optional
        Folder against which a relative ``study.config`` path is resolved; default the
        current directory.
    source : str, optional
        Where the text comes from (its path), shown when it is not valid TOML.

    Returns
    -------
    Study

    Raises
    ------
    InputError
        Invalid TOML, an unknown section, key or parameter, a config file not found, a
        bad value (sampling, samples, seed, replicates, signal, shafts, units), an empty
        list or range, a grid range without ``num``, ``fault`` together with ``flank``
        or ``crack_depth``, or ``severity`` without ``fault``.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("study", source, f"is not valid TOML: {exc}") from None
    for key in doc:
        if key not in ("study", "parameters"):
            raise InputError(key, "...", "unknown section; allowed: study, parameters")
    st = doc.get("study", {})
    require(isinstance(st, dict), "study", st, "must be a table")
    for key in st:
        if key not in STUDY_KEYS:
            raise InputError(f"study.{key}", st[key], "unknown key; allowed: "
                             + ", ".join(STUDY_KEYS))
    config = st.get("config", "idler-table1")
    require(isinstance(config, str) and config.strip() != "", "study.config",
            config if config != "" else '""', "must name a config file or a built-in example: "
            + ", ".join(EXAMPLES))
    if config in EXAMPLES and not Path(config).exists():
        config_text = example_text(config)
    else:
        p = Path(config)
        if not p.is_absolute() and base_dir is not None:
            p = Path(base_dir) / p
        if not p.exists():
            raise InputError("study.config", config, "file not found (or give a built-in "
                             "example: " + ", ".join(EXAMPLES) + ")")
        if not p.is_file():
            raise InputError("study.config", config, "is not a file")
        try:
            config, config_text = str(p), p.read_text(encoding="utf-8-sig")
        except (OSError, UnicodeDecodeError) as exc:
            raise InputError("study.config", config, f"cannot be read: "
                             f"{getattr(exc, 'strerror', None) or exc}") from None
    sampling = st.get("sampling", "grid")
    require(sampling in ("grid", "random"), "study.sampling", sampling,
            'must be "grid" or "random"')
    samples = st.get("samples", 0 if sampling == "grid" else None)
    if sampling == "random":
        require(isinstance(samples, int) and not isinstance(samples, bool) and samples >= 1,
                "study.samples", _toml(samples) if samples is not None else "missing",
                "random sampling needs an integer >= 1" + _quoted(samples))
    seed = st.get("seed", 0)
    require(isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0, "study.seed",
            _toml(seed), "must be an integer >= 0" + _quoted(seed))
    replicates = st.get("replicates", 1)
    require(isinstance(replicates, int) and not isinstance(replicates, bool)
            and replicates >= 1, "study.replicates", _toml(replicates),
            "must be an integer >= 1" + _quoted(replicates))
    shafts = st.get("shafts", "all")
    require(shafts in ("all", "reference"), "study.shafts", shafts,
            'must be "all" or "reference"')
    store_signals = st.get("store_signals", False)
    require(isinstance(store_signals, bool), "study.store_signals", store_signals,
            "must be true or false")
    dyn_raw = st.get("dynamics", {})
    require(isinstance(dyn_raw, dict), "study.dynamics", dyn_raw, "must be a table")
    dynamics = convert(dyn_raw, DYNAMICS_OVERRIDES, "study.dynamics")
    signal = st.get("signal")
    if signal is None:  # the gearbox's first record in the study's model: what a rig measures
        gb = loads(config_text)
        if "model" in dynamics:  # a model the box cannot take: refused, named, when the
            with contextlib.suppress(InputError):  # study is checked (check_study)
                gb = gb.replace(dynamics={"model": dynamics["model"]})
        signal = gb.default_signal
    require(isinstance(signal, str) and len(signal) > 0, "study.signal", signal,
            "must be a variable name, optionally with [shaft,axis]")
    params_raw = doc.get("parameters", {})
    require(isinstance(params_raw, dict), "parameters", params_raw, "must be a table")
    parameters: dict[str, Any] = {}
    for key, value in params_raw.items():
        if key not in PARAMETERS and not NAMED_BEARING.fullmatch(key):
            raise InputError(f"parameters.{key}", value, "unknown parameter; allowed: "
                             + ", ".join(PARAMETERS) + ', "bearing_stiffness[SHAFT]" (SHAFT '
                             "a shaft's name of letters, digits, '_', '-' or '.', as the "
                             "store's coordinate is named)")
        parameters[key] = _values(key, value)
    if sampling == "grid":
        for key, value in parameters.items():
            if isinstance(value, dict):
                require(value["num"] is not None, f"parameters.{key}.num", "missing",
                        "a grid range needs num (number of points)")
    name = st.get("name", "parameter study")
    require(isinstance(name, str), "study.name", name, "must be a string")
    max_cases = st.get("max_cases", MAX_CASES)
    require(isinstance(max_cases, int) and not isinstance(max_cases, bool) and max_cases >= 1,
            "study.max_cases", max_cases, "must be an integer >= 1")
    if not parameters:
        raise InputError("parameters", "none", "nothing to vary: give at least one of "
                         + ", ".join(PARAMETERS) + " under [parameters]")
    if "fault" in parameters:
        for key in CRACK_ONLY:
            if key in parameters:
                raise InputError(f"parameters.{key}", params_raw[key],
                                 "cannot be combined with parameters.fault: a study varies "
                                 "either the crack (flank, crack_depth) or the fault class "
                                 "(fault, severity; the working and non-working crack are "
                                 "fault classes too); remove one of them")
    else:
        for key, what in (("severity", "the fault classes it sizes"),
                          ("gear", "the fault classes it places")):
            if key in parameters:
                raise InputError(f"parameters.{key}", params_raw[key],
                                 f"needs parameters.fault ({what})")
    study = Study(name=name, text=text, config=config, config_text=config_text,
                  sampling=sampling, samples=int(samples or 0), seed=seed,
                  replicates=replicates, signal=signal, shafts=shafts,
                  store_signals=store_signals, dynamics=dynamics, parameters=parameters)
    n = case_count(study)
    if n > max_cases:
        what = ("samples x replicates" if sampling == "random"
                else "product of the parameter list lengths x replicates")
        raise InputError("study", f"{n} cases ({what})",
                         f"at most {max_cases} cases; set study.max_cases to allow more")
    check_study(study)
    return study


def case_count(study: Study) -> int:
    """Number of cases of a study, without listing them.

    Parameters
    ----------
    study : Study
        The parsed study.

    Returns
    -------
    int
        ``len(expand(study))``: grid: the product of the lengths of the parameter lists
        (ranges: ``num``) times ``replicates``; random: ``samples`` times ``replicates``.
    """
    if study.sampling == "random":
        return study.samples * study.replicates
    n = study.replicates
    for spec in study.parameters.values():
        n *= len(spec) if isinstance(spec, tuple) else int(spec["num"])
    return n


def _raw_parameter(study: Study, name: str) -> Any:
    try:
        return tomllib.loads(study.text).get("parameters", {}).get(name)
    except tomllib.TOMLDecodeError:  # pragma: no cover (the text was parsed before)
        return None


def _points(study: Study, name: str) -> list[tuple[str, Any, float]]:
    """(parameter name, value as written, SI value) of each value a parameter can take.

    For a range, its ends (every grid point and every random draw lies between them).
    """
    spec = study.parameters[name]
    raw = _raw_parameter(study, name)
    where = f"parameters.{name}"
    if isinstance(spec, dict):
        raw = raw if isinstance(raw, dict) else {}
        return [(f"{where}.{k}", raw.get(k, spec[k]), spec[k]) for k in ("min", "max")]
    raw = raw if isinstance(raw, list) else [raw] * len(spec)
    return [(f"{where}[{i}]", raw[i] if i < len(raw) else v, v) for i, v in enumerate(spec)]


def check_study(study: Study) -> None:
    """Check every study-wide setting once, before any case runs.

    A bad setting here would fail every case alike; it is refused instead: the dynamics
    overrides (applied with :meth:`gearsim.model.Gearbox.replace`, which checks them,
    and finite), the analysed signal (one of :meth:`gearsim.model.Gearbox.signals`), the
    bearing stiffness values (as dynamics settings), each crack depth on each cracked flank
    of the study (:meth:`gearsim.model.Gearbox.with_crack` checks it fits the tooth), each
    torque, each fault class at the lowest and highest severity of the study
    (:func:`gearsim.model.variants.fault_variant` builds and checks the variant), the
    recorded duration (at least one revolution of the slowest shaft at the lowest speed,
    and what the analysis of every case needs there: two revolutions of the reference
    shaft and the sideband resolution of the analysed shafts) and the output rate at the
    highest speed (:meth:`gearsim.model.Gearbox.check_run`: mesh harmonics and run cost;
    then the highest sideband the analysis reads).
    :func:`loads_study` calls it; the values' signs were checked when they were read.

    Parameters
    ----------
    study : Study
        The parsed study.

    Raises
    ------
    InputError
        Naming the study key or parameter value (``study.dynamics.fs``,
        ``parameters.crack_depth[2]``, ``parameters.severity[1]``, ``study.signal``, ...).
    """
    gb = loads(study.config_text)
    for key, value in study.dynamics.items():
        if isinstance(value, float):
            require(math.isfinite(value), f"study.dynamics.{key}", value, "must be finite")
    try:
        gb = gb.replace(dynamics=dict(study.dynamics))
    except InputError as exc:
        name = exc.parameter
        if name.startswith("dynamics."):
            name = "study." + name
        raise InputError(name, exc.value, exc.limit) from None
    except TypeError as exc:  # pragma: no cover (keys were checked when read)
        raise InputError("study.dynamics", dict(study.dynamics), str(exc)) from None
    choices = gb.signals()
    if gb.signal_key(study.signal) not in choices:
        # the names of the signal's own family (acceleration[...]) in full, else the
        # first few and every family
        family = [c for c in choices if c.split("[")[0] == study.signal.split("[")[0]]
        families = dict.fromkeys(c.split("[")[0] + "[...]" for c in choices if "[" in c)
        shown = (", ".join(family) if family else ", ".join(choices[:6]) + ", ..."
                 + (" and the families " + ", ".join(families) if families else ""))
        raise InputError("study.signal", study.signal,
                         f"not a variable of the {gb.dynamics.model} simulation; give one "
                         f"of {shown}")
    require(not ("speed" in study.parameters and gb.dynamics.speed_times is not None),
            "parameters.speed", _raw_parameter(study, "speed"), "changes nothing: the "
            "configuration's speed profile ([dynamics] speed_times, speed_values) sets the "
            "speed of every case (remove it to vary the speed)")
    bearings = [n for n in study.parameters
                if n == "bearing_stiffness" or NAMED_BEARING.fullmatch(n)]
    if bearings and gb.dynamics.model == "torsional":
        raise InputError(f"parameters.{bearings[0]}", _raw_parameter(study, bearings[0]),
                         "changes nothing: the torsional model has no bearing coordinates "
                         "(dynamics.model = \"torsional\")")
    if "bearing_stiffness" in study.parameters:
        require(gb.default_bearings, "parameters.bearing_stiffness",
                _raw_parameter(study, "bearing_stiffness"), "changes nothing: every bearing "
                "of the gearbox has its own stiffness in the configuration (remove some to "
                "let the study set them)")
        for where, raw, value in _points(study, "bearing_stiffness"):
            try:
                gb.replace(dynamics={"bearing_stiffness": value})
            except InputError as exc:
                raise InputError(where, raw, exc.limit) from None
    for name in (n for n in study.parameters if NAMED_BEARING.fullmatch(n)):
        shaft = NAMED_BEARING.fullmatch(name).group(1)
        require(shaft in gb.bearing_names(), f"parameters.{name}", _raw_parameter(study, name),
                "names no shaft of the gearbox; its bearings: " + ", ".join(gb.bearing_names()))
        for where, raw, value in _points(study, name):
            try:
                gb.with_bearing(shaft, value)
            except InputError as exc:
                raise InputError(where, raw, exc.limit) from None
    flanks = study.parameters.get("flank")
    if flanks is None:
        flanks = (gb.cracks[0].flank,) if gb.cracks else ("none",)
    if "fault" in study.parameters:
        flanks = ("none",)  # the fault variants replace the base train's cracks
        _check_faults(study, gb)
    cracked = [f for f in dict.fromkeys(flanks) if f != "none"]
    if "crack_depth" in study.parameters and not cracked:
        raise InputError("parameters.crack_depth", _raw_parameter(study, "crack_depth"),
                         "changes nothing: no case has a crack (give a crack in the "
                         "configuration or a cracked parameters.flank)")
    if "crack_depth" in study.parameters:
        depths = _points(study, "crack_depth")
    else:
        d = gb.cracks[0].depth if gb.cracks else None
        depths = [("crack.depth", d, d)]
    for flank in cracked:
        for where, raw, value in depths:
            try:
                gb.with_crack(flank, depth=value)
            except InputError as exc:
                raise InputError(where, raw, f"{exc.limit} (flank {flank})") from None
    speed, torque = gb.operating()
    speeds = ([v for _, _, v in _points(study, "speed")] if "speed" in study.parameters
              else [speed])
    for key in ("speed", "torque"):  # each value named as written
        for where, raw, value in (_points(study, key) if key in study.parameters else []):
            try:
                gb.at(**{"speed": speed, "torque": torque, key: value})
            except InputError as exc:
                raise InputError(where, raw, exc.limit) from None
    from gearsim.signals._checks import WINDOWS
    from gearsim.signals.analysis import kinematics

    rpm = 30.0 / math.pi
    slowest = gb.at(speed=min(speeds), torque=torque)
    member, f_slow = slowest.slowest_shaft()
    duration = gb.dynamics.duration
    # a run covers one revolution of the slowest shaft; the analysis of every case needs
    # two revolutions of the reference shaft (TSA) and 2 L window bins per sideband
    # spacing of each analysed shaft: the larger is the limit
    ref = slowest.reference(study.shafts, study.signal)[0]
    kin = kinematics(**slowest.analysis_train(study.shafts, study.signal))
    window = gb.analysis.window
    need = max(2.0 / kin.reference_frequency, 2 * WINDOWS[window] / min(kin.shafts.values()))
    at = f"the lowest speed of the study, {min(speeds) * rpm:.6g} rpm"
    require(duration >= max(need, 1 / f_slow) * (1 - 1e-9), "study.dynamics.duration",
            f"{duration:g} s", f"must be >= {1 / f_slow:.6g} s (one revolution of the {member}, "
            f"the slowest shaft, at {at})" if need < 1 / f_slow else
            f"must be >= {need:.6g} s for the analysis of every case at {at} (two "
            f"revolutions of {ref}, {2 * WINDOWS[window]} {window} bins per sideband spacing "
            f"of the slowest analysed shaft, {min(kin.shafts.values()):.4g} Hz)")
    # aliasing and run cost of the most demanding case (highest speed): refused here,
    # not case by case inside the cluster
    fastest = gb.at(speed=max(speeds), torque=torque)
    n = max(gb.analysis.orders)
    try:
        fastest.check_run(harmonics=n)
    except InputError as exc:
        name = exc.parameter
        if name.startswith("dynamics."):
            name = "study." + name
        raise InputError(name, exc.value, f"{exc.limit} (at the highest speed of the study, "
                         f"{max(speeds) * rpm:.6g} rpm)") from None
    kin = kinematics(**fastest.analysis_train(study.shafts, study.signal))
    f_mesh = max([kin.mesh_frequency, *(st.mesh_frequency for st in kin.stages)])
    f_top = n * f_mesh + gb.analysis.n_sidebands * max(kin.shafts.values())
    if not gb.dynamics.fs > 2.0 * f_top:
        raise InputError("study.dynamics.fs", gb.dynamics.fs,
                         f"must be > {2 * f_top:.6g} Hz, twice the highest line the analysis "
                         f"reads ({n} f_m with {gb.analysis.n_sidebands} sidebands, "
                         f"{f_top:.6g} Hz) at the highest speed of the study "
                         f"({max(speeds) * rpm:.6g} rpm)")


def _check_faults(study: Study, gb: Gearbox) -> None:
    """Each fault class at each severity end of the study makes a valid variant of ``gb``."""
    severities = (_points(study, "severity") if "severity" in study.parameters
                  else [("parameters.fault", None, 1.0)])
    if "gear" in study.parameters:
        names = [g.name for t in gb.chains for g in t.gears]  # beside stages too
        names += [n for n in fault_gears(gb) if n not in names]  # and stage members
        for where, raw, name in _points(study, "gear"):
            require(name in names, where, raw, "is not a gear of the gearbox; its gears: "
                    + ", ".join(names))
    gears = [g for _, _, g in _points(study, "gear")] if "gear" in study.parameters else [None]
    for where_f, raw_f, kind in _points(study, "fault"):
        if kind == "none":
            continue
        for where_s, raw_s, s in severities:
            for gear in gears:
                try:
                    fault_variant(gb, kind, s, gear=gear)
                except InputError as exc:
                    where, raw = ((where_s, raw_s) if "severity" in study.parameters
                                  else (where_f, raw_f))
                    on = "" if gear is None else f", gear {gear}"
                    raise InputError(where, raw, f"{exc} (fault {kind}, severity {s:g}"
                                     f"{on})") from None


def _base_values(study: Study) -> dict[str, tuple]:
    gb = loads(study.config_text)
    depth = gb.cracks[0].depth if gb.cracks else 0.0
    flank = gb.cracks[0].flank if gb.cracks else "none"
    if "fault" in study.parameters:  # the fault variants replace the cracks
        depth, flank, fault, severity = 0.0, "none", None, 1.0
    else:
        fault = severity = None
    speed, torque = gb.operating()
    return {"crack_depth": (depth,), "flank": (flank,), "fault": (fault,),
            "severity": (severity,), "gear": (None,), "closure": (gb.stiffness.closure,),
            "speed": (speed,), "torque": (torque,),
            "bearing_stiffness": (gb.dynamics.bearing_stiffness,), "noise": (0.0,)}


def _grid(spec: tuple | dict) -> tuple:
    if isinstance(spec, tuple):
        return spec
    f = np.geomspace if spec["log"] else np.linspace
    return tuple(float(v) for v in f(spec["min"], spec["max"], spec["num"]))


def _draw(spec: tuple | dict, rng: np.random.Generator) -> Any:
    if isinstance(spec, tuple):
        return spec[int(rng.integers(len(spec)))]
    if spec["log"]:
        return float(math.exp(rng.uniform(math.log(spec["min"]), math.log(spec["max"]))))
    return float(rng.uniform(spec["min"], spec["max"]))


def expand(study: Study) -> list[Case]:
    """All cases of a study, in a fixed order (grid: last parameter varies fastest).

    Random sampling draws each parameter independently with
    ``numpy.random.default_rng(study.seed)``. Each parameter combination is repeated
    ``study.replicates`` times (replicate number 0, 1, ...). Parameters the study does
    not vary take the base train's value (noise: 0; with ``fault``: severity 1, flank
    ``"none"``, crack depth 0; without: fault and severity ``None``).

    Parameters
    ----------
    study : Study
        The parsed study.

    Returns
    -------
    list of Case
        Cases with ``index`` 0, 1, ... in that order.

    Examples
    --------
    Two flanks x two noise levels x two replicates = 8 cases on the Table-1 train
    (input speed 1900 rpm = 198.968 rad/s, torque 4876 N m):

    >>> from gearsim.studies.sweep import expand, loads_study
    >>> st = loads_study('''
    ... [study]
    ... replicates = 2
    ... [parameters]
    ... flank = ["none", "working"]
    ... noise = [0.0, 0.5]
    ... ''')
    >>> cases = expand(st)
    >>> len(cases)
    8
    >>> [(c.flank, c.noise, c.replicate) for c in cases[:3]]
    [('none', 0.0, 0), ('none', 0.0, 1), ('none', 0.5, 0)]
    >>> round(cases[0].speed, 3), cases[0].torque
    (198.968, 4876.0)
    """
    specs = {**_base_values(study), **study.parameters}
    named = [n for n in study.parameters if NAMED_BEARING.fullmatch(n)]
    names = [*PARAMETERS, *named]
    if study.sampling == "grid":
        combos = list(itertools.product(*(_grid(specs[n]) for n in names)))
    else:
        rng = np.random.default_rng(study.seed)
        combos = [tuple(_draw(specs[n], rng) for n in names) for _ in range(study.samples)]
    cases = []
    for combo in combos:
        kw = dict(zip(names, combo, strict=True))
        bearings = tuple((NAMED_BEARING.fullmatch(n).group(1), kw.pop(n)) for n in named)
        if bearings:
            kw["bearings"] = bearings
        for r in range(study.replicates):
            cases.append(Case(index=len(cases), replicate=r, **kw))
    return cases
