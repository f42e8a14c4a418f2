"""Mesh residual, off-tone fraction, sideband spacing, window peak, analysis settings.

Every expected value is a closed form of the synthetic input: the residual of mesh
harmonics plus a known non-harmonic tone is that tone (within the cubic-spline error
bound), and the spectral measures are evaluated on hand-built spectra whose answer
follows from their definitions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.signals import (
    AnalysisSettings,
    Spectrum,
    analyze,
    mesh_residual,
    off_tone_fraction,
    sideband_spacing,
    window_peak,
)
from gearsim.signals._checks import check_speed_source
from gearsim.signals.settings import KEYS, LIST_KEYS, parse_analysis
from gearsim.signals.tsa import order_mask

FS = 50_000.0
F_R = 31.25       # Hz: 1600 samples per revolution
Z = 40            # teeth: f_m = 1250 Hz, 40 samples per mesh period
F_M = Z * F_R
REVS = 20


def _spline_bound(tones, h):
    """Hall & Meyer (1976): ``|f - s| <= (5/384) h^4 max|f''''|`` for cubic-spline
    interpolation with step ``h``; for a tone ``A cos(w t)``, ``max|f''''| = A w^4``."""
    return sum(5 / 384 * amp * (2 * np.pi * f * h) ** 4 for amp, f in tones)


def test_mesh_residual_returns_the_non_harmonic_component():
    n = int(REVS * FS / F_R)
    t = np.arange(n) / FS
    # f_c = 7.35 f_r: on bin 147 of the 20-revolution angle record, not a mesh order.
    f_c, b = 7.35 * F_R, 5.0
    c = b * np.cos(2 * np.pi * f_c * t + 0.3)
    tones = ((1000.0, F_M), (200.0, 2 * F_M), (b, f_c))
    x = (43e3 + 1000 * np.cos(2 * np.pi * F_M * t + 0.2)
         + 200 * np.cos(4 * np.pi * F_M * t + 1.1) + c)
    r = mesh_residual(x, FS, mesh_frequency=F_M, shaft_frequency=F_R)
    # Forward: spline through the time samples (h = 1/fs) of all three tones. Zeroing the
    # mesh bins only removes error components (an orthogonal projection). Back: spline
    # through the angle samples (M = 2048 per revolution) of what is left, the tone c.
    m = 2048
    bound = _spline_bound(tones, 1 / FS) + _spline_bound(((b, f_c),), 1 / (m * F_R))
    err = np.abs(r - c)
    assert err[8:-8].max() < bound
    # The first and last few samples lie on the spline's end pieces (not-a-knot, and the
    # last angle sample extrapolated by 0.22 of a time sample): still fourth order, with
    # a larger constant than Hall-Meyer's; a factor 2 covers it.
    assert err.max() < 2 * bound
    # Without the harmonic removal the error would be ~1200 N, without the tone ~5 N.
    assert bound < 0.05


def test_mesh_residual_refuses_bad_input():
    x = np.ones(4000)
    with pytest.raises(InputError, match="whole number of teeth"):
        mesh_residual(x, FS, mesh_frequency=F_M + 1.0, shaft_frequency=F_R)
    with pytest.raises(InputError, match="one revolution"):
        mesh_residual(x[:1000], FS, mesh_frequency=F_M, shaft_frequency=F_R)


