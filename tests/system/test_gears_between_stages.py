"""Gears between two planetary stages: stage 1's output member drives a gear pair whose
shaft drives stage 2's input member (``NextStage.input_train``; in a graph, the gears on
the shafts of the two members).

The box: stage 1 24/24/72 x 3, ring held, carrier in at 300 rpm and 800 N m, sun out on
``sun-shaft`` (2e6 N m/rad to the gear); a 23-tooth gear there drives 57 teeth on
``mid`` (3e6 N m/rad to the member), which carries the sun of stage 2, 20/40/100 x 4,
ring held, carrier out. Every expected number is built here from the tooth counts and
the gears' base radii (loss-free Willis kinematics and statics), not read from the model.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
from two_stage_boxes import TOML_CHAINS_GRAPH, refused_in_one_line

from gearsim.cli import run as cli_run
from gearsim.dynamics.compose import (
    NextStage,
    build_stage_chain_model,
    chain_of_record,
    chain_operating,
    stage_operating,
)
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.errors import InputError
from gearsim.geometry.gear import Gear, Material
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.model import Gearbox, loads
from gearsim.stiffness.settings import StiffnessSettings, model_options
from gearsim.system import GearTrain
from gearsim.system.graph import MeshSpec, Shaft
from gearsim.system.planetary import PlanetaryTrain, StageOperating

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

#: Kinematics: products and quotients of tooth counts, a few roundings.
KIN_RTOL = 1e-12
#: Static balance of the assembled model (a least-squares solve of the mean system).
STATIC_RTOL = 1e-9
#: Mean of a simulated record against its static value (0.5 s at 5 kHz: the parametric
#: excitation averages out to this; the sampled mean converges as fs^-2).
MEAN_RTOL = 1e-4
#: A mesh line in a spectrum: its peak (within one bin) over the median of the spectrum
#: 3 to 40 Hz around it.
LINE = 20.0

BOX = """name = "gears between two planetary stages"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "rotor"
[[shafts]]
name = "sun-shaft"
torsional_stiffness = "2e6 N*m/rad"
[[shafts]]
name = "mid"
torsional_stiffness = "3e6 N*m/rad"
[[shafts]]
name = "out"
[[stages]]
carrier = "rotor"
sun = "sun-shaft"
ring = "housing"
sun_teeth = 24
planet_teeth = 24
ring_teeth = 72
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
[[gears]]
name = "g23"
shaft = "sun-shaft"
teeth = 23
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[gears]]
name = "g57"
shaft = "mid"
teeth = 57
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[meshes]]
gears = ["g23", "g57"]
[[stages]]
sun = "mid"
carrier = "out"
ring = "housing"
sun_teeth = 20
planet_teeth = 40
ring_teeth = 100
planets = 4
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
face_width = "40 mm"
ring_addendum_coefficient = 0.8
[operating]
speed = "300 rpm"
torque = "800 N*m"
[dynamics]
duration = 0.2
fs = 20000
"""

#: The same box in the stage form: [[stages]] with the gears driving stage 2 as its
#: [stages.input_chain] (its shaft_stiffness the shaft to stage 2's sun; the stage's
#: shaft_stiffness the one from stage 1's sun to the gears).
STAGE_FORM = """name = "gears between two planetary stages"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[stages]]
sun_teeth = 24
planet_teeth = 24
ring_teeth = 72
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
[[stages]]
fixed = "ring"
input = "sun"
shaft_stiffness = "2e6 N*m/rad"
sun_teeth = 20
planet_teeth = 40
ring_teeth = 100
planets = 4
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
face_width = "40 mm"
ring_addendum_coefficient = 0.8
[stages.input_chain]
name = "gears before stage 2"
shaft_stiffness = "3e6 N*m/rad"
[stages.input_chain.common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[stages.input_chain.shafts]]
name = "sun-shaft"
[[stages.input_chain.shafts]]
name = "mid"
[[stages.input_chain.gears]]
name = "g23"
shaft = "sun-shaft"
teeth = 23
[[stages.input_chain.gears]]
name = "g57"
shaft = "mid"
teeth = 57
[[stages.input_chain.meshes]]
gears = ["g23", "g57"]
[operating]
fixed = "ring"
input = "carrier"
speed = "300 rpm"
torque = "800 N*m"
[dynamics]
duration = 0.2
fs = 20000
"""

# --- by hand ------------------------------------------------------------------------
F_C1, T_C1 = 300 / 60, 800.0  # the input: stage 1's carrier [Hz], [N m]
RATIO_1 = 1 + 72 / 24  # ring held, carrier in, sun out: the sun turns 4 x faster
F_S1, T_S1 = F_C1 * RATIO_1, T_C1 / RATIO_1  # 20 Hz, 200 N m on sun-shaft
F_MID, T_MID = F_S1 * 23 / 57, T_S1 * 57 / 23  # 8.0702 Hz, 495.65 N m on mid
RATIO_2 = 1 + 100 / 20  # ring held, sun in, carrier out
F_C2, T_C2 = F_MID / RATIO_2, T_MID * RATIO_2  # 1.3450 Hz, 2973.9 N m on out
#: mesh frequencies: ring held, z_r f_c (= z_s |f_s - f_c|); the gears z_23 f_sun
F_M1, F_G, F_M2 = 72 * F_C1, 23 * F_S1, 100 * F_C2  # 360, 460, 134.50 Hz
#: stage 2 read without the gears' ratio (its sun on stage 1's): no such line
F_M2_WITHOUT_GEARS = 100 * F_S1 / RATIO_2


@pytest.fixture(scope="module")
def box():
    return loads(BOX)


@pytest.fixture(scope="module")
def run(box):
    return box.simulate(duration=0.5, fs=5000.0)


def test_every_shaft_speed_and_torque_by_hand(box):
    assert F_S1 == pytest.approx(20.0, rel=KIN_RTOL)
    assert F_MID * 57 == pytest.approx(460.0, rel=KIN_RTOL)
    rows = {sh["name"]: sh for sh in box.layout()["shafts"]}
    assert list(rows) == ["rotor", "sun-shaft", "mid", "out"]  # in power-flow order
    for name, f, t, on in (("rotor", F_C1, T_C1, ["stage1-carrier"]),
                           ("sun-shaft", F_S1, T_S1, ["g23", "stage1-sun"]),
                           ("mid", F_MID, T_MID, ["g57", "stage2-sun"]),
                           ("out", F_C2, T_C2, ["stage2-carrier"])):
        assert rows[name]["speed_rpm"] == pytest.approx(60 * f, rel=KIN_RTOL), name
        assert rows[name]["torque_Nm"] == pytest.approx(t, rel=KIN_RTOL), name
        assert sorted(rows[name]["gears"] + rows[name]["members"]) == sorted(on), name
    s1, s2 = box.stages
    (gears,) = box.chains
    assert gears is box.next_stages[0].input_train and box.train is None
    assert gears.operating.speed == pytest.approx(2 * math.pi * F_S1, rel=KIN_RTOL)
    assert gears.operating.torque == pytest.approx(T_S1, rel=KIN_RTOL)
    assert s2.operating.speed == pytest.approx(2 * math.pi * F_MID, rel=KIN_RTOL)
    assert s2.operating.torque == pytest.approx(T_MID, rel=KIN_RTOL)
    assert abs(s2.speeds["carrier"]) == pytest.approx(2 * math.pi * F_C2, rel=KIN_RTOL)
    assert abs(s2.torques["carrier"]) == pytest.approx(T_C2, rel=KIN_RTOL)
    # the overall ratio: 4 x 23/57 / 6 (a speed-up, the gears, a reduction)
    assert F_C2 / F_C1 == pytest.approx(4 * 23 / 57 / 6, rel=KIN_RTOL)
    assert box.slowest_shaft() == ("out", pytest.approx(F_C2, rel=KIN_RTOL))
    moved = box.at(speed=2 * box.operating()[0], torque=3 * T_C1)  # every part follows
    assert moved.next_stages[0].input_train.operating.torque == pytest.approx(
        3 * T_S1, rel=KIN_RTOL)
    assert abs(moved.stages[1].speeds["carrier"]) == pytest.approx(4 * math.pi * F_C2,
                                                                   rel=KIN_RTOL)


def test_every_mesh_frequency_by_hand(box):
    s1, s2 = box.stages
    assert (F_M1, F_G) == (pytest.approx(360.0), pytest.approx(460.0))
    assert s1.mesh_frequency == pytest.approx(F_M1, rel=KIN_RTOL)
    assert s1.mesh_frequency == pytest.approx(24 * (F_S1 - F_C1), rel=KIN_RTOL)
    assert box.chains[0].mesh_frequencies == (pytest.approx(F_G, rel=KIN_RTOL),)
    assert s2.mesh_frequency == pytest.approx(F_M2, rel=KIN_RTOL)
    assert s2.mesh_frequency == pytest.approx(20 * (F_MID - F_C2), rel=KIN_RTOL)
    (mesh,) = box.layout()["meshes"]
    assert (mesh["mesh"], mesh["driver"], mesh["driven"]) == ("I", "g23", "g57")
    assert mesh["mesh_frequency_hz"] == pytest.approx(F_G, rel=KIN_RTOL)


def _model(gb, model):
    dyn = dataclasses.replace(gb.dynamics, model=model)
    return build_stage_chain_model(gb.stage, gb.train, gb.members, dyn,
                                   shaft_stiffness=gb.shaft_stiffness,
                                   input_chain=gb.input_train,
                                   input_shaft_stiffness=gb.input_shaft_stiffness,
                                   stages=gb.next_stages)


@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_static_torque_balance_at_every_shaft(box, model):
    """k_mean V q_static of the assembled model: each stage mesh T_s / (N r_b,s) of its
    own sun torque, the gear mesh T / r_b on either gear, the shaft from stage 1's sun
    T_s1 and the one to stage 2's sun T_mid; the nominal motion deflects no spring."""
    m = _model(box, model)
    f = m.mean_stiffness() * (m.V @ m.q_static)
    first, second = m.info["stages"]
    (gears,) = m.info["chains"]
    assert gears["side"] == "between"
    assert f[gears["shaft_row"]] == pytest.approx(T_S1, rel=STATIC_RTOL)
    assert f[second["shaft_row"]] == pytest.approx(T_MID, rel=STATIC_RTOL)
    g23, g57 = box.chains[0].gears
    (row,) = gears["rows"]
    assert f[row] == pytest.approx(T_S1 / g23.base_radius, rel=STATIC_RTOL)
    assert f[row] == pytest.approx(T_MID / g57.base_radius, rel=STATIC_RTOL)
    for entry, t_s, st in ((first, T_S1, box.stages[0]), (second, T_MID, box.stages[1])):
        n, r_bs = st.stage.planets, st.stage.sun.base_radius
        assert len(entry["rows"]) == 2 * n
        for r in entry["rows"]:
            assert f[r] == pytest.approx(t_s / (n * r_bs), rel=STATIC_RTOL)
    assert (gears["shaft_stiffness"], second["shaft_stiffness"]) == (2e6, 3e6)
    w = m.info["nominal_velocity"]
    assert np.abs(m.V @ w).max() <= 1e-12 * np.abs(w).max()
    # the stage rows read their tables at their own mesh frequency
    assert m.rate[second["rows"][0]] * m.mesh_frequency == pytest.approx(F_M2, rel=KIN_RTOL)
    assert m.rate[row] * m.mesh_frequency == pytest.approx(F_G, rel=KIN_RTOL)


