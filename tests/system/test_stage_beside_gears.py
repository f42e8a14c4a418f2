"""A planetary stage beside gears, written as a graph: the keys of the shafts that carry
stage members, the variants of a crack on a gear beside the stage, and the numbering
of the gears' meshes (``contact``, ``stiffness --out``), the shafts and stages of
``layout``.

HELI: a 30/90 spur pair (m 3, 20 deg) on shafts ``engine`` and ``sun-shaft`` drives the
sun of 27/35/97 x 4 (ring held), whose carrier sits alone on ``mast``; 6000 rpm,
500 N m; HELI_BOTH adds a 60/20 pair (m 3) from ``mast`` to ``tail``. Checked against
numbers that do not come from the loader: the stiffness the assembled equations carry on
each coordinate (read by the coordinates' own labels), the box written with the varied
crack, the static mesh forces by hand.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from two_stage_boxes import TOML_CHAINS_GRAPH, refused_in_one_line

import gearsim as gs
from gearsim.cli import run as cli_run
from gearsim.dynamics.compose import build_stage_chain_model
from gearsim.studies.sweep import expand, loads_study
from gearsim.studies.sweep_case import build_case
from gearsim.viz.layout import plot_layout

HELI = """name = "heli"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "engine"
[[shafts]]
name = "sun-shaft"
torsional_stiffness = "5e5 N*m/rad"
[[shafts]]
name = "mast"
[[gears]]
name = "engine-pinion"
shaft = "engine"
teeth = 30
normal_module = "3 mm"
face_width = "40 mm"
[[gears]]
name = "bull-gear"
shaft = "sun-shaft"
teeth = 90
normal_module = "3 mm"
face_width = "40 mm"
[[meshes]]
gears = ["engine-pinion", "bull-gear"]
[[stages]]
sun = "sun-shaft"
ring = "housing"
carrier = "mast"
sun_teeth = 27
planet_teeth = 35
ring_teeth = 97
planets = 4
normal_module = "4 mm"
face_width = "50 mm"
ring_addendum_coefficient = 0.8
[operating]
speed = "6000 rpm"
torque = "500 N*m"
[stiffness]
positions_per_cycle = 10
slices = 3
[dynamics]
duration = 0.02
fs = 25000
"""
#: HELI with a 1.5 mm crack at tooth 0 of the engine pinion (working flank).
CRACKED_PINION = HELI + """[[cracks]]
gear = "engine-pinion"
tooth = 0
depth = "1.5 mm"
"""
#: ... and a 2 mm crack on planet 2's tooth 0.
BOTH_CRACKED = CRACKED_PINION.replace("[operating]", """[[stages.cracks]]
gear = "planet-2"
tooth = 0
depth = "2 mm"
[operating]""")
#: HELI with a 60/20 pair driven by the carrier's shaft.
HELI_BOTH = HELI.replace("[[stages]]", """[[shafts]]
name = "tail"
[[gears]]
name = "mast-gear"
shaft = "mast"
teeth = 60
normal_module = "3 mm"
face_width = "40 mm"
[[gears]]
name = "tail-pinion"
shaft = "tail"
teeth = 20
normal_module = "3 mm"
face_width = "40 mm"
[[meshes]]
gears = ["mast-gear", "tail-pinion"]
[[stages]]""")


def _on(shaft: str, keys: str, text: str = HELI) -> str:
    """``text`` with ``keys`` (TOML lines) added to shaft ``shaft``."""
    at = f'name = "{shaft}"\n'
    assert at in text
    return text.replace(at, at + keys + "\n", 1)


def _kb(gb: gs.Gearbox) -> dict[str, float]:
    m = build_stage_chain_model(gb.stage, gb.train, gb.members, gb.dynamics,
                                shaft_stiffness=gb.shaft_stiffness,
                                input_chain=gb.input_train,
                                input_shaft_stiffness=gb.input_shaft_stiffness,
                                stages=gb.next_stages)
    return dict(zip(m.dof_labels, m.kb, strict=True))


@pytest.mark.parametrize(("shaft", "keys", "parameter", "says"), [
    ("mast", "foo = 1", "shafts[2].foo", "unknown key"),
    ("mast", 'mass = "-5 kg"', "shafts[2].mass", "must be in [0"),
    ("mast", 'mass = "5 kg"', "shafts[2].mass", "[stages.members] keys (carrier_mass"),
    ("mast", 'inertia = "nan kg*m^2"', "shafts[2].inertia", "finite"),
    ("mast", 'axial_stiffness = "1e8 N/m"', "shafts[2].axial_stiffness", "no axial bearing"),
    ("mast", 'torsional_stiffness = "5e5 N*m/rad"', "shafts[2].torsional_stiffness",
     "nothing for it to twist between"),
    ("mast", 'bearing_stiffness = "1e20 N/m"', "shafts[2].bearing_stiffness",
     "must be in [100000, 1e+15] N/m"),
    ("sun-shaft", 'bearing_stiffness = "-1 N/m"', "shafts[1].bearing_stiffness", "must be"),
])
def test_a_key_of_a_members_shaft_is_checked_as_any_shafts(tmp_path, capsys, shaft, keys,
                                                           parameter, says):
    line = refused_in_one_line(_on(shaft, keys), tmp_path, capsys, parameter)
    assert says in line, line


def test_the_shaft_between_two_stages_takes_no_mass_of_its_own(tmp_path, capsys):
    line = refused_in_one_line(_on("between", 'mass = "500 kg"', TOML_CHAINS_GRAPH),
                               tmp_path, capsys, "shafts[2].mass")
    assert "the carrier of stages[0] and the sun of stages[1]" in line


def test_a_shafts_bearing_stiffness_reaches_every_member_on_it_as_with_bearing():
    default = 1e9  # [dynamics] bearing_stiffness
    kb = _kb(gs.loads(_on("mast", 'bearing_stiffness = "3e8 N/m"')))
    assert [kb["carrier.x"], kb["carrier.y"]] == [3e8, 3e8]
    assert [kb["sun.x"], kb["ring.x"], kb["sun-shaft.x"], kb["engine.y"]] == [default] * 4
    # a member and a gear on one shaft: both (the gear's axial bearing follows the radial)
    gb = gs.loads(_on("sun-shaft", 'bearing_stiffness = "4e8 N/m"'))
    kb = _kb(gb)
    assert [kb["sun.x"], kb["sun.y"]] + [kb[f"sun-shaft.{a}"] for a in "xyz"] == [4e8] * 5
    assert gb == gs.loads(HELI).with_bearing("sun-shaft", 4e8)  # the study's meaning
    # the member's own bearing ([stages.members]) wins over its shaft's
    kb = _kb(gs.loads(_on("sun-shaft", 'bearing_stiffness = "4e8 N/m"').replace(
        "[operating]", '[stages.members]\nsun_bearing = "6e8 N/m"\n[operating]')))
    assert [kb["sun.x"], kb["sun-shaft.x"]] == [6e8, 4e8]
    # two stages' members on one shaft: both
    kb = _kb(gs.loads(_on("between", 'bearing_stiffness = "2e8 N/m"', TOML_CHAINS_GRAPH)))
    assert [kb["stage1-carrier.x"], kb["stage2-sun.y"], kb["stage1-sun.x"]] == [2e8, 2e8,
                                                                              default]


def test_a_crack_on_a_gear_beside_the_stage_is_varied_as_the_config_writes_it():
    gb = gs.loads(CRACKED_PINION)
    # the variant is the box written with that crack (the loader: another route)
    for flank, depth in (("non-working", 0.8e-3), ("working", 2e-3)):
        written = CRACKED_PINION.replace('depth = "1.5 mm"',
                                         f'depth = "{depth * 1e3} mm"\nflank = "{flank}"')
        assert gb.with_crack(flank, depth=depth) == gs.loads(written)
    assert gb.with_crack(None, depth=2e-3).input_train.cracks[0].depth == 2e-3
    assert gb.with_crack("none") == gs.loads(HELI)

    def k(box):  # input pair over one revolution of the 30-tooth pinion, 10 per tooth
        return box.input_train.mesh_stiffness(0).k

    healthy, cracked = k(gs.loads(HELI)), k(gb)
    assert np.array_equal(k(gb.with_crack("working", depth=0.0)), healthy)  # depth 0
    # tooth 0 carries load in at most ceil(eps_alpha = 1.75) + 1 = 3 of the 30 mesh cycles:
    # only they change, and they soften
    changed = {i // 10 for i in np.flatnonzero(cracked != healthy)}
    assert 1 <= len(changed) <= 3 and np.all(cracked <= healthy)


def test_every_crack_moves_with_a_crack_on_both_a_stage_member_and_a_gear():
    gb = gs.loads(BOTH_CRACKED).with_crack("non-working", depth=0.5e-3)
    moved = gb.stage.cracks + gb.input_train.cracks
    assert [(c.gear, c.flank, c.depth) for c in moved] == [
        ("planet-2", "non-working", 0.5e-3), ("engine-pinion", "non-working", 0.5e-3)]
    with pytest.raises(gs.InputError, match="the gearbox has no crack to vary"):
        gs.loads(HELI).with_crack("working")


def test_cli_and_sweep_vary_the_crack_of_a_gear_beside_a_stage(tmp_path, capsys):
    box = tmp_path / "box.toml"
    box.write_text(CRACKED_PINION)
    assert cli_run(["stiffness", str(box), "--crack", "non-working"]) == 0
    assert cli_run(["simulate", str(box), "--crack", "working", "--duration", "0.01",
                    "--out", str(tmp_path / "r.nc")]) == 0
    st = loads_study(f"""[study]
