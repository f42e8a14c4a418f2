"""The default (accurate) model against the FE gear pair beyond the 19/48 example.

Issue 25 names four pairs: 19/48 (tests/stiffness/test_calibrated.py), the Table-1 mesh I
section (tests/stiffness/test_table1_level2*.py), a 17-tooth pinion with profile shift
+0.3 against 60 teeth, and a 25-tooth pair at 25 deg pressure angle. The last two are
checked here, healthy, at the 19/48 example's 100 N m and at 4 times it, against the FE
pair (:mod:`gearsim.fem.pair`, both gears meshed whole, exact contact) at mesh level 2,
the issue's: pointwise inside both contact zones (where the FE pair touches on the
nominal path only) and at the zone ends (the positions within 0.1 of a cycle of a
nominal transition, where the loaded FE pair touches outside the nominal path, tip
corners).

With cracks, and the max / min / mean of 4-cycle windows, the level-2 numbers of both
pairs are in docs/stiffness.md section 4c (``benchmarks/bench_calibrated.py --accuracy
--extra --level 2``): inside the zones +0.9 to +2.3 %, ends -0.3 to +2.1 %, means
+1.1 to +1.7 %.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gearsim.fem import pair as fp
from gearsim.geometry.gear import Gear
from gearsim.model import load
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import MODELS, StiffnessSettings
from gearsim.system.train import GearTrain, Operating, body_coupling, tooth_compliance

#: FE pair level (module docstring).
LEVEL = 2
#: Driver torques [N m]: the 19/48 example's and 4 times it.
TORQUES = (100.0, 400.0)
#: The issue's targets: the default model within 3 % of the FE pair inside the zones and
#: within 5 % at the zone ends.
TARGET = 0.03
END_TARGET = 0.05
#: Measured band of the default model at every position checked (2026-11-28, level 2,
#: with the tip edge: -0.3 ... +2.1 %; the FE tooth's superposition error is +1.1-1.7 %,
#: docs/fem.md): a regression guard, not the target. Before the tip edge the ends of the
#: 17/60 pair reached +3.9 %.
BAND = (-0.01, 0.03)
#: Margin from the nominal transitions (u = 0, eps_alpha - 1, 1) of the positions called
#: inside [-]: the FE pair's corner contacts reach 0.05 of a cycle past a transition on
#: these pairs (docs/stiffness.md 4c, 20 positions per cycle); the positions nearer a
#: transition are zone ends.
MARGIN = 0.1
#: Table positions per cycle (the FE positions are multiples of 1 / NPC = 0.05).
NPC = 20

#: (teeth, pinion profile shift, pressure angle [deg], rack tip round rho_f*): the tip
#: round 0.38 of the example does not fit the rack tooth at 25 deg (the largest is 0.318)
#: and at 0.3 the FE mesher finds the outline self-intersecting: 0.25 there.
PAIRS = {"17/60 x1=+0.3": ((17, 60), 0.3, 20.0, 0.38),
         "25/25 at 25 deg": ((25, 25), 0.0, 25.0, 0.25)}


def _train(teeth, shift, alpha_deg, rho) -> GearTrain:
    """The 19/48 example (m 3.2 mm, b 16 mm, its material) with other teeth, pinion
    shift (gear unshifted: the working centre distance follows), pressure angle, tip
    round."""
    base = load("spur-19-48").train
    g0 = base.gears[0]
    gears = tuple(dataclasses.replace(g0, name=n, teeth=z, profile_shift=x,
                                      normal_pressure_angle=math.radians(alpha_deg),
                                      fillet_radius_coefficient=rho)
                  for n, z, x in (("pinion", teeth[0], shift), ("gear", teeth[1], 0.0)))
    assert all(isinstance(g, Gear) for g in gears)
    return GearTrain(gears=gears, operating=Operating(speed=base.operating.speed,
                                                      torque=TORQUES[0]),
                     stiffness=base.stiffness)


def _positions(eps: float) -> tuple[list[float], list[float]]:
    """Positions (multiples of 0.05): one inside the double zone (0, eps - 1) and one
    inside the single zone (eps - 1, 1), at least MARGIN from the transitions, and the
    zone ends, every position nearer a transition than MARGIN."""
    us = np.round(np.arange(20) * 0.05, 10)
    dist = np.min(np.abs(us[:, None] - np.array([0.0, eps - 1, 1.0])[None, :]), axis=1)
    double = [float(u) for u in us if MARGIN <= u <= eps - 1 - MARGIN]
    single = [float(u) for u in us if eps - 1 + MARGIN <= u <= 1 - MARGIN]
    inside = [double[len(double) // 2], single[len(single) // 2]]
    ends = [float(u) for u in us[dist < MARGIN - 1e-9]]
    return inside, ends


@pytest.mark.parametrize("name", list(PAIRS))
def test_default_model_within_targets_inside_and_at_the_ends(name):
    pair = _train(*PAIRS[name]).pairs[0]
    inside, ends = _positions(pair.transverse_contact_ratio)
    assert len(ends) >= 5
    model = fp.FEPairModel(pair, torque=TORQUES[0], level=LEVEL)
    for torque in TORQUES:
        us = inside + ends
        k_fe = np.array([model.solve(u, torque=torque).stiffness for u in us])
        force = torque / pair.driver.base_radius
        rel = {}
        for label in ("accurate", "seed"):
            st = StiffnessSettings(positions_per_cycle=NPC, **MODELS[label])
            ms = mesh_stiffness(pair, settings=st, compliance=tooth_compliance(st.source),
                                force=force, coupling=body_coupling(st))
            rel[label] = ms.k[[int(round(u * NPC)) for u in us]] / k_fe - 1.0
        acc = dict(zip(us, rel["accurate"], strict=True))
        for u in inside:
            assert abs(acc[u]) < TARGET, (torque, u, acc)
        for u in ends:
            assert abs(acc[u]) < END_TARGET, (torque, u, acc)
        assert all(BAND[0] < e < BAND[1] for e in acc.values()), (torque, acc)
        # and the FE pair is an independent model: the seed's method misses it by far in
        # double contact (+25-28 %; in single contact its error falls with the load, to
        # +5-6 % at 400 N m)
        assert abs(rel["seed"][0]) > 3 * abs(rel["accurate"][0]), rel["seed"]
