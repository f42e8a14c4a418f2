"""Two planetary stages in series (issue 23: helicopter and other transmissions).

Stage 1: 24/24/72, three planets, ring held, sun in at 3000 rpm and 200 N m, carrier out;
its carrier drives, through a shaft of 3e6 N m/rad, the sun of stage 2: 20/40/100, four
planets, ring held, carrier out. Expected numbers are built here from the tooth counts
and the gears' radii (loss-free kinematics and statics, Willis), not read from the model.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from two_stage_boxes import TOML, TOML_CHAINS, refused_in_one_line

from gearsim.cli import run as cli_run
from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.dynamics.modal import modes
from gearsim.dynamics.stage import build_stage_model, model_radii
from gearsim.model import loads

#: Static balance of the assembled model (a least-squares solve of the mean system).
STATIC_RTOL = 1e-9
#: Natural frequencies against the hand-assembled matrix (two eigen-solvers of the same
#: matrices agree to round-off times the condition number).
MODES_RTOL = 1e-9
#: Kinematics: products and quotients of tooth counts, a few roundings.
KIN_RTOL = 1e-12
#: Mean of a simulated record against its static value (the parametric excitation
#: averages out over the record to this).
MEAN_RTOL = 1e-4


W_IN, T_IN = 3000 * 2 * math.pi / 60, 200.0
RATIO_1, RATIO_2 = 1 + 72 / 24, 1 + 100 / 20  # ring held, sun in, carrier out: 4 and 6
K_SHAFT = 3e6
#: by hand: stage 1's carrier torque drives stage 2's sun
T_S1, T_C1 = T_IN, T_IN * RATIO_1  # 200, 800 N m
T_S2, T_C2 = T_C1, T_C1 * RATIO_2  # 800, 4800 N m


@pytest.fixture(scope="module")
def box():
    return loads(TOML)


def _model(box, model="lta"):
    dyn = dataclasses.replace(box.dynamics, model=model)
    return build_stage_chain_model(box.stage, box.train, box.members, dyn,
                                   shaft_stiffness=box.shaft_stiffness,
                                   input_chain=box.input_train,
                                   input_shaft_stiffness=box.input_shaft_stiffness,
                                   stages=box.next_stages)


def test_kinematics_by_hand(box):
    s1, s2 = box.stages
    assert box.next_stages[0].shaft_stiffness == K_SHAFT
    w_c1 = W_IN / RATIO_1
    w_c2 = w_c1 / RATIO_2  # 125 rpm
    assert s1.speeds["carrier"] == pytest.approx(w_c1, rel=KIN_RTOL)
    assert s2.operating.speed == pytest.approx(w_c1, rel=KIN_RTOL)
    assert s2.operating.torque == pytest.approx(T_C1, rel=KIN_RTOL)
    # the overall ratio is the product of the stages' ratios, 4 x 6 = 24
    assert s2.speeds["carrier"] == pytest.approx(w_c2, rel=KIN_RTOL)
    assert W_IN / s2.speeds["carrier"] == pytest.approx(RATIO_1 * RATIO_2, rel=KIN_RTOL)
    assert W_IN / s2.speeds["carrier"] == pytest.approx(24.0, rel=KIN_RTOL)
    # f_m = z_s |omega_s - omega_c| / 2 pi: 24 (50 - 12.5) = 900 Hz, 20 (12.5 - 12.5/6)
    f_s1, f_c1 = 3000 / 60, 3000 / 60 / 4
    assert s1.mesh_frequency == pytest.approx(24 * (f_s1 - f_c1), rel=KIN_RTOL)
    assert s1.mesh_frequency == pytest.approx(900.0, rel=KIN_RTOL)
    assert s2.mesh_frequency == pytest.approx(20 * (f_c1 - f_c1 / 6), rel=KIN_RTOL)
    assert s2.mesh_frequency == pytest.approx(625 / 3, rel=KIN_RTOL)
    # the physical torques of each stage (Willis torque balance)
    assert s1.torques == pytest.approx({"sun": T_S1, "ring": 3 * T_S1, "carrier": -T_C1},
                                       rel=KIN_RTOL)
    assert s2.torques == pytest.approx({"sun": T_S2, "ring": 5 * T_S2, "carrier": -T_C2},
                                       rel=KIN_RTOL)


def test_at_moves_every_stage(box):
    moved = box.at(speed=2 * W_IN, torque=3 * T_IN)
    s1, s2 = moved.stages
    assert s2.operating.speed == pytest.approx(2 * W_IN / RATIO_1, rel=KIN_RTOL)
    assert s2.operating.torque == pytest.approx(3 * T_IN * RATIO_1, rel=KIN_RTOL)
    assert moved.next_stages[0].shaft_stiffness == K_SHAFT


@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_static_torque_balance(box, model):
    m = _model(box, model)
    f = m.mean_stiffness() * (m.V @ m.q_static)
    first, second = m.info["stages"]
    assert f[second["shaft_row"]] == pytest.approx(T_C1, rel=STATIC_RTOL)
    for entry, t_s, st in ((first, T_S1, box.stages[0]), (second, T_S2, box.stages[1])):
        n, r_bs = st.stage.planets, st.stage.sun.base_radius
        assert len(entry["rows"]) == 2 * n
        for r in entry["rows"]:  # sun-planet and ring-planet meshes: T_s / (N r_b,s)
            assert f[r] == pytest.approx(t_s / (n * r_bs), rel=STATIC_RTOL)
    # the nominal motion deflects no spring (the shaft included)
    w = m.info["nominal_velocity"]
    assert np.abs(m.V @ w).max() <= 1e-12 * np.abs(w).max()


def test_mesh_names_are_unique_and_name_the_stage(box):
    m = _model(box)
    names = [m.info["row_names"][r] for r in m.info["mesh_rows"]]
    assert len(set(names)) == len(names) == 2 * 3 + 2 * 4
    assert names[:2] == ["stage1-sun-planet-1", "stage1-ring-planet-1"]
    assert names[6:8] == ["stage2-sun-planet-1", "stage2-ring-planet-1"]
    assert len(set(m.dof_labels)) == len(m.dof_labels)


def test_torsional_model_equals_a_hand_assembled_matrix(box):
    """Kahraman's torsional model of each stage (u = r theta of carrier, ring, sun and
    each planet; the carrier carries the planets' mass), joined by the shaft k_t
    (u_c1 / r_c1 - u_s2 / r_s2), r_c the planet-centre radius, r_s the sun base radius."""
    m = _model(box, "torsional")
    lps = [build_stage_model(st, box.members, box.dynamics).info["lin_parker"]
           for st in box.stages]
    sizes = [3 + lp.planets for lp in lps]
    n_all = sum(sizes)
    M = np.zeros(n_all)
    K = np.zeros((n_all, n_all))
    off = 0
    for lp in lps:
        n = lp.planets
        M[off:off + 3 + n] = ([lp.carrier_inertia + n * lp.planet_mass, lp.ring_inertia,
                               lp.sun_inertia] + [lp.planet_inertia] * n)
        K[off:off + 3, off:off + 3] += np.diag([lp.carrier_torsional, lp.ring_torsional,
                                                lp.sun_torsional])
        for j in range(n):
            for k, alpha, (member, sign) in ((lp.sun_mesh, lp.sun_pressure_angle, (2, 1.0)),
                                             (lp.ring_mesh, lp.ring_pressure_angle, (1, -1.0))):
                b = np.zeros(n_all)
                b[off], b[off + member], b[off + 3 + j] = -math.cos(alpha), 1.0, sign
                K += k * np.outer(b, b)
        off += 3 + n
    b = np.zeros(n_all)
    b[0] = 1.0 / model_radii(box.stages[0].stage)["carrier"]
    b[sizes[0] + 2] = -1.0 / model_radii(box.stages[1].stage)["sun"]
    K += K_SHAFT * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, np.diag(M), eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    got = modes(m).frequencies
    np.testing.assert_allclose(got[got > 1e-6 * got.max()], expected, rtol=MODES_RTOL)


def test_one_stages_table_is_the_stage_section(box):
    """``[[stages]]`` with one entry is ``[stage]``: the same model, array for array."""
    one = TOML[:TOML.index("[[stages]]", TOML.index("[[stages]]") + 1)] + TOML[
        TOML.index("[operating]"):]
    a = loads(one)
    b = loads(one.replace("[[stages]]", "[stage]"))
    assert not a.next_stages and a.stages == (a.stage,)
    for model in ("lta", "torsional"):
        dyn = dataclasses.replace(a.dynamics, model=model)
        ma, mb = (build_stage_model(g.stage, g.members, dyn) for g in (a, b))
        for f in ("mass", "kb", "cb", "fext", "V", "cm", "phase", "q_static",
                  "static_force"):
            assert np.array_equal(getattr(ma, f), getattr(mb, f)), f
        assert all(np.array_equal(x.k, y.k) for x, y in zip(ma.tables, mb.tables,
                                                             strict=True))


def test_simulate_prints_every_stage(box, tmp_path, capsys):
    path = tmp_path / "two.toml"
    path.write_text(TOML)
    code = cli_run(["simulate", str(path), "--out", str(tmp_path / "two.nc")])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "mesh stage2-sun-planet-4: mean" in out
    assert "stage1: f_m 900 Hz, sun torque 200 N m, carrier torque -800 N m" in out
    assert ("stage2: f_m 208.333 Hz, sun torque 800 N m, carrier torque -4800 N m; shaft "
            "shaft-stage1-carrier-stage2-sun: torque mean") in out
    assert "\nnatural frequencies of the whole mean-stiffness lta model [Hz]: " in out


def test_result_records_and_summary(box):
    ds = box.simulate(duration=0.1)
    assert ds.sizes["mesh"] == 14 and len(set(ds["mesh"].values)) == 14
    assert list(ds.attrs["stage_sun_torque"]) == pytest.approx([T_S1, T_S2], rel=KIN_RTOL)
    assert list(ds.attrs["stage_carrier_torque"]) == pytest.approx([-T_C1, -T_C2],
                                                                   rel=KIN_RTOL)
    s = box.summary(ds)
    assert [st["stage"] for st in s["stages"]] == ["stage1", "stage2"]
    assert s["stages"][1]["static_shaft_torque"] == pytest.approx(T_C1, rel=STATIC_RTOL)
    assert s["stages"][1]["shaft_torque_mean"] == pytest.approx(T_C1, rel=MEAN_RTOL)
    r_bs2 = box.stages[1].stage.sun.base_radius
    mesh = {m["mesh"]: m for m in s["meshes"]}
    assert mesh["stage2-sun-planet-1"]["static_force"] == pytest.approx(
        T_S2 / (4 * r_bs2), rel=STATIC_RTOL)
    for spec in box.signals():  # every record a study may ask for is one record
        assert box.select(ds, spec).shape == (ds.sizes["time"],), spec
    assert "stage_shaft_torque[shaft-stage1-carrier-stage2-sun]" in box.signals()
    assert "stage2-carrier" in list(ds["shaft"].values)  # its tacho
    assert box.reference(signal="mesh_force[stage2-sun-planet-1]")[0] == "stage2-carrier"


# --- with gears on both sides: gears, two planetary stages, gears ------------------------



@pytest.mark.parametrize("model", ["lta", "torsional"])
def test_gears_stages_gears_static_torque_at_every_shaft(model):
    gb = loads(TOML_CHAINS)
    t_sun1 = T_IN * 60 / 20  # the input gears: 600 N m on sun 1
    t_c1, t_c2 = t_sun1 * RATIO_1, t_sun1 * RATIO_1 * RATIO_2  # 2400, 14400 N m
    assert gb.stages[0].operating.torque == pytest.approx(t_sun1, rel=KIN_RTOL)
    assert gb.train.operating.torque == pytest.approx(t_c2, rel=KIN_RTOL)
    assert gb.train.operating.speed == pytest.approx(
        1500 * 2 * math.pi / 60 / 3 / RATIO_1 / RATIO_2, rel=KIN_RTOL)
    m = _model(gb, model)
    f = m.mean_stiffness() * (m.V @ m.q_static)
    chains = {e["side"]: e for e in m.info["chains"]}
    assert f[chains["input"]["shaft_row"]] == pytest.approx(t_sun1, rel=STATIC_RTOL)
    assert f[m.info["stages"][1]["shaft_row"]] == pytest.approx(t_c1, rel=STATIC_RTOL)
    assert f[chains["output"]["shaft_row"]] == pytest.approx(t_c2, rel=STATIC_RTOL)
    (row,) = chains["output"]["rows"]
    cg, op = gb.train.gears
    assert f[row] * op.base_radius == pytest.approx(t_c2 * 25 / 50, rel=STATIC_RTOL)
    for entry, t_s, st in zip(m.info["stages"], (t_sun1, t_c1), gb.stages, strict=True):
        for r in entry["rows"]:
            assert f[r] == pytest.approx(
                t_s / (st.stage.planets * st.stage.sun.base_radius), rel=STATIC_RTOL)


# --- bad input: one line naming the parameter, exit 2, before any work -------------------

SECOND = 'fixed = "ring"\ninput = "sun"\nshaft_stiffness = "3e6 N*m/rad"'


@pytest.mark.parametrize(("edit", "parameter"), [
    ((SECOND, SECOND.replace('fixed = "ring"', 'fixed = "moon"')), "stages[1].fixed"),
    ((SECOND, SECOND.replace('input = "sun"', 'input = "planet"')), "stages[1].input"),
    ((SECOND, SECOND.replace('input = "sun"', 'input = "ring"')), "stages[1].input"),
    (('"3e6 N*m/rad"', '"0 N*m/rad"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"-3e6 N*m/rad"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"1e300 N*m/rad"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"3e6 mm"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"1e-300 N*m/rad"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"inf N*m/rad"'), "stages[1].shaft_stiffness"),
    (('"3e6 N*m/rad"', '"nan N*m/rad"'), "stages[1].shaft_stiffness"),
    ((SECOND, SECOND + '\nmembers = {moon_mass = "3 kg"}'), "stages[1].members.moon_mass"),
    ((SECOND, SECOND + '\nmembers = {sun_mass = "-3 kg"}'), "stages[1].members.sun_mass"),
    ((SECOND, SECOND + '\nspeed = "3 rpm"'), "stages[1].speed"),
    (("sun_teeth = 20", "sun_teeth = 21"), "stages[1].ring_teeth"),
    (("[[stages]]\nsun_teeth = 24", '[[stages]]\nshaft_stiffness = "3e6 N*m/rad"\n'
      "sun_teeth = 24"), "stages[0].shaft_stiffness"),
    (("[operating]", "[stage]\nsun_teeth = 30\n[operating]"), "stages"),
])
def test_bad_second_stage_is_one_line(tmp_path, capsys, edit, parameter):
    assert edit[0] in TOML
    refused_in_one_line(TOML.replace(*edit, 1), tmp_path, capsys, parameter)


@pytest.mark.parametrize(("first", "second"), [
    (("ring", "carrier"), ("ring", "carrier")),  # a wind turbine's: both model frames mirrored
    (("ring", "sun"), ("carrier", "sun")),  # the second a star stage: its ring turns back
    (("sun", "carrier"), ("carrier", "ring")),
    (("ring", "carrier"), ("sun", "ring")),
])
def test_any_held_and_driven_members_balance(first, second):
    """Each stage's sun-planet force T_s / (N r_b,s), the shaft the first stage's output
    torque, and no spring deflected by the nominal motion, whichever members are held
    and driven (the senses of rotation of the shaft's ends in each stage's frame)."""
    text = TOML.replace('[operating]\nfixed = "ring"\ninput = "sun"',
                        '[operating]\nfixed = "{}"\ninput = "{}"'.format(*first))
    text = text.replace(SECOND, SECOND.replace('fixed = "ring"\ninput = "sun"',
                                               'fixed = "{}"\ninput = "{}"'.format(*second)))
    gb = loads(text.replace('"3000 rpm"', '"30 rpm"'))
    s1, s2 = gb.stages
    out = next(k for k in ("sun", "ring", "carrier") if k not in first)
    assert (s2.operating.fixed, s2.operating.input) == second
    for model in ("lta", "torsional"):
        m = _model(gb, model)
        f = m.mean_stiffness() * (m.V @ m.q_static)
        e1, e2 = m.info["stages"]
        assert f[e2["shaft_row"]] == pytest.approx(abs(s1.torques[out]), rel=STATIC_RTOL)
        for entry, st in ((e1, s1), (e2, s2)):
            for r in entry["rows"]:
                assert f[r] == pytest.approx(st.sun_torque / (
                    st.stage.planets * st.stage.sun.base_radius), rel=STATIC_RTOL)
        w = m.info["nominal_velocity"]
        assert np.abs(m.V @ w).max() <= 1e-12 * np.abs(w).max()


def test_stiffness_and_layout_print_every_stage(tmp_path, capsys):
    path = tmp_path / "two.toml"
    path.write_text(TOML)
    assert cli_run(["stiffness", str(path)]) == 0
    out = capsys.readouterr().out
    assert "stage2 (two planetary stages in series, stage 2): f_m 208.333 Hz" in out
    assert "mesh stage2-ring-planet-4: k mean" in out
    assert cli_run(["layout", str(path)]) == 0
    out = capsys.readouterr().out
    assert "stage 2 20/40/100 x 4: sun in, ring held; f_m 208.333 Hz" in out


# --- a crack on the second stage ([[stages.cracks]]) --------------------------------------

#: a 2 mm crack at the root of tooth 3 of stage 2's sun (20 teeth)
STAGE2_CRACK = '[[stages.cracks]]\ngear = "sun"\ntooth = 3\ndepth = "2 mm"\n'
#: by hand: stage 2's sun turns at stage 1's carrier speed, f_s2 = 50 / 4 = 12.5 Hz, its
#: carrier at f_c2 = 12.5 / 6 Hz; the cracked sun tooth meets planet 1 once per sun
#: revolution relative to the carrier, 1 / (f_s2 - f_c2) = 0.096 s, and one of the four
#: planets every 0.024 s (a stage-1 reading would give z_s2 / f_m1 = 20 / 900 s)
F_S2, F_C2 = 3000 / 60 / RATIO_1, 3000 / 60 / RATIO_1 / RATIO_2
PERIOD_2 = 1.0 / (F_S2 - F_C2)


@pytest.fixture(scope="module")
def cracked():
    return loads(TOML.replace("[operating]", STAGE2_CRACK + "[operating]"))


def _lag(x: np.ndarray, dt: float, lo: float, hi: float) -> float:
    """Lag [s] in (lo, hi) of the largest (unbiased) autocorrelation of ``x``."""
    x = x - x.mean()
    r = np.correlate(x, x, "full")[x.size - 1:] / (x.size - np.arange(x.size))
    k = np.arange(x.size)
    band = (k * dt > lo) & (k * dt < hi)
    return float(k[band][np.argmax(r[band])] * dt)


def test_stage_two_crack_changes_only_its_sun_tables(box, cracked):
    s1, s2 = cracked.stages
    assert not s1.cracks and [(c.gear, c.tooth, c.depth) for c in s2.cracks] == [
        ("sun", 3, 2e-3)]
    healthy, model = _model(box), _model(cracked)
    e1, e2 = model.info["stages"]
    sun2 = set(e2["rows"][0::2])  # stage 2's sun-planet meshes
    for r in range(model.n_mesh):
        same = np.array_equal(healthy.tables[r].k, model.tables[r].k)
        assert same == (r not in sun2), model.info["row_names"][r]
    # stage 1's arrays are the healthy model's (stage 2's held ring spring and its mesh
    # damping follow its mean sun-mesh stiffness, which the crack lowers)
    dofs, rows = slice(*e1["dofs"]), slice(0, e2["rows"][0])
    for f, part in (("mass", dofs), ("kb", dofs), ("cb", dofs), ("cm", rows),
                    ("phase", rows), ("V", slice(None)), ("rate", slice(None)),
                    ("static_force", slice(None))):
        assert np.array_equal(getattr(healthy, f)[part], getattr(model, f)[part]), f
    # the cracked table spans a sun revolution relative to the carrier: z_s2 mesh cycles,
    # read at stage 2's f_m (rate f_m2 / f_m1): 20 / 208.33 Hz = 0.096 s
    for r in sun2:
        assert model.tables[r].period == 20
        assert model.tables[r].period / (model.rate[r] * model.mesh_frequency) == (
            pytest.approx(PERIOD_2, rel=KIN_RTOL))
    assert cracked.healthy().next_stages[0].train.cracks == ()
    moved = cracked.with_crack("non-working", depth=1e-3).stages[1].cracks
    assert [(c.flank, c.depth) for c in moved] == [("non-working", 1e-3)]


def test_stage_two_crack_period_in_the_simulated_mesh_force(box, cracked):
    """The crack's force change (cracked - healthy run) recurs at stage 2's kinematics."""
    dh, dc = box.simulate(duration=0.3), cracked.simulate(duration=0.3)
    assert dc.attrs["cracks"] == "stage2-sun:3:working:0.002"
    dt = 1.0 / dc.attrs["fs"]
    sun2 = [f"stage2-sun-planet-{j}" for j in range(1, 5)]
    d = (dc["mesh_force"] - dh["mesh_force"]).sel(mesh=sun2).values
    assert _lag(d[:, 0], dt, 0.03, 0.2) == pytest.approx(PERIOD_2, abs=dt)
    assert _lag(d.sum(axis=1), dt, 0.01, 0.05) == pytest.approx(PERIOD_2 / 4, abs=dt)


SPALL = ('[[stages.faults]]\nkind = "spall"\ngear = "{}"\nradius = "41 mm"\n'
         'length = "1 mm"\nwidth = "5 mm"\ndepth = "0.01 mm"\n')


def test_stage_two_fault_is_its_own():
    gb = loads(TOML.replace("[operating]", SPALL.format("planet-2") + "[operating]"))
    s1, s2 = gb.stages
    assert not s1.faults and [f.gear for f in s2.faults] == ["planet-2"]
    assert not any(st.faults for st in gb.healthy().stages)


@pytest.mark.parametrize(("edit", "parameter"), [
    (STAGE2_CRACK.replace('"sun"', '"planet-9"'), "stages[1].cracks[0].gear"),
    (STAGE2_CRACK.replace('"sun"', '"moon"'), "stages[1].cracks[0].gear"),
    (STAGE2_CRACK.replace("tooth = 3", "tooth = 20"), "stages[1].cracks[0].tooth"),
    (STAGE2_CRACK.replace('"2 mm"', '"30 mm"'), "stages[1].cracks[0].depth"),
    (STAGE2_CRACK.replace('"2 mm"', '"-2 mm"'), "stages[1].cracks[0].depth"),
    (STAGE2_CRACK.replace('"2 mm"', '"inf mm"'), "stages[1].cracks[0].depth"),
    (STAGE2_CRACK.replace('"2 mm"', '"nan mm"'), "stages[1].cracks[0].depth"),
    (STAGE2_CRACK.replace('"2 mm"', '"1e300 mm"'), "stages[1].cracks[0].depth"),
    (STAGE2_CRACK + STAGE2_CRACK.replace("tooth = 3", "tooth = 4"), "stages[1].cracks[1].gear"),
    (STAGE2_CRACK + STAGE2_CRACK.replace('"sun"', '"planet-1"'), "stages[1].cracks"),
    (STAGE2_CRACK.replace("depth", "deep"), "stages[1].cracks[0].deep"),
    (SPALL.format("ring"), "stages[1].faults[0].gear"),
    (SPALL.format("planet-5"), "stages[1].faults[0].gear"),
    (STAGE2_CRACK.replace("[[stages.", "[[") .replace('"sun"', '"planet-4"'),
     "cracks[0].gear"),  # the first stage's: three planets
])
def test_bad_stage_damage_is_one_line(tmp_path, capsys, edit, parameter):
    refused_in_one_line(TOML.replace("[operating]", edit + "[operating]"), tmp_path, capsys,
                        parameter)


def test_first_stage_damage_is_top_level(tmp_path, capsys):
    text = TOML.replace("ring_addendum_coefficient = 0.8\n[[stages]]",
                        "ring_addendum_coefficient = 0.8\n" + STAGE2_CRACK + "[[stages]]", 1)
    path = tmp_path / "box.toml"
    path.write_text(text)
    assert cli_run(["simulate", str(path), "--out", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("gearsim: error: stages[0].cracks = ...") and "[[cracks]]" in err


def test_lta_modes_are_the_whole_assembly(box):
    """The LTA result's natural frequencies are those of the assembled model: each stage's
    Lin & Parker mass and mean stiffness matrices (``LinParkerModel.mass_matrix``,
    ``stiffness_matrix``) on the diagonal, and the shaft k_t (u_c1 / r_c1 - u_s2 / r_s2)
    between them; not stage 1's alone."""
    dyns = (box.members, box.next_stages[0].members)
    lps = [build_stage_model(st, d, box.dynamics).info["lin_parker"]
           for st, d in zip(box.stages, dyns, strict=True)]
    M = scipy.linalg.block_diag(*(lp.mass_matrix() for lp in lps))
    K = scipy.linalg.block_diag(*(lp.stiffness_matrix() for lp in lps))
    b = np.zeros(M.shape[0])
    b[lps[0].dof_index("carrier").start + 2] = 1.0 / model_radii(box.stages[0].stage)[
        "carrier"]
    b[lps[0].n_dof + lps[1].dof_index("sun").start + 2] = -1.0 / model_radii(
        box.stages[1].stage)["sun"]
    K += K_SHAFT * np.outer(b, b)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    expected = np.sqrt(w2[w2 > 1e-12 * w2.max()]) / (2 * math.pi)
    ds = box.simulate(duration=0.02)
    got = ds["mode_frequency"].values
    assert got.size == expected.size == 3 * (3 + 3) + 3 * (3 + 4) - 1  # less the rotation
    np.testing.assert_allclose(got, expected, rtol=MODES_RTOL)
    alone = lps[0].modes().frequencies
    assert not np.isin(np.round(alone, 6), np.round(got, 6)).all()  # not stage 1's modes
    assert set(ds["mode_kind"].values) == {"coupled"}
    s = box.summary(ds)
    assert s["modes_of"] == "natural frequencies of the whole mean-stiffness lta model"