def test_simulated_means_are_the_static_forces(box, run):
    s = box.summary(run)
    g23, g57 = box.chains[0].gears
    for m in s["meshes"]:
        st = box.stages[0 if m["mesh"].startswith("stage1-") else 1]
        t_s = T_S1 if st is box.stages[0] else T_MID
        hand = t_s / (st.stage.planets * st.stage.sun.base_radius)
        assert m["static_force"] == pytest.approx(hand, rel=STATIC_RTOL), m["mesh"]
        assert m["mean"] == pytest.approx(hand, rel=MEAN_RTOL), m["mesh"]
    (gm,) = s["chain_meshes"]
    assert gm["static_force"] == pytest.approx(T_S1 / g23.base_radius, rel=STATIC_RTOL)
    assert gm["mean"] == pytest.approx(T_S1 / g23.base_radius, rel=MEAN_RTOL)
    st2 = s["stages"][1]
    assert st2["shaft"] == "shaft-g57-stage2-sun"
    assert st2["static_shaft_torque"] == pytest.approx(T_MID, rel=STATIC_RTOL)
    assert st2["shaft_torque_mean"] == pytest.approx(T_MID, rel=MEAN_RTOL)
    tq = run["stage_shaft_torque"]
    assert float(tq.sel(stage_shaft="shaft-stage1-sun-g23").mean()) == pytest.approx(
        T_S1, rel=MEAN_RTOL)
    assert "shaft_torque" not in run and "chain_side" not in run.attrs  # no gears at an end


