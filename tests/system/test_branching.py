"""Gearboxes whose power branches (issue 23): one gear or one shaft driving two outputs.

Every expected number is built here by hand from the gear data and the outputs' power
shares (speeds, torques, static forces, the torsional matrices), and the mesh phases of a
gear driving two meshes from an independent construction: where the line of action
tangent to both base circles meets the driven tip circle, and the involute's polar
angle there (not the layout's roll-length bookkeeping), and Parker & Lin's sun-planet
phasing (:mod:`gearsim.geometry.planetary`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from branching_boxes import GEAR_SPLIT, IDLER_SPLIT, SHAFT_SPLIT
from two_stage_boxes import refused_in_one_line

import gearsim as gs
from gearsim.dynamics.layout import layout
from gearsim.dynamics.modal import modes
from gearsim.dynamics.simulate import build_model, summary
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.io.results import read_results
from gearsim.model import example_text, loads

#: Assembly checks (the same sums and eigenvalues in another order): round-off.
ROUND_OFF = 1e-9
#: The independent phase construction against the layout's [mesh cycles]: both are a few
#: trigonometric evaluations of the same geometry (measured 0 ... 5.3e-15).
PHASE_TOL = 1e-12
#: Mean simulated mesh force vs static force (as tests/system/test_gearbox_graph.py: the
#: mesh harmonics that alias onto 0 Hz at fs = 384 kHz x 4).
MEAN_FORCE_RTOL = 1e-6

@pytest.fixture(scope="module")
def split():
    return loads(GEAR_SPLIT)


@pytest.fixture(scope="module")
def shaft_split():
    return loads(SHAFT_SPLIT)


def test_gear_split_by_hand(split):
    tr = split.train
    f_in = 1500 / 60
    assert tr.flow.meshes == (("pinion", "gear-a"), ("pinion", "gear-b"))
    assert [tr.shaft_frequency(i) for i in range(3)] == pytest.approx(
        [f_in, f_in * 20 / 40, f_in * 20 / 60], rel=1e-12)
    assert tr.mesh_frequencies == pytest.approx((20 * f_in, 20 * f_in), rel=1e-12)
    r_p = tr.gear("pinion").base_radius
    assert r_p == pytest.approx(0.5 * 3e-3 * 20 * math.cos(math.radians(20)), rel=1e-12)
    assert tr.static_mesh_force(0) == pytest.approx(0.25 * 100 / r_p, rel=1e-12)
    assert tr.static_mesh_force(1) == pytest.approx(0.75 * 100 / r_p, rel=1e-12)
    # output torques: the share of the power at the output's speed
    assert tr.torque(1) == pytest.approx(0.25 * 100 * 40 / 20, rel=1e-12)
    assert tr.torque(2) == pytest.approx(0.75 * 100 * 60 / 20, rel=1e-12)
    assert tr.torque(0) == pytest.approx(100.0, rel=1e-12)


def test_shaft_split_by_hand(shaft_split):
    tr = shaft_split.train
    f_in = 25.0
    f_mid = f_in * 24 / 48
    assert tr.mesh_frequencies == pytest.approx((24 * f_in, 20 * f_mid, 25 * f_mid), rel=1e-12)
    t_mid = 100 * 48 / 24
    rb = {g.name: g.base_radius for g in tr.gears}
    assert [tr.static_mesh_force(i) for i in range(3)] == pytest.approx(
        [100 / rb["p1"], 0.4 * t_mid / rb["p2"], 0.6 * t_mid / rb["p3"]], rel=1e-12)
    assert tr.torque(tr.gear_index("g2")) == pytest.approx(0.4 * t_mid * 50 / 20, rel=1e-12)
    assert tr.torque(tr.gear_index("g3")) == pytest.approx(0.6 * t_mid * 40 / 25, rel=1e-12)


@pytest.mark.parametrize("fidelity", ["torsional", "lta"])
def test_static_equilibrium_carries_each_branch(split, shaft_split, fidelity):
    for box in (split, shaft_split):
        m = build_model(box.train, box.replace(dynamics={"model": fidelity}).dynamics)
        f = m.mean_stiffness() * (m.V @ m.q_static)
        nm = len(box.train.pairs)
        np.testing.assert_allclose(f[:nm], [box.train.static_mesh_force(i) for i in range(nm)],
                                   rtol=ROUND_OFF)
        # the shaft segments (mid: p2 | g1 | p3): 0.4 and 0.6 of the shaft's torque
        np.testing.assert_allclose(np.abs(f[nm:]), m.static_force[nm:], rtol=ROUND_OFF)
    m = build_model(shaft_split.train, shaft_split.replace(dynamics={"model": fidelity}).dynamics)
    np.testing.assert_allclose(m.static_force[3:], [0.4 * 200.0, 0.6 * 200.0], rtol=1e-12)


def test_torsional_natural_frequencies_equal_a_hand_assembled_matrix(split):
    g = {n: split.train.gear(n) for n in ("pinion", "gear-a", "gear-b")}
    M = np.diag([g[n].polar_inertia for n in ("pinion", "gear-a", "gear-b")])
    k1 = split.train.mesh_stiffness(0).k[:40].mean()
    k2 = split.train.mesh_stiffness(1).k[:40].mean()
    v1 = np.array([g["pinion"].base_radius, -g["gear-a"].base_radius, 0.0])
    v2 = np.array([g["pinion"].base_radius, 0.0, -g["gear-b"].base_radius])
    w2 = scipy.linalg.eigh(k1 * np.outer(v1, v1) + k2 * np.outer(v2, v2), M, eigvals_only=True)
    model = build_model(split.train, split.replace(dynamics={"model": "torsional"}).dynamics)
    np.testing.assert_allclose(modes(model).frequencies, np.sqrt(w2[1:]) / (2 * math.pi),
                               rtol=ROUND_OFF)


def test_simulated_mean_mesh_force_equals_static_force(split):
    # 0.2 s: whole periods of the mesh (500 Hz) and of every shaft (25, 12.5, 8.33 Hz);
    # 40 ms of transient
    ds = gs.simulate(split, duration=0.24, transient=0.04, model="torsional", fs=384e3,
                     oversample=4)
    for mesh in summary(ds)["meshes"]:
        assert abs(mesh["mean_error"]) < MEAN_FORCE_RTOL, mesh


def _inv(a: float) -> float:
    return math.tan(a) - a


def _entry_angle(drv, dvn, centre: np.ndarray, phi: float, sense: int) -> float:
    """Own-sense base-point angle of the driver's loaded flank when it reaches the start
    of contact: the line of action tangent to both base circles (driver at the origin)
    meets the driven tip circle nearer the driver, and the involute through that point
    lies inv(alpha_r) behind its base point. A clockwise driver is mirrored (y -> -y)."""
    if sense < 0:
        centre, phi = centre * np.array([1.0, -1.0]), -phi
    rb1, rb2 = drv.base_radius, dvn.base_radius
    a = float(np.hypot(*centre))
    aw = math.acos((rb1 + rb2) / a)
    e = np.array([math.cos(phi), math.sin(phi)])
    n = math.cos(aw) * np.array([-e[1], e[0]]) + math.sin(aw) * e
    t1 = rb1 * np.array([math.cos(phi - aw), math.sin(phi - aw)])
    assert abs(np.dot(t1, n)) < 1e-12 * rb1 and abs(np.dot(centre - t1, n) - np.sqrt(
        a * a - (rb1 + rb2) ** 2)) < 1e-9 * a  # tangent to both base circles
    d = t1 - centre
    b = float(np.dot(d, n))
    ell = -b - math.sqrt(b * b - (np.dot(d, d) - dvn.tip_radius ** 2))
    point = t1 + ell * n
    return math.atan2(point[1], point[0]) + _inv(math.acos(rb1 / float(np.hypot(*point))))


@pytest.mark.parametrize("text, angles", [
    (GEAR_SPLIT, ("120 deg", "97 deg", "-150 deg")),
    (IDLER_SPLIT, ("-95 deg", "-160 deg", "200 deg")),
    # a profile-shifted gear-b: mesh II at its own working pressure angle
    (GEAR_SPLIT.replace("teeth = 60", "teeth = 60\nprofile_shift = 0.4"), ("120 deg", "-150 deg")),
])
def test_second_mesh_phase_from_the_involute(text, angles):
    for angle in angles:
        tr = loads(text.replace(f'"{angles[0]}"', f'"{angle}"')).train
        lay = layout(tr, (math.pi,) * text.count('shaft = "idler"'))
        fl = tr.flow
        first, second = (i for i, (d, _) in enumerate(fl.meshes)
                         if sum(m[0] == d for m in fl.meshes) == 2)  # one gear's two meshes
        drv = tr.gear(fl.meshes[first][0])
        s = int(fl.sense[fl.shaft_of[drv.name]])
        origin = lay.centres[fl.shaft_of[drv.name]]
        psi = [_entry_angle(drv, tr.gear(fl.meshes[i][1]),
                            lay.centres[fl.shaft_of[fl.meshes[i][1]]] - origin,
                            lay.line_angle[i], s) for i in (first, second)]
        # modulo z: a revolution of the driver brings the same tooth back (the integer part
        # below z says which tooth enters the second mesh: a crack's)
        z = drv.teeth
        expected = (psi[0] - psi[1]) * z / (2 * math.pi)
        got = lay.phase[second] - lay.phase[first]
        assert (got - expected + z / 2) % z - z / 2 == pytest.approx(0.0, abs=PHASE_TOL)


def test_pinion_driving_three_gears_has_parker_lins_phases():
    text = GEAR_SPLIT.replace("teeth = 20", "teeth = 22").replace("power_share = 0.75",
                                                                  "power_share = 0.25")
    text = text.replace("teeth = 60", "teeth = 41").replace("teeth = 40", "teeth = 41") + """
