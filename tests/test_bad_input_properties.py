"""Property-based tests: every kind of bad input is refused cleanly by the CLI.

Hypothesis builds bad inputs from a valid starting point (the built-in ``spur-19-48``
example, a small study, a small measured record) by replacing ONE value with a value that
is non-finite, of the wrong unit, of the wrong type or out of range, and runs the CLI in
process (:func:`gearsim.cli.run`). Every such run must

* exit with status 2,
* print exactly one line on standard error, ``gearsim: error: ...`` (or a click usage
  message of at most 3 lines), with no ``Traceback`` and no ``internal error``,
* name the parameter in that line (``gears[0].face_width``, ``dynamics.fs``, ``--fs``,
  the measured file's name, ...),
* write nothing: the ``--out`` / ``--plot`` targets do not exist afterwards and the
  output folder stays empty (no temporary or partial files),
* refuse before the expensive work: the integrator, the stiffness computation, the FE
  solve, the sweep's Dask cluster and the figure writer are replaced by guards that
  record the call and stop the run (so a silently accepted value fails fast).

Each kind of failure raises its own assertion class, so Hypothesis reports distinct
failures of one test separately. The examples are derandomized and bounded.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import tempfile
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import gearsim.cli as cli
from gearsim.model import example_text

# ------------------------------------------------------------------------------ settings

SETTINGS = settings(
    derandomize=True,
    database=None,
    deadline=None,
    max_examples=6,
    # the values come from finite catalogs of one-field changes, already minimal: no
    # shrinking, so the run time does not grow with the number of failures
    phases=(Phase.explicit, Phase.reuse, Phase.generate),
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                           HealthCheck.filter_too_much],
)
FEW = settings(SETTINGS, max_examples=6)
MORE = settings(SETTINGS, max_examples=12)
#: single (non-parametrized) tests over a whole catalog: cheap refusals, more examples
WIDE = settings(SETTINGS, max_examples=40)
WIDEST = settings(SETTINGS, max_examples=150)


# ----------------------------------------------------------------------- failure classes


class BadInputFailure(AssertionError):
    """Base class: the CLI did not refuse a bad input cleanly."""


class AcceptedBadInput(BadInputFailure):
    """The bad value got past validation: the expensive work started (guard hit)."""


class Crashed(BadInputFailure):
    """A traceback or ``gearsim: internal error`` instead of a refusal."""


class WrongExitStatus(BadInputFailure):
    """Exit status other than 2."""


class BadStderr(BadInputFailure):
    """Standard error is not one ``gearsim: error:`` line (or a short usage message)."""


class ParameterNotNamed(BadInputFailure):
    """The message does not name the parameter the user gave."""


class OutputWritten(BadInputFailure):
    """An --out / --plot target or a temporary file exists after the refusal."""


class StdoutNotEmpty(BadInputFailure):
    """Something was printed on standard output by a refused run."""


# ------------------------------------------------------------------------- work guards


class ReachedWork(Exception):
    """Raised by a guard: the run got to the expensive part."""


REACHED: list[str] = []


def _guard(where: str):
    def guard(*_args: Any, **_kwargs: Any):
        REACHED.append(where)
        raise ReachedWork(f"work started: {where}")
    return guard


#: (module, attribute) replaced by a guard during every test of this file. A missing
#: attribute is skipped (the guard only bounds the time; acceptance is seen anyway).
GUARDS = [
    ("gearsim.dynamics.simulate", "run_kernel"),           # the integrator
    ("gearsim.system", "train_stiffness"),                 # `stiffness` verb's work
    ("gearsim.system.planetary", "stage_stiffness"),       # ... on a planetary stage
    ("gearsim.fem.check", "compare_gear"),                 # FE solve of `fe-check`
    ("gearsim.studies.reproduce", "simulate_cases"),       # `reproduce` simulations
    ("gearsim.commands.analysis", "save_all"),             # `analyze --plot` figures
    ("distributed", "LocalCluster"),                       # `sweep` cluster
    ("distributed", "Client"),
]


@pytest.fixture(autouse=True)
def _work_guards(monkeypatch):
    import importlib

    for mod_name, attr in GUARDS:
        try:
            mod = importlib.import_module(mod_name)
        except ImportError:
            continue
        if hasattr(mod, attr):
            monkeypatch.setattr(mod, attr, _guard(f"{mod_name}.{attr}"))
    monkeypatch.delenv("GEARSIM_DEBUG", raising=False)
    yield


# ------------------------------------------------------------------------- invocation


@dataclass
class Result:
    argv: list[str]
    status: int
    stdout: str
    stderr: str
    reached: list[str] = field(default_factory=list)


def invoke(argv: list[str]) -> Result:
    """Run the CLI in process; the exit status and what it printed."""
    REACHED.clear()
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            if hasattr(cli, "run"):
                status = cli.run(argv)
            else:  # before gearsim.cli.run existed: the semantics of main()
                import sys

                old = sys.argv
                sys.argv = ["gearsim", *argv]
                try:
                    cli.main()
                    status = 0
                finally:
                    sys.argv = old
        except SystemExit as exc:
            status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except ReachedWork:
            status = 1
        except BaseException as exc:  # noqa: BLE001  an escaped exception is a crash
            import traceback

            err.write("Traceback (most recent call last):\n"
                      + "".join(traceback.format_exception(exc)))
            status = 1
    return Result(argv, status, out.getvalue(), err.getvalue(), list(REACHED))


def _listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def check_refusal(res: Result, expected: str | tuple[str, ...], out_dir: Path,
                  targets: tuple[Path, ...] = (), what: str = "") -> None:
    """Assert the run was refused cleanly (see module docstring)."""
    names = (expected,) if isinstance(expected, str) else tuple(expected)
    ctx = (f"\n  case: {what}\n  argv: {res.argv}\n  exit: {res.status}\n"
           f"  stderr: <<{res.stderr[-1500:]}>>\n  stdout: <<{res.stdout[:300]}>>")
    if res.reached:
        raise AcceptedBadInput(f"bad value accepted, work started ({res.reached[0]}){ctx}")
    if "Traceback" in res.stderr or "internal error" in res.stderr:
        raise Crashed(f"crash instead of a refusal{ctx}")
    if res.status != 2:
        raise WrongExitStatus(f"exit status {res.status}, expected 2{ctx}")
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    one = len(lines) == 1 and lines[0].startswith("gearsim: error:")
    usage = (1 <= len(lines) <= 3 and lines[0].startswith("Usage:")
             and any("Error" in ln for ln in lines))
    if not (one or usage):
        raise BadStderr(f"stderr is not one 'gearsim: error:' line{ctx}")
    if not any(n in res.stderr for n in names):
        raise ParameterNotNamed(f"message does not name {' or '.join(names)}{ctx}")
    left = [t for t in targets if t.exists()]
    listing = _listing(out_dir)
    if left or listing:
        raise OutputWritten(f"written despite the refusal: {left or listing}{ctx}")
    if res.stdout.strip():
        raise StdoutNotEmpty(f"stdout not empty on a refusal{ctx}")


@contextlib.contextmanager
def workspace():
    """Fresh input and (empty) output folders."""
    with tempfile.TemporaryDirectory(prefix="gearsim-bad-") as tmp:
        base = Path(tmp)
        (base / "in").mkdir()
        (base / "out").mkdir()
        yield base / "in", base / "out"


# ---------------------------------------------------------------------- TOML writing


@dataclass(frozen=True)
class Raw:
    """A TOML literal written as is (``inf``, ``nan``, ``1e400``, a date)."""

    text: str

    def __repr__(self) -> str:
        return f"Raw({self.text!r})"


def lit(v: Any) -> str:
    """TOML text of a value."""
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(lit(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {lit(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dumps(doc: dict[str, Any]) -> str:
    """TOML text of a document (top-level scalars, tables and arrays of tables)."""
    lines: list[str] = []
    for k, v in doc.items():
        if not isinstance(v, dict) and not (isinstance(v, list) and v
                                            and all(isinstance(t, dict) for t in v)):
            lines.append(f"{json.dumps(k)} = {lit(v)}")

    def table(header: str, t: dict[str, Any]) -> None:
        subs = {k: v for k, v in t.items() if isinstance(v, dict) and k == "dynamics"
                and header == "study"}
        lines.append(f"\n[{header}]" if not header.startswith("[") else f"\n{header}")
        for k, v in t.items():
            if k not in subs:
                lines.append(f"{json.dumps(k)} = {lit(v)}")
        for k, v in subs.items():
            table(f"{header}.{k}", v)

    for k, v in doc.items():
        if isinstance(v, dict):
            table(k, v)
        elif isinstance(v, list) and v and all(isinstance(t, dict) for t in v):
            for t in v:
                table(f"[[{k}]]", t)
    return "\n".join(lines) + "\n"


def set_path(doc: dict[str, Any], path: tuple, value: Any) -> dict[str, Any]:
    """A deep copy of ``doc`` with the value at ``path`` replaced (tables created)."""
    doc = json.loads(json.dumps(doc))  # deep copy (the example has no non-JSON values)
    node: Any = doc
    for key in path[:-1]:
        if isinstance(key, int):
            node = node[key]
        else:
            node = node.setdefault(key, {})
    node[path[-1]] = value
    return doc


def dotted(path: tuple) -> str:
    """``("gears", 0, "face_width")`` -> ``gears[0].face_width``."""
    out = ""
    for key in path:
        out += f"[{key}]" if isinstance(key, int) else (f".{key}" if out else key)
    return out


# ------------------------------------------------------------------- bad-value catalog

#: SI unit text of each quantity kind, for "inf <unit>" style values.
UNIT = {"length": "mm", "angle": "deg", "speed": "rpm", "torque": "N*m", "pressure": "GPa",
        "density": "kg/m^3", "time": "s", "frequency": "Hz", "stiffness": "N/m",
        "damping": "N*s/m", "dimensionless": ""}
#: Units of a plainly different dimension than the kind (pint: rad and deg are
#: dimensionless, so none of these is an angle or a pure number).
OTHER_UNITS = ("kg", "s", "mm", "N", "A")


def nonfinite(kind: str) -> list[Any]:
    u = UNIT[kind]
    vals: list[Any] = [Raw("inf"), Raw("-inf"), Raw("nan"), Raw("1e400"), Raw("-1e400")]
    if u:
        vals += [f"inf {u}", f"nan {u}", f"-inf {u}", f"1e400 {u}"]
    else:
        vals += ["inf", "nan", "1e400"]
    return vals


def wrong_unit(kind: str) -> list[Any]:
    own = {"length": "mm", "time": "s"}.get(kind)
    return [f"3 {u}" for u in OTHER_UNITS if u != own]


def wrong_type_quantity() -> list[Any]:
    return [True, False, [1, 2], {"a": 1}, "abc", "", "mm", Raw("1979-05-27")]


def wrong_type_int() -> list[Any]:
    return [1.5, "abc", "20", True, [20], {"a": 1}, Raw("inf"), Raw("nan"), ""]


def wrong_type_str() -> list[Any]:
    return [1, True, 2.5, ["a"], {"a": 1}, Raw("nan")]


def wrong_type_bool() -> list[Any]:
    return ["true", 1, 0, "yes", [True], Raw("nan")]


@dataclass(frozen=True)
class Field:
    """One config field: path in the document, value kind and bad values."""

    path: tuple
    kind: str
    out_of_range: tuple = ()
    names: tuple[str, ...] = ()        # accepted parameter names (default: dotted path)
    list_ok: bool = False              # a list of values is valid (LIST_KEYS)

    @property
    def name(self) -> str:
        return dotted(self.path)

    def expected(self) -> tuple[str, ...]:
        return self.names or (self.name,)

    def bad_values(self) -> list[Any]:
        k = self.kind
        if k == "int":
            vals = wrong_type_int()
        elif k == "str":
            vals = wrong_type_str()
        elif k == "bool":
            vals = wrong_type_bool()
        elif k == "table":
            vals = [5, "steel", [1], True]
        elif k == "choice":
            vals = wrong_type_str()
        else:
            vals = nonfinite(k) + wrong_unit(k) + wrong_type_quantity()
            if self.list_ok:  # a list is valid here: put the bad value inside one
                vals = [v for v in vals if not isinstance(v, list)]
                vals += [[], [[0.0]], [Raw("nan")], ["1 mm", "abc"]]
        if self.list_ok and k == "int":
            vals = [v for v in vals if not isinstance(v, list)] + [[], [1, 0], [True]]
        return list(self.out_of_range) + vals


def gear_fields(prefix: tuple, teeth_index: int | None) -> list[Field]:
    """Fields of a [[gears]] table (or of [common])."""
    F = Field
    fields = [
        # [common] teeth are overridden by every gear of the example: only its type counts
        F((*prefix, "teeth"), "int", (6, 0, -19, 3) if teeth_index is not None else ()),
        F((*prefix, "normal_module"), "length", (0, "-3.2 mm", "0.2 m", "1 m", "0 mm")),
        F((*prefix, "normal_pressure_angle"), "angle",
          ("4 deg", "36 deg", "0 deg", "-20 deg", "90 deg")),
        F((*prefix, "helix_angle"), "angle", ("45 deg", "-60 deg", "90 deg")),
        F((*prefix, "face_width"), "length", (0, "-16 mm", "0 mm")),
        F((*prefix, "addendum_coefficient"), "dimensionless", (0, -1)),
        F((*prefix, "dedendum_coefficient"), "dimensionless", (0, -1.25)),
        F((*prefix, "fillet_radius_coefficient"), "dimensionless", (-0.1, 5)),
        # zero and small negative shifts are valid; -3 undercuts and 5 points both gears
        F((*prefix, "profile_shift"), "dimensionless", (-3, 5)),
        F((*prefix, "bore_radius"), "length", (0, "-5 mm", "1 m")),
        F((*prefix, "material"), "table",
          ({"youngs_modulus": -1}, {"poisson_ratio": 0.6}, {"density": "nan kg/m^3"},
           {"unknown_key": 1})),
    ]
    if teeth_index is not None:  # a gear's own name: wrong types, or a duplicate name
        other = "gear" if teeth_index == 0 else "pinion"
        # a duplicate belongs to no one gear: the list-level name gears.name is right too
        fields.append(F((*prefix, "name"), "str", (other,),
                        names=(dotted((*prefix, "name")), "gears.name")))
    return fields


def config_fields() -> list[Field]:
    """Every field of a configuration file checked on ``stiffness CONFIG``."""
    F = Field
    fields = [
        F(("name",), "str"),
        F(("material", "youngs_modulus"), "pressure", (0, -1, "-206.8 GPa", "0 GPa")),
        # negative Poisson ratios down to -1 are physically admissible (auxetic materials)
        F(("material", "poisson_ratio"), "dimensionless", (0.5, 0.75, 2, -1, -1.5)),
        F(("material", "density"), "density", (0, "-7800 kg/m^3")),
        *gear_fields(("common",), None),
        *gear_fields(("gears", 0), 0),
        *gear_fields(("gears", 1), 1),
        F(("operating", "speed"), "speed", (0, "-1800 rpm", "0 rpm")),
        F(("operating", "torque"), "torque", (0, "-100 N*m")),
        F(("stiffness", "closure"), "choice", ("closed", "")),
        F(("stiffness", "plane"), "choice", ("plain", "")),
        F(("stiffness", "source"), "choice", ("fem", "")),
        F(("stiffness", "contact"), "choice", ("hertz", "")),
        F(("stiffness", "coupling"), "choice", ("yes", "")),
        F(("stiffness", "slices"), "int", (0, -1, 2001)),
        F(("stiffness", "positions_per_cycle"), "int", (3, 0, 10001)),
        F(("stiffness", "gauss_points"), "int", (1, 0, 201)),
        F(("cracks", 0, "gear"), "choice", ("wheel", "")),
        F(("cracks", 0, "tooth"), "int", (-1, 19, 1000)),
        F(("cracks", 0, "flank"), "choice", ("both", "")),
        F(("cracks", 0, "depth"), "length", ("-1 mm", "20 mm", "1 m")),
        F(("cracks", 0, "angle"), "angle", ("0 deg", "-45 deg", "91 deg", "180 deg")),
        F(("cracks", 0, "extent"), "dimensionless", (0, -0.5, 1.5)),
        F(("cracks", 0, "profile"), "choice", ("cubic", "")),
        F(("cracks", 0, "start_radius"), "length", (0, "-1 mm", "1 m", "10 mm")),
        F(("analysis", "orders"), "int", (0, -1), list_ok=True),
        F(("analysis", "n_sidebands"), "int", (0, -1)),
        F(("analysis", "window"), "choice", ("hamming", "")),
        F(("analysis", "remove_mean"), "bool"),
        F(("analysis", "impact_factor"), "dimensionless", (0, -1)),
        F(("analysis", "band_fraction"), "dimensionless", (0, 1, 1.5, -0.5)),
        F(("analysis", "stft_frames_per_rev"), "int", (0, -4)),
        F(("analysis", "shaft_harmonics"), "int", (-1,)),
        F(("analysis", "sideband_orders"), "int", (-1,)),
        F(("analysis", "emd_method"), "choice", ("fft", "")),
        F(("analysis", "emd_threshold"), "dimensionless", ()),
        F(("analysis", "emd_max_imf"), "int", (0, -2)),
        F(("analysis", "pulses_per_rev"), "int", (0, -1)),
    ]
    return fields


def dynamics_fields() -> list[Field]:
    """Every field of [dynamics], checked on ``simulate CONFIG``."""
    F = Field
    d = "dynamics"
    return [
        F((d, "model"), "choice", ("lt", "")),
        F((d, "step"), "time", (0, "-1 us")),
        F((d, "duration"), "time", (0, "-1 s")),
        F((d, "transient"), "time", ("-1 s", "-1 ms")),
        F((d, "fs"), "frequency", (0, "-10 kHz")),
        F((d, "oversample"), "int", (0, 65, -1)),
        F((d, "bearing_stiffness"), "stiffness", (0, "-1e9 N/m")),
        F((d, "bearing_axial_stiffness"), "stiffness", (0, -1)),
        F((d, "bearing_damping"), "damping", (-1, "-10 N*s/m")),
        F((d, "bearing_damping_ratio"), "dimensionless", (-0.1, 1, 1.5)),
        F((d, "mesh_damping_ratio"), "dimensionless", (-0.1, 1, 2)),
        F((d, "backlash"), "length", ("-1 um", ["-1 um"], ["10 um", "10 um"]), list_ok=True),
        F((d, "nonlinear"), "bool"),
        F((d, "idler_angle"), "angle", ("0 deg", "360 deg", "-10 deg", "400 deg"),
          list_ok=True),
        F((d, "profile_modification"), "length", ("-1 um", ["1 um", "1 um"]), list_ok=True),
        F((d, "crowning"), "length", ("-1 um", ["1 um", "1 um"]), list_ok=True),
        F((d, "runout"), "length", ("-5 um", ["1 um", "1 um", "1 um"]), list_ok=True),
        F((d, "runout_phase"), "angle", (["0 deg", "0 deg", "0 deg"],), list_ok=True),
        F((d, "assembly_error"), "length", (["1 um", "1 um"],), list_ok=True),
    ]


#: Physically absurd magnitudes (and work no machine finishes), field -> value, verb.
ABSURD = [
    (("gears", 0, "teeth"), 10**9, "stiffness"),
    (("gears", 1, "teeth"), 10**9, "stiffness"),
    (("gears", 0, "face_width"), "1e30 m", "stiffness"),
    (("material", "youngs_modulus"), "1e30 GPa", "stiffness"),
    (("material", "density"), "1e30 kg/m^3", "stiffness"),
    (("operating", "speed"), "1e30 rpm", "stiffness"),
    (("operating", "torque"), "1e30 N*m", "stiffness"),
    (("dynamics", "duration"), "1e9 s", "simulate"),
    (("dynamics", "fs"), "1e15 Hz", "simulate"),
    (("dynamics", "step"), "1e-30 s", "simulate"),
    (("dynamics", "transient"), "1e9 s", "simulate"),
    (("dynamics", "bearing_stiffness"), "1e30 N/m", "simulate"),
]


# ------------------------------------------------------------------------ base inputs

BASE_DOC = tomllib.loads(example_text("spur-19-48"))
#: A short, cheap simulation (one revolution of the 48-tooth gear is 84 ms).
BASE_DOC["dynamics"] = {"duration": "0.1 s", "fs": "10 kHz"}


def _config_case(doc_path: tuple, value: Any, verb: str):
    doc = set_path(BASE_DOC, doc_path, value)
    text = dumps(doc)
    # the mutated document must read back with the bad value in place
    return text


def run_config(doc_path: tuple, value: Any, verb: str, expected: tuple[str, ...]) -> None:
    text = _config_case(doc_path, value, verb)
    with workspace() as (inp, out):
        cfg = inp / "train.toml"
        cfg.write_text(text, encoding="utf-8")
        if verb == "stiffness":
            targets = (out / "k.csv", out / "k.png")
            argv = ["stiffness", str(cfg), "--json", "--out", str(targets[0]),
                    "--plot", str(targets[1])]
        else:
            targets = (out / "run.nc", out / "run.png")
            argv = ["simulate", str(cfg), "--out", str(targets[0]), "--plot", "--json"]
        res = invoke(argv)
        check_refusal(res, expected, out, targets,
                      what=f"{dotted(doc_path)} = {lit(value)} ({verb})")


# --------------------------------------------------------------------- sanity checks


def test_base_config_is_valid_and_written():
    """The starting config and the harness: a valid run exits 0 (guard aside)."""
    text = dumps(BASE_DOC)
    assert tomllib.loads(text) == BASE_DOC
    from gearsim.model import loads

    loads(text)  # valid
    for f in [*config_fields(), *dynamics_fields()]:
        for v in f.bad_values():  # every generated document is valid TOML
            tomllib.loads(dumps(set_path(BASE_DOC, f.path, v)))


def test_guards_fire_on_valid_input():
    """A valid config reaches the (guarded) work: acceptance is seen, not hidden."""
    with workspace() as (inp, out):
        cfg = inp / "train.toml"
        cfg.write_text(dumps(BASE_DOC), encoding="utf-8")
        res = invoke(["stiffness", str(cfg), "--json"])
        assert res.reached, res
        res = invoke(["simulate", str(cfg), "--out", str(out / "run.nc")])
        assert res.reached, res


# ---------------------------------------------------------------- config properties

CONFIG_FIELDS = config_fields()
DYNAMICS_FIELDS = dynamics_fields()


@pytest.mark.parametrize("fld", CONFIG_FIELDS, ids=lambda f: f.name)
@MORE
@given(data=st.data())
def test_config_field_refused(fld: Field, data):
    """stiffness CONFIG with one bad value: refused, parameter named, nothing written."""
    value = data.draw(st.sampled_from(fld.bad_values()), label="value")
    run_config(fld.path, value, "stiffness", fld.expected())


@pytest.mark.parametrize("fld", DYNAMICS_FIELDS, ids=lambda f: f.name)
@MORE
@given(data=st.data())
def test_dynamics_field_refused(fld: Field, data):
    """simulate CONFIG with one bad [dynamics] value: refused before the integration."""
    value = data.draw(st.sampled_from(fld.bad_values()), label="value")
    run_config(fld.path, value, "simulate", fld.expected())


@SETTINGS
@given(case=st.sampled_from(ABSURD))
def test_absurd_magnitude_refused(case):
    """Physically absurd magnitudes (1e30 N*m, 1e9 teeth, 1e15 Hz) are refused up front."""
    path, value, verb = case
    run_config(path, value, verb, (dotted(path),))


@FEW
@given(section=st.sampled_from(["material", "common", "operating", "stiffness",
                                "dynamics", "analysis"]),
       value=st.sampled_from([5, "x", [1, 2], True]))
def test_section_of_wrong_type_refused(section, value):
    """A section that is not a table (``material = 5``) is refused naming the section."""
    doc = {**BASE_DOC, section: value}
    text = dumps(doc)
    with workspace() as (inp, out):
        cfg = inp / "train.toml"
        cfg.write_text(text, encoding="utf-8")
        res = invoke(["stiffness", str(cfg), "--json", "--out", str(out / "k.csv")])
        check_refusal(res, section, out, (out / "k.csv",), what=f"{section} = {lit(value)}")


@FEW
@given(section=st.sampled_from(["material", "common", "operating", "stiffness",
                                "dynamics", "analysis", "gears[0]", "cracks[0]"]),
       key=st.sampled_from(["foo", "Face_width", "speed_rpm"]))
def test_unknown_key_refused(section, key):
    """An unknown key in any section is refused naming section.key."""
    if section.endswith("]"):
        name, idx = section[:-1].split("[")
        path: tuple = (name, int(idx), key)
    else:
        path = (section, key)
    run_config(path, 1, "stiffness", (f"{section}.{key}",))


# ------------------------------------------------------------------- CLI arguments

NUMBER_GARBAGE = ["nan", "inf", "-inf", "1e400", "abc", "", "1,5", "0x", "--"]


def _simulate_argv(cfg: Path, out: Path, opt: str, value: str) -> list[str]:
    argv = ["simulate", str(cfg), "--out", str(out / "run.nc"), "--plot", "--json"]
    if opt != "--duration":
        argv += ["--duration", "0.1"]
    return argv + [f"{opt}={value}"]


SIMULATE_BAD = {
    "--duration": NUMBER_GARBAGE + ["-1", "0", "1e30"],
    "--fs": NUMBER_GARBAGE + ["-1", "0", "1e30"],
    "--step": NUMBER_GARBAGE + ["-1", "0", "1e-30"],
    "--transient": NUMBER_GARBAGE + ["-1", "1e30"],
    "--model": ["xyz", "", "1", "nan"],
    "--crack": ["both", "", "1", "nan"],
}


@WIDE
@given(data=st.data())
def test_simulate_options_refused(data):
    """simulate with a bad --duration/--fs/--step/--transient/--model/--crack."""
    opt = data.draw(st.sampled_from(sorted(SIMULATE_BAD)), label="option")
    value = data.draw(st.sampled_from(SIMULATE_BAD[opt]), label="value")
    with workspace() as (inp, out):
        cfg = inp / "train.toml"
        cfg.write_text(dumps(BASE_DOC), encoding="utf-8")
        res = invoke(_simulate_argv(cfg, out, opt, value))
        check_refusal(res, opt, out, (out / "run.nc", out / "run.png"),
                      what=f"simulate {opt}={value!r}")


REPRODUCE_BAD = {
    "--depth": ["nan", "inf", "-inf", "-1", "-1 mm", "1 kg", "abc", "", "inf mm",
                "nan mm", "100 mm", "1e400"],
    "--depths": ["nan", "1, nan", "-1", "", ",", "1 kg", "1, abc", "1, 100", "inf",
                 "1, -1"],
    "--revolutions": ["0", "-1", "3", "abc", "1.5", "1e400", "", "nan", "10000000000"],
}


@WIDE
@given(data=st.data())
def test_reproduce_options_refused(data):
    """reproduce with a bad --depth/--depths/--revolutions: nothing run, no folder."""
    opt = data.draw(st.sampled_from(sorted(REPRODUCE_BAD)), label="option")
    value = data.draw(st.sampled_from(REPRODUCE_BAD[opt]), label="value")
    with workspace() as (_inp, out):
        target = out / "rep"
        given_opts = {"--config": "spur-19-48", "--depth": "1 mm", "--depths": "0.5, 1",
                      "--revolutions": "16", opt: value}
        argv = ["reproduce", "--out", str(target), "--no-fe", "--quiet"]
        for k, v in given_opts.items():
            argv.append(f"{k}={v}")
        res = invoke(argv)
        check_refusal(res, opt, out, (target,), what=f"reproduce {opt}={value!r}")


FE_BAD = {
    "--points": ["0", "2", "-1", "abc", "1.5", "", "nan", "100000000"],
    "--level": ["-1", "abc", "1.5", "", "nan", "7", "100"],
    "--crack": ["both", "", "1"],
    "--closure": ["closed", "", "1"],
    "--gear": ["wheel", "", "1"],
}


@WIDE
@given(data=st.data())
def test_fe_check_options_refused(data):
    """fe-check with a bad --points/--level/--crack/--closure/--gear: no FE solve."""
    opt = data.draw(st.sampled_from(sorted(FE_BAD)), label="option")
    value = data.draw(st.sampled_from(FE_BAD[opt]), label="value")
    with workspace() as (_inp, out):
        figs = out / "figs"
        res = invoke(["fe-check", "spur-19-48", "--plot", str(figs), "--json",
                      f"{opt}={value}"])
        check_refusal(res, opt, out, (figs,), what=f"fe-check {opt}={value!r}")


# ------------------------------------------------------------------ measured records

FS = 4000.0   # base record: 2 s at 4 kHz, 600 rpm, 20 teeth (order 4 + 6 sidebands < Nyquist)
N = 8000


def _samples() -> list[float]:
    return [math.sin(2 * math.pi * 200 * i / FS) + 0.1 * math.sin(2 * math.pi * 210 * i / FS)
            for i in range(N)]


BASE_SAMPLES = _samples()


def _csv(values: list[Any], header: str | None = "acc") -> str:
    body = "\n".join(v if isinstance(v, str) else f"{v:.6g}" for v in values)
    return (f"{header}\n" if header is not None else "") + body + "\n"


ANALYZE_BAD = {
    "--fs": ["0", "-1", "nan", "inf", "abc", "1e400", "", "-inf"],
    "--shaft-rpm": ["0", "-600", "nan", "inf", "abc", "", "1e400"],
    "--teeth": ["0", "-20", "abc", "1.5", "", "nan"],
    "--channel": ["nosuch", "", "1"],
}


def _analyze_argv(rec: Path, out: Path, **opts: str) -> list[str]:
    given_opts = {"--fs": "4000", "--shaft-rpm": "600", "--teeth": "20", **opts}
    argv = ["analyze", str(rec), "--plot", str(out / "figs"), "--json"]
    return argv + [f"{k}={v}" for k, v in given_opts.items()]


@WIDE
@given(data=st.data())
def test_analyze_options_refused(data):
    """analyze a valid record with a bad --fs/--shaft-rpm/--teeth/--channel."""
    opt = data.draw(st.sampled_from(sorted(ANALYZE_BAD)), label="option")
    value = data.draw(st.sampled_from(ANALYZE_BAD[opt]), label="value")
    with workspace() as (inp, out):
        rec = inp / "rec.csv"
        rec.write_text(_csv(BASE_SAMPLES), encoding="utf-8")
        res = invoke(_analyze_argv(rec, out, **{opt: value}))
        check_refusal(res, opt, out, (out / "figs",), what=f"analyze {opt}={value!r}")


class Blob(bytes):
    """File content with a short repr (Hypothesis prints the drawn examples)."""

    def __repr__(self) -> str:
        return f"<{len(self)} bytes: {bytes(self[:24])!r}...>"


@st.composite
def _bad_records(draw) -> tuple[str, bytes, str]:
    """(file name, content, description) of a measured file that cannot be analysed."""
    # (a two-sample record is analysable since the tiers: its statistics are computed and
    # the tiers it is too short for are skipped with the reason, tests/signals)
    kind = draw(st.sampled_from(["bad-cell", "empty", "header-only", "one-sample",
                                 "binary", "garbage-other", "ragged", "all-nan",
                                 "bom-text"]))
    if kind == "bad-cell":
        cell = draw(st.sampled_from(["inf", "nan", "-inf", "abc", "1e400", "", "1,5"]))
        # an empty first cell of a one-column file is a blank line before the data, which
        # the reader skips as layout: only an empty cell between samples is a lost sample
        i = draw(st.integers(1 if cell == "" else 0, N - 1))
        vals: list[Any] = list(BASE_SAMPLES)
        vals[i] = cell
        return "rec.csv", _csv(vals).encode(), f"CSV with cell {i} = {cell!r}"
    if kind == "empty":
        return "rec.csv", b"", "empty CSV"
    if kind == "header-only":
        return "rec.csv", b"acc\n", "header-only CSV"
    if kind == "one-sample":
        return "rec.csv", _csv([0.5]).encode(), "CSV with one sample"
    if kind == "binary":
        blob = draw(st.binary(min_size=16, max_size=256))
        return "rec.csv", b"\x00\xff\xfe" + blob, "binary garbage with a .csv extension"
    if kind == "garbage-other":
        ext = draw(st.sampled_from([".wav", ".mat", ".nc", ".tdms", ".uff", ".txt"]))
        return f"rec{ext}", b"\x00\x01garbage\xff" * 8, f"garbage with a {ext} extension"
    if kind == "ragged":
        text = _csv(BASE_SAMPLES[:100]) + "1,2,3\n" + _csv(BASE_SAMPLES[100:], header=None)
        return "rec.csv", text.encode(), "CSV with a ragged row"
    if kind == "all-nan":
        return "rec.csv", _csv(["nan"] * N).encode(), "CSV of nan only"
    return "rec.csv", ("acc\n" + "hello\n" * 50).encode(), "CSV of text"


def bad_records() -> st.SearchStrategy[tuple[str, bytes, str]]:
    return _bad_records().map(lambda r: (r[0], Blob(r[1]), r[2]))


@WIDEST
@given(rec=bad_records())
def test_measured_file_refused(rec):
    """analyze FILE on a damaged record: refused naming the file, no figures."""
    name, content, what = rec
    with workspace() as (inp, out):
        path = inp / name
        path.write_bytes(content)
        res = invoke(_analyze_argv(path, out))
        # the file, or the record it holds ("record duration = ...: must be >= ...")
        check_refusal(res, (name, str(path), "record"), out, (out / "figs",), what=what)


# ------------------------------------------------------------------------- studies

BASE_STUDY: dict[str, Any] = {
    "study": {"name": "bad-input property test", "config": "spur-19-48",
              "sampling": "grid", "seed": 1, "replicates": 1,
              "signal": "acceleration[pinion,y]", "shafts": "all", "store_signals": False,
              # long enough for the sideband analysis of every case (refused up front)
              "dynamics": {"duration": "0.4 s", "fs": "10 kHz"}},
    "parameters": {"crack_depth": ["0.5 mm"], "flank": ["working"], "noise": [0.0]},
}

STUDY_BAD: dict[tuple, list[Any]] = {
    ("study", "name"): [5, True, ["a"]],
    ("study", "config"): ["no-such-train.toml", 5, "", True],
    ("study", "sampling"): ["sobol", "", 1, True],
    ("study", "seed"): [-1, 1.5, "x", True, Raw("nan")],
    ("study", "replicates"): [0, -1, 1.5, "2", True, 10**12],
    ("study", "signal"): ["", 5, "no_such_signal", "acceleration[nosuch,y]",
                          "acceleration[pinion,q]"],
    ("study", "shafts"): ["some", "", 1],
    ("study", "store_signals"): ["yes", 1, "true"],
    ("study", "dynamics", "duration"): [0, "-1 s", Raw("nan"), "inf s", "3 kg", "1e9 s"],
    ("study", "dynamics", "fs"): [0, "-1 Hz", Raw("nan"), Raw("inf"), "3 mm", "1e15 Hz"],
    ("study", "dynamics", "transient"): ["-1 s", Raw("nan"), "3 kg"],
    ("study", "dynamics", "step"): [0, "-1 us", Raw("nan"), "1e-30 s"],
    ("study", "dynamics", "model"): ["lt", 1, ""],
    ("study", "dynamics", "foo"): [1],
    ("parameters", "crack_depth"): [[Raw("nan")], ["-1 mm"], ["1 kg"], ["100 mm"], [],
                                    ["inf mm"], {"min": "2 mm", "max": "1 mm", "num": 2},
                                    {"min": "1 mm", "max": "2 mm", "num": 0},
                                    {"min": "1 mm", "max": "2 mm"}, {"min": "nan mm",
                                                                      "max": "1 mm",
                                                                      "num": 2}],
    ("parameters", "flank"): [["both"], [""], [1], []],
    ("parameters", "closure"): [["closed"], [1], []],
    ("parameters", "speed"): [["-1 rpm"], [0], ["inf rpm"], [Raw("nan")], ["5 s"]],
    ("parameters", "torque"): [[-1], [Raw("nan")], ["1 kg"], ["0 N*m"]],
    ("parameters", "bearing_stiffness"): [[0], [-1], [Raw("inf")], ["1 kg"]],
    ("parameters", "noise"): [[-0.1], [Raw("nan")], [Raw("inf")], ["1 mm"]],
    ("parameters", "foo"): [[1]],
}


def _study_expected(path: tuple) -> str:
    return ".".join(str(p) for p in path)


def _study_text(path: tuple, value: Any) -> str:
    doc = set_path(BASE_STUDY, path, value)
    return dumps(doc)


def test_base_study_is_valid():
    from gearsim.studies.sweep import expand, loads_study

    text = dumps(BASE_STUDY)
    assert tomllib.loads(text) == BASE_STUDY
    assert len(expand(loads_study(text))) == 1
    for path, values in STUDY_BAD.items():
        for v in values:
            tomllib.loads(_study_text(path, v))


@WIDEST
@given(data=st.data())
def test_study_file_refused(data):
    """sweep STUDY with one bad [study] or [parameters] value: no store, no parts."""
    path = data.draw(st.sampled_from(sorted(STUDY_BAD, key=str)), label="field")
    value = data.draw(st.sampled_from(STUDY_BAD[path]), label="value")
    with workspace() as (inp, out):
        study = inp / "study.toml"
        study.write_text(_study_text(path, value), encoding="utf-8")
        store = out / "S.nc"
        res = invoke(["sweep", str(study), "--out", str(store), "--workers", "1",
                      "--no-progress"])
        expected = (_study_expected(path),)
        if path == ("study", "replicates"):  # the case-count cap names its own key
            expected += ("study.max_cases",)
        check_refusal(res, expected, out,
                      (store, out / "S.nc.parts"),
                      what=f"{_study_expected(path)} = {lit(value)}")


SWEEP_BAD = {
    "--workers": ["0", "-1", "abc", "1.5", ""],
    "--out": ["S.txt", "", "S"],
}


@FEW
@given(data=st.data())
def test_sweep_options_refused(data):
    """sweep with a bad --workers or --out: nothing written."""
    opt = data.draw(st.sampled_from(sorted(SWEEP_BAD)), label="option")
    value = data.draw(st.sampled_from(SWEEP_BAD[opt]), label="value")
    with workspace() as (inp, out):
        study = inp / "study.toml"
        study.write_text(dumps(BASE_STUDY), encoding="utf-8")
        opts = {"--out": str(out / "S.nc"), "--workers": "1", opt: value}
        if opt == "--out":
            opts["--out"] = str(out / value) if value else ""
        argv = ["sweep", str(study), "--no-progress"] + [f"{k}={v}" for k, v in opts.items()]
        old = os.getcwd()
        os.chdir(out)  # a relative store must not appear either
        try:
            res = invoke(argv)
        finally:
            os.chdir(old)
        check_refusal(res, opt, out, (), what=f"sweep {opt}={value!r}")
