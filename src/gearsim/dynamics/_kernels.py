"""Compiled kernels of the train dynamics (numba, float arrays and scalars only).

The equations are those of :mod:`gearsim.dynamics.model`; the Python wrapper
:func:`gearsim.dynamics.simulate.run_kernel` checks and converts the inputs.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["integrate_rk4", "mesh_forces", "rhs"]


@njit(cache=True, error_model="numpy")
def _table_index(length, npc, period, c):
    """Samples (i, j) around cycle ``c`` of a periodic table and the weight of j."""
    cm = c - period * math.floor(c / period)
    pos = cm * npc
    i = int(math.floor(pos))
    w = pos - i
    if i >= length:
        i -= length
    j = i + 1
    if j >= length:
        j -= length
    return i, j, w


@njit(cache=True, inline="always", error_model="numpy")
def _table_k(tab, off, length, npc, period, c):
    """Linear periodic interpolation of table ``tab[off:off+length]`` at cycle ``c``."""
    i, j, w = _table_index(length, npc, period, c)
    return tab[off + i] * (1.0 - w) + tab[off + j] * w


@njit(cache=True, error_model="numpy")
def _listed(ptr, kx, sx, row, x):
    """Force sum k_j max(0, x - s_j) and closed stiffness of the listed contacts of a row
    (sorted by separation: the loop stops at the first open contact)."""
    f = 0.0
    kc = 0.0
    for p in range(ptr[row], ptr[row + 1]):
        g = x - sx[p]
        if g <= 0.0:
            break
        f += kx[p] * g
        kc += kx[p]
    return f, kc


@njit(cache=True, error_model="numpy")
def _contact_force(x, xd, b2, cm, ks, tab, tabz, off, length, npc, period, c, ptr, poff,
                   kx, sx):
    """Force of a mesh of contacts (docs/contacts.md; :mod:`gearsim.dynamics.model`)."""
    i, j, w = _table_index(length, npc, period, c)
    ka = ks * (tab[off + i] * (1.0 - w) + tab[off + j] * w)
    kz = ks * (tabz[off + i] * (1.0 - w) + tabz[off + j] * w)
    f0, k0 = _listed(ptr, kx, sx, poff + i, x)
    f1, k1 = _listed(ptr, kx, sx, poff + j, x)
    fx = ks * (f0 * (1.0 - w) + f1 * w)
    kc = ks * (k0 * (1.0 - w) + k1 * w)
    frac_all = 1.0 if ka <= 0.0 else 1.0 / ka
    if b2 == np.inf:  # linear mesh: zero-separation contacts stay bilateral
        return kz * x + fx + cm * xd * (kz + kc) * frac_all
    kzc = kz if x > 0.0 else 0.0
    closed = kzc + kc
    if closed > 0.0:
        return max(kzc * x + fx + cm * xd * closed * frac_all, 0.0)
    if x <= -b2:  # back flanks (healthy, every contact of the table)
        return min(ka * (x + b2) + cm * xd, 0.0)
    return 0.0


@njit(cache=True, error_model="numpy")
def mesh_forces(t, q, v, V, kappa, kscale, cm, clear, tab, tab_off, tab_len, tab_npc,
                tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr, ptr_off, kx,
                sx, f_out, d_out):
    """Mesh forces f_i [N] (into ``f_out``) and deflections V_i.q [m] (into ``d_out``)."""
    nm = V.shape[0]
    n = V.shape[1]
    for i in range(nm):
        d = 0.0
        dd = 0.0
        for j in range(n):
            d += V[i, j] * q[j]
            dd += V[i, j] * v[j]
        d_out[i] = d
        e = e0[i]
        ed = 0.0
        for h in range(h_amp.shape[1]):
            a = h_amp[i, h]
            if a != 0.0:
                arg = h_om[i, h] * t + h_ph[i, h]
                e += a * math.sin(arg)
                ed += a * h_om[i, h] * math.cos(arg)
        x = d - e
        xd = dd - ed
        b2 = clear[i]
        if c_on[i] != 0:
            f_out[i] = kappa[i] * _contact_force(
                x, xd, b2, cm[i], kscale[i], tab, tabz, tab_off[i], tab_len[i], tab_npc[i],
                tab_period[i], fm * t + phase[i], ptr, ptr_off[i], kx, sx)
            continue
        k = kscale[i] * _table_k(tab, tab_off[i], tab_len[i], tab_npc[i], tab_period[i],
                                 fm * t + phase[i])
        if b2 == np.inf:  # linear mesh
            f = k * x + cm[i] * xd
        elif x > 0.0:  # working flanks in contact: contact force cannot pull
            f = max(k * x + cm[i] * xd, 0.0)
        elif x <= -b2:  # back flanks in contact: it cannot push
            f = min(k * (x + b2) + cm[i] * xd, 0.0)
        else:  # teeth separated
            f = 0.0
        f_out[i] = kappa[i] * f


@njit(cache=True, error_model="numpy")
def rhs(t, q, v, minv, kb, cb, fext, V, kappa, kscale, cm, clear, tab, tab_off, tab_len,
        tab_npc, tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr, ptr_off, kx,
        sx, a_out, f_out, d_out):
    """Accelerations M^-1 (F_ext - K_b q - C_b q' - sum V_i f_i) into ``a_out``."""
    mesh_forces(t, q, v, V, kappa, kscale, cm, clear, tab, tab_off, tab_len, tab_npc,
                tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr, ptr_off, kx,
                sx, f_out, d_out)
    n = q.size
    nm = V.shape[0]
    for j in range(n):
        s = fext[j] - kb[j] * q[j] - cb[j] * v[j]
        for i in range(nm):
            s -= V[i, j] * f_out[i]
        a_out[j] = s * minv[j]


@njit(cache=True, error_model="numpy")
def integrate_rk4(q0, v0, t0, dt, n_steps, rec_start, rec_every, n_rec, qlim, minv, kb, cb,
                  fext, V, kappa, kscale, cm, clear, tab, tab_off, tab_len, tab_npc,
                  tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr, ptr_off, kx,
                  sx):
    """Classical fixed-step RK4 from t0 over ``n_steps`` steps of ``dt``.

    Records q, q' and the mesh forces at steps ``rec_start + r rec_every`` (r < n_rec),
    i.e. at instantaneous sample times. Stops when a coordinate is not finite or exceeds
    ``qlim`` in magnitude.

    Returns
    -------
    status : 0 finished, 1 diverged
    step : the step at which it stopped
    rec_q, rec_v : (n_rec, n) recorded state
    rec_f : (n_rec, n_mesh) recorded mesh forces
    q, v : final state
    """
    n = q0.size
    nm = V.shape[0]
    q = q0.copy()
    v = v0.copy()
    qt = np.empty(n)
    vt = np.empty(n)
    k1q = np.empty(n)
    k1v = np.empty(n)
    k2q = np.empty(n)
    k2v = np.empty(n)
    k3q = np.empty(n)
    k3v = np.empty(n)
    k4v = np.empty(n)
    f = np.empty(nm)
    d = np.empty(nm)
    rec_q = np.zeros((n_rec, n))
    rec_v = np.zeros((n_rec, n))
    rec_f = np.zeros((n_rec, nm))
    h2 = 0.5 * dt
    h6 = dt / 6.0
    r = 0
    next_rec = rec_start
    for s in range(n_steps + 1):
        t = t0 + s * dt
        rhs(t, q, v, minv, kb, cb, fext, V, kappa, kscale, cm, clear, tab, tab_off, tab_len,
            tab_npc, tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr, ptr_off,
            kx, sx, k1v, f, d)
        if s == next_rec and r < n_rec:
            for j in range(n):
                rec_q[r, j] = q[j]
                rec_v[r, j] = v[j]
            for i in range(nm):
                rec_f[r, i] = f[i]
            r += 1
            next_rec += rec_every
        if s == n_steps:
            break
        for j in range(n):
            k1q[j] = v[j]
            qt[j] = q[j] + h2 * v[j]
            vt[j] = v[j] + h2 * k1v[j]
        rhs(t + h2, qt, vt, minv, kb, cb, fext, V, kappa, kscale, cm, clear, tab, tab_off,
            tab_len, tab_npc, tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr,
            ptr_off, kx, sx, k2v, f, d)
        for j in range(n):
            k2q[j] = vt[j]
            qt[j] = q[j] + h2 * vt[j]
            vt[j] = v[j] + h2 * k2v[j]
        rhs(t + h2, qt, vt, minv, kb, cb, fext, V, kappa, kscale, cm, clear, tab, tab_off,
            tab_len, tab_npc, tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr,
            ptr_off, kx, sx, k3v, f, d)
        for j in range(n):
            k3q[j] = vt[j]
            qt[j] = q[j] + dt * vt[j]
            vt[j] = v[j] + dt * k3v[j]
        rhs(t + dt, qt, vt, minv, kb, cb, fext, V, kappa, kscale, cm, clear, tab, tab_off,
            tab_len, tab_npc, tab_period, fm, phase, e0, h_amp, h_om, h_ph, tabz, c_on, ptr,
            ptr_off, kx, sx, k4v, f, d)
        bad = False
        for j in range(n):
            q[j] += h6 * (k1q[j] + 2.0 * k2q[j] + 2.0 * k3q[j] + vt[j])
            v[j] += h6 * (k1v[j] + 2.0 * k2v[j] + 2.0 * k3v[j] + k4v[j])
            if not (abs(q[j]) <= qlim):  # also catches NaN
                bad = True
        if bad:
            return 1, s + 1, rec_q, rec_v, rec_f, q, v
    return 0, n_steps, rec_q, rec_v, rec_f, q, v