[[shafts]]
name = "out-c"
power_share = 0.5
[[gears]]
name = "gear-c"
shaft = "out-c"
teeth = 41
[[meshes]]
gears = ["pinion", "gear-c"]
angle = "240 deg"
"""
    tr = loads(text).train
    lay = layout(tr, ())
    ps = PlanetaryStage(sun_teeth=22, planet_teeth=41, ring_teeth=104, planets=3,
                      normal_module=3e-3, face_width=20e-3)
    gamma = ps.sun_planet_phases  # mesh n lags mesh 1 by gamma_n mesh periods
    got = np.mod(lay.phase - lay.phase[0], 1.0)
    np.testing.assert_allclose(got, np.mod(-gamma, 1.0), atol=PHASE_TOL)
    assert gamma.tolist() == pytest.approx([0.0, 1 / 3, 2 / 3])


def test_crack_on_a_branch_gear_modulates_at_its_own_shaft(split):
    cracked = loads(GEAR_SPLIT + '[[cracks]]\ngear = "gear-b"\ndepth = "1.5 mm"\n')
    ds = gs.simulate(cracked, duration=0.48, transient=0.12, model="torsional")
    fs = ds.attrs["fs"]

    def lines(var, offsets):
        x = ds[var].values - ds[var].values.mean()
        spec = np.abs(np.fft.rfft(x * np.hanning(x.size)))
        freq = np.fft.rfftfreq(x.size, 1 / fs)
        return [spec[np.argmin(np.abs(freq - (500.0 + o)))] for o in offsets]

    f_b, f_a = 25 / 3, 12.5  # out-b (cracked) and out-a shaft frequencies [Hz]
    side_b = lines("mesh_force_2", (-2 * f_b, -f_b, f_b, 2 * f_b))
    side_a = lines("mesh_force_2", (-f_a, f_a))
    assert min(side_b) > 10 * max(side_a), (side_b, side_a)


@pytest.mark.parametrize("edit, parameter", [
    (("power_share = 0.25\n", ""), "shafts.out-a.power_share"),
    (("power_share = 0.75", "power_share = 0.7"), "shafts.power_share"),
    (("power_share = 0.25", "power_share = 0"), "shafts[1].power_share"),
    (("power_share = 0.25", "power_share = -0.25"), "shafts[1].power_share"),
    (("power_share = 0.25", "power_share = nan"), "shafts[1].power_share"),
    (("power_share = 0.25", "power_share = 1e300"), "shafts[1].power_share"),
    (("power_share = 0.25", "power_share = inf"), "shafts[1].power_share"),
    (("power_share = 0.25", "power_share = 1e-300"), "shafts[1].power_share"),
    (("power_share = 0.25", 'power_share = "3 mm"'), "shafts[1].power_share"),
    (('name = "input"\n', 'name = "input"\npower_share = 0.5\n'), "shafts.input.power_share"),
    (('angle = "120 deg"\n', ""), "meshes[1].angle"),
    (('angle = "120 deg"', 'angle = "40 deg"'), "meshes[1].angle"),
])
def test_bad_branching_is_refused_in_one_line(edit, parameter, tmp_path, capsys):
    old, new = edit
    assert old in GEAR_SPLIT
    refused_in_one_line(GEAR_SPLIT.replace(old, new, 1), tmp_path, capsys, parameter)


def test_one_output_takes_all_the_power(tmp_path, capsys):
    text = (GEAR_SPLIT.split("[[shafts]]")[0] + '[[shafts]]\nname = "input"\n[[shafts]]\n'
            'name = "out-a"\npower_share = 0.5\n[[gears]]\nname = "pinion"\nshaft = "input"\n'
            'teeth = 20\n[[gears]]\nname = "gear-a"\nshaft = "out-a"\nteeth = 40\n'
            '[[meshes]]\ngears = ["pinion", "gear-a"]\n')
    line = refused_in_one_line(text, tmp_path, capsys, "shafts.out-a.power_share")
    assert "the only output takes all the power" in line
    # the same box with the share 1 is read
    assert loads(text.replace("power_share = 0.5", "power_share = 1")).train.flow.share == (
        1.0, 1.0)


def test_branching_gears_the_last_stage_drives_are_read():
    from two_stage_boxes import TOML_CHAINS

    head, chain = TOML_CHAINS.split("[chain]\n")
    branched = head + "[chain]\n" + chain.split("[[chain.gears]]")[0] + """
