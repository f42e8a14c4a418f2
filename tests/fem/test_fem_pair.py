"""FE gear pair in contact (gearsim.fem.pair): checks against independent references.

* Hertz: two elastic discs in line contact, FE half width, peak pressure and pressure
  profile against the 2D Hertz solution (Johnson 1985, eqs. 4.43-4.45).
* Kinematics and statics: rigid involutes touch on the line of action (initial gaps);
  a conjugate rotation of both hubs transmits no force; the driven hub carries
  T z2 / z1 (frictionless contact, normals along the line of action).
* Back flanks: a reversed torque loads the ``-x`` flanks, and the result is the mirror
  image of the drive-flank result at the mirrored mesh position.
* Superposition: the FE pair against a model built from independent parts: the FE
  single-gear compliances (the measure of :mod:`gearsim.fem.tooth`, with the cross
  terms between neighbouring teeth) in series with the 2D Hertz approach between the
  contact point and the measuring points (Johnson 1985, ch. 4, axis stresses of the
  Hertz line contact, integrated; Weber & Banaschek 1953).
* Potential energy: TVMS of the healthy 19/48 spur pair over a mesh cycle against
  ``mesh_stiffness``; the issue's 5 % target is not reached (strict xfail), the measured
  differences and their mechanism are asserted with named bounds.
* Mesh convergence in the level (uniform refinement of the whole size field).
* Bad input: one-line InputError.

Numbers quoted in docs/fem.md, "Gear pair in contact".
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem import pair as fp
from gearsim.fem.geometry import FlankRefinement, SectorOptions, element_size, mesh_sector
from gearsim.fem.solve import ElasticModel
from gearsim.fem.tooth import PATCH_HALF_LENGTH, _patch, load_geometry
from gearsim.geometry.gear import Material
from gearsim.geometry.pair import GearPair
from gearsim.geometry.profile import ToothProfile
from gearsim.model import load
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import StiffnessSettings

#: Nominal torque of the built-in 19/48 example (pinion, face width 16 mm) [N m].
TORQUE = 100.0
#: FE / Hertz half width of the disc contact (second moment of the pressure).
HERTZ_WIDTH_TOL = 0.01
#: FE / Hertz peak pressure.
HERTZ_PEAK_TOL = 0.02
#: RMS of (p_FE - p_Hertz) over the contact, relative to p0.
HERTZ_PROFILE_TOL = 0.03
#: Driven torque against T z2 / z1.
EQUILIBRIUM_TOL = 1e-3
#: Initial gap of rigid involutes at the contact nodes [m]: chord sag of the flank
#: polygon, h_c^2 / (8 rho) < 0.2 um at level 1.
RIGID_GAP_TOL = 0.5e-6
#: Back-flank result against the mirrored drive-flank result (meshes not mirrored).
MIRROR_TOL = 0.005
#: FE pair against FE teeth (with cross terms) + 2D Hertz approach, and its load share.
SUPERPOSITION_TOL = 0.03
SHARE_TOL = 0.01
#: Half widths of the gear contacts against 2D Hertz at the pair's force and curvature.
GEAR_HERTZ_TOL = 0.05
#: The issue's target for PE against the FE pair.
PE_TARGET = 0.05
#: Measured PE - FE differences (docs/fem.md): single contact (both models one pair)
#: and double contact (both two pairs), (k_PE - k_FE) / k_FE.
PE_SINGLE_BOUNDS = (0.05, 0.20)
PE_DOUBLE_BOUNDS = (0.25, 0.45)
#: Convergence: fitted order range and extrapolated error of the default level. The
#: level-to-level changes are 1e-3 and below, near the remeshing noise (meshes are not
#: nested), so the fitted order scatters between positions (0.4-2.9 over a cycle in
#: benchmarks/bench_fem_pair.py --full, 0.9 for the cycle mean): the bound is loose.
#: The test fits levels 0-1-2 (see test_mesh_convergence for why not 1-2-3).
ORDER_RANGE = (0.4, 4.0)
DEFAULT_LEVEL_ERROR = 0.005
#: Single-contact change between levels 1 and 2 (at the remeshing noise; measured
#: 0.058 %, and 0.040 % from level 2 to 3).
SINGLE_LEVEL_CHANGE = 0.002
#: Positions of the cycle study: u = (i + 1/2) / N.
N_POSITIONS = 8


@pytest.fixture(scope="module")
def pair():
    """The 19/48 spur pair of the built-in example."""
    return load("spur-19-48").train.pairs[0]


@pytest.fixture(scope="module")
def model1(pair):
    """Drive-flank model at level 1."""
    return fp.FEPairModel(pair, torque=TORQUE, level=1)


@pytest.fixture(scope="module")
def tvms2(pair):
    """Level-2 (default) FE TVMS over a mesh cycle, and its model."""
    model = fp.FEPairModel(pair, torque=TORQUE, level=fp.DEFAULT_LEVEL)
    u = (np.arange(N_POSITIONS) + 0.5) / N_POSITIONS
    return model, u, [model.solve(float(v)) for v in u]


# ------------------------------------------------------------------ (a) Hertz
@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_hertz_line_contact_of_two_discs(plane):
    """Discs R1 = 20 mm, R2 = 30 mm, 200 kN/m: b, p0 and the pressure ellipse (Johnson)."""
    res = fp.fe_cylinder_contact(0.02, 0.03, 2e5, plane=plane)
    b, p0 = res.hertz_half_width, res.hertz_peak_pressure
    # independent closed form: b = sqrt(4 F R / (pi E*)), R = R1 R2 / (R1 + R2)
    e = Material().youngs_modulus
    nu = Material().poisson_ratio
    e_star = e / (2.0 * ((1 - nu**2) if plane == "strain" else 1.0))
    assert b == pytest.approx(math.sqrt(4 * 2e5 * 0.012 / (math.pi * e_star)), rel=1e-12)
    assert abs(res.half_width / b - 1) < HERTZ_WIDTH_TOL
    assert abs(res.peak_pressure / p0 - 1) < HERTZ_PEAK_TOL
    ph = p0 * np.sqrt(np.clip(1 - (res.x / b) ** 2, 0, None))
    assert np.sqrt(np.mean((res.pressure - ph) ** 2)) / p0 < HERTZ_PROFILE_TOL
    # the contact ends where Hertz says, within two elements
    assert abs(res.extent - b) < 2 * res.h_contact


# ------------------------------------------------------------------ (b) kinematics
def test_rigid_involutes_touch_on_the_line_of_action(pair, model1):
    """Initial gaps: ~0 (chord sag) at the contact points, never negative."""
    for u in (0.1, 0.5, 0.8):
        b1, b2 = model1.bodies
        b1.angle = model1.phi1 - u * model1.pitch1
        b2.angle = model1.phi2 + u * model1.pitch2
        (s1, _), (s2, _) = model1.surfaces
        pr = fp._project(s1, b1, s2, b2, 0, True)
        for k in (0, 1):
            lk = model1.roll_position(u, k)
            if not pair.start_of_contact < lk < pair.end_of_contact:
                continue
            x = model1.t1 + lk * model1.direction
            near = (pr.label == k) & (np.hypot(*(pr.xy - x).T) < 2 * model1.h_contact)
            assert near.any()
            assert pr.g0[near].min() > -1e-9
            assert pr.g0[near].min() < RIGID_GAP_TOL
        assert np.nanmin(pr.g0) > -1e-9  # no rigid overlap anywhere


def test_conjugate_rotation_transmits_no_force(pair, model1):
    """Both hubs turned together (r_b1 theta1 + r_b2 theta2 = 0): zero force."""
    rb1, rb2 = pair.driver.base_radius, pair.driven.base_radius
    for u in (0.3, 0.8):
        for th in (-1e-5, -1e-4):
            res = model1.solve(u, rotation=th, driven_rotation=-th * rb1 / rb2)
            assert res.pair_force.size == 0 or np.all(res.pair_force == 0.0)
            assert res.torque == 0.0 and res.driven_torque == 0.0
        # the same driver rotation against a held driven hub does transmit a torque
        held = model1.solve(u, rotation=-1e-5)
        assert held.torque > 0 and held.stiffness > 0


def test_equilibrium_and_load_sharing(pair, tvms2):
    """Driven torque T z2 / z1; shares sum to 1; contact widths are Hertz's."""
    model, u, results = tvms2
    ratio = pair.driven.teeth / pair.driver.teeth
    for r in results:
        ls = [model.roll_position(r.position, int(k)) for k in r.pair_teeth]
        if all(pair.start_of_contact < lv < pair.end_of_contact for lv in ls):
            # involute contacts only: forces along the line of action
            assert r.driven_torque == pytest.approx(TORQUE * ratio, rel=EQUILIBRIUM_TOL)
        else:  # a tip corner touches off the line of action (extended contact)
            assert r.driven_torque == pytest.approx(TORQUE * ratio, rel=0.02)
        assert r.load_share.sum() == pytest.approx(1.0, abs=1e-12)
        assert np.all(r.load_share >= 0)
        assert r.force == pytest.approx(TORQUE / pair.driver.base_radius)
        assert r.transmission_error > 0 and r.stiffness > 0
        # pairs in the interior of the path: width and peak pressure of 2D Hertz
        for i, k in enumerate(r.pair_teeth):
            lk = model.roll_position(r.position, int(k))
            inside = pair.start_of_contact + 0.1 * pair.base_pitch < lk < \
                pair.end_of_contact - 0.1 * pair.base_pitch
            if inside and r.load_share[i] > 0.2:
                bh = r.hertz_half_width[i]
                assert abs(r.contact_half_width[i] / bh - 1) < GEAR_HERTZ_TOL
                p0 = 2 * r.pair_force[i] / pair.face_width / (math.pi * bh)
                assert abs(r.peak_pressure[i] / p0 - 1) < GEAR_HERTZ_TOL
        assert np.all(r.root_stress_driver > 0) and np.all(r.root_stress_driven > 0)