def _line(x: np.ndarray, fs: float, f0: float) -> float:
    """Peak of the Hann spectrum of ``x`` within one bin of ``f0`` over the median of
    the spectrum 3 to 40 Hz around it."""
    X = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    f = np.fft.rfftfreq(x.size, 1.0 / fs)
    near = np.abs(f - f0) <= 1.01 * (f[1] - f[0])
    band = (np.abs(f - f0) <= 40.0) & (np.abs(f - f0) > 3.0)
    return float(X[near].max() / np.median(X[band]))


def test_every_mesh_line_is_in_the_simulated_spectra(run):
    """Each mesh's own line in its force, and all three in the torque of the shaft that
    drives stage 2 (measured 66x, 289x, 161x); none where stage 2 would mesh without the
    gears' ratio (333.3 Hz)."""
    fs = run.attrs["fs"]
    own = {F_M1: run["mesh_force"].sel(mesh="stage1-sun-planet-1").values,
           F_G: run["chain_mesh_force"].sel(chain_mesh="I").values,
           F_M2: run["mesh_force"].sel(mesh="stage2-ring-planet-1").values}
    for f0, x in own.items():
        assert _line(x, fs, f0) > LINE, f0
    shaft = run["stage_shaft_torque"].sel(stage_shaft="shaft-g57-stage2-sun").values
    for f0 in (F_M1, F_G, F_M2):
        assert _line(shaft, fs, f0) > LINE, f0
    assert _line(own[F_M2], fs, F_M2_WITHOUT_GEARS) < 5.0
    assert run.attrs["stage_mesh_frequency"] == pytest.approx([F_M1, F_M2], rel=KIN_RTOL)
    assert run.attrs["chain_mesh_frequencies"] == pytest.approx([F_G], rel=KIN_RTOL)