[[chain.shafts]]
name = "c"
[[chain.shafts]]
name = "o1"
power_share = 0.5
[[chain.shafts]]
name = "o2"
power_share = 0.5
[[chain.gears]]
name = "carrier-gear"
shaft = "c"
teeth = 50
[[chain.gears]]
name = "output-pinion"
shaft = "o1"
teeth = 25
[[chain.gears]]
name = "output-b"
shaft = "o2"
teeth = 30
[[chain.meshes]]
gears = ["carrier-gear", "output-pinion"]
[[chain.meshes]]
gears = ["carrier-gear", "output-b"]
angle = "120 deg"
"""
    # (refused before: the gears beside a stage passed the power in one path)
    tr = loads(branched).train
    assert tr.flow.share == (1.0, 0.5, 0.5)
    t_c2 = 200 * 60 / 20 * 4 * 6  # stage 2's carrier: 14400 N m
    assert [tr.torque(i) for i in range(3)] == pytest.approx(
        [t_c2, 0.5 * t_c2 * 25 / 50, 0.5 * t_c2 * 30 / 50], rel=1e-12)


def test_branching_after_the_stage_in_the_graph_form_is_read():
    text = example_text("wind-turbine-grc").replace(
        '[[shafts]]\nname = "high-speed"', '[[shafts]]\nname = "pto"\npower_share = 0.1\n'
        '[[shafts]]\nname = "high-speed"\npower_share = 0.9', 1) + """