@pytest.mark.parametrize(("signal", "k"), [
    ("mesh_force[stage2-sun-planet-1]", 2), ("mesh_force[stage2-ring-planet-4]", 2),
    ("stage_shaft_torque[shaft-stage1-carrier-stage2-sun]", 2),
    ("mesh_force[stage1-ring-planet-2]", 1), ("sensor", 1), ("ring_acceleration[x]", 1),
    (None, 1),
])
def test_analysis_kinematics_of_the_records_stage(box, signal, k):
    """A record of stage k is analysed with stage k's carrier and teeth: by hand, ring
    held, the carrier at f_c1 = 50 / 4 = 12.5 Hz and f_c2 = 12.5 / 6 = 2.0833 Hz, and
    f_m = z_r f_c: 72 x 12.5 = 900 Hz, 100 x 12.5 / 6 = 208.33 Hz."""
    from gearsim.signals.analysis import kinematics

    f_c, teeth, f_m = {1: (3000 / 60 / RATIO_1, [72, 24, 24], 900.0),
                       2: (F_C2, [100, 20, 40], 625 / 3)}[k]
    member, freq, z = box.reference(signal=signal)
    assert (member, z) == (f"stage{k}-carrier", teeth)
    assert freq == pytest.approx(f_c, rel=KIN_RTOL)
    train = box.analysis_train(signal=signal)
    assert train == {"shaft_frequency": pytest.approx(f_c, rel=KIN_RTOL), "teeth": teeth}
    assert kinematics(**train).mesh_frequency == pytest.approx(f_m, rel=KIN_RTOL)