def test_order_mask_over_several_revolutions():
    """Bin b of an R-revolution record is order b / R: mesh orders q Z at q Z R, shaft
    harmonic h at h R, sidebands q Z +- s at (q Z +- s) R."""
    r, m, z = 3, 64, 8
    mask = order_mask(r * m, teeth=z, shaft_harmonics=2, sideband_orders=1, revolutions=r)
    expected = {0, 3, 6} | {q * z * r + s * r for q in (1, 2, 3, 4) for s in (-1, 0, 1)}
    assert set(np.flatnonzero(mask)) == {b for b in expected if b <= r * m // 2}


def _spectrum(lines: dict[float, float], df: float = 1.0, f_max: float = 4000.0) -> Spectrum:
    """Hand-built spectrum: the given lines on bins of width df, zero elsewhere."""
    f = np.arange(0.0, f_max + df, df)
    a = np.zeros_like(f)
    for freq, amp in lines.items():
        a[int(round(freq / df))] = amp
    return Spectrum(frequency=f, amplitude=a, window="hann", fs=2 * f_max,
                    n_samples=int(round(2 * f_max / df)))


def test_off_tone_fraction_of_a_hand_built_family():
    # Tone 1 at 1000 Hz, sidebands 0.1 at +-25 k Hz (k = 1..3), a line outside the band.
    lines = {1000.0: 1.0, 1600.0: 3.0}
    lines |= {1000.0 + 25 * k: 0.1 for k in (-3, -2, -1, 1, 2, 3)}
    s = _spectrum(lines)
    eta = off_tone_fraction(s, center=1000.0, line_half_width=12.5, band_half_width=500.0)
    assert eta == pytest.approx(6 * 0.01 / (1 + 6 * 0.01), rel=1e-12)
    pure = _spectrum({1000.0: 1.0, 1600.0: 3.0})
    assert off_tone_fraction(pure, center=1000.0, line_half_width=12.5,
                             band_half_width=500.0) == 0.0
    assert math.isnan(off_tone_fraction(_spectrum({}), center=1000.0, line_half_width=12.5,
                                        band_half_width=500.0))
    with pytest.raises(InputError, match="band_half_width"):
        off_tone_fraction(s, center=1000.0, line_half_width=50.0, band_half_width=20.0)


def test_sideband_spacing_of_hand_built_families():
    # Lines must be local maxima: isolated non-zero bins on a zero floor are.
    fam = {1000.0: 1.0} | {1000.0 + 25 * k: 0.1 / abs(k) for k in (-3, -2, -1, 1, 2, 3)}
    assert sideband_spacing(_spectrum(fam), center=1000.0, shaft_frequency=25.0,
                            n_sidebands=3) == 25.0
    # A stray line (of another shaft) between the sidebands does not move the mode.
    stray = fam | {1037.0: 0.2}
    assert sideband_spacing(_spectrum(stray), center=1000.0, shaft_frequency=25.0,
                            n_sidebands=3) == 25.0
    # Spacing is measured, not assumed: a family at +-20 Hz searched with f_r = 25 Hz.
    other = {1000.0: 1.0} | {1000.0 + 20 * k: 0.1 for k in (-3, -2, -1, 1, 2, 3)}
    assert sideband_spacing(_spectrum(other), center=1000.0, shaft_frequency=25.0,
                            n_sidebands=3) == 20.0
    # Ties go to the smaller spacing: steps 10 and 30 once each on one side.
    tie = {1000.0: 1.0, 1010.0: 0.1, 1020.0: 0.1, 1050.0: 0.1}
    assert sideband_spacing(_spectrum(tie), center=1000.0, shaft_frequency=25.0,
                            n_sidebands=2) == 10.0
    # One line per side: no spacing.
    lone = {1000.0: 1.0, 975.0: 0.1, 1025.0: 0.1}
    assert math.isnan(sideband_spacing(_spectrum(lone), center=1000.0,
                                       shaft_frequency=25.0, n_sidebands=3))
    # The mesh line's Hann main lobe (+-2 bins) is not a sideband.
    lobe = {998.0: 0.5, 1000.0: 1.0, 1002.0: 0.5} | {1000.0 + 25 * k: 0.1
                                                   for k in (1, 2, 3)}
    assert sideband_spacing(_spectrum(lobe), center=1000.0, shaft_frequency=25.0,
                            n_sidebands=3) == 25.0


def test_window_peak():
    x = np.zeros(1000)
    x[500] = -3.0
    x[100] = 2.0
    fs = 1000.0
    p = window_peak(x, fs, np.array([0.5, 0.103, 0.3, 0.9995]), 0.005)
    assert p[0] == 3.0          # |min| counts
    assert p[1] == 2.0          # 100 is 3 samples from 103, inside +-5
    assert p[2] == 0.0
    assert math.isnan(p[3])     # window mostly outside the record


def test_analysis_settings_defaults_and_validation():
    s = AnalysisSettings()
    assert s.orders == (1, 2, 3, 4) and s.n_sidebands == 6 and s.window == "hann"
    assert set(KEYS) == set(s.to_dict()) and set(LIST_KEYS) <= set(KEYS)
    for kw, name in (({"orders": ()}, "analysis.orders"), ({"orders": (1, 0)}, "orders[1]"),
                     ({"n_sidebands": 0}, "analysis.n_sidebands"),
                     ({"window": "hamming"}, "analysis.window"),
                     ({"band_fraction": 1.0}, "analysis.band_fraction"),
                     ({"impact_factor": -1.0}, "analysis.impact_factor"),
                     ({"emd_method": "energy"}, "analysis.emd_method"),
                     ({"emd_threshold": "high"}, "analysis.emd_threshold"),
                     ({"emd_max_imf": 0}, "analysis.emd_max_imf"),
                     ({"pulses_per_rev": 1.5}, "analysis.pulses_per_rev"),
                     ({"remove_mean": 1}, "analysis.remove_mean")):
        with pytest.raises(InputError, match=name.replace("[", r"\[").replace("]", r"\]")):
            AnalysisSettings(**kw)


def test_parse_analysis_section():
    s = parse_analysis({"orders": [1, 2], "n_sidebands": 3, "emd_method": "correlation",
                        "emd_threshold": "ayenu-prah", "band_fraction": "80 %"})
    assert s.orders == (1, 2) and s.n_sidebands == 3 and s.emd_threshold == "ayenu-prah"
    assert s.band_fraction == pytest.approx(0.8, rel=1e-12)
    with pytest.raises(InputError, match="analysis.foo"):
        parse_analysis({"foo": 1})


def test_analyze_settings_and_keyword_overrides_agree():
    n = int(16 * FS / F_R)
    t = np.arange(n) / FS
    x = np.cos(2 * np.pi * F_M * t) + 0.1 * np.cos(2 * np.pi * (F_M + F_R) * t)
    a = analyze(x, FS, teeth=[Z, 2 * Z], shaft_frequency=F_R, orders=(1, 2), n_sidebands=3)
    b = analyze(x, FS, teeth=[Z, 2 * Z], shaft_frequency=F_R,
                settings=AnalysisSettings(orders=(1, 2), n_sidebands=3))
    assert a.options == b.options and a.orders == (1, 2)
    assert [f.ser for f in a.families] == [f.ser for f in b.families]
    with pytest.raises(InputError, match="not an analysis option"):
        analyze(x, FS, teeth=[Z], shaft_frequency=F_R, bogus=1)
    with pytest.raises(InputError, match="analysis.n_sidebands"):
        analyze(x, FS, teeth=[Z], shaft_frequency=F_R, n_sidebands=0)


def test_speed_source_rule():
    assert check_speed_source(10.0, None) == 10.0
    assert check_speed_source(None, np.ones(3)) is None
    with pytest.raises(InputError, match="neither.*exactly one"):
        check_speed_source(None, None)
    with pytest.raises(InputError, match="--shaft-rpm/--tacho = both"):
        check_speed_source(1900.0, "tacho", names=("--shaft-rpm", "--tacho"), unit="rpm")
    with pytest.raises(InputError, match="> 0 rpm"):
        check_speed_source(-5.0, None, names=("--shaft-rpm", "--tacho"), unit="rpm")
