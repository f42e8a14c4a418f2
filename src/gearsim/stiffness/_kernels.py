"""Compiled kernels of the potential-energy tooth compliance (numba, floats only).

Per unit face width (L = 1 m) and unit contact force, for a contact point at radius
``rc`` on the involute, the kernel integrates over the tooth from the root circle to
the height of the contact point, with fixed Gauss-Legendre rules in the outline's own
parameters (fillet angle, involute radius):

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
    profile_dy,
    profile_point,
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
        x, y = profile_point(seg, p, prof)
        dxdp, dydp = profile_dy(seg, p, prof)
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
def _integrate_contact_piece(seg, pa, pb, cr, prof, fb, fa, xc, yc, e_mod, g_mod, nodes,
                             weights, acc):
    """Cracked piece under the contact model, split where the closure state changes.

    The integrand has a kink where the crack goes from closed to partly closed to open;
    splitting there keeps the fixed Gauss-Legendre rule at full accuracy.
    """
    n_samp = 24
    lo = pa
    x0, y0 = profile_point(seg, pa, prof)
    st_lo = _closure_state(x0, y0, cr, fb, fa, xc, yc)
    for i in range(1, n_samp + 1):
        p = pa + (pb - pa) * i / n_samp
        x1, y1 = profile_point(seg, p, prof)
        st = _closure_state(x1, y1, cr, fb, fa, xc, yc)
        a = pa + (pb - pa) * (i - 1) / n_samp
        # a sample interval may hold two changes (closed -> partly closed -> open when
        # the partly closed band is narrow): cut at each one in turn
        for _ in range(4):
            if st == st_lo:
                break
            b = p
            for _ in range(60):
                m = 0.5 * (a + b)
                xm, ym = profile_point(seg, m, prof)
                if _closure_state(xm, ym, cr, fb, fa, xc, yc) == st_lo:
                    a = m
                else:
                    b = m
            cut = 0.5 * (a + b)
            _integrate_piece(seg, lo, cut, True, cr, MODEL_CONTACT, prof, fb, fa, xc, yc,
                             e_mod, g_mod, nodes, weights, acc)
            lo = cut
            xb, yb = profile_point(seg, b, prof)
            st_lo = _closure_state(xb, yb, cr, fb, fa, xc, yc)
            a = b
    _integrate_piece(seg, lo, pb, True, cr, MODEL_CONTACT, prof, fb, fa, xc, yc, e_mod, g_mod,
                     nodes, weights, acc)


@njit(cache=True)
def _segment(seg, pa, pb, cr, model, prof, fb, fa, xc, yc, e_mod, g_mod, nodes, weights, acc):
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
                                         g_mod, nodes, weights, acc)
            else:
                _integrate_piece(seg, lo, hi, cracked, cr, model, prof, fb, fa, xc, yc,
                                 e_mod, g_mod, nodes, weights, acc)
        lo = hi


@njit(cache=True)
def tooth_compliance(prof, rc, cr, model, e_mod, g_mod, e_found, sainsot, nodes, weights,
                     out):
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
             nodes, weights, acc)
    # involute from the form circle to the contact point
    if rc > prof[P_RF]:
        _segment(1, prof[P_RF], rc, cr, model, prof, fb, fa, xc, yc, e_mod, g_mod, nodes,
                 weights, acc)
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
    for i in range(rcs.shape[0]):
        if rcs[i] <= 0.0:
            out[i, :] = np.nan
            continue
        tooth_compliance(prof, rcs[i], crs[i], model, e_mod, g_mod, e_found, sainsot, nodes,
                         weights, buf)
        out[i, 0] = buf[0]
        out[i, 1] = buf[1]
        out[i, 2] = buf[2]
        out[i, 3] = buf[3]
    return out


@njit(cache=True, parallel=True)
def tooth_compliance_batch_parallel(prof, rcs, crs, model, e_mod, g_mod, e_found, sainsot,
                                    nodes, weights, out):
    """Threaded variant of :func:`tooth_compliance_batch` (numba prange).

    Parameters
    ----------
    prof, rcs, crs, model, e_mod, g_mod, e_found, sainsot, nodes, weights, out
        As :func:`tooth_compliance_batch`.

    Returns
    -------
    ndarray
        ``out``.
    """
    for i in prange(rcs.shape[0]):
        buf = np.empty(4)
        if rcs[i] <= 0.0:
            for j in range(4):
                out[i, j] = np.nan
            continue
        tooth_compliance(prof, rcs[i], crs[i], model, e_mod, g_mod, e_found, sainsot, nodes,
                         weights, buf)
        for j in range(4):
            out[i, j] = buf[j]
    return out


__all__ = [
    "C_SIZE",
    "MODEL_CONTACT",
    "MODEL_OPEN",
    "P_AN",
    "tooth_compliance",
    "tooth_compliance_batch",
    "tooth_compliance_batch_parallel",
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
