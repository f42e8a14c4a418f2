"""The analytic outline derivatives and the Jacobian of the compliance integrals.

``profile_point_d`` returns the outline point with its analytic derivatives (fillet:
d/dg of the generated trochoid; involute: d/dr); the tooth compliance kernel takes its
Jacobian dy/dp from it instead of the former central difference (``profile_dy``,
step 1e-7). These tests check the derivatives against Richardson-extrapolated central
differences of the outline point itself (independent of the derivative formulas) and
the Gauss sums of the kernel
against the same sums taken with the extrapolated Jacobian and with the former
central difference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gearsim.geometry import _kernels as G
from gearsim.geometry.gear import Gear
from gearsim.model import example
from gearsim.stiffness import _kernels as K
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.tooth import ToothModel, gauss_rule

# Two Richardson levels on central differences of steps h, h/2, h/4 leave a truncation
# error O(h^6) (h = 1e-3 rad on the fillet, 1e-3 r on the involute, at most 1/40 of the
# distance to the base circle, where the involute's derivatives grow like
# (r - r_b)^(1/2 - k)) and a round-off of about 3 eps |(x, y)| / (h/4) = 3e-11 of
# |(dx, dy)| (|(x, y)| ~ r ~ 25 m_n, |dx/dg| >= ~0.38 m_n at the root): observed max
# 6.4e-11 on these gears. The former central difference (step 1e-7) misses by
# 2.6e-8 to 8.4e-8 here (2.6e-7 on the 125-tooth Table-1 output gear), so the bound
# also tells the two apart.
DERIV_RTOL = 1e-9
# A Gauss sum with the extrapolated Jacobian against the kernel's: the Jacobians agree
# to DERIV_RTOL, the points and energies are the same.
SUM_RTOL = 1e-9


def _gears() -> dict[str, Gear]:
    spur = example("spur-19-48").train.gears
    return {
        "spur-19": spur[0],
        "spur-48": spur[1],
        "table1-input (helical, transverse)": example("idler-table1").train.gears[0],
        "shifted-17": Gear(teeth=17, normal_module=3e-3, profile_shift=0.4, name="p17"),
    }


GEARS = _gears()


def _richardson(seg: int, p: float, prof: np.ndarray) -> np.ndarray:
    """(dx/dp, dy/dp) by two Richardson levels on central differences of the point."""
    h = 1e-3 if seg == 0 else 1e-3 * prof[G.P_R]
    if seg == 1:
        h = min(h, (p - prof[G.P_RB]) / 40.0)

    def cd(step: float) -> np.ndarray:
        a = np.array(G.profile_point(seg, p + step, prof))
        b = np.array(G.profile_point(seg, p - step, prof))
        return (a - b) / (2.0 * step)

    d1, d2, d3 = cd(h), cd(0.5 * h), cd(0.25 * h)
    r1 = (4.0 * d2 - d1) / 3.0
    r2 = (4.0 * d3 - d2) / 3.0
    return (16.0 * r2 - r1) / 15.0


def _segments(prof: np.ndarray) -> list[tuple[int, float, float]]:
    return [(0, prof[G.P_AN], 0.5 * math.pi), (1, prof[G.P_RF], prof[G.P_RA])]


@pytest.mark.parametrize("name", list(GEARS))
def test_derivatives_match_richardson(name):
    prof = ToothModel(GEARS[name]).profile.packed
    worst = 0.0
    for seg, lo, hi in _segments(prof):
        # interior parameters (the central differences straddle p); the fillet ends
        # are included (its formula is smooth past both), the involute's base end not
        ps = np.linspace(lo, hi, 241)
        if seg == 1:
            ps = ps[1:]
        for p in ps:
            x, y, dx, dy = G.profile_point_d(seg, float(p), prof)
            assert (x, y) == G.profile_point(seg, float(p), prof)  # one point
            ref = _richardson(seg, float(p), prof)
            err = np.abs(ref - (dx, dy)).max() / math.hypot(dx, dy)
            worst = max(worst, err)
    assert worst < DERIV_RTOL, worst


def test_involute_below_base_circle_is_the_clipped_point():
    """Below r_b the point is clipped to the base circle: the derivatives are the
    clipped function's, (sin psi_b, cos psi_b)."""
    prof = ToothModel(GEARS["spur-19"]).profile.packed
    rb = prof[G.P_RB]
    x, y, dx, dy = G.involute_point_d(0.99 * rb, prof)
    assert (x, y) == G.involute_point(0.99 * rb, prof)
    assert (dx, dy) == (math.sin(prof[G.P_PSIB]), math.cos(prof[G.P_PSIB]))


