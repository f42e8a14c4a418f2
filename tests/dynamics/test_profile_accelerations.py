"""Angular accelerations under speed and load profiles (docs/dynamics.md eq. 6a).

Under a profile each coordinate is a deviation q_j from the nominal motion w_j tau(t), and
the kernel integrates m_j q_j'' = lambda(t) F_j + g_j tau'' - k_b q_j - c_b q_j' - sum_i
V_ij f_i. The record ``angular_acceleration`` is the rotation's own acceleration, w_j tau''
+ q_j'', the second derivative of ``shaft_angle`` = w_j tau + q_j. Two references, neither
of them the records' code:

* the equations of motion themselves: ``_kernels.rhs`` evaluated at the run's own states
  (every channel recorded, no filter), plus w_j tau'';
* kinematics: the integral of the record over the run equals the change of the shaft's
  speed, taken by central differences of the recorded ``shaft_angle``.

Before the records took lambda(t) and tau'' in, the input's and the output's accelerations
of a run-up under a load ramp were off by 1e3 times the speed change (the constant
operating torque where the load had changed) and by up to the record's peak.
"""

from __future__ import annotations

import numpy as np
import pytest

import gearsim as gs
from gearsim.dynamics import _kernels
from gearsim.dynamics.simulate import _kernel_args, _prepare, record

#: Against the equations of motion at the same states: round-off of sums whose terms
#: exceed the record (measured 3.8e-12 of the record's peak at most).
RHS_RTOL = 1e-9
#: Integral of the record (trapezoid, 20 kHz) against the speed change from central
#: differences of the angle: both err on the mesh vibration (accelerations of 1e3-2e4
#: rad/s^2 RMS at 570-1500 Hz): measured 3.5 % at most (the 19/48 pinion), 1.4 % on the
#: reducer, 6e-5 on the Table-1 train.
KINEMATIC_RTOL = 0.05

PROFILE = {"speed_times": [0.0, 1.0], "speed_values": [150.0, 250.0],
           "load_times": [0.0, 1.0], "load_values": [0.6, 1.4]}


def _box(name: str, model: str, **dyn) -> gs.Gearbox:
    return gs.example(name).replace(dynamics={"model": model, "fs": 20e3, **PROFILE, **dyn})


@pytest.mark.parametrize(("name", "model"), [("spur-19-48", "lta"),
                                             ("two-stage-reducer", "torsional")])
def test_records_are_the_equations_of_motion_plus_the_nominal_acceleration(name, model):
    gb = _box(name, model, duration=0.2, oversample=1)
    ds = gb.simulate()
    s, dm, dt, m, _ = _prepare(gb.train, gb.dynamics, None, None, True, 1, None)
    t, q, v, _, _ = record(dm, s, dt=dt, m=m, transient=ds.attrs["transient"])
    np.testing.assert_array_equal(t, ds["time"].values)
    args = _kernel_args(dm)
    w = dm.info["nominal_velocity"]
    taudd = dm.nominal(t)[2]
    assert np.ptp(taudd) == 0.0 and taudd[0] > 0.0  # a run-up, one segment
    a, f, d = np.empty(dm.n_dof), np.empty(dm.n_mesh), np.empty(dm.n_mesh)
    for r in ds["rotation"].values:
        j = dm.dof_labels.index(f"{r}.theta")
        got = ds["angular_acceleration"].sel(rotation=r).values
        one = gb.record(f"angular_acceleration[{r}]")  # a study's path
        want = np.empty(t.size)
        for k in range(t.size):
            _kernels.rhs(t[k], q[k], v[k], *args, False, True, a, f, d)
            want[k] = a[j] + w[j] * taudd[k]
        scale = np.max(np.abs(want))
        assert np.max(np.abs(got - want)) <= RHS_RTOL * scale, r
        assert np.max(np.abs(one - want)) <= RHS_RTOL * scale, r


@pytest.mark.parametrize(("name", "model"), [("idler-table1", "lta"),
                                             ("spur-19-48", "lta"),
                                             ("two-stage-reducer", "lta")])
def test_integral_of_the_record_is_the_speed_change(name, model):
    gb = _box(name, model, duration=0.4)
    ds = gb.simulate()
    t = ds["time"].values
    h = t[1] - t[0]
    checked = 0
    for r in ds["rotation"].values:
        if r not in ds["shaft"].values:  # a gear's own rotation on a twisting shaft
            continue
        acc = ds["angular_acceleration"].sel(rotation=r).values
        angle = ds["shaft_angle"].sel(shaft=r).values
        w0 = (angle[2] - angle[0]) / (2 * h)
        w1 = (angle[-1] - angle[-3]) / (2 * h)
        gain = np.trapezoid(acc[1:-1], t[1:-1])
        assert gain == pytest.approx(w1 - w0, rel=KINEMATIC_RTOL), r
        checked += 1
    assert checked >= 2
