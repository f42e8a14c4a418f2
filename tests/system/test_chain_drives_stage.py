"""A parallel input stage driving a planetary output stage (issue 23: a stage anywhere).

20/60 spur pair at 1500 rpm and 200 N m on the pinion; its gear drives the sun of a
24/24/72 stage (three planets, ring held, carrier out). Expected numbers are built here
from the tooth counts and the gears' radii (loss-free kinematics and statics, Willis), not
read from the model.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

from gearsim.cli import run as cli_run
from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.modal import modes
from gearsim.dynamics.stage import build_stage_model, model_radii
from gearsim.model import loads

#: Static balance of the assembled model (a least-squares solve of the mean system).
STATIC_RTOL = 1e-8
#: Natural frequencies against the hand-assembled matrix: two eigen-solvers of the same
#: matrices agree to round-off of the condition number (~1e6 here).
MODES_RTOL = 1e-9

TOML = """
name = "parallel input stage driving a planetary output stage"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[stage]
sun_teeth = 24
planet_teeth = 24
ring_teeth = 72
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
[operating]
fixed = "ring"
input = "sun"
speed = "1500 rpm"
torque = "200 N*m"
[dynamics]
duration = 0.5
fs = 20000
[input_chain]
name = "input stage"
shaft_stiffness = "2e6 N*m/rad"
[input_chain.common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[input_chain.gears]]
name = "input-pinion"
teeth = 20
[[input_chain.gears]]
name = "sun-drive-gear"
teeth = 60
"""

W_IN = 1500 * 2 * math.pi / 60
T_IN = 200.0


@pytest.fixture(scope="module")
def box():
    return loads(TOML)


def test_the_stage_runs_at_the_chains_output(box):
    assert box.train is None and box.chains == (box.input_train,)
    assert box.operating() == (pytest.approx(W_IN, rel=1e-15), T_IN)
    op = box.stage.operating
    assert (op.input, op.fixed) == ("sun", "ring")
    assert op.speed == pytest.approx(W_IN * 20 / 60, rel=1e-12)
    assert op.torque == pytest.approx(T_IN * 60 / 20, rel=1e-12)
    # Willis, ring held: omega_c = omega_s z_s / (z_s + z_r)
    assert box.stage.speeds["carrier"] == pytest.approx(W_IN * 20 / 60 * 24 / 96, rel=1e-12)
    f_c = 1500 / 60 * 20 / 60 * 24 / 96
    assert box.stage.mesh_frequency == pytest.approx(72 * f_c, rel=1e-12)  # 150 Hz
    assert box.input_train.mesh_frequency == pytest.approx(20 * 25.0, rel=1e-12)  # 500 Hz


def test_at_moves_the_input_and_the_stage_follows(box):
    moved = box.at(speed=2 * W_IN, torque=3 * T_IN)
    assert moved.input_train.operating.speed == 2 * W_IN
    assert moved.stage.operating.speed == pytest.approx(2 * W_IN / 3, rel=1e-12)
    assert moved.stage.operating.torque == pytest.approx(9 * T_IN, rel=1e-12)


def test_static_torque_balance_at_every_shaft(box):
    model = build_stage_chain_model(box.stage, None, box.members, box.dynamics,
                                    input_chain=box.input_train,
                                    input_shaft_stiffness=box.input_shaft_stiffness)
    f = model.mean_stiffness() * (model.V @ model.q_static)
    t_sun = T_IN * 60 / 20
    assert f[model.info["shaft_row"]] == pytest.approx(t_sun, rel=STATIC_RTOL)
    (row,) = model.info["chain_rows"]
    pin, gear = box.input_train.gears
    assert f[row] * pin.base_radius == pytest.approx(T_IN, rel=STATIC_RTOL)
    assert f[row] * gear.base_radius == pytest.approx(t_sun, rel=STATIC_RTOL)
    r_bs = box.stage.stage.sun.base_radius
    for r in model.info["mesh_rows"]:  # every sun-planet and ring-planet mesh: T_s / (N r_bs)
        assert f[r] == pytest.approx(t_sun / (3 * r_bs), rel=STATIC_RTOL)


def test_torsional_model_equals_a_hand_assembled_matrix(box):
    """Chain pinion and gear (theta, J), the shaft k_t (theta_g - u_s / r_s), the stage as
    Kahraman's torsional model (u = r theta of carrier, ring, sun and each planet)."""
    dyn = dataclasses.replace(box.dynamics, model="torsional")
    model = build_stage_chain_model(box.stage, None, box.members, dyn,
                                    input_chain=box.input_train,
                                    input_shaft_stiffness=box.input_shaft_stiffness)
    lp = build_stage_model(box.stage, box.members, box.dynamics).info["lin_parker"]
    n = lp.planets
    pin, gear = box.input_train.gears
    k_c = model.tables[model.info["chain_rows"][0]].mean
    k_t = box.input_shaft_stiffness
    r_s = model_radii(box.stage.stage)["sun"]
    # coordinates: carrier, ring, sun, planets (u), then pinion, gear (theta)
    m = 3 + n + 2
    M = np.diag([lp.carrier_inertia + n * lp.planet_mass, lp.ring_inertia, lp.sun_inertia]
                + [lp.planet_inertia] * n + [pin.polar_inertia, gear.polar_inertia])
    K = np.zeros((m, m))
    K[:3, :3] = np.diag([lp.carrier_torsional, lp.ring_torsional, lp.sun_torsional])
    for j in range(n):
        for k, alpha, v in ((lp.sun_mesh, lp.sun_pressure_angle, (2, 1.0, 1.0)),
                            (lp.ring_mesh, lp.ring_pressure_angle, (1, 1.0, -1.0))):
            b = np.zeros(m)
            b[0], b[v[0]], b[3 + j] = -math.cos(alpha), v[1], v[2]
            K += k * np.outer(b, b)
    b = np.zeros(m)
    b[-2], b[-1] = pin.base_radius, gear.base_radius  # the chain mesh
    K += k_c * np.outer(b, b)
    b = np.zeros(m)
    b[-1], b[2] = 1.0, 1.0 / r_s  # the shaft from the gear to the sun
    K += k_t * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    got = modes(model).frequencies
    np.testing.assert_allclose(got[got > 1e-6 * got.max()], expected, rtol=MODES_RTOL)


