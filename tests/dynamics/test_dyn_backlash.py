"""Backlash: tooth separation and back-side contact (piecewise mesh force, clearance 2b)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearsim.dynamics import DynamicsSettings, build_model, simulate
from gearsim.dynamics import _kernels as K
from gearsim.dynamics.lta import agma_backlash
from gearsim.dynamics.simulate import _kernel_args
from gearsim.model import load
from gearsim.system import Operating


def test_piecewise_mesh_force():
    tr = load("idler-table1").train.with_cracks(())
    m = build_model(tr, DynamicsSettings(backlash=(2e-4,), mesh_damping_ratio=0.0))
    _, vcol, vval, mp, mi, tab, tabz, tabd, _prof, harm, ptr, cx, _lam = _kernel_args(m)
    k = m.tables[0].k[0]
    f = np.zeros(2)
    d = np.zeros(2)
    v = np.zeros(m.n_dof)
    for x, expected in ((1e-5, k * 1e-5), (-1e-4, 0.0), (-2.5e-4, k * (-2.5e-4 + 2e-4))):
        q = np.zeros(m.n_dof)
        q[3] = x / m.V[0, 3]  # deflection of mesh 1 through the input rotation only
        K.mesh_forces(0.0, 1.0, q, v, vcol, vval, mp, mi, tab, tabz, tabd, harm, ptr, cx, False, f,
                      d)
        assert d[0] == pytest.approx(x)
        assert f[0] == pytest.approx(expected, rel=1e-12, abs=1e-9)


def test_agma_default_backlash():
    tr = load("idler-table1").train
    # (2/3)(0.06 + 0.0005 a + 0.03 m_n) mm with a = 301.73 mm, m_n = 6 mm -> 0.2606 mm normal
    assert agma_backlash(tr, 0) * np.cos(tr.gears[0].base_helix_angle) == pytest.approx(
        2.606e-4, rel=2e-3)


def test_light_load_separates_and_hits_back_side():
    """At a light load near the mesh-II resonance, excited by a 2 um profile-modification
    STE (force amplitude k e >> static force), the teeth lose contact; with a small
    clearance they strike the back flanks (negative force); the linear mesh does not
    stay at zero force. No NaN, mean force still equals the static force."""
    tr = load("idler-table1").train.with_cracks(())
    fm_target = 1732.0  # mesh-II resonance (test_dyn_modal)
    op = Operating(speed=tr.operating.speed * fm_target / tr.mesh_frequency, torque=150.0)
    tr = dataclasses.replace(tr, operating=op)
    # instantaneous samples (oversample 1): the anti-alias filter would ring around
    # the contact impacts and blur the exact zeros of the separated phases
    base = DynamicsSettings(duration=0.1, fs=40_000.0, oversample=1,
                            profile_modification=(2e-6,))
    out = {}
    for name, s in (("linear", dataclasses.replace(base, nonlinear=False)),
                    ("clearance", dataclasses.replace(base, backlash=(2e-6,))),
                    ("agma", base)):
        x = simulate(tr, s)["mesh_force_2"].values
        assert np.all(np.isfinite(x))
        out[name] = x
    fs2 = tr.static_mesh_force(1)
    assert out["linear"].min() < -0.5 * fs2  # linear spring pulls: unphysical tension
    assert np.mean(out["agma"] == 0.0) > 0.05  # separated part of the time
    assert out["agma"].min() >= 0.0 - 1e-6 * fs2  # wide clearance: never back side
    assert out["clearance"].min() < -0.05 * fs2  # narrow clearance: back-side impacts
    for name, x in out.items():
        # torque balance; the window holds a non-integer number of cycles of a
        # fluctuation ~20x the static force, so compare with 1 % of that fluctuation
        assert abs(np.mean(x) - fs2) < 1e-2 * np.std(x), name
