"""The default (accurate) model against the FE gear pair beyond the 19/48 example.

Issue 25 names four pairs: 19/48 (tests/stiffness/test_calibrated.py), the Table-1 mesh I
section (tests/studies/test_fe_pair_check.py), a 17-tooth pinion with profile shift +0.3
against 60 teeth, and a 25-tooth pair at 25 deg pressure angle. The last two are checked
here, healthy, at the rated torque of the 19/48 example (100 N m), pointwise inside both
contact zones (where the FE pair touches on the nominal path only) against the FE pair
(:mod:`gearsim.fem.pair`, both gears meshed whole, exact contact), solved at level 1
(0.06-0.24 % from level 2 on 19/48, docs/fem.md, at a quarter of the cost).

The level-2 numbers of both pairs at 100 and 400 N m, with cracks and at the zone ends,
are in docs/stiffness.md section 4c (``benchmarks/bench_calibrated.py --accuracy --extra``):
inside the zones +1.1 to +2.2 %, healthy, at both torques; the cycle mean misses 3 % at
400 N m and the zone ends are 2.6-29 % soft (contact outside the path: issue 25 item 2).
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
LEVEL = 1
#: Driver torque [N m]: the 19/48 example's.
TORQUE = 100.0
#: The issue's target: the default model within 3 % of the FE pair inside the zones.
TARGET = 0.03
#: Margin from the nominal transitions (u = 0, eps_alpha - 1, 1) of the positions called
#: inside [-]: under 100 N m the FE pair's corner contacts reach 0.05 of a cycle past a
#: transition on these pairs (docs/stiffness.md 4c, 20 positions per cycle).
MARGIN = 0.1
#: Table positions per cycle (the FE positions are multiples of 1 / NPC).
NPC = 200

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
                                                      torque=TORQUE),
                     stiffness=base.stiffness)


def _inside(eps: float) -> list[float]:
    """Positions (multiples of 0.05) at least MARGIN inside the double zone (0, eps - 1)
    and the single zone (eps - 1, 1)."""
    us = np.round(np.arange(20) * 0.05, 10)
    keep = ((us >= MARGIN) & (us <= eps - 1 - MARGIN)) | \
        ((us >= eps - 1 + MARGIN) & (us <= 1 - MARGIN))
    return [float(u) for u in us[keep]]


@pytest.mark.parametrize("name", list(PAIRS))
def test_default_model_within_target_inside_the_zones(name):
    pair = _train(*PAIRS[name]).pairs[0]
    us = _inside(pair.transverse_contact_ratio)
    eps = pair.transverse_contact_ratio
    assert any(u < eps - 1 for u in us) and any(u > eps - 1 for u in us)  # both zones
    model = fp.FEPairModel(pair, torque=TORQUE, level=LEVEL)
    k_fe = np.array([model.solve(u).stiffness for u in us])
    force = TORQUE / pair.driver.base_radius
    rel = {}
    for label in ("accurate", "seed"):
        st = StiffnessSettings(positions_per_cycle=NPC, **MODELS[label])
        ms = mesh_stiffness(pair, settings=st, compliance=tooth_compliance(st.source),
                            force=force, coupling=body_coupling(st))
        rel[label] = ms.k[[int(round(u * NPC)) for u in us]] / k_fe - 1.0
    assert np.all(np.abs(rel["accurate"]) < TARGET), (us, rel["accurate"])
    # and the FE pair is an independent model: the seed's method misses it by far
    assert np.all(np.abs(rel["seed"]) > 3 * np.abs(rel["accurate"])), rel["seed"]
