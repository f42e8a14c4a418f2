"""The high-level analyze() on a synthetic cracked-gear signal."""

import json

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.errors import InputError
from gearsim.signals import analyze
from gearsim.signals.synthetic import ImpactSpec, gear_signal

#: Brief requirements: amplitudes within 1 %, impact period within 1 %.
RTOL_AMPLITUDE = 0.01
RTOL_PERIOD = 0.01

FS = 20_000.0
F_R = 1900.0 / 60.0
TEETH = (39, 59, 125)


def _signal(impact=4.0, seed=0, duration=2.0):
    return gear_signal(
        fs=FS, duration=duration, shaft_frequency=F_R, teeth=TEETH[0],
        mesh_amplitudes={1: 1.0, 2: 0.5}, sidebands={(1, -1): 0.05, (1, 1): 0.04},
        impacts=ImpactSpec(amplitude=impact, decay=3e-4, carrier=4000.0, first=0.01)
        if impact else None,
        noise=0.002, offset=100.0, seed=seed,
    )


def test_analyze_recovers_known_content_and_is_json():
    x = _signal()
    a = analyze(x, FS, teeth=TEETH, shaft_frequency=F_R, orders=(1, 2), n_sidebands=3)
    assert_allclose(a.kinematics.mesh_frequency, 39 * F_R, rtol=1e-12)
    assert_allclose(a.kinematics.shafts["shaft2"], 39 * F_R / 59, rtol=1e-12)
    assert_allclose(a.impacts.period, 1.0 / F_R, rtol=RTOL_PERIOD)
    fam = next(f for f in a.families if f.order == 1 and f.shaft == "shaft1")
    # Impacts add a broadband comb at multiples of f_r: compare without them.
    b = analyze(_signal(impact=0.0), FS, teeth=TEETH, shaft_frequency=F_R, orders=(1, 2),
                n_sidebands=3)
    fam0 = next(f for f in b.families if f.order == 1 and f.shaft == "shaft1")
    assert_allclose(fam0.amplitude[fam0.k == -1][0], 0.05, rtol=RTOL_AMPLITUDE)
    assert_allclose(fam0.amplitude[fam0.k == 1][0], 0.04, rtol=RTOL_AMPLITUDE)
    assert_allclose(b.harmonics[0].amplitude, 1.0, rtol=RTOL_AMPLITUDE)
    assert fam.ser > fam0.ser  # the crack raises the sideband level
    assert a.indicators.fm4 > 3.0 * b.indicators.fm4  # impulsive difference signal
    # Band energy pulses once per revolution with sidebands or impacts, not without.
    flat = gear_signal(fs=FS, duration=2.0, shaft_frequency=F_R, teeth=TEETH[0],
                       mesh_amplitudes={1: 1.0, 2: 0.5}, noise=0.002, seed=5)
    c = analyze(flat, FS, teeth=TEETH, shaft_frequency=F_R, orders=(1, 2), n_sidebands=3)
    assert c.band_modulation[1] < 0.01
    assert a.band_modulation[1] > 0.1 and b.band_modulation[1] > 0.1
    assert_allclose(a.stats.mean, 100.0, rtol=1e-3)
    d = json.loads(json.dumps(a.to_dict()))
    assert d["impacts"]["count"] == a.impacts.count
    assert {"fm0", "fm4", "na4", "m6a", "m8a"} <= set(d["tsa"])
    assert d["options"]["orders"] == [1, 2]


def test_analyze_baseline_ratios_and_tacho():
    x = _signal()
    base = _signal(impact=0.0, seed=1)
    t = np.arange(x.size) / FS
    tacho = (np.mod(t * F_R, 1.0) < 0.2).astype(float)
    a = analyze(x, FS, teeth=TEETH, tacho=tacho, baseline=base, baseline_tacho=tacho,
                orders=(1, 2), n_sidebands=3)
    assert a.ratios["rms"] > 1.0 and a.ratios["peak"] > 1.5
    assert_allclose(a.kinematics.reference_frequency, F_R, rtol=1e-3)
    assert a.options["speed_source"] == "tacho"
    assert np.isfinite(a.indicators.na4)


def test_plots_written(tmp_path):
    a = analyze(_signal(duration=1.0), FS, teeth=TEETH[:1], shaft_frequency=F_R, orders=(1, 2),
                n_sidebands=3)
    from gearsim.viz import save_all

    paths = save_all(a.figures(units="N"), tmp_path)
    assert len(paths) == 5
    for p in paths:
        assert p.stat().st_size > 10_000


def test_analyze_bad_inputs():
    x = _signal(duration=1.0)
    bad = x.copy()
    bad[123] = np.nan
    with pytest.raises(InputError, match=r"signal\[123\]"):
        analyze(bad, FS, teeth=TEETH, shaft_frequency=F_R)
    with pytest.raises(InputError, match="Nyquist"):
        analyze(x, 8000.0, teeth=TEETH, shaft_frequency=F_R, orders=(1, 2, 3, 4))
    with pytest.raises(InputError, match="record duration"):
        analyze(x[:2000], FS, teeth=TEETH, shaft_frequency=F_R, orders=(1,))
    with pytest.raises(InputError, match="exactly one"):
        analyze(x, FS, teeth=TEETH)
    with pytest.raises(InputError, match="teeth"):
        analyze(x, FS, teeth=(0,), shaft_frequency=F_R)
