"""Gears driven by the last planetary stage may branch the power (a power take-off).

A wind-turbine-like box: stage 20/40/100, three planets, ring held, the carrier driven
at 300 rpm with 1000 N m; its sun shaft carries a 25-tooth pinion driving a 50-tooth
gear on out-a (power share 0.7) and a 75-tooth gear on out-b (0.3). The shares are not
the 0.6/0.4 of the brief: with 0.6/0.4 both outputs take the same torque (200 N m), and
a swap of the shares would go unseen. Every expected number is built here from the
tooth counts, the radii and the shares (loss-free kinematics and statics), not read from
the model; the torsional model's natural frequencies against a matrix assembled here.
Gears that drive a stage still pass the power in one path (one line naming the element).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from two_stage_boxes import TOML_CHAINS, TOML_CHAINS_GRAPH, refused_in_one_line

from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.modal import modes
from gearsim.model import loads

#: Kinematics and statics: products and quotients of tooth counts and radii.
KIN_RTOL = 1e-12
#: Static balance of the assembled model (a linear solve).
STATIC_RTOL = 1e-9
#: Mean simulated mesh force against the static one over 0.2 s (whole periods of the
#: carrier, 5 Hz, of every shaft and of both mesh frequencies): measured 4e-6 (LTA) and
#: 1.4e-5 (torsional), the start transient's remainder; a share read wrongly (0.3 for
#: 0.7) moves a mean by more than 50 %.
MEAN_RTOL = 1e-4
#: Natural frequencies against the hand-assembled matrix (two eigen-solvers of the same
#: matrices agree to round-off times the condition number).
MODES_RTOL = 1e-9
#: A mesh line stands this far above the neighbouring bins of the force's spectrum.
LINE_RATIO = 10.0

HEAD = """
name = "planetary stage with a power take-off"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
"""
STAGE = """sun_teeth = 20
planet_teeth = 40
ring_teeth = 100
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
"""
TAIL = """
[dynamics]
duration = 0.2
fs = 20000
"""
#: The box as a graph: the gears after the (last) stage branch.
GRAPH = HEAD + """
[[shafts]]
name = "carrier-in"
[[shafts]]
name = "sun-shaft"
[[shafts]]
name = "out-a"
power_share = 0.7
[[shafts]]
name = "out-b"
power_share = 0.3
[[stages]]
carrier = "carrier-in"
sun = "sun-shaft"
ring = "housing"
""" + STAGE + """
[common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "20 mm"
[[gears]]
name = "pinion"
shaft = "sun-shaft"
teeth = 25
[[gears]]
name = "gear-a"
shaft = "out-a"
teeth = 50
[[gears]]
name = "gear-b"
shaft = "out-b"
teeth = 75
[[meshes]]
gears = ["pinion", "gear-a"]
[[meshes]]
gears = ["pinion", "gear-b"]
angle = "120 deg"
[operating]
speed = "300 rpm"
torque = "1000 N*m"
""" + TAIL
#: The same box in the stage form: a [stage] and its [chain].
STAGE_FORM = HEAD + "[stage]\n" + STAGE + """
[operating]
fixed = "ring"
input = "carrier"
speed = "300 rpm"
torque = "1000 N*m"
[chain]
name = "output gears"
[chain.common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "20 mm"
[[chain.shafts]]
name = "sun-shaft"
[[chain.shafts]]
name = "out-a"
power_share = 0.7
[[chain.shafts]]
name = "out-b"
power_share = 0.3
[[chain.gears]]
name = "pinion"
shaft = "sun-shaft"
teeth = 25
[[chain.gears]]
name = "gear-a"
shaft = "out-a"
teeth = 50
[[chain.gears]]
name = "gear-b"
shaft = "out-b"
teeth = 75
[[chain.meshes]]
gears = ["pinion", "gear-a"]
[[chain.meshes]]
gears = ["pinion", "gear-b"]
angle = "120 deg"
""" + TAIL

# --- by hand -------------------------------------------------------------------------
F_C, T_C = 300 / 60, 1000.0  # carrier: 5 Hz, 1000 N m
P = T_C * 2 * math.pi * F_C  # 31.4 kW
F_SUN = F_C * (1 + 100 / 20)  # ring held, carrier in: the sun at 6 x, 30 Hz
T_SUN = T_C / (1 + 100 / 20)  # 166.67 N m
F_A, F_B = F_SUN * 25 / 50, F_SUN * 25 / 75  # 15 Hz, 10 Hz
T_A = 0.7 * P / (2 * math.pi * F_A)  # 233.33 N m
T_B = 0.3 * P / (2 * math.pi * F_B)  # 150 N m
F_M_STAGE = 100 * F_C  # z_r |f_c - f_r|: 500 Hz
F_M_GEARS = 25 * F_SUN  # 750 Hz, both meshes (one pinion)
COS20 = math.cos(math.radians(20))
R_B = {z: 0.5 * 3e-3 * z * COS20 for z in (20, 25, 40, 50, 75, 100)}  # base radii [m]
F_I, F_II = 0.7 * T_SUN / R_B[25], 0.3 * T_SUN / R_B[25]  # 3310.8 N, 1418.9 N
F_SUN_PLANET = T_SUN / (3 * R_B[20])  # 1970.7 N


@pytest.fixture(scope="module")
def box():
    return loads(GRAPH)


@pytest.fixture(scope="module", params=["lta", "torsional"])
def run(box, request):
    return box.simulate(model=request.param)


def test_speeds_torques_and_forces_by_hand(box):
    st, tr = box.stage, box.train
    assert P == pytest.approx(T_SUN * 2 * math.pi * F_SUN, rel=KIN_RTOL)
    assert abs(st.speeds["sun"]) / (2 * math.pi) == pytest.approx(F_SUN, rel=KIN_RTOL)
    assert abs(st.torques["sun"]) == pytest.approx(T_SUN, rel=KIN_RTOL)
    assert st.mesh_frequency == pytest.approx(F_M_STAGE, rel=KIN_RTOL)
    assert tr.flow.share == (1.0, 0.7, 0.3)
    assert [tr.shaft_frequency(i) for i in range(3)] == pytest.approx(
        [F_SUN, F_A, F_B], rel=KIN_RTOL)
    assert [tr.torque(i) for i in range(3)] == pytest.approx([T_SUN, T_A, T_B], rel=KIN_RTOL)
    assert (T_A, T_B) == pytest.approx((700 / 3, 150.0), rel=KIN_RTOL)
    assert tr.mesh_frequencies == pytest.approx((F_M_GEARS, F_M_GEARS), rel=KIN_RTOL)
    assert [tr.static_mesh_force(i) for i in range(2)] == pytest.approx([F_I, F_II],
                                                                         rel=KIN_RTOL)
    # each output's torque from its own mesh: F r_b of the driven gear
    assert (F_I * R_B[50], F_II * R_B[75]) == pytest.approx((T_A, T_B), rel=KIN_RTOL)
    lay = box.layout()
    assert [(s["name"], s["speed_rpm"], s["torque_Nm"]) for s in lay["shafts"]] == [
        ("carrier-in", pytest.approx(300.0), pytest.approx(T_C)),
        ("sun-shaft", pytest.approx(60 * F_SUN), pytest.approx(T_SUN)),
        ("out-a", pytest.approx(60 * F_A), pytest.approx(T_A)),
        ("out-b", pytest.approx(60 * F_B), pytest.approx(T_B))]
    assert [m["static_force_N"] for m in lay["meshes"]] == pytest.approx([F_I, F_II])


def test_stage_form_is_the_same_box_and_to_toml_reads_back(box):
    staged = loads(STAGE_FORM)
    assert (staged.stage, staged.train) == (box.stage, box.train)
    again = loads(box.to_toml())
    assert again == box and again.train.flow.share == (1.0, 0.7, 0.3)
    assert loads(staged.to_toml()).train == box.train


@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_static_equilibrium_at_the_sun_shaft(box, model):
    dyn = dataclasses.replace(box.dynamics, model=model)
    m = build_stage_chain_model(box.stage, box.train, box.members, dyn)
    f = m.static_force
    rows = m.info["chain_rows"]
    assert [f[r] for r in rows] == pytest.approx([F_I, F_II], rel=STATIC_RTOL)
    # the shaft carries the sun's torque, which the pinion's two meshes take
    assert f[m.info["shaft_row"]] == pytest.approx(T_SUN, rel=STATIC_RTOL)
    assert (f[rows[0]] + f[rows[1]]) * R_B[25] == pytest.approx(T_SUN, rel=STATIC_RTOL)
    # every planet mesh: F = T_sun / (3 r_b,sun), a planet's ring mesh the same (its
    # torque balance), and the three ring meshes hold the ring's 1000 - 166.67 N m
    assert [f[i] for i in m.info["mesh_rows"]] == pytest.approx([F_SUN_PLANET] * 6,
                                                                 rel=STATIC_RTOL)
    assert 3 * F_SUN_PLANET * R_B[100] == pytest.approx(T_C - T_SUN, rel=KIN_RTOL)


def test_mean_mesh_forces_are_the_static_ones_and_each_mesh_line_is_there(run):
    f = run["chain_mesh_force"].values
    assert list(run["chain_mesh"].values) == ["I", "II"]
    assert f.mean(axis=0) == pytest.approx([F_I, F_II], rel=MEAN_RTOL)
    g = run["mesh_force"].values  # each planet's ring mesh as its sun mesh (its torque)
    assert g.mean(axis=0) == pytest.approx([F_SUN_PLANET] * 6, rel=MEAN_RTOL)
    assert float(run["shaft_torque"].mean()) == pytest.approx(T_SUN, rel=MEAN_RTOL)
    fs = float(run.attrs["fs"])
    for x, f_m in ((f[:, 0], F_M_GEARS), (f[:, 1], F_M_GEARS), (g[:, 0], F_M_STAGE)):
        spec = np.abs(np.fft.rfft(x - x.mean()))
        k = int(round(f_m * x.size / fs))  # an exact bin: 0.2 s holds whole periods
        assert k * fs / x.size == pytest.approx(f_m, rel=KIN_RTOL)
        assert spec[k] > LINE_RATIO * max(spec[k - 1], spec[k + 1])


def test_torsional_natural_frequencies_against_a_hand_assembled_matrix(box):
    """Kahraman's torsional stage (u = r theta of carrier, ring, sun and each planet; the
    carrier carries the planets' mass; the ring held by its torsional spring), the shaft
    k_t (u_s / r_s - theta_1) to the pinion, and each mesh r_b1 theta_1 + r_b2 theta_2
    with every gear's angle in its own sense of rotation (signs of whole coordinates do
    not change the frequencies)."""
    dyn = dataclasses.replace(box.dynamics, model="torsional")
    m = build_stage_chain_model(box.stage, box.train, box.members, dyn)
    lp = m.info["lin_parker"]
    n = lp.planets
    tr = box.train
    k_i, k_ii = (m.tables[r].mean for r in m.info["chain_rows"])
    k_t = 10.0 * k_i * R_B[25] ** 2  # the default shaft: ten times the first mesh's
    # carrier, ring, sun, planets, pinion, gear-a, gear-b
    M = np.array([lp.carrier_inertia + n * lp.planet_mass, lp.ring_inertia, lp.sun_inertia]
                 + [lp.planet_inertia] * n + [tr.gear(g).polar_inertia
                                               for g in ("pinion", "gear-a", "gear-b")])
    size = M.size
    K = np.zeros((size, size))
    K[1, 1] = lp.ring_torsional
    for j in range(n):
        for k, alpha, member, sign in ((lp.sun_mesh, lp.sun_pressure_angle, 2, 1.0),
                                       (lp.ring_mesh, lp.ring_pressure_angle, 1, -1.0)):
            b = np.zeros(size)
            b[0], b[member], b[3 + j] = -math.cos(alpha), 1.0, sign
            K += k * np.outer(b, b)
    p = 3 + n
    for k, row in ((k_t, {2: 1.0 / R_B[20], p: -1.0}),
                   (k_i, {p: R_B[25], p + 1: R_B[50]}), (k_ii, {p: R_B[25], p + 2: R_B[75]})):
        b = np.zeros(size)
        for i, v in row.items():
            b[i] = v
        K += k * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, np.diag(M), eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    assert expected.size == size - 1  # one rigid-body rotation: input and outputs free
    got = modes(m).frequencies
    np.testing.assert_allclose(got[got > 1e-6 * got.max()], expected, rtol=MODES_RTOL)


@pytest.mark.parametrize(("signal", "kin"), [
    ("chain_mesh_force[I]", {"teeth": [25, 50]}),
    ("chain_mesh_force[II]", {"teeth": [25, 75]}),
    ("chain_acceleration[out-b,y]", {"teeth": [25, 75]}),
    ("chain_acceleration[out-a,y]", {"teeth": [25, 50]}),
    ("shaft_torque", {"teeth": [25, 50]}),  # the first shaft: mesh I, as a gear train's
    ("mesh_force[sun-planet-2]", {"teeth": [100, 20, 40]}),
])
def test_each_record_is_analysed_with_its_own_path(box, signal, kin):
    """A record of out-b sees 25 -> 75 (its shaft at f_m / 75 = 10 Hz), not the other
    branch; the reference is the sun shaft (30 Hz), a stage record's the carrier."""
    got = box.analysis_train(signal=signal)
    f_ref = F_C if "teeth" in kin and kin["teeth"][0] == 100 else F_SUN
    assert got == {"shaft_frequency": pytest.approx(f_ref, rel=KIN_RTOL), **kin}


@pytest.fixture(scope="module")
def result(box, tmp_path_factory):
    from gearsim.io.results import write_results

    path = tmp_path_factory.mktemp("pto") / "pto.nc"
    write_results(box.simulate(duration=0.05, model="torsional"), path)
    return path


@pytest.mark.parametrize(("channel", "signal", "teeth"), [
    ("chain_mesh_force[chain_mesh=II]", "chain_mesh_force[II]", [25, 75]),
    ("chain_mesh_force[chain_mesh=I]", "chain_mesh_force[I]", [25, 50]),
    ("shaft_torque", "shaft_torque", [25, 50]),
    ("q[dof=out-b.theta]", "q[out-b.theta]", [25, 75]),  # a coordinate: its shaft's path
])
def test_a_result_files_record_is_analysed_with_its_path(result, box, channel, signal,
                                                         teeth):
    """``gearsim analyze RESULT.nc``: as ``analysis_train(signal=)`` (before: mesh II's
    record with 25/50, the file's first mesh, and 25/50/75 from the gearbox)."""
    from gearsim.studies.batch import analyze_file

    out, problems = analyze_file(str(result), channels=[channel])
    assert problems == []
    rec = out[0]["record"]
    assert rec["speed_hz"] == pytest.approx(F_SUN, rel=KIN_RTOL)
    assert rec["teeth"] == teeth and rec["speed_provenance"] == "file"
    assert box.analysis_train(signal=signal)["teeth"] == teeth


# --- what stays out: branching in gears that drive a stage -----------------------------

PTO = """
[[shafts]]
name = "pto"
power_share = 0.5
[[gears]]
name = "pto-gear"
shaft = "pto"
teeth = 40
normal_module = "3 mm"
[[meshes]]
gears = ["{gear}", "pto-gear"]
angle = "90 deg"
"""


#: tests/system/two_stage_boxes.py's TOML_CHAINS whose input pinion drives a power
#: take-off beside the gear on stage 1's sun.
INPUT_BRANCHING = TOML_CHAINS.replace('''[[input_chain.gears]]
name = "input-pinion"
teeth = 20
[[input_chain.gears]]
name = "sun-drive-gear"
teeth = 60
''', '''[[input_chain.shafts]]
name = "in"
[[input_chain.shafts]]
name = "to-stage"
power_share = 0.5
[[input_chain.shafts]]
name = "pto"
power_share = 0.5
[[input_chain.gears]]
name = "input-pinion"
shaft = "in"
teeth = 20
[[input_chain.gears]]
name = "sun-drive-gear"
shaft = "to-stage"
teeth = 60
[[input_chain.gears]]
name = "pto-gear"
shaft = "pto"
teeth = 40
[[input_chain.meshes]]
gears = ["input-pinion", "sun-drive-gear"]
[[input_chain.meshes]]
gears = ["input-pinion", "pto-gear"]
angle = "120 deg"
''')

#: TOML_CHAINS_GRAPH (gears 20/60, stage 1, stage 2, gears 50/25) with a 30/20 pair
#: between the stages: stage 1's carrier (on "between") drives 30 teeth meshing 20 on
#: "mid", which carries stage 2's sun (as tests/system/test_gears_between_stages.py).
FIVE = TOML_CHAINS_GRAPH.replace('sun = "between"', 'sun = "mid"') + """
[[shafts]]
name = "mid"
[[gears]]
name = "mid-gear"
shaft = "between"
teeth = 30
normal_module = "3 mm"
[[gears]]
name = "mid-pinion"
shaft = "mid"
teeth = 20
normal_module = "3 mm"
[[meshes]]
gears = ["mid-gear", "mid-pinion"]
"""


def test_gears_after_the_last_of_two_stages_branch_too():
    """FIVE's output gears 50/25 with a 40-tooth take-off on the carrier gear (shares
    0.8/0.2): by hand, stage 2's carrier takes 200 x 60/20 x 4 x 20/30 x 6 = 9600 N m
    at 1500 x 20/60 / 4 x 30/20 / 6 = 15.625 rpm; the meshes are numbered through the
    three chains (I, II, then III and IV), each record analysed with its own path."""
    gb = loads(FIVE.replace('name = "output"\n', 'name = "output"\npower_share = 0.8\n')
               + PTO.format(gear="carrier-gear").replace("0.5", "0.2").replace(
                   '"3 mm"', '"5 mm"\nface_width = "60 mm"'))
    tr = gb.train
    w_c2, t_c2 = 1500 * 20 / 60 / 4 * 30 / 20 / 6, 9600.0
    assert gb.train.operating.speed * 30 / math.pi == pytest.approx(w_c2, rel=KIN_RTOL)
    assert [tr.torque(tr.gear_index(g)) for g in ("output-pinion", "pto-gear")] == \
        pytest.approx([0.8 * t_c2 * 25 / 50, 0.2 * t_c2 * 40 / 50], rel=KIN_RTOL)
    rb = tr.gear("carrier-gear").base_radius
    assert [tr.static_mesh_force(i) for i in range(2)] == pytest.approx(
        [0.8 * t_c2 / rb, 0.2 * t_c2 / rb], rel=KIN_RTOL)
    assert gb.analysis_train(signal="chain_mesh_force[IV]")["teeth"] == [50, 40]
    assert gb.analysis_train(signal="chain_mesh_force[III]")["teeth"] == [50, 25]
    assert gb.analysis_train(signal="chain_mesh_force[II]")["teeth"] == [30, 20]
    assert loads(gb.to_toml()) == gb
    ds = gb.simulate(duration=0.05, fs=5000.0, model="torsional")
    assert list(ds["chain_mesh"].values) == ["I", "II", "III", "IV"]
    assert float(ds.attrs["static_shaft_torque"]) == pytest.approx(t_c2, rel=STATIC_RTOL)


def test_branching_in_gears_driving_a_stage_is_one_line(tmp_path, capsys):
    assert "pto-gear" in INPUT_BRANCHING
    line = refused_in_one_line(INPUT_BRANCHING, tmp_path, capsys, "input_chain.shafts")
    assert "the gears driving a planetary stage pass the power in one path" in line


@pytest.mark.parametrize(("text", "parameter"), [
    # the gears before stage 1 (its sun shaft also drives a take-off)
    (TOML_CHAINS_GRAPH.replace("[operating]", PTO.format(gear="sun-drive-gear")
                               + "[operating]"), "shafts[1]"),
    # the gears between the two stages (stage 1's carrier gear also drives a take-off)
    (FIVE + PTO.format(gear="mid-gear"), "shafts[2]"),
])
def test_branching_in_graph_gears_driving_a_stage_is_one_line(tmp_path, capsys, text,
                                                              parameter):
    line = refused_in_one_line(text, tmp_path, capsys, parameter)
    assert "branching power beside a planetary stage is read in the gears after the " \
           "last stage only" in line
