"""Compiled kernels of the potential-energy tooth compliance (numba, floats only).

Per unit face width (L = 1 m) and unit contact force, for a contact point at radius
``rc`` on the involute, the kernel integrates over the tooth from the root circle to
the height of the contact point, with fixed Gauss-Legendre rules in the outline's own
parameters (fillet angle, involute radius), the Jacobian dy/dp at each node analytic
(:func:`gearsim.geometry._kernels.profile_point_d`, computed with the point):

    1/k_b = int (F_b (y_c - y) - F_a x_c)^2 / (E I_y) dy       (bending, seed eq. 4)
    1/k_s = int 1.2 F_b^2 / (G A_y) dy                           (shear, seed eq. 6)
    1/k_a = int F_a^2 / (E A_y) dy                               (axial compression, seed
                                                                 eq. 5 with E: the printed
                                                                 1.2 and G are a misprint)

with F_b = cos(a1), F_a = sin(a1), a1 = alpha_r - psi(r_c) the angle of the contact
force to the normal of the tooth centre line, A_y = 2 h L, I_y = (2h)^3 L / 12; and the
fillet-foundation compliance of Sainsot, Velex & Duverger (2004), seed eq. 7,

    1/k_f = cos^2(a1) / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a1)].

Cracked sections (limiting-line model, Tian 2004, seed eqs. 10-11): between the crack
tip height and the height ``g_c`` where the line through the tip parallel to the centre
line meets the outline, the part of the section between that line (at signed distance
h_c from the centre line, positive on the cracked side) and the cracked flank is lost.
Past the centre line (h_c = -h_q < 0, a crack through the centre line, Tian 2004, Wu,
Zuo & Parey 2008: A_x = (h_x - h_q) L, I_x = (h_x - h_q)^3 L / 12) the same formulas hold
with h_c < 0 and the line reaches the tip circle (``g_c`` = top); the records of
:mod:`gearsim.stiffness.crack` keep h + h_c > 0 on every section (a crack that would
cut the tooth off is refused there):

* ``open`` model: A = (h_c + h) L, I = (h_c + h)^3 L / 12, moment about the centre
  line (the seed's equations as printed);
* ``contact`` model: the lost part still carries normal stress where it is compressed
  (frictionless crack faces: no shear). The effective section is [-h, c] (s towards the
  cracked flank) with c in [h_c, h] fixed by zero stress at s = c:
  c = 2h + 3 M_s / N; normal-stress energy M_e^2/(E I_e) + N^2/(E A_e) with the moment
  M_e about the effective centroid; shear on (h_c + h) L.

Under the contact model the integrand has a kink where the state changes (closed /
partly closed / open); each cracked piece is cut there so that the fixed rule stays
exact. The state is sampled at N_SCAN + 1 points of the piece, and each change is cut
where a bisection of N_BISECT steps on the state puts it (to the double). The cut is
that double, so the result does not depend on how it is found (with the former
central-difference Jacobian a node moved by one double changed the compliance by up to
~1e-10; with the analytic one, by round-off). :func:`_locate_change` finds the same
double with a secant search on the closure stresses and a replay of the bisection where
round-off can flip the state (about 5 x fewer outline evaluations), and a batch keeps
the scan samples of the pieces whose ends come from the crack record (the same for all
its contact points).

The mesh law of the tables with tip-corner contacts
(:func:`gearsim.stiffness.mesh.extended_law`, docs/stiffness.md section 4c) has its
active-set solve here too: :func:`extended_law_solve` (and
:func:`extended_law_solve_threads`) solve, for every position of a mesh cycle at once,
the tridiagonal compliance systems of the pairs of each slice by elimination
(:func:`tridiagonal_solve`, the Thomas algorithm) and update the set of closed tip
corners. They repeat the numpy implementation they replace operation for operation
(the sums over a position in numpy's pairwise order, :func:`pairwise_sum`), so the
tables are the same to the last bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from gearsim.geometry._kernels import (
    P_AN,
    P_RF,
    P_RROOT,
    P_THF,
    P_YROOT,
    involute_point,
    profile_point,
    profile_point_d,
)

# crack record layout (one per slice of the cracked tooth)
C_ACTIVE = 0  # 1.0 when a crack is present
C_SIDE = 1  # +1 crack on the loaded flank (tension side), -1 on the unloaded flank
C_HC = 2  # signed distance of the limiting line from the centre line, < 0 past it [m]
C_YLO = 3  # lower end of the cracked range (crack tip height, >= root) [m]
C_YHI = 4  # upper end g_c of the cracked range [m]
C_SEGLO = 5  # outline segment of C_YLO (0 fillet, 1 involute)
C_PLO = 6  # outline parameter of C_YLO
C_SEGHI = 7
C_PHI = 8
C_SIZE = 9

MODEL_OPEN = 0
MODEL_CONTACT = 1

# closure changes of the contact model: the state is sampled at N_SCAN + 1 points of a
# cracked piece and each change cut where a bisection of N_BISECT steps puts it
N_SCAN = 24
N_BISECT = 60
SCAN_SLOTS = 64  # cracked pieces whose scan samples a batch keeps
_WINDOW_ULPS = 16.0  # least round-off band of a located change [doubles]
_SLOPE_ULPS = 1048576.0  # least bracket whose secant gives the stress's slope [doubles]
_NOISE_SAFETY = 4.0  # round-off band / (round-off of the stress / its slope)


@njit(cache=True)
def _section_energy(h, y, cracked, cr, model, fb, fa, xc, yc, e_mod, g_mod):
    """Energy densities (bending, shear, axial) per unit force^2 and length at height y."""
    mom = fb * (yc - y) - fa * xc
    if not cracked:
        w = 2.0 * h
        return mom * mom * 12.0 / (e_mod * w * w * w), 1.2 * fb * fb / (g_mod * w), \
            fa * fa / (e_mod * w)
    hc = cr[C_HC]
    w_int = hc + h
    shear = 1.2 * fb * fb / (g_mod * w_int)
    if model == MODEL_OPEN:
        return mom * mom * 12.0 / (e_mod * w_int ** 3), shear, fa * fa / (e_mod * w_int)
    # contact model: find the load-carrying extent c in [hc, h]
    n = -fa
    ms = cr[C_SIDE] * mom
    # fully closed: stress at s = h of the full section
    sig_h = n / (2.0 * h) + 1.5 * ms / (h * h)
    if sig_h <= 0.0:
        c = h
    else:
        s0 = 0.5 * (hc - h)
        sig_hc = n / w_int + 6.0 * (ms - s0 * n) / (w_int * w_int)
        if sig_hc >= 0.0:
            c = hc
        else:
            c = 2.0 * h + 3.0 * ms / n
            if c < hc:
                c = hc
            elif c > h:
                c = h
    we = c + h
    s0 = 0.5 * (c - h)
    me = ms - s0 * n
    return me * me * 12.0 / (e_mod * we ** 3), shear, n * n / (e_mod * we)


@njit(cache=True)
def _integrate_piece(seg, pa, pb, cracked, cr, model, prof, fb, fa, xc, yc, e_mod, g_mod,
                     nodes, weights, acc):
    """Add the Gauss-Legendre integral over outline parameters [pa, pb] to ``acc``."""
    half = 0.5 * (pb - pa)
    mid = 0.5 * (pb + pa)
    for k in range(nodes.shape[0]):
        p = mid + half * nodes[k]
        x, y, _, dydp = profile_point_d(seg, p, prof)
        jac = abs(dydp * half) * weights[k]
        eb, es, ea = _section_energy(x, y, cracked, cr, model, fb, fa, xc, yc, e_mod, g_mod)
        acc[0] += eb * jac
        acc[1] += es * jac
        acc[2] += ea * jac


@njit(cache=True)
def _closure_state(h, y, cr, fb, fa, xc, yc):
    """0 crack closed, 1 partly closed, 2 open (contact model) at height y."""
    mom = fb * (yc - y) - fa * xc
    n = -fa
    ms = cr[C_SIDE] * mom
    if n / (2.0 * h) + 1.5 * ms / (h * h) <= 0.0:
        return 0
    hc = cr[C_HC]
    w_int = hc + h
    s0 = 0.5 * (hc - h)
    if n / w_int + 6.0 * (ms - s0 * n) / (w_int * w_int) >= 0.0:
        return 2
    return 1


@njit(cache=True)
def _closure_eval(h, y, cr, fb, fa, xc, yc):
    """Closure state and the two stresses that decide it, at height y.

    The same expressions as :func:`_closure_state` (so the same state, bit for bit),
    returning also sig_h, the normal stress at s = h of the full section, and sig_hc,
    the stress at s = h_c of the section [-h, h_c] (per unit force and width [1/m^2]);
    both are continuous along the outline, the state is their sign pattern.

    Returns
    -------
    tuple
        (state, sig_h, sig_hc); sig_hc = -inf where h + h_c = 0 (the records keep
        h + h_c > 0 on the cracked range).
    """
    mom = fb * (yc - y) - fa * xc
    n = -fa
    ms = cr[C_SIDE] * mom
    sig_h = n / (2.0 * h) + 1.5 * ms / (h * h)
    hc = cr[C_HC]
    w_int = hc + h
    if w_int != 0.0:
        s0 = 0.5 * (hc - h)
        sig_hc = n / w_int + 6.0 * (ms - s0 * n) / (w_int * w_int)
    else:
        sig_hc = -math.inf
    if sig_h <= 0.0:
        st = 0
    elif sig_hc >= 0.0:
        st = 2
    else:
        st = 1
    return st, sig_h, sig_hc


@njit(cache=True)
def _closure_which(st_lo, a_h, a_hc, b_h, b_hc):
    """The stress whose sign change ends closure state ``st_lo`` first on [a, b].

    Closed (0) ends where sig_h > 0; any state ends in closed where sig_h <= 0;
    partly closed (1) ends in open where sig_hc >= 0, open (2) in partly closed where
    sig_hc < 0. When both stresses have changed sign at ``b``, the one whose linear
    interpolation crosses nearer ``a`` (the search switches if that guess is wrong).

    Parameters
    ----------
    st_lo
        Closure state at ``a``.
    a_h, a_hc, b_h, b_hc
        sig_h and sig_hc at ``a`` and at ``b`` [1/m^2].

    Returns
    -------
    int
        +-1 (sig_h) or +-2 (sig_hc), signed so that the stress times the sign is >= 0
        while ``st_lo`` holds.
    """
    if st_lo == 0:
        return -1
    s_hc = -2 if st_lo == 1 else 2
    c_hc = b_hc >= 0.0 if st_lo == 1 else b_hc < 0.0
    if b_h <= 0.0 and c_hc:
        d_h = a_h - b_h
        d_hc = a_hc - b_hc
        if d_h != 0.0 and d_hc != 0.0 and a_hc / d_hc < a_h / d_h:
            return s_hc
        return 1
    if c_hc:
        return s_hc
    return 1


@njit(cache=True)
def _closure_fn(which, sig_h, sig_hc):
    """The signed stress named by :func:`_closure_which` [1/m^2] (smooth along the
    outline; it steers the search of a change, the state decides every bracket)."""
    if which == -1:
        return -sig_h
    if which == 1:
        return sig_h
    if which == -2:
        return -sig_hc
    return sig_hc


@njit(cache=True)
def _closure_noise(h, y, cr, fb, fa, xc, yc):
    """Round-off bound of sig_h and sig_hc at an outline point (h, y) [1/m^2].

    The outline point carries the round-off of coordinates of the size of the radius
    (taken as 8 spacings of the doubles at y, in h and in y), propagated with the
    stresses' partial derivatives (finite differences over 1 nm), plus 16 spacings of
    the stresses' own terms.

    Returns
    -------
    tuple of float
        Bounds on the error of sig_h and of sig_hc.
    """
    dl = 1e-9
    err = 8.0 * _ulp(y)
    _, f1, f2 = _closure_eval(h, y, cr, fb, fa, xc, yc)
    _, h1, h2 = _closure_eval(h + dl, y, cr, fb, fa, xc, yc)
    _, y1, y2 = _closure_eval(h, y + dl, cr, fb, fa, xc, yc)
    n = -fa
    ms = cr[C_SIDE] * (fb * (yc - y) - fa * xc)
    w_int = cr[C_HC] + h
    eps16 = 16.0 * 2.220446049250313e-16
    e1 = (abs(h1 - f1) + abs(y1 - f1)) * (err / dl) \
        + eps16 * (abs(n / (2.0 * h)) + abs(1.5 * ms / (h * h)))
    e2 = (abs(h2 - f2) + abs(y2 - f2)) * (err / dl)
    if w_int > 0.0:
        e2 += eps16 * (abs(n / w_int) + abs(6.0 * ms / (w_int * w_int))
                       + abs(3.0 * (cr[C_HC] - h) * n / (w_int * w_int)))
    return e1, e2


@njit(cache=True)
def _ulp(x):
    """Spacing of the doubles at |x| (x != 0) [units of x]."""
    return math.ldexp(1.0, math.frexp(abs(x))[1] - 53)


@njit(cache=True)
def new_scan_cache(slots):
    """Empty store of closure-scan samples for ``slots`` cracked pieces.

    The closure scan samples the outline at fixed parameters of a piece whose ends come
    from the crack record (not from the contact point), so the contact points of a batch
    share them; the store keeps them per (segment, start, end).

    Parameters
    ----------
    slots
        Number of pieces kept (replaced in turn when full).

    Returns
    -------
    tuple of ndarray
        Keys (slots, 3) (segment, start, end; NaN when empty), points
        (slots, 2, N_SCAN + 1) (half width x, height y [m]), and the next slot (1,).
    """
    keys = np.full((slots, 3), np.nan)
    pts = np.empty((slots, 2, N_SCAN + 1))
    nxt = np.zeros(1, np.int64)
    return keys, pts, nxt


@njit(cache=True)
def _scan_samples(seg, pa, pb, prof, keys, pts, nxt):
    """Slot of ``keys``/``pts`` holding the outline at the scan's N_SCAN + 1 parameters.

    The parameters pa + (pb - pa) i / N_SCAN, i = 0 .. N_SCAN (the same expression, so
    the same points, as a scan computing them in place); computed on a miss.
    """
    for j in range(keys.shape[0]):
        if keys[j, 0] == seg and keys[j, 1] == pa and keys[j, 2] == pb:
            return j
    j = nxt[0]
    nxt[0] = (j + 1) % keys.shape[0]
    x0, y0 = profile_point(seg, pa, prof)
    pts[j, 0, 0] = x0
    pts[j, 1, 0] = y0
    for i in range(1, N_SCAN + 1):
        p = pa + (pb - pa) * i / N_SCAN
        x1, y1 = profile_point(seg, p, prof)
        pts[j, 0, i] = x1
        pts[j, 1, i] = y1
    keys[j, 0] = seg
    keys[j, 1] = pa
    keys[j, 2] = pb
    return j


@njit(cache=True)
def _bisect_change(seg, a, b, st_lo, xb, yb, st_b, cr, prof, fb, fa, xc, yc):
    """The cut of a change of closure state on [a, b] by N_BISECT bisection steps.

    The definition of the cut (state(a) = ``st_lo`` != state(b) = ``st_b``): the half
    whose ends still differ is kept, and the cut is the middle of the final bracket
    (adjacent doubles). Returns as :func:`_locate_change`.
    """
    for _ in range(N_BISECT):
        m = 0.5 * (a + b)
        if m == a or m == b:  # adjacent doubles: no further change
            break
        x, y = profile_point(seg, m, prof)
        st = _closure_state(x, y, cr, fb, fa, xc, yc)
        if st == st_lo:
            a = m
        else:
            b = m
            xb = x
            yb = y
            st_b = st
    return 0.5 * (a + b), b, xb, yb, st_b


@njit(cache=True)
def _locate_change(seg, a, b, st_lo, xa, ya, xb, yb, cr, prof, fb, fa, xc, yc):
    """Where the closure state leaves ``st_lo`` on [a, b]: the cut of a 60-step bisection.

    The cut is defined by a bisection on the discrete state (:func:`_bisect_change`:
    N_BISECT halvings of [a, b] keeping the half whose ends differ, closing to adjacent
    doubles) and is reproduced bit for bit with about 8 to 20 outline evaluations
    instead of 61 (each a latency-bound chain of trigonometric calls):

    1. the search starts a little past ``a`` (twice the round-off band below; ``a`` may
       be a change just cut, next to which the state flickers where the bisection
       never looks unless the change sought is there); if the state has changed there
       already, or [a, b] is too short, the bisection itself is run;
    2. the change is bracketed to [lo, hi] (state(lo) = ``st_lo``, state(hi) !=
       ``st_lo``, every bracket end decided by the state itself) by the secant method
       on the stress whose sign change ends ``st_lo`` (:func:`_closure_which`; switched
       if an iterate shows the other one), kept at least tol / 2 inside the bracket,
       nudged across the change when two iterates fall on one side, with a bisection
       step when three steps have not halved the bracket, until the bracket is within
       the round-off band (at least _WINDOW_ULPS doubles);
    3. the bisection is replayed: a midpoint more than the band beyond lo on the side
       of ``a`` keeps the state, one more than the band beyond hi on the side of ``b``
       has changed, and only the midpoints in between, where round-off of the outline
       point may flip the state, are evaluated. The band is _NOISE_SAFETY times the
       stresses' round-off (:func:`_closure_noise`) over their slope along the outline
       (the secant of the last bracket wider than _SLOPE_ULPS doubles): 1e3-2e3 doubles
       on the Table-1 fillet, where the widest flicker seen is 64.

    The parameter may decrease from ``a`` to ``b`` (the fillet angle runs from the root
    down). A flicker wider than the band would make the cut differ from the bisection's
    by a few doubles (the compliance by ~1e-10 relative); the tests compare both.

    Parameters
    ----------
    seg
        Outline segment (0 fillet, 1 involute).
    a, b
        Ends of the bracket: state(a) = ``st_lo``, state(b) != ``st_lo``.
    st_lo
        Closure state at ``a``.
    xa, ya, xb, yb
        Outline points at ``a`` and ``b`` [m].
    cr, prof, fb, fa, xc, yc
        As :func:`_section_energy` and the contact point.

    Returns
    -------
    tuple
        (cut, b', x(b'), y(b'), state(b')): the cut 0.5 (a' + b') of the final bracket
        [a', b'] and its upper end, where the next piece's state is read.
    """
    st_b, s1, s2 = _closure_eval(xb, yb, cr, fb, fa, xc, yc)
    _, t1, t2 = _closure_eval(xa, ya, cr, fb, fa, xc, yc)
    # the stress whose sign change ends st_lo, signed >= 0 while st_lo holds
    which = _closure_which(st_lo, t1, t2, s1, s2)
    flo = _closure_fn(which, t1, t2)
    fhi = _closure_fn(which, s1, s2)
    hi_h = s1
    hi_hc = s2
    # lo keeps st_lo, hi does not; the parameter runs either way (sgn)
    sgn = 1.0 if b > a else -1.0
    tol = _WINDOW_ULPS * _ulp(max(abs(a), abs(b)))
    slope = abs(fhi - flo) / abs(b - a)
    # ``a`` may lie at a change just cut (the state flickers with round-off next to
    # it, where the bisection never looks unless the change sought is there): the
    # search starts past that band, at a point that keeps the state
    e1, e2 = _closure_noise(xa, ya, cr, fb, fa, xc, yc)
    err = max(e1, e2)
    skip = tol
    if slope > 0.0:
        skip = max(tol, 2.0 * _NOISE_SAFETY * err / slope)
    if not 4.0 * skip < abs(b - a):
        return _bisect_change(seg, a, b, st_lo, xb, yb, st_b, cr, prof, fb, fa, xc, yc)
    lo = a + sgn * skip
    xlo, ylo = profile_point(seg, lo, prof)
    st, t1, t2 = _closure_eval(xlo, ylo, cr, fb, fa, xc, yc)
    if st != st_lo:  # the change is next to a: the bisection itself
        return _bisect_change(seg, a, b, st_lo, xb, yb, st_b, cr, prof, fb, fa, xc, yc)
    flo = _closure_fn(which, t1, t2)
    lo_h = t1
    lo_hc = t2
    hi = b
    # secant on the two newest iterates (x1 newest), kept inside the bracket; when
    # the newest two fall on the same side, a nudge of 1 % of the last correction
    # (at least tol / 2) puts the next iterate across the change
    x0 = hi
    f0 = fhi
    x1 = lo
    f1 = flo
    same_side = False
    w_ref = abs(hi - lo)
    count = 0
    for _ in range(100):
        width = abs(hi - lo)
        if width > _SLOPE_ULPS * tol / _WINDOW_ULPS:  # far above round-off: a sound slope
            slope = abs(fhi - flo) / width
        wnd = abs(b - a)
        if slope > 0.0:
            wnd = min(wnd, max(tol, _NOISE_SAFETY * err / slope))
        if width <= wnd:
            break
        # bisection when three steps have not halved the bracket
        count += 1
        force = False
        if count == 3:
            force = width > 0.5 * w_ref
            w_ref = width
            count = 0
        m = math.nan
        if f1 != f0:
            m = x1 - f1 * ((x1 - x0) / (f1 - f0))
        if force or not math.isfinite(m):
            m = 0.5 * (lo + hi)
        else:
            if same_side:
                # towards the end the two newest iterates left alone
                nudge = max(0.5 * tol, 0.01 * abs(m - x1))
                m += nudge * sgn if x1 == lo else -nudge * sgn
            # at least tol / 2 inside the bracket
            d = (m - lo) * sgn
            if d < 0.5 * tol:
                d = 0.5 * tol
            elif d > width - 0.5 * tol:
                d = width - 0.5 * tol
            m = lo + sgn * d
            if not (min(lo, hi) < m < max(lo, hi)):
                m = 0.5 * (lo + hi)
        x, y = profile_point(seg, m, prof)
        st, t1, t2 = _closure_eval(x, y, cr, fb, fa, xc, yc)
        f = _closure_fn(which, t1, t2)
        if st == st_lo:
            same_side = x1 == lo
            lo = m
            flo = f
            lo_h = t1
            lo_hc = t2
            xlo = x
            ylo = y
        else:
            same_side = x1 == hi
            hi = m
            fhi = f
            hi_h = t1
            hi_hc = t2
            if f >= 0.0 and st_lo != 0:
                # the state ended by the other stress: search on that one
                which = (-2 if st_lo == 1 else 2) if abs(which) == 1 else 1
                flo = _closure_fn(which, lo_h, lo_hc)
                fhi = _closure_fn(which, hi_h, hi_hc)
                same_side = False
                x0 = lo
                f0 = flo
                x1 = hi
                f1 = fhi
                continue
        x0 = x1
        f0 = f1
        x1 = m
        f1 = f
    # the window: where round-off of the outline point may flip the state
    e1, e2 = _closure_noise(xlo, ylo, cr, fb, fa, xc, yc)
    wnd = abs(b - a)
    if slope > 0.0:
        wnd = min(wnd, max(tol, _NOISE_SAFETY * max(e1, e2) / slope))
    w_lo = lo - sgn * wnd
    w_hi = hi + sgn * wnd
    # the bisection replayed
    aa = a
    bb = b
    known = True
    for _ in range(N_BISECT):
        m = 0.5 * (aa + bb)
        if m == aa or m == bb:  # closed to adjacent doubles: no further change
            break
        if (m - w_lo) * sgn <= 0.0:
            aa = m
        elif (m - w_hi) * sgn >= 0.0:
            bb = m
            known = False
        else:
            x, y = profile_point(seg, m, prof)
            st = _closure_state(x, y, cr, fb, fa, xc, yc)
            if st == st_lo:
                aa = m
            else:
                bb = m
                xb = x
                yb = y
                st_b = st
                known = True
    if not known:
        xb, yb = profile_point(seg, bb, prof)
        st_b = _closure_state(xb, yb, cr, fb, fa, xc, yc)
    return 0.5 * (aa + bb), bb, xb, yb, st_b


@njit(cache=True)
def _integrate_contact_piece(seg, pa, pb, cr, prof, fb, fa, xc, yc, e_mod, g_mod, nodes,
                             weights, acc, keys, pts, nxt):
    """Cracked piece under the contact model, split where the closure state changes.

    The integrand has a kink where the crack goes from closed to partly closed to open;
    splitting there keeps the fixed Gauss-Legendre rule at full accuracy. The state is
    sampled at N_SCAN + 1 points of the piece (kept in the scan store for the next
    contact point) and each change located by :func:`_locate_change`.
    """
    j = _scan_samples(seg, pa, pb, prof, keys, pts, nxt)
    lo = pa
    st_lo = _closure_state(pts[j, 0, 0], pts[j, 1, 0], cr, fb, fa, xc, yc)
    for i in range(1, N_SCAN + 1):
        p = pa + (pb - pa) * i / N_SCAN
        xp = pts[j, 0, i]
        yp = pts[j, 1, i]
        st = _closure_state(xp, yp, cr, fb, fa, xc, yc)
        if st == st_lo:
            continue
        a = pa + (pb - pa) * (i - 1) / N_SCAN
        xa = pts[j, 0, i - 1]
        ya = pts[j, 1, i - 1]
        # a sample interval may hold two changes (closed -> partly closed -> open when
        # the partly closed band is narrow): cut at each one in turn
        for _ in range(4):
            if st == st_lo:
                break
            cut, b, xb, yb, st_b = _locate_change(seg, a, p, st_lo, xa, ya, xp, yp, cr,
                                                  prof, fb, fa, xc, yc)
            _integrate_piece(seg, lo, cut, True, cr, MODEL_CONTACT, prof, fb, fa, xc, yc,
                             e_mod, g_mod, nodes, weights, acc)
            lo = cut
            st_lo = st_b
            a = b
            xa = xb
            ya = yb
    _integrate_piece(seg, lo, pb, True, cr, MODEL_CONTACT, prof, fb, fa, xc, yc, e_mod, g_mod,
                     nodes, weights, acc)


@njit(cache=True)
def _segment(seg, pa, pb, cr, model, prof, fb, fa, xc, yc, e_mod, g_mod, nodes, weights, acc,
             keys, pts, nxt):
    """Integrate one outline segment, split at the ends of the cracked range."""
    # break points on this segment, in the direction pa -> pb
    b0 = pa
    b1 = pb
    nb = 0
    bp0 = 0.0
    bp1 = 0.0
    if cr[C_ACTIVE] > 0.0:
        lo_in = cr[C_SEGLO] == seg and (cr[C_PLO] - pa) * (cr[C_PLO] - pb) < 0.0
        hi_in = cr[C_SEGHI] == seg and (cr[C_PHI] - pa) * (cr[C_PHI] - pb) < 0.0
        if lo_in:
            bp0 = cr[C_PLO]
            nb += 1
        if hi_in:
            if nb == 0:
                bp0 = cr[C_PHI]
            else:
                bp1 = cr[C_PHI]
            nb += 1
        if nb == 2 and abs(bp1 - pa) < abs(bp0 - pa):
            tmp = bp0
            bp0 = bp1
            bp1 = tmp
    lo = b0
    for i in range(nb + 1):
        if i < nb:
            hi = bp0 if i == 0 else bp1
        else:
            hi = b1
        if hi != lo:
            pm = 0.5 * (lo + hi)
            xm, ym = profile_point(seg, pm, prof)
            cracked = cr[C_ACTIVE] > 0.0 and cr[C_YLO] <= ym <= cr[C_YHI]
            if cracked and model == MODEL_CONTACT:
                _integrate_contact_piece(seg, lo, hi, cr, prof, fb, fa, xc, yc, e_mod,
                                         g_mod, nodes, weights, acc, keys, pts, nxt)
            else:
                _integrate_piece(seg, lo, hi, cracked, cr, model, prof, fb, fa, xc, yc,
                                 e_mod, g_mod, nodes, weights, acc)
        lo = hi


@njit(cache=True)
def tooth_compliance(prof, rc, cr, model, e_mod, g_mod, e_found, sainsot, nodes, weights,
                     out):
    """Compliances (bending, shear, axial, foundation) of one tooth, unit width [m/N].

    :func:`tooth_compliance_scan` with a scan store of its own; see there.
    """
    keys, pts, nxt = new_scan_cache(2)
    tooth_compliance_scan(prof, rc, cr, model, e_mod, g_mod, e_found, sainsot, nodes,
                          weights, out, keys, pts, nxt)


@njit(cache=True)
def tooth_compliance_scan(prof, rc, cr, model, e_mod, g_mod, e_found, sainsot, nodes,
                          weights, out, keys, pts, nxt):
    """Compliances (bending, shear, axial, foundation) of one tooth, unit width [m/N].

    Parameters
    ----------
    prof
        Packed outline (``gearsim.geometry._kernels``).
    rc
        Contact radius on the involute [m].
    cr
        Crack record (``C_*`` layout); ``cr[C_ACTIVE] = 0`` for a healthy tooth.
    model
        ``MODEL_OPEN`` or ``MODEL_CONTACT``.
    e_mod, g_mod
        Moduli of the beam terms (plane stress E or E/(1-nu^2); G) [Pa].
    e_found
        Young's modulus of the Sainsot formula [Pa].
    sainsot
        (L*, M*, P*, Q*) of this gear [-].
    nodes, weights
        Gauss-Legendre rule on [-1, 1].
    out
        Array of 4, filled with the compliances for L = 1 m [m/N].
    keys, pts, nxt
        Store of the closure scan's samples (:func:`new_scan_cache`), shared by the
        contact points of a batch; the results do not depend on its content.

    References
    ----------
    Seed eqs. 4-7 and 10-11; Yang & Lin (1987); Tian (2004); Chen & Shao (2011);
    Sainsot, Velex & Duverger (2004).
    """
    rb = prof[1]
    ca = rb / rc
    if ca > 1.0:
        ca = 1.0
    ar = math.acos(ca)
    xc, yc = involute_point(rc, prof)
    psi = math.atan2(xc, yc)
    a1 = ar - psi
    fb = math.cos(a1)
    fa = math.sin(a1)
    acc = np.zeros(3)
    # fillet from the root (g = pi/2) up to the form circle (g = alpha_n)
    _segment(0, 0.5 * math.pi, prof[P_AN], cr, model, prof, fb, fa, xc, yc, e_mod, g_mod,
             nodes, weights, acc, keys, pts, nxt)
    # involute from the form circle to the contact point
    if rc > prof[P_RF]:
        _segment(1, prof[P_RF], rc, cr, model, prof, fb, fa, xc, yc, e_mod, g_mod, nodes,
                 weights, acc, keys, pts, nxt)
    out[0] = acc[0]
    out[1] = acc[1]
    out[2] = acc[2]
    # Sainsot et al. (2004) fillet-foundation term
    thf = prof[P_THF]
    rf = prof[P_RROOT]
    sf = 2.0 * rf * thf
    uf = (yc - xc * math.tan(a1)) - prof[P_YROOT]
    ratio = uf / sf
    t = math.tan(a1)
    out[3] = (fb * fb / e_found) * (sainsot[0] * ratio * ratio + sainsot[1] * ratio
                                    + sainsot[2] * (1.0 + sainsot[3] * t * t))


@njit(cache=True, parallel=False)
def tooth_compliance_batch(prof, rcs, crs, model, e_mod, g_mod, e_found, sainsot, nodes,
                           weights, out):
    """:func:`tooth_compliance` for many contact radii.

    Parameters
    ----------
    prof
        Packed outline.
    rcs
        Contact radii, shape (n,) [m]; entries <= 0 give NaN rows.
    crs
        Crack records, shape (n, C_SIZE), one per radius.
    model, e_mod, g_mod, e_found, sainsot, nodes, weights
        As :func:`tooth_compliance`.
    out
        Array (n, 4), filled with the compliances for L = 1 m [m/N].

    Returns
    -------
    ndarray
        ``out``.
    """
    buf = np.empty(4)
    keys, pts, nxt = new_scan_cache(SCAN_SLOTS)
    for i in range(rcs.shape[0]):
        if rcs[i] <= 0.0:
            out[i, :] = np.nan
            continue
        tooth_compliance_scan(prof, rcs[i], crs[i], model, e_mod, g_mod, e_found, sainsot,
                              nodes, weights, buf, keys, pts, nxt)
        out[i, 0] = buf[0]
        out[i, 1] = buf[1]
        out[i, 2] = buf[2]
        out[i, 3] = buf[3]
    return out


@njit(cache=True, parallel=True)
def tooth_compliance_batch_threads(prof, rcs, crs, model, e_mod, g_mod, e_found, sainsot,
                                   nodes, weights, out, chunks):
    """:func:`tooth_compliance_batch` on ``chunks`` threads (numba ``prange``).

    The radii are cut into ``chunks`` contiguous runs, each computed by
    :func:`tooth_compliance_batch` with its own closure-scan store; the store memoises
    samples that do not depend on the contact point, so every row is the serial kernel's,
    bit for bit.

    Parameters
    ----------
    prof, rcs, crs, model, e_mod, g_mod, e_found, sainsot, nodes, weights, out
        As :func:`tooth_compliance_batch`.
    chunks
        Number of runs (the threads numba may use).

    Returns
    -------
    ndarray
        ``out``.
    """
    n = rcs.shape[0]
    for c in prange(chunks):
        lo = c * n // chunks
        hi = (c + 1) * n // chunks
        tooth_compliance_batch(prof, rcs[lo:hi], crs[lo:hi], model, e_mod, g_mod, e_found,
                               sainsot, nodes, weights, out[lo:hi])
    return out


__all__ = [
    "C_SIZE",
    "MODEL_CONTACT",
    "MODEL_OPEN",
    "P_AN",
    "extended_law_solve",
    "extended_law_solve_threads",
    "pairwise_sum",
    "tooth_compliance",
    "tooth_compliance_batch",
    "tooth_compliance_batch_threads",
    "tridiagonal_solve",
]


@njit(cache=True)
def rectangular_beam_compliance(half_width, length, a1, xc, e_mod, g_mod, nodes, weights):
    """Bending, shear, axial compliances of a cantilever of constant section, L = 1 m.

    The same section energies and Gauss-Legendre mapping as the tooth kernel, on a
    straight beam 0 <= y <= ``length`` of width 2 ``half_width`` loaded at its free end;
    used to check the kernel against the Timoshenko closed forms.

    Parameters
    ----------
    half_width
        Half width h of the section [m].
    length
        Beam length [m].
    a1
        Angle of the unit end load to the normal of the beam axis [rad].
    xc
        Eccentricity of the load from the beam axis [m].
    e_mod, g_mod
        E and G [Pa].
    nodes, weights
        Gauss-Legendre rule on [-1, 1].

    Returns
    -------
    ndarray, shape (3,)
        Bending, shear, axial compliance [m/N].
    """
    fb = math.cos(a1)
    fa = math.sin(a1)
    acc = np.zeros(3)
    half = 0.5 * length
    dummy = np.zeros(C_SIZE)
    for k in range(nodes.shape[0]):
        y = half + half * nodes[k]
        eb, es, ea = _section_energy(half_width, y, False, dummy, MODEL_OPEN, fb, fa, xc,
                                     length, e_mod, g_mod)
        acc[0] += eb * half * weights[k]
        acc[1] += es * half * weights[k]
        acc[2] += ea * half * weights[k]
    return acc


# --- the mesh law's active-set solve (gearsim.stiffness.mesh.extended_law) -------------


@njit(cache=True)
def _pairwise_block(x, lo, n):
    """numpy's pairwise sum of ``x[lo:lo + n]`` for n <= 128 (one block, no split).

    Parameters
    ----------
    x
        Values [any unit].
    lo
        First index.
    n
        Number of values, <= 128.

    Returns
    -------
    float
        The sum, in the order of :func:`pairwise_sum` [unit of ``x``].
    """
    if n < 8:
        res = -0.0
        for i in range(lo, lo + n):
            res += x[i]
        return res
    r0 = x[lo]
    r1 = x[lo + 1]
    r2 = x[lo + 2]
    r3 = x[lo + 3]
    r4 = x[lo + 4]
    r5 = x[lo + 5]
    r6 = x[lo + 6]
    r7 = x[lo + 7]
    i = 8
    end = n - n % 8
    while i < end:
        k = lo + i
        r0 += x[k]
        r1 += x[k + 1]
        r2 += x[k + 2]
        r3 += x[k + 3]
        r4 += x[k + 4]
        r5 += x[k + 5]
        r6 += x[k + 6]
        r7 += x[k + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += x[lo + i]
        i += 1
    return res


@njit(cache=True)
def _pairwise_split(n):
    """Length of the first half of numpy's split of a run of values.

    Parameters
    ----------
    n
        Length of the run, > 128.

    Returns
    -------
    int
        n // 2 rounded down to a multiple of 8.
    """
    n2 = n // 2
    return n2 - n2 % 8


@njit(cache=True)
def pairwise_sum(x, lo, n):
    """Sum of ``x[lo:lo + n]`` in numpy's pairwise order (``np.add.reduce``).

    numpy sums a contiguous run of float64 by blocks of at most 128 values, each with
    eight interleaved partial sums combined as ((r0 + r1) + (r2 + r3)) + ((r4 + r5) +
    (r6 + r7)), a longer run split in two at a multiple of 8 near its middle and the
    halves' sums added (``pairwise_sum`` in numpy/_core/src/umath/loops_utils.h.src;
    Higham, The accuracy of floating point summation, SIAM J. Sci. Comput. 14 (1993)
    783-799). Repeating that order makes a compiled sum equal numpy's to the last bit.

    Parameters
    ----------
    x
        Values, shape (>= lo + n,) [any unit].
    lo
        First index.
    n
        Number of values.

    Returns
    -------
    float
        The sum [unit of ``x``].
    """
    return _pairwise_sum(x, lo, n, np.empty((64, 3), dtype=np.int64), np.empty(64))


@njit(cache=True)
def _pairwise_sum(x, lo, n, stack, left):
    """:func:`pairwise_sum` with its work space.

    numpy's recursion is an explicit stack here (numba cannot call a recursive function
    from a parallel region): per level the run's start and length and its state (0 new,
    1 left half being summed, 2 right half being summed), and the left half's sum.

    Parameters
    ----------
    x, lo, n
        As :func:`pairwise_sum`.
    stack
        Work space, int64, shape (64, 3) (64 levels: runs up to 128 x 2^63 values).
    left
        Work space, shape (64,) [unit of ``x``].

    Returns
    -------
    float
        The sum [unit of ``x``].
    """
    if n <= 128:
        return _pairwise_block(x, lo, n)
    if n <= 256:  # one split (a table's 7 ages x 40 slices)
        n2 = _pairwise_split(n)
        return _pairwise_block(x, lo, n2) + _pairwise_block(x, lo + n2, n - n2)
    top = 0
    stack[0, 0] = lo
    stack[0, 1] = n
    stack[0, 2] = 0
    while True:
        if stack[top, 1] > 128:
            n2 = _pairwise_split(stack[top, 1])
            stack[top, 2] = 1
            stack[top + 1, 0] = stack[top, 0]
            stack[top + 1, 1] = n2
            stack[top + 1, 2] = 0
            top += 1
            continue
        v = _pairwise_block(x, stack[top, 0], stack[top, 1])
        while True:  # hand the sum up
            if top == 0:
                return v
            top -= 1
            if stack[top, 2] == 1:  # the left half: now the right one
                left[top] = v
                stack[top, 2] = 2
                n2 = _pairwise_split(stack[top, 1])
                stack[top + 1, 0] = stack[top, 0] + n2
                stack[top + 1, 1] = stack[top, 1] - n2
                stack[top + 1, 2] = 0
                top += 1
                break
            v = left[top] + v


@njit(cache=True, error_model="numpy")
def _thomas(d, o, r, x, cp, den):
    """Symmetric tridiagonal systems side by side, several right-hand sides (Thomas).

    Elimination without pivoting (Golub & Van Loan, Matrix Computations, 4th ed., 2013,
    sec. 4.3: stable for a diagonally dominant matrix, as a slice's compliance matrix
    is), in the order of the numpy implementation it replaces: c'_i = o_i / den_i,
    den_{i+1} = d_{i+1} - o_i c'_i, x'_{i+1} = (r_{i+1} - o_i x'_i) / den_{i+1}, then
    x_i = x'_i - c'_i x_{i+1} backwards. The k systems (columns) are independent and
    swept row by row together, so their division chains overlap.

    Parameters
    ----------
    d
        Diagonals, shape (m, k) [m^2/N].
    o
        Off-diagonals between rows i and i + 1, shape (m - 1, k) [m^2/N].
    r
        Right-hand sides, shape (nr, m, k) [any unit].
    x
        Out: the solutions, shape (nr, m, k) [unit of r / m^2/N].
    cp, den
        Work space, shapes (m - 1, k) [-] and (k,) [m^2/N].
    """
    m, k = d.shape
    nr = r.shape[0]
    for s in range(k):
        den[s] = d[0, s]
    for j in range(nr):
        for s in range(k):
            x[j, 0, s] = r[j, 0, s] / den[s]
    for i in range(1, m):
        for s in range(k):
            c = o[i - 1, s] / den[s]
            cp[i - 1, s] = c
            den[s] = d[i, s] - o[i - 1, s] * c
        for j in range(nr):
            for s in range(k):
                x[j, i, s] = (r[j, i, s] - o[i - 1, s] * x[j, i - 1, s]) / den[s]
    for i in range(m - 2, -1, -1):
        for j in range(nr):
            for s in range(k):
                x[j, i, s] = x[j, i, s] - cp[i, s] * x[j, i + 1, s]


@njit(cache=True, error_model="numpy")
def tridiagonal_solve(diag, off, rhs, out):
    """Symmetric tridiagonal systems along axis 1 of ``diag``, several right-hand sides.

    The compliance matrix C of the pairs of a slice (contact plus both teeth on the
    diagonal, the body cross compliance of adjacent pairs off it; docs/stiffness.md
    sections 4b, 4c) solved by :func:`_thomas` for every (row, column) of axes 0 and 2.

    Parameters
    ----------
    diag
        Diagonal, shape (n, m, k) [m^2/N].
    off
        Off-diagonal between rows i and i + 1, shape (n, m - 1, k) [m^2/N].
    rhs
        Right-hand sides, shape (n, nr, m, k) [any unit].
    out
        Array of the shape of ``rhs``, filled with the solutions C^-1 rhs
        [unit of rhs / m^2/N].

    Returns
    -------
    ndarray
        ``out``.
    """
    n, m, k = diag.shape
    cp = np.empty((max(m - 1, 0), k))
    den = np.empty(k)
    for p in range(n):
        _thomas(diag[p], off[p], rhs[p], out[p], cp, den)
    return out


@njit(cache=True, error_model="numpy")
def extended_law_solve(cdiag, act, path, cand, width, rho, s_pos, cross, coupled, force,
                       passes, q, delta):
    """Active-set solve of the mesh law with tip-corner contacts, all positions at once.

    At a position the contacts j (pair ages m, slices) with per-unit-width compliance
    matrix C per slice (``cdiag`` on the diagonal, ``cross`` between adjacent ages; no
    coupling: C diagonal), widths w, no-load separations s and closing rates rho carry
    the normal loads per unit width q >= 0 at the mesh deflection delta under the force
    F (docs/stiffness.md section 4c, "Law"): for the active (closed) set A,

        q_A = delta C_AA^-1 rho_A - C_AA^-1 (rho s)_A,
        delta = (F + w rho . C^-1 (rho s)) / (w rho . C^-1 rho),

    C_AA^-1 by :func:`_thomas`, the slices side by side (the inactive rows: 1 on the
    diagonal, no coupling, right-hand sides 0). A closed corner opens when its q <= 0;
    an open one closes when its gap rho (delta - s) - (C q) > 0 (the neighbours' loads
    through the cross compliance). The passes stop at a position when its set does not
    change (positions are independent: the numpy law's passes over all positions at
    once, which stop when no position's set changes, give each the same), after
    ``passes`` passes at most (then ``act`` holds the last update and ``q``, ``delta``
    the solve before it, as in the numpy law). Sums over a position in numpy's pairwise
    order, each product and quotient as numpy forms it: the numpy law's result to the
    last bit.

    Parameters
    ----------
    cdiag
        Compliance of each contact per unit width, contact plus both teeth, shape
        (npc, n_age, ns) [m^2/N].
    act
        In/out: the closed contacts, bool, shape (npc, n_age, ns); the start of the
        active set (the path contacts and the corners closed so far), updated.
    path
        Contacts on the path of contact (always closed), bool, shape (npc, n_age, ns).
    cand
        Tip-corner contacts that can close, bool, shape (npc, n_age, ns).
    width
        Width of each contact [m] (0: none), shape (npc, n_age, ns).
    rho
        Closing rate of each contact per unit delta [-] (1 except at a corner).
    s_pos
        No-load separation of each contact along the line of action [m] (0 except at a
        corner).
    cross
        Body cross compliance between ages m and m + 1 per unit width, shape
        (npc, n_age - 1, ns) [m^2/N]; not read unless ``coupled``.
    coupled
        Whether the pairs of a slice are coupled through ``cross``.
    force
        Line-of-action force of the mesh F [N].
    passes
        Largest number of active-set passes.
    q
        Out: normal load per unit width of each contact, shape (npc, n_age, ns) [N/m]
        (0 where open).
    delta
        Out: mesh deflection of each position along the line of action, shape (npc,)
        [m].

    Returns
    -------
    ndarray
        ``delta``.
    """
    npc, m, ns = cdiag.shape
    nn = m * ns
    d = np.empty((m, ns))
    o = np.empty((max(m - 1, 0), ns))
    cp = np.empty((max(m - 1, 0), ns))
    den = np.empty(ns)
    r = np.empty((2, m, ns))
    x = np.empty((2, m, ns))
    ca = x[0]  # C^-1 rho
    cb = x[1]  # C^-1 (rho s)
    ta = np.empty(nn)
    tb = np.empty(nn)
    stack = np.empty((64, 3), dtype=np.int64)
    left = np.empty(64)
    new = np.empty((m, ns), dtype=np.bool_)
    for p in range(npc):
        for _ in range(passes):
            if coupled:
                for i in range(m):
                    for s in range(ns):
                        on = act[p, i, s]
                        d[i, s] = cdiag[p, i, s] if on else 1.0
                        r[0, i, s] = rho[p, i, s] if on else 0.0
                        r[1, i, s] = rho[p, i, s] * s_pos[p, i, s] if on else 0.0
                for i in range(m - 1):
                    for s in range(ns):
                        o[i, s] = cross[p, i, s] if act[p, i, s] and act[p, i + 1, s] else 0.0
                _thomas(d, o, r, x, cp, den)
            else:
                for i in range(m):
                    for s in range(ns):
                        a = rho[p, i, s] / cdiag[p, i, s] if act[p, i, s] else 0.0
                        ca[i, s] = a
                        cb[i, s] = a * s_pos[p, i, s]
            k = 0
            for i in range(m):
                for s in range(ns):
                    wr = width[p, i, s] * rho[p, i, s]
                    tb[k] = wr * cb[i, s]
                    ta[k] = wr * ca[i, s]
                    k += 1
            # np.sum starts from its identity 0.0
            dl = ((force + (0.0 + _pairwise_sum(tb, 0, nn, stack, left)))
                  / (0.0 + _pairwise_sum(ta, 0, nn, stack, left)))
            delta[p] = dl
            for i in range(m):
                for s in range(ns):
                    q[p, i, s] = dl * ca[i, s] - cb[i, s] if act[p, i, s] else 0.0
            same = True
            for i in range(m):
                for s in range(ns):
                    if path[p, i, s]:
                        nw = True
                    elif not cand[p, i, s]:
                        nw = False
                    elif act[p, i, s]:
                        nw = q[p, i, s] > 0.0
                    else:  # the gap, the neighbours' loads deflecting the open corner
                        gap = rho[p, i, s] * (dl - s_pos[p, i, s])
                        if coupled:
                            if i >= 1:
                                gap = gap - cross[p, i - 1, s] * q[p, i - 1, s]
                            if i < m - 1:
                                gap = gap - cross[p, i, s] * q[p, i + 1, s]
                        nw = gap > 0.0
                    new[i, s] = nw
                    if nw != act[p, i, s]:
                        same = False
            if same:
                break
            for i in range(m):
                for s in range(ns):
                    act[p, i, s] = new[i, s]
    return delta


@njit(cache=True, parallel=True)
def extended_law_solve_threads(cdiag, act, path, cand, width, rho, s_pos, cross, coupled,
                               force, passes, q, delta, chunks):
    """:func:`extended_law_solve` on ``chunks`` threads (numba ``prange``).

    The positions are cut into ``chunks`` contiguous runs, each solved by
    :func:`extended_law_solve` with its own work space; a position's solve does not
    depend on the others', so every result is the serial kernel's, bit for bit.

    Parameters
    ----------
    cdiag, act, path, cand, width, rho, s_pos, cross, coupled, force, passes, q, delta
        As :func:`extended_law_solve` (``act``, ``q``, ``delta`` filled in place).
    chunks
        Number of runs (the threads numba may use).

    Returns
    -------
    ndarray
        ``delta`` [m].
    """
    n = cdiag.shape[0]
    for c in prange(chunks):
        lo = c * n // chunks
        hi = (c + 1) * n // chunks
        extended_law_solve(cdiag[lo:hi], act[lo:hi], path[lo:hi], cand[lo:hi], width[lo:hi],
                           rho[lo:hi], s_pos[lo:hi], cross[lo:hi], coupled, force, passes,
                           q[lo:hi], delta[lo:hi])
    return delta
