"""Compiled kernels of the train dynamics (numba, float arrays and scalars only).

The equations are those of :mod:`gearsim.dynamics.model`; the Python wrapper
:func:`gearsim.dynamics.simulate.run_kernel` checks and converts the inputs.

Packed arguments (built by :func:`gearsim.dynamics.simulate._kernel_args`):

* ``dof`` (5, n): 1/M, K_b, C_b, F_ext of each coordinate and its inertial load per unit
  nominal acceleration g (speed profiles);
* ``vcol``, ``vval`` (n_mesh, w): the mesh rows V_i of the model, sparse (ELL): the
  columns and values of each row's nonzero entries, ascending, padded with column 0 and
  value 0 (w = the most nonzeros of a row). A mesh row couples only its two gears'
  coordinates, so the products V q and V^T f cost w instead of n per row; the sums run
  in the dense order, so the result is the dense one to the bit;
* ``mp`` (n_mesh, 9): kappa, kscale, c_m, clearance 2b, phase, e0, positions per
  cycle and period of each mesh's table, and its mesh frequency f_i [Hz] at the
  reference speed (the table is read at c_i = f_i tau(t) + phase_i);
* ``prof`` (n_seg, 4): the speed profile as segments (t_k, tau_k, tau'_k, tau''_k):
  nominal time tau(t) = tau_k + tau'_k (t - t_k) + tau''_k (t - t_k)^2 / 2 on
  [t_k, t_k+1), tau' = omega(t) / omega_ref (constant speed: one segment (0, 0, 1, 0),
  tau = t); ``lam`` (n_l, 2): load factor lambda(t) on F_ext, piecewise linear in t;
* ``mi`` (n_mesh, 4) int: table offset and length in ``tab``, mesh-of-contacts flag,
  offset of its rows in ``ptr``;
* ``harm`` (6, n_mesh, n_h): amplitude, angular frequency (at the reference speed: the
  argument is omega tau + phase) and phase of the STE harmonics (rows 0-2) and of the
  centre-distance change (rows 3-5);
* ``tabd``: dk/da on the samples of ``tab`` (zeros where not used): the stiffness is
  k(c) + Delta a(t) dk/da(c);
* ``tab``: the tables k (every contact); ``tabz``: k_zero of the meshes of contacts
  (``tab`` elsewhere); ``ptr``, ``cx`` (2, n): rows of listed contacts, their stiffness
  and separation (sorted by separation in each row).

Four integrators share one RK4 body (:func:`_rk4`, inlined): with or without meshes of
contacts, with or without speed and load profiles. Kept apart, the table-only,
constant-speed integrator compiles without the contact and profile code and keeps its
speed (the profile code in the same function made it 1.6x slower).

A right-hand side is two passes over the mesh rows: the parts that depend on the
nominal time only (:func:`_mesh_time`: table samples and stiffness, harmonics), then
those of the state (:func:`_mesh_state`: deflections, force laws). RK4's stages 2 and 3
are at the same time t + dt/2, so a step computes the time parts three times, not four.
Per run, :func:`_rk4` finds each row's length without the ELL padding and the rows
with nonzero harmonics: the loops skip the padding's zero products and the rows without
harmonics their harmonic loops. Each value is computed with the same operations in the
same order as row by row over the padded rows (results identical to the bit).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["integrate_rk4", "integrate_rk4_contacts", "integrate_rk4_contacts_profile",
           "integrate_rk4_profile", "mesh_forces", "nominal", "rhs"]

# columns of mp
KAPPA, KSCALE, CM, CLEAR, PHASE, E0, NPC, PERIOD, FREQ = range(9)
# columns of mi
TOFF, TLEN, CON, CROW = range(4)


@njit(cache=True, inline="always", error_model="numpy")
def _table_index(length, npc, period, c):
    """Samples (i, j) around cycle ``c`` of a periodic table and the weight of j.

    The floors stay floats (np.floor: math.floor's integer, converted back to a float for
    the products, is the same value); ``period == 1`` (most tables) skips the division
    (c / 1.0 and 1.0 * floor are exact)."""
    if period == 1.0:
        cm = c - np.floor(c)
    else:
        cm = c - period * np.floor(c / period)
    pos = cm * npc
    fl = np.floor(pos)
    w = pos - fl
    i = int(fl)
    if i >= length:
        i -= length
    j = i + 1
    if j >= length:
        j -= length
    return i, j, w


@njit(cache=True, inline="always", error_model="numpy")
def _segment(a, t):
    """Last row k of the first column of ``a`` with a[k, 0] <= t (0 before the first)."""
    lo = 0
    hi = a.shape[0] - 1
    while lo < hi:  # binary search; a single row (constant speed) does no work
        mid = (lo + hi + 1) // 2
        if a[mid, 0] <= t:
            lo = mid
        else:
            hi = mid - 1
    return lo


@njit(cache=True, inline="always", error_model="numpy")
def nominal(t, prof, lam):
    """(tau, tau', tau'', lambda) at time ``t``: nominal time of the speed profile and the
    load factor (layout of ``prof`` and ``lam`` in the module docstring)."""
    k = _segment(prof, t)
    d = t - prof[k, 0]
    tau = prof[k, 1] + prof[k, 2] * d + 0.5 * prof[k, 3] * d * d
    taud = prof[k, 2] + prof[k, 3] * d
    j = _segment(lam, t)
    load = lam[j, 1]
    if j + 1 < lam.shape[0] and t > lam[j, 0]:
        w = (t - lam[j, 0]) / (lam[j + 1, 0] - lam[j, 0])
        load = lam[j, 1] * (1.0 - w) + lam[j + 1, 1] * w
    return tau, taud, prof[k, 3], load


@njit(cache=True, inline="always", error_model="numpy")
def _contact_force(x, xd, b2, cm, ks, tab, tabz, dk, off, i, j, w, ptr, row0, cx):
    """Force of a mesh of contacts (docs/contacts.md; :mod:`gearsim.dynamics.model`);
    ``dk`` the centre-distance change of the stiffness, added to the zero-separation part."""
    ka = ks * (tab[off + i] * (1.0 - w) + tab[off + j] * w + dk)
    kz = ks * (tabz[off + i] * (1.0 - w) + tabz[off + j] * w + dk)
    # listed contacts of the two rows, each sorted by separation: stop at the first open
    fx = 0.0
    kc = 0.0
    for row, wt in ((row0 + i, 1.0 - w), (row0 + j, w)):
        p = ptr[row]
        end = ptr[row + 1]
        while p < end:
            g = x - cx[1, p]
            if g <= 0.0:
                break
            fx += wt * cx[0, p] * g
            kc += wt * cx[0, p]
            p += 1
    fx *= ks
    kc *= ks
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


@njit(cache=True, inline="always", error_model="numpy")
def _harmonic_rows(harm):
    """Harmonics in use: ``hn`` (2, n_mesh), 1 + the last harmonic with a nonzero amplitude
    of each row (STE, centre distance; 0: none), and the rows that have any."""
    nm = harm.shape[1]
    hn = np.zeros((2, nm), dtype=np.int64)
    for i in range(nm):
        for h in range(harm.shape[2]):
            if harm[0, i, h] != 0.0:
                hn[0, i] = h + 1
            if harm[3, i, h] != 0.0:
                hn[1, i] = h + 1
    return hn, np.nonzero(hn[0] + hn[1])[0]


@njit(cache=True, inline="always", error_model="numpy")
def _row_lengths(vval):
    """1 + the last nonzero entry of each ELL row (the padding after it is skipped)."""
    nz = np.zeros(vval.shape[0], dtype=np.int64)
    for i in range(vval.shape[0]):
        for p in range(vval.shape[1]):
            if vval[i, p] != 0.0:
                nz[i] = p + 1
    return nz


@njit(cache=True, inline="always", error_model="numpy")
def _mesh_time(tau, taud, mp, mi, tab, tabd, harm, hn, hrows, contacts, tm, ti):
    """The parts of the mesh forces that depend on the nominal time only: per row, into
    ``tm`` e, e', the table weight w, dk and k (meshes of tables), into ``ti`` the
    table samples (i, j).

    Every row's table first, then the rows with harmonics (STE: e, e'; centre distance:
    dk and k again): the arithmetic of each value is the same as row by row."""
    nm = mp.shape[0]
    for i in range(nm):
        off = mi[i, TOFF]
        i0, j0, w = _table_index(mi[i, TLEN], mp[i, NPC], mp[i, PERIOD],
                                 mp[i, FREQ] * tau + mp[i, PHASE])
        tm[i, 0] = mp[i, E0]
        tm[i, 1] = 0.0
        tm[i, 2] = w
        tm[i, 3] = 0.0
        ti[i, 0] = i0
        ti[i, 1] = j0
        if not (contacts and mi[i, CON] != 0):
            # dk = 0 here (the rows with harmonics are redone below): the sum with dk
            tm[i, 4] = mp[i, KSCALE] * (tab[off + i0] * (1.0 - w) + tab[off + j0] * w + 0.0)
    for r in range(hrows.size):
        i = hrows[r]
        e = mp[i, E0]
        ed = 0.0
        for h in range(hn[0, i]):
            a = harm[0, i, h]
            if a != 0.0:
                arg = harm[1, i, h] * tau + harm[2, i, h]
                e += a * math.sin(arg)
                ed += a * harm[1, i, h] * taud * math.cos(arg)
        tm[i, 0] = e
        tm[i, 1] = ed
        if hn[1, i] > 0:  # centre-distance change (eccentric gears)
            dk = 0.0
            for h in range(hn[1, i]):
                a = harm[3, i, h]
                if a != 0.0:
                    dk += a * math.sin(harm[4, i, h] * tau + harm[5, i, h])
            off = mi[i, TOFF]
            i0 = ti[i, 0]
            j0 = ti[i, 1]
            w = tm[i, 2]
            if dk != 0.0:
                dk *= tabd[off + i0] * (1.0 - w) + tabd[off + j0] * w
            tm[i, 3] = dk
            if not (contacts and mi[i, CON] != 0):
                tm[i, 4] = mp[i, KSCALE] * (tab[off + i0] * (1.0 - w) + tab[off + j0] * w + dk)


@njit(cache=True, inline="always", error_model="numpy")
def _mesh_state(q, v, vcol, vval, nz, mp, mi, tab, tabz, ptr, cx, contacts, tm, ti, f_out,
                d_out):
    """Mesh forces f_i (into ``f_out``) and deflections V_i.q (into ``d_out``) from the state
    and the time parts ``tm``, ``ti`` of :func:`_mesh_time` (``nz``: the rows' lengths)."""
    nm = vcol.shape[0]
    for i in range(nm):
        d = 0.0
        dd = 0.0
        for p in range(nz[i]):  # the row's nonzero entries, by column (padding: 0 at col 0)
            j = vcol[i, p]
            d += vval[i, p] * q[j]
            dd += vval[i, p] * v[j]
        d_out[i] = d
        x = d - tm[i, 0]
        xd = dd - tm[i, 1]
        b2 = mp[i, CLEAR]
        cmi = mp[i, CM]
        if contacts and mi[i, CON] != 0:
            f = _contact_force(x, xd, b2, cmi, mp[i, KSCALE], tab, tabz, tm[i, 3], mi[i, TOFF],
                               ti[i, 0], ti[i, 1], tm[i, 2], ptr, mi[i, CROW], cx)
        else:
            k = tm[i, 4]
            if b2 == np.inf:  # linear mesh
                f = k * x + cmi * xd
            elif x > 0.0:  # working flanks in contact: contact force cannot pull
                f = max(k * x + cmi * xd, 0.0)
            elif x <= -b2:  # back flanks in contact: it cannot push
                f = min(k * (x + b2) + cmi * xd, 0.0)
            else:  # teeth separated
                f = 0.0
        f_out[i] = mp[i, KAPPA] * f


@njit(cache=True, error_model="numpy")
def mesh_forces(tau, taud, q, v, vcol, vval, mp, mi, tab, tabz, tabd, harm, ptr, cx, contacts,
                f_out, d_out):
    """Mesh forces f_i [N] (into ``f_out``) and deflections V_i.q [m] (into ``d_out``) at
    nominal time ``tau`` (rate ``taud`` = tau'); ``contacts`` as in :func:`rhs`."""
    nm = vcol.shape[0]
    tm = np.zeros((nm, 5))
    ti = np.zeros((nm, 2), dtype=np.int64)
    hn, hrows = _harmonic_rows(harm)
    _mesh_time(tau, taud, mp, mi, tab, tabd, harm, hn, hrows, contacts, tm, ti)
    _mesh_state(q, v, vcol, vval, _row_lengths(vval), mp, mi, tab, tabz, ptr, cx, contacts, tm,
                ti, f_out, d_out)


@njit(cache=True, inline="always", error_model="numpy")
def _accelerations(taudd, load, profiled, q, v, dof, vcol, vval, nz, f, a_out):
    """M^-1 (lambda F_ext + g tau'' - K_b q - C_b q' - V^T f) into ``a_out`` (``nz``: the
    rows' lengths, :func:`_row_lengths`)."""
    n = q.size
    nm = vcol.shape[0]
    for j in range(n):
        s = load * dof[3, j] - dof[1, j] * q[j] - dof[2, j] * v[j]
        if profiled and taudd != 0.0:
            s += taudd * dof[4, j]
        a_out[j] = s
    for i in range(nm):  # - V^T f over the nonzero entries, rows in order (as dense)
        fi = f[i]
        for p in range(nz[i]):
            a_out[vcol[i, p]] -= vval[i, p] * fi
    for j in range(n):
        a_out[j] *= dof[0, j]


@njit(cache=True, error_model="numpy")
def rhs(t, q, v, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam,
        contacts, profiled, a_out, f_out, d_out):
    """Accelerations M^-1 (lambda F_ext + g tau'' - K_b q - C_b q' - sum V_i f_i) into
    ``a_out``, mesh forces into ``f_out`` and deflections into ``d_out`` (one evaluation;
    :func:`_rk4` calls the parts directly). ``contacts`` with ``False``: no meshes of
    contacts; ``profiled`` with ``False``: constant speed and load, tau = t."""
    if profiled:
        tau, taud, taudd, load = nominal(t, prof, lam)
    else:
        tau, taud, taudd, load = t, 1.0, 0.0, 1.0
    mesh_forces(tau, taud, q, v, vcol, vval, mp, mi, tab, tabz, tabd, harm, ptr, cx, contacts,
                f_out, d_out)
    _accelerations(taudd, load, profiled, q, v, dof, vcol, vval, _row_lengths(vval), f_out,
                   a_out)


@njit(cache=True, inline="always", error_model="numpy")
def _rk4(contacts, profiled, q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v, rec_f,
         cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam):
    """Classical fixed-step RK4 (body of both integrators; see :func:`integrate_rk4`)."""
    n = q0.size
    nm = vcol.shape[0]
    q = q0.copy()
    v = v0.copy()
    qt = np.empty(n)
    vt = np.empty(n)
    kq = np.empty((3, n))  # q' of stages 1-3 (that of stage 4 is vt)
    kv = np.empty((4, n))  # v' of the four stages
    f = np.empty(nm)
    d = np.empty(nm)
    hn, hrows = _harmonic_rows(harm)
    nz = _row_lengths(vval)
    tm = np.zeros((nm, 5))
    ti = np.zeros((nm, 2), dtype=np.int64)
    n_rec = rec_q.shape[1]
    h2 = 0.5 * dt
    h6 = dt / 6.0
    r = 0
    next_rec = rec_start
    for s in range(n_steps + 1):
        t = t0 + s * dt
        for j in range(n):
            qt[j] = q[j]
            vt[j] = v[j]
        tau, taud, taudd, load = t, 1.0, 0.0, 1.0
        # the four stages in one loop, so that the right-hand side is compiled (inlined)
        # once, not four times; the arithmetic is the classical RK4's, in its order
        for stage in range(4):
            # stages 2 and 3 are at the same time: the time parts are those of stage 2
            if stage != 2:
                ts = t if stage == 0 else (t + dt if stage == 3 else t + h2)
                if profiled:
                    tau, taud, taudd, load = nominal(ts, prof, lam)
                else:
                    tau = ts
                _mesh_time(tau, taud, mp, mi, tab, tabd, harm, hn, hrows, contacts, tm, ti)
            _mesh_state(qt, vt, vcol, vval, nz, mp, mi, tab, tabz, ptr, cx, contacts, tm, ti, f, d)
            _accelerations(taudd, load, profiled, qt, vt, dof, vcol, vval, nz, f, kv[stage])
            if stage == 0:
                if s == next_rec and r < n_rec:  # the recorded columns only
                    for k in range(cq.size):
                        rec_q[k, r] = q[cq[k]]
                    for k in range(cv.size):
                        rec_v[k, r] = v[cv[k]]
                    for k in range(cf.size):
                        rec_f[k, r] = f[cf[k]]
                    r += 1
                    next_rec += rec_every
                if s == n_steps:
                    break
            if stage < 3:
                a = dt if stage == 2 else h2
                for j in range(n):
                    kq[stage, j] = vt[j]
                    qt[j] = q[j] + a * vt[j]
                    vt[j] = v[j] + a * kv[stage, j]
        if s == n_steps:
            break
        bad = False
        for j in range(n):
            q[j] += h6 * (kq[0, j] + 2.0 * kq[1, j] + 2.0 * kq[2, j] + vt[j])
            v[j] += h6 * (kv[0, j] + 2.0 * kv[1, j] + 2.0 * kv[2, j] + kv[3, j])
            if not (abs(q[j]) <= qlim):  # also catches NaN
                bad = True
        if bad:
            return 1, s + 1, rec_q, rec_v, rec_f, q, v
    return 0, n_steps, rec_q, rec_v, rec_f, q, v


@njit(cache=True, error_model="numpy")
def integrate_rk4(q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v, rec_f, cq, cv, cf,
                  qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam):
    """Classical fixed-step RK4 from t0 over ``n_steps`` steps of ``dt`` (stiffness tables,
    constant speed and load).

    Records the columns ``cq`` of q, ``cv`` of q' and ``cf`` of the mesh forces (int64
    index arrays) into ``rec_q``, ``rec_v`` and ``rec_f`` (columns, n_rec): one channel
    per row, record r in column r, at steps ``rec_start + r rec_every`` (r < n_rec), i.e.
    at instantaneous sample times (a study records the few channels it analyses, not
    every coordinate). A channel's record is contiguous, the layout the anti-aliasing
    filter (:func:`fir_decimate`) reads, so the records need no transposed copy; the
    caller passes three row blocks of one array. The caller allocates them with numpy,
    which advises huge pages for large arrays: allocating and writing the 20 MB of
    records of one simulated second of the Table-1 train, every step, took 5-6 ms
    instead of 13-16 ms with numba's allocation.
    Stops when a coordinate is not finite or exceeds ``qlim`` in magnitude.

    Returns
    -------
    status : 0 finished, 1 diverged
    step : the step at which it stopped
    rec_q, rec_v : (columns, n_rec) recorded state (the arrays passed)
    rec_f : (columns, n_rec) recorded mesh forces (the array passed)
    q, v : final state
    """
    return _rk4(False, False, q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v,
                rec_f, cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam)


@njit(cache=True, error_model="numpy")
def integrate_rk4_contacts(q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v, rec_f,
                           cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx,
                           lam):
    """:func:`integrate_rk4` with meshes of contacts (same arguments and returns)."""
    return _rk4(True, False, q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v,
                rec_f, cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam)


@njit(cache=True, error_model="numpy")
def integrate_rk4_profile(q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v, rec_f,
                          cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx,
                          lam):
    """:func:`integrate_rk4` with speed and load profiles (same arguments and returns)."""
    return _rk4(False, True, q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v,
                rec_f, cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam)


@njit(cache=True, error_model="numpy")
def integrate_rk4_contacts_profile(q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v,
                                   rec_f, cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof,
                                   harm, ptr, cx, lam):
    """:func:`integrate_rk4` with meshes of contacts and profiles (same arguments)."""
    return _rk4(True, True, q0, v0, t0, dt, n_steps, rec_start, rec_every, rec_q, rec_v,
                rec_f, cq, cv, cf, qlim, dof, vcol, vval, mp, mi, tab, tabz, tabd, prof, harm, ptr, cx, lam)


#: Outputs per block of :func:`fir_decimate`: the block's accumulators (4 kB) and its
#: polyphase samples (2 x 4.2 kB for ``down`` = 2) stay in the L1 cache while every tap
#: passes over them (256 to 1024 measured within 5 %).
FIR_BLOCK = 512


@njit(cache=True, error_model="numpy")
def fir_decimate(h, x, down, first, n_out):
    """Filter each row of ``x`` by the FIR ``h`` and keep every ``down``-th sample.

    y[c, o] = sum_i h[i] x[c, (first + o) down - i], i = 0 .. len(h) - 1: the full
    convolution of row c with h, sampled at (first + o) down (the polyphase decimation of
    ``scipy.signal.upfirdn(h, x, down=down)[:, first:first + n_out]``, summed in its
    order, from the oldest sample: the same numbers to the bit, tested). The caller
    guarantees first down >= len(h) - 1 and (first + n_out - 1) down < x.shape[1] (no
    sample outside the record).

    Each row is taken in blocks of :data:`FIR_BLOCK` outputs. A block's samples are
    split into their ``down`` polyphase components (sample s of phase p: x[c, s0 + p +
    s down]), so that tap i reads a contiguous run of one phase for all the block's
    outputs; the taps go in upfirdn's order, i from len(h) - 1 down to 0, eight in one
    pass (((acc + a h_i) + b h_i-1) + ...) (:func:`_split_phases`, :func:`_filter_phases`,
    shared with :func:`decimate_linear`), written left to right: without fast-math the
    compiler keeps that order, so each output is the same sum of the same products as
    tap by tap (0 + the first product is that product). The outputs of a pass are
    independent, so the loop vectorises: 6-7 ms for the 26 rows x 50 000 outputs x 49
    taps of one simulated second of the Table-1 train with four taps a pass, against
    29-30 ms with the stride-``down`` reads of one sample per output and tap (measured,
    2026-11-28).

    Parameters
    ----------
    h : ndarray, shape (L,)
        Filter taps.
    x : ndarray, shape (n_channel, n)
        Records, one channel per row.
    down : int
        Decimation factor.
    first : int
        Index of the first output sample in the full convolution's decimated grid.
    n_out : int
        Output samples per channel.

    Returns
    -------
    ndarray, shape (n_channel, n_out)
    """
    n_ch = x.shape[0]
    taps = h.size
    y = np.empty((n_ch, n_out))
    # polyphase samples of a block: its outputs and the taps' reach into the past
    span = (FIR_BLOCK - 1) * down + taps
    ph = np.empty((down, (span + down - 1) // down))
    for c in range(n_ch):
        for ob in range(0, n_out, FIR_BLOCK):
            nb = min(FIR_BLOCK, n_out - ob)
            s0 = (first + ob) * down - (taps - 1)  # oldest sample of the block
            _split_phases(x[c, s0:], (nb - 1) * down + taps, down, ph)
            _filter_phases(h, ph, down, nb, y[c, ob:])
    return y


@njit(cache=True, inline="always", error_model="numpy")
def _split_phases(src, n, down, ph):
    """The ``n`` samples ``src[:n]`` into their ``down`` polyphase components:
    ph[p, k] = src[p + k down] (a copy; the stride 2 of the default oversampling
    written out, so that the compiler vectorises it)."""
    if down == 2:
        p0 = ph[0]
        p1 = ph[1]
        for k in range(n // 2):
            p0[k] = src[2 * k]
            p1[k] = src[2 * k + 1]
        if n % 2:
            p0[n // 2] = src[n - 1]
    else:
        for p in range(down):
            php = ph[p]
            for k in range((n - p + down - 1) // down):
                php[k] = src[p + k * down]


@njit(cache=True, inline="always", error_model="numpy")
def _filter_phases(h, ph, down, nb, acc):
    """acc[o] = sum_i h[i] s[(taps - 1) + o down - i], o < nb, from the polyphase
    components ``ph`` of the samples s (s[p + k down] = ph[p, k]): the tap passes of
    :func:`fir_decimate`, in ``upfirdn``'s order (the same numbers to the bit), eight
    taps a pass, the first pass from 0 (not from a cleared ``acc``)."""
    taps = h.size
    d = 0
    if taps >= 8:
        a0 = ph[0, 0:]
        a1 = ph[1 % down, 1 // down:]
        a2 = ph[2 % down, 2 // down:]
        a3 = ph[3 % down, 3 // down:]
        a4 = ph[4 % down, 4 // down:]
        a5 = ph[5 % down, 5 // down:]
        a6 = ph[6 % down, 6 // down:]
        a7 = ph[7 % down, 7 // down:]
        h0 = h[taps - 1]
        h1 = h[taps - 2]
        h2 = h[taps - 3]
        h3 = h[taps - 4]
        h4 = h[taps - 5]
        h5 = h[taps - 6]
        h6 = h[taps - 7]
        h7 = h[taps - 8]
        for o in range(nb):
            acc[o] = (((((((0.0 + a0[o] * h0) + a1[o] * h1) + a2[o] * h2) + a3[o] * h3)
                        + a4[o] * h4) + a5[o] * h5) + a6[o] * h6) + a7[o] * h7
        d = 8
    else:
        for o in range(nb):
            acc[o] = 0.0
    while d + 8 <= taps:
        a0 = ph[d % down, d // down:]
        a1 = ph[(d + 1) % down, (d + 1) // down:]
        a2 = ph[(d + 2) % down, (d + 2) // down:]
        a3 = ph[(d + 3) % down, (d + 3) // down:]
        a4 = ph[(d + 4) % down, (d + 4) // down:]
        a5 = ph[(d + 5) % down, (d + 5) // down:]
        a6 = ph[(d + 6) % down, (d + 6) // down:]
        a7 = ph[(d + 7) % down, (d + 7) // down:]
        h0 = h[taps - 1 - d]
        h1 = h[taps - 2 - d]
        h2 = h[taps - 3 - d]
        h3 = h[taps - 4 - d]
        h4 = h[taps - 5 - d]
        h5 = h[taps - 6 - d]
        h6 = h[taps - 7 - d]
        h7 = h[taps - 8 - d]
        for o in range(nb):
            acc[o] = (((((((acc[o] + a0[o] * h0) + a1[o] * h1) + a2[o] * h2) + a3[o] * h3)
                        + a4[o] * h4) + a5[o] * h5) + a6[o] * h6) + a7[o] * h7
        d += 8
    while d + 4 <= taps:
        a0 = ph[d % down, d // down:]
        a1 = ph[(d + 1) % down, (d + 1) // down:]
        a2 = ph[(d + 2) % down, (d + 2) // down:]
        a3 = ph[(d + 3) % down, (d + 3) // down:]
        h0 = h[taps - 1 - d]
        h1 = h[taps - 2 - d]
        h2 = h[taps - 3 - d]
        h3 = h[taps - 4 - d]
        for o in range(nb):
            acc[o] = (((acc[o] + a0[o] * h0) + a1[o] * h1) + a2[o] * h2) + a3[o] * h3
        d += 4
    while d < taps:
        a0 = ph[d % down, d // down:]
        h0 = h[taps - 1 - d]
        for o in range(nb):
            acc[o] = acc[o] + a0[o] * h0
        d += 1


@njit(cache=True, inline="always", error_model="numpy")
def _signal_phases(x, s0, n, down, k0, k1, col, wt, u, ph):
    """The polyphase components of one block of a signal (:func:`decimate_linear`, step
    1): the n samples from s0 of sum_k wt[k] x[col[k]], k = k0 .. k1 - 1, in that order."""
    if k1 - k0 == 1 and wt[k0] == 1.0:  # a channel alone: its samples
        _split_phases(x[col[k0], s0:], n, down, ph)
    elif down == 2 and k1 > k0:  # the terms added into the two phases (no pass over u)
        src = x[col[k0], s0:]
        w = wt[k0]
        p0 = ph[0]
        p1 = ph[1]
        for k in range(n // 2):
            p0[k] = w * src[2 * k]
            p1[k] = w * src[2 * k + 1]
        if n % 2:
            p0[n // 2] = w * src[n - 1]
        for kk in range(k0 + 1, k1):
            src = x[col[kk], s0:]
            w = wt[kk]
            for k in range(n // 2):
                p0[k] = p0[k] + w * src[2 * k]
                p1[k] = p1[k] + w * src[2 * k + 1]
            if n % 2:
                p0[n // 2] = p0[n // 2] + w * src[n - 1]
    else:
        if k1 == k0:
            for s in range(n):
                u[s] = 0.0
        else:
            src = x[col[k0], s0:]
            w = wt[k0]
            for s in range(n):
                u[s] = w * src[s]
            for k in range(k0 + 1, k1):
                src = x[col[k], s0:]
                w = wt[k]
                for s in range(n):
                    u[s] = u[s] + w * src[s]
        _split_phases(u, n, down, ph)


@njit(cache=True, error_model="numpy")
def decimate_linear(h, x, down, first, n_out, pre_ptr, pre_col, pre_w, extra, post_ptr,
                    post_col, post_w, post_b, post_d, z):
    """Linear records of the decimated channels: combine, filter, decimate, combine.

    Three linear steps:

    1. signals at the internal rate, u_m[s] = sum_k pre_w[k] x[pre_col[k], s] over
       k = pre_ptr[m] .. pre_ptr[m + 1] - 1, in that order (a single term of weight 1 is
       the channel itself, not multiplied);
    2. each signal filtered by the FIR ``h`` and kept every ``down``-th sample, as
       :func:`fir_decimate` (the same operations, the same numbers to the bit):
       y_m[o] = sum_i h[i] u_m[(first + o) down - i]; the rows of ``extra`` (values at
       the output times, not filtered) follow as y_{n_sig + e};
    3. records z[j, o] = (post_b[j] + sum_k post_w[k] y_{post_col[k]}[o]) / post_d[j],
       the terms k = post_ptr[j] .. post_ptr[j + 1] - 1 added in that order; a record
       that is a signal itself (b = 0, one term of weight 1, d = 1) is the filter's
       output, written in its row (0 + y is y but for the sign of a zero); a signal
       without such a record is written in the row of a record that reads it (of at
       most three terms), formed in place once the others are (each value read before
       it is replaced): no memory beside the records.

    Signal by signal, in blocks of :data:`FIR_BLOCK` outputs (steps 1 and 2: a signal's
    few channels are read in long runs, which the memory's prefetch follows), then record
    by record, each over its whole length (step 3: a row in the cache while its terms
    are added).

    The filter acts on each signal alone and the decimation is linear, so a record
    linear in the channels is the same, to round-off, whether it is formed before the
    filter (step 1), after it (step 3) or from the decimated channels: what is combined
    where only decides how many signals are filtered (the filter's products are most of
    the cost).

    Parameters
    ----------
    h : ndarray, shape (L,)
        Filter taps.
    x : ndarray, shape (n_channel, n)
        Records, one channel per row (the caller guarantees first down >= L - 1 and
        (first + n_out - 1) down < n, as for :func:`fir_decimate`).
    down : int
        Decimation factor.
    first : int
        Index of the first output sample in the full convolution's decimated grid.
    n_out : int
        Output samples.
    pre_ptr, pre_col, pre_w : ndarray
        Step 1 in compressed rows: (n_sig + 1,) int, (n_pre,) int, (n_pre,) float.
    extra : ndarray, shape (n_extra, n_out)
        Rows at the output times after the filtered signals.
    post_ptr, post_col, post_w, post_b, post_d : ndarray
        Step 3: (n_z + 1,) int, (n_post,) int (rows of the filtered signals, then of
        ``extra``), (n_post,), (n_z,), (n_z,) float.
    z : ndarray, shape (n_z, n_out)
        Output, written and returned.

    Returns
    -------
    ndarray, shape (n_z, n_out)
        ``z``.
    """
    n_sig = pre_ptr.size - 1
    n_z = post_b.size
    taps = h.size
    # the record each signal is written to (a record that is the signal), else a row of y
    home = np.full(n_sig, -1, dtype=np.int64)
    done = np.zeros(n_z, dtype=np.bool_)
    for j in range(n_z):
        k = post_ptr[j]
        if post_ptr[j + 1] - k == 1 and post_col[k] < n_sig and post_w[k] == 1.0 \
                and post_b[j] == 0.0 and post_d[j] == 1.0 and home[post_col[k]] < 0:
            home[post_col[k]] = j
            done[j] = True
    # a record of at most three terms (one pass) that reads a signal without a record
    # of its own, and otherwise only such records and extra rows, holds that signal and
    # is formed in place after every other record (the only ones that read the signal)
    host = np.zeros(n_z, dtype=np.bool_)
    for j in range(n_z):
        k0 = post_ptr[j]
        k1 = post_ptr[j + 1]
        if done[j] or k1 - k0 > 3:
            continue
        free = -1
        ok = True
        for k in range(k0, k1):
            c = post_col[k]
            if c < n_sig and home[c] < 0:
                if free >= 0 and c != free:
                    ok = False
                free = c
            elif c < n_sig and not done[home[c]]:
                ok = False  # a signal held by another record, changed in place
        if ok and free >= 0:
            home[free] = j
            host[j] = True
    at = np.full(n_sig, -1, dtype=np.int64)
    n_y = 0
    for m in range(n_sig):
        if home[m] < 0:
            at[m] = n_y
            n_y += 1
    y = np.empty((n_y, n_out))
    span = (FIR_BLOCK - 1) * down + taps  # samples of a full block
    u = np.empty(span)
    ph = np.empty((down, (span + down - 1) // down))
    for m in range(n_sig):
        out = z[home[m]] if home[m] >= 0 else y[at[m]]
        for ob in range(0, n_out, FIR_BLOCK):
            nb = min(FIR_BLOCK, n_out - ob)
            s0 = (first + ob) * down - (taps - 1)  # oldest sample of the block
            _signal_phases(x, s0, (nb - 1) * down + taps, down, pre_ptr[m], pre_ptr[m + 1],
                           pre_col, pre_w, u, ph)
            _filter_phases(h, ph, down, nb, out[ob:])
    for jj in range(2 * n_z):  # the records that hold a signal last
        j = jj % n_z
        if done[j] or host[j] != (jj >= n_z):
            continue
        out = z[j]
        b = post_b[j]
        dj = post_d[j]
        k0 = post_ptr[j]
        k1 = post_ptr[j + 1]
        # the first up to three terms and the division in one pass, the same operations
        # in the same order as term by term: ((b + w0 s0) + w1 s1) + w2 s2, / d (not
        # divided by d = 1: x / 1 = x)
        s0 = _post_source(k0, k1, k0, post_col, n_sig, extra, home, at, z, y)
        s1 = _post_source(k0, k1, k0 + 1, post_col, n_sig, extra, home, at, z, y)
        s2 = _post_source(k0, k1, k0 + 2, post_col, n_sig, extra, home, at, z, y)
        nt = min(k1 - k0, 3)
        w0 = post_w[k0] if nt > 0 else 0.0
        w1 = post_w[k0 + 1] if nt > 1 else 0.0
        w2 = post_w[k0 + 2] if nt > 2 else 0.0
        last = k1 - k0 <= 3 and dj != 1.0
        if nt == 0:
            for o in range(n_out):
                out[o] = b
        elif nt == 1:
            for o in range(n_out):
                out[o] = b + w0 * s0[o]
        elif nt == 2:
            if last:
                for o in range(n_out):
                    out[o] = ((b + w0 * s0[o]) + w1 * s1[o]) / dj
            else:
                for o in range(n_out):
                    out[o] = (b + w0 * s0[o]) + w1 * s1[o]
        else:
            if last:
                for o in range(n_out):
                    out[o] = (((b + w0 * s0[o]) + w1 * s1[o]) + w2 * s2[o]) / dj
            else:
                for o in range(n_out):
                    out[o] = ((b + w0 * s0[o]) + w1 * s1[o]) + w2 * s2[o]
        for k in range(k0 + 3, k1):
            src = _post_source(k0, k1, k, post_col, n_sig, extra, home, at, z, y)
            w = post_w[k]
            for o in range(n_out):
                out[o] = out[o] + w * src[o]
        if dj != 1.0 and not (last and nt >= 2):
            for o in range(n_out):
                out[o] = out[o] / dj
    return z


@njit(cache=True, inline="always", error_model="numpy")
def _post_source(k0, k1, k, post_col, n_sig, extra, home, at, z, y):
    """The row that term k of a record reads (:func:`decimate_linear`, step 3): a row of
    ``extra``, the record a signal was written to, or its row of ``y``; outside the
    record's terms, any row (not read)."""
    c = post_col[k] if k < k1 else post_col[k0] if k0 < k1 else n_sig
    if c >= n_sig:
        return extra[c - n_sig] if extra.shape[0] > 0 else z[0]
    if home[c] >= 0:
        return z[home[c]]
    return y[at[c]]


@njit(cache=True, error_model="numpy")
def tacho_pulses(a, width, volts, out):
    """``volts`` where ``numpy.mod(a, 2 pi) < width``, else 0, element by element.

    The decision of :func:`gearsim.dynamics.simulate.tacho_variable` (its Notes): the
    remainder by floor, a - floor(a / 2 pi) 2 pi, decides every angle whose remainder
    lies more than (|a| + 2 (2 pi)) 2^-50 inside [0, width) or [width, 2 pi); the others
    take the floating remainder ``a % (2 pi)``, numpy's and Python's (fmod, then the
    divisor added where the signs differ). The same pulses as ``numpy.mod``, bit for bit.

    Parameters
    ----------
    a : ndarray, shape (n,)
        Angles [rad].
    width : float
        Pulse width [rad].
    volts : float
        Pulse level.
    out : ndarray, shape (n,)
        Written and returned.

    Returns
    -------
    ndarray, shape (n,)
        ``out``.
    """
    turn = 2.0 * np.pi
    unsure = 0
    for i in range(a.size):  # without branches (vectorised): the decided angles
        x = a[i]
        r = x - math.floor(x / turn) * turn
        tol = (abs(x) + 2.0 * turn) * 2.0 ** -50
        on = (r >= tol) & (r < width - tol)
        off = (r >= width + tol) & (r < turn - tol)
        out[i] = volts if on else 0.0
        unsure += not (on | off)
    if unsure:
        for i in range(a.size):  # the others (none or a few): the remainder itself
            x = a[i]
            r = x - math.floor(x / turn) * turn
            tol = (abs(x) + 2.0 * turn) * 2.0 ** -50
            if not (((r >= tol) & (r < width - tol)) | ((r >= width + tol) & (r < turn - tol))):
                out[i] = volts if x % turn < width else 0.0
    return out
