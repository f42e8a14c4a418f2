"""Tier 1-2: FE tooth compliance, mesh convergence, and FE versus potential energy.

Numbers measured at mesh level 2 (docs/fem.md; CI runs level 1, within 2 %), 7 positions
over the path of contact of each gear's first mesh, difference 100 (k_PE - k_FE)/k_FE of
the max / min / mean tooth stiffness (Hertz excluded):

=====================  ========================  ========================
case                    Table-1 input (z = 39)     19/48 pinion (z = 19)
=====================  ========================  ========================
healthy                 -12.4 / -8.2 / -11.8       -13.1 / -8.9 / -13.1
working crack, open     -8.8 / -2.9 / -6.7         -2.1 / -5.3 / -5.5
non-working, contact    -14.4 / -8.0 / -13.2       -15.3 / -8.5 / -14.5
=====================  ========================  ========================

The potential-energy model is 8-15 % softer than the FE model. The seed's 10 % is met
with a working-flank crack but not for the healthy tooth or the closed non-working
crack. This is a finding, not a tuning target (docs/fem.md, "Why the PE model is
softer"): in 2D the split of the deflection into Hertzian and structural parts
depends on where the deflection is measured (moving the FE measure point from the
tooth centre line halfway to the contact point raises the FE compliance by 4-12 %), and
beam theory ignores the compression of the tooth across its thickness. The tests
assert the tolerance those reasons support, ``TOL_PE = 18 %``, the sign (PE softer),
and the seed's 10 % for the working-flank crack with the open model.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.fem.check import compare_gear, contact_radii
from gearsim.fem.geometry import SectorOptions
from gearsim.fem.tooth import fe_tooth_compliance

#: Tolerance on the FE-vs-PE max / min / mean differences that the physics supports [%].
TOL_PE = 18.0
#: The seed's claim (Fig. 3b), met by the working-flank crack with the open model [%].
TOL_SEED = 10.0
LEVEL = 1
POINTS = 7

CASES = {
    "healthy": (None, 0, "open"),
    "working-open": ("crack", 1, "open"),
    "non-working-contact": ("crack", -1, "contact"),
}


@pytest.fixture(scope="module")
def results(table1, spur):
    out = {}
    for tname, train in (("table1", table1), ("spur", spur)):
        gear = train.gears[0]
        radii = contact_radii(train, gear.name, POINTS)
        for case, (has_crack, side, closure) in CASES.items():
            crack = train.cracks[0] if has_crack else None
            out[tname, case] = compare_gear(gear, radii, crack=crack, side=side,
                                            closure=closure,
                                            options=SectorOptions(level=LEVEL), label=case)
    return out


@pytest.mark.parametrize("train", ["table1", "spur"])
@pytest.mark.parametrize("case", list(CASES))
def test_fem_pe_differences_within_supported_tolerance(results, train, case):
    d = results[train, case].differences()
    for key, val in d.items():
        assert abs(val) <= TOL_PE, f"{train} {case} {key}: {val:+.2f} % (all: {d})"
        assert val < 0.5, f"{train} {case} {key}: PE expected softer than FE, got {val:+.2f} %"


@pytest.mark.parametrize("train", ["table1", "spur"])
def test_fem_working_open_meets_seed_ten_percent(results, train):
    d = results[train, "working-open"].differences()
    assert all(abs(v) <= TOL_SEED for v in d.values()), d


@pytest.mark.parametrize("train", ["table1", "spur"])
def test_fem_crack_effects_have_the_expected_order(results, train):
    h = results[train, "healthy"].fe
    w = results[train, "working-open"].fe
    nw = results[train, "non-working-contact"]
    # a crack on the tension side softens the tooth everywhere on the path
    assert np.all(w > h * 1.01)
    # on the compressed side the faces close: the tooth stays close to healthy (within
    # 3 %; frictionless faces lose only shear transfer) and far stiffer than open
    assert_allclose(nw.fe, h, rtol=0.03)
    assert np.all(nw.fe_result.closed_fraction > 0.8)


def test_fem_contact_equals_open_when_faces_open(table1):
    """Working-flank crack: in tension the faces separate, contact changes nothing."""
    gear = table1.gears[0]
    r = contact_radii(table1, gear.name, 3)
    c = table1.cracks[0]
    opt = SectorOptions(level=LEVEL)
    a = fe_tooth_compliance(gear, r, crack=c, side=1, closure="open", options=opt)
    b = fe_tooth_compliance(gear, r, crack=c, side=1, closure="contact", options=opt)
    assert_allclose(b.compliance, a.compliance, rtol=1e-6)
    assert np.all(b.closed_fraction < 0.5)


#: Relative agreement of the crack-face contact solve with its factorization reused
#: across load positions and the solve that factorizes afresh at every one: the same
#: matrix and factorization, so only the solver's round-off may differ.
REUSE_RTOL = 1e-9


@pytest.mark.parametrize("side", [1, -1])
def test_fem_contact_reuses_the_factorization_of_an_unchanged_active_set(
        table1, monkeypatch, side):
    """Crack-face contact: one factorization per set of closed faces, not per load
    position, and the compliance the fresh factorizations give (working-flank crack
    open, non-working closed)."""
    from gearsim.fem.solve import ElasticModel

    gear = table1.gears[0]
    r = contact_radii(table1, gear.name, 5)
    c = table1.cracks[0]
    opt = SectorOptions(level=LEVEL)
    count = {"n": 0}
    factorize = ElasticModel._factorize

    def counted(self, fixed, extra):
        count["n"] += 1
        return factorize(self, fixed, extra)

    monkeypatch.setattr(ElasticModel, "_factorize", counted)
    reused = fe_tooth_compliance(gear, r, crack=c, side=side, closure="contact",
                                 options=opt)
    n_reused = count["n"]
    solve = ElasticModel.contact_solve
    monkeypatch.setattr(ElasticModel, "contact_solve",
                        lambda self, *a, reuse=None, **k: solve(self, *a, **k))
    count["n"] = 0
    fresh = fe_tooth_compliance(gear, r, crack=c, side=side, closure="contact",
                                options=opt)
    assert_allclose(reused.compliance, fresh.compliance, rtol=REUSE_RTOL, atol=0.0)
    assert_allclose(reused.closed_fraction, fresh.closed_fraction, rtol=0.0, atol=0.0)
    assert count["n"] == int(np.sum(fresh.contact_iterations))  # one per iteration before
    assert n_reused < count["n"]
    if side == -1:
        assert np.all(fresh.closed_fraction > 0.5)  # the faces closed under the load


def test_fem_non_working_open_faces_overlap_contact_prevents_it(spur):
    """Open model on the compressed side is softer than the contact model."""
    gear = spur.gears[0]
    r = contact_radii(spur, gear.name, 3)
    c = spur.cracks[0]
    opt = SectorOptions(level=LEVEL)
    a = fe_tooth_compliance(gear, r, crack=c, side=-1, closure="open", options=opt)
    b = fe_tooth_compliance(gear, r, crack=c, side=-1, closure="contact", options=opt)
    assert np.all(a.compliance > b.compliance * 1.01)


def test_fem_mesh_convergence_rate(table1):
    """Three levels of uniform refinement: observed order by Richardson.

    Expected order 2: P2 fields on straight-sided triangles, whose polygonal boundary
    is an O(h^2) approximation of the curved fillet, bore and flanks. Accepted [1.5, 3.5].
    The extrapolated error of level 2 must be < 0.5 % (tables use level 2).
    """
    gear = table1.gears[0]
    r = contact_radii(table1, gear.name, 3)
    c = np.array([fe_tooth_compliance(gear, r, options=SectorOptions(level=k)).compliance
                  for k in (0, 1, 2)])
    d01 = c[1] - c[0]
    d12 = c[2] - c[1]
    rate = np.log2(np.abs(d01) / np.abs(d12))
    assert np.all((rate >= 1.5) & (rate <= 3.5)), f"observed orders {rate}"
    extrapolated = c[2] + d12 / (2.0 ** rate - 1.0)
    assert np.all(np.abs(c[2] / extrapolated - 1.0) < 5e-3)


def test_fem_contact_radii_of_each_gear_of_a_graph_train():
    """Two-stage reducer (m 1.5 mm, 20 deg, standard): every gear's path in its own mesh,
    by hand on the line of action. Mesh II (48/64, a = 84 mm): the pinion from
    sqrt(r_b1^2 + (a sin 20 - sqrt(r_a2^2 - r_b2^2))^2) = 34.842 mm to its tip 37.5 mm
    (r_b1 = 33.83 mm); the 64-tooth gear from 46.818 mm to 49.5 mm. Mesh I (32/80)."""
    from gearsim.model import load

    train = load("two-stage-reducer").train
    al = np.radians(20.0)
    for names, (z1, z2) in ((("input-pinion", "intermediate-gear"), (32, 80)),
                            (("intermediate-pinion", "output-gear"), (48, 64))):
        r = 0.75e-3 * np.array([z1, z2])
        rb, ra, line = r * np.cos(al), r + 1.5e-3, r.sum() * np.sin(al)
        for i, name in enumerate(names):
            lo = np.hypot(rb[i], line - np.sqrt(ra[1 - i] ** 2 - rb[1 - i] ** 2))
            got = contact_radii(train, name, 3)
            assert_allclose(got[[0, -1]], [lo, ra[i]], rtol=1e-9, err_msg=name)
    got = contact_radii(train, "intermediate-pinion", 3)
    assert_allclose(got[[0, -1]], [34.842e-3, 37.5e-3], atol=1e-6)
    assert_allclose(train.gear("intermediate-pinion").base_radius, 33.829e-3, atol=1e-6)
