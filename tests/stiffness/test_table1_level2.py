"""The default model on the Table-1 mesh I section against the FE gear pair at level 2.

The issue's targets (issue 25) on the pair where they bind: the helical Table-1 mesh I,
transverse section (:func:`gearsim.studies.fe_pair_check.section_tvms`, the quantity the
2D FE pair computes), healthy at the train's 4876 N m and at a quarter of it, the FE gear
pair in contact (:mod:`gearsim.fem.pair`, an independent model: both gears meshed whole,
exact contact) at mesh level 2, the level the issue names. The positions: inside both
contact zones and at their ends (the start and end of contact, and where the loaded FE
pair touches outside the nominal path: the tip corners after E, u = 0.70-0.75, and before
the next A, u = 0.90-0.95; docs/stiffness.md 4c). The cracked cases are in
``test_table1_level2_cracked.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearsim.fem import pair as fp
from gearsim.stiffness.settings import MODELS
from gearsim.studies.fe_pair_check import section_tvms

#: FE pair mesh level: the issue's.
LEVEL = 2
#: Positions per cycle of the model's section table (the positions below are on it).
NPC = 20
#: Mesh cycle positions checked: the start of contact, inside the double-contact zone,
#: the end of contact and the outgoing tip corner (eps_alpha - 1 = 0.68), inside the
#: single-contact zone, the incoming tip corner.
POSITIONS = (0.0, 0.3, 0.65, 0.7, 0.75, 0.85, 0.9, 0.95)
#: Positions inside the zones (the others are zone ends).
INSIDE = (0.3, 0.85)
#: The issue's targets, relative: within 3 % inside the zones, 5 % at the ends.
TARGET = 0.03
END_TARGET = 0.05
#: Measured band of the default model over the positions (2026-11-28, level 2: +1.4 ...
#: +2.4 %; the FE tooth's superposition error against the FE pair, +1.1-1.7 %, docs/fem.md,
#: "Verification"): a regression guard, not the target. Without the tip edge the ends
#: were up to +5.0 % here.
BAND = (0.005, 0.03)


@pytest.fixture(scope="module")
def healthy(table1):
    return table1.with_cracks(())


@pytest.fixture(scope="module")
def fe(healthy):
    """FE pair at level 2, both torques, at POSITIONS."""
    torque = healthy.mesh_torque(0)
    model = fp.FEPairModel(healthy.pairs[0], torque=torque, level=LEVEL,
                           plane=healthy.stiffness.plane)
    return {(t, u): model.solve(u, torque=t).stiffness
            for t in (torque, torque / 4) for u in POSITIONS}


def _section(train, torque: float, **settings) -> np.ndarray:
    tr = dataclasses.replace(train, operating=dataclasses.replace(train.operating,
                                                                  torque=torque))
    st = dataclasses.replace(tr.stiffness, **MODELS["accurate"], **settings)
    return section_tvms(tr, 0, st, NPC)[1]


@pytest.mark.parametrize("quarter", [False, True], ids=["4876 N m", "1219 N m"])
def test_default_model_within_targets_inside_and_at_the_ends(healthy, fe, quarter):
    """Healthy: within 3 % inside the zones and within 5 % at the ends of the FE pair at
    level 2; the same table on the path of contact only misses the ends by > 10 %."""
    torque = healthy.mesh_torque(0) / (4 if quarter else 1)
    k = _section(healthy, torque)
    path = _section(healthy, torque, corner_contact=False)
    err = {u: k[round(u * NPC)] / fe[torque, u] - 1.0 for u in POSITIONS}
    for u, e in err.items():
        assert abs(e) < (TARGET if u in INSIDE else END_TARGET), (u, e)
        assert BAND[0] < e < BAND[1], (u, e)
    worst_path = min(path[round(u * NPC)] / fe[torque, u] - 1.0 for u in POSITIONS)
    assert worst_path < -0.10
