"""The cracked tooth's fast closure search against its definition and an oracle.

Under the ``contact`` crack-face model the kernel cuts each cracked piece where the
closure state changes. The cut is defined by a bisection of N_BISECT steps on the
discrete state (``_bisect_change``); ``_locate_change`` finds the same double with a
superlinear search on the closure stresses and replays the bisection only where
round-off can flip the state. These tests hold it to that definition bit for bit (the
results then do not depend on the search; with the former finite-difference Jacobian
of the Gauss rule a cut moved by one double changed the compliance by 1e-10, with the
analytic one by round-off), check the batch's shared scan store against single
evaluations, the compliance against the independent quad oracle, and its continuity in
the contact radius across closure boundaries.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from gearsim.geometry._kernels import P_AN, P_RA, P_RB, P_RF, involute_point, profile_point
from gearsim.geometry.gear import Gear
from gearsim.model import example
from gearsim.stiffness import _kernels as K
from gearsim.stiffness.crack import Crack, crack_record
from gearsim.stiffness.reference import reference_compliance
from gearsim.stiffness.tooth import ToothModel, gauss_rule

# kernel (16-point rules) against adaptive quad: see tests/test_reference_independent.py
ORACLE_RTOL = 1e-6


def _spur_pinion() -> Gear:
    """19-tooth pinion of the built-in 19/48 spur pair (Tian 2004), m 3.2 mm, b 16 mm."""
    return example("spur-19-48").train.gears[0]


def _table1_input() -> Gear:
    """Input gear of the built-in Table-1 idler train (z 39, m_n 6 mm, beta 13 deg)."""
    return example("idler-table1").train.gears[0]


def _load(prof: np.ndarray, rc: float) -> tuple[float, float, float, float]:
    """(F_b, F_a, x_c, y_c) of a unit load at contact radius rc, as the kernel has them."""
    ar = math.acos(min(prof[P_RB] / rc, 1.0))
    xc, yc = involute_point(rc, prof)
    a1 = ar - math.atan2(xc, yc)
    return math.cos(a1), math.sin(a1), xc, yc


def _cracked_pieces(prof: np.ndarray, rec: np.ndarray, rc: float) -> list[tuple]:
    """(segment, start, end) of the cracked range below the contact radius."""
    seg_lo, p_lo = int(rec[K.C_SEGLO]), rec[K.C_PLO]
    seg_hi, p_hi = int(rec[K.C_SEGHI]), rec[K.C_PHI]
    if seg_lo == seg_hi:
        pieces = [(seg_lo, p_lo, p_hi)]
    else:
        pieces = [(0, p_lo, prof[P_AN]), (1, prof[P_RF], p_hi)]
    out = []
    for seg, pa, pb in pieces:
        if seg == 1:
            pb = min(pb, rc)
            if pb <= pa:
                continue
        out.append((seg, pa, pb))
    return out


def _changes(gear: Gear, depth: float, side: int, flank: str, n_radii: int) -> int:
    """Compare _locate_change with _bisect_change at every change a scan finds."""
    tm = ToothModel(gear, closure="contact")
    prof = tm.profile.packed
    rec = crack_record(tm.profile, Crack(gear=gear.name, depth=depth, flank=flank), depth,
                       side)
    n = 0
    for rc in np.linspace(prof[P_RF] * 1.001, prof[P_RA] * 0.999, n_radii):
        fb, fa, xc, yc = _load(prof, float(rc))
        for seg, pa, pb in _cracked_pieces(prof, rec, float(rc)):
            params = [pa + (pb - pa) * i / K.N_SCAN for i in range(K.N_SCAN + 1)]
            pts = [profile_point(seg, p, prof) for p in params]
            st_lo = K._closure_state(*pts[0], rec, fb, fa, xc, yc)
            for i in range(1, K.N_SCAN + 1):
                st = K._closure_state(*pts[i], rec, fb, fa, xc, yc)
                a, (xa, ya) = params[i - 1], pts[i - 1]
                p, (xp, yp) = params[i], pts[i]
                for _ in range(4):
                    if st == st_lo:
                        break
                    fast = K._locate_change(seg, a, p, st_lo, xa, ya, xp, yp, rec, prof,
                                            fb, fa, xc, yc)
                    ref = K._bisect_change(seg, a, p, st_lo, xp, yp, st, rec, prof, fb, fa,
                                           xc, yc)
                    assert fast == ref, (rc, seg, a, p, st_lo)
                    n += 1
                    _, a, xa, ya, st_lo = ref
    return n


@pytest.mark.parametrize("make,depth,side,flank", [
    (_table1_input, 1e-3, 1, "working"), (_table1_input, 2e-3, 1, "working"),
    (_table1_input, 2e-3, -1, "working"), (_table1_input, 4e-3, 1, "non-working"),
    (_table1_input, 8e-3, -1, "working"), (_table1_input, 11e-3, 1, "working"),
    (_spur_pinion, 1e-3, 1, "working"), (_spur_pinion, 2.5e-3, -1, "working"),
    (_spur_pinion, 4e-3, 1, "non-working")])
def test_located_cut_is_the_bisection_cut(make, depth, side, flank):
    """Every closure change found by the scan: the same cut, end, point and state."""
    assert _changes(make(), depth, side, flank, 25) > 0


def test_closure_eval_agrees_with_closure_state():
    """The search's state (with both stresses) is the integrator's, at many points."""
    tm = ToothModel(_table1_input(), closure="contact")
    prof = tm.profile.packed
    rec = crack_record(tm.profile, Crack(gear="input", depth=3e-3), 3e-3, 1)
    for rc in np.linspace(prof[P_RF] * 1.001, prof[P_RA] * 0.999, 9):
        load = _load(prof, float(rc))
        for seg, pa, pb in _cracked_pieces(prof, rec, float(rc)):
            for p in np.linspace(pa, pb, 301):
                x, y = profile_point(seg, float(p), prof)
                assert K._closure_eval(x, y, rec, *load)[0] == K._closure_state(x, y, rec,
                                                                                *load)


@pytest.mark.parametrize("closure", ["contact", "open"])
def test_batch_store_equals_single_evaluations(closure):
    """The batch's shared scan store (also overfull: more pieces than its slots) gives
    the single evaluations bit for bit, with records changing from row to row."""
    tm = ToothModel(_table1_input(), closure=closure)
    prof = tm.profile.packed
    crack = Crack(gear="input", depth=2e-3)
    depths = np.linspace(0.5e-3, 9e-3, K.SCAN_SLOTS + 6)
    recs = np.array([crack_record(tm.profile, crack, float(d), 1 if i % 3 else -1)
                     for i, d in enumerate(depths)])
    radii = np.linspace(prof[P_RF] * 1.001, prof[P_RA] * 0.999, 7)
    rr = np.repeat(radii, depths.size)
    rec_rows = np.tile(recs, (radii.size, 1))
    nodes, weights = gauss_rule(tm.gauss_points)
    e, g = tm.beam_moduli
    args = (tm.model_code, e, g, tm.gear.material.youngs_modulus, tm.sainsot, nodes, weights)
    batch = K.tooth_compliance_batch(prof, rr, rec_rows, *args, np.empty((rr.size, 4)))
    one = np.empty(4)
    for i in range(rr.size):
        K.tooth_compliance(prof, rr[i], rec_rows[i], *args, one)
        assert np.array_equal(batch[i], one), i
    again = K.tooth_compliance_batch(prof, rr[::-1].copy(), rec_rows[::-1].copy(), *args,
                                     np.empty((rr.size, 4)))
    assert np.array_equal(again[::-1], batch)


@pytest.mark.parametrize("chunks", [2, 3, 7])
def test_threaded_batch_equals_the_serial_batch(chunks):
    """The batch on numba's threads (runs of radii, each with its own scan store) is the
    serial batch bit for bit, healthy and cracked rows mixed."""
    tm = ToothModel(_table1_input(), closure="contact")
    prof = tm.profile.packed
    crack = Crack(gear="input", depth=2e-3)
    radii = np.linspace(prof[P_RF] * 1.001, prof[P_RA] * 0.999, 301)
    recs = np.array([crack_record(tm.profile, crack, 0.5e-3 + 1e-5 * i, 1 if i % 4 else -1)
                     if i % 5 else np.zeros(K.C_SIZE) for i in range(radii.size)])
    nodes, weights = gauss_rule(tm.gauss_points)
    e, g = tm.beam_moduli
    args = (tm.model_code, e, g, tm.gear.material.youngs_modulus, tm.sainsot, nodes, weights)
    serial = K.tooth_compliance_batch(prof, radii, recs, *args, np.empty((radii.size, 4)))
    threaded = K.tooth_compliance_batch_threads(prof, radii, recs, *args,
                                                np.empty((radii.size, 4)), chunks)
    assert np.array_equal(threaded, serial)


def test_mesh_table_on_two_threads_is_the_one_thread_table():
    """A whole cracked revolution table (Table-1 mesh I), computed in a process with two
    numba threads (the batches above THREADED_MIN_RADII take the threaded kernel) and
    with one: the same numbers bit for bit. A separate process, as the suite's workers
    run with one numba thread."""
    import subprocess
    import sys

    prog = ("import numba, numpy as np\n"
            "from gearsim.model import example\n"
            "import gearsim.system.train as tm, gearsim.stiffness.tooth as to\n"
            "tr = example('idler-table1').train\n"
            "out = []\n"
            "for n in (1, 2):\n"
            "    numba.set_num_threads(n)\n"
            "    tm._TABLES.clear(); to._healthy_compliance.cache_clear()\n"
            "    out.append(tr.mesh_stiffness(0).k.copy())\n"
            "print(numba.get_num_threads(), np.array_equal(*out), out[0].size)\n")
    env = {**__import__("os").environ, "NUMBA_NUM_THREADS": "2"}
    res = subprocess.run([sys.executable, "-c", prog], capture_output=True, text=True,
                         env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["2", "True", "1560"]


@pytest.mark.parametrize("make,depth,side", [
    (_table1_input, 2e-3, 1), (_table1_input, 8e-3, -1), (_table1_input, 11e-3, 1),
    (_spur_pinion, 2.5e-3, -1)])
def test_cracked_compliance_matches_quad_oracle(make, depth, side):
    """Contact closure, cracks up to past the centre line: kernel = adaptive quad."""
    gear = make()
    tm = ToothModel(gear, closure="contact")
    crack = Crack(gear=gear.name, depth=depth)
    rec = crack_record(tm.profile, crack, depth, side)
    radii = np.linspace(tm.profile.form_radius * 1.002, gear.tip_radius * 0.999, 3)
    got = tm.compliance(radii, rec)
    past_centre = rec[K.C_HC] < 0.0  # the oracle's own geometry stops at the centre line
    for r, row in zip(radii, got, strict=True):
        if past_centre:  # its integration and closure still its own, on the record's h_c
            ref = reference_compliance(tm, float(r), rec)
        else:
            ref = reference_compliance(tm, float(r), crack=crack, side=side)
        assert_allclose(row, ref, rtol=ORACLE_RTOL, err_msg=f"r = {r}")


@pytest.mark.parametrize("depth,side", [(2e-3, 1), (2e-3, -1), (6e-3, 1), (11e-3, -1)])
def test_continuous_across_closure_boundaries(depth, side):
    """Along the contact radius the closure changes enter and leave the cracked range;
    the beam compliance stays smooth: no second difference of a 4001-point sweep above
    10 x their median (a jump of 1e-6 relative would be ~4 x the median's size)."""
    gear = _table1_input()
    tm = ToothModel(gear, closure="contact")
    rec = crack_record(tm.profile, Crack(gear=gear.name, depth=depth), depth, side)
    r = np.linspace(tm.profile.form_radius * 1.002, gear.tip_radius * 0.999, 4001)
    c = tm.compliance(r, rec)[:, :3].sum(axis=1)
    d2 = np.abs(np.diff(c, 2)) / c[1:-1]
    assert d2.max() < 10.0 * np.median(d2)


def test_integrand_continuous_at_a_cut():
    """Section energies on both sides of a located cut (adjacent doubles) agree."""
    tm = ToothModel(_table1_input(), closure="contact")
    prof = tm.profile.packed
    rec = crack_record(tm.profile, Crack(gear="input", depth=2e-3), 2e-3, 1)
    e, g = tm.beam_moduli
    checked = 0
    for rc in np.linspace(prof[P_RF] * 1.001, prof[P_RA] * 0.999, 15):
        fb, fa, xc, yc = _load(prof, float(rc))
        for seg, pa, pb in _cracked_pieces(prof, rec, float(rc)):
            params = [pa + (pb - pa) * i / K.N_SCAN for i in range(K.N_SCAN + 1)]
            states = [K._closure_state(*profile_point(seg, p, prof), rec, fb, fa, xc, yc)
                      for p in params]
            for i in range(1, K.N_SCAN + 1):
                if states[i] == states[i - 1]:
                    continue
                xa, ya = profile_point(seg, params[i - 1], prof)
                xp, yp = profile_point(seg, params[i], prof)
                _, b, _, _, _ = K._locate_change(seg, params[i - 1], params[i],
                                                 states[i - 1], xa, ya, xp, yp, rec, prof,
                                                 fb, fa, xc, yc)
                a = np.nextafter(b, params[i - 1])
                ea = K._section_energy(*profile_point(seg, a, prof), True, rec,
                                       K.MODEL_CONTACT, fb, fa, xc, yc, e, g)
                eb = K._section_energy(*profile_point(seg, b, prof), True, rec,
                                       K.MODEL_CONTACT, fb, fa, xc, yc, e, g)
                assert_allclose(ea, eb, rtol=1e-9)
                checked += 1
    assert checked > 0
