"""The NREL GRC wind-turbine gearbox: a planetary stage driving two parallel stages (issue 23).

Expected numbers are built here from the tooth counts (Willis for the stage, z ratios for
the parallel stages) and the gears' base radii, not read from the model.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

import gearsim as gs
from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.modal import modes
from gearsim.model import example_text, loads

#: Static balance of the assembled model (a least-squares solve of the mean system).
STATIC_RTOL = 1e-8


@pytest.fixture(scope="module")
def box():
    return gs.example("wind-turbine-grc")


def test_overall_ratio_is_the_reports(box):
    ratio = (1 + 99 / 21) * 82 / 23 * 88 / 22
    assert ratio == pytest.approx(81.49, abs=0.005)  # NREL/TP-5000-47773: 1:81.49
    hs = box.train.speed(box.train.gear_index("high-speed-pinion"))
    assert box.stage.speeds["carrier"] / hs == pytest.approx(1 / ratio, rel=1e-12)


def test_static_torque_balance_at_every_shaft(box):
    model = build_stage_chain_model(box.stage, box.train, box.members, box.dynamics)
    f = model.mean_stiffness() * (model.V @ model.q_static)
    t_in = 324e3
    t_sun = t_in / (1 + 99 / 21)
    assert f[model.info["shaft_row"]] == pytest.approx(t_sun, rel=STATIC_RTOL)
    rows = model.info["chain_rows"]
    ch = box.train
    g = {n: ch.gear(n) for n in ("low-speed-gear", "intermediate-pinion", "intermediate-gear",
                                 "high-speed-pinion")}
    f1, f2 = f[rows[0]], f[rows[1]]
    assert f1 * g["low-speed-gear"].base_radius == pytest.approx(t_sun, rel=STATIC_RTOL)
    # intermediate shaft: torque in from mesh I = torque out to mesh II
    assert f1 * g["intermediate-pinion"].base_radius == pytest.approx(
        f2 * g["intermediate-gear"].base_radius, rel=STATIC_RTOL)
    ratio = (1 + 99 / 21) * 82 / 23 * 88 / 22
    assert f2 * g["high-speed-pinion"].base_radius == pytest.approx(t_in / ratio, rel=1e-6)


def _amplitude(x: np.ndarray, fs: float, f: float) -> float:
    """Amplitude of the line at f from a Hann-windowed FFT (nearest bin)."""
    x = x - x.mean()
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size))) * 4 / x.size
    return float(spec[np.argmin(np.abs(np.fft.rfftfreq(x.size, 1 / fs) - f))])


@pytest.fixture(scope="module")
def run(box):
    return gs.simulate(box, duration=3.0)


def test_every_stage_mesh_line_is_in_the_spectrum(box, run):
    fs = run.attrs["fs"]
    f_p = run.attrs["mesh_frequency"]
    f_i, f_h = box.train.mesh_frequencies
    assert f_p == pytest.approx(99 * 22.1 / 60, rel=1e-12)
    assert f_i == pytest.approx(82 * 22.1 / 60 * (1 + 99 / 21), rel=1e-12)
    assert f_h == pytest.approx(88 * 22.1 / 60 * (1 + 99 / 21) * 82 / 23, rel=1e-12)
    acc = run["chain_acceleration"].sel(chain_shaft="intermediate", chain_axis="y").values
    for f in (f_i, f_h):  # the intermediate bearing hears both parallel meshes
        line = _amplitude(acc, fs, f)
        off = max(_amplitude(acc, fs, f * 1.07), _amplitude(acc, fs, f * 0.93))
        assert line > 20 * off, (f, line, off)
    sensor = run["sensor"].values  # the ring sensor hears the planetary mesh
    assert _amplitude(sensor, fs, f_p) > 20 * _amplitude(sensor, fs, f_p * 1.07)


def test_cracked_intermediate_pinion_sidebands_at_the_intermediate_shaft(box, run):
    cracked = loads(example_text("wind-turbine-grc") + """