def _pieces(prof, rec, rc):
    """Outline pieces below contact radius rc: whole segments, and the cracked range."""
    out = [(0, 0.5 * math.pi, prof[G.P_AN], False), (1, prof[G.P_RF], rc, False)]
    seg_lo, p_lo = int(rec[K.C_SEGLO]), rec[K.C_PLO]
    seg_hi, p_hi = int(rec[K.C_SEGHI]), rec[K.C_PHI]
    if seg_lo == seg_hi:
        cracked = [(seg_lo, p_lo, p_hi)]
    else:
        cracked = [(0, p_lo, prof[G.P_AN]), (1, prof[G.P_RF], p_hi)]
    for seg, pa, pb in cracked:
        if seg == 1:
            pb = min(pb, rc)
        if pb != pa:
            out.append((seg, pa, pb, True))
    return out


@pytest.mark.parametrize("name", list(GEARS))
def test_gauss_sums_against_extrapolated_and_former_jacobian(name):
    """The kernel's Gauss sum on each piece (healthy segments, the cracked range under
    both crack-face models) against the same sum taken in Python with (a) the
    extrapolated Jacobian: within SUM_RTOL; (b) the former central difference
    (``profile_dy``, the previous implementation): within that difference's own
    error, sum of w |e| |dy_fd - dy_ref| |half|, plus SUM_RTOL."""
    gear = GEARS[name]
    tm = ToothModel(gear)
    prof = tm.profile.packed
    e_mod, g_mod = tm.beam_moduli
    nodes, weights = gauss_rule(16)
    depth = 0.4 * gear.normal_module
    rec = crack_record(tm.profile, Crack(gear=gear.name, depth=depth), depth, 1)
    moved = 0.0
    for rc in np.linspace(prof[G.P_RF] * 1.01, prof[G.P_RA] * 0.999, 5):
        ar = math.acos(min(prof[G.P_RB] / rc, 1.0))
        xc, yc = G.involute_point(float(rc), prof)
        a1 = ar - math.atan2(xc, yc)
        fb, fa = math.cos(a1), math.sin(a1)
        for seg, pa, pb, cracked in _pieces(prof, rec, float(rc)):
            for model in (K.MODEL_OPEN, K.MODEL_CONTACT):
                acc = np.zeros(3)
                K._integrate_piece(seg, pa, pb, cracked, rec, model, prof, fb, fa, xc, yc,
                                   e_mod, g_mod, nodes, weights, acc)
                half = 0.5 * (pb - pa)
                mid = 0.5 * (pb + pa)
                s_ref = np.zeros(3)
                s_fd = np.zeros(3)
                bound = np.zeros(3)
                for t, w in zip(nodes, weights, strict=True):
                    p = mid + half * t
                    x, y = G.profile_point(seg, p, prof)
                    en = np.array(K._section_energy(x, y, cracked, rec, model, fb, fa, xc,
                                                    yc, e_mod, g_mod))
                    d_ref = _richardson(seg, p, prof)[1]
                    d_fd = G.profile_dy(seg, p, prof)[1]
                    s_ref += en * abs(d_ref * half) * w
                    s_fd += en * abs(d_fd * half) * w
                    bound += np.abs(en) * abs(d_fd - d_ref) * abs(half) * w
                scale = np.abs(acc).max()
                np.testing.assert_allclose(acc, s_ref, rtol=SUM_RTOL, atol=SUM_RTOL * scale)
                assert np.all(np.abs(acc - s_fd) <= bound + SUM_RTOL * np.abs(acc))
                nz = acc != 0.0
                moved = max(moved, float(np.max(np.abs(s_fd[nz] / acc[nz] - 1.0))))
            if not cracked:
                break  # the model only matters on the cracked range
    # the former Jacobian's error is of the order of its round-off, eps r / 1e-7
    assert moved < 1e-6, moved