# ------------------------------------------------------------------ (c) back flanks
def test_reversed_torque_loads_the_back_flanks(pair, model1):
    """T < 0: contact on the -x flanks, the mirror image of the drive-flank contact."""
    back = fp.FEPairModel(pair, torque=-TORQUE, level=1)
    for u in (0.1, 0.5, 0.8):
        rb = back.solve(u)
        rf = model1.solve(back.mirror_position(u))
        assert rb.theta1 > 0 > rf.theta1  # driver pushed the other way
        assert rb.driven_torque < 0 < rf.driven_torque
        # contact on the back flanks: the mirror image x -> -x of the drive contact
        xb = np.sort(rb.contact_xy[:, 0])
        xf = np.sort(-rf.contact_xy[:, 0])
        assert min(xb.max(), xf.max()) > max(xb.min(), xf.min())  # same places
        assert abs(rb.stiffness / rf.stiffness - 1) < MIRROR_TOL
        assert sorted(np.round(rb.load_share, 2)) == pytest.approx(
            sorted(np.round(rf.load_share, 2)), abs=0.011)
    # the labels of a model without meshing it (as the cracked FE pair table reads them
    # when the healthy table is cached) are those of the meshed models, both flanks
    assert fp.FEPairModel.tooth_labels(pair, torque=-TORQUE) == back.teeth
    assert fp.FEPairModel.tooth_labels(pair, torque=TORQUE) == model1.teeth
    # and the back-flank contacts are on the -x involutes of the driver: the driver
    # flank normal at a contact point points to +x in the tooth frame when mirrored
    b1 = back.bodies[0]
    loc = (rb.contact_xy - b1.centre) @ b1.rotation  # global -> local
    for k in rb.pair_teeth:
        sel = rb.contact_pair == k
        a = -int(k) * back.pitch1
        x_tooth = math.cos(-a) * loc[sel, 0] - math.sin(-a) * loc[sel, 1]
        assert np.all(x_tooth < 0)


