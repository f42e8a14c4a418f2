"""The calibrated tooth (``stiffness.source = "calibrated"``) against the FE gear pair.

The calibrated tooth is the PE tooth (cracks included) times the FE/PE compliance ratio of
the healthy tooth, measured once per gear and cached (:mod:`gearsim.fem.calibration`), and
a crack on the loaded flank times its measured correction Q = F_FE / F_PE (FE tooth at a
grid of crack depths, once per gear and crack family), with the 2D line contact and the
FE body coupling (docs/stiffness.md, section 4c). It is
checked on the 19/48 spur pair against the FE gear pair in contact (:mod:`gearsim.fem.
pair`, an independent model: both gears meshed whole, exact contact) at two torques a
factor 4 apart, healthy and with the example's 1 mm pinion crack on the working and on
the non-working flank (faces in contact). The FE pair runs at level 1: 0.06-0.24 % from
level 2 on this pair (docs/fem.md, "Convergence and cost") at a quarter of the cost, so
the module stays under a minute; it is solved once per module.

Positions: inside the contact zones, where the FE pair touches on the nominal path
(u = 0.15, 0.35 double, 0.85 single contact at both torques), at the zone ends (the
start of contact u = 0 and the positions where the FE pair touches outside the nominal
path at 400 N m, tip corners: u = 0.65-0.75 after the end of contact at
u = eps_alpha - 1 = 0.646, 0.90-0.95 before the next start; the tables close the tip
corners under load, issue 25 item 2, docs/stiffness.md 4c), and a whole cycle for max /
min / mean.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearsim.errors import InputError, ModelRangeWarning
from gearsim.fem import calibration as cal
from gearsim.fem import pair as fp
from gearsim.fem.tables import fe_compliance, fe_nodes
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.stiffness.source import PotentialEnergyCompliance
from gearsim.stiffness.tooth import ToothModel
from gearsim.system.train import body_coupling, tooth_compliance

#: FE pair level (see the module docstring).
LEVEL = 1
#: Driver torques [N m]: the example's and 4 times it.
TORQUES = (100.0, 400.0)
#: Positions inside the double- and single-contact zones at both torques.
DOUBLE = (0.15, 0.35)
SINGLE = (0.85,)
#: Zone ends: the start of contact and the positions with tip-corner contact in the FE
#: pair at 400 N m (load share > 0.1 % on a contact without Hertz width).
ENDS = (0.0, 0.65, 0.7, 0.75, 0.9, 0.95)
#: Positions of the cracked checks: the cracked tooth in double contact (the younger
#: pair) and alone in single contact.
CRACKED = (0.35, 0.85)
#: FE positions per cycle of the max / min / mean check (the table is sampled at the
#: same positions, so the sampling of the mean is common to both).
CYCLE = 10
#: Positions per cycle of the tables (a multiple of CYCLE and 1 / 0.05).
NPC = 400
#: The issue's target, relative: calibrated table within 3 % of the FE pair.
TARGET = 0.03
#: The issue's target at the zone ends, relative: within 5 % of the FE pair (measured
#: -0.7 ... +2.1 % on this pair with the tip edge, bench_calibrated.py --accuracy --level 2;
#: +0.6 ... +3.5 % at level 1 before it, when the corner took the path end's whole Hertz
#: strip).
END_TARGET = 0.05
#: Measured band of the healthy calibrated table inside the zones (bench_calibrated.py:
#: +1.2 ... +1.8 %): the FE tooth's superposition error against the FE pair (+1.1-1.7 %,
#: docs/fem.md, "Verification"), the ratio's spline and FE level 1 vs 2 (0.2 %).
HEALTHY_BAND = (0.005, 0.025)
#: Measured band of the cracked calibrated tables inside the zones (1 mm crack, 19/48,
#: bench_calibrated.py, both torques: working flank with the crack correction +1.0 ...
#: +2.0 %, before it +1.2 ... +5.7 %; non-working closed, the PE section reduction,
#: +0.9 ... +1.9 %; no tip corner closes at the positions of this test, u = 0.35 and
#: 0.85): the healthy band, which holds the FE tooth's superposition error that the
#: corrected crack shares; regression guard, not the target.
CRACK_BAND = HEALTHY_BAND
#: Measured band of the cycle mean (100 N m: +1.4 %, 400 N m: +1.1 %, bench_calibrated.py
#: --level 2 with the tip edge; -2.1 % and -4.2 % with the path of contact only): the band
#: inside the zones, now that the tables close the tip corners under load as the FE pair
#: does.
MEAN_BAND = (0.005, 0.025)


@pytest.fixture(scope="module")
def pair(spur):
    return spur.pairs[0]


@pytest.fixture(scope="module")
def fe(spur, pair):
    """FE pair (level 1) results: healthy cycle at both torques, cracks at the positions."""
    out = {}
    model = fp.FEPairModel(pair, torque=TORQUES[0], level=LEVEL)
    for t in TORQUES:
        for u in sorted({i / CYCLE for i in range(CYCLE)} | set(DOUBLE + SINGLE + ENDS)):
            out["none", t, u] = model.solve(u, torque=t).stiffness
    crack = spur.with_crack("working").mesh_cracks(0)[0].crack
    for flank, side in (("working", 1), ("non-working", -1)):
        # the cracked pinion tooth in pair 0: table cycle 0 of its revolution
        cm = fp.FEPairModel(pair, torque=TORQUES[0], level=LEVEL,
                            crack=fp.PairCrack(gear=1, pair=0, crack=crack, side=side,
                                               closure="contact"))
        for t in TORQUES:
            for u in CRACKED:
                out[flank, t, u] = cm.solve(u, torque=t).stiffness
    return out


def _table(spur, pair, flank: str, torque: float, source: str = "calibrated",
           corner: bool = True):
    tr = spur.with_crack(flank, closure="contact")
    kw = {"contact": "line", "coupling": "fe"} if source != "seed" else {}
    st = StiffnessSettings(positions_per_cycle=NPC, source="pe" if source == "seed" else source,
                           corner_contact=corner, **kw)
    return mesh_stiffness(pair, cracks=tr.mesh_cracks(0), settings=st,
                          compliance=tooth_compliance(st.source),
                          force=torque / pair.driver.base_radius, coupling=body_coupling(st))


def _err(ms, k_fe: float, u: float) -> float:
    i = int(round(u * NPC))
    assert abs(i / NPC - u) < 1e-12
    return ms.k[i] / k_fe - 1.0


@pytest.mark.parametrize("torque", TORQUES)
def test_healthy_inside_the_zones(spur, pair, fe, torque):
    """Healthy 19/48: calibrated table within 3 % of the FE pair inside both zones."""
    ms = _table(spur, pair, "none", torque)
    for u in DOUBLE + SINGLE:
        e = _err(ms, fe["none", torque, u], u)
        assert abs(e) < TARGET, (u, e)
        assert HEALTHY_BAND[0] < e < HEALTHY_BAND[1], (u, e)


@pytest.mark.parametrize("torque", TORQUES)
def test_healthy_zone_ends(spur, pair, fe, torque):
    """Healthy 19/48: at the zone ends (start of contact, tip-corner contact in the FE
    pair) the calibrated table is within the issue's 5 % of the FE pair; the table on the
    path of contact only (corner_contact = False) misses them by up to 29 %."""
    ms = _table(spur, pair, "none", torque)
    path = _table(spur, pair, "none", torque, corner=False)
    errs = [_err(ms, fe["none", torque, u], u) for u in ENDS]
    assert max(abs(e) for e in errs) < END_TARGET, dict(zip(ENDS, errs, strict=True))
    assert min(_err(path, fe["none", torque, u], u) for u in ENDS) < -0.1


@pytest.mark.parametrize("torque", TORQUES)
@pytest.mark.parametrize("flank", ["working", "non-working"])
def test_cracked_inside_the_zones_band(spur, pair, fe, flank, torque):
    """Cracked 19/48 (1 mm, faces in contact): the measured band inside the zones."""
    ms = _table(spur, pair, flank, torque)
    for u in CRACKED:
        e = _err(ms, fe[flank, torque, u], u)
        assert CRACK_BAND[0] < e < CRACK_BAND[1], (u, e)


@pytest.mark.parametrize("torque", TORQUES)
def test_working_crack_within_target(spur, pair, fe, torque):
    """Issue 25 target for the working-flank crack: within 3 % inside the zones, with the
    measured crack correction (before it +4 to +6 % in single contact: the PE section
    reduction costs less stiffness than the FE slit; docs/stiffness.md 4c).

    Holds on the three spur pairs of the benchmark at both torques (19/48 here; 17/60
    x1 = +0.3 and 25/25 at 25 deg, bench_calibrated.py --accuracy --extra) and on
    Table-1 mesh I with its 6 mm crack since the cracked body's coupling of the pair away
    from the crack (test_crack_coupling.py; +3.8 % at 4876 N m and +4.4 % at 1219 N m
    with the healthy body's coupling, docs/stiffness.md 4c finding 3).
    """
    ms = _table(spur, pair, "working", torque)
    errs = [_err(ms, fe["working", torque, u], u) for u in CRACKED]
    assert max(abs(e) for e in errs) < TARGET, errs


def test_non_working_crack_within_target(spur, pair, fe):
    """Closed non-working crack: within the 3 % target inside the zones, both torques."""
    for torque in TORQUES:
        ms = _table(spur, pair, "non-working", torque)
        for u in CRACKED:
            assert abs(_err(ms, fe["non-working", torque, u], u)) < TARGET, (torque, u)


@pytest.mark.parametrize("torque", TORQUES)
def test_cycle_max_and_min(spur, pair, fe, torque):
    """Healthy cycle: max and min of the table within 3 % of the FE pair's."""
    ms = _table(spur, pair, "none", torque)
    k_fe = np.array([fe["none", torque, i / CYCLE] for i in range(CYCLE)])
    k = ms.k[:NPC]
    assert np.max(k) == pytest.approx(np.max(k_fe), rel=TARGET)
    assert np.min(k) == pytest.approx(np.min(k_fe), rel=TARGET)


def _mean_error(spur, pair, fe, torque):
    ms = _table(spur, pair, "none", torque)
    k_fe = np.array([fe["none", torque, i / CYCLE] for i in range(CYCLE)])
    return np.mean(ms.k[:NPC:NPC // CYCLE]) / np.mean(k_fe) - 1.0


@pytest.mark.parametrize("torque", TORQUES)
def test_cycle_mean_band(spur, pair, fe, torque):
    """Healthy cycle mean: the measured band (the zone ends pull it down)."""
    assert MEAN_BAND[0] < _mean_error(spur, pair, fe, torque) < MEAN_BAND[1]


@pytest.mark.parametrize("torque", TORQUES)
def test_cycle_mean_within_target(spur, pair, fe, torque):
    """Issue 25 target for the cycle mean at both torques (at 400 N m it was -4.3 %
    before the tables closed the tip corners under load)."""
    assert abs(_mean_error(spur, pair, fe, torque)) < TARGET


def test_seed_model_is_far_from_the_fe_pair(spur, pair, fe):
    """Context: the seed model at the same positions is 10-35 % stiff (docs/fem.md)."""
    ms = _table(spur, pair, "none", TORQUES[0], source="seed")
    for u in DOUBLE + SINGLE:
        assert 0.10 < _err(ms, fe["none", TORQUES[0], u], u) < 0.35


# --- the calibration itself ---------------------------------------------------------


def test_calibrated_healthy_tooth_is_the_fe_tooth_at_the_nodes(pair):
    """Healthy: c_cal = c_FE at the FE-table radii (definition of the ratio)."""
    g = pair.driver
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    nodes, ratio = cal.calibration_ratio(g)
    c = cal.CalibratedCompliance().compliance(g, nodes[:, None], None, np.array([0.5]), st)
    np.testing.assert_allclose(c.sum(axis=-1)[:, 0], fe_compliance(g, nodes)[:, 0],
                               rtol=1e-6)  # calibration solved afresh, the table cached
    assert np.all((ratio > 0.8) & (ratio < 0.95))  # the PE tooth is 5-20 % softer


def test_crack_without_the_correction_is_the_pe_section_reduction(spur, pair):
    """Correction off (and a crack side it does not apply to): c_cal / c_PE is the
    healthy ratio, component by component (the model before the crack correction)."""
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    r = np.concatenate([[0.0], np.linspace(max(g.base_radius, g.root_radius) * 1.02,
                                           g.tip_radius * 0.99, 7)])[:, None]
    z = np.array([0.5])
    ratio = cal.CalibratedCompliance().ratio(g, r, st)
    for flank, sides in (("working", ()), ("non-working", cal.CORRECTED_SIDES)):
        tc = spur.with_crack(flank).mesh_cracks(0)[0]
        assert tc.side not in sides
        pe = PotentialEnergyCompliance().compliance(g, r, tc, z, st)
        c = cal.CalibratedCompliance(corrected_sides=sides).compliance(g, r, tc, z, st)
        np.testing.assert_allclose(c, pe * ratio[..., None], rtol=1e-12)
        assert np.all(c[r[:, 0] == 0] == 0)


# --- the measured crack correction ---------------------------------------------------

#: Interpolation error of the crack correction in depth allowed against a fresh FE tooth
#: at a depth between grid points [-]: the spline of F_FE through F(0) = 1 and the
#: CRACK_GRID depths was within 0.29 % of FE at 0.2 q_c (0.87 mm on the 19/48 pinion)
#: and 0.41 % at any of 10 depths 0.1-0.95 q_c (docs/stiffness.md 4c); 1 mm is 0.23 q_c,
#: in the widest relative gap (0.1-0.3 q_c). 0.5 % is that bound with margin, a sixth of
#: the 3 % target.
DEPTH_INTERPOLATION_TOL = 0.005


def test_working_crack_at_a_grid_depth_is_the_fe_tooth(spur, pair):
    """At the FE-table radii and a grid depth the corrected tooth is the calibrated
    healthy tooth times the measured F_FE (definition), in the PE component split."""
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    crack = spur.with_crack("working").mesh_cracks(0)[0]
    nodes, depths, factor = cal.crack_factor_table(g, crack.crack, crack.side)
    model = cal.CalibratedCompliance()
    z = np.array([0.5])
    healthy = model.compliance(g, nodes[:, None], None, z, st).sum(axis=-1)[:, 0]
    for i, q in enumerate(depths):
        tc = dataclasses.replace(crack, crack=dataclasses.replace(crack.crack, depth=float(q)))
        c = model.compliance(g, nodes[:, None], tc, z, st)[:, 0]
        np.testing.assert_allclose(c.sum(axis=-1), healthy * factor[i], rtol=1e-9)
        pe = PotentialEnergyCompliance().compliance(g, nodes[:, None], tc, z, st)[:, 0]
        split = c / pe  # R Q, the same for the four components
        np.testing.assert_allclose(split, split[:, :1] * np.ones((1, 4)), rtol=1e-12)
    assert np.all(np.diff(factor, axis=0) > 0)  # a deeper crack is more compliant


def test_depth_interpolation_against_a_fresh_fe_tooth(spur, pair):
    """19/48 pinion, 1 mm working crack (between grid depths 0.1 and 0.3 q_c): the
    calibrated cracked tooth at the FE-table radii is the FE tooth with that crack, solved
    afresh, within DEPTH_INTERPOLATION_TOL."""
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    tc = spur.with_crack("working").mesh_cracks(0)[0]
    depths = cal.crack_depths(g, tc.crack)
    assert np.all(np.abs(depths - tc.crack.depth) > 0.2e-3)  # not a grid depth
    nodes = fe_nodes(g)
    c = cal.CalibratedCompliance().compliance(g, nodes[:, None], tc, np.array([0.5]), st)
    fe = fe_compliance(g, nodes, crack=tc.crack, depth=tc.crack.depth, side=tc.side,
                       settings=st, use_cache=False)[:, 0]
    err = c.sum(axis=-1)[:, 0] / fe - 1.0
    assert np.max(np.abs(err)) < DEPTH_INTERPOLATION_TOL, err


def test_crack_deeper_than_the_grid_keeps_the_deepest_correction(spur, pair):
    """Past the deepest grid depth (the FE tooth takes no crack past the centre line) Q
    is held: c_cal = c_PE,crack R Q(q_top), continuous at q_top, growing with depth."""
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    crack = spur.with_crack("working").mesh_cracks(0)[0]
    q_top = cal.crack_depths(g, crack.crack)[-1]
    model = cal.CalibratedCompliance()
    r = fe_nodes(g)[:, None]
    z = np.array([0.5])

    def at(q):
        tc = dataclasses.replace(crack, crack=dataclasses.replace(crack.crack, depth=q))
        return tc, model.compliance(g, r, tc, z, st).sum(axis=-1)[:, 0]

    tc_top, c_top = at(q_top)
    q_top_factor = model.crack_factor(g, r, tc_top, z, st)
    tc_deep, c_deep = at(q_top * 1.2)  # past the centre line: PE only
    pe_deep = PotentialEnergyCompliance().compliance(g, r, tc_deep, z, st).sum(axis=-1)
    ratio = model.ratio(g, r, st)
    np.testing.assert_allclose(c_deep, (pe_deep * ratio * q_top_factor)[:, 0], rtol=1e-9)
    assert np.all(c_deep > c_top)
    np.testing.assert_allclose(at(q_top * (1 + 1e-9))[1], c_top, rtol=1e-6)


def test_crack_profile_takes_each_slice_depth(spur, pair):
    """A crack profile along the face width: each slice is the uniform crack of its local
    depth (one measurement for all of them)."""
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    tc = spur.with_crack("working").mesh_cracks(0)[0]
    tc = dataclasses.replace(tc, crack=dataclasses.replace(tc.crack, depth=2e-3,
                                                           profile="linear", extent=0.8))
    z = np.array([0.1, 0.5, 0.9])  # depths 1.75, 0.75 and 0 mm
    r = np.repeat(fe_nodes(g)[::3, None], z.size, axis=1)
    model = cal.CalibratedCompliance()
    c = model.compliance(g, r, tc, z, st)
    for k, q in enumerate(tc.crack.depth_at(z)):
        one = dataclasses.replace(tc, crack=dataclasses.replace(tc.crack, depth=float(q),
                                                                profile="uniform", extent=1.0))
        np.testing.assert_allclose(c[:, k], model.compliance(g, r[:, k:k + 1], one,
                                                             np.array([0.5]), st)[:, 0],
                                   rtol=1e-12)


def test_crack_the_fe_tooth_refuses_stays_the_pe_section_reduction(spur, pair,
                                                                   monkeypatch):
    """A crack family the FE tooth cannot mesh (e.g. at 10 deg on the 19/48 pinion the
    mesher loses the tip at 0.99 q_c) keeps the PE section reduction, with a
    ModelRangeWarning naming it."""
    def refuse(*a, **kw):
        raise InputError("crack.tip", "(0, 0)", "is not a node of the mesh")

    monkeypatch.setattr(cal, "crack_factor_table", refuse)
    monkeypatch.setattr(cal, "_CRACK_MEMO", {})
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    tc = spur.with_crack("working").mesh_cracks(0)[0]
    r = fe_nodes(g)[:, None]
    z = np.array([0.5])
    with pytest.warns(ModelRangeWarning, match="crack correction of gear pinion"):
        c = cal.CalibratedCompliance().compliance(g, r, tc, z, st)
    before = cal.CalibratedCompliance(corrected_sides=()).compliance(g, r, tc, z, st)
    np.testing.assert_array_equal(c, before)


def test_crack_of_zero_depth_needs_no_measurement(spur, pair, monkeypatch):
    """A crack of depth 0 (the start of a depth sweep) is the healthy calibrated tooth,
    without an FE run."""
    def refuse(*a, **kw):
        raise AssertionError("no FE crack factors for a crack of depth 0")

    monkeypatch.setattr(cal, "crack_factor_table", refuse)
    monkeypatch.setattr(cal, "_CRACK_MEMO", {})
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    g = pair.driver
    tc = spur.with_crack("working").mesh_cracks(0)[0]
    tc = dataclasses.replace(tc, crack=dataclasses.replace(tc.crack, depth=0.0))
    r = fe_nodes(g)[:, None]
    z = np.array([0.5])
    model = cal.CalibratedCompliance()
    np.testing.assert_array_equal(model.compliance(g, r, tc, z, st),
                                  model.compliance(g, r, None, z, st))


def test_crack_correction_key_names_the_crack_family_not_its_depth(pair, monkeypatch):
    g = pair.driver
    crack = Crack(gear=g.name, depth=1e-3)
    key = cal.crack_correction_key(g, crack, 1)[0]
    same = [cal.crack_correction_key(g, dataclasses.replace(crack, depth=2e-3), 1)[0],
            cal.crack_correction_key(g, dataclasses.replace(crack, profile="linear"), 1)[0]]
    assert set(same) == {key}
    others = [cal.crack_correction_key(g, crack, -1)[0],
              cal.crack_correction_key(g, dataclasses.replace(crack, angle=0.6), 1)[0],
              cal.crack_correction_key(g, dataclasses.replace(crack, start_radius=0.031),
                                       1)[0],
              cal.crack_correction_key(g, crack, 1, closure="open")[0],
              cal.crack_correction_key(g, crack, 1, plane="strain")[0],
              cal.crack_correction_key(g, crack, 1, level=3)[0],
              cal.crack_correction_key(dataclasses.replace(g, teeth=20), crack, 1)[0]]
    monkeypatch.setattr(cal, "__version__", "9.9.9")
    others.append(cal.crack_correction_key(g, crack, 1)[0])
    assert len({key, *others}) == 9


def test_corrupt_or_stale_crack_entry_is_rebuilt(pair, tmp_path, monkeypatch):
    """A corrupt, stale or implausible crack-correction file is detected and rebuilt,
    never used. The FE tooth is replaced by a stand-in (F = 1 + depth / 1 mm; the
    neighbours G_load = 1 + depth / 1 mm, G_read = (1 + depth / 1 mm) / 2): the test is
    about the cache file, not the FE solve."""
    monkeypatch.setenv("GEARSIM_CACHE", str(tmp_path))
    g = pair.driver
    crack = Crack(gear=g.name, depth=1e-3)
    calls = []
    n = fe_nodes(g).size

    def stand_in(gear, radii, *, crack=None, depth=0.0, **kw):
        calls.append(depth)  # a healthy tooth 0.9 times the PE tooth
        out = np.zeros((np.size(radii), 4))
        out[:, 0] = 0.9 * ToothModel(gear).compliance(radii).sum(axis=1)
        return out

    def crack_stand_in(gear, nodes, crack, depth, side, closure, plane, level):
        calls.append(depth)  # F = 1 + q / 1 mm, neighbours (1 + q / 1 mm) 1e-12 m^2/N
        c = 0.9 * ToothModel(gear).compliance(nodes).sum(axis=1) * (1 + depth / 1e-3)
        return c, np.full((2, n, n), 1e-12 * (1 + depth / 1e-3))

    def healthy_neighbours(gear, **kw):
        return fe_nodes(gear), np.full((n, n), 1e-12), np.full((n, n), 2e-12)

    monkeypatch.setattr(cal, "fe_compliance", stand_in)
    monkeypatch.setattr(cal, "_crack_solve", crack_stand_in)
    monkeypatch.setattr(cal, "fe_neighbour_coupling", healthy_neighbours)
    nodes, depths, fresh = cal.crack_factor_table(g, crack, 1)
    n_grid = len(cal.CRACK_GRID)
    assert len(calls) == 1 + n_grid  # the healthy calibration, then one per depth
    np.testing.assert_allclose(fresh, (1.0 + depths / 1e-3)[:, None] * np.ones(nodes.size),
                               rtol=1e-12)
    _, _, load, read = cal.crack_cross_table(g, crack, 1)  # the same entry, no new solve
    assert len(calls) == 1 + n_grid
    np.testing.assert_allclose(load, (1.0 + depths / 1e-3)[:, None, None] * np.ones((n, n)),
                               rtol=1e-12)
    np.testing.assert_allclose(read, 0.5 * load, rtol=1e-12)
    key, doc = cal.crack_correction_key(g, crack, 1)
    path = cal.calibration_dir() / f"crack-{key}.npz"
    assert path.exists()
    assert np.array_equal(cal.crack_factor_table(g, crack, 1)[2], fresh)
    assert len(calls) == 1 + n_grid  # read from the cache

    def rebuilt() -> None:
        n = len(calls)
        np.testing.assert_array_equal(cal.crack_factor_table(g, crack, 1)[2], fresh)
        assert len(calls) == n + n_grid
        assert cal._read_crack(path, doc, nodes, depths) is not None  # overwritten

    path.write_bytes(b"not an npz file")  # corrupt
    rebuilt()
    path.write_bytes(path.read_bytes()[:100])  # truncated
    rebuilt()
    other = cal.crack_correction_key(g, crack, -1)[1]  # stale: written for another key
    np.savez(path, key=np.array(other), radii=nodes, depths=depths, factor=fresh)
    rebuilt()
    for bad in (np.full_like(fresh, np.nan), np.full_like(fresh, 50.0), fresh[:-1]):
        np.savez(path, key=np.array(doc), radii=nodes, depths=depths, factor=bad)
        rebuilt()
    np.savez(path, key=np.array(doc), radii=nodes, depths=depths * 1.01, factor=fresh)
    rebuilt()
    np.savez(path, key=np.array(doc), radii=nodes * 1.01, depths=depths, factor=fresh)
    rebuilt()
    for bad in (np.full_like(load, np.nan), np.full_like(load, 50.0), load[:, :-1]):
        np.savez(path, key=np.array(doc), radii=nodes, depths=depths, factor=fresh,
                 cross_load=bad, cross_read=read)
        rebuilt()
    np.savez(path, key=np.array(doc), radii=nodes, depths=depths, factor=fresh,
             cross_load=load)  # written before the coupling factors: no cross_read
    rebuilt()


def test_source_needs_line_contact_and_coupling():
    with pytest.raises(InputError, match="stiffness.source"):
        StiffnessSettings(source="calibrated")
    with pytest.raises(InputError, match="coupling"):
        StiffnessSettings(source="calibrated", contact="line")
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe")
    assert tooth_compliance(st.source).name == "calibrated"


def test_cache_key_names_geometry_material_level_plane_and_version(pair, monkeypatch):
    g = pair.driver
    key = cal.calibration_key(g)[0]
    others = [cal.calibration_key(g, plane="strain")[0], cal.calibration_key(g, level=3)[0],
              cal.calibration_key(dataclasses.replace(g, teeth=20))[0],
              cal.calibration_key(dataclasses.replace(g, material=dataclasses.replace(
                  g.material, youngs_modulus=2.1e11)))[0]]
    monkeypatch.setattr(cal, "__version__", "9.9.9")
    others.append(cal.calibration_key(g)[0])
    assert len({key, *others}) == 6


def test_corrupt_or_stale_cache_entry_is_rebuilt(pair, tmp_path, monkeypatch):
    """A corrupt, stale or implausible cache file is detected and rebuilt, never used."""
    g = pair.driver
    monkeypatch.setattr(cal, "calibration_dir", lambda: tmp_path)
    calls = []
    real = cal.fe_compliance

    def counting(*a, **kw):  # FE values from the FE-table cache: the test is about the
        calls.append(1)      # calibration file, not the FE solve (1-3 s each)
        return real(*a, **{**kw, "use_cache": True})

    monkeypatch.setattr(cal, "fe_compliance", counting)
    nodes, fresh = cal.calibration_ratio(g)
    path = tmp_path / f"{cal.calibration_key(g)[0]}.npz"
    assert path.exists() and len(calls) == 1
    assert np.array_equal(cal.calibration_ratio(g)[1], fresh) and len(calls) == 1  # cached

    def rebuilt() -> None:
        n = len(calls)
        np.testing.assert_array_equal(cal.calibration_ratio(g)[1], fresh)
        assert len(calls) == n + 1
        assert cal._read(path, cal.calibration_key(g)[1], nodes) is not None  # overwritten

    path.write_bytes(b"not an npz file")  # corrupt
    rebuilt()
    path.write_bytes(path.read_bytes()[:100])  # truncated
    rebuilt()
    _, other_doc = cal.calibration_key(g, level=3)  # stale: written for another key
    np.savez(path, key=np.array(other_doc), radii=nodes, ratio=np.full(nodes.size, 0.5))
    rebuilt()
    doc = cal.calibration_key(g)[1]
    for bad in (np.full(nodes.size, np.nan), np.full(nodes.size, 50.0), fresh[:-1]):
        np.savez(path, key=np.array(doc), radii=nodes[:bad.size], ratio=bad)
        rebuilt()
    np.savez(path, key=np.array(doc), radii=nodes * 1.01, ratio=fresh)  # other radii
    rebuilt()


def test_config_file_names_the_calibrated_model(spur, pair):
    """``[stiffness] source = "calibrated"`` in a config: the train's table is the
    calibrated table at the train's mesh force (the load of the line contact)."""
    from importlib.resources import files

    from gearsim.model.config import loads

    text = files("gearsim.data").joinpath("spur-19-48.toml").read_text()
    text = text.replace("[stiffness]\n", '[stiffness]\nsource = "calibrated"\n'
                        'contact = "line"\ncoupling = "fe"\n')
    tr = loads(text).train
    ms = tr.mesh_stiffness(0)
    assert ms.attrs["source"] == "calibrated"
    st = tr.stiffness
    direct = mesh_stiffness(pair, cracks=tr.mesh_cracks(0), settings=st,
                            compliance=tooth_compliance(st.source),
                            force=TORQUES[0] / pair.driver.base_radius,
                            coupling=body_coupling(st))
    np.testing.assert_allclose(ms.k, direct.k, rtol=1e-12)
    with pytest.raises(InputError, match="stiffness.source"):
        loads(text.replace('contact = "line"\n', ""))


@pytest.mark.parametrize(("closure", "expected"), [("contact", 1.0), ("open", 2.0)])
def test_unloaded_flank_takes_q_only_when_open(spur, pair, monkeypatch, closure, expected):
    """The closed crack on the unloaded flank stays the PE section reduction (measured
    better without Q); an open one, with no face contact, takes its Q as on the loaded
    flank (a stand-in Q of 2 here, no FE)."""
    monkeypatch.setattr(cal.CalibratedCompliance, "crack_factor",
                        lambda self, gear, r, *a, **kw: np.full(np.shape(r), 2.0))
    st = StiffnessSettings(source="calibrated", contact="line", coupling="fe",
                           closure=closure)
    g = pair.driver
    tc = spur.with_crack("non-working").mesh_cracks(0)[0]
    assert tc.side == -1
    r = fe_nodes(g)[:, None]
    z = np.array([0.5])
    c = cal.CalibratedCompliance().compliance(g, r, tc, z, st)
    before = cal.CalibratedCompliance(corrected_sides=()).compliance(g, r, tc, z, st)
    np.testing.assert_allclose(c, expected * before, rtol=1e-15)
