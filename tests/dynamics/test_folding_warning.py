"""A record whose content reaches the internal Nyquist frequency warns of folding.

The kernel samples the state at r fs and the FIR filter acts after: content above
r fs / 2 has folded in before it. A 24/36/96 stage with four planets (carrier in at
20 rpm, 300 kN m) driving a 90/23 pair (mesh 150 Hz) recorded at fs = 2 kHz with r = 2:
the two largest lines of the pair's mesh force were 550 Hz and 100 Hz, 3450 and 2100 Hz
folded at 4 kHz, with no word (a tester's report). The run now warns; with r = 8 the
same run does not; neither do the examples (their top-band share 0.0014-0.13 against
the threshold ALIAS_SHARE = 0.25; docs/dynamics.md 5).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import gearsim as gs
from gearsim.errors import ModelRangeWarning

BOX = """
name = "24/36/96 x 4 then 90/23"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "rotor"
[[shafts]]
name = "sun-shaft"
[[shafts]]
name = "hss"
[[stages]]
carrier = "rotor"
sun = "sun-shaft"
ring = "housing"
sun_teeth = 24
planet_teeth = 36
ring_teeth = 96
planets = 4
normal_module = "8 mm"
normal_pressure_angle = "20 deg"
helix_angle = "7.5 deg"
face_width = "200 mm"
ring_addendum_coefficient = 0.8
[common]
normal_pressure_angle = "20 deg"
helix_angle = "12 deg"
normal_module = "6 mm"
face_width = "150 mm"
[[gears]]
name = "wheel"
shaft = "sun-shaft"
teeth = 90
[[gears]]
name = "pinion"
shaft = "hss"
teeth = 23
[[meshes]]
gears = ["wheel", "pinion"]
[operating]
speed = "20 rpm"
torque = "300 kN*m"
[stiffness]
positions_per_cycle = 20
slices = 5
[dynamics]
duration = 0.5
fs = 2000
"""


def _folding_warnings(gb) -> tuple[list[str], object]:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ds = gb.simulate()
    return [str(w.message) for w in seen if issubclass(w.category, ModelRangeWarning)
            and "anti-aliasing" in str(w.message)], ds


def _top_lines(x: np.ndarray, fs: float) -> np.ndarray:
    a = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size)))
    return np.fft.rfftfreq(x.size, 1 / fs)[np.argsort(a)[::-1][:2]]


def test_a_record_of_folded_lines_warns_and_more_oversampling_does_not():
    gb = gs.loads(BOX)
    said, ds = _folding_warnings(gb)
    assert len(said) == 1 and "internal Nyquist frequency 2000 Hz" in said[0], said
    # the warning is right: the two largest lines are no harmonic of f_m = 150 Hz
    lines = _top_lines(ds["chain_mesh_force"].values[:, 0], 2000.0)
    assert all(abs(f / 150.0 - round(f / 150.0)) > 0.1 for f in lines), lines
    said, ds = _folding_warnings(gb.replace(dynamics={"oversample": 8}))
    assert said == []
    lines = _top_lines(ds["chain_mesh_force"].values[:, 0], 2000.0)
    assert np.allclose(lines / 150.0, np.round(lines / 150.0), atol=0.02), lines


@pytest.mark.parametrize("name", ["idler-table1", "two-stage-reducer", "lin-parker-1999"])
def test_the_examples_do_not_warn(name):
    gb = gs.example(name)
    said, _ = _folding_warnings(gb.replace(dynamics={"duration": min(gb.dynamics.duration,
                                                                     0.3)}))
    assert said == []


def test_round_off_is_not_content():
    """A constant force (a stage of constant mesh stiffnesses) carries round-off of 1e-16
    of its mean, whose spectrum is flat: not a reason to warn. The same record with a
    line of 1 N near the internal Nyquist frequency over a 0.5 N line in the band is."""
    import importlib

    from gearsim.dynamics.settings import DynamicsSettings

    sim = importlib.import_module("gearsim.dynamics.simulate")
    fs, n = 2000.0, 4000
    t = np.arange(n) / (2 * fs)
    rng = np.random.default_rng(1)
    flat = 900.0 + 1e-13 * rng.standard_normal(n)
    lines = 900.0 + 0.5 * np.sin(2 * np.pi * 150.0 * t) + np.sin(2 * np.pi * 1900.0 * t)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        sim._warn_folding(flat[:, None], DynamicsSettings(fs=fs))
        assert seen == []
        sim._warn_folding(lines[:, None], DynamicsSettings(fs=fs))
    assert len(seen) == 1 and "holds 2 times its largest line" in str(seen[0].message)


PAIR = """
name = "23/57 spur pair"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[common]
normal_module = "2 mm"
normal_pressure_angle = "20 deg"
face_width = "20 mm"
[[gears]]
name = "pinion"
teeth = 23
[[gears]]
name = "gear"
teeth = 57
[operating]
speed = "1500 rpm"
torque = "40 N*m"
[dynamics]
duration = 0.1
fs = 5000
"""


def test_a_gear_train_warns_as_a_stage_does():
    """A 23/57 pair (f_m 575 Hz) at fs 5 kHz, r = 2: its mesh force's largest lines were
    1950, 1375 and 800 Hz (6.5, 2.9, 2.5 N; at r = 24 under 1e-4 N) beside the true 575
    and 1150 Hz (1.3, 4.2 N), and ``simulate`` of a gear train never ran the check (only
    a stage's run and a study's record did); at r = 24 it is quiet."""
    gb = gs.loads(PAIR)
    said, ds = _folding_warnings(gb)
    assert len(said) == 1, said
    top = _top_lines(ds["mesh_force_1"].values, 5000.0)[0]  # 10 Hz bins
    assert abs(top - 575.0 * round(top / 575.0)) > 20.0, top  # no harmonic of f_m
    said, _ = _folding_warnings(gb.replace(dynamics={"oversample": 24}))
    assert said == []
