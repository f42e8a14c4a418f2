"""Tier 1: a cracked input gear gives impacts once per input revolution and sidebands
at n f_m +- k f_r1 in the mesh force (checked with plain numpy).

Sampling at fs = 40 f_m over exactly four input revolutions puts 40 samples in each mesh
cycle and every n f_m +- k f_r1 on an FFT bin (f_r1 / 4 resolution), so no window is
needed. The healthy train is exactly mesh-periodic: its sideband bins are at round-off
level, which is the baseline.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.dynamics import DynamicsSettings, simulate
from gearsim.model import load


@pytest.mark.parametrize("model", ["lta", "seed"])
def test_impacts_and_sidebands(model):
    tr = load("idler-table1").train  # 2 mm working-flank crack, input gear, tooth 0
    z1 = tr.gears[0].teeth
    fr1, fm = tr.shaft_frequency(0), tr.mesh_frequency
    revs = 4
    s = DynamicsSettings(model=model, duration=revs / fr1, fs=40 * fm)
    x = {}
    for name, train in (("cracked", tr), ("healthy", tr.with_cracks(()))):
        x[name] = simulate(train, s)["mesh_force_1"].values
    n = x["cracked"].size
    assert n == revs * z1 * 40
    # impacts: per-mesh-cycle RMS of the residual from the mean mesh cycle
    cyc = x["cracked"].reshape(revs * z1, 40)
    r = np.sqrt(((cyc - cyc.mean(axis=0)) ** 2).mean(axis=1))
    top = np.sort(np.argsort(r)[-revs:])
    np.testing.assert_array_equal(np.diff(top), z1)  # period = z1 mesh cycles = 1/f_r1
    assert r[top].min() > 5 * np.median(r)
    # sidebands
    spec = {k: np.abs(np.fft.rfft(v - v.mean())) * 2 / n for k, v in x.items()}
    df = fr1 / revs
    for harmonic in (1, 2):
        c = int(round(harmonic * fm / df))
        for k in (1, 2, 3):
            for side in (-1, 1):
                b = c + side * k * revs
                sb = spec["cracked"][b]
                assert sb > 0.02, (harmonic, side * k, sb)  # N
                assert sb > 1e3 * spec["healthy"][b]
                # between the sidebands (half-order of f_r1) there is nothing
                assert spec["cracked"][b + revs // 2] < 1e-2 * sb


def test_cracked_idler_shows_in_both_meshes():
    """An idler crack appears once per idler revolution (59 mesh cycles) in both meshes;
    with cracks on input and idler, mesh I's table spans lcm(39, 59) cycles."""
    from gearsim.dynamics.tables import mesh_tables
    from gearsim.stiffness.crack import Crack

    tr = load("idler-table1").train
    idler = tr.gears[1]
    tr_i = tr.with_cracks((Crack(gear=idler.name, tooth=3, depth=2e-3),))
    tabs = mesh_tables(tr_i)
    assert [t.period for t in tabs] == [idler.teeth, idler.teeth]
    both = mesh_tables(tr.with_cracks((*tr.cracks, *tr_i.cracks)))
    assert both[0].period == tr.gears[0].teeth * idler.teeth
    fm = tr.mesh_frequency
    revs = 3  # >= one output revolution
    s = DynamicsSettings(duration=revs * idler.teeth / fm, fs=40 * fm)
    ds = simulate(tr_i, s, tables=tabs)
    for i in (1, 2):
        cyc = ds[f"mesh_force_{i}"].values.reshape(revs * idler.teeth, 40)
        r = np.sqrt(((cyc - cyc.mean(axis=0)) ** 2).mean(axis=1))
        top = np.sort(np.argsort(r)[-revs:])
        np.testing.assert_array_equal(np.diff(top), idler.teeth, err_msg=f"mesh {i}")
