"""Property-based suite over the verbs' numeric options with extreme finite values
(issue 24, bad input round three): every run ends with exit 0, or exit 2 and exactly one
``gearsim: error:`` line on standard error; never a traceback or ``internal error``.

The CLI runs in process (:func:`gearsim.cli.run`). The expensive work (mesh stiffness
tables and the integrator of ``simulate``, the contact analysis, the FE solves, the
reproduction's simulations, a Dask cluster) is replaced by a guard that stops the run:
a value that reaches it passed every up-front check, which is all this suite can afford
to see (a run beyond the guard is what the slow suites exercise).
"""

from __future__ import annotations

import contextlib
import io
import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import gearsim.cli as cli

#: Extreme finite numbers and huge counts, as typed on a command line.
NUMBERS = ["1e-300", "-1e-300", "5e-324", "1e300", "-1e300", "1.7e308", "0", "-0", "-1",
           "1", "0.5", "1e-9", "1e9"]
COUNTS = ["0", "-1", "-100", "1", "2", "1000000", "100000000000000000000",
          "9223372036854775808"]
SETTINGS = settings(derandomize=True, database=None, deadline=None, max_examples=30,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])


class ReachedWork(Exception):
    """Raised by a guard: the value passed every up-front check."""


GUARDS = [("gearsim.dynamics.simulate", "mesh_tables"), ("gearsim.dynamics.simulate", "run_kernel"),
          ("gearsim.stiffness.ltca", "loaded_contact"), ("gearsim.fem.pair", "mesh_sector"),
          ("gearsim.studies.reproduce", "simulate_cases"), ("distributed", "LocalCluster"),
          ("gearsim.studies.sweep_run", "part_bytes")]  # a one-worker sweep runs in-process


@pytest.fixture(autouse=True)
def _guards(monkeypatch):
    import importlib

    def guard(*_a, **_k):
        raise ReachedWork("ReachedWork: the value passed every up-front check")

    for mod, path in GUARDS:
        owner, _, attr = path.rpartition(".")
        target = importlib.import_module(mod)
        monkeypatch.setattr(getattr(target, owner) if owner else target, attr, guard)
    monkeypatch.delenv("GEARSIM_DEBUG", raising=False)


def check(argv: list[str]) -> None:
    """Run ``argv``: exit 0, or exit 2 with one error line, or the guard reached."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.run(argv)
    text = err.getvalue()
    if "ReachedWork" in text:
        return
    assert "Traceback" not in text and "internal error" not in text, (argv, text)
    errors = [ln for ln in text.splitlines() if not ln.startswith(("gearsim: warning:",
                                                                   "gearsim: note:"))]
    assert code in (0, 2), (argv, code, text)
    if code == 2:
        assert len(errors) == 1 and errors[0].startswith("gearsim: error: "), (argv, text)


@pytest.fixture(scope="module")
def record(tmp_path_factory) -> Path:
    """2 s at 4 kHz: a 200 Hz mesh line (600 rpm x 20 teeth) with a 10 Hz sideband."""
    path = tmp_path_factory.mktemp("rec") / "rec.csv"
    path.write_text("acc\n" + "\n".join(
        f"{math.sin(2 * math.pi * 200 * i / 4000) + 0.1 * math.sin(2 * math.pi * 210 * i / 4000):.6g}"
        for i in range(8000)) + "\n")
    return path


@settings(SETTINGS, max_examples=60)
@given(data=st.data())
def test_analyze_numeric_options(record, tmp_path, data):
    opt = data.draw(st.sampled_from(["--fs", "--shaft-rpm", "--speed-search", "--workers"]))
    if opt == "--speed-search":
        value = f"{data.draw(st.sampled_from(NUMBERS))},{data.draw(st.sampled_from(NUMBERS))}"
    else:
        value = data.draw(st.sampled_from(COUNTS if opt == "--workers" else NUMBERS))
    base = {"--fs": "4000", "--teeth": "20"} | ({} if opt == "--speed-search" else
                                                {"--shaft-rpm": "600"})
    check(["analyze", str(record), *(f"{k}={v}" for k, v in (base | {opt: value}).items())])


@SETTINGS
@given(opt=st.sampled_from(["--duration", "--fs"]), value=st.sampled_from(NUMBERS))
def test_simulate_numeric_options(tmp_path, opt, value):
    check(["simulate", "spur-19-48", "--out", str(tmp_path / "r.nc"), "--duration=0.1",
           f"{opt}={value}"])


@SETTINGS
@given(verb=st.sampled_from(["contact", "fe-pair"]), value=st.sampled_from(NUMBERS),
       unit=st.sampled_from(["", " N*m"]))
def test_torque(tmp_path, verb, value, unit):
    check([verb, "spur-19-48", f"--torque={value}{unit}"]
          + (["--positions=1"] if verb == "fe-pair" else []))


@SETTINGS
@given(value=st.one_of(st.sampled_from(COUNTS), st.sampled_from(NUMBERS).map("0.5,{}".format)))
def test_fe_pair_positions(value):
    check(["fe-pair", "spur-19-48", f"--positions={value}"])


@SETTINGS
@given(value=st.one_of(st.sampled_from(NUMBERS), st.sampled_from(NUMBERS).map("1, {}".format)))
def test_reproduce_depths(tmp_path, value):
    check(["reproduce", "--out", str(tmp_path / "r"), "--config=spur-19-48", "--no-fe",
           "--quiet", "--fault-severities=none", "--depth=1 mm", f"--depths={value}"])


@settings(SETTINGS, max_examples=8)
@given(value=st.sampled_from(COUNTS))
def test_sweep_workers(tmp_path, value):
    check(["sweep", "diagnostic", "--out", str(tmp_path / "s.nc"), "--no-progress",
           f"--workers={value}"])