def _python_box() -> Gearbox:
    """BOX written in Python, part by part, each at the operating point of the part
    driving it."""
    mat = Material(youngs_modulus=206e9, poisson_ratio=0.3, density=7850.0)
    stiffness = StiffnessSettings(**model_options({}, "stiffness"))  # the default model
    s1 = PlanetaryTrain(PlanetaryStage(24, 24, 72, 3e-3, planets=3, face_width=0.03,
                                       material=mat, ring_addendum_coefficient=0.8),
                        StageOperating(fixed="ring", input="carrier",
                                       speed=300 * 2 * math.pi / 60, torque=800.0),
                        stiffness, name="gears between two planetary stages")
    gears = GearTrain(
        gears=tuple(Gear(teeth=z, normal_module=3e-3, face_width=0.03, material=mat,
                         name=f"g{z}") for z in (23, 57)),
        operating=chain_operating(s1), stiffness=stiffness, name="gears before stage 2",
        shafts=(Shaft("sun-shaft", ("g23",)), Shaft("mid", ("g57",))),
        meshes=(MeshSpec(("g23", "g57")),))
    s2 = PlanetaryTrain(PlanetaryStage(20, 40, 100, 4e-3, planets=4, face_width=0.04,
                                       material=mat, ring_addendum_coefficient=0.8),
                        stage_operating(gears, "ring", "sun"), stiffness,
                        name="gears between two planetary stages, stage 2")
    return Gearbox(train=None, stage=s1, dynamics=DynamicsSettings(duration=0.2, fs=20000.0),
                   next_stages=(NextStage(train=s2, shaft_stiffness=2e6, input_train=gears,
                                          input_shaft_stiffness=3e6),))


