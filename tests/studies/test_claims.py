"""The seed-study measures of :mod:`gearsim.studies.claims` on a signal with a known answer.

Healthy load: two mesh harmonics in phase, ``S = A1 + A2`` at every mesh crest, plus a
small broadband part (non-harmonic tones, ``|b| <= delta``). Cracked load: the same plus,
once per revolution, a burst ``P w(t - t_c) cos(w_m (t - t_c))`` (Hann envelope ``w`` of
three mesh periods, ``w(0) = 1``) centred on a mesh crest ``t_c``. Without the broadband
part, ``max |d|`` near ``t_c`` is ``S + P`` (every term attains its bound at ``t_c``) and
``max |d_h|`` there is ``S`` (the window holds a crest), so the impact ratio is
``(S + P) / S``; half a revolution away the loads are equal (far-field ratio 1). The
broadband part and the mean removal move each peak by at most ``delta'``, which sets the
tolerances. The bursts repeat every ``1 / f_r`` exactly (1600 samples).
"""

from __future__ import annotations

import numpy as np
import pytest

from gearsim.signals import analyze, mesh_residual
from gearsim.studies.claims import case_metrics

FS = 50_000.0
F_R = 31.25          # Hz: 1600 samples per revolution
Z = 40               # f_m = 1250 Hz: 40 samples per mesh period, crests every 40 samples
F_M = Z * F_R
REVS = 20
A1, A2, P = 1000.0, 200.0, 300.0
S = A1 + A2
BROADBAND = ((0.6, 7.35 * F_R, 0.4), (0.4, 113.6 * F_R, 1.9))  # (amplitude, Hz, phase)
DELTA = sum(a for a, _, _ in BROADBAND)
CONTACT_RATIO = 3.0  # impact window +- 1.5 mesh periods (+- 60 samples)


def _loads():
    n = int(REVS * FS / F_R)
    t = np.arange(n) / FS
    mesh = A1 * np.cos(2 * np.pi * F_M * t) + A2 * np.cos(4 * np.pi * F_M * t)
    b = sum(a * np.cos(2 * np.pi * f * t + ph) for a, f, ph in BROADBAND)
    healthy = 43e3 + mesh + b
    w = int(3 * FS / F_M)                      # 120 samples, even: centre at w // 2
    k = np.arange(w + 1) - w // 2              # symmetric about the crest
    burst = P * 0.5 * (1 + np.cos(2 * np.pi * k / w)) * np.cos(2 * np.pi * F_M * k / FS)
    centres = 480 + 1600 * np.arange(REVS)     # 0.3 rev in, on a crest (multiple of 40)
    cracked = healthy.copy()
    for c in centres:
        cracked[c - w // 2:c + w // 2 + 1] += burst
    return t, healthy, cracked, centres / FS


@pytest.fixture(scope="module")
def metrics():
    _, h, x, centres = _loads()
    ah = analyze(h, FS, teeth=[Z], shaft_frequency=F_R)
    a = analyze(x, FS, teeth=[Z], shaft_frequency=F_R)
    return case_metrics("working", x, a, h, ah, contact_ratio=CONTACT_RATIO), h, x, centres


def test_impact_ratio_is_the_closed_form(metrics):
    m, h, x, _ = metrics
    # Bound on what the broadband part and the mean removal add to any sample of d, d_h.
    dp = DELTA + max(abs(x.mean() - 43e3), abs(h.mean() - 43e3))
    assert m.impact_count == REVS
    lo, hi = (S + P - dp) / (S + dp), (S + P + dp) / (S - dp)
    assert lo <= m.impact_ratio <= hi
    assert (hi - lo) / ((S + P) / S) < 4e-3  # the bound is tight: 1.25 +- 0.15 %
    assert (S - dp) / (S + dp) <= m.far_field_ratio <= (S + dp) / (S - dp)


def test_impacts_are_found_at_the_bursts_one_revolution_apart(metrics):
    m, _, _, centres = metrics
    # The residual is exactly periodic in the revolution away from the record ends (the
    # bursts and the removed mesh harmonics both are), so every impact sits at the same
    # offset from its burst: the fitted period is 1/f_r to rounding; 1e-9 leaves room
    # for the spline's end pieces, whose influence decays by 0.27 per sample.
    assert m.impact_period == pytest.approx(1 / F_R, rel=1e-9)
    assert m.impact_period_std < 1e-9 / F_R
    assert np.max(np.abs(m.impact_times - centres)) <= 2 / FS  # within two samples


def test_residual_is_kept_for_plots_but_not_written(metrics):
    m, h, x, _ = metrics
    e = mesh_residual((x - x.mean()) - (h - h.mean()), FS, mesh_frequency=F_M,
                      shaft_frequency=F_R)
    np.testing.assert_array_equal(m.residual, e)
    d = m.to_dict()
    assert "residual" not in d and "impact_ratio" in d
