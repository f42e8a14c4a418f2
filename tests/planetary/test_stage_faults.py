"""Surface faults on a planetary stage: the sun-planet meshes as meshes of contacts.

Independent numbers: the healthy stage (stiffness tables, no contacts), which a fault of
negligible depth must reproduce in both senses of the contacts (this checks the contact
table, its phases and its reversal); the fault frequencies from the kinematics; the
teeth in mesh from the healthy table's pair-to-tooth map.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.signal import hilbert

from gearsim import cli
from gearsim.dynamics.settings import DynamicsSettings
from gearsim.dynamics.stage import StageDynamics, simulate_stage
from gearsim.errors import InputError
from gearsim.geometry.planetary import PlanetaryStage
from gearsim.model.config import example_text, loads
from gearsim.signals.planetary import planetary_frequencies
from gearsim.stiffness.crack import Crack
from gearsim.stiffness.faults import BrokenTooth, Spall
from gearsim.stiffness.mesh import mesh_stiffness
from gearsim.stiffness.settings import StiffnessSettings
from gearsim.system.planetary import PlanetaryTrain, StageOperating

pytestmark = pytest.mark.filterwarnings("ignore::gearsim.errors.ModelRangeWarning")

#: A 1e-12 m spall closes at once under load: mesh forces as the healthy stage's (on
#: meshes of contacts) to this, relative to the static force (measured 2.1e-6: the
#: spalled contacts carry k (x - 1e-12) and the run responds to that).
NEGLIGIBLE = 1e-5
#: Envelope-spectrum resolution of a 0.8 s record: 1.25 Hz.
FREQ_TOL = 1.5

STAGE = PlanetaryStage(30, 24, 78, 2e-3, planets=4, face_width=0.02,
                       ring_addendum_coefficient=0.8)
SUN_IN = StageOperating(speed=18.0 * 2 * math.pi, torque=100.0)  # contacts forwards
CARRIER_IN = StageOperating(fixed="ring", input="carrier", speed=5.0 * 2 * math.pi,
                            torque=360.0)  # the planets drive the sun: backwards
SETTINGS = StiffnessSettings(positions_per_cycle=16)
RUN = DynamicsSettings(duration=0.8, fs=5000.0, oversample=8)


def _spall(gear: str, depth: float, tooth: int = 0) -> Spall:
    g = STAGE.sun if gear == "sun" else STAGE.planet
    return Spall(gear=gear, tooth=tooth, radius=g.pitch_radius, length=1.5e-3, width=0.02,
                 depth=depth)


def _envelope_peak(x: np.ndarray, lo: float, hi: float) -> float:
    env = np.abs(hilbert(x - x.mean()))
    spec = np.abs(np.fft.rfft(env - env.mean()))
    f = np.fft.rfftfreq(env.size, 1 / RUN.fs)
    band = (f > lo) & (f < hi)
    return float(f[band][np.argmax(spec[band])])


@pytest.mark.parametrize("op", [SUN_IN, CARRIER_IN], ids=["forwards", "backwards"])
def test_negligible_spall_reproduces_the_healthy_stage(op) -> None:
    # the healthy stage on meshes of contacts (the mesh of contacts scales the mesh
    # damping by the closed share of all its listed contacts, off-path ones included,
    # k_zero / k = 1 / 1.68 here, which a stiffness table does not: docs/planetary.md)
    run = dataclasses.replace(RUN, duration=0.2)
    healthy = simulate_stage(PlanetaryTrain(STAGE, op, SETTINGS, contacts=True),
                             StageDynamics(), run)
    tr = PlanetaryTrain(STAGE, op, SETTINGS, faults=(_spall("sun", 1e-12),))
    assert tr.direction == (1 if op is SUN_IN else -1)
    faulty = simulate_stage(tr, StageDynamics(), run)
    assert faulty.attrs["dt"] == healthy.attrs["dt"]
    scale = healthy.attrs["static_mesh_force"]
    diff = np.abs(faulty["mesh_force"].values - healthy["mesh_force"].values).max()
    assert diff < NEGLIGIBLE * scale


def test_table_changes_only_where_the_tooth_meshes() -> None:
    tr = PlanetaryTrain(STAGE, SUN_IN, SETTINGS, faults=(_spall("planet-2", 2e-5, tooth=5),))
    healthy = PlanetaryTrain(STAGE, SUN_IN, SETTINGS)
    t = tr.mesh_table("sun", 1)
    assert t.grid is not None and t.period == STAGE.planet_teeth
    ms = mesh_stiffness(healthy.sun_pair, settings=SETTINGS, revolution_of=2)
    k_h = ms.k  # over a planet revolution
    meshing = ((ms.pair_tooth2 == 5) & (ms.pair_k > 0)).any(axis=1)
    k_f = t.table.k
    np.testing.assert_allclose(k_f[~meshing], k_h[~meshing], rtol=1e-12)
    assert np.all(k_f[meshing] <= k_h[meshing] * (1 + 1e-12))
    assert np.any(k_f[meshing] < 0.9 * k_h[meshing])
    # the other planets' sun meshes are healthy meshes of contacts (one cycle); the ring
    # meshes, which do not meet a working flank, keep their tables
    other = tr.mesh_table("sun", 0)
    assert other.grid is not None and other.period == 1
    np.testing.assert_allclose(other.k, ms.k[:SETTINGS.positions_per_cycle], rtol=1e-12)
    assert tr.mesh_table("ring", 1).grid is None


@pytest.mark.parametrize("op", [SUN_IN, CARRIER_IN], ids=["forwards", "backwards"])
def test_sun_spall_modulates_at_the_sun_fault_frequency(op) -> None:
    tr = PlanetaryTrain(STAGE, op, SETTINGS, faults=(_spall("sun", 2e-5),))
    ds = simulate_stage(tr, StageDynamics(), RUN)
    fc = ds.attrs["carrier_frequency"]
    fq = planetary_frequencies(30, 24, 78, 4, carrier=fc)
    assert _envelope_peak(ds["sensor"].values, 5.0, 200.0) == pytest.approx(fq.sun_fault,
                                                                           abs=FREQ_TOL)


def test_planet_spall_modulates_its_sun_mesh_at_the_planet_fault_frequency() -> None:
    tr = PlanetaryTrain(STAGE, SUN_IN, SETTINGS, faults=(_spall("planet-2", 2e-5),))
    ds = simulate_stage(tr, StageDynamics(), RUN)
    fq = planetary_frequencies(30, 24, 78, 4, sun=18.0)
    f2 = ds["mesh_force"].sel(mesh="sun-planet-2").values
    assert _envelope_peak(f2, 2.0, 100.0) == pytest.approx(fq.planet_fault, abs=FREQ_TOL)


@pytest.mark.parametrize("kw,parameter,words", [
    (dict(faults=(_spall("ring", 1e-5),)), "fault.gear", "ring tooth faults"),
    (dict(faults=(_spall("planet-5", 1e-5),)), "fault.gear", "no such planet"),
    (dict(faults=(Spall(gear="planet-1", flank="non-working", radius=0.024, length=1e-3,
                        width=0.01, depth=1e-5),)), "fault.flank", "meets the ring"),
    (dict(faults=(BrokenTooth(gear="planet-1"),)), "fault.kind", "ring mesh"),
    (dict(faults=(Spall(gear="sun", flank="non-working", radius=0.03, length=1e-3,
                        width=0.01, depth=1e-5),)), "fault.flank", "never loaded"),
    (dict(faults=(_spall("sun", 1e-5),), cracks=(Crack(gear="planet-1", depth=1e-3),)),
     "faults", "one member"),
    (dict(faults=(_spall("sun", 1e-5),), sun_mesh_stiffness=5e8),
     "stage.sun_mesh_stiffness", "cannot carry faults"),
])
def test_refusals(kw, parameter, words) -> None:
    with pytest.raises(InputError) as err:
        PlanetaryTrain(STAGE, SUN_IN, SETTINGS, **kw)
    assert err.value.parameter == parameter and words in str(err.value)


def test_faults_in_a_stage_file(capsys, tmp_path) -> None:
    text = "\n".join(ln for ln in example_text("lin-parker-1999").splitlines()
                     if "mesh_stiffness" not in ln).replace("duration = 1.0", "duration = 0.1")
    text += ('\n[[faults]]\nkind = "spall"\ngear = "sun"\ntooth = 3\nradius = "31 mm"\n'
             'length = "1.5 mm"\nwidth = "10 mm"\ndepth = "10 um"\n')
    box = loads(text)
    assert len(box.stage.faults) == 1 and box.stage.faults[0].gear == "sun"
    path = tmp_path / "f.toml"
    path.write_text(text)
    code = cli.run(["simulate", str(path), "--out", str(tmp_path / "f.nc")])
    assert code == 0, capsys.readouterr().err
