"""Speed and load that change (issue 23, item 3): run-ups, coast-downs and the tacho."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.signal import stft

import gearsim as gs
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import build_model, reference_rhs, run_kernel
from gearsim.errors import InputError
from gearsim.signals.ordertrack import order_spectrum
from gearsim.signals.speed import speed_from_tacho
from gearsim.stiffness.settings import MODELS

TWO_PI = 2 * math.pi
#: RK4 at 2.5 us against DOP853 at rtol 1e-10 over 5 ms of a run-up, relative to the
#: largest elastic displacement, on the seed's stiffness tables (measured over 20 ms:
#: 1.1e-6, and 1.8e-4 at 10 us, 7.9e-6 at 5 us: the kernel converges to the reference at
#: fourth order). The default tables close the tip corners under load (docs/stiffness.md
#: 4c): their corner ramps put kinks into the right-hand side, and RK4 converges there
#: at about order 1.5 (measured over 5 ms: 5.5e-5 at 10 us, 5.6e-5 at 2.5 us, 2.1e-5 at
#: 1.25 us, 6.9e-6 at 0.625 us, of a 4.1e-6 m response); what this test checks, that
#: the kernel follows the speed profile as the reference equations do, is independent
#: of the table, so it uses the seed's, where the tolerance can be tight.
KERNEL_RTOL = 1e-5


@pytest.fixture(scope="module")
def box():
    return gs.example("two-stage-reducer")


def _runup(**kw):
    return DynamicsSettings(speed_times=(0.0, 2.0), speed_values=(10 * TWO_PI, 30 * TWO_PI), **kw)


def test_nominal_time_integrates_the_speed_profile():
    st = DynamicsSettings(speed_times=(0.5, 1.5, 2.0), speed_values=(60.0, 120.0, 90.0))
    train = gs.example("spur-19-48").train
    ref = train.operating.speed
    prof, _ = st.profiles(ref)
    m = build_model(train, st)
    t = np.linspace(0, 3, 3001)
    tau, taud, _, _ = m.nominal(t)
    omega = np.interp(t, st.speed_times, st.speed_values)  # held outside the points
    assert np.allclose(taud, omega / ref, rtol=0, atol=1e-12)
    # the angle is the integral of the speed (trapezoid on a fine grid, exact for linear)
    expected = np.concatenate([[0], np.cumsum(0.5 * (omega[1:] + omega[:-1]) * np.diff(t))])
    np.testing.assert_allclose(tau * ref, expected, rtol=1e-9, atol=1e-9)
    assert prof.shape == (4, 4)


def test_kernel_follows_the_profile_like_solve_ivp(box):
    seed = box.replace(stiffness=MODELS["seed"])  # smooth tables (KERNEL_RTOL)
    m = build_model(seed.train, _runup(model="torsional"))
    dt, n = 2.5e-6, 2000
    raw = run_kernel(m, dt=dt, n_steps=n, rec_every=n)
    sol = solve_ivp(reference_rhs(m), (0.0, n * dt), np.concatenate([m.q_static,
                    np.zeros(m.n_dof)]), rtol=1e-10, atol=1e-15, method="DOP853")
    q_ref = sol.y[:m.n_dof, -1]
    scale = np.max(np.abs(q_ref - m.q_static))
    assert np.max(np.abs(raw.q_end - q_ref)) < KERNEL_RTOL * scale


def test_rigid_rotation_stays_at_rest_during_a_run_up(box):
    """The input takes the whole train's inertia torque: the rigid rotation (theta_j
    proportional to the speed ratios) is not forced, so its momentum stays zero."""
    m = build_model(box.train, _runup(model="torsional"))
    raw = run_kernel(m, dt=1e-5, n_steps=20000, rec_every=20000)
    ratios = np.array([box.train.speed(box.train.gear_index(sh.gears[0]))
                       for sh in box.train.flow.shafts]) / box.train.operating.speed
    momentum = np.sum(m.mass * ratios * raw.v_end)
    typical = np.sum(m.mass * ratios * ratios) * np.max(np.abs(raw.v_end))
    assert abs(momentum) < 1e-9 * typical


@pytest.fixture(scope="module")
def runup(box):
    return gs.simulate(box, duration=2.0, transient=0.05, fs=20e3, speed_times=[0.05, 2.05],
                       speed_values=[10 * TWO_PI, 30 * TWO_PI])


def test_mesh_lines_sweep_with_the_speed(box, runup):
    fs = runup.attrs["fs"]
    for mesh, order in ((1, 32.0), (2, 48 * 32 / 80)):
        x = runup[f"mesh_force_{mesh}"].values
        f, t, z = stft(x - x.mean(), fs=fs, nperseg=2000, noverlap=1000)
        t = t + float(runup.time[0])
        for j in range(2, t.size - 2, 4):
            expected = order * (10 + 10 * (t[j] - 0.05))  # input shaft 10 -> 30 Hz in 2 s
            band = (f > 0.6 * expected) & (f < 1.4 * expected)
            peak = f[band][np.argmax(np.abs(z[band, j]))]
            assert abs(peak - expected) < 2 * fs / 2000, (mesh, t[j], peak, expected)


def test_order_spectrum_from_the_own_tacho_has_every_stage_mesh_order(runup):
    fs = runup.attrs["fs"]
    prof = speed_from_tacho(runup["tacho"].sel(shaft="input").values, fs)
    assert prof.mean_frequency == pytest.approx(20.0, rel=0.02)
    # the intermediate bearing hears both meshes; x, where the second mesh's order line
    # stands 12.7x over its neighbours with the default tables (y: 9.2x; 32: 194x and
    # 165x; before the tip-corner contacts smoothed the tables both exceeded 10x)
    x = runup["acceleration"].sel(shaft="intermediate", axis="x").values
    orders, amp = order_spectrum(x, fs, prof, samples_per_rev=256)
    for order in (32.0, 48 * 32 / 80):  # 32 and 19.2 input-shaft orders
        near = np.abs(orders - order) < 0.3
        away = (np.abs(orders - order) > 1.5) & (np.abs(orders - order) < 4)
        assert amp[near].max() > 10 * np.median(amp[away]), order


@pytest.mark.parametrize("kw, match", [
    ({"speed_times": (0.0, 1.0), "speed_values": (-1.0, 10.0)}, r"speed_values = \[-1.0"),
    ({"speed_times": (0.0, 1.0), "speed_values": (math.inf, 10.0)}, r"speed_values"),
    ({"speed_times": (1.0, 0.5), "speed_values": (5.0, 10.0)}, r"speed_times .*must increase"),
    ({"speed_times": (0.0, math.nan), "speed_values": (5.0, 10.0)}, r"speed_times"),
    ({"speed_times": (0.0, 1.0)}, r"speed_times .*together"),
    ({"speed_times": (0.0, 1.0), "speed_values": (5.0,)}, r"speed_values .*one value per"),
    ({"load_times": (0.0,), "load_values": (1e300,)}, r"load_values = \[1e\+300\]"),
])
def test_bad_profiles_are_refused(kw, match):
    with pytest.raises(InputError, match=match):
        DynamicsSettings(**kw)


def test_cli_refuses_a_decreasing_profile_in_one_line(tmp_path, gearsim_here):
    from gearsim.model import example_text

    cfg = tmp_path / "box.toml"
    cfg.write_text(example_text("two-stage-reducer").replace(
        '[dynamics]\nfs = "20 kHz"', '[dynamics]\nfs = "20 kHz"\nspeed_times = [1.0, 0.5]\n'
        'speed_values = ["600 rpm", "1800 rpm"]'))
    out = tmp_path / "run.nc"
    r = gearsim_here("simulate", cfg, "--out", out)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "dynamics.speed_times = [1.0, 0.5]: must increase" in r.stderr
    assert not out.exists()


def test_cli_refuses_a_speed_step_within_one_integration_step(tmp_path, gearsim_here):
    """A speed table that changes within less than dynamics.step (10 us): 600 -> 1800 rpm
    in 1 ns is 1.3e11 rad/s^2, which the run cannot follow (it diverged, exit 1, probe-a
    #9); refused in one line naming the entry and the bound 0 + 10 us. One step apart, or
    a hold of the same speed closer than a step, is accepted."""
    from gearsim.model import example_text

    cfg = tmp_path / "box.toml"
    cfg.write_text(example_text("two-stage-reducer").replace(
        '[dynamics]\nfs = "20 kHz"', '[dynamics]\nfs = "20 kHz"\nspeed_times = [0.0, 1e-9]\n'
        'speed_values = ["600 rpm", "1800 rpm"]'))
    out = tmp_path / "run.nc"
    r = gearsim_here("simulate", cfg, "--out", out)
    assert r.returncode == 2 and r.stderr.strip().splitlines() == [
        "gearsim: error: dynamics.speed_times[1] = 1e-09 s: must be >= speed_times[0] + "
        "dynamics.step = 1e-05 s: the speed changes within less than one integration step, "
        "an acceleration the run cannot follow (or write a smaller [dynamics] step)"], r.stderr
    assert not out.exists()
    DynamicsSettings(speed_times=(0.0, 1e-5), speed_values=(60.0, 180.0))
    DynamicsSettings(speed_times=(0.0, 1e-9, 1.0), speed_values=(60.0, 60.0, 180.0))
    with pytest.raises(InputError, match=r"speed_times\[2\] = 0.5 s: must be >= speed_times"
                       r"\[1\] \+ dynamics.step = 0.51 s"):
        DynamicsSettings(speed_times=(0.0, 0.49, 0.5), speed_values=(60.0, 60.0, 180.0),
                         step=0.02)


def test_analyze_with_the_own_tacho_reports_each_stage_mesh_orders(runup, tmp_path,
                                                                   gearsim_here):
    """gearsim analyze of a run-up result: with its own tacho channel the order spectrum
    of every channel is made of harmonics of the stages' mesh orders (32 and 19.2
    input-shaft orders), and the strongest lines of mesh force i are harmonics of its own
    stage's (the stages are coupled through the intermediate shaft: with the accurate
    stiffness model the 14th harmonic of stage 2, order 268.8, shows in mesh force 1 at
    a third of its strongest line)."""
    import json

    nc = tmp_path / "runup.nc"
    runup.to_netcdf(nc, engine="h5netcdf")

    def lines(channel):
        r = gearsim_here("analyze", nc, "--channel", channel, "--tacho", "tacho[shaft=input]",
                         "--json")
        assert r.returncode == 0, r.stderr
        rec = json.loads(r.stdout)["records"][0]
        assert rec["speed_provenance"] == "file"
        osp = rec["tiers"]["shaft"]["order_spectrum"]
        ranked = sorted(osp["lines"], key=lambda o: -o["amplitude"])
        return [o["order"] for o in ranked], osp["resolution_orders"]

    def harmonic(order, base, res):
        # a bin and a half, or o f_max / fs: a tacho edge is known to one sample, so the
        # speed between two pulses is uncertain by f / fs (1.5e-3 at 30 Hz and 20 kHz),
        # which shifts order o by that fraction (measured: 172.69 for 9 x 19.2, 6e-4)
        return abs(order / base - round(order / base)) * base <= max(1.5 * res,
                                                                     order * 30.0 / 20e3)

    for channel, own in (("mesh_force_1", 32.0), ("mesh_force_2", 19.2),
                         ("acceleration[shaft=intermediate,axis=y]", None)):
        orders, res = lines(channel)  # strongest first
        assert len(orders) >= 4
        bad = [o for o in orders if not any(harmonic(o, b, res) for b in (32.0, 19.2))]
        assert not bad, (channel, bad, orders)
        if own is not None:
            assert all(harmonic(o, own, res) for o in orders[:3]), (channel, orders)


def test_the_seed_model_follows_a_run_up():
    # the seed's 3-DOF model reads its tables at f_i tau(t) like the others (it ran at
    # constant speed whatever the profile said, its shaft angles and tacho included)
    gb = gs.example("idler-table1")
    ds = gs.simulate(gb, model="seed", duration=1.0, transient=0.02, fs=20e3,
                     speed_times=[0.02, 1.02], speed_values=[100.0, 200.0])
    fs, t0 = ds.attrs["fs"], float(ds.time[0])
    z1 = gb.train.gears[0].teeth
    x = ds["mesh_force_1"].values
    f, t, z = stft(x - x.mean(), fs=fs, nperseg=2000, noverlap=1000)
    for j in range(2, t.size - 2, 3):
        expected = z1 * (100.0 + 100.0 * (t[j] + t0 - 0.02)) / TWO_PI
        band = (f > 0.7 * expected) & (f < 1.3 * expected)
        peak = f[band][np.argmax(np.abs(z[band, j]))]
        assert abs(peak - expected) < 2 * fs / 2000, (t[j], peak, expected)
    # the input's angle is the integral of its speed
    ang = ds["shaft_angle"].sel(shaft="input").values
    tt = ds.time.values - 0.02
    want = 100.0 * tt + 50.0 * tt ** 2
    np.testing.assert_allclose(ang - ang[0], want - want[0], rtol=0, atol=1e-3)


def test_the_seed_model_refuses_a_load_profile():
    with pytest.raises(InputError, match=r"dynamics.load_times = \[0.0, 1.0\]: needs model"):
        DynamicsSettings(model="seed", load_times=(0.0, 1.0), load_values=(0.5, 1.0))


def test_the_summary_compares_the_mean_force_with_the_load_it_was_given(box):
    """Load rising from 0.5 to 1.5 over 1 s at constant speed, a record from 0.5 to 1 s
    (after a 0.5 s transient): lambda = 0.5 + t averages 1.25 over it (the record's
    samples: to 1e-3), and the mean mesh force is that times the static force within
    1 %; before, the summary set it against the operating load's static force (+25 %)."""
    gb = box.replace(dynamics={"duration": 0.5, "transient": 0.5, "load_times": [0.0, 1.0],
                               "load_values": [0.5, 1.5]})
    for m in gb.summary(gb.simulate())["meshes"]:
        assert m["load_factor"] == pytest.approx(1.25, abs=1e-3)
        assert abs(m["mean_error"]) < 0.01, m