def test_graph_stage_form_and_python_are_one_gearbox(box):
    python, staged = _python_box(), loads(STAGE_FORM)
    assert dataclasses.replace(box, member_shafts=()) == python
    assert staged == python
    assert dict(box.member_shafts) == {"stage1-carrier": "rotor", "stage1-sun": "sun-shaft",
                                       "stage2-sun": "mid", "stage2-carrier": "out"}


def test_written_back_reads_to_itself_and_runs_bit_identical(box):
    """to_toml of the Python box (no shaft names of its own: the gears' shafts carry the
    members) reads back to it, writes the same text, and runs to the same arrays."""
    gb = _python_box().replace(dynamics={"duration": 0.02, "fs": 5000.0})
    text = gb.to_toml()
    back = loads(text)
    assert dataclasses.replace(back, member_shafts=()) == gb
    assert back.to_toml() == text and loads(box.to_toml()) == box
    a, b = gb.simulate(), back.simulate()
    assert list(a.data_vars) == list(b.data_vars)
    for v in a.data_vars:
        if v != "tacho":
            assert np.array_equal(a[v].values, b[v].values), v
    for shaft in b["shaft"].values:  # one tacho a shaft, the first member's on it
        assert np.array_equal(b["tacho"].sel(shaft=shaft), a["tacho"].sel(
            shaft={"rotor": "stage1-carrier", "out": "stage2-carrier"}.get(shaft, shaft)))
    assert a.attrs["config"] == b.attrs["config"] == text


def test_a_crack_on_a_gear_between_the_stages(box):
    cracked = loads(BOX.replace("[operating]", '[[cracks]]\ngear = "g57"\ntooth = 3\n'
                                'flank = "working"\ndepth = "1 mm"\n[operating]'))
    ((c,),) = [t.cracks for t in cracked.chains]
    assert (c.gear, c.tooth, c.depth) == ("g57", 3, 1e-3)
    assert not cracked.stages[0].cracks and not cracked.stages[1].cracks
    assert cracked.with_crack("non-working").chains[0].cracks[0].flank == "non-working"
    assert cracked.healthy() == box
    assert loads(cracked.to_toml()) == cracked


def test_records_and_their_kinematics(box, run):
    """Every record of Gearbox.signals is one record; the gears' records are analysed at
    their first shaft (20 Hz, 23/57), the shaft driving stage 2 and stage 2's meshes on
    stage 2's carrier, the shaft leaving stage 1 (driving the gears) at the gears', by
    hand."""
    for spec in box.signals():
        assert box.select(run, spec).shape == (run.sizes["time"],), spec
    assert [s for s in box.signals() if s.startswith("stage_shaft")] == [
        "stage_shaft_torque[shaft-stage1-sun-g23]", "stage_shaft_torque[shaft-g57-stage2-sun]"]
    assert list(run["chain_shaft"].values) == ["sun-shaft", "mid"]
    assert sorted(run["shaft"].values) == ["mid", "out", "rotor", "sun-shaft"]
    for signal, shaft, f, teeth in (
            ("chain_mesh_force[I]", "sun-shaft", F_S1, [23, 57]),
            ("chain_acceleration[mid,y]", "sun-shaft", F_S1, [23, 57]),
            ("mesh_force[stage2-sun-planet-1]", "out", F_C2, [100, 20, 40]),
            ("stage_shaft_torque[shaft-g57-stage2-sun]", "out", F_C2, [100, 20, 40]),
            # the shaft leaving stage 1 drives the gears: their kinematics, its own speed
            ("stage_shaft_torque[shaft-stage1-sun-g23]", "sun-shaft", F_S1, [23, 57]),
            ("sensor", "rotor", F_C1, [72, 24, 24])):
        member, freq, z = box.reference(signal=signal)
        assert (member, z) == (shaft, teeth), signal
        assert freq == pytest.approx(f, rel=KIN_RTOL), signal


