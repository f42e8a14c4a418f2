"""A cracked gear body's coupling of the pairs beside the cracked tooth (issue 25).

The calibrated model couples adjacent tooth pairs through the gear body with the cross
compliance X measured on the healthy gear (:mod:`gearsim.fem.coupling`). A crack in the
fillet of the loaded flank changes it: the same FE solves that measure the crack
correction Q read the cracked tooth's neighbours, and the mesh multiplies X of the pair
of the cracked tooth and its neighbour away from the crack by G = X_crack / X_healthy
(:meth:`gearsim.fem.calibration.CalibratedCompliance.cross_factor`, docs/stiffness.md
4c).

Checked against the FE gear pair (:mod:`gearsim.fem.pair`, an independent model: both
gears meshed whole with the crack in the driver body, exact contact) on the transverse
section of Table-1 mesh I with the reproduction's 6 mm input-gear crack on the working
flank, at its two torques: in the double contact after the cracked tooth's single
contact (cracked tooth in the outgoing pair, the healthy incoming pair behind it) the
table with the healthy coupling was +3.3 ... +4.2 % off the FE pair, outside the 3 %
target; with the crack's coupling it is within it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gearsim as gs
from gearsim.fem import calibration as cal
from gearsim.fem import pair as fp
from gearsim.stiffness import mesh as sm
from gearsim.stiffness.settings import MODELS
from gearsim.studies.fe_pair_check import section_tvms

#: The issue's target inside the contact zones, relative.
TARGET = 0.03
#: FE pair level: level 1, as the benchmark windows (docs/stiffness.md 4c) and the
#: 19/48 checks of test_calibrated.py (0.06-0.24 % from level 2 there).
LEVEL = 1
#: Driver torques of Table-1 mesh I [N m]: the reproduction's and a quarter of it.
TORQUES = (4876.0, 1219.0)
#: (pair label of the cracked tooth in the FE pair, position in the cycle): the
#: cracked tooth in the outgoing pair beside the healthy incoming one (label 1; before
#: +3.3 / +3.7 % at 4876 N m, +3.9 / +4.2 % at 1219 N m) and in the incoming pair with
#: the older pair across its crack (label 0; healthy coupling there, +0.3 / +0.9 %).
POSITIONS = ((1, 0.3), (1, 0.6), (0, 0.3))
#: Positions per cycle of the table (point samples: 0.05 apart).
NPC = 20


@pytest.fixture(scope="module")
def table1():
    return gs.example("idler-table1").train.with_crack("working", closure="contact",
                                                        source="pe", depth=6e-3)


@pytest.fixture(scope="module")
def fe(table1):
    """FE pair stiffness at POSITIONS and TORQUES, the crack on the pair's driver tooth."""
    tc = table1.mesh_cracks(0)[0]
    out = {}
    for label in sorted({p[0] for p in POSITIONS}):
        model = fp.FEPairModel(table1.pairs[0], torque=TORQUES[0], level=LEVEL,
                               crack=fp.PairCrack(gear=1, pair=label, crack=tc.crack, side=1,
                                                  closure="contact"))
        for torque in TORQUES:
            for lab, u in POSITIONS:
                if lab == label:
                    out[torque, label, u] = model.solve(u, torque=torque).stiffness
    return out


def _errors(table1, fe, torque):
    tr = dataclasses.replace(table1, operating=dataclasses.replace(table1.operating,
                                                                   torque=torque))
    st = dataclasses.replace(tr.stiffness, **MODELS["accurate"])
    cycles, k = section_tvms(tr, 0, st, NPC)
    out = []
    for label, u in POSITIONS:  # the crack is on tooth 0: cycle `label` of the revolution
        i = int(round((label + u) * NPC))
        assert abs(cycles[i] - (label + u)) < 1e-12
        out.append(k[i] / fe[torque, label, u] - 1.0)
    return np.array(out)


@pytest.mark.slow
@pytest.mark.parametrize("torque", TORQUES)
def test_table1_working_crack_within_target(table1, fe, torque, monkeypatch):
    """Table-1 mesh I, 6 mm working crack: within the 3 % target of the FE pair where
    the cracked tooth and a neighbour carry load together; with the healthy coupling
    (the model before) the outgoing cracked tooth's double contact missed it."""
    errs = _errors(table1, fe, torque)
    assert np.max(np.abs(errs)) < TARGET, errs
    monkeypatch.setattr(cal.CalibratedCompliance, "cross_factor",
                        lambda self, *a, **kw: None)
    before = _errors(table1, fe, torque)
    assert before[1] > TARGET, before  # the healthy coupling: +3.7 / +4.2 % measured


def test_crack_factors_of_the_6mm_crack(table1):
    """The measured factor of the 6 mm crack (0.65 q_c): the neighbour behind the
    cracked tooth is coupled more (the load goes round the crack through the other
    fillet; 1.16-1.34 measured, the benchmark's windows); the pair across the crack
    keeps the healthy coupling (None: the neighbour's load closes the faces there);
    G -> 1 as the depth -> 0 (the spline through G(0) = 1)."""
    tc = table1.mesh_cracks(0)[0]
    gear = table1.pairs[0].driver
    st = dataclasses.replace(table1.stiffness, **MODELS["accurate"])
    model = cal.CalibratedCompliance()
    r = cal._fe_nodes(gear)
    a, b = np.meshgrid(r, r, indexing="ij")
    z = np.array([0.5])
    load = model.cross_factor(gear, a[..., None], b[..., None], tc, False, z, st)
    assert 1.1 < load.min() and load.max() < 1.4
    assert model.cross_factor(gear, a[..., None], b[..., None], tc, True, z, st) is None
    # 1 um, the shallowest crack a Crack takes: G - 1 is the spline's slope at 0 times
    # 1 um, about 0.3 / 6 mm x 1 um = 5e-5; 1e-3 allows 20 times that
    shallow = dataclasses.replace(tc, crack=dataclasses.replace(tc.crack, depth=1e-6))
    np.testing.assert_allclose(model.cross_factor(gear, a[..., None], b[..., None],
                                                  shallow, False, z, st), 1.0, atol=1e-3)


def test_closed_unloaded_flank_crack_and_seed_keep_the_healthy_coupling(table1,
                                                                        monkeypatch):
    """The closed crack on the unloaded flank takes no crack correction and so no
    coupling factor, and the seed model has no coupling: both tables are the ones
    without the factors, bit for bit."""
    tr = gs.example("idler-table1").train.with_crack("non-working", closure="contact",
                                                     source="pe", depth=6e-3)
    st = dataclasses.replace(tr.stiffness, **MODELS["accurate"])
    st_seed = dataclasses.replace(table1.stiffness, **MODELS["seed"])
    runs = [(tr, st), (table1, st_seed)]
    before = [section_tvms(t, 0, s, NPC)[1] for t, s in runs]
    monkeypatch.setattr(sm, "crack_cross_factors", lambda *a, **kw: None)
    for (t, s), k in zip(runs, before, strict=True):
        np.testing.assert_array_equal(section_tvms(t, 0, s, NPC)[1], k)
    assert cal.CalibratedCompliance().cross_factor(
        tr.pairs[0].driver, np.array([[0.1]]), np.array([[0.1]]), tr.mesh_cracks(0)[0],
        True, np.array([0.5]), st) is None