def test_a_load_profile_of_zeros_has_no_relative_error(box):
    """No load over the record: the mean mesh force is the unloaded gears' (near 0 N
    against static forces of kN), and the summary leaves the relative error out (it
    divided by lambda static = 0: an internal error after the run, probe round 8 #2)."""
    gb = box.replace(dynamics={"duration": 0.12, "transient": 0.05, "load_times": [0.0, 1.0],
                               "load_values": [0.0, 0.0]})
    for m in gb.summary(gb.simulate())["meshes"]:
        assert m["load_factor"] == 0.0 and "mean_error" not in m
        assert abs(m["mean"]) < 1e-3 * m["static_force"], m


@pytest.mark.parametrize("rpm_held", [0.0, 1.0])
def test_a_profile_that_does_not_turn_the_slowest_gear_once_is_refused(box, rpm_held):
    """The constant-speed rule (one revolution of the slowest gear over the record) at the
    profile's speeds: held at 0 or 1 rpm over the record (0.1 to 1.1 s) the reducer's
    output turns 0 and 1/60 x 32/80 x 48/64 = 0.005 times; before, both ran (probe round
    8 #9)."""
    w = rpm_held * math.pi / 30
    gb = box.replace(dynamics={"duration": 1.0, "transient": 0.1, "speed_times": [0.0, 2.0],
                               "speed_values": [w, w]})
    hand = rpm_held / 60 * 1.0 * 32 / 80 * 48 / 64
    with pytest.raises(InputError, match=rf"dynamics.speed_values = .*: turn the slowest "
                       rf"gear, output-gear, {hand:.3g} revolutions over the record \(0.1 "
                       r"to 1.1 s\): must turn it at least once"):
        gb.simulate()