@pytest.mark.parametrize(("channel", "speed", "teeth", "planetary"), [
    ("chain_mesh_force[chain_mesh=I]", F_S1, [23, 57], None),
    ("mesh_force[mesh=stage2-sun-planet-1]", F_C2, [100, 20, 40], F_M2),
    ("mesh_force[mesh=stage1-ring-planet-2]", F_C1, [72, 24, 24], F_M1),
    ("stage_shaft_torque[stage_shaft=shaft-g57-stage2-sun]", F_C2, [100, 20, 40], F_M2),
    ("stage_shaft_torque[stage_shaft=shaft-stage1-sun-g23]", F_S1, [23, 57], None),
    # a chain shaft's coordinate is the chain's (it took stage 1's carrier and teeth:
    # probe round 9), a stage member's its stage's
    ("q[dof=mid.y]", F_S1, [23, 57], None),
    ("q[dof=stage2-sun.x]", F_C2, [100, 20, 40], F_M2),
])
def test_analyze_a_result_file_per_part(run, tmp_path, channel, speed, teeth, planetary):
    from gearsim.io.results import write_results
    from gearsim.studies.batch import analyze_file

    path = write_results(run, tmp_path / "between.nc")
    out, problems = analyze_file(str(path), channels=[channel])
    assert problems == []
    rec = out[0]["record"]
    assert rec["speed_hz"] == pytest.approx(speed, rel=KIN_RTOL)
    assert rec["teeth"] == teeth
    tier = rec["tiers"].get("planetary")
    assert (tier is None) == (planetary is None)
    if tier is not None:
        assert tier["frequencies"]["mesh"] == pytest.approx(planetary, rel=KIN_RTOL)


def test_layout_and_stiffness_print_the_gears_between(tmp_path, capsys):
    path = tmp_path / "box.toml"
    path.write_text(BOX)
    assert cli_run(["layout", str(path), "--plot", str(tmp_path / "l.png")]) == 0
    out = capsys.readouterr().out
    assert "shaft mid: g57, stage2-sun; 484.211 rpm, 495.652 N m" in out
    assert "mesh I: g23 -> g57; f_m 460 Hz" in out
    assert cli_run(["stiffness", str(path)]) == 0
    lines = capsys.readouterr().out.splitlines()
    at = [i for i, s in enumerate(lines) if s.startswith(("stage1 ", "chain mesh I", "stage2 "))]
    assert [lines[i].split()[0] for i in at] == ["stage1", "chain", "stage2"]  # in order


# --- gears, a stage, gears, a stage, gears -------------------------------------------

#: TOML_CHAINS_GRAPH (gears 20/60, stage 1, stage 2, gears 50/25, at 1500 rpm and
#: 200 N m) with a 30/20 pair between the stages: stage 1's carrier (on "between")
#: drives 30 teeth meshing 20 on "mid", which carries stage 2's sun.
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


