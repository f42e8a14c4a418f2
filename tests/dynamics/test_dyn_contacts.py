"""Dynamics with the mesh of contacts: identity with the table path, the numpy reference,
pitch-error orders, runout modulation, broken-tooth contact loss, energy conservation.

Spectra use fs = 40 f_m over whole pinion revolutions, so every shaft order falls on an
FFT bin and no window is needed (as in test_dyn_crack.py).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gearsim as gs
from gearsim.dynamics import DynamicsSettings, simulate
from gearsim.dynamics.simulate import build_model, reference_mesh_forces, run_kernel
from gearsim.stiffness.faults import BrokenTooth, Spall
from gearsim.stiffness.modifications import Modification
from gearsim.stiffness.settings import MODELS

#: Identity of two routes that sum the same terms in another order.
IDENTICAL = 1e-9


@pytest.fixture(scope="module")
def spur():
    """The 19/48 pair with the seed's stiffness law: the checks below are of the kernel
    and the contact mechanics, with numbers measured on it (the accurate law's contacts
    are checked against its table in test_zero_separations_reproduce_the_table_path)."""
    tr = gs.example("spur-19-48").train.with_crack("none")
    return dataclasses.replace(tr, stiffness=dataclasses.replace(tr.stiffness,
                                                                 **MODELS["seed"]))


def _settings(tr, revs=3, **kw):
    fm = tr.mesh_frequency
    return DynamicsSettings(duration=revs / tr.shaft_frequency(0), fs=40 * fm, **kw)


@pytest.mark.parametrize("nonlinear, law", [(True, {}), (False, {}),
                                            (True, {"contact": "line", "coupling": "fe"})])
def test_zero_separations_reproduce_the_table_path(spur, nonlinear, law):
    """A healthy mesh run as a mesh of contacts (without the tip-corner contacts, which
    the stiffness table does not have) gives the table path's 0.1 s result, with the
    seed's contact and with the line contact and body coupling (both linearised at the
    static force)."""
    s = DynamicsSettings(duration=0.1, fs=20_000.0, nonlinear=nonlinear)
    tr = dataclasses.replace(spur, stiffness=dataclasses.replace(spur.stiffness,
                                                                 corner_contact=False, **law))
    a = simulate(tr, s)
    b = simulate(tr, dataclasses.replace(s, contact_mesh=True))
    for name in ("mesh_force_1", "dte_1", "acceleration"):
        x, y = a[name].values, b[name].values
        assert np.max(np.abs(x - y)) <= IDENTICAL * np.max(np.abs(x)), name


def test_kernel_matches_numpy_reference_with_faults(spur):
    """Compiled contact force against the plain-numpy force law at random states."""
    g = spur.gears[0]
    tr = spur.with_faults((Spall(gear="pinion", tooth=2, radius=g.pitch_radius, length=3e-3,
                                 width=6e-3, depth=3e-6),
                           BrokenTooth(gear="pinion", tooth=7, width=5e-3)),
                          (Modification(gear="gear", tip_relief=8e-6,
                                        tip_relief_length=2e-3, pitch_grade=6),))
    for nonlinear in (True, False):
        model = build_model(tr, DynamicsSettings(nonlinear=nonlinear))
        assert all(t.has_contacts for t in model.tables)
        rng = np.random.default_rng(1)
        for _ in range(40):
            t = rng.uniform(0, 0.05)
            q = model.q_static + rng.normal(0, 3e-6, model.n_dof)
            v = rng.normal(0, 1e-3, model.n_dof)
            raw = run_kernel(dataclasses.replace(model, fext=np.zeros(model.n_dof)),
                             dt=1e-12, n_steps=0, q0=q, v0=v, t0=t)
            ref = reference_mesh_forces(model, t, q, v)
            np.testing.assert_allclose(raw.f[0], ref, rtol=1e-9, atol=1e-6)


def _spectrum(x):
    return np.abs(np.fft.rfft(x - x.mean())) * 2 / x.size


#: Dynamic against quasi-static transmission error at low shaft orders: the orders are
#: far below the mesh resonance (about 0.3 % of it at order 7), so the dynamic
#: amplification 1 / (1 - (f / f_n)^2) differs from 1 by < 1e-4; the rest is the
#: dynamics' table interpolation and integration error. The quasi-static reference is
#: sampled at the table positions while the dynamics interpolates between them, and the
#: contacts entering and leaving the path carry their cells' in-path fractions (in_path_
#: fraction): the two differ by a sampling error that shrinks with the positions per
#: cycle (largest over orders 1-7: 40 -> 0.57 %, 80 -> 0.36 %, 160 -> 0.08 %); 80 here.
QUASI_STATIC = 0.005
QUASI_STATIC_POSITIONS = 80


def test_pitch_error_gives_shaft_order_lines(spur):
    """One pinion tooth recessed 5 um: lines at the pinion's shaft orders k f_r1 in the
    dynamic transmission error, equal to the quasi-static loaded contact analysis's
    (0.5 %), and at round-off in the healthy run."""
    from gearsim.stiffness.ltca import loaded_contact

    pe = [0.0] * 19
    pe[3] = 5e-6
    spur = dataclasses.replace(spur, stiffness=dataclasses.replace(
        spur.stiffness, positions_per_cycle=QUASI_STATIC_POSITIONS))
    tr = spur.with_faults((), (Modification(gear="pinion", pitch_errors=tuple(pe)),))
    revs = 3
    s = _settings(spur, revs)
    dyn = _spectrum(simulate(tr, s)["dte_1"].values)
    healthy = _spectrum(simulate(spur, s)["dte_1"].values)
    lc = loaded_contact(tr.mesh_contacts(0), tr.static_mesh_force(0))
    quasi = _spectrum(lc.delta)  # one pinion revolution: order k at bin k
    for k in (1, 2, 3, 5, 7):
        assert dyn[k * revs] == pytest.approx(quasi[k], rel=QUASI_STATIC), k
        assert dyn[k * revs] > 1e3 * healthy[k * revs]
    assert quasi[1] > 0.1 * 5e-6 / 19  # a real line: order of e / z


def test_runout_is_a_transmission_error_at_the_shaft_order(spur):
    """20 um pinion runout: the dynamic transmission error has a line of 20 um x the
    projection at the pinion's shaft order (the eccentricity on the line of action,
    Velex & Maatar 1996), 1 % tolerance (dynamic amplification at f_r1 and the mesh
    tone's leakage are below it)."""
    revs = 3
    s = _settings(spur, revs)
    x = simulate(spur, dataclasses.replace(s, runout=(20e-6, 0.0)))["dte_1"].values
    assert _spectrum(x)[revs] == pytest.approx(20e-6, rel=0.01)


def _raw_mesh_force(tr, revs, dt=2e-6):
    model = build_model(tr, DynamicsSettings())
    n = int(round(revs / tr.shaft_frequency(0) / dt))
    raw = run_kernel(model, dt=dt, n_steps=n)
    return raw.t, raw.f[:, 0], raw.q @ model.V[0]


def test_broken_tooth_without_corner_contact_loses_contact(spur):
    """Contacts only on the path of contact: while the broken pinion tooth would carry
    the load alone, nothing carries it: the mesh force is exactly zero for the length
    of the single-contact zone, (2 - eps_alpha) / f_m (one step of tolerance), then the
    incoming pair re-engages with an impact."""
    tr = spur.with_faults((BrokenTooth(gear="pinion", tooth=0),))
    tr = dataclasses.replace(tr, stiffness=dataclasses.replace(tr.stiffness,
                                                               corner_contact=False))
    dt = 2e-6
    t, f, _ = _raw_mesh_force(tr, 1, dt)
    _, fh, _ = _raw_mesh_force(spur, 1, dt)
    zero = np.flatnonzero(f == 0.0)
    assert zero.size > 0
    gaps = np.flatnonzero(np.diff(zero) > 1)  # later stretches: the gears rattle after
    zero = zero[: gaps[0] + 1] if gaps.size else zero
    # the table: n0 samples with no contact; linear interpolation between samples makes
    # the force zero over (n0 - 1) sample intervals (one integration step of tolerance)
    grid = tr.mesh_contacts(0)
    npc = grid.positions_per_cycle
    n0 = int(np.sum(grid.k_total == 0.0))
    fm = spur.mesh_frequency
    assert abs(zero.size * dt - (n0 - 1) / (npc * fm)) <= 1.5 * dt
    # the single-contact zone Z = (2 - eps_alpha) / f_m: each sample carries its cell's
    # in-path fraction (in_path_fraction), so a sample is zero only if its whole cell h
    # lies in the zone (Z / h - 1 samples, rounded either way) and the interpolated
    # force is exactly zero over one interval less: Z - 3 h < zero <= Z - h
    eps = spur.pairs[0].transverse_contact_ratio
    zone, h = (2 - eps) / fm, 1 / (npc * fm)
    assert zone - 3 * h - 1.5 * dt < zero.size * dt <= zone - h + 1.5 * dt
    assert f[zero[-1] + 1:zero[-1] + 200].max() > 2 * fh.max()  # the impact


def test_broken_tooth_with_corner_contact_dips_and_impacts(spur):
    """Default model (tip-corner contacts): the outgoing pair's tip corner carries the
    load past the end of the path while the driver runs ahead (dynamic transmission
    error well above the healthy one), the mesh force dips below the healthy minimum,
    and the incoming pair's re-engagement is an impact above the healthy maximum, once
    per pinion revolution."""
    tr = spur.with_faults((BrokenTooth(gear="pinion", tooth=0),))
    revs = 3
    t, f, d = _raw_mesh_force(tr, revs)
    _, fh, dh = _raw_mesh_force(spur, revs)
    per = f.size // revs
    for r in range(revs):
        seg = f[r * per:(r + 1) * per]
        assert seg.min() < 0.8 * fh.min()
        assert seg.max() > 1.2 * fh.max()
        assert d[r * per:(r + 1) * per].max() > 3 * dh.max()
    assert f.min() > 0  # tip contact: contact never lost at this speed and load


def test_energy_is_conserved_in_a_free_undamped_run(spur):
    """Frozen mesh position (f_m = 0), no damping or load, a shallow spall (2 um: its
    recessed contact closes and opens during the oscillation): the total energy
    1/2 v'Mv + 1/2 q'K_b q + V_mesh(delta) is constant to 1e-4 and converges with the
    step (smooth stretches: RK4 energy error ~(w dt)^6 / 144 per step, 1e-7 over the
    run)."""
    g = spur.gears[0]
    tr = spur.with_faults((Spall(gear="pinion", tooth=0, radius=g.pitch_radius, length=2e-3,
                                 width=8e-3, depth=2e-6),))
    model = build_model(tr, DynamicsSettings())
    tab = model.tables[0]
    row = int(np.argmax(np.diff(tab.ptr)))  # a position with listed (separated) contacts
    phase = row / tab.positions_per_cycle
    n = model.n_dof
    free = dataclasses.replace(model, mesh_frequency=0.0, phase=np.array([phase]),
                               cm=np.zeros(1), cb=np.zeros(n), fext=np.zeros(n),
                               h_amp=np.zeros_like(model.h_amp), e0=np.zeros(1))
    kk = np.concatenate([[tab.k_zero[row]], tab.kx[tab.ptr[row]:tab.ptr[row + 1]]])
    ss = np.concatenate([[0.0], tab.sx[tab.ptr[row]:tab.ptr[row + 1]]])
    b2 = model.clearance[0]

    def energy(q, v):
        d = model.V[0] @ q
        mesh = 0.5 * np.sum(kk * np.maximum(0.0, d - ss) ** 2)
        if d <= -b2:
            mesh += 0.5 * tab.k[row] * (d + b2) ** 2
        return 0.5 * np.sum(model.mass * v ** 2) + 0.5 * np.sum(model.kb * q ** 2) + mesh

    q0 = np.zeros(n)
    q0[3] = 6e-6 / tr.gears[0].base_radius  # twist the pinion: 6 um along the line
    w_max = np.sqrt(np.max((model.kb + kk.sum() * model.V[0] ** 2) / model.mass))
    drift = []
    for per_period in (200, 400):
        dt = 2 * np.pi / w_max / per_period
        n = 100 * per_period * 5
        raw = run_kernel(free, dt=dt, n_steps=n, q0=q0, rec_every=per_period)
        e = np.array([energy(q, v) for q, v in zip(raw.q, raw.v, strict=True)])
        d = raw.q @ model.V[0]
        assert np.any(d > 2e-6) and np.any(d < 2e-6)  # the spalled contact opens, closes
        drift.append(np.max(np.abs(e - e[0])) / e[0])
    # each contact opening or closing (at delta = 0 and at the spall depth) is a kink of
    # the force law, where RK4 loses its order: the energy error jumps there (measured
    # 4.0e-5 of the energy over 500 periods at 200 steps per period, 2.7e-5 at 400; the
    # jumps depend on where the events fall in a step, so the decrease is not a clean
    # power of dt). A leak of the model (non-conservative force law) would grow with
    # time instead and not shrink with the step.
    assert drift[0] < 1e-4, drift
    assert drift[1] < drift[0], drift


def test_eccentricity_modulates_the_mesh_tone(spur):
    """20 um pinion runout also moves the centre distance by +-20 um once per revolution:
    the contact ratio follows (d eps_alpha/da = -1/(p_b sin alpha_wt)), so the mesh
    stiffness and the mesh tone are amplitude-modulated at f_r1: sidebands f_m +- f_r1
    in the mesh force at > 1e-4 of the tone and > 1000x the healthy run's round-off.
    The table's dk/da averages to the derivative of the mean TVMS computed directly at
    two centre distances (1 %: second-order terms of the central difference)."""
    import math

    from gearsim.stiffness.mesh import mesh_stiffness

    revs = 3
    s = _settings(spur, revs)
    xh = simulate(spur, s)["mesh_force_1"].values
    ecc = dataclasses.replace(s, runout=(20e-6, 0.0))
    xr = simulate(spur, ecc)["mesh_force_1"].values
    sh, sr = _spectrum(xh), _spectrum(xr)
    c = 19 * revs
    for side in (-1, 1):
        b = c + side * revs
        assert sr[b] > 1e3 * sh[b]
        assert sr[b] > 1e-4 * sr[c]
    # the derivative: mean stiffness at a +- 20 um, 4000 positions per cycle
    pair = spur.pairs[0]
    st = dataclasses.replace(spur.stiffness, positions_per_cycle=4000)
    means = [mesh_stiffness(dataclasses.replace(pair, centre_distance_offset=h),
                            settings=st).k[:4000].mean() for h in (20e-6, -20e-6)]
    direct = (means[0] - means[1]) / 40e-6
    table = build_model(spur, ecc).tables[0]
    assert table.dk_da.mean() == pytest.approx(direct, rel=0.01)
    # pulling the gears apart shortens the double-contact zone: the stiffness drops, by
    # at least the lost double-contact time times the pair stiffness at A
    ka = float(np.max(np.diff(mesh_stiffness(pair, settings=st).k[:4000])))
    jump_only = -ka / (pair.base_pitch * math.sin(pair.working_pressure_angle))
    assert direct < jump_only < 0
