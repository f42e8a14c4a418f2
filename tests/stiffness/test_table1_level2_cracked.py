"""The default model with a root crack on the Table-1 mesh I section, FE pair at level 2.

As ``test_table1_level2.py``, with the reproduction's 6 mm crack on tooth 0 of the input
gear (45 deg from the 30 deg tangent point, uniform across the face), on the working flank
(the measured crack correction and the cracked body's coupling, docs/stiffness.md 4c)
and on the non-working flank (faces closed), at the train's 4876 N m. The FE pair carries
the same crack on the same tooth (:class:`gearsim.fem.pair.PairCrack`, faces in frictionless
contact). Driver tooth 0 is pair k = c of the FE pair in mesh cycle c of the model's
revolution table: the positions run from the cycle before it enters (its tip corner is
the incoming corner at u = 0.85-0.95) over its double and single contacts to its outgoing
tip corner after E in cycle 1.
"""

from __future__ import annotations

import dataclasses

import pytest

from gearsim.fem import pair as fp
from gearsim.stiffness.settings import MODELS
from gearsim.studies.fe_pair_check import section_tvms

#: FE pair mesh level: the issue's.
LEVEL = 2
#: Positions per cycle of the model's section table.
NPC = 20
#: Crack depth [m]: the reproduction's reference depth (docs/reproduce.md).
DEPTH = 6e-3
#: (cycle, u) checked: the cracked tooth's incoming corner, its cycles 0 and 1 at the
#: start of contact, inside the zones, the end of contact and its outgoing corner.
POSITIONS = ((-1, 0.9), (-1, 0.95),
             (0, 0.0), (0, 0.3), (0, 0.65), (0, 0.7), (0, 0.85), (0, 0.95),
             (1, 0.0), (1, 0.3), (1, 0.65), (1, 0.7))
#: Positions inside the zones (the others are zone ends: transitions and tip corners).
INSIDE = {(0, 0.3), (0, 0.85), (1, 0.3)}
#: The issue's targets, relative: within 3 % inside the zones, 5 % at the ends.
TARGET = 0.03
END_TARGET = 0.05


@pytest.mark.parametrize("flank,side", [("working", 1), ("non-working", -1)])
def test_cracked_default_model_within_targets(table1, flank, side):
    """Working-flank and closed non-working crack: within 3 % inside the zones, 5 % at
    the ends (measured 2026-11-28 with bench_calibrated.py --level 2: ends +0.5 ... +2.3 %
    working, before the tip edge up to +5.2 %)."""
    tr = table1.with_crack(flank, closure="contact", depth=DEPTH)
    crack = tr.mesh_cracks(0)[0]
    assert crack.gear == 1 and crack.crack.tooth == 0
    torque = tr.mesh_torque(0)
    st = dataclasses.replace(tr.stiffness, **MODELS["accurate"])
    k = section_tvms(tr, 0, st, NPC)[1]
    z = tr.pairs[0].driver.teeth
    models = {c: fp.FEPairModel(tr.pairs[0], torque=torque, level=LEVEL,
                                plane=tr.stiffness.plane,
                                crack=fp.PairCrack(gear=1, pair=c, crack=crack.crack,
                                                   side=side, closure="contact"))
              for c in (-1, 0, 1)}
    errs = {}
    for c, u in POSITIONS:
        k_fe = models[c].solve(u, torque=torque).stiffness
        errs[c, u] = k[(c % z) * NPC + round(u * NPC)] / k_fe - 1.0
    for pos, e in errs.items():
        assert abs(e) < (TARGET if pos in INSIDE else END_TARGET), (pos, e, errs)