def test_analyze_a_stage_two_record(box):
    """gs.analyze of a record named as stage 2's: its carrier 12.5 / 6 Hz, f_m 208.33 Hz,
    the sun and a planet relative to the carrier at f_s2 - f_c2 = 10.417 Hz and
    (20 / 40) of it = 5.208 Hz, by hand (a noise record: only the kinematics matter)."""
    import gearsim as gs

    fs = 5000.0
    x = np.random.default_rng(1).standard_normal(int(2.0 * fs))
    train = gs.analyze(x, fs, gearbox=box, signal="mesh_force[stage2-sun-planet-1]"
                       ).to_dict()["train"]
    assert train["teeth"] == [100, 20, 40]
    assert train["mesh_frequency_hz"] == pytest.approx(625 / 3, rel=KIN_RTOL)
    assert list(train["shaft_frequencies_hz"].values()) == pytest.approx(
        [F_C2, F_S2 - F_C2, (F_S2 - F_C2) * 20 / 40], rel=KIN_RTOL)


# --- the analysis of a result file: each record with its own part's kinematics ----------

#: By hand for TOML_CHAINS: input 1500 rpm = 25 Hz through 20/60 to stage 1's sun, each
#: stage's carrier at its sun / (1 + z_r / z_s), the output gears on stage 2's carrier.
F_IN = 1500 / 60
F_C1_CH = F_IN * 20 / 60 / RATIO_1
F_C2_CH = F_C1_CH / RATIO_2


