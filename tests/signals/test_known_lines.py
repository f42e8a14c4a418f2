"""Lines the kinematics know are never read for one another, and a record too short is
told the length that suffices at once.

Three tester findings: a three-stage record lengthened to the stated minimum was refused
again with a longer one (the first unmet sideband spacing was named, not the binding
one); stage 1's third mesh harmonic (1425 Hz) was read from stage 3's 23rd (1426.198 Hz)
in a record of 0.25 Hz bins; a healthy planetary stage's planet-pass line (30 Hz) was
read as its planet-fault line (26.667 Hz) in a 0.4 s record of 2.5 Hz bins.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.signals.analysis import analyze
from gearsim.signals.planetary_tier import StageSpec, planetary_tier

#: 19/71, 23/67, 27/61 at 25 Hz: shafts 25, 6.690, 2.2966 and 1.01653 Hz; meshes 475,
#: 153.873 and 62.0086 Hz.
STAGES = ((19, 71), (23, 67), (27, 61))
F_IN, FS = 25.0, 5000.0
F_OUT = F_IN * 19 * 23 * 27 / (71 * 67 * 61)  # 1.01653 Hz
F_M3 = F_IN * 19 / 71 * 23 / 67 * 27  # 62.0086 Hz


def _tones(duration: float, lines: dict[float, float]) -> np.ndarray:
    t = np.arange(round(duration * FS)) / FS
    return sum(a * np.cos(2 * np.pi * f * t) for f, a in lines.items())


def test_a_short_record_is_told_the_length_that_suffices():
    # the output shaft's sidebands need 4 Hann bins: 4 / 1.01653 Hz = 3.935 s; before,
    # a 1 s record was told 1.742 s (stage 2's 2.2966 Hz shaft) and refused again there
    with pytest.raises(InputError) as exc:
        analyze(_tones(1.0, {475.0: 1.0}), FS, shaft_frequency=F_IN, stages=STAGES)
    need = float(re.search(r"must be >= ([\d.]+) s", str(exc.value)).group(1))
    assert need == pytest.approx(4.0 / F_OUT, abs=1e-3)
    res = analyze(_tones(math.ceil(need * FS) / FS, {475.0: 1.0}), FS, shaft_frequency=F_IN,
                  stages=STAGES)
    assert len(res.stages) == 3


def test_a_harmonic_is_not_read_from_another_stages_line_beside_it():
    # stage 1's 3 f_m = 1425 Hz (amplitude 0.8) and stage 3's 23 f_m = 1426.198 Hz
    # (amplitude 2): 1.198 Hz = 4.8 bins of 0.25 Hz apart, resolved by the Hann window
    lines = {475.0: 1.0, 1425.0: 0.8, 23 * F_M3: 2.0}
    res = analyze(_tones(4.0, lines), FS, shaft_frequency=F_IN, stages=STAGES)
    third = res.stages[0].harmonics[2]
    assert third.frequency == pytest.approx(1425.0, abs=0.05)
    assert third.amplitude == pytest.approx(0.8, rel=0.01)
    # the sideband families read the same line
    fam = next(f for f in res.stages[0].families if f.order == 3)
    assert fam.mesh.amplitude == pytest.approx(0.8, rel=0.01)


# ring held, 18/27/72 x 3 at f_c = 10 Hz: f_m = 720 Hz, planet pass 3 f_c = 30 Hz,
# planet fault f_m / z_p = 26.667 Hz, sun fault 3 (50 - 10) = 120 Hz
HOIST = StageSpec(18, 27, 72, 3, carrier_frequency=10.0)


def _modulated(duration: float, m_pass: float, m_planet: float) -> np.ndarray:
    """The ring-mesh tone modulated at the planet pass (depth ``m_pass``) and at the
    planet fault frequency (``m_planet``): squared-envelope lines 2 m at each."""
    t = np.arange(round(duration * FS)) / FS
    env = 1 + m_pass * np.cos(2 * np.pi * 30.0 * t) \
        + m_planet * np.cos(2 * np.pi * 720.0 / 27 * t)
    return env * np.cos(2 * np.pi * 720.0 * t)


def test_the_planet_fault_line_is_not_read_from_the_planet_pass():
    # 0.4 s: 2.5 Hz bins; before, the planet-fault line was the largest of 25-30 Hz, the
    # planet pass's 1.0 (46 dB over the floor for a healthy stage)
    skipped: list = []
    res = planetary_tier(_modulated(0.4, 0.5, 0.0), FS, HOIST, skipped)
    assert "planet_fault" not in res["envelope"]["lines"]
    why = {s["tier"]: s["reason"] for s in skipped}
    # 4 Hann bins across 30 - 26.667 = 3.333 Hz: 1.2 s
    assert "must be >= 1.2 s" in why["planetary.envelope.planet_fault"]
    assert "planetary.envelope.ring_fault_planet_pass" in why


def test_a_long_record_reads_both_lines():
    # 2.4 s: 0.4167 Hz bins, both lines on a bin: 2 x 0.5 and 2 x 0.05
    lines = planetary_tier(_modulated(2.4, 0.5, 0.05), FS, HOIST)["envelope"]["lines"]
    assert lines["ring_fault_planet_pass"]["amplitude"] == pytest.approx(1.0, rel=1e-3)
    assert lines["planet_fault"]["amplitude"] == pytest.approx(0.1, rel=1e-3)
