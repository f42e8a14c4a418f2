"""Built-in planetary examples and the CLI on stages: example, stiffness, simulate,
analyze, sweep; assembly refusals as one line with exit status 2.

Independent numbers: the Lin & Parker (1999) example model as coded from the paper's
parameter list (:meth:`LinParkerModel.lin_parker_example`), against which the example
TOML (inertias given as masses times squared base radii) must give the same natural
frequencies; the GRC stage's kinematics from its published speed (22.1 rpm carrier, ring
held: f_m = 99 x 22.1 / 60 Hz).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from gearsim import cli
from gearsim.dynamics.planetary import LinParkerModel
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.stage import build_stage_model
from gearsim.model.config import example_text, loads

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

#: The example TOML gives the Lin & Parker inertias I/r^2 times the squared base radii to
#: six significant figures: frequencies agree to half that relative error.
ROUNDING = 1e-5


def _run(capsys, *args) -> tuple[int, str, str]:
    code = cli.run([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_lin_parker_example_is_their_model() -> None:
    box = loads(example_text("lin-parker-1999"))
    assert box.train is None and box.stage is not None
    model = build_stage_model(box.stage, box.members, DynamicsSettings(duration=0.01,
                                                                       fs=20000.0))
    ours = model.info["lin_parker"].modes()
    theirs = LinParkerModel.lin_parker_example().modes()
    top = theirs.frequencies.max()
    keep = theirs.frequencies > 1e-6 * top  # the free sun-carrier rotation: 0 Hz
    assert np.sum(ours.frequencies < 1e-6 * top) == np.sum(~keep) == 1
    np.testing.assert_allclose(ours.frequencies[keep], theirs.frequencies[keep], rtol=ROUNDING)
    assert [(g.multiplicity, g.kind) for g in ours.groups] == [
        (g.multiplicity, g.kind) for g in theirs.groups]


def test_examples_print_and_load(capsys) -> None:
    for name in ("lin-parker-1999", "nrel-grc"):
        code, out, _ = _run(capsys, "example", name)
        assert code == 0 and "[stage]" in out
        assert loads(out).stage is not None


def test_grc_stiffness_json(capsys, tmp_path) -> None:
    code, out, err = _run(capsys, "stiffness", "nrel-grc", "--json")
    assert code == 0, err
    s = json.loads(out)
    assert s["mesh_frequency"] == pytest.approx(99 * 22.1 / 60.0, rel=1e-12)
    names = [m["mesh"] for m in s["meshes"]]
    assert names == [f"{k}-planet-{n}" for n in (1, 2, 3) for k in ("sun", "ring")]
    # 21 / 3 and 99 / 3 are integers: the planets mesh in phase
    phases = [m["phase_cycles"] % 1.0 for m in s["meshes"] if m["mesh"].startswith("sun")]
    np.testing.assert_allclose(np.minimum(phases, 1 - np.array(phases)), 0.0, atol=1e-9)


def test_grc_simulate_analyze(capsys, tmp_path) -> None:
    nc = tmp_path / "grc.nc"
    code, out, err = _run(capsys, "simulate", "nrel-grc", "--duration", "0.4", "--out", nc)
    assert code == 0, err
    assert "natural frequencies" in out
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert ds.attrs["kind"] == "planetary" and ds.sizes["time"] == 2000
        assert ds.attrs["cracks"].startswith("planet-1:0:working")
        assert np.all(np.isfinite(ds["sensor"].values))
    code, out, err = _run(capsys, "analyze", nc, "--channel", "sensor", "--shaft-rpm", "22.1",
                          "--teeth", "99")
    assert code == 0, err
    assert "RMS" in out
    # the stage result brings its stage and carrier speed: the planetary tier runs
    assert "planetary [stage file" in out and "f_m 36.465 Hz" in out


def test_lin_parker_simulate_is_static(capsys, tmp_path) -> None:
    nc = tmp_path / "lp.nc"
    code, out, err = _run(capsys, "simulate", "lin-parker-1999", "--duration", "0.05",
                          "--out", nc)
    assert code == 0, err
    assert "no parametric excitation" in out
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        f = ds["mesh_force"].values
        np.testing.assert_allclose(f, ds.attrs["static_mesh_force"], rtol=1e-9)


def test_sweep_on_a_stage_example(capsys, tmp_path) -> None:
    (tmp_path / "grc.toml").write_text(example_text("nrel-grc"))
    (tmp_path / "study.toml").write_text(
        '[study]\nname = "grc crack"\nconfig = "grc.toml"\n'
        '[study.dynamics]\nduration = "11 s"\ntransient = "0.5 s"\n'
        '[parameters]\nflank = ["none", "working"]\n')
    out_nc = tmp_path / "store.nc"
    # --workers 1: the two groups run in this process (the default, 2, started a Dask
    # cluster whose workers each imported gearsim again); sweeps on a cluster are
    # tests/studies/test_sweep.py's
    code, out, err = _run(capsys, "sweep", tmp_path / "study.toml", "--out", out_nc,
                          "--workers", 1, "--no-progress")
    assert code == 0, err
    with xr.open_dataset(out_nc, engine="h5netcdf") as ds:
        assert ds.sizes["case"] == 2


# ------------------------------------------------------------------------ bad input
GOOD = example_text("lin-parker-1999")


def _config(tmp_path, **stage) -> str:
    text = GOOD
    for key, value in stage.items():
        lines = [ln for ln in text.splitlines() if not ln.startswith(f"{key} =")]
        i = lines.index("[stage]")
        lines.insert(i + 1, f"{key} = {value}")
        text = "\n".join(lines) + "\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("stage,words", [
    # coaxiality: z_r = z_s + 2 z_p for unshifted gears (30 + 48 = 78, not 80)
    (dict(ring_teeth=80, sun_shift=0, planet_shift=0, ring_shift=0), ["80", "78"]),
    # (z_s + z_r) / N: (30 + 78) / 5 is not an integer
    (dict(planets=5), ["(30 + 78)/5 = 21.6"]),
    # planets' tip circles overlap: five 30-tooth planets (tip radius 32 mm) on a 50 mm
    # radius are 2 x 50 sin(36 deg) = 58.8 mm apart, less than 64 mm
    (dict(sun_teeth=20, planet_teeth=30, ring_teeth=80, planets=5, sun_shift=0,
          planet_shift=0, ring_shift=0), ["collide", "58.7785 mm", "64 mm"]),
])
def test_assembly_refused_in_one_line(capsys, tmp_path, stage, words) -> None:
    code, out, err = _run(capsys, "stiffness", _config(tmp_path, **stage))
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("gearsim: error: stage")
    for w in words:
        assert w in lines[0], lines[0]


def test_crack_on_missing_planet_refused(capsys, tmp_path) -> None:
    text = example_text("nrel-grc").replace('gear = "planet-1"', 'gear = "planet-5"')
    path = tmp_path / "p5.toml"
    path.write_text(text)
    code, out, err = _run(capsys, "stiffness", path)
    assert code == 2
    assert err.strip() == ("gearsim: error: cracks[0].gear = planet-5: no such planet: the stage "
                           "has 3 planets (planet-1 .. planet-3)")


def test_sensor_angle_past_a_turn_refused(capsys, tmp_path) -> None:
    # 1e300 deg ran (probe round 8 #8)
    text = example_text("lin-parker-1999").replace('[sensor]\nangle = "0 deg"',
                                                    '[sensor]\nangle = "1e300 deg"')
    path = tmp_path / "s.toml"
    path.write_text(text)
    code, out, err = _run(capsys, "simulate", path, "--out", tmp_path / "x.nc")
    assert code == 2 and not (tmp_path / "x.nc").exists()
    assert err.strip() == ("gearsim: error: sensor.angle = 1e300 deg: must be a finite angle "
                           "in [-360, 360] deg")


def test_constant_mesh_with_crack_refused(capsys, tmp_path) -> None:
    path = tmp_path / "lpc.toml"
    path.write_text(GOOD + '\n[[cracks]]\ngear = "planet-1"\ndepth = "1 mm"\n')
    code, out, err = _run(capsys, "simulate", path, "--out", tmp_path / "x.nc")
    assert code == 2
    assert "constant mesh stiffness cannot carry a crack" in err
    assert not (tmp_path / "x.nc").exists()


def test_grc_kinematics_in_file() -> None:
    box = loads(example_text("nrel-grc"))
    w = box.stage.speeds
    assert w["carrier"] == pytest.approx(22.1 * 2 * math.pi / 60)
    # ring held, carrier input: the sun runs at (1 + z_r / z_s) times the carrier
    assert w["sun"] / w["carrier"] == pytest.approx(1 + 99 / 21)


def test_stage_stiffness_plot(capsys, tmp_path) -> None:
    png = tmp_path / "meshes.png"
    code, out, err = _run(capsys, "stiffness", "lin-parker-1999", "--plot", png)
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_python_api_simulates_a_stage() -> None:
    import gearsim as gs

    box = gs.load("lin-parker-1999")
    for model in ("lin-parker-1999", box):
        ds = gs.simulate(model, duration=0.01, fs=20000.0)
        assert ds.attrs["kind"] == "planetary" and ds.sizes["time"] == 200
