"""The FE mesher works in any thread, as a Dask worker runs it.

gmsh's default ``interruptible`` session installs a SIGINT handler, which Python allows in
the main thread only: in a worker thread the sector mesher raised "signal only works in
main thread", the crack correction took it for a crack the FE tooth refuses and fell
back to Q = 1, so a study's crack cases depended on ``--workers`` (a tester's
two-stage-reducer study: FM4 3.14 against 33.71 at 20 N m). Two threads meshing at once
must also give each its own mesh (gmsh keeps one state per process).
"""

from __future__ import annotations

import threading

import numpy as np

from gearsim.fem.geometry import SectorOptions, crack_line, mesh_sector
from gearsim.geometry.profile import ToothProfile


def _mesh(gear, cl):
    m = mesh_sector(gear, crack=cl, options=SectorOptions(level=1))
    return m.p.shape, m.t.shape, m.crack_pairs.shape


def test_a_cracked_sector_meshes_in_worker_threads_as_in_the_main_thread(spur):
    gear = spur.gears[0]
    cl = crack_line(ToothProfile(gear), spur.cracks[0], 1e-3, 1)
    want = _mesh(gear, cl)
    got, errors = [], []

    def work():
        try:
            got.append(_mesh(gear, cl))
        except Exception as exc:  # noqa: BLE001  (the test reports it)
            errors.append(repr(exc))

    threads = [threading.Thread(target=work) for _ in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert errors == []
    assert got == [want, want]
    assert np.prod(want[1]) > 0 and want[2][1] > 0  # triangles, split crack faces
