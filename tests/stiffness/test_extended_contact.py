"""Tip-corner contact under load in the stiffness tables (issue 25 item 2).

Under the line contact law (the accurate model) the tables close the tip corners of the
pairs just outside the path of contact when the loaded transmission error exceeds their
separation (:func:`gearsim.stiffness.mesh.extended_law`, docs/stiffness.md 4c); the
seed's law keeps the path of contact. Accuracy against the FE gear pair is in
``test_calibrated.py`` (zone ends, cycle mean); here: the gate, the identity with the
path-only table where no corner closes, continuity across the ends of the path, and the
corner's separation in the FE pair's position convention.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gearsim as gs
from gearsim.geometry.corners import corner_separation
from gearsim.stiffness.mesh import corner_closing, extended_grid, mesh_stiffness
from gearsim.stiffness.settings import MODELS
from gearsim.system.train import body_coupling, tooth_compliance

#: Round-off level of results that must be identical to another route.
IDENTICAL = 1e-9
#: Largest relative change of the extended table between adjacent samples at 400
#: positions per cycle (measured 2.5 % at 100 N m where an incoming corner starts to
#: carry load, 1.2 % at 400 N m); the path-only table jumps by 23-24 % at the ends.
CONTINUOUS_STEP = 0.05
#: Positions per cycle of the continuity check.
FINE = 400


def _table(train, corner: bool, model: str = "accurate", torque: float = 100.0,
           npc: int = 40):
    pair = train.pairs[0]
    st = dataclasses.replace(train.stiffness, positions_per_cycle=npc, corner_contact=corner,
                             **MODELS[model])
    return mesh_stiffness(pair, cracks=train.mesh_cracks(0), settings=st,
                          compliance=tooth_compliance(st.source),
                          force=torque / pair.driver.base_radius, coupling=body_coupling(st))


@pytest.fixture(scope="module")
def spur():
    return gs.example("spur-19-48").train


@pytest.mark.parametrize("name", ["spur-19-48", "idler-table1"])
def test_seed_table_is_untouched(name):
    """The seed's law (load-independent contact) has no tip-corner contact in its
    tables: the option changes nothing, bit for bit (cracked, spur and helical)."""
    tr = gs.example(name).train
    tr = dataclasses.replace(tr, stiffness=dataclasses.replace(tr.stiffness, slices=10))
    a = _table(tr, True, "seed", npc=20)
    b = _table(tr, False, "seed", npc=20)
    assert tr.mesh_cracks(0)
    for x, y in ((a.k, b.k), (a.pair_k, b.pair_k), (a.pair_tooth1, b.pair_tooth1),
                 *((a.components[c], b.components[c]) for c in a.components)):
        assert np.array_equal(x, y)
    assert a.attrs == b.attrs


def _near_an_edge(pair, torque: float, npc: int) -> np.ndarray:
    """Positions of a cycle where a path contact lies within a Hertz half width of a tip
    edge (the half width of the whole mesh force on one contact: the widest strip)."""
    st = dataclasses.replace(gs.example("spur-19-48").train.stiffness,
                             positions_per_cycle=npc, **MODELS["accurate"])
    lmid, width, corner, *_, edge = extended_grid(pair, st)
    w = torque / pair.driver.base_radius / pair.face_width
    rel = 1.0 / (1.0 / lmid + 1.0 / (pair.line_length - lmid))
    e_inv = 1.0 / pair.driver.material.youngs_modulus + 1.0 / pair.driven.material.youngs_modulus
    half = np.sqrt(4.0 * w * rel * e_inv / np.pi)
    return np.any((width > 0) & ~corner & (edge > -half), axis=(1, 2))


@pytest.mark.parametrize("torque", [100.0, 400.0])
def test_path_table_where_no_corner_closes(spur, torque):
    """Where no corner carries load and no path contact reaches a tip edge, the extended
    table is the path-only table: the same law, fixed point and coupling (1e-9); where a
    corner carries load and no edge cuts a path contact it is stiffer."""
    ext = _table(spur.with_cracks(()), True, torque=torque)
    path = _table(spur.with_cracks(()), False, torque=torque)
    npc = 40
    u = (np.arange(ext.k.size) % npc) / npc
    eps1 = spur.pairs[0].transverse_contact_ratio - 1.0
    # cells that straddle a transition carry in-path fractions in the path-only table
    whole = (np.abs(u - eps1) > 1.0 / npc) & (u > 0.5 / npc) & (u < 1 - 0.5 / npc)
    on_path = np.where(u <= eps1, 2, 1)  # pairs on the path of contact (eps < 2)
    no_corner = np.sum(ext.pair_k > 0, axis=1) == on_path  # no corner loaded
    near = np.tile(_near_an_edge(spur.pairs[0], torque, npc), ext.k.size // npc)
    free = whole & no_corner & ~near
    assert free.sum() > 0.5 * ext.k.size
    np.testing.assert_allclose(ext.k[free], path.k[free], rtol=IDENTICAL)
    assert np.all(ext.k[~near] >= path.k[~near] * (1 - IDENTICAL))
    assert np.any(ext.k > 1.05 * path.k)


@pytest.mark.parametrize("torque", [100.0, 400.0])
def test_no_jump_at_the_ends_of_the_path(spur, torque):
    """The tip corner's law at zero separation is the path end's: the table is
    continuous where the path-only table jumps (start and end of contact)."""
    tr = spur.with_cracks(())
    for corner, lo, hi in ((True, 0.0, CONTINUOUS_STEP), (False, 0.2, 1.0)):
        k = _table(tr, corner, torque=torque, npc=FINE).k[:FINE]
        step = np.max(np.abs(np.diff(np.r_[k, k[0]])) / k)
        assert lo < step < hi, (corner, step)


def test_corner_closing_in_the_fe_pair_convention(spur):
    """Incoming corner: the separation of corner_separation (a driver rotation, the
    driven gear held), closing rate 1. Outgoing corner: corner_separation measures a
    driven rotation; with the driven gear held the mesh advances with the deflection,
    so the separation is the fixed point delta* = s(l + delta*) and the rate
    1 - s'(l + delta*) lies in (0, 1)."""
    pair = spur.pairs[0]
    la, le, pb = pair.start_of_contact, pair.end_of_contact, pair.base_pitch
    before = la - np.array([0.02, 0.1, 0.3]) * pb
    s, rate = corner_closing(pair, before)
    np.testing.assert_array_equal(s, corner_separation(pair, before))
    np.testing.assert_array_equal(rate, 1.0)
    after = le + np.array([0.02, 0.05, 0.1]) * pb  # where corners close under load
    s, rate = corner_closing(pair, after)
    np.testing.assert_allclose(s, corner_separation(pair, after + s), rtol=1e-6)
    assert np.all(s > corner_separation(pair, after))  # the corner moves away first
    assert np.all((rate > 0.5) & (rate < 1.0))
    h = 1e-4 * pb
    slope = (corner_separation(pair, after + s + h) - corner_separation(pair, after + s - h)
             ) / (2 * h)
    np.testing.assert_allclose(rate, 1.0 - slope, rtol=1e-4)