# ------------------------------------------------------------------ superposition
def _gear_compliance(gear, teeth, radii, level):
    """FE single-gear compliance matrix at the points Q (cross terms between teeth)."""
    prof = ToothProfile(gear)
    pitch = 2 * math.pi / gear.teeth
    sm = mesh_sector(gear, options=SectorOptions(level=level),
                     refine=FlankRefinement(teeth=tuple(sorted(set(teeth))), sides=(1,),
                                            size=element_size(gear, level) / 4))
    model = ElasticModel(sm.p, sm.t, gear.material.youngs_modulus,
                         gear.material.poisson_ratio, plane="stress")
    fixed = model.dofs_on_facets(model.facets_on_nodes(sm.bore))
    half = PATCH_HALF_LENGTH * gear.normal_module
    loads, dirs, qs = [], [], []
    for k, r in zip(teeth, radii, strict=True):
        pt, d, q = load_geometry(prof, r)
        c, s = math.cos(-k * pitch), math.sin(-k * pitch)
        rot = np.array([[c, -s], [s, c]])
        pt, d, q = rot @ pt, rot @ d, rot @ q
        facets = _patch(model, model.facets_on_nodes(sm.parts[(k, 1, "involute")]), pt, half)

        def bell(x, y, point=pt, d=d):
            s2 = ((x - point[0]) ** 2 + (y - point[1]) ** 2) / half**2
            w = np.where(s2 < 1, (1 - s2) ** 2, 0.0)
            return d[0] * w, d[1] * w

        f = model.traction_load(facets, bell, intorder=12)
        loads.append(f / float(np.dot(d, [f[0::2].sum(), f[1::2].sum()])))
        dirs.append(d)
        qs.append(q)
    u = model.solve(np.column_stack(loads), fixed)
    vals = model.probe(np.array(qs).T) @ u
    n = len(teeth)
    return np.array([[dirs[i] @ vals[[i, n + i], j] for j in range(n)] for i in range(n)])


