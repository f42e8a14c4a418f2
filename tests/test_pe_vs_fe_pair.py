"""The mesh-stiffness options beyond the seed against the FE gear pair (issue 15).

``stiffness.contact = "line"`` (2D Hertz line contact up to the tooth centre lines) and
``stiffness.coupling = "fe"`` (neighbouring loaded teeth coupled through the FE gear
body) are checked against the finite-element gear pair in contact
(:mod:`gearsim.fem.pair`), an independent model: both bodies meshed whole, contact
solved exactly, the mesh stiffness read from the hub rotation. Positions are inside
the single- and double-contact zones; near the transitions the FE pair touches outside
the nominal path of contact under load (extended contact), which no option of the
table models (docs/stiffness.md, "Beyond the seed").
"""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem import pair as fp
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.train import body_coupling, tooth_compliance

#: FE pair level of these checks: level 1 differs from the default level 2 by
#: 0.06-0.24 % (docs/fem.md, convergence) and costs 0.2 s per position.
LEVEL = 1
#: Driver torque of the 19/48 checks [N m] (the docs/fem.md comparison).
TORQUE = 100.0
#: Positions inside double contact (u < eps - 1 = 0.646) and single contact.
DOUBLE = (0.15, 0.35)
SINGLE = (0.82,)
#: FE tooth + line contact + FE coupling against the FE pair: the superposition of FE
#: gear compliances and the 2D Hertz approach matches the FE pair within 1.1-1.7 %
#: (tests/fem/test_fem_pair.py); the table adds the spline of the FE tooth curve and
#: the Q-point convention of the single-tooth model: 3 %.
SUPERPOSITION_TOL = 0.03
#: Load shares of the two pairs in double contact, absolute.
SHARE_TOL = 0.03
#: Growth of the stiffness from 50 to 400 N m in single contact: FE pair against the
#: line contact law, relative (both grow by ln(w) of the contact approach).
LOAD_RATIO_TOL = 0.01
#: Measured band of the potential-energy tooth with both options against the FE pair
#: inside the zones (docs/stiffness.md: -6.2 % double, -8.1 % single contact): the PE
#: tooth is 12-15 % softer than the FE tooth (docs/fem.md). A regression guard, not a
#: target: the issue's 5 % is not reached by the PE tooth.
PE_BAND = (-0.10, -0.04)
#: Positions per cycle of the tables interpolated at the FE positions.
NPC = 400


@pytest.fixture(scope="module")
def pair(spur):
    return spur.pairs[0]


@pytest.fixture(scope="module")
def fe(pair):
    model = fp.FEPairModel(pair, torque=TORQUE, level=LEVEL)
    return {u: model.solve(u) for u in DOUBLE + SINGLE}, model


def _table(pair, torque, **kw):
    st = StiffnessSettings(positions_per_cycle=NPC, **kw)
    return mesh_stiffness(pair, settings=st, compliance=tooth_compliance(st.source),
                          force=torque / pair.driver.base_radius,
                          coupling=body_coupling(st))


def _at(ms, u):
    i = int(round(u * NPC))
    assert abs(i / NPC - u) < 1e-12
    return ms.k[i], ms.pair_k[i]


def test_fe_tooth_with_line_contact_and_coupling_equals_fe_pair(pair, fe):
    """FE teeth + 2D line contact + body coupling = FE pair inside both contact zones."""
    results, _ = fe
    ms = _table(pair, TORQUE, source="fe", contact="line", coupling="fe")
    for u, res in results.items():
        k, _ = _at(ms, u)
        assert k == pytest.approx(res.stiffness, rel=SUPERPOSITION_TOL), u


def test_coupled_load_shares_equal_fe_pair(pair, fe):
    """The coupled pairs share the load as the FE pair's two pairs do."""
    results, _ = fe
    ms = _table(pair, TORQUE, source="fe", contact="line", coupling="fe")
    for u in DOUBLE:
        k, pk = _at(ms, u)
        share_pe = np.sort(pk[pk > 0] / k)
        share_fe = np.sort(results[u].load_share[results[u].load_share > 0])
        assert share_pe.size == share_fe.size == 2
        np.testing.assert_allclose(share_pe, share_fe, atol=SHARE_TOL)


