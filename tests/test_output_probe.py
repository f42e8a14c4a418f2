"""Output targets that permissions cannot judge (a read-only pseudo file system, as root
too) are refused before any work, by every verb that writes (issue 24, bad input).

The verbs run in this process (``gearsim_here`` of tests/conftest.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not Path("/proc/self").exists(), reason="needs /proc (Linux)")


@pytest.mark.parametrize("args", [
    ["stiffness", "spur-19-48", "--out", "/proc/k.csv"],
    ["stiffness", "spur-19-48", "--plot", "/proc/k.png"],
    ["simulate", "spur-19-48", "--out", "/proc/run.nc"],
    ["contact", "spur-19-48", "--out", "/proc/c.nc"],
    ["layout", "two-stage-reducer", "--plot", "/proc/l.png"],
    ["reproduce", "--out", "/proc/rep"],
    ["sweep", "diagnostic", "--out", "/proc/s.nc"],
])
def test_unwritable_target_is_refused_before_work(args, gearsim_here):
    r = gearsim_here(*args)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2, r.stderr
    assert len(lines) == 1 and "cannot be written" in lines[0], r.stderr
