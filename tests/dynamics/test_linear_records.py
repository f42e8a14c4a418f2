"""The records of ``simulate`` against an independent reference (issue 26).

``simulate`` forms its records with linear maps around the anti-aliasing decimation
(``linear_records``, ``_kernels.decimate_linear``): the bearing forces k_b q + c_b q'
and the mesh deflections V q are combined at the internal rate and filtered as one
signal each, the mesh forces, DTE, accelerations and shaft angles are combined from the
filtered signals at the output rate. The reference here does none of that: it takes the
kernel's records of *every* channel at the internal rate (``run_kernel`` on the grid of
docs/dynamics.md section 5, written out again), decimates them with
``scipy.signal.upfirdn`` and the same taps, and forms each record of docs/dynamics.md
section 6 from the decimated q, q' and f with numpy, the way ``simulate`` did before.

Filtering and combining are both linear, so the two orders give the same records up to
rounding, and rounding is all that may differ: each variable agrees with the reference
to :data:`RECORD_RTOL` of its largest magnitude (the issue's measure). Measured on these
cases: at most 3.7e-14 (the accelerations, whose terms F_j, k_b q_j + c_b q'_j and
V_ij f_i nearly cancel; the DTE 2.2e-14, bearing forces 1.4e-15, angular accelerations
6.3e-16). The mesh forces,
shaft torques and shaft angles come out of the filter with the same operations in the
same order as ``upfirdn``'s (and the product or sum after it): equal to the bit; the
tacho is that of the angles.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import upfirdn

import gearsim as gs
from gearsim.data import example_text
from gearsim.dynamics import simulate
from gearsim.dynamics.simulate import (
    FIR_HALF_PER_R,
    TACHO_VOLTS,
    TACHO_WIDTH,
    anti_alias_taps,
    build_model,
    linear_records,
    run_kernel,
)
from gearsim.model import loads
from gearsim.model.variants import fault_variant

#: Largest difference of a record from the reference, relative to the record's largest
#: magnitude: rounding only (issue 26: "results identical to before (1e-12)").
RECORD_RTOL = 1e-12


def _box(name: str, **dyn) -> gs.Gearbox:
    return gs.example(name).replace(dynamics={"duration": 0.11, "fs": 20e3, **dyn})


def _springs() -> gs.Gearbox:
    """The two-stage reducer with a torsionally elastic intermediate shaft: a shaft
    spring row beside the meshes (``shaft_torque``)."""
    text = example_text("two-stage-reducer").replace(
        'name = "intermediate"\n', 'name = "intermediate"\ntorsional_stiffness = "2e5 N*m/rad"\n')
    return loads(text).replace(dynamics={"duration": 0.4})


CASES = {
    "table1-lta": lambda: _box("idler-table1"),
    "table1-torsional": lambda: _box("idler-table1", model="torsional"),
    "table1-seed3dof": lambda: _box("idler-table1", model="seed"),
    "table1-oversample-1": lambda: _box("idler-table1", oversample=1),
    "table1-oversample-3": lambda: _box("idler-table1", oversample=3),
    "table1-ste-harmonics": lambda: _box("idler-table1", profile_modification=2e-6,
                                         runout=5e-6),
    # 0.16 s: the output turns once at the profile's speeds (0.71 times in 0.11 s)
    "table1-profiles": lambda: _box("idler-table1", transient=0.01, duration=0.16,
                                    speed_times=[0.0, 0.13], speed_values=[100.0, 160.0],
                                    load_times=[0.0, 0.13], load_values=[0.5, 1.2]),
    "spur-spall-contacts": lambda: fault_variant(_box("spur-19-48"), "spall", 1.0),
    "reducer-lta": lambda: _box("two-stage-reducer", duration=0.4),
    "reducer-shaft-spring": _springs,
}


def _reference(gb: gs.Gearbox, ds) -> dict[str, np.ndarray]:
    """Every record of ``ds`` from full-rate records, ``upfirdn`` and numpy."""
    train, s = gb.train, gb.dynamics
    model = build_model(train, s)
    r, fs = s.oversample, s.fs
    t_int = 1.0 / (r * fs)
    dt = ds.attrs["step"]
    m = round(t_int / dt)
    half = FIR_HALF_PER_R * r if r > 1 else 0
    n_out = ds.sizes["time"]
    # the first output sample is centred on the end of the transient (a whole number of
    # internal samples, at least the filter's half length): the kernel records from
    # half internal samples before it to half after the last output sample
    tr_samples = round(ds.attrs["transient"] / t_int)
    n_rec = (n_out - 1) * r + 1 + 2 * half
    rec_start = (tr_samples - half) * m
    raw = run_kernel(model, dt=dt, n_steps=rec_start + (n_rec - 1) * m,
                     rec_start=rec_start, rec_every=m, n_rec=n_rec)
    x = np.vstack([raw.q.T, raw.v.T, raw.f.T])  # every channel, full rate
    if r > 1:
        y = upfirdn(anti_alias_taps(r, fs), x, up=1, down=r, axis=-1)
        y = y[:, 2 * half // r:2 * half // r + n_out]
    else:
        y = x
    n = model.n_dof
    q, v, f = y[:n].T, y[n:2 * n].T, y[2 * n:].T
    t = ds["time"].values
    if model.profile is None and model.load is None:
        acc = (model.fext - model.kb * q - model.cb * v - f @ model.V) / model.mass
    else:  # the absolute acceleration w tau'' + q'' (docs/dynamics.md eq. 6a)
        _, _, taudd, lam = model.nominal(t)
        c = model.inertial + model.mass * model.info["nominal_velocity"]
        acc = (lam[:, None] * model.fext + taudd[:, None] * c - model.kb * q - model.cb * v
               - f @ model.V) / model.mass
    bd = model.bearing_dofs
    ref = {"bearing_force": model.kb[bd] * q[:, bd] + model.cb[bd] * v[:, bd],
           "acceleration": acc[:, bd]}
    dte = q @ model.V.T + model.dte_offset
    for i in range(len(train.pairs)):
        ref[f"mesh_force_{i + 1}"] = f[:, i] * model.to_transverse[i]
        ref[f"dte_{i + 1}"] = dte[:, i]
        ref[f"ste_{i + 1}"] = model.ste(t)[:, i]
    if "shaft_rows" in model.info and model.info["shaft_rows"]:
        ref["shaft_torque"] = f[:, list(model.info["shaft_rows"])]
    rot = [j for j, lab in enumerate(model.dof_labels)
           if lab.endswith(".theta") and model.kind != "seed"]
    if rot:
        ref["angular_acceleration"] = acc[:, rot]
    tau = model.nominal(t)[0]
    angles = []
    for sh in train.flow.shafts:
        own = [lab for lab in (f"{sh.name}.theta", f"{sh.gears[0]}.theta")
               if lab in model.dof_labels and model.kind != "seed"]
        elastic = q[:, model.dof_labels.index(own[0])] if own else 0.0
        angles.append(train.speed(train.gear_index(sh.gears[0])) * tau + elastic)
    ref["shaft_angle"] = np.stack(angles, axis=1)
    return ref


@pytest.mark.parametrize("case", list(CASES))
def test_records_match_upfirdn_and_numpy(case):
    gb = CASES[case]()
    ds = gb.simulate()
    ref = _reference(gb, ds)
    assert set(ref) | {"tacho"} == set(ds.data_vars)
    for name, want in ref.items():
        got = ds[name].values
        assert got.shape == want.shape, name
        err = np.max(np.abs(got - want), initial=0.0)
        assert err <= RECORD_RTOL * np.max(np.abs(want), initial=0.0), (name, err)
    # unchanged by the maps: what the filter gives, as upfirdn (the same sums)
    for i in range(len(gb.train.pairs)):
        np.testing.assert_array_equal(ds[f"mesh_force_{i + 1}"].values,
                                      ref[f"mesh_force_{i + 1}"])
    np.testing.assert_array_equal(ds["shaft_angle"].values, ref["shaft_angle"])
    # the tacho of the result's own angles, numpy.mod's pulses
    pulses = np.where(np.mod(ds["shaft_angle"].values, 2 * np.pi) < TACHO_WIDTH,
                      TACHO_VOLTS, 0.0)
    np.testing.assert_array_equal(ds["tacho"].values, pulses)


def test_maps_name_every_record_and_record_only_what_they_use():
    gb = _box("idler-table1")
    model = build_model(gb.train, gb.dynamics)
    lin = linear_records(model, gb.train)
    n_rec = lin.post[0].size - 1
    assert len(lin.names) == n_rec == lin.post[3].size == lin.post[4].size
    # Table 1, LTA: 3 shafts x 3 axes of bearings; 16 signals filtered (2 mesh forces,
    # 2 deflections, 9 bearing forces, 3 rotations) from 23 channels (no rotation speed:
    # no bearing damps a rotation)
    assert lin.pre[0].size - 1 == 16
    assert [c.size for c in lin.channels] == [12, 9, 2]
    assert sum("acceleration[" in n for n in lin.names) == 12


def test_a_selected_record_is_the_one_a_study_forms():
    # a study forms its record after the filter (simulate_record, the order studies had
    # before); the maps form it before: the same numbers to rounding
    gb = _box("spur-19-48")
    ds = simulate(gb.train, gb.dynamics)
    for spec in ("acceleration[pinion,y]", "dte_1", "bearing_force[gear,x]"):
        want = gb.select(ds, spec)
        err = np.max(np.abs(gb.record(spec) - want))
        assert err <= RECORD_RTOL * np.max(np.abs(want)), (spec, err)


def test_reference_grid_is_the_documented_one():
    # the reference's grid must be simulate's: same times, transient a whole number of
    # internal samples
    gb = _box("idler-table1", transient=0.0123)
    ds = gb.simulate()
    s = gb.dynamics
    t_int = 1.0 / (s.oversample * s.fs)
    tr = ds.attrs["transient"]
    assert tr == pytest.approx(round(tr / t_int) * t_int, rel=1e-12)
    np.testing.assert_array_equal(ds["time"].values, tr + np.arange(ds.sizes["time"]) / s.fs)