@pytest.fixture(scope="module")
def chains_result(tmp_path_factory):
    from gearsim.io.results import write_results

    path = tmp_path_factory.mktemp("chains") / "chains.nc"
    write_results(loads(TOML_CHAINS).simulate(duration=0.05, fs=5000.0), path)
    return path


@pytest.mark.parametrize(("channel", "signal", "speed", "teeth", "planetary"), [
    ("mesh_force[mesh=stage2-sun-planet-1]", "mesh_force[stage2-sun-planet-1]", F_C2_CH,
     [100, 20, 40], 2),
    ("mesh_force[mesh=stage1-ring-planet-3]", "mesh_force[stage1-ring-planet-3]", F_C1_CH,
     [72, 24, 24], 1),
    ("stage_shaft_torque[stage_shaft=shaft-stage1-carrier-stage2-sun]",
     "stage_shaft_torque[shaft-stage1-carrier-stage2-sun]", F_C2_CH, [100, 20, 40], 2),
    ("sensor", "sensor", F_C1_CH, [72, 24, 24], 1),
    ("chain_mesh_force[chain_mesh=I]", "chain_mesh_force[I]", F_IN, [20, 60], None),
    ("chain_mesh_force[chain_mesh=II]", "chain_mesh_force[II]", F_C2_CH, [50, 25], None),
    ("shaft_torque", "shaft_torque", F_C2_CH, [50, 25], None),
    ("input_shaft_torque", "input_shaft_torque", F_IN, [20, 60], None),
])
def test_analyze_a_result_file_per_part(chains_result, channel, signal, speed, teeth,
                                        planetary):
    """``gearsim analyze RESULT.nc`` analyses each record with the speed and teeth of the
    part it belongs to (by hand above), the same as ``gs.analyze(..., signal=)`` takes
    from the gearbox; a stage's record adds that stage's planetary tier (f_c, and
    f_m = z_r f_c: 100 f_c2 for stage 2), a gear chain's record none."""
    from gearsim.studies.batch import analyze_file

    out, problems = analyze_file(str(chains_result), channels=[channel])
    assert problems == []
    rec = out[0]["record"]
    assert rec["speed_hz"] == pytest.approx(speed, rel=KIN_RTOL)
    assert rec["teeth"] == teeth and rec["speed_provenance"] == "file"
    api = loads(TOML_CHAINS).analysis_train(signal=signal)
    assert api == {"shaft_frequency": pytest.approx(rec["speed_hz"], rel=KIN_RTOL),
                   "teeth": rec["teeth"]}
    tier = rec["tiers"].get("planetary")
    if planetary is None:
        assert tier is None
    else:
        f_c, z_r = {1: (F_C1_CH, 72), 2: (F_C2_CH, 100)}[planetary]
        assert tier["frequencies"]["carrier"] == pytest.approx(f_c, rel=KIN_RTOL)
        assert tier["frequencies"]["mesh"] == pytest.approx(z_r * f_c, rel=KIN_RTOL)