def test_line_contact_follows_the_load_like_the_fe_pair(pair, fe):
    """k(400 N m) / k(50 N m) in single contact: FE pair against the line contact law."""
    _, model = fe
    u = SINGLE[0]
    fe_ratio = model.solve(u, torque=400.0).stiffness / model.solve(u, torque=50.0).stiffness
    pe_ratio = (_at(_table(pair, 400.0, source="fe", contact="line"), u)[0]
                / _at(_table(pair, 50.0, source="fe", contact="line"), u)[0])
    assert fe_ratio > 1.02  # the FE pair stiffens with the load (wider contact)
    assert pe_ratio == pytest.approx(fe_ratio, rel=LOAD_RATIO_TOL)


def test_coupling_acts_in_double_contact_only(pair):
    """Coupling lowers k where two pairs carry load and leaves single contact unchanged."""
    free = _table(pair, TORQUE, contact="line")
    coupled = _table(pair, TORQUE, contact="line", coupling="fe")
    n_pairs = (free.pair_k[:NPC] > 0).sum(axis=1)
    single = n_pairs == 1
    np.testing.assert_allclose(coupled.k[:NPC][single], free.k[:NPC][single], rtol=1e-12)
    assert np.all(coupled.k[:NPC][~single] < free.k[:NPC][~single])


def test_potential_energy_tooth_band(pair, fe):
    """PE tooth + both options: inside the measured band of the FE pair (regression guard)."""
    results, _ = fe
    ms = _table(pair, TORQUE, contact="line", coupling="fe")
    for u, res in results.items():
        k, _ = _at(ms, u)
        assert PE_BAND[0] < k / res.stiffness - 1 < PE_BAND[1], u


def test_options_need_their_inputs(pair):
    st = StiffnessSettings(contact="line")
    with pytest.raises(InputError, match="force"):
        mesh_stiffness(pair, settings=st)
    with pytest.raises(InputError, match="stiffness.coupling"):
        mesh_stiffness(pair, settings=StiffnessSettings(coupling="fe"))
    with pytest.raises(InputError, match="stiffness.contact"):
        StiffnessSettings(contact="hertz")


def test_mesh_of_contacts_needs_the_options_inputs(pair):
    """The mesh of contacts takes the line contact and the coupling (tests/test_contacts.py)
    and, like the table, needs the force and the coupling model for them: refused, named."""
    from gearsim.stiffness.contacts import contact_grid

    with pytest.raises(InputError, match="force"):
        contact_grid(pair, settings=StiffnessSettings(contact="line"))
    with pytest.raises(InputError, match="stiffness.coupling"):
        contact_grid(pair, settings=StiffnessSettings(coupling="fe"))


#: Approach of two discs: load derivative against 2D elasticity. The FE approach of the
#: hubs differs from the closed form by the discs' ring bending, which is linear in the
#: load; only the contact makes delta / F depend on the load, by exactly
#: d(delta / F) / d ln F = -1 / (pi E*) (Johnson 1985, ch. 5: per body
#: 2 (1 - nu^2) / (pi E) [ln(2 d / a) - ...] with a ~ F^1/2). Measured 0.08 % (strain),
#: 0.06 % (stress) with the contact element b / 12 at the smaller load; 0.5 % allows the
#: discretisation of the contact zone.
APPROACH_SLOPE_TOL = 0.005


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_fe_disc_approach_follows_2d_elasticity(plane):
    """FE discs R 20 / 30 mm at 100 and 400 kN/m: d(delta/F)/d ln F = -1 / (pi E*), the
    logarithmic load dependence the line contact law (stiffness.contact = "line") uses."""
    import math

    from gearsim.geometry.gear import Material
    from gearsim.stiffness.tooth import line_contact_compliance

    mat = Material()
    e, nu = mat.youngs_modulus, mat.poisson_ratio
    e_star = e / (2.0 * ((1 - nu**2) if plane == "strain" else 1.0))
    h = math.sqrt(4 * 1e5 * 0.012 / (math.pi * e_star)) / 12
    lo, hi = (fp.fe_cylinder_contact(0.02, 0.03, f, plane=plane, h_contact=h) for f in (1e5, 4e5))
    slope = (hi.approach / 4e5 - lo.approach / 1e5) / math.log(4.0)
    assert slope == pytest.approx(-1.0 / (math.pi * e_star), rel=APPROACH_SLOPE_TOL)
    # the law gearsim uses has the same slope (any depths)
    law = [line_contact_compliance(f, 0.02, 0.03, 5e-3, 5e-3, mat, mat, plane) for f in (1e5, 4e5)]
    assert (law[1] - law[0]) / math.log(4.0) == pytest.approx(slope, rel=APPROACH_SLOPE_TOL)
