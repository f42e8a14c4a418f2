"""A planetary stage driving a chain of parallel gears through its output shaft.

Independent numbers: the torque balance of the stage (Willis, the chain's gear ratio);
the stage and the chain each built alone by their own builders, whose natural
frequencies a very soft shaft must leave unchanged and whose chain dynamics it must
reproduce; ``scipy.integrate.solve_ivp`` on the numpy right-hand side for the kernel
with two mesh frequencies; the chain mesh frequency z_1 f_out from the kinematics.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp

from gearsim import cli
from gearsim.dynamics.compose import (
    SHAFT_FACTOR,
    build_stage_chain_model,
    chain_operating,
    simulate_stage_chain,
)
from gearsim.dynamics.lta import build_lta
from gearsim.dynamics.model import DynamicModel
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.simulate import reference_mesh_forces, reference_rhs, run_kernel, simulate
from gearsim.dynamics.stage import StageDynamics, build_stage_model
from gearsim.errors import InputError
from gearsim.geometry.gear import Gear
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.model.config import example_text, loads
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system import GearTrain
from gearsim.system.planetary import PlanetaryTrain, StageOperating

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

#: Static equilibrium: a linear solve (round-off only).
STATIC = 1e-8
#: A shaft 1e-8 times the default leaves both parts' frequencies within this (the
#: coupling shifts them by about k_t / k_mode; measured 4e-9).
DECOUPLED = 1e-5
#: Kernel against solve_ivp (RK45, rtol 1e-8), as tests/dynamics/test_dyn_ivp.py.
REL_TOL = 1e-4
#: Chain mesh force with a very soft shaft (1e-4 of the default) against the chain alone
#: driven by a constant torque: the shaft passes k_t times the output's dynamic twist;
#: RMS of the dynamic force within 1 % (measured 0.04 %).
CHAIN_ALONE = 0.01


def _stage_train() -> PlanetaryTrain:
    # ring held, sun input 18 Hz: carrier output at 5 Hz, f_m 390 Hz
    st = PlanetaryStage(30, 24, 78, 2e-3, planets=3, face_width=0.02,
                        ring_addendum_coefficient=0.8)
    return PlanetaryTrain(st, StageOperating(speed=18.0 * 2 * math.pi, torque=100.0),
                          StiffnessSettings(positions_per_cycle=16, slices=2))


def _chain(train: PlanetaryTrain) -> GearTrain:
    gears = (Gear(teeth=60, normal_module=2e-3, face_width=0.02, name="wheel"),
             Gear(teeth=21, normal_module=2e-3, face_width=0.02, name="pinion"))
    return GearTrain(gears=gears, operating=chain_operating(train), name="parallel",
                     stiffness=StiffnessSettings(positions_per_cycle=16, slices=2))


@pytest.fixture(scope="module")
def parts():
    tr = _stage_train()
    return tr, _chain(tr)


def _frequencies(m: DynamicModel) -> np.ndarray:
    K = np.diag(m.kb).astype(float)
    for i, t in enumerate(m.tables):
        K += t.mean * np.outer(m.V[i], m.V[i])
    w2 = scipy.linalg.eigh(K, np.diag(m.mass), eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi)


def test_operating_point_and_static_torques(parts) -> None:
    tr, ch = parts
    op = chain_operating(tr)
    # ring held: carrier at z_s / (z_s + z_r) of the sun, torque (1 + z_r / z_s) T_s
    assert op.speed == pytest.approx(18.0 * 2 * math.pi * 30 / 108, rel=1e-12)
    assert op.torque == pytest.approx(100.0 * 108 / 30, rel=1e-12)
    m = build_stage_chain_model(tr, ch)
    kmean = np.array([t.mean for t in m.tables])
    f = kmean * (m.V @ m.q_static)
    assert f[m.info["shaft_row"]] == pytest.approx(op.torque, rel=STATIC)
    (row,) = m.info["chain_rows"]
    assert f[row] == pytest.approx(op.torque / ch.gears[0].base_radius, rel=STATIC)
    # the stage's meshes carry what they carry alone: T_s / (N r_b,s)
    for i in m.info["mesh_rows"]:
        assert f[i] == pytest.approx(100.0 / (3 * tr.stage.sun.base_radius), rel=1e-6)
    # two mesh frequencies: the chain's at z_1 f_carrier
    assert m.mesh_frequencies[row] == pytest.approx(60 * 5.0, rel=1e-12)
    assert m.mesh_frequencies[m.info["mesh_rows"][0]] == pytest.approx(390.0, rel=1e-12)


def test_soft_shaft_leaves_both_parts_frequencies(parts) -> None:
    tr, ch = parts
    s = DynamicsSettings()
    alone = np.concatenate([_frequencies(build_stage_model(tr, StageDynamics(), s)),
                            _frequencies(build_lta(ch, s))])
    k_default = SHAFT_FACTOR * build_lta(ch, s).tables[0].mean * ch.gears[0].base_radius ** 2
    both = _frequencies(build_stage_chain_model(tr, ch, settings=s,
                                                shaft_stiffness=1e-8 * k_default))
    top = alone.max()
    keep_a = np.sort(alone[alone > 1e-3 * top])
    keep_b = np.sort(both[both > 1e-3 * top])
    np.testing.assert_allclose(keep_b, keep_a, rtol=DECOUPLED)
    # the stiff default shaft couples them: the shaft mode rises among the elastic ones
    # and some frequency is more than 1 % from every frequency of the parts alone
    stiff = _frequencies(build_stage_chain_model(tr, ch, settings=s))
    stiff = np.sort(stiff[stiff > 1e-3 * top])
    assert stiff.size == keep_a.size + 1
    nearest = np.min(np.abs(stiff[:, None] / keep_a[None, :] - 1), axis=1)
    assert nearest.max() > 0.01


def test_kernel_with_two_mesh_frequencies_matches_solve_ivp(parts) -> None:
    tr, ch = parts
    m = build_stage_chain_model(tr, ch, settings=DynamicsSettings(nonlinear=False))
    dt = 2e-6
    window = 0.004  # 1.6 stage and 1.2 chain mesh periods, with the start transient
    n = int(round(window / dt))
    raw = run_kernel(m, dt=dt, n_steps=n, rec_every=25)
    y0 = np.concatenate([m.q_static, np.zeros(m.n_dof)])
    sol = solve_ivp(reference_rhs(m), (0.0, raw.t[-1]), y0, method="RK45", rtol=1e-8,
                    atol=1e-15, t_eval=raw.t, max_step=1e-5)
    assert sol.success
    f_ivp = np.array([reference_mesh_forces(m, t, y[:m.n_dof], y[m.n_dof:])
                      for t, y in zip(sol.t, sol.y.T, strict=True)])
    rows = list(m.info["mesh_rows"]) + list(m.info["chain_rows"]) + [m.info["shaft_row"]]
    err = np.abs(raw.f[:, rows] - f_ivp[:, rows]).max(axis=0) / np.abs(f_ivp[:, rows]).max(
        axis=0)
    assert np.all(err < REL_TOL), err


def test_soft_shaft_chain_runs_as_alone(parts) -> None:
    tr, ch = parts
    s = DynamicsSettings(duration=0.2, fs=20000.0, transient=0.4)
    k_default = SHAFT_FACTOR * build_lta(ch, s).tables[0].mean * ch.gears[0].base_radius ** 2
    # 1e-4 of the default: a static twist of 0.3 rad, inside the kernel's bounds
    both = simulate_stage_chain(tr, ch, settings=s, shaft_stiffness=1e-4 * k_default)
    alone = simulate(ch, s)
    f_both = both["chain_mesh_force"].values[:, 0]
    f_alone = alone["mesh_force_1"].values
    assert np.mean(f_both) == pytest.approx(np.mean(f_alone), rel=1e-4)
    assert np.std(f_both) == pytest.approx(np.std(f_alone), rel=CHAIN_ALONE)


def test_chain_mesh_line_in_the_run(parts) -> None:
    tr, ch = parts
    # 0.2 s: whole periods of both mesh frequencies (390 and 300 Hz) and of the carrier
    ds = simulate_stage_chain(tr, ch, settings=DynamicsSettings(duration=0.2, fs=5000.0))
    f = ds["chain_mesh_force"].values[:, 0]
    spec = np.abs(np.fft.rfft(f - f.mean()))
    k = int(round(300.0 * f.size / 5000.0))  # the chain's mesh frequency, an exact bin
    assert spec[k] > 10 * max(spec[k - 1], spec[k + 1])
    g = ds["mesh_force"].values[:, 0]
    gs = np.abs(np.fft.rfft(g - g.mean()))
    j = int(round(390.0 * g.size / 5000.0))  # the stage's, in its own mesh forces
    assert gs[j] > 10 * max(gs[j - 1], gs[j + 1])
    assert ds.attrs["chain_mesh_frequency"] == pytest.approx(300.0)
    assert ds["shaft_torque"].mean() == pytest.approx(360.0, rel=1e-3)


def test_bad_chain_input() -> None:
    tr = _stage_train()
    ch = _chain(tr)
    wrong = dataclasses.replace(ch, operating=dataclasses.replace(ch.operating, torque=1.0))
    with pytest.raises(InputError, match="chain.operating.torque"):
        build_stage_chain_model(tr, wrong)
    for bad in (-1.0, 0.0, math.inf, math.nan):
        with pytest.raises(InputError, match="chain.shaft_stiffness"):
            build_stage_chain_model(tr, ch, shaft_stiffness=bad)
    with pytest.raises(InputError, match="twice the highest mesh frequency"):
        simulate_stage_chain(tr, ch, settings=DynamicsSettings(fs=700.0))


CHAIN = """
[chain]
name = "parallel stage"
shaft_stiffness = "2e5 N*m/rad"
[chain.common]
normal_module = "2 mm"
face_width = "20 mm"
[[chain.gears]]
name = "wheel"
teeth = 60
[[chain.gears]]
name = "pinion"
teeth = 21
"""


def _stage_config() -> str:
    text = example_text("lin-parker-1999")
    return "\n".join(ln for ln in text.splitlines() if "mesh_stiffness" not in ln) + "\n"


def test_config_and_cli(capsys, tmp_path) -> None:
    box = loads(_stage_config() + CHAIN)
    assert box.train is not None and box.shaft_stiffness == pytest.approx(2e5)
    assert box.train.operating == chain_operating(box.stage)
    path = tmp_path / "sc.toml"
    path.write_text(_stage_config().replace("duration = 1.0", "duration = 0.1") + CHAIN)
    nc = tmp_path / "sc.nc"
    code = cli.run(["simulate", str(path), "--out", str(nc)])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "chain mesh I" in out.out and "output shaft (carrier)" in out.out
    code = cli.run(["stiffness", str(path)])
    out = capsys.readouterr()
    assert code == 0 and "chain mesh I (wheel -> pinion)" in out.out


@pytest.mark.parametrize("extra,parameter", [
    ('[chain]\nspeed = "100 rpm"\n', "chain.speed"),
    ('[chain]\nshaft_stiffness = "-1 N*m/rad"\n[[chain.gears]]\nteeth = 30\n'
     '[[chain.gears]]\nteeth = 40\n', "chain.shaft_stiffness"),
    ('[chain]\nshaft_stiffness = "inf N*m/rad"\n[[chain.gears]]\nteeth = 30\n'
     '[[chain.gears]]\nteeth = 40\n', "chain.shaft_stiffness"),
    ('[chain]\nshaft_stiffness = "nan N*m/rad"\n[[chain.gears]]\nteeth = 30\n'
     '[[chain.gears]]\nteeth = 40\n', "chain.shaft_stiffness"),
    ('[chain]\n[chain.common]\nnormal_module = "2 mm"\n[[chain.gears]]\nteeth = 3\n'
     '[[chain.gears]]\nteeth = 40\n', "chain.gears[0].teeth"),
])
def test_bad_chain_config_names_the_chain(extra, parameter) -> None:
    with pytest.raises(InputError) as err:
        loads(_stage_config() + extra)
    assert err.value.parameter == parameter


def test_a_stage_with_a_chain_is_a_study_like_any_gearbox(tmp_path) -> None:
    """One model: a stage driving gears is studied through the same case list (it was
    refused before the gearbox types were merged); its default record is the ring sensor
    and a fault class, which needs an external gear mesh, is refused up front."""
    from gearsim.studies.sweep import expand, loads_study
    from gearsim.studies.sweep_case import build_case

    (tmp_path / "sc.toml").write_text(_stage_config() + CHAIN)
    head = '[study]\nconfig = "sc.toml"\n'
    st = loads_study(head + '[parameters]\ntorque = ["50 N*m", "100 N*m"]\n',
                     base_dir=tmp_path)
    assert st.signal == "sensor"
    gb = build_case(st, expand(st)[0])
    assert gb.stage.operating.torque == 50.0 and gb.train is not None
    # the chain follows the stage's output: its torque scales with the input's
    ratio = gb.train.operating.torque / build_case(st, expand(st)[1]).train.operating.torque
    assert ratio == pytest.approx(0.5, rel=1e-12)
    with pytest.raises(InputError) as err:
        loads_study(head + '[parameters]\nfault = ["none", "spall"]\n', base_dir=tmp_path)
    assert err.value.parameter == "parameters.fault[1]"
