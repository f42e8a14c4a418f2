"""gearsim.io.atomic.exclusive: processes computing the same cache entry take turns (the
calibration cache: test workers, Dask workers and the install's warm-up)."""

from __future__ import annotations

import subprocess
import sys
import time

from gearsim.io.atomic import exclusive

HOLD = """
import sys, time
from gearsim.io.atomic import exclusive
with exclusive(sys.argv[1]):
    print("held", flush=True)
    time.sleep(float(sys.argv[2]))
"""


def test_a_second_process_waits_for_the_first(tmp_path):
    lock = tmp_path / "sub" / "k.lock"  # the folder is created
    hold = 1.0
    p = subprocess.Popen([sys.executable, "-c", HOLD, str(lock), str(hold)],
                         stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "held"
        t0 = time.monotonic()
        with exclusive(lock):
            waited = time.monotonic() - t0
        assert waited > 0.5 * hold  # blocked until the other process let go
    finally:
        p.wait(timeout=30)
    t0 = time.monotonic()
    with exclusive(lock):  # free now: no wait
        pass
    assert time.monotonic() - t0 < 0.5 * hold and lock.exists()