[[cracks]]
gear = "intermediate-pinion"
depth = "4 mm"
""")
    ds = gs.simulate(cracked, duration=3.0)
    fs = ds.attrs["fs"]
    # what the crack adds: same run otherwise (deterministic), so the difference is its own
    x = (ds["chain_mesh_force"] - run["chain_mesh_force"]).sel(chain_mesh="I").values
    f_i = box.train.mesh_frequencies[0]
    f_int = box.train.shaft_frequency(box.train.gear_index("intermediate-pinion"))
    f_sun = box.stage.speeds["sun"] / (2 * math.pi)
    # sideband order by order: the crack's +-k f_int lines against the same order at
    # the sun shaft's rate (measured 2026-11-28: orders 1 and 2 at 27x and 89x)
    for order in (1, 2):
        own = [_amplitude(x, fs, f_i + k * f_int) for k in (-order, order)]
        sun = [_amplitude(x, fs, f_i + k * f_sun) for k in (-order, order)]
        assert min(own) > 10 * max(sun), (order, own, sun)


def test_torsional_stage_equals_a_hand_assembled_torsional_planetary_model():
    """Purely torsional planetary model (Kahraman 1994): u = r theta of carrier, ring, sun
    and each planet; planet centres ride on the carrier, delta_sn = u_s + u_n - u_c cos
    alpha_s, delta_rn = u_r - u_n - u_c cos alpha_r (Lin & Parker's deflections with the
    translations held); the carrier's coordinate carries the planets' masses."""
    from gearsim.dynamics.stage import build_stage_model

    gb = gs.example("nrel-grc").with_crack("none")
    dyn = dataclasses.replace(gb.dynamics, model="torsional")
    model = build_stage_model(gb.stage, gb.members, dyn)
    lp = build_stage_model(gb.stage, gb.members, gb.dynamics).info["lin_parker"]
    n = lp.planets
    M = np.diag([lp.carrier_inertia + n * lp.planet_mass, lp.ring_inertia, lp.sun_inertia]
                + [lp.planet_inertia] * n)
    K = np.diag([lp.carrier_torsional, lp.ring_torsional, lp.sun_torsional] + [0.0] * n)
    for j in range(n):
        for k, alpha, v in ((lp.sun_mesh, lp.sun_pressure_angle, (2, 1.0, 1.0)),
                            (lp.ring_mesh, lp.ring_pressure_angle, (1, 1.0, -1.0))):
            b = np.zeros(3 + n)
            b[0], b[v[0]], b[3 + j] = -math.cos(alpha), v[1], v[2]
            K += k * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    assert model.dof_labels == ("carrier.u", "ring.u", "sun.u", "planet-1.u", "planet-2.u",
                                "planet-3.u")
    np.testing.assert_allclose(modes(model).frequencies, expected, rtol=1e-9)


def test_result_file_brings_the_parallel_stages_to_the_analysis(box, run, tmp_path):
    """A written stage-plus-gears result is analysed with its shafts' speeds: the reader
    takes the stage output (sun) shaft as the reference, 22.1 rpm x (1 + 99/21) by
    Willis, and the parallel stages 82/23, 88/22 (not only the planetary tier)."""
    from gearsim.io.measured import read_record
    from gearsim.signals.tiers import analyze_record

    path = tmp_path / "wt.nc"
    run.to_netcdf(path, engine="h5netcdf")
    channel = "chain_acceleration[chain_shaft=intermediate,chain_axis=y]"
    rec = read_record(path, channels=[channel])
    assert rec.metadata["rpm"] == pytest.approx(22.1 * (1 + 99 / 21), rel=1e-12)
    assert rec.metadata["stages"] == ((82, 23), (88, 22))
    out = analyze_record(rec.data[channel], rec.fs, speed=rec.metadata["rpm"] / 60.0,
                         stages=rec.metadata["stages"]).to_dict()
    stages = out["tiers"]["gear"]["analysis"]["stages"]
    f_sun = 22.1 / 60 * (1 + 99 / 21)
    assert [s["mesh_frequency_hz"] for s in stages] == pytest.approx(
        [82 * f_sun, 88 * f_sun * 82 / 23], rel=1e-12)


def test_a_study_analyses_a_bearing_of_the_parallel_stages(box):
    """Sensors anywhere: the intermediate bearing is a study's record, analysed with the
    parallel stages' kinematics (sun shaft 22.1 rpm x (1 + 99/21), stages 82/23, 88/22),
    not the stage's carrier."""
    from gearsim.studies.sweep import expand, loads_study
    from gearsim.studies.sweep_case import run_group

    signal = "chain_acceleration[intermediate,y]"
    assert signal in box.signals() and "chain_mesh_force[II]" in box.signals()
    train = box.analysis_train(signal=signal)
    assert train["shaft_frequency"] == pytest.approx(22.1 / 60 * (1 + 99 / 21), rel=1e-12)
    assert train["stages"] == ((82, 23), (88, 22))
    assert box.analysis_train()["shaft_frequency"] == pytest.approx(22.1 / 60, rel=1e-12)
    study = loads_study(f"""
[study]
name = "wind-turbine bearings"
config = "wind-turbine-grc"
signal = "{signal}"
[study.dynamics]
duration = "3 s"
[parameters]
torque = ["200 kN*m", "324 kN*m"]
""")
    ds = run_group(study, expand(study)[:1], None)
    assert str(ds["status"].values[0]) == "ok", str(ds["error"].values[0])
    assert "stage2_mesh_amplitude_o1" in ds and np.isfinite(ds["stage2_mesh_amplitude_o1"]).all()