config = "{box}"
[study.dynamics]
duration = "0.6 s"
[parameters]
flank = ["none", "non-working"]
crack_depth = ["1 mm"]
""")
    cases = [build_case(st, c) for c in expand(st)]
    assert [gb.input_train.cracks for gb in cases][0] == ()
    assert [(c.flank, c.depth) for c in cases[1].input_train.cracks] == [("non-working",
                                                                         1e-3)]


def test_contact_counts_the_meshes_as_layout_and_simulate_name_them(tmp_path, capsys):
    cos20 = np.cos(np.radians(20.0))
    t_mast = 500.0 * 3.0 * (1.0 + 97.0 / 27.0)  # 90/30, then the ring-held stage
    # the static force T / r_b of each driver: r_b = z m / 2 cos 20 deg
    forces = {"I": 500.0 / (0.045 * cos20), "II": t_mast / (0.09 * cos20)}
    assert round(forces["I"]) == 11824 and round(forces["II"]) == 81456
    box = tmp_path / "box.toml"
    for text, meshes in ((HELI, ["I"]), (HELI_BOTH, ["I", "II"])):
        box.write_text(text)
        gb = gs.load(str(box))
        assert [m["mesh"] for m in gb.layout()["meshes"]] == meshes
        assert [s[17:-1] for s in gb.signals() if s.startswith("chain_mesh_force")] == meshes
        for i, name in enumerate(meshes):
            assert cli_run(["contact", str(box), "--mesh", str(i), "--json"]) == 0
            got = json.loads(capsys.readouterr().out)
            assert got["mesh"] == name
            assert got["force_N"] == pytest.approx(forces[name], rel=1e-9)
    assert cli_run(["contact", str(box), "--mesh", "1", "--torque", "1000 N*m",
                    "--json"]) == 0  # the gearbox's input torque, doubled
    assert json.loads(capsys.readouterr().out)["force_N"] == pytest.approx(
        2 * forces["II"], rel=1e-9)
    assert cli_run(["contact", str(box), "--mesh", "2"]) == 2
    assert "--mesh = 2: must be in 0 .. 1" in capsys.readouterr().err


def test_the_results_cracks_name_a_gears_crack_beside_the_stage():
    gb = gs.loads(BOTH_CRACKED)
    assert gb.simulate(duration=0.01).attrs["cracks"] == (
        "planet-2:0:working:0.002, engine-pinion:0:working:0.0015")
    assert gb.with_crack("none").simulate(duration=0.01).attrs["cracks"] == "none"


def test_stiffness_writes_every_stages_and_every_gears_mesh(tmp_path):
    """TOML_CHAINS_GRAPH: 20/60 (m 3), 24/24/72 x 3, 20/40/100 x 4, 50/25 (m 5); the
    tables of every mesh, named as the results name them, each the one the part's own
    computation gives (40 positions a cycle by default)."""
    gb = gs.loads(TOML_CHAINS_GRAPH)
    box = tmp_path / "box.toml"
    box.write_text(TOML_CHAINS_GRAPH)
    assert cli_run(["stiffness", str(box), "--out", str(tmp_path / "k.csv"),
                    "--plot", str(tmp_path / "k.png")]) == 0
    rows = [r.split(",") for r in (tmp_path / "k.csv").read_text().splitlines()[2:]]
    meshes = [f"stage{k}-{m}-planet-{j}" for k, n in ((1, 3), (2, 4))
              for j in range(1, n + 1) for m in ("sun", "ring")] + ["I", "II"]
    assert list(dict.fromkeys(r[0] for r in rows)) == meshes
    # the gears: one revolution of each driver, 20 and 50 teeth, 40 positions a tooth
    assert [sum(r[0] == m for r in rows) for m in ("I", "II")] == [20 * 40, 50 * 40]
    assert cli_run(["stiffness", str(box), "--out", str(tmp_path / "k.nc")]) == 0
    with xr.open_dataset(tmp_path / "k.nc") as ds:
        np.testing.assert_allclose(ds["k_II"].values, gb.train.mesh_stiffness(0).k,
                                   rtol=1e-12)
        k_s2 = gb.next_stages[0].train.tables()[0]  # stage 2, sun-planet-1
        np.testing.assert_allclose(ds["k_stage2-sun-planet-1"].values, k_s2.table.k,
                                   rtol=1e-12)
        assert set(ds.data_vars) == {f"k_{m}" for m in meshes}
    titles = [ax.get_title() for ax in gb.tvms().figure().axes]
    assert len(titles) == 2 * 2 + 2 * 2  # two panels a stage, two a mesh of the gears
    assert "mesh II: carrier-gear -> output-pinion" in titles


def test_layout_lists_every_shaft_and_draws_every_stage():
    """TOML_CHAINS_GRAPH at 1500 rpm, 200 N m: 20/60, then 24/24/72 (ring held: carrier
    = sun / (1 + 72/24)), 20/40/100 (/ (1 + 100/20)), then 50/25."""
    speeds = [1500.0, 500.0, 125.0, 125.0 / 6, 125.0 / 6 * 2]  # rpm
    torques = [200.0, 600.0, 600.0 * 4, 600.0 * 4 * 6, 600.0 * 4 * 6 / 2]  # N m
    out = gs.loads(TOML_CHAINS_GRAPH).layout()
    got = [(sh["name"], sh["gears"], sh.get("members", [])) for sh in out["shafts"]]
    assert got == [("in", ["input-pinion"], []), ("sun-shaft", ["sun-drive-gear"],
                                                  ["stage1-sun"]),
                   ("between", [], ["stage1-carrier", "stage2-sun"]),
                   ("out", ["carrier-gear"], ["stage2-carrier"]),
                   ("output", ["output-pinion"], [])]
    np.testing.assert_allclose([sh["speed_rpm"] for sh in out["shafts"]], speeds, rtol=1e-9)
    np.testing.assert_allclose([sh["torque_Nm"] for sh in out["shafts"]], torques, rtol=1e-9)
    d = out["plan"]
    fig = plot_layout(d["shafts"], d["gears"], d["links"], title="x", stage=d["stage"],
                      upstream=d["upstream"])
    titles = [ax.get_title() for ax in fig.axes]
    assert "planetary stage 1" in titles and "planetary stage 2" in titles
    legend = [t.get_text() for t in fig.axes[titles.index("planetary stage 2")]
              .get_legend().get_texts()]
    assert legend[0] == "sun (z 20, on between)"
    # a lone stage's output shaft, and its member torques (1500 x (1 + 97/27) N m)
    heli = gs.loads(HELI).layout()
    mast = heli["shafts"][-1]
    assert (mast["name"], mast["members"]) == ("mast", ["carrier"])
    assert mast["speed_rpm"] == pytest.approx(2000.0 / (1 + 97 / 27), rel=1e-12)
    assert mast["torque_Nm"] == pytest.approx(1500.0 * 124 / 27, rel=1e-12)
    assert heli["stage"]["torques_Nm"]["sun"] == pytest.approx(1500.0, rel=1e-12)