def _hertz_approach(gear, radius, half_width):
    """Plane-stress 2D Hertz approach between the contact and Q per unit load [m/(N/m)].

    Integral of the strain on the axis of a Hertz line contact (Johnson 1985, ch. 4):
    (2 / (pi E)) (ln(2 d / b) - nu / 2), d = |contact point - Q|, d >> b.
    """
    p, _, q = load_geometry(ToothProfile(gear), radius)
    d = float(np.hypot(*(p - q)))
    e, nu = gear.material.youngs_modulus, gear.material.poisson_ratio
    return 2.0 / (math.pi * e) * (math.log(2.0 * d / half_width) - 0.5 * nu)


def test_pair_equals_teeth_plus_contact_superposition(pair, tvms2):
    """FE pair = FE gear compliances (with cross terms) + 2D Hertz approach, within 3 %."""
    model, u, results = tvms2
    g1, g2 = pair.driver, pair.driven
    b = pair.face_width
    for i in (2, 6):  # u = 0.3125 (two pairs), 0.8125 (one pair)
        r = results[i]
        ks = [int(k) for k in r.pair_teeth]
        ls = [model.roll_position(u[i], k) for k in ks]
        r1 = [math.hypot(g1.base_radius, lv) for lv in ls]
        r2 = [math.hypot(g2.base_radius, pair.line_length - lv) for lv in ls]
        c = _gear_compliance(g1, ks, r1, fp.DEFAULT_LEVEL) + \
            _gear_compliance(g2, [-k for k in ks], r2, fp.DEFAULT_LEVEL)
        c += np.diag([_hertz_approach(g1, r1[j], r.hertz_half_width[j])
                      + _hertz_approach(g2, r2[j], r.hertz_half_width[j])
                      for j in range(len(ks))])
        f = np.linalg.solve(c, np.ones(len(ks)))  # equal approach delta = 1 for all pairs
        k_ref = b * f.sum()
        assert abs(r.stiffness / k_ref - 1) < SUPERPOSITION_TOL
        assert np.allclose(r.load_share, f / f.sum(), atol=SHARE_TOL)


# ------------------------------------------------------------------ (d) potential energy
def _pe_differences(pair, u, results):
    pe = mesh_stiffness(pair, settings=StiffnessSettings(plane="stress",
                                                         positions_per_cycle=2 * N_POSITIONS))
    k_pe = pe.k[1:2 * N_POSITIONS:2]  # u = (i + 1/2) / N
    assert np.allclose(fp.pe_slice_stiffness(pair, u), k_pe, rtol=1e-10)
    k_fe = np.array([r.stiffness for r in results])
    n_pe = (pe.pair_k[1:2 * N_POSITIONS:2] > 0).sum(axis=1)
    n_fe = np.array([r.pair_teeth.size for r in results])
    return (k_pe - k_fe) / k_fe, n_pe, n_fe