def test_cli_analyze_of_a_stage_two_record(chains_result, capsys):
    code = cli_run(["analyze", str(chains_result), "--channel",
                    "mesh_force[mesh=stage2-sun-planet-1]", "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    import json

    rec = json.loads(out)["records"][0]
    assert rec["teeth"] == [100, 20, 40]
    assert rec["tiers"]["planetary"]["frequencies"]["mesh"] == pytest.approx(
        100 * F_C2_CH, rel=KIN_RTOL)


@pytest.mark.parametrize("parts", ["not json", '{"stages": [{"z_sun": 24}], "chains": []}',
                                   '{"stages": [], "chains": []}'])
def test_a_result_with_broken_parts_is_analysed_as_a_plain_record(chains_result, tmp_path,
                                                                  parts):
    """A result whose ``analysis_parts`` is not JSON, misses keys or names no stage is read
    as a result written before that attribute: the first stage's attributes for every
    record (stage 1's carrier and f_m = 72 f_c1, by hand), never a traceback."""
    import xarray as xr

    from gearsim.io.results import write_results
    from gearsim.studies.batch import analyze_file

    with xr.open_dataset(chains_result, engine="h5netcdf") as ds:
        ds = ds.load()
    ds.attrs["analysis_parts"] = parts
    path = write_results(ds, tmp_path / "broken.nc")
    out, problems = analyze_file(str(path), channels=["mesh_force[mesh=stage2-sun-planet-1]"])
    assert problems == []
    tier = out[0]["record"]["tiers"]["planetary"]
    assert tier["frequencies"]["mesh"] == pytest.approx(72 * F_C1_CH, rel=KIN_RTOL)
