"""Shared fixtures."""

from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

from gearsim.model import load


@pytest.fixture(scope="session")
def table1():
    """The built-in Table-1 idler train (with its example crack)."""
    return load("idler-table1").train


@pytest.fixture(scope="session")
def spur():
    """The built-in 19/48 spur pair."""
    return load("spur-19-48").train


@pytest.fixture(scope="session")
def build_once(tmp_path_factory) -> Callable[[str, Callable[[Path], None]], Path]:
    """``build_once(name, build)``: the folder ``build(folder)`` made once per test session.

    Shared by the pytest-xdist workers of the session (a folder beside their own base
    temporary folders), built by whichever worker asks first while the others wait on
    a file lock; a build that raised is retried by the next caller. Callers must treat
    the folder as read-only (copy it to change it).
    """
    base = tmp_path_factory.getbasetemp()
    # an xdist worker's base is <session>/popen-gwN: its parent is the session's own
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "shared-builds"
    root.mkdir(parents=True, exist_ok=True)

    def build(name: str, make: Callable[[Path], None]) -> Path:
        folder, done = root / name, root / f"{name}.done"
        with open(root / f"{name}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                if not done.exists():
                    if folder.exists():  # a build that failed part-way
                        shutil.rmtree(folder)
                    folder.mkdir()
                    make(folder)
                    done.touch()
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)
        return folder

    return build


def reproduce_small(folder: Path) -> None:
    """``gearsim reproduce`` at reduced size into ``folder / "rep"``: no FE route, 13 input
    revolutions (the least the sideband analysis accepts), one sensitivity depth, the
    fault-magnitude section at one severity (every figure of the report is drawn)."""
    from gearsim import cli

    mp = pytest.MonkeyPatch()
    mp.setenv("GEARSIM_CACHE", str(folder / "cache"))
    try:
        code = cli.run(["reproduce", "--no-fe", "--revolutions", str(SMALL_REVOLUTIONS),
                        "--depths", "2mm", "--fault-severities", "1",
                        "--out", str(folder / "rep"), "--quiet"])
    finally:
        mp.undo()
    assert code == 0, "gearsim reproduce (small) failed"


#: Input revolutions of the small reproduction: the least ``reproduce`` accepts.
SMALL_REVOLUTIONS = 13


@pytest.fixture(scope="session")
def small_reproduction(build_once) -> Path:
    """Output folder of the small ``gearsim reproduce`` (read-only; copy it to change it),
    built once per session and shared by the test files that need a whole report."""
    return build_once("reproduce-small", reproduce_small) / "rep"


@pytest.fixture
def gearsim_here(capsys) -> Callable[..., subprocess.CompletedProcess]:
    """``gearsim_here(*args, cwd=None)``: the command line ``gearsim *args`` run in this
    process (:func:`gearsim.cli.run`, the function behind the installed script, in
    ``cwd``), returned like :func:`subprocess.run` with ``capture_output=True, text=True``
    (status, stdout, stderr). Spares the ~4.5 s of CPU a new interpreter pays on imports;
    tests/test_cli_errors.py checks the script itself in a real process."""
    from gearsim import cli

    def run(*args, cwd=None) -> subprocess.CompletedProcess:
        capsys.readouterr()  # drop what came before
        with contextlib.chdir(cwd) if cwd is not None else contextlib.nullcontext():
            code = cli.run([str(a) for a in args])
        out = capsys.readouterr()
        return subprocess.CompletedProcess(["gearsim", *map(str, args)], code, out.out,
                                           out.err)

    return run
