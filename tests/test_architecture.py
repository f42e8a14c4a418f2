"""The layer contracts of pyproject.toml ([tool.importlinter]) hold, and can fail.

import-linter builds the import graph of the package (function-level imports included;
imports under ``if TYPE_CHECKING:`` excluded) and checks the declared layers
geometry -> stiffness -> fem -> system -> dynamics -> model -> studies -> api -> commands,
with signals, viz and io beside the chain, and that only ``gearsim.viz`` imports
matplotlib.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINT = [sys.executable, "-c", "import sys; from importlinter.cli import lint_imports_command;"
        " sys.exit(lint_imports_command())"]


def _lint(src: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(src)}
    return subprocess.run([*LINT, "--config", str(ROOT / "pyproject.toml"), "--no-cache"],
                          capture_output=True, text=True, env=env, cwd=src, timeout=300)


def test_layer_contracts_hold():
    res = _lint(ROOT / "src")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "2 kept, 0 broken" in res.stdout


def test_a_forbidden_import_breaks_the_contract(tmp_path):
    """A lower layer importing a higher one (geometry -> commands) is reported."""
    src = tmp_path / "src"
    shutil.copytree(ROOT / "src" / "gearsim", src / "gearsim",
                    ignore=shutil.ignore_patterns("__pycache__"))
    gear = src / "gearsim" / "geometry" / "gear.py"
    gear.write_text(gear.read_text() + "\nimport gearsim.commands.basic  # noqa\n")
    res = _lint(src)
    assert res.returncode != 0
    assert "BROKEN" in res.stdout
    assert "gearsim.geometry.gear -> gearsim.commands.basic" in res.stdout