@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_five_parts_static_torque_at_every_shaft(model):
    """By hand: 200 N m x 60/20 = 600 N m on stage 1's sun, x 4 = 2400 N m on its
    carrier, x 20/30 = 1600 N m on stage 2's sun, x 6 = 9600 N m on its carrier."""
    gb = loads(FIVE)
    assert [t.name for t in gb.chains] == ["input gears", "gears before stage 2",
                                           "output gears"]
    m = _model(gb, model)
    f = m.mean_stiffness() * (m.V @ m.q_static)
    sides = [e["side"] for e in m.info["chains"]]
    assert sides == ["between", "output", "input"]  # in the order joined
    inp, mid, out = (m.info["chains"][sides.index(s)] for s in ("input", "between", "output"))
    for row, t in ((inp["shaft_row"], 600.0), (mid["shaft_row"], 2400.0),
                   (m.info["stages"][1]["shaft_row"], 1600.0), (out["shaft_row"], 9600.0)):
        assert f[row] == pytest.approx(t, rel=STATIC_RTOL)
    (row,) = mid["rows"]
    assert f[row] * gb.chains[1].gears[0].base_radius == pytest.approx(2400.0, rel=STATIC_RTOL)
    (row,) = out["rows"]
    assert f[row] * gb.chains[2].gears[1].base_radius == pytest.approx(9600 * 25 / 50,
                                                                       rel=STATIC_RTOL)
    # the output gears at stage 2's carrier: 1500 rpm / 3 / 4 x 30/20 / 6
    assert gb.train.operating.speed == pytest.approx(
        1500 * 2 * math.pi / 60 / 3 / 4 * 1.5 / 6, rel=KIN_RTOL)


def test_five_parts_records_and_their_chains():
    gb = loads(FIVE)
    sig = gb.signals()
    assert [s for s in sig if s.startswith("chain_mesh")] == [
        "chain_mesh_force[I]", "chain_mesh_force[II]", "chain_mesh_force[III]"]
    assert "shaft_torque" in sig and "input_shaft_torque" in sig
    # shaft_torque is the output gears', input_shaft_torque the input gears': never the
    # gears between, whichever end is missing
    assert gb.reference(signal="shaft_torque")[0] == "out"
    assert gb.reference(signal="input_shaft_torque")[0] == "in"
    # the gears between and the shaft driving them (on stage 1's carrier): the gears' 30/20
    for signal in ("chain_mesh_force[II]", "stage_shaft_torque[shaft-stage1-carrier-mid-gear]"):
        assert gb.reference(signal=signal) == (
            "between", pytest.approx(1500 / 60 / 3 / 4, rel=KIN_RTOL), [30, 20]), signal
    shafts, meshes = [["a"], ["b"], ["c"]], [["I"], ["II"], ["III"]]
    assert chain_of_record("shaft_torque", None, shafts[:2], meshes[:2], [False, True]) == 0
    assert chain_of_record("shaft_torque", None, shafts, meshes, [False, True, False]) == 2
    assert chain_of_record("input_shaft_torque", None, shafts[1:], meshes[1:],
                           [True, False]) == 1
    ds = gb.simulate(duration=0.02, fs=5000.0, model="torsional")
    assert list(ds["chain_mesh"].values) == ["I", "II", "III"]
    assert float(ds.attrs["static_input_shaft_torque"]) == pytest.approx(600.0, rel=STATIC_RTOL)
    assert float(ds.attrs["static_shaft_torque"]) == pytest.approx(9600.0, rel=STATIC_RTOL)
    assert list(ds["stage_shaft"].values) == ["shaft-mid-pinion-stage2-sun",
                                              "shaft-stage1-carrier-mid-gear"]
    assert ds.attrs["static_stage_shaft_torque"] == pytest.approx([1600.0, 2400.0],
                                                                  rel=STATIC_RTOL)


# --- what stays out: one line naming the element -----------------------------------------