[[gears]]
name = "pto-gear"
shaft = "pto"
teeth = 40
normal_module = "5 mm"
face_width = "110 mm"
[[meshes]]
gears = ["intermediate-gear", "pto-gear"]
angle = "120 deg"
"""
    assert 'name = "pto"' in text
    # by hand: 750 kW ... at 22.1 rpm; the intermediate shaft at 22.1 (1 + 99/21) 82/23
    # rpm, the take-off (0.1 of the power) at that x 88/40 (refused before: branching)
    tr = loads(text).train
    p = 324e3 * 22.1 * math.pi / 30
    n_pto = 22.1 * (1 + 99 / 21) * 82 / 23 * 88 / 40
    assert tr.torque(tr.gear_index("pto-gear")) == pytest.approx(
        0.1 * p / (n_pto * math.pi / 30), rel=1e-12)
    assert tr.flow.share[tr.flow.shaft_of["pto-gear"]] == 0.1


def test_branching_box_round_trips_through_the_effective_configuration(split, shaft_split):
    # results files embed the effective configuration: the shares must come back
    for box in (split, shaft_split):
        again = loads(box.to_toml())
        assert again.train == box.train
        assert again.train.flow.share == box.train.flow.share


def test_a_record_is_analysed_with_the_path_to_its_shaft(split, shaft_split):
    # by hand: out-b is reached through mesh I (24/48) and mesh III (25/40), out-a through
    # mesh I and mesh II (20/50); the input shaft and mid see mesh I alone
    tr = shaft_split.train
    expected = {"acceleration[out-b,y]": {"stages": ((24, 48), (25, 40))},
                "acceleration[shaft=out-a,axis=x]": {"stages": ((24, 48), (20, 50))},
                "mesh_force_3": {"stages": ((24, 48), (25, 40))},
                "dte_2": {"stages": ((24, 48), (20, 50))},
                "shaft_torque[spring=mid:p2-g1]": {"teeth": (24, 48)},
                "angular_acceleration[rotation=p3]": {"teeth": (24, 48)},
                "tacho[shaft=input]": {"teeth": (24, 48)}}
    for signal, kin in expected.items():
        assert tr.path_kinematics(tr.record_shaft(signal)) == kin, signal
    assert tr.record_shaft("acceleration[nowhere,y]") is None
    run = shaft_split.analysis_train(signal="acceleration[out-b,y]")
    assert run == {"shaft_frequency": pytest.approx(25.0, rel=1e-12),
                   "stages": ((24, 48), (25, 40))}
    assert shaft_split.analysis_train("reference", "acceleration[out-b,y]")["teeth"] == [24]
    # one pinion driving both: out-b's record sees mesh II alone (20/60)
    assert split.analysis_train(signal="acceleration[out-b,y]") == {
        "shaft_frequency": pytest.approx(25.0, rel=1e-12), "teeth": [20, 60]}


def test_gearsim_analyze_of_a_branching_result_takes_the_records_path(tmp_path, capsys):
    from gearsim.cli import run as cli_run

    cfg, out = tmp_path / "box.toml", tmp_path / "run.nc"
    cfg.write_text(SHAFT_SPLIT)
    assert cli_run(["simulate", str(cfg), "--duration", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    # the mesh forces [N] alone in static_force (before: the shaft springs' torques [N m]
    # after them, probe-a #8), the springs' torques by hand (0.4 and 0.6 of 200 N m) in
    # their own attribute, one per spring
    rb = {g: loads(SHAFT_SPLIT).train.gear(g).base_radius for g in ("p1", "p2", "p3")}
    ds = read_results(out)
    np.testing.assert_allclose(ds.attrs["static_force"], [
        100 / rb["p1"], 0.4 * 200 / rb["p2"], 0.6 * 200 / rb["p3"]], rtol=1e-12)
    np.testing.assert_allclose(ds.attrs["static_shaft_torque"], [80.0, 120.0], rtol=1e-12)
    assert list(ds["spring"].values) == ["mid:p2-g1", "mid:g1-p3"]
    assert cli_run(["analyze", str(out), "--channel", "acceleration[shaft=out-b,axis=y]"]) == 0
    text = capsys.readouterr().out
    assert "stages 24/48, 25/40 (file)" in text
    # stage 2 by hand: mid at 25 x 24 / 48 = 12.5 Hz, f_m = 25 x 12.5 = 312.5 Hz, out-b at
    # 12.5 x 25 / 40 = 7.8125 Hz
    assert "gear stage 2 (25/40): f_m 312.5 Hz, shafts shaft2 12.5 Hz, shaft3 7.8125 Hz" in text


def test_analyze_config_of_a_branching_box_names_each_outputs_path(tmp_path, gearsim_here):
    """An idler driving two gears (21 -> 31 -> 26 and 43): a measured record's stages
    depend on the shaft measured, so ``gearsim analyze --config`` names each output's
    path instead of taking every gear as one chain (before: teeth 21, 31, 26, 43 as one
    train, sidebands of shafts that do not exist); refused before the record is read."""
    box = tmp_path / "split.toml"
    box.write_text(IDLER_SPLIT)
    rec = tmp_path / "rec.csv"
    rec.write_text("a1\n" + "0.5\n" * 64)
    r = gearsim_here("analyze", rec, "--fs", "1000", "--config", box)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].endswith("give --stages of its path (out-a: 21/31,31/26; "
                             "out-b: 21/31,31/43)"), lines[0]