def test_healthy_tvms_against_potential_energy(pair, tvms2):
    """19/48, 100 N m: PE stiffer by the 2D contact and tooth-coupling terms (docs)."""
    _, u, results = tvms2
    d, n_pe, n_fe = _pe_differences(pair, u, results)
    print("\n(k_PE - k_FE)/k_FE [%]:", np.round(100 * d, 1), "max", round(100 * d.max(), 1),
          "min", round(100 * d.min(), 1), "mean", round(100 * d.mean(), 1))
    single = (n_pe == 1) & (n_fe == 1)
    double = (n_pe == 2) & (n_fe == 2)
    assert single.sum() >= 2 and double.sum() >= 4
    assert np.all((d[single] > PE_SINGLE_BOUNDS[0]) & (d[single] < PE_SINGLE_BOUNDS[1]))
    assert np.all((d[double] > PE_DOUBLE_BOUNDS[0]) & (d[double] < PE_DOUBLE_BOUNDS[1]))
    # the FE path of contact is longer under load: a pair still (or already) carries
    # load where the PE model has one pair only
    assert np.any((n_pe == 1) & (n_fe == 2))


@pytest.mark.xfail(strict=True, reason="the seed's PE options are 10-35 % stiffer than "
                   "the FE pair (2D contact compliance ~4x the PE Hertz term, tooth coupling "
                   "through the body in double contact); docs/fem.md. The FE tooth with "
                   "stiffness.contact = line and coupling = fe meets the target: "
                   "tests/studies/test_fe_pair_check.py")
def test_pe_within_target_of_fe_pair(pair, tvms2):
    """The issue's target with the seed's PE options: within 5 % at every position."""
    d, _, _ = _pe_differences(pair, tvms2[1], tvms2[2])
    assert np.all(np.abs(d) < PE_TARGET)


# ------------------------------------------------------------------ (e) convergence
def test_mesh_convergence(pair, model1, tvms2):
    """Levels 0-1-2 (h_c = 100, 50, 25 um): order, extrapolated error of level 2.

    The levels: the error of the default level 2 is the Richardson estimate of the finest
    of three levels, k_ext - k_2 = (k_2 - k_1) / (2^p - 1), p fitted on levels 0-1-2.
    Levels 1-2-3 (the level-3 model: 570 000 dofs, 48 s of CPU of the 50 s of this test,
    against 1.5 s for level 0) give the same picture at u = 0.3125: k = 297.92 (level 0),
    298.58, 299.04, 299.35 (level 3) MN/m; order 0.51 (0-1-2) and 0.58 (1-2-3); level-2
    error 0.36 % from 0-1-2 and 0.31 % from 1-2-3 (the coarser fit is the more
    conservative here), both under the 0.5 % bound. Level 0 resolves the contact (h_c =
    100 um < Hertz b = 142 um at the pitch point under 100 N m; the model refuses
    coarser). Single contact (u = 0.8125): change 0.058 % from level 1 to 2, 0.040 % from
    2 to 3. The full 1-2-3 study over a cycle: benchmarks/bench_fem_pair.py --full.
    """
    model2, u, res2 = tvms2
    model0 = fp.FEPairModel(pair, torque=TORQUE, level=0)
    i_double, i_single = 2, 6  # u = 0.3125, 0.8125
    k = np.array([[m.solve(float(u[i])).stiffness for i in (i_double, i_single)]
                  for m in (model0, model1)]
                 + [[res2[i_double].stiffness, res2[i_single].stiffness]])
    d1, d2 = k[1, 0] - k[0, 0], k[2, 0] - k[1, 0]
    order = math.log2(abs(d1 / d2))
    k_ext = k[2, 0] + d2 / (2**order - 1)
    err2 = abs(k[2, 0] / k_ext - 1)
    print(f"\nlevels 0-1-2, u = {u[i_double]}: k = {k[:, 0]}, order {order:.2f}, "
          f"level-2 error {100 * err2:.3f} %; u = {u[i_single]}: k = {k[:, 1]}")
    assert d1 * d2 > 0 and abs(d2) < abs(d1)  # monotone, changes shrinking
    assert ORDER_RANGE[0] < order < ORDER_RANGE[1]
    assert err2 < DEFAULT_LEVEL_ERROR
    assert abs(k[2, 1] / k[1, 1] - 1) < SINGLE_LEVEL_CHANGE