def _amplitude(x: np.ndarray, fs: float, f: float) -> float:
    x = x - x.mean()
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size))) * 4 / x.size
    return float(spec[np.argmin(np.abs(np.fft.rfftfreq(x.size, 1 / fs) - f))])


def test_both_mesh_lines_in_the_simulated_spectrum(box):
    ds = box.simulate()
    fs = ds.attrs["fs"]
    assert ds.attrs["chain_side"] == "input" and ds.attrs["shaft_member"] == "sun"
    acc = ds["chain_acceleration"].sel(chain_shaft="sun-drive-gear", chain_axis="y").values
    line = _amplitude(acc, fs, 500.0)
    assert line > 20 * max(_amplitude(acc, fs, 535.0), _amplitude(acc, fs, 465.0))
    sensor = ds["sensor"].values  # the ring sensor hears the planetary mesh, 72 f_c
    assert _amplitude(sensor, fs, 150.0) > 20 * _amplitude(sensor, fs, 160.5)
    # the shaft carries the chain's output torque on average (static 600 N m)
    assert float(ds["shaft_torque"].mean()) == pytest.approx(600.0, rel=1e-4)


@pytest.mark.parametrize(("edit", "parameter"), [
    (('name = "sun-drive-gear"', 'name = "sun"'), "input_chain.gears"),
    (("[input_chain.common]", "side = 3\n[input_chain.common]"), "input_chain.side"),
    (('shaft_stiffness = "2e6 N*m/rad"', 'shaft_stiffness = "0 N*m/rad"'),
     "input_chain.shaft_stiffness"),
    (('shaft_stiffness = "2e6 N*m/rad"', 'shaft_stiffness = "1e300 N*m/rad"'),
     "input_chain.shaft_stiffness"),
    (('shaft_stiffness = "2e6 N*m/rad"', 'shaft_stiffness = "-2e6 N*m/rad"'),
     "input_chain.shaft_stiffness"),
    (('teeth = 60', 'teeth = 0'), "input_chain.gears"),
])
def test_bad_input_chain_is_one_line(tmp_path, capsys, edit, parameter):
    path = tmp_path / "box.toml"
    path.write_text(TOML.replace(*edit))
    code = cli_run(["stiffness", str(path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and parameter in err[0], err


# --- the stage between two chains: gears, a planetary stage, gears ---------------------

TOML_BOTH = TOML.replace('name = "parallel input stage driving a planetary output stage"',
                         'name = "parallel, planetary, parallel"') + """
[chain]
name = "output stage"
shaft_stiffness = "5e6 N*m/rad"
[chain.common]
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
face_width = "40 mm"
[[chain.gears]]
name = "carrier-gear"
teeth = 50
[[chain.gears]]
name = "output-pinion"
teeth = 25
"""
#: by hand: sun 600 N m at 500 rpm, carrier 4 x 600 N m at 125 rpm, output pinion
#: 2400 x 25 / 50 N m at 250 rpm
T_SUN, T_CARRIER, T_OUT = 600.0, 2400.0, 1200.0


@pytest.fixture(scope="module")
def both():
    return loads(TOML_BOTH)


def _both_model(both, model="lta"):
    dyn = dataclasses.replace(both.dynamics, model=model)
    return build_stage_chain_model(both.stage, both.train, both.members, dyn,
                                   shaft_stiffness=both.shaft_stiffness,
                                   input_chain=both.input_train,
                                   input_shaft_stiffness=both.input_shaft_stiffness)


def test_three_parts_run_at_the_hand_operating_points(both):
    assert both.chains == (both.input_train, both.train)
    w_c = W_IN * 20 / 60 * 24 / 96
    assert both.stage.speeds["carrier"] == pytest.approx(w_c, rel=1e-12)
    assert both.train.operating.speed == pytest.approx(w_c, rel=1e-12)
    assert both.train.operating.torque == pytest.approx(T_CARRIER, rel=1e-12)
    out = both.train.gear_index("output-pinion")
    assert both.train.speed(out) == pytest.approx(2 * w_c, rel=1e-12)
    moved = both.at(speed=2 * W_IN, torque=T_IN)
    assert moved.train.operating.speed == pytest.approx(2 * w_c, rel=1e-12)


def test_three_parts_static_torque_at_every_shaft(both):
    model = _both_model(both)
    f = model.mean_stiffness() * (model.V @ model.q_static)
    entries = {e["side"]: e for e in model.info["chains"]}
    assert f[entries["input"]["shaft_row"]] == pytest.approx(T_SUN, rel=STATIC_RTOL)
    assert f[entries["output"]["shaft_row"]] == pytest.approx(T_CARRIER, rel=STATIC_RTOL)
    (row,) = entries["output"]["rows"]
    cg, op = both.train.gears
    assert f[row] * cg.base_radius == pytest.approx(T_CARRIER, rel=STATIC_RTOL)
    assert f[row] * op.base_radius == pytest.approx(T_OUT, rel=STATIC_RTOL)
    r_bs = both.stage.stage.sun.base_radius
    for r in model.info["mesh_rows"]:
        assert f[r] == pytest.approx(T_SUN / (3 * r_bs), rel=STATIC_RTOL)


def test_three_parts_torsional_model_equals_a_hand_assembled_matrix(both):
    """The input chain and Kahraman's torsional stage as above, plus the output chain on
    the carrier: k_t2 (theta_cg - u_c / r_c), r_c the carrier (planet-centre) radius."""
    model = _both_model(both, "torsional")
    lp = build_stage_model(both.stage, both.members, both.dynamics).info["lin_parker"]
    n = lp.planets
    entries = {e["side"]: e for e in model.info["chains"]}
    pin, gear = both.input_train.gears
    cg, op = both.train.gears
    radii = model_radii(both.stage.stage)
    m = 3 + n + 4
    M = np.diag([lp.carrier_inertia + n * lp.planet_mass, lp.ring_inertia, lp.sun_inertia]
                + [lp.planet_inertia] * n
                + [pin.polar_inertia, gear.polar_inertia, cg.polar_inertia, op.polar_inertia])
    K = np.zeros((m, m))
    K[:3, :3] = np.diag([lp.carrier_torsional, lp.ring_torsional, lp.sun_torsional])
    for j in range(n):
        for k, alpha, v in ((lp.sun_mesh, lp.sun_pressure_angle, (2, 1.0, 1.0)),
                            (lp.ring_mesh, lp.ring_pressure_angle, (1, 1.0, -1.0))):
            b = np.zeros(m)
            b[0], b[v[0]], b[3 + j] = -math.cos(alpha), v[1], v[2]
            K += k * np.outer(b, b)
    i = 3 + n
    for (a, za), (c, zc), side in (((i, pin), (i + 1, gear), "input"),
                                   ((i + 2, cg), (i + 3, op), "output")):
        b = np.zeros(m)
        b[a], b[c] = za.base_radius, zc.base_radius
        K += model.tables[entries[side]["rows"][0]].mean * np.outer(b, b)
    for gear_i, member_i, r, kt in ((i + 1, 2, radii["sun"], both.input_shaft_stiffness),
                                    (i + 2, 0, radii["carrier"], both.shaft_stiffness)):
        b = np.zeros(m)
        b[gear_i], b[member_i] = 1.0, 1.0 / r
        K += kt * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    got = modes(model).frequencies
    np.testing.assert_allclose(got[got > 1e-6 * got.max()], expected, rtol=MODES_RTOL)


def test_three_parts_result_and_records(both):
    ds = both.simulate()
    fs = ds.attrs["fs"]
    assert ds.attrs["chain_side"] == "both"
    assert list(ds["chain_mesh"].values) == ["I", "II"]
    assert float(ds["input_shaft_torque"].mean()) == pytest.approx(T_SUN, rel=1e-4)
    assert float(ds["shaft_torque"].mean()) == pytest.approx(T_CARRIER, rel=1e-4)
    f_out = 50 * 125 / 60  # the output mesh, 104.2 Hz
    acc = ds["chain_acceleration"].sel(chain_shaft="output-pinion", chain_axis="y").values
    assert _amplitude(acc, fs, f_out) > 20 * _amplitude(acc, fs, 1.15 * f_out)
    acc = ds["chain_acceleration"].sel(chain_shaft="input-pinion", chain_axis="y").values
    assert _amplitude(acc, fs, 500.0) > 20 * _amplitude(acc, fs, 535.0)
    names = both.signals()
    for spec in ("chain_mesh_force[II]", "input_shaft_torque",
                 "chain_acceleration[output-pinion,y]"):
        assert spec in names
        assert both.select(ds, spec).shape == (ds.sizes["time"],)
    # each chain's record is analysed with its own chain's kinematics
    assert both.analysis_train(signal="chain_acceleration[output-pinion,y]")[
        "shaft_frequency"] == pytest.approx(125 / 60, rel=1e-12)
    assert both.analysis_train(signal="chain_mesh_force[I]")[
        "shaft_frequency"] == pytest.approx(25.0, rel=1e-12)