@pytest.mark.parametrize(("text", "parameter", "words"), [
    # stage 1's sun shaft drives the gears and stage 2 beside them
    (BOX.replace('sun = "mid"', 'sun = "sun-shaft"'), "shafts[1]", "drives two parts"),
    # g57 on stage 2's shaft also drives a power take-off beside stage 2
    (BOX.replace("[operating]", '[[shafts]]\nname = "pto"\n[[gears]]\nname = "pto-pinion"\n'
                 'shaft = "pto"\nteeth = 20\nnormal_module = "3 mm"\n[[meshes]]\n'
                 'gears = ["g57", "pto-pinion"]\nangle = "90 deg"\n[operating]'),
     "shafts[2]", "branching power beside a planetary stage"),
    # g23 on stage 1's sun shaft drives a second gear beside g57
    (BOX.replace("[operating]", '[[shafts]]\nname = "x"\n[[gears]]\nname = "g40"\n'
                 'shaft = "x"\nteeth = 40\nnormal_module = "3 mm"\n[[meshes]]\n'
                 'gears = ["g23", "g40"]\nangle = "90 deg"\n[operating]'),
     "shafts[1]", "branching power beside a planetary stage"),
    # gears driving stage 1 whose last shaft (stage 1's sun) also drives a power
    # take-off: before, read as a stage driven by the take-off's pinion at its speed
    (TOML_CHAINS_GRAPH.replace("[operating]", '[[shafts]]\nname = "pto"\n[[gears]]\n'
                               'name = "pto-pinion"\nshaft = "pto"\nteeth = 20\n'
                               'normal_module = "3 mm"\n[[meshes]]\n'
                               'gears = ["sun-drive-gear", "pto-pinion"]\n'
                               'angle = "90 deg"\n[operating]'),
     "shafts[1]", "branching power beside a planetary stage"),
    # a key of a shaft named as written (was stages[1].input_chain.shafts.mid.power_share)
    (BOX.replace('name = "mid"\n', 'name = "mid"\npower_share = 0.5\n'),
     "shafts[2].power_share", "the only output takes all the power"),
    (BOX.replace('"3e6 N*m/rad"', '"-3e6 N*m/rad"'), "shafts[2].torsional_stiffness",
     "-3e6"),
    (BOX.replace('name = "g57"', 'name = "g23"'), "gears[1].name", "unique"),
    (STAGE_FORM.replace("[stages.input_chain]\n", "[stages.input_chain]\nspeed = 3\n"),
     "stages[1].input_chain.speed", "unknown key"),
    (STAGE_FORM.replace('"3e6 N*m/rad"', '"0 N*m/rad"'), "stages[1].input_chain."
     "shaft_stiffness", "N*m/rad"),
    (STAGE_FORM.replace('name = "g57"', 'name = "sun"').replace('"g57"]', '"sun"]'),
     "stages[1].input_chain.gears", "unique"),
    (STAGE_FORM.replace("ring_addendum_coefficient = 0.8\n[[stages]]",
                        "ring_addendum_coefficient = 0.8\ninput_chain = {}\n[[stages]]", 1),
     "stages[0].input_chain", "[input_chain]"),
])
def test_what_stays_out_is_one_line(tmp_path, capsys, text, parameter, words):
    line = refused_in_one_line(text, tmp_path, capsys, parameter)
    assert words in line, line


@pytest.mark.parametrize("old,new,name,shaft,torque", [
    ('"2e6 N*m/rad"', "20", "shafts[1].torsional_stiffness", "sun-shaft", "200"),
    ('"3e6 N*m/rad"', "30", "shafts[2].torsional_stiffness", "mid", "495.652"),
])
def test_a_soft_shaft_beside_the_gears_between_is_named_as_written(old, new, name, shaft,
                                                                    torque):
    # stage 1's sun torque 800 / 4 = 200 N m; into stage 2: 200 x 57 / 23 = 495.652 N m
    with pytest.raises(InputError, match=rf"^{re.escape(name)} = {new} N\*m/rad: twists shaft "
                       rf"{shaft} by .* under its static torque of {torque} N\*m"):
        loads(BOX.replace(old, f'"{new} N*m/rad"')).simulate()