# ------------------------------------------------------------------ bad input
def test_bad_input_is_one_line(pair):
    """Positions, torque, level, flanks and backlash: InputError naming the parameter."""
    cases = [
        (lambda: fp.fe_pair_solve(pair, 1.0, torque=TORQUE), "position"),
        (lambda: fp.fe_pair_solve(pair, -0.1, torque=TORQUE), "position"),
        (lambda: fp.fe_pair_solve(pair, float("nan"), torque=TORQUE), "position"),
        (lambda: fp.fe_pair_solve(pair, 0.5, torque=0.0), "torque"),
        (lambda: fp.fe_pair_solve(pair, 0.5, torque=float("inf")), "torque"),
        (lambda: fp.FEPairModel(pair, torque=-TORQUE, flanks="drive"), "torque"),
        (lambda: fp.FEPairModel(pair, torque=TORQUE, flanks="back"), "torque"),
        (lambda: fp.FEPairModel(pair, torque=TORQUE, flanks="left"), "flanks"),
        (lambda: fp.fe_pair_solve(pair, 0.5, torque=10.0, level=1), "fem.level"),
        (lambda: fp.fe_pair_solve(pair, 0.5, torque=TORQUE, level=9), "fem.level"),
        (lambda: fp.fe_pair_solve(pair, 0.5, torque=TORQUE, plane="3d"), "plane"),
        (lambda: fp.fe_pair_tvms(pair, 0, torque=TORQUE), "positions"),
        (lambda: fp.fe_pair_tvms(pair, [0.2, 1.5], torque=TORQUE), "position"),
        (lambda: fp.FEPairModel(GearPair(pair.driver, pair.driven,
                                         centre_distance_offset=2e-5),
                                torque=-TORQUE), "torque"),
        (lambda: fp.fe_cylinder_contact(0.02, -0.03, 1e5), "radius2"),
    ]
    for call, name in cases:
        with pytest.raises(InputError) as info:
            call()
        assert info.value.parameter == name
        assert "\n" not in str(info.value)
    with pytest.raises(InputError, match="use level >= 2"):
        fp.fe_pair_solve(pair, 0.5, torque=10.0, level=1)


def test_torque_of_the_other_sign_is_refused_by_a_model(model1):
    """A model loads one flank side; a torque that would separate it is refused."""
    with pytest.raises(InputError, match="separate"):
        model1.solve(0.5, torque=-TORQUE)
    with pytest.raises(InputError, match="too coarse"):
        model1.solve(0.5, torque=1.0)


def test_vertex_stresses_of_pure_bending():
    """The root-stress recovery is exact for a linear stress field (P2, pure bending)."""
    from gearsim.fem.cantilever import _rectangle

    p, t = _rectangle(0.02, 0.004, 0.5e-3)
    e, nu, kappa = 206e9, 0.3, 0.01
    model = ElasticModel(p, t, e, nu, plane="stress")
    loc = model.basis.doflocs
    x, y = loc
    # pure bending sxx = -E kappa y: u = -kappa x y, v = kappa (x^2 + nu y^2) / 2
    exact = np.where(np.isin(np.arange(model.ndofs), model.basis.nodal_dofs[1])
                     | np.isin(np.arange(model.ndofs), model.basis.facet_dofs[1]),
                     0.5 * kappa * (x**2 + nu * y**2), -kappa * x * y)
    bnd = model.basis.get_dofs().flatten()
    u = model.solve(np.zeros(model.ndofs), bnd, values=exact)
    s = fp._vertex_stress(model, u)
    assert np.allclose(s[0], -e * kappa * p[1], atol=1e-6 * e * kappa * 0.002)
    assert np.allclose(s[1:], 0.0, atol=1e-6 * e * kappa * 0.002)
    assert np.allclose(fp._max_principal(s), np.maximum(-e * kappa * p[1], 0.0),
                       atol=1e-6 * e * kappa * 0.002)
